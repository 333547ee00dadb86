//! Engine CPU per second of 48 kHz audio for each factory preset with 1, 4 and 8 sounding
//! voices. One iteration renders 0.1 s (4 800 samples in 256-sample blocks) after re-striking
//! every voice, so the voices keep sounding; criterion's time per iteration × 10 is the CPU
//! time per second of audio (real time on one core needs < 1 s).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use noether::engine::{Engine, ParamId, Preset, SharedParams};
use std::sync::Arc;
use std::time::Duration;

const KEYS: [u8; 8] = [0, 4, 7, 12, 16, 19, 24, 28];

fn bench(c: &mut Criterion) {
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

criterion_group!(benches, bench);
criterion_main!(benches);
