//! [`Engine`]: the audio-thread object (lifecycle, events, block processing, voice pool).

use super::bank::{Bank, CHUNK};
use super::events::{Event, GuiCommand};
use super::governor::Governor;
use super::handle::{BuildRequest, EngineHandle, Worker, WorkerStatus};
use super::handover_state::Handover;
use super::meters::{Counts, Meters};
use super::mix::{run_bank, Sharing, Tally};
use super::note_state::NoteState;
use super::output::OutputStage;
use super::params::{ParamId, ParamValues, SharedParams};
use super::pool::Pool;
use super::telemetry::Telemetry;
use super::voice_jobs::VoiceJobs;
use crossbeam_channel::{bounded, Receiver, Sender};
use ringbuf::traits::Split;
use ringbuf::{HeapCons, HeapProd, HeapRb};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Lowest host rate of the offline renders (`noether play --rate`, Hz: the rates a WAV file
/// is played at). The engine itself activates at every positive finite rate: the models run
/// at their own simulation rate and are resampled to the host's.
pub const MIN_HOST_RATE: f64 = 8_000.0;
/// Highest host rate of the offline renders (Hz; see [`MIN_HOST_RATE`]).
pub const MAX_HOST_RATE: f64 = 768_000.0;
/// Shortest interval between two retunes of the sounding voices (s): continuous automation
/// costs at most one O(N) retune per voice every 2 ms.
pub(super) const RETUNE_INTERVAL: f64 = 0.002;
/// Cross-fade of a replaced bank (s).
pub(super) const FADE: f64 = 0.02;
/// Polling period of a blocking activation waiting for its bank.
pub(super) const POLL_WAIT: Duration = Duration::from_millis(2);

/// The real-time engine (audio thread). See the module documentation of [`super`] for the
/// lifecycle and threading rules.
pub struct Engine {
    pub(super) params: Arc<SharedParams>,
    pub(super) values: ParamValues,
    pub(super) bank: Option<Box<Bank>>,
    /// The banks on their way in (from the worker) and out (fading, parked, back to the
    /// worker).
    pub(super) handover: Handover,
    pub(super) bank_tx: Sender<Box<Bank>>,
    pub(super) retire_rx: Receiver<Box<Bank>>,
    pub(super) commands: HeapCons<GuiCommand>,
    pub(super) telemetry_tx: HeapProd<Telemetry>,
    pub(super) status: Arc<WorkerStatus>,
    /// What the worker builds for (this engine's host rate and generation).
    pub(super) request: Arc<Mutex<BuildRequest>>,
    /// The current activation; banks of other generations are not played.
    pub(super) generation: u64,
    /// The worker thread (started by the first activation, joined on drop).
    pub(super) worker: Option<Worker>,
    /// The voices' jobs on the pool's workers: the pool, the step board, the bank a late
    /// job holds and the events waiting for it.
    pub(super) jobs: VoiceJobs,
    pub(super) host_rate: f64,
    pub(super) max_block: usize,
    /// The player's controllers, the key table and what the sounding voices were tuned with.
    pub(super) notes: NoteState,
    pub(super) frame: u64,
    pub(super) gain: f32,
    /// Low cut, limiter and full-scale guard at the host rate (rebuilt by `activate`).
    pub(super) output: OutputStage,
    pub(super) fade_len: usize,
    pub(super) scratch: [Vec<f32>; 2],
    pub(super) watch: Option<u8>,
    /// What the engine counted since it was created (reported by `readout.rs`).
    pub(super) counts: Counts,
    /// The telemetry accumulators between two frames.
    pub(super) meters: Meters,
    /// The CPU governor (off until [`Engine::set_governor`]).
    pub(super) governor: Governor,
}

impl Engine {
    /// Creates an engine reading `params`, and its control handle. Main thread (allocates the
    /// queues); the engine makes no sound until [`Self::activate`].
    pub fn new(params: Arc<SharedParams>) -> (Engine, EngineHandle) {
        let (cmd_tx, cmd_rx) = HeapRb::<GuiCommand>::new(256).split();
        let (tel_tx, tel_rx) = HeapRb::<Telemetry>::new(8).split();
        let (bank_tx, bank_rx) = bounded(1);
        let (retire_tx, retire_rx) = bounded(4);
        let status = Arc::new(WorkerStatus::default());
        let values = params.snapshot();
        let engine = Engine {
            params: params.clone(),
            values,
            bank: None,
            handover: Handover::new(bank_rx, retire_tx),
            bank_tx,
            retire_rx,
            commands: cmd_rx,
            telemetry_tx: tel_tx,
            status: status.clone(),
            request: Arc::new(Mutex::new(BuildRequest {
                host_rate: 48_000.0,
                generation: 0,
                active: false,
                last_good: None,
                preview: false,
                governed: false,
                kept: None,
            })),
            generation: 0,
            worker: None,
            jobs: VoiceJobs::new(),
            host_rate: 48_000.0,
            max_block: 0,
            notes: NoteState::new(values, &params),
            frame: 0,
            gain: 1.0,
            output: OutputStage::new(48_000.0),
            fade_len: 1,
            scratch: [vec![0.0; CHUNK], vec![0.0; CHUNK]],
            watch: None,
            counts: Counts::default(),
            meters: Meters::default(),
            governor: Governor {
                cores: Pool::default_workers() as f64 + 1.0,
                ..Governor::default()
            },
        };
        let handle = EngineHandle {
            params,
            commands: cmd_tx,
            telemetry: tel_rx,
            status,
        };
        (engine, handle)
    }

    /// Puts every voice at rest, clears the resampler histories, controllers and telemetry
    /// accumulators. Audio thread safe (no allocation, no drop of a bank). While a late voice
    /// job holds the bank, its voices are reset when it returns.
    pub fn reset(&mut self) {
        self.jobs.reset_pending = self.jobs.held.is_some();
        if let Some(b) = self.bank.as_mut() {
            for v in &mut b.voices {
                v.reset();
            }
            b.resampler.reset();
            b.above.reset();
        }
        if let Some((old, _)) = self.handover.retiring.take() {
            self.retire(old);
        }
        self.notes.reset_controllers();
        self.gain = db_to_gain(self.values.get(ParamId::Gain));
        self.output.reset();
        self.meters.next = self.frame;
    }

    /// Processes one block without events: `left` and `right` (equal lengths, any length) are
    /// overwritten. Audio thread: no allocation, lock or I/O; bounded work.
    pub fn process(&mut self, left: &mut [f32], right: &mut [f32]) {
        self.process_events(&[], left, right);
    }

    /// Processes one block, applying `events` (sorted by offset) at their sample offsets.
    /// Audio thread: no allocation, lock or I/O; bounded work (internal chunks of
    /// [`CHUNK`] samples, at most `Modes` steps of each voice per simulation sample).
    pub fn process_events(&mut self, events: &[Event], left: &mut [f32], right: &mut [f32]) {
        let start = Instant::now();
        let n = left.len().min(right.len());
        self.poll_commands();
        self.values = self.params.snapshot();
        if let Some(t) = self
            .params
            .tuning()
            .read_if_changed(&mut self.notes.tuning_seen)
        {
            self.notes.key_tuning = t;
        }
        let mut ev = 0;
        let mut pos = 0;
        while pos < n {
            while ev < events.len() && events[ev].offset as usize <= pos {
                self.apply(events[ev].kind);
                ev += 1;
            }
            let next = events.get(ev).map_or(n, |e| (e.offset as usize).min(n));
            let end = next.min(pos + CHUNK).min(n).max(pos + 1);
            let (l, r) = (&mut left[pos..end], &mut right[pos..end]);
            self.render(l, r);
            pos = end;
        }
        for e in &events[ev..] {
            self.apply(e.kind);
        }
        for x in left[n..].iter_mut().chain(right[n..].iter_mut()) {
            *x = 0.0;
        }
        self.account(&left[..n], &right[..n], start);
    }

    /// Renders one chunk (at most [`CHUNK`] samples).
    ///
    /// When a voice job is late (still running on a worker after the bounded wait), the bank
    /// is held aside: only this loop touches it (through its job lanes), so its other voices
    /// keep sounding, while events and GUI commands wait; when the job is done the bank
    /// returns and the waiting events apply, in order.
    fn render(&mut self, left: &mut [f32], right: &mut [f32]) {
        let len = left.len();
        self.swap_bank();
        self.retune_voices(len);
        left.fill(0.0);
        right.fill(0.0);
        let mut t = Tally::default();
        // Participants from the `threads` parameter (0: every worker and the audio thread),
        // at most the pool's workers plus one.
        let workers = self.jobs.pool.as_ref().map_or(0, |p| p.workers());
        let want = match self.values.index_of(ParamId::Threads) {
            0 => workers + 1,
            t => t.min(workers + 1),
        };
        self.jobs.threads_used = want as u8;
        let share = Sharing {
            pool: self.jobs.pool.as_ref(),
            helpers: want - 1,
            wait: self
                .jobs
                .job_wait
                .unwrap_or_else(|| Duration::from_secs_f64(len as f64 / self.host_rate)),
        };
        let mut hold = false;
        let mut release = false;
        if let Some(b) = self.bank.as_mut() {
            hold = run_bank(b, share, left, right, &mut t);
        } else if let Some(b) = self.jobs.held.as_mut() {
            release = !run_bank(b, share, left, right, &mut t);
        }
        if let Some((old, done)) = self.handover.retiring.as_mut() {
            let [sl, sr] = &mut self.scratch;
            let (sl, sr) = (&mut sl[..len], &mut sr[..len]);
            sl.fill(0.0);
            sr.fill(0.0);
            // A late job of the retiring bank needs nothing more: the bank is only run here
            // and handed away only when the pool is quiescent.
            run_bank(old, share, sl, sr, &mut t);
            for i in 0..len {
                let g = 1.0 - ((*done + i) as f32 / self.fade_len as f32).min(1.0);
                left[i] += g * sl[i];
                right[i] += g * sr[i];
            }
            *done += len;
            if *done >= self.fade_len {
                if let Some((old, _)) = self.handover.retiring.take() {
                    self.retire(old);
                }
            }
        }
        self.counts.newton_cap_hits += t.hits;
        self.counts.mallet_impacts += t.impacts;
        self.counts.diverged += t.diverged;
        self.counts.late += t.late;
        if hold {
            self.jobs.held = self.bank.take();
        } else if release {
            self.bank = self.jobs.held.take();
            if std::mem::take(&mut self.jobs.reset_pending) {
                if let Some(b) = self.bank.as_mut() {
                    for v in &mut b.voices {
                        v.reset();
                    }
                }
            }
            for i in 0..std::mem::take(&mut self.jobs.deferred_len) {
                self.apply(self.jobs.deferred[i]);
            }
        }
        // Output gain, smoothed per sample towards the target (time constant about 5 ms).
        let target = db_to_gain(self.values.get(ParamId::Gain));
        let k = 1.0 - (-1.0 / (0.005 * self.host_rate as f32)).exp();
        for (l, r) in left.iter_mut().zip(right.iter_mut()) {
            self.gain += k * (target - self.gain);
            *l *= self.gain;
            *r *= self.gain;
        }
        let limit = self.values.index_of(ParamId::Limiter) == 1;
        self.output
            .process(left, right, self.values.get(ParamId::LowCut), limit);
        self.frame += len as u64;
        self.rest_if_silent(target);
    }

    /// At rest (no voice sounds, no bank is held by a late job or fading out, the resampler
    /// reads only zeros and the output stage holds only zeros), puts the chain after the voices
    /// back in the state a new engine's silence has: the resampler's time origin
    /// ([`crate::engine::resample::Resampler::reanchor`]), the limiter's release state, and the
    /// output gain exactly at its target (the smoother can stop an ulp or a few away). Nothing
    /// audible changes (everything is silent), and the next note after any performance sounds
    /// bit for bit as on a new instance (`tests/engine/long_performance.rs`). Audio thread,
    /// O(history + look-ahead).
    fn rest_if_silent(&mut self, gain_target: f32) {
        if self.jobs.held.is_some() || self.handover.retiring.is_some() {
            return;
        }
        let Some(b) = self.bank.as_mut() else {
            return;
        };
        if b.voices.iter().any(|v| v.active) || !self.output.is_at_rest() {
            return;
        }
        b.above.reanchor();
        if b.resampler.reanchor() {
            self.output.reset();
            self.gain = gain_target;
        }
    }
}

impl Drop for Engine {
    /// Stops the pool and joins the worker thread (main thread; a build under way finishes
    /// first).
    fn drop(&mut self) {
        self.deactivate();
        if let Some(mut w) = self.worker.take() {
            w.stop();
        }
    }
}

fn db_to_gain(db: f32) -> f32 {
    10f32.powf(db / 20.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::bank::ModalCache;
    use crate::models::plate::StepBoard;

    /// A string set the models refuse (a 1 km string: outside `string.length`'s range; the
    /// table's ranges never allow it, so it is written around them).
    fn refused_string() -> ParamValues {
        let mut v = ParamValues::defaults();
        v.0[ParamId::Model.index()] = 4.0;
        v.0[ParamId::Modes.index()] = 16.0;
        v.0[ParamId::Size.index()] = 1000.0;
        v
    }

    #[test]
    fn a_refused_set_falls_back_to_the_last_good_model_then_the_defaults() {
        let mut cache = ModalCache::default();
        let board = Arc::new(StepBoard::new());
        let mut good = ParamValues::defaults();
        good.0[ParamId::Model.index()] = 3.0;
        good.0[ParamId::Modes.index()] = 16.0;
        good.0[ParamId::Gain.index()] = -3.0;
        let mut wanted = refused_string();
        wanted.0[ParamId::Gain.index()] = -12.0;
        let (bank, refused) =
            Bank::build_playable(wanted, Some(good), 48_000.0, &mut cache, &board, 1, None)
                .unwrap();
        let refused = refused.expect("the refusal is returned");
        assert!(refused.field.contains("length"), "{refused}");
        // The last good model's structure with the wanted playing values.
        assert_eq!(bank.values.rebuild_key(), good.rebuild_key());
        assert_eq!(bank.values.get(ParamId::Gain), -12.0);
        // With no last good model: the table's defaults.
        let (bank, refused) =
            Bank::build_playable(wanted, None, 48_000.0, &mut cache, &board, 2, None).unwrap();
        assert!(refused.is_some());
        assert_eq!(bank.kind, super::super::kinds::ModelKind::Gong);
        // A buildable set is built as asked.
        let (bank, refused) =
            Bank::build_playable(good, None, 48_000.0, &mut cache, &board, 3, None).unwrap();
        assert!(refused.is_none());
        assert_eq!(bank.values, good);
    }
}
