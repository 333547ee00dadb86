//! Standard MIDI files (SMF, read with `midly`) to a [`Timeline`] of engine events in seconds,
//! for `noether play --midi`.
//!
//! - Formats 0 (one track) and 1 (parallel tracks, merged); format 2 (independent sequential
//!   patterns) is refused. Every channel is played.
//! - Time: metrical files follow the tempo map (`Set Tempo` meta events, in any track, applied
//!   from their tick on; 120 bpm = 500 000 µs per quarter note until the first); SMPTE timecode
//!   files use `fps × ticks per frame` ticks per second (29.97 fps for drop-frame).
//! - Events: through the core's MIDI 1.0 and MPE mapping ([`crate::engine::midi`]), the one
//!   the plugin uses for a host's MIDI: note on with velocity v > 0 → note on at v/127 (a note
//!   on with velocity 0 is a note off, as in MIDI 1.0); note off; pitch bend → [-1, 1] (8192
//!   is the centre); CC 1 (mod wheel) → [0, 1]; CC 64 (sustain) → pedal down at values ≥ 64;
//!   CC 120 → all sound off; CC 123 → all notes off; and MPE: after an MPE Configuration
//!   Message (RPN 6), member channels' bends tune their own notes (48 semitones until RPN 0
//!   sets the zone's range), and channel pressure and CC 74 press and brighten them. Other
//!   events (program changes, polyphonic aftertouch, other controllers, SysEx, meta) are
//!   ignored.
//!
//! Runs on the calling (CLI) thread.

use super::play::{TimedEvent, Timeline};
use crate::engine::midi::{MidiMap, MidiMessage as Message};
use crate::engine::{Event, EventKind};
use crate::error::ParamError;
use midly::{Format, MetaMessage, MidiMessage, Smf, Timing, TrackEventKind};
use std::path::Path;

/// Tempo before the first `Set Tempo` event (µs per quarter note: 120 bpm, the SMF default).
const DEFAULT_TEMPO_US: f64 = 500_000.0;

/// Reads and converts the MIDI file at `path` (errors name `--midi`, the file and the problem).
pub fn load_midi(path: &Path) -> Result<Timeline, ParamError> {
    let bytes = std::fs::read(path)
        .map_err(|e| ParamError::new("--midi", path.display(), format!("a readable file ({e})")))?;
    read_midi(&bytes).map_err(|e| {
        ParamError::new(
            "--midi",
            format!("{}: {}", path.display(), e.value),
            e.allowed,
        )
    })
}

/// Converts the bytes of a standard MIDI file (see the module documentation).
pub fn read_midi(bytes: &[u8]) -> Result<Timeline, ParamError> {
    let smf = Smf::parse(bytes).map_err(|e| {
        ParamError::new(
            "--midi",
            format!("not a standard MIDI file ({e})"),
            "a standard MIDI file (format 0 or 1)",
        )
    })?;
    if smf.header.format == Format::Sequential {
        return Err(ParamError::new(
            "--midi",
            "format 2 (sequential patterns)",
            "a standard MIDI file of format 0 or 1",
        ));
    }
    // Every event with its absolute tick and track, merged in time (stable: within a tick, the
    // file's order, track by track).
    let mut all: Vec<(u64, usize, TrackEventKind<'_>)> = Vec::new();
    for (t, track) in smf.tracks.iter().enumerate() {
        let mut tick = 0u64;
        for ev in track {
            tick += u64::from(ev.delta.as_int());
            all.push((tick, t, ev.kind));
        }
    }
    all.sort_by_key(|&(tick, track, _)| (tick, track));
    let seconds_per_tick_fixed = match smf.header.timing {
        Timing::Metrical(tpq) => {
            if tpq.as_int() == 0 {
                return Err(ParamError::new(
                    "--midi",
                    "0 ticks per quarter note",
                    "a header with 1 to 32767 ticks per quarter note",
                ));
            }
            None
        }
        Timing::Timecode(fps, sub) => {
            let per_second = f64::from(fps.as_f32()) * f64::from(sub.max(1));
            Some(1.0 / per_second)
        }
    };
    let tpq = match smf.header.timing {
        Timing::Metrical(t) => f64::from(t.as_int()),
        Timing::Timecode(..) => 1.0,
    };
    let mut tempo_us = DEFAULT_TEMPO_US;
    let (mut last_tick, mut now) = (0u64, 0.0f64);
    let mut events = Vec::new();
    let mut map = MidiMap::default();
    // The map's output for one message (a member channel's bend retunes up to 128 notes).
    let mut out: Vec<Event> = Vec::with_capacity(256);
    for (tick, _, kind) in all {
        let dt = (tick - last_tick) as f64;
        now += match seconds_per_tick_fixed {
            Some(s) => dt * s,
            None => dt * tempo_us * 1e-6 / tpq,
        };
        last_tick = tick;
        match kind {
            TrackEventKind::Meta(MetaMessage::Tempo(us)) => {
                tempo_us = f64::from(us.as_int()).max(1.0);
            }
            TrackEventKind::Midi { channel, message } => {
                if let Some(m) = channel_message(channel.as_int(), message) {
                    out.clear();
                    map.translate(0, m, &mut out);
                    events.extend(out.iter().map(|e| TimedEvent {
                        time: now,
                        kind: e.kind,
                    }));
                }
            }
            _ => {}
        }
    }
    if !events
        .iter()
        .any(|e| matches!(e.kind, EventKind::NoteOn { .. }))
    {
        return Err(ParamError::new(
            "--midi",
            "no note on event",
            "a MIDI file with at least one note",
        ));
    }
    Ok(Timeline::new(events))
}

/// One SMF channel message as the core's MIDI message (`None`: none the mapping reads).
fn channel_message(channel: u8, m: MidiMessage) -> Option<Message> {
    Some(match m {
        MidiMessage::NoteOn { key, vel } => Message::NoteOn {
            channel: Some(channel),
            key: key.as_int(),
            velocity: f32::from(vel.as_int()) / 127.0,
        },
        MidiMessage::NoteOff { key, .. } => Message::NoteOff { key: key.as_int() },
        MidiMessage::PitchBend { bend } => Message::PitchBend {
            channel,
            value: bend.0.as_int(),
        },
        MidiMessage::Controller { controller, value } => Message::ControlChange {
            channel,
            cc: controller.as_int(),
            value: value.as_int(),
        },
        MidiMessage::ChannelAftertouch { vel } => Message::ChannelPressure {
            channel,
            pressure: f32::from(vel.as_int()) / 127.0,
        },
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use midly::num::{u15, u24, u28, u4, u7};
    use midly::{Header, TrackEvent};

    fn ev(delta: u32, kind: TrackEventKind<'static>) -> TrackEvent<'static> {
        TrackEvent {
            delta: u28::new(delta),
            kind,
        }
    }

    fn note(on: bool, key: u8, vel: u8) -> TrackEventKind<'static> {
        let (key, vel) = (u7::new(key), u7::new(vel));
        TrackEventKind::Midi {
            channel: u4::new(0),
            message: if on {
                MidiMessage::NoteOn { key, vel }
            } else {
                MidiMessage::NoteOff { key, vel }
            },
        }
    }

    /// 480 ticks per quarter: one quarter at the default 120 bpm is 0.5 s; after a tempo of
    /// 1 000 000 µs per quarter (60 bpm), one quarter is 1 s. Times exact to 1e-12 s (sums of
    /// a few binary fractions); a note on with velocity 0 is a note off.
    #[test]
    fn tempo_map_and_velocity_zero() {
        let track = vec![
            ev(0, note(true, 60, 127)),
            ev(480, note(true, 60, 0)),
            ev(
                0,
                TrackEventKind::Meta(MetaMessage::Tempo(u24::new(1_000_000))),
            ),
            ev(480, note(true, 64, 64)),
            ev(480, note(false, 64, 0)),
            ev(0, TrackEventKind::Meta(MetaMessage::EndOfTrack)),
        ];
        let smf = Smf {
            header: Header::new(Format::SingleTrack, Timing::Metrical(u15::new(480))),
            tracks: vec![track],
        };
        let mut bytes = Vec::new();
        smf.write_std(&mut bytes).unwrap();
        let t = read_midi(&bytes).unwrap();
        let times: Vec<f64> = t.events.iter().map(|e| e.time).collect();
        let want = [0.0, 0.5, 1.5, 2.5];
        assert_eq!(times.len(), want.len(), "{:?}", t.events);
        for (a, b) in times.iter().zip(want) {
            assert!((a - b).abs() < 1e-12, "{times:?}");
        }
        assert!(matches!(t.events[1].kind, EventKind::NoteOff { key: 60 }));
        assert!(
            matches!(t.events[2].kind, EventKind::NoteOn { key: 64, velocity } if (velocity - 64.0 / 127.0).abs() < 1e-7)
        );
        assert!((t.end - 2.5).abs() < 1e-12);
    }

    /// Garbage and note-less files are refused, naming `--midi`.
    #[test]
    fn bad_files_are_refused() {
        let e = read_midi(b"not a midi file").unwrap_err();
        assert_eq!(e.field, "--midi");
        let smf = Smf {
            header: Header::new(Format::SingleTrack, Timing::Metrical(u15::new(96))),
            tracks: vec![vec![ev(0, TrackEventKind::Meta(MetaMessage::EndOfTrack))]],
        };
        let mut bytes = Vec::new();
        smf.write_std(&mut bytes).unwrap();
        let e = read_midi(&bytes).unwrap_err();
        assert!(e.value.contains("no note"), "{e}");
    }
}
