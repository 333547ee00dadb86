//! The engine activates at every host rate a host may use and for every combination of
//! in-range parameter values (a plugin must never refuse the host): rates 8 kHz to 384 kHz,
//! seeded random parameter sets, every parameter alone at its bounds, all at their minima and
//! all at their maxima. Each activation must build the requested model (`Ok(None)`: no
//! fallback) and a note through it must be accepted by the model and give finite samples.
//!
//! Cost bound: the quality parameters (`modes`, `in_plane_modes`, `polyphony`, and the
//! drone's tuning by ear, seconds of simulation per string) are capped in the random and bound
//! draws so each build takes milliseconds from the modal cache; their full ranges are built
//! by the tier, preset and drone tests. (The drone keeps at least the modes its jivari needs.)

use noether::engine::{Engine, ParamId, ParamKind, ParamValues, SharedParams, PARAMS};
use noether_testkit::take;
use std::sync::Arc;

/// The host rates the published plugin validators try (Hz).
const HOST_RATES: [f64; 10] = [
    8_000.0, 11_025.0, 16_000.0, 22_050.0, 44_100.0, 48_000.0, 96_000.0, 176_400.0, 192_000.0,
    384_000.0,
];

/// Caps of the quality parameters in the random draws (see the module doc).
fn cap_quality(v: &mut ParamValues) {
    let caps = [
        (ParamId::Modes, 24.0),
        (ParamId::InPlaneModes, 6.0),
        (ParamId::Polyphony, 2.0),
        (ParamId::DroneEar, 0.0),
    ];
    for (id, cap) in caps {
        v.0[id.index()] = v.get(id).min(cap);
    }
}

/// Activates an engine on `v` at `rate`, plays a note for `seconds` and returns the output's
/// peak; panics (naming `what`) if activation fails, falls back, or the output is not finite.
fn play(v: &ParamValues, rate: f64, seconds: f64, what: &str) -> f32 {
    let params = Arc::new(SharedParams::new());
    params.set_all(v).unwrap();
    let (mut e, _h) = Engine::new(params);
    match e.activate(rate, 256) {
        Ok(None) => {}
        Ok(Some(refused)) => panic!("{what}: the model was refused ({refused})"),
        Err(err) => panic!("{what}: activation failed ({err})"),
    }
    // The root key: the model at its nominal parameters (other keys rescale them).
    e.note_on(v.get(ParamId::RootKey) as u8, 1.0);
    let t = take::render(&mut e, &[], (seconds * rate) as usize, 256);
    let (l, r) = (&t.left, &t.right);
    assert!(
        l.iter().chain(r).all(|x| x.is_finite()),
        "{what}: non-finite output"
    );
    // A note the model refuses (coefficients out of its stability region) is silence. The
    // conservative θ = 1 scheme (index 0) is only conditionally stable (ω h < 2): a plate
    // whose lowest 8 modes already lie above that at the bank's rate refuses its notes (the
    // refusal is counted and shown); the other schemes must accept every note.
    if v.index_of(ParamId::Scheme) != 0 || what.contains("theta") {
        assert_eq!(e.refused_notes(), 0, "{what}: the note was refused");
    }
    t.peak()
}

/// A small deterministic generator (xorshift64*), so a failing draw can be replayed.
struct Rng(u64);

impl Rng {
    fn unit(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A value of `p` drawn uniformly over its range (logarithmically for logarithmic ones,
/// integers and enumerations over their values).
fn draw(p: &noether::engine::ParamInfo, rng: &mut Rng) -> f32 {
    let (lo, hi) = (p.min as f64, p.max as f64);
    let u = rng.unit();
    match p.kind {
        ParamKind::Float { log: true } if lo > 0.0 => (lo * (hi / lo).powf(u)) as f32,
        ParamKind::Float { .. } => (lo + (hi - lo) * u) as f32,
        _ => (lo + ((hi - lo + 1.0) * u).floor()).min(hi) as f32,
    }
}

#[test]
fn activates_at_every_host_rate() {
    let mut gong = ParamValues::defaults();
    gong.set(ParamId::Modes, 64.0).unwrap();
    let mut tanpura = gong;
    tanpura.set(ParamId::Model, 4.0).unwrap();
    tanpura.set(ParamId::SimRate, 48_000.0).unwrap();
    for rate in HOST_RATES {
        for (name, v) in [("gong", &gong), ("tanpura", &tanpura)] {
            let peak = play(v, rate, 0.2, &format!("{name} at {rate} Hz"));
            // Sounding: a strike at velocity 1 gives peaks of 0.1-1 full scale; 1e-3 is far
            // below any working note and far above a silent (all-zero) output.
            assert!(peak > 1e-3, "{name} at {rate} Hz is silent (peak {peak})");
        }
    }
}

#[test]
fn random_in_range_parameter_sets_always_build() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for draw_index in 0..60 {
        let mut v = ParamValues::defaults();
        for p in PARAMS {
            v.0[p.id.index()] = draw(p, &mut rng);
        }
        cap_quality(&mut v);
        play(&v, 48_000.0, 0.02, &format!("draw {draw_index}: {:?}", v.0));
    }
}

#[test]
fn every_parameter_at_its_bounds_builds() {
    let mut all_min = ParamValues::defaults();
    let mut all_max = ParamValues::defaults();
    for p in PARAMS {
        all_min.0[p.id.index()] = p.min;
        all_max.0[p.id.index()] = p.max;
    }
    for model in 0..noether::engine::ModelKind::ALL.len() {
        for (name, base) in [("all at min", all_min), ("all at max", all_max)] {
            let mut v = base;
            v.0[ParamId::Model.index()] = model as f32;
            cap_quality(&mut v);
            play(&v, 48_000.0, 0.02, &format!("model {model}, {name}"));
        }
        for p in PARAMS {
            for x in [p.min, p.max] {
                let mut v = ParamValues::defaults();
                v.0[ParamId::Model.index()] = model as f32;
                v.0[p.id.index()] = x;
                cap_quality(&mut v);
                play(
                    &v,
                    48_000.0,
                    0.02,
                    &format!("model {model}, {} = {x}", p.key),
                );
            }
        }
    }
}

/// The lecture's gong with the conservative θ = 1 scheme, at its root key, sounds: the bank's
/// rate keeps the band within the scheme's stability limit and the note takes the largest
/// tier it integrates stably (at the rate of the exact schemes every note was refused).
#[test]
fn the_theta1_scheme_plays_the_gong() {
    let mut v = noether::engine::Preset::factory_named("gong-40N")
        .unwrap()
        .values()
        .unwrap();
    v.set(ParamId::Scheme, 0.0).unwrap();
    v.set(ParamId::Modes, 64.0).unwrap();
    let peak = play(&v, 48_000.0, 0.1, "gong-40N with the theta = 1 scheme");
    assert!(peak > 1e-3, "silent (peak {peak})");
}
