//! The bounded real-time soak (`noether_testkit::soak`): a seeded random host drives the
//! engine for a fixed number of blocks, [`BLOCKS`] (or `NOETHER_SOAK_BLOCKS`), so the seed
//! names the same main sequence of choices on any machine (blocks played while a rebuild is
//! pending come from a second sequence; their number follows the worker's speed), with
//! automation of every parameter each block, note storms, rebuild bursts (model, modes, rate,
//! scheme, polyphony) and host rate changes from 8 to 384 kHz with blocks of 1 to 8192
//! samples. A wall-time limit (`SoakConfig::wall_limit`, 220 s here) fails the test; it
//! never shortens the run.
//!
//! The global allocator of this test binary aborts on any allocation inside
//! `assert_no_alloc` (debug assertions are on in the test profile), which wraps every
//! `process_events` call. The soak itself fails on non-finite output, output above full
//! scale, and, in blocks played with the limiter on (the `limiter` parameter is automated
//! with the others, the gain over -60..+60 dB), output above the limiter's ceiling or any
//! sample the output stage's guard had to clip; on a rebuild that neither arrives nor is
//! refused within 30 s, or a failed activation. The `threads` parameter is automated like
//! the others, so the voices run on the voice pool's workers in most blocks (with the
//! real-time wait: on the loaded machine some jobs are late, which the summary counts), and
//! one burst in ten builds a gong whose voice splits each step with a worker. The
//! block time over its real-time duration is printed, not asserted (the machine is shared).
//! The longer run: `cargo run --release --example soak`.

use assert_no_alloc::assert_no_alloc;
use noether::engine::{Engine, ParamId, Preset, SharedParams, VOICE_CEILING};
use noether_testkit::soak::{self, SoakConfig};
use std::sync::Arc;

/// Blocks of the main sequence. With seed `0x5eed_0007`, 10 000 blocks (plus about 8 200
/// played while rebuilds were pending) are 57 s of audio and took 14 to 15 s of wall time (test
/// profile, on the idle two-core development machine, 2026-11-24); they made 65 rebuilds (4
/// of them gongs with split steps, about 6 600 halves run on a worker per run), 24 host rate
/// changes and about 16 000 note-ons in each of three runs, far above what the test requires
/// (3, 2, 1000 and one half).
const BLOCKS: u64 = 10_000;

#[test]
fn soak_under_load() {
    let blocks = std::env::var("NOETHER_SOAK_BLOCKS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(BLOCKS);
    let cfg = SoakConfig::quick(0x5eed_0007, blocks);
    let s = soak::run(&cfg, |e, ev, l, r| {
        assert_no_alloc(|| e.process_events(ev, l, r))
    })
    .unwrap_or_else(|f| panic!("{f}"));
    println!("{s}");
    // Every request resolved: the loop ends only between bursts.
    assert_eq!(
        s.rebuilds_requested,
        s.rebuilds_arrived + s.rebuilds_refused
    );
    // The run exercised what it claims (the default run makes dozens of each).
    assert!(s.rebuilds_arrived >= 3, "{s}");
    assert!(s.rate_changes >= 2, "{s}");
    // Random key tables reached the engine between blocks (about one block in a hundred).
    assert!(s.tunings >= 20, "{s}");
    assert!(s.storm.note_ons >= 1000, "{s}");
    // Both sides of the output stage were played: the limiter on and off (one draw in two
    // each block).
    assert!(s.limited_blocks > 0 && s.limited_blocks < s.blocks, "{s}");
    // The voices were shared between threads (`threads` is automated over 0..16, 1 meaning
    // the audio thread alone), on a machine with a worker.
    // ... and heavy plate voices shared their steps with a worker (one burst in ten asks for
    // such a bank).
    if std::thread::available_parallelism().is_ok_and(|n| n.get() >= 2) {
        assert!(s.threaded_blocks > 0 && s.worker_jobs > 0, "{s}");
        assert!(s.shared_step_halves > 0, "{s}");
    }
}

/// The case the soak found, made deterministic: a lossless string whose tension jumps between
/// the table's extremes (1 N and 2000 N) every block. Each jump rescales the stiffness under the
/// moving string, so the voice gains energy parametrically without bound (here from a 1 mm
/// pluck to the ceiling in 7 blocks). Without the ceiling, such a voice's output passes every
/// level up to its state's overflow (the soak saw inf samples); with it, the engine silences the
/// voice at `VOICE_CEILING` and counts it. Checks: output finite and within twice the ceiling
/// (one voice, resampler kernel ℓ1 < 2, gain 0 dB) every block, and the voice was silenced (so
/// the case does reach the ceiling). Single-threaded (no rebuild), so it is reproducible.
#[test]
fn pumped_voice_is_silenced_not_infinite() {
    let params = Arc::new(SharedParams::new());
    Preset::factory_named("tanpura")
        .unwrap()
        .apply(&params)
        .unwrap();
    for (id, x) in [
        (ParamId::Modes, 30.0),
        (ParamId::SimRate, 48_000.0),
        (ParamId::Polyphony, 1.0),
        (ParamId::DampingScale, 0.0),
        (ParamId::Gain, 0.0),
    ] {
        params.set(id, x).unwrap();
    }
    let (mut e, _h) = Engine::new(params.clone());
    e.activate(48_000.0, 128).unwrap();
    let (mut l, mut r) = (vec![0.0f32; 128], vec![0.0f32; 128]);
    e.note_on(60, 1.0);
    let mut blocks = 0;
    // 2.7 ms blocks retune every block (the engine retunes at most every 2 ms).
    while e.diverged_voices() == 0 && blocks < 40_000 {
        let t = if blocks % 2 == 0 { 2000.0 } else { 1.0 };
        params.set(ParamId::Tension, t).unwrap();
        assert_no_alloc(|| e.process(&mut l, &mut r));
        let peak = l
            .iter()
            .chain(&r)
            .fold(0.0f64, |m, &x| m.max(x.abs() as f64));
        assert!(
            l.iter().chain(&r).all(|x| x.is_finite()) && peak <= 2.0 * VOICE_CEILING,
            "block {blocks}: peak {peak}"
        );
        blocks += 1;
    }
    println!("voice silenced after {blocks} blocks of 128 samples at 48 kHz");
    assert_eq!(
        e.diverged_voices(),
        1,
        "the tension jumps did not pump the voice"
    );
    assert_eq!(e.active_voices(), 0);
}

/// Random playing at accelerated speed leaves the instrument as it was: the soak's note storm
/// (`noether_testkit::performance::storm`: 8 notes a second on every key, random velocities,
/// bends, wheel, pedal, per-note expressions and per-note parameter values, every block under
/// `assert_no_alloc`) for 40 s of audio on the 40 N gong (SAV, 120 modes: the drift the SAV
/// relaxation removes is independent of the mode count) and on the sitar, then, once every
/// voice is idle, a soft strike on the root key is the same strike on a new instance: bands
/// within 1 dB, centroid within 10 %, and bit for bit. The hour-long run of docs/robustness.md:
/// `cargo run --release --example long_performance -- --storm 3600 PRESET`.
#[test]
fn random_playing_leaves_the_instrument_as_it_was() {
    use noether_testkit::performance::after_storm;
    use noether_testkit::presets::preset_params;
    for (stem, sets, key) in [
        ("gong-40N", vec![(ParamId::Modes, 120.0)], 60),
        ("sitar", vec![], 55),
    ] {
        let c = after_storm(
            || preset_params(stem, &sets),
            40.0,
            8.0,
            0x5eed_0029,
            |e, ev, l, r| assert_no_alloc(|| e.process_events(ev, l, r)),
            key,
            40.0 / 127.0,
            2.0,
            120.0,
        );
        println!(
            "{stem}: {} notes, settled in {:.1} s, worst band {:+.2} dB, centroid {:.0} / {:.0} Hz, \
             identical {}",
            c.notes, c.settle_s, c.worst_band_db, c.centroid_after, c.centroid_fresh, c.identical
        );
        assert!(c.notes > 250, "{stem}: {c:?}");
        assert!(c.worst_band_db.abs() <= 1.0, "{stem}: {c:?}");
        assert!(c.centroid_change().abs() <= 0.1, "{stem}: {c:?}");
        assert!(c.identical, "{stem}: {c:?}");
    }
}
