//! Host note and MIDI events to engine events (audio thread; no allocation: the caller passes a
//! buffer with spare capacity).
//!
//! Mapping: note on/off (a note on with velocity 0 is a note off, as in MIDI 1.0), choke →
//! note off; pitch bend → `[-1, 1]` (nice-plug's 0.5 is the centre); CC 1 (mod wheel) →
//! `[0, 1]`; CC 64 (sustain) → pedal down at values ≥ 64/127 (the MIDI 1.0 convention);
//! CC 120 → all sound off, CC 123 → all notes off. Other events are ignored.

use nice_plug::prelude::*;
use noether_core::engine::{Event, EventKind};

/// Appends the engine event(s) for `event` to `out` (nothing if it has no engine meaning).
pub fn translate<S>(event: &NoteEvent<S>, out: &mut Vec<Event>) {
    let kind = match *event {
        NoteEvent::NoteOn { key, velocity, .. } => match key.number() {
            Some(key) if velocity > 0.0 => EventKind::NoteOn {
                key,
                velocity: velocity.min(1.0),
            },
            Some(key) => EventKind::NoteOff { key },
            None => return,
        },
        NoteEvent::NoteOff { key, .. } | NoteEvent::Choke { key, .. } => match key.number() {
            Some(key) => EventKind::NoteOff { key },
            None => EventKind::AllNotesOff,
        },
        NoteEvent::MidiPitchBend { value, .. } => {
            EventKind::PitchBend((2.0 * value - 1.0).clamp(-1.0, 1.0))
        }
        NoteEvent::MidiCC { cc, value, .. } => match cc {
            control_change::MODULATION_MSB => EventKind::ModWheel(value.clamp(0.0, 1.0)),
            control_change::DAMPER_PEDAL => EventKind::Sustain(value >= 64.0 / 127.0),
            control_change::ALL_SOUND_OFF => EventKind::AllSoundOff,
            control_change::ALL_NOTES_OFF => EventKind::AllNotesOff,
            _ => return,
        },
        _ => return,
    };
    out.push(Event::new(event.timing(), kind));
}

#[cfg(test)]
mod tests {
    use super::*;
    use nice_plug::midi::{Channel, Key, VoiceID};

    fn one(e: NoteEvent<()>) -> Vec<Event> {
        let mut v = Vec::with_capacity(4);
        translate(&e, &mut v);
        v
    }

    #[test]
    fn notes_bend_wheel_and_pedal() {
        let on = one(NoteEvent::NoteOn {
            timing: 7,
            voice_id: VoiceID::Wildcard,
            channel: Channel::Number(0),
            key: Key::Number(60),
            velocity: 0.5,
        });
        assert_eq!(
            on,
            vec![Event::new(
                7,
                EventKind::NoteOn {
                    key: 60,
                    velocity: 0.5
                }
            )]
        );
        let zero = one(NoteEvent::NoteOn {
            timing: 3,
            voice_id: VoiceID::Wildcard,
            channel: Channel::Number(0),
            key: Key::Number(61),
            velocity: 0.0,
        });
        assert_eq!(zero, vec![Event::new(3, EventKind::NoteOff { key: 61 })]);
        let bend = one(NoteEvent::MidiPitchBend {
            timing: 0,
            channel: 0,
            value: 0.75,
        });
        assert_eq!(bend, vec![Event::new(0, EventKind::PitchBend(0.5))]);
        let wheel = one(NoteEvent::MidiCC {
            timing: 1,
            channel: 0,
            cc: 1,
            value: 0.25,
        });
        assert_eq!(wheel, vec![Event::new(1, EventKind::ModWheel(0.25))]);
        let down = one(NoteEvent::MidiCC {
            timing: 2,
            channel: 0,
            cc: 64,
            value: 1.0,
        });
        assert_eq!(down, vec![Event::new(2, EventKind::Sustain(true))]);
        let up = one(NoteEvent::MidiCC {
            timing: 2,
            channel: 0,
            cc: 64,
            value: 63.0 / 127.0,
        });
        assert_eq!(up, vec![Event::new(2, EventKind::Sustain(false))]);
        assert!(one(NoteEvent::MidiCC {
            timing: 0,
            channel: 0,
            cc: 7,
            value: 1.0
        })
        .is_empty());
    }
}
