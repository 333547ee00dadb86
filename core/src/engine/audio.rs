//! [`Engine`]: the audio-thread object (lifecycle, events, block processing, voice pool).

use super::bank::{Bank, ModalCache, CHUNK};
use super::events::{Event, EventKind, GuiCommand};
use super::handle::{EngineHandle, Worker, WorkerSetup, WorkerStatus};
use super::kinds::ModelKind;
use super::params::{ParamId, ParamValues, SharedParams, PARAMS};
use super::telemetry::{Telemetry, VoiceModelInfo, VoiceTelemetry, MAX_VOICES};
use super::voice::Physics;
use crate::error::{check_closed, ParamError};
use crate::models::source::EnergyTerms;
use crossbeam_channel::{bounded, Receiver, Sender};
use ringbuf::traits::{Consumer, Producer, Split};
use ringbuf::{HeapCons, HeapProd, HeapRb};
use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::Instant;

/// Lowest accepted host rate (Hz).
pub const MIN_HOST_RATE: f64 = 22_050.0;
/// Highest accepted host rate (Hz).
pub const MAX_HOST_RATE: f64 = 192_000.0;
/// A voice ends when its stored energy falls below this fraction of its peak after the
/// excitation (1e-10: -100 dB in amplitude, since energy goes as amplitude squared).
pub const SILENCE_RATIO: f64 = 1e-10;
/// Telemetry frames per second.
const TELEMETRY_RATE: f64 = 30.0;
/// Shortest interval between two retunes of the sounding voices (s): continuous automation
/// costs at most one O(N) retune per voice every 2 ms.
const RETUNE_INTERVAL: f64 = 0.002;
/// Cross-fade of a replaced bank (s).
const FADE: f64 = 0.02;

/// The real-time engine (audio thread). See the module documentation of [`super`] for the
/// lifecycle and threading rules.
pub struct Engine {
    params: Arc<SharedParams>,
    values: ParamValues,
    /// The non-rebuild values and bend the sounding voices were last tuned with.
    applied: (ParamValues, f32),
    bank: Option<Box<Bank>>,
    retiring: Option<(Box<Bank>, usize)>,
    pending_drop: [Option<Box<Bank>>; 3],
    overflow: Option<Box<Bank>>,
    bank_rx: Receiver<Box<Bank>>,
    retire_tx: Sender<Box<Bank>>,
    bank_tx: Sender<Box<Bank>>,
    retire_rx: Receiver<Box<Bank>>,
    commands: HeapCons<GuiCommand>,
    telemetry_tx: HeapProd<Telemetry>,
    status: Arc<WorkerStatus>,
    worker: Option<Worker>,
    host_rate: f64,
    max_block: usize,
    bend: f32,
    wheel: f32,
    sustain: bool,
    frame: u64,
    gain: f32,
    retune_wait: usize,
    fade_len: usize,
    scratch: [Vec<f32>; 2],
    watch: Option<u8>,
    newton_cap_hits: u64,
    diverged: u64,
    refused: u64,
    // Telemetry accumulators.
    tele_next: u64,
    peak: [f32; 2],
    sumsq: [f64; 2],
    tele_samples: u64,
    busy: f64,
    cpu_peak: f32,
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
            applied: (values, 0.0),
            bank: None,
            retiring: None,
            pending_drop: [None, None, None],
            overflow: None,
            bank_rx,
            retire_tx,
            bank_tx,
            retire_rx,
            commands: cmd_rx,
            telemetry_tx: tel_tx,
            status: status.clone(),
            worker: None,
            host_rate: 48_000.0,
            max_block: 0,
            bend: 0.0,
            wheel: 0.5,
            sustain: false,
            frame: 0,
            gain: 1.0,
            retune_wait: 0,
            fade_len: 1,
            scratch: [vec![0.0; CHUNK], vec![0.0; CHUNK]],
            watch: None,
            newton_cap_hits: 0,
            diverged: 0,
            refused: 0,
            tele_next: 0,
            peak: [0.0; 2],
            sumsq: [0.0; 2],
            tele_samples: 0,
            busy: 0.0,
            cpu_peak: 0.0,
        };
        let handle = EngineHandle {
            params,
            commands: cmd_tx,
            telemetry: tel_rx,
            status,
        };
        (engine, handle)
    }

    /// Prepares for host rate `host_rate` (Hz, 22 050 to 192 000) and blocks of at most
    /// `max_block` samples (1 to 8192 are tested; longer blocks are split internally too):
    /// builds the voice bank for the current parameters on the calling thread (from the modal
    /// cache this takes milliseconds; a new large basis takes seconds) and starts the worker
    /// thread. Main thread; allocates. Calling it again re-activates (new rate).
    pub fn activate(&mut self, host_rate: f64, max_block: usize) -> Result<(), ParamError> {
        check_closed("host_rate", host_rate, MIN_HOST_RATE, MAX_HOST_RATE)?;
        if max_block == 0 {
            return Err(ParamError::new("max_block", 0, "integer >= 1"));
        }
        self.deactivate();
        // Banks still queued were built for the old rate: drop them here (main thread).
        while self.bank_rx.try_recv().is_ok() {}
        while self.retire_rx.try_recv().is_ok() {}
        self.retiring = None;
        self.pending_drop = [None, None, None];
        self.overflow = None;
        let values = self.params.snapshot();
        let mut cache = ModalCache::default();
        let next = self.bank.as_ref().map_or(1, |b| b.id + 1);
        let bank = Bank::build(&values, host_rate, &mut cache, next)?;
        self.host_rate = host_rate;
        self.max_block = max_block;
        self.fade_len = ((FADE * host_rate) as usize).max(1);
        self.values = values;
        self.applied = (values, self.bend);
        self.bank = Some(Box::new(bank));
        self.reset();
        let worker = Worker::spawn(WorkerSetup {
            params: self.params.clone(),
            status: self.status.clone(),
            host_rate,
            bank_tx: self.bank_tx.clone(),
            retire_rx: self.retire_rx.clone(),
            cache,
            built_key: values.rebuild_key(),
            next_id: next + 1,
        })
        .map_err(|e| ParamError::new("worker thread", e, "a thread the OS can start"))?;
        self.worker = Some(worker);
        Ok(())
    }

    /// Stops the worker thread (main thread). The engine keeps its bank and can still
    /// process, without rebuilds, until re-activated.
    pub fn deactivate(&mut self) {
        if let Some(mut w) = self.worker.take() {
            w.stop();
        }
    }

    /// Puts every voice at rest, clears the resampler histories, controllers and telemetry
    /// accumulators. Audio thread safe (no allocation, no drop of a bank).
    pub fn reset(&mut self) {
        if let Some(b) = self.bank.as_mut() {
            for v in &mut b.voices {
                v.reset();
            }
            b.resampler.reset();
        }
        if let Some((old, _)) = self.retiring.take() {
            self.retire(old);
        }
        self.bend = 0.0;
        self.wheel = 0.5;
        self.sustain = false;
        self.gain = db_to_gain(self.values.get(ParamId::Gain));
        self.retune_wait = 0;
        self.tele_next = self.frame;
    }

    /// Host rate set by [`Self::activate`] (Hz).
    pub fn host_rate(&self) -> f64 {
        self.host_rate
    }

    /// Latency in host samples (the resampler's half-width; report it to the host).
    pub fn latency_samples(&self) -> u32 {
        self.bank
            .as_ref()
            .map_or(0, |b| b.latency_host().round() as u32)
    }

    /// Identifier of the voice bank in use (0 before activation; changes with every swap).
    pub fn bank_id(&self) -> u64 {
        self.bank.as_ref().map_or(0, |b| b.id)
    }

    /// The model of the bank in use.
    pub fn model(&self) -> Option<ModelKind> {
        self.bank.as_ref().map(|b| b.kind)
    }

    /// Simulation rate of the bank in use (Hz).
    pub fn sim_rate(&self) -> Option<f64> {
        self.bank.as_ref().map(|b| b.sim_rate)
    }

    /// Voices in the pool of the bank in use.
    pub fn polyphony(&self) -> usize {
        self.bank.as_ref().map_or(0, |b| b.voices.len())
    }

    /// Sounding voices.
    pub fn active_voices(&self) -> usize {
        self.bank
            .as_ref()
            .map_or(0, |b| b.voices.iter().filter(|v| v.active).count())
    }

    /// Energy terms (J) of voice `slot` if it is sounding. O(N) for strings.
    pub fn voice_energy(&self, slot: usize) -> Option<EnergyTerms> {
        let v = self.bank.as_ref()?.voices.get(slot)?;
        v.active.then(|| v.energy_terms())
    }

    /// What voice `slot` simulates for its note, if it is sounding. O(N_Φ).
    pub fn voice_model(&self, slot: usize) -> Option<VoiceModelInfo> {
        let v = self.bank.as_ref()?.voices.get(slot)?;
        v.active.then(|| v.model_info())
    }

    /// Key of voice `slot` if it is sounding.
    pub fn voice_key(&self, slot: usize) -> Option<u8> {
        let v = self.bank.as_ref()?.voices.get(slot)?;
        v.active.then_some(v.key)
    }

    /// Contact Newton solves that hit the cap since creation.
    pub fn newton_cap_hits(&self) -> u64 {
        self.newton_cap_hits
    }

    /// Voices silenced because their state became non-finite or their output passed
    /// [`VOICE_CEILING`].
    pub fn diverged_voices(&self) -> u64 {
        self.diverged
    }

    /// Notes refused because their coefficients would be unstable (θ = 1 scheme above its
    /// limit, or an exact-scheme mode on a multiple of π).
    pub fn refused_notes(&self) -> u64 {
        self.refused
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

    /// Starts a note now (velocity in (0, 1]; 0 is a note-off).
    pub fn note_on(&mut self, key: u8, velocity: f32) {
        self.apply(EventKind::NoteOn { key, velocity });
    }

    /// Releases a note now.
    pub fn note_off(&mut self, key: u8) {
        self.apply(EventKind::NoteOff { key });
    }

    /// Pitch bend now, normalised to [-1, 1].
    pub fn pitch_bend(&mut self, value: f32) {
        self.apply(EventKind::PitchBend(value));
    }

    /// Mod wheel now, normalised to [0, 1].
    pub fn mod_wheel(&mut self, value: f32) {
        self.apply(EventKind::ModWheel(value));
    }

    /// Sustain pedal now.
    pub fn sustain(&mut self, down: bool) {
        self.apply(EventKind::Sustain(down));
    }

    fn physics(&self) -> Physics {
        Physics {
            values: self.values,
            bend: self.bend,
        }
    }

    /// Applies one event at the current position.
    fn apply(&mut self, kind: EventKind) {
        match kind {
            EventKind::NoteOn { key, velocity } if velocity > 0.0 && velocity.is_finite() => {
                self.start_note(key.min(127), velocity.min(1.0))
            }
            EventKind::NoteOn { key, .. } | EventKind::NoteOff { key } => self.release(key),
            EventKind::PitchBend(x) if x.is_finite() => {
                self.bend = x.clamp(-1.0, 1.0) * self.values.get(ParamId::PitchBendRange);
            }
            EventKind::ModWheel(x) if x.is_finite() => self.wheel = x.clamp(0.0, 1.0),
            EventKind::Sustain(down) => {
                self.sustain = down;
                if !down {
                    let p = self.physics();
                    if let Some(b) = self.bank.as_mut() {
                        for v in b.voices.iter_mut().filter(|v| v.active && v.sustained) {
                            v.sustained = false;
                            if !v.retune(&p) {
                                v.reset();
                                self.refused += 1;
                            }
                        }
                    }
                }
            }
            EventKind::AllNotesOff => {
                for key in 0..=127 {
                    self.release(key);
                }
            }
            EventKind::AllSoundOff => {
                if let Some(b) = self.bank.as_mut() {
                    for v in &mut b.voices {
                        v.reset();
                    }
                }
            }
            EventKind::PitchBend(_) | EventKind::ModWheel(_) => {}
        }
    }

    fn start_note(&mut self, key: u8, vel: f32) {
        let p = self.physics();
        let (frame, wheel) = (self.frame, self.wheel);
        let Some(b) = self.bank.as_mut() else { return };
        let slot = b
            .voices
            .iter()
            .position(|v| v.active && v.key == key)
            .or_else(|| b.voices.iter().position(|v| !v.active))
            .or_else(|| {
                // Steal the quietest released voice, else the oldest.
                let quiet = b
                    .voices
                    .iter()
                    .enumerate()
                    .filter(|(_, v)| v.released())
                    .min_by(|x, y| x.1.energy.total_cmp(&y.1.energy))
                    .map(|(i, _)| i);
                quiet.or_else(|| {
                    b.voices
                        .iter()
                        .enumerate()
                        .min_by_key(|(_, v)| v.started)
                        .map(|(i, _)| i)
                })
            });
        if let Some(i) = slot {
            if !b.voices[i].start(&p, key, vel, wheel, frame) {
                self.refused += 1;
            }
        }
    }

    fn release(&mut self, key: u8) {
        let p = self.physics();
        let sustain = self.sustain;
        let Some(b) = self.bank.as_mut() else { return };
        for v in b
            .voices
            .iter_mut()
            .filter(|v| v.active && v.held && v.key == key)
        {
            v.held = false;
            if sustain {
                v.sustained = true;
            } else if !v.retune(&p) {
                v.reset();
                self.refused += 1;
            }
        }
    }

    fn poll_commands(&mut self) {
        while let Some(c) = self.commands.try_pop() {
            match c {
                GuiCommand::Event(k) => self.apply(k),
                GuiCommand::Reset => self.reset(),
                GuiCommand::Watch(w) => self.watch = w,
            }
        }
    }

    /// Sends a replaced bank back to the worker, or parks it until the queue has room (new
    /// banks are accepted only when nothing is parked, so at most two banks are ever parked:
    /// the slots never overflow and no bank is dropped on the audio thread).
    fn retire(&mut self, bank: Box<Bank>) {
        if let Err(e) = self.retire_tx.try_send(bank) {
            let b = e.into_inner();
            if let Some(slot) = self.pending_drop.iter_mut().find(|s| s.is_none()) {
                *slot = Some(b);
            } else {
                // Unreachable (see above); keep the bank alive rather than drop it here.
                self.overflow = Some(b);
            }
        }
    }

    fn swap_bank(&mut self) {
        for i in 0..self.pending_drop.len() {
            if let Some(b) = self.pending_drop[i].take() {
                if let Err(e) = self.retire_tx.try_send(b) {
                    self.pending_drop[i] = Some(e.into_inner());
                }
            }
        }
        if self.pending_drop.iter().any(|s| s.is_some()) || self.overflow.is_some() {
            return;
        }
        let Ok(new) = self.bank_rx.try_recv() else {
            return;
        };
        if new.host_rate != self.host_rate {
            self.retire(new);
            return;
        }
        if let Some((old, _)) = self.retiring.take() {
            self.retire(old);
        }
        if let Some(old) = self.bank.replace(new) {
            if old.voices.iter().any(|v| v.active) {
                self.retiring = Some((old, 0));
            } else {
                self.retire(old);
            }
        }
        // Notes of the new bank take the current tuning at their start.
        self.applied = (self.values, self.bend);
    }

    fn retune_voices(&mut self, len: usize) {
        self.retune_wait = self.retune_wait.saturating_sub(len);
        let changed = self.applied.1 != self.bend
            || PARAMS
                .iter()
                .filter(|p| !p.rebuild)
                .any(|p| self.applied.0.get(p.id).to_bits() != self.values.get(p.id).to_bits());
        if !changed || self.retune_wait > 0 {
            return;
        }
        self.applied = (self.values, self.bend);
        self.retune_wait = (RETUNE_INTERVAL * self.host_rate) as usize;
        let p = self.physics();
        if let Some(b) = self.bank.as_mut() {
            for v in b.voices.iter_mut().filter(|v| v.active) {
                if !v.retune(&p) {
                    v.reset();
                    self.refused += 1;
                }
            }
        }
    }

    /// Renders one chunk (at most [`CHUNK`] samples).
    fn render(&mut self, left: &mut [f32], right: &mut [f32]) {
        let len = left.len();
        self.swap_bank();
        self.retune_voices(len);
        left.fill(0.0);
        right.fill(0.0);
        let (mut hits, mut div) = (0, 0);
        if let Some(b) = self.bank.as_mut() {
            run_bank(b, left, right, &mut hits, &mut div);
        }
        if let Some((old, done)) = self.retiring.as_mut() {
            let [sl, sr] = &mut self.scratch;
            let (sl, sr) = (&mut sl[..len], &mut sr[..len]);
            sl.fill(0.0);
            sr.fill(0.0);
            run_bank(old, sl, sr, &mut hits, &mut div);
            for i in 0..len {
                let g = 1.0 - ((*done + i) as f32 / self.fade_len as f32).min(1.0);
                left[i] += g * sl[i];
                right[i] += g * sr[i];
            }
            *done += len;
            if *done >= self.fade_len {
                if let Some((old, _)) = self.retiring.take() {
                    self.retire(old);
                }
            }
        }
        self.newton_cap_hits += hits;
        self.diverged += div;
        // Output gain, smoothed per sample towards the target (time constant about 5 ms).
        let target = db_to_gain(self.values.get(ParamId::Gain));
        let k = 1.0 - (-1.0 / (0.005 * self.host_rate as f32)).exp();
        for (l, r) in left.iter_mut().zip(right.iter_mut()) {
            self.gain += k * (target - self.gain);
            *l *= self.gain;
            *r *= self.gain;
        }
        self.frame += len as u64;
    }

    fn account(&mut self, left: &[f32], right: &[f32], start: Instant) {
        for (c, x) in [left, right].into_iter().enumerate() {
            for &s in x {
                self.peak[c] = self.peak[c].max(s.abs());
                self.sumsq[c] += (s as f64) * (s as f64);
            }
        }
        self.tele_samples += left.len() as u64;
        let dur = left.len() as f64 / self.host_rate;
        let spent = start.elapsed().as_secs_f64();
        self.busy += spent;
        if dur > 0.0 {
            self.cpu_peak = self.cpu_peak.max((spent / dur) as f32);
        }
        if self.frame >= self.tele_next {
            self.tele_next = self.frame + (self.host_rate / TELEMETRY_RATE) as u64;
            self.send_telemetry();
        }
    }

    fn send_telemetry(&mut self) {
        let mut t = Telemetry {
            frame: self.frame,
            cpu_load: (self.busy / (self.tele_samples.max(1) as f64 / self.host_rate)) as f32,
            cpu_peak: self.cpu_peak,
            rebuilding: self.status.rebuilding.load(Ordering::Acquire),
            newton_cap_hits: self.newton_cap_hits,
            diverged: self.diverged,
            ..Telemetry::default()
        };
        for c in 0..2 {
            t.peak[c] = self.peak[c];
            t.rms[c] = (self.sumsq[c] / self.tele_samples.max(1) as f64).sqrt() as f32;
        }
        self.peak = [0.0; 2];
        self.sumsq = [0.0; 2];
        self.tele_samples = 0;
        self.busy = 0.0;
        self.cpu_peak = 0.0;
        if let Some(b) = self.bank.as_mut() {
            t.bank = b.id;
            t.sim_rate = b.sim_rate as f32;
            let mut loudest: Option<(usize, f64)> = None;
            for (i, v) in b.voices.iter().enumerate().take(MAX_VOICES) {
                if !v.active {
                    continue;
                }
                let e = v.energy_terms();
                t.voices[i] = VoiceTelemetry {
                    active: true,
                    key: v.key,
                    held: v.held || v.sustained,
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
            if let Some(w) = watched {
                t.watched = Some(w as u8);
                b.voices[w].snapshot(&mut t.displacement, &mut t.mode_freq, &mut t.mode_amplitude);
            }
        }
        let _ = self.telemetry_tx.try_push(t);
    }
}

impl Drop for Engine {
    fn drop(&mut self) {
        self.deactivate();
    }
}

fn db_to_gain(db: f32) -> f32 {
    10f32.powf(db / 20.0)
}

/// Runs every active voice of `b` for the chunk and resamples into `left`/`right`.
fn run_bank(b: &mut Bank, left: &mut [f32], right: &mut [f32], hits: &mut u64, div: &mut u64) {
    let m = b.resampler.input_needed(left.len());
    let any = b.voices.iter().any(|v| v.active);
    if !any && b.resampler.is_silent() {
        b.resampler.advance_silent(left.len(), m);
        left.fill(0.0);
        right.fill(0.0);
        return;
    }
    let (sl, sr) = (&mut b.sim_l[..m], &mut b.sim_r[..m]);
    let (vl, vr) = (&mut b.voice_l[..m], &mut b.voice_r[..m]);
    sl.fill(0.0);
    sr.fill(0.0);
    for v in b.voices.iter_mut().filter(|v| v.active) {
        vl.fill(0.0);
        vr.fill(0.0);
        if !v.run(vl, vr, b.norm) {
            v.reset();
            *div += 1;
            continue;
        }
        for i in 0..m {
            sl[i] += vl[i];
            sr[i] += vr[i];
        }
        *hits += v.take_cap_hits();
        let e = v.level_energy();
        v.energy = e;
        v.peak_energy = v.peak_energy.max(e);
        if !v.exciting() && (!e.is_finite() || e <= SILENCE_RATIO * v.peak_energy) {
            if !e.is_finite() {
                *div += 1;
            }
            v.reset();
        }
    }
    b.resampler.push(sl, sr);
    b.resampler.produce(left, right);
}
