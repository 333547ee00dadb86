//! Strings coupled through a moving bridge (`noether::models::network`): the closed form of
//! two identical one-mode strings on a one-mode bridge, the network's energy without and with
//! losses, sympathy (an unplucked string in tune rings, one a semitone away barely does, and
//! none rings on a bridge that cannot move), and the real-time step without allocation.

use noether::models::network::{
    BridgeMode, NetworkConfig, NetworkOutput, SeatedString, StringNetwork,
};
use noether::models::string::{
    ContactLaw, Losses, Obstacle, OutputChannel, Quantity, Readout, SeatSpec, StringConfig,
    StringParams, TrianglePluck, ValetteLosses,
};
use std::f64::consts::TAU;

/// The lecture's string (1 m, 180.5 N, 196 Hz) with `intervals` grid intervals at `fs`, its
/// tension scaled by `tension_ratio`, a pickup at 0.37 m (displacement, grid).
fn string(
    intervals: usize,
    fs: f64,
    tension_ratio: f64,
    losses: Losses,
    obstacle: Obstacle,
) -> StringConfig {
    let mut params = StringParams::lecture_guitar(intervals, fs);
    params.tension *= tension_ratio;
    StringConfig {
        params,
        losses,
        obstacle,
        contact: ContactLaw::lecture(),
        outputs: vec![OutputChannel::Pickup {
            position: 0.37,
            quantity: Quantity::Displacement,
            readout: Readout::Grid,
        }],
    }
}

/// Two identical one-mode strings (`N = 2`: the single node at L/2 is the mode, effective mass
/// `m = μL/2`, stiffness `mω²`) seated at that node by springs `K` on one bridge mode
/// (`M`, `Ω`, shape 1 under both). The normal modes in closed form:
/// antisymmetric `ω_A² = ω² + K/m` (the bridge at rest); symmetric, the roots of
/// `(a - λ)(d - λ) = 2K²/(mM)`, `a = ω² + K/m`, `d = Ω² + 2K/M`, with bridge/string ratio
/// `r = (a - λ)m/K`. Striking string A alone (`u̇_A(0) = V`, everything else at rest) gives
/// `u_B(t) = α₁ sin(ω₁t)/ω₁ + α₂ sin(ω₂t)/ω₂ - (V/2) sin(ω_A t)/ω_A`,
/// `α₁ = (V/2) r₂/(r₂ - r₁)`, `α₂ = -(V/2) r₁/(r₂ - r₁)`: string B's energy beats at
/// `|ω₁ - ω_A|` (here 1.75 Hz: it first holds nearly all of A's energy at 0.281 s).
///
/// (A strike, not a pluck: the model's start `(u¹, u⁰)` is the free motion's, exact while
/// the coupling force is zero, and it is zero at a strike's start; a pluck's seat force would
/// be left out of the first step, a first-order error.)
/// Over 1 s the simulated `u_B` follows the closed form within 1.2 % of `A = V/ω_A` at 96 kHz
/// (measured 7.0e-3) and the error falls 4-fold at twice the rate (second order: the
/// coupling's averages `(w^{n+1} + w^{n-1})/2` shift the coupled frequencies by `O((ωh)²)`, a
/// phase error growing linearly in time; measured order 2.00). String
/// B's own energy `m(u̇² + ω²u²)/2` is fullest within 0.5 % of the closed form's time.
#[test]
fn two_strings_on_a_bridge_beat_as_the_closed_form_says() {
    let at_96k = beat_against_closed_form(96_000.0);
    let at_192k = beat_against_closed_form(192_000.0);
    let order = (at_96k / at_192k).log2();
    eprintln!("u_B error {at_96k:.2e} (96 kHz), {at_192k:.2e} (192 kHz): order {order:.2}");
    assert!(
        at_96k < 1.2e-2,
        "u_B off the closed form by {at_96k:.2e} of A"
    );
    assert!(
        (order - 2.0).abs() < 0.2,
        "convergence order {order:.2}, want 2"
    );
}

/// One run of [`two_strings_on_a_bridge_beat_as_the_closed_form_says`] at `fs`: returns the
/// largest `|u_B - closed form|` over 1 s relative to `A`, after checking the time string B is
/// fullest.
fn beat_against_closed_form(fs: f64) -> f64 {
    let (k_seat, m_bridge, f_bridge) = (200.0, 0.005, 260.0);
    let one = || {
        let mut cfg = string(2, fs, 1.0, Losses::None, Obstacle::None);
        // The pickup on the single node (at 0.37 m it would read 0.74 of it, the grid's
        // linear interpolation).
        cfg.outputs = vec![OutputChannel::Pickup {
            position: 0.5,
            quantity: Quantity::Displacement,
            readout: Readout::Grid,
        }];
        SeatedString {
            config: cfg,
            seat: SeatSpec {
                position: 0.5,
                stiffness: k_seat,
            },
            bridge_shape: vec![1.0],
            band_limit: f64::INFINITY,
        }
    };
    let mut net = StringNetwork::new(&NetworkConfig {
        strings: vec![one(), one()],
        bridge: vec![BridgeMode {
            frequency: f_bridge,
            mass: m_bridge,
            t60: f64::INFINITY,
        }],
        outputs: vec![NetworkOutput::String {
            string: 1,
            channel: 0,
        }],
    })
    .unwrap();
    let p = StringParams::lecture_guitar(2, fs);
    let phi = p.mode_shape(1, 0.5);
    let speed = 1.0;
    net.string_mut(0).set_modal_state(&[0.0], &[speed / phi]);
    net.string_mut(1).set_modal_state(&[0.0], &[0.0]);

    let m = p.linear_density * p.length / 2.0;
    let w2 = p.omega(1).powi(2);
    let (a, d) = (
        w2 + k_seat / m,
        (TAU * f_bridge).powi(2) + 2.0 * k_seat / m_bridge,
    );
    let s = ((0.5 * (a - d)).powi(2) + 2.0 * k_seat * k_seat / (m * m_bridge)).sqrt();
    let (l1, l2) = (0.5 * (a + d) - s, 0.5 * (a + d) + s);
    let (r1, r2) = ((a - l1) * m / k_seat, (a - l2) * m / k_seat);
    let (w1, wb, wa) = (l1.sqrt(), l2.sqrt(), a.sqrt());
    let amp = speed / wa;
    let alpha1 = 0.5 * speed * r2 / (r2 - r1);
    let alpha2 = -0.5 * speed * r1 / (r2 - r1);
    let closed = |t: f64| {
        alpha1 * (w1 * t).sin() / w1 + alpha2 * (wb * t).sin() / wb
            - 0.5 * speed * (wa * t).sin() / wa
    };
    let closed_velocity =
        |t: f64| alpha1 * (w1 * t).cos() + alpha2 * (wb * t).cos() - 0.5 * speed * (wa * t).cos();
    let own_energy = |u: f64, v: f64| 0.5 * m * (v * v + w2 * u * u);

    let h = 1.0 / fs;
    let first_beat = std::f64::consts::PI / (w1 - wa).abs();
    let (mut worst, mut sim_best, mut cf_best) = (0.0f64, (0.0f64, 0.0), (0.0f64, 0.0));
    for n in 0..fs as usize {
        net.step();
        // After n+1 steps from the initial (u¹, u⁰) the state is u^{n+2}.
        let t = (n + 2) as f64 * h;
        let u_b = net.output(0);
        worst = worst.max((u_b - closed(t)).abs());
        if t < 1.5 * first_beat {
            let b = &net.strings()[1];
            let e = b.energy_terms().total() - b.seat_energy();
            if e > sim_best.0 {
                sim_best = (e, t);
            }
            let e = own_energy(closed(t), closed_velocity(t));
            if e > cf_best.0 {
                cf_best = (e, t);
            }
        }
    }
    eprintln!(
        "{fs} Hz: beat {:.4} Hz; u_B error {:.2e} of A; B fullest at {:.4} s (closed form {:.4} s)",
        (w1 - wa).abs() / TAU,
        worst / amp,
        sim_best.1,
        cf_best.1
    );
    assert!(
        (sim_best.1 / cf_best.1 - 1.0).abs() < 5e-3,
        "B fullest at {} s, closed form {} s",
        sim_best.1,
        cf_best.1
    );
    worst / amp
}

/// The bridge of the network tests: two modes (a bounce at 180 Hz, 40 g, and a rocking mode
/// at 430 Hz, 25 g), lossless or with the given T60.
fn bridge(t60: f64) -> Vec<BridgeMode> {
    vec![
        BridgeMode {
            frequency: 180.0,
            mass: 0.04,
            t60,
        },
        BridgeMode {
            frequency: 430.0,
            mass: 0.025,
            t60,
        },
    ]
}

/// Three lecture strings (Sa, Pa below, Sa below by tension) on the two-mode bridge, each
/// with a point jawari 10 mm from its end riding on the bridge and seated 5 mm from the end;
/// string 0 plucked 1 mm at 0.3 m.
fn drone(fs: f64, losses: Losses, t60: f64) -> StringNetwork {
    band_limited_drone(fs, losses, t60, f64::INFINITY)
}

/// [`drone`] with every string stepping only its modes below `band` Hz.
fn band_limited_drone(fs: f64, losses: Losses, t60: f64, band: f64) -> StringNetwork {
    let shapes = [[1.0, 0.8], [1.0, 0.0], [0.9, -0.7]];
    // Tension ratios: Pa below Sa (3/4 of its frequency), Sa an octave below.
    let ratios = [1.0, 0.5625, 0.25];
    let strings = shapes
        .iter()
        .zip(ratios)
        .map(|(sh, r)| SeatedString {
            config: string(
                200,
                fs,
                r,
                losses.clone(),
                Obstacle::Point {
                    position: 0.01,
                    height: 0.0,
                    width: 0.0,
                },
            ),
            seat: SeatSpec {
                position: 0.005,
                stiffness: 2e5,
            },
            bridge_shape: sh.to_vec(),
            band_limit: band,
        })
        .collect();
    let mut net = StringNetwork::new(&NetworkConfig {
        strings,
        bridge: bridge(t60),
        outputs: vec![NetworkOutput::Bridge {
            quantity: Quantity::Velocity,
            weights: vec![1.0, 0.5],
        }],
    })
    .unwrap();
    pluck_first(&mut net);
    net
}

/// Plucks string 0 by 1 mm at 0.3 m.
fn pluck_first(net: &mut StringNetwork) {
    let pluck = TrianglePluck {
        position: 0.3,
        amplitude: 1e-3,
    };
    net.pluck(0, &pluck).unwrap();
}

/// Without losses the network's energy (three strings with their jawari contacts and seats,
/// the two-mode bridge) is conserved to round-off over 0.5 s at 48 kHz: measured 2e-14 of
/// the largest energy, bound 1e-12 (the Newton solves' 1e-13 tolerance times the few
/// thousand contact steps, still round-off). The unplucked strings take energy from the
/// bridge (each above 1e-6 of the total at the end), so the coupling is not idle; the
/// jawari was touched. With the strings' and the bridge's losses, the power balance closes
/// to the same bound.
///
/// The same holds with every string band-limited to 20 kHz (about half of its 199 modes
/// stepped, the jawari and the seat solved against their compliance: `StiffString::
/// set_band_limit`).
#[test]
fn the_network_conserves_its_energy_and_closes_its_balance() {
    for (what, losses, t60, band) in [
        ("lossless", Losses::None, f64::INFINITY, f64::INFINITY),
        (
            "lossy",
            Losses::Valette(ValetteLosses::default()),
            1.5,
            f64::INFINITY,
        ),
        ("lossless, band-limited", Losses::None, f64::INFINITY, 20e3),
        (
            "lossy, band-limited",
            Losses::Valette(ValetteLosses::default()),
            1.5,
            20e3,
        ),
    ] {
        let mut net = band_limited_drone(48_000.0, losses, t60, band);
        if band.is_finite() {
            let stepped = net.strings()[0].stepped_modes();
            assert!(
                (60..150).contains(&stepped),
                "{what}: {stepped} modes stepped"
            );
        }
        let b0 = net.energy_terms().balance();
        let (mut worst, mut e_max) = (0.0f64, 0.0f64);
        for _ in 0..24_000 {
            net.step();
            let e = net.energy_terms();
            e_max = e_max.max(e.total());
            worst = worst.max((e.balance() - b0).abs());
        }
        let rel = worst / e_max;
        let total = net.energy_terms().total();
        let shares: Vec<f64> = (1..3)
            .map(|s| net.string_energy(s).total() / total)
            .collect();
        let contact = net.strings()[0].contact_stats().contact_steps;
        let stats = net.stats();
        eprintln!(
            "{what}: balance {rel:.2e} of the largest energy; unplucked shares {shares:?}; \
             contact steps {contact}; Newton mean {:.2}, max {}, cap hits {}",
            stats.iterations as f64 / stats.steps as f64,
            stats.max_iterations,
            stats.cap_hits
        );
        assert!(rel < 1e-12, "{what}: balance off by {rel:.2e}");
        assert!(
            shares.iter().all(|&s| s > 1e-6),
            "{what}: shares {shares:?}"
        );
        assert!(contact > 0, "{what}: the jawari was never touched");
        assert_eq!(stats.cap_hits, 0, "{what}");
    }
}

/// A band limit above every mode steps them all, and the network follows the full one to
/// round-off: the compliance of all the modes is `k` at a node and 0 between nodes (the sine
/// transform's orthogonality, computed as a sum of products: 1e-15 relative), so the coupled
/// point solve is the full string's per-node solve. Over 0.25 s (with the jawari touched) the
/// bridge's velocity differs by at most 1e-9 of its peak (measured 3e-13: the rounding of the
/// two paths, carried by the contact's nonlinearity).
#[test]
fn a_band_limit_above_every_mode_changes_nothing() {
    let mut full = drone(48_000.0, Losses::None, f64::INFINITY);
    let mut limited = band_limited_drone(48_000.0, Losses::None, f64::INFINITY, 1e9);
    assert_eq!(limited.strings()[0].stepped_modes(), 199);
    let (mut diff, mut peak) = (0.0f64, 0.0f64);
    for _ in 0..12_000 {
        full.step();
        limited.step();
        let (a, b) = (full.output(0), limited.output(0));
        diff = diff.max((a - b).abs());
        peak = peak.max(a.abs());
    }
    eprintln!(
        "full against limited above every mode: {:.2e} of the peak",
        diff / peak
    );
    assert!(full.strings()[0].contact_stats().contact_steps > 0);
    assert!(diff <= 1e-9 * peak, "{:.2e} of the peak", diff / peak);
}

/// A band-limited string follows its limit through a retune: the tension raised fourfold (an
/// octave up) lifts its modes, fewer lie below 20 kHz, and those that climb over it are
/// dropped, their energy booked as the retune's work, so the power balance still closes.
#[test]
fn a_band_limit_follows_a_retune() {
    let mut net = band_limited_drone(48_000.0, Losses::None, f64::INFINITY, 20e3);
    for _ in 0..2400 {
        net.step();
    }
    let before = net.strings()[0].stepped_modes();
    let tension = net.strings()[0].params().tension;
    let b0 = net.energy_terms().balance();
    assert!(net.retune_string(0, 4.0 * tension, 0.0, 0.0));
    let after = net.strings()[0].stepped_modes();
    assert!(
        after < before && after > before / 3,
        "{before} -> {after} modes"
    );
    let mut e_max = 0.0f64;
    let mut worst = 0.0f64;
    for _ in 0..4800 {
        net.step();
        let e = net.energy_terms();
        e_max = e_max.max(e.total());
        worst = worst.max((e.balance() - b0).abs());
    }
    assert!(
        worst < 1e-12 * e_max,
        "balance off by {:.2e}",
        worst / e_max
    );
}

/// Sympathy: string 0 plucked, string 1 unplucked; after 1 s string 1 holds at least 100
/// times more energy when it is tuned to string 0 than when it is a semitone above (measured
/// in the docs' table); on a bridge 10⁶ times heavier (one that barely moves) the tuned string
/// holds less than 1e-6 of what it holds on the real bridge.
#[test]
fn a_string_in_tune_rings_in_sympathy_and_one_a_semitone_away_does_not() {
    let fs = 48_000.0;
    let run = |ratio: f64, mass_scale: f64| {
        let mk = |r: f64| SeatedString {
            config: string(
                200,
                fs,
                r,
                Losses::Valette(ValetteLosses::default()),
                Obstacle::None,
            ),
            seat: SeatSpec {
                position: 0.005,
                stiffness: 2e5,
            },
            bridge_shape: vec![1.0, 0.5],
            band_limit: f64::INFINITY,
        };
        let mut modes = bridge(1.0);
        for m in &mut modes {
            m.mass *= mass_scale;
        }
        let mut net = StringNetwork::new(&NetworkConfig {
            strings: vec![mk(1.0), mk(ratio)],
            bridge: modes,
            outputs: vec![],
        })
        .unwrap();
        pluck_first(&mut net);
        for _ in 0..fs as usize {
            net.step();
        }
        net.string_energy(1).total()
    };
    let semitone = 2f64.powf(1.0 / 6.0); // tension ratio of a semitone (f ∝ √T)
    let tuned = run(1.0, 1.0);
    let off = run(semitone, 1.0);
    let fixed = run(1.0, 1e6);
    eprintln!("sympathy: tuned {tuned:.3e} J, a semitone above {off:.3e} J (ratio {:.0}), fixed bridge {fixed:.3e} J", tuned / off);
    assert!(tuned > 100.0 * off, "tuned {tuned:e}, semitone {off:e}");
    assert!(
        fixed < 1e-6 * tuned,
        "fixed bridge {fixed:e}, tuned {tuned:e}"
    );
}

/// The network's step, pluck and reset do not allocate (the binary's counting allocator).
#[test]
fn the_network_steps_without_allocating() {
    let mut net = drone(48_000.0, Losses::Valette(ValetteLosses::default()), 1.5);
    let n = noether_testkit::alloc::count_allocations(|| {
        for _ in 0..2000 {
            net.step();
            std::hint::black_box(net.output(0));
        }
        net.pluck(
            1,
            &TrianglePluck {
                position: 0.4,
                amplitude: 5e-4,
            },
        )
        .unwrap();
        for _ in 0..2000 {
            net.step();
        }
        net.reset();
    })
    .1;
    assert_eq!(n, 0, "allocations in the network's real-time methods");
}

/// Bad configurations name the field.
#[test]
fn bad_networks_are_refused_with_the_field_named() {
    let mut cfg = NetworkConfig {
        strings: vec![SeatedString {
            config: string(200, 48_000.0, 1.0, Losses::None, Obstacle::tanpura()),
            seat: SeatSpec {
                position: 0.01,
                stiffness: 2e5,
            },
            bridge_shape: vec![1.0],
            band_limit: f64::INFINITY,
        }],
        bridge: vec![BridgeMode {
            frequency: 200.0,
            mass: 0.05,
            t60: 1.0,
        }],
        outputs: vec![],
    };
    StringNetwork::new(&cfg).unwrap();
    let field = |cfg: &NetworkConfig| StringNetwork::new(cfg).unwrap_err().field;
    cfg.strings[0].seat.position = 0.006; // the tanpura's obstacle node
    assert_eq!(field(&cfg), "network.strings[0].seat.position");
    cfg.strings[0].seat.position = 0.01;
    cfg.strings[0].bridge_shape = vec![1.0, 2.0];
    assert_eq!(field(&cfg), "network.strings[0].bridge_shape");
    cfg.strings[0].bridge_shape = vec![1.0];
    cfg.bridge[0].mass = 0.0;
    assert_eq!(field(&cfg), "bridge.modes[0].mass");
    cfg.bridge[0].mass = 0.05;
    cfg.outputs = vec![NetworkOutput::String {
        string: 3,
        channel: 0,
    }];
    assert_eq!(field(&cfg), "network.outputs[0].string");
}
