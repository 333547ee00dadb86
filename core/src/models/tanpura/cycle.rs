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
    /// The next pluck: cycle index and string.
    cycle: u64,
    /// String of the next pluck.
    next_string: usize,
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
            cycle: 0,
            next_string: 0,
        }
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
        let base = (self.cycle as f64 + self.pattern.onset(i, self.strings)) * self.period;
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
        }
        PluckEvent {
            step: (base + shift).max(0.0).round() as u64,
            string: i,
            strength,
        }
    }
}
