//! The CPU governor: processing in bounded time while a live host waits for every block.
//!
//! **The cost of a note.** A voice's step costs about `c · W`: `W` its work in *units* (a
//! plate tier's stored coupling-tensor entries plus its modes, the kernels' multiply-adds; a
//! string's `N²`), `c` seconds per unit per step, learned on the audio thread from the voice
//! jobs' own wall times ([`CostModel::observe`]: an exponential average over the jobs of at
//! least [`MIN_OBSERVED_STEPS`] steps, per bank, since the unit's cost depends on the scheme
//! and the model; before the first job, [`PRIOR_SECONDS_PER_UNIT`]). A voice then costs
//! `c · W · f_s` seconds per second of audio at simulation rate `f_s`.
//!
//! **Before a note starts** (plates), the engine sums the cost of the voices that keep
//! sounding and gives the new note the work that fits in the budget: the note's band comes
//! down a tier at a time (each tier `1/√2` of the modes, the in-plane modes in proportion;
//! `voice::plate`) until its step fits. If not even the smallest tier fits, the quietest
//! other voices are ended (polyphony, the last resort) until it does. The order is that of
//! musical harm: a narrower band first, then fewer voices.
//!
//! **While playing** ([`Governor::watch`]) it follows the measured wall time of each block
//! against the block's duration (an average over about [`WATCH_SECONDS`]); above
//! [`OVERLOAD`] it ends the quietest voice (at most one per [`WATCH_SECONDS`]), with a fade of
//! [`FADE_CHUNKS`] chunks.
//!
//! Every reduction is counted (notes started on a smaller tier, voices ended) and reported:
//! telemetry, the editor, `Engine::governor_counts`. The governor is off by default (offline
//! renders keep every note's full band, so they repeat bit for bit); a live host turns it on
//! (`Engine::set_governor`). Its budget is the `cpu_budget` parameter (cores, 0: 70 % of the
//! machine's).
//!
//! Threads: audio thread (the cost model in the bank, the governor in the engine); the voice
//! jobs write their wall time into their voice on whichever thread runs them.

/// Seconds per work unit per step assumed before the first measured job (a generous 2 ns:
/// the plates' kernels measure 0.24-0.8 ns per stored entry on this machine, docs/
/// performance.md), so a first note errs on the cheap side of its band.
pub(crate) const PRIOR_SECONDS_PER_UNIT: f64 = 2e-9;

/// Jobs shorter than this many steps are not measured (their fixed costs would dominate).
pub(crate) const MIN_OBSERVED_STEPS: usize = 16;

/// Weight of a new measurement in the cost model's average.
const COST_WEIGHT: f64 = 0.1;

/// Averaging time of the block load, and the shortest interval between two ended voices (s).
pub const WATCH_SECONDS: f64 = 0.1;

/// Block load (wall time over the block's duration, averaged) above which a voice is ended.
pub const OVERLOAD: f64 = 1.0;

/// Chunks over which an ended voice fades out.
pub(crate) const FADE_CHUNKS: u8 = 8;

/// Share of the machine's cores the default budget (`cpu_budget` 0) takes: 0.7 kept every
/// block-time mean of 12 random parameter sets within real time on this 2-core machine, where
/// 0.8 let one reach 1.02 (`examples/governor_blocks.rs`, docs/robustness.md): the voices'
/// work does not split perfectly over the cores, and the audio thread waits for the slowest.
pub const AUTO_SHARE: f64 = 0.7;

/// The budget (seconds of work per second of audio) for the `cpu_budget` value `cores` on a
/// machine of `machine_cores` cores (0: [`AUTO_SHARE`] of them). Any thread.
pub fn budget_of(cores: f32, machine_cores: f64) -> f64 {
    if cores > 0.0 {
        f64::from(cores)
    } else {
        AUTO_SHARE * machine_cores.max(1.0)
    }
}

/// The most one voice may cost (seconds of work per second of audio) under the `cpu_budget`
/// value `cores`: a voice's step runs on one thread, so at most [`AUTO_SHARE`] of one core,
/// and never more than the whole budget. The worker fits a string bank to it
/// (`engine/string_bank.rs`). Any thread.
pub fn voice_share(cores: f32, machine_cores: f64) -> f64 {
    budget_of(cores, machine_cores).min(AUTO_SHARE)
}

/// A bank's learned cost of a work unit (audio thread).
#[derive(Debug, Clone, Copy)]
pub(crate) struct CostModel {
    /// Seconds per work unit per step.
    pub seconds_per_unit: f64,
    /// Jobs measured.
    pub observed: u64,
}

impl Default for CostModel {
    fn default() -> Self {
        Self {
            seconds_per_unit: PRIOR_SECONDS_PER_UNIT,
            observed: 0,
        }
    }
}

impl CostModel {
    /// Learns from one job: `seconds` of wall time for `steps` steps of `work` units each.
    /// The first measurement replaces the prior; later ones are averaged in.
    pub fn observe(&mut self, work: f64, steps: usize, seconds: f64) {
        if steps < MIN_OBSERVED_STEPS || work <= 0.0 || seconds.is_nan() || seconds <= 0.0 {
            return;
        }
        let x = seconds / (work * steps as f64);
        self.seconds_per_unit = if self.observed == 0 {
            x
        } else {
            (1.0 - COST_WEIGHT) * self.seconds_per_unit + COST_WEIGHT * x
        };
        self.observed += 1;
    }

    /// Seconds of work per second of audio of a voice of `work` units at `sim_rate` (Hz).
    pub fn load(&self, work: f64, sim_rate: f64) -> f64 {
        self.seconds_per_unit * work * sim_rate
    }
}

/// The engine's governor state (audio thread).
#[derive(Debug, Clone, Default)]
pub(crate) struct Governor {
    /// On (a live host) or off (offline renders).
    pub on: bool,
    /// Cores of the machine (the default budget's base).
    pub cores: f64,
    /// The block load, averaged over about [`WATCH_SECONDS`].
    pub load: f64,
    /// Host frames before the next voice may be ended by the watch.
    pub cooldown: u64,
    /// Notes started on a smaller tier than their band asks.
    pub reduced: u64,
    /// Voices ended to make room (at a note-on or by the watch).
    pub shed: u64,
}

impl Governor {
    /// The budget (seconds of work per second of audio) for the `cpu_budget` value `cores`
    /// (0: [`AUTO_SHARE`] of the machine's cores); `None` while the governor is off.
    pub fn budget(&self, cores: f32) -> Option<f64> {
        self.on.then(|| budget_of(cores, self.cores))
    }

    /// Folds a block's `spent` wall seconds over its `duration` into the load; returns whether
    /// a voice should be ended now (on, overloaded, and the last one ended long enough ago).
    pub fn watch(&mut self, spent: f64, duration: f64, frames: u64, host_rate: f64) -> bool {
        if duration <= 0.0 {
            return false;
        }
        let w = (duration / WATCH_SECONDS).min(1.0);
        self.load = (1.0 - w) * self.load + w * spent / duration;
        self.cooldown = self.cooldown.saturating_sub(frames);
        if !self.on || self.load <= OVERLOAD || self.cooldown > 0 {
            return false;
        }
        self.cooldown = (WATCH_SECONDS * host_rate).ceil() as u64;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cost model replaces its prior with the first job, averages later ones, ignores
    /// short jobs, and predicts a voice's load as `c W f_s`.
    #[test]
    fn the_cost_model_learns_from_jobs() {
        let mut c = CostModel::default();
        assert_eq!(c.seconds_per_unit, PRIOR_SECONDS_PER_UNIT);
        c.observe(1000.0, 8, 1.0);
        assert_eq!(c.observed, 0, "a job of 8 steps is not measured");
        c.observe(1000.0, 100, 1e-4);
        assert!((c.seconds_per_unit - 1e-9).abs() < 1e-24);
        c.observe(1000.0, 100, 2e-4);
        assert!((c.seconds_per_unit - 1.1e-9).abs() < 1e-22);
        // 1.1 ns x 10 000 units x 20 kHz = 0.22 s per second.
        assert!((c.load(10_000.0, 20_000.0) - 0.22).abs() < 1e-12);
    }

    /// Off: no budget and no watch. On: the budget is the parameter, or 70 % of the cores
    /// at 0; the watch ends a voice once the averaged load passes 1, then waits.
    #[test]
    fn the_watch_ends_a_voice_once_overloaded_then_waits() {
        let mut g = Governor {
            cores: 2.0,
            ..Governor::default()
        };
        assert_eq!(g.budget(0.0), None);
        assert!(!g.watch(1.0, 0.01, 480, 48_000.0));
        g.on = true;
        g.load = 0.0;
        assert!((g.budget(0.0).unwrap() - 1.4).abs() < 1e-12);
        assert_eq!(g.budget(3.0), Some(3.0));
        // One voice: at most 70 % of one core, within the budget.
        assert!((voice_share(0.0, 2.0) - 0.7).abs() < 1e-12);
        assert!((voice_share(0.25, 2.0) - 0.25).abs() < 1e-12);
        assert!((voice_share(8.0, 2.0) - 0.7).abs() < 1e-12);
        // Blocks at half their duration: never.
        for _ in 0..100 {
            assert!(!g.watch(0.005, 0.01, 480, 48_000.0));
        }
        // Blocks at twice their duration: the average passes 1 within a few blocks.
        let n = (0..100)
            .position(|_| g.watch(0.02, 0.01, 480, 48_000.0))
            .expect("ends a voice");
        assert!(n < 10, "after {n} blocks");
        // Then not again for 0.1 s (10 blocks of 10 ms).
        let again = (0..100)
            .position(|_| g.watch(0.02, 0.01, 480, 48_000.0))
            .expect("ends another");
        assert_eq!(again, 9);
    }
}
