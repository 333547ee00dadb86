//! Real-time factor of one gong voice (the real-time gong target): the lecture's material,
//! a = 0.4 m, h = 1 mm, free edge, 10 ms strike at 40 N, power-law damping, simulated at `fs` (default
//! 48 kHz), on one thread.
//!
//! `cargo run --release --example gong_rtf -- SCHEME FS N_PHI[:N_PSI] ...`, for example
//! `cargo run --release --example gong_rtf -- sav 48000 100 300:90 600`. `N_PSI` defaults to
//! `0.3 N_PHI` (the README's tables). For each size: build (modal data cached on disk), run
//! 0.1 s past the strike, then time three runs of 0.5 s of simulated sound; prints the median
//! wall time per step and `RTF = simulated time / wall time` (real time holds when RTF ≥ 1),
//! then the same from the thread's CPU time (immune to other load on a shared machine), and
//! the thread-CPU time per step divided by the tensor's stored entries (ns per entry).
//! Output is always 48 kHz (`PlateVoice::process`, resampling included); `FS` is the
//! simulation rate. stderr: the coupling's block layout, and with `GONG_RTF_KERNEL` set a
//! thread-CPU comparison of the block and run kernels of the SAV step.
//! `GONG_RTF_WARM` and `GONG_RTF_SECONDS` (s) change the 0.1 s and 0.5 s (for profiling under
//! callgrind with a few steps). `GONG_RTF_SYMMETRY` (`full`, default, or `strike-mirror`) and
//! `GONG_RTF_STORAGE` (`double`, default, or `single`) set the scene's `plate.symmetry` and
//! `plate.tensor_storage`. `GONG_RTF_THREADS=2` shares each `sav` step between this thread and
//! a helper (`render::step_join::SpinJoin`); the thread-CPU columns then count this thread only,
//! so read the wall-time RTF (on an otherwise idle machine).

use std::time::{Duration, Instant};

use noether::modal::CouplingTensor;

use noether::models::plate::voice::PlateVoice;
use noether::render::source::RenderSource;

#[path = "../benches/common/seed_gong.rs"]
mod seed_gong;
use seed_gong::seed_gong_voice;

/// The lecture's gong (`assets/scenes/seed-gong-40N.toml`: 10 ms strike at 40 N) with
/// `n_phi × n_psi` modes under `scheme` at `fs` Hz, its basis and tensor storage from the
/// environment (`GONG_RTF_SYMMETRY`, `GONG_RTF_STORAGE`).
fn voice(scheme: &str, fs: f64, n_phi: usize, n_psi: usize) -> PlateVoice {
    let symmetry = std::env::var("GONG_RTF_SYMMETRY").unwrap_or_else(|_| "full".into());
    let storage = std::env::var("GONG_RTF_STORAGE").unwrap_or_else(|_| "double".into());
    let sets = [
        format!("plate.n_phi={n_phi}"),
        format!("plate.n_psi={n_psi}"),
        format!("plate.sim_rate={fs}"),
        format!("plate.scheme={scheme}"),
        format!("plate.symmetry={symmetry}"),
        format!("plate.tensor_storage={storage}"),
    ];
    seed_gong_voice(&sets)
}

/// CPU time consumed by the calling thread so far (`noether::clock`).
fn thread_cpu_time() -> Duration {
    noether::clock::thread_cpu_time().expect("the thread CPU clock (Unix)")
}

/// Thread-CPU nanoseconds per call of the fused SAV kernel, block layout then run layout
/// (median of 5 batches, same tensor, same pseudo-random `q`).
fn kernel_ab(t: &CouplingTensor) -> (f64, f64) {
    let (nf, np) = (t.n_phi(), t.n_psi());
    let q: Vec<f64> = (0..nf)
        .map(|s| ((s * 7919) % 1000) as f64 * 1e-3 - 0.5)
        .collect();
    let w = vec![1.0; np];
    let (mut eta, mut grad, mut scratch) = (
        vec![0.0; np],
        vec![0.0; nf],
        vec![0.0; t.quartic_scratch_len()],
    );
    let reps = (2e7 / t.nnz().max(1) as f64).ceil() as usize;
    let mut time = |blocks: bool| {
        let mut v: Vec<f64> = (0..5)
            .map(|_| {
                let t0 = thread_cpu_time();
                for _ in 0..reps {
                    if blocks {
                        t.quartic_gradient(&q, &w, &mut eta, &mut grad, &mut scratch);
                    } else {
                        t.quartic_gradient_runs(&q, &w, &mut eta, &mut grad, &mut scratch);
                    }
                    std::hint::black_box(&grad);
                }
                (thread_cpu_time() - t0).as_secs_f64() * 1e9 / reps as f64
            })
            .collect();
        v.sort_by(f64::total_cmp);
        v[2]
    };
    (time(true), time(false))
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 3 {
        eprintln!("usage: gong_rtf SCHEME FS N_PHI[:N_PSI] ...");
        std::process::exit(2);
    }
    let scheme = &args[0];
    let fs: f64 = args[1].parse().expect("FS: a number (Hz)");
    println!(
        "scheme\tfs\tn_phi\tn_psi\tus_per_step\trtf\tcpu_us_per_step\trtf_cpu\tcpu_ns_per_entry"
    );
    for size in &args[2..] {
        let (n_phi, n_psi) = match size.split_once(':') {
            Some((a, b)) => (a.parse().expect("N_PHI"), b.parse().expect("N_PSI")),
            None => {
                let n: usize = size.parse().expect("N_PHI");
                (n, ((0.3 * n as f64).round() as usize).max(1))
            }
        };
        let mut v = voice(scheme, fs, n_phi, n_psi);
        if std::env::var("GONG_RTF_THREADS").is_ok_and(|t| t == "2") {
            let join = noether::render::step_join::SpinJoin::new().expect("a helper thread");
            let on = v.set_step_join(Some(std::sync::Arc::new(join)));
            eprintln!("{n_phi}x{n_psi}: step shared by two threads: {on}");
        }
        let t = v.model().coupling();
        let (classes, dense, stored, rest) = t.block_stats();
        eprintln!(
            "{n_phi}x{n_psi}: {} entries, {} storage; {classes} mode classes, {dense} dense \
             blocks ({stored} stored values), {rest} entries in the gathered remainder",
            t.nnz(),
            t.storage().name()
        );
        let nnz = t.nnz().max(1) as f64;
        if std::env::var("GONG_RTF_KERNEL").is_ok() {
            let (b, r) = kernel_ab(t);
            eprintln!(
                "  kernel (thread CPU): blocks {:.1} us ({:.3} ns/entry), runs {:.1} us \
                 ({:.3} ns/entry), ratio {:.2}",
                b * 1e-3,
                b / t.nnz() as f64,
                r * 1e-3,
                r / t.nnz() as f64,
                r / b
            );
        }
        let block = 256;
        let secs = |var: &str, default: f64| -> f64 {
            std::env::var(var)
                .ok()
                .map_or(default, |s| s.parse().expect("seconds"))
        };
        let block = block
            .min((secs("GONG_RTF_SECONDS", 0.5) * fs) as usize)
            .max(1);
        let mut out = vec![vec![0.0; block]; v.channels()];
        let warm = (secs("GONG_RTF_WARM", 0.1) * fs) as usize / block;
        for _ in 0..warm {
            v.process(&mut out, block);
        }
        let blocks = ((secs("GONG_RTF_SECONDS", 0.5) * fs) as usize / block).max(1);
        let (mut times, mut cpu): (Vec<f64>, Vec<f64>) = (0..3)
            .map(|_| {
                let (t, c) = (Instant::now(), thread_cpu_time());
                for _ in 0..blocks {
                    v.process(&mut out, block);
                }
                (
                    t.elapsed().as_secs_f64(),
                    (thread_cpu_time() - c).as_secs_f64(),
                )
            })
            .unzip();
        times.sort_by(f64::total_cmp);
        cpu.sort_by(f64::total_cmp);
        let steps = (blocks * block) as f64;
        let (per_step, cpu_step) = (times[1] / steps, cpu[1] / steps);
        println!(
            "{scheme}\t{fs}\t{n_phi}\t{n_psi}\t{:.3}\t{:.3}\t{:.3}\t{:.3}\t{:.3}",
            per_step * 1e6,
            1.0 / (per_step * fs),
            cpu_step * 1e6,
            1.0 / (cpu_step * fs),
            cpu_step * 1e9 / nnz
        );
        assert!(
            out.iter().flatten().all(|x| x.is_finite()),
            "non-finite output"
        );
    }
}
