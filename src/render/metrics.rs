//! The distances between a render and its reference that `noether accuracy` reports (stated
//! in docs/ACCURACY.md): the waveform error of the attack, the log-spectral distance over STFT
//! bins, and the same distance over third-octave bands.
//!
//! - **relative L2 error over the first 50 ms**: `‖y - y_ref‖₂ / ‖y_ref‖₂` over the first
//!   `round(0.05 · rate)` samples (long waveforms of nonlinear models diverge in phase, so only
//!   the attack is compared sample by sample);
//! - **log-spectral distance** (LSD): the RMS over STFT frames and bins of
//!   `10 log10(P + ε) - 10 log10(P_ref + ε)` (dB), Hann window of 2048 samples, hop 512, with
//!   `ε` = 1e-8 of the reference's largest bin power (a -80 dB floor, so bins silent in both do
//!   not count);
//! - **band-level distance**: the same RMS after the power of each frame is summed over
//!   third-octave bands (base-2 centres `1 kHz · 2^(k/3)`, edges `2^(±1/6)` around them, IEC
//!   61260-1; each bin above DC belongs to the band holding its frequency, bands holding no bin
//!   are left out), a band's `ε` the bins' `ε` times its number of bins (the same floor of
//!   power per hertz). A single bin's power of
//!   a noise-like signal (a buzz, a gong's cascade) is an exponential random variable whose
//!   level spreads by 5.6 dB (its standard deviation) however long the render, so two renders
//!   with the same spectrum but independent fine structure are several dB apart in the LSD. A
//!   band sums many bins at high frequencies and measures the spectral envelope, which such
//!   renders share (the bands at the lowest frequencies hold one or two bins and weigh as in
//!   the LSD).
//!
//! Runs on the CLI thread (allocates).

use rustfft::{num_complex::Complex, FftPlanner};
use serde::Serialize;

/// STFT window of the log-spectral distance (samples).
pub const LSD_WINDOW: usize = 2048;
/// STFT hop of the log-spectral distance (samples).
pub const LSD_HOP: usize = 512;
/// Floor of the log-spectral and band-level distances relative to the reference's largest bin
/// (band) power.
pub const LSD_FLOOR: f64 = 1e-8;
/// Length of the waveform comparison (s).
pub const L2_SECONDS: f64 = 0.05;

/// Relative L2 error `‖y - r‖ / ‖r‖` over the first `n` samples (or the common length).
pub fn relative_l2(y: &[f64], reference: &[f64], n: usize) -> f64 {
    let n = n.min(y.len()).min(reference.len());
    let (mut num, mut den) = (0.0, 0.0);
    for (a, b) in y[..n].iter().zip(&reference[..n]) {
        num += (a - b) * (a - b);
        den += b * b;
    }
    if den > 0.0 {
        (num / den).sqrt()
    } else {
        num.sqrt()
    }
}

/// Power spectra `|X|²` of Hann-windowed frames of `x`.
pub fn power_frames(x: &[f64]) -> Vec<Vec<f64>> {
    let fft = FftPlanner::<f64>::new().plan_fft_forward(LSD_WINDOW);
    let hann: Vec<f64> = (0..LSD_WINDOW)
        .map(|n| 0.5 - 0.5 * (std::f64::consts::TAU * n as f64 / LSD_WINDOW as f64).cos())
        .collect();
    let mut out = Vec::new();
    let mut buf = vec![Complex::new(0.0, 0.0); LSD_WINDOW];
    let mut start = 0;
    loop {
        for (n, b) in buf.iter_mut().enumerate() {
            *b = Complex::new(x.get(start + n).copied().unwrap_or(0.0) * hann[n], 0.0);
        }
        fft.process(&mut buf);
        out.push(
            buf[..=LSD_WINDOW / 2]
                .iter()
                .map(|c| c.norm_sqr())
                .collect(),
        );
        start += LSD_HOP;
        if start + LSD_WINDOW > x.len() {
            break;
        }
    }
    out
}

/// Log-spectral distance in dB between `y` and `reference` (see the module doc).
pub fn log_spectral_distance(y: &[f64], reference: &[f64]) -> f64 {
    let n = y.len().min(reference.len());
    lsd_of_frames(&power_frames(&y[..n]), &power_frames(&reference[..n]))
}

/// The log-spectral distance (dB) of the frames `a` of a render from the frames `b` of its
/// reference: the RMS over frames and bins of [`level_difference`] with the bin floor.
fn lsd_of_frames(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    let eps = bin_floor(b);
    let (mut sum, mut count) = (0.0, 0usize);
    for (fa, fb) in a.iter().zip(b) {
        for (&pa, &pb) in fa.iter().zip(fb) {
            let d = level_difference(pa, pb, eps);
            sum += d * d;
            count += 1;
        }
    }
    (sum / count.max(1) as f64).sqrt()
}

/// The floor `ε` of one bin: [`LSD_FLOOR`] times the largest bin power of the reference's
/// frames (and at least the smallest positive `f64`, so silence in both compares as equal).
fn bin_floor(reference: &[Vec<f64>]) -> f64 {
    let peak = reference.iter().flatten().fold(0.0f64, |m, &p| m.max(p));
    (LSD_FLOOR * peak).max(f64::MIN_POSITIVE)
}

/// `10 log10((p + ε) / (p_ref + ε))` in dB: one cell's (bin's or band's) level difference.
fn level_difference(p: f64, p_ref: f64, eps: f64) -> f64 {
    10.0 * ((p + eps) / (p_ref + eps)).log10()
}

/// The third-octave bands of an STFT of `LSD_WINDOW` samples at `rate` Hz: for each band that
/// holds a bin, the range of its bins (bin `j` is at `j · rate / LSD_WINDOW` Hz; DC is left
/// out). Band `k` holds the frequencies whose `3 log2(f / 1 kHz)` rounds to `k`.
pub fn third_octave_bands(rate: f64) -> Vec<std::ops::Range<usize>> {
    let band_of = |j: usize| band_index(j, rate);
    let mut bands: Vec<std::ops::Range<usize>> = Vec::new();
    let mut current = band_of(1);
    let mut first = 1;
    for j in 2..=LSD_WINDOW / 2 {
        let k = band_of(j);
        if k != current {
            bands.push(first..j);
            first = j;
            current = k;
        }
    }
    bands.push(first..LSD_WINDOW / 2 + 1);
    bands
}

/// One third-octave band of a comparison: where it lies, how loud the reference is there and
/// how far the render is from it, per band and per bin.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BandComparison {
    /// Centre frequency `1 kHz · 2^(k/3)` (Hz).
    pub centre_hz: f64,
    /// STFT bins in the band.
    pub bins: usize,
    /// The reference's band power averaged over the frames, in dB relative to its loudest
    /// band (0 dB there).
    pub reference_level_db: f64,
    /// RMS over the frames of the band-level difference (dB): this band's part of
    /// [`band_level_distance`].
    pub band_db: f64,
    /// RMS over the frames and the band's bins of the bin-level difference (dB): this band's
    /// part of [`log_spectral_distance`].
    pub bins_db: f64,
    /// The render's band power averaged over the frames against the reference's, in dB (with
    /// the band's floor): positive where the render is louder in this band over the whole
    /// render. A model that misses part of the spectrum shows here as a bias, while two
    /// renders that differ only in their fine structure are near 0.
    pub mean_diff_db: f64,
}

/// The distances of `y` from `reference` (both at `rate` Hz) band by band (module doc; same
/// frames, bands and floors as [`band_level_distance`] and [`log_spectral_distance`]).
pub fn band_breakdown(y: &[f64], reference: &[f64], rate: f64) -> Vec<BandComparison> {
    let n = y.len().min(reference.len());
    breakdown_of_frames(&power_frames(&y[..n]), &power_frames(&reference[..n]), rate)
}

/// [`band_breakdown`] of the frames `a` of a render against the frames `b` of its reference
/// (as many frames each).
fn breakdown_of_frames(a: &[Vec<f64>], b: &[Vec<f64>], rate: f64) -> Vec<BandComparison> {
    let frames = b.len().max(1) as f64;
    let bands = third_octave_bands(rate);
    let floor = bin_floor(b);
    let mean_power: Vec<f64> = bands
        .iter()
        .map(|r| {
            b.iter()
                .map(|f| f[r.clone()].iter().sum::<f64>())
                .sum::<f64>()
                / frames
        })
        .collect();
    let loudest = mean_power.iter().fold(f64::MIN_POSITIVE, |m, &p| m.max(p));
    bands
        .iter()
        .zip(&mean_power)
        .map(|(r, &power)| {
            let e = floor * r.len() as f64;
            let (mut band, mut bins, mut power_a) = (0.0, 0.0, 0.0);
            for (fa, fb) in a.iter().zip(b) {
                let pa: f64 = fa[r.clone()].iter().sum();
                power_a += pa;
                let d = level_difference(pa, fb[r.clone()].iter().sum(), e);
                band += d * d;
                for (&pa, &pb) in fa[r.clone()].iter().zip(&fb[r.clone()]) {
                    let d = level_difference(pa, pb, floor);
                    bins += d * d;
                }
            }
            BandComparison {
                centre_hz: 1000.0 * 2f64.powf(band_index(r.start, rate) as f64 / 3.0),
                bins: r.len(),
                reference_level_db: 10.0 * (power.max(f64::MIN_POSITIVE) / loudest).log10(),
                band_db: (band / frames).sqrt(),
                bins_db: (bins / (frames * r.len() as f64)).sqrt(),
                mean_diff_db: level_difference(power_a / frames, power, e),
            }
        })
        .collect()
}

/// Every distance a study reports between a render and its reference (both at `rate` Hz),
/// from one STFT of each.
#[derive(Debug, Clone, PartialEq)]
pub struct SignalDistances {
    /// [`relative_l2`] over the first [`L2_SECONDS`].
    pub l2_50ms: f64,
    /// [`log_spectral_distance`] (dB).
    pub lsd_db: f64,
    /// [`band_level_distance`] (dB).
    pub band_db: f64,
    /// [`band_breakdown`].
    pub bands: Vec<BandComparison>,
}

/// The [`SignalDistances`] of `y` from `reference`, both at `rate` Hz: the same values as the
/// four functions, with the frames of each signal computed once.
pub fn signal_distances(y: &[f64], reference: &[f64], rate: f64) -> SignalDistances {
    let n = y.len().min(reference.len());
    let (a, b) = (power_frames(&y[..n]), power_frames(&reference[..n]));
    let bands = breakdown_of_frames(&a, &b, rate);
    SignalDistances {
        l2_50ms: relative_l2(y, reference, (L2_SECONDS * rate).round() as usize),
        lsd_db: lsd_of_frames(&a, &b),
        band_db: band_level_of(&bands),
        bands,
    }
}

/// The third-octave band `k = round(3 log2(f / 1 kHz))` of STFT bin `j ≥ 1` at `rate` Hz.
fn band_index(j: usize, rate: f64) -> i64 {
    let f = j as f64 * rate / LSD_WINDOW as f64;
    (3.0 * (f / 1000.0).log2()).round() as i64
}

/// Band-level distance in dB between `y` and `reference`, both at `rate` Hz (see the module
/// doc): the RMS over the bands of [`band_breakdown`]'s `band_db` (every band has the same
/// frames). A band's floor is the bin floor of [`log_spectral_distance`] times its number of
/// bins (the same floor of power per hertz), so a band whose bins all lie below the bin floor
/// counts as silent here as they do there.
pub fn band_level_distance(y: &[f64], reference: &[f64], rate: f64) -> f64 {
    band_level_of(&band_breakdown(y, reference, rate))
}

/// The band-level distance (dB) of a [`band_breakdown`]: the RMS of its `band_db`.
pub fn band_level_of(bands: &[BandComparison]) -> f64 {
    let sum: f64 = bands.iter().map(|b| b.band_db * b.band_db).sum();
    (sum / bands.len().max(1) as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `n` samples of deterministic white noise (xorshift64 from `seed`), uniform in [-1, 1).
    fn noise(seed: u64, n: usize) -> Vec<f64> {
        let mut state = seed;
        (0..n)
            .map(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 11) as f64 / (1u64 << 52) as f64 - 1.0
            })
            .collect()
    }

    /// Identical signals have zero distance; a 1 % amplitude change gives L2 = 0.01 exactly
    /// (to round-off, 1e-12) and, on a broadband signal whose bins and bands all lie far above
    /// the -80 dB floor, an LSD and a band distance of 20 log10(1.01) = 0.0864 dB (the floor's
    /// pull is below 1e-6 dB here).
    #[test]
    fn metrics_of_known_differences() {
        let x = noise(0x9E37_79B9_7F4A_7C15, 48_000);
        let y: Vec<f64> = x.iter().map(|v| 1.01 * v).collect();
        assert_eq!(relative_l2(&x, &x, 2400), 0.0);
        assert_eq!(log_spectral_distance(&x, &x), 0.0);
        assert_eq!(band_level_distance(&x, &x, 48_000.0), 0.0);
        assert!((relative_l2(&y, &x, 2400) - 0.01).abs() < 1e-12);
        let full = 20.0 * 1.01f64.log10();
        let lsd = log_spectral_distance(&y, &x);
        assert!((lsd - full).abs() < 1e-6, "{lsd} vs {full}");
        let bands = band_level_distance(&y, &x, 48_000.0);
        assert!((bands - full).abs() < 1e-6, "{bands} vs {full}");
    }

    /// The bands tile the bins above DC in order, each holds the bins of one third octave
    /// (`3 log2(f / 1 kHz)` rounds to one integer inside it and to a larger one in the next),
    /// and the 1 kHz band is the bins from 891 to 1122 Hz (`1000 · 2^(±1/6)`).
    #[test]
    fn third_octave_bands_tile_the_spectrum() {
        let rate = 48_000.0;
        let bands = third_octave_bands(rate);
        let hz = |j: usize| j as f64 * rate / LSD_WINDOW as f64;
        let k = |j: usize| (3.0 * (hz(j) / 1000.0).log2()).round() as i64;
        assert_eq!(bands[0].start, 1);
        assert_eq!(bands.last().unwrap().end, LSD_WINDOW / 2 + 1);
        for w in bands.windows(2) {
            assert_eq!(w[0].end, w[1].start);
            assert!(k(w[0].end - 1) < k(w[1].start));
        }
        for b in &bands {
            assert!(!b.is_empty());
            assert_eq!(k(b.start), k(b.end - 1));
        }
        let one_k = bands.iter().find(|b| k(b.start) == 0).unwrap();
        let (lo, hi) = (
            1000.0 * 2f64.powf(-1.0 / 6.0),
            1000.0 * 2f64.powf(1.0 / 6.0),
        );
        assert!(hz(one_k.start) >= lo && hz(one_k.start - 1) < lo);
        assert!(hz(one_k.end - 1) <= hi && hz(one_k.end) > hi);
    }

    /// `ψ₁(x)`, the trigamma function, for `x ≥ 1`: the recurrence `ψ₁(x) = ψ₁(x + 1) + 1/x²`
    /// up to `x ≥ 6`, then its asymptotic series (Abramowitz and Stegun 6.4.12, error below
    /// 1e-9 there).
    fn trigamma(mut x: f64) -> f64 {
        let mut s = 0.0;
        while x < 6.0 {
            s += 1.0 / (x * x);
            x += 1.0;
        }
        let x2 = x * x;
        s + 1.0 / x + 1.0 / (2.0 * x2) + 1.0 / (6.0 * x2 * x) - 1.0 / (30.0 * x2 * x2 * x)
            + 1.0 / (42.0 * x2 * x2 * x2 * x)
    }

    /// Two independent white noises of equal spectrum, 10 s at 48 kHz (about 10⁶ frame-bins
    /// from 937 frames).
    ///
    /// A bin's power is an exponential random variable; its level `10 log10 P` has a variance
    /// of `c² ψ₁(1) = c² π²/6` with `c = 10/ln 10` (5.57 dB standard deviation), so the level
    /// difference of two independent ones has an RMS of `√2 · 5.57 = 7.88 dB`, the LSD's
    /// expectation, which 10⁶ samples must reproduce within 0.3 dB (the neighbouring bins of a
    /// Hann window are correlated, which leaves each bin's distribution as it is).
    ///
    /// A band of `n` bins sums them: for independent bins a Gamma(n) variable, whose level has
    /// the variance `c² ψ₁(n)`; the Hann window's neighbouring bins overlap (its noise bandwidth
    /// is 1.5 bins), so the sum averages between `n / 1.5` and `n` independent values. The band
    /// distance must lie between the two predictions `√(mean over bands of 2 c² ψ₁(n_eff))`
    /// (3.99 and 4.36 dB here; the bands of one or two bins below 100 Hz weigh as much as the wide
    /// ones, which is why it is not smaller), within 3 % (the sampling error of the narrow
    /// bands' mean over 937 frames).
    #[test]
    fn bands_measure_the_envelope_of_noise() {
        let rate = 48_000.0;
        let a = noise(0x9E37_79B9_7F4A_7C15, 480_000);
        let b = noise(0xD1B5_4A32_D192_ED03, 480_000);
        let lsd = log_spectral_distance(&a, &b);
        let bands = band_level_distance(&a, &b, rate);
        let c2 = (10.0 / 10f64.ln()).powi(2);
        let theory = (2.0 * c2 * trigamma(1.0)).sqrt();
        assert!(
            (lsd - theory).abs() < 0.3,
            "LSD {lsd} dB, theory {theory} dB"
        );
        let widths = third_octave_bands(rate);
        let predicted = |spread: f64| {
            let sum: f64 = widths
                .iter()
                .map(|w| 2.0 * c2 * trigamma((w.len() as f64 / spread).max(1.0)))
                .sum();
            (sum / widths.len() as f64).sqrt()
        };
        let (low, high) = (predicted(1.0), predicted(1.5));
        assert!(
            bands > 0.97 * low && bands < 1.03 * high,
            "bands {bands} dB, predicted {low}-{high} dB"
        );
        eprintln!(
            "white noise: LSD {lsd:.3} dB (theory {theory:.3}), bands {bands:.3} dB \
             (predicted {low:.3}-{high:.3})"
        );
    }

    /// The breakdown adds up: its `bins_db` weighted by the bins give the LSD over the bins
    /// above DC (computed here from the frames, to 1e-12 relative: only the summation order
    /// differs), a 1 % louder copy is 0.0864 dB away in every band and every band's bins, and
    /// 0.0864 dB louder in every band's mean (the reference -0.0864 dB against it; all to
    /// 2e-5 dB: the -80 dB floor pulls the rare white-noise bins far below the peak, by
    /// `0.0864 dB · ε / P`, 2e-6 dB measured in the worst band), and
    /// the loudest band of a 1 kHz tone over faint noise is the 1 kHz band, at 0 dB.
    #[test]
    fn the_breakdown_adds_up() {
        let rate = 48_000.0;
        let x = noise(0x9E37_79B9_7F4A_7C15, 48_000);
        let z = noise(0xD1B5_4A32_D192_ED03, 48_000);
        let bands = band_breakdown(&z, &x, rate);
        let (fa, fb) = (power_frames(&z), power_frames(&x));
        let floor = bin_floor(&fb);
        let (mut sum, mut count) = (0.0, 0usize);
        for (a, b) in fa.iter().zip(&fb) {
            for (pa, pb) in a[1..].iter().zip(&b[1..]) {
                sum += (10.0 * ((pa + floor) / (pb + floor)).log10()).powi(2);
                count += 1;
            }
        }
        let direct = (sum / count as f64).sqrt();
        let weighted: f64 = bands
            .iter()
            .map(|b| b.bins as f64 * b.bins_db * b.bins_db)
            .sum();
        let bins: usize = bands.iter().map(|b| b.bins).sum();
        let combined = (weighted / bins as f64).sqrt();
        assert!(
            (combined - direct).abs() < 1e-12 * direct,
            "{combined} vs {direct}"
        );

        let y: Vec<f64> = x.iter().map(|v| 1.01 * v).collect();
        let full = 20.0 * 1.01f64.log10();
        for b in band_breakdown(&y, &x, rate) {
            assert!((b.band_db - full).abs() < 2e-5, "{b:?}");
            assert!((b.bins_db - full).abs() < 2e-5, "{b:?}");
            assert!((b.mean_diff_db - full).abs() < 2e-5, "{b:?}");
        }
        // Quieter is negative: the reference against the louder copy.
        for b in band_breakdown(&x, &y, rate) {
            assert!((b.mean_diff_db + full).abs() < 2e-5, "{b:?}");
        }

        let tone: Vec<f64> = (0..48_000)
            .map(|n| (std::f64::consts::TAU * 1000.0 * n as f64 / rate).sin() + 1e-3 * x[n])
            .collect();
        let bands = band_breakdown(&tone, &tone, rate);
        let loudest = bands
            .iter()
            .max_by(|a, b| a.reference_level_db.total_cmp(&b.reference_level_db))
            .unwrap();
        assert_eq!(loudest.centre_hz, 1000.0);
        assert_eq!(loudest.reference_level_db, 0.0);
        assert!(bands
            .iter()
            .all(|b| b.band_db == 0.0 && b.bins_db == 0.0 && b.mean_diff_db == 0.0));
    }

    /// [`signal_distances`] gives exactly (bit for bit) what the four separate functions give:
    /// it only shares their frames.
    #[test]
    fn signal_distances_equal_the_separate_metrics() {
        let rate = 48_000.0;
        let x = noise(0x9E37_79B9_7F4A_7C15, 30_000);
        let z: Vec<f64> = noise(0xD1B5_4A32_D192_ED03, 30_000)
            .iter()
            .zip(&x)
            .map(|(n, s)| s + 0.1 * n)
            .collect();
        let d = signal_distances(&z, &x, rate);
        let n = (L2_SECONDS * rate).round() as usize;
        assert_eq!(d.l2_50ms, relative_l2(&z, &x, n));
        assert_eq!(d.lsd_db, log_spectral_distance(&z, &x));
        assert_eq!(d.band_db, band_level_distance(&z, &x, rate));
        assert_eq!(d.bands, band_breakdown(&z, &x, rate));
        assert!(d.l2_50ms > 0.0 && d.lsd_db > 0.0 && d.band_db > 0.0);
    }
}
