//! The real-time engine: a fixed pool of plate or string voices driven by notes, mixed to
//! stereo and resampled to the host rate, with model building on a worker thread.
//! No plugin, GUI or audio-device dependency.
//!
//! # API summary (stable; later changes are additive)
//!
//! ```no_run
//! use noether_core::engine::{Engine, Event, EventKind, ParamId, SharedParams, Preset};
//! use std::sync::Arc;
//!
//! let params = Arc::new(SharedParams::new());                 // host / GUI write, audio reads
//! Preset::factory_named("gong-40N").unwrap().apply(&params).unwrap();
//! let (mut engine, mut handle) = Engine::new(params.clone()); // main thread
//! engine.activate(48_000.0, 512).unwrap();                    // main thread: allocates, starts worker
//! // audio thread, every block (any length 1..=8192):
//! let (mut l, mut r) = (vec![0.0f32; 512], vec![0.0f32; 512]);
//! let events = [Event::new(0, EventKind::NoteOn { key: 60, velocity: 0.8 })];
//! engine.process_events(&events, &mut l, &mut r);              // sample-accurate events
//! engine.process(&mut l, &mut r);                              // or no events
//! // host / GUI thread:
//! params.set(ParamId::Size, 0.5).unwrap();                     // rescale, no rebuild
//! params.set(ParamId::Model, 3.0).unwrap();                    // sitar: the worker rebuilds
//! let _frame = handle.telemetry();                             // energies, levels, CPU, ...
//! let _busy = handle.is_rebuilding();
//! ```
//!
//! - [`Engine`] (audio thread): [`Engine::new`] → ([`Engine`], [`EngineHandle`]);
//!   [`Engine::activate`]`(host_rate, max_block)` (any positive rate; builds the first bank, or the
//!   last model that built when the parameters are refused; starts the worker; main thread); [`Engine::reset`]; [`Engine::process`] /
//!   [`Engine::process_events`] (`&[Event]` sorted by offset); direct note calls
//!   [`Engine::note_on`], [`Engine::note_off`], [`Engine::pitch_bend`], [`Engine::mod_wheel`],
//!   [`Engine::sustain`]; [`Engine::latency_samples`] for the host; read-outs for tests
//!   ([`Engine::bank_id`], [`Engine::voice_energy`], [`Engine::active_voices`], ...).
//! - [`EngineHandle`] (GUI / main thread): [`EngineHandle::send`] a [`GuiCommand`] (ringbuf),
//!   [`EngineHandle::telemetry`] (newest [`Telemetry`], ringbuf), [`EngineHandle::is_rebuilding`],
//!   [`EngineHandle::last_error`], [`EngineHandle::params`].
//! - Parameters: [`PARAMS`] (static table of [`ParamInfo`]: key, name, unit, min, max,
//!   default, kind, whether it rebuilds), [`ParamId`] (`id as usize` indexes the table),
//!   [`SharedParams`] (one `AtomicU32` of `f32` bits each; `set` refuses out-of-range values
//!   with a [`crate::ParamError`]), [`ParamValues`] (a plain copy).
//! - Presets: [`Preset`] (TOML, keys of the table, enumerations by name),
//!   [`Preset::factory`] (embedded `assets/presets/*.toml`).
//!
//! # Threads and real-time rules
//!
//! `process` allocates nothing, takes no lock and does no I/O (checked by
//! `tests/engine/engine_alloc.rs` with `assert_no_alloc`); its work is bounded: the block is split
//! into chunks of [`CHUNK`] host samples; each chunk runs every sounding voice for the
//! simulation steps the resampler needs (at most `ceil(CHUNK · fs_sim / fs_host) + 2R`) and
//! each step is bounded (plates: one Cholesky of fixed size; strings: at most
//! [`crate::models::string::NEWTON_CAP`] Newton iterations per contact node, after which the
//! step completes with the capped iterate and the event is counted in the telemetry).
//!
//! With the CPU governor on ([`Engine::set_governor`], a live host; [`governor`]) a note's
//! band comes down, and the quietest voices end, so that the voices' measured work stays
//! within the `cpu_budget` parameter and blocks within real time.
//!
//! The voices of a chunk run in parallel on the voice pool (`engine/pool.rs`): `activate` starts
//! `available_parallelism() - 1` worker threads, the `threads` parameter ([`ParamId::Threads`],
//! read per chunk; 0 = every core, 1 = the audio thread alone) sets how many threads share a
//! chunk. The audio thread hands the jobs over lock-free (an atomic state per voice), runs jobs
//! itself, and waits at most the chunk's duration ([`Engine::set_job_wait`]) for the jobs a
//! worker holds; a job still running then is late: that voice's chunk is left out of the mix
//! and counted. The mix, the divergence and silence checks and the resampler stay on the audio
//! thread, in voice order, so the output does not depend on the number of threads. Workers
//! spin briefly, then park; `deactivate` and drop join them. No allocation in their job loop
//! either (checked by `tests/engine/engine_threads.rs`).
//!
//! Model builds (modal bases and coupling tensors through the on-disk cache, string grids and
//! obstacles, the voice pool) run on the worker thread (started by the first activation,
//! joined on drop; [`Engine::activate_realtime`] returns without waiting for it): it polls the
//! parameters whose [`ParamInfo::rebuild`] flag is set, debounces 30 ms, builds a bank and
//! sends it through a bounded crossbeam channel; the audio thread takes it with `try_recv` at
//! a chunk boundary, cross-fades the old bank out over 20 ms (sounding notes of the old model
//! end there) and sends it back through a second channel to be dropped on the worker.
//! Parameters without the flag (size and thickness of plates, material E and ρ, damping,
//! tension and inharmonicity, tuning, gain, excitation) apply on the audio thread without a
//! rebuild: the voices' per-mode coefficients are recomputed in place
//! ([`crate::models::plate::PlateModel::retune`], [`crate::models::string::StiffString::retune`])
//! at most every 2 ms while they change.
//!
//! # Simulation rate and resampling
//!
//! Each bank runs at the `sim_rate` parameter (its quality) and is resampled to the host rate
//! by a Kaiser-windowed sinc interpolator written here ([`resample`]: why not rubato is
//! explained there); latency is its half-width, 12 zero crossings (about 0.4 ms at a 32 kHz
//! simulation rate), reported by [`Engine::latency_samples`] with the output stage's.
//!
//! # Output stage
//!
//! After the output gain, at the host rate: a low cut (`low_cut`), a transparent look-ahead
//! limiter at -0.3 dBFS (`limiter`) and a guard that bounds every sample to 0 dBFS and
//! zeroes non-finite ones, so no setting sends a host more than full scale ([`output`]).
//! Each note's level follows the `key_level` tracking (dB per octave from the root key).
//!
//! # Tuning
//!
//! Key `k` plays the pitch `p(k)` of the [`KeyTuning`] table in [`SharedParams::tuning`]
//! (12-tone equal temperament, `p(k) = k`, unless a host or GUI thread publishes another, for
//! instance from a Scala file): the pitch ratio to the root key is
//! `2^((p(k) - root + bend)/12) · a4/440`. The audio thread takes a new table at a block start
//! (lock-free, see [`tuning`]) and retunes the sounding voices like a bend.
//!
//! # Voices
//!
//! Polyphony is fixed per bank (parameter, 1..16). A note takes the voice already playing its
//! key, else a free voice, else steals the quietest released voice, else the oldest. A voice
//! ends (and costs nothing more) when its level energy (`Voice::level_energy`) falls below [`SILENCE_RATIO`] of its
//! peak after the excitation, and is silenced (its chunk dropped, counted as diverged) if its
//! output passes [`VOICE_CEILING`]; when no voice sounds and the resampler history is zero, the
//! bank costs only a buffer fill. Note to pitch, release and the physical mapping: [`voice`].

mod above_mix;
mod activation;
mod audio;
mod bank;
mod cost_trial;
#[cfg(test)]
mod cost_trial_tests;
mod drone_bank;
mod drone_tuning;
mod events;
pub mod governor;
mod handle;
mod handover;
mod handover_state;
mod kinds;
pub mod memory;
#[cfg(test)]
mod memory_tests;
mod meters;
pub mod midi;
mod mix;
mod model_spec;
mod network_bank;
mod note_state;
mod notes;
pub mod output;
pub mod param_meta;
#[cfg(test)]
mod param_meta_tests;
mod param_names;
pub mod params;
mod plate_bank;
mod pool;
pub mod preset;
mod readout;
pub mod resample;
pub mod scala;
mod sitar_bank;
mod string_bank;
mod telemetry;
pub mod tuning;
pub mod voice;
mod voice_jobs;

pub use crate::models::plate::spec::Material;
pub use audio::{Engine, MAX_HOST_RATE, MIN_HOST_RATE};
pub use bank::{CHUNK, PLATE_VELOCITY_REF, STRING_VELOCITY_REF};
pub use drone_bank::DRONE_ANCHORS;
pub use drone_tuning::{DroneTuning, DRONE_TUNING_BUDGET, SITAR_TUNING_BUDGET};
pub use events::{Event, EventKind, GuiCommand, NoteExpression, MAX_NOTE_TUNING, MAX_NOTE_VOLUME};
pub use handle::{EngineHandle, DEBOUNCE};
pub use kinds::ModelKind;
pub use memory::{FitReason, ModesFitted};
pub use mix::SILENCE_RATIO;
pub use sitar_bank::SITAR_ANCHORS;

/// Slowest host tempo the engine takes (beats per minute; `Engine::set_host_tempo`).
pub const MIN_TEMPO: f64 = 20.0;

/// Fastest host tempo the engine takes (beats per minute).
pub const MAX_TEMPO: f64 = 400.0;
pub use model_spec::{drone_modes, DRONE_MIN_SIM_RATE};
pub use output::{OutputStage, CEILING, LOOKAHEAD};
pub use param_meta::{ParamGroup, Reads, Shown};
pub use params::{
    ParamId, ParamInfo, ParamKind, ParamValues, SharedParams, DRONE_PATTERN_KEYS,
    DRONE_PATTERN_NAMES, DRONE_TUNING_KEYS, DRONE_TUNING_NAMES, EXCITER_NAMES, MALLET_HEAD_NAMES,
    MATERIAL_NAMES, MODEL_KEYS, MODEL_NAMES, ON_OFF_NAMES, PARAMS, PARAM_COUNT, SCHEME_KEYS,
    SCHEME_NAMES, THAAT_KEYS, THAAT_NAMES,
};
pub use plate_bank::plate_sim_rate;
pub use pool::in_voice_job;
pub use preset::{legacy_bridge_fraction, Preset, PresetValue, LEGACY_BRIDGE_POSITION};
pub use scala::{load_scala, scala_tuning, ScalaError, ScalaTuning};
pub use telemetry::{
    DroneView, Telemetry, VoiceModelInfo, VoiceTelemetry, DRONE_VIEW_POINTS, MAX_DRONE_STRINGS,
    MAX_VOICES, SNAPSHOT_POINTS, SPECTRUM_MODES,
};
pub use tuning::{KeyTuning, SharedTuning, KEY_COUNT};
pub use voice::{
    mallet_law, DRONE_FORCE_REF, HAND_MIN_RADIUS, HAND_STRING_POSITION, HAND_T60,
    MALLET_ALPHA_HARD, MALLET_ALPHA_SOFT, MALLET_K_HARD, MALLET_K_SOFT, MALLET_LOSS,
    MALLET_MAX_FLIGHT, REACH_CHECK_STEPS, SITAR_FORCE_REF, VOICE_CEILING,
};
