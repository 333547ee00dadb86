//! Stiff string against an obstacle (SEED.md 3.2): exactness of the linear scheme, the DST grid
//! map, the offline render path, parameter errors. Every test prints the figures it checks
//! (`--nocapture`). Energy conservation with contact and the power balance with losses and
//! forcing (with the Newton counters) are the catalogue's (`tests/schemes/catalogue.rs`).

use noether::analysis::frequency::measure;
use noether::models::string::{
    ContactLaw, ContactScheme, Losses, ModalMap, Obstacle, OutputChannel, Quantity, Readout,
    StiffString, Stiffness, StrikeForce, StringConfig, StringParams, TrianglePluck, ValetteLosses,
};
use noether::render::offline::render;
use noether::render::source::RenderSource;

// ---------------------------------------------------------------- the lecture string

/// Lecture string (L = 1 m, T = 180.5 N, μ = 1.17e-3 kg/m, B = 2e-5, d = 0.43 mm) with the
/// lecture's contact law (K = 1e13, α = 1.5) and the given grid, rate, losses and obstacle;
/// outputs: grid displacement at 0.37 m, modal velocity at 0.37 m, obstacle force.
fn lecture(n: usize, fs: f64, losses: Losses, obstacle: Obstacle) -> StiffString {
    noether_testkit::harness::lecture_string(
        n,
        fs,
        losses,
        obstacle,
        ContactScheme::NewtonDiscreteGradient,
    )
}

/// The lecture's pluck: triangle of 1 mm at 0.3 m, at rest.
fn pluck(s: &mut StiffString) {
    s.pluck(&TrianglePluck {
        position: 0.3,
        amplitude: 1e-3,
    })
    .unwrap();
}

// ---------------------------------------------------------------- linear exactness

/// Single-mode initial condition `q = e_j`: the grid pickup must oscillate at exactly ω_j.
/// Tolerance 1e-9 relative: `measure` locates crossings to ~1e-12 of a period over tens of
/// periods while `ω_j h ≲ 0.3` (its degree-7 interpolant loses accuracy beyond, so faster
/// partials are checked sample by sample in `modes_above_nyquist_keep_exact_samples`); the
/// scheme's own frequency error is round-off, so anything above 1e-9 is a bug (the θ = 1
/// explicit scheme at 48 kHz is off by ~3e-4 at 4 kHz).
#[test]
fn partial_frequencies_are_exact_at_several_rates() {
    for &(fs, n, modes, seconds) in &[
        (8_000.0, 64, &[1usize, 2][..], 1.0),
        (48_000.0, 64, &[1, 5, 11][..], 0.5),
        (2_000_000.0, 64, &[1, 20, 60][..], 0.12),
    ] {
        let mut s = lecture(n, fs, Losses::None, Obstacle::None);
        let p = s.params().clone();
        for &j in modes {
            let mut q0 = vec![0.0; n - 1];
            q0[j - 1] = 1e-4;
            s.set_modal_state(&q0, &vec![0.0; n - 1]);
            let steps = (seconds * fs) as usize;
            let mut out = vec![vec![0.0; steps]; 3];
            s.process(&mut out, steps);
            let m = measure(&out[0], 1.0 / fs).expect("oscillation");
            let rel = m.omega / p.omega(j) - 1.0;
            eprintln!(
                "fs {fs:>9} mode {j:>2}: f = {:.6} Hz, {} periods, rel error {rel:.2e}",
                p.omega(j) / std::f64::consts::TAU,
                m.periods
            );
            assert!(rel.abs() < 1e-9, "fs {fs} mode {j}: {rel:e}");
        }
    }
}

/// At fs = 8 kHz most of the 63 modes are above Nyquist; their samples must still be exactly
/// `q0 cos(ω_j n h)` (aliased, not unstable or detuned). Tolerance 1e-9 of q0 after 8000 steps:
/// the two-step recursion's round-off grows at most linearly, ~n·ε/|sin ω_j h| ≲ 1e-10 here.
#[test]
fn modes_above_nyquist_keep_exact_samples() {
    let (n, fs) = (64, 8_000.0);
    let mut s = lecture(n, fs, Losses::None, Obstacle::None);
    let p = s.params().clone();
    let q0: Vec<f64> = (1..n).map(|j| 1.0 / j as f64).collect();
    s.set_modal_state(&q0, &vec![0.0; n - 1]);
    let above = (1..n).filter(|&j| p.omega(j) / p.sample_rate > std::f64::consts::PI);
    eprintln!("modes above Nyquist at 8 kHz: {}", above.count());
    let mut worst = 0.0f64;
    for step in 1..=8000usize {
        s.step();
        for (j, &q) in s.modal_displacement().iter().enumerate() {
            let want = q0[j] * (p.omega(j + 1) * (step + 1) as f64 / fs).cos();
            worst = worst.max((q - want).abs() / q0[j]);
        }
    }
    eprintln!("worst sample error / q0 over 8000 steps: {worst:.2e}");
    assert!(worst < 1e-9, "{worst:e}");
}

/// σ = ω (critical) and σ = 3ω (overdamped) via per-mode losses: no 0/0, and the samples
/// follow the closed forms `(1 + σt)e^{-σt}` and the two-exponential decay to 1e-12 of q0
/// (round-off of a few hundred steps of a contracting recursion).
#[test]
fn critical_and_overdamped_modes_follow_closed_forms() {
    let (n, fs) = (8, 48_000.0);
    let p = StringParams::lecture_guitar(n, fs);
    let (w1, w2) = (p.omega(1), p.omega(2));
    let mut sig = vec![0.0; n - 1];
    sig[0] = w1;
    sig[1] = 3.0 * w2;
    let mut s = lecture(n, fs, Losses::PerMode(sig), Obstacle::None);
    let mut q0 = vec![0.0; n - 1];
    q0[0] = 1.0;
    q0[1] = 1.0;
    s.set_modal_state(&q0, &vec![0.0; n - 1]);
    let lam = (9.0f64 - 1.0).sqrt() * w2;
    let s2 = 3.0 * w2;
    let mut worst = 0.0f64;
    for step in 1..400 {
        s.step();
        let t = (step + 1) as f64 / fs;
        let c1 = (1.0 + w1 * t) * (-w1 * t).exp();
        // q(0) = 1, q̇(0) = 0: ((λ+σ)e^{(λ-σ)t} + (λ-σ)e^{-(λ+σ)t}) / (2λ)
        let c2 = ((lam + s2) * ((lam - s2) * t).exp() + (lam - s2) * (-(lam + s2) * t).exp())
            / (2.0 * lam);
        let q = s.modal_displacement();
        worst = worst.max((q[0] - c1).abs()).max((q[1] - c2).abs());
    }
    eprintln!("critical / overdamped worst sample error: {worst:.2e}");
    assert!(worst < 1e-12, "{worst:e}");
}

// ---------------------------------------------------------------- grid map

/// The DST-I route and the dense matrix `S` agree to 1e-12 relative (max-norm) for small and
/// large N, both directions (`S⁻¹ = Δx S`); the dense `S·(Δx S)` is the identity to 1e-13.
#[test]
fn dst_and_dense_maps_agree() {
    for &n in &[3usize, 8, 27, 64, 501, 1000] {
        let l = 1.0;
        let m = n - 1;
        let dense = ModalMap::dense(l, n);
        let mut map = ModalMap::new(l, n);
        let x: Vec<f64> = (0..m)
            .map(|i| ((i * 37 + 11) % 101) as f64 / 50.0 - 1.0)
            .collect();
        let want: Vec<f64> = (0..m)
            .map(|i| (0..m).map(|j| dense[i * m + j] * x[j]).sum())
            .collect();
        let mut y = x.clone();
        map.synthesis(&mut y);
        let scale = want.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        let err = y
            .iter()
            .zip(&want)
            .fold(0.0f64, |a, (u, v)| a.max((u - v).abs()))
            / scale;
        let mut z = x.clone();
        map.analysis(&mut z);
        let dx = l / n as f64;
        let err_inv = z
            .iter()
            .zip(&want)
            .fold(0.0f64, |a, (u, v)| a.max((u - dx * v).abs()))
            / (dx * scale);
        eprintln!("N = {n:>4}: DST vs dense rel error {err:.1e}, inverse {err_inv:.1e}");
        assert!(
            err < 1e-12 && err_inv < 1e-12,
            "N = {n}: {err:e} {err_inv:e}"
        );
        if n <= 64 {
            for i in 0..m {
                for k in 0..m {
                    let sij: f64 = (0..m)
                        .map(|j| dense[i * m + j] * dx * dense[j * m + k])
                        .sum();
                    let id = if i == k { 1.0 } else { 0.0 };
                    assert!((sij - id).abs() < 1e-13, "N = {n} ({i},{k}): {sij}");
                }
            }
        }
    }
}

/// Grid readout at a node equals the modal sum there (both read the same field), to 1e-12
/// relative.
#[test]
fn grid_and_modal_pickups_agree_at_a_node() {
    let n = 100;
    let mk = |readout| OutputChannel::Pickup {
        position: 0.37,
        quantity: Quantity::Displacement,
        readout,
    };
    let mut s = StiffString::new(&StringConfig {
        params: StringParams::lecture_guitar(n, 48_000.0),
        losses: Losses::None,
        obstacle: Obstacle::None,
        contact: ContactLaw::lecture(),
        outputs: vec![mk(Readout::Grid), mk(Readout::Modal)],
    })
    .unwrap();
    pluck(&mut s);
    let mut out = vec![vec![0.0; 500]; 2];
    s.process(&mut out, 500);
    let scale = out[0].iter().fold(0.0f64, |a, b| a.max(b.abs()));
    for (a, b) in out[0].iter().zip(&out[1]) {
        assert!((a - b).abs() < 1e-12 * scale, "{a} {b}");
    }
}

/// The offline renderer runs the model as a `RenderSource` and reports the same conservation.
#[test]
fn offline_renderer_runs_the_string() {
    let mut s = lecture(200, 48_000.0, Losses::None, Obstacle::tanpura());
    pluck(&mut s);
    let r = render(&mut s, 0.2, 48_000, 1.0, 100, |_| {}).unwrap();
    eprintln!(
        "render: drift {:.2e}, extras {:?}",
        r.stats.energy.max_rel_drift,
        s.details()
    );
    assert_eq!(r.sim.len(), 3);
    assert_eq!(r.stats.nan_count, 0);
    assert!(r.stats.energy.max_rel_drift < 1e-10);
}

// ---------------------------------------------------------------- parameter errors

/// Every bad input is rejected with a `ParamError` naming its field.
#[test]
fn bad_parameters_name_the_field() {
    let base = StringConfig {
        params: StringParams::lecture_guitar(100, 48_000.0),
        losses: Losses::None,
        obstacle: Obstacle::None,
        contact: ContactLaw::lecture(),
        outputs: vec![OutputChannel::ObstacleForce],
    };
    let field = |c: StringConfig| StiffString::new(&c).unwrap_err().field;
    let with = |f: &dyn Fn(&mut StringConfig)| {
        let mut c = base.clone();
        f(&mut c);
        c
    };
    assert_eq!(field(with(&|c| c.params.length = 0.0)), "length");
    assert_eq!(field(with(&|c| c.params.tension = f64::NAN)), "tension");
    assert_eq!(
        field(with(&|c| c.params.linear_density = -1.0)),
        "linear_density"
    );
    assert_eq!(
        field(with(
            &|c| c.params.stiffness = Stiffness::BendingStiffness(-1.0)
        )),
        "bending_stiffness"
    );
    assert_eq!(
        field(with(
            &|c| c.params.stiffness = Stiffness::Inharmonicity(f64::INFINITY)
        )),
        "inharmonicity"
    );
    assert_eq!(field(with(&|c| c.params.diameter = -1e-3)), "diameter");
    assert_eq!(field(with(&|c| c.params.intervals = 1)), "intervals");
    assert_eq!(field(with(&|c| c.params.sample_rate = 0.0)), "sample_rate");
    assert_eq!(
        field(with(&|c| c.contact.stiffness = 0.0)),
        "contact.stiffness"
    );
    assert_eq!(
        field(with(&|c| c.contact.exponent = 0.5)),
        "contact.exponent"
    );
    assert_eq!(
        field(with(&|c| c.losses = Losses::PerMode(vec![0.0; 3]))),
        "losses.sigma.len"
    );
    assert_eq!(
        field(with(&|c| c.losses = Losses::Valette(ValetteLosses {
            air_density: -1.0,
            ..Default::default()
        }))),
        "losses.air_density"
    );
    assert_eq!(
        field(with(&|c| c.obstacle = Obstacle::Point {
            position: 1.5,
            height: 0.0,
            width: 0.0
        })),
        "obstacle.position"
    );
    assert_eq!(
        field(with(
            &|c| c.obstacle = Obstacle::Points(vec![(0.5, 0.0), (0.2, f64::NAN)])
        )),
        "obstacle.points[1].height"
    );
    assert_eq!(
        field(with(
            &|c| c.obstacle = Obstacle::Fretboard { distance: -1.0 }
        )),
        "obstacle.distance"
    );
    assert_eq!(
        field(with(&|c| c.outputs = vec![OutputChannel::Pickup {
            position: 0.0,
            quantity: Quantity::Velocity,
            readout: Readout::Grid
        }])),
        "outputs[0].position"
    );
    let mut s = StiffString::new(&base).unwrap();
    let e = s
        .pluck(&TrianglePluck {
            position: 0.3,
            amplitude: f64::NAN,
        })
        .unwrap_err();
    assert_eq!(e.field, "pluck.amplitude");
    let e = s
        .strike(&StrikeForce {
            position: 0.3,
            duration: 0.0,
            peak: 1.0,
        })
        .unwrap_err();
    assert_eq!(e.field, "strike.duration");
    assert!(e.to_string().contains("strike.duration") && e.to_string().contains("> 0"));
}
