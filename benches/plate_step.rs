//! Cost of one step of the modal plate schemes with a dense coupling tensor
//! (`cargo bench --bench plate_step`): ns per step at N_Φ = 50 and 100, N_Ψ = N_Φ / 2.
//!
//! The dense tensor makes every coupling kernel cost N_Ψ N_Φ² multiply-adds; a sparse tensor
//! (Bessel modes) lowers that term, not the solve.

use std::f64::consts::PI;
use std::hint::black_box;
use std::sync::Arc;

use criterion::{criterion_group, criterion_main, Criterion};
use noether::models::plate::{DenseCoupling, LinearSolve, PlateModel, PlateParams, PlateScheme};

/// Deterministic numbers in [-1, 1).
fn lcg(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

fn model(n_phi: usize, scheme: PlateScheme, solve: LinearSolve) -> PlateModel<DenseCoupling> {
    let n_psi = n_phi / 2;
    let mut seed = 42;
    let coupling =
        Arc::new(DenseCoupling::from_fn(n_phi, n_psi, |_, _, _| lcg(&mut seed)).unwrap());
    let omega: Vec<f64> = (0..n_phi)
        .map(|s| 2.0 * PI * (50.0 + 2000.0 * s as f64 / n_phi as f64))
        .collect();
    let params = PlateParams {
        damping: omega.iter().map(|w| 0.005 * w.powf(0.6)).collect(),
        omega,
        zeta4: (0..n_psi).map(|l| 1e4 * (1.0 + l as f64)).collect(),
        rho_h: 7.86,
        e_h: 2e8,
        coupling_scale: 1.0,
        fs: 44_100.0,
        scheme,
        solve,
    };
    let mut m = PlateModel::new(&params, coupling, vec![0.1; n_phi], vec![]).unwrap();
    let q0: Vec<f64> = (0..n_phi).map(|_| 1e-6 * lcg(&mut seed)).collect();
    m.set_state(&q0, &vec![0.0; n_phi]).unwrap();
    m
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("plate_step");
    for n_phi in [50, 100] {
        for (label, scheme, solve) in [
            (
                "theta1-woodbury",
                PlateScheme::ConservativeTheta1,
                LinearSolve::Woodbury,
            ),
            (
                "exact-woodbury",
                PlateScheme::ConservativeExact,
                LinearSolve::Woodbury,
            ),
            (
                "exact-direct",
                PlateScheme::ConservativeExact,
                LinearSolve::Direct,
            ),
            (
                "stormer-verlet",
                PlateScheme::StormerVerletExact,
                LinearSolve::Auto,
            ),
            ("sav", PlateScheme::SavExact, LinearSolve::Auto),
        ] {
            let mut m = model(n_phi, scheme, solve);
            group.bench_function(format!("{label}/n_phi={n_phi}"), |b| {
                b.iter(|| {
                    m.step(black_box(0.0)).unwrap();
                    black_box(m.q()[0])
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
