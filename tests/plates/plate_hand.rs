//! The player's hand on the modal plate (`core/src/models/plate/model/hand_solve.rs`): a point damper
//! solved implicitly with every plate scheme, alone, under a force pulse and jointly with a
//! mallet in contact. The power balance closes to round-off with the hand's dissipation
//! counted, `c = 0` is the step without the hand bit for bit, the joint solve is the plate step
//! under the solved mallet force, and the hand damps a mode at the designed rate. Figures are
//! printed with `--nocapture`.

use std::f64::consts::PI;
use std::sync::Arc;

use crate::plate_mallet::{plate, sounding, Rng};
use noether::models::plate::{
    hand_damping_for_t60, DenseCoupling, LinearSolve, Mallet, PickupKind, PickupWeights,
    PlateModel, PlateParams, PlateScheme,
};
use noether_testkit::alloc::allocations;

const ALL: [PlateScheme; 4] = [
    PlateScheme::SavExact,
    PlateScheme::ConservativeExact,
    PlateScheme::ConservativeTheta1,
    PlateScheme::StormerVerletExact,
];

/// The hand's test coefficient (N·s/m): with `ρh = 7.86` and weights ≈ 1/m a mode gets
/// `σ ≈ c Φ²/2ρh ≈ 13` 1/s, so the hand removes a large part of the energy in the 0.2 s runs.
const C_HAND: f64 = 200.0;

/// Hand weights ≈ 1/m, different from the force weights.
fn hand_weights() -> Vec<f64> {
    Rng(21).vec(12).iter().map(|w| 0.8 + 0.6 * w).collect()
}

/// The plate for `scheme` sounding at ≈ 0.2 J with modal damping 3 1/s (nonlinear for the
/// conservative schemes; linear for Störmer-Verlet, whose nonlinear energy is not conserved).
fn sounding_plate(scheme: PlateScheme) -> PlateModel<DenseCoupling> {
    if scheme == PlateScheme::StormerVerletExact {
        let mut p = plate(scheme, 0.0, 3.0, 7.86);
        let q0: Vec<f64> = Rng(5).vec(12).iter().map(|d| 2e-4 * d).collect();
        p.set_state(&q0, &[0.0; 12]).unwrap();
        p
    } else {
        sounding(scheme, 3.0)
    }
}

/// Runs `steps` steps with the hand at `c` and either a mallet re-launched every 1100 steps at
/// 3 m/s or a raised-cosine pulse (peak 300 N, 2 ms) at the start; returns the largest
/// deviation of the (joint) balance from its start relative to the largest stored energy, and
/// the hand's dissipated energy over the stored energy at the start. `count_hand = false`
/// subtracts the hand's share from the balance (the deliberately broken bookkeeping).
fn balance_drift(scheme: PlateScheme, c: f64, with_mallet: bool, count_hand: bool) -> (f64, f64) {
    let mut p = sounding_plate(scheme);
    p.set_hand(&hand_weights(), c).unwrap();
    let mut m = Mallet::new(0.05, 1e9, 2.5, 0.4, p.h()).unwrap();
    let e0 = p.energy().total();
    let balance = |p: &PlateModel<DenseCoupling>, m: &Mallet| {
        let e = p.energy();
        let b = if with_mallet {
            m.energy().joint_balance(&e)
        } else {
            e.balance()
        };
        if count_hand {
            b
        } else {
            b - e.hand_dissipated
        }
    };
    let mut start = None;
    let (mut worst, mut scale): (f64, f64) = (0.0, 0.0);
    let pulse = 88;
    for n in 0..8820 {
        if with_mallet && n % 1100 == 0 {
            p.launch_mallet(&mut m, 3.0).unwrap();
        }
        let base = *start.get_or_insert_with(|| balance(&p, &m));
        if with_mallet {
            p.step_with_mallet(&mut m).unwrap();
        } else {
            let f = if n < pulse {
                150.0 * (1.0 - (2.0 * PI * n as f64 / pulse as f64).cos())
            } else {
                0.0
            };
            p.step(f).unwrap();
        }
        scale = scale.max(p.energy().total() + m.energy().total());
        worst = worst.max((balance(&p, &m) - base).abs());
        assert!(p.energy().hand_dissipated >= 0.0);
    }
    if with_mallet {
        assert!(m.stats().impacts >= 8 && m.stats().solver_failures == 0);
    }
    (worst / scale, p.energy().hand_dissipated / e0)
}

/// With the hand (`c = 200` N·s/m) on a sounding plate, under a force pulse and with a mallet
/// striking 8 times (felt loss on, modal damping 3 1/s), the power balance (stored +
/// dissipated by modes, felt and hand - work - launched) closes to round-off on every scheme.
/// Bound 5e-13 relative to the largest stored energy, as the mallet's lossy balance (the
/// random walk of 8820 steps' rounding of a few `ε` each, `√8820 · 20 ε ≈ 4e-13`;
/// Störmer-Verlet on its linear plate 1.5e-12, as there). Measured (`--nocapture`): at most 9e-14. The hand takes a
/// large part of the energy (hand_dissipated > 10 % of the starting energy). Left out of the
/// balance, the hand's dissipation opens it by that part: the same check then fails (> 1e-2;
/// measured 0.51 to 0.87, also with the bookkeeping removed from the model).
#[test]
fn power_balance_closes_with_the_hand() {
    for scheme in ALL {
        let bound = if scheme == PlateScheme::StormerVerletExact {
            1.5e-12
        } else {
            5e-13
        };
        for with_mallet in [false, true] {
            let (drift, taken) = balance_drift(scheme, C_HAND, with_mallet, true);
            let (broken, _) = balance_drift(scheme, C_HAND, with_mallet, false);
            println!(
                "{scheme:?} mallet {with_mallet}: balance {drift:.2e}, hand took {taken:.2} of \
                 the start, without its share {broken:.2e}"
            );
            assert!(drift < bound, "{scheme:?} {with_mallet}: {drift:e}");
            assert!(taken > 0.1, "{scheme:?} {with_mallet}: {taken}");
            assert!(broken > 1e-2, "{scheme:?} {with_mallet}: {broken:e}");
        }
    }
}

/// `c = 0` is the step without the hand bit for bit (the hand path is skipped), under a pulse
/// and with the mallet, on every scheme: twins (one with hand weights set and `c = 0`, one
/// never given a hand) agree in every bit of `q` and of the energy for 3000 steps. The check
/// is sensitive: a hand of `c = 1e-6` N·s/m on the first twin breaks the equality.
#[test]
fn zero_hand_is_the_plain_step_bit_for_bit() {
    let run = |scheme, c: f64| {
        let mut a = sounding_plate(scheme);
        let mut b = sounding_plate(scheme);
        a.set_hand(&hand_weights(), c).unwrap();
        let mut ma = Mallet::new(0.05, 1e9, 2.5, 0.4, a.h()).unwrap();
        let mut mb = ma.clone();
        let mut same = true;
        for n in 0..3000 {
            if n < 1500 {
                let f = if n < 88 { 100.0 } else { 0.0 };
                a.step(f).unwrap();
                b.step(f).unwrap();
            } else {
                if n == 1500 {
                    a.launch_mallet(&mut ma, 3.0).unwrap();
                    b.launch_mallet(&mut mb, 3.0).unwrap();
                }
                a.step_with_mallet(&mut ma).unwrap();
                b.step_with_mallet(&mut mb).unwrap();
            }
            same &= a
                .q()
                .iter()
                .zip(b.q())
                .all(|(x, y)| x.to_bits() == y.to_bits())
                && a.energy().balance().to_bits() == b.energy().balance().to_bits();
        }
        assert!(mb.stats().contact_steps > 50);
        same
    };
    for scheme in ALL {
        assert!(run(scheme, 0.0), "{scheme:?}: c = 0 changed the step");
        assert!(
            !run(scheme, 1e-6),
            "{scheme:?}: the comparison missed c = 1e-6"
        );
    }
}

/// The joint solve with the hand eliminated is the plate step under the solved forces: a twin
/// with the same hand stepped with `step(F)`, `F` the mallet's force read back, follows to
/// round-off through the contact on all four schemes (the twin solves the hand with the force
/// in the right-hand side; the joint step shifts `q*` and `z` by the hand first). Bound 2e-12
/// as the mallet's own twin test (measured `--nocapture`: at most 2e-13); the hand forces
/// (tens of N) agree within 1e-9 N (measured at most 9e-12 N). Neither path allocates. With
/// the hand's coupling `k` dropped from the mallet's response the twins part by 1.7e-2
/// (measured on a deliberately broken build).
#[test]
fn joint_step_with_the_hand_equals_the_plate_step() {
    for scheme in ALL {
        let mut a = sounding(scheme, 2.0);
        let mut b = sounding(scheme, 2.0);
        a.set_hand(&hand_weights(), C_HAND).unwrap();
        b.set_hand(&hand_weights(), C_HAND).unwrap();
        let mut m = Mallet::new(0.05, 1e9, 2.5, 0.3, a.h()).unwrap();
        a.launch_mallet(&mut m, 3.0).unwrap();
        let before = allocations();
        let (mut worst, mut worst_f): (f64, f64) = (0.0, 0.0);
        for _ in 0..150 {
            a.step_with_mallet(&mut m).unwrap();
            b.step(m.force()).unwrap();
            let norm = a.q().iter().map(|x| x.abs()).fold(0.0, f64::max);
            for (x, y) in a.q().iter().zip(b.q()) {
                worst = worst.max((x - y).abs() / norm);
            }
            worst_f = worst_f.max((a.hand_force() - b.hand_force()).abs());
        }
        assert_eq!(allocations(), before, "{scheme:?} allocated");
        assert!(m.stats().contact_steps > 50 && m.force() == 0.0);
        let fscale = a.hand_force().abs().max(1e-3);
        println!(
            "{scheme:?}: joint vs plate step with the hand {worst:.2e}, hand force {worst_f:.2e} N"
        );
        assert!(worst < 2e-12, "{scheme:?}: {worst:e}");
        assert!(worst_f < 1e-9 * fscale.max(1.0), "{scheme:?}: {worst_f:e}");
    }
}

/// A linear, lossless plate of 8 well separated modes (100 · (s+1)^1.5 Hz: the lowest two
/// 1150 rad/s apart) with mode 0 alone sounding and the hand set by
/// [`hand_damping_for_t60`] for a 60 dB decay of that mode in 0.15 s: the mode's energy
/// `½ρh((δ_{t-}q₀)² + ω₀² q₀(n) q₀(n-1))` falls by 60 dB in the designed time, within 5 %
/// (the design neglects the hand's coupling to the other modes, of relative order
/// `σ/Δω ≈ 0.04`, and the exact scheme's own damping map; measured `--nocapture`: within
/// 0.2 %). With the factor 2 of `σ = cΦ²/2ρh` dropped from the design formula the measured
/// time is 0.30 s, twice the design (measured on a deliberately broken build), and with no
/// hand the mode does not decay at all: both fail the 5 % bound.
#[test]
fn the_hand_damps_the_mode_at_the_designed_rate() {
    let nf = 8;
    let t60 = 0.15;
    for scheme in [PlateScheme::ConservativeExact, PlateScheme::SavExact] {
        let params = PlateParams {
            omega: (0..nf)
                .map(|s| 2.0 * PI * 100.0 * ((s + 1) as f64).powf(1.5))
                .collect(),
            damping: vec![0.0; nf],
            zeta4: vec![1e4],
            rho_h: 7.86,
            e_h: 2e8,
            coupling_scale: 0.0,
            fs: 44100.0,
            scheme,
            solve: LinearSolve::Auto,
        };
        let coupling = Arc::new(DenseCoupling::from_fn(nf, 1, |_, _, _| 0.0).unwrap());
        let pickup = PickupWeights::new(vec![1.0; nf], PickupKind::Displacement).unwrap();
        let mut p = PlateModel::new(&params, coupling, vec![1.0; nf], vec![pickup]).unwrap();
        let hw: Vec<f64> = Rng(3).vec(nf).iter().map(|w| 1.0 + 0.5 * w).collect();
        let c = hand_damping_for_t60(params.rho_h, hw[0], t60);
        p.set_hand(&hw, c).unwrap();
        let mut q0 = vec![0.0; nf];
        q0[0] = 1e-4;
        p.set_state(&q0, &vec![0.0; nf]).unwrap();
        let (h, w0) = (p.h(), params.omega[0]);
        let mode_energy = |p: &PlateModel<DenseCoupling>| {
            let (x, xp) = (p.q()[0], p.q_prev()[0]);
            0.5 * params.rho_h * (((x - xp) / h).powi(2) + w0 * w0 * x * xp)
        };
        let e0 = mode_energy(&p);
        let steps = (t60 / h).round() as usize;
        for _ in 0..steps {
            p.step(0.0).unwrap();
        }
        let drop_db = -10.0 * (mode_energy(&p) / e0).log10();
        let measured = steps as f64 * h * 60.0 / drop_db;
        println!("{scheme:?}: c = {c:.1} N·s/m, T60 measured {measured:.4} s, design {t60} s");
        assert!(
            (measured / t60 - 1.0).abs() < 0.05,
            "{scheme:?}: {measured} s"
        );
    }
}
