//! Note and controller events (host MIDI, sample-accurate within a block) and GUI commands.
//!
//! Plain `Copy` data: built by the host layer or the GUI, consumed by the audio thread.

/// What happens at an [`Event`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EventKind {
    /// Note on: MIDI key 0..=127, velocity in `(0, 1]` (a velocity of 0 is a note off).
    NoteOn {
        /// MIDI key number.
        key: u8,
        /// Normalised velocity.
        velocity: f32,
    },
    /// Note off (the voice enters its release, or waits for the sustain pedal).
    NoteOff {
        /// MIDI key number.
        key: u8,
    },
    /// Pitch bend, normalised to `[-1, 1]` (scaled by the `pitch_bend_range` parameter).
    PitchBend(f32),
    /// Mod wheel, normalised to `[0, 1]`.
    ModWheel(f32),
    /// Sustain pedal down (`true`) or up.
    Sustain(bool),
    /// Every sounding voice enters its release (MIDI all-notes-off).
    AllNotesOff,
    /// Every voice stops at once (MIDI all-sound-off, panic).
    AllSoundOff,
    /// A per-note expression for the voice sounding `key` (CLAP note expressions, MPE
    /// per-channel controllers mapped to their note by the host layer). Ignored when no voice
    /// sounds the key; non-finite values are ignored; a new note starts neutral.
    NoteExpression {
        /// MIDI key of the note.
        key: u8,
        /// What changes.
        expression: NoteExpression,
    },
    /// The note sounding `key` gets its own value of one of the per-note parameters
    /// ([`crate::engine::voice::modulation::POLY_PARAMS`]: a host's polyphonic modulation),
    /// in the parameter's unit, clamped into its range. Ignored when no voice sounds the key,
    /// for other parameters and for non-finite values; a new note starts with none.
    NoteModulation {
        /// MIDI key of the note.
        key: u8,
        /// The parameter.
        param: crate::engine::params::ParamId,
        /// The note's value (the parameter's unit).
        value: f32,
    },
}

/// Largest per-note tuning offset (semitones), either way: MPE's default bend range is 48.
pub const MAX_NOTE_TUNING: f32 = 96.0;
/// Largest per-note volume (linear gain; CLAP's volume expression spans 0 to 4).
pub const MAX_NOTE_VOLUME: f32 = 4.0;

/// A per-note expression ([`EventKind::NoteExpression`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NoteExpression {
    /// Pitch offset of this note in semitones, added to the key's pitch and the channel bend
    /// (clamped to ±[`MAX_NOTE_TUNING`], the host protocol's range).
    Tuning(f32),
    /// Output gain of this note (linear, 0 to [`MAX_NOTE_VOLUME`]; 1 is neutral).
    Volume(f32),
    /// Pressure of the player's hand on this note's plate or string, 0 (off, neutral) to 1
    /// (clamped): a hand resting on the instrument damps it (CLAP pressure, MPE channel
    /// pressure).
    Pressure(f32),
    /// Brightness of this note's next strikes or plucks, 0 to 1 (clamped; 0.5 is neutral):
    /// a harder mallet or a shorter pulse, a pluck nearer the string's end (CLAP brightness,
    /// MPE's CC 74).
    Brightness(f32),
    /// Stereo position of this note, 0 (left) to 1 (right), clamped; 0.5 is neutral (both
    /// pickups at their level). A balance: towards one side the other pickup's gain falls
    /// linearly to 0, `g_left = min(1, 2(1 - p))`, `g_right = min(1, 2p)` (CLAP pan).
    Pan(f32),
}

/// An event at a sample offset inside the block given to
/// [`Engine::process_events`](super::Engine::process_events).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Event {
    /// Host-rate sample index in the block at which the event takes effect (events past the
    /// end of the block apply at its end).
    pub offset: u32,
    /// The event.
    pub kind: EventKind,
}

impl Event {
    /// An event at `offset`.
    pub fn new(offset: u32, kind: EventKind) -> Self {
        Self { offset, kind }
    }
}

/// A command from the GUI (or any control thread) to the audio thread, sent through the
/// lock-free queue of [`EngineHandle::send`](super::EngineHandle::send) and applied at the
/// start of the next block.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GuiCommand {
    /// A note or controller event from the editor's keyboard (applied at the block start).
    Event(EventKind),
    /// Puts every voice at rest (like [`Engine::reset`](super::Engine::reset)).
    Reset,
    /// Chooses the voice shown by the displacement snapshot and mode spectrum of the
    /// telemetry (`None`: the loudest).
    Watch(Option<u8>),
}
