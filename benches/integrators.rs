//! Cost per step of every one-oscillator scheme and every N-DOF method.
//!
//! `cargo bench --bench integrators`. Figures quoted in the README are criterion medians.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use noether::schemes::ndof::{build_method, build_system, SystemSpec, METHOD_NAMES};
use noether::schemes::{build_oscillator, OscillatorSpec};
use std::hint::black_box;

const STEPS: u64 = 10_000;

fn oscillators(c: &mut Criterion) {
    let cases = [
        OscillatorSpec::Theta {
            omega0: 1.0,
            theta: 0.8,
        },
        OscillatorSpec::Exact {
            omega0: 1.0,
            xi: 0.1,
        },
        OscillatorSpec::DuffingVerlet {
            omega0: 1.0,
            gamma: 5.0,
        },
        OscillatorSpec::DuffingConservative {
            omega0: 1.0,
            gamma: 5.0,
            theta1: 0.8,
            theta2: 1.0,
        },
        OscillatorSpec::DuffingConservative {
            omega0: 1.0,
            gamma: 5.0,
            theta1: 1.0,
            theta2: 0.0,
        },
        OscillatorSpec::Impact {
            mass: 1.0,
            stiffness: 1.0,
            contact_stiffness: 1e13,
            alpha: 1.5,
            gap: 0.5,
            theta: 0.5,
        },
    ];
    let mut g = c.benchmark_group("oscillator-steps");
    g.throughput(Throughput::Elements(STEPS));
    for spec in cases {
        let h = if matches!(spec, OscillatorSpec::Impact { .. }) {
            1e-3
        } else {
            0.0628
        };
        let mut s = build_oscillator(&spec, h).unwrap();
        let id = match spec {
            OscillatorSpec::DuffingConservative { theta2, .. } => {
                format!("duffing-conservative-theta2={theta2}")
            }
            _ => spec.scheme_name().to_string(),
        };
        g.bench_function(id, |b| {
            b.iter(|| {
                s.reset(1.0, 0.0);
                for _ in 0..STEPS {
                    s.step();
                }
                black_box(s.displacement())
            })
        });
    }
    g.finish();
}

fn ndof_methods(c: &mut Criterion) {
    let system = build_system(&SystemSpec::Fpu {
        n: 8,
        k: 1.0,
        beta: 1.0,
    })
    .unwrap();
    let mut g = c.benchmark_group("fpu8-steps");
    g.throughput(Throughput::Elements(1000));
    for &name in METHOD_NAMES {
        let mut m = build_method(name, 8).unwrap();
        g.bench_function(name, |b| {
            b.iter(|| {
                let mut y = vec![0.0; 16];
                y[0] = 1.0;
                for _ in 0..1000 {
                    m.step(system.as_ref(), 0.1, &mut y);
                }
                black_box(y[0])
            })
        });
    }
    g.finish();
}

criterion_group!(benches, oscillators, ndof_methods);
criterion_main!(benches);
