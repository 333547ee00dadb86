//! Duffing oscillator `ü + ω0² u + γ u³ = 0`, `H = ½u̇² + ½ω0²u² + ¼γu⁴` (SEED.md section 1.3).
//!
//! - [`DuffingVerlet`]: Störmer-Verlet `δ_{tt}u + ω0² u_n + γ u_n³ = 0`. Symplectic, so its
//!   energy error is bounded and oscillates at `O(h²)` without secular drift (E. Hairer,
//!   C. Lubich, G. Wanner, *Geometric Numerical Integration*, Springer 2006, chapter IX), but no
//!   discrete energy is exactly conserved.
//! - [`DuffingConservative`]: the (θ1, θ2) family
//!   `δ_{tt}u + ω0²(θ1 + (1-θ1)μ_{t.})u + γ(θ2 u² + (1-θ2) μ_{t.}(u²)) μ_{t.}u = 0`, which
//!   conserves exactly (S. Bilbao, *Numerical Sound Synthesis*, Wiley 2009, chapter 4)
//!   `h_n = ½(δ_{t-}u)² + ω0²(θ1 ½ u e_{t-}u + (1-θ1) ½ μ_{t-}u²) +
//!   (γ/4)(θ2 u²(e_{t-}u)² + (1-θ2) μ_{t-}(u⁴))`.
//!
//! Both store `(u_n, d_n)`, `d_n = u_n - u_{n-1}`, and compute the second difference
//! `q = u_{n+1} - 2u_n + u_{n-1}`, then `d_{n+1} = d_n + q`, `u_{n+1} = u_n + d_{n+1}`: the
//! unknown is small (`O(h²)`), so solving for it to relative machine precision pins `u_{n+1}`
//! far below one ulp, and step rounding perturbs the energy by `O(ε)` relatively.
//!
//! For `θ2 < 1` the update is a cubic in `q` (SEED.md 1.3 writes it in `u_{n+1}`):
//! `G(q) = c1 q + h²ω0² u_n + γh² N(q) (u_n + q/2) = 0`, `c1 = 1 + (1-θ1)h²ω0²/2`,
//! `N(q) = θ2 u_n² + (1-θ2)((u_{n+1})² + (u_{n-1})²)/2`, `u_{n+1} = u_n + d_n + q`. In
//! `s = u_{n+1} + u_{n-1}` the nonlinear term is `(γh²/4)[2θ2u_n² s + (1-θ2) s(s² - 2su_{n-1} +
//! 2u_{n-1}²)]` whose derivative `3s² - 4su_{n-1} + 2u_{n-1}²` has negative discriminant, so
//! `G' ≥ c1 ≥ 1`: one real root, lying within `|G(q̂)|` of any guess `q̂`. It is found by
//! `solve_increasing` (Newton with a bisection safeguard) from the θ2 = 1 value.
//!
//! Starting values (both schemes): `u_{-1} = u_1 - 2h v0` so that `δ_{t.}u_0 = v0`, with the
//! explicit (θ2 = 1, or Verlet) second difference `q̂(u0)`: `d_0 = h v0 - q̂(u0)/2`. This is the
//! exact symmetric start of the explicit schemes (and of the θ-scheme when `γ = 0`) and a
//! second-order accurate one for `θ2 < 1`.

use super::linear::check_stable_step;
use super::{OscillatorStepper, StepperStats};
use crate::error::{check_closed, check_non_negative, check_positive, ParamError};

/// Iteration cap of [`solve_increasing`] (per step).
pub(crate) const MAX_ITERATIONS: u32 = 100;

/// Outcome of [`solve_increasing`].
pub(crate) struct Root {
    /// The root estimate.
    pub x: f64,
    /// Function evaluations used.
    pub iterations: u32,
    /// False when the cap was hit (then `x` is the last bracketed iterate).
    pub converged: bool,
}

/// Safeguarded Newton for a non-decreasing function with a known bracket.
///
/// `f(x)` returns `(G(x), G'(x))`; `G(lo) ≤ 0 ≤ G(hi)` is expected. Each evaluation shrinks the
/// bracket; a Newton step leaving it is replaced by bisection. Stops when a step is below
/// `tol(x)` (the step is then taken), when the bracket is narrower than `tol(x)`, or when
/// `G(x) = 0`; otherwise after [`MAX_ITERATIONS`] evaluations, returning the last iterate with
/// `converged = false`. Bounded work, no allocation, never panics (NaN input gives a NaN root
/// with `converged = false`). Shared by the Duffing and impact schemes.
pub(crate) fn solve_increasing(
    mut f: impl FnMut(f64) -> (f64, f64),
    x0: f64,
    mut lo: f64,
    mut hi: f64,
    tol: impl Fn(f64) -> f64,
) -> Root {
    let mut x = x0;
    if x < lo || x.is_nan() {
        x = lo;
    }
    if x > hi {
        x = hi;
    }
    for it in 1..=MAX_ITERATIONS {
        let (g, dg) = f(x);
        if g > 0.0 {
            hi = x;
        } else if g < 0.0 {
            lo = x;
        } else if g == 0.0 {
            return Root {
                x,
                iterations: it,
                converged: true,
            };
        } else {
            break;
        }
        let newton = x - g / dg;
        let next = if newton >= lo && newton <= hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if (next - x).abs() <= tol(next) || hi - lo <= tol(x) {
            return Root {
                x: next,
                iterations: it,
                converged: true,
            };
        }
        x = next;
    }
    Root {
        x,
        iterations: MAX_ITERATIONS,
        converged: false,
    }
}

/// Adds one step's solver outcome to `stats`.
pub(crate) fn record(stats: &mut StepperStats, root: &Root) {
    stats.solver_iterations += u64::from(root.iterations);
    stats.max_iterations_per_step = stats.max_iterations_per_step.max(root.iterations);
    if !root.converged {
        stats.solver_failures += 1;
    }
}

/// Störmer-Verlet for Duffing; explicit, not energy conserving.
///
/// Built once, then owned and stepped by one thread; no allocation.
#[derive(Debug, Clone)]
pub struct DuffingVerlet {
    /// Linear angular frequency ω0, rad per time unit.
    omega0: f64,
    /// Cubic coefficient γ ≥ 0, per (displacement² · time²).
    gamma: f64,
    /// Time step `h`, time units.
    h: f64,
    /// Displacement `u_n`.
    u: f64,
    /// Increment `d_n = u_n - u_{n-1}`.
    d: f64,
    /// Steps since the last reset.
    n: u64,
}

impl DuffingVerlet {
    /// Builds the scheme; `omega0 > 0`, `gamma ≥ 0`, `h > 0`, all finite.
    pub fn new(omega0: f64, gamma: f64, h: f64) -> Result<Self, ParamError> {
        check_positive("omega0", omega0)?;
        check_non_negative("gamma", gamma)?;
        check_positive("h", h)?;
        // Linearised about rest the scheme is the θ = 1 one: stable only for h ω0 < 2. The
        // cubic term lowers the limit with the amplitude (see [`Self::check_amplitude`]).
        check_stable_step(h, omega0, 1.0, "theta (Störmer-Verlet is θ = 1)")?;
        Ok(Self {
            omega0,
            gamma,
            h,
            u: 0.0,
            d: 0.0,
            n: 0,
        })
    }

    /// Refuses initial conditions whose motion is too large for this step: Störmer-Verlet
    /// linearised about the turning point `u = A` (the amplitude of the free motion with
    /// energy `H0 = ½v0² + ½ω0²u0² + ¼γu0⁴`) is the θ = 1 scheme with the local stiffness
    /// `ω0² + 3γA²`, which is stable only for `h²(ω0² + 3γA²) < 4` (SEED.md 1.1, 1.3). Beyond
    /// it the iteration explodes within a few periods, so a caller that knows the initial
    /// conditions (the lab) checks them here. Errors name `u0` (or `v0` when `u0 = 0`).
    pub fn check_amplitude(&self, u0: f64, v0: f64) -> Result<(), ParamError> {
        let w2 = self.omega0 * self.omega0;
        let h0 = 0.5 * v0 * v0 + 0.5 * w2 * u0 * u0 + 0.25 * self.gamma * u0.powi(4);
        let a2 = if self.gamma > 0.0 {
            4.0 * h0 / (w2 + (w2 * w2 + 4.0 * self.gamma * h0).sqrt())
        } else {
            2.0 * h0 / w2
        };
        let local = self.h * self.h * (w2 + 3.0 * self.gamma * a2);
        if local.is_finite() && local < 4.0 {
            return Ok(());
        }
        let (field, value) = if u0 != 0.0 { ("u0", u0) } else { ("v0", v0) };
        Err(ParamError::new(
            field,
            value,
            format!(
                "initial conditions with amplitude A = {} below {} (Störmer-Verlet stability \
                 h²(ω0² + 3γA²) < 4 at h = {}); use a smaller h or the conservative scheme",
                a2.sqrt(),
                (((4.0 / (self.h * self.h) - w2) / (3.0 * self.gamma)).max(0.0)).sqrt(),
                self.h
            ),
        ))
    }

    /// Second difference `q = -h²(ω0² u + γ u³)` of the scheme at displacement `u`.
    fn second_difference(&self, u: f64) -> f64 {
        -self.h * self.h * u * (self.omega0 * self.omega0 + self.gamma * u * u)
    }
}

impl OscillatorStepper for DuffingVerlet {
    fn name(&self) -> &'static str {
        "duffing-verlet"
    }

    fn step_size(&self) -> f64 {
        self.h
    }

    fn reset(&mut self, u0: f64, v0: f64) {
        self.u = u0;
        self.d = self.h * v0 - 0.5 * self.second_difference(u0);
        self.n = 0;
    }

    fn step(&mut self) {
        self.d += self.second_difference(self.u);
        self.u += self.d;
        self.n += 1;
    }

    fn steps_taken(&self) -> u64 {
        self.n
    }

    fn displacement(&self) -> f64 {
        self.u
    }

    fn velocity(&self) -> f64 {
        self.d / self.h
    }

    /// The energy expression of the conservative scheme with θ1 = θ2 = 1,
    /// `½(δ_{t-}u)² + ½ω0² u_n u_{n-1} + (γ/4) u_n² u_{n-1}²`: Verlet differs from that scheme
    /// only in its force (`γu_n³` instead of `γu_n² μ_{t.}u`), so the drift of this expression
    /// isolates the effect of the non-conservative force. Not conserved: bounded `O(h²)`
    /// oscillation.
    fn discrete_energy(&self) -> f64 {
        let (u, p) = (self.u, self.u - self.d);
        let v = self.d / self.h;
        0.5 * v * v + 0.5 * self.omega0 * self.omega0 * u * p + 0.25 * self.gamma * u * u * p * p
    }

    fn physical_energy(&self) -> f64 {
        duffing_hamiltonian(self.omega0, self.gamma, self.u, self.velocity())
    }
}

/// `H(u, v) = ½v² + ½ω0²u² + ¼γu⁴`.
fn duffing_hamiltonian(omega0: f64, gamma: f64, u: f64, v: f64) -> f64 {
    let u2 = u * u;
    0.5 * v * v + 0.5 * omega0 * omega0 * u2 + 0.25 * gamma * u2 * u2
}

/// Energy-conserving (θ1, θ2) scheme for Duffing; explicit for θ2 = 1, one monotone cubic
/// solve per step otherwise.
///
/// Built once, then owned and stepped by one thread; no allocation.
#[derive(Debug, Clone)]
pub struct DuffingConservative {
    /// Linear angular frequency ω0, rad per time unit.
    omega0: f64,
    /// Cubic coefficient γ ≥ 0, per (displacement² · time²).
    gamma: f64,
    /// θ1 in [0, 1] (linear term).
    theta1: f64,
    /// θ2 in [0, 1] (cubic term).
    theta2: f64,
    /// Time step `h`, time units.
    h: f64,
    /// `w = h²ω0²`, dimensionless.
    w: f64,
    /// `c1 = 1 + (1-θ1) w / 2`, dimensionless.
    c1: f64,
    /// `g = γh²`, per displacement².
    g: f64,
    /// Displacement `u_n`.
    u: f64,
    /// Increment `d_n = u_n - u_{n-1}`.
    d: f64,
    /// Steps since the last reset.
    n: u64,
    /// Solver counters since the last reset.
    stats: StepperStats,
}

impl DuffingConservative {
    /// Builds the scheme; `omega0 > 0`, `gamma ≥ 0`, `theta1`, `theta2` in [0, 1], `h > 0`.
    pub fn new(
        omega0: f64,
        gamma: f64,
        theta1: f64,
        theta2: f64,
        h: f64,
    ) -> Result<Self, ParamError> {
        check_positive("omega0", omega0)?;
        check_non_negative("gamma", gamma)?;
        check_closed("theta1", theta1, 0.0, 1.0)?;
        check_closed("theta2", theta2, 0.0, 1.0)?;
        check_positive("h", h)?;
        // The energy's linear part is positive definite only below the θ1 limit (SEED.md 1.3).
        check_stable_step(h, omega0, theta1, "theta1")?;
        let w = h * h * omega0 * omega0;
        Ok(Self {
            omega0,
            gamma,
            theta1,
            theta2,
            h,
            w,
            c1: 1.0 + 0.5 * (1.0 - theta1) * w,
            g: gamma * h * h,
            u: 0.0,
            d: 0.0,
            n: 0,
            stats: StepperStats::default(),
        })
    }

    /// Whether the update is explicit (θ2 = 1 or γ = 0).
    pub fn is_explicit(&self) -> bool {
        self.theta2 == 1.0 || self.gamma == 0.0
    }

    /// The θ2 = 1 second difference at displacement `u` (SEED.md 1.3 explicit formula).
    fn explicit_second_difference(&self, u: f64) -> f64 {
        let gu2 = self.g * u * u;
        -(self.w + gu2) * u / (self.c1 + 0.5 * gu2)
    }

    /// `(G(q), G'(q))` of the implicit update at the current state.
    fn residual(&self, q: f64) -> (f64, f64) {
        let (u, d, t2) = (self.u, self.d, self.theta2);
        let (next, prev) = (u + d + q, u - d);
        let nq = t2 * u * u + 0.5 * (1.0 - t2) * (next * next + prev * prev);
        let mid = u + 0.5 * q;
        let g = self.c1 * q + self.w * u + self.g * nq * mid;
        let dg = self.c1 + self.g * ((1.0 - t2) * next * mid + 0.5 * nq);
        (g, dg)
    }
}

impl OscillatorStepper for DuffingConservative {
    fn name(&self) -> &'static str {
        "duffing-conservative"
    }

    fn step_size(&self) -> f64 {
        self.h
    }

    fn reset(&mut self, u0: f64, v0: f64) {
        self.u = u0;
        self.d = self.h * v0 - 0.5 * self.explicit_second_difference(u0);
        self.n = 0;
        self.stats = StepperStats::default();
    }

    fn step(&mut self) {
        let q0 = self.explicit_second_difference(self.u);
        let q = if self.is_explicit() {
            q0
        } else {
            // G' ≥ c1, so the root is within |G(q0)|/c1 of q0 (doubled for round-off).
            let r = 2.0 * self.residual(q0).0.abs() / self.c1;
            let root = solve_increasing(
                |q| self.residual(q),
                q0,
                q0 - r,
                q0 + r,
                |x| 8.0 * f64::EPSILON * x.abs() + f64::MIN_POSITIVE,
            );
            record(&mut self.stats, &root);
            root.x
        };
        self.d += q;
        self.u += self.d;
        self.n += 1;
    }

    fn steps_taken(&self) -> u64 {
        self.n
    }

    fn displacement(&self) -> f64 {
        self.u
    }

    fn velocity(&self) -> f64 {
        self.d / self.h
    }

    fn discrete_energy(&self) -> f64 {
        let (u, d) = (self.u, self.d);
        let p = u - d;
        let v = d / self.h;
        let linear = 0.5 * u * p + 0.25 * (1.0 - self.theta1) * d * d;
        let (u2, p2) = (u * u, p * p);
        let quartic = self.theta2 * u2 * p2 + 0.5 * (1.0 - self.theta2) * (u2 * u2 + p2 * p2);
        0.5 * v * v + self.omega0 * self.omega0 * linear + 0.25 * self.gamma * quartic
    }

    fn physical_energy(&self) -> f64 {
        duffing_hamiltonian(self.omega0, self.gamma, self.u, self.velocity())
    }

    fn stats(&self) -> StepperStats {
        self.stats
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn explicit_update_matches_seed_formula() {
        // SEED.md 1.3: u_{n+1} = (2 - h²ω0²θ1) u_n / (1 + (1-θ1)h²ω0²/2 + γh²u_n²/2) - u_{n-1}.
        // Same arithmetic up to reassociation: agreement to 1e-14 of the unit amplitude.
        let (w, g, t1, h) = (1.0, 5.0, 0.8, 0.0628);
        let mut s = DuffingConservative::new(w, g, t1, 1.0, h).unwrap();
        s.reset(1.0, 0.3);
        let (mut prev, mut cur) = (s.u - s.d, s.u);
        for _ in 0..200 {
            let next = (2.0 - h * h * w * w * t1) * cur
                / (1.0 + 0.5 * (1.0 - t1) * h * h * w * w + 0.5 * g * h * h * cur * cur)
                - prev;
            s.step();
            assert!((s.displacement() - next).abs() < 1e-14);
            (prev, cur) = (cur, s.displacement());
        }
    }

    #[test]
    fn implicit_update_solves_seed_cubic() {
        // SEED.md 1.3 (θ2 = 0, θ1 = 1): the residual of the cubic in u_{n+1}, at the computed
        // u_{n+1}, must be at round-off level (terms are O(1); 1e-14 allows a few ulps).
        let (w, g, h) = (1.0, 5.0, 0.1);
        let mut s = DuffingConservative::new(w, g, 1.0, 0.0, h).unwrap();
        s.reset(1.0, 0.0);
        for _ in 0..500 {
            let (prev, cur) = (s.u - s.d, s.u);
            s.step();
            let next = s.displacement();
            let res = next - 2.0 * cur
                + prev
                + h * h * w * w * cur
                + h * h * 0.25 * g * (next + prev) * (next * next + prev * prev);
            assert!(res.abs() < 1e-14, "{res}");
        }
        let st = s.stats();
        assert_eq!(st.solver_failures, 0);
        assert!(st.max_iterations_per_step >= 2 && st.max_iterations_per_step < 10);
    }

    #[test]
    fn solver_safeguard_bisects_and_reports_the_cap() {
        // G(x) = x³ - 8 with a useless derivative: only bisection can converge, in ~60 halvings.
        let r = solve_increasing(|x| (x * x * x - 8.0, 1e-300), 0.0, 0.0, 10.0, |_| 1e-15);
        assert!(r.converged && (r.x - 2.0).abs() < 1e-14, "{}", r.x);
        let r = solve_increasing(|x| (x - 1.0, 1e-300), 0.0, 0.0, 1e300, |_| 0.0);
        assert!(!r.converged && r.iterations == MAX_ITERATIONS);
    }
}
