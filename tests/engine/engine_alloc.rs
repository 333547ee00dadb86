//! `assert_no_alloc` around `Engine::process`: notes, every parameter automated, model swaps
//! (waiting for the worker's bank), quality changes, host rates 22.05 to 192 kHz and block
//! sizes 1 to 8192. The global allocator of this test binary aborts on any allocation inside
//! `assert_no_alloc` (debug assertions are on in the test profile). Output finite and within
//! full scale throughout; with the limiter on (automated with the others, the gain over its
//! whole range -60..+60 dB) within the limiter's ceiling and with no sample clipped by the
//! output stage's guard. Key tables (12-TET, and 19 steps per octave with every fifth key
//! unmapped) are published between blocks, so the audio thread takes and retunes with them;
//! per-note tuning, volume and pressure expressions arrive with the notes (a pressure puts the
//! player's hand, a point damper, on the plate with the force pulse or the mallet). The exciter is automated with
//! the others (about half the blocks strike with the physical mallet, launched against the
//! moving plate, with its mass, hardness and speed drawn over their ranges), and
//! `mallet_blocks_never_allocate` plays the mallet alone. Every block also carries brightness
//! and per-note values (polyphonic modulation) of random per-note parameters, some with the
//! note-on, so strikes and pickups are re-placed on the audio thread.

use assert_no_alloc::assert_no_alloc;
use noether::engine::voice::modulation::POLY_PARAMS;
use noether::engine::{
    Engine, Event, EventKind, KeyTuning, NoteExpression, ParamId, ParamKind, SharedParams, CEILING,
    KEY_COUNT, PARAMS,
};
use noether_testkit::presets::preset_params;
use std::time::{Duration, Instant};

/// A deterministic pseudo-random sequence (xorshift64).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Slack on the ceiling: the limiter's gain is `CEILING / peak` in `f32`, so a limited sample
/// can pass the ceiling by a few ulps (6e-8 each); 1e-6 is 16 ulps.
const CEILING_ROUNDING: f32 = 1.000_001;

/// One block; `limiter`: whether the `limiter` parameter is on for it. Returns the peak.
fn block(e: &mut Engine, limiter: bool, events: &[Event], l: &mut [f32], r: &mut [f32]) -> f32 {
    let guarded = e.guarded_samples();
    assert_no_alloc(|| e.process_events(events, l, r));
    let worst = l.iter().chain(r.iter()).fold(0.0f32, |m, x| m.max(x.abs()));
    // No setting takes the output past full scale (the guard bounds it to 1 in any case), and
    // with the limiter on the limiter does it: its ceiling holds and the guard never acts.
    assert!(worst.is_finite() && worst <= 1.0, "output {worst}");
    if limiter {
        assert!(
            worst <= CEILING * CEILING_ROUNDING,
            "output {worst}, limiter on"
        );
        assert_eq!(
            e.guarded_samples(),
            guarded,
            "samples clipped by the guard with the limiter on (peak {worst})"
        );
    }
    worst
}

fn limiter(params: &SharedParams) -> bool {
    params.snapshot().index_of(ParamId::Limiter) == 1
}

/// A per-note value of a random per-note parameter, drawn over its range, for `key`.
fn per_note(rng: &mut Rng, at: u32, key: u8) -> Event {
    let param = POLY_PARAMS[(rng.next() * POLY_PARAMS.len() as f64) as usize % POLY_PARAMS.len()];
    let info = param.info();
    let value = info.min + (info.max - info.min) * rng.next() as f32;
    Event::new(at, EventKind::NoteModulation { key, param, value })
}

#[test]
fn process_never_allocates() {
    let params = preset_params("gong-40N", &[]);
    let (mut e, h) = Engine::new(params.clone());
    let mut rng = Rng(0x9e3779b97f4a7c15);
    let (mut l, mut r) = (vec![0.0f32; 8192], vec![0.0f32; 8192]);
    let mut peak_limited = 0.0f32;
    let tables = [
        KeyTuning::equal(),
        KeyTuning::from_mapped_frequencies(&std::array::from_fn::<_, KEY_COUNT, _>(|k| {
            (k % 5 != 0).then(|| 261.625_565 * ((k as f64 - 60.0) / 19.0).exp2())
        }))
        .unwrap(),
    ];
    let rates = [22_050.0, 44_100.0, 48_000.0, 96_000.0, 192_000.0];
    let blocks = [1usize, 7, 64, 333, 8192];
    for (k, &rate) in rates.iter().enumerate() {
        e.activate(rate, 8192).unwrap();
        // Notes at sample offsets, automation of every non-rebuild parameter each block.
        for (j, &bs) in blocks.iter().enumerate() {
            let blocks_n = ((0.05 * rate) as usize / bs).clamp(2, 400);
            for b in 0..blocks_n {
                let key = 48 + ((b + j) % 24) as u8;
                let events = [
                    Event::new(
                        0,
                        EventKind::NoteOn {
                            key,
                            velocity: 0.3 + 0.7 * rng.next() as f32,
                        },
                    ),
                    Event::new(
                        (bs / 2) as u32,
                        EventKind::PitchBend(2.0 * rng.next() as f32 - 1.0),
                    ),
                    Event::new((bs / 2) as u32, EventKind::ModWheel(rng.next() as f32)),
                    Event::new(
                        (bs - 1) as u32,
                        EventKind::NoteOff {
                            key: key.wrapping_sub(3),
                        },
                    ),
                    Event::new((bs - 1) as u32, EventKind::Sustain(b % 7 == 0)),
                    Event::new(
                        (bs / 3) as u32,
                        EventKind::NoteExpression {
                            key,
                            expression: NoteExpression::Tuning(4.0 * rng.next() as f32 - 2.0),
                        },
                    ),
                    Event::new(
                        (bs / 3) as u32,
                        EventKind::NoteExpression {
                            key,
                            expression: NoteExpression::Volume(4.0 * rng.next() as f32),
                        },
                    ),
                    // Brightness and a per-note value with the note-on (they shape its
                    // strike), and another per-note value later in the block.
                    Event::new(
                        0,
                        EventKind::NoteExpression {
                            key,
                            expression: NoteExpression::Brightness(rng.next() as f32),
                        },
                    ),
                    per_note(&mut rng, 0, key),
                    per_note(&mut rng, (bs / 3) as u32, key.wrapping_sub(1)),
                    Event::new(
                        (bs / 2) as u32,
                        EventKind::NoteExpression {
                            key,
                            expression: NoteExpression::Pressure(rng.next() as f32),
                        },
                    ),
                ];
                for p in PARAMS.iter().filter(|p| !p.rebuild) {
                    let x = p.min as f64 + rng.next() * (p.max - p.min) as f64;
                    let x = match p.kind {
                        ParamKind::Float { .. } => x as f32,
                        _ => x.round() as f32,
                    };
                    // Keep the plate away from absurd sizes only through the table's ranges.
                    params.set(p.id, x.clamp(p.min, p.max)).unwrap();
                }
                if b % 3 == 0 {
                    params.tuning().set(&tables[(b / 3) % 2]);
                }
                let on = limiter(&params);
                let peak = block(&mut e, on, &events, &mut l[..bs], &mut r[..bs]);
                if on {
                    peak_limited = peak_limited.max(peak);
                }
            }
        }
        // A model swap and a quality change, waited for with process running.
        let model = [3.0, 4.0, 2.0, 1.0, 0.0][k];
        let old = e.bank_id();
        params.set(ParamId::Model, model).unwrap();
        params
            .set(ParamId::Modes, [30.0, 60.0, 40.0, 20.0, 50.0][k])
            .unwrap();
        params
            .set(
                ParamId::SimRate,
                [48_000.0, 96_000.0, 16_000.0, 24_000.0, 32_000.0][k],
            )
            .unwrap();
        params.set(ParamId::Size, 0.4).unwrap();
        params.set(ParamId::Thickness, 0.001).unwrap();
        params.set(ParamId::Tension, 180.5).unwrap();
        params.set(ParamId::BridgePosition, 0.03).unwrap();
        let start = Instant::now();
        let events = [Event::new(
            0,
            EventKind::NoteOn {
                key: 60,
                velocity: 1.0,
            },
        )];
        while e.bank_id() == old {
            assert!(
                start.elapsed() < Duration::from_secs(60),
                "no bank at {rate}: error {:?}, rebuilding {}, built {}",
                h.last_error(),
                h.is_rebuilding(),
                h.banks_built()
            );
            block(
                &mut e,
                limiter(&params),
                &events,
                &mut l[..256],
                &mut r[..256],
            );
            std::thread::sleep(Duration::from_millis(1));
        }
        for _ in 0..20 {
            block(
                &mut e,
                limiter(&params),
                &events,
                &mut l[..512],
                &mut r[..512],
            );
        }
        println!(
            "rate {rate}: model {:?}, sim {:?} Hz, cap hits {}, refused {}, diverged {}, \
             guard {} samples (limiter off), peak with the limiter on {peak_limited:.4}",
            e.model(),
            e.sim_rate(),
            e.newton_cap_hits(),
            e.refused_notes(),
            e.diverged_voices(),
            e.guarded_samples()
        );
    }
}

/// Notes, re-strikes of sounding keys and mallet parameter automation with `exciter = mallet`
/// throughout (the mallet launched, stepped, dropped), the player's hand on the plate at a
/// random pressure in two blocks of three (solved jointly with the mallet), at 48 kHz and
/// blocks of 1 to 512: no allocation, and the output within the limiter's ceiling (the
/// limiter on).
#[test]
fn mallet_blocks_never_allocate() {
    let params = preset_params(
        "gong-40N",
        &[(ParamId::Exciter, 1.0), (ParamId::Limiter, 1.0)],
    );
    let (mut e, _h) = Engine::new(params.clone());
    e.activate(48_000.0, 512).unwrap();
    let mut rng = Rng(0x2545f4914f6cdd1d);
    let (mut l, mut r) = (vec![0.0f32; 512], vec![0.0f32; 512]);
    let mallet = [
        ParamId::MalletMass,
        ParamId::MalletHardness,
        ParamId::MalletSpeed,
    ];
    for b in 0..600 {
        let bs = [1usize, 64, 512][b % 3];
        let key = 57 + (b % 6) as u8;
        // A hand on the struck plate in two blocks of three (the mallet solved with it).
        let pressure = if b % 3 == 0 { 0.0 } else { rng.next() as f32 };
        let events = [
            Event::new(
                0,
                EventKind::NoteOn {
                    key,
                    velocity: 0.2 + 0.8 * rng.next() as f32,
                },
            ),
            Event::new(
                0,
                EventKind::NoteExpression {
                    key,
                    expression: NoteExpression::Pressure(pressure),
                },
            ),
        ];
        for id in mallet {
            let p = id.info();
            let x = p.min as f64 + rng.next() * (p.max - p.min) as f64;
            params.set(id, (x as f32).clamp(p.min, p.max)).unwrap();
        }
        block(&mut e, true, &events, &mut l[..bs], &mut r[..bs]);
    }
}
