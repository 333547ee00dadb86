//! `compare A.wav B.wav`: two renders of the same notes (at different host rates and block
//! sizes, e.g. 22.05 kHz in 1-frame blocks and 192 kHz in 8192-frame blocks) must agree where
//! both can: the level over the first second, the spectrum below 9 kHz (both rates represent it;
//! the plugin's model runs at its own simulation rate and is resampled to the host rate, so the
//! host rate must not change what is heard) and the frequency of the strongest partial.
//!
//! The figures: RMS over all channels and the first `seconds` (trapezoid rule; dB difference);
//! Welch power spectral density (P. D. Welch, IEEE Trans. Audio Electroacoust. 15 (1967)
//! 70-73: 100 ms Hann frames, 50 % overlap, |X|² / (rate Σw²) so that the same signal gives the
//! same density at any rate) compared bin by bin on a 10 Hz grid from 20 Hz to `max_freq` as a
//! log-spectral distance, sqrt(mean (10 log10(Pa / Pb))²) in dB, each density floored at 60 dB
//! below the larger peak of the two (the resamplers' stop bands and the rounding floor differ
//! with the rate and carry no sound); and the strongest partial of one Hann-windowed DFT of the
//! whole segment (1 Hz bins at 1 s), refined by a parabola through the log powers of its bin
//! and its neighbours (Gaussian interpolation, within a few hundredths of a bin for a Hann
//! window).

use crate::args::{parse_num, path_arg};
use crate::check::read_wav;
use rustfft::num_complex::Complex;
use rustfft::FftPlanner;
use std::path::PathBuf;

/// Lowest frequency compared, Hz: below the low cut of the output stage (20 Hz by default) the
/// renders hold only its residue.
const MIN_FREQ: f64 = 20.0;
/// Welch frame length, s: 10 Hz bins, ten frames per second to average.
const FRAME: f64 = 0.1;
/// Density floor below the larger peak of the two spectra, dB.
const FLOOR_DB: f64 = 60.0;

/// Default bound of the level difference, dB. The bounds are each about five times the figure
/// measured between the plugin CI's renders at 22.05 kHz in 1-frame blocks and at 192 kHz in
/// 8192-frame blocks (default preset, key 60, velocity 0.8, note-off at 0.6 s; release build;
/// the renders are bit-identical from run to run): level 4.2e-6 dB apart, log-spectral
/// distance 2.1e-4 dB, strongest partial (55.125 Hz) 7.9e-5 cents apart. Below 9 kHz the two
/// renders agree to rounding: the model runs at its own simulation rate and only the final
/// resampling sees the host rate and block size, so anything in the host layer that changes
/// the sound (a lost or repeated block, an event at the wrong sample, a rate-dependent gain or
/// tuning) shows. A deliberate change to the resampler that moves these figures must re-measure
/// them. Broken inputs are far outside: key 61 instead of 60 gives 9.9 dB and +163 cents,
/// output gain -6 dB gives -6.0 dB, damping 2x gives 0.75 dB and -692 cents.
pub const DEFAULT_MAX_LEVEL_DB: f64 = 2e-5;
/// Default bound of the log-spectral distance, dB (measured 2.1e-4 dB: see
/// [`DEFAULT_MAX_LEVEL_DB`]).
pub const DEFAULT_MAX_LSD_DB: f64 = 1e-3;
/// Default bound of the distance between the strongest partials, cents (measured 7.9e-5
/// cents: see [`DEFAULT_MAX_LEVEL_DB`]).
pub const DEFAULT_MAX_CENTS: f64 = 5e-4;

/// Options of `compare`.
#[derive(Debug, Clone)]
pub struct CompareOptions {
    /// The first render (WAV, integer or float, any channel count and rate).
    pub a: PathBuf,
    /// The second render of the same notes.
    pub b: PathBuf,
    /// Length compared from the start of each file, s (default 1).
    pub seconds: f64,
    /// Highest frequency of the spectral comparisons, Hz (default 9000: below the Nyquist
    /// frequency of 22.05 kHz with room for the resampler's transition band).
    pub max_freq: f64,
    /// Largest allowed RMS level difference, dB.
    pub max_level_db: f64,
    /// Largest allowed log-spectral distance, dB.
    pub max_lsd_db: f64,
    /// Largest allowed distance between the strongest partials, cents.
    pub max_cents: f64,
}

impl CompareOptions {
    /// Parses `A.wav B.wav [--seconds S] [--max-freq HZ] [--max-level-db X] [--max-lsd-db X]
    /// [--max-cents X]`.
    pub fn parse(args: &[String]) -> Result<Self, String> {
        let mut it = args.iter();
        let a = path_arg("A.wav", it.next())?;
        let b = path_arg("B.wav", it.next())?;
        let mut o = Self {
            a,
            b,
            seconds: 1.0,
            max_freq: 9000.0,
            max_level_db: DEFAULT_MAX_LEVEL_DB,
            max_lsd_db: DEFAULT_MAX_LSD_DB,
            max_cents: DEFAULT_MAX_CENTS,
        };
        while let Some(flag) = it.next() {
            let v = parse_num::<f64>(flag, it.next());
            match flag.as_str() {
                "--seconds" => o.seconds = v?,
                "--max-freq" => o.max_freq = v?,
                "--max-level-db" => o.max_level_db = v?,
                "--max-lsd-db" => o.max_lsd_db = v?,
                "--max-cents" => o.max_cents = v?,
                other => return Err(format!("unknown option `{other}`")),
            }
        }
        if o.seconds.is_nan() || o.seconds < 2.0 * FRAME {
            return Err(format!(
                "--seconds: {} is outside the allowed range [{}, inf) s (two Welch frames)",
                o.seconds,
                2.0 * FRAME
            ));
        }
        if o.max_freq.is_nan() || o.max_freq <= MIN_FREQ + 10.0 {
            return Err(format!(
                "--max-freq: {} is outside the allowed range ({}, Nyquist) Hz",
                o.max_freq,
                MIN_FREQ + 10.0
            ));
        }
        Ok(o)
    }
}

/// What `compare` measures of one file.
#[derive(Debug)]
struct Analysis {
    rate: u32,
    /// RMS over the segment and all channels, dBFS.
    level_db: f64,
    /// Welch density on the 10 Hz grid from `MIN_FREQ` to `max_freq`.
    psd: Vec<f64>,
    /// Strongest partial below `max_freq`, Hz.
    partial: f64,
}

/// Power spectra (|X|², summed over channels) of Hann-windowed frames of `len` samples starting
/// at each of `starts`, averaged over frames; and Σw² of the window.
fn power(ch: &[Vec<f64>], len: usize, starts: &[usize]) -> (Vec<f64>, f64) {
    let fft = FftPlanner::<f64>::new().plan_fft_forward(len);
    let w: Vec<f64> = (0..len)
        .map(|i| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * i as f64 / len as f64).cos())
        .collect();
    let mut p = vec![0.0; len / 2 + 1];
    let mut buf = vec![Complex::new(0.0, 0.0); len];
    for x in ch {
        for &s in starts {
            for (i, b) in buf.iter_mut().enumerate() {
                *b = Complex::new(x[s + i] * w[i], 0.0);
            }
            fft.process(&mut buf);
            for (pk, b) in p.iter_mut().zip(&buf) {
                *pk += b.norm_sqr() / starts.len() as f64;
            }
        }
    }
    (p, w.iter().map(|v| v * v).sum())
}

fn analyse(path: &PathBuf, o: &CompareOptions) -> Result<Analysis, String> {
    let (samples, nch, rate) = read_wav(path)?;
    let rate_f = f64::from(rate);
    let n = (o.seconds * rate_f).round() as usize;
    if samples.len() / nch < n + 1 {
        return Err(format!(
            "{}: {} frames at {rate} Hz, shorter than the {} s compared and one frame",
            path.display(),
            samples.len() / nch,
            o.seconds
        ));
    }
    if o.max_freq >= 0.5 * rate_f {
        return Err(format!(
            "--max-freq: {} Hz is outside the allowed range (30, {}) Hz of {} (its Nyquist \
             frequency)",
            o.max_freq,
            0.5 * rate_f,
            path.display()
        ));
    }
    let ch: Vec<Vec<f64>> = (0..nch)
        .map(|c| {
            samples
                .iter()
                .skip(c)
                .step_by(nch)
                .take(n)
                .copied()
                .collect()
        })
        .collect();
    if let Some(bad) = ch.iter().flatten().find(|v| !v.is_finite()) {
        return Err(format!("{}: non-finite sample {bad}", path.display()));
    }
    // Mean power over [0, seconds] by the trapezoid rule (the samples at both ends weighted
    // 1/2): the plain mean over n samples carries an end error of order x(T)² / n, which
    // differs with the rate (1.4e-4 dB between 22.05 and 192 kHz for a 220.37 Hz tone), the
    // trapezoid's is of order 1 / n².
    let (first, last) = (&samples[..nch], &samples[n * nch..(n + 1) * nch]);
    let ends: f64 = first.iter().chain(last).map(|v| v * v).sum();
    let sum2: f64 = ch.iter().flatten().map(|v| v * v).sum::<f64>() - ends / 2.0
        + last.iter().map(|v| v * v).sum::<f64>();
    let level_db = 10.0 * (sum2 / (n * nch) as f64).log10();
    // Welch density on the 10 Hz grid: bin of frequency f is round(f len / rate).
    let len = (FRAME * rate_f).round() as usize;
    let starts: Vec<usize> = (0..)
        .map(|k| k * len / 2)
        .take_while(|s| s + len <= n)
        .collect();
    let (p, w2) = power(&ch, len, &starts);
    let grid = ((o.max_freq - MIN_FREQ) / 10.0).floor() as usize + 1;
    let psd = (0..grid)
        .map(|k| {
            let f = MIN_FREQ + 10.0 * k as f64;
            p[(f * len as f64 / rate_f).round() as usize] / (rate_f * w2)
        })
        .collect();
    // Strongest partial: one frame over the whole segment.
    let (p, _) = power(&ch, n, &[0]);
    let lo = (MIN_FREQ * n as f64 / rate_f).ceil() as usize;
    let hi = (o.max_freq * n as f64 / rate_f).floor() as usize;
    let k = (lo..=hi).fold(lo, |m, k| if p[k] > p[m] { k } else { m });
    let (l, c, r) = (p[k - 1].ln(), p[k].ln(), p[k + 1].ln());
    let den = l - 2.0 * c + r;
    let delta = if den < 0.0 { 0.5 * (l - r) / den } else { 0.0 };
    Ok(Analysis {
        rate,
        level_db,
        psd,
        partial: (k as f64 + delta) * rate_f / n as f64,
    })
}

/// Whether |x| <= bound (false for NaN).
fn within(x: f64, bound: f64) -> bool {
    x.abs() <= bound
}

/// Runs the comparison and prints the figures it is based on.
pub fn compare(o: &CompareOptions) -> Result<(), String> {
    let a = analyse(&o.a, o)?;
    let b = analyse(&o.b, o)?;
    for (path, x) in [(&o.a, &a), (&o.b, &b)] {
        println!(
            "{}: {} Hz, RMS of the first {} s {:.3} dBFS, strongest partial below {} Hz at \
             {:.3} Hz",
            path.display(),
            x.rate,
            o.seconds,
            x.level_db,
            o.max_freq,
            x.partial
        );
    }
    let top = a.psd.iter().chain(&b.psd).fold(0.0f64, |m, &v| m.max(v));
    if top <= 0.0 {
        return Err(format!(
            "silent: no power from {MIN_FREQ} to {} Hz in either file",
            o.max_freq
        ));
    }
    let floor = top * 10f64.powf(-FLOOR_DB / 10.0);
    let d2: f64 = a
        .psd
        .iter()
        .zip(&b.psd)
        .map(|(&x, &y)| (10.0 * (x.max(floor) / y.max(floor)).log10()).powi(2))
        .sum();
    let lsd = (d2 / a.psd.len() as f64).sqrt();
    let level = b.level_db - a.level_db;
    let cents = 1200.0 * (b.partial / a.partial).log2();
    println!(
        "B - A: level {level:+.2e} dB (bound {}), log-spectral distance {MIN_FREQ}-{} Hz {lsd:.2e} \
         dB (bound {}), strongest partial {cents:+.2e} cents (bound {})",
        o.max_level_db, o.max_freq, o.max_lsd_db, o.max_cents
    );
    let mut fails = Vec::new();
    if !within(level, o.max_level_db) {
        fails.push(format!(
            "levels differ by {level:+.3} dB (bound {} dB)",
            o.max_level_db
        ));
    }
    if !within(lsd, o.max_lsd_db) {
        fails.push(format!(
            "spectra differ: log-spectral distance {lsd:.3} dB (bound {} dB)",
            o.max_lsd_db
        ));
    }
    if !within(cents, o.max_cents) {
        fails.push(format!(
            "strongest partials differ by {cents:+.2} cents ({:.3} vs {:.3} Hz; bound {} cents)",
            a.partial, b.partial, o.max_cents
        ));
    }
    if !fails.is_empty() {
        return Err(format!(
            "{} and {} disagree: {}",
            o.a.display(),
            o.b.display(),
            fails.join("; ")
        ));
    }
    println!("ok: same level, spectrum and pitch within the bounds");
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testwav;

    /// A steady inharmonic tone (partials at `pitch` × 1, 2.67, 5.99 and 13.64 with amplitudes
    /// 0.3, 0.15, 0.08 and 0.02, scaled by `gain`), 1.2 s at `rate` Hz in 32-bit float.
    fn tone(name: &str, rate: u32, pitch: f64, gain: f64) -> PathBuf {
        let partials = [(1.0, 0.3), (2.67, 0.15), (5.99, 0.08), (13.64, 0.02)];
        testwav::write(&format!("compare-{name}"), rate, 1.2, true, |t| {
            partials
                .iter()
                .map(|&(r, a)| gain * a * (2.0 * std::f64::consts::PI * r * pitch * t).sin())
                .sum()
        })
    }

    fn options(a: &std::path::Path, b: &std::path::Path) -> CompareOptions {
        CompareOptions::parse(&[a.display().to_string(), b.display().to_string()]).unwrap()
    }

    #[test]
    fn the_same_tone_at_22_05_and_192_khz_passes_the_default_bounds() {
        // 220.37 Hz: off the 1 Hz and 10 Hz grids, so the interpolation and the leakage of
        // the Hann window are exercised; they depend on the frame's duration, not on the rate,
        // so the figures agree far inside the bounds measured on the renders.
        let a = tone("eq-22k", 22_050, 220.37, 1.0);
        let b = tone("eq-192k", 192_000, 220.37, 1.0);
        assert_eq!(compare(&options(&a, &b)), Ok(()));
        std::fs::remove_file(a).ok();
        std::fs::remove_file(b).ok();
    }

    #[test]
    fn a_level_change_of_6_db_fails() {
        let a = tone("lvl-22k", 22_050, 220.37, 1.0);
        let b = tone("lvl-192k", 192_000, 220.37, 0.5);
        let e = compare(&options(&a, &b)).unwrap_err();
        assert!(e.contains("levels differ by -6.02"), "{e}");
        // Every partial 6 dB down: the same pitch (the comparison of partials does not fail).
        assert!(!e.contains("partials differ"), "{e}");
        std::fs::remove_file(a).ok();
        std::fs::remove_file(b).ok();
    }

    #[test]
    fn a_pitch_change_of_one_semitone_fails() {
        let a = tone("st-22k", 22_050, 220.37, 1.0);
        let b = tone("st-192k", 192_000, 220.37 * 2f64.powf(1.0 / 12.0), 1.0);
        let e = compare(&options(&a, &b)).unwrap_err();
        // 100 cents, measured to within 0.5 cent (Gaussian interpolation of a Hann window's
        // peak on 1 Hz bins is within a few hundredths of a bin, 0.2 cent at 233 Hz).
        let at = e.find("partials differ by +").expect(&e) + "partials differ by +".len();
        let cents: f64 = e[at..].split(' ').next().unwrap().parse().unwrap();
        assert!((cents - 100.0).abs() < 0.5, "{e}");
        assert!(e.contains("spectra differ"), "{e}");
        std::fs::remove_file(a).ok();
        std::fs::remove_file(b).ok();
    }

    #[test]
    fn bad_options_are_refused_with_their_range() {
        let args = |extra: &[&str]| {
            let mut v = vec!["a.wav".to_string(), "b.wav".to_string()];
            v.extend(extra.iter().map(|s| s.to_string()));
            CompareOptions::parse(&v)
        };
        let e = args(&["--seconds", "0.1"]).unwrap_err();
        assert!(e.contains("--seconds: 0.1 is outside"), "{e}");
        let e = args(&["--max-freq", "nan"]).unwrap_err();
        assert!(e.contains("--max-freq: NaN is outside"), "{e}");
        assert!(args(&["--max-cents", "2"]).is_ok());
    }
}
