//! The sitar tuned by ear: every string at its open note (`crate::models::tanpura::tune`),
//! then the played string at its fret notes, as corrections of its `T ∝ f²` tension law
//! ([`SaMap`] over one string). A player sets each fret by ear too: what the jawari and the
//! bridge add to the pitch changes with the string's tension (3 to 4 cents over four to five
//! semitones at 192 kHz).
//!
//! A scene's phrase tunes the notes it plays; the engine's sitar tunes anchor keys around Sa
//! and reads the tuning back from the cache (`crate::models::tanpura::tuning_cache`), since at
//! 192 kHz the factory sitar's tuning takes its worker tens of seconds.
//!
//! Control or worker thread (allocates; simulates).

use super::spec::SitarSpec;
use crate::error::ParamError;
use crate::models::string::TrianglePluck;
use crate::models::tanpura::tune::{
    map_on_threads, tune_by_ear, tune_string_by_ear, tuning_threads,
};
use crate::models::tanpura::tuning_cache::{cached, CacheKey};
use crate::models::tanpura::{SaMap, TunedStrings, TuningSource};
use std::path::Path;

/// Amplitude of the pluck that tunes a taraf string by ear, m.
const TARAF_TUNING_PLUCK: f64 = 3e-4;

/// Every string's pluck: the played string's and the chikari's at the spec's position and
/// amplitude (their plucks at full strength), a taraf string's small one at 0.3 of its
/// length (the pluck that tunes it).
pub fn plucks(spec: &SitarSpec) -> Vec<TrianglePluck> {
    (0..spec.strings())
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
        .collect()
}

/// The notes (Hz) of `spec`'s phrase other than the open note: the frets' notes and the
/// meends' targets, sorted, each once.
pub fn phrase_notes(spec: &SitarSpec) -> Vec<f64> {
    let mut notes: Vec<f64> = spec
        .phrase
        .iter()
        .flat_map(|s| std::iter::once(s.note).chain(s.meend_to))
        .filter(|&f| f != spec.note)
        .collect();
    notes.sort_by(f64::total_cmp);
    notes.dedup();
    notes
}

/// `spec` tuned by ear: every string's tension scale at its open note, and the played
/// string's corrections at `frets` (Hz; other than its open note). With tuning by ear off:
/// the nominal tensions and no corrections.
pub fn tune(spec: &SitarSpec, frets: &[f64]) -> Result<TunedStrings, ParamError> {
    spec.validate()?;
    if !spec.tune_by_ear {
        return Ok(TunedStrings {
            scales: vec![1.0; spec.strings()],
            sa_map: SaMap::none(1),
        });
    }
    let plucks = plucks(spec);
    let scales = tune_by_ear(|s| spec.network(s), &spec.targets(), &plucks)?;
    let sa_map = fret_map(spec, &scales, &plucks[0], frets)?;
    Ok(TunedStrings { scales, sa_map })
}

/// [`tune`] at the anchor keys `anchors` (semitones from the open note, 0 excluded), read
/// from `dir` if an earlier build saved it, else tuned and saved. Worker thread.
pub fn tune_cached(
    spec: &SitarSpec,
    anchors: &[f64],
    dir: Option<&Path>,
) -> Result<(TunedStrings, TuningSource), ParamError> {
    spec.validate()?;
    let frets: Vec<f64> = anchors
        .iter()
        .map(|a| spec.note * (a / 12.0).exp2())
        .collect();
    if !spec.tune_by_ear {
        return Ok((tune(spec, &frets)?, TuningSource::Nominal));
    }
    let key = CacheKey {
        spec,
        prefix: "sitar",
        strings: spec.strings(),
        mapped: 1,
    };
    cached(&key, anchors, dir, || tune(spec, &frets))
}

/// The played string tuned by ear at every note of `frets` (Hz) as corrections of `T ∝ f²`
/// (`scales`: the open tuning of every string), 1 at the open note. Each note is tuned on its
/// own network: the notes share the tuning threads.
fn fret_map(
    spec: &SitarSpec,
    scales: &[f64],
    pluck: &TrianglePluck,
    frets: &[f64],
) -> Result<SaMap, ParamError> {
    let mut notes: Vec<f64> = frets.iter().copied().chain([spec.note]).collect();
    notes.sort_by(f64::total_cmp);
    notes.dedup();
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
