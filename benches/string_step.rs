//! Wall time of the stiff-string model per simulated second.
//!
//! - `string_2mhz/Nm`: one lossy string against the sitar bridge at fs = 2 MHz (the lecture's
//!   rate), 2 ms simulated per iteration (4000 steps): wall time per simulated second =
//!   reported time × 500.
//! - `string_8x48k/Nm`: the same string at the real-time-friendly rate fs = 8 × 48 kHz =
//!   384 kHz (the rate of `assets/scenes/sitar.toml`), 10 ms simulated per iteration (3840
//!   steps): wall time per simulated second = reported time × 100; one voice runs in real time
//!   on one core when that is below 1 s.
//!
//! - `string_scheme/{newton,quadratised}-{384k,2m}/Nm`: the same string under each contact
//!   scheme (the lecture's Newton discrete gradient, the energy-quadratised closed form), at
//!   384 kHz (3840 steps per iteration, × 100 for a simulated second) and 2 MHz (4000 steps,
//!   × 500), N_m = 209 and 1007.
//!
//! - `string_synthesis/{rows,dst}/Nm`: the 2 MHz string with grid values from the stored rows
//!   of `S` at the 20 bridge nodes and the pickup's two nodes (the default) or from one DST of
//!   the whole grid per step (`GridSynthesis::Dst`), 4000 steps per iteration (× 500).
//!
//! Throughput is reported in simulation steps per second. Every string is plucked once before
//! timing and keeps ringing (and touching its bridge) across iterations.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use noether::models::string::{
    ContactLaw, ContactScheme, GridSynthesis, Losses, Obstacle, OutputChannel, Quantity, Readout,
    StiffString, StringConfig, StringParams, TrianglePluck, ValetteLosses,
};
use noether::render::source::RenderSource;
use std::hint::black_box;
use std::time::Duration;

/// Requested mode counts; each is raised to the next FFT-friendly grid
/// ([`StringParams::smooth_intervals`]): N_m = 53, 104, 209, 503, 1007.
const MODES: [usize; 5] = [50, 100, 200, 500, 1000];

fn intervals(modes: usize) -> usize {
    StringParams::smooth_intervals(modes + 1)
}

fn string(modes: usize, fs: f64) -> StiffString {
    let mut s = StiffString::new(&StringConfig {
        params: StringParams::lecture_guitar(intervals(modes), fs),
        losses: Losses::Valette(ValetteLosses::default()),
        obstacle: Obstacle::seed_sitar(),
        contact: ContactLaw::lecture(),
        outputs: vec![
            OutputChannel::Pickup {
                position: 0.37,
                quantity: Quantity::Velocity,
                readout: Readout::Grid,
            },
            OutputChannel::ObstacleForce,
        ],
    })
    .expect("valid bench parameters");
    s.pluck(&TrianglePluck {
        position: 0.3,
        amplitude: 1e-3,
    })
    .expect("valid pluck");
    s
}

/// Group `group`: `steps` steps of the lecture's sitar string at `fs` Hz, per mode count,
/// measured for `seconds`.
fn bench_at_rate(c: &mut Criterion, group: &str, fs: f64, steps: usize, seconds: u64) {
    let mut g = c.benchmark_group(group);
    g.sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(seconds));
    g.throughput(Throughput::Elements(steps as u64));
    for &m in &MODES {
        let mut s = string(m, fs);
        let mut out = vec![vec![0.0; steps]; s.channels()];
        g.bench_with_input(BenchmarkId::from_parameter(intervals(m) - 1), &m, |b, _| {
            b.iter(|| {
                s.process(&mut out, steps);
                black_box(out[0][steps - 1])
            })
        });
    }
    g.finish();
}

fn bench_2mhz(c: &mut Criterion) {
    bench_at_rate(c, "string_2mhz", 2_000_000.0, 4000, 4);
}

fn bench_8x48k(c: &mut Criterion) {
    bench_at_rate(c, "string_8x48k", 384_000.0, 3840, 3);
}

fn bench_schemes(c: &mut Criterion) {
    let mut g = c.benchmark_group("string_scheme");
    g.sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    for (rate, fs, steps) in [("384k", 384_000.0, 3840usize), ("2m", 2_000_000.0, 4000)] {
        g.throughput(Throughput::Elements(steps as u64));
        for &m in &[200, 1000] {
            for scheme in ContactScheme::ALL {
                let mut s = string(m, fs);
                s.set_contact_scheme(scheme);
                let mut out = vec![vec![0.0; steps]; s.channels()];
                let id = BenchmarkId::new(format!("{}-{rate}", scheme.name()), intervals(m) - 1);
                g.bench_with_input(id, &m, |b, _| {
                    b.iter(|| {
                        s.process(&mut out, steps);
                        black_box(out[0][steps - 1])
                    })
                });
            }
        }
    }
    g.finish();
}

fn bench_synthesis(c: &mut Criterion) {
    let mut g = c.benchmark_group("string_synthesis");
    g.sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    let steps = 4000;
    g.throughput(Throughput::Elements(steps as u64));
    for &m in &[200, 1000] {
        for (name, path) in [("rows", GridSynthesis::Rows), ("dst", GridSynthesis::Dst)] {
            let mut s = string(m, 2_000_000.0);
            assert_eq!(s.set_grid_synthesis(path), path);
            let mut out = vec![vec![0.0; steps]; s.channels()];
            let id = BenchmarkId::new(name, intervals(m) - 1);
            g.bench_with_input(id, &m, |b, _| {
                b.iter(|| {
                    s.process(&mut out, steps);
                    black_box(out[0][steps - 1])
                })
            });
        }
    }
    g.finish();
}

criterion_group!(
    benches,
    bench_2mhz,
    bench_8x48k,
    bench_schemes,
    bench_synthesis
);
criterion_main!(benches);
