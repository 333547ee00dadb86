//! The drone's (and the sitar's, `crate::models::sitar::tuning`) tuning by ear, kept on
//! disk: each tuning simulates every string for
//! `TUNE_PASSES` seconds (`super::tune`), so the factory drone, tuned at 25 keys, takes its
//! worker about 55 s of CPU (four alias-free strings at 48 kHz). The result depends on nothing but the
//! spec and the anchor keys, and it is a few numbers per string, so it is saved beside the
//! plates' modal bases (`crate::modal::circular::default_cache_dir`) and read back by the
//! next build of the same drone.
//!
//! A file holds the spec and the anchors it was tuned for, the tension scales at Sa and the
//! corrections at the anchors ([`TunedStrings`]), as TOML (`f64`s written in their shortest
//! round-trip form, so they read back bit for bit). It is named by a hash of the spec and
//! anchors and trusted only if the spec and anchors it holds are equal to those asked for and
//! its numbers are finite, positive and of the right count; anything else is tuned again
//! and the file rewritten (atomically: a temporary file, then a rename). A file that cannot
//! be written leaves the tuning valid.
//!
//! Worker (or control) thread: file I/O and allocation.

use super::key_map::SaMap;
use super::spec::TanpuraSpec;
use super::tune::tension_scales;
use crate::error::ParamError;
use crate::modal::circular::cache::{hash_words, write_atomic};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Version of the file layout and of the tuning method; bump it when either changes.
pub const TUNING_CACHE_VERSION: u32 = 1;

/// What a drone's strings were tuned to: plain data, built on the worker, moved into the drone.
#[derive(Debug, Clone, PartialEq)]
pub struct TunedStrings {
    /// Per string, the tension over its nominal tension at Sa.
    pub scales: Vec<f64>,
    /// Per string, the corrections at the anchor keys.
    pub sa_map: SaMap,
}

/// Where a tuning came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TuningSource {
    /// Read from the cache.
    Cached,
    /// Tuned by ear now (and saved, if the cache could be written).
    Tuned,
    /// Tuning by ear is off for the spec: nominal tensions, nothing simulated.
    Nominal,
}

/// The file's contents: the tuning of the instrument whose tuning key is `spec`.
#[derive(Debug, Serialize, Deserialize)]
struct TuningFile<S> {
    version: u32,
    anchors: Vec<f64>,
    scales: Vec<f64>,
    semitones: Vec<f64>,
    corrections: Vec<f64>,
    spec: S,
}

/// What a cached tuning is of: the instrument's tuning key (the part of its spec the tuning
/// depends on, written into the file and compared on reading), the file names' prefix, and
/// how many strings the tuning holds: tension scales (`strings`) and strings mapped over the
/// anchor keys (`mapped`).
pub(crate) struct CacheKey<'a, S> {
    /// The tuning key.
    pub spec: &'a S,
    /// The file names' prefix (`"tanpura"`, `"sitar"`).
    pub prefix: &'a str,
    /// Strings with a tension scale.
    pub strings: usize,
    /// Strings with corrections at the anchors.
    pub mapped: usize,
}

/// Tunes `spec` by ear at its Sa and at `anchors` (semitones, [`SaMap::tune`]), or reads the
/// result from `dir` where an earlier build saved it; saves what it tuned. Worker thread.
pub fn tune_cached(
    spec: &TanpuraSpec,
    anchors: &[f64],
    dir: Option<&Path>,
) -> Result<(TunedStrings, TuningSource), ParamError> {
    spec.validate()?;
    if !spec.tune_by_ear {
        return Ok((
            TunedStrings {
                scales: vec![1.0; spec.strings],
                sa_map: SaMap::none(spec.strings),
            },
            TuningSource::Nominal,
        ));
    }
    let key = tuning_key(spec);
    cached(&drone_key(&key, spec), anchors, dir, || {
        let scales = tension_scales(spec)?;
        let sa_map = if anchors.is_empty() {
            SaMap::none(spec.strings)
        } else {
            SaMap::tune(spec, &scales, anchors)?
        };
        Ok(TunedStrings { scales, sa_map })
    })
}

/// The tuning of `key` at `anchors` read from `dir`, or else `tune()`d and saved there (a
/// cache that cannot be written costs the next build its time, nothing else). Worker thread.
pub(crate) fn cached<S: Serialize + DeserializeOwned + PartialEq>(
    key: &CacheKey<'_, S>,
    anchors: &[f64],
    dir: Option<&Path>,
    tune: impl FnOnce() -> Result<TunedStrings, ParamError>,
) -> Result<(TunedStrings, TuningSource), ParamError> {
    let path = dir.map(|d| d.join(file_name_of(key, anchors)));
    if let Some(tuned) = path.as_deref().and_then(|p| read_of(p, key, anchors)) {
        return Ok((tuned, TuningSource::Cached));
    }
    let tuned = tune()?;
    if let Some(p) = &path {
        let _ = write_of(p, key, anchors, &tuned);
    }
    Ok((tuned, TuningSource::Tuned))
}

/// The part of `spec` a tuning depends on: the cycle (its period, pattern, variation and seed)
/// plays no part in tuning by ear (each string is plucked alone, `super::tune`), so a drone
/// that differs only there shares its tuning.
fn tuning_key(spec: &TanpuraSpec) -> TanpuraSpec {
    let at = TanpuraSpec::at(spec.sa);
    TanpuraSpec {
        cycle_seconds: at.cycle_seconds,
        pattern: at.pattern,
        timing_jitter_ms: at.timing_jitter_ms,
        strength_jitter: at.strength_jitter,
        seed: at.seed,
        ..spec.clone()
    }
}

/// The cache file's name for the drone `spec`: a hash of its tuning key ([`tuning_key`])
/// and the anchors as they are written.
pub fn file_name(spec: &TanpuraSpec, anchors: &[f64]) -> String {
    let key = tuning_key(spec);
    file_name_of(&drone_key(&key, spec), anchors)
}

/// The cache key of the drone `spec` whose tuning key is `key`.
fn drone_key<'a>(key: &'a TanpuraSpec, spec: &TanpuraSpec) -> CacheKey<'a, TanpuraSpec> {
    CacheKey {
        spec: key,
        prefix: "tanpura",
        strings: spec.strings,
        mapped: spec.strings,
    }
}

/// The cache file's name: the prefix, a hash of the tuning key and the anchors as they are
/// written.
pub(crate) fn file_name_of<S: Serialize>(key: &CacheKey<'_, S>, anchors: &[f64]) -> String {
    let mut bytes = toml::to_string(key.spec).unwrap_or_default().into_bytes();
    bytes.extend(anchors.iter().flat_map(|a| a.to_bits().to_le_bytes()));
    let h = hash_words(&bytes);
    format!(
        "{}-tuning-{h:016x}-v{TUNING_CACHE_VERSION}.toml",
        key.prefix
    )
}

/// The file at `path`, if it holds a valid tuning of exactly the drone `spec` and `anchors`.
#[cfg(test)]
fn read(path: &Path, spec: &TanpuraSpec, anchors: &[f64]) -> Option<TunedStrings> {
    let key = tuning_key(spec);
    read_of(path, &drone_key(&key, spec), anchors)
}

/// The file at `path`, if it holds a valid tuning of exactly `key` and `anchors`.
fn read_of<S: DeserializeOwned + PartialEq>(
    path: &Path,
    key: &CacheKey<'_, S>,
    anchors: &[f64],
) -> Option<TunedStrings> {
    let text = std::fs::read_to_string(path).ok()?;
    let f: TuningFile<S> = toml::from_str(&text).ok()?;
    let good = |x: &f64| x.is_finite() && *x > 0.0;
    let valid = f.version == TUNING_CACHE_VERSION
        && f.spec == *key.spec
        && f.anchors.len() == anchors.len()
        && f.anchors
            .iter()
            .zip(anchors)
            .all(|(a, b)| a.to_bits() == b.to_bits())
        && f.scales.len() == key.strings
        && f.scales.iter().all(good)
        && !f.semitones.is_empty()
        && f.semitones.iter().all(|s| s.is_finite())
        && f.semitones.windows(2).all(|w| w[0] < w[1])
        && f.semitones.contains(&0.0)
        && f.corrections.len() == f.semitones.len() * key.mapped
        && f.corrections.iter().all(good);
    valid.then(|| TunedStrings {
        scales: f.scales,
        sa_map: SaMap::from_parts(f.semitones, f.corrections, key.mapped),
    })
}

/// Writes `tuned` to `path` atomically (a temporary file, then a rename).
fn write_of<S: Serialize>(
    path: &Path,
    key: &CacheKey<'_, S>,
    anchors: &[f64],
    tuned: &TunedStrings,
) -> std::io::Result<()> {
    let (semitones, corrections) = tuned.sa_map.parts();
    let f = TuningFile {
        version: TUNING_CACHE_VERSION,
        anchors: anchors.to_vec(),
        scales: tuned.scales.clone(),
        semitones: semitones.to_vec(),
        corrections: corrections.to_vec(),
        spec: key.spec,
    };
    let text = toml::to_string(&f).map_err(std::io::Error::other)?;
    write_atomic(path, text.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tuning saved and read back is the same bit for bit; a different spec is not read
    /// from another spec's file; a corrupted file is tuned again and rewritten.
    #[test]
    fn a_saved_tuning_reads_back_exactly_and_only_for_its_spec() {
        let dir = std::env::temp_dir().join(format!("noether-tuning-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        // A small drone: 64 modes at 16 kHz, the jivari taken out (its node needs a fine grid).
        let spec = TanpuraSpec {
            modes: 64,
            sim_rate: 16_000.0,
            jivari_mm: vec![0.0],
            ..TanpuraSpec::at(200.0)
        };
        let anchors = [-6.0, 6.0];
        let (first, src) = tune_cached(&spec, &anchors, Some(&dir)).expect("tunes");
        assert_eq!(src, TuningSource::Tuned);
        let (again, src) = tune_cached(&spec, &anchors, Some(&dir)).expect("reads");
        assert_eq!(src, TuningSource::Cached);
        assert_eq!(first, again);
        let other = TanpuraSpec {
            sa: 201.0,
            ..spec.clone()
        };
        assert_ne!(file_name(&spec, &anchors), file_name(&other, &anchors));
        let path = dir.join(file_name(&spec, &anchors));
        assert!(read(&path, &other, &anchors).is_none());
        assert!(read(&path, &spec, &[-6.0]).is_none());
        // Another cycle shares the tuning.
        let cycle = TanpuraSpec {
            cycle_seconds: 7.0,
            timing_jitter_ms: 10.0,
            ..spec.clone()
        };
        assert_eq!(file_name(&spec, &anchors), file_name(&cycle, &anchors));
        assert_eq!(read(&path, &cycle, &anchors), Some(first.clone()));
        std::fs::write(&path, "version = 1\nscales = [\"x\"]").expect("write");
        let (retuned, src) = tune_cached(&spec, &anchors, Some(&dir)).expect("tunes again");
        assert_eq!(src, TuningSource::Tuned);
        assert_eq!(retuned, first);
        assert!(read(&path, &spec, &anchors).is_some());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
