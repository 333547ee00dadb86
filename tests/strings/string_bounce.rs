//! Contact against an independent closed form: a single-mode string bouncing on a point
//! obstacle at its rest height.
//!
//! With `N = 2` intervals the string has one mode and one interior node, at `x = L/2`; a point
//! obstacle there at height 0 is met whenever the node goes below its rest position. Written in
//! the node displacement `u = u(L/2)` (mode shape `sin(πx/L)`), the kinetic energy is
//! `μ (L/2) u̇²/2`, the linear potential `μ (L/2) ω₁² u²/2` and the contact energy
//! `Δx K [-u]_+^{α+1}/(α+1)` with `Δx = L/2`: an oscillator of frequency
//! `ω₁ = (π c / L) √(1 + B)` (`c = √(T/μ)`) against a one-sided spring `(K/μ) [-u]_+^α`.
//!
//! For `α = 1` this is the bilinear oscillator, periodic with period
//! `P = π/ω₁ + π/ω_c`, `ω_c = √(ω₁² + K/μ)` (half a free period above the rest line, half a
//! contact period below it: Shaw & Holmes, "A periodically forced piecewise linear oscillator",
//! J. Sound Vib. 90, 1983, sec. 2). As `K → ∞` the contact half vanishes and `P → T/2`, half the
//! free period `T = 2π/ω₁`: the oscillator against a rigid wall at its equilibrium (the impact
//! oscillator of `tests/schemes/oscillators.rs` with zero gap). The deviation from `T/2` is the
//! contact time over `T/2`, `ω₁/ω_c ≈ ω₁ √(μ/K)`, the `O(K^{-1/(α+1)})` penalty error; for
//! `α = 1.5` the same argument (contact time of a Hertz-like law,
//! `t_c ∝ (μ/K)^{1/(α+1)} v^{(1-α)/(1+α)}`, Hunt & Crossley, J. Appl. Mech. 42, 1975) gives a
//! deviation falling as `K^{-0.4}`.
//!
//! The data are the lecture's string's (L = 1 m, T = 180.5 N, μ = 1.17e-3 kg/m, B = 2e-5), the
//! motion starts from a 1 mm pluck at the node (above the obstacle) at rest, the period is
//! measured from the node's displacement with the crossing estimator
//! (`analysis::frequency::measure`) over 40 bounces. The frequencies are computed here from
//! `T, μ, B`, not read from the model.

use noether::analysis::frequency::measure;
use noether::models::string::{
    ContactLaw, Losses, Obstacle, OutputChannel, Quantity, Readout, StiffString, Stiffness,
    StringConfig, StringParams, TrianglePluck,
};
use noether::render::source::RenderSource;
use std::f64::consts::PI;

const LENGTH: f64 = 1.0;
const TENSION: f64 = 180.5;
const DENSITY: f64 = 1.17e-3;
const B: f64 = 2e-5;

/// `ω₁ = (π c / L) √(1 + B)` in rad/s.
fn omega1() -> f64 {
    PI * (TENSION / DENSITY).sqrt() / LENGTH * (1.0 + B).sqrt()
}

/// Period (s) of the single-mode string against the point obstacle at rest height, contact law
/// `(K, α)`, simulated at `fs` for 40 bounces.
fn bounce_period(k: f64, alpha: f64, fs: f64) -> f64 {
    let config = StringConfig {
        params: StringParams {
            length: LENGTH,
            tension: TENSION,
            linear_density: DENSITY,
            stiffness: Stiffness::Inharmonicity(B),
            diameter: 0.43e-3,
            intervals: 2,
            sample_rate: fs,
        },
        losses: Losses::None,
        obstacle: Obstacle::Point {
            position: 0.5 * LENGTH,
            height: 0.0,
            width: 0.0,
        },
        contact: ContactLaw {
            stiffness: k,
            exponent: alpha,
        },
        outputs: vec![OutputChannel::Pickup {
            position: 0.5 * LENGTH,
            quantity: Quantity::Displacement,
            readout: Readout::Grid,
        }],
    };
    let mut s = StiffString::new(&config).unwrap();
    s.pluck(&TrianglePluck {
        position: 0.5 * LENGTH,
        amplitude: 1e-3,
    })
    .unwrap();
    let n = (40.5 * PI / omega1() * fs).ceil() as usize;
    let mut out = vec![vec![0.0; n]];
    s.process(&mut out, n);
    measure(&out[0], 1.0 / fs).expect("bounces").period
}

/// α = 1, `K = μ ω₁² (r² - 1)` so that `ω_c = r ω₁`, for r = 10, 100, 1000 at a contact
/// resolution `ω_c h = 0.03`, and r = 100 at `ω_c h = 0.015`.
///
/// Against the bilinear closed form `P = π/ω₁ + π/ω_c`: the linear part of the scheme is exact,
/// so the error is the contact half's, `(P - π/ω₁)/(π/ω_c) - 1`, second order in `ω_c h` (the
/// discrete gradient of a linear spring is the trapezoid rule, plus the sub-step onset and end of
/// contact). Measured: 1.85e-4 / 1.875e-4 / 1.875e-4 at `ω_c h = 0.03` (0.208 (ω_c h)²) and
/// 4.69e-5 at 0.015 (exactly a quarter, printed). Tolerance: `0.25 (ω_c h)²`, the measured
/// coefficient plus 20 %, so a first-order error (a contact force at the wrong time level) or a
/// wrong stiffness (`K/μ` off by 1 % moves `ω_c` by 0.5 %, 25 times the bound at r = 100) fails.
///
/// Against the rigid wall: `P/(T/2) - 1` must lie in `(0, 1.001/r]`, the penalty error
/// `ω₁/ω_c ≈ ω₁√(μ/K) = O(K^{-1/2})` (measured `1.000187/r`: the same `ω_c h` error).
#[test]
fn linear_penalty_bounce_matches_the_bilinear_closed_form_and_the_rigid_limit() {
    let w1 = omega1();
    let half = PI / w1;
    for (r, wch) in [(10.0, 0.03), (100.0, 0.03), (1000.0, 0.03), (100.0, 0.015)] {
        let k = DENSITY * w1 * w1 * (r * r - 1.0);
        let wc = r * w1;
        let fs = wc / wch;
        let p = bounce_period(k, 1.0, fs);
        let closed = half + PI / wc;
        let contact_error = (p - half) / (PI / wc) - 1.0;
        let rigid = p / half - 1.0;
        eprintln!(
            "alpha 1, K {k:.4e} (omega_c/omega_1 = {r}, omega_c h = {wch}): P {p:.12e} s, \
             bilinear {closed:.12e} s, contact half error {contact_error:.3e}, \
             P/(T/2) - 1 = {rigid:.6e}"
        );
        assert!(
            contact_error.abs() < 0.25 * wch * wch,
            "r {r}: contact half error {contact_error:e}"
        );
        assert!(
            rigid > 0.0 && rigid <= 1.001 / r,
            "r {r}: P/(T/2) - 1 = {rigid:e}"
        );
    }
}

/// Contact time of the impact at speed `v` on the one-sided law `(K/μ) η^α` (per unit mass),
/// the linear restoring force neglected (its share of the force at the deepest point,
/// `ω₁² η_m / ((K/μ) η_m^α)`, is 3.8e-4 at K = 1e9, 1e-5 at 1e11, 2e-7 at 1e13):
/// `t_c = 2 (η_m / v) ∫₀¹ ds / √(1 - s^{α+1})`, `η_m = ((α+1) μ v² / (2K))^{1/(α+1)}`
/// (energy conservation during the contact; Hunt & Crossley 1975). The integral is taken with
/// `s = 1 - t²` (regular integrand) by Simpson's rule on 2000 intervals (error ~1e-12).
fn hertz_contact_time(k: f64, alpha: f64, v: f64) -> f64 {
    let p = alpha + 1.0;
    let eta_m = (p * DENSITY * v * v / (2.0 * k)).powf(1.0 / p);
    let f = |t: f64| {
        if t == 0.0 {
            2.0 / p.sqrt()
        } else {
            2.0 * t / (1.0 - (1.0 - t * t).powf(p)).sqrt()
        }
    };
    let n = 2000;
    let dt = 1.0 / n as f64;
    let sum: f64 = (0..=n)
        .map(|i| {
            let w = if i == 0 || i == n {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            w * f(i as f64 * dt)
        })
        .sum();
    2.0 * eta_m / v * sum * dt / 3.0
}

/// α = 1.5 (K = 1e9, 1e11, 1e13): the period against `π/ω₁ + t_c` (free half-period plus the
/// Hertz-law contact time above, impact speed `v = ω₁ A`, A = 1 mm) and the deviation from the
/// rigid-wall period `T/2`, `t_c/(T/2) ∝ K^{-1/(α+1)} = K^{-0.4}`. The rate resolves each
/// contact with about 100 steps (`fs = 100/t_c`). Measured contact-time errors (printed):
/// 9.3e-5, 2.5e-4, 2.5e-4 (the time step's, plus the neglected linear force at K = 1e9).
/// Tolerance 1e-3 relative on `t_c`, four times the worst: a 1 % error in K moves `t_c` by
/// 0.4 %. The log-log slopes of the deviation from `T/2` between successive K must be -0.4
/// within 0.002 (measured -0.39997 and -0.399999).
#[test]
fn hertz_penalty_bounce_matches_the_contact_time_and_tends_to_the_rigid_limit() {
    let w1 = omega1();
    let half = PI / w1;
    let v = w1 * 1e-3;
    let mut devs = Vec::new();
    for k in [1e9, 1e11, 1e13] {
        let tc = hertz_contact_time(k, 1.5, v);
        let fs = 100.0 / tc;
        let p = bounce_period(k, 1.5, fs);
        let tc_error = (p - half) / tc - 1.0;
        let rigid = p / half - 1.0;
        eprintln!(
            "alpha 1.5, K {k:e}, fs {fs:.3e}: t_c {tc:.6e} s, measured {:.6e} s (rel {tc_error:.2e}), \
             P/(T/2) - 1 = {rigid:.6e}",
            p - half
        );
        assert!(
            tc_error.abs() < 1e-3,
            "K {k:e}: contact time error {tc_error:e}"
        );
        devs.push(rigid);
    }
    let slopes: Vec<f64> = devs
        .windows(2)
        .map(|d| (d[1] / d[0]).log10() / 2.0)
        .collect();
    eprintln!("log-log slopes of P/(T/2) - 1 against K: {slopes:?}");
    for s in slopes {
        assert!((s + 0.4).abs() < 2e-3, "slope {s}");
    }
}
