//! Cost of the gong (real Bessel modal data, sparse tensor) per step, against N_Φ and scheme,
//! and the cost of the modal precomputation.
//!
//! `cargo bench --bench plate_gong`. The README's table quotes criterion medians; a simulated
//! second at fs costs `fs ×` the per-step time. Environment (optional, to run a subset):
//! `NOETHER_BENCH_SCHEMES=sav,conservative` (scene scheme names, comma separated; default all
//! four) and `NOETHER_BENCH_SIZES=100x30,1000x300` (`N_Φ x N_Ψ`; default
//! 50x15, 100x30, 300x100, 1000x300).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use noether::modal::{default_cache_dir, CircularEdge, CircularPlateSpec, PlateModes};
use noether::models::plate::voice::PlateVoice;
use noether::render::source::RenderSource;
use std::hint::black_box;

#[path = "common/seed_gong.rs"]
mod seed_gong;
use seed_gong::seed_gong_voice;

const STEPS: usize = 32;

/// The lecture's gong (`assets/scenes/seed-gong-40N.toml`) with `n_phi × n_psi` modes under
/// `scheme`, at 40 kHz, struck for 1 ms at 80 N.
fn voice(n_phi: usize, n_psi: usize, scheme: &str) -> PlateVoice {
    let sets = [
        format!("plate.n_phi={n_phi}"),
        format!("plate.n_psi={n_psi}"),
        format!("plate.scheme={scheme}"),
        "plate.excitation.duration=0.001".into(),
        "plate.excitation.peak_force=80".into(),
    ];
    seed_gong_voice(&sets)
}

/// The comma-separated list in `var`, or `default`.
fn list(var: &str, default: &str) -> Vec<String> {
    std::env::var(var)
        .unwrap_or_else(|_| default.to_string())
        .split(',')
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .collect()
}

fn steps(c: &mut Criterion) {
    let mut g = c.benchmark_group("gong-step");
    g.sample_size(10);
    g.throughput(Throughput::Elements(STEPS as u64));
    let sizes = list("NOETHER_BENCH_SIZES", "50x15,100x30,300x100,1000x300");
    let schemes = list(
        "NOETHER_BENCH_SCHEMES",
        "conservative,conservative-exact,stormer-verlet,sav",
    );
    for size in &sizes {
        let (a, b) = size.split_once('x').expect("NOETHER_BENCH_SIZES: NxM");
        let (n_phi, n_psi): (usize, usize) = (a.parse().unwrap(), b.parse().unwrap());
        for scheme in &schemes {
            let mut v = voice(n_phi, n_psi, scheme);
            let mut out = vec![vec![0.0; STEPS]; v.channels()];
            // Past the strike, into the free decay.
            for _ in 0..4 {
                v.process(&mut out, STEPS);
            }
            g.bench_function(format!("{scheme}/{n_phi}x{n_psi}"), |b| {
                b.iter(|| {
                    v.process(&mut out, STEPS);
                    black_box(out[0][STEPS - 1])
                })
            });
        }
    }
    g.finish();
}

fn precompute(c: &mut Criterion) {
    if std::env::var("NOETHER_BENCH_SKIP_PRECOMPUTE").is_ok() {
        return;
    }
    let mut g = c.benchmark_group("gong-precompute");
    g.sample_size(10);
    for (n_phi, n_psi) in [(100, 30), (1000, 300)] {
        let spec = CircularPlateSpec::new(CircularEdge::Free, 0.3, n_phi, n_psi, None).unwrap();
        g.bench_function(format!("{n_phi}x{n_psi}"), |b| {
            b.iter(|| black_box(PlateModes::build(&spec).unwrap().coupling.nnz()))
        });
    }
    g.finish();
}

/// The fused SAV kernel alone (`quartic_gradient`: η and ∇U, one pass over the tensor), the
/// dense selection-rule block layout against the run layout it replaced, on the gong's tensor
/// at the sizes of `NOETHER_BENCH_SIZES`. Throughput: tensor entries (criterion's elem/s gives
/// ns per entry as its inverse).
fn kernel(c: &mut Criterion) {
    let mut g = c.benchmark_group("gong-kernel");
    g.sample_size(20);
    for size in &list("NOETHER_BENCH_SIZES", "50x15,100x30,300x100,1000x300") {
        let (a, b) = size.split_once('x').expect("NOETHER_BENCH_SIZES: NxM");
        let (n_phi, n_psi): (usize, usize) = (a.parse().unwrap(), b.parse().unwrap());
        let spec = CircularPlateSpec::new(CircularEdge::Free, 0.3, n_phi, n_psi, None).unwrap();
        let (modes, _) = PlateModes::load_or_build(&spec, &default_cache_dir()).unwrap();
        let t = &modes.coupling;
        g.throughput(Throughput::Elements(t.nnz() as u64));
        let q: Vec<f64> = (0..n_phi)
            .map(|s| ((s * 7919) % 1000) as f64 * 1e-3 - 0.5)
            .collect();
        let w = vec![1.0; n_psi];
        let (mut eta, mut grad) = (vec![0.0; n_psi], vec![0.0; n_phi]);
        let mut scratch = vec![0.0; t.quartic_scratch_len()];
        g.bench_function(format!("blocks/{n_phi}x{n_psi}"), |b| {
            b.iter(|| {
                t.quartic_gradient(&q, &w, &mut eta, &mut grad, &mut scratch);
                black_box(grad[0])
            })
        });
        g.bench_function(format!("runs/{n_phi}x{n_psi}"), |b| {
            b.iter(|| {
                t.quartic_gradient_runs(&q, &w, &mut eta, &mut grad, &mut scratch);
                black_box(grad[0])
            })
        });
    }
    g.finish();
}

criterion_group!(benches, steps, kernel, precompute);
criterion_main!(benches);
