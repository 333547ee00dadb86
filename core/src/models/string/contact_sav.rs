//! The energy-quadratised (scalar auxiliary variable) contact: a linearly implicit,
//! non-iterative alternative to the discrete-gradient Newton solve of [`super::contact`].
//!
//! After M. Ducceschi, S. Bilbao, S. Willemsen, S. Serafin, "Linearly-implicit schemes for
//! collisions in musical acoustics based on energy quadratization", JASA 149(5), 2021 (and
//! M. Ducceschi, S. Bilbao, "Non-iterative solvers for nonlinear problems: the case of
//! collisions", DAFx-19).
//!
//! # Quadratisation
//! The contact potential `ψ(η) = K/(α+1) [η]_+^{α+1} ≥ 0` (J/m) is written as a square,
//! `ψ = z²/2` with `z = √(2ψ(η))` (√(J/m)), so `ψ'(η) = z g(η)` with
//! `g = dz/dη = ψ'(η)/√(2ψ(η))`. For the power law this is, where `η > 0`,
//! `g(η) = K η^α / √(2K η^{α+1}/(α+1)) = √(K(α+1)/2) η^{(α-1)/2}`  (√(N/m)/m),
//! and `g = 0` where `η ≤ 0` (there `ψ' = 0`: a regularised `g = ψ'/√(2ψ + ε)`, the usual
//! guard of quadratised schemes, is exactly 0 for any `ε > 0`, and this is its `ε → 0` limit). For `α ≥ 1` (the range [`ContactLaw`]
//! accepts) the exponent `(α-1)/2 ≥ 0`, so `g` is bounded near `η = 0⁺` (`→ 0` for `α > 1`,
//! `√K` for `α = 1`) and is evaluated in closed form: no `0/0`, no regularisation `ε` needed.
//! (`α < 1` would make `g` blow up as `η → 0⁺`; that is where an `ε > 0` is required.)
//!
//! # Scheme (per obstacle node i, with `k = h²/μ` as in [`super`])
//! `z_i` lives at half steps. With `g_i = g(η_i^n)` from the current state,
//! - `z^{n+1/2} - z^{n-1/2} = g_i (η^{n+1} - η^{n-1}) / 2`   (`δ_{t-} z = g δ_{t·} η`),
//! - `f_i^n = g_i (z^{n+1/2} + z^{n-1/2}) / 2`                 (`f = g μ_{t·} z ≈ ψ'(η)`).
//!
//! The node's update is `η^{n+1} = η_free - k f` (module doc of [`super`]), so with
//! `r = η^{n+1} - η^{n-1}`, `b = η_free - η^{n-1}`:
//! `r = b - k g (z⁻ + g r/4)`, i.e. **`r = (b - k g z⁻) / (1 + k g²/4)`**,
//! then `z⁺ = z⁻ + g r/2` and `f = g (z⁻ + g r/4)`; it is computed through the mean
//! `w = (z⁺ + z⁻)/2 = (z⁻ + g b/4)/(1 + k g²/4)` ([`solve_point_quadratised`]). One division per node: no iteration, no
//! tolerance, no cap, and the denominator is `≥ 1` for every state, so the solution exists
//! and is unique at any `K`, `α`, `h`.
//!
//! # Conserved energy
//! The linear part's identity is unchanged (module doc of [`super`]):
//! `δ_{t-} H_lin^{n+1/2} + dissipation = Σ_j F_j δ_{t·}q_j = Δx Σ_i f_i δ_{t·} u_i`.
//! With `δ_{t·} u_i = -δ_{t·} η_i` and the two update lines above,
//! `f_i δ_{t·} u_i = -g_i μ_{t·}z_i δ_{t·}η_i = -μ_{t·}z_i δ_{t-}z_i^{n+1/2} = -δ_{t-}(z_i²/2)`
//! (also when `g_i = 0`: then `f_i = 0` and `z_i` does not change). Hence
//! `H_q^{n+1/2} = H_lin^{n+1/2} + Δx Σ_i (z_i^{n+1/2})²/2` (kinetic + potential + contact)
//! is exactly conserved without losses, and with losses `H_q + dissipated (- work)` is.
//! The contact term is a square, so `H_q ≥ 0` and the scheme is unconditionally stable.
//!
//! # What the quadratisation costs
//! `z` is an independent variable: it equals `√(2ψ(η))` only up to the scheme's consistency
//! error. In particular, when a node leaves the obstacle `g` drops to 0 and `z` freezes at
//! whatever the last increment left, generally not 0; that energy stays in the contact term
//! (it is conserved, not lost) and `f = g μ_{t·}z` may be slightly negative (attractive) in the
//! first steps of the next contact if `z` froze below 0. By default this implementation keeps
//! `z` as the scheme defines it, so `H_q` is conserved exactly; a relaxation of the `z` of
//! nodes off the obstacle toward 0, with the energy it removes counted as dissipation, is
//! available (`StiffString::set_sav_relaxation`, [`crate::models::sav_relaxation`]; off by
//! default: measured in docs/models.md, "Long performances"). The gap `Δx Σ (z²/2 - ψ)` is reported
//! ([`crate::models::string::StiffString::quadratisation_gap`]). Measured (docs/ACCURACY.md):
//! on the lossless sitar at 2 MHz the gap stays below 7.5e-4 of H and the bridge force dips to
//! -0.7 N against peaks of 2-4 N. A second cost: at low rates the force `g μ_{t·}z` is bounded
//! by the energy in `z`, not by `ψ'(η)`, so the contact is soft (sitar at 48 kHz: 120 µm of
//! penetration against Newton's 0.87 µm). Against Newton the scheme converges with order about
//! 1.5 for a resolved contact (K = 1e9; the onset and release are not smooth) and agrees to
//! 1.4e-4 (L2, first 50 ms) on the lecture's sitar at 4 MHz.
//!
//! Initial value: `z^{1/2} = √(ψ(η^1) + ψ(η^0))`, so `H_q` starts equal to the Newton scheme's
//! `H` (whose contact term is `Δx Σ (ψ(η^{n+1}) + ψ(η^n))/2`).
//!
//! Runs on the audio thread: no allocation, O(1) per obstacle node.

use super::contact::ContactLaw;
use crate::error::ParamError;

/// How the string's contact force is computed.
///
/// Chosen on the control thread (scene or API); read by the audio thread in `step`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ContactScheme {
    /// The lecture's discrete-gradient force `(ψ(η^{n+1}) - ψ(η^{n-1}))/(η^{n+1} - η^{n-1})`,
    /// solved per node by capped safeguarded Newton ([`super::contact`]); conserves `H`.
    #[default]
    NewtonDiscreteGradient,
    /// The energy-quadratised force of this module: closed form per node; conserves `H_q`.
    Quadratised,
}

impl ContactScheme {
    /// Every scheme, in the order of [`ContactScheme::name`]'s list.
    pub const ALL: [ContactScheme; 2] = [
        ContactScheme::NewtonDiscreteGradient,
        ContactScheme::Quadratised,
    ];

    /// The scene name: `"newton"` or `"quadratised"`.
    pub fn name(self) -> &'static str {
        match self {
            ContactScheme::NewtonDiscreteGradient => "newton",
            ContactScheme::Quadratised => "quadratised",
        }
    }

    /// Parses a scene name; the error names `field`, the value and the allowed names.
    pub fn parse(field: &str, value: &str) -> Result<Self, ParamError> {
        Self::ALL
            .into_iter()
            .find(|s| s.name() == value)
            .ok_or_else(|| {
                ParamError::new(field, format!("{value:?}"), "\"newton\" or \"quadratised\"")
            })
    }
}

impl ContactLaw {
    /// `g(η) = ψ'(η)/√(2ψ(η)) = √(K(α+1)/2) [η]_+^{(α-1)/2}` in √(N/m)/m, 0 for `η ≤ 0`
    /// (see the module doc; bounded for `α ≥ 1`).
    pub fn quadratised_slope(&self, eta: f64) -> f64 {
        if eta > 0.0 {
            let a = self.exponent;
            (0.5 * self.stiffness * (a + 1.0)).sqrt() * eta.powf(0.5 * (a - 1.0))
        } else {
            0.0
        }
    }
}

/// One node's quadratised update.
///
/// Produced and consumed on the audio thread.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuadratisedPoint {
    /// `r = η^{n+1} - η^{n-1}` in m.
    pub r: f64,
    /// Contact force density `f^n = g (z⁺ + z⁻)/2` in N/m (≥ 0 up to the release effect of
    /// the module doc).
    pub force: f64,
    /// `z^{n+1/2}` in √(J/m).
    pub z: f64,
}

/// Solves the node's linear equation (module doc) with `g = g(η^n)` (`slope`),
/// `z⁻ = z^{n-1/2}` (`z_prev`), `b = η_free - η^{n-1}` (m) and `k = h²/μ`, in the form
/// `w = μ_{t·}z = (z⁻ + g b/4) / (1 + k g²/4)`, `f = g w`, `z⁺ = 2w - z⁻`, `r = b - k f`
/// (the same solution as `r = (b - k g z⁻)/(1 + k g²/4)`, but without the cancellation of
/// `b` against `k g z⁻` when the contact is stiff, `k g² ≫ 1`: the energy identity
/// `f r = z⁺² - z⁻²` then holds to round-off of `w`, not of `b`).
pub fn solve_point_quadratised(slope: f64, z_prev: f64, b: f64, k: f64) -> QuadratisedPoint {
    if slope == 0.0 {
        return QuadratisedPoint {
            r: b,
            force: 0.0,
            z: z_prev,
        };
    }
    let w = (z_prev + 0.25 * slope * b) / (1.0 + 0.25 * k * slope * slope);
    let force = slope * w;
    QuadratisedPoint {
        r: b - k * force,
        force,
        z: 2.0 * w - z_prev,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `g` is `ψ'/√(2ψ)` where `ψ > 0` (to 1e-14, a few ulps of the two `powf` forms), 0 at
    /// and below contact, `√K` just above 0 for `α = 1`.
    #[test]
    fn slope_matches_its_definition() {
        for &(k, a) in &[(1e13, 1.5), (1e3, 1.0), (1e16, 4.0)] {
            let law = ContactLaw {
                stiffness: k,
                exponent: a,
            };
            for &eta in &[1e-9, 3e-6, 1e-3] {
                let want = law.force(eta) / (2.0 * law.psi(eta)).sqrt();
                let got = law.quadratised_slope(eta);
                assert!(
                    (got / want - 1.0).abs() < 1e-14,
                    "{k} {a} {eta}: {got} {want}"
                );
            }
            assert_eq!(law.quadratised_slope(0.0), 0.0);
            assert_eq!(law.quadratised_slope(-1e-3), 0.0);
        }
        let lin = ContactLaw {
            stiffness: 4e6,
            exponent: 1.0,
        };
        assert_eq!(lin.quadratised_slope(1e-300), 2e3);
    }

    /// The closed form solves the node's linear equation `w (1 + k g²/4) = z⁻ + g b/4` to
    /// round-off (4 ulps of its largest term), `z⁺ + z⁻ = 2w`, `f = g w`, and the energy
    /// identity `f r = z⁺² - z⁻²` holds to 1e-14 of its scale `|f b| + z⁺² + z⁻²` (`r = b - k f`
    /// loses the digits `b` and `k f` share when the contact is stiff, which is why `|f b|` is
    /// in the scale), also in an extremely stiff case (`k g² = 1e12`).
    #[test]
    fn closed_form_satisfies_the_update() {
        let eps = f64::EPSILON;
        for &(g, z, b, k) in &[
            (3e5, 1e-2, 1e-7, 2e-10),
            (3e5, -1e-3, -4e-7, 2e-10),
            (1e8, 0.0, 1e-6, 1e-4),
            (1e8, 3e-9, -2e-6, 1e-4),
        ] {
            let p = solve_point_quadratised(g, z, b, k);
            let w = 0.5 * (p.z + z);
            let d = 1.0 + 0.25 * k * g * g;
            let terms = z.abs() + 0.25 * (g * b).abs() + w.abs() * d;
            assert!(
                (w * d - z - 0.25 * g * b).abs() <= 4.0 * eps * terms,
                "{p:?}"
            );
            assert!(
                (p.force - g * w).abs() <= 4.0 * eps * p.force.abs(),
                "{p:?}"
            );
            assert_eq!(p.r, b - k * p.force);
            let (lhs, rhs) = (p.force * p.r, p.z * p.z - z * z);
            let scale = (p.force * b).abs() + p.z * p.z + z * z;
            assert!((lhs - rhs).abs() <= 1e-14 * scale, "{lhs} {rhs} {scale}");
        }
        let free = solve_point_quadratised(0.0, 0.3, 1e-6, 1e-9);
        assert_eq!((free.r, free.force, free.z), (1e-6, 0.0, 0.3));
    }

    #[test]
    fn names_round_trip_and_bad_names_are_refused() {
        for s in ContactScheme::ALL {
            assert_eq!(ContactScheme::parse("f", s.name()).unwrap(), s);
        }
        let e = ContactScheme::parse("string.contact_scheme", "sav").unwrap_err();
        let msg = e.to_string();
        assert!(
            msg.contains("string.contact_scheme") && msg.contains("sav"),
            "{msg}"
        );
    }
}
