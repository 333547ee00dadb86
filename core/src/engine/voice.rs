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
//! pickup weights are zeroed): the exact scheme keeps them stable but their samples alias.
//!
//! Threads: built on the worker thread (inside a bank); everything else runs on the audio
//! thread without allocating.

use super::kinds::Material;
use super::params::{ParamId, ParamValues};
use super::telemetry::{VoiceModelInfo, SNAPSHOT_POINTS, SPECTRUM_MODES};
use crate::modal::CouplingTensor;
use crate::models::plate::{PlateModel, RaisedCosine};
use crate::models::source::EnergyTerms;
use crate::models::string::params::Stiffness;
use crate::models::string::{StiffString, TrianglePluck, ValetteLosses};
use std::sync::Arc;

/// Largest normalised output of one voice (pickup velocity over the model's velocity
/// reference, see [`super::PLATE_VELOCITY_REF`]): a voice past it is treated as diverged
/// (silenced, its chunk dropped, counted in [`Engine::diverged_voices`]). 1e5 is 100 km/s at a
/// plate pickup (400 km/s on a string): above the fastest longitudinal wave the parameter
/// table allows, `√(E_max / ρ_min) = √(5e11 / 500) ≈ 31.6 km/s`, so the strain would exceed 1
/// and no elastic model holds. Voices get there only by divergence of a conditionally stable
/// scheme or by parametric pumping (stiffness or tension automated faster than the voice
/// rings); without the ceiling their output reached inf in f32 before their f64 state
/// overflowed (found by `tests/robustness/soak.rs`).
pub const VOICE_CEILING: f64 = 1e5;

/// Per-bank data of a plate model: the dimensionless modal data and the mode values at the
/// strike point, the pickups and the snapshot points (unit-size plate). Shared read-only by
/// the voices of a bank.
#[derive(Debug)]
pub(crate) struct PlateData {
    /// `λ_s²`: `ω_s = λ_s² √(D/ρh) / a²`.
    pub lambda2: Vec<f64>,
    /// `ζ̂_l⁴` of the unit plate (`ζ_l⁴ = ζ̂_l⁴ / a⁴`).
    pub zeta4: Vec<f64>,
    /// Whether the plate is linear (no in-plane modes: `κ = 0`).
    pub linear: bool,
    /// `Φ̂_s` at the strike point.
    pub strike: Vec<f64>,
    /// `Φ̂_s` at the left and right pickups.
    pub pickups: [Vec<f64>; 2],
    /// `Φ̂_s` at the snapshot points, row-major `[point][mode]`.
    pub snapshot: Vec<f64>,
    /// Poisson ratio `ν` the basis was built with.
    pub poisson: f64,
}

/// A plate voice's model and scratch.
pub(crate) struct PlateVoice {
    pub model: PlateModel<CouplingTensor>,
    pub data: Arc<PlateData>,
    omega: Vec<f64>,
    damping: Vec<f64>,
    zeta4: Vec<f64>,
    /// Length scale `a` (m) of the last retune (weights scale as `1/a`).
    size: f64,
    strike: Option<RaisedCosine>,
    /// Steps since the strike started.
    strike_step: u64,
    fs: f64,
}

/// A string voice's model and the root-key constants.
pub(crate) struct StringVoice {
    pub model: StiffString,
    losses: ValetteLosses,
    /// Newton cap hits already counted into the engine's total.
    pub cap_hits_seen: u64,
}

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
    /// Largest total energy seen since the note started (J).
    pub peak_energy: f64,
    /// Last measured total energy (J).
    pub energy: f64,
    /// Whether the coefficients need a retune before the next step.
    pub dirty: bool,
}

/// Everything the physical mapping reads, from the parameter snapshot and controllers.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Physics {
    pub values: ParamValues,
    /// Pitch bend in semitones.
    pub bend: f32,
}

/// Pitch ratio of `key` (see the module doc).
pub(crate) fn pitch_ratio(v: &ParamValues, key: u8, bend: f32) -> f64 {
    let semis = key as f64 - v.get(ParamId::RootKey) as f64 + bend as f64;
    (v.get(ParamId::TuningA4) as f64 / 440.0) * (semis / 12.0).exp2()
}

/// Release decay rate `σ = ln(1000) / T60` (1/s): amplitude down 60 dB in `T60`.
fn release_sigma(v: &ParamValues) -> f64 {
    1000f64.ln() / v.get(ParamId::ReleaseT60) as f64
}

impl PlateVoice {
    /// Wraps a built model (worker thread; allocates the scratch).
    pub fn new(model: PlateModel<CouplingTensor>, data: Arc<PlateData>, fs: f64) -> Self {
        let (nf, np) = (data.lambda2.len(), data.zeta4.len());
        Self {
            model,
            data,
            omega: vec![0.0; nf],
            damping: vec![0.0; nf],
            zeta4: vec![0.0; np],
            size: 1.0,
            strike: None,
            strike_step: 0,
            fs,
        }
    }

    /// Computes and applies the coefficients for `key` (module doc). `released`: apply the
    /// release floor. Returns `false` if the model refused them (then unchanged).
    fn retune(&mut self, p: &Physics, key: u8, released: bool) -> bool {
        let v = &p.values;
        let m = Material::from_params(v);
        let a = v.get(ParamId::Size) as f64;
        let h = v.get(ParamId::Thickness) as f64 * pitch_ratio(v, key, p.bend);
        let nu = self.data.poisson;
        let d = m.youngs_modulus * h * h * h / (12.0 * (1.0 - nu * nu));
        let rho_h = m.density * h;
        let scale = (d / rho_h).sqrt() / (a * a);
        let (ds, da, db, dc) = (
            v.get(ParamId::DampingScale) as f64,
            v.get(ParamId::DampingA) as f64,
            v.get(ParamId::DampingB) as f64,
            v.get(ParamId::DampingC0) as f64,
        );
        let floor = if released {
            2.0 * release_sigma(v)
        } else {
            0.0
        };
        for (s, &l2) in self.data.lambda2.iter().enumerate() {
            let w = l2 * scale;
            self.omega[s] = w;
            // The release floor is capped at critical damping (c = 2ω): a heavier damping
            // would make a low mode creep back slower (rate ω²/c).
            self.damping[s] = (ds * (da * w.powf(db) + dc)).max(floor.min(2.0 * w));
        }
        let a4 = a.powi(4);
        for (z, &zh) in self.zeta4.iter_mut().zip(&self.data.zeta4) {
            *z = zh / a4;
        }
        let kappa = if self.data.linear { 0.0 } else { a.powi(-5) };
        let ok = self
            .model
            .retune(
                &self.omega,
                &self.damping,
                &self.zeta4,
                rho_h,
                m.youngs_modulus * h,
                kappa,
            )
            .is_ok();
        if ok {
            self.size = a;
            self.write_weights(a);
        }
        ok
    }

    /// Strike and pickup weights `Φ̂_s / a`, zero above `0.45 fs`.
    fn write_weights(&mut self, a: f64) {
        let wmax = 0.45 * std::f64::consts::TAU * self.fs;
        let inv_a = 1.0 / a;
        let fw = self.model.force_weights_mut();
        for (s, w) in fw.iter_mut().enumerate() {
            *w = if self.omega[s] < wmax {
                self.data.strike[s] * inv_a
            } else {
                0.0
            };
        }
        for c in 0..2 {
            let pw = self.model.pickup_weights_mut(c);
            for (s, w) in pw.iter_mut().enumerate() {
                *w = if self.omega[s] < wmax {
                    self.data.pickups[c][s] * inv_a
                } else {
                    0.0
                };
            }
        }
    }
}

impl StringVoice {
    /// Wraps a built model (worker thread).
    pub fn new(model: StiffString, losses: ValetteLosses) -> Self {
        Self {
            model,
            losses,
            cap_hits_seen: 0,
        }
    }

    fn retune(&mut self, p: &Physics, key: u8, released: bool) -> bool {
        let v = &p.values;
        let r = pitch_ratio(v, key, p.bend);
        let t_root = v.get(ParamId::Tension) as f64;
        let l = self.model.params().length;
        let ei = v.get(ParamId::Inharmonicity) as f64 * t_root * l * l
            / (std::f64::consts::PI * std::f64::consts::PI);
        let floor = if released { release_sigma(v) } else { 0.0 };
        self.model
            .retune(
                t_root * r * r,
                Stiffness::BendingStiffness(ei),
                Some(&self.losses),
                v.get(ParamId::DampingScale) as f64,
                floor,
            )
            .is_ok()
    }
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
        }
    }

    /// Whether the voice is in its release (key up and not sustained).
    pub fn released(&self) -> bool {
        !self.held && !self.sustained
    }

    /// Re-applies the physical mapping for the current key. Returns `false` if refused.
    pub fn retune(&mut self, p: &Physics) -> bool {
        self.dirty = false;
        let released = self.released();
        match &mut self.model {
            VoiceModel::Plate(pv) => pv.retune(p, self.key, released),
            VoiceModel::String(sv) => sv.retune(p, self.key, released),
        }
    }

    /// Starts note `key` at velocity `vel` (0..1] with mod wheel `wheel` (0..1). A voice
    /// already playing the same key is struck again without a reset (plates: a new force
    /// pulse on the moving plate; strings: re-plucked). Returns `false` (voice left silent)
    /// if the model refused the note's coefficients.
    pub fn start(&mut self, p: &Physics, key: u8, vel: f32, wheel: f32, now: u64) -> bool {
        let same = self.active && self.key == key;
        if !same {
            self.reset();
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
        let ok = match &mut self.model {
            VoiceModel::Plate(pv) => {
                let peak = v.get(ParamId::StrikeForce) as f64 * amount;
                match RaisedCosine::new(v.get(ParamId::StrikeDuration) as f64, peak) {
                    Ok(s) => {
                        pv.strike = Some(s);
                        pv.strike_step = 0;
                        true
                    }
                    Err(_) => false,
                }
            }
            VoiceModel::String(sv) => {
                let l = sv.model.params().length;
                let pluck = TrianglePluck {
                    position: v.get(ParamId::PluckPosition) as f64 * l,
                    amplitude: v.get(ParamId::PluckAmplitude) as f64 * amount,
                };
                // `pluck` resets the string: count the contact statistics first.
                sv.cap_hits_seen = 0;
                sv.model.pluck(&pluck).is_ok()
            }
        };
        if !ok {
            self.reset();
            return false;
        }
        self.active = true;
        self.started = now;
        self.peak_energy = 0.0;
        self.energy = 0.0;
        true
    }

    /// Silences the voice (state at rest) and frees it. No allocation.
    pub fn reset(&mut self) {
        match &mut self.model {
            VoiceModel::Plate(pv) => {
                pv.model.reset();
                pv.strike = None;
                pv.strike_step = 0;
            }
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
    }

    /// Advances `left.len()` steps, adding `gain ·` the two pickups into `left`/`right`.
    /// Returns `false` if the state became non-finite or `gain ·` a pickup passed
    /// [`super::VOICE_CEILING`] (the caller resets the voice and drops the chunk).
    pub fn run(&mut self, left: &mut [f32], right: &mut [f32], gain: f64) -> bool {
        match &mut self.model {
            VoiceModel::Plate(pv) => {
                for (l, r) in left.iter_mut().zip(right.iter_mut()) {
                    let f = match pv.strike {
                        Some(s) => {
                            let t = pv.strike_step as f64 / pv.fs;
                            pv.strike_step += 1;
                            if t > s.duration {
                                pv.strike = None;
                            }
                            s.force(t)
                        }
                        None => 0.0,
                    };
                    if pv.model.step(f).is_err() {
                        return false;
                    }
                    let o = pv.model.outputs();
                    let (a, b) = (gain * o[0], gain * o[1]);
                    if !(a.abs() <= VOICE_CEILING && b.abs() <= VOICE_CEILING) {
                        return false;
                    }
                    *l += a as f32;
                    *r += b as f32;
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

    /// What the voice simulates for its current note (see [`VoiceModelInfo`]). Audio thread,
    /// O(N_Φ), no allocation.
    pub fn model_info(&self) -> VoiceModelInfo {
        match &self.model {
            VoiceModel::Plate(pv) => {
                let wmax = 0.45 * std::f64::consts::TAU * pv.fs;
                let top = pv
                    .omega
                    .iter()
                    .copied()
                    .filter(|&w| w < wmax)
                    .fold(0.0, f64::max);
                VoiceModelInfo {
                    n_phi: pv.model.q().len() as u32,
                    n_psi: if pv.data.linear {
                        0
                    } else {
                        pv.data.zeta4.len() as u32
                    },
                    top_mode_hz: (top / std::f64::consts::TAU) as f32,
                    sim_rate: pv.fs as f32,
                }
            }
            VoiceModel::String(sv) => {
                let params = sv.model.params();
                let n = sv.model.modal_displacement().len();
                VoiceModelInfo {
                    n_phi: n as u32,
                    n_psi: 0,
                    top_mode_hz: (params.omega(n) / std::f64::consts::TAU) as f32,
                    sim_rate: params.sample_rate as f32,
                }
            }
        }
    }

    /// Whether an excitation force is still being applied.
    pub fn exciting(&self) -> bool {
        match &self.model {
            VoiceModel::Plate(pv) => pv.strike.is_some(),
            VoiceModel::String(_) => false,
        }
    }

    /// Energy terms of the voice (J).
    pub fn energy_terms(&self) -> EnergyTerms {
        match &self.model {
            VoiceModel::Plate(pv) => pv.model.energy().into(),
            VoiceModel::String(sv) => sv.model.energy_terms(),
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
            VoiceModel::Plate(pv) => {
                let q = pv.model.q();
                let n = q.len();
                for (p, d) in disp.iter_mut().enumerate() {
                    let row = &pv.data.snapshot[p * n..(p + 1) * n];
                    let w: f64 = row.iter().zip(q).map(|(a, b)| a * b).sum();
                    *d = (w / pv.size) as f32;
                }
                for s in 0..n.min(SPECTRUM_MODES) {
                    freq[s] = (pv.omega[s] / std::f64::consts::TAU) as f32;
                    amp[s] = q[s].abs() as f32;
                }
            }
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
