//! Host note and MIDI events to engine events (audio thread; no allocation: the caller passes a
//! buffer with spare capacity, and [`MidiMap::translate`] stops appending when it is full).
//!
//! Mapping: note on/off (a note on with velocity 0 is a note off, as in MIDI 1.0), choke →
//! note off; pitch bend → `[-1, 1]` ([`bend_of`]: MIDI 1.0's 14-bit value, 8192 the centre); CC 1 (mod wheel) →
//! `[0, 1]`; CC 64 (sustain) → pedal down at values ≥ 64/127 (the MIDI 1.0 convention);
//! CC 120 → all sound off, CC 123 → all notes off.
//!
//! Per-note expressions ([`EventKind::NoteExpression`]):
//! - CLAP note expressions (nice-plug's `PolyTuning`, `PolyVolume`) for a given key: tuning in
//!   semitones → [`NoteExpression::Tuning`], volume (linear gain, CLAP's 0 to 4) →
//!   [`NoteExpression::Volume`]. An expression for every key (CLAP key -1) is ignored.
//! - MPE (MIDI Polyphonic Expression 1.0): off until the host sends an MPE Configuration
//!   Message (RPN 6 on channel 1 for the lower zone, on channel 16 for the upper zone; data
//!   entry MSB = number of member channels, 0 turns the zone off). In a zone, a pitch bend on a
//!   member channel becomes `Tuning(bend × range)` for the keys sounding on that channel; a
//!   bend sent before a note-on applies to that note right after its note-on (MPE sends the
//!   initial bend first); the master channel's bend stays the global bend. `range` is the
//!   zone's member pitch-bend sensitivity: 48 semitones (MPE's default, restored by every
//!   configuration message) until RPN 0 arrives on a member channel (it applies to the whole
//!   zone, as the MPE specification says). Channels outside any zone keep the global bend.
//!
//! - Pressure and brightness: CLAP's pressure and brightness expressions for a given key →
//!   [`NoteExpression::Pressure`], [`NoteExpression::Brightness`]; channel pressure and CC 74
//!   (MPE's pressure and timbre; on a channel outside MPE they act on the keys held on it) →
//!   the same expressions for the keys held on the channel, CC 74's `c` as brightness
//!   `c / 128` (64, MPE's default, is the neutral 0.5). Like bends, the channel's values sent
//!   before a note-on apply to that note right after it (a note's strike is committed at its
//!   first step, so its brightness shapes it).
//!
//! - CLAP pan for a key → [`NoteExpression::Pan`] (0 left, 0.5 centre, 1 right).
//!
//! Parsed but not used (no event is sent): CLAP vibrato and expression. Other events are
//! ignored.

use nice_plug::midi::Key;
use nice_plug::prelude::*;
use noether_core::engine::voice::modulation::NEUTRAL_BRIGHTNESS;
use noether_core::engine::{Event, EventKind, NoteExpression};

/// MPE's default pitch-bend sensitivity of member channels (semitones).
pub const MPE_MEMBER_BEND_RANGE: f32 = 48.0;
/// No channel (a key not sounding).
const NO_CHANNEL: u8 = u8::MAX;
/// The RPN "null" selection (CC 101 and CC 100 at 127).
const RPN_NULL: (u8, u8) = (127, 127);

/// An MPE zone (lower: master channel 0, members 1..; upper: master 15, members ..14).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Zone {
    /// Member channels (0-based), inclusive range.
    first: u8,
    /// Last member channel (0-based).
    last: u8,
    /// Pitch-bend sensitivity of the member channels (semitones).
    range: f32,
}

impl Zone {
    fn has(&self, channel: u8) -> bool {
        (self.first..=self.last).contains(&channel)
    }
}

/// Note-to-channel and MPE state of one plugin instance (audio thread only; fixed size).
#[derive(Debug, Clone)]
pub struct MidiMap {
    /// MIDI channel (0-based) of each sounding key, [`NO_CHANNEL`] if the key is not held.
    key_channel: [u8; 128],
    /// Last pitch bend per channel, `[-1, 1]`.
    bend: [f32; 16],
    /// Selected RPN (MSB, LSB) per channel.
    rpn: [(u8, u8); 16],
    /// Last channel pressure per channel, `[0, 1]`.
    pressure: [f32; 16],
    /// Last CC 74 per channel as brightness, `[0, 1)` (0.5 neutral).
    brightness: [f32; 16],
    /// Data entry MSB of RPN 0 per channel (kept for the LSB, cents, that may follow).
    bend_semitones: [u8; 16],
    /// MPE lower zone (master channel 1), if configured.
    lower: Option<Zone>,
    /// MPE upper zone (master channel 16), if configured.
    upper: Option<Zone>,
}

impl Default for MidiMap {
    fn default() -> Self {
        Self {
            key_channel: [NO_CHANNEL; 128],
            bend: [0.0; 16],
            pressure: [0.0; 16],
            brightness: [NEUTRAL_BRIGHTNESS; 16],
            rpn: [RPN_NULL; 16],
            bend_semitones: [0; 16],
            lower: None,
            upper: None,
        }
    }
}

/// Appends `event` if `out` has spare capacity (never reallocates on the audio thread).
fn push(out: &mut Vec<Event>, event: Event) {
    if out.len() < out.capacity() {
        out.push(event);
    }
}

/// A pitch bend in nice-plug's `[0, 1]` (the 14-bit MIDI value over 16383) to `[-1, 1]`:
/// the 14-bit value `v` is recovered and mapped with MIDI 1.0's centre, 8192 → 0 exactly (so a
/// bend at rest does not detune a note by 1/16383 of its range, 0.3 cent at MPE's 48
/// semitones), 0 → -1, 16383 → +1 (`(v - 8192) / 8192` below the centre, `/ 8191` above);
/// a non-finite value is the centre.
pub fn bend_of(value: f32) -> f32 {
    if !value.is_finite() {
        return 0.0;
    }
    let v = (value.clamp(0.0, 1.0) * 16383.0).round() - 8192.0;
    if v < 0.0 {
        v / 8192.0
    } else {
        v / 8191.0
    }
}

/// A CC value in nice-plug's `[0, 1]` back to MIDI's 0 to 127.
fn cc7(value: f32) -> u8 {
    (value * 127.0).round().clamp(0.0, 127.0) as u8
}

impl MidiMap {
    /// Forgets held notes and channel bends (the host's `reset`); keeps the MPE configuration
    /// and bend ranges, which the host set up for the device, not for the notes.
    pub fn reset(&mut self) {
        self.key_channel = [NO_CHANNEL; 128];
        self.bend = [0.0; 16];
        self.pressure = [0.0; 16];
        self.brightness = [NEUTRAL_BRIGHTNESS; 16];
    }

    /// Whether MPE is on (some zone configured).
    pub fn mpe(&self) -> bool {
        self.lower.is_some() || self.upper.is_some()
    }

    /// The MPE zone of which `channel` is a member channel.
    fn member_zone(&self, channel: u8) -> Option<&Zone> {
        [self.lower.as_ref(), self.upper.as_ref()]
            .into_iter()
            .flatten()
            .find(|z| z.has(channel))
    }

    /// The per-note tuning (semitones) a member channel's bend gives, if `channel` is one.
    fn channel_tuning(&self, channel: u8) -> Option<f32> {
        let z = self.member_zone(channel)?;
        Some(self.bend[usize::from(channel)] * z.range)
    }

    /// Appends the engine event(s) for `event` to `out` (nothing if it has no engine meaning).
    pub fn translate<S>(&mut self, event: &NoteEvent<S>, out: &mut Vec<Event>) {
        let at = event.timing();
        let note_expr = |key: &Key, expression| {
            key.number()
                .map(|key| EventKind::NoteExpression { key, expression })
        };
        let kind = match *event {
            NoteEvent::NoteOn {
                key,
                velocity,
                channel,
                ..
            } => match key.number() {
                Some(key) if velocity > 0.0 => {
                    return self.note_on(at, key, velocity, channel.number(), out)
                }
                Some(key) => self.note_off(key),
                None => return,
            },
            NoteEvent::NoteOff { key, .. } | NoteEvent::Choke { key, .. } => match key.number() {
                Some(key) => self.note_off(key),
                None => EventKind::AllNotesOff,
            },
            NoteEvent::PolyTuning { key, tuning, .. } => {
                match note_expr(&key, NoteExpression::Tuning(tuning)) {
                    Some(k) => k,
                    None => return,
                }
            }
            NoteEvent::PolyVolume { key, gain, .. } => {
                match note_expr(&key, NoteExpression::Volume(gain)) {
                    Some(k) => k,
                    None => return,
                }
            }
            NoteEvent::PolyPressure { key, pressure, .. } => {
                match note_expr(&key, NoteExpression::Pressure(pressure)) {
                    Some(k) => k,
                    None => return,
                }
            }
            NoteEvent::PolyBrightness {
                key, brightness, ..
            } => match note_expr(&key, NoteExpression::Brightness(brightness)) {
                Some(k) => k,
                None => return,
            },
            NoteEvent::PolyPan { key, pan, .. } => {
                match note_expr(&key, NoteExpression::Pan(pan)) {
                    Some(k) => k,
                    None => return,
                }
            }
            NoteEvent::MidiChannelPressure {
                pressure, channel, ..
            } => {
                let Some(c) = self.pressure.get_mut(usize::from(channel)) else {
                    return;
                };
                *c = pressure.clamp(0.0, 1.0);
                let p = NoteExpression::Pressure(*c);
                return self.express_channel(at, channel, p, out);
            }
            NoteEvent::MidiPitchBend { value, channel, .. } => {
                let bend = bend_of(value);
                let Some(c) = self.bend.get_mut(usize::from(channel)) else {
                    return;
                };
                *c = bend;
                if let Some(tuning) = self.channel_tuning(channel) {
                    return self.retune_channel(at, channel, tuning, out);
                }
                EventKind::PitchBend(bend)
            }
            NoteEvent::MidiCC {
                cc, value, channel, ..
            } => match cc {
                control_change::MODULATION_MSB => EventKind::ModWheel(value.clamp(0.0, 1.0)),
                control_change::DAMPER_PEDAL => EventKind::Sustain(value >= 64.0 / 127.0),
                control_change::ALL_SOUND_OFF => EventKind::AllSoundOff,
                control_change::ALL_NOTES_OFF => EventKind::AllNotesOff,
                // RPN selection and data entry: MPE configuration and bend sensitivity.
                101 | 100 | 6 | 38 => return self.rpn(channel, cc, cc7(value)),
                74 => {
                    let Some(c) = self.brightness.get_mut(usize::from(channel)) else {
                        return;
                    };
                    *c = f32::from(cc7(value)) / 128.0;
                    let b = NoteExpression::Brightness(*c);
                    return self.express_channel(at, channel, b, out);
                }
                _ => return,
            },
            // CLAP vibrato and expression: parsed by nice-plug, not used.
            _ => return,
        };
        push(out, Event::new(at, kind));
    }

    /// A note-on: records its channel; on an MPE member channel, the channel's current bend
    /// follows as the note's tuning; on any channel, its pressure and CC 74 when not at rest.
    fn note_on(&mut self, at: u32, key: u8, velocity: f32, ch: Option<u8>, out: &mut Vec<Event>) {
        let Some(slot) = self.key_channel.get_mut(usize::from(key)) else {
            return;
        };
        *slot = ch.filter(|&c| c < 16).unwrap_or(NO_CHANNEL);
        let velocity = velocity.min(1.0);
        push(out, Event::new(at, EventKind::NoteOn { key, velocity }));
        if let Some(tuning) = ch.and_then(|c| self.channel_tuning(c)) {
            if tuning != 0.0 {
                let expression = NoteExpression::Tuning(tuning);
                push(
                    out,
                    Event::new(at, EventKind::NoteExpression { key, expression }),
                );
            }
        }
        if let Some(c) = ch.filter(|&c| c < 16).map(usize::from) {
            for (expression, rest) in [
                (
                    NoteExpression::Pressure(self.pressure[c]),
                    self.pressure[c] == 0.0,
                ),
                (
                    NoteExpression::Brightness(self.brightness[c]),
                    self.brightness[c] == NEUTRAL_BRIGHTNESS,
                ),
            ] {
                if !rest {
                    push(
                        out,
                        Event::new(at, EventKind::NoteExpression { key, expression }),
                    );
                }
            }
        }
    }

    /// `expression` for every key held on `channel`.
    fn express_channel(
        &self,
        at: u32,
        channel: u8,
        expression: NoteExpression,
        out: &mut Vec<Event>,
    ) {
        for (key, _) in (0u8..).zip(self.key_channel).filter(|&(_, c)| c == channel) {
            push(
                out,
                Event::new(at, EventKind::NoteExpression { key, expression }),
            );
        }
    }

    /// A note-off: the key no longer sounds on its channel.
    fn note_off(&mut self, key: u8) -> EventKind {
        if let Some(slot) = self.key_channel.get_mut(usize::from(key)) {
            *slot = NO_CHANNEL;
        }
        EventKind::NoteOff { key }
    }

    /// Tunes every key held on `channel` by `tuning` semitones.
    fn retune_channel(&self, at: u32, channel: u8, tuning: f32, out: &mut Vec<Event>) {
        for (key, _) in (0u8..).zip(self.key_channel).filter(|&(_, c)| c == channel) {
            let expression = NoteExpression::Tuning(tuning);
            push(
                out,
                Event::new(at, EventKind::NoteExpression { key, expression }),
            );
        }
    }

    /// RPN selection (CC 101 MSB, CC 100 LSB) and data entry (CC 6 MSB, CC 38 LSB) on
    /// `channel`: RPN 6 on channel 1 or 16 configures an MPE zone, RPN 0 on a member channel
    /// sets the zone's bend sensitivity (semitones + cents / 100). Others are ignored.
    fn rpn(&mut self, channel: u8, cc: u8, v: u8) {
        let ch = usize::from(channel);
        let Some(sel) = self.rpn.get_mut(ch) else {
            return;
        };
        match cc {
            101 => sel.0 = v,
            100 => sel.1 = v,
            6 if *sel == (0, 6) => self.configure(channel, v),
            6 if *sel == (0, 0) => {
                self.bend_semitones[ch] = v;
                self.set_range(channel, f32::from(v));
            }
            38 if *sel == (0, 0) => {
                let semis = f32::from(self.bend_semitones[ch]);
                self.set_range(channel, semis + f32::from(v.min(99)) / 100.0);
            }
            _ => {}
        }
    }

    /// MPE Configuration Message: `members` member channels for the zone mastered by `channel`
    /// (0: lower, 15: upper); 0 members turns the zone off. The zones never overlap: a new
    /// zone shrinks the other one (MPE's rule), turning it off if nothing is left.
    fn configure(&mut self, channel: u8, members: u8) {
        let members = members.min(15);
        let zone = |first, last| Zone {
            first,
            last,
            range: MPE_MEMBER_BEND_RANGE,
        };
        match channel {
            0 => {
                self.lower = (members > 0).then(|| zone(1, members));
                if let (Some(l), Some(u)) = (self.lower, self.upper.as_mut()) {
                    u.first = u.first.max(l.last + 2);
                    if u.first > u.last {
                        self.upper = None;
                    }
                }
            }
            15 => {
                self.upper = (members > 0).then(|| zone(15 - members, 14));
                if let (Some(u), Some(l)) = (self.upper, self.lower.as_mut()) {
                    l.last = l.last.min(u.first.saturating_sub(2));
                    if l.last < l.first {
                        self.lower = None;
                    }
                }
            }
            _ => {}
        }
    }

    /// Bend sensitivity `semitones` for the zone of which `channel` is a member.
    fn set_range(&mut self, channel: u8, semitones: f32) {
        for z in [self.lower.as_mut(), self.upper.as_mut()]
            .into_iter()
            .flatten()
        {
            if z.has(channel) {
                z.range = semitones;
            }
        }
    }
}

#[cfg(test)]
#[path = "midi_tests.rs"]
mod tests;
