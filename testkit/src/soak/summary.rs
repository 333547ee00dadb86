//! What a soak did and saw: counts, the worst block time against the block's real-time
//! duration, the largest output level, the engine's own counters; printed as a summary.
//!
//! Threads: driver thread (plain data).

use super::draw::StormCounts;
use super::quality::{signature, Signature};
use super::SoakConfig;
use noether_core::engine::{Engine, EngineHandle, ModelKind};
use std::fmt;
use std::time::Duration;

/// The block with the largest time over real-time ratio (for one class of block lengths).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct WorstBlock {
    /// Wall time spent in `process` over the block's duration `n / host_rate`
    /// (1 = a whole block period).
    pub ratio: f64,
    /// Wall time spent in `process` (s).
    pub seconds: f64,
    /// Block length (host samples).
    pub len: usize,
    /// Host rate (Hz).
    pub host_rate: f64,
    /// The bank in use after the block (model, simulation rate, voices).
    pub bank: Option<Signature>,
    /// Voices sounding after the block.
    pub active: usize,
}

impl WorstBlock {
    fn offer(&mut self, b: WorstBlock) {
        if b.ratio > self.ratio {
            *self = b;
        }
    }
}

impl fmt::Display for WorstBlock {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{:.3} ({:.3} ms for {} samples at {:.0} Hz; bank {}, {} voices sounding)",
            self.ratio,
            self.seconds * 1e3,
            self.len,
            self.host_rate,
            self.bank.map_or("none".to_string(), |b| b.to_string()),
            self.active
        )
    }
}

/// Counts and worst cases of one soak run (printed with `{}`). Plain data.
#[derive(Debug, Clone, Default)]
pub struct SoakSummary {
    /// Seed of the run.
    pub seed: u64,
    /// Wall time of the run (s).
    pub wall: f64,
    /// Blocks processed (main sequence and rebuild waits).
    pub blocks: u64,
    /// Blocks processed while a rebuild was pending (choices from the second sequence,
    /// paced at real time; their number depends on the worker's speed).
    pub wait_blocks: u64,
    /// Host samples processed (per channel).
    pub samples: u64,
    /// Host audio processed (s): the sum of `n / host_rate` over blocks.
    pub audio: f64,
    /// Shortest and longest block (samples).
    pub block_range: (usize, usize),
    /// Parameter writes (automation and bursts).
    pub param_writes: u64,
    /// Key tables published (random microtunings with unmapped keys).
    pub tunings: u64,
    /// Events of the note storm.
    pub storm: StormCounts,
    /// Rebuild requests (bursts' final steps).
    pub rebuilds_requested: u64,
    /// Requests whose bank arrived.
    pub rebuilds_arrived: u64,
    /// Requests the worker refused with an error.
    pub rebuilds_refused: u64,
    /// Up to five refusals: the request and the worker's message.
    pub refusals: Vec<(Signature, String)>,
    /// Longest wall time from a request to its bank's arrival.
    pub rebuild_wait: Duration,
    /// Bank changes seen by the audio side (handovers, activations excluded).
    pub handovers: u64,
    /// Host sample-rate changes (re-activations).
    pub rate_changes: u64,
    /// Lowest and highest host rate used (Hz).
    pub rate_range: (f64, f64),
    /// Longest re-activation (main thread; builds the bank).
    pub activation_wall: Duration,
    /// Blocks played by each model, in [`ModelKind::ALL`] order.
    pub model_blocks: [u64; ModelKind::ALL.len()],
    /// Worst block over all lengths.
    pub worst: WorstBlock,
    /// Worst block of at least 256 samples (shorter blocks are dominated by per-call costs).
    pub worst_long: WorstBlock,
    /// Total wall time in `process` over the audio processed (mean load).
    pub mean_load: f64,
    /// Blocks played with the `limiter` parameter on.
    pub limited_blocks: u64,
    /// Largest `|output|` in blocks with the limiter on (full scale 1; bound: the ceiling).
    pub peak_limited: f32,
    /// Largest `|output|` in blocks with the limiter off (bound: 1, the guard's clip).
    pub peak_unlimited: f32,
    /// Samples the output stage's guard changed in blocks with the limiter off (clipped to
    /// full scale); with it on any such sample fails the soak.
    pub guarded_unlimited: u64,
    /// The engine's counters at the end: contact Newton solves that hit the cap, voices
    /// silenced as non-finite, notes refused as unstable.
    pub newton_cap_hits: u64,
    /// See [`Self::newton_cap_hits`].
    pub diverged_voices: u64,
    /// See [`Self::newton_cap_hits`].
    pub refused_notes: u64,
    /// Banks the worker built.
    pub banks_built: u64,
    /// Blocks whose chunks shared the voices between two threads or more (the `threads`
    /// parameter is automated with the others).
    pub threaded_blocks: u64,
    /// Voice jobs run by the voice pool's workers, and jobs still running past the audio
    /// thread's bounded wait (late: the voice's chunk left out), at the end.
    pub worker_jobs: u64,
    /// See [`Self::worker_jobs`].
    pub late_jobs: u64,
    /// Halves of split plate steps run by a worker, and those a worker took but did not
    /// finish within the owner's bounded wait (the voice computed them itself), at the end.
    pub shared_step_halves: u64,
    /// See [`Self::shared_step_halves`].
    pub late_step_halves: u64,
    busy: f64,
}

impl SoakSummary {
    /// An empty summary for `cfg`.
    pub fn new(cfg: &SoakConfig) -> Self {
        Self {
            seed: cfg.seed,
            block_range: (usize::MAX, 0),
            rate_range: (f64::INFINITY, 0.0),
            ..Self::default()
        }
    }

    pub(super) fn note_rate(&mut self, rate: f64) {
        self.rate_range = (self.rate_range.0.min(rate), self.rate_range.1.max(rate));
    }

    pub(super) fn refusal(&mut self, want: Signature, why: String) {
        self.rebuilds_refused += 1;
        if self.refusals.len() < 5 {
            self.refusals.push((want, why));
        }
    }

    /// Records a block's output level: its peak, whether the limiter was on, and the samples
    /// the guard changed.
    pub(super) fn level(&mut self, peak: f32, limiter: bool, guarded: u64) {
        if limiter {
            self.limited_blocks += 1;
            self.peak_limited = self.peak_limited.max(peak);
        } else {
            self.peak_unlimited = self.peak_unlimited.max(peak);
            self.guarded_unlimited += guarded;
        }
    }

    pub(super) fn block(&mut self, n: usize, rate: f64, spent: Duration, e: &Engine) {
        self.blocks += 1;
        self.samples += n as u64;
        self.audio += n as f64 / rate;
        self.busy += spent.as_secs_f64();
        self.block_range = (self.block_range.0.min(n), self.block_range.1.max(n));
        if e.threads_used() > 1 {
            self.threaded_blocks += 1;
        }
        if let Some(m) = e.model() {
            let i = ModelKind::ALL.iter().position(|&k| k == m).unwrap_or(0);
            self.model_blocks[i] += 1;
        }
        let b = WorstBlock {
            ratio: spent.as_secs_f64() * rate / n as f64,
            seconds: spent.as_secs_f64(),
            len: n,
            host_rate: rate,
            bank: signature(e),
            active: e.active_voices(),
        };
        self.worst.offer(b);
        if n >= 256 {
            self.worst_long.offer(b);
        }
    }

    pub(super) fn finish(
        &mut self,
        e: &Engine,
        h: &EngineHandle,
        storm: StormCounts,
        wall: Duration,
    ) {
        self.storm = storm;
        self.wall = wall.as_secs_f64();
        self.mean_load = self.busy / self.audio.max(1e-12);
        self.newton_cap_hits = e.newton_cap_hits();
        self.diverged_voices = e.diverged_voices();
        self.refused_notes = e.refused_notes();
        self.banks_built = h.banks_built();
        self.worker_jobs = e.worker_jobs();
        self.late_jobs = e.late_jobs();
        self.shared_step_halves = e.shared_step_halves();
        self.late_step_halves = e.late_step_halves();
    }
}

impl fmt::Display for SoakSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let st = &self.storm;
        writeln!(f, "soak seed {}: {:.1} s wall", self.seed, self.wall)?;
        writeln!(
            f,
            "  blocks {} ({} while rebuilds were pending; {} samples, {:.1} s of audio), \
             lengths {}..{}",
            self.blocks,
            self.wait_blocks,
            self.samples,
            self.audio,
            self.block_range.0,
            self.block_range.1
        )?;
        writeln!(
            f,
            "  notes: {} on, {} zero-velocity on, {} off ({:.0} note-ons per second of audio); \
             {} controller events, {} per-note events, {} all-off",
            st.note_ons,
            st.zero_velocity,
            st.note_offs,
            (st.note_ons + st.zero_velocity) as f64 / self.audio.max(1e-12),
            st.controllers,
            st.per_note,
            st.panics
        )?;
        writeln!(f, "  parameter writes {}", self.param_writes)?;
        writeln!(f, "  key tables published {}", self.tunings)?;
        writeln!(
            f,
            "  rebuilds: {} requested, {} arrived, {} refused by the worker; {} handovers, {} \
             banks built; longest wait {:.2} s",
            self.rebuilds_requested,
            self.rebuilds_arrived,
            self.rebuilds_refused,
            self.handovers,
            self.banks_built,
            self.rebuild_wait.as_secs_f64()
        )?;
        for (want, why) in &self.refusals {
            writeln!(f, "    refused {want}: {why}")?;
        }
        writeln!(
            f,
            "  host rate changes {} ({:.0}..{:.0} Hz), longest activation {:.2} s",
            self.rate_changes,
            self.rate_range.0,
            self.rate_range.1,
            self.activation_wall.as_secs_f64()
        )?;
        write!(f, "  blocks per model:")?;
        for (k, n) in ModelKind::ALL.iter().zip(self.model_blocks) {
            write!(f, " {} {n}", k.key())?;
        }
        writeln!(f)?;
        writeln!(f, "  worst block time / block duration: {}", self.worst)?;
        writeln!(f, "  worst for blocks >= 256 samples:  {}", self.worst_long)?;
        writeln!(
            f,
            "  mean load (process time / audio time) {:.3}",
            self.mean_load
        )?;
        writeln!(
            f,
            "  output: limiter on in {} blocks, peak {:.4} (ceiling {:.4}); off, peak {:.4} \
             with {} samples clipped by the guard",
            self.limited_blocks,
            self.peak_limited,
            super::CEILING,
            self.peak_unlimited,
            self.guarded_unlimited
        )?;
        writeln!(
            f,
            "  voice pool: {} threaded blocks, {} jobs on workers, {} late jobs; split steps: {} halves on workers, {} late",
            self.threaded_blocks,
            self.worker_jobs,
            self.late_jobs,
            self.shared_step_halves,
            self.late_step_halves
        )?;
        write!(
            f,
            "  engine: {} Newton cap hits, {} diverged voices, {} refused notes",
            self.newton_cap_hits, self.diverged_voices, self.refused_notes
        )
    }
}

/// A failed soak check: what failed, and the summary up to that block.
#[derive(Debug, Clone)]
pub struct SoakFailure {
    /// The failed check, with the values involved.
    pub message: String,
    /// Counts up to the failure.
    pub summary: SoakSummary,
}

impl fmt::Display for SoakFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "soak failed: {}\n{}", self.message, self.summary)
    }
}

impl std::error::Error for SoakFailure {}
