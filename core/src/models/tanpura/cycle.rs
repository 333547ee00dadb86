//! The pluck cycle: when each string is plucked, and how hard.
//!
//! A cycle of `period` seconds plucks the strings in order at fixed fractions of the period:
//! `Classic` is the usual tanpura rhythm, the strings one after another at equal gaps with a
//! pause of twice a gap before the cycle repeats (4 strings: 0, 1/5, 2/5, 3/5 of the period);
//! `Even` spreads them evenly (0, 1/4, 2/4, 3/4). Human variation moves each onset by up to
//! `±timing_jitter` seconds and scales each pluck's strength by up to `±strength_jitter`,
//! from a seeded generator (xorshift64*, Vigna 2016), so a render is repeatable.
//!
//! Built on the control thread; [`PluckCycle::next`] runs on the stepping thread (no
//! allocation, O(1)).

use serde::{Deserialize, Serialize};

/// The rhythm of a cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Pattern {
    /// Equal gaps, then a pause of two gaps.
    #[default]
    Classic,
    /// Equal gaps over the whole period.
    Even,
}

impl Pattern {
    /// Onset of string `i` of `n` as a fraction of the period.
    pub fn onset(self, i: usize, n: usize) -> f64 {
        match self {
            Pattern::Classic => i as f64 / (n + 1) as f64,
            Pattern::Even => i as f64 / n as f64,
        }
    }
}

/// One pluck the cycle asks for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PluckEvent {
    /// The step at which the pluck starts.
    pub step: u64,
    /// The string.
    pub string: usize,
    /// Strength factor (1 without variation).
    pub strength: f64,
}

/// The cycle's sequencer.
///
/// Owned by the stepping thread.
#[derive(Debug, Clone)]
pub struct PluckCycle {
    /// Period in steps (fractional).
    period: f64,
    /// The rhythm.
    pattern: Pattern,
    /// Number of strings.
    strings: usize,
    /// Largest onset shift in steps.
    jitter_steps: f64,
    /// Largest relative change of strength.
    strength_jitter: f64,
    /// Generator state (never 0).
    rng: u64,
    /// Step at which cycle 0 of the present timing starts (a retiming moves it to the cycle
    /// boundary where the new timing takes over).
    origin: f64,
    /// A new timing waiting for the next cycle boundary ([`PluckCycle::retime`]).
    pending: Option<Timing>,
    /// The next pluck: cycle index (since `origin`) and string.
    cycle: u64,
    /// String of the next pluck.
    next_string: usize,
}

/// A cycle's timing in steps: what [`PluckCycle::retime`] changes.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Timing {
    /// Period in steps.
    period: f64,
    /// The rhythm.
    pattern: Pattern,
    /// Largest onset shift in steps.
    jitter_steps: f64,
    /// Largest relative change of strength.
    strength_jitter: f64,
}

impl PluckCycle {
    /// A cycle of `period` s at step `h` s over `strings` strings.
    pub fn new(
        period: f64,
        h: f64,
        pattern: Pattern,
        strings: usize,
        timing_jitter: f64,
        strength_jitter: f64,
        seed: u64,
    ) -> Self {
        Self {
            period: period / h,
            pattern,
            strings,
            jitter_steps: timing_jitter / h,
            strength_jitter,
            rng: seed.max(1),
            origin: 0.0,
            pending: None,
            cycle: 0,
            next_string: 0,
        }
    }

    /// Changes the period (s, at step `h` s), the pattern and the variation (as in
    /// [`Self::new`]) from the next cycle boundary on: the cycle under way finishes in its own
    /// timing, and the first pluck of the next one comes where it was due, so the drone never
    /// skips or doubles a pluck (between a cycle's last draw and the next one's first, the
    /// next cycle takes the new timing). Stepping thread; O(1), no allocation.
    pub fn retime(
        &mut self,
        period: f64,
        h: f64,
        pattern: Pattern,
        timing_jitter: f64,
        strength_jitter: f64,
    ) {
        let t = Timing {
            period: period / h,
            pattern,
            jitter_steps: timing_jitter / h,
            strength_jitter,
        };
        if self.next_string == 0 {
            self.apply(t);
        } else {
            self.pending = Some(t);
        }
    }

    /// Applies `t` at cycle `self.cycle` of the present timing (a boundary).
    fn apply(&mut self, t: Timing) {
        self.origin += self.cycle as f64 * self.period;
        self.cycle = 0;
        self.period = t.period;
        self.pattern = t.pattern;
        self.jitter_steps = t.jitter_steps;
        self.strength_jitter = t.strength_jitter;
    }

    /// Where the cycle is at step `step`: the time since the present cycle's start over its
    /// period (0 to 1). O(1).
    pub fn phase_at(&self, step: u64) -> f64 {
        ((step as f64 - self.origin) / self.period).rem_euclid(1.0)
    }

    /// String `i`'s onset as a fraction of the period (the present pattern).
    pub fn onset(&self, i: usize) -> f64 {
        self.pattern.onset(i, self.strings)
    }

    /// The period in s at step `h` s.
    pub fn period_seconds(&self, h: f64) -> f64 {
        self.pending.map_or(self.period, |t| t.period) * h
    }

    /// A uniform number in [-1, 1) (xorshift64*).
    fn uniform(&mut self) -> f64 {
        let mut x = self.rng;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.rng = x;
        let r = x.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11;
        r as f64 / (1u64 << 52) as f64 - 1.0
    }

    /// The next pluck, in order (the onsets' jitter is less than a gap, so plucks never
    /// change order except by the jitter itself, which is applied in time order). O(1).
    pub fn next_pluck(&mut self) -> PluckEvent {
        let i = self.next_string;
        let base =
            self.origin + (self.cycle as f64 + self.pattern.onset(i, self.strings)) * self.period;
        let shift = if self.jitter_steps > 0.0 {
            self.uniform() * self.jitter_steps
        } else {
            0.0
        };
        let strength = if self.strength_jitter > 0.0 {
            1.0 + self.uniform() * self.strength_jitter
        } else {
            1.0
        };
        self.next_string += 1;
        if self.next_string == self.strings {
            self.next_string = 0;
            self.cycle += 1;
            if let Some(t) = self.pending.take() {
                self.apply(t);
            }
        }
        PluckEvent {
            step: (base + shift).max(0.0).round() as u64,
            string: i,
            strength,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A retiming takes over at the next cycle boundary: the cycle under way keeps its
    /// onsets, the next cycle starts where it was due and runs on the new period and pattern
    /// (steps exact: h = 1 ms, no variation).
    #[test]
    fn a_retiming_takes_over_at_the_next_cycle() {
        let mut c = PluckCycle::new(4.0, 1e-3, Pattern::Classic, 4, 0.0, 0.0, 1);
        let mut steps = vec![c.next_pluck().step, c.next_pluck().step];
        c.retime(2.0, 1e-3, Pattern::Even, 0.0, 0.0);
        steps.extend((0..7).map(|_| c.next_pluck().step));
        assert_eq!(steps, [0, 800, 1600, 2400, 4000, 4500, 5000, 5500, 6000]);
        // Between a cycle's last draw and the next one's first, the new timing applies at once.
        let mut c = PluckCycle::new(4.0, 1e-3, Pattern::Even, 2, 0.0, 0.0, 1);
        let first: Vec<u64> = (0..2).map(|_| c.next_pluck().step).collect();
        c.retime(1.0, 1e-3, Pattern::Even, 0.0, 0.0);
        let next: Vec<u64> = (0..3).map(|_| c.next_pluck().step).collect();
        assert_eq!((first, next), (vec![0, 2000], vec![4000, 4500, 5000]));
        assert!((c.phase_at(4750) - 0.75).abs() < 1e-12);
    }
}
