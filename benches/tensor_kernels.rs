//! The von Kármán coupling tensor's cost per stored entry, double against single storage
//! (`plate.tensor_storage`), on the gong's tensors: the fused SAV kernel alone
//! (`CouplingTensor::quartic_gradient`), and a whole `sav` step of the gong voice
//! (a = 0.4 m, h = 1 mm, 40 N strike, simulated at 12 kHz, as `examples/gong_rtf.rs`).
//!
//! `cargo bench --bench tensor_kernels`. Times are the bench thread's CPU time
//! (`CLOCK_THREAD_CPUTIME_ID`, through `iter_custom`: the machine is shared, and wall time
//! counts the other processes). Throughput is in tensor entries (one step = `nnz` entries), so
//! criterion's `elem/s` inverts to ns per entry per step. Environment (optional):
//! `NOETHER_BENCH_TENSORS=mirror:510x15,full:1000x30` (`full` or `mirror` basis, `N_Φ x N_Ψ`;
//! default `mirror:510x15,mirror:510x30,full:1000x30`).
//! The whole-step group also runs the double-storage step without the relaxation of `ψ`
//! (`plain/...`, `plate.sav_relaxation = 0`): the relaxation's cost is the ratio of the two.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use noether::modal::{
    default_cache_dir, CircularEdge, CircularPlateSpec, PlateModes, TensorStorage,
};
use noether::models::plate::voice::PlateVoice;
use noether::render::source::RenderSource;
use std::hint::black_box;
use std::time::Duration;

#[path = "common/seed_gong.rs"]
mod seed_gong;
use seed_gong::seed_gong_voice;

/// Steps per iteration of the whole-step bench.
const STEPS: usize = 32;

/// CPU time consumed by the calling thread so far (`noether::clock`).
fn thread_cpu_time() -> Duration {
    noether::clock::thread_cpu_time().expect("the thread CPU clock (Unix)")
}

/// Thread-CPU time of `iters` calls of `f`.
fn cpu_time(iters: u64, mut f: impl FnMut()) -> Duration {
    let t0 = thread_cpu_time();
    for _ in 0..iters {
        f();
    }
    thread_cpu_time() - t0
}

/// The tensors of `NOETHER_BENCH_TENSORS`: `(label, mirror basis, N_Φ, N_Ψ)`.
fn sizes() -> Vec<(String, bool, usize, usize)> {
    std::env::var("NOETHER_BENCH_TENSORS")
        .unwrap_or_else(|_| "mirror:510x15,mirror:510x30,full:1000x30".into())
        .split(',')
        .map(|s| {
            let (basis, size) = s.trim().split_once(':').expect("BASIS:NxM");
            let (a, b) = size.split_once('x').expect("NxM");
            let mirror = match basis {
                "mirror" => true,
                "full" => false,
                _ => panic!("NOETHER_BENCH_TENSORS: basis `full` or `mirror`, got {basis}"),
            };
            (
                s.trim().to_string(),
                mirror,
                a.parse().unwrap(),
                b.parse().unwrap(),
            )
        })
        .collect()
}

/// The gong voice of `examples/gong_rtf.rs` (the lecture's gong, `sav` at 12 kHz) with the
/// given basis, size, storage and SAV relaxation time constant (s; 0: off).
fn voice(mirror: bool, n_phi: usize, n_psi: usize, storage: &str, relax: f64) -> PlateVoice {
    let symmetry = if mirror { "strike-mirror" } else { "full" };
    let sets = [
        format!("plate.n_phi={n_phi}"),
        format!("plate.n_psi={n_psi}"),
        "plate.sim_rate=12000".into(),
        "plate.scheme=sav".into(),
        format!("plate.symmetry={symmetry}"),
        format!("plate.tensor_storage={storage}"),
        format!("plate.sav_relaxation={relax}"),
    ];
    seed_gong_voice(&sets)
}

/// The fused SAV kernel alone, per storage.
fn kernel(c: &mut Criterion) {
    let mut g = c.benchmark_group("tensor-kernel");
    g.sample_size(20);
    for (label, mirror, n_phi, n_psi) in sizes() {
        let mut spec = CircularPlateSpec::new(CircularEdge::Free, 0.3, n_phi, n_psi, None).unwrap();
        if mirror {
            spec = spec.mirror_symmetric();
        }
        let (modes, _) = PlateModes::load_or_build(&spec, &default_cache_dir()).unwrap();
        let q: Vec<f64> = (0..n_phi)
            .map(|s| ((s * 7919) % 1000) as f64 * 1e-3 - 0.5)
            .collect();
        let w = vec![1.0; n_psi];
        for storage in [TensorStorage::Double, TensorStorage::Single] {
            let t = modes.coupling.with_storage(storage).unwrap();
            g.throughput(Throughput::Elements(t.nnz() as u64));
            let (mut eta, mut grad) = (vec![0.0; n_psi], vec![0.0; n_phi]);
            let mut scratch = vec![0.0; t.quartic_scratch_len()];
            g.bench_function(format!("{}/{label}", storage.name()), |b| {
                b.iter_custom(|iters| {
                    cpu_time(iters, || {
                        t.quartic_gradient(&q, &w, &mut eta, &mut grad, &mut scratch);
                        black_box(grad[0]);
                    })
                })
            });
        }
    }
    g.finish();
}

/// A whole `sav` step of the gong voice (`PlateVoice::process`: one model step per frame at
/// the 12 kHz simulation rate, pickups and energy included), per storage.
fn step(c: &mut Criterion) {
    let mut g = c.benchmark_group("tensor-sav-step");
    g.sample_size(10);
    let relaxed = noether::models::plate::spec::default_sav_relaxation();
    for (label, mirror, n_phi, n_psi) in sizes() {
        for (storage, relax, name) in [
            (TensorStorage::Double, relaxed, "double"),
            (TensorStorage::Single, relaxed, "single"),
            (TensorStorage::Double, 0.0, "plain"),
        ] {
            let mut v = voice(mirror, n_phi, n_psi, storage.name(), relax);
            let nnz = v.model().coupling().nnz();
            g.throughput(Throughput::Elements((nnz * STEPS) as u64));
            let mut out = vec![vec![0.0; STEPS]; v.channels()];
            // Past the 10 ms strike, into the free decay.
            for _ in 0..8 {
                v.process(&mut out, STEPS);
            }
            g.bench_function(format!("{name}/{label}"), |b| {
                b.iter_custom(|iters| {
                    cpu_time(iters, || {
                        v.process(&mut out, STEPS);
                        black_box(out[0][STEPS - 1]);
                    })
                })
            });
        }
    }
    g.finish();
}

criterion_group!(benches, kernel, step);
criterion_main!(benches);
