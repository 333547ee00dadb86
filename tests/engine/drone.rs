//! The tanpura drone through the engine (the factory `tanpura-drone` preset, one voice, 48 kHz,
//! the audio thread alone): the held key is Sa, the cycle plucks on its pattern, the latch
//! keeps it going after the key is let go, the release lets it ring out, and no block
//! allocates. The model's own tuning, cycle and energy are verified in `tests/strings/`;
//! here the engine must play that model as the keyboard asks.

use noether::analysis::fundamental::fundamental_near;
use noether::engine::{Engine, EngineHandle, EventKind, ParamId, SharedParams};
use noether::models::source::RenderSource;
use noether::models::tanpura::{Tanpura, TanpuraSpec};
use noether_testkit::presets::preset_params;
use noether_testkit::take::{run_blocks, BlockRun};
use std::sync::Arc;

const RATE: f64 = 48_000.0;
/// Host samples per block (2.67 ms).
const BLOCK: usize = 128;
/// The preset's root key, C#3: Sa = 138.59 Hz.
const ROOT: u8 = 49;

/// The factory drone with `sets`, the human variation off, one voice on the audio thread;
/// its parameters and its handle.
fn drone(sets: &[(ParamId, f32)]) -> (Engine, Arc<SharedParams>, EngineHandle) {
    let mut all = vec![
        (ParamId::DroneVariation, 0.0),
        (ParamId::Threads, 1.0),
        (ParamId::Polyphony, 1.0),
    ];
    all.extend_from_slice(sets);
    let params = preset_params("tanpura-drone", &all);
    let (mut e, h) = Engine::new(params.clone());
    assert!(e.activate(RATE, BLOCK).unwrap().is_none());
    (e, params, h)
}

/// Plays `blocks` blocks of [`BLOCK`] samples (`noether_testkit::take::run_blocks`: no
/// allocation, every sample within full scale).
fn run(e: &mut Engine, events: &[(usize, EventKind)], blocks: usize) -> BlockRun {
    run_blocks(e, events, blocks, BLOCK)
}

fn blocks(seconds: f64) -> usize {
    (seconds * RATE / BLOCK as f64).round() as usize
}

fn note_on(key: u8, velocity: f32) -> EventKind {
    EventKind::NoteOn { key, velocity }
}

/// The blocks at which the voice's energy jumps: a pluck adds its energy at once (more than 5 %
/// of what the strings hold in one block), while the losses take less than 0.1 % per block.
fn pluck_blocks(energy: &[f64]) -> Vec<usize> {
    (1..energy.len())
        .filter(|&b| energy[b] > 1.05 * energy[b - 1] + 1e-12)
        .collect()
}

/// The Sa band's frequency (Hz) of `x` (the left output from 2 s on): the partial near `sa`
/// (the two middle Sa strings and the lower Sa's second partial; the Pa string's nearest
/// partials lie 26 Hz or more away, outside the ±20 Hz band), from the band's zero crossings.
fn sa_band(x: &[f64], sa: f64) -> f64 {
    fundamental_near(&x[(2.0 * RATE) as usize..], RATE, sa, 20.0).expect("the Sa band oscillates")
}

/// The held key is Sa: at root - 5, root and root + 7 the engine's drone (built and tuned by
/// ear at the root, retuned to the key by `SaMap`'s corrections) sounds the Sa band of a drone
/// the model builds and tunes by ear at that key's Sa itself (`Sa · 2^(k/12)`, `Sa = 440 ·
/// 2^((49 - 69)/12)` Hz), over 6 s of the same 8 s drone, within 0.3 cents (printed: within
/// 0.01), against a semitone (100 cents) for a key mapped wrongly, 3.9 cents for an A4 of
/// 441 Hz, and up to 1.5 cents at these keys for the tensions without the corrections
/// (docs/models.md). The band itself sits up to 4.5 cents below the nominal Sa at root - 5 in
/// both (the strings are tuned on their first partial just after each pluck, and their pitch
/// glides down as the jawari's grazing fades; printed), so the reference is the model, not
/// the nominal pitch; the model's strings are held within 1 cent of their notes by
/// `tests/strings/tanpura.rs`.
#[test]
fn the_held_key_is_sa() {
    let sa = 440.0 * ((f64::from(ROOT) - 69.0) / 12.0).exp2();
    for k in [-5i32, 0, 7] {
        let (mut e, _, _) = drone(&[]);
        let key = (i32::from(ROOT) + k) as u8;
        let t = run(&mut e, &[(0, note_on(key, 0.8))], blocks(8.0));
        let want = sa * (f64::from(k) / 12.0).exp2();
        let heard = sa_band(&t.left, want);
        // The model at that Sa, plucked as the engine plucks (velocity 0.8 on a curve of 1).
        let spec = TanpuraSpec {
            modes: 480,
            sim_rate: RATE,
            alias_free: true,
            ..TanpuraSpec::at(want)
        };
        let mut model = Tanpura::build(&spec).unwrap();
        model.set_strength(0.8).unwrap();
        let mut out = vec![vec![0.0; (8.0 * RATE) as usize]; 2];
        let frames = out[0].len();
        model.process(&mut out, frames);
        let reference = sa_band(&out[0], want);
        let cents = 1200.0 * (heard / reference).log2();
        println!(
            "key {key}: engine {heard:.4} Hz, model tuned at {want:.3} Hz: {reference:.4} Hz \
             ({:+.2} cents from nominal), engine - model {cents:+.3} cents",
            1200.0 * (reference / want).log2()
        );
        assert!(cents.abs() < 0.3, "key {key}: {cents:+.3} cents");
    }
}

/// The cycle: four plucks at 0, 0.8, 1.6 and 2.4 s, again at 4 s (the classic pattern of the
/// preset, 4 s), found as the blocks where the voice's energy jumps, within one block (2.7
/// ms; the model's onsets are exact to a step, `tests/strings/tanpura.rs`), over two cycles;
/// with the `even` pattern at 0, 1, 2 and 3 s.
#[test]
fn the_cycle_plucks_on_its_pattern() {
    for (pattern, onsets) in [(0.0f32, [0.0, 0.8, 1.6, 2.4]), (1.0, [0.0, 1.0, 2.0, 3.0])] {
        let (mut e, _, _) = drone(&[(ParamId::DronePattern, pattern)]);
        let t = run(&mut e, &[(0, note_on(ROOT, 0.8))], blocks(7.9));
        let found = pluck_blocks(&t.energy);
        let want: Vec<f64> = onsets
            .iter()
            .chain(onsets.iter().map(|o| o + 4.0).collect::<Vec<_>>().iter())
            .copied()
            .collect();
        let found_s: Vec<f64> = found.iter().map(|&b| (b * BLOCK) as f64 / RATE).collect();
        println!("pattern {pattern}: plucks at {found_s:.4?} s");
        // The first pluck lands in the first block, whose energy is the reference (0 before).
        let found_s: Vec<f64> = std::iter::once(0.0).chain(found_s).collect();
        assert_eq!(found_s.len(), want.len(), "plucks {found_s:.4?}");
        for (f, w) in found_s.iter().zip(&want) {
            assert!(
                (f - w).abs() <= BLOCK as f64 / RATE + 1e-9,
                "pluck at {f:.4} s, pattern {w} s"
            );
        }
    }
}

/// Let go without the latch, the drone stops plucking and rings out: no pluck after the
/// note-off, and the voice ends (its energy 0) within the release's reach. With the latch on,
/// the same note-off changes nothing: the next cycle's plucks come on time; turning the latch
/// off then releases it.
#[test]
fn the_latch_keeps_the_drone_and_the_release_ends_it() {
    let off = blocks(1.0);
    let events = [
        (0, note_on(ROOT, 0.8)),
        (off, EventKind::NoteOff { key: ROOT }),
    ];
    let (mut e, _, _) = drone(&[(ParamId::ReleaseT60, 0.5)]);
    let t = run(&mut e, &events, blocks(6.0));
    let after: Vec<usize> = pluck_blocks(&t.energy)
        .into_iter()
        .filter(|&b| b > off)
        .collect();
    assert!(after.is_empty(), "plucks after the release: {after:?}");
    assert_eq!(
        *t.energy.last().unwrap(),
        0.0,
        "the released drone still sounds"
    );

    let (mut e, params, mut handle) = drone(&[(ParamId::DroneLatch, 1.0)]);
    let t = run(&mut e, &events, blocks(6.0));
    let late = pluck_blocks(&t.energy);
    assert!(
        late.iter().any(|&b| b.abs_diff(blocks(4.0)) <= 1),
        "latched: no pluck at 4 s ({late:?})"
    );
    // The editor reads the voice as latched, not released (the newest telemetry after a
    // tenth of a second more).
    let newest = |e: &mut Engine, handle: &mut EngineHandle| {
        while handle.telemetry().is_some() {}
        run(e, &[], blocks(0.1));
        handle.telemetry().expect("telemetry").voices[0]
    };
    let v = newest(&mut e, &mut handle);
    assert!(v.active && !v.held && v.latched, "{v:?}");
    params.set(ParamId::DroneLatch, 0.0).unwrap();
    let v = newest(&mut e, &mut handle);
    assert!(v.active && !v.held && !v.latched, "unlatched: {v:?}");
    let t = run(&mut e, &[], blocks(8.0));
    assert!(
        pluck_blocks(&t.energy).is_empty() || t.energy.last() == Some(&0.0),
        "unlatched: the drone keeps plucking"
    );
    assert_eq!(*t.energy.last().unwrap(), 0.0, "unlatched: still sounding");
}

/// Velocity sets the plucks' strength: the drone at velocity 1 peaks higher than at 0.4, by
/// about the ratio of the pluck amplitudes (the strings' motion, and their force on the bridge,
/// scale with it up to the jawari's mild nonlinearity: within 30 % of 2.5), and within full
/// scale (-6 dBFS at velocity 100/127 with the preset's gain, docs/models.md).
#[test]
fn velocity_sets_the_plucks_strength() {
    let peak = |v: f32| {
        let (mut e, _, _) = drone(&[]);
        let t = run(&mut e, &[(0, note_on(ROOT, v))], blocks(3.0));
        t.left.iter().fold(0.0f64, |m, x| m.max(x.abs()))
    };
    let (soft, loud) = (peak(0.4), peak(1.0));
    println!("peaks: velocity 0.4 {soft:.3}, velocity 1 {loud:.3}");
    assert!(loud < 1.0 && soft > 0.0);
    let ratio = loud / soft;
    assert!((ratio / 2.5 - 1.0).abs() < 0.3, "ratio {ratio:.2}");
}

/// With `drone_sync` on the cycle lasts `drone_beats` beats of the host's tempo: 8 beats at
/// 240 bpm plucks at 0, 0.4, 0.8 and 1.2 s and again from 2 s; the tempo moved to 120 bpm at
/// 1 s lets that cycle finish and the next one (from 2 s) last 4 s (2.0, 2.8, 3.6, 4.4, then
/// 6.0 s); each pluck within one block (2.7 ms). Without a tempo the cycle period holds.
#[test]
fn the_cycle_follows_the_hosts_tempo() {
    let sync = [(ParamId::DroneSync, 1.0), (ParamId::DroneBeats, 8.0)];
    let (mut e, _, _) = drone(&sync);
    e.set_host_tempo(Some(240.0));
    let first = run(&mut e, &[(0, note_on(ROOT, 0.8))], blocks(1.0));
    e.set_host_tempo(Some(120.0));
    let rest = run(&mut e, &[], blocks(5.5));
    let energy: Vec<f64> = first.energy.iter().chain(&rest.energy).copied().collect();
    let found: Vec<f64> = std::iter::once(0.0)
        .chain(
            pluck_blocks(&energy)
                .iter()
                .map(|&b| (b * BLOCK) as f64 / RATE),
        )
        .collect();
    println!("240 then 120 bpm: plucks at {found:.4?} s");
    let want = [0.0, 0.4, 0.8, 1.2, 2.0, 2.8, 3.6, 4.4, 6.0];
    assert_eq!(found.len(), want.len(), "plucks {found:.4?}");
    for (f, w) in found.iter().zip(want) {
        assert!(
            (f - w).abs() <= BLOCK as f64 / RATE + 1e-9,
            "pluck at {f:.4} s, want {w} s"
        );
    }
    // No tempo from the host: the 4 s period of the preset.
    let (mut e, _, _) = drone(&sync);
    let t = run(&mut e, &[(0, note_on(ROOT, 0.8))], blocks(2.0));
    let second = pluck_blocks(&t.energy)[0] as f64 * BLOCK as f64 / RATE;
    assert!(
        (second - 0.8).abs() <= BLOCK as f64 / RATE + 1e-9,
        "second pluck at {second} s"
    );
}
