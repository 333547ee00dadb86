//! [`Sitar`]: the played string, its taraf and its chikari on the bridges, tuned by ear, one
//! note or a phrase plucked.

use super::phrase::{phrase_steps, StrokeSteps};
use super::spec::{SitarSpec, CHIKARI_PAN};
use crate::error::ParamError;
use crate::models::network::{BridgeInstrument, StringNetwork};
use crate::models::string::params::Stiffness;
use crate::models::string::{TrianglePluck, ValetteLosses};
use crate::models::tanpura::instrument::pan_gains;
use crate::models::tanpura::tune::{
    map_on_threads, tune_by_ear, tune_string_by_ear, tuning_threads,
};
use crate::models::tanpura::SaMap;

/// Amplitude of the pluck that tunes a taraf string by ear, m.
const TARAF_TUNING_PLUCK: f64 = 3e-4;

/// A sitar: the played string (string 0, with the curved jawari of the main bridge), its
/// taraf (strings 1 to `taraf`) and its chikari (the last strings, on the main bridge's
/// jawari too) on the bridges' shared modes. The played string plays the phrase (or, without
/// one, is plucked at the first step) and the phrase's chikari strokes pluck the chikari; the
/// taraf answers through the bridges. The output is the strings' forces on the bridges, the
/// played string in the centre, the chikari beside it and the taraf spread across the image.
///
/// Built on the control thread ([`Sitar::build`]); stepped without allocating.
#[derive(Debug)]
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
}

impl Sitar {
    /// Validates `spec`, tunes every string by ear, builds the network and plucks the played
    /// string. Control thread.
    pub fn build(spec: &SitarSpec) -> Result<Self, ParamError> {
        spec.validate()?;
        let n = spec.strings();
        let targets = spec.targets();
        let plucks: Vec<TrianglePluck> = (0..n)
            .map(|i| {
                let (length, _, _) = spec.geometry(i);
                if i == 0 || spec.is_chikari(i) {
                    TrianglePluck {
                        position: spec.pluck_position * length,
                        amplitude: spec.pluck_amplitude,
                    }
                } else {
                    TrianglePluck {
                        position: 0.3 * length,
                        amplitude: TARAF_TUNING_PLUCK,
                    }
                }
            })
            .collect();
        let scales = if spec.tune_by_ear {
            tune_by_ear(|s| spec.network(s), &targets, &plucks)?
        } else {
            vec![1.0; n]
        };
        let mut network = StringNetwork::new(&spec.network(&scales)?)?;
        if spec.phrase.is_empty() {
            network.pluck(0, &plucks[0])?;
        }
        let phrase = phrase_steps(&spec.phrase, spec.note, network.h());
        let frets = if spec.tune_by_ear {
            fret_map(spec, &scales, &plucks[0])?
        } else {
            SaMap::none(1)
        };
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
            frets,
            step: 0,
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
        let c = self.frets.correction(0, 12.0 * ratio.log2());
        // Kept through the retune (the string is built, and retuned, with it).
        let ei = self.network.strings()[0].params().bending_stiffness();
        // Finite and positive by the phrase's validation: cannot refuse.
        let ok = self
            .network
            .string_mut(0)
            .retune(
                self.tensions[0] * ratio * ratio * c,
                Stiffness::BendingStiffness(ei),
                Some(&ValetteLosses::default()),
                1.0,
                0.0,
            )
            .is_ok();
        debug_assert!(ok);
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.step
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

/// The played string tuned by ear at every note of `spec`'s phrase (the frets' notes and the
/// meends' targets) other than its open note, as corrections of `T ∝ f²` (`scales`: the open
/// tuning of every string). A player sets each fret's pitch by ear too: what the jawari and
/// the bridge add to the pitch changes with the string's tension (3 to 4 cents over four to
/// five semitones at 192 kHz). Control thread; one tuning of the played string per note.
fn fret_map(spec: &SitarSpec, scales: &[f64], pluck: &TrianglePluck) -> Result<SaMap, ParamError> {
    let mut notes: Vec<f64> = spec
        .phrase
        .iter()
        .flat_map(|s| std::iter::once(s.note).chain(s.meend_to))
        .chain([spec.note])
        .collect();
    notes.sort_by(f64::total_cmp);
    notes.dedup();
    // Each note is tuned on its own network: the notes share the tuning threads.
    let corrections = map_on_threads(notes.len(), tuning_threads(), |i| {
        let f = notes[i];
        if f == spec.note {
            return Ok(1.0);
        }
        let ratio2 = (f / spec.note).powi(2);
        let mut start = scales.to_vec();
        start[0] *= ratio2;
        let tuned = tune_string_by_ear(|s| spec.network(s), &start, 0, f, pluck)?;
        Ok(tuned / (scales[0] * ratio2))
    })?;
    let semitones = notes
        .iter()
        .map(|f| 12.0 * (f / spec.note).log2())
        .collect();
    Ok(SaMap::from_parts(semitones, corrections, 1))
}
