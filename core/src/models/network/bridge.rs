//! The bridge body: a few damped modes that every seated string pushes on.
//!
//! Mode `k` (modal mass `M_k`, frequency `ω_k`, damping `σ_k`) obeys
//! `M_k(ÿ_k + 2σ_k ẏ_k + ω_k² y_k) = G_k`, `G_k = -Σ_s Φ_{k,s} F_s` (the reactions of the
//! strings' forces `F_s`, [`super`]). It is stepped by the same exact two-step scheme as a
//! string mode ([`crate::models::string::exact`], SEED.md 1.2 and 3.2):
//! `Δ^{n+1} = c̃ Δ^n - β y^n + (h²/M_k) G_k^n`, `y^{n+1} = y^n + Δ^{n+1}`, with the energy
//! `E = Σ_k M_k[(1 + c̃ + c)/8 (Δ^{n+1}/h)² + β/(8h²) (y^{n+1} + y^n)²]` and the dissipation
//! `M_k s_k/(2h) (Δ^{n+1} + Δ^n)²` per step (the weights of the string's exact scheme with `μ`
//! replaced by `M_k`), so that `δ_{t-}E = -Σ 2M_k s_k (δ_t. y_k)² + Σ G_k δ_t. y_k` exactly.
//!
//! Built on the control thread; stepped by the thread that steps the network (audio or
//! render), without allocation.

use crate::error::{check_positive, ParamError};
use crate::models::string::exact::ModeCoefficients;

/// Largest number of bridge modes: the network's Newton step solves a dense system of this
/// size on the stack.
pub const MAX_BRIDGE_MODES: usize = 6;

/// One mode of the bridge.
///
/// Read on the control thread.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BridgeMode {
    /// Frequency in Hz (> 0).
    pub frequency: f64,
    /// Modal mass in kg (> 0): the mass a unit force at a point where the mode shape is 1
    /// accelerates in this mode.
    pub mass: f64,
    /// Time for the free mode to decay by 60 dB, in s (> 0; `f64::INFINITY` for a lossless
    /// mode).
    pub t60: f64,
}

impl BridgeMode {
    /// Damping `σ = 3 ln 10 / T60` in s⁻¹ (0 for an infinite T60).
    pub fn sigma(&self) -> f64 {
        3.0 * std::f64::consts::LN_10 / self.t60
    }

    /// Checks every field; `index` names the mode in the error.
    pub fn validate(&self, index: usize) -> Result<(), ParamError> {
        check_positive(&format!("bridge.modes[{index}].frequency"), self.frequency)?;
        check_positive(&format!("bridge.modes[{index}].mass"), self.mass)?;
        let t60 = format!("bridge.modes[{index}].t60");
        if self.t60.is_nan() || self.t60 <= 0.0 {
            return Err(ParamError::new(&t60, self.t60, "> 0 s (inf for no loss)"));
        }
        Ok(())
    }
}

/// The bridge's modal state and its scheme's coefficients (struct of arrays, one entry per
/// mode).
///
/// Owned by the network; stepped by the thread that steps it.
#[derive(Debug, Clone)]
pub struct BridgeBody {
    /// `h²/M_k` in s²/kg: the increment a unit modal force makes in one step.
    pub(super) force_factor: Vec<f64>,
    /// `c̃_k`.
    c_tilde: Vec<f64>,
    /// `β_k`.
    beta: Vec<f64>,
    /// Energy weight of `(Δ^{n+1})²`, `M(1 + c̃ + c)/(8h²)` in kg/s².
    w_kin: Vec<f64>,
    /// Energy weight of `(y^{n+1} + y^n)²`, `Mβ/(8h²)` in kg/s².
    w_pot: Vec<f64>,
    /// Dissipation weight of `(Δ^{n+1} + Δ^n)²`, `M s/(2h)` in kg/s².
    w_diss: Vec<f64>,
    /// `y^{n+1}` in m.
    pub(super) y: Vec<f64>,
    /// `Δ^{n+1} = y^{n+1} - y^n` in m.
    pub(super) dy: Vec<f64>,
    /// The free increment of the step under way (m).
    pub(super) dy_free: Vec<f64>,
    /// Energy dissipated since the start (J).
    pub(super) dissipated: f64,
}

impl BridgeBody {
    /// Validates `modes` (1 to [`MAX_BRIDGE_MODES`]) and computes the coefficients at step
    /// `h` (s). Control thread.
    pub fn new(modes: &[BridgeMode], h: f64) -> Result<Self, ParamError> {
        if modes.is_empty() || modes.len() > MAX_BRIDGE_MODES {
            return Err(ParamError::new(
                "bridge.modes",
                modes.len() as f64,
                format!("1 to {MAX_BRIDGE_MODES} modes"),
            ));
        }
        for (k, m) in modes.iter().enumerate() {
            m.validate(k)?;
        }
        let coeffs: Vec<ModeCoefficients> = modes
            .iter()
            .map(|m| ModeCoefficients::new(std::f64::consts::TAU * m.frequency, m.sigma(), h))
            .collect();
        let h2 = h * h;
        let per = |f: &dyn Fn(&BridgeMode, &ModeCoefficients) -> f64| -> Vec<f64> {
            modes.iter().zip(&coeffs).map(|(m, c)| f(m, c)).collect()
        };
        let n = modes.len();
        Ok(Self {
            force_factor: per(&|m, _| h2 / m.mass),
            c_tilde: per(&|_, c| c.c_tilde),
            beta: per(&|_, c| c.beta),
            w_kin: per(&|m, c| m.mass * (2.0 + 2.0 * c.c_tilde - c.beta) / (8.0 * h2)),
            w_pot: per(&|m, c| m.mass * c.beta / (8.0 * h2)),
            w_diss: per(&|m, c| m.mass * c.s / (2.0 * h)),
            y: vec![0.0; n],
            dy: vec![0.0; n],
            dy_free: vec![0.0; n],
            dissipated: 0.0,
        })
    }

    /// Number of modes.
    pub fn modes(&self) -> usize {
        self.y.len()
    }

    /// At rest, the dissipation account cleared.
    pub fn reset(&mut self) {
        self.y.fill(0.0);
        self.dy.fill(0.0);
        self.dy_free.fill(0.0);
        self.dissipated = 0.0;
    }

    /// The free increment `Δ_free = c̃Δ - βy` of the step under way, into `dy_free`; mode
    /// `k`'s free position is `y_k + Δ_free,k`.
    pub(super) fn free(&mut self) {
        for k in 0..self.y.len() {
            self.dy_free[k] = self.c_tilde[k] * self.dy[k] - self.beta[k] * self.y[k];
        }
    }

    /// Ends the step with the modal forces `g` (N): `Δ^{n+1} = Δ_free + (h²/M) g`, the
    /// dissipation, the rotation.
    pub(super) fn finish(&mut self, g: &[f64]) {
        let modes = self
            .y
            .iter_mut()
            .zip(self.dy.iter_mut())
            .zip(self.dy_free.iter().zip(&self.force_factor))
            .zip(g.iter().zip(&self.w_diss));
        for (((y, dy), (free, ff)), (g, wd)) in modes {
            let next = free + ff * g;
            let v = next + *dy;
            self.dissipated += wd * v * v;
            *y += next;
            *dy = next;
        }
    }

    /// `(kinetic, potential)` energy at the current state (J).
    pub fn energy(&self) -> (f64, f64) {
        let (mut kin, mut pot) = (0.0, 0.0);
        for k in 0..self.y.len() {
            let d = self.dy[k];
            let s = 2.0 * self.y[k] - d;
            kin += self.w_kin[k] * d * d;
            pot += self.w_pot[k] * s * s;
        }
        (kin, pot)
    }

    /// Energy dissipated since the start (J).
    pub fn dissipated(&self) -> f64 {
        self.dissipated
    }

    /// Mode displacements `y^{n+1}` (m).
    pub fn displacement(&self) -> &[f64] {
        &self.y
    }

    /// Mode increments `Δ^{n+1}` (m); divided by `h`, the velocities at `n + 1/2`.
    pub fn increment(&self) -> &[f64] {
        &self.dy
    }
}
