//! The CPU governor: processing in bounded time while a live host waits for every block.
//!
//! **The cost of a note.** Every voice has a price: the seconds one simulation step of its
//! current model takes. Under the governor the worker measures it before it sends the bank
//! (`engine/cost_trial.rs`): it times one voice playing a note struck or plucked at full
//! strength, each plate tier in turn and the string model, in thread CPU time (so the load
//! of other threads does not count). Off the governor (offline renders) nothing is measured
//! and a price is the prior estimate [`PRIOR_SECONDS_PER_UNIT`] per work unit (a plate tier's
//! stored coupling-tensor entries plus its modes, a string's `N²`). On the audio thread a
//! bank's [`CostModel`] corrects the prices by the ratio of the voice jobs' measured wall
//! times to their prices (an exponential average over the jobs of at least
//! [`MIN_OBSERVED_STEPS`] steps; 1 before the first job), which follows what the trial
//! cannot see: the machine's other load, a helper taking half of a large step, the keys
//! played. A voice then costs `r · c · f_s` seconds per second of audio, `c` its price, `r`
//! the correction and `f_s` the simulation rate.
//!
//! **Before a note starts**, the engine sums the cost of the voices that keep sounding; if
//! the budget has no room for the note's cheapest model (a plate's smallest tier, the string;
//! priced at least at its trial's price, [`CostModel::attack_load`]) the quietest other voices
//! are ended (polyphony) until it has. A plate note then starts on
//! the largest tier its band asks for that fits both the room left and one voice's share
//! ([`voice_share`]: a voice's step runs on one thread, so a voice priced above the share
//! would make every block late however few voices sound). The band comes down a tier at a
//! time (each tier `1/√2` of the modes, the in-plane modes in proportion; `voice::plate`).
//! The order is that of musical harm: a narrower band first, then fewer voices. A string is
//! one model, fitted to the share when the bank is built (`engine/string_bank.rs`).
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
//! Threads: worker (the prices), audio thread (the correction in the bank, the governor in
//! the engine); the voice jobs write their wall time into their voice on whichever thread
//! runs them.

/// The prior price of a work unit (seconds per step), used where nothing was measured
/// (offline renders, where the governor is off, and a machine without a thread clock): a
/// generous 2 ns (the plates' kernels measure 0.24-0.8 ns per stored entry on this machine,
/// docs/performance.md).
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

/// A bank's correction of its voices' prices by their measured jobs (audio thread).
#[derive(Debug, Clone, Copy)]
pub(crate) struct CostModel {
    /// Measured job wall time over the price of its steps (dimensionless; 1 before the first
    /// job).
    pub ratio: f64,
    /// Jobs measured.
    pub observed: u64,
}

impl Default for CostModel {
    fn default() -> Self {
        Self {
            ratio: 1.0,
            observed: 0,
        }
    }
}

impl CostModel {
    /// Learns from one job: `seconds` of wall time for `steps` steps priced `price` seconds
    /// each. The first measurement replaces the prior; later ones are averaged in.
    pub fn observe(&mut self, price: f64, steps: usize, seconds: f64) {
        let usable = |x: f64| x.is_finite() && x > 0.0;
        if steps < MIN_OBSERVED_STEPS || !usable(price) || !usable(seconds) {
            return;
        }
        let x = seconds / (price * steps as f64);
        if !x.is_finite() {
            return;
        }
        self.ratio = if self.observed == 0 {
            x
        } else {
            (1.0 - COST_WEIGHT) * self.ratio + COST_WEIGHT * x
        };
        self.observed += 1;
    }

    /// Seconds of work per second of audio of a sounding voice priced `price` seconds per
    /// step at `sim_rate` (Hz).
    pub fn load(&self, price: f64, sim_rate: f64) -> f64 {
        self.ratio * price * sim_rate
    }

    /// The load of a note about to start: as [`Self::load`], but never below its price. The
    /// trial priced the attack, where a string's bridge contact is densest; the correction
    /// learns from the sounding voices, mostly past their attacks (strings' ratios fall to
    /// 0.2-0.4), and a new note priced with it made its note-on blocks late.
    pub fn attack_load(&self, price: f64, sim_rate: f64) -> f64 {
        self.ratio.max(1.0) * price * sim_rate
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

    /// The correction replaces its prior with the first job, averages later ones, ignores
    /// short jobs and unusable times, and predicts a voice's load as `r c f_s`.
    #[test]
    fn the_cost_model_learns_from_jobs() {
        let mut c = CostModel::default();
        assert_eq!(c.ratio, 1.0);
        // 10 µs per step before the first job: 0.2 s per second at 20 kHz.
        assert!((c.load(1e-5, 20_000.0) - 0.2).abs() < 1e-12);
        c.observe(1e-5, 8, 1.0);
        assert_eq!(c.observed, 0, "a job of 8 steps is not measured");
        c.observe(1e-5, 100, f64::NAN);
        c.observe(0.0, 100, 1e-3);
        assert_eq!(c.observed, 0, "no price or no time: nothing learned");
        c.observe(1e-5, 100, 2e-3);
        assert!((c.ratio - 2.0).abs() < 1e-12);
        c.observe(1e-5, 100, 1e-3);
        assert!((c.ratio - 1.9).abs() < 1e-12);
        // 1.9 x 10 µs x 20 kHz = 0.38 s per second.
        assert!((c.load(1e-5, 20_000.0) - 0.38).abs() < 1e-12);
        assert!((c.attack_load(1e-5, 20_000.0) - 0.38).abs() < 1e-12);
        // A ratio below 1 lowers the sounding voices' loads, not a new note's.
        c.ratio = 0.25;
        assert!((c.load(1e-5, 20_000.0) - 0.05).abs() < 1e-12);
        assert!((c.attack_load(1e-5, 20_000.0) - 0.2).abs() < 1e-12);
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
