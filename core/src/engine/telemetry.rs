//! Data sent from the audio thread to the GUI (about 30 times a second) through a ringbuf
//! queue ([`EngineHandle::telemetry`](super::EngineHandle::telemetry)).
//!
//! Plain `Copy` data of fixed size: pushing it never allocates.

use super::drone_tuning::DroneTuning;
use super::memory::ModesFitted;
use crate::models::source::EnergyTerms;

/// Largest polyphony (the `polyphony` parameter's maximum): the telemetry holds this many
/// voice slots.
pub const MAX_VOICES: usize = 16;

/// Points of the displacement snapshot (along a diameter for circular plates, along the
/// diagonal for rectangles, along the length for strings).
pub const SNAPSHOT_POINTS: usize = 64;

/// Modes in the telemetry's mode spectrum (the lowest ones).
pub const SPECTRUM_MODES: usize = 64;

/// One voice as the GUI sees it.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct VoiceTelemetry {
    /// Whether the voice is sounding.
    pub active: bool,
    /// MIDI key it plays.
    pub key: u8,
    /// Whether the key is still held (or sustained).
    pub held: bool,
    /// Whether the voice, its key released, plays on by itself (a latched drone).
    pub latched: bool,
    /// Energy terms in J (kinetic, linear potential, nonlinear: in-plane energy of a plate or
    /// contact energy of a string; dissipated and work since the note started).
    pub energy: EnergyTerms,
    /// Seconds since the note started.
    pub age: f32,
    /// What the voice simulates for its note.
    pub model: VoiceModelInfo,
}

/// The model a sounding voice actually simulates for its note (after the note's pitch scaling
/// and band limit). Plain `Copy` data, written on the audio thread.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct VoiceModelInfo {
    /// Transverse plate modes `N_Φ` stepped (string: modes `N - 1`).
    pub n_phi: u32,
    /// In-plane plate modes `N_Ψ` stepped (0: linear plate or a string).
    pub n_psi: u32,
    /// Frequency (Hz) of the highest mode that is driven and heard, after the note's scaling.
    pub top_mode_hz: f32,
    /// Simulation rate of the voice (Hz).
    pub sim_rate: f32,
    /// Modes of the plate's band above the simulation (0: none, off, or a string).
    pub above_modes: u32,
    /// Frequency (Hz) of the band above's highest mode (0 without one).
    pub above_top_hz: f32,
}

/// Most strings a drone view carries (the drone has four to six).
pub const MAX_DRONE_STRINGS: usize = 6;

/// Points of each string's displacement in a drone view.
pub const DRONE_VIEW_POINTS: usize = 48;

/// The watched drone voice's strings and cycle, for the editor's drone view. Plain `Copy`
/// data written on the audio thread.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DroneView {
    /// Strings in use (the first `strings` entries of the arrays).
    pub strings: u8,
    /// Each string's note over Sa (Pa 0.75, Ma 0.667, Ni 0.9375, Sa 1, the lower Sa 0.5).
    pub ratio: [f32; MAX_DRONE_STRINGS],
    /// Each string's energy (J).
    pub energy: [f32; MAX_DRONE_STRINGS],
    /// Each string's displacement (m) at `DRONE_VIEW_POINTS` points from the bridge to the
    /// far end.
    pub displacement: [[f32; DRONE_VIEW_POINTS]; MAX_DRONE_STRINGS],
    /// Sa (Hz) the drone sounds.
    pub sa_hz: f32,
    /// The cycle's period (s).
    pub cycle_seconds: f32,
    /// Where the cycle is: the time since its start over its period (0 to 1).
    pub cycle_phase: f32,
    /// Each string's pluck in the cycle, as a fraction of the period.
    pub onsets: [f32; MAX_DRONE_STRINGS],
    /// Whether the cycle plucks (the note is held, sustained or latched).
    pub plucking: bool,
}

impl Default for DroneView {
    fn default() -> Self {
        Self {
            strings: 0,
            ratio: [0.0; MAX_DRONE_STRINGS],
            energy: [0.0; MAX_DRONE_STRINGS],
            displacement: [[0.0; DRONE_VIEW_POINTS]; MAX_DRONE_STRINGS],
            sa_hz: 0.0,
            cycle_seconds: 0.0,
            cycle_phase: 0.0,
            onsets: [0.0; MAX_DRONE_STRINGS],
            plucking: false,
        }
    }
}

/// One telemetry frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Telemetry {
    /// Host-rate samples processed since activation when the frame was taken.
    pub frame: u64,
    /// Every voice slot (only the first `polyphony` are used).
    pub voices: [VoiceTelemetry; MAX_VOICES],
    /// Peak absolute output per channel (left, right) since the previous frame.
    pub peak: [f32; 2],
    /// RMS output per channel since the previous frame.
    pub rms: [f32; 2],
    /// Displacement snapshot in m of the watched voice ([`Telemetry::watched`]); zeros if
    /// none.
    pub displacement: [f32; SNAPSHOT_POINTS],
    /// Voice slot shown by `displacement` and `mode_amplitude`.
    pub watched: Option<u8>,
    /// Frequencies (Hz) of the lowest modes of the watched voice.
    pub mode_freq: [f32; SPECTRUM_MODES],
    /// Amplitudes `|q_s|` of those modes (model units: m² for plates, m^3/2 for strings).
    pub mode_amplitude: [f32; SPECTRUM_MODES],
    /// CPU time of every thread working on the audio over the last frame, per second of
    /// audio: the audio thread's time in `process` plus the voice pool's workers' thread CPU
    /// time (1 = one core fully busy; up to the number of threads). Written on the audio
    /// thread.
    pub cpu_load: f32,
    /// The audio thread's time in `process` over the last frame, per second of audio: the
    /// share that must stay below 1 for real time (it includes waiting for the workers).
    pub audio_load: f32,
    /// Largest single-block load of the audio thread in the last frame (block time / block
    /// duration).
    pub cpu_peak: f32,
    /// Threads allowed to share the last chunk's voices, the audio thread included (the
    /// `threads` parameter, capped at the machine's cores; a chunk with one sounding voice
    /// runs on the audio thread alone).
    pub threads: u8,
    /// Voice jobs still running on a worker when the audio thread's bounded wait ended,
    /// since activation (their chunks were left out of the mix; see `Engine::set_job_wait`).
    pub late_jobs: u64,
    /// Notes the CPU governor started with a narrower band than asked, since the engine was
    /// created (`engine/governor.rs`).
    pub governor_reduced: u64,
    /// Voices the CPU governor ended to make room or because blocks overran.
    pub governor_shed: u64,
    /// The string bank in use was built with fewer modes than asked, to fit one voice in the
    /// CPU budget (`engine/string_bank.rs`).
    pub modes_fitted: Option<ModesFitted>,
    /// How the drone bank's strings were tuned (`None`: not a drone).
    pub drone_tuning: Option<DroneTuning>,
    /// The watched voice's strings and cycle when it is a drone.
    pub drone: Option<DroneView>,
    /// The bank in use is a preview (a small model while the full one builds).
    pub preview: bool,
    /// Heap bytes of the engine's coupling tensors (`Engine::memory_bytes`).
    pub memory_bytes: u64,
    /// Whether the worker is building a new voice bank.
    pub rebuilding: bool,
    /// Identifier of the voice bank in use (increments with every swap).
    pub bank: u64,
    /// Contact Newton solves that hit the iteration cap since activation (strings; the step
    /// then completes with the capped iterate, see `models::string::contact`).
    pub newton_cap_hits: u64,
    /// Voices whose state became non-finite or whose output passed
    /// [`VOICE_CEILING`](super::VOICE_CEILING) since activation (they are silenced and freed).
    pub diverged: u64,
    /// Output samples the output stage's guard bounded to full scale or zeroed as non-finite
    /// since the engine was created (`Engine::guarded_samples`; 0 while the limiter is on).
    /// Written on the audio thread.
    pub guarded: u64,
    /// Simulation rate of the bank in use (Hz).
    pub sim_rate: f32,
    /// Sounding voices.
    pub active_voices: u8,
}

impl Default for Telemetry {
    fn default() -> Self {
        Self {
            frame: 0,
            voices: [VoiceTelemetry::default(); MAX_VOICES],
            peak: [0.0; 2],
            rms: [0.0; 2],
            displacement: [0.0; SNAPSHOT_POINTS],
            watched: None,
            mode_freq: [0.0; SPECTRUM_MODES],
            mode_amplitude: [0.0; SPECTRUM_MODES],
            cpu_load: 0.0,
            audio_load: 0.0,
            cpu_peak: 0.0,
            threads: 1,
            late_jobs: 0,
            governor_reduced: 0,
            governor_shed: 0,
            modes_fitted: None,
            drone_tuning: None,
            drone: None,
            preview: false,
            memory_bytes: 0,
            rebuilding: false,
            bank: 0,
            newton_cap_hits: 0,
            diverged: 0,
            guarded: 0,
            sim_rate: 0.0,
            active_voices: 0,
        }
    }
}
