//! Physical models, each runnable as a [`crate::models::source::RenderSource`]:
//!
//! - [`plate`]: modal von Kármán plate (gongs, plates; SEED.md section 3.1);
//! - [`string`]: stiff string against a unilateral obstacle (sitar, tanpura), modal exact
//!   linear scheme with an energy-conserving contact force (SEED.md section 3.2);
//! - [`network`]: strings seated on a moving bridge, coupled both ways through it (tanpura
//!   drone, sympathetic strings);
//! - [`tanpura`]: the tanpura drone on that network (tunings, tuning by ear, pluck cycle);
//! - [`sitar`]: the sitar's played string and its taraf of sympathetic strings on it.

pub mod network;
pub mod plate;
pub mod quantity;
pub mod ranges;
pub mod sav_relaxation;
pub mod sitar;
pub mod source;
pub mod string;
pub mod tanpura;

/// Magnitude below which the models set a modal state value to exactly zero after each step
/// (in the state's own units: m² for the plate's `q`, m^3/2 for the string's `q` and `Δ`).
///
/// Why: a decaying voice's modal state falls exponentially, and once values enter the
/// subnormal range (below 2.2e-308) x86-64 multiplies and adds on them take a microcode assist
/// of about a hundred cycles each, which can make a step of a silent voice many times slower
/// than a loud one. A step and its energy form products of up to four state values (the
/// plate's in-plane energy is quadratic in `η ∝ q²`) with coefficients, so the threshold keeps
/// those far above the subnormal range: `(1e-60)⁴ = 1e-240`, and coefficients down to 1e-60
/// still leave a normal number. Physically it is nothing: audible amplitudes are 1e-9 to 1e-3
/// and 1e-60 is fifty orders below hearing; the energy a flush removes is of order
/// `ω² · 1e-120` J, far below the round-off of any audible state, so the energy balances are
/// unaffected (checked in `tests/robustness/denormals.rs`). Chosen over setting the CPU's flush-to-zero
/// flag because that is per-thread, platform-specific state the engine would have to set and
/// restore around every host callback, and it would not cover the offline renderer.
pub const FLUSH_TO_ZERO_BELOW: f64 = 1e-60;

/// Sets every `|x| < FLUSH_TO_ZERO_BELOW` in `values` to `0.0` (NaN and infinities are kept, so
/// divergence stays detectable). Audio thread: one compare per value, no allocation.
#[inline]
pub fn flush_tiny(values: &mut [f64]) {
    for x in values {
        if x.abs() < FLUSH_TO_ZERO_BELOW {
            *x = 0.0;
        }
    }
}

/// `Σ a_i b_i` over the shorter length, with four independent partial sums (breaks the
/// floating-point add dependency chain, so the compiler can keep several multiply-adds in
/// flight; ~3-4× faster than a single running sum on the coupling kernels and the string's
/// modal pickups). Any thread, no allocation.
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut acc = [0.0f64; 4];
    let (ac, bc) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ar, br) = (ac.remainder(), bc.remainder());
    for (x, y) in ac.zip(bc) {
        acc[0] += x[0] * y[0];
        acc[1] += x[1] * y[1];
        acc[2] += x[2] * y[2];
        acc[3] += x[3] * y[3];
    }
    let tail: f64 = ar.iter().zip(br).map(|(x, y)| x * y).sum();
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}
