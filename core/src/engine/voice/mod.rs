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
mod hand;
mod mallet;
mod mapping;
pub mod modulation;
mod plate;
mod strike;
mod string;

pub use mallet::{
    mallet_law, MALLET_ALPHA_HARD, MALLET_ALPHA_SOFT, MALLET_K_HARD, MALLET_K_SOFT, MALLET_LOSS,
    MALLET_MAX_FLIGHT, REACH_CHECK_STEPS,
};
use mapping::key_level_gain;
pub(crate) use mapping::Physics;
pub use mapping::VOICE_CEILING;

pub(crate) use above::AboveModes;
pub(crate) use hand::hand_radius;
pub use hand::{HAND_MIN_RADIUS, HAND_STRING_POSITION, HAND_T60};
pub(crate) use plate::{tier_ladder, Frame, PlateData, PlateVoice, HEARD_FRACTION};
pub(crate) use string::StringVoice;

use super::params::ParamId;
use super::telemetry::{VoiceModelInfo, SNAPSHOT_POINTS, SPECTRUM_MODES};
use crate::models::source::EnergyTerms;
use modulation::NoteOverrides;
use strike::{commit_plate, commit_string, PendingStrike};

/// The model of a voice.
pub(crate) enum VoiceModel {
    Plate(Box<PlateVoice>),
    String(Box<StringVoice>),
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
        match &self.model {
            VoiceModel::Plate(pv) => pv.price(),
            VoiceModel::String(sv) => sv.price,
        }
    }

    /// Whether the model of the voice's current note offers the second half of its steps to
    /// the voice pool's workers (a plate tier with a large coupling tensor). Audio thread.
    pub fn offers_step_halves(&self) -> bool {
        match &self.model {
            VoiceModel::Plate(pv) => pv.model().offers_step_halves(),
            _ => false,
        }
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
        match &mut self.model {
            VoiceModel::Plate(pv) => pv.retune(p, self.key, self.note_tuning, released),
            VoiceModel::String(sv) => sv.retune(p, self.key, self.note_tuning, released),
        }
    }

    /// Starts note `key` at velocity `vel` (0..1] with mod wheel `wheel` (0..1). A voice
    /// already playing the same key is struck again without a reset (plates: a new force
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
            self.reset();
            if let VoiceModel::Plate(pv) = &mut self.model {
                pv.begin(p, key);
            }
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
        match &mut self.model {
            VoiceModel::Plate(pv) => commit_plate(pv, &s, v, self.note_brightness),
            VoiceModel::String(sv) => commit_string(sv, &s, v, self.note_brightness),
        }
    }

    /// Silences the voice (state at rest) and frees it. No allocation.
    pub fn reset(&mut self) {
        match &mut self.model {
            VoiceModel::Plate(pv) => pv.reset(),
            VoiceModel::String(sv) => {
                sv.model.reset();
                sv.cap_hits_seen = 0;
            }
        }
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
        match &mut self.model {
            VoiceModel::Plate(pv) => {
                if !pv.run(left, right, gain) {
                    return false;
                }
            }
            VoiceModel::String(sv) => {
                for (l, r) in left.iter_mut().zip(right.iter_mut()) {
                    sv.model.step();
                    let (mut a, mut b) = (0.0, 0.0);
                    sv.model
                        .read_outputs(|c, x| if c == 0 { a = x } else { b = x });
                    let (a, b) = (gain * a, gain * b);
                    if !(a.abs() <= VOICE_CEILING && b.abs() <= VOICE_CEILING) {
                        return false;
                    }
                    *l += a as f32;
                    *r += b as f32;
                }
            }
        }
        true
    }

    /// Runs the band above the simulation of a plate voice for `left.len()` samples at the bank's above rate
    /// (after [`Self::run`] ran the chunk's simulation samples), adding `gain ·` its pickups;
    /// `false` past [`super::VOICE_CEILING`]. Strings have none (O(1)). Audio thread or the
    /// voice's job; no allocation.
    pub fn run_above(&mut self, left: &mut [f32], right: &mut [f32], gain: f64) -> bool {
        match &mut self.model {
            VoiceModel::Plate(pv) => pv.run_above(left, right, gain),
            VoiceModel::String(_) => true,
        }
    }

    /// The note's hand pressure on its model (a point damper, see [`HAND_T60`]): O(1), no
    /// allocation, audio thread.
    fn apply_pressure(&mut self) {
        let p = self.note_pressure as f64;
        match &mut self.model {
            VoiceModel::Plate(pv) => pv.set_pressure(p),
            VoiceModel::String(sv) => sv.set_pressure(p),
        }
    }

    /// What the voice simulates for its current note (see [`VoiceModelInfo`]). Audio thread,
    /// O(N_Φ), no allocation.
    pub fn model_info(&self) -> VoiceModelInfo {
        match &self.model {
            VoiceModel::Plate(pv) => pv.model_info(),
            VoiceModel::String(sv) => {
                let params = sv.model.params();
                let n = sv.model.modal_displacement().len();
                VoiceModelInfo {
                    n_phi: n as u32,
                    n_psi: 0,
                    top_mode_hz: (params.omega(n) / std::f64::consts::TAU) as f32,
                    sim_rate: params.sample_rate as f32,
                    ..VoiceModelInfo::default()
                }
            }
        }
    }

    /// Whether an excitation force is still being applied (a pulse, or a mallet in flight).
    pub fn exciting(&self) -> bool {
        match &self.model {
            _ if self.pending.is_some() => true,
            VoiceModel::Plate(pv) => pv.strike.is_some() || pv.mallet.live(),
            VoiceModel::String(_) => false,
        }
    }

    /// Energy terms of the voice (J).
    pub fn energy_terms(&self) -> EnergyTerms {
        match &self.model {
            VoiceModel::Plate(pv) => pv.energy_terms(),
            VoiceModel::String(sv) => sv.model.energy_terms(),
        }
    }

    /// The energy (J) that measures how loud the voice still is, for its end and for voice
    /// stealing: kinetic plus linear potential plus, for strings, the contact energy. A plate's
    /// nonlinear term is left out: under the SAV scheme it is the auxiliary `ψ²/2`, which
    /// keeps an `O(h²)` residue after the motion has died away, while the physical quartic
    /// energy vanishes faster than the linear one as `q → 0`.
    pub fn level_energy(&self) -> f64 {
        let e = self.energy_terms();
        match &self.model {
            VoiceModel::Plate(_) => e.kinetic + e.linear,
            VoiceModel::String(_) => e.total(),
        }
    }

    /// Mallet contacts begun since the last call (plates with the mallet; 0 otherwise).
    pub fn take_impacts(&mut self) -> u64 {
        match &mut self.model {
            VoiceModel::Plate(pv) => u64::from(pv.mallet.take_impacts()),
            VoiceModel::String(_) => 0,
        }
    }

    /// Newton cap hits since the last call (strings; 0 for plates).
    pub fn take_cap_hits(&mut self) -> u64 {
        match &mut self.model {
            VoiceModel::Plate(_) => 0,
            VoiceModel::String(sv) => {
                let total = sv.model.contact_stats().cap_hits;
                let d = total.saturating_sub(sv.cap_hits_seen);
                sv.cap_hits_seen = total;
                d
            }
        }
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
        match &mut self.model {
            VoiceModel::Plate(pv) => pv.snapshot(disp, freq, amp),
            VoiceModel::String(sv) => {
                let u = sv.model.grid_displacement();
                let n = u.len() + 1; // intervals
                for (p, d) in disp.iter_mut().enumerate() {
                    // Node position x = (p + 1) / (P + 1) of the length, interpolated.
                    let xi = (p + 1) as f64 / (SNAPSHOT_POINTS + 1) as f64 * n as f64;
                    let i = xi.floor() as usize;
                    let w = xi - i as f64;
                    let at = |k: usize| if k == 0 || k >= n { 0.0 } else { u[k - 1] };
                    *d = ((1.0 - w) * at(i) + w * at(i + 1)) as f32;
                }
                let q = sv.model.modal_displacement();
                let params = sv.model.params();
                for j in 0..q.len().min(SPECTRUM_MODES) {
                    freq[j] = (params.omega(j + 1) / std::f64::consts::TAU) as f32;
                    amp[j] = q[j].abs() as f32;
                }
            }
        }
    }
}
