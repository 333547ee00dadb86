//! Host note and MIDI events to engine events (audio thread; no allocation: the caller passes a
//! buffer with spare capacity, and [`MidiMap::translate`] stops appending when it is full).
//!
//! MIDI 1.0 and MPE (notes, bends, controllers, channel pressure, MPE zones) go through the
//! core's mapping ([`noether_core::engine::midi`], shared with `noether play --midi`): this file
//! only turns nice-plug's events into MIDI channel messages (its `[0, 1]` values back to MIDI's
//! units). A choke is a note off; a note off without a key, all notes off.
//!
//! CLAP's own per-note expressions, for a given key (an expression for every key, CLAP key
//! -1, is ignored): tuning in semitones → [`NoteExpression::Tuning`], volume (linear gain,
//! CLAP's 0 to 4) → [`NoteExpression::Volume`], pressure and brightness →
//! [`NoteExpression::Pressure`], [`NoteExpression::Brightness`], pan →
//! [`NoteExpression::Pan`] (0 left, 0.5 centre, 1 right).
//!
//! Parsed but not used (no event is sent): CLAP vibrato and expression. Other events are
//! ignored.

use nice_plug::midi::Key;
use nice_plug::prelude::*;
use noether_core::engine::midi::{self, bend_of_14, push, MidiMessage};
use noether_core::engine::{Event, EventKind, NoteExpression};

pub use noether_core::engine::midi::MPE_MEMBER_BEND_RANGE;

/// A pitch bend in nice-plug's `[0, 1]` (the 14-bit MIDI value over 16383) to `[-1, 1]`: the
/// 14-bit value is recovered and mapped by the core ([`bend_of_14`]: 8192 → 0 exactly, 0 → -1,
/// 16383 → +1); a non-finite value is the centre.
pub fn bend_of(value: f32) -> f32 {
    bend_of_14(bend_14(value))
}

/// nice-plug's `[0, 1]` pitch bend back to MIDI's 14-bit value (non-finite: the centre).
fn bend_14(value: f32) -> u16 {
    if value.is_finite() {
        (value.clamp(0.0, 1.0) * 16383.0).round() as u16
    } else {
        8192
    }
}

/// A CC value in nice-plug's `[0, 1]` back to MIDI's 0 to 127.
fn cc7(value: f32) -> u8 {
    (value * 127.0).round().clamp(0.0, 127.0) as u8
}

/// The MIDI state of one plugin instance (audio thread only; fixed size): the core's map.
#[derive(Debug, Clone, Default)]
pub struct MidiMap {
    map: midi::MidiMap,
}

impl MidiMap {
    /// Forgets held notes and channel bends (the host's `reset`); keeps the MPE configuration
    /// and bend ranges, which the host set up for the device, not for the notes.
    pub fn reset(&mut self) {
        self.map.reset();
    }

    /// Whether MPE is on (some zone configured).
    pub fn mpe(&self) -> bool {
        self.map.mpe()
    }

    /// The member channels (first, last; 0-based) of the lower and the upper MPE zone.
    pub fn zones(&self) -> [Option<(u8, u8)>; 2] {
        self.map.zones()
    }

    /// Appends the engine event(s) for `event` to `out` (nothing if it has no engine meaning).
    pub fn translate<S>(&mut self, event: &NoteEvent<S>, out: &mut Vec<Event>) {
        let at = event.timing();
        let note_expr = |key: &Key, expression| {
            key.number()
                .map(|key| EventKind::NoteExpression { key, expression })
        };
        let message = match *event {
            NoteEvent::NoteOn {
                key,
                velocity,
                channel,
                ..
            } => match key.number() {
                Some(key) => MidiMessage::NoteOn {
                    channel: channel.number(),
                    key,
                    velocity: if velocity.is_finite() { velocity } else { 0.0 },
                },
                None => return,
            },
            NoteEvent::NoteOff { key, .. } | NoteEvent::Choke { key, .. } => match key.number() {
                Some(key) => MidiMessage::NoteOff { key },
                None => return push(out, Event::new(at, EventKind::AllNotesOff)),
            },
            NoteEvent::MidiChannelPressure {
                pressure, channel, ..
            } => MidiMessage::ChannelPressure { channel, pressure },
            NoteEvent::MidiPitchBend { value, channel, .. } => MidiMessage::PitchBend {
                channel,
                value: bend_14(value),
            },
            NoteEvent::MidiCC {
                cc, value, channel, ..
            } => MidiMessage::ControlChange {
                channel,
                cc,
                value: cc7(value),
            },
            NoteEvent::PolyTuning { key, tuning, .. } => {
                return expression(out, at, note_expr(&key, NoteExpression::Tuning(tuning)))
            }
            NoteEvent::PolyVolume { key, gain, .. } => {
                return expression(out, at, note_expr(&key, NoteExpression::Volume(gain)))
            }
            NoteEvent::PolyPressure { key, pressure, .. } => {
                return expression(out, at, note_expr(&key, NoteExpression::Pressure(pressure)))
            }
            NoteEvent::PolyBrightness {
                key, brightness, ..
            } => {
                let e = note_expr(&key, NoteExpression::Brightness(brightness));
                return expression(out, at, e);
            }
            NoteEvent::PolyPan { key, pan, .. } => {
                return expression(out, at, note_expr(&key, NoteExpression::Pan(pan)))
            }
            // CLAP vibrato and expression: parsed by nice-plug, not used.
            _ => return,
        };
        self.map.translate(at, message, out);
    }
}

/// Appends a CLAP per-note expression, if it is for a key.
fn expression(out: &mut Vec<Event>, at: u32, kind: Option<EventKind>) {
    if let Some(kind) = kind {
        push(out, Event::new(at, kind));
    }
}

#[cfg(test)]
#[path = "midi_tests.rs"]
mod tests;
