//! The sitar's phrase: strokes of the mizrab on the played string, each at a fret, with an
//! optional meend (the pull across the fret that bends the note), and on the chikari (the
//! rhythmic drone strokes of alap's jor and of jhala).
//!
//! The fret and the meend move the played string's pitch by its tension (`T ∝ f²`, on the
//! string's fixed length and grid): a meend is a tension change on a real sitar, a fret is a
//! shorter length, so a fretted note here keeps the open string's pluck position and
//! inharmonicity (in proportion to its length) where a real fret would change both a little.
//! The tension change does work on the ringing string, booked as work
//! ([`crate::models::string::StiffString::retune`]), so the power balance closes through a
//! phrase. A meend glides in log-frequency along a raised cosine,
//! `f(τ) = f_0 (f_1/f_0)^{(1 - cos πτ)/2}` over `τ ∈ [0, 1]`: no jump in pitch or its slope at
//! either end.
//!
//! [`SitarStroke`] is scene data (any thread); [`PhraseSteps`] is built on the control thread
//! and read by the stepping thread without allocating.

use crate::error::{check_closed, ParamError};
use serde::{Deserialize, Serialize};

/// One stroke of the phrase.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SitarStroke {
    /// Time of the stroke, s from the start (0 to 3600; strokes in time order).
    pub at: f64,
    /// The fret's note, Hz (60 to 1200).
    pub note: f64,
    /// Strength of the stroke: its amplitude over the scene's `pluck_amplitude` (0 to 1). 0
    /// leaves the played string alone, as a stroke on the chikari alone does: it is not
    /// struck, and its fret and a meend under way go on (`note` and the meend are not used).
    #[serde(default = "default_strength")]
    pub strength: f64,
    /// Strength of the stroke on the chikari, every chikari string at once: its amplitude over
    /// the scene's `pluck_amplitude` (0 to 1; default 0, the chikari not struck).
    #[serde(default)]
    pub chikari: f64,
    /// The meend's target note, Hz (within 7 semitones of `note`; none: no meend).
    #[serde(default)]
    pub meend_to: Option<f64>,
    /// Start of the meend after the stroke, s (0 to 10).
    #[serde(default = "default_meend_after")]
    pub meend_after: f64,
    /// Length of the meend's glide, s (0.01 to 10).
    #[serde(default = "default_meend_seconds")]
    pub meend_seconds: f64,
}

fn default_strength() -> f64 {
    1.0
}
fn default_meend_after() -> f64 {
    0.15
}
fn default_meend_seconds() -> f64 {
    0.4
}

impl SitarStroke {
    /// A stroke of full strength at `at` s on `note` Hz, without meend.
    pub fn at(at: f64, note: f64) -> Self {
        Self {
            at,
            note,
            strength: default_strength(),
            chikari: 0.0,
            meend_to: None,
            meend_after: default_meend_after(),
            meend_seconds: default_meend_seconds(),
        }
    }

    /// Checks the stroke, `previous` the time of the stroke before it; errors name
    /// `sitar.phrase[i].<field>`.
    pub fn validate(&self, i: usize, previous: f64) -> Result<(), ParamError> {
        let f = |name: &str| format!("sitar.phrase[{i}].{name}");
        check_closed(&f("at"), self.at, 0.0, 3600.0)?;
        if self.at < previous {
            return Err(ParamError::new(
                f("at"),
                self.at,
                format!("at or after the stroke before it ({previous} s)"),
            ));
        }
        check_closed(&f("note"), self.note, 60.0, 1200.0)?;
        check_closed(&f("strength"), self.strength, 0.0, 1.0)?;
        check_closed(&f("chikari"), self.chikari, 0.0, 1.0)?;
        if let Some(to) = self.meend_to {
            let (lo, hi) = (
                self.note * 2f64.powf(-7.0 / 12.0),
                self.note * 2f64.powf(7.0 / 12.0),
            );
            if !(to.is_finite() && to >= lo && to <= hi) {
                return Err(ParamError::new(
                    f("meend_to"),
                    to,
                    format!("{lo:.2} to {hi:.2} Hz (within 7 semitones of the note)"),
                ));
            }
        }
        check_closed(&f("meend_after"), self.meend_after, 0.0, 10.0)?;
        check_closed(&f("meend_seconds"), self.meend_seconds, 0.01, 10.0)?;
        Ok(())
    }
}

/// A stroke in steps, its pitches as ratios to the played string's tuning.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StrokeSteps {
    /// Step of the stroke.
    pub at: u64,
    /// The fret's pitch over the open tuning.
    pub ratio: f64,
    /// Amplitude factor (0 to 1).
    pub strength: f64,
    /// Amplitude factor of the chikari's pluck (0 to 1).
    pub chikari: f64,
    /// The meend: `(start step, steps, target ratio)`.
    pub meend: Option<(u64, u64, f64)>,
}

impl StrokeSteps {
    /// The pitch ratio at step `n` (≥ the stroke's): the fret's, or on the meend's glide.
    pub fn ratio_at(&self, n: u64) -> f64 {
        match self.meend {
            Some((start, len, to)) if n > start => {
                let tau = ((n - start) as f64 / len as f64).min(1.0);
                let w = 0.5 * (1.0 - (std::f64::consts::PI * tau).cos());
                self.ratio * (to / self.ratio).powf(w)
            }
            _ => self.ratio,
        }
    }

    /// Whether the pitch moves at step `n` (on the meend's glide, its last step included).
    pub fn gliding(&self, n: u64) -> bool {
        matches!(self.meend, Some((start, len, _)) if n > start && n <= start + len)
    }
}

/// The phrase in steps, for a played string tuned to `open` Hz at step `h` s. Control thread.
pub fn phrase_steps(phrase: &[SitarStroke], open: f64, h: f64) -> Vec<StrokeSteps> {
    let step = |t: f64| (t / h).round() as u64;
    phrase
        .iter()
        .map(|s| StrokeSteps {
            at: step(s.at),
            ratio: s.note / open,
            strength: s.strength,
            chikari: s.chikari,
            meend: s.meend_to.map(|to| {
                (
                    step(s.at + s.meend_after),
                    step(s.meend_seconds).max(1),
                    to / open,
                )
            }),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The glide starts at the fret's pitch, ends on the target, passes the geometric mean at
    /// half time (the raised cosine in log-frequency; tolerance 1e-12, a few roundings), and
    /// holds the target after.
    #[test]
    fn the_meend_glides_in_log_frequency() {
        let s = SitarStroke {
            meend_to: Some(330.0),
            meend_after: 0.1,
            meend_seconds: 0.2,
            ..SitarStroke::at(1.0, 220.0)
        };
        let p = phrase_steps(&[s], 220.0, 1e-3)[0];
        assert_eq!(p.at, 1000);
        assert_eq!(p.meend, Some((1100, 200, 1.5)));
        let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
        assert!(close(p.ratio_at(1050), 1.0));
        assert!(close(p.ratio_at(1100), 1.0));
        assert!(close(p.ratio_at(1200), 1.5f64.sqrt()));
        assert!(close(p.ratio_at(1300), 1.5));
        assert!(close(p.ratio_at(5000), 1.5));
        assert!(p.gliding(1300) && !p.gliding(1301) && !p.gliding(1100));
    }

    /// Bad strokes name the field.
    #[test]
    fn bad_strokes_name_the_field() {
        let s = SitarStroke::at(1.0, 220.0);
        assert_eq!(s.validate(2, 1.5).unwrap_err().field, "sitar.phrase[2].at");
        let far = SitarStroke {
            meend_to: Some(400.0),
            ..s
        };
        assert_eq!(
            far.validate(0, 0.0).unwrap_err().field,
            "sitar.phrase[0].meend_to"
        );
        let weak = SitarStroke { strength: 1.5, ..s };
        assert_eq!(
            weak.validate(0, 0.0).unwrap_err().field,
            "sitar.phrase[0].strength"
        );
        let chikari = SitarStroke { chikari: -0.1, ..s };
        assert_eq!(
            chikari.validate(0, 0.0).unwrap_err().field,
            "sitar.phrase[0].chikari"
        );
    }
}
