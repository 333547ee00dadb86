//! The instrument's gong shows the von Kármán cascade: struck hard, energy reaches frequencies
//! the strike never drove. A 10 ms raised-cosine strike has a spectrum falling as `f⁻³` past
//! 200 Hz, so what a linear plate sounds above 3 kHz is a trace; the nonlinear plate transfers
//! energy up its modes within the first second (the lecture's shimmer).

use noether::analysis::spectrogram::spectrogram;
use noether::engine::{Engine, Event, EventKind, ParamId};
use noether_testkit::presets::preset_params;
use noether_testkit::take;

/// Share of the left channel's spectral energy above `f_cut` Hz over the first second of a
/// full-velocity note at the root key of `preset` (with `in_plane` in-plane modes; 0 is the
/// linear plate), and the time (s) of the first spectrogram frame whose energy above `f_cut` is
/// within 60 dB of that frame's total (visible on a spectrogram of 60 dB range).
fn high_share(preset: &str, in_plane: f32, f_cut: f64) -> (f64, Option<f64>) {
    let params = preset_params(preset, &[(ParamId::InPlaneModes, in_plane)]);
    let (mut e, _h) = Engine::new(params.clone());
    e.activate(48_000.0, 512).unwrap();
    let key = params.get(ParamId::RootKey) as u8;
    let note = Event::new(0, EventKind::NoteOn { key, velocity: 1.0 });
    let x = take::render(&mut e, &[note], 48_000, 512).left_f64();
    let s = spectrogram(&x, 48_000.0, 2048, 1024);
    let (mut high, mut all) = (0.0, 0.0);
    let mut first = None;
    for (t, frame) in s.times.iter().zip(&s.db) {
        let (mut fh, mut fa) = (0.0, 0.0);
        for (f, db) in s.freqs.iter().zip(frame) {
            let p = 10f64.powf(db / 10.0);
            fa += p;
            if *f > f_cut {
                fh += p;
            }
        }
        if first.is_none() && fa > 0.0 && fh >= 1e-6 * fa {
            first = Some(*t);
        }
        high += fh;
        all += fa;
    }
    (high / all, first)
}

/// At full velocity the 80 N gong's spectrum reaches above 2 kHz within the first second (a
/// frame with its energy above 2 kHz within 60 dB of the frame's total), and that energy is the
/// nonlinearity's: the same preset made linear (no in-plane modes) has at least 1000 times less
/// of its first second's energy there. Both are printed. Its model resolved (1400 modes to
/// 16 kHz, 30 in-plane modes, 62.4 kHz) holds its 2 kHz third-octave 38 dB and its 3.2 kHz one
/// 61 dB under the total over 0.3-1.5 s (docs/ACCURACY.md, "The time step's aliasing"): the
/// cascade of this stroke has not reached 3 kHz by one second. (This test asked for 3 kHz
/// while the preset ran at 13.4 kHz, where the time step's aliasing filled the top of the
/// band from the stroke on.)
#[test]
fn gong_80n_cascades_above_2_khz_within_a_second() {
    let (nonlinear, first) = high_share("gong-80N", 15.0, 2000.0);
    let (linear, _) = high_share("gong-80N", 0.0, 2000.0);
    println!("share above 2 kHz: nonlinear {nonlinear:.3e}, linear {linear:.3e}; first frame within 60 dB at {first:?} s");
    assert!(
        first.is_some_and(|t| t < 1.0),
        "no frame reaches 2 kHz: {first:?}"
    );
    assert!(
        nonlinear >= 1000.0 * linear,
        "{nonlinear:e} vs linear {linear:e}"
    );
}

/// Share (dB) of the left channel's spectral energy above `f_cut` Hz in each spectrogram frame
/// (2048 points, hop 1024, 48 kHz) of `seconds` of a full-velocity note `above` semitones over
/// the root key of `preset` with `sets` changed, with the frames' times (s).
fn high_share_frames(
    preset: &str,
    sets: &[(ParamId, f32)],
    above: u8,
    f_cut: f64,
    seconds: f64,
) -> Vec<(f64, f64)> {
    let params = preset_params(preset, sets);
    let (mut e, _h) = Engine::new(params.clone());
    e.activate(48_000.0, 512).unwrap();
    let key = params.get(ParamId::RootKey) as u8 + above;
    let note = Event::new(0, EventKind::NoteOn { key, velocity: 1.0 });
    let x = take::render(&mut e, &[note], (seconds * 48_000.0) as usize, 512).left_f64();
    let s = spectrogram(&x, 48_000.0, 2048, 1024);
    s.times
        .iter()
        .zip(&s.db)
        .map(|(&t, frame)| {
            let (mut high, mut all) = (0.0, 0.0);
            for (f, db) in s.freqs.iter().zip(frame) {
                let p = 10f64.powf(db / 10.0);
                all += p;
                if *f > f_cut {
                    high += p;
                }
            }
            (t, 10.0 * (high / all).max(1e-30).log10())
        })
        .collect()
}

/// The mean of the frames' dB shares over `[from, to)` s.
fn mean_share(frames: &[(f64, f64)], from: f64, to: f64) -> f64 {
    let inside: Vec<f64> = frames
        .iter()
        .filter(|(t, _)| (from..to).contains(t))
        .map(|f| f.1)
        .collect();
    inside.iter().sum::<f64>() / inside.len() as f64
}

/// The tam-tam's delayed shimmer (Fletcher & Rossing, *The Physics of Musical Instruments*, ch.
/// 20): at full velocity the share of its energy above 1 kHz is low at the stroke and rises over
/// the first second, as its model resolved to 1000 modes and 60 in-plane modes does
/// (docs/ACCURACY.md, "The tam-tam's stroke"): from the first 0.1 s to 0.5-1 s it rises by at
/// least 12 dB (measured 17.8 dB, from -35.3 to -17.5 dB) to within 30 dB of the total. The
/// preset's former stroke (2 m/s, 15 in-plane modes) rose 7.0 dB to -61.6 dB, a dark gong, and
/// fails both; the linear plate (no in-plane modes) falls by 5.1 dB and fails.
#[test]
fn the_tam_tam_shimmer_builds_up_over_the_first_second() {
    let frames = high_share_frames("tam-tam", &[(ParamId::Polyphony, 1.0)], 0, 1000.0, 1.2);
    let (stroke, bloom) = (mean_share(&frames, 0.0, 0.1), mean_share(&frames, 0.5, 1.0));
    println!("tam-tam: energy above 1 kHz {stroke:.1} dB at the stroke, {bloom:.1} dB at 0.5-1 s");
    assert!(bloom - stroke >= 12.0, "rose only {:.1} dB", bloom - stroke);
    assert!(bloom >= -30.0, "{bloom:.1} dB of the total above 1 kHz");
}

/// The time step does not pump the top modes: the 80 N gong's cascade stops near 3 kHz
/// (resolved at twice the preset's rate and more, its 4-8 kHz band stays 92-103 dB under the
/// total for six seconds; docs/ACCURACY.md, "The time step's aliasing"). At the former rate of
/// its 6 kHz band, 13.4 kHz (`band / 0.45`), the in-plane stress pumped the top modes through
/// the step's alias of the parametric resonance, and the band above 4 kHz sat 45-67 dB under
/// the total from the stroke on. An octave up (key 72) the note's tier holds modes to 7.5 kHz,
/// past the band: left free, they were pumped the same way; they are overdamped
/// (`engine/voice/plate/kept.rs`). The largest share above 4 kHz in a frame of the first
/// 1.5 s must stay under -80 dB on the root key (measured -84.5 dB; -42.6 dB with the
/// engine's nonlinear rate fraction put back to 0.45) and under -85 dB an octave
/// up (measured -90.7 dB; -77.8 dB with the modes above the band left free). Each limit fails
/// its mutation (checked).
#[test]
fn the_time_step_does_not_pump_the_gongs_top_modes() {
    for (above, limit) in [(0, -80.0), (12, -85.0)] {
        let frames =
            high_share_frames("gong-80N", &[(ParamId::Polyphony, 1.0)], above, 4000.0, 1.5);
        let worst = frames.iter().map(|f| f.1).fold(f64::NEG_INFINITY, f64::max);
        println!(
            "gong-80N, root + {above}: largest share above 4 kHz in the first 1.5 s {worst:.1} dB"
        );
        assert!(
            worst < limit,
            "root + {above}: {worst:.1} dB of a frame above 4 kHz (limit {limit} dB)"
        );
    }
}
