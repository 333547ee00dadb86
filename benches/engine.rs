//! Engine CPU per second of 48 kHz audio for each factory preset with 1, 4 and 8 sounding
//! voices. One iteration renders 0.1 s (4 800 samples in 256-sample blocks) after re-striking
//! every voice, so the voices keep sounding; criterion's time per iteration × 10 is the CPU
//! time per second of audio (real time on one core needs < 1 s). `crash-plain` is the crash
//! preset with its cascade closure off: the closure's cost is `crash` over `crash-plain`;
//! `crash-no-above` keeps the closure but not the band above the simulation (the band's cost
//! is `crash` over `crash-no-above`; compare one voice: with more, the bands run in the voice
//! pool's jobs, partly on workers this thread's clock does not see).
//!
//! Measured in CPU time of the benchmark thread (`CLOCK_THREAD_CPUTIME_ID`), not wall time:
//! on the shared 2-core machine other builds take the core away for part of an iteration,
//! which inflates wall time but not the engine's own CPU time. `NOETHER_BENCH_WALL=1` measures
//! wall time instead (criterion's default).
//!
//! The group `engine_pool_0.1s_48k` compares the voice pool's `threads` = 1 (the audio thread
//! alone) with `threads` = 0 (every core): four gong voices (the gong-40N preset as the plugin
//! plays it: 510 modes in the strike-mirror band below 6 kHz, 15 in-plane modes, `sav`,
//! polyphony 4). Its clock is the CPU time of the whole process
//! (`CLOCK_PROCESS_CPUTIME_ID`: the audio thread plus the pool's workers, plus the idle bank
//! builder's polls), so the two settings compare in CPU spent per second of audio; with
//! `NOETHER_BENCH_WALL=1` it measures wall time, the real-time ratio (valid only on an
//! otherwise idle machine: state the load from `uptime`); with `NOETHER_BENCH_POOL_CLOCK=thread`
//! it measures the benchmark (audio) thread's own CPU time, the share that meets the deadline.
//! After each setting it prints the engine's late jobs (0 expected on an idle machine).
//!
//! The group `engine_split_0.1s_48k` does the same for one heavy voice, the moonshot: the
//! gong-40N preset with a band of 11.7 kHz (1030 strike-mirror modes, 15 in-plane, 26 kHz), whose
//! coupling tensor is large enough that the voice shares each step with a worker
//! (`models::plate::step_board`); with `threads` 1 it runs both halves itself. It prints the
//! halves run on the worker and the late ones.

use criterion::measurement::{Measurement, ValueFormatter, WallTime};
use criterion::{criterion_group, criterion_main, BenchmarkGroup, BenchmarkId, Criterion};
use noether::engine::{Engine, EngineHandle, ParamId, Preset, SharedParams};
use noether_testkit::presets::preset_params;
use std::sync::Arc;
use std::time::Duration;

/// CPU time consumed by the calling thread so far (`noether::clock`).
fn thread_cpu_time() -> Duration {
    noether::clock::thread_cpu_time().expect("the thread CPU clock (Unix)")
}

/// CPU time consumed by every thread of the process so far (`noether::clock`).
fn process_cpu_time() -> Duration {
    noether::clock::process_cpu_time().expect("the process CPU clock (Unix)")
}

/// Criterion measurement: CPU time of the benchmark thread or of the whole process, or wall
/// time (see the file doc).
struct Cpu {
    /// Measure wall time instead of CPU time.
    wall: bool,
    /// CPU time of every thread of the process, not only the benchmark thread.
    process: bool,
    /// Criterion's duration formatter (both measurements are durations in ns).
    fmt: WallTime,
}

impl Measurement for Cpu {
    type Intermediate = (Duration, std::time::Instant);
    type Value = Duration;

    fn start(&self) -> Self::Intermediate {
        (self.cpu(), std::time::Instant::now())
    }
    fn end(&self, (cpu, wall): Self::Intermediate) -> Duration {
        if self.wall {
            wall.elapsed()
        } else {
            self.cpu() - cpu
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

impl Cpu {
    fn cpu(&self) -> Duration {
        if self.process {
            process_cpu_time()
        } else {
            thread_cpu_time()
        }
    }
}

fn measurement(process: bool) -> Criterion<Cpu> {
    let wall = std::env::var_os("NOETHER_BENCH_WALL").is_some_and(|v| v == "1");
    Criterion::default().with_measurement(Cpu {
        wall,
        process,
        fmt: WallTime,
    })
}

fn config() -> Criterion<Cpu> {
    measurement(false)
}

fn config_process() -> Criterion<Cpu> {
    let thread = std::env::var_os("NOETHER_BENCH_POOL_CLOCK").is_some_and(|v| v == "thread");
    measurement(!thread)
}

const KEYS: [u8; 8] = [0, 4, 7, 12, 16, 19, 24, 28];

/// The first `voices` keys of [`KEYS`] from an octave below the root key of `params`.
fn chord(params: &SharedParams, voices: usize) -> Vec<u8> {
    let root = params.get(ParamId::RootKey) as u8;
    KEYS.iter().take(voices).map(|k| root - 12 + k).collect()
}

/// Benchmarks `name`/`parameter` in `g`: an engine on `params`, activated at 48 kHz with blocks
/// of 256 samples, whose every iteration strikes `keys` at velocity 0.8 and renders 0.1 s
/// (4800 samples). Before it, one strike and 20 blocks, after which every key must sound.
/// Returns the engine (and its handle) for the caller's counters.
fn bench_strikes(
    g: &mut BenchmarkGroup<'_, Cpu>,
    name: &str,
    parameter: impl std::fmt::Display,
    params: Arc<SharedParams>,
    keys: &[u8],
) -> (Engine, EngineHandle) {
    let (mut e, h) = Engine::new(params);
    e.activate(48_000.0, 256).unwrap();
    let (mut l, mut r) = (vec![0.0f32; 256], vec![0.0f32; 256]);
    let strike = |e: &mut Engine| {
        for &k in keys {
            e.note_on(k, 0.8);
        }
    };
    strike(&mut e);
    for _ in 0..20 {
        e.process(&mut l, &mut r);
    }
    assert_eq!(e.active_voices(), keys.len(), "{name} {parameter}");
    g.bench_function(BenchmarkId::new(name, parameter), |b| {
        b.iter(|| {
            strike(&mut e);
            for _ in 0..(4800 / 256) {
                e.process(&mut l, &mut r);
            }
            e.process(&mut l[..4800 % 256], &mut r[..4800 % 256]);
        })
    });
    (e, h)
}

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
            let keys = chord(&params, voices);
            bench_strikes(&mut g, stem, voices, params, &keys);
            // The crash without its cascade closure: the closure's cost is the ratio.
            if stem == "crash" {
                let params = Arc::new(SharedParams::new());
                preset.apply(&params).unwrap();
                params.set(ParamId::Polyphony, voices as f32).unwrap();
                params.set(ParamId::Closure, 0.0).unwrap();
                bench_strikes(&mut g, "crash-plain", voices, params, &keys);
                // With the closure but without the band above: the band's cost is the ratio.
                let params = Arc::new(SharedParams::new());
                preset.apply(&params).unwrap();
                params.set(ParamId::Polyphony, voices as f32).unwrap();
                params.set(ParamId::BandAbove, 0.0).unwrap();
                bench_strikes(&mut g, "crash-no-above", voices, params, &keys);
            }
        }
    }
    g.finish();
}

/// Four gong voices, `threads` 1 against 0 (file doc).
fn bench_pool(c: &mut Criterion<Cpu>) {
    let mut g = c.benchmark_group("engine_pool_0.1s_48k");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(4));
    for threads in [1.0f32, 0.0] {
        let params = preset_params(
            "gong-40N",
            &[(ParamId::Polyphony, 4.0), (ParamId::Threads, threads)],
        );
        let keys = chord(&params, 4);
        let (e, _h) = bench_strikes(&mut g, "gong-40N-4voices-threads", threads, params, &keys);
        println!(
            "threads {threads}: {} participants, {} jobs on workers, {} late jobs",
            e.threads_used(),
            e.worker_jobs(),
            e.late_jobs()
        );
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = config();
    targets = bench
}
/// One moonshot voice, `threads` 1 against 0 (file doc).
fn bench_split(c: &mut Criterion<Cpu>) {
    let mut g = c.benchmark_group("engine_split_0.1s_48k");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(6));
    for threads in [1.0f32, 0.0] {
        let params = preset_params(
            "gong-40N",
            &[
                (ParamId::Polyphony, 1.0),
                (ParamId::BandLimit, 11_700.0),
                (ParamId::Modes, 1030.0),
                (ParamId::Threads, threads),
            ],
        );
        let root = [params.get(ParamId::RootKey) as u8];
        let (e, _h) = bench_strikes(&mut g, "moonshot-11.7kHz-threads", threads, params, &root);
        println!(
            "threads {threads}: {} halves on the worker, {} late",
            e.shared_step_halves(),
            e.late_step_halves()
        );
    }
    g.finish();
}

criterion_group! {
    name = pool;
    config = config_process();
    targets = bench_pool, bench_split
}
criterion_main!(benches, pool);
