//! What the modes above a truncated plate do at the mallet's contact: a spring and a dashpot
//! in parallel, in series with the simulated plate.
//!
//! # Why
//!
//! A truncated modal plate has no modes above its top `ω_c`. Driven at a point above that
//! frequency it answers like a mass (its point admittance `iω Σ_s Φ_s²/ρh(ω_s² - ω²)` tends to
//! `-i Σ_s Φ_s² / ρh ω`), where the real plate absorbs: a thin plate's point impedance is the
//! resistance `Z = 8 √(D ρh)` at every frequency where its modes are dense (Cremer, Heckl &
//! Petersson, *Structure-Borne Sound*, 3rd ed., Springer 2005, section 5.3; `D` the flexural
//! rigidity). A hard stick's contact, a fraction of a millisecond, has its spectrum there:
//! against the truncated plate it rebounds as from a mass, too briefly and with too much
//! force above `ω_c`, and the band above the simulation, struck by that force
//! ([`super::extension`], "The strike"), rings too loud just above the cutoff.
//!
//! The modes left out, at the contact point, are a linear system whose admittance is that of
//! the plate's modes above `ω_c`: springs below `ω_c` (their static compliance
//! `Σ_{ω_e > ω_c} Φ_e²/ρh ω_e²`) and the plate's resistance above it. With the modes evenly
//! spread in frequency (a plate's modal density `n` is constant, Weyl's law) the resistance is
//! `Z = 2ρh / (π n ⟨Φ²⟩)` and the compliance `n ⟨Φ²⟩ / (ρh ω_c) = 2 / (π Z ω_c)`. A dashpot
//! `r = Z` in parallel with a spring `k = (π/2) Z ω_c` has exactly these two limits (its
//! admittance `iω / (k + iωr)`), so the contact point moves by `w + u` with
//!
//! ```text
//! k u + r u̇ = F        (F the contact force, N; u the residual displacement, m).
//! ```
//!
//! # Scheme and energy
//!
//! Centred like the plate: `k μ_{t.}u + r δ_{t.}u = F(n)`, so `u(n+1) = u* + c_u F(n)` is
//! affine in the force (`c_u = 1/(k/2 + r/2h)`) and joins the mallet's scalar solve as more
//! compliance. Multiplying by `δ_{t.}u`: the force's work `h F δ_{t.}u` is the spring's
//! energy change `δ_{t+}(k/4 (u(n)² + u(n-1)²))` plus the dashpot's `h r (δ_{t.}u)² ≥ 0`, to
//! round-off: the mallet's work on plate and residual together is accounted, and the joint
//! balance of plate and mallet still closes. The dashpot's energy is what the modes above take
//! from the contact; the band above receives its strike through the force itself.
//!
//! Lifecycle: owned by the plate model; [`ContactResidual::set`], [`ContactResidual::advance`]
//! and [`ContactResidual::reset`] on the audio thread without allocation.

use crate::error::ParamError;
use std::f64::consts::FRAC_PI_2;

/// The residual of the modes above the truncation at the contact point (module doc).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ContactResidual {
    /// Spring `k` (N/m) and dashpot `r` (N·s/m); both 0: off.
    k: f64,
    r: f64,
    /// `u(n)` and `u(n-1)` (m).
    u: f64,
    u_prev: f64,
    /// The spring's energy `k/4 (u(n)² + u(n-1)²)` (J).
    stored: f64,
    /// Cumulative energy the dashpot took (J, ≥ 0).
    dissipated: f64,
    /// Cumulative work of the contact force on the residual (J).
    work: f64,
    /// The part of `dissipated` already taken by [`Self::take_dissipated`] (J).
    taken: f64,
}

impl ContactResidual {
    /// The spring and dashpot of the modes above `omega_c` (rad/s, the top simulated mode) of
    /// a plate of flexural rigidity `d` (N·m) and surface density `rho_h` (kg/m²): `r = 8 √(D
    /// ρh)`, `k = (π/2) r ω_c` (module doc). Errors name the field when a value is not
    /// positive and finite.
    pub fn for_plate(d: f64, rho_h: f64, omega_c: f64) -> Result<(f64, f64), ParamError> {
        for (name, x) in [("d", d), ("rho_h", rho_h), ("omega_c", omega_c)] {
            if !(x.is_finite() && x > 0.0) {
                return Err(ParamError::new(
                    format!("contact_residual.{name}"),
                    x,
                    "positive and finite",
                ));
            }
        }
        let r = 8.0 * (d * rho_h).sqrt();
        Ok((FRAC_PI_2 * r * omega_c, r))
    }

    /// Sets the spring `k` (N/m) and dashpot `r` (N·s/m); `(0, 0)` turns the residual off.
    /// The state is kept. Errors name the field when a value is negative or not finite, or
    /// only one is zero. No allocation.
    pub fn set(&mut self, k: f64, r: f64) -> Result<(), ParamError> {
        for (name, x) in [("k", k), ("r", r)] {
            if !(x.is_finite() && x >= 0.0) {
                return Err(ParamError::new(
                    format!("contact_residual.{name}"),
                    x,
                    "non-negative and finite",
                ));
            }
        }
        if (k == 0.0) != (r == 0.0) {
            return Err(ParamError::new(
                "contact_residual.k",
                k,
                "0 together with r, or both positive",
            ));
        }
        self.k = k;
        self.r = r;
        Ok(())
    }

    /// Whether the residual is on.
    pub fn is_on(&self) -> bool {
        self.r > 0.0
    }

    /// `u(n-1)` (m).
    pub fn u_prev(&self) -> f64 {
        self.u_prev
    }

    /// `u(n)` (m).
    pub fn u(&self) -> f64 {
        self.u
    }

    /// `(u*, c_u)` for a step of `h` (s): `u(n+1) = u* + c_u F` (m, m/N); `(0, 0)` when off.
    pub fn predict(&self, h: f64) -> (f64, f64) {
        if !self.is_on() {
            return (0.0, 0.0);
        }
        let (a, b) = (0.5 * self.k, 0.5 * self.r / h);
        let c_u = 1.0 / (a + b);
        (-(a - b) * self.u_prev * c_u, c_u)
    }

    /// Advances one step of `h` (s) under the force `force` (N), accounting its work, the
    /// spring's energy and the dashpot's loss. No allocation.
    pub fn advance(&mut self, h: f64, force: f64) {
        if !self.is_on() {
            return;
        }
        let (u_star, c_u) = self.predict(h);
        let next = u_star + c_u * force;
        let d = next - self.u_prev;
        self.work += 0.5 * force * d;
        let rate = 0.5 * d / h;
        self.dissipated += h * self.r * rate * rate;
        self.u_prev = self.u;
        self.u = next;
        self.stored = 0.25 * self.k * (self.u * self.u + self.u_prev * self.u_prev);
    }

    /// Puts the residual at rest and clears its energy terms. No allocation.
    pub fn reset(&mut self) {
        *self = Self {
            k: self.k,
            r: self.r,
            ..Self::default()
        };
    }

    /// The dashpot's energy since the last call (J, ≥ 0): what the modes above take from the
    /// contact (their band's strike, [`crate::models::plate::extension`]). No allocation.
    pub fn take_dissipated(&mut self) -> f64 {
        let fresh = (self.dissipated - self.taken).max(0.0);
        self.taken = self.dissipated;
        fresh
    }

    /// `(stored, dissipated, work)` (J): the spring's energy, the dashpot's cumulative loss and
    /// the force's cumulative work; `stored + dissipated - work` stays 0 to round-off.
    pub fn energy(&self) -> (f64, f64, f64) {
        (self.stored, self.dissipated, self.work)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Driven by a half-sine pulse and then left free, the residual's work is its spring's
    /// energy plus its dashpot's loss to round-off, and it comes back to rest; a steady force
    /// compresses it statically by `F / k`.
    #[test]
    fn the_work_is_the_spring_energy_plus_the_loss() {
        let (k, r) = ContactResidual::for_plate(20.0, 6.9, std::f64::consts::TAU * 7000.0)
            .expect("valid plate");
        let mut x = ContactResidual::default();
        x.set(k, r).unwrap();
        let h = 1.0 / 31_200.0;
        for n in 0..400 {
            let t = n as f64 * h;
            let f = if t < 3e-4 {
                100.0 * (std::f64::consts::PI * t / 3e-4).sin()
            } else {
                0.0
            };
            x.advance(h, f);
            let (s, d, w) = x.energy();
            assert!((s + d - w).abs() <= 1e-13 * w.abs().max(1e-12), "step {n}");
        }
        let (s, d, w) = x.energy();
        assert!(w > 0.0 && d > 0.99 * w && s < 1e-9 * w, "{s} {d} {w}");
        let mut y = ContactResidual::default();
        y.set(k, r).unwrap();
        for _ in 0..2000 {
            y.advance(h, 50.0);
        }
        assert!((y.u() * k / 50.0 - 1.0).abs() < 1e-9, "{}", y.u() * k);
    }

    /// Bad values are errors naming the field.
    #[test]
    fn bad_values_name_the_field() {
        let e = ContactResidual::for_plate(-1.0, 1.0, 1.0).unwrap_err();
        assert!(e.to_string().contains("contact_residual.d"), "{e}");
        let mut x = ContactResidual::default();
        let e = x.set(f64::NAN, 1.0).unwrap_err();
        assert!(e.to_string().contains("contact_residual.k"), "{e}");
        assert!(x.set(1.0, 0.0).is_err());
        assert!(x.set(0.0, 0.0).is_ok() && !x.is_on());
    }
}
