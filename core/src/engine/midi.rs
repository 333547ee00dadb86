//! MIDI 1.0 and MPE to engine events: the one mapping the plugin (a host's MIDI,
//! `plugin/src/midi.rs`) and `noether play --midi` (a standard MIDI file, `src/render/midi.rs`)
//! share. Its input is a channel message ([`MidiMessage`]) in MIDI's own units; its output,
//! engine [`Event`]s. Audio thread (no allocation: the caller passes a buffer with spare
//! capacity, and [`MidiMap::translate`] stops appending when it is full) or any thread.
//!
//! Mapping: note on/off (a note on with velocity 0 is a note off, as in MIDI 1.0); pitch bend
//! → `[-1, 1]` ([`bend_of_14`]: MIDI 1.0's 14-bit value, 8192 the centre); CC 1 (mod wheel) →
//! `[0, 1]`; CC 64 (sustain) → pedal down at values ≥ 64 (the MIDI 1.0 convention); CC 120 →
//! all sound off, CC 123 → all notes off.
//!
//! - MPE (MIDI Polyphonic Expression 1.0): off until an MPE Configuration Message arrives
//!   (RPN 6 on channel 1 for the lower zone, on channel 16 for the upper zone; data entry MSB =
//!   number of member channels, 0 turns the zone off). In a zone, a pitch bend on a member
//!   channel becomes `Tuning(bend × range)` for the keys sounding on that channel; a bend sent
//!   before a note-on applies to that note right after its note-on (MPE sends the initial bend
//!   first); the master channel's bend stays the global bend. `range` is the zone's member
//!   pitch-bend sensitivity: 48 semitones (MPE's default, restored by every configuration
//!   message) until RPN 0 arrives on a member channel (it applies to the whole zone, as the MPE
//!   specification says). Channels outside any zone keep the global bend.
//! - Pressure and brightness: channel pressure and CC 74 (MPE's pressure and timbre; on a
//!   channel outside MPE they act on the keys held on it) → [`NoteExpression::Pressure`] and
//!   [`NoteExpression::Brightness`] for the keys held on the channel, CC 74's `c` as
//!   brightness `c / 128` (64, MPE's default, is the neutral 0.5). Like bends, the channel's
//!   values sent before a note-on apply to that note right after it (a note's strike is
//!   committed at its first step, so its brightness shapes it).
//!
//! Other messages have no engine meaning.

use super::events::{Event, EventKind, NoteExpression};
use super::voice::modulation::NEUTRAL_BRIGHTNESS;

/// CC 1, the modulation wheel.
const CC_MOD_WHEEL: u8 = 1;
/// CC 64, the sustain (damper) pedal.
const CC_SUSTAIN: u8 = 64;
/// CC 74, MPE's timbre (brightness).
const CC_BRIGHTNESS: u8 = 74;
/// CC 120, all sound off.
const CC_ALL_SOUND_OFF: u8 = 120;
/// CC 123, all notes off.
const CC_ALL_NOTES_OFF: u8 = 123;

/// One MIDI 1.0 channel message, channels 0 to 15 (others are ignored), in MIDI's units.
/// Plain `Copy` data.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MidiMessage {
    /// A note on (velocity 0: a note off). `channel`: `None` for a host note without one.
    NoteOn {
        /// MIDI channel (0-based), if the note has one.
        channel: Option<u8>,
        /// MIDI key.
        key: u8,
        /// Velocity 0 to 1 (MIDI's 0..127 over 127; a host's finer velocities as they are).
        velocity: f32,
    },
    /// A note off.
    NoteOff {
        /// MIDI key.
        key: u8,
    },
    /// A pitch bend: the 14-bit value, 8192 the centre.
    PitchBend {
        /// MIDI channel (0-based).
        channel: u8,
        /// 0 to 16383.
        value: u16,
    },
    /// A control change.
    ControlChange {
        /// MIDI channel (0-based).
        channel: u8,
        /// Controller number.
        cc: u8,
        /// 0 to 127.
        value: u8,
    },
    /// Channel pressure (aftertouch).
    ChannelPressure {
        /// MIDI channel (0-based).
        channel: u8,
        /// 0 to 1 (MIDI's 0..127 over 127).
        pressure: f32,
    },
}

/// A 14-bit pitch-bend value to `[-1, 1]` with MIDI 1.0's centre: 8192 → 0 exactly (so a
/// bend at rest does not detune a note by 1/16383 of its range, 0.3 cent at MPE's 48
/// semitones), 0 → -1, 16383 → +1 (`(v - 8192) / 8192` below the centre, `/ 8191` above;
/// values past 16383 are 16383).
pub fn bend_of_14(value: u16) -> f32 {
    let v = f32::from(value.min(16383)) - 8192.0;
    if v < 0.0 {
        v / 8192.0
    } else {
        v / 8191.0
    }
}

/// Appends `event` if `out` has spare capacity (never reallocates on the audio thread).
pub fn push(out: &mut Vec<Event>, event: Event) {
    if out.len() < out.capacity() {
        out.push(event);
    }
}

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

/// Note-to-channel and MPE state of one instrument (one plugin instance, one MIDI file's
/// playback; the thread that translates its messages; fixed size).
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

impl MidiMap {
    /// Forgets held notes and channel bends (a host's `reset`); keeps the MPE configuration
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

    /// The member channels (first, last; 0-based) of the lower and the upper MPE zone.
    pub fn zones(&self) -> [Option<(u8, u8)>; 2] {
        [self.lower, self.upper].map(|z| z.map(|z| (z.first, z.last)))
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

    /// Appends the engine event(s) for `message`, at sample offset `at` of the block, to `out`
    /// (nothing if it has no engine meaning; events past `out`'s capacity are dropped).
    pub fn translate(&mut self, at: u32, message: MidiMessage, out: &mut Vec<Event>) {
        let kind = match message {
            MidiMessage::NoteOn {
                channel,
                key,
                velocity,
            } if velocity > 0.0 => return self.note_on(at, key, velocity, channel, out),
            MidiMessage::NoteOn { key, .. } | MidiMessage::NoteOff { key } => self.note_off(key),
            MidiMessage::ChannelPressure { channel, pressure } => {
                let Some(c) = self.pressure.get_mut(usize::from(channel)) else {
                    return;
                };
                *c = if pressure.is_finite() {
                    pressure.clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let p = NoteExpression::Pressure(*c);
                return self.express_channel(at, channel, p, out);
            }
            MidiMessage::PitchBend { channel, value } => {
                let bend = bend_of_14(value);
                let Some(c) = self.bend.get_mut(usize::from(channel)) else {
                    return;
                };
                *c = bend;
                if let Some(tuning) = self.channel_tuning(channel) {
                    return self.retune_channel(at, channel, tuning, out);
                }
                EventKind::PitchBend(bend)
            }
            MidiMessage::ControlChange { channel, cc, value } => match cc {
                CC_MOD_WHEEL => EventKind::ModWheel(f32::from(value.min(127)) / 127.0),
                CC_SUSTAIN => EventKind::Sustain(value >= 64),
                CC_ALL_SOUND_OFF => EventKind::AllSoundOff,
                CC_ALL_NOTES_OFF => EventKind::AllNotesOff,
                // RPN selection and data entry: MPE configuration and bend sensitivity.
                101 | 100 | 6 | 38 => return self.rpn(channel, cc, value.min(127)),
                CC_BRIGHTNESS => {
                    let Some(c) = self.brightness.get_mut(usize::from(channel)) else {
                        return;
                    };
                    *c = f32::from(value.min(127)) / 128.0;
                    let b = NoteExpression::Brightness(*c);
                    return self.express_channel(at, channel, b, out);
                }
                _ => return,
            },
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
