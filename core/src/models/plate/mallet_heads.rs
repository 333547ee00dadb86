//! Factory mallets: a soft felt, a hard felt, a rubber, a wooden and a metal head, each a mass
//! and a contact law `F = K [δ]_+^α` (with a felt loss λ) for [`super::Mallet`].
//!
//! **Solid heads (rubber, wood, metal)** are spheres of radius [`HEAD_RADIUS`] pressed into a
//! steel plate: Hertz's law, `α = 3/2` and `K = (4/3) E* √R` with
//! `1/E* = (1 - ν₁²)/E₁ + (1 - ν₂²)/E₂` (Hertz 1882; Johnson, *Contact Mechanics*, 1985,
//! eqs. 4.22-4.23; the plate's local bending is the model's, not the contact's). Moduli are
//! handbook values (Ashby, *Materials Selection in Mechanical Design*, 4th ed., 2011,
//! chapter 4 charts): natural rubber `E = 2 MPa`, `ν = 0.49`; hard maple along the grain
//! `E = 11 GPa`, `ν = 0.35` (a turned head strikes across the grain too, so this is its
//! stiffer end); steel `E = 200 GPa`, `ν = 0.3`. The rubber's internal loss is large (a
//! rebound coefficient near 0.8 at these speeds), the wood's and steel's small.
//!
//! **Felt heads** follow a power law with `α` within the measured range of felts, 2.1 to 3.5
//! (Boutillon, J. Acoust. Soc. Am. 83(2), 1988, piano hammers; Chaigne & Doutaut, J. Acoust.
//! Soc. Am. 101(1), 1997, mallets): `α = 2.5`. Felt has no modulus to start from, so each `K`
//! is chosen from the contact a gong player expects: the soft beater rests about 10 ms on a
//! rigid target at 2 m/s, the hard one about 2 ms ([`felt_stiffness`] inverts Hertz's
//! duration for that).
//!
//! Masses are those of the beaters: 0.3 kg for a large felt gong beater, 0.15 kg for the hard
//! felt, 0.1 kg for the rubber and metal heads, 0.05 kg for the wooden one.
//!
//! Any thread; plain functions.

use crate::error::ParamError;
use serde::{Deserialize, Serialize};

/// Radius of the solid heads (m).
pub const HEAD_RADIUS: f64 = 0.015;
/// Young's modulus (Pa) and Poisson ratio of the struck plate's steel.
pub const PLATE_STEEL: (f64, f64) = (200e9, 0.3);
/// The felts' exponent.
pub const FELT_EXPONENT: f64 = 2.5;
/// The speed (m/s) at which the felts' contact durations are chosen.
pub const FELT_DESIGN_SPEED: f64 = 2.0;

/// A factory mallet head (scenes name it in kebab case: `soft-felt`, ...).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MalletHead {
    /// A large soft felt gong beater.
    SoftFelt,
    /// A hard felt beater.
    HardFelt,
    /// A rubber head.
    Rubber,
    /// A wooden head.
    Wood,
    /// A metal head.
    Metal,
}

/// The names of [`MalletHead::ALL`] in scenes and reports.
pub const HEAD_NAMES: [&str; 5] = ["soft-felt", "hard-felt", "rubber", "wood", "metal"];

/// A head's mass and contact law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeadLaw {
    /// Mass `M` (kg).
    pub mass: f64,
    /// Contact stiffness `K` (N/m^α).
    pub stiffness: f64,
    /// Contact exponent `α`.
    pub exponent: f64,
    /// Felt loss `λ` (s/m, Hunt-Crossley).
    pub loss: f64,
}

/// `∫₀¹ (1 - x^p)^{-1/2} dx` (`= B(1/p, 1/2)/p`) for `p > 1`, by the substitution
/// `x = 1 - t²` (smooth integrand) and composite Simpson on 4000 intervals (error ~1e-13;
/// `π/2` at `p = 2`).
pub fn hertz_integral(p: f64) -> f64 {
    let f = |t: f64| {
        if t == 0.0 {
            2.0 / p.sqrt()
        } else {
            2.0 * t / (-(p * (-t * t).ln_1p()).exp_m1()).sqrt()
        }
    };
    let n = 4000;
    let h = 1.0 / n as f64;
    let mut s = f(0.0) + f(1.0);
    for i in 1..n {
        s += if i % 2 == 1 { 4.0 } else { 2.0 } * f(i as f64 * h);
    }
    s * h / 3.0
}

/// Hertz's contact duration (s) of a mass `mass` (kg) at `speed` (m/s) on a rigid target
/// through `K [δ]_+^α`: `t_c = 2 (δ_max/v) ∫₀¹ dx/√(1 - x^{α+1})`,
/// `δ_max = ((α+1) M v²/(2K))^{1/(α+1)}` (Johnson 1985, section 11.4; Chaigne & Doutaut
/// 1997, eq. 7).
pub fn hertz_duration(mass: f64, stiffness: f64, exponent: f64, speed: f64) -> f64 {
    let p = exponent + 1.0;
    let delta_max = (p * mass * speed * speed / (2.0 * stiffness)).powf(1.0 / p);
    2.0 * delta_max / speed * hertz_integral(p)
}

/// The felt stiffness `K` (N/m^α) that makes a mass `mass` rest `duration` s on a rigid
/// target at `speed` (the inverse of [`hertz_duration`]: `t_c ∝ K^{-1/(α+1)}`).
pub fn felt_stiffness(mass: f64, exponent: f64, speed: f64, duration: f64) -> f64 {
    let at_one = hertz_duration(mass, 1.0, exponent, speed);
    (at_one / duration).powf(exponent + 1.0)
}

/// Hertz's `K = (4/3) E* √R` (N/m^1.5) of a sphere of radius `radius` (m), modulus `e` (Pa)
/// and Poisson ratio `nu` on a flat of [`PLATE_STEEL`].
pub fn hertz_stiffness(e: f64, nu: f64, radius: f64) -> f64 {
    let (e2, nu2) = PLATE_STEEL;
    let e_star = 1.0 / ((1.0 - nu * nu) / e + (1.0 - nu2 * nu2) / e2);
    4.0 / 3.0 * e_star * radius.sqrt()
}

impl MalletHead {
    /// Every factory head, soft to hard.
    pub const ALL: [MalletHead; 5] = [
        MalletHead::SoftFelt,
        MalletHead::HardFelt,
        MalletHead::Rubber,
        MalletHead::Wood,
        MalletHead::Metal,
    ];

    /// The head's name in scenes (`soft-felt`, `hard-felt`, `rubber`, `wood`, `metal`).
    pub fn name(self) -> &'static str {
        HEAD_NAMES[self as usize]
    }

    /// The head called `name`; the error names `field`, the value and the names allowed.
    pub fn from_name(field: &str, name: &str) -> Result<Self, ParamError> {
        Self::ALL
            .into_iter()
            .find(|h| h.name() == name)
            .ok_or_else(|| {
                ParamError::new(field, name, format!("one of {}", HEAD_NAMES.join(", ")))
            })
    }

    /// The head's mass and contact law (module doc).
    pub fn law(self) -> HeadLaw {
        let felt = |mass: f64, duration: f64, loss: f64| HeadLaw {
            mass,
            stiffness: felt_stiffness(mass, FELT_EXPONENT, FELT_DESIGN_SPEED, duration),
            exponent: FELT_EXPONENT,
            loss,
        };
        let solid = |mass: f64, (e, nu): (f64, f64), loss: f64| HeadLaw {
            mass,
            stiffness: hertz_stiffness(e, nu, HEAD_RADIUS),
            exponent: 1.5,
            loss,
        };
        match self {
            MalletHead::SoftFelt => felt(0.3, 0.010, 0.2),
            MalletHead::HardFelt => felt(0.15, 0.002, 0.1),
            MalletHead::Rubber => solid(0.1, (2e6, 0.49), 0.2),
            MalletHead::Wood => solid(0.05, (11e9, 0.35), 0.02),
            MalletHead::Metal => solid(0.1, PLATE_STEEL, 0.01),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hertz_integral_matches_the_harmonic_case() {
        // p = 2: ∫ dx/√(1-x²) = π/2, so t_c = π √(M/K), half a period of the linear spring.
        assert!((hertz_integral(2.0) - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        let t = hertz_duration(0.1, 1e4, 1.0, 3.0);
        assert!((t / (std::f64::consts::PI * (0.1f64 / 1e4).sqrt()) - 1.0).abs() < 1e-12);
    }

    /// The felts rest their design time on a rigid target; the solid heads are ordered by
    /// stiffness; every name round-trips and a wrong one is named.
    #[test]
    fn heads_have_their_designed_contacts() {
        for (head, want) in [(MalletHead::SoftFelt, 0.010), (MalletHead::HardFelt, 0.002)] {
            let l = head.law();
            let t = hertz_duration(l.mass, l.stiffness, l.exponent, FELT_DESIGN_SPEED);
            assert!((t / want - 1.0).abs() < 1e-12, "{head:?}: {t}");
        }
        let k = |h: MalletHead| h.law().stiffness;
        assert!(k(MalletHead::Rubber) < k(MalletHead::Wood));
        assert!(k(MalletHead::Wood) < k(MalletHead::Metal));
        // Steel on steel: E* = E / 2(1 - ν²).
        let steel = 200e9 / (2.0 * (1.0 - 0.09));
        assert!((k(MalletHead::Metal) / (4.0 / 3.0 * steel * 0.015f64.sqrt()) - 1.0).abs() < 1e-12);
        for h in MalletHead::ALL {
            assert_eq!(MalletHead::from_name("head", h.name()).unwrap(), h);
        }
        let e = MalletHead::from_name("plate.excitation.head", "glass").unwrap_err();
        assert!(e.to_string().contains("glass") && e.to_string().contains("hard-felt"));
    }
}
