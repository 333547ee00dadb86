//! What the engine tells: read-outs for the host and tests, and the telemetry frames it sends
//! to the GUI (about 30 a second, through a ringbuf queue).
//!
//! Threads: the read-outs on whichever thread owns the engine; `account` and the telemetry on
//! the audio thread (no allocation: the frame is plain `Copy` data).

use super::audio::Engine;
use super::bank::Bank;
use super::kinds::ModelKind;
use super::resample::Resampler;
use super::telemetry::{DroneView, Telemetry, VoiceModelInfo, VoiceTelemetry, MAX_VOICES};
use crate::models::source::EnergyTerms;
use ringbuf::traits::Producer;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

/// Telemetry frames per second.
const TELEMETRY_RATE: f64 = 30.0;

impl Engine {
    /// Sets the longest time the audio thread waits, per chunk, for the voice jobs workers
    /// hold once it has no job left to run itself (`None`, the default: the chunk's duration
    /// at the host rate, 1.3 ms for 64 samples at 48 kHz). A job still running then is late:
    /// its voice's chunk is left out of the mix and counted ([`Self::late_jobs`]). Offline
    /// renders and tests that compare outputs bit for bit set a long wait (any thread that
    /// owns the engine).
    pub fn set_job_wait(&mut self, wait: Option<Duration>) {
        self.jobs.job_wait = wait;
    }

    /// Voice jobs that were still running on a worker when the audio thread's wait ended,
    /// since the engine was created (their chunks were left out of the mix).
    pub fn late_jobs(&self) -> u64 {
        self.counts.late
    }

    /// Threads allowed to share the last chunk's voices, the audio thread included: the
    /// `threads` parameter capped at the pool's workers plus one (1: the audio thread alone;
    /// a chunk with one sounding voice runs on the audio thread, helped by a worker only
    /// when its steps are split).
    pub fn threads_used(&self) -> usize {
        self.jobs.threads_used as usize
    }

    /// Voice jobs run by the voice pool's workers (not the audio thread) since the engine
    /// was created.
    pub fn worker_jobs(&self) -> u64 {
        self.counts.worker_jobs_past + self.jobs.pool.as_ref().map_or(0, |p| p.worker_jobs())
    }

    /// Halves of split plate steps run by the pool's workers (`step_board`: voices whose
    /// coupling tensor has at least [`crate::models::plate::SPLIT_MIN_ENTRIES`] entries),
    /// since the engine was created.
    pub fn shared_step_halves(&self) -> u64 {
        self.jobs.board.shared_halves()
    }

    /// Halves of split plate steps a worker took but did not finish within the owner's
    /// bounded wait (the owner computed them itself; the sound is the same), since the engine
    /// was created.
    pub fn late_step_halves(&self) -> u64 {
        self.jobs.board.late_halves()
    }

    /// Events lost because more than 256 arrived while a late job held the bank.
    pub fn deferred_events_lost(&self) -> u64 {
        self.counts.deferred_lost
    }

    /// Host rate set by [`Self::activate`] (Hz).
    pub fn host_rate(&self) -> f64 {
        self.host_rate
    }

    /// Latency in host samples (the resampler's half-width plus the output limiter's look-ahead;
    /// report it to the host).
    pub fn latency_samples(&self) -> u32 {
        // Before the first bank of an activation arrives: the latency it will have (the
        // resampler's half-width for the current parameters' simulation rate).
        let bank = self.any_bank().map_or_else(
            || {
                let sim = Bank::sim_rate_of(&self.values);
                Resampler::half_width(sim, self.host_rate) as f64 * self.host_rate / sim
            },
            |b| b.latency_host(),
        );
        bank.round() as u32 + self.output.latency() as u32
    }

    /// Identifier of the voice bank in use (0 before activation; changes with every swap).
    pub fn bank_id(&self) -> u64 {
        self.any_bank().map_or(0, |b| b.id)
    }

    /// The model of the bank in use.
    pub fn model(&self) -> Option<ModelKind> {
        self.any_bank().map(|b| b.kind)
    }

    /// Simulation rate of the bank in use (Hz).
    pub fn sim_rate(&self) -> Option<f64> {
        self.any_bank().map(|b| b.sim_rate)
    }

    /// Voices in the pool of the bank in use.
    pub fn polyphony(&self) -> usize {
        self.any_bank().map_or(0, |b| b.voices.len())
    }

    /// The bank in use, also while a late voice job holds it (bank-level values only: its
    /// voices must not be read then).
    fn any_bank(&self) -> Option<&Bank> {
        self.bank.as_deref().or(self.jobs.held.as_deref())
    }

    /// Sounding voices (while a late voice job holds the bank: those sounding at the end of
    /// the last chunk).
    pub fn active_voices(&self) -> usize {
        match (&self.bank, &self.jobs.held) {
            (Some(b), _) => b.voices.iter().filter(|v| v.active).count(),
            (None, Some(h)) => h.lanes.sounding(),
            (None, None) => 0,
        }
    }

    /// Energy terms (J) of voice `slot` if it is sounding (`None` while a late voice job holds
    /// the bank). O(N) for strings.
    pub fn voice_energy(&self, slot: usize) -> Option<EnergyTerms> {
        let v = self.bank.as_ref()?.voices.get(slot)?;
        v.active.then(|| v.energy_terms())
    }

    /// What voice `slot` simulates for its note, if it is sounding (`None` while a late voice
    /// job holds the bank). O(N_Φ).
    pub fn voice_model(&self, slot: usize) -> Option<VoiceModelInfo> {
        let v = self.bank.as_ref()?.voices.get(slot)?;
        v.active.then(|| v.model_info())
    }

    /// Key of voice `slot` if it is sounding (`None` while a late voice job holds the bank).
    pub fn voice_key(&self, slot: usize) -> Option<u8> {
        let v = self.bank.as_ref()?.voices.get(slot)?;
        v.active.then_some(v.key)
    }

    /// Mallet contacts begun since the engine was created: every strike of the physical
    /// mallet and every re-strike it makes by itself. Audio thread.
    pub fn mallet_impacts(&self) -> u64 {
        self.counts.mallet_impacts
    }

    /// Contact Newton solves that hit the cap since creation.
    pub fn newton_cap_hits(&self) -> u64 {
        self.counts.newton_cap_hits
    }

    /// Voices silenced because their state became non-finite or their output passed
    /// [`super::VOICE_CEILING`].
    pub fn diverged_voices(&self) -> u64 {
        self.counts.diverged
    }

    /// Notes refused because their coefficients would be unstable (θ = 1 scheme above its
    /// limit, or an exact-scheme mode on a multiple of π).
    pub fn refused_notes(&self) -> u64 {
        self.counts.refused
    }

    /// Output samples the output stage's last guard had to change since the engine was created:
    /// samples above full scale bounded to ±1 and non-finite samples set to 0 (see
    /// [`super::output`]). Written on the audio thread (a counter, no allocation); read on
    /// the thread that owns the engine. With the `limiter` parameter on it stays 0: the
    /// limiter keeps every sample under its ceiling (-0.3 dBFS) before the guard, so a count
    /// in a block played with the limiter on means the limiter failed. With the limiter off
    /// it counts the hard-clipped samples.
    pub fn guarded_samples(&self) -> u64 {
        self.counts.guarded_past + self.output.guarded()
    }

    pub(super) fn account(&mut self, left: &[f32], right: &[f32], start: Instant) {
        for (c, x) in [left, right].into_iter().enumerate() {
            for &s in x {
                self.meters.peak[c] = self.meters.peak[c].max(s.abs());
                self.meters.sumsq[c] += (s as f64) * (s as f64);
            }
        }
        self.meters.samples += left.len() as u64;
        let dur = left.len() as f64 / self.host_rate;
        let spent = start.elapsed().as_secs_f64();
        self.meters.busy += spent;
        if dur > 0.0 {
            self.meters.cpu_peak = self.meters.cpu_peak.max((spent / dur) as f32);
        }
        self.watch_load(spent, left.len());
        if self.frame >= self.meters.next {
            self.meters.next = self.frame + (self.host_rate / TELEMETRY_RATE) as u64;
            self.send_telemetry();
        }
    }

    fn send_telemetry(&mut self) {
        let audio_s = self.meters.samples.max(1) as f64 / self.host_rate;
        let workers = self.jobs.pool.as_mut().map_or(0.0, |p| p.take_cpu());
        let mut t = Telemetry {
            frame: self.frame,
            cpu_load: ((self.meters.busy + workers) / audio_s) as f32,
            audio_load: (self.meters.busy / audio_s) as f32,
            cpu_peak: self.meters.cpu_peak,
            threads: self.jobs.threads_used,
            late_jobs: self.counts.late,
            governor_reduced: self.governor.reduced,
            governor_shed: self.governor.shed,
            rebuilding: self.status.rebuilding.load(Ordering::Acquire),
            newton_cap_hits: self.counts.newton_cap_hits,
            diverged: self.counts.diverged,
            guarded: self.guarded_samples(),
            memory_bytes: self.memory_bytes(),
            ..Telemetry::default()
        };
        for c in 0..2 {
            t.peak[c] = self.meters.peak[c];
            t.rms[c] = (self.meters.sumsq[c] / self.meters.samples.max(1) as f64).sqrt() as f32;
        }
        self.meters.peak = [0.0; 2];
        self.meters.sumsq = [0.0; 2];
        self.meters.samples = 0;
        self.meters.busy = 0.0;
        self.meters.cpu_peak = 0.0;
        if let Some(b) = self.bank.as_mut() {
            t.bank = b.id;
            t.modes_fitted = b.fitted;
            t.drone_tuning = b.drone_tuning;
            t.preview = b.preview;
            t.sim_rate = b.sim_rate as f32;
            let mut loudest: Option<(usize, f64)> = None;
            for (i, v) in b.voices.iter().enumerate().take(MAX_VOICES) {
                if !v.active {
                    continue;
                }
                let e = v.energy_terms();
                let held = v.held || v.sustained;
                t.voices[i] = VoiceTelemetry {
                    active: true,
                    key: v.key,
                    held,
                    latched: !held && v.model.body_ref().plays_on(),
                    energy: e,
                    age: ((self.frame - v.started) as f64 / self.host_rate) as f32,
                    model: v.model_info(),
                };
                t.active_voices += 1;
                if loudest.is_none_or(|(_, x)| e.total() > x) {
                    loudest = Some((i, e.total()));
                }
            }
            let watched = match self.watch {
                Some(w) if b.voices.get(w as usize).is_some_and(|v| v.active) => Some(w as usize),
                _ => loudest.map(|l| l.0),
            };
            t.drone = None;
            if let Some(w) = watched {
                t.watched = Some(w as u8);
                b.voices[w].snapshot(&mut t.displacement, &mut t.mode_freq, &mut t.mode_amplitude);
                let mut view = DroneView::default();
                if b.voices[w].drone_view(&mut view) {
                    t.drone = Some(view);
                }
            }
        }
        let _ = self.telemetry_tx.try_push(t);
    }
}
