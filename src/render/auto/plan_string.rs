//! The candidate ladder of `quality = "auto"` for a string scene: the scene's `modes` and
//! `sim_rate` are the full model; candidates are mode counts whose top mode covers the heard
//! band, up to the full count, each at the scene's rate and at the lowest divisor of it that
//! keeps every mode below the Nyquist limit (with a margin) and at or above the output rate.
//! The contact scheme, law, obstacle, losses, excitation and pickups are the scene's. Nothing
//! is rendered here ([`super::verify`] does that).
//!
//! Runs on the thread that selects the model (CLI main thread); allocates.

use super::ladder::{divisor_rate, Candidate, Plan, HEARING_LIMIT};
use super::size::{string_size, ModelSize};
use crate::error::Error;
use crate::models::string::StringParams;
use crate::scene::plate::Symmetry;
use crate::scene::Scene;
use std::f64::consts::TAU;

/// Multiples of the heard-band mode count `n_hear` tried (each capped at the full count).
pub const HEAR_MULTIPLES: [f64; 5] = [1.0, 1.5, 2.0, 3.0, 4.0];
/// Fractions of the full mode count tried (those at or above `n_hear`).
pub const FULL_FRACTIONS: [f64; 3] = [0.5, 0.75, 1.0];
/// A reduced rate must exceed `NYQUIST_MARGIN × 2 f_max` of its candidate: docs/ACCURACY.md
/// ("The lecture's sitar: simulation rate") finds the buzz converging only once the top mode
/// is below the Nyquist limit (modes above it alias and the contact feeds them back into the
/// audible band); 10 % keeps the top mode clear of it.
pub const NYQUIST_MARGIN: f64 = 1.1;

/// Frequency of mode `n` of the string (Hz): `f_n = n f_1 √(1 + B n²)`, the closed form of
/// the stiff string's exact linear part (`StringParams::omega`, SEED.md 3.2).
pub fn mode_hz(p: &StringParams, n: usize) -> f64 {
    p.omega(n) / TAU
}

/// The smallest mode count whose top mode reaches `f` (Hz), or `None` above `max` modes.
pub fn modes_to_cover(p: &StringParams, f: f64, max: usize) -> Option<usize> {
    // f_n increases with n: bisection on [1, max].
    if mode_hz(p, max) < f {
        return None;
    }
    let (mut lo, mut hi) = (1usize, max);
    while lo < hi {
        let mid = (lo + hi) / 2;
        if mode_hz(p, mid) >= f {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    Some(lo)
}

/// The smallest mode count `≥ n` whose grid (`n + 1` intervals) has a fast sine transform,
/// capped at `full` (the full count is always allowed).
fn fast_count(n: usize, full: usize) -> usize {
    (StringParams::smooth_intervals(n + 1) - 1).min(full)
}

/// Estimated work per simulated second: `fs N log2(N + 1)` (one sine transform pair per
/// step; the contact's Newton work on the bridge nodes is left out). Ordering only: the
/// verification measures time.
pub fn string_cost(s: &ModelSize) -> f64 {
    let n = s.n_phi as f64;
    s.sim_rate * n * (n + 1.0).log2().max(1.0)
}

/// Builds the ladder for `scene` (a validated string scene).
pub fn plan_string(scene: &Scene) -> Result<Plan, Error> {
    let st = scene
        .string
        .as_ref()
        .ok_or(Error::WrongModel("plan_string needs a string scene"))?;
    let p = st.params();
    let full_n = st.modes;
    let full = string_size(full_n, st.sim_rate, mode_hz(&p, full_n));
    let out_rate = scene.output.sample_rate as f64;
    let f_hear = (0.5 * out_rate).min(HEARING_LIMIT);
    let mut reasons = vec![format!(
        "heard band: f_hear = min(output Nyquist {:.0} Hz, 20 kHz) = {f_hear:.0} Hz; the full \
         model's {full_n} modes reach {:.0} Hz (f_n = n f_1 sqrt(1 + B n^2), f_1 = {:.2} Hz, \
         B = {:e})",
        0.5 * out_rate,
        full.f_max_hz,
        mode_hz(&p, 1),
        p.inharmonicity()
    )];
    let n_hear = modes_to_cover(&p, f_hear, full_n);
    let counts: Vec<usize> = match n_hear {
        None => {
            reasons.push(format!(
                "modes: the full model does not reach f_hear, so every candidate keeps its \
                 {full_n} modes"
            ));
            vec![full_n]
        }
        Some(nh) => {
            let mut c: Vec<usize> = HEAR_MULTIPLES
                .iter()
                .map(|m| (m * nh as f64).ceil() as usize)
                .chain(
                    FULL_FRACTIONS
                        .iter()
                        .map(|f| (f * full_n as f64).ceil() as usize),
                )
                .filter(|&n| n >= nh && n <= full_n)
                .map(|n| fast_count(n, full_n))
                .collect();
            c.sort_unstable();
            c.dedup();
            reasons.push(format!(
                "modes: {nh} modes cover f_hear; ladder 1, 1.5, 2, 3, 4 x {nh} and 1/2, 3/4, all \
                 of {full_n}, never above {full_n}, each rounded up to a fast sine-transform \
                 grid -> modes in {c:?} (with a bridge the contact couples every mode, so the \
                 buzz may need them all: docs/ACCURACY.md, verified below)"
            ));
            c
        }
    };
    reasons.push(format!(
        "rate: each count at the scene's {} Hz and at the lowest divisor of it with fs >= \
         max({NYQUIST_MARGIN} x 2 f_max, output rate {out_rate} Hz) (every mode below the \
         Nyquist limit: the buzz aliases otherwise); contact scheme `{}` kept",
        st.sim_rate, st.contact_scheme
    ));
    let mut candidates = Vec::new();
    let mut skipped = Vec::new();
    for &n in &counts {
        let f_max = mode_hz(&p, n);
        let low = divisor_rate(st.sim_rate, (NYQUIST_MARGIN * 2.0 * f_max).max(out_rate));
        let mut rates = vec![st.sim_rate];
        if low < st.sim_rate {
            rates.insert(0, low);
        }
        for rate in rates {
            if n == full_n && rate == st.sim_rate {
                continue;
            }
            let size = string_size(n, rate, f_max);
            if let Err(e) = size.apply(scene) {
                skipped.push(format!("{}: {e}", size.label()));
                continue;
            }
            candidates.push(Candidate {
                estimated_cost: string_cost(&size),
                size,
                band_fraction: f_max / f_hear,
                psi_fraction: 1.0,
            });
        }
    }
    if !skipped.is_empty() {
        reasons.push(format!(
            "skipped (not a valid scene, e.g. a bridge shorter than one grid spacing): {}",
            skipped.join("; ")
        ));
    }
    candidates.sort_by(|a, b| a.estimated_cost.total_cmp(&b.estimated_cost));
    Ok(Plan {
        full,
        symmetry: Symmetry::Full,
        f_hear,
        reasons,
        candidates,
    })
}
