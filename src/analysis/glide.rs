//! Pitch glide of one partial (the opera gongs' rising or falling fundamental): the partial
//! isolated by an FFT band mask on the whole signal under a Tukey window (flat but for
//! 2 % cosine tapers at the ends, so the partial's level over time is kept), its frequency measured in
//! short overlapping windows from upward zero crossings ([`super::frequency::measure`]), and
//! the glide rate in Hz/s as the least-squares slope of that track over a time span.
//!
//! Resolution: a window of `T` seconds holds `f T` periods, and the crossing method places
//! each crossing to far below a sample, so a steady partial is measured to about 1e-9
//! relative; within a window a glide of `g` Hz/s is averaged, which is exact for a linear
//! glide at the window's centre. The band mask must hold the whole glide and exclude the
//! neighbouring partials: its half-width is a parameter.
//!
//! Offline (allocates).

use super::frequency::measure;
use super::fundamental::band_near_windowed;

/// A partial's frequency over time.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct GlideTrack {
    /// Window centres (s).
    pub times: Vec<f64>,
    /// The partial's frequency in each window (Hz).
    pub freqs: Vec<f64>,
    /// The band-masked partial's RMS in each window (units of the signal).
    pub levels: Vec<f64>,
}

/// A straight-line fit of a track over a time span.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlideRate {
    /// Slope in Hz/s (positive: the pitch rises).
    pub hz_per_second: f64,
    /// The fitted frequency at the span's start and end (Hz).
    pub start_hz: f64,
    /// See `start_hz`.
    pub end_hz: f64,
    /// The span actually fitted (s).
    pub from: f64,
    /// See `from`.
    pub to: f64,
    /// Windows in the fit.
    pub windows: usize,
    /// RMS deviation of the track from the line (Hz).
    pub residual_hz: f64,
}

impl GlideRate {
    /// The glide over the span in cents (`1200 log2(end/start)`).
    pub fn cents(&self) -> f64 {
        1200.0 * (self.end_hz / self.start_hz).log2()
    }
}

/// The track of the partial of `x` (sampled at `rate` Hz) near `near` Hz, isolated within
/// `half_band` Hz, in windows of `window` seconds every `hop` seconds. Windows where the
/// partial shows fewer than 4 periods, or whose frequency falls outside the band, are
/// skipped. Offline (allocates).
pub fn track_partial(
    x: &[f64],
    rate: f64,
    near: f64,
    half_band: f64,
    window: f64,
    hop: f64,
) -> GlideTrack {
    let y = band_mask(x, rate, near, half_band);
    let (len, step) = (
        ((window * rate) as usize).max(16),
        ((hop * rate) as usize).max(1),
    );
    let mut track = GlideTrack::default();
    let mut start = 0;
    while start + len <= y.len() {
        let w = &y[start..start + len];
        if let Some(m) = measure(w, 1.0 / rate) {
            let f = m.omega / std::f64::consts::TAU;
            if m.periods >= 4 && (f - near).abs() <= half_band {
                track.times.push((start as f64 + 0.5 * len as f64) / rate);
                track.freqs.push(f);
                track
                    .levels
                    .push((w.iter().map(|v| v * v).sum::<f64>() / len as f64).sqrt());
            }
        }
        start += step;
    }
    track
}

/// `x` under a Tukey window (cosine tapers over the first and last 2 %), with only its
/// spectrum within `half_band` Hz of `f` kept, back in the time domain.
fn band_mask(x: &[f64], rate: f64, f: f64, half_band: f64) -> Vec<f64> {
    let n = x.len();
    let taper = (n / 50).max(1);
    band_near_windowed(x, rate, f, half_band, |k| {
        let e = k.min(n - 1 - k);
        if e >= taper {
            1.0
        } else {
            0.5 - 0.5 * (std::f64::consts::PI * e as f64 / taper as f64).cos()
        }
    })
}

/// The least-squares line through `track` over `[from, to]` seconds; `None` with fewer than
/// 3 windows there.
pub fn glide_rate(track: &GlideTrack, from: f64, to: f64) -> Option<GlideRate> {
    let pts: Vec<(f64, f64)> = track
        .times
        .iter()
        .zip(&track.freqs)
        .filter(|(t, _)| **t >= from && **t <= to)
        .map(|(&t, &f)| (t, f))
        .collect();
    if pts.len() < 3 {
        return None;
    }
    let n = pts.len() as f64;
    let (mt, mf) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let stt: f64 = pts.iter().map(|p| (p.0 - mt).powi(2)).sum();
    let stf: f64 = pts.iter().map(|p| (p.0 - mt) * (p.1 - mf)).sum();
    let slope = stf / stt;
    let at = |t: f64| mf + slope * (t - mt);
    let residual = (pts.iter().map(|p| (p.1 - at(p.0)).powi(2)).sum::<f64>() / n).sqrt();
    let (t0, t1) = (pts[0].0, pts[pts.len() - 1].0);
    Some(GlideRate {
        hz_per_second: slope,
        start_hz: at(t0),
        end_hz: at(t1),
        from: t0,
        to: t1,
        windows: pts.len(),
        residual_hz: residual,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    /// A decaying partial gliding linearly from 500 Hz at +20 Hz/s under a louder steady
    /// partial at 1130 Hz, 2 s at 48 kHz: the measured rate is 20 Hz/s to 1e-3 relative (the
    /// window average of a linear glide is its centre value; the band mask's edge effects stay
    /// far below that, measured in the printout), a falling glide gives -20, and a steady
    /// partial 0 to 1e-3 Hz/s.
    #[test]
    fn recovers_a_linear_glide() {
        let rate = 48_000.0;
        for g in [20.0, -20.0, 0.0] {
            let x: Vec<f64> = (0..96_000)
                .map(|k| {
                    let t = k as f64 / rate;
                    let phase = TAU * (500.0 * t + 0.5 * g * t * t);
                    (-t).exp() * phase.sin() + 2.0 * (TAU * 1130.0 * t).sin()
                })
                .collect();
            let track = track_partial(&x, rate, 500.0, 120.0, 0.05, 0.025);
            let r = glide_rate(&track, 0.2, 1.8).unwrap();
            println!(
                "glide {g}: measured {:.6} Hz/s, residual {:.2e} Hz, {} windows",
                r.hz_per_second, r.residual_hz, r.windows
            );
            assert!((r.hz_per_second - g).abs() < 1e-3 * 20.0, "{g}: {r:?}");
            assert!((r.start_hz - (500.0 + g * r.from)).abs() < 0.05, "{r:?}");
        }
    }
}
