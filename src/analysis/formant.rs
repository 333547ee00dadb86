//! The jawari's sweeping formant, measured from a plucked string's sound: a band of
//! harmonics louder than the spectrum's trend, whose centre moves down over the first second
//! of a pluck (Raman 1921; Valette, *Mechanics of Musical Instruments*, 1995).
//!
//! Per frame (Hann window of [`FORMANT_WINDOW`] samples at 48 kHz, the same duration at other
//! rates, starting at each time):
//! 1. the level `L_n` (dB) of harmonic `n = 1 …`: the largest bin within ±1.5 % of `n f_1`
//!    (the partials of a stiff string against a bridge lie within that of `n f_1`);
//! 2. the trend: a straight line in `log₂ n` fitted to `L_n` over `n ≥ 3` by least squares
//!    (a plucked string's spectrum falls by a number of dB per octave); `R_n = L_n - trend`;
//! 3. `R` smoothed over three neighbouring harmonics; the formant is its largest value over
//!    harmonics [`FIRST_HARMONIC`] to [`LAST_HARMONIC`], and its prominence is that value
//!    over the median of `R` within half an octave either side.
//!
//! A string without the thread has no such band: its largest bump is the steady shape of the
//! pluck's comb and the losses, which does not move. Offline analysis (allocates).

use rustfft::{num_complex::Complex, FftPlanner};

/// Samples per frame at 48 kHz (0.17 s: harmonics of 100 Hz resolved 17 times over); at other
/// rates the power of two nearest the same duration.
pub const FORMANT_WINDOW: usize = 8192;

/// Lowest harmonic the formant may sit on (below it the trend's fit is the fundamental's).
pub const FIRST_HARMONIC: usize = 6;

/// Highest harmonic the formant may sit on.
pub const LAST_HARMONIC: usize = 50;

/// Harmonics measured (the trend is fitted over 3 to this).
const HARMONICS: usize = 60;

/// The formant of one frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FormantFrame {
    /// Start of the frame (s).
    pub time: f64,
    /// The harmonic at the formant's centre.
    pub harmonic: usize,
    /// Its frequency, `harmonic · f_1` (Hz).
    pub hz: f64,
    /// How far it stands above its surroundings (dB, see the module doc).
    pub prominence_db: f64,
}

/// The formant of `x` (sampled at `rate` Hz, fundamental `f1` Hz) in frames starting at each
/// of `times` (s): each frame's largest excess over the trend. Frames that would run past the
/// signal's end are left out; harmonics above 0.45 `rate` are not measured.
pub fn harmonic_formant(x: &[f64], rate: f64, f1: f64, times: &[f64]) -> Vec<FormantFrame> {
    excess_over_trend(x, rate, f1, times)
        .into_iter()
        .map(|(time, smooth)| {
            let best = (FIRST_HARMONIC..=LAST_HARMONIC)
                .max_by(|&a, &b| smooth[a - 1].total_cmp(&smooth[b - 1]))
                .unwrap_or(FIRST_HARMONIC);
            frame(time, best, f1, &smooth)
        })
        .collect()
}

/// The formant followed as a ridge: from the first frame's largest excess, in each next frame
/// the highest local maximum of the excess within [`RIDGE_DOWN`] harmonics below and
/// [`RIDGE_UP`] above the last one (a moving band is followed while it moves; a band standing
/// still stays where it is, even when another outgrows it elsewhere). Frames as
/// [`harmonic_formant`]'s.
pub fn formant_ridge(x: &[f64], rate: f64, f1: f64, times: &[f64]) -> Vec<FormantFrame> {
    let mut last: Option<usize> = None;
    excess_over_trend(x, rate, f1, times)
        .into_iter()
        .map(|(time, smooth)| {
            let top = smooth.len().min(LAST_HARMONIC);
            let (lo, hi) = match last {
                None => (FIRST_HARMONIC, top),
                Some(h) => (
                    h.saturating_sub(RIDGE_DOWN).max(FIRST_HARMONIC),
                    (h + RIDGE_UP).min(top),
                ),
            };
            let peak = |h: usize| {
                let v = smooth[h - 1];
                (h == 1 || v >= smooth[h - 2]) && (h == smooth.len() || v >= smooth[h])
            };
            let best = (lo..=hi)
                .filter(|&h| last.is_none() || peak(h))
                .max_by(|&a, &b| smooth[a - 1].total_cmp(&smooth[b - 1]))
                .or(last)
                .unwrap_or(FIRST_HARMONIC);
            last = Some(best);
            frame(time, best, f1, &smooth)
        })
        .collect()
}

/// Harmonics a ridge may move down between frames.
pub const RIDGE_DOWN: usize = 8;

/// Harmonics a ridge may move up between frames.
pub const RIDGE_UP: usize = 2;

/// The frame at `time` with the formant on harmonic `best` of the smoothed excess `smooth`.
fn frame(time: f64, best: usize, f1: f64, smooth: &[f64]) -> FormantFrame {
    let (lo, hi) = (best as f64 / 1.5, best as f64 * 1.5);
    let mut near: Vec<f64> = (1..=smooth.len())
        .filter(|&h| (h as f64) >= lo && (h as f64) <= hi)
        .map(|h| smooth[h - 1])
        .collect();
    near.sort_by(f64::total_cmp);
    FormantFrame {
        time,
        harmonic: best,
        hz: best as f64 * f1,
        prominence_db: smooth[best - 1] - near[near.len() / 2],
    }
}

/// Per frame (its start time, s), the harmonics' excess over the spectrum's trend, smoothed
/// over three harmonics (dB; index `n - 1` for harmonic `n`; module doc, steps 1 to 3).
fn excess_over_trend(x: &[f64], rate: f64, f1: f64, times: &[f64]) -> Vec<(f64, Vec<f64>)> {
    let n_fft = window_at(rate);
    let fft = FftPlanner::<f64>::new().plan_fft_forward(n_fft);
    let hann: Vec<f64> = (0..n_fft)
        .map(|n| 0.5 - 0.5 * (std::f64::consts::TAU * n as f64 / n_fft as f64).cos())
        .collect();
    let top = HARMONICS.min((0.45 * rate / f1).floor() as usize);
    let mut out = Vec::new();
    let mut buf = vec![Complex::new(0.0, 0.0); n_fft];
    for &t in times {
        let start = (t * rate).round() as usize;
        if top < LAST_HARMONIC.min(HARMONICS) || start + n_fft > x.len() {
            continue;
        }
        for (n, b) in buf.iter_mut().enumerate() {
            *b = Complex::new(x[start + n] * hann[n], 0.0);
        }
        fft.process(&mut buf);
        let bin_hz = rate / n_fft as f64;
        let level: Vec<f64> = (1..=top)
            .map(|h| {
                let f = h as f64 * f1;
                let lo = ((f * 0.985 / bin_hz).ceil() as usize).max(1);
                let hi = ((f * 1.015 / bin_hz).floor() as usize).min(n_fft / 2);
                let peak = (lo..=hi.max(lo))
                    .map(|j| buf[j].norm())
                    .fold(0.0f64, f64::max);
                20.0 * (peak + 1e-300).log10()
            })
            .collect();
        // Least-squares line in log2 n over n = 3..=top.
        let pts: Vec<(f64, f64)> = (3..=top)
            .map(|h| ((h as f64).log2(), level[h - 1]))
            .collect();
        let m = pts.len() as f64;
        let (sx, sy) = pts.iter().fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
        let (mx, my) = (sx / m, sy / m);
        let (sxy, sxx) = pts.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
            (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
        });
        let slope = sxy / sxx;
        let resid: Vec<f64> = (1..=top)
            .map(|h| level[h - 1] - (my + slope * ((h as f64).log2() - mx)))
            .collect();
        let smooth: Vec<f64> = (0..top)
            .map(|i| {
                let (a, b) = (i.saturating_sub(1), (i + 1).min(top - 1));
                resid[a..=b].iter().sum::<f64>() / (b - a + 1) as f64
            })
            .collect();
        out.push((t, smooth));
    }
    out
}

/// The frame length at `rate` Hz: the power of two nearest [`FORMANT_WINDOW`]'s duration at
/// 48 kHz.
fn window_at(rate: f64) -> usize {
    let exact = FORMANT_WINDOW as f64 * rate / 48_000.0;
    1usize << (exact.max(16.0).log2().round() as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A synthetic spectrum: harmonics of 100 Hz falling 6 dB per octave, with harmonic 20 and
    /// its neighbours 12 dB louder. The formant is found on harmonic 20 (or a neighbour, the
    /// three-harmonic smoothing) and stands out by several dB; without the band it does not.
    #[test]
    fn finds_a_band_of_loud_harmonics() {
        let rate = 48_000.0;
        let signal = |band: bool| -> Vec<f64> {
            (0..FORMANT_WINDOW)
                .map(|i| {
                    let t = i as f64 / rate;
                    (1..=60)
                        .map(|h| {
                            let boost = if band && (19..=21).contains(&h) {
                                4.0
                            } else {
                                1.0
                            };
                            boost / h as f64 * (std::f64::consts::TAU * 100.0 * h as f64 * t).sin()
                        })
                        .sum()
                })
                .collect()
        };
        let with = harmonic_formant(&signal(true), rate, 100.0, &[0.0]);
        assert_eq!(with.len(), 1);
        assert!((19..=21).contains(&with[0].harmonic), "{with:?}");
        assert!(with[0].prominence_db > 6.0, "{with:?}");
        let without = harmonic_formant(&signal(false), rate, 100.0, &[0.0]);
        assert!(without[0].prominence_db < 1.0, "{without:?}");
    }
}
