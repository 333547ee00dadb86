//! The truncation closure: a damping of the highest simulated modes that takes the energy the
//! nonlinear cascade piles up at the cutoff, as the modes left out would carry it away.
//!
//! # Why this form
//!
//! A struck plate's nonlinearity carries energy from the modes the strike excites to ever
//! higher ones (wave turbulence: Düring, Josserand & Rica, PRL 97, 2006; Ducceschi, Cadot,
//! Touzé & Bilbao, Physica D 280-281, 2014). A Galerkin truncation keeps the transfer among the
//! kept modes but has no modes above the cutoff to take the flux: the energy stays in the top
//! modes, which fill up and become loud (the bottleneck of truncated Euler flows, Cichowlas,
//! Bonaïti, Debbasch & Brachet, PRL 95, 2005). Turbulence models close the truncation with an
//! eddy viscosity on the scales next to the cutoff whose strength rises with the energy there
//! (Kraichnan, J. Atmos. Sci. 33, 1976). Here:
//!
//! - **The pile-up is measured against the spectrum continued from below.** A plate's modal
//!   density is constant in frequency, so without a bottleneck the mean energy per mode of the
//!   top layer `L` (`ω ≥ r₀ ω_max`, [`DEFAULT_LAYER`]) continues that of the band below it
//!   (`r₀² ω_max ≤ ω < r₀ ω_max`). Their ratio `X = ē_L / ē_B` (each averaged over `τ`,
//!   [`DEFAULT_TIME_CONSTANT`]) grows with the pile-up.
//! - **The rate rises with the pile-up** (negative feedback: damping the layer lowers `X` and
//!   with it the rate; the band below is never damped, so the comparison cannot run away).
//!   A weakly struck note, linear, has the falling spectrum of its strike (`X` about 0.02-0.05
//!   on the crash cymbal at velocity 10), so the closure leaves it alone; the cascade of a loud
//!   one fills the top (`X` several times `X₀` at velocity 127):
//!
//! - **It acts only while the plate is nonlinear.** Whether the top layer holds more than its
//!   share depends on what the strike put there too: a hard stick resolved by a finer step, or
//!   a heavy head on a shallow gong, fills the top of a weak, linear note (`X` grew to 9.5 on
//!   the rising opera gong on key 60 at velocity 10, and passed `X₀` on the crash at twice its
//!   rate), and a damping there would change a note that has no cascade. The rate is therefore
//!   gated by the plate's nonlinearity `ε̄`, the share of its energy held by the nonlinear
//!   (cubic and quartic) part of its in-plane energy, averaged over `τ_ε`
//!   ([`NONLINEARITY_TIME_CONSTANT`]; the model's `in_plane_split`): the cascade's transfer
//!   rate scales with that share (the nonlinear time scale of wave turbulence), it is
//!   independent of the strike's spectrum, and a linear note holds none of it. The gate opens
//!   from `ε₀` ([`NONLINEARITY_THRESHOLD`]) and is full at `2ε₀`, `g = (ε̄/ε₀ - 1)` clamped to
//!   `[0, 1]` (measured on key 60, docs/ACCURACY.md: `ε̄` 0.7-1.4 on the crash and 1.4-2.8 on
//!   the ride at velocity 127, at most 0.025 and 0.075 at velocity 10). The gate applies to
//!   curved plates only ([`TruncationClosure::set_gated`]): there the curvature's linear
//!   stiffness makes the nonlinear share of a loud note large (its cubic part), and there the
//!   pile-up measure failed; a flat plate's loud notes hold a share of 0.02-0.07, of the order
//!   of a shell's weak notes, so one threshold cannot serve both (the flat gongs' cascade
//!   stops inside their band at the nonlinear plates' rate, so they need no closure; the
//!   80 N gong's `X` of 7-2800 measured at 13.4 kHz was the time step's aliasing,
//!   docs/ACCURACY.md):
//!
//! ```text
//! γ = β ω_max (X / X₀ - 1)⁺ g(ε̄),   mode s damped at w_s γ
//! (w_s: 0 at r₀ ω_max, ramping to 1 at the top)
//! ```
//!
//! capped at [`MAX_RATE_RATIO`]` ω_max`. `X₀` ([`PILE_UP_THRESHOLD`]) and `β`
//! ([`DEFAULT_STRENGTH`]) are calibrated against the crash cymbal's resolved reference (its band
//! doubled; docs/ACCURACY.md): `X₀ = 1` (the continued spectrum itself) leaves most of the
//! pile-up, because the resolved plate's energy per mode falls across the top half-octave (its
//! damping grows with frequency and the cascade's front is still moving up).
//! `X` compares physical energies: the exact scheme's discrete energy of a mode is its
//! physical energy times `ω̃²/ω²`, undone mode by mode.
//!
//! # Energy
//!
//! `γ` is fixed before a step (from the steps before it), so the step is the scheme's with the
//! damping `c̃_s + w_s γ`: centred, hence dissipative for any `γ ≥ 0` and stable as the scheme
//! is. Its energy `h ρh Σ_s w_s γ (δ_{t.} q_s)²` is counted as dissipated
//! ([`super::PlateEnergy::closure`]), and the power balance closes to round-off.
//!
//! Lifecycle: [`TruncationClosure::new`] allocates (worker thread); [`TruncationClosure::retune`]
//! (after the frequencies change), [`TruncationClosure::observe`] (after every step) and
//! [`TruncationClosure::reset`] run on the audio thread without allocation.

/// The default lower edge `r₀` of the closure's layer, as a fraction of the top mode's angular
/// frequency: the top half-octave (`2^{-1/2} ≈ 0.71`), rounded.
pub const DEFAULT_LAYER: f64 = 0.7;

/// The default averaging time `τ` of the layers' energies (s): long against the periods near
/// the cutoff (0.1-0.3 ms) and the beats of near-resonant top modes, short against a cascade's
/// growth (tens of ms).
pub const DEFAULT_TIME_CONSTANT: f64 = 3e-3;

/// The cap of the closure's rate as a fraction of the top mode's angular frequency (the top mode
/// keeps a quality factor of at least `1/(2·0.25) = 2`).
pub const MAX_RATE_RATIO: f64 = 0.25;

/// The pile-up ratio `X₀` above which the layer is damped (see the module doc): calibrated
/// on the crash at its present rate (SAV, 31.2 kHz) against its model resolved to 14 kHz at
/// 62.4 kHz (docs/ACCURACY.md, the crash's closure at its rate). It was 0.1, calibrated at
/// 15.6 kHz, where the time step's aliasing added to the top's pile-up; at 31.2 kHz 0.1
/// over-damps the top third-octave by 2-5 dB, 0.2 leaves it within 3.1 dB and the band above
/// within 2.9 dB.
pub const PILE_UP_THRESHOLD: f64 = 0.2;

/// The nonlinearity `ε₀` above which the closure's gate opens (see the module doc): the share
/// of the plate's energy held by the nonlinear part of its in-plane energy. Set between the
/// weak and the loud notes measured on the cymbals (0.075 at most at velocity 10, 0.7 at least
/// at velocity 127, docs/ACCURACY.md), 2.7 and 1.8 times from either.
pub const NONLINEARITY_THRESHOLD: f64 = 0.2;

/// The averaging time `τ_ε` of the gate's nonlinearity (s): the in-plane energy of a mode
/// swings at twice its frequency, so the average spans the periods of the lowest modes
/// (20-30 ms on the cymbals), short against a note's decay.
pub const NONLINEARITY_TIME_CONSTANT: f64 = 0.05;

/// The gate samples the nonlinearity once in this many steps (its average spans
/// [`NONLINEARITY_TIME_CONSTANT`], hundreds of steps; the in-plane split costs `O(N_Φ N_Ψ)` on a
/// curved plate, as much as a tenth of the step).
pub const GATE_STRIDE: u32 = 8;

/// A mode whose damping exceeds this multiple of its angular frequency (five times critical)
/// is not an oscillator the cascade fills: [`TruncationClosure::retune`] leaves it out.
pub const OVERDAMPED_RATIO: f64 = 10.0;

/// The calibrated closure strength `β` (see the module doc): a pile-up twice the threshold
/// damps the top mode at a tenth of its angular frequency.
pub const DEFAULT_STRENGTH: f64 = 0.1;

/// The largest strength a scene or preset may set, as a multiple of [`DEFAULT_STRENGTH`] (the
/// unit of [`super::PlateModel::set_closure`], the scene's `plate.closure` and the engine's
/// `closure` parameter).
pub const MAX_STRENGTH: f64 = 40.0;

/// The truncation closure's state and scratch (see the module doc). Owned by the plate model
/// (audio thread).
#[derive(Debug, Clone)]
pub struct TruncationClosure {
    /// `β` (0: off).
    strength: f64,
    /// `r₀`: the layer's lower edge as a fraction of `ω_max`.
    layer: f64,
    /// `τ` (s), and the per-step averaging weight `1 - e^{-h/τ}`.
    time_constant: f64,
    smoothing: f64,
    /// The averaging weight of `ε̄` per sample, `1 - e^{-S h/τ_ε}` (one sample every
    /// [`GATE_STRIDE`] `= S` steps; [`NONLINEARITY_TIME_CONSTANT`]).
    gate_smoothing: f64,
    /// Steps until the next sample of the nonlinearity (0: this step's is taken).
    gate_countdown: u32,
    /// Whether the gate applies (a curved plate; a flat plate's closure is ungated).
    gated: bool,
    /// `w_s ∈ [0, 1]`, zero below the layer (length `N_Φ`).
    weights: Vec<f64>,
    /// Per mode: 1 in the layer, -1 in the band below it, 0 elsewhere.
    band: Vec<i8>,
    /// `ω_s² / ω̃_s²`: the exact scheme's discrete energy of a mode is its physical energy
    /// times `ω̃_s²/ω_s²` (the warped frequency), undone before the bands are compared.
    unwarp: Vec<f64>,
    /// Mode counts of the layer and the band below.
    n_layer: usize,
    n_below: usize,
    /// `ω_max` (rad/s).
    top: f64,
    /// `ē_L`, `ē_B`: averaged mean energies per mode of the layer and the band below (J).
    layer_energy: f64,
    below_energy: f64,
    /// `ε̄`: the averaged share of the plate's energy held by the nonlinear part of its
    /// in-plane energy (dimensionless; the gate, see the module doc).
    nonlinearity: f64,
    /// `γ` (1/s) of the coming step; the mode `s` gets `w_s γ`.
    rate: f64,
}

impl TruncationClosure {
    /// An inactive closure for `n_phi` modes (strength 0, default layer and time constant).
    /// Worker thread: allocates.
    pub fn new(n_phi: usize) -> Self {
        Self {
            strength: 0.0,
            layer: DEFAULT_LAYER,
            time_constant: DEFAULT_TIME_CONSTANT,
            smoothing: 0.0,
            gate_smoothing: 0.0,
            gate_countdown: 0,
            gated: false,
            weights: vec![0.0; n_phi],
            band: vec![0; n_phi],
            unwarp: vec![1.0; n_phi],
            n_layer: 0,
            n_below: 0,
            top: 0.0,
            layer_energy: 0.0,
            below_energy: 0.0,
            nonlinearity: 0.0,
            rate: 0.0,
        }
    }

    /// Whether the closure acts (`β > 0`).
    pub fn is_on(&self) -> bool {
        self.strength > 0.0
    }

    /// `γ` (1/s) the top mode gets in the coming step.
    pub fn rate(&self) -> f64 {
        self.rate
    }

    /// `X = ē_L / ē_B`, the layer's averaged energy per mode over the band below's (0 before
    /// any energy).
    pub fn pile_up(&self) -> f64 {
        if self.below_energy > 0.0 {
            self.layer_energy / self.below_energy
        } else {
            0.0
        }
    }

    /// `ε̄`, the averaged share of the plate's energy held by the nonlinear part of its in-plane
    /// energy (0 before any energy; the gate opens from [`NONLINEARITY_THRESHOLD`]).
    pub fn nonlinearity(&self) -> f64 {
        self.nonlinearity
    }

    /// The gate `g ∈ [0, 1]` of the coming step: `(ε̄/ε₀ - 1)` clamped on a curved plate, 1 on
    /// a flat one (module doc).
    pub fn gate(&self) -> f64 {
        if self.gated {
            (self.nonlinearity / NONLINEARITY_THRESHOLD - 1.0).clamp(0.0, 1.0)
        } else {
            1.0
        }
    }

    /// Applies the gate (`true`: a curved plate) or not (a flat plate); the averages are kept.
    /// Any thread that owns the closure; no allocation.
    pub fn set_gated(&mut self, gated: bool) {
        self.gated = gated;
    }

    /// Sets `β` (0 to [`MAX_STRENGTH`] times [`DEFAULT_STRENGTH`]), `r₀` (0 to 1, exclusive)
    /// and `τ` (s, > 0); the caller validated them. The averages and the rate are forgotten;
    /// the layer follows at the next [`Self::retune`]. Any thread that owns the closure; no
    /// allocation.
    pub fn configure(&mut self, strength: f64, layer: f64, time_constant: f64) {
        self.strength = strength;
        self.layer = layer;
        self.time_constant = time_constant;
        self.reset();
    }

    /// Recomputes the layer, the band below and the weights from the modes' physical angular
    /// frequencies `omega` (rad/s; not the exact scheme's warped `ω̃`, which crowds the top
    /// modes together below `2/h`), their `ω̃²` (`omega_sq`), their physical damping `damping`
    /// (1/s) and the step `h` (s), after the coefficients changed; the averages and the rate
    /// are kept (a pitch bend does not restart the cascade). A mode damped past
    /// [`OVERDAMPED_RATIO`]` ω` does not oscillate (a note's modes above its kept band,
    /// `engine/voice/plate/kept.rs`): it belongs to neither layer and does not set the top.
    /// Audio thread: no allocation, `O(N_Φ)`.
    pub fn retune(&mut self, omega: &[f64], omega_sq: &[f64], damping: &[f64], h: f64) {
        let live = |s: usize| damping[s] <= OVERDAMPED_RATIO * omega[s];
        let top = (0..omega.len())
            .filter(|&s| live(s))
            .fold(0.0f64, |m, s| m.max(omega[s]));
        let lower = self.layer * top;
        let floor = self.layer * lower;
        (self.n_layer, self.n_below) = (0, 0);
        for s in 0..self.weights.len() {
            let warp = omega_sq[s] / (omega[s] * omega[s]);
            self.unwarp[s] = if warp.is_finite() && warp > 0.0 {
                1.0 / warp
            } else {
                1.0
            };
            if !live(s) {
                (self.weights[s], self.band[s]) = (0.0, 0);
                continue;
            }
            let omega = omega[s].max(0.0);
            let x = (omega - lower) / (top - lower);
            self.weights[s] = if x.is_finite() {
                x.clamp(0.0, 1.0)
            } else {
                0.0
            };
            self.band[s] = if omega >= lower {
                self.n_layer += 1;
                1
            } else if omega >= floor {
                self.n_below += 1;
                -1
            } else {
                0
            };
        }
        self.top = top;
        self.smoothing = 1.0 - (-h / self.time_constant).exp();
        self.gate_smoothing = 1.0 - (-(GATE_STRIDE as f64) * h / NONLINEARITY_TIME_CONSTANT).exp();
        self.rate = self.rate.min(MAX_RATE_RATIO * top);
    }

    /// Forgets the averages and the rate (the plate was put at rest or restarted). No
    /// allocation.
    pub fn reset(&mut self) {
        self.layer_energy = 0.0;
        self.below_energy = 0.0;
        self.nonlinearity = 0.0;
        self.gate_countdown = 0;
        self.rate = 0.0;
    }

    /// Writes the linear coefficients of the coming step for the layer's modes: the damping
    /// `c̃_s + w_s γ` in `a_s = 1 + c h/2`, `1/a_s`, `d_s = 1 - c h/2` (the other modes are left
    /// as they are). Audio thread: no allocation.
    pub fn write_coefficients(
        &self,
        c_eff: &[f64],
        h: f64,
        a: &mut [f64],
        inv_a: &mut [f64],
        d: &mut [f64],
    ) {
        for (s, &w) in self.weights.iter().enumerate() {
            if w > 0.0 {
                let c = c_eff[s] + w * self.rate;
                a[s] = 1.0 + 0.5 * c * h;
                inv_a[s] = 1.0 / a[s];
                d[s] = 1.0 - 0.5 * c * h;
            }
        }
    }

    /// Whether the coming [`Self::observe`] samples the nonlinearity (one step in
    /// [`GATE_STRIDE`]): only then does the caller compute the in-plane split it takes.
    pub fn samples_gate(&self) -> bool {
        self.gated && self.gate_countdown == 0
    }

    /// After a step: returns the energy the closure removed in it (J, `≥ 0`), then updates the
    /// averages and the rate of the next step. `q_next`, `q`, `q_prev` are `q(n+1)`, `q(n)`,
    /// `q(n-1)`; `omega_sq` the linear part's `ω̃_s²` (the per-mode discrete energy is
    /// `(ρh/2)[(δ_{t+}q_s)² + ω̃_s² q_s(n+1) q_s(n)]`); `in_plane` the step's in-plane energy,
    /// its nonlinear part and the whole `(U_nl, U)` (J, the model's `in_plane_split`), given
    /// when [`Self::samples_gate`] asked for it (ignored otherwise).
    /// Audio thread: no allocation, `O(N_Φ)`.
    pub fn observe(
        &mut self,
        (q_next, q, q_prev): (&[f64], &[f64], &[f64]),
        omega_sq: &[f64],
        in_plane: Option<(f64, f64)>,
        rho_h: f64,
        h: f64,
    ) -> f64 {
        let sample = self.samples_gate().then_some(in_plane).flatten();
        self.gate_countdown = match self.gate_countdown {
            0 => GATE_STRIDE - 1,
            n => n - 1,
        };
        let (inv_h, inv_2h) = (1.0 / h, 0.5 / h);
        let (mut absorbed, mut e_layer, mut e_below, mut e_all) = (0.0, 0.0, 0.0, 0.0);
        for s in 0..self.weights.len() {
            let band = self.band[s];
            if band == 0 && sample.is_none() {
                continue;
            }
            let v = (q_next[s] - q[s]) * inv_h;
            let e = 0.5 * rho_h * (v * v + omega_sq[s] * q_next[s] * q[s]) * self.unwarp[s];
            e_all += e;
            match band {
                0 => {}
                b if b > 0 => {
                    let vc = (q_next[s] - q_prev[s]) * inv_2h;
                    absorbed += h * rho_h * self.weights[s] * self.rate * vc * vc;
                    e_layer += e;
                }
                _ => e_below += e,
            }
        }
        let k = self.smoothing;
        self.layer_energy += k * (e_layer / self.n_layer.max(1) as f64 - self.layer_energy);
        self.below_energy += k * (e_below / self.n_below.max(1) as f64 - self.below_energy);
        if let Some((u_nonlinear, u_total)) = sample {
            let energy = e_all + u_total;
            let share = if energy > 0.0 {
                u_nonlinear / energy
            } else {
                0.0
            };
            self.nonlinearity += self.gate_smoothing * (share - self.nonlinearity);
        }
        let excess = (self.pile_up() / PILE_UP_THRESHOLD - 1.0).max(0.0);
        let rate = self.strength * self.top * excess * self.gate();
        self.rate = if rate.is_finite() {
            rate.min(MAX_RATE_RATIO * self.top)
        } else {
            0.0
        };
        absorbed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The layer: zero below `r₀ ω_max`, a ramp to 1 at the top mode, whatever the order of
    /// the modes; the band below is the next `r₀` factor down.
    #[test]
    fn weights_ramp_over_the_top_layer() {
        let mut c = TruncationClosure::new(5);
        c.configure(1.0, 0.5, 1e-3);
        let omega = [100.0f64, 400.0, 50.0, 300.0, 150.0];
        c.retune(&omega, &omega.map(|w| w * w), &[0.0; 5], 1e-5);
        // (ω - 200) / 200, clamped.
        let expect = [0.0, 1.0, 0.0, 0.5, 0.0];
        for (w, e) in c.weights.iter().zip(expect) {
            assert!((w - e).abs() < 1e-15, "{w} vs {e}");
        }
        assert_eq!(c.band, [-1, 1, 0, 1, -1]);
        assert_eq!((c.n_layer, c.n_below), (2, 2));
    }

    /// An overdamped mode (a note's mode above its kept band) is left out: the top is the
    /// highest live mode (300), the layer ramps from 150, and the overdamped mode 400 is in
    /// neither layer. At exactly `OVERDAMPED_RATIO ω` a mode is still live.
    #[test]
    fn overdamped_modes_are_left_out() {
        let mut c = TruncationClosure::new(5);
        c.configure(1.0, 0.5, 1e-3);
        let omega = [100.0f64, 400.0, 50.0, 300.0, 150.0];
        let damping = [0.0, 4001.0, 0.0, 3000.0, 0.0];
        c.retune(&omega, &omega.map(|w| w * w), &damping, 1e-5);
        // (ω - 150) / 150, clamped.
        let expect = [0.0, 0.0, 0.0, 1.0, 0.0];
        for (w, e) in c.weights.iter().zip(expect) {
            assert!((w - e).abs() < 1e-15, "{w} vs {e}");
        }
        assert_eq!(c.band, [-1, 0, 0, 1, 1]);
        assert_eq!((c.n_layer, c.n_below), (2, 1));
    }

    /// The rate is `β ω_max (X/X₀ - 1)⁺ g`: none while the layer holds little energy per mode
    /// against the band below (a linear note's falling spectrum), rising with the pile-up; and
    /// none, whatever the pile-up, while the plate holds no nonlinear in-plane energy.
    #[test]
    fn the_rate_follows_the_pile_up_while_the_plate_is_nonlinear() {
        let h = 1.0 / 48_000.0;
        let mut c = TruncationClosure::new(2);
        c.configure(0.01, 0.5, 1e-9);
        let omega = [900.0f64, 2000.0];
        let w2: Vec<f64> = omega.iter().map(|w| w * w).collect();
        c.retune(&omega, &w2, &vec![0.0; omega.len()], h);
        // Still modes (e = ½ω²q²): X = ½·2000²·q₁² / ½·900²·q₀².
        let x = |q: [f64; 2]| (2000.0 * q[1] / (900.0 * q[0])).powi(2);
        let piled = [1.0, 0.3];
        // A curved plate that is linear (no nonlinear in-plane energy): piled up, yet no rate.
        c.set_gated(true);
        c.observe((&piled, &piled, &piled), &w2, Some((0.0, 0.0)), 1.0, h);
        assert!(
            (c.pile_up() / x(piled) - 1.0).abs() < 1e-12,
            "X = {}",
            c.pile_up()
        );
        assert!(x(piled) > PILE_UP_THRESHOLD);
        assert_eq!((c.nonlinearity(), c.gate(), c.rate()), (0.0, 0.0, 0.0));
        // A strongly nonlinear one: after one sample (weight 1 - e^{-S h/τ_ε}) the average is
        // `k · share` with the share `U_nl / (Σ e_s + U)`, past 2ε₀: the gate is open.
        // The next sample is GATE_STRIDE steps on; the steps between take no in-plane split.
        for _ in 1..GATE_STRIDE {
            assert!(!c.samples_gate());
            c.observe((&piled, &piled, &piled), &w2, None, 1.0, h);
        }
        assert!(c.samples_gate());
        let energy = 0.5 * (w2[0] * 1.0 + w2[1] * 0.09);
        let u_nl = 1e4 * energy;
        c.observe((&piled, &piled, &piled), &w2, Some((u_nl, 0.0)), 1.0, h);
        let k = 1.0 - (-(GATE_STRIDE as f64) * h / NONLINEARITY_TIME_CONSTANT).exp();
        assert!(
            (c.nonlinearity() / (k * u_nl / energy) - 1.0).abs() < 1e-12,
            "ε̄ = {}",
            c.nonlinearity()
        );
        assert_eq!(c.gate(), 1.0);
        let want = 0.01 * 2000.0 * (x(piled) / PILE_UP_THRESHOLD - 1.0);
        assert!(
            (c.rate() / want - 1.0).abs() < 1e-12,
            "{} vs {want}",
            c.rate()
        );
        // A falling spectrum (X < X₀): no rate.
        let falling = [1.0, 0.1];
        c.observe(
            (&falling, &falling, &falling),
            &w2,
            Some((u_nl, 0.0)),
            1.0,
            h,
        );
        assert!(x(falling) < PILE_UP_THRESHOLD);
        assert_eq!(c.rate(), 0.0);
        // Capped at a quarter of the top angular frequency.
        c.configure(MAX_STRENGTH * DEFAULT_STRENGTH, 0.5, 1e-9);
        c.retune(&omega, &w2, &vec![0.0; omega.len()], h);
        c.observe((&piled, &piled, &piled), &w2, Some((u_nl, 0.0)), 1.0, h);
        c.observe((&piled, &piled, &piled), &w2, Some((u_nl, 0.0)), 1.0, h);
        assert_eq!(c.rate(), MAX_RATE_RATIO * 2000.0);
    }
}
