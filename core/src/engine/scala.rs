//! Microtuning from Scala files: a `.scl` scale and an optional `.kbm` keyboard mapping, turned
//! into the engine's key table ([`KeyTuning`]). Runs on the caller's thread (offline) or a GUI
//! thread (plugin), never on the audio thread.
//!
//! - `.scl`: read with the `tune` crate (`Scl::import`; the ratio of a scale degree,
//!   `Scl::relative_pitch_of`, periodic in the scale's last entry).
//! - `.kbm`: read here, after the Scala program's definition
//!   (<https://www.huygens-fokker.org/scala/help.htm#mappings>): map size `n`, first and last
//!   key, middle key `m` (where the mapping's first entry applies), reference key `r` and its
//!   frequency `f_r`, formal-octave degree `o` (0: the scale's size), then `n` entries, a degree
//!   or `x`. Key `k` in range: `j = k - m`, entry `e = map[j mod n]`, degree
//!   `d(k) = e + o·⌊j/n⌋` (a map size of 0 is linear: `d(k) = j`), frequency
//!   `f_r · R(d(k)) / R(d(r))`. `tune`'s own `Kbm::import` indexes the mapping from the
//!   reference key instead of the middle key, which maps other keys than Scala (and Surge's
//!   tuning library) for the common "middle 60, reference 69" files with unmapped keys, so the
//!   mapping is not taken from it.
//! - Without a `.kbm`: the scale's degree 0 on key 60 at 12-TET middle C (261.626 Hz), one
//!   degree per key (the Scala program's default).

use super::tuning::{pitch_to_hz, KeyTuning, KEY_COUNT};
use std::fmt;
use std::path::Path;
use tune::scala::Scl;

/// A tuning file (Scala `.scl` or `.kbm`) that could not be read or used: the file (or the
/// name given for the text) and what is wrong with it. Built on the thread that reads it.
#[derive(Debug, Clone, PartialEq)]
pub struct ScalaError {
    /// The file, or the name given for the text.
    pub file: String,
    /// What is wrong with it.
    pub message: String,
}

impl fmt::Display for ScalaError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "tuning file {}: {}", self.file, self.message)
    }
}

impl std::error::Error for ScalaError {}

/// A key table and what it came from.
#[derive(Debug, Clone)]
pub struct ScalaTuning {
    /// The pitch of every key (unmapped keys of the `.kbm` play nothing).
    pub table: KeyTuning,
    /// The `.scl` file's description line, and the files, for reports.
    pub description: String,
}

/// Reads `scl` (and `kbm`, if given) from disk; see [`scala_tuning`]. Errors name the file.
pub fn load_scala(scl: &Path, kbm: Option<&Path>) -> Result<ScalaTuning, ScalaError> {
    let read = |p: &Path| {
        std::fs::read_to_string(p).map_err(|e| ScalaError {
            file: p.display().to_string(),
            message: e.to_string(),
        })
    };
    let scl_text = read(scl)?;
    let kbm_text = kbm.map(read).transpose()?;
    let mut t = scala_tuning(
        &scl_text,
        kbm_text.as_deref(),
        &scl.display().to_string(),
        &kbm.map(|p| p.display().to_string()).unwrap_or_default(),
    )?;
    t.description = match kbm {
        Some(k) => format!("{} ({}, {})", t.description, scl.display(), k.display()),
        None => format!("{} ({})", t.description, scl.display()),
    };
    Ok(t)
}

/// The key table of a Scala scale (`scl_text`) and mapping (`kbm_text`; `None`: the default
/// above). `scl_name`/`kbm_name` name the sources in errors. A key whose pitch falls outside
/// the engine's range is an error naming the key (`tuning.key[k]`), its frequency and the range.
pub fn scala_tuning(
    scl_text: &str,
    kbm_text: Option<&str>,
    scl_name: &str,
    kbm_name: &str,
) -> Result<ScalaTuning, ScalaError> {
    let scl = Scl::import(scl_text.as_bytes()).map_err(|e| ScalaError {
        file: scl_name.to_string(),
        message: format!("not a Scala scale: {e:?}"),
    })?;
    let kbm = match kbm_text {
        Some(text) => Kbm::parse(text).map_err(|message| ScalaError {
            file: kbm_name.to_string(),
            message,
        })?,
        None => Kbm::default_mapping(),
    };
    let octave = if kbm.octave_degree == 0 {
        i32::from(scl.num_items())
    } else {
        kbm.octave_degree
    };
    let ratio = |d: i32| scl.relative_pitch_of(d).as_float();
    let reference = kbm
        .degree_of(kbm.reference, octave)
        .ok_or_else(|| ScalaError {
            file: kbm_name.to_string(),
            message: format!(
                "the reference key {} is unmapped (allowed: a mapped key)",
                kbm.reference
            ),
        })?;
    let base = kbm.reference_hz / ratio(reference);
    let hz: [Option<f64>; KEY_COUNT] =
        std::array::from_fn(|k| kbm.degree_of(k as i32, octave).map(|d| base * ratio(d)));
    let table = KeyTuning::from_mapped_frequencies(&hz).map_err(|e| ScalaError {
        file: scl_name.to_string(),
        message: e.to_string(),
    })?;
    Ok(ScalaTuning {
        table,
        description: scl.description().to_string(),
    })
}

/// A Scala keyboard mapping (see the module doc).
#[derive(Debug, Clone, PartialEq)]
struct Kbm {
    first: i32,
    last: i32,
    middle: i32,
    reference: i32,
    reference_hz: f64,
    octave_degree: i32,
    /// `None`: unmapped (`x`); empty: linear.
    map: Vec<Option<i32>>,
}

impl Kbm {
    /// Scala's default: linear, degree 0 on key 60 at 12-TET middle C.
    fn default_mapping() -> Self {
        Self {
            first: 0,
            last: 127,
            middle: 60,
            reference: 60,
            reference_hz: pitch_to_hz(60.0),
            octave_degree: 0,
            map: Vec::new(),
        }
    }

    /// Parses the text of a `.kbm` file: `!` starts a comment line; each value is the first
    /// word of its line. Errors name the line and the item.
    fn parse(text: &str) -> Result<Self, String> {
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim()))
            .filter(|(_, l)| !l.starts_with('!') && !l.is_empty())
            .map(|(i, l)| (i, l.split_whitespace().next().unwrap_or("")));
        let size = next_int(&mut lines, "map size", 0, 4096)? as usize;
        let first = next_int(&mut lines, "first key", 0, 127)? as i32;
        let last = next_int(&mut lines, "last key", 0, 127)? as i32;
        let middle = next_int(&mut lines, "middle key", 0, 127)? as i32;
        let reference = next_int(&mut lines, "reference key", 0, 127)? as i32;
        let (line, word) = lines
            .next()
            .ok_or("missing the reference frequency (allowed: a frequency in Hz > 0)")?;
        let reference_hz = word
            .parse::<f64>()
            .ok()
            .filter(|f| f.is_finite() && *f > 0.0)
            .ok_or_else(|| {
                format!(
                    "line {line}: reference frequency `{word}` (allowed: a frequency in Hz > 0)"
                )
            })?;
        let octave_degree = next_int(&mut lines, "formal octave degree", 0, 65_535)? as i32;
        let mut map = Vec::with_capacity(size);
        for (line, word) in lines.by_ref().take(size) {
            map.push(if word.eq_ignore_ascii_case("x") {
                None
            } else {
                Some(word.parse::<i32>().map_err(|_| {
                    format!("line {line}: mapping entry `{word}` (allowed: a scale degree or x)")
                })?)
            });
        }
        // Scala pads a short mapping with unmapped keys.
        map.resize(size, None);
        if first > last {
            return Err(format!(
                "first key {first} above last key {last} (allowed: first <= last)"
            ));
        }
        Ok(Self {
            first,
            last,
            middle,
            reference,
            reference_hz,
            octave_degree,
            map,
        })
    }

    /// The scale degree of `key` (`None`: outside the range or unmapped); `octave` is the
    /// formal octave's degree.
    fn degree_of(&self, key: i32, octave: i32) -> Option<i32> {
        if !(self.first..=self.last).contains(&key) {
            return None;
        }
        let j = key - self.middle;
        if self.map.is_empty() {
            return Some(j);
        }
        let n = self.map.len() as i32;
        self.map[j.rem_euclid(n) as usize].map(|e| e + octave * j.div_euclid(n))
    }
}

/// The next value of a `.kbm` file as an integer from `lo` to `hi` (`what` names it in errors).
fn next_int<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
    what: &str,
    lo: i64,
    hi: i64,
) -> Result<i64, String> {
    let (line, word) = lines
        .next()
        .ok_or_else(|| format!("missing the {what} (allowed: an integer from {lo} to {hi})"))?;
    word.parse::<i64>()
        .ok()
        .filter(|v| (lo..=hi).contains(v))
        .ok_or_else(|| {
            format!("line {line}: {what} `{word}` (allowed: an integer from {lo} to {hi})")
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    const NINETEEN_EDO: &str = "! 19-edo.scl\n19 equal divisions of the octave\n 19\n!\n";

    fn edo19() -> String {
        let steps: Vec<String> = (1..=19)
            .map(|i| format!(" {:.10}", 1200.0 * i as f64 / 19.0))
            .collect();
        format!("{NINETEEN_EDO}{}\n", steps.join("\n"))
    }

    #[test]
    fn nineteen_edo_steps_by_a_nineteenth_of_an_octave_from_middle_c() {
        let t = scala_tuning(&edo19(), None, "19-edo.scl", "").unwrap();
        assert_eq!(t.description, "19 equal divisions of the octave");
        // Key 60 at middle C exactly (to the rounding of log2/exp2: 1e-12 semitones), each
        // key 12/19 semitones above the previous, 19 keys an octave.
        assert!((t.table.pitch(60) - 60.0).abs() < 1e-12);
        for k in 40..100u8 {
            let want = 60.0 + (f64::from(k) - 60.0) * 12.0 / 19.0;
            assert!((t.table.pitch(k) - want).abs() < 1e-9, "key {k}");
        }
        assert_eq!(t.table.mapped_keys(), KEY_COUNT);
    }

    #[test]
    fn a_kbm_maps_white_keys_and_leaves_others_out() {
        // Map size 12, keys 0-127, middle note 60, reference 69 at 432 Hz, octave degree 7:
        // the seven white keys take degrees 0-6 of a 7-note scale, black keys unmapped.
        let kbm = "12\n0\n127\n60\n69\n432.0\n7\n0\nx\n1\nx\n2\n3\nx\n4\nx\n5\nx\n6\n";
        let scl = "! just.scl\nJust major\n 7\n!\n 9/8\n 5/4\n 4/3\n 3/2\n 5/3\n 15/8\n 2/1\n";
        let t = scala_tuning(scl, Some(kbm), "just.scl", "white.kbm").unwrap();
        assert!(!t.table.is_mapped(61) && !t.table.is_mapped(63) && t.table.is_mapped(64));
        // Key 69 is the reference (432 Hz, degree 5 = 5/3 above key 60); key 64 is 5/4.
        assert!((t.table.frequency(69) / 432.0 - 1.0).abs() < 1e-12);
        let c = 432.0 / (5.0 / 3.0);
        assert!((t.table.frequency(64) / (c * 5.0 / 4.0) - 1.0).abs() < 1e-12);
        assert!((t.table.frequency(72) / (2.0 * c) - 1.0).abs() < 1e-12);
        // Below the middle key: key 59 (B) is entry 11, degree 6 one formal octave down.
        assert!((t.table.frequency(59) / (c * 15.0 / 16.0) - 1.0).abs() < 1e-12);
        // The same mapping with its reference on an unmapped key is refused.
        let bad = kbm.replace("\n69\n432.0", "\n70\n432.0");
        let e = scala_tuning(scl, Some(&bad), "just.scl", "white.kbm").unwrap_err();
        assert!(
            e.to_string().contains("reference key 70 is unmapped"),
            "{e}"
        );
    }

    #[test]
    fn bad_files_are_errors_naming_the_file() {
        let e = scala_tuning("not a scale", None, "bad.scl", "").unwrap_err();
        assert!(e.to_string().contains("bad.scl"), "{e}");
        let e = scala_tuning(&edo19(), Some("12\n0\n"), "19-edo.scl", "bad.kbm").unwrap_err();
        assert!(e.to_string().contains("bad.kbm"), "{e}");
        // A scale whose step is 1200 cents (each key an octave) leaves the engine's range:
        // the error names a key and its frequency.
        let e = scala_tuning("! o.scl\noctaves\n 1\n!\n 2/1\n", None, "o.scl", "").unwrap_err();
        assert!(e.to_string().contains("tuning.key["), "{e}");
    }
}
