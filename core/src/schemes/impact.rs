//! Impact oscillator `m ü + k u = -K [u - d]_+^α` with an energy-conserving discrete-gradient
//! contact force (SEED.md section 1.4).
//!
//! Potential `Φ(u) = K/(α+1) [u - d]_+^{α+1}`, `H = ½ m u̇² + ½ k u² + Φ(u)`. Scheme:
//! `m δ_{tt}u + k(θ + (1-θ)μ_{t.})u = -f_n`, `f_n = (Φ(u_{n+1}) - Φ(u_{n-1})) / (u_{n+1} - u_{n-1})`
//! (S. Bilbao, *Numerical Sound Synthesis*, Wiley 2009, chapter 4; C. Issanchou et al.,
//! J. Sound Vib. 2017). Multiplying by `δ_{t.}u` gives `δ_{t+} E_n = 0` with
//! `E_n = ½m(δ_{t-}u_n)² + k(θ ½ u_n u_{n-1} + (1-θ) ½ μ_{t-}u_n²) + μ_{t-}Φ(u_n)`.
//! SEED.md writes the contact term as `μ_{t+}Φ(u_n)`, paired with a `δ_{t+}` kinetic term; here
//! every term is evaluated on the same pair `(u_n, u_{n-1})`, so it is `(Φ(u_n) + Φ(u_{n-1}))/2`.
//!
//! # Solve
//! Unknown: `r = u_{n+1} - u_{n-1}`, written `r = 2 d_n + q` with `d_n = u_n - u_{n-1}` and the
//! (small away from contact) second difference `q`; Newton in `q` has the same iterates as
//! Newton in `r` but carries fewer rounding errors. With `w = h²k/m`, `c0 = 1 + (1-θ)w/2`:
//! `G(q) = c0 q + w u_n + (h²/m) Q(r)`, `Q(r) = (Φ(u_{n-1} + r) - Φ(u_{n-1}))/r`, `Q(0) = Φ'(u_{n-1})`.
//! `Q` is the mean of the non-decreasing convex `Φ'` over `[u_{n-1}, u_{n-1} + r]`, so `G` is
//! increasing (`G' ≥ c0 ≥ 1`) and convex: one root. Without contact the root is the θ-scheme
//! value `q_L = -w u_n / c0`; contact only pushes back, so the root lies in
//! `[q_L - (h²/m)Q(q_L)/c0, q_L]` and Newton started at `q_L` decreases monotonically to it
//! (convexity); `solve_increasing` adds a bisection safeguard and an iteration cap (then the
//! last iterate is used and `solver_failures` is incremented).
//!
//! # Rounding
//! - The state is stored relative to the wall: `x_n = u_n - gap` (the penetration when positive)
//!   and `d_n`, so the stiff contact term sees positions with ulp `ε|x|`, not `ε|u|`; the gap
//!   only enters the soft spring term `k u = k(x + gap)`.
//! - `Q` is never formed as a difference of nearly equal `Φ` values: with both ends in contact,
//!   `x_hi = max`, `s = |r| / x_hi ∈ [0, 1)`,
//!   `Q = (K/(α+1)) x_hi^α (1 - (1-s)^{α+1}) / s`, and `1 - (1-s)^{α+1}` is evaluated as
//!   `-expm1((α+1) ln1p(-s))`, accurate to a few ulps for every `s` (this replaces a Taylor
//!   series in `r`; `s = 0` gives the limit `Φ'(u_{n-1})` exactly). With one end out of
//!   contact, `Q = Φ(x_hi) / |r|` with `|r| ≥ x_hi`: no cancellation. The Newton derivative
//!   `∂Q/∂x_{n+1} = (Φ'(x_{n+1}) - Q)/r` uses `Φ''(x_mid)/2` when `s < 1e-5` (it only sets the
//!   convergence rate).
//!
//! Starting values: `d_0 = h v0 - q̂/2` with the contact-free `q̂ = -w u0/c0`, i.e. the exact
//! symmetric start of the θ-scheme (`δ_{t.}u_0 = v0` while no contact is involved); a start in
//! contact ignores the contact force in this history.

use super::duffing::{record, solve_increasing};
use super::linear::check_stable_step;
use super::{OscillatorStepper, StepperStats};
use crate::error::{check_closed, check_finite, check_non_negative, check_positive, ParamError};

/// Below this `|r| / x_hi` the Newton derivative uses the midpoint `Φ''/2`.
const TAYLOR_SPAN: f64 = 1e-5;

/// The power-law contact `Φ'(x) = K [x]_+^α` on a penetration (or compression) `x`, with its
/// potential and the rounding-safe discrete gradient of the module docs. Shared by
/// [`ImpactScheme`] and the plate's mallet ([`crate::models::plate::Mallet`]); plain `Copy`
/// data, any thread.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzContact {
    /// Contact stiffness `K` (force per displacement^α, N/m^α), `> 0`.
    pub stiffness: f64,
    /// Exponent α (dimensionless), in [1, 4].
    pub alpha: f64,
}

impl HertzContact {
    /// Potential `Φ(x) = K/(α+1) [x]_+^{α+1}` (energy units).
    pub fn potential(&self, x: f64) -> f64 {
        if x > 0.0 {
            self.stiffness / (self.alpha + 1.0) * x.powf(self.alpha + 1.0)
        } else {
            0.0
        }
    }

    /// Force `Φ'(x) = K [x]_+^α` (force units).
    pub fn force(&self, x: f64) -> f64 {
        if x > 0.0 {
            self.stiffness * x.powf(self.alpha)
        } else {
            0.0
        }
    }

    /// Discrete-gradient force `Q = (Φ(xb) - Φ(xa)) / (xb - xa)` between `xa` (step n-1) and
    /// `xb` (step n+1), and `∂Q/∂xb` (see the module docs for the forms used): `Q ≥ 0`,
    /// non-decreasing and convex in `xb`, `Q(xa, xa) = Φ'(xa)`. No allocation.
    pub fn secant(&self, xa: f64, xb: f64) -> (f64, f64) {
        let (lo, hi) = if xa <= xb { (xa, xb) } else { (xb, xa) };
        if hi <= 0.0 || hi.is_nan() {
            return (0.0, 0.0);
        }
        let (k, a) = (self.stiffness, self.alpha);
        let span = hi - lo;
        if lo <= 0.0 {
            let q = k / (a + 1.0) * hi.powf(a + 1.0) / span;
            return (q, (self.force(xb) - q) / (xb - xa));
        }
        let s = span / hi;
        let ratio = if s > 0.0 {
            -((a + 1.0) * (-s).ln_1p()).exp_m1() / s
        } else {
            a + 1.0
        };
        let q = k / (a + 1.0) * hi.powf(a) * ratio;
        let dq = if s < TAYLOR_SPAN {
            0.5 * k * a * (0.5 * (lo + hi)).powf(a - 1.0)
        } else {
            (self.force(xb) - q) / (xb - xa)
        };
        (q, dq)
    }
}

/// Impact oscillator stepper (conservative discrete-gradient contact, Newton solve per step).
///
/// Built once, then owned and stepped by one thread; `step` does no allocation and at most
/// `MAX_ITERATIONS` (100) residual evaluations.
#[derive(Debug, Clone)]
pub struct ImpactScheme {
    /// Mass `m`, mass units.
    mass: f64,
    /// Linear spring stiffness `k`, force per displacement.
    stiffness: f64,
    /// The contact law `K [x]_+^α` (`K` force per displacement^α, α in [1, 4]).
    law: HertzContact,
    /// Gap `d` from rest to the wall, displacement units.
    gap: f64,
    /// θ in [0, 1] of the linear part.
    theta: f64,
    /// Time step `h`, time units.
    h: f64,
    /// `w = h²k/m`, dimensionless.
    w: f64,
    /// `c0 = 1 + (1-θ)w/2`, dimensionless.
    c0: f64,
    /// `h²/m`, time² per mass.
    h2_over_m: f64,
    /// Penetration coordinate `x_n = u_n - gap`.
    x: f64,
    /// Increment `d_n = u_n - u_{n-1}`.
    d: f64,
    /// Whether the previous step had an active contact force (for counting impacts).
    in_contact: bool,
    /// Steps since the last reset.
    n: u64,
    /// Solver and contact counters since the last reset.
    stats: StepperStats,
}

impl ImpactScheme {
    /// Builds the scheme. Requires `mass > 0`, `stiffness ≥ 0`, `contact_stiffness > 0`,
    /// `alpha` in [1, 4], finite `gap`, `theta` in [0, 1], `h > 0`.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        mass: f64,
        stiffness: f64,
        contact_stiffness: f64,
        alpha: f64,
        gap: f64,
        theta: f64,
        h: f64,
    ) -> Result<Self, ParamError> {
        check_positive("mass", mass)?;
        check_non_negative("stiffness", stiffness)?;
        check_positive("contact_stiffness", contact_stiffness)?;
        check_closed("alpha", alpha, 1.0, 4.0)?;
        check_finite("gap", gap)?;
        check_closed("theta", theta, 0.0, 1.0)?;
        check_positive("h", h)?;
        if stiffness > 0.0 {
            // The contact term is a discrete gradient (energy ≥ 0 for any h); the linear
            // spring's part of the energy is positive definite only below the θ limit.
            check_stable_step(h, (stiffness / mass).sqrt(), theta, "theta")?;
        }
        let w = h * h * stiffness / mass;
        Ok(Self {
            mass,
            stiffness,
            law: HertzContact {
                stiffness: contact_stiffness,
                alpha,
            },
            gap,
            theta,
            h,
            w,
            c0: 1.0 + 0.5 * (1.0 - theta) * w,
            h2_over_m: h * h / mass,
            x: -gap,
            d: 0.0,
            in_contact: false,
            n: 0,
            stats: StepperStats::default(),
        })
    }

    /// Contact potential `Φ` at penetration `x = u - gap`: `K/(α+1) [x]_+^{α+1}`, energy units.
    pub fn potential(&self, x: f64) -> f64 {
        self.law.potential(x)
    }

    /// Contact force `Φ'(x) = K [x]_+^α` at penetration `x = u - gap`, force units.
    pub fn contact_force(&self, x: f64) -> f64 {
        self.law.force(x)
    }

    /// Discrete-gradient force between penetrations `xa` (step n-1) and `xb` (step n+1).
    fn secant(&self, xa: f64, xb: f64) -> (f64, f64) {
        self.law.secant(xa, xb)
    }

    /// `(G(q), G'(q))` at the current state.
    fn residual(&self, q: f64) -> (f64, f64) {
        let (qf, dq) = self.secant(self.x - self.d, self.x + (self.d + q));
        (
            self.c0 * q + self.w * (self.x + self.gap) + self.h2_over_m * qf,
            self.c0 + self.h2_over_m * dq,
        )
    }
}

impl OscillatorStepper for ImpactScheme {
    fn name(&self) -> &'static str {
        "impact"
    }

    fn step_size(&self) -> f64 {
        self.h
    }

    fn reset(&mut self, u0: f64, v0: f64) {
        self.x = u0 - self.gap;
        self.d = self.h * v0 + 0.5 * self.w * u0 / self.c0;
        self.in_contact = false;
        self.n = 0;
        self.stats = StepperStats::default();
    }

    fn step(&mut self) {
        let q_lin = -self.w * (self.x + self.gap) / self.c0;
        let (q_contact, _) = self.secant(self.x - self.d, self.x + (self.d + q_lin));
        let contact = q_contact > 0.0;
        let q = if contact {
            let lo = q_lin - 2.0 * self.h2_over_m * q_contact / self.c0;
            let (x, d) = (self.x, self.d);
            let root = solve_increasing(
                |q| self.residual(q),
                q_lin,
                lo,
                q_lin,
                |q| 4.0 * f64::EPSILON * q.abs().max((d + q).abs()).max((x + d + q).abs()),
            );
            record(&mut self.stats, &root);
            self.stats.contact_steps += 1;
            if !self.in_contact {
                self.stats.impacts += 1;
            }
            root.x
        } else {
            q_lin
        };
        self.in_contact = contact;
        self.d += q;
        self.x += self.d;
        self.n += 1;
    }

    fn steps_taken(&self) -> u64 {
        self.n
    }

    fn displacement(&self) -> f64 {
        self.x + self.gap
    }

    fn velocity(&self) -> f64 {
        self.d / self.h
    }

    fn discrete_energy(&self) -> f64 {
        let (x, d) = (self.x, self.d);
        let u = x + self.gap;
        let v = d / self.h;
        let spring = 0.5 * u * (u - d) + 0.25 * (1.0 - self.theta) * d * d;
        0.5 * self.mass * v * v
            + self.stiffness * spring
            + 0.5 * (self.potential(x) + self.potential(x - d))
    }

    fn physical_energy(&self) -> f64 {
        let (u, v) = (self.x + self.gap, self.velocity());
        0.5 * self.mass * v * v + 0.5 * self.stiffness * u * u + self.potential(self.x)
    }

    fn stats(&self) -> StepperStats {
        self.stats
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn secant_matches_direct_quotient_and_limit() {
        // Where the direct quotient is well conditioned (|r| comparable to x) both forms agree
        // to ~1e-14 relative; at r = 0 the limit Φ'(x) is returned exactly; for tiny r the
        // stable form stays within a few ulps of Φ' at the midpoint (the direct quotient would lose ~10 digits).
        let s = ImpactScheme::new(1.0, 1.0, 1e13, 1.5, 0.0, 1.0, 1e-3).unwrap();
        for &(xa, xb) in &[(1e-6, 3e-6), (2e-6, -1e-6), (-1e-6, 5e-7), (4e-6, 1e-6)] {
            let direct = (s.potential(xb) - s.potential(xa)) / (xb - xa);
            let (q, _) = s.secant(xa, xb);
            assert!((q / direct - 1.0).abs() < 1e-14, "{xa} {xb}");
        }
        assert_eq!(s.secant(2e-6, 2e-6).0, s.contact_force(2e-6));
        let (q, dq) = s.secant(2e-6, 2e-6 * (1.0 + 1e-12));
        assert!((q / s.contact_force(2e-6 * (1.0 + 0.5e-12)) - 1.0).abs() < 1e-15);
        let second = 1e13 * 1.5 * (2e-6f64).sqrt();
        assert!((dq / (0.5 * second) - 1.0).abs() < 1e-10);
        assert_eq!(s.secant(-1.0, -2.0), (0.0, 0.0));
    }
}
