//! Engine CPU per second of 48 kHz audio for each factory preset with 1, 4 and 8 sounding
//! voices. One iteration renders 0.1 s (4 800 samples in 256-sample blocks) after re-striking
//! every voice, so the voices keep sounding; criterion's time per iteration × 10 is the CPU
//! time per second of audio (real time on one core needs < 1 s).
//!
//! Measured in CPU time of the benchmark thread (`CLOCK_THREAD_CPUTIME_ID`), not wall time:
//! on the shared 2-core machine other builds take the core away for part of an iteration,
//! which inflates wall time but not the engine's own CPU time. `NOETHER_BENCH_WALL=1` measures
//! wall time instead (criterion's default).

use criterion::measurement::{Measurement, ValueFormatter, WallTime};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use noether::engine::{Engine, ParamId, Preset, SharedParams};
use std::sync::Arc;
use std::time::Duration;

/// CPU time consumed by the calling thread so far.
fn thread_cpu_time() -> Duration {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; CLOCK_THREAD_CPUTIME_ID is supported by
    // Linux since 2.6.12 (the call fails only for an invalid clock or pointer).
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID) failed");
    Duration::new(ts.tv_sec as u64, ts.tv_nsec as u32)
}

/// Criterion measurement: CPU time of the benchmark thread (or wall time, see the file doc).
struct Cpu {
    /// Measure wall time instead of the thread's CPU time.
    wall: bool,
    /// Criterion's duration formatter (both measurements are durations in ns).
    fmt: WallTime,
}

impl Measurement for Cpu {
    type Intermediate = (Duration, std::time::Instant);
    type Value = Duration;

    fn start(&self) -> Self::Intermediate {
        (thread_cpu_time(), std::time::Instant::now())
    }
    fn end(&self, (cpu, wall): Self::Intermediate) -> Duration {
        if self.wall {
            wall.elapsed()
        } else {
            thread_cpu_time() - cpu
        }
    }
    fn add(&self, a: &Duration, b: &Duration) -> Duration {
        *a + *b
    }
    fn zero(&self) -> Duration {
        Duration::ZERO
    }
    fn to_f64(&self, v: &Duration) -> f64 {
        v.as_nanos() as f64
    }
    fn formatter(&self) -> &dyn ValueFormatter {
        self.fmt.formatter()
    }
}

fn config() -> Criterion<Cpu> {
    let wall = std::env::var_os("NOETHER_BENCH_WALL").is_some_and(|v| v == "1");
    Criterion::default().with_measurement(Cpu {
        wall,
        fmt: WallTime,
    })
}

const KEYS: [u8; 8] = [0, 4, 7, 12, 16, 19, 24, 28];

fn bench(c: &mut Criterion<Cpu>) {
    let mut g = c.benchmark_group("engine_0.1s_48k");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    for (stem, preset) in Preset::factory() {
        for voices in [1usize, 4, 8] {
            let params = Arc::new(SharedParams::new());
            preset.apply(&params).unwrap();
            params.set(ParamId::Polyphony, voices as f32).unwrap();
            let root = params.get(ParamId::RootKey) as u8;
            let (mut e, _h) = Engine::new(params.clone());
            e.activate(48_000.0, 256).unwrap();
            let (mut l, mut r) = (vec![0.0f32; 256], vec![0.0f32; 256]);
            let strike = |e: &mut Engine| {
                for k in KEYS.iter().take(voices) {
                    e.note_on(root - 12 + k, 0.8);
                }
            };
            strike(&mut e);
            for _ in 0..20 {
                e.process(&mut l, &mut r);
            }
            assert_eq!(e.active_voices(), voices, "{stem}");
            g.bench_function(BenchmarkId::new(stem, voices), |b| {
                b.iter(|| {
                    strike(&mut e);
                    for _ in 0..(4800 / 256) {
                        e.process(&mut l, &mut r);
                    }
                    e.process(&mut l[..4800 % 256], &mut r[..4800 % 256]);
                })
            });
        }
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = config();
    targets = bench
}
criterion_main!(benches);
