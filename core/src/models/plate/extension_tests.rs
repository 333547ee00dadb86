//! The band above's tests: energy accounting of the closure's and the strike's feeds, and
//! the shares.

use super::*;

fn bank(n: usize, fs: f64, c: f64) -> BandExtension {
    let mut x = BandExtension::new(n);
    let omega: Vec<f64> = (0..n)
        .map(|e| std::f64::consts::TAU * (7000.0 + 40.0 * e as f64))
        .collect();
    x.retune(&omega, &vec![c; n], 6.88, 1.0 / fs);
    for (e, w) in x.pickup_weights_mut(0).iter_mut().enumerate() {
        *w = if e % 3 == 0 { 2.0 } else { -1.3 };
    }
    x
}

/// Every joule received is stored, pending or dissipated, to round-off, through feeding
/// and free decay, with and without damping.
#[test]
fn the_energy_received_is_accounted_to_round_off() {
    for c in [0.0, 40.0] {
        let mut x = bank(300, 48_000.0, c);
        for chunk in 0..400 {
            let e = if chunk < 200 {
                1e-3 * (chunk % 7) as f64
            } else {
                0.0
            };
            x.run(e, 0.0, 64, |_, _| {});
            let en = x.energy();
            assert!(
                en.balance().abs() <= 1e-12 * en.received,
                "chunk {chunk}, c = {c}: balance {:e} of {:e} received",
                en.balance(),
                en.received
            );
        }
        let en = x.energy();
        assert!(en.pending < 1e-15 * en.received, "{en:?}");
        if c == 0.0 {
            assert!((en.stored / en.received - 1.0).abs() < 1e-12, "{en:?}");
        } else {
            assert!(en.dissipated > 0.5 * en.received, "{en:?}");
        }
    }
}

/// Energy from the closure and the strike together (the strike at a point where a third
/// of the modes have a node) is accounted to round-off, and the lossless bank ends up
/// holding all of it; the strike's energy goes only to the modes the point reaches.
#[test]
fn the_strike_and_the_closure_are_accounted_to_round_off() {
    for c in [0.0, 40.0] {
        let mut x = bank(300, 48_000.0, c);
        let phi: Vec<f64> = (0..300)
            .map(|e| {
                if e % 3 == 1 {
                    0.0
                } else {
                    1.0 + 0.01 * e as f64
                }
            })
            .collect();
        x.set_strike(&phi);
        for chunk in 0..300 {
            let (e, s) = match chunk {
                0..=9 => (1e-3, 2e-3),
                10..=99 => (1e-4 * (chunk % 3) as f64, 0.0),
                _ => (0.0, 0.0),
            };
            x.run(e, s, 64, |_, _| {});
            let en = x.energy();
            let scale = en.received + en.struck;
            assert!(
                en.balance().abs() <= 1e-12 * scale,
                "chunk {chunk}, c = {c}: balance {:e} of {scale:e}",
                en.balance()
            );
        }
        let en = x.energy();
        assert!(en.pending < 1e-15 * (en.received + en.struck), "{en:?}");
        if c == 0.0 {
            let held = en.stored / (en.received + en.struck);
            assert!((held - 1.0).abs() < 1e-12, "{en:?}");
        }
    }
    // Struck alone, the modes on a node stay at rest.
    let mut x = bank(64, 48_000.0, 0.0);
    let phi: Vec<f64> = (0..64)
        .map(|e| if e % 3 == 1 { 0.0 } else { 1.0 })
        .collect();
    x.set_strike(&phi);
    x.run(0.0, 1.0, 64 * STRIDE, |_, _| {});
    for e in 0..64 {
        let moving = x.q[e] != 0.0 || x.q_prev[e] != 0.0;
        assert_eq!(moving, e % 3 != 1, "mode {e}");
    }
}

/// The shares follow `(ω/ω_0)^{-α}`: after feeding a lossless bank, the energy of each
/// turn's modes is in that ratio.
#[test]
fn the_energy_is_shared_by_the_spectral_slope() {
    let mut x = bank(64, 48_000.0, 0.0);
    x.run(1.0, 0.0, 64 * STRIDE, |_, _| {});
    let h = x.h;
    let energy = |e: usize| {
        let v = (x.q[e] - x.q_prev[e]) / h;
        0.5 * x.rho_h * (v * v + x.omega_sq[e] * x.q[e] * x.q_prev[e])
    };
    let w = |e: usize| 7000.0 + 40.0 * e as f64;
    for e in [9, 17, 40, 63] {
        let want = (w(e) / w(1)).powf(-SPECTRAL_SLOPE);
        let got = energy(e) / energy(1);
        assert!((got / want - 1.0).abs() < 0.02, "mode {e}: {got} vs {want}");
    }
}
