//! A physical mallet for the modal plate: a lumped mass thrown against the plate at the strike
//! point through a power-law felt (the impact oscillator of SEED.md section 1.4, coupled to the
//! plate modes).
//!
//! # Model
//!
//! Mallet position `y` (m) and plate displacement at the strike point `w = Σ_s Φ_s(x₀) q_s`
//! (m), both positive in the direction the mallet travels; compression `δ = y - w` (positive
//! in contact). With the felt law of Chaigne & Doutaut (J. Acoust. Soc. Am. 101(1), 1997,
//! section II.B) and a Hunt-Crossley loss (Hunt & Crossley, J. Appl. Mech. 42, 1975):
//!
//! ```text
//! M ÿ = -F,   ρh (q̈_s + ω_s² q_s + c_s q̇_s) = … + Φ_s(x₀) F,
//! F = K [δ]_+^α (1 + λ δ̇),   clamped to F ≥ 0 (the felt pushes, never pulls),
//! ```
//!
//! `M` (kg), `K` (N/m^α), α in [1, 4], `λ` (s/m). Energy: plate energy `+ ½ M ẏ² + φ(δ)`,
//! `φ(δ) = K/(α+1) [δ]_+^{α+1}`, decreasing by the plate's modal losses and the felt loss.
//!
//! # Scheme (Bilbao, *Numerical Sound Synthesis*, Wiley 2009, chapter 4)
//!
//! `M δ_tt y = -F(n)`, the plate scheme under the force `F(n)` (any [`super::PlateScheme`]),
//! and the discrete-gradient force with the felt loss on the centred rate `δ_{t.}δ`:
//!
//! ```text
//! F(n) = max(0, Q (1 + λ δ_{t.}δ(n))),   Q = (φ(δ(n+1)) - φ(δ(n-1))) / (δ(n+1) - δ(n-1)).
//! ```
//!
//! **Energy.** Multiplying the mallet equation by `δ_{t.}y`, the plate's by `δ_{t.}q_s` and
//! adding, the work terms combine into `-F δ_{t.}δ`; `Q δ_{t.}δ = δ_{t+}(μ_{t-}φ(δ(n)))` and
//! `(F - Q) δ_{t.}δ ≥ 0` (it is `λ Q (δ_{t.}δ)²` unclamped, `-Q δ_{t.}δ` with `δ_{t.}δ < 0`
//! clamped). So with the plate's `𝔥` ([`super::PlateEnergy`])
//!
//! ```text
//! δ_{t+}[𝔥 + ½M(δ_{t-}y)² + μ_{t-}φ(δ)] = -(plate damping power) - (F - Q) δ_{t.}δ ≤ 0,
//! ```
//!
//! exactly (the lossless sum is conserved to round-off), for any `h`: the contact adds a
//! non-negative energy, so it never destabilises the plate scheme ([`MalletEnergy`]).
//!
//! # Solve
//!
//! Every plate scheme's `q(n+1)` is affine in `F(n)`: `q(n+1) = q*(n+1) + F z`, with `q*` the
//! force-free step and `z` the response to a unit force (diagonal for Störmer-Verlet, one
//! Sherman-Morrison correction for SAV, one more back-substitution with the already factored
//! matrix for the conservative schemes). So `w(n+1) = w* + c F` with the step compliance
//! `c = Φ·z ≥ 0`, `y(n+1) = 2y(n) - y(n-1) - (h²/M) F`, and with `r = δ(n+1) - δ(n-1)`,
//! `r_0 = 2y(n) - y(n-1) - w* - δ(n-1)`, `β = h²/M + c`:
//!
//! ```text
//! G(r) = r - r_0 + β F(r) = 0.
//! ```
//!
//! `F(r) = max(0, Q(r) + (λ/2h)(φ(δ(n-1) + r) - φ(δ(n-1))))` is non-decreasing and convex in
//! `r` (`Q` is the mean of the convex `φ'` over a growing interval), so `G` is increasing
//! (`G' ≥ 1`) and convex: one root, in `[r_0 - β F(r_0), r_0]`; Newton from `r_0` decreases
//! monotonically to it. The solve is the impact oscillator's safeguarded Newton
//! ([`crate::schemes::duffing`]'s `solve_increasing`: bisection safeguard, 100-evaluation cap,
//! the last iterate used and counted in [`StepperStats::solver_failures`] on the cap) with the
//! rounding-safe `Q` of [`HertzContact::secant`]. Out of contact (`F(r_0) = 0`) nothing is
//! solved and the step is the plate's own.
//!
//! Threads: built on any thread; stepped by the thread that steps the plate
//! ([`super::PlateModel::step_with_mallet`]), no allocation.

use crate::error::{check_closed, check_non_negative, check_positive, ParamError};
use crate::schemes::duffing::{record, solve_increasing};
use crate::schemes::impact::HertzContact;
use crate::schemes::StepperStats;

/// The mallet's discrete energy terms and accumulators (J), written at every step by the thread
/// that steps the plate, copied out by value ([`Mallet::energy`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MalletEnergy {
    /// Kinetic energy `½ M (δ_{t-}y(n))²` (J).
    pub kinetic: f64,
    /// Felt potential `μ_{t-}φ(δ(n)) = (φ(δ(n)) + φ(δ(n-1)))/2` (J).
    pub contact: f64,
    /// Cumulative energy removed by the felt loss, `Σ_m (F - Q) (δ(m+1) - δ(m-1))/2` (J), ≥ 0.
    pub dissipated: f64,
    /// Cumulative work of the contact force on the plate, `Σ_m F(m) (w(m+1) - w(m-1))/2` (J)
    /// (the plate's own [`super::PlateEnergy::work`] counts the same, up to round-off).
    pub work_on_plate: f64,
    /// Cumulative energy put in by launches ([`super::PlateModel::launch_mallet`]) (J).
    pub launched: f64,
}

impl MalletEnergy {
    /// Stored energy of the mallet and the felt, `kinetic + contact` (J).
    pub fn total(&self) -> f64 {
        self.kinetic + self.contact
    }

    /// The joint invariant of plate and mallet (J): `plate.balance() + work_on_plate + total +
    /// dissipated - launched`, i.e. stored energies plus everything dissipated minus everything
    /// put in (launches and any other force the plate took). Constant to round-off.
    pub fn joint_balance(&self, plate: &super::PlateEnergy) -> f64 {
        plate.balance() + self.work_on_plate + self.total() + self.dissipated - self.launched
    }
}

/// A lumped mallet with a power-law felt, struck against a [`super::PlateModel`] at its force
/// point (equations, energy and solve in the module docs).
///
/// Plain scalar state; built with [`Mallet::new`] (validates, no allocation), launched with
/// [`super::PlateModel::launch_mallet`], advanced with [`super::PlateModel::step_with_mallet`]
/// by the thread that owns the plate.
#[derive(Debug, Clone)]
pub struct Mallet {
    /// Felt law `K [δ]_+^α`.
    law: HertzContact,
    /// Mass `M` (kg).
    mass: f64,
    /// Felt loss `λ` (s/m).
    loss: f64,
    /// Time step `h` (s), the plate's.
    h: f64,
    /// Position `y(n)` and increment `d(n) = y(n) - y(n-1)` (m); the increment is carried
    /// (not `y(n-1)`) so the velocity `d/h` does not lose `ε|y|/h` at each step (as in the
    /// impact oscillator).
    y: f64,
    d: f64,
    /// Compression `δ(n)` and `δ(n-1)` (m) as solved (the contact energy uses these).
    delta: f64,
    delta_prev: f64,
    /// Launched at least once (until then the plate steps force-free).
    active: bool,
    /// The last step had a contact force (counts impacts).
    in_contact: bool,
    /// The force `F(n-1)` of the last step (N).
    force: f64,
    energy: MalletEnergy,
    stats: StepperStats,
}

impl Mallet {
    /// A mallet of mass `mass` (kg, > 0) with felt stiffness `stiffness` (N/m^α, > 0), felt
    /// exponent `exponent` (α in [1, 4]) and felt loss `loss` (λ, s/m, ≥ 0), for a plate with
    /// time step `h` (s, > 0). Errors name the field, the value and the allowed range. Parked
    /// (not yet launched).
    pub fn new(
        mass: f64,
        stiffness: f64,
        exponent: f64,
        loss: f64,
        h: f64,
    ) -> Result<Self, ParamError> {
        check_positive("mass", mass)?;
        check_positive("stiffness", stiffness)?;
        check_closed("exponent", exponent, 1.0, 4.0)?;
        check_non_negative("loss", loss)?;
        check_positive("h", h)?;
        Ok(Self {
            law: HertzContact {
                stiffness,
                alpha: exponent,
            },
            mass,
            loss,
            h,
            y: 0.0,
            d: 0.0,
            delta: 0.0,
            delta_prev: 0.0,
            active: false,
            in_contact: false,
            force: 0.0,
            energy: MalletEnergy::default(),
            stats: StepperStats::default(),
        })
    }

    /// Mass `M` (kg).
    pub fn mass(&self) -> f64 {
        self.mass
    }

    /// The felt law `K [δ]_+^α`.
    pub fn law(&self) -> HertzContact {
        self.law
    }

    /// Time step `h` (s) the mallet was built for.
    pub fn h(&self) -> f64 {
        self.h
    }

    /// Whether the mallet has been launched.
    pub fn is_active(&self) -> bool {
        self.active
    }

    /// Compression `δ(n)` (m), positive in contact.
    pub fn compression(&self) -> f64 {
        self.delta
    }

    /// Position `y(n)` (m) and velocity `δ_{t-}y(n)` (m/s), positive towards the plate.
    pub fn position_velocity(&self) -> (f64, f64) {
        (self.y, self.d / self.h)
    }

    /// Contact force `F(n-1)` of the last step (N, ≥ 0).
    pub fn force(&self) -> f64 {
        self.force
    }

    /// Energy terms and accumulators.
    pub fn energy(&self) -> MalletEnergy {
        self.energy
    }

    /// Solver and contact counters (iterations, capped solves, contact steps, impacts).
    pub fn stats(&self) -> StepperStats {
        self.stats
    }

    /// Puts the mallet just short of the plate surface `w(n)` (the plate was at `w(n-1)` one
    /// step before), moving towards it at `speed` (m/s): `y(n) = w(n) - g`,
    /// `y(n-1) = y(n) - speed h`, with the gap `g = speed h + max(0, w(n) - w(n-1))` so that
    /// `δ(n), δ(n-1) < 0` even on a plate moving towards the mallet (no felt energy at launch).
    /// The change of the mallet's energy is added to [`MalletEnergy::launched`].
    pub(crate) fn launch(&mut self, speed: f64, w: f64, w_prev: f64) -> Result<(), ParamError> {
        check_positive("speed", speed)?;
        let before = self.energy.total();
        let step = speed * self.h;
        let gap = step + (w - w_prev).max(0.0);
        self.y = w - gap;
        self.d = step;
        self.delta = -gap;
        self.delta_prev = (self.y - step) - w_prev;
        self.active = true;
        self.in_contact = false;
        self.update_stored();
        self.energy.launched += self.energy.total() - before;
        Ok(())
    }

    /// `F(r)` and `F'(r)` for `r = δ(n+1) - δ(n-1)` (module docs).
    fn force_of(&self, r: f64) -> (f64, f64) {
        let (q, dq) = self.law.secant(self.delta_prev, self.delta_prev + r);
        let gain = self.loss / (2.0 * self.h);
        let f = q * (1.0 + gain * r);
        if f > 0.0 {
            (f, dq * (1.0 + gain * r) + q * gain)
        } else {
            (0.0, 0.0)
        }
    }

    /// One step of the mallet given the plate's force-free `w* = Φ·q*(n+1)` (m), its step
    /// compliance `c = Φ·z` (m/N) and `w(n-1)` (m): solves for `F(n)` (N), advances `y`, `δ`
    /// and the energy, and returns `F(n)`. No allocation, at most 100 residual evaluations.
    pub(crate) fn contact_step(&mut self, w_star: f64, compliance: f64, w_prev: f64) -> f64 {
        let h2_over_m = self.h * self.h / self.mass;
        let r_free = (self.y + self.d - w_star) - self.delta_prev;
        let (f_free, _) = self.force_of(r_free);
        let (r, force) = if f_free > 0.0 {
            let beta = h2_over_m + compliance;
            let dm = self.delta_prev;
            let root = solve_increasing(
                |r| {
                    let (f, df) = self.force_of(r);
                    (r - r_free + beta * f, 1.0 + beta * df)
                },
                r_free,
                r_free - beta * f_free,
                r_free,
                |r| 4.0 * f64::EPSILON * r.abs().max(dm.abs()).max((dm + r).abs()),
            );
            record(&mut self.stats, &root);
            self.stats.contact_steps += 1;
            let (f, _) = self.force_of(root.x);
            (root.x, f)
        } else {
            (r_free, 0.0)
        };
        if force > 0.0 && !self.in_contact {
            self.stats.impacts += 1;
        }
        self.in_contact = force > 0.0;
        let elastic = self.law.secant(self.delta_prev, self.delta_prev + r).0;
        self.energy.dissipated += 0.5 * (force - elastic) * r;
        self.energy.work_on_plate += 0.5 * force * (w_star + compliance * force - w_prev);
        self.d -= h2_over_m * force;
        self.y += self.d;
        let delta_next = self.delta_prev + r;
        self.delta_prev = self.delta;
        self.delta = delta_next;
        self.force = force;
        self.update_stored();
        force
    }

    /// Recomputes the kinetic and felt energy from `d(n)`, `δ(n)` and `δ(n-1)`.
    fn update_stored(&mut self) {
        let v = self.d / self.h;
        self.energy.kinetic = 0.5 * self.mass * v * v;
        self.energy.contact =
            0.5 * (self.law.potential(self.delta) + self.law.potential(self.delta_prev));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constructor_names_the_field_and_range() {
        let e = Mallet::new(0.0, 1e8, 2.5, 0.0, 1e-5)
            .unwrap_err()
            .to_string();
        assert!(e.contains("mass"), "{e}");
        let e = Mallet::new(0.01, 1e8, 4.5, 0.0, 1e-5)
            .unwrap_err()
            .to_string();
        assert!(e.contains("exponent") && e.contains("4.5"), "{e}");
        let e = Mallet::new(0.01, 1e8, 2.5, -1.0, 1e-5)
            .unwrap_err()
            .to_string();
        assert!(e.contains("loss"), "{e}");
        let e = Mallet::new(0.01, f64::NAN, 2.5, 0.0, 1e-5)
            .unwrap_err()
            .to_string();
        assert!(e.contains("stiffness"), "{e}");
        let mut m = Mallet::new(0.01, 1e8, 2.5, 0.0, 1e-5).unwrap();
        let e = m.launch(-1.0, 0.0, 0.0).unwrap_err().to_string();
        assert!(e.contains("speed"), "{e}");
    }

    #[test]
    fn rigid_target_conserves_and_reverses_the_velocity() {
        // Against a fixed target (w* = 0, c = 0) the lossless scheme conserves ½Mẏ² + μφ to
        // round-off and the rebound speed equals the launch speed to the same accuracy; with
        // λ > 0 it rebounds slower and the loss is accounted. Contact ≈ 2.5 ms ≈ 250 steps;
        // measured max relative drift 1.7e-15 (lossless) and 9.3e-16 (lossy); bound 2e-14.
        for loss in [0.0, 0.5] {
            let mut m = Mallet::new(0.03, 1e9, 2.5, loss, 1e-5).unwrap();
            m.launch(2.0, 0.0, 0.0).unwrap();
            let e0 = m.energy().total();
            let mut worst: f64 = 0.0;
            for _ in 0..1000 {
                m.contact_step(0.0, 0.0, 0.0);
                let e = m.energy();
                worst = worst.max(((e.total() + e.dissipated - e0) / e0).abs());
            }
            assert!(worst < 2e-14, "drift {worst}");
            let (_, v) = m.position_velocity();
            assert_eq!(m.stats().impacts, 1);
            assert_eq!(m.stats().solver_failures, 0);
            assert_eq!(m.force(), 0.0);
            if loss == 0.0 {
                assert!((v + 2.0).abs() < 1e-12, "{v}");
            } else {
                assert!(v < 0.0 && v > -2.0 * 0.99, "{v}");
                assert!(m.energy().dissipated > 0.0);
            }
        }
    }
}
