//! Long performances: minutes of playing on one engine, then a fresh strike compared with the
//! same strike on a new instance of the same preset ("an hour of playing leaves the instrument
//! as it was").
//!
//! A [`Performance`] is a seeded script of what a percussionist or a keyboard player does with
//! one preset: rolls at several velocities on one key (re-strikes of a sounding voice), chords,
//! held notes under the sustain pedal, pitch bends and the mod wheel on a sounding note, hand
//! pressure, fast random re-strikes, and at the end every controller back where a new engine
//! has it (bend 0, wheel [`NEUTRAL_WHEEL`], pedal up) and every note released. [`after_performance`] plays it, waits until every voice has gone idle, then
//! strikes the key and compares the strike's third-octave band levels and spectral centroid with
//! the same strike on a new engine ([`StrikeComparison`]). The bands come from a Welch average
//! (4096-point Hann, half overlap) of the mono mix, as the issue measured them.
//!
//! Threads: test and example set-up only; the engine runs on the calling thread (its worker
//! builds the banks). Allocates freely outside `Engine::process_events`.

use crate::soak::{Draw, Storm};
use noether_core::engine::{Engine, Event, EventKind, NoteExpression, ParamId, SharedParams};
use oorandom::Rand64;
use rustfft::{num_complex::Complex, FftPlanner};
use std::sync::Arc;

/// The host rate the performances run at (Hz).
pub const HOST_RATE: f64 = 48_000.0;

/// The host block (samples).
pub const BLOCK: usize = 256;

/// Bands whose level in the fresh strike is more than this far below its strongest band (dB)
/// are not compared: at -60 dB they are inaudible under the strike, and their ratio is the
/// noise of the estimate.
pub const BAND_RANGE_DB: f64 = 60.0;

/// The mod wheel's value on a new engine (the centre of its range: velocity scaled by 1), to
/// which the performance returns it.
pub const NEUTRAL_WHEEL: f32 = 0.5;

/// One scripted event at a host sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Timed {
    /// Host sample from the start of the performance.
    pub at: u64,
    /// The event.
    pub kind: EventKind,
}

/// A seeded script of playing (module doc).
#[derive(Debug, Clone)]
pub struct Performance {
    /// The events, in time order.
    pub events: Vec<Timed>,
    /// Length of the script (host samples); every note is released by then.
    pub samples: u64,
}

impl Performance {
    /// `seconds` of playing around `key` (repeating an 8 s cycle of gestures; at least one
    /// cycle), seeded by `seed`, at [`HOST_RATE`].
    pub fn new(seconds: f64, key: u8, seed: u64) -> Self {
        let mut rng = Rand64::new(seed as u128 | 1);
        let mut ev: Vec<(f64, EventKind)> = Vec::new();
        let on = |key: u8, velocity: f32| EventKind::NoteOn { key, velocity };
        let off = |key: u8| EventKind::NoteOff { key };
        let up = |d: i16| (key as i16 + d).clamp(0, 127) as u8;
        let cycles = (seconds / 8.0).ceil().max(1.0) as usize;
        for c in 0..cycles {
            let t0 = 8.0 * c as f64;
            // 0-2 s: a roll, 4 strikes a second at soft, medium and full velocity, each held
            // 0.2 s: re-strikes of the sounding voice.
            for i in 0..8 {
                let t = t0 + 0.25 * i as f64;
                ev.push((t, on(key, [0.3, 0.6, 1.0][i % 3])));
                ev.push((t + 0.2, off(key)));
            }
            // 2-3 s: a chord.
            for d in [0, 4, 7] {
                ev.push((t0 + 2.0, on(up(d), 0.8)));
                ev.push((t0 + 2.8, off(up(d))));
            }
            // 3-4.5 s: a note held by the sustain pedal after its key is released.
            ev.push((t0 + 3.0, on(up(12), 0.7)));
            ev.push((t0 + 3.2, EventKind::Sustain(true)));
            ev.push((t0 + 3.5, off(up(12))));
            ev.push((t0 + 4.4, EventKind::Sustain(false)));
            // 4.5-6 s: a held note bent up and down, the mod wheel moved, a hand pressing.
            ev.push((t0 + 4.5, on(key, 0.9)));
            for i in 0..=20 {
                let x = i as f32 / 20.0;
                let bend = 0.5 * (std::f32::consts::TAU * x).sin();
                ev.push((t0 + 4.55 + 0.06 * i as f64, EventKind::PitchBend(bend)));
                let wheel = NEUTRAL_WHEEL + 0.45 * (std::f32::consts::PI * x).sin();
                ev.push((t0 + 4.55 + 0.06 * i as f64, EventKind::ModWheel(wheel)));
            }
            ev.push((
                t0 + 5.2,
                EventKind::NoteExpression {
                    key,
                    expression: NoteExpression::Pressure(0.5),
                },
            ));
            ev.push((t0 + 5.8, off(key)));
            ev.push((t0 + 5.8, EventKind::PitchBend(0.0)));
            ev.push((t0 + 5.8, EventKind::ModWheel(NEUTRAL_WHEEL)));
            // 6-8 s: fast re-strikes at random velocities and times, some neighbours.
            let mut t = t0 + 6.0;
            while t < t0 + 7.7 {
                let k = if rng.rand_float() < 0.7 {
                    key
                } else {
                    up(rng.rand_range(0..5) as i16 - 2)
                };
                let v = 0.1 + 0.9 * rng.rand_float() as f32;
                ev.push((t, on(k, v)));
                ev.push((t + 0.05, off(k)));
                t += 0.06 + 0.1 * rng.rand_float();
            }
        }
        let end = 8.0 * cycles as f64;
        ev.push((end, EventKind::PitchBend(0.0)));
        ev.push((end, EventKind::ModWheel(NEUTRAL_WHEEL)));
        ev.push((end, EventKind::Sustain(false)));
        ev.push((end, EventKind::AllNotesOff));
        // Stable sort: simultaneous events keep their written order.
        ev.sort_by(|a, b| a.0.total_cmp(&b.0));
        let events = ev
            .into_iter()
            .map(|(t, kind)| Timed {
                at: (t * HOST_RATE).round() as u64,
                kind,
            })
            .collect();
        Self {
            events,
            samples: (end * HOST_RATE).round() as u64 + 1,
        }
    }

    /// Number of note-ons in the script.
    pub fn notes(&self) -> usize {
        self.events
            .iter()
            .filter(|e| matches!(e.kind, EventKind::NoteOn { .. }))
            .count()
    }
}

/// Plays `seconds` of the soak's note storm (`crate::soak::Storm`: notes on every key at
/// `notes_per_second`, random velocities, offsets, bends, wheel, pedal, per-note expressions
/// and per-note parameter values; seeded by `seed`) in blocks of [`BLOCK`], each block through
/// `process` (which must call `engine.process_events(events, left, right)`, wrapped as the
/// caller likes: `assert_no_alloc`), then puts every controller back where a new engine has
/// it and releases every note. Returns the notes played.
pub fn storm<F>(
    e: &mut Engine,
    seconds: f64,
    notes_per_second: f64,
    seed: u64,
    mut process: F,
) -> u64
where
    F: FnMut(&mut Engine, &[Event], &mut [f32], &mut [f32]),
{
    let mut d = Draw::new(seed);
    let mut storm = Storm::new(notes_per_second);
    let (mut l, mut r) = (vec![0.0f32; BLOCK], vec![0.0f32; BLOCK]);
    let mut events: Vec<Event> = Vec::with_capacity(4096);
    let blocks = (seconds * HOST_RATE / BLOCK as f64).ceil() as u64;
    for _ in 0..blocks {
        storm.fill(&mut d, BLOCK, HOST_RATE, &mut events);
        process(e, &events, &mut l, &mut r);
    }
    let end = [
        EventKind::PitchBend(0.0),
        EventKind::ModWheel(NEUTRAL_WHEEL),
        EventKind::Sustain(false),
        EventKind::AllNotesOff,
    ]
    .map(|kind| Event::new(0, kind));
    process(e, &end, &mut l, &mut r);
    storm.counts.note_ons
}

/// The soak's storm (`seconds` at `notes_per_second`, [`storm`]) on a new engine of
/// `params()`, then, once every voice is idle (at most `settle_limit_s`), a strike of `key` at
/// `velocity` (held `held_s`, rendered `seconds_strike`) against the same strike on another new
/// engine of `params()`.
#[allow(clippy::too_many_arguments)]
pub fn after_storm<F>(
    params: impl Fn() -> Arc<SharedParams>,
    seconds: f64,
    notes_per_second: f64,
    seed: u64,
    process: F,
    key: u8,
    velocity: f32,
    seconds_strike: f64,
    settle_limit_s: f64,
) -> StrikeComparison
where
    F: FnMut(&mut Engine, &[Event], &mut [f32], &mut [f32]),
{
    let mut played = engine(params());
    let notes = storm(&mut played, seconds, notes_per_second, seed, process);
    let strike = (key, velocity, 0.2, seconds_strike);
    settled_strike(
        played,
        engine(params()),
        strike,
        settle_limit_s,
        notes as usize,
    )
}

/// Once every voice of `played` is idle (at most `settle_limit_s`; panics past it), the
/// strike `(key, velocity, held s, rendered s)` on it against the same strike on `new`;
/// `notes` played before.
fn settled_strike(
    mut played: Engine,
    mut new: Engine,
    (key, velocity, held_s, seconds): (u8, f32, f64, f64),
    settle_limit_s: f64,
    notes: usize,
) -> StrikeComparison {
    let settle_s = settle(&mut played, settle_limit_s)
        .unwrap_or_else(|| panic!("voices still sounding {settle_limit_s} s after the playing"));
    let after = strike(&mut played, key, velocity, held_s, seconds);
    let fresh = strike(&mut new, key, velocity, held_s, seconds);
    let (worst_band_db, worst_band_hz, centroid_after, centroid_fresh) = compare(&after, &fresh);
    StrikeComparison {
        worst_band_db,
        worst_band_hz,
        centroid_after,
        centroid_fresh,
        identical: after == fresh,
        settle_s,
        notes,
    }
}

/// An engine on `params`, activated at [`HOST_RATE`] with blocks of [`BLOCK`].
pub fn engine(params: Arc<SharedParams>) -> Engine {
    let (mut e, _handle) = Engine::new(params);
    e.activate(HOST_RATE, BLOCK)
        .unwrap_or_else(|err| panic!("activate: {err}"));
    e
}

/// Plays `events` (host samples from now) for `samples` host samples in blocks of [`BLOCK`],
/// each event at its offset inside its block. Returns the mono mix `(l + r)/2`.
pub fn play(e: &mut Engine, events: &[Timed], samples: u64) -> Vec<f32> {
    let mut out = Vec::with_capacity(samples as usize);
    let (mut l, mut r) = (vec![0.0f32; BLOCK], vec![0.0f32; BLOCK]);
    let mut next = 0;
    let mut block_events: Vec<Event> = Vec::with_capacity(64);
    let mut t = 0u64;
    while t < samples {
        let n = (samples - t).min(BLOCK as u64) as usize;
        block_events.clear();
        while next < events.len() && events[next].at < t + n as u64 {
            block_events.push(Event::new((events[next].at - t) as u32, events[next].kind));
            next += 1;
        }
        l[..n].fill(0.0);
        r[..n].fill(0.0);
        e.process_events(&block_events, &mut l[..n], &mut r[..n]);
        out.extend(l[..n].iter().zip(&r[..n]).map(|(a, b)| 0.5 * (a + b)));
        t += n as u64;
    }
    out
}

/// Renders silence until no voice sounds (at most `limit_s` seconds); returns the seconds
/// it took, or `None` if voices still sounded at the limit.
pub fn settle(e: &mut Engine, limit_s: f64) -> Option<f64> {
    let mut t = 0.0;
    while e.active_voices() > 0 {
        if t >= limit_s {
            return None;
        }
        play(e, &[], BLOCK as u64);
        t += BLOCK as f64 / HOST_RATE;
    }
    Some(t)
}

/// A strike of `key` at `velocity` held `held_s`, rendered for `seconds` (mono mix), after
/// 0.1 s of silence (past the resampler's first block on a new engine).
pub fn strike(e: &mut Engine, key: u8, velocity: f32, held_s: f64, seconds: f64) -> Vec<f32> {
    play(e, &[], (0.1 * HOST_RATE) as u64);
    let events = [
        Timed {
            at: 0,
            kind: EventKind::NoteOn { key, velocity },
        },
        Timed {
            at: (held_s * HOST_RATE) as u64,
            kind: EventKind::NoteOff { key },
        },
    ];
    play(e, &events, (seconds * HOST_RATE) as u64)
}

/// Third-octave band levels (IEC 61260-1 base-2 centres `1000·2^(k/3)` Hz, from the band
/// around 100 Hz up to the highest band below `rate/2`) of `x`, from a Welch average of
/// 4096-point Hann frames with half overlap: `(centre Hz, level dB)`, plus the spectral
/// centroid (Hz) of the averaged power spectrum.
pub fn band_levels(x: &[f32], rate: f64) -> (Vec<(f64, f64)>, f64) {
    const N: usize = 4096;
    let fft = FftPlanner::<f64>::new().plan_fft_forward(N);
    let window: Vec<f64> = (0..N)
        .map(|i| 0.5 - 0.5 * (std::f64::consts::TAU * i as f64 / N as f64).cos())
        .collect();
    let mut power = vec![0.0f64; N / 2 + 1];
    let mut buf = vec![Complex::new(0.0, 0.0); N];
    let mut frames = 0usize;
    let mut start = 0;
    while start + N <= x.len() {
        for ((b, &s), w) in buf.iter_mut().zip(&x[start..start + N]).zip(&window) {
            *b = Complex::new(s as f64 * w, 0.0);
        }
        fft.process(&mut buf);
        for (p, b) in power.iter_mut().zip(&buf) {
            *p += b.norm_sqr();
        }
        frames += 1;
        start += N / 2;
    }
    let df = rate / N as f64;
    let total: f64 = power.iter().sum();
    let centroid = power
        .iter()
        .enumerate()
        .map(|(k, p)| k as f64 * df * p)
        .sum::<f64>()
        / total.max(f64::MIN_POSITIVE);
    let mut bands = Vec::new();
    for k in -10..=13 {
        let centre = 1000.0 * 2f64.powf(k as f64 / 3.0);
        let (lo, hi) = (
            centre * 2f64.powf(-1.0 / 6.0),
            centre * 2f64.powf(1.0 / 6.0),
        );
        if hi > rate / 2.0 {
            break;
        }
        let p: f64 = power
            .iter()
            .enumerate()
            .filter(|(k, _)| (lo..hi).contains(&(*k as f64 * df)))
            .map(|(_, p)| p)
            .sum();
        let level = 10.0 * (p / frames.max(1) as f64).max(1e-300).log10();
        bands.push((centre, level));
    }
    (bands, centroid)
}

/// [`band_levels`] of `x[from..to]` (seconds at `rate`), each relative to the window's total
/// over the bands (dB): a spectrum's shape, whatever the render's gain.
pub fn relative_band_levels(x: &[f32], rate: f64, (from, to): (f64, f64)) -> Vec<(f64, f64)> {
    let cut = &x[(from * rate) as usize..((to * rate) as usize).min(x.len())];
    let (bands, _) = band_levels(cut, rate);
    let total = 10.0
        * bands
            .iter()
            .map(|b| 10f64.powf(b.1 / 10.0))
            .sum::<f64>()
            .log10();
    bands.into_iter().map(|(hz, l)| (hz, l - total)).collect()
}

/// The level (dB) of the band of `bands` (centre Hz, level) centred nearest `hz`; NaN for no
/// band.
pub fn level_at(bands: &[(f64, f64)], hz: f64) -> f64 {
    bands
        .iter()
        .min_by(|a, b| (a.0 / hz).ln().abs().total_cmp(&(b.0 / hz).ln().abs()))
        .map_or(f64::NAN, |b| b.1)
}

/// The parameter changes that make a plate preset its resolved reference: the band raised to
/// `band_hz` with up to 1400 modes, the conservative-exact scheme at `rate_hz`, no closure and
/// no band above (docs/ACCURACY.md; `examples/closure_bands`, the engine's closure and strike
/// tests).
pub fn resolved_reference(band_hz: f32, rate_hz: f32) -> [(ParamId, f32); 6] {
    [
        (ParamId::Closure, 0.0),
        (ParamId::BandAbove, 0.0),
        (ParamId::BandLimit, band_hz),
        (ParamId::Modes, 1400.0),
        (ParamId::Scheme, 1.0), // conservative-exact
        (ParamId::SimRate, rate_hz),
    ]
}

/// A strike after a performance against the same strike on a new engine.
#[derive(Debug, Clone, PartialEq)]
pub struct StrikeComparison {
    /// The largest `|after - fresh|` over the compared bands (dB; [`BAND_RANGE_DB`]).
    pub worst_band_db: f64,
    /// Centre of that band (Hz).
    pub worst_band_hz: f64,
    /// Spectral centroid of the strike after the performance (Hz).
    pub centroid_after: f64,
    /// Spectral centroid of the fresh strike (Hz).
    pub centroid_fresh: f64,
    /// Whether the two strikes are the same samples, bit for bit.
    pub identical: bool,
    /// Seconds of silence the performance needed before every voice was idle.
    pub settle_s: f64,
    /// Notes played in the performance.
    pub notes: usize,
}

impl StrikeComparison {
    /// The centroid's relative change, `after/fresh - 1`.
    pub fn centroid_change(&self) -> f64 {
        self.centroid_after / self.centroid_fresh - 1.0
    }
}

/// Compares two renders of one strike (module doc).
pub fn compare(after: &[f32], fresh: &[f32]) -> (f64, f64, f64, f64) {
    let (a, ca) = band_levels(after, HOST_RATE);
    let (f, cf) = band_levels(fresh, HOST_RATE);
    let top = f.iter().map(|b| b.1).fold(f64::NEG_INFINITY, f64::max);
    let (mut worst, mut at) = (0.0f64, 0.0);
    for ((hz, la), (_, lf)) in a.iter().zip(&f) {
        if *lf < top - BAND_RANGE_DB {
            continue;
        }
        if (la - lf).abs() > worst.abs() {
            (worst, at) = (la - lf, *hz);
        }
    }
    (worst, at, ca, cf)
}

/// Plays `performance` on a new engine of `params()`, waits until every voice is idle (at most
/// `settle_limit_s`; panics past it), then strikes `key` at `velocity` (held `held_s`,
/// rendered `seconds`); compares it with the same strike on another new engine of
/// `params()`.
pub fn after_performance(
    params: impl Fn() -> Arc<SharedParams>,
    performance: &Performance,
    key: u8,
    velocity: f32,
    held_s: f64,
    seconds: f64,
    settle_limit_s: f64,
) -> StrikeComparison {
    let mut played = engine(params());
    play(&mut played, &performance.events, performance.samples);
    let strike = (key, velocity, held_s, seconds);
    settled_strike(
        played,
        engine(params()),
        strike,
        settle_limit_s,
        performance.notes(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sine at a band's centre lands in that band, 60 dB above its neighbours two bands
    /// away; the centroid of a sine is its frequency (to half a bin).
    #[test]
    fn bands_and_centroid_of_a_sine() {
        let f = 1000.0;
        let x: Vec<f32> = (0..48_000)
            .map(|n| (std::f64::consts::TAU * f * n as f64 / HOST_RATE).sin() as f32)
            .collect();
        let (bands, centroid) = band_levels(&x, HOST_RATE);
        let i = bands.iter().position(|b| b.0 == 1000.0).unwrap();
        assert!(bands[i].1 > bands[i - 2].1 + 60.0 && bands[i].1 > bands[i + 2].1 + 60.0);
        assert!(
            (centroid - f).abs() < 0.5 * HOST_RATE / 4096.0,
            "{centroid}"
        );
    }

    /// The script is in time order, releases everything, and plays notes in every cycle.
    #[test]
    fn script_is_ordered_and_ends_released() {
        let p = Performance::new(20.0, 60, 7);
        assert!(p.events.windows(2).all(|w| w[0].at <= w[1].at));
        assert_eq!(p.events.last().unwrap().kind, EventKind::AllNotesOff);
        assert!(p.notes() > 3 * 20, "{}", p.notes());
        assert!(p.events.iter().all(|e| e.at < p.samples));
    }
}
