//! [`Sitar`]: the played string, its taraf and its chikari on the bridges, tuned by ear, one
//! note or a phrase plucked.

use super::phrase::{phrase_steps, StrokeSteps};
use super::spec::{SitarSpec, CHIKARI_PAN};
use super::tuning::{phrase_notes, plucks, tune, tune_cached};
use crate::error::ParamError;
use crate::models::network::{BridgeInstrument, StringNetwork};
use crate::models::string::TrianglePluck;
use crate::models::tanpura::instrument::{pan_gains, RetuneRefusal};
use crate::models::tanpura::{SaMap, TunedStrings, TuningSource};
use std::path::Path;

/// Largest pluck strength over the spec's amplitude (the engine's velocity times the mod
/// wheel's factor): five times the 1 mm a sitar is tuned at.
pub const MAX_STRENGTH: f64 = 10.0;

/// A sitar: the played string (string 0, with the curved jawari of the main bridge), its
/// taraf (strings 1 to `taraf`) and its chikari (the last strings, on the main bridge's
/// jawari too) on the bridges' shared modes. The played string plays the phrase (or, without
/// one, is plucked at the first step) and the phrase's chikari strokes pluck the chikari; the
/// taraf answers through the bridges. The output is the strings' forces on the bridges, the
/// played string in the centre, the chikari beside it and the taraf spread across the image.
///
/// Built on the control thread ([`Sitar::build`]); stepped without allocating.
#[derive(Debug, Clone)]
pub struct Sitar {
    /// The strings on the bridges.
    network: StringNetwork,
    /// Per string, `[left, right]` gains.
    pan: Vec<[f64; 2]>,
    /// Per string, its tension after tuning (N).
    tensions: Vec<f64>,
    /// The phrase in steps (empty: the one pluck at build).
    phrase: Vec<StrokeSteps>,
    /// The next stroke of the phrase.
    next: usize,
    /// The stroke sounding (its fret and meend set the played string's pitch).
    sounding: Option<StrokeSteps>,
    /// The played string's pluck at full strength.
    pluck: TrianglePluck,
    /// The chikari's strings (indices) and their plucks at full strength.
    chikari: Vec<(usize, TrianglePluck)>,
    /// The played string's tension corrections at the phrase's notes, tuned by ear (one
    /// string; semitones from its open note).
    frets: SaMap,
    /// Steps taken.
    step: u64,
    /// The played string's open note, Hz.
    note: f64,
    /// The played string's pitch over its open note (the engine's fret).
    ratio: f64,
    /// The damping scale and the floor (1/s) every string's losses were last set with.
    losses: (f64, f64),
}

impl Sitar {
    /// Validates `spec`, tunes every string by ear (and the played string at the phrase's
    /// notes), builds the network and, without a phrase, plucks the played string. Control
    /// thread.
    pub fn build(spec: &SitarSpec) -> Result<Self, ParamError> {
        let tuned = tune(spec, &phrase_notes(spec))?;
        let mut sitar = Self::from_tuned(spec, tuned)?;
        if spec.phrase.is_empty() {
            sitar.network.pluck(0, &sitar.pluck)?;
        }
        Ok(sitar)
    }

    /// The engine's sitar: `spec` without its phrase, tuned by ear at the open notes and at
    /// `anchors` (semitones over the open note) or read from the cache in `dir`, at rest.
    /// Worker thread.
    pub fn build_cached(
        spec: &SitarSpec,
        anchors: &[f64],
        dir: Option<&Path>,
    ) -> Result<(Self, TuningSource), ParamError> {
        let spec = SitarSpec {
            phrase: Vec::new(),
            ..spec.clone()
        };
        let (tuned, source) = tune_cached(&spec, anchors, dir)?;
        Ok((Self::from_tuned(&spec, tuned)?, source))
    }

    /// The sitar of `spec` with its strings tuned as `tuned` says (one tension scale per
    /// string; the played string's fret corrections), at rest. Control thread.
    pub fn from_tuned(spec: &SitarSpec, tuned: TunedStrings) -> Result<Self, ParamError> {
        spec.validate()?;
        let n = spec.strings();
        let TunedStrings { scales, sa_map } = tuned;
        if scales.len() != n {
            return Err(ParamError::new(
                "sitar.scales",
                scales.len(),
                format!("one per string ({n})"),
            ));
        }
        let plucks = plucks(spec);
        let network = StringNetwork::new(&spec.network(&scales)?)?;
        let phrase = phrase_steps(&spec.phrase, spec.note, network.h());
        let taraf = spec.taraf;
        let pan = (0..n)
            .map(|i| {
                if i == 0 {
                    pan_gains(0.0)
                } else if spec.is_chikari(i) {
                    pan_gains(CHIKARI_PAN)
                } else {
                    pan_gains(0.8 * (2.0 * (i - 1) as f64 / (taraf - 1).max(1) as f64 - 1.0))
                }
            })
            .collect();
        let chikari = (0..n)
            .filter(|&i| spec.is_chikari(i))
            .map(|i| (i, plucks[i]))
            .collect();
        let tensions = (0..n)
            .map(|i| spec.nominal_tension(i) * scales[i])
            .collect();
        Ok(Self {
            network,
            pan,
            tensions,
            phrase,
            next: 0,
            sounding: None,
            pluck: plucks[0],
            chikari,
            frets: sa_map,
            step: 0,
            note: spec.note,
            ratio: 1.0,
            losses: (1.0, 0.0),
        })
    }

    /// The network (string 0 the played string, then the taraf, then the chikari).
    pub fn network(&self) -> &StringNetwork {
        &self.network
    }

    /// Each string's tension after tuning by ear (N).
    pub fn tensions(&self) -> &[f64] {
        &self.tensions
    }

    /// Plays the phrase's strokes due at this step (a stroke of non-zero strength sets the
    /// played string's tension to its fret and plucks it on top of its motion; a chikari
    /// stroke plucks the chikari), moves the pitch along a meend, then advances the network
    /// one step. No allocation; O(modes) on a step that retunes.
    pub fn step(&mut self) {
        let n = self.step;
        while let Some(&stroke) = self.phrase.get(self.next).filter(|s| s.at <= n) {
            self.next += 1;
            // A stroke of strength 0 (on the chikari alone) leaves the played string as it
            // is: its fret, and a meend under way, go on.
            if stroke.strength > 0.0 {
                self.sounding = Some(stroke);
                self.set_pitch(stroke.ratio);
                let p = TrianglePluck {
                    amplitude: self.pluck.amplitude * stroke.strength,
                    ..self.pluck
                };
                // The amplitude was validated at build and the strength is at most 1.
                let ok = self.network.pluck(0, &p).is_ok();
                debug_assert!(ok);
            }
            if stroke.chikari > 0.0 {
                for &(i, pluck) in &self.chikari {
                    let p = TrianglePluck {
                        amplitude: pluck.amplitude * stroke.chikari,
                        ..pluck
                    };
                    let ok = self.network.pluck(i, &p).is_ok();
                    debug_assert!(ok);
                }
            }
        }
        if let Some(stroke) = self.sounding.filter(|s| s.gliding(n)) {
            self.set_pitch(stroke.ratio_at(n));
        }
        self.network.step();
        self.step += 1;
    }

    /// Sets the played string to `ratio` times its open pitch by its tension (`T ∝ ratio²`,
    /// corrected as tuned by ear at the phrase's notes and interpolated between them).
    fn set_pitch(&mut self, ratio: f64) {
        // Finite and positive by the phrase's validation: cannot refuse.
        let ok = self.try_fret(ratio, 1.0, 0.0).is_ok();
        debug_assert!(ok);
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.step
    }

    /// The played string's open note, Hz.
    pub fn note(&self) -> f64 {
        self.note
    }

    /// The played string's pitch over its open note.
    pub fn ratio(&self) -> f64 {
        self.ratio
    }

    /// The played string's pluck amplitude at strength 1, m.
    pub fn pluck_amplitude(&self) -> f64 {
        self.pluck.amplitude
    }

    /// The engine's fret: the played string at `ratio` times its open pitch by its tension
    /// (`T = ratio² c T_open`, `c` its correction at that note from the notes tuned by ear),
    /// every string's Valette losses times `damping` and at least the decay rate `floor`
    /// (1/s: the player's hand on the strings, a release; 0 lets them ring). The taraf and
    /// the chikari keep their tensions and are retuned only when `damping` or `floor`
    /// changes. Refused (nothing changes) for a ratio that is not finite and positive, a
    /// damping or a floor that is not finite and ≥ 0, or a tension that would not be finite
    /// and positive. Stepping thread; no allocation, also when it refuses; O(modes) of the
    /// played string (of every string when the losses change).
    pub fn try_fret(&mut self, ratio: f64, damping: f64, floor: f64) -> Result<(), RetuneRefusal> {
        if !(damping.is_finite() && damping >= 0.0) {
            return Err(RetuneRefusal::Damping);
        }
        if !(ratio.is_finite() && ratio > 0.0) {
            return Err(RetuneRefusal::Ratio);
        }
        if !(floor.is_finite() && floor >= 0.0) {
            return Err(RetuneRefusal::Floor);
        }
        let tension =
            self.tensions[0] * ratio * ratio * self.frets.correction(0, 12.0 * ratio.log2());
        if !(tension.is_finite() && tension > 0.0) {
            return Err(RetuneRefusal::Tension);
        }
        let strings = if (damping, floor) == self.losses {
            1
        } else {
            self.tensions.len()
        };
        for i in 0..strings {
            let t = if i == 0 { tension } else { self.tensions[i] };
            // The inputs are checked above: the string cannot refuse them.
            let ok = self.network.retune_string(i, t, damping, floor);
            debug_assert!(ok);
        }
        self.ratio = ratio;
        self.losses = (damping, floor);
        Ok(())
    }

    /// Plucks the played string at `strength` times its pluck amplitude, on top of its
    /// motion. `false` (nothing changes) outside 0 to [`MAX_STRENGTH`]. Stepping thread; no
    /// allocation.
    pub fn try_pluck(&mut self, strength: f64) -> bool {
        if !(0.0..=MAX_STRENGTH).contains(&strength) {
            return false;
        }
        let p = TrianglePluck {
            amplitude: self.pluck.amplitude * strength,
            ..self.pluck
        };
        self.network.pluck(0, &p).is_ok()
    }

    /// Plucks every chikari at `strength` times its pluck amplitude (a stroke across them).
    /// `false` (nothing changes) outside 0 to [`MAX_STRENGTH`]. Stepping thread; no
    /// allocation.
    pub fn try_pluck_chikari(&mut self, strength: f64) -> bool {
        if !(0.0..=MAX_STRENGTH).contains(&strength) {
            return false;
        }
        for &(i, pluck) in &self.chikari {
            let p = TrianglePluck {
                amplitude: pluck.amplitude * strength,
                ..pluck
            };
            if self.network.pluck(i, &p).is_err() {
                return false;
            }
        }
        true
    }

    /// Puts every string and the bridges at rest and the phrase back at its start; the
    /// played string keeps its fret. Stepping thread; no allocation.
    pub fn reset(&mut self) {
        self.network.reset();
        self.next = 0;
        self.sounding = None;
        self.step = 0;
    }

    /// String `i`'s displacement at the grid's interior nodes (m, from the bridge's end;
    /// [`crate::models::string::StiffString::grid_displacement`]: one inverse transform).
    /// For views; the motion is not changed. Stepping thread, no allocation.
    pub fn string_grid_displacement(&mut self, i: usize) -> &[f64] {
        self.network.string_mut(i).grid_displacement()
    }
}

impl BridgeInstrument for Sitar {
    fn network(&self) -> &StringNetwork {
        &self.network
    }

    fn advance(&mut self) {
        self.step();
    }

    fn gains(&self) -> &[[f64; 2]] {
        &self.pan
    }
}
