//! Unit tests of [`super::MidiMap`]: pure mapping from nice-plug events to engine events.

use super::*;
use nice_plug::midi::{Channel, Key, VoiceID};

fn one(m: &mut MidiMap, e: NoteEvent<()>) -> Vec<Event> {
    let mut v = Vec::with_capacity(16);
    m.translate(&e, &mut v);
    v
}

fn note_on(channel: u8, key: u8) -> NoteEvent<()> {
    NoteEvent::NoteOn {
        timing: 5,
        voice_id: VoiceID::Wildcard,
        channel: Channel::Number(channel),
        key: Key::Number(key),
        velocity: 1.0,
    }
}

fn cc(channel: u8, cc: u8, value: u8) -> NoteEvent<()> {
    NoteEvent::MidiCC {
        timing: 0,
        channel,
        cc,
        value: f32::from(value) / 127.0,
    }
}

/// A pitch bend of 14-bit value `raw` (8192 the centre) as nice-plug delivers it.
fn bend(channel: u8, raw: u16) -> NoteEvent<()> {
    NoteEvent::MidiPitchBend {
        timing: 9,
        channel,
        value: f32::from(raw) / 16383.0,
    }
}

/// The centre, the ends and a quarter of the way down are exact (MIDI 1.0: 8192 is no bend);
/// the VST3 proxy parameter's 0.5 is the centre too.
#[test]
fn bend_values() {
    for (raw, want) in [(8192u16, 0.0), (0, -1.0), (16383, 1.0), (4096, -0.5)] {
        assert_eq!(bend_of(f32::from(raw) / 16383.0), want, "{raw}");
    }
    assert_eq!(bend_of(0.5), 0.0);
    assert_eq!(bend_of(-3.0), -1.0);
    assert_eq!(bend_of(f32::NAN), 0.0);
}

fn tuning(at: u32, key: u8, semitones: f32) -> Event {
    let expression = NoteExpression::Tuning(semitones);
    Event::new(at, EventKind::NoteExpression { key, expression })
}

/// Sends the RPN `(msb, lsb)` with data entry `value` (and `cents` on CC 38) on `channel`.
fn rpn(m: &mut MidiMap, channel: u8, lsb: u8, value: u8, cents: Option<u8>) {
    for e in [
        cc(channel, 101, 0),
        cc(channel, 100, lsb),
        cc(channel, 6, value),
    ] {
        assert!(one(m, e).is_empty(), "RPN messages make no engine event");
    }
    if let Some(c) = cents {
        assert!(one(m, cc(channel, 38, c)).is_empty());
    }
}

#[test]
fn notes_bend_wheel_and_pedal() {
    let mut m = MidiMap::default();
    let on = one(&mut m, note_on(0, 60));
    assert_eq!(
        on,
        vec![Event::new(
            5,
            EventKind::NoteOn {
                key: 60,
                velocity: 1.0
            }
        )]
    );
    let zero = one(
        &mut m,
        NoteEvent::NoteOn {
            timing: 3,
            voice_id: VoiceID::Wildcard,
            channel: Channel::Number(0),
            key: Key::Number(61),
            velocity: 0.0,
        },
    );
    assert_eq!(zero, vec![Event::new(3, EventKind::NoteOff { key: 61 })]);
    assert_eq!(
        one(&mut m, bend(0, 12288)),
        vec![Event::new(9, EventKind::PitchBend(4096.0 / 8191.0))]
    );
    assert_eq!(
        one(&mut m, cc(0, 1, 32)),
        vec![Event::new(0, EventKind::ModWheel(32.0 / 127.0))]
    );
    assert_eq!(
        one(&mut m, cc(0, 64, 127)),
        vec![Event::new(0, EventKind::Sustain(true))]
    );
    assert_eq!(
        one(&mut m, cc(0, 64, 63)),
        vec![Event::new(0, EventKind::Sustain(false))]
    );
    assert!(one(&mut m, cc(0, 7, 127)).is_empty());
}

/// CLAP note expressions: tuning (semitones) and volume (linear gain) for a key; an
/// expression for every key and the expressions the engine does not take make no event.
#[test]
fn clap_note_expressions() {
    let mut m = MidiMap::default();
    let poly = |key| (VoiceID::Wildcard, Channel::Number(0), key);
    let (voice_id, channel, key) = poly(Key::Number(62));
    let t = one(
        &mut m,
        NoteEvent::PolyTuning {
            timing: 4,
            voice_id,
            channel,
            key,
            tuning: -1.25,
        },
    );
    assert_eq!(t, vec![tuning(4, 62, -1.25)]);
    let v = one(
        &mut m,
        NoteEvent::PolyVolume {
            timing: 2,
            voice_id,
            channel,
            key,
            gain: 0.5,
        },
    );
    let expression = NoteExpression::Volume(0.5);
    assert_eq!(
        v,
        vec![Event::new(
            2,
            EventKind::NoteExpression {
                key: 62,
                expression
            }
        )]
    );
    let (voice_id, channel, key) = poly(Key::Wildcard);
    let any = NoteEvent::PolyTuning {
        timing: 0,
        voice_id,
        channel,
        key,
        tuning: 3.0,
    };
    assert!(one(&mut m, any).is_empty(), "an expression for every key");
    let (voice_id, channel, key) = poly(Key::Number(62));
    let expr = |expression| {
        vec![Event::new(
            0,
            EventKind::NoteExpression {
                key: 62,
                expression,
            },
        )]
    };
    let pressure = NoteEvent::PolyPressure {
        timing: 0,
        voice_id,
        channel,
        key,
        pressure: 0.25,
    };
    assert_eq!(one(&mut m, pressure), expr(NoteExpression::Pressure(0.25)));
    let brightness = NoteEvent::PolyBrightness {
        timing: 0,
        voice_id,
        channel,
        key,
        brightness: 0.75,
    };
    assert_eq!(
        one(&mut m, brightness),
        expr(NoteExpression::Brightness(0.75))
    );
    let pan = NoteEvent::PolyPan {
        timing: 0,
        voice_id,
        channel,
        key,
        pan: 0.5,
    };
    assert_eq!(one(&mut m, pan), expr(NoteExpression::Pan(0.5)));
}

/// Channel pressure and CC 74 act on the keys held on their channel (MPE's pressure and
/// timbre on a member channel); values sent before a note-on follow it; CC 74's 64 is the
/// neutral brightness 0.5, and a channel at rest adds nothing to a note-on.
#[test]
fn channel_pressure_and_cc74_reach_their_notes() {
    let mut m = MidiMap::default();
    let expr = |key, expression| Event::new(0, EventKind::NoteExpression { key, expression });
    let at5 = |key, expression| Event::new(5, EventKind::NoteExpression { key, expression });
    let on = |key| Event::new(5, EventKind::NoteOn { key, velocity: 1.0 });
    // At rest: a note-on alone.
    assert_eq!(one(&mut m, note_on(3, 60)), vec![on(60)]);
    assert_eq!(
        one(&mut m, cc(3, 74, 127)),
        vec![expr(60, NoteExpression::Brightness(127.0 / 128.0))]
    );
    let pressure = |channel, p| NoteEvent::MidiChannelPressure {
        timing: 0,
        channel,
        pressure: p,
    };
    assert_eq!(
        one(&mut m, pressure(3, 0.5)),
        vec![expr(60, NoteExpression::Pressure(0.5))]
    );
    assert!(
        one(&mut m, pressure(4, 0.5)).is_empty(),
        "no key on channel 5"
    );
    // Sent before the note-on, on another channel: they follow it.
    assert!(one(&mut m, cc(4, 74, 32)).is_empty());
    assert_eq!(
        one(&mut m, note_on(4, 62)),
        vec![
            on(62),
            at5(62, NoteExpression::Pressure(0.5)),
            at5(62, NoteExpression::Brightness(0.25)),
        ]
    );
    assert_eq!(
        one(&mut m, cc(4, 74, 64)),
        vec![expr(62, NoteExpression::Brightness(0.5))],
        "64 is neutral"
    );
}

/// Without an MPE configuration a bend on any channel is the global bend; after one (lower
/// zone, 15 members) a member channel's bend tunes its notes (range 48, then RPN 0's), the
/// initial bend follows the note-on, the master's bend stays global; a configuration with 0
/// members turns MPE off.
#[test]
fn mpe_member_bends_tune_their_notes() {
    let mut m = MidiMap::default();
    assert_eq!(
        one(&mut m, bend(1, 4096)),
        vec![Event::new(9, EventKind::PitchBend(-0.5))],
        "no MPE configuration: global"
    );
    rpn(&mut m, 0, 6, 15, None);
    assert!(m.mpe());
    // The initial bend comes first and applies right after the note-on.
    assert!(
        one(&mut m, bend(1, 16383)).is_empty(),
        "no note on channel 2 yet"
    );
    let on = one(&mut m, note_on(1, 60));
    assert_eq!(
        on,
        vec![
            Event::new(
                5,
                EventKind::NoteOn {
                    key: 60,
                    velocity: 1.0
                }
            ),
            tuning(5, 60, 48.0)
        ]
    );
    let on = one(&mut m, note_on(2, 64));
    assert_eq!(
        on,
        vec![Event::new(
            5,
            EventKind::NoteOn {
                key: 64,
                velocity: 1.0
            }
        )],
        "no bend on channel 3: the note starts neutral"
    );
    assert_eq!(one(&mut m, bend(2, 4096)), vec![tuning(9, 64, -24.0)]);
    assert_eq!(
        one(&mut m, bend(0, 4096)),
        vec![Event::new(9, EventKind::PitchBend(-0.5))],
        "the master channel's bend is global"
    );
    // RPN 0 on channel 3 (12 semitones, 50 cents) sets the range of the whole zone.
    rpn(&mut m, 2, 0, 12, Some(50));
    assert_eq!(one(&mut m, bend(1, 16383)), vec![tuning(9, 60, 12.5)]);
    // After the note-off the channel's bend tunes nothing.
    let off = NoteEvent::NoteOff {
        timing: 1,
        voice_id: VoiceID::Wildcard,
        channel: Channel::Number(1),
        key: Key::Number(60),
        velocity: 0.0,
    };
    assert_eq!(
        one(&mut m, off),
        vec![Event::new(1, EventKind::NoteOff { key: 60 })]
    );
    assert!(one(&mut m, bend(1, 8192)).is_empty());
    // A configuration with no members turns MPE off: member bends are global again.
    rpn(&mut m, 0, 6, 0, None);
    assert!(!m.mpe());
    assert_eq!(
        one(&mut m, bend(2, 4096)),
        vec![Event::new(9, EventKind::PitchBend(-0.5))]
    );
}

/// The upper zone (master channel 16) shrinks the lower one; a full buffer takes no more
/// events (no reallocation on the audio thread).
#[test]
fn upper_zone_and_full_buffer() {
    let mut m = MidiMap::default();
    rpn(&mut m, 0, 6, 15, None);
    rpn(&mut m, 15, 6, 3, None);
    // Upper zone: members 13..=15 (0-based 12..=14); the lower zone keeps 1..=10.
    assert_eq!(m.zones(), [Some((1, 10)), Some((12, 14))]);
    assert_eq!(
        one(&mut m, bend(11, 4096)),
        vec![Event::new(9, EventKind::PitchBend(-0.5))],
        "channel 12 is in no zone"
    );
    assert!(one(&mut m, bend(13, 16383)).is_empty());
    let mut out = Vec::with_capacity(1);
    m.translate(&note_on(13, 70), &mut out);
    assert_eq!(out.len(), 1, "the tuning does not fit");
    assert_eq!(out.capacity(), 1);
}
