//! Short-time Fourier transform magnitude (Hann window) for spectrogram figures.

use rustfft::{num_complex::Complex, FftPlanner};

/// A magnitude spectrogram in decibels.
#[derive(Debug, Clone)]
pub struct Spectrogram {
    /// Frame start times (s).
    pub times: Vec<f64>,
    /// Bin centre frequencies (Hz), 0 to Nyquist.
    pub freqs: Vec<f64>,
    /// `db[frame][bin]`, `20 log10(|X| / max|X|)` (0 dB at the loudest cell), floored at -200.
    pub db: Vec<Vec<f64>>,
}

/// Computes the spectrogram of `x` sampled at `rate` Hz with a Hann window of `window`
/// samples and hop `hop`.
pub fn spectrogram(x: &[f64], rate: f64, window: usize, hop: usize) -> Spectrogram {
    let window = window.max(16);
    let hop = hop.max(1);
    let fft = FftPlanner::<f64>::new().plan_fft_forward(window);
    let hann: Vec<f64> = (0..window)
        .map(|n| 0.5 - 0.5 * (std::f64::consts::TAU * n as f64 / window as f64).cos())
        .collect();
    let bins = window / 2 + 1;
    let mut mags = Vec::new();
    let mut times = Vec::new();
    let mut buf = vec![Complex::new(0.0, 0.0); window];
    let mut start = 0;
    while start + window <= x.len().max(window) {
        for (n, b) in buf.iter_mut().enumerate() {
            let v = x.get(start + n).copied().unwrap_or(0.0);
            *b = Complex::new(v * hann[n], 0.0);
        }
        fft.process(&mut buf);
        mags.push(buf[..bins].iter().map(|c| c.norm()).collect::<Vec<f64>>());
        times.push(start as f64 / rate);
        start += hop;
        if start + window > x.len() {
            break;
        }
    }
    let peak = mags.iter().flatten().fold(0.0f64, |m, &v| m.max(v));
    let peak = if peak > 0.0 { peak } else { 1.0 };
    let db = mags
        .into_iter()
        .map(|f| {
            f.into_iter()
                .map(|m| (20.0 * (m / peak).log10()).max(-200.0))
                .collect()
        })
        .collect();
    Spectrogram {
        times,
        freqs: (0..bins).map(|k| k as f64 * rate / window as f64).collect(),
        db,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peak_at_the_sine_frequency() {
        let rate = 8000.0;
        let x: Vec<f64> = (0..8000)
            .map(|n| (std::f64::consts::TAU * 1000.0 * n as f64 / rate).sin())
            .collect();
        let s = spectrogram(&x, rate, 512, 256);
        let frame = &s.db[3];
        let k = (0..frame.len())
            .max_by(|&a, &b| frame[a].total_cmp(&frame[b]))
            .unwrap();
        assert!(
            (s.freqs[k] - 1000.0).abs() <= rate / 512.0,
            "peak at {}",
            s.freqs[k]
        );
    }
}
