//! Notes, controllers and GUI commands on the audio thread: the [`Engine`]'s event handling
//! (note on and off with voice allocation, bend, wheel, sustain), the physical inputs the
//! voices read ([`Physics`]) and the retune of sounding voices when playing values change.

use super::audio::{Engine, RETUNE_INTERVAL};
use super::bank::Bank;
use super::events::{EventKind, GuiCommand, NoteExpression, MAX_NOTE_TUNING, MAX_NOTE_VOLUME};
use super::governor::{voice_share, FADE_CHUNKS};
use super::params::{ParamId, PARAMS};
use super::voice::{Physics, Voice, VoiceModel};
use ringbuf::traits::Consumer;

impl Engine {
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

    /// The host's tempo in beats per minute (`None`: the host gives none, or stopped giving
    /// one), for the drone's cycle when it follows the tempo (`drone_sync`). Values outside
    /// [`MIN_TEMPO`](super::MIN_TEMPO) to [`MAX_TEMPO`](super::MAX_TEMPO) or not finite are
    /// taken as none. A change retunes the sounding voices (at most every
    /// `RETUNE_INTERVAL`). Audio thread, O(1), no allocation; a host calls it each block.
    pub fn set_host_tempo(&mut self, bpm: Option<f64>) {
        self.notes.tempo =
            bpm.filter(|b| b.is_finite() && (super::MIN_TEMPO..=super::MAX_TEMPO).contains(b));
    }

    pub(super) fn physics(&self) -> Physics {
        Physics {
            values: self.values,
            bend: self.notes.bend,
            tuning: self.notes.key_tuning,
            price_cap: f64::INFINITY,
            tempo: self.notes.tempo,
        }
    }

    /// Applies one event at the current position (or keeps it while a late job holds the
    /// bank).
    pub(super) fn apply(&mut self, kind: EventKind) {
        if self.jobs.held.is_some() {
            if let Some(slot) = self.jobs.deferred.get_mut(self.jobs.deferred_len) {
                *slot = kind;
                self.jobs.deferred_len += 1;
            } else {
                self.counts.deferred_lost += 1;
            }
            return;
        }
        match kind {
            // A key the tuning leaves unmapped (a Scala `.kbm` 'x') plays nothing.
            EventKind::NoteOn { key, velocity } if velocity > 0.0 && velocity.is_finite() => {
                if self.notes.key_tuning.is_mapped(key.min(127)) {
                    self.start_note(key.min(127), velocity.min(1.0))
                }
            }
            EventKind::NoteOn { key, .. } | EventKind::NoteOff { key } => self.release(key),
            EventKind::PitchBend(x) if x.is_finite() => {
                self.notes.bend = x.clamp(-1.0, 1.0) * self.values.get(ParamId::PitchBendRange);
            }
            EventKind::ModWheel(x) if x.is_finite() => self.notes.wheel = x.clamp(0.0, 1.0),
            EventKind::Sustain(down) => {
                self.notes.sustain = down;
                if !down {
                    let p = self.physics();
                    if let Some(b) = self.bank.as_mut() {
                        for v in b.voices.iter_mut().filter(|v| v.active && v.sustained) {
                            v.sustained = false;
                            if !v.retune(&p) {
                                v.reset();
                                self.counts.refused += 1;
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
            EventKind::NoteExpression { key, expression } => self.note_expression(key, expression),
            EventKind::NoteModulation { key, param, value } => {
                self.note_modulation(key, param, value)
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

    pub(super) fn start_note(&mut self, key: u8, vel: f32) {
        let p = self.physics();
        let (frame, wheel) = (self.frame, self.notes.wheel);
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
            let mut p = p;
            let cores = self.values.get(ParamId::CpuBudget);
            if let Some(budget) = self.governor.budget(cores) {
                let share = voice_share(cores, self.governor.cores);
                let (cap, shed) = fit_note(b, i, budget, share);
                p.price_cap = cap;
                self.governor.shed += shed;
            }
            let v = &mut b.voices[i];
            if !v.start(&p, key, vel, wheel, frame) {
                self.counts.refused += 1;
            }
            if let VoiceModel::Plate(pv) = &mut v.model {
                self.governor.reduced += u64::from(std::mem::take(&mut pv.governed));
            }
        }
    }

    /// The CPU governor's watch (`engine/governor.rs`): after a block of `spent` wall seconds
    /// over `frames` host samples, ends the quietest voice if the blocks overrun. Audio thread.
    pub(super) fn watch_load(&mut self, spent: f64, frames: usize) {
        let duration = frames as f64 / self.host_rate;
        if !self
            .governor
            .watch(spent, duration, frames as u64, self.host_rate)
        {
            return;
        }
        if let Some(b) = self.bank.as_mut() {
            if b.voices
                .iter()
                .filter(|v| v.active && v.fading == 0)
                .count()
                > 1
            {
                if let Some(v) = quietest(&mut b.voices, usize::MAX) {
                    v.fading = FADE_CHUNKS;
                    self.governor.shed += 1;
                }
            }
        }
    }

    pub(super) fn release(&mut self, key: u8) {
        let p = self.physics();
        let sustain = self.notes.sustain;
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
                self.counts.refused += 1;
            }
        }
    }

    pub(super) fn poll_commands(&mut self) {
        // While a late job holds the bank, commands wait in their queue.
        while self.jobs.held.is_none() {
            let Some(c) = self.commands.try_pop() else {
                break;
            };
            match c {
                GuiCommand::Event(k) => self.apply(k),
                GuiCommand::Reset => self.reset(),
                GuiCommand::Watch(w) => self.watch = w,
            }
        }
    }

    /// A per-note expression for the voice sounding `key` (a re-struck key has one voice).
    /// A tuning marks the voice for a retune at the next chunk (at most one O(modes) retune
    /// per voice and chunk however many expressions arrive); a volume applies in the mix.
    fn note_expression(&mut self, key: u8, expression: NoteExpression) {
        let Some(b) = self.bank.as_mut() else {
            return;
        };
        let Some(v) = b.voices.iter_mut().find(|v| v.active && v.key == key) else {
            return;
        };
        match expression {
            NoteExpression::Tuning(s) if s.is_finite() => {
                v.note_tuning = s.clamp(-MAX_NOTE_TUNING, MAX_NOTE_TUNING);
                v.dirty = true;
            }
            NoteExpression::Volume(g) if g.is_finite() => {
                v.note_volume = g.clamp(0.0, MAX_NOTE_VOLUME);
            }
            NoteExpression::Pressure(x) if x.is_finite() => {
                v.note_pressure = x.clamp(0.0, 1.0);
            }
            NoteExpression::Brightness(x) if x.is_finite() => {
                v.note_brightness = x.clamp(0.0, 1.0);
            }
            NoteExpression::Pan(x) if x.is_finite() => v.note_pan = x.clamp(0.0, 1.0),
            _ => {}
        }
    }

    /// The note sounding `key` gets its own `value` of `param` (module doc of
    /// [`crate::engine::voice::modulation`]): damping at the next chunk's retune, pickups at
    /// once, strike values at its next strike. O(N_Φ) at most, no allocation.
    fn note_modulation(&mut self, key: u8, param: ParamId, value: f32) {
        let Some(b) = self.bank.as_mut() else {
            return;
        };
        let Some(v) = b.voices.iter_mut().find(|v| v.active && v.key == key) else {
            return;
        };
        if !v.overrides.set(param, value) {
            return;
        }
        let own = v.overrides.get(param).unwrap_or(value) as f64;
        match (param, &mut v.model) {
            (ParamId::DampingScale, _) => v.dirty = true,
            (ParamId::PickupLeftPos, VoiceModel::Plate(pv)) => pv.place_pickup(0, own),
            (ParamId::PickupRightPos, VoiceModel::Plate(pv)) => pv.place_pickup(1, own),
            _ => {}
        }
    }

    /// Keys of the voices sounding now, as a bit set (bit `k` for MIDI key `k`): a host
    /// layer compares it across blocks to tell the host which notes have ended (CLAP's note
    /// end). While a late voice job holds the bank, the set of the last block that had it.
    /// Audio thread, O(voices).
    pub fn sounding_keys(&mut self) -> u128 {
        if let Some(b) = self.bank.as_ref() {
            self.notes.sounding_keys = b
                .voices
                .iter()
                .filter(|v| v.active)
                .fold(0u128, |set, v| set | 1u128 << v.key.min(127));
        }
        self.notes.sounding_keys
    }

    /// Retunes the sounding voices when playing values, the bend or the key table changed
    /// (at most every [`RETUNE_INTERVAL`]), and every voice whose own tuning changed.
    pub(super) fn retune_voices(&mut self, len: usize) {
        let dirty = |v: &&mut crate::engine::voice::Voice| v.active && v.dirty;
        if self
            .bank
            .as_ref()
            .is_some_and(|b| b.voices.iter().any(|v| v.active && v.dirty))
        {
            let p = self.physics();
            let b = self.bank.as_mut().expect("checked above");
            for v in b.voices.iter_mut().filter(dirty) {
                if !v.retune(&p) {
                    v.reset();
                    self.counts.refused += 1;
                }
            }
        }
        self.notes.retune_wait = self.notes.retune_wait.saturating_sub(len);
        let changed = self.notes.applied.1 != self.notes.bend
            || self.notes.tempo_applied != self.notes.tempo
            || self.notes.tuning_applied != self.notes.tuning_seen
            || PARAMS.iter().filter(|p| !p.rebuild).any(|p| {
                self.notes.applied.0.get(p.id).to_bits() != self.values.get(p.id).to_bits()
            });
        if !changed || self.notes.retune_wait > 0 || self.bank.is_none() {
            return;
        }
        self.notes.applied = (self.values, self.notes.bend);
        self.notes.tempo_applied = self.notes.tempo;
        self.notes.tuning_applied = self.notes.tuning_seen;
        self.notes.retune_wait = (RETUNE_INTERVAL * self.host_rate) as usize;
        let p = self.physics();
        if let Some(b) = self.bank.as_mut() {
            for v in b.voices.iter_mut().filter(|v| v.active) {
                if !v.retune(&p) {
                    v.reset();
                    self.counts.refused += 1;
                }
            }
        }
    }
}

/// The price cap (s per step) for a note about to start on voice `slot` of `b` within
/// `budget` seconds of work per second of audio, a voice costing at most `share`, and how
/// many other voices were ended to make room (only when the budget has no room for the
/// note's cheapest model: a plate's smallest tier, the string; `engine/governor.rs`). Audio
/// thread.
fn fit_note(b: &mut Bank, slot: usize, budget: f64, share: f64) -> (f64, u64) {
    let rate = b.sim_rate;
    let cost = b.cost;
    let cheapest = match &b.voices[slot].model {
        VoiceModel::Plate(pv) => pv.data.tier_price.last().copied().unwrap_or(0.0),
        VoiceModel::String(sv) => sv.price,
        VoiceModel::Drone(dv) => dv.price,
        VoiceModel::Sitar(sv) => sv.price,
    };
    let mut shed = 0;
    let room = loop {
        let others: f64 = b
            .voices
            .iter()
            .enumerate()
            .filter(|(k, v)| *k != slot && v.active && v.fading == 0)
            .map(|(_, v)| cost.load(v.price(), rate))
            .sum();
        let room = budget - others;
        if room >= cost.attack_load(cheapest, rate) {
            break room;
        }
        match quietest(&mut b.voices, slot) {
            Some(v) => {
                v.fading = FADE_CHUNKS;
                shed += 1;
            }
            // Nothing left to end: the note takes its cheapest model.
            None => break room,
        }
    };
    (room.min(share) / cost.attack_load(1.0, rate), shed)
}

/// The quietest sounding voice not already fading (released voices first), other than
/// `except`. Audio thread.
fn quietest(voices: &mut [Voice], except: usize) -> Option<&mut Voice> {
    voices
        .iter_mut()
        .enumerate()
        .filter(|(k, v)| *k != except && v.active && v.fading == 0)
        .min_by(|(_, x), (_, y)| {
            (!x.released(), x.energy)
                .partial_cmp(&(!y.released(), y.energy))
                .unwrap_or(std::cmp::Ordering::Equal)
        })
        .map(|(_, v)| v)
}
