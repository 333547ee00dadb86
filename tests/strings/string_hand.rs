//! The player's hand on the stiff string (`core/src/models/string/model/hand_solve.rs`): a point
//! damper at a grid node off the bridge, solved in closed form with the exact modal step. The
//! power balance closes to round-off with the hand's dissipation counted (with the bridge
//! contact under both contact schemes, both synthesis paths, and a force pulse), `c = 0` is the
//! step without the hand bit for bit, and the hand damps a mode at the designed rate. Figures
//! are printed with `--nocapture`.

use noether::models::plate::hand_damping_for_t60;
use noether::models::string::{
    ContactLaw, ContactScheme, GridSynthesis, Losses, Obstacle, StiffString, StrikeForce,
};
use noether_testkit::harness::{lecture_string_with_law, LECTURE_PLUCK};

/// The hand's test position (m): 0.1 L from the nut of the 1 m lecture string, the bridge at
/// the other end.
const HAND_AT: f64 = 0.9;
/// The hand's test coefficient (N·s/m): the fundamental (`φ₁(0.9)² = 0.19` 1/m, `μ = 1.17e-3`
/// kg/m) gets `σ = cφ²/2μ ≈ 16` 1/s, so the hand takes most of the energy in the 0.25 s runs.
const C_HAND: f64 = 0.2;

/// The lecture string at N = 500, 48 kHz, against the sitar bridge, with `losses`, `scheme`
/// and `path`, plucked (1 mm at 0.3 m).
fn plucked(losses: Losses, scheme: ContactScheme, path: GridSynthesis) -> StiffString {
    let mut s = lecture_string_with_law(
        500,
        48_000.0,
        losses,
        Obstacle::seed_sitar(),
        ContactLaw::lecture(),
        scheme,
    );
    assert_eq!(s.set_grid_synthesis(path), path);
    s.pluck(&LECTURE_PLUCK).unwrap();
    s
}

/// Runs 0.25 s with the hand at `c`, a force pulse (−2 N, 1 ms at 0.5 m) struck at 0.1 s;
/// returns the largest balance deviation relative to the largest stored energy, the hand's
/// share of the starting energy and the contact steps. `count_hand = false` subtracts the
/// hand's share from the balance (the deliberately broken bookkeeping).
fn drift(scheme: ContactScheme, path: GridSynthesis, count_hand: bool) -> (f64, f64, u64) {
    let mut s = plucked(Losses::PerMode(vec![1.0; 499]), scheme, path);
    s.set_hand(HAND_AT, C_HAND).unwrap();
    let balance = |s: &StiffString| {
        let e = s.energy_terms();
        e.balance() - if count_hand { 0.0 } else { s.hand_dissipated() }
    };
    let (b0, e0) = (balance(&s), s.energy_terms().total());
    let (mut worst, mut max): (f64, f64) = (0.0, e0);
    for n in 0..12_000 {
        if n == 4800 {
            s.strike(&StrikeForce {
                position: 0.5,
                duration: 1e-3,
                peak: -2.0,
            })
            .unwrap();
        }
        s.step();
        max = max.max(s.energy_terms().total());
        worst = worst.max((balance(&s) - b0).abs());
        assert!(s.hand_dissipated() >= 0.0);
    }
    (
        worst / max,
        s.hand_dissipated() / e0,
        s.contact_stats().contact_steps,
    )
}

/// With the hand (`c = 0.2` N·s/m at 0.9 m), modal damping 1 1/s, the sitar bridge in contact
/// and a force pulse, `H + dissipated - work` stays constant to round-off under both contact
/// schemes and both grid-synthesis paths. Bound 2e-13 relative to the largest stored energy:
/// the random walk of 12 000 steps' rounding of a few `ε` each (`√12000 · 10 ε ≈ 2.4e-13`);
/// measured (`--nocapture`) at most 6.7e-14. The hand takes a large part of the energy (more
/// than the pluck brought: the pulse brings more), so left out of the balance it opens it: the
/// same check then fails (> 1e-2; measured 0.94 to 0.95).
#[test]
fn power_balance_closes_with_the_hand() {
    for scheme in [
        ContactScheme::NewtonDiscreteGradient,
        ContactScheme::Quadratised,
    ] {
        for path in [GridSynthesis::Rows, GridSynthesis::Dst] {
            let (d, taken, contacts) = drift(scheme, path, true);
            let (broken, ..) = drift(scheme, path, false);
            println!(
                "{scheme:?} {path:?}: balance {d:.2e}, hand took {taken:.2} of the pluck, \
                 {contacts} contact steps, without its share {broken:.2e}"
            );
            assert!(d < 2e-13, "{scheme:?} {path:?}: {d:e}");
            assert!(taken > 0.3 && contacts > 100, "{taken} {contacts}");
            assert!(broken > 1e-2, "{broken:e}");
        }
    }
}

/// `c = 0` is the step without the hand bit for bit (the hand path is skipped): twins, one
/// with the hand placed at `c = 0`, agree in every bit of `q` and of the energy balance for
/// 6000 steps with contact and a pulse. The comparison is sensitive: a hand of `c = 1e-9`
/// N·s/m breaks it.
#[test]
fn zero_hand_is_the_plain_step_bit_for_bit() {
    let run = |c: f64| {
        let mut a = plucked(
            Losses::PerMode(vec![1.0; 499]),
            ContactScheme::NewtonDiscreteGradient,
            GridSynthesis::Rows,
        );
        let mut b = plucked(
            Losses::PerMode(vec![1.0; 499]),
            ContactScheme::NewtonDiscreteGradient,
            GridSynthesis::Rows,
        );
        a.set_hand(HAND_AT, c).unwrap();
        let mut same = true;
        for n in 0..6000 {
            if n == 100 {
                let f = StrikeForce {
                    position: 0.5,
                    duration: 1e-3,
                    peak: -2.0,
                };
                a.strike(&f).unwrap();
                b.strike(&f).unwrap();
            }
            a.step();
            b.step();
            same &= a
                .modal_displacement()
                .iter()
                .zip(b.modal_displacement())
                .all(|(x, y)| x.to_bits() == y.to_bits())
                && a.energy_terms().balance().to_bits() == b.energy_terms().balance().to_bits();
        }
        same
    };
    assert!(run(0.0), "c = 0 changed the step");
    assert!(!run(1e-9), "the comparison missed c = 1e-9");
}

/// Mode 1's 60 dB decay time (s) on the lossless lecture string without obstacle at N = 100
/// (every mode below 22 kHz, under the Nyquist frequency of 48 kHz), only its fundamental
/// (196 Hz) sounding at the start, the hand at 0.9 m set by `hand_damping_for_t60` (with `μ`
/// for `ρh` and `φ₁(x_h)` in m^-1/2: the same `σ = cφ²/2μ`) for `t60`; and `c`.
fn fundamental_t60(t60: f64) -> (f64, f64) {
    let mut s = lecture_string_with_law(
        100,
        48_000.0,
        Losses::None,
        Obstacle::None,
        ContactLaw::lecture(),
        ContactScheme::NewtonDiscreteGradient,
    );
    let (p, h) = (s.params().clone(), 1.0 / 48_000.0);
    let mut q0 = vec![0.0; 99];
    q0[0] = 1e-4;
    s.set_modal_state(&q0, &[0.0; 99]);
    s.set_hand(HAND_AT, 1.0).unwrap();
    let phi = p.mode_shape(1, s.hand_position());
    let c = hand_damping_for_t60(p.linear_density, phi, t60);
    s.set_hand_damping(c).unwrap();
    let w1 = p.omega(1);
    // Mode 1's energy ½μ((δ_{t-}q)² + ω₁² q(n) q(n-1)) from two consecutive q₁.
    let energy =
        |q: f64, qp: f64| 0.5 * p.linear_density * (((q - qp) / h).powi(2) + w1 * w1 * q * qp);
    let mut prev = s.modal_displacement()[0];
    s.step();
    let e0 = energy(s.modal_displacement()[0], prev);
    let steps = (t60 * 48_000.0).round() as usize;
    for _ in 0..steps {
        prev = s.modal_displacement()[0];
        s.step();
    }
    let drop_db = -10.0 * (energy(s.modal_displacement()[0], prev) / e0).log10();
    (steps as f64 * h * 60.0 / drop_db, c)
}

/// The hand damps the fundamental at the designed rate. In the weak regime (T60 = 3 s: `c` is
/// 3 % of the string's wave impedance `√(Tμ) = 0.46` N·s/m, so the hand barely reflects and
/// barely couples the modes) the measured time is the design within 5 % (measured 3.0007 s).
/// At the engine's full pressure (T60 = 0.15 s at 0.1 L from the nut, `c = 0.56` N·s/m, above
/// `√(Tμ)`) the point damper also reflects waves, outside the perturbation formula: the
/// measured time is within a factor 1.25 of the design (measured 0.161 s). With the factor
/// 2 dropped from the design formula the weak case measures twice the design, and without the
/// hand the mode does not decay: both fail. The string's modes must lie below the Nyquist
/// frequency for the design to hold: at N = 500 (modes to 98 kHz at 48 kHz) the exact scheme
/// aliases the upper modes and the hand, which couples them, damps the fundamental 25 % less
/// (balance still exact, see [`power_balance_closes_with_the_hand`]).
#[test]
fn the_hand_damps_the_fundamental_at_the_designed_rate() {
    let (weak, c_weak) = fundamental_t60(3.0);
    let (full, c_full) = fundamental_t60(0.15);
    println!("weak: c = {c_weak:.4} N·s/m, T60 {weak:.4} s (design 3 s); full: c = {c_full:.4} N·s/m, T60 {full:.4} s (design 0.15 s)");
    assert!((weak / 3.0 - 1.0).abs() < 0.05, "{weak} s");
    assert!(full > 0.15 / 1.25 && full < 0.15 * 1.25, "{full} s");
}

/// The hand must sit off the bridge and inside the string: the errors name the field and the
/// value.
#[test]
fn hand_off_the_bridge_only() {
    let mut s = plucked(
        Losses::None,
        ContactScheme::NewtonDiscreteGradient,
        GridSynthesis::Rows,
    );
    for bad in [0.005, -0.1, 1.0, f64::NAN] {
        let e = s.set_hand(bad, 1.0).unwrap_err().to_string();
        assert!(e.contains("hand_position"), "{e}");
    }
    let e = s.set_hand(HAND_AT, -1.0).unwrap_err().to_string();
    assert!(e.contains("hand_damping") && e.contains("-1"), "{e}");
    assert_eq!(s.hand_damping(), 0.0);
}
