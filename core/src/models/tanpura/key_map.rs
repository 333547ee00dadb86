//! Tuning by ear over a range of keys: the drone a player retunes by the key they hold.
//!
//! Moving every string's tension by `ratio²` moves its ideal pitch by `ratio`, but not what the
//! seat, the moving bridge and the jawari add to it: their stiffness is fixed while the
//! string's tension changes, so a drone tuned by ear on C#3 and retuned by its tensions alone
//! is 3 to 4 cents sharp an octave down and up to 2.6 cents flat an octave up (about 0.2 cents
//! per semitone near the tuned key; docs/models.md, "The tanpura drone"). A player retunes by
//! ear at every Sa; here the worker does it at a few *anchor* keys ([`SaMap::tune`], each
//! anchor one tuning of [`super::tune`]) and the stepping thread interpolates each string's
//! tension correction between them, linearly in semitones (beyond the outer anchors, along
//! the outer segment).
//!
//! Built on the worker (allocates, `anchors · TUNE_PASSES · strings` seconds of simulation);
//! read on the stepping thread without allocating.

use super::spec::TanpuraSpec;
use super::tune::tension_scales;
use crate::error::ParamError;

/// Per string, the tension correction at each anchor key, relative to the tuning at the
/// drone's own Sa.
///
/// Built on the worker; read by the stepping thread ([`SaMap::correction`]).
#[derive(Debug, Clone, PartialEq)]
pub struct SaMap {
    /// Anchor keys in semitones from the drone's Sa, increasing (0 among them).
    semitones: Vec<f64>,
    /// Per anchor `a`, per string `i`, at `a · strings + i`: the tension scale at the anchor
    /// over `ratio²` times the scale at Sa.
    corrections: Vec<f64>,
    /// Number of strings.
    strings: usize,
}

impl SaMap {
    /// No correction: the tensions follow `ratio²` alone (a drone tuned at its own Sa only).
    pub fn none(strings: usize) -> Self {
        Self {
            semitones: vec![0.0],
            corrections: vec![1.0; strings],
            strings,
        }
    }

    /// Tunes `spec` by ear at its Sa moved by each of `anchors` (semitones; 0 is added, the
    /// others sorted, those whose Sa leaves the spec's range of 30 to 1000 Hz dropped) and
    /// keeps each string's correction. `at_sa`: the tension scales of the tuning at Sa itself
    /// (already measured by the caller). Worker thread.
    pub fn tune(spec: &TanpuraSpec, at_sa: &[f64], anchors: &[f64]) -> Result<Self, ParamError> {
        let n = spec.strings;
        let mut keys: Vec<f64> = anchors
            .iter()
            .copied()
            .filter(|a| a.is_finite() && *a != 0.0)
            .filter(|a| (30.0..=1000.0).contains(&(spec.sa * 2f64.powf(a / 12.0))))
            .chain([0.0])
            .collect();
        keys.sort_by(f64::total_cmp);
        keys.dedup();
        let mut corrections = Vec::with_capacity(keys.len() * n);
        for &a in &keys {
            if a == 0.0 {
                corrections.extend(std::iter::repeat_n(1.0, n));
                continue;
            }
            let mut moved = spec.clone();
            moved.sa = spec.sa * 2f64.powf(a / 12.0);
            let scales = tension_scales(&moved)?;
            corrections.extend(scales.iter().zip(at_sa).map(|(s, s0)| s / s0));
        }
        Ok(Self {
            semitones: keys,
            corrections,
            strings: n,
        })
    }

    /// A map of `strings` strings from its anchors (semitones, increasing, 0 among them) and
    /// the corrections at them (`anchor · strings + string`). Control thread.
    pub(crate) fn from_parts(semitones: Vec<f64>, corrections: Vec<f64>, strings: usize) -> Self {
        debug_assert_eq!(semitones.len() * strings, corrections.len());
        debug_assert!(semitones.windows(2).all(|w| w[0] < w[1]));
        Self {
            semitones,
            corrections,
            strings,
        }
    }

    /// String `string`'s tension correction at `semitones` from Sa: linear between the
    /// anchors, along the outer segment beyond them (1 with a single anchor). O(anchors), no
    /// allocation.
    pub fn correction(&self, string: usize, semitones: f64) -> f64 {
        let k = &self.semitones;
        let at = |a: usize| self.corrections[a * self.strings + string];
        if k.len() < 2 {
            return at(0);
        }
        // The segment: the last anchor at or below, within [0, len - 2].
        let seg = k[1..k.len() - 1]
            .iter()
            .take_while(|&&x| x <= semitones)
            .count();
        let (x0, x1) = (k[seg], k[seg + 1]);
        let w = (semitones - x0) / (x1 - x0);
        at(seg) + w * (at(seg + 1) - at(seg))
    }

    /// The anchor keys (semitones from Sa).
    pub fn anchors(&self) -> &[f64] {
        &self.semitones
    }

    /// The anchor keys and the corrections at them (`anchor · strings + string`), as
    /// [`Self::from_parts`] takes them back.
    pub fn parts(&self) -> (&[f64], &[f64]) {
        (&self.semitones, &self.corrections)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Interpolation through hand-set anchors: exact at the anchors, linear between and along
    /// the outer segments beyond (tolerance 1e-15, a few roundings).
    #[test]
    fn corrections_interpolate_linearly_in_semitones() {
        let m = SaMap {
            semitones: vec![-12.0, 0.0, 12.0],
            corrections: vec![0.9, 1.2, 1.0, 1.0, 1.1, 0.7],
            strings: 2,
        };
        let close = |a: f64, b: f64| (a - b).abs() < 1e-15;
        assert!(close(m.correction(0, -12.0), 0.9));
        assert!(close(m.correction(0, -6.0), 0.95));
        assert!(close(m.correction(0, 6.0), 1.05));
        assert!(close(m.correction(0, 24.0), 1.2));
        assert!(close(m.correction(1, -24.0), 1.4));
        assert!(close(m.correction(1, 12.0), 0.7));
        assert!(close(SaMap::none(3).correction(2, 7.0), 1.0));
    }
}
