//! Every factory preset at the extremes a musician can reach with a keyboard: a chord of
//! [`MAX_VOICES`] keys at velocity 127 with the mod wheel at 1 (all voices, each struck or
//! plucked as hard as the preset allows), single notes at the lowest and highest keys the
//! engine accepts (0 and 127) and at the piano's ends (21 and 108), velocity 127, mod wheel at
//! 1, and notes at velocity 1 (the root key and keys 21 and 108, mod wheel at rest, 0.5). The
//! product's rule is that no setting takes the output past full scale and that the limiter
//! (on in every preset), not the output stage's last-resort guard, keeps it there.
//!
//! Each render (48 kHz, [`SECONDS`] after the note-ons, [`CHORD_SECONDS`] for the chord, the
//! output stage as shipped) must be
//! finite, peak at most at the limiter's [`CEILING`] (-0.3 dBFS) times [`CEILING_ROUNDING`],
//! leave `Engine::guarded_samples` at 0, and sound: peak above [`FLOOR_DB`] wherever a note
//! was accepted. A note the engine refuses (its coefficients would be unstable, see
//! `Engine::refused_notes`) is allowed to be silent only if it is counted as refused; the
//! chord and the velocity-1 notes must not be refused at all.

use noether::engine::{Engine, ParamId, Preset, SharedParams, CEILING, MAX_VOICES};
use noether_testkit::take;
use std::sync::Arc;
use std::time::Duration;

const RATE: f64 = 48_000.0;
const BLOCK: usize = 256;
/// Render length after the note-ons (s): the attacks (strikes of a few ms, plucks released at
/// once), the strings' first bounces against their bridges and the plates' swell (the gongs'
/// key 21 peaks 0.7 dB higher over 0.3 s than over 0.15 s, their velocity-1 root 3 dB).
const SECONDS: f64 = 0.3;
/// Render length of the chord (s): the 16 attacks together, where the sum is furthest above
/// full scale (each voice peaks near -3.5 dBFS alone, so up to +20 dBFS in phase). Its 16
/// voices cost 2.7 to 6.9 s of CPU per 0.3 s (the strings at 192 kHz), most of the test's
/// cost at that length.
const CHORD_SECONDS: f64 = 0.1;
/// Slack on the ceiling: the limiter's gain is `CEILING / peak` in `f32`, so a limited sample
/// can pass the ceiling by a few ulps (6e-8 each); 1e-6 is 16 ulps.
const CEILING_ROUNDING: f32 = 1.000_001;
/// A sounding note peaks above this (dBFS). The quietest case measured is -56.6 dBFS (key 108
/// at velocity 1 on the rectangular plate, whose high modes are damped fastest); -80 dBFS
/// leaves 23 dB for changes of the presets and stays far above the engine's silence (exact
/// zeros).
const FLOOR_DB: f64 = -80.0;
/// The extreme keys: the lowest and highest the engine accepts, and the piano's ends.
const EXTREME_KEYS: [u8; 4] = [0, 21, 108, 127];

/// What one render gave.
struct Played {
    /// Largest `|sample|` (full scale 1).
    peak: f32,
    /// Whether every sample was finite.
    finite: bool,
    /// Samples the output stage's guard changed.
    guarded: u64,
    /// Notes the engine refused.
    refused: u64,
}

impl Played {
    fn db(&self) -> f64 {
        20.0 * f64::from(self.peak).max(1e-12).log10()
    }
}

/// One preset's engine at 48 kHz with every voice ([`MAX_VOICES`]); the takes share it (built
/// once: activation builds the modal bases, most of the test's cost otherwise).
fn engine(preset: &Preset) -> Engine {
    let params = Arc::new(SharedParams::new());
    preset.apply(&params).unwrap();
    params.set(ParamId::Polyphony, MAX_VOICES as f32).unwrap();
    let (mut e, _h) = Engine::new(params);
    assert!(e.activate(RATE, BLOCK).unwrap().is_none());
    // No voice's chunk is dropped for lateness: the render is the same on any machine.
    e.set_job_wait(Some(Duration::from_secs(10)));
    e
}

/// Plays `keys` together at `velocity` (0..1) with the mod wheel at `wheel` for `seconds`,
/// from rest (`Engine::reset`: voices, resampler and output stage cleared).
fn play(e: &mut Engine, keys: &[u8], velocity: f32, wheel: f32, seconds: f64) -> Played {
    e.reset();
    let (guarded, refused) = (e.guarded_samples(), e.refused_notes());
    e.mod_wheel(wheel);
    for &k in keys {
        e.note_on(k, velocity);
    }
    let t = take::render(e, &[], (seconds * RATE) as usize / BLOCK * BLOCK, BLOCK);
    let all = || t.left.iter().chain(&t.right);
    Played {
        peak: all().fold(0.0f32, |m, x| m.max(x.abs())),
        finite: all().all(|x| x.is_finite()),
        guarded: e.guarded_samples() - guarded,
        refused: e.refused_notes() - refused,
    }
}

/// The checks every render shares; `what` names it in the failures.
fn bounded(what: &str, t: &Played, failures: &mut Vec<String>) {
    if !t.finite {
        failures.push(format!("{what}: non-finite output"));
    }
    if t.peak > CEILING * CEILING_ROUNDING {
        failures.push(format!(
            "{what}: peak {:.6} above the ceiling {CEILING}",
            t.peak
        ));
    }
    if t.guarded > 0 {
        failures.push(format!(
            "{what}: {} samples clipped by the guard with the limiter on",
            t.guarded
        ));
    }
}

#[test]
fn factory_presets_stay_under_the_ceiling_and_sound_at_the_extremes() {
    let mut failures = Vec::new();
    for (stem, preset) in Preset::factory() {
        let v = preset.values().unwrap();
        assert_eq!(v.index_of(ParamId::Limiter), 1, "{stem}: limiter off");
        let root = v.get(ParamId::RootKey) as u8;
        // A chord of every voice: whole tones from 16 below the root (clamped to the keys).
        let chord: Vec<u8> = (0..MAX_VOICES)
            .map(|i| (i32::from(root) - 16 + 2 * i as i32).clamp(0, 127) as u8)
            .collect();
        let mut e = engine(&preset);
        let t = play(&mut e, &chord, 1.0, 1.0, CHORD_SECONDS);
        println!(
            "{stem}: chord of {MAX_VOICES} at velocity 127, wheel 1: peak {:.2} dBFS",
            t.db()
        );
        bounded(&format!("{stem} chord"), &t, &mut failures);
        if t.refused > 0 || t.db() <= FLOOR_DB {
            failures.push(format!(
                "{stem} chord: {} refused, peak {:.1} dBFS",
                t.refused,
                t.db()
            ));
        }
        for key in EXTREME_KEYS {
            let t = play(&mut e, &[key], 1.0, 1.0, SECONDS);
            let refused = t.refused == 1;
            println!(
                "  key {key:3} at velocity 127, wheel 1: peak {:7.2} dBFS{}",
                t.db(),
                if refused { " (refused, counted)" } else { "" }
            );
            bounded(&format!("{stem} key {key}"), &t, &mut failures);
            if !refused && t.db() <= FLOOR_DB {
                failures.push(format!(
                    "{stem} key {key}: silent ({:.1} dBFS) but not refused",
                    t.db()
                ));
            }
        }
        for key in [root, 21, 108] {
            let t = play(&mut e, &[key], 1.0 / 127.0, 0.5, SECONDS);
            println!("  key {key:3} at velocity 1: peak {:7.2} dBFS", t.db());
            bounded(&format!("{stem} key {key} velocity 1"), &t, &mut failures);
            if t.refused > 0 || t.db() <= FLOOR_DB {
                failures.push(format!(
                    "{stem} key {key} velocity 1: {} refused, peak {:.1} dBFS",
                    t.refused,
                    t.db()
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
