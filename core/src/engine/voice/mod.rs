//! One voice of the pool: a plate or a string model, its note state, its excitation, and the
//! mapping from parameters and note to the model's physical coefficients (pitch, size,
//! material, damping, release), applied in place without allocating.
//!
//! Pitch (the note number maps to pitch in a physically meaningful way): with
//! `r = (A4 / 440) · 2^((key - root + bend) / 12)`,
//! - plates scale their thickness, `h_note = r h`: `ω_s = λ_s² √(D/ρh) / a² ∝ h / a²`
//!   (`D = E h³ / 12(1-ν²)`), so every partial moves by `r`; `Eh` and `ρh` follow `h_note`
//!   (a thinner plate is more nonlinear at the same force, as a real one);
//! - strings scale their tension, `T_note = r² T`, with the bending stiffness `EI` of the root
//!   string kept (`f_j = (j c / 2L) √(1 + B j²)`, `c = √(T/μ)`, `B = π² EI / (T L²)`): the
//!   fundamental moves by `r` (exactly for `B = 0`) and the string gets less inharmonic as it
//!   is tightened, as a real one.
//!
//! Release: after note-off every mode decays at least at `σ = ln(1000) / T60` (60 dB in the
//! `release_t60` parameter), except modes with `ω_s < σ`, which get critical damping (their
//! fastest decay).
//!
//! Transverse plate modes above `0.45 fs_sim` are neither driven nor heard (their strike and
//! pickup weights are zeroed): the exact scheme keeps them stable but their samples alias. A
//! plate note simulates only the modes under the band limit (`plate.rs`: tiers and the strike
//! frame); strings are in `string.rs`.
//!
//! Threads: built on the worker thread (inside a bank); everything else runs on the audio
//! thread without allocating.

mod above;
mod body;
mod drone;
mod hand_placement;
mod mallet;
mod mapping;
pub mod modulation;
mod network_voice;
mod plate;
mod sitar;
mod strike;
mod string;
mod string_view;

pub use mallet::{
    mallet_law, MALLET_ALPHA_HARD, MALLET_ALPHA_SOFT, MALLET_K_HARD, MALLET_K_SOFT, MALLET_LOSS,
    MALLET_MAX_FLIGHT, REACH_CHECK_STEPS,
};
use mapping::key_level_gain;
pub(crate) use mapping::Physics;
pub use mapping::VOICE_CEILING;

pub(crate) use above::AboveModes;
pub(crate) use drone::DroneVoice;
pub use drone::DRONE_FORCE_REF;
pub(crate) use hand_placement::hand_radius;
pub use hand_placement::{HAND_MIN_RADIUS, HAND_STRING_POSITION, HAND_T60};
pub(crate) use plate::{band_fraction, tier_ladder, Frame, PlateData, PlateVoice};
#[cfg(doc)]
pub(crate) use plate::{HEARD_FRACTION, NONLINEAR_BAND_FRACTION};
pub(crate) use sitar::SitarVoice;
pub use sitar::SITAR_FORCE_REF;
pub(crate) use string::StringVoice;

use super::params::ParamId;
use super::telemetry::{VoiceModelInfo, SNAPSHOT_POINTS, SPECTRUM_MODES};
use crate::models::source::EnergyTerms;
pub(crate) use body::VoiceBody;
use modulation::NoteOverrides;
use strike::PendingStrike;

/// The model of a voice: a plate, a string, the drone or the sitar, each a [`VoiceBody`].
pub(crate) enum VoiceModel {
    Plate(Box<PlateVoice>),
    String(Box<StringVoice>),
    Drone(Box<DroneVoice>),
    Sitar(Box<SitarVoice>),
}

impl VoiceModel {
    /// The model as the lifecycle the engine drives.
    pub fn body(&mut self) -> &mut dyn VoiceBody {
        match self {
            Self::Plate(pv) => pv.as_mut(),
            Self::String(sv) => sv.as_mut(),
            Self::Drone(dv) => dv.as_mut(),
            Self::Sitar(sv) => sv.as_mut(),
        }
    }

    /// The model as the lifecycle the engine drives, to read.
    pub fn body_ref(&self) -> &dyn VoiceBody {
        match self {
            Self::Plate(pv) => pv.as_ref(),
            Self::String(sv) => sv.as_ref(),
            Self::Drone(dv) => dv.as_ref(),
            Self::Sitar(sv) => sv.as_ref(),
        }
    }
}

/// One voice of the pool.
pub(crate) struct Voice {
    pub model: VoiceModel,
    /// Sounding.
    pub active: bool,
    /// MIDI key.
    pub key: u8,
    /// Key held (note-off not yet received).
    pub held: bool,
    /// Note-off received while the sustain pedal was down.
    pub sustained: bool,
    /// Host sample at which the note started (for oldest-voice stealing and telemetry).
    pub started: u64,
    /// Largest level energy ([`Self::level_energy`]) since the note started (J).
    pub peak_energy: f64,
    /// Last measured level energy (J).
    pub energy: f64,
    /// Whether the coefficients need a retune before the next step.
    pub dirty: bool,
    /// The note's output level from the `key_level` tracking (linear gain, set by `retune`).
    pub level: f64,
    /// The note's own pitch offset (semitones, per-note tuning expression; 0 at note-on).
    pub note_tuning: f32,
    /// The note's own gain (per-note volume expression; 1 at note-on).
    pub note_volume: f32,
    /// The note's stereo position (per-note pan expression, 0 left to 1 right; 0.5 at
    /// note-on). Audio thread.
    pub note_pan: f32,
    /// The player's hand pressure on this note (per-note pressure expression, 0 to 1; 0 at
    /// note-on). Audio thread.
    pub note_pressure: f32,
    /// The note's brightness (per-note brightness expression, 0 to 1; 0.5 at note-on).
    /// Audio thread.
    pub note_brightness: f32,
    /// The note's own values of the per-note parameters (polyphonic modulation). Audio
    /// thread.
    pub overrides: NoteOverrides,
    /// The strike or pluck of the last note-on, committed at the voice's next step.
    pending: Option<PendingStrike>,
    /// Wall time (s) of the voice's last job ([`Self::run`] and [`Self::run_above`]),
    /// written by the thread that ran it; the CPU governor learns from it.
    pub job_seconds: f64,
    /// Chunks left of a fade-out ordered by the CPU governor (0: none).
    pub fading: u8,
}

impl Voice {
    /// A silent voice around `model`.
    pub fn new(model: VoiceModel) -> Self {
        Self {
            model,
            active: false,
            key: 0,
            held: false,
            sustained: false,
            started: 0,
            peak_energy: 0.0,
            energy: 0.0,
            dirty: false,
            level: 1.0,
            note_tuning: 0.0,
            note_volume: 1.0,
            note_pan: 0.5,
            note_pressure: 0.0,
            note_brightness: modulation::NEUTRAL_BRIGHTNESS,
            overrides: NoteOverrides::default(),
            pending: None,
            job_seconds: 0.0,
            fading: 0,
        }
    }

    /// The CPU governor's price of one step of the voice's current model (s;
    /// `engine/governor.rs`): its plate tier's or its string's. Audio thread.
    pub fn price(&self) -> f64 {
        self.model.body_ref().price()
    }

    /// Whether the model of the voice's current note offers the second half of its steps to
    /// the voice pool's workers (a plate tier with a large coupling tensor). Audio thread.
    pub fn offers_step_halves(&self) -> bool {
        self.model.body_ref().offers_step_halves()
    }

    /// Whether the voice is in its release (key up and not sustained).
    pub fn released(&self) -> bool {
        !self.held && !self.sustained
    }

    /// Re-applies the physical mapping for the current key (with the note's own values of the
    /// per-note parameters). Returns `false` if refused.
    pub fn retune(&mut self, p: &Physics) -> bool {
        let own = Physics {
            values: self.overrides.apply(p.values),
            ..*p
        };
        let p = &own;
        self.dirty = false;
        self.level = key_level_gain(&p.values, self.key);
        let released = self.released();
        self.model
            .body()
            .retune(p, self.key, self.note_tuning, released)
    }

    /// Starts note `key` at velocity `vel` (0..1] with mod wheel `wheel` (0..1). A voice
    /// already playing the same key, or any key of a legato model (the sitar:
    /// [`VoiceBody::legato`]), is struck again without a reset (plates: a new force
    /// pulse, or with `exciter = mallet` a mallet launched at `mallet_speed · vel^curve` (times
    /// the wheel's factor) against the moving plate; strings: the pluck's shape added to the
    /// motion). Returns `false` (voice left silent)
    /// if the model refused the note's coefficients.
    pub fn start(&mut self, p: &Physics, key: u8, vel: f32, wheel: f32, now: u64) -> bool {
        let same = self.active && self.key == key;
        // Every note starts with neutral expressions and no modulation of its own.
        self.note_tuning = 0.0;
        self.note_volume = 1.0;
        self.note_pan = 0.5;
        self.note_pressure = 0.0;
        self.note_brightness = modulation::NEUTRAL_BRIGHTNESS;
        self.overrides = NoteOverrides::default();
        // A string not yet plucked (a fresh note whose pluck is still pending) stays fresh.
        let fresh = !same || self.pending.is_some_and(|s| s.fresh);
        if !same {
            // A legato model (the sitar) keeps its motion into the new key.
            if !(self.active && self.model.body_ref().legato()) {
                self.reset();
            }
            self.model.body().begin(p, key);
        }
        self.key = key;
        self.held = true;
        self.sustained = false;
        if !self.retune(p) {
            self.reset();
            return false;
        }
        let v = &p.values;
        let curve = v.get(ParamId::VelocityCurve);
        let depth = v.get(ParamId::ModWheelDepth);
        let amount = (vel.clamp(0.0, 1.0).powf(curve) * (1.0 + depth * (2.0 * wheel - 1.0))) as f64;
        // The excitation itself is committed at the voice's next step (`strike.rs`), so the
        // note's own expressions and modulations sent with its note-on shape it.
        self.pending = Some(PendingStrike {
            amount,
            fresh,
            values: p.values,
        });
        self.active = true;
        self.started = now;
        self.peak_energy = 0.0;
        self.energy = 0.0;
        true
    }

    /// Commits the pending strike, if any (`strike.rs`). Returns `false` if its excitation
    /// was refused (the caller silences the voice).
    fn commit_strike(&mut self) -> bool {
        let Some(s) = self.pending.take() else {
            return true;
        };
        let v = self.overrides.apply(s.values);
        self.model.body().strike(&s, v, self.note_brightness)
    }

    /// Silences the voice (state at rest) and frees it. No allocation.
    pub fn reset(&mut self) {
        self.model.body().reset();
        self.active = false;
        self.held = false;
        self.sustained = false;
        self.peak_energy = 0.0;
        self.energy = 0.0;
        self.pending = None;
        self.fading = 0;
    }

    /// Advances `left.len()` steps, adding `gain ·` the two pickups into `left`/`right`.
    /// Returns `false` if the state became non-finite or `gain ·` a pickup passed
    /// [`super::VOICE_CEILING`] (the caller resets the voice and drops the chunk).
    pub fn run(&mut self, left: &mut [f32], right: &mut [f32], gain: f64) -> bool {
        if !self.commit_strike() {
            return false;
        }
        self.apply_pressure();
        self.model.body().run(left, right, gain)
    }

    /// Runs the band above the simulation of a plate voice for `left.len()` samples at the bank's above rate
    /// (after [`Self::run`] ran the chunk's simulation samples), adding `gain ·` its pickups;
    /// `false` past [`super::VOICE_CEILING`]. Strings have none (O(1)). Audio thread or the
    /// voice's job; no allocation.
    pub fn run_above(&mut self, left: &mut [f32], right: &mut [f32], gain: f64) -> bool {
        self.model.body().run_above(left, right, gain)
    }

    /// The note's hand pressure on its model (a point damper, see [`HAND_T60`]): O(1), no
    /// allocation, audio thread.
    fn apply_pressure(&mut self) {
        let p = self.note_pressure as f64;
        self.model.body().set_pressure(p);
    }

    /// What the voice simulates for its current note (see [`VoiceModelInfo`]). Audio thread,
    /// O(N_Φ), no allocation.
    pub fn model_info(&self) -> VoiceModelInfo {
        self.model.body_ref().model_info()
    }

    /// Whether an excitation force is still being applied (a pulse, or a mallet in flight).
    pub fn exciting(&self) -> bool {
        self.pending.is_some() || self.model.body_ref().exciting()
    }

    /// Energy terms of the voice (J).
    pub fn energy_terms(&self) -> EnergyTerms {
        self.model.body_ref().energy_terms()
    }

    /// The energy (J) that measures how loud the voice still is, for its end and for voice
    /// stealing ([`VoiceBody::level_energy`]: a string's total energy, a plate's kinetic and
    /// linear potential energy).
    pub fn level_energy(&self) -> f64 {
        self.model.body_ref().level_energy()
    }

    /// Mallet contacts begun since the last call (plates with the mallet; 0 otherwise).
    pub fn take_impacts(&mut self) -> u64 {
        self.model.body().take_impacts()
    }

    /// Newton cap hits since the last call (strings; 0 for plates).
    pub fn take_cap_hits(&mut self) -> u64 {
        self.model.body().take_cap_hits()
    }

    /// Fills `view` with the drone's strings and cycle (`false`: not a drone). Audio thread,
    /// no allocation.
    pub fn drone_view(&mut self, view: &mut super::telemetry::DroneView) -> bool {
        self.model.body().drone_view(view)
    }

    /// Writes the displacement snapshot (m), the lowest mode frequencies (Hz) and `|q_s|`.
    pub fn snapshot(
        &mut self,
        disp: &mut [f32; SNAPSHOT_POINTS],
        freq: &mut [f32; SPECTRUM_MODES],
        amp: &mut [f32; SPECTRUM_MODES],
    ) {
        freq.fill(0.0);
        amp.fill(0.0);
        self.model.body().snapshot(disp, freq, amp);
    }
}
