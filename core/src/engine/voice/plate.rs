//! A plate voice: one model per mode tier, the note's tier chosen from its band, the strike
//! frame of the note, and the note-to-coefficient mapping applied in place.
//!
//! **Model only what a note requires.** A note scales every partial by its pitch ratio `r`
//! (see [`super`]), so the number of transverse modes under the band limit `B` falls as the note
//! rises. The bank holds a ladder of truncations of its basis (tiers of `N_k ≈ N 2^{-k/2}`
//! transverse modes, the first `N_k` by frequency, each with its own sub-tensor, see
//! [`crate::modal::CouplingTensor::truncated`]); a voice owns one model per tier and a note uses
//! the smallest tier that still holds every mode under `B` (the largest if the CPU budget `N`
//! stops first). In-plane modes follow the transverse count in proportion (at least
//! [`data::MIN_TIER_PSI`]): the in-plane modes represent the products of the transverse modes kept,
//! whose content scales with the transverse band.
//!
//! **Strike frame.** A circular plate is simulated in the strike-mirror basis (the cosine modes
//! `Φ_s = R_s(r) cos(n_s θ)`, symmetric about the strike's diameter: the strike excites no other
//! mode, and the von Kármán coupling never leaves that subspace). A strike at angle `θ_0` is the
//! strike at 0 with the pickups rotated by `-θ_0`: `Φ_s(r_p, θ_p - θ_0) = Φ_s(r_p, 0) cos(n_s
//! (θ_p - θ_0))`, so the strike angle needs no rebuild. A voice keeps the frame of the strike
//! that started it: struck again while it sounds (the same key), the new strike lands on the
//! voice's own diameter whatever the strike-angle parameter says now, because a strike off that
//! diameter would drive the antisymmetric modes the voice does not carry. Rectangles use the
//! full basis and evaluate the strike point at each fresh note (allocation-free).
//!
//! Threads: built on the worker thread (inside a bank); everything else runs on the audio
//! thread without allocating.

use super::above::Above;
use super::hand_placement::hand_radius;
use super::mallet::VoiceMallet;
use super::mapping::{pitch_ratio, release_sigma, Physics, VOICE_CEILING};
use crate::engine::params::ParamId;
use crate::engine::telemetry::{VoiceModelInfo, SNAPSHOT_POINTS, SPECTRUM_MODES};
use crate::modal::scaling::{flexural_rigidity, in_plane_divisor, pulsation_scale};
use crate::modal::CouplingTensor;
use crate::models::plate::spec::Position;
use crate::models::plate::{PlateModel, RaisedCosine};
use std::f64::consts::TAU;
use std::sync::Arc;

pub(crate) use data::{tier_ladder, Frame, PlateData};

/// Fraction of the simulation rate below which a mode is driven and heard: modes above it are
/// kept stable by the exact scheme but their samples would alias (their weights are zeroed).
pub(crate) const HEARD_FRACTION: f64 = 0.45;

/// Largest ratio of a nonlinear plate's band (the top mode a note keeps in motion) to the
/// simulation rate: the top mode's alias of the parametric resonance under the in-plane
/// stress then lies at `0.28 fs`, above the stress's strong part (`plate/kept.rs` says why
/// and what was measured; the bank's rate follows, [`crate::engine::plate_sim_rate`]).
pub(crate) const NONLINEAR_BAND_FRACTION: f64 = 0.36;

/// The fraction of the simulation rate under which a plate's notes keep their modes in
/// motion (and its bank's band lies): [`HEARD_FRACTION`] for a linear plate,
/// [`NONLINEAR_BAND_FRACTION`] for a nonlinear one. Any thread.
pub(crate) fn band_fraction(linear: bool) -> f64 {
    if linear {
        HEARD_FRACTION
    } else {
        NONLINEAR_BAND_FRACTION
    }
}

/// A plate voice: its tier models and per-note scratch.
pub(crate) struct PlateVoice {
    /// One model per tier of [`PlateData::tiers`], same order.
    models: Vec<PlateModel<CouplingTensor>>,
    /// The tier in use.
    tier: usize,
    /// Whether the CPU governor put the current note on a smaller tier than its band asks
    /// (audio thread; read and cleared by the engine after the note-on).
    pub governed: bool,
    /// The tier every note takes in the worker's cost trial (`engine/cost_trial.rs`), whatever
    /// its band asks; `None` in play (worker thread only).
    pub trial_tier: Option<usize>,
    pub data: Arc<PlateData>,
    /// `ω_s` (rad/s) and `c_s` (1/s) of every mode of the basis for the current note.
    omega: Vec<f64>,
    damping: Vec<f64>,
    zeta4: Vec<f64>,
    /// `Φ̂_s` at the strike and the pickups in the voice's frame (unit plate, every mode).
    strike_w: Vec<f64>,
    pickup_w: [Vec<f64>; 2],
    /// Strike angle (rad) of the note's frame.
    angle: f64,
    /// The note's own strike radius and pickup radii, where they differ from the bank's.
    own_strike: Option<f64>,
    own_pickups: [Option<f64>; 2],
    /// `Φ̂_s` at the hand point in the voice's frame (unit plate, every mode; [`super::hand_placement::hand_radius`]).
    hand_w: Vec<f64>,
    /// The hand's damper coefficient at full pressure for the current note (N·s/m,
    /// [`super::hand_placement::hand_c_max`]; 0 before the first retune).
    hand_c_max: f64,
    /// The hand pressure applied to the model (0 to 1).
    pressure: f64,
    /// Length scale `a` (m) of the last retune (weights scale as `1/a`).
    pub size: f64,
    /// Mass per area `ρh` (kg/m²) of the last retune.
    rho_h: f64,
    /// The strike being applied, if any.
    pub strike: Option<RaisedCosine>,
    /// Steps since the strike started.
    pub strike_step: u64,
    /// The physical mallet while it is in flight or in contact (exciter `mallet`).
    pub mallet: VoiceMallet,
    /// Simulation rate (Hz).
    pub fs: f64,
    /// The rest shape's scratch `a_k` (m², every mode) and the amplitudes `(L h dome, L h
    /// boss)` (m²) last set on each tier's model ([`rest_shape`]).
    rest: Vec<f64>,
    rest_set: Vec<(f64, f64)>,
    /// The band above the note's simulation ([`above`]).
    above: Above,
}

impl PlateVoice {
    /// Wraps the tier models, the band above running at `above_rate` (Hz) (worker thread;
    /// allocates the scratch).
    pub fn new(
        models: Vec<PlateModel<CouplingTensor>>,
        data: Arc<PlateData>,
        fs: f64,
        above_rate: f64,
    ) -> Self {
        let (nf, np) = (data.lambda2.len(), data.zeta4.len());
        let tiers_n = data.tiers.len();
        let above = Above::new(&data.above, above_rate);
        Self {
            models,
            tier: 0,
            governed: false,
            trial_tier: None,
            data,
            omega: vec![0.0; nf],
            damping: vec![0.0; nf],
            zeta4: vec![0.0; np],
            strike_w: vec![0.0; nf],
            pickup_w: [vec![0.0; nf], vec![0.0; nf]],
            angle: 0.0,
            own_strike: None,
            own_pickups: [None; 2],
            hand_w: vec![0.0; nf],
            hand_c_max: 0.0,
            pressure: 0.0,
            size: 1.0,
            rho_h: 1.0,
            strike: None,
            strike_step: 0,
            mallet: VoiceMallet::default(),
            fs,
            rest: vec![0.0; nf],
            rest_set: vec![(0.0, 0.0); tiers_n],
            above,
        }
    }

    /// The governor's price of one step of the tier in use (s).
    pub fn price(&self) -> f64 {
        self.data.tier_price[self.tier]
    }

    /// The model of the tier in use.
    pub fn model(&self) -> &PlateModel<CouplingTensor> {
        &self.models[self.tier]
    }

    /// `(ω scale, a, h, ρh, E)` for `key`: `ω_s = λ_s² · scale`.
    fn note_scalars(&self, p: &Physics, key: u8, note: f32) -> (f64, f64, f64, f64, f64) {
        let v = &p.values;
        let m = v.material();
        let a = v.get(ParamId::Size) as f64;
        let h = v.get(ParamId::Thickness) as f64 * pitch_ratio(p, key, note);
        let nu = self.data.poisson;
        let d = flexural_rigidity(m.youngs_modulus, h, nu);
        let rho_h = m.density * h;
        (pulsation_scale(d, rho_h, a), a, h, rho_h, m.youngs_modulus)
    }

    /// Prepares a fresh note: the smallest tier holding every mode under the band limit (the
    /// largest when the budget stops first; for the θ = 1 scheme at most the largest tier it
    /// integrates stably; at most the price `p.price_cap` when the CPU governor is on; exactly
    /// [`Self::trial_tier`] in the worker's cost trial), that
    /// model at rest, and the strike frame at the current strike angle. Audio thread, O(N_Φ),
    /// no allocation.
    pub fn begin(&mut self, p: &Physics, key: u8) {
        // A note starts with a neutral tuning expression.
        let (scale, ..) = self.note_scalars(p, key, 0.0);
        let limit = TAU * self.data.band_hz / scale;
        let n_band = self.data.lambda2.partition_point(|&l2| l2 <= limit);
        let tiers = &self.data.tiers;
        self.tier = (0..tiers.len())
            .rev()
            .find(|&k| tiers[k].0 >= n_band)
            .unwrap_or(0);
        // The conditionally stable scheme (θ = 1: ω h < 2) takes the largest tier whose top
        // mode is within ω h ≤ 1.9; the bank's rate keeps the band itself within 1.5.
        if !self.models[0].scheme().exact_linear_part() {
            let stable = |k: usize| {
                let top = tiers[k].0.min(self.data.lambda2.len()).max(1) - 1;
                self.data.lambda2[top] * scale / self.fs <= 1.9
            };
            while !stable(self.tier) && self.tier + 1 < tiers.len() {
                self.tier += 1;
            }
        }
        // The CPU governor's cap on the step's price (infinite unless it is on): the band
        // comes down a tier at a time (in-plane modes in proportion) until the note fits.
        let natural = self.tier;
        while self.data.tier_price[self.tier] > p.price_cap && self.tier + 1 < tiers.len() {
            self.tier += 1;
        }
        self.governed = self.tier != natural;
        if let Some(t) = self.trial_tier {
            self.tier = t.min(tiers.len() - 1);
        }
        let angle = p.values.get(ParamId::StrikeAngle) as f64;
        self.angle = angle;
        self.own_strike = None;
        self.own_pickups = [None; 2];
        self.set_frame(angle);
        self.models[self.tier].reset();
        // A multiple of the calibrated strength, in range by the parameter table (0 to 4), so
        // this cannot fail (and does not allocate).
        let closure = p.values.get(ParamId::Closure) as f64;
        let _ = self.models[self.tier].set_closure(closure);
        self.above.reset();
        self.above.on = p.values.index_of(ParamId::BandAbove) == 1;
        self.above.contact = p.values.index_of(ParamId::StrikeAbove) == 1;
        self.strike = None;
        self.strike_step = 0;
        self.mallet.drop_mallet();
    }

    /// Strikes the sounding (or fresh) plate with a mallet at `speed` (m/s, > 0) built from
    /// `v` (mass and hardness), at the strike point of the tier in use; a force pulse still
    /// running is ended. Audio thread, no allocation.
    pub fn launch_mallet(
        &mut self,
        v: &crate::engine::params::ParamValues,
        speed: f64,
    ) -> Result<(), crate::error::ParamError> {
        self.strike = None;
        let reach = self.reach();
        self.mallet.launch(v, &self.models[self.tier], speed, reach)
    }

    /// `2 Σ_s Φ_s²/ω̃_s² / ρh` (m²/J) at the strike point over the modes driven (module doc
    /// of [`super::mallet`]): `ω̃_s = (2/h) sin(ω_s h/2)`, the lower bound of both schemes'
    /// modified frequencies. Audio thread, O(N_Φ).
    fn reach(&self) -> f64 {
        let h = 1.0 / self.fs;
        let wmax = self.kept_limit();
        let n = self.data.tiers[self.tier].0;
        let sum: f64 = (0..n)
            .filter(|&s| self.omega[s] < wmax && self.omega[s] > 0.0)
            .map(|s| {
                let phi = self.strike_w[s] / self.size;
                let w = 2.0 / h * (0.5 * self.omega[s] * h).sin();
                phi * phi / (w * w)
            })
            .sum();
        2.0 * sum / self.rho_h
    }

    /// Unit-plate strike and pickup values in the frame of a strike at `angle` (rad), at the
    /// bank's radii or the note's own ([`Self::place_strike`], [`Self::place_pickup`]).
    /// O(N_Φ); a note's own radius costs one mode-shape evaluation per mode. No allocation.
    fn set_frame(&mut self, angle: f64) {
        let polar = |r: f64, a: f64| Position {
            r: Some(r),
            angle: Some(a),
            ..Position::default()
        };
        match &self.data.frame {
            Frame::Mirror {
                basis,
                orders,
                strike,
                hand,
                pickups,
                pickup_angles,
                ..
            } => {
                match self.own_strike {
                    None => self.strike_w.copy_from_slice(strike),
                    Some(r) => {
                        for (s, w) in self.strike_w.iter_mut().enumerate() {
                            *w = basis.phi_at(s, &polar(r, 0.0));
                        }
                    }
                }
                // The hand opposite the strike: Φ_s(r_h, π) = (-1)^{n_s} Φ̂_s(r_h, 0).
                let own_hand = self.own_strike.map(hand_radius);
                for (s, w) in self.hand_w.iter_mut().enumerate() {
                    let radial = match own_hand {
                        None => hand[s],
                        Some(r) => basis.phi_at(s, &polar(r, 0.0)),
                    };
                    *w = if orders[s] % 2 == 0 { radial } else { -radial };
                }
                for c in 0..2 {
                    let d = pickup_angles[c] - angle;
                    let own = self.own_pickups[c];
                    for (s, w) in self.pickup_w[c].iter_mut().enumerate() {
                        let radial = match own {
                            None => pickups[c][s],
                            Some(r) => basis.phi_at(s, &polar(r, 0.0)),
                        };
                        *w = radial * (orders[s] as f64 * d).cos();
                    }
                }
            }
            Frame::Fixed {
                basis,
                strike_radius,
                pickups,
                pickup_points,
            } => {
                let side = |r: f64, a: f64| Position {
                    x: Some(0.5 + 0.5 * r * a.cos()),
                    y: Some(0.5 + 0.5 * r * a.sin()),
                    ..Position::default()
                };
                let at = side(self.own_strike.unwrap_or(*strike_radius), angle);
                for (s, w) in self.strike_w.iter_mut().enumerate() {
                    *w = basis.phi_at(s, &at);
                }
                for c in 0..2 {
                    match self.own_pickups[c] {
                        None => self.pickup_w[c].copy_from_slice(&pickups[c]),
                        Some(r) => {
                            let at = side(r, pickup_points[c].1);
                            for (s, w) in self.pickup_w[c].iter_mut().enumerate() {
                                *w = basis.phi_at(s, &at);
                            }
                        }
                    }
                }
                let r_hand = hand_radius(self.own_strike.unwrap_or(*strike_radius));
                let hand_at = side(r_hand, angle + std::f64::consts::PI);
                for (s, w) in self.hand_w.iter_mut().enumerate() {
                    *w = basis.phi_at(s, &hand_at);
                }
            }
        }
    }

    /// The bank's strike radius and pickup radii.
    fn bank_radii(&self) -> (f64, [f64; 2]) {
        match &self.data.frame {
            Frame::Mirror {
                strike_radius,
                pickup_radii,
                ..
            } => (*strike_radius, *pickup_radii),
            Frame::Fixed {
                strike_radius,
                pickup_points,
                ..
            } => (*strike_radius, pickup_points.map(|p| p.0)),
        }
    }

    /// Puts the note's strikes at `radius` (the `strike_radius` parameter's fraction) from
    /// the next one on: the strike weights are re-evaluated if it differs from where they
    /// are. Audio thread; O(N_Φ) mode-shape evaluations when it moves, no allocation.
    pub fn place_strike(&mut self, radius: f64) {
        let own = (radius != self.bank_radii().0).then_some(radius);
        if own != self.own_strike {
            self.own_strike = own;
            self.set_frame(self.angle);
            self.write_weights(self.size);
            // The hand stays opposite the strike.
            self.write_hand(self.size, self.rho_h);
        }
    }

    /// Puts pickup `c` (0 left, 1 right) of the note at `radius` (the pickup position
    /// parameter's fraction), at once. Audio thread; as [`Self::place_strike`].
    pub fn place_pickup(&mut self, c: usize, radius: f64) {
        let own = (radius != self.bank_radii().1[c]).then_some(radius);
        if own != self.own_pickups[c] {
            self.own_pickups[c] = own;
            self.set_frame(self.angle);
            self.write_weights(self.size);
        }
    }

    /// Computes and applies the coefficients for `key` to the tier in use (module doc of
    /// [`super`]), with the note's own tuning `note` (semitones). `released`: apply the release
    /// floor. Returns `false` if the model refused
    /// them (then unchanged).
    pub fn retune(&mut self, p: &Physics, key: u8, note: f32, released: bool) -> bool {
        let v = &p.values;
        let (scale, a, h, rho_h, e) = self.note_scalars(p, key, note);
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
        let (n, m) = self.data.tiers[self.tier];
        // The release floor is capped at critical damping (c = 2ω): a heavier damping would
        // make a low mode creep back slower (rate ω²/c).
        let law = |w: f64| (ds * (da * w.powf(db) + dc)).max(floor.min(2.0 * w));
        for (s, &l2) in self.data.lambda2.iter().enumerate().take(n) {
            self.omega[s] = l2 * scale;
        }
        // A nonlinear note's modes from the kept limit on are overdamped (`kept.rs`).
        self.write_damping(n, law);
        let a4 = in_plane_divisor(a);
        for (z, &zh) in self.zeta4.iter_mut().zip(&self.data.zeta4).take(m) {
            *z = zh / a4;
        }
        let kappa = if self.data.linear { 0.0 } else { a.powi(-5) };
        let ok = self.models[self.tier]
            .retune(
                &self.omega[..n],
                &self.damping[..n],
                &self.zeta4[..m],
                rho_h,
                e * h,
                kappa,
            )
            .is_ok();
        if ok {
            self.retune_above(scale, law, a, rho_h);
            self.set_residual(e, h, rho_h, n);
            self.set_shape(v, a, h);
            self.size = a;
            self.rho_h = rho_h;
            self.write_weights(a);
            self.write_hand(a, rho_h);
        }
        ok
    }

    /// Strike and pickup weights `Φ̂_s / a` of the tier in use, zero from the kept limit on
    /// ([`Self::kept_limit`]: [`HEARD_FRACTION`]` fs` on a linear plate,
    /// [`NONLINEAR_BAND_FRACTION`]` fs` on a nonlinear one).
    fn write_weights(&mut self, a: f64) {
        let wmax = self.kept_limit();
        let inv_a = 1.0 / a;
        let model = &mut self.models[self.tier];
        let omega = &self.omega;
        let heard = |s: usize, x: f64| if omega[s] < wmax { x * inv_a } else { 0.0 };
        for (s, w) in model.force_weights_mut().iter_mut().enumerate() {
            *w = heard(s, self.strike_w[s]);
        }
        for c in 0..2 {
            for (s, w) in model.pickup_weights_mut(c).iter_mut().enumerate() {
                *w = heard(s, self.pickup_w[c][s]);
            }
        }
    }

    /// Silences the voice (state at rest). No allocation.
    pub fn reset(&mut self) {
        self.models[self.tier].reset();
        self.above.reset();
        self.strike = None;
        self.strike_step = 0;
        self.mallet.drop_mallet();
    }

    /// Advances `left.len()` steps, adding `gain ·` the pickups; `false` on divergence or
    /// output past [`VOICE_CEILING`].
    pub fn run(&mut self, left: &mut [f32], right: &mut [f32], gain: f64) -> bool {
        let model = &mut self.models[self.tier];
        for (l, r) in left.iter_mut().zip(right.iter_mut()) {
            let stepped = if self.mallet.live() {
                self.mallet.step(model)
            } else {
                let f = match self.strike {
                    Some(s) => {
                        let t = self.strike_step as f64 / self.fs;
                        self.strike_step += 1;
                        if t > s.duration {
                            self.strike = None;
                        }
                        s.force(t)
                    }
                    None => 0.0,
                };
                model.step(f)
            };
            if stepped.is_err() {
                return false;
            }
            let o = model.outputs();
            let (a, b) = (gain * o[0], gain * o[1]);
            if !(a.abs() <= VOICE_CEILING && b.abs() <= VOICE_CEILING) {
                return false;
            }
            *l += a as f32;
            *r += b as f32;
        }
        true
    }

    /// What the voice simulates for its note.
    pub fn model_info(&self) -> VoiceModelInfo {
        let (n, m) = self.data.tiers[self.tier];
        let wmax = self.kept_limit();
        let top = self.omega[..n]
            .iter()
            .copied()
            .filter(|&w| w < wmax)
            .fold(0.0, f64::max);
        VoiceModelInfo {
            n_phi: n as u32,
            n_psi: if self.data.linear { 0 } else { m as u32 },
            top_mode_hz: (top / TAU) as f32,
            sim_rate: self.fs as f32,
            above_modes: self.above_modes() as u32,
            above_top_hz: (self.above_top() / TAU) as f32,
        }
    }

    /// Writes the displacement snapshot (m), the lowest mode frequencies (Hz) and `|q_s|`.
    pub fn snapshot(
        &self,
        disp: &mut [f32; SNAPSHOT_POINTS],
        freq: &mut [f32; SPECTRUM_MODES],
        amp: &mut [f32; SPECTRUM_MODES],
    ) {
        let q = self.model().q();
        let (n, stride) = (q.len(), self.data.lambda2.len());
        for (p, d) in disp.iter_mut().enumerate() {
            let row = &self.data.snapshot[p * stride..p * stride + n];
            let w: f64 = row.iter().zip(q).map(|(a, b)| a * b).sum();
            *d = (w / self.size) as f32;
        }
        for s in 0..n.min(SPECTRUM_MODES) {
            freq[s] = (self.omega[s] / TAU) as f32;
            amp[s] = q[s].abs() as f32;
        }
    }
}

mod above;
mod data;
mod hand_pressure;
mod kept;
mod rest_shape;
#[cfg(test)]
mod same_plate_tests;
