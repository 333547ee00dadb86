//! The engine's note-playing state: the player's controllers, the key table the voices play
//! and what the sounding voices were last tuned with. The events that change it are handled
//! in `engine/notes.rs`.

use super::params::{ParamValues, SharedParams};
use super::tuning::KeyTuning;

/// The engine's part that plays notes: the player's controllers, the key table the voices
/// play, and what the sounding voices were last tuned with (so a change of a playing value,
/// the bend or the table retunes them, at most every `RETUNE_INTERVAL`).
///
/// Threads: owned by the audio thread's `Engine`.
pub(super) struct NoteState {
    /// The channel's pitch bend (semitones: the wheel times the bend range).
    pub bend: f32,
    /// The mod wheel (0 to 1).
    pub wheel: f32,
    /// The sustain pedal.
    pub sustain: bool,
    /// The key table the voices play (taken from `params.tuning()` at block starts).
    pub key_tuning: KeyTuning,
    /// Sequence number of `key_tuning` in `params.tuning()`.
    pub tuning_seen: u64,
    /// Sequence number of the table the sounding voices were last tuned with.
    pub tuning_applied: u64,
    /// The non-rebuild values and bend the sounding voices were last tuned with.
    pub applied: (ParamValues, f32),
    /// Host samples until the sounding voices may be retuned again.
    pub retune_wait: usize,
    /// Keys sounding at the last `Engine::sounding_keys` that could read the bank.
    pub sounding_keys: u128,
    /// The host's tempo (beats per minute; `None`: none given).
    pub tempo: Option<f64>,
    /// The tempo the sounding voices were last tuned with.
    pub tempo_applied: Option<f64>,
}

impl NoteState {
    /// Controllers at rest, the table of `params`, the voices tuned with `values`. Main
    /// thread.
    pub fn new(values: ParamValues, params: &SharedParams) -> Self {
        Self {
            bend: 0.0,
            wheel: 0.5,
            sustain: false,
            key_tuning: params.tuning().get(),
            tuning_seen: params.tuning().sequence(),
            tuning_applied: params.tuning().sequence(),
            applied: (values, 0.0),
            retune_wait: 0,
            sounding_keys: 0,
            tempo: None,
            tempo_applied: None,
        }
    }

    /// Puts the controllers at rest (bend 0, wheel at its centre, pedal up) and allows a
    /// retune at once. Audio thread, no allocation.
    pub fn reset_controllers(&mut self) {
        self.bend = 0.0;
        self.wheel = 0.5;
        self.sustain = false;
        self.retune_wait = 0;
    }
}
