//! Microtuning: the pitch of every MIDI key, as a table the host or GUI thread writes and the
//! audio thread reads without locks.
//!
//! A key's pitch is a fractional MIDI note number `p` (semitones; 69 is 440 Hz before the
//! `tuning_a4` parameter scales it): 12-tone equal temperament is `p(k) = k`. The voices take
//! the pitch ratio `2^((p(k) - root + bend)/12) · a4/440` to the preset's root key (see
//! `voice::mapping`), so a table changes which pitch each key plays and nothing else: the root
//! key keeps the preset's model, and the A4 parameter still transposes the whole table.
//!
//! Tables come from frequencies (a Scala `.scl`/`.kbm` pair read with the `tune` crate by the
//! offline crate or the plugin, off the audio thread) through [`KeyTuning::from_frequencies`].

use crate::error::ParamError;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

/// Number of MIDI keys (0 to 127).
pub const KEY_COUNT: usize = 128;

/// Lowest pitch a table may give a key (fractional MIDI note number): 8.18 Hz at key 0 in
/// 12-TET is 0; -36 is three octaves lower (1.02 Hz), below any audible fundamental.
pub const MIN_KEY_PITCH: f64 = -36.0;
/// Highest pitch a table may give a key: 12-TET's key 127 is 12.5 kHz; 163 is three octaves
/// higher (100 kHz). The engine's pitch ratio is checked again by each model at note-on.
pub const MAX_KEY_PITCH: f64 = 163.0;

/// The pitch of every MIDI key (fractional MIDI note numbers), or none for a key the mapping
/// leaves out (it plays nothing). `Copy` data, any thread.
#[derive(Debug, Clone, Copy)]
pub struct KeyTuning {
    /// `NaN` marks an unmapped key.
    pitch: [f64; KEY_COUNT],
}

impl PartialEq for KeyTuning {
    /// Equal pitches and the same unmapped keys (bitwise, so `NaN` equals itself).
    fn eq(&self, other: &Self) -> bool {
        self.pitch
            .iter()
            .zip(&other.pitch)
            .all(|(a, b)| a.to_bits() == b.to_bits())
    }
}

impl Default for KeyTuning {
    fn default() -> Self {
        Self::equal()
    }
}

impl KeyTuning {
    /// 12-tone equal temperament: key `k` plays pitch `k`.
    pub fn equal() -> Self {
        Self {
            pitch: std::array::from_fn(|k| k as f64),
        }
    }

    /// A table from fractional MIDI note numbers. Errors name the key (`tuning.key[k]`), its
    /// value and the allowed range [`MIN_KEY_PITCH`] to [`MAX_KEY_PITCH`]; `NaN` and infinities
    /// are refused. Any thread (no allocation on success).
    pub fn from_pitches(pitch: &[f64; KEY_COUNT]) -> Result<Self, ParamError> {
        for (k, &p) in pitch.iter().enumerate() {
            if !(MIN_KEY_PITCH..=MAX_KEY_PITCH).contains(&p) {
                return Err(ParamError::new(
                    format!("tuning.key[{k}]"),
                    p,
                    format!("a pitch from {MIN_KEY_PITCH} to {MAX_KEY_PITCH} (MIDI note numbers)"),
                ));
            }
        }
        Ok(Self { pitch: *pitch })
    }

    /// A table from the frequency (Hz) of every key: `p = 69 + 12 log2(f / 440)`. Errors as
    /// [`Self::from_pitches`], naming the frequency (`tuning.key[k]` in Hz, finite and within
    /// 1.02 Hz to 100 kHz). Any thread.
    pub fn from_frequencies(hz: &[f64; KEY_COUNT]) -> Result<Self, ParamError> {
        let lo = pitch_to_hz(MIN_KEY_PITCH);
        let hi = pitch_to_hz(MAX_KEY_PITCH);
        for (k, &f) in hz.iter().enumerate() {
            if !(lo..=hi).contains(&f) {
                return Err(ParamError::new(
                    format!("tuning.key[{k}]"),
                    f,
                    format!("a frequency from {lo:.3} Hz to {hi:.0} Hz"),
                ));
            }
        }
        Self::from_pitches(&std::array::from_fn(|k| hz_to_pitch(hz[k])))
    }

    /// A table where `None` leaves a key unmapped (silent); the pitches are checked as in
    /// [`Self::from_frequencies`]. Any thread.
    pub fn from_mapped_frequencies(hz: &[Option<f64>; KEY_COUNT]) -> Result<Self, ParamError> {
        let mapped: [f64; KEY_COUNT] = std::array::from_fn(|k| hz[k].unwrap_or(440.0));
        let mut t = Self::from_frequencies(&mapped)?;
        for (p, f) in t.pitch.iter_mut().zip(hz) {
            if f.is_none() {
                *p = f64::NAN;
            }
        }
        Ok(t)
    }

    /// Whether `key` plays (false for a key the mapping leaves out).
    pub fn is_mapped(&self, key: u8) -> bool {
        !self.pitch(key).is_nan()
    }

    /// Number of keys that play.
    pub fn mapped_keys(&self) -> usize {
        self.pitch.iter().filter(|p| !p.is_nan()).count()
    }

    /// The pitch of `key` (fractional MIDI note number; `NaN` when unmapped; keys above 127
    /// take key 127's).
    pub fn pitch(&self, key: u8) -> f64 {
        self.pitch[usize::from(key).min(KEY_COUNT - 1)]
    }

    /// The frequency (Hz) of `key` before the `tuning_a4` parameter scales it (`NaN` when
    /// unmapped).
    pub fn frequency(&self, key: u8) -> f64 {
        pitch_to_hz(self.pitch(key))
    }

    /// Whether this is 12-tone equal temperament exactly.
    pub fn is_equal(&self) -> bool {
        *self == Self::equal()
    }
}

/// Fractional MIDI note number of `hz` (69 at 440 Hz).
pub fn hz_to_pitch(hz: f64) -> f64 {
    69.0 + 12.0 * (hz / 440.0).log2()
}

/// Frequency (Hz) of a fractional MIDI note number.
pub fn pitch_to_hz(pitch: f64) -> f64 {
    440.0 * ((pitch - 69.0) / 12.0).exp2()
}

/// The key table shared by the host or GUI thread (writer) and the audio thread (reader).
///
/// A sequence lock over 128 atomics: the writer makes the sequence odd, stores the pitches,
/// then makes it even again; the reader takes a table only when the sequence was even and
/// unchanged across its reads, else keeps its previous table and tries again at its next
/// block. Writers are serialised by a mutex the audio thread never touches. Reads are
/// wait-free and bounded (one pass over 128 values).
#[derive(Debug)]
pub struct SharedTuning {
    pitch: [AtomicU64; KEY_COUNT],
    sequence: AtomicU64,
    writer: Mutex<()>,
}

impl Default for SharedTuning {
    fn default() -> Self {
        Self::new(&KeyTuning::equal())
    }
}

impl SharedTuning {
    /// A shared table holding `t`.
    pub fn new(t: &KeyTuning) -> Self {
        Self {
            pitch: std::array::from_fn(|k| AtomicU64::new(t.pitch[k].to_bits())),
            sequence: AtomicU64::new(0),
            writer: Mutex::new(()),
        }
    }

    /// Publishes `t` (host or GUI thread; never the audio thread: it takes the writers' lock).
    pub fn set(&self, t: &KeyTuning) {
        let _guard = self.writer.lock().unwrap_or_else(|e| e.into_inner());
        self.sequence.fetch_add(1, Ordering::AcqRel);
        for (slot, p) in self.pitch.iter().zip(t.pitch) {
            slot.store(p.to_bits(), Ordering::Release);
        }
        self.sequence.fetch_add(1, Ordering::AcqRel);
    }

    /// The sequence number: even when no write is in progress, and changed by every write.
    pub fn sequence(&self) -> u64 {
        self.sequence.load(Ordering::Acquire)
    }

    /// The table, if it changed since `seen` and no write is in progress; `seen` is updated.
    /// Audio thread: wait-free, no allocation. `None` means keep the table you have.
    pub fn read_if_changed(&self, seen: &mut u64) -> Option<KeyTuning> {
        let before = self.sequence.load(Ordering::Acquire);
        if before == *seen || before % 2 == 1 {
            return None;
        }
        let pitch = std::array::from_fn(|k| f64::from_bits(self.pitch[k].load(Ordering::Acquire)));
        if self.sequence.load(Ordering::Acquire) != before {
            return None;
        }
        *seen = before;
        Some(KeyTuning { pitch })
    }

    /// The current table (any thread other than the writer's; waits for a write in progress,
    /// so not for the audio thread).
    pub fn get(&self) -> KeyTuning {
        let _guard = self.writer.lock().unwrap_or_else(|e| e.into_inner());
        KeyTuning {
            pitch: std::array::from_fn(|k| f64::from_bits(self.pitch[k].load(Ordering::Acquire))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_temperament_is_the_identity_and_a4_is_440() {
        let t = KeyTuning::equal();
        assert_eq!(t.pitch(60), 60.0);
        assert_eq!(t.frequency(69), 440.0);
        // 12-TET key 60 to 1e-12 relative (exp2 and log2 are within an ulp or two).
        assert!((t.frequency(60) / 261.625_565_300_598_6 - 1.0).abs() < 1e-12);
        assert!(t.is_equal());
    }

    #[test]
    fn frequencies_round_trip_and_bad_values_name_the_key() {
        let hz: [f64; KEY_COUNT] = std::array::from_fn(|k| 100.0 * (1.0 + k as f64 / 10.0));
        let t = KeyTuning::from_frequencies(&hz).unwrap();
        for k in 0..KEY_COUNT as u8 {
            // Round trip through log2 and exp2: a few ulps.
            assert!((t.frequency(k) / hz[usize::from(k)] - 1.0).abs() < 1e-13);
        }
        let mut bad = hz;
        bad[7] = f64::NAN;
        let e = KeyTuning::from_frequencies(&bad).unwrap_err();
        assert!(e.to_string().contains("tuning.key[7]"), "{e}");
        bad[7] = 0.5;
        let e = KeyTuning::from_frequencies(&bad).unwrap_err();
        assert!(
            e.to_string().contains("tuning.key[7]") && e.to_string().contains("0.5"),
            "{e}"
        );
        let mut p = [60.0; KEY_COUNT];
        p[127] = 200.0;
        let e = KeyTuning::from_pitches(&p).unwrap_err();
        assert!(e.to_string().contains("tuning.key[127]"), "{e}");
    }

    #[test]
    fn a_reader_sees_each_write_once() {
        let s = SharedTuning::default();
        let mut seen = s.sequence();
        assert!(s.read_if_changed(&mut seen).is_none());
        let t = KeyTuning::from_pitches(&std::array::from_fn(|k| k as f64 + 0.5)).unwrap();
        s.set(&t);
        assert_eq!(s.read_if_changed(&mut seen), Some(t));
        assert!(s.read_if_changed(&mut seen).is_none());
        assert_eq!(s.get(), t);
    }

    #[test]
    fn unmapped_keys_are_kept_and_counted() {
        let mut hz = [Some(440.0); KEY_COUNT];
        hz[61] = None;
        let t = KeyTuning::from_mapped_frequencies(&hz).unwrap();
        assert!(!t.is_mapped(61) && t.is_mapped(60));
        assert_eq!(t.mapped_keys(), 127);
        let s = SharedTuning::default();
        s.set(&t);
        assert_eq!(s.get(), t);
        assert!(!s.get().is_equal());
    }

    #[test]
    fn a_reader_never_sees_a_torn_table() {
        // Two tables whose entries all differ; the writer alternates them 20 000 times while
        // the reader takes every table it can, each of which must be one of the two, whole.
        // After the writer ends, the reader catches up with the last table (it may have taken
        // it already: then there is nothing new). How
        // many reads overlapped writes depends on the scheduler, so it is printed, not
        // asserted; without the sequence check, tables mixing both appear in most runs.
        let s = std::sync::Arc::new(SharedTuning::default());
        let a = KeyTuning::equal();
        let b = KeyTuning::from_pitches(&std::array::from_fn(|k| k as f64 + 0.25)).unwrap();
        let w = {
            let s = s.clone();
            std::thread::spawn(move || {
                for i in 0..20_000 {
                    s.set(if i % 2 == 0 { &b } else { &a });
                }
            })
        };
        let mut seen = s.sequence();
        let mut during = 0;
        while !w.is_finished() {
            if let Some(t) = s.read_if_changed(&mut seen) {
                assert!(t == a || t == b, "torn table");
                during += 1;
            }
        }
        w.join().unwrap();
        println!("{during} tables taken while the writer ran");
        let last = s.read_if_changed(&mut seen);
        assert!(last.is_none() || last == Some(a));
        assert_eq!(seen, s.sequence());
    }
}
