//! A band-limited [`super::StiffString`]: only the modes below a frequency are stepped, and its point
//! contact and seat are solved against the modal compliance of those modes.
//!
//! # Why
//! The exact scheme steps any mode exactly, but a stiff string's modes climb far above the
//! Nyquist frequency (a drone string of 480 modes reaches 137-163 kHz), and its couplings
//! (seat, jawari, bridge) are sampled: a mode above the Nyquist frequency answers a sampled
//! force at an aliased frequency, and each such mode adds the compliance `h²/μ` of a free mass
//! to the contact point where its true, stiffness-dominated compliance is `1/(μω²)`, far
//! smaller (docs/models.md, "The drone's grid and rate"). Dropping those modes keeps the
//! grid, so the jivari stays where the player put it and the contact law's `Δx` with it,
//! while every mode that sounds lies below the Nyquist frequency.
//!
//! # Scheme
//! With `m < N` modes stepped, a force density `f_p` at node `p` moves node `r` by
//! `c_{rp} f_p` within the step, `c_{rp} = k Δx Σ_{j ≤ m} φ_j(x_r) φ_j(x_p)` (`k = h²/μ`; the
//! modal correction `Δ_j += k Δx φ_j(x_p) f_p` read back through `u_r = Σ_j φ_j(x_r) q_j`).
//! With all modes `c_{rp} = k δ_{rp}` (the sine transform's orthogonality), the full string's
//! per-node solve. A band-limited string has at most one obstacle node `a` (a point jawari)
//! and its seat `t`, so the step's coupled system is two unknowns, the seat's linear:
//! - seat: `f_t = -κ(u_t^{n+1} - λ + w^{n-1})`, `κ = K/(2Δx)`, and
//!   `u_t^{n+1} = u_t^{free} + c_{tt} f_t + c_{ta} f_a` give `f_t = s_0 - σ c_{ta} f_a` with
//!   `σ = κ/(1 + κ c_{tt})`, `s_0 = -σ(u_t^{free} - λ + w^{n-1})`;
//! - contact: `u_a^{n+1} = u_a^{free} + c_{at} s_0 + k_e f_a`, `k_e = c_{aa} - σ c_{at}²`
//!   (a Schur complement of the positive definite compliance, so `k_e > 0`), which is the
//!   full string's scalar equation `r + k_e Φ(r) = b` with `u^{free}` and `k` replaced: the
//!   same safeguarded Newton solve.
//!
//! The string's force on itself is `F = Δx (f_a + f_t)`, and for the bridge's Newton
//! iteration `dF/dλ = Δx (σ + Φ'(1 - σ c_{at})²/(1 + k_e Φ'))` (`Φ'` the discrete gradient's
//! slope at the solution). The forces are the same discrete gradients as on the full string,
//! applied through the same modal map that reads the displacements, so the energy proof of
//! [`crate::models::network`] holds unchanged: conserved to round-off without losses.
//!
//! A retune moves the modes; the stepped count follows the limit at every retune (a mode
//! that climbs over the limit is dropped, its energy booked with the retune's work).
//!
//! The first `StiffString::set_band_limit` allocates the compliance columns (control thread,
//! at the network's build); a later one, a retune and the solve allocate nothing.

/// The band limit of a [`super::StiffString`] and the compliances of its stepped modes.
///
/// Owned by the string's stepping thread.
#[derive(Debug, Clone)]
pub(crate) struct BandLimit {
    /// Highest mode frequency stepped (Hz, exclusive).
    pub(crate) hz: f64,
    /// Modes stepped, `m` (the lowest ones).
    pub(crate) stepped: usize,
    /// Whether `stepped` and the compliances have been applied to the string once.
    pub(crate) applied: bool,
    /// Per stored row `r`: `c_{ra}` (m per N/m; the obstacle node's column, 0 without one).
    pub(crate) contact_col: Vec<f64>,
    /// Per stored row `r`: `c_{rt}` (the seat's column, 0 without a seat).
    pub(crate) seat_col: Vec<f64>,
}
