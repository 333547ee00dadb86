//! The soak's random choices: parameter values over their whole range (extremes included),
//! block sizes, host rates and the note storm of one block. Seeded (PCG through `oorandom`),
//! so a seed names one sequence of choices; the worker thread's timing still varies the run.
//!
//! Threads: everything here runs on the thread driving the engine, between blocks (it
//! allocates only the event vector's growth, outside `process`).

use noether_core::engine::voice::modulation::POLY_PARAMS;
use noether_core::engine::{
    Event, EventKind, NoteExpression, ParamInfo, ParamKind, MAX_NOTE_TUNING, MAX_NOTE_VOLUME,
};
use oorandom::Rand64;

/// Probability that a drawn parameter value is exactly its minimum (and, separately, its
/// maximum): the extremes of the table are hit about every fifth draw.
pub const EXTREME_CHANCE: f64 = 0.1;

/// A seeded source of the soak's choices. Driver thread only.
pub struct Draw(Rand64);

impl Draw {
    /// The sequence named by `seed`.
    pub fn new(seed: u64) -> Self {
        Self(Rand64::new(seed as u128))
    }

    /// Uniform in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        self.0.rand_float()
    }

    /// `true` with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }

    /// Uniform integer in `[0, n)` (`n ≥ 1`).
    pub fn below(&mut self, n: u64) -> u64 {
        self.0.rand_range(0..n.max(1))
    }

    /// Uniform in `[lo, hi)`.
    pub fn between(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Log-uniform in `[lo, hi)` (`0 < lo ≤ hi`).
    pub fn log_between(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.unit()).exp()
    }

    /// One element of `xs` (non-empty).
    pub fn pick<T: Copy>(&mut self, xs: &[T]) -> T {
        xs[self.below(xs.len() as u64) as usize]
    }

    /// A value of parameter `p` anywhere in its range `[min, max]`: exactly `min` or exactly
    /// `max` with probability [`EXTREME_CHANCE`] each, otherwise uniform (log-uniform for
    /// logarithmic ranges); integers and enumerations are rounded. Always accepted by
    /// [`ParamInfo::check`] (the `f32` rounding of a log draw is kept inside the range).
    pub fn value(&mut self, p: &ParamInfo) -> f32 {
        let (lo, hi) = (p.min as f64, p.max as f64);
        let u = self.unit();
        let x = if u < EXTREME_CHANCE {
            lo
        } else if u < 2.0 * EXTREME_CHANCE {
            hi
        } else {
            match p.kind {
                ParamKind::Float { log: true } if lo > 0.0 => self.log_between(lo, hi),
                ParamKind::Float { .. } => self.between(lo, hi),
                ParamKind::Int | ParamKind::Enum { .. } => self.between(lo, hi + 1.0).floor(),
            }
        };
        (x as f32).clamp(p.min, p.max)
    }

    /// A block length in `[1, max_block]`: exactly 1 or exactly `max_block` with probability
    /// 0.05 each, otherwise log-uniform (short blocks are as common as long ones per decade).
    pub fn block(&mut self, max_block: usize) -> usize {
        let u = self.unit();
        if u < 0.05 {
            1
        } else if u < 0.1 {
            max_block
        } else {
            (self.log_between(1.0, max_block as f64 + 1.0) as usize).clamp(1, max_block)
        }
    }
}

/// Counts of the events the storm generated.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct StormCounts {
    /// Note-ons with a velocity above zero.
    pub note_ons: u64,
    /// Note-ons with velocity 0 (MIDI's note-off spelling).
    pub zero_velocity: u64,
    /// Note-offs.
    pub note_offs: u64,
    /// Pitch-bend, mod-wheel and sustain events.
    pub controllers: u64,
    /// All-notes-off and all-sound-off events.
    pub panics: u64,
    /// Per-note expressions (tuning, volume, pressure, pan, brightness) and per-note parameter
    /// values (polyphonic modulation).
    pub per_note: u64,
}

/// The note storm: note-ons and note-offs at a mean rate, on every key, at random offsets in
/// the block, with pitch bend, mod wheel and sustain, per-note expressions and per-note
/// parameter values. Driver thread only.
pub struct Storm {
    /// Mean note-ons per second of host time (and as many note-offs).
    pub notes_per_second: f64,
    /// Events generated so far.
    pub counts: StormCounts,
}

impl Storm {
    /// A storm of `notes_per_second` note-ons (and note-offs) per second.
    pub fn new(notes_per_second: f64) -> Self {
        Self {
            notes_per_second,
            counts: StormCounts::default(),
        }
    }

    /// Replaces `out` with the events of one block of `n` samples at `rate` Hz, sorted by
    /// offset (stable: events at one offset keep their order). The number of note-ons is the
    /// mean `notes_per_second · n / rate` rounded up or down at random (its expectation is
    /// the mean); velocities are uniform in `[0, 1]` with the ends drawn exactly 1 time in 20.
    pub fn fill(&mut self, d: &mut Draw, n: usize, rate: f64, out: &mut Vec<Event>) {
        out.clear();
        let mean = self.notes_per_second * n as f64 / rate;
        let count = mean.floor() as u64 + u64::from(d.chance(mean.fract()));
        let at = |d: &mut Draw| d.below(n as u64) as u32;
        for _ in 0..count {
            let key = d.below(128) as u8;
            let velocity = match d.unit() {
                u if u < 0.05 => 0.0,
                u if u < 0.1 => 1.0,
                _ => d.unit() as f32,
            };
            if velocity > 0.0 {
                self.counts.note_ons += 1;
            } else {
                self.counts.zero_velocity += 1;
            }
            out.push(Event::new(at(d), EventKind::NoteOn { key, velocity }));
            let off = d.below(128) as u8;
            out.push(Event::new(at(d), EventKind::NoteOff { key: off }));
            self.counts.note_offs += 1;
        }
        let extreme = |d: &mut Draw, lo: f32, hi: f32| match d.unit() {
            u if u < 0.1 => lo,
            u if u < 0.2 => hi,
            _ => d.between(lo as f64, hi as f64) as f32,
        };
        if d.chance(0.5) {
            let x = extreme(d, -1.0, 1.0);
            out.push(Event::new(at(d), EventKind::PitchBend(x)));
            self.counts.controllers += 1;
        }
        if d.chance(0.5) {
            let x = extreme(d, 0.0, 1.0);
            out.push(Event::new(at(d), EventKind::ModWheel(x)));
            self.counts.controllers += 1;
        }
        if d.chance(0.1) {
            let down = d.chance(0.5);
            out.push(Event::new(at(d), EventKind::Sustain(down)));
            self.counts.controllers += 1;
        }
        // Per-note expressions and values on a random key (most keys sound nothing: then
        // they are ignored), at their extremes one time in five.
        if d.chance(0.5) {
            let key = d.below(128) as u8;
            let expression = match d.below(5) {
                0 => NoteExpression::Tuning(extreme(d, -MAX_NOTE_TUNING, MAX_NOTE_TUNING)),
                1 => NoteExpression::Volume(extreme(d, 0.0, MAX_NOTE_VOLUME)),
                2 => NoteExpression::Pressure(extreme(d, 0.0, 1.0)),
                3 => NoteExpression::Pan(extreme(d, 0.0, 1.0)),
                _ => NoteExpression::Brightness(extreme(d, 0.0, 1.0)),
            };
            out.push(Event::new(
                at(d),
                EventKind::NoteExpression { key, expression },
            ));
            self.counts.per_note += 1;
        }
        if d.chance(0.5) {
            let key = d.below(128) as u8;
            let param = POLY_PARAMS[d.below(POLY_PARAMS.len() as u64) as usize];
            let info = param.info();
            let value = extreme(d, info.min, info.max);
            out.push(Event::new(
                at(d),
                EventKind::NoteModulation { key, param, value },
            ));
            self.counts.per_note += 1;
        }
        if d.chance(0.002) {
            let k = if d.chance(0.5) {
                EventKind::AllNotesOff
            } else {
                EventKind::AllSoundOff
            };
            out.push(Event::new(at(d), k));
            self.counts.panics += 1;
        }
        out.sort_by_key(|e| e.offset);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use noether_core::engine::PARAMS;

    #[test]
    fn values_stay_in_range_and_hit_the_extremes() {
        let mut d = Draw::new(7);
        for p in PARAMS {
            let (mut lo, mut hi) = (false, false);
            for _ in 0..400 {
                let x = d.value(p);
                p.check(x).unwrap();
                lo |= x == p.min;
                hi |= x == p.max;
            }
            // P(missing one end in 400 draws) = 0.9^400 ≈ 5e-19.
            assert!(lo && hi, "{}", p.key);
        }
    }

    #[test]
    fn storm_rate_and_order() {
        let mut d = Draw::new(3);
        let mut s = Storm::new(300.0);
        let mut ev = Vec::new();
        let (n, rate, blocks) = (500, 48_000.0, 2000);
        for _ in 0..blocks {
            s.fill(&mut d, n, rate, &mut ev);
            assert!(ev.windows(2).all(|w| w[0].offset <= w[1].offset));
            assert!(ev.iter().all(|e| (e.offset as usize) < n));
        }
        // Mean 3.125 a block: 3 plus a Bernoulli(0.125) each block, so 6250 expected over
        // 2000 blocks with standard deviation √(2000 · 0.125 · 0.875) ≈ 15; ±100 is 6.8 σ.
        let notes = s.counts.note_ons + s.counts.zero_velocity;
        assert!((notes as i64 - 6250).abs() < 100, "{notes}");
        assert_eq!(s.counts.note_offs, notes);
    }
}
