//! The two ways a string step computes grid values ([`GridSynthesis`]): one DST of the whole
//! grid, or dot products with stored rows of `S` at the obstacle and pickup nodes only. On the
//! lecture's sitar (SEED.md 3.2, `assets/scenes/seed-sitar.toml`: 1007 modes, fs = 2 MHz,
//! 20 bridge nodes, Valette losses) both must give the same sound, modal state and energy
//! account to round-off, and the on-demand grid must be the DST of the modal state.

use noether::models::string::{
    ContactLaw, GridSynthesis, Losses, ModalMap, Obstacle, OutputChannel, Quantity, Readout,
    StiffString, StringConfig, StringParams, TrianglePluck, ValetteLosses,
};
use noether::render::source::RenderSource;

/// The seed-sitar scene's string at `intervals` and `fs`: two grid velocity pickups (0.37 m,
/// 0.83 m) and the obstacle force, plucked 1 mm at 0.3 m.
fn sitar(intervals: usize, fs: f64) -> StiffString {
    let mut s = StiffString::new(&StringConfig {
        params: StringParams::lecture_guitar(intervals, fs),
        losses: Losses::Valette(ValetteLosses::default()),
        obstacle: Obstacle::seed_sitar(),
        contact: ContactLaw::lecture(),
        outputs: vec![
            OutputChannel::Pickup {
                position: 0.37,
                quantity: Quantity::Velocity,
                readout: Readout::Grid,
            },
            OutputChannel::Pickup {
                position: 0.83,
                quantity: Quantity::Velocity,
                readout: Readout::Grid,
            },
            OutputChannel::ObstacleForce,
        ],
    })
    .unwrap();
    s.pluck(&TrianglePluck {
        position: 0.3,
        amplitude: 1e-3,
    })
    .unwrap();
    s
}

/// Runs `steps` steps, returning every channel's samples.
fn run(s: &mut StiffString, steps: usize) -> Vec<Vec<f64>> {
    let mut out = vec![vec![0.0; steps]; s.channels()];
    s.process(&mut out, steps);
    out
}

/// Largest `|a - b|` over the largest `|b|`.
fn rel_diff(a: &[f64], b: &[f64]) -> f64 {
    let d = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    d / b.iter().fold(0.0f64, |m, y| m.max(y.abs()))
}

/// 5 ms of the 2 MHz sitar (10 000 steps, the string wraps onto the bridge and leaves it
/// several times: thousands of contact steps, all 20 nodes active at times) on both paths.
///
/// Tolerance 1e-10 relative (outputs, modal state, energy terms; measured: a few 1e-12). Each step's grid value at a
/// node differs between the paths by the round-off of an `N_m = 1007`-term sum, a few ulps ×
/// `√N_m` ≈ 1e-14 relative; the linear modal recursion is neutrally stable, so the difference
/// grows at most linearly with the step count (≤ 1e4 × 1e-14 = 1e-10), and the contact solve
/// adds differences at the level of its tolerance (`NEWTON_TOL` = 1e-13 relative per solve).
/// A wrong row, a missed node or a stale grid value gives differences of order 1 (the
/// contact force and the pickups would use another displacement), far above 1e-10.
#[test]
fn rows_and_dst_paths_agree_on_the_seed_sitar() {
    let (n, fs, steps) = (1008, 2_000_000.0, 10_000);
    let mut rows = sitar(n, fs);
    let mut dst = sitar(n, fs);
    assert_eq!(rows.grid_synthesis(), GridSynthesis::Rows);
    assert_eq!(
        dst.set_grid_synthesis(GridSynthesis::Dst),
        GridSynthesis::Dst
    );
    let (a, b) = (run(&mut rows, steps), run(&mut dst, steps));
    let contact = rows.contact_stats().contact_steps;
    assert_eq!(contact, dst.contact_stats().contact_steps);
    eprintln!("contact steps {contact} of {steps}");
    assert!(contact > 1000, "the run must exercise the contact");
    for (c, (x, y)) in a.iter().zip(&b).enumerate() {
        let d = rel_diff(x, y);
        eprintln!("channel {c}: relative difference {d:.2e}");
        assert!(d < 1e-10, "channel {c}: {d:e}");
    }
    let dq = rel_diff(rows.modal_displacement(), dst.modal_displacement());
    eprintln!("modal state: relative difference {dq:.2e}");
    assert!(dq < 1e-10, "{dq:e}");
    let (ea, eb) = (rows.energy_terms(), dst.energy_terms());
    for (name, x, y) in [
        ("kinetic", ea.kinetic, eb.kinetic),
        ("linear", ea.linear, eb.linear),
        ("contact", ea.nonlinear, eb.nonlinear),
        ("dissipated", ea.dissipated, eb.dissipated),
    ] {
        let d = (x - y).abs() / eb.total().max(eb.dissipated);
        eprintln!("{name}: {x:.6e} J vs {y:.6e} J, difference {d:.2e} of the energy scale");
        assert!(d < 1e-10, "{name}: {d:e}");
    }
}

/// On the rows path the whole grid is computed on demand from the modal state: it equals a
/// fresh DST of `q` exactly (same transform, same input), and at a stored node it equals the
/// step's own value (read through a grid displacement pickup sitting exactly on node 126,
/// x = 0.25 m) to round-off: tolerance 1e-12 of the largest displacement, a few ulps × √N_m
/// for N_m = 503 with margin.
#[test]
fn on_demand_grid_is_the_dst_of_the_modes() {
    let (n, fs) = (504, 384_000.0);
    let mut s = StiffString::new(&StringConfig {
        params: StringParams::lecture_guitar(n, fs),
        losses: Losses::Valette(ValetteLosses::default()),
        obstacle: Obstacle::tanpura(),
        contact: ContactLaw::lecture(),
        outputs: vec![OutputChannel::Pickup {
            position: 0.25,
            quantity: Quantity::Displacement,
            readout: Readout::Grid,
        }],
    })
    .unwrap();
    s.pluck(&TrianglePluck {
        position: 0.3,
        amplitude: 1e-3,
    })
    .unwrap();
    assert_eq!(s.grid_synthesis(), GridSynthesis::Rows);
    let out = run(&mut s, 3001);
    let q = s.modal_displacement().to_vec();
    let fresh = ModalMap::new(1.0, n).synthesized(&q);
    assert_eq!(s.grid_displacement(), &fresh[..]);
    let shape = s.shape(0.0).unwrap();
    assert_eq!(&shape.u[1..n], &fresh[..]);
    assert_eq!((shape.u[0], shape.u[n]), (0.0, 0.0));
    let scale = fresh.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let stepped = out[0][3000];
    let d = (stepped - fresh[125]).abs();
    eprintln!(
        "node 126: step {stepped:.6e} m, DST {:.6e} m, difference {d:.1e} m",
        fresh[125]
    );
    assert!(stepped.abs() > 1e-2 * scale, "the node must be moving");
    assert!(d <= 1e-12 * scale, "{d:e} of {scale:e}");
}
