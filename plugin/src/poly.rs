//! CLAP polyphonic modulation and note ends (audio thread; fixed-size state, no allocation).
//!
//! The parameters of [`POLY_PARAMS`] carry a poly-modulation id (their index there), so a
//! CLAP host may modulate them per note: nice-plug turns the host's `CLAP_EVENT_PARAM_MOD`
//! with a note id into [`NoteEvent::PolyModulation`] (a normalised offset on the parameter's
//! unmodulated value) and an automation of such a parameter into
//! [`NoteEvent::MonoAutomation`]. [`PolyVoices`] keeps, per key, the host's voice (note id and
//! channel) of the note sounding it and its offsets, and sends the engine the note's own plain
//! value, `param.preview_plain(normalised + offset)` (nice-plug's recipe, which clamps to the
//! range), as [`EventKind::NoteModulation`]: at the modulation, and again for every modulated
//! note when the parameter's global value moves.
//!
//! The engine has one voice per key: a new note on a sounding key takes that voice over (the
//! engine strikes it again), so the older note id ends there. The plugin therefore declares no
//! overlapping voices, and sends the host a [`NoteEvent::VoiceTerminated`] (CLAP's note end)
//! for every note whose voice stopped sounding, was stolen or taken over, or never sounded (a
//! note the engine refused, a key the tuning leaves unmapped): [`PolyVoices::end_voices`]
//! compares the engine's sounding keys after each block with the notes it knows.

use crate::params::{NoetherParams, Slot};
use nice_plug::midi::{Channel, Key, NoteEvent, VoiceID};
use nice_plug::params::Param;
use noether_core::engine::voice::modulation::POLY_PARAMS;
use noether_core::engine::{Event, EventKind};

/// Blocks a note may wait without its key sounding before it counts as never started (the
/// engine defers events while a late voice job holds its bank, for a block or two at most).
const START_GRACE_BLOCKS: u16 = 8;

/// The host's note on one key.
#[derive(Debug, Clone, Copy)]
struct HostNote {
    /// CLAP note id (`None`: the host gave none).
    id: Option<i32>,
    /// MIDI channel (0-based), if the host gave one.
    channel: Option<u8>,
    /// Seen sounding in the engine at the end of a block.
    seen: bool,
    /// Blocks since the note-on while not yet seen sounding.
    waited: u16,
    /// Normalised offsets of [`POLY_PARAMS`] (NaN: not modulated).
    offsets: [f32; POLY_PARAMS.len()],
}

/// A voice end to report: `(note id, channel, key)`.
pub type Ended = (Option<i32>, Option<u8>, u8);

/// The host's notes and their polyphonic modulation (module doc). Audio thread.
#[derive(Debug, Clone)]
pub struct PolyVoices {
    notes: [Option<HostNote>; 128],
}

impl Default for PolyVoices {
    fn default() -> Self {
        Self { notes: [None; 128] }
    }
}

/// Appends `event` if `out` has spare capacity (never reallocates on the audio thread).
fn push(out: &mut Vec<Event>, event: Event) {
    if out.len() < out.capacity() {
        out.push(event);
    }
}

/// Appends the engine event giving the note on `key` its own value of poly parameter `slot`:
/// the plain value at normalised `base + offset` (clamped; `base` the parameter's unmodulated
/// value when `None`). Nothing for a stepped parameter (none is a poly parameter).
fn modulate(
    out: &mut Vec<Event>,
    params: &NoetherParams,
    at: u32,
    key: u8,
    slot: usize,
    base: Option<f32>,
    offset: f32,
) {
    let param = POLY_PARAMS[slot];
    let Slot::Float(p) = params.slot(param) else {
        return;
    };
    let n = base.unwrap_or_else(|| p.unmodulated_normalized_value());
    let value = p.preview_plain((n + offset).clamp(0.0, 1.0));
    push(
        out,
        Event::new(at, EventKind::NoteModulation { key, param, value }),
    );
}

impl PolyVoices {
    /// Forgets every note (the host's `reset`); no note end is reported for them.
    pub fn reset(&mut self) {
        self.notes = [None; 128];
    }

    /// Follows `event`: note-ons record the host's note (reporting through `ended` an older
    /// note the new one takes over); polyphonic modulation and mono automation append the
    /// engine's [`EventKind::NoteModulation`] events to `out`.
    pub fn observe<S>(
        &mut self,
        event: &NoteEvent<S>,
        params: &NoetherParams,
        out: &mut Vec<Event>,
        mut ended: impl FnMut(Ended),
    ) {
        let at = event.timing();
        match *event {
            NoteEvent::NoteOn {
                voice_id,
                channel,
                key,
                velocity,
                ..
            } if velocity > 0.0 => {
                let Some(k) = key.number() else { return };
                let new = HostNote {
                    id: voice_id.id(),
                    channel: channel.number(),
                    seen: false,
                    waited: 0,
                    offsets: [f32::NAN; POLY_PARAMS.len()],
                };
                if let Some(old) = self.notes[usize::from(k)].replace(new) {
                    if old.id != new.id || old.channel != new.channel {
                        ended((old.id, old.channel, k));
                    }
                }
            }
            NoteEvent::PolyModulation {
                voice_id,
                poly_modulation_id,
                normalized_offset,
                ..
            } => {
                let slot = poly_modulation_id as usize;
                if slot >= POLY_PARAMS.len() || !normalized_offset.is_finite() {
                    return;
                }
                let Some(k) = (0..128u8)
                    .find(|&k| self.notes[usize::from(k)].is_some_and(|n| n.id == Some(voice_id)))
                else {
                    return;
                };
                if let Some(n) = self.notes[usize::from(k)].as_mut() {
                    n.offsets[slot] = normalized_offset;
                }
                modulate(out, params, at, k, slot, None, normalized_offset);
            }
            NoteEvent::MonoAutomation {
                poly_modulation_id,
                normalized_value,
                ..
            } => {
                let slot = poly_modulation_id as usize;
                if slot >= POLY_PARAMS.len() {
                    return;
                }
                for k in 0..128u8 {
                    let Some(n) = self.notes[usize::from(k)] else {
                        continue;
                    };
                    let offset = n.offsets[slot];
                    if offset.is_nan() {
                        continue;
                    }
                    modulate(out, params, at, k, slot, Some(normalized_value), offset);
                }
            }
            _ => {}
        }
    }

    /// After a block: reports through `ended` (and forgets) every note whose key the engine
    /// no longer sounds (`sounding`, bit `k` for key `k`), and every note not sounding
    /// [`START_GRACE_BLOCKS`] blocks after its note-on.
    pub fn end_voices(&mut self, sounding: u128, mut ended: impl FnMut(Ended)) {
        for k in 0..128u8 {
            let Some(n) = self.notes[usize::from(k)].as_mut() else {
                continue;
            };
            if sounding & (1u128 << k) != 0 {
                n.seen = true;
                continue;
            }
            n.waited = n.waited.saturating_add(1);
            if n.seen || n.waited > START_GRACE_BLOCKS {
                ended((n.id, n.channel, k));
                self.notes[usize::from(k)] = None;
            }
        }
    }
}

/// The nice-plug event for an ended note at `timing`.
pub fn terminated<S>(timing: u32, (id, channel, key): Ended) -> NoteEvent<S> {
    NoteEvent::VoiceTerminated {
        timing,
        voice_id: id.map_or(VoiceID::Wildcard, VoiceID::ID),
        channel: channel.map_or(Channel::Wildcard, Channel::Number),
        key: Key::Number(key),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use noether_core::engine::ParamId;

    fn on(id: i32, key: u8) -> NoteEvent<()> {
        NoteEvent::NoteOn {
            timing: 0,
            voice_id: VoiceID::ID(id),
            channel: Channel::Number(0),
            key: Key::Number(key),
            velocity: 1.0,
        }
    }

    fn modulation(id: i32, slot: u32, offset: f32) -> NoteEvent<()> {
        NoteEvent::PolyModulation {
            timing: 3,
            voice_id: id,
            poly_modulation_id: slot,
            normalized_offset: offset,
        }
    }

    /// A modulation reaches the note with that id as its plain value; an automation of the
    /// parameter re-sends it on the new base; other notes and unknown ids get nothing.
    #[test]
    fn modulation_follows_the_note_id_and_the_automation() {
        let params = NoetherParams::default();
        let mut p = PolyVoices::default();
        let mut out = Vec::with_capacity(8);
        let mut ended = Vec::new();
        for (id, key) in [(7, 60), (8, 64)] {
            p.observe(&on(id, key), &params, &mut out, |e| ended.push(e));
        }
        let slot = POLY_PARAMS
            .iter()
            .position(|&id| id == ParamId::DampingScale)
            .unwrap() as u32;
        p.observe(&modulation(8, slot, 0.1), &params, &mut out, |e| {
            ended.push(e)
        });
        p.observe(&modulation(99, slot, 0.1), &params, &mut out, |e| {
            ended.push(e)
        });
        let Slot::Float(damping) = params.slot(ParamId::DampingScale) else {
            panic!("damping is continuous")
        };
        let want = damping.preview_plain(damping.unmodulated_normalized_value() + 0.1);
        assert!((want - 3.0).abs() < 1e-5, "{want}: 1 + 0.1 of 0 to 20");
        let event = |value| {
            Event::new(
                3,
                EventKind::NoteModulation {
                    key: 64,
                    param: ParamId::DampingScale,
                    value,
                },
            )
        };
        assert_eq!(out, vec![event(want)]);
        out.clear();
        let automation: NoteEvent<()> = NoteEvent::MonoAutomation {
            timing: 3,
            poly_modulation_id: slot,
            normalized_value: 0.5,
        };
        p.observe(&automation, &params, &mut out, |e| ended.push(e));
        assert_eq!(out, vec![event(damping.preview_plain(0.6))]);
        assert!(ended.is_empty());
    }

    /// Notes end when their key stops sounding, when a new note takes the key over, or when
    /// they never sound within the grace.
    #[test]
    fn note_ends_are_reported_once() {
        let params = NoetherParams::default();
        let mut p = PolyVoices::default();
        let mut out = Vec::with_capacity(8);
        let mut ended = Vec::new();
        p.observe(&on(1, 60), &params, &mut out, |e| ended.push(e));
        p.observe(&on(2, 62), &params, &mut out, |e| ended.push(e));
        p.end_voices(1 << 60 | 1 << 62, |e| ended.push(e));
        assert!(ended.is_empty());
        // A new note on key 60 takes its voice over: note 1 ends.
        p.observe(&on(3, 60), &params, &mut out, |e| ended.push(e));
        assert_eq!(ended, vec![(Some(1), Some(0), 60)]);
        // Key 62 stops sounding: note 2 ends, once.
        p.end_voices(1 << 60, |e| ended.push(e));
        p.end_voices(1 << 60, |e| ended.push(e));
        assert_eq!(ended[1..], [(Some(2), Some(0), 62)]);
        // A note that never sounds ends after the grace.
        p.observe(&on(4, 70), &params, &mut out, |e| ended.push(e));
        for _ in 0..START_GRACE_BLOCKS {
            p.end_voices(1 << 60, |e| ended.push(e));
        }
        assert_eq!(ended.len(), 2);
        p.end_voices(1 << 60, |e| ended.push(e));
        assert_eq!(ended[2..], [(Some(4), Some(0), 70)]);
    }
}
