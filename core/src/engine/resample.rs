//! Streaming band-limited resampler from a bank's simulation rate to the host rate: a
//! Kaiser-windowed sinc kernel evaluated from a table, pulled one host sample at a time.
//!
//! Written by hand rather than rubato's `process_into_buffer`: rubato's resamplers work in
//! fixed chunks (fixed input or fixed output length) and add a chunk of latency and a
//! chunk-sized buffering layer on top; the engine needs any host block size from 1 to 8192,
//! exactly as many simulation steps as the next host samples need (so silence and note
//! onsets are sample-accurate), and a latency of only the kernel's half-width. This one is
//! that: `input_needed(n)` tells the engine how many simulation steps to run, `push` appends
//! them, `produce` writes `n` host samples. All buffers are allocated in [`Resampler::new`]
//! (worker thread); `push`/`produce` never allocate (audio thread).
//!
//! Kernel (Smith, "Digital Audio Resampling", and the windowed-sinc design of Kaiser):
//! `k(x) = f_c sinc(f_c x) w(x / R)` on `|x| ≤ R` input samples, `f_c = 0.9 min(1, fs_out/fs_in)`
//! (cutoff 0.45 of the lower of the two rates, relative to the input rate), `R = Z / f_c` for
//! `Z = 12` zero crossings, Kaiser window with `β = 8` (side lobes about -80 dB). The output
//! sample `j` is `Σ_i x_i k(t_j - i)` with `t_j = j · fs_in / fs_out`; the latency is `R` input
//! samples.

/// Zero crossings of the sinc on each side of the kernel.
const ZERO_CROSSINGS: f64 = 12.0;
/// Kaiser window shape.
const KAISER_BETA: f64 = 8.0;
/// Cutoff as a fraction of the lower Nyquist frequency.
const CUTOFF: f64 = 0.9;

/// Modified Bessel function `I0(x)` by its power series (converges for every `x`; `x ≤ 8`
/// here needs about 25 terms for full double precision).
fn bessel_i0(x: f64) -> f64 {
    let (mut sum, mut term) = (1.0, 1.0);
    let q = 0.25 * x * x;
    for k in 1..60 {
        term *= q / (k * k) as f64;
        sum += term;
        if term < 1e-17 * sum {
            break;
        }
    }
    sum
}

/// A stereo streaming resampler (see the module doc). Built on the worker thread, used on the
/// audio thread.
#[derive(Debug, Clone)]
pub struct Resampler {
    /// Input samples per output sample, `fs_in / fs_out`.
    ratio: f64,
    /// Kernel half-width `R` in input samples (integer ceiling).
    half: usize,
    /// Table resolution: entries per input sample.
    per_sample: f64,
    /// `k(x)` at `x = i / per_sample - half`, plus one guard entry.
    table: Vec<f32>,
    /// Input history, one ring per channel, length a power of two.
    hist: [Vec<f32>; 2],
    mask: usize,
    /// Input samples pushed so far.
    written: u64,
    /// Left edge of the next output's kernel, in input samples: that output is at input
    /// time `pos + half` (the latency `half`).
    pos: f64,
    /// Largest output block `produce` accepts.
    max_out: usize,
    /// Consecutive zero input samples pushed most recently.
    zero_run: usize,
}

impl Resampler {
    /// A resampler from `fs_in` to `fs_out` (Hz) for output blocks of at most `max_out`
    /// samples. Worker thread (allocates). Rates must be finite and positive (checked by the
    /// caller's parameter validation).
    pub fn new(fs_in: f64, fs_out: f64, max_out: usize) -> Self {
        let ratio = fs_in / fs_out;
        let fc = CUTOFF * (fs_out / fs_in).min(1.0);
        let half = Self::half_width(fs_in, fs_out);
        // 256 table points per zero crossing (at least 16 per input sample while the cutoff is
        // above 1/16 of the input rate, where both agree; far below, at host rates of a few
        // hundred hertz, the kernel spans thousands of input samples and is as smooth).
        let per_sample = 256.0 * fc;
        let len = (2.0 * half as f64 * per_sample).ceil() as usize + 2;
        let i0b = bessel_i0(KAISER_BETA);
        let table: Vec<f32> = (0..len)
            .map(|i| {
                let x = i as f64 / per_sample - half as f64;
                let u = x / half as f64;
                if u.abs() >= 1.0 {
                    return 0.0;
                }
                let arg = std::f64::consts::PI * fc * x;
                let sinc = if arg.abs() < 1e-12 {
                    1.0
                } else {
                    arg.sin() / arg
                };
                let w = bessel_i0(KAISER_BETA * (1.0 - u * u).sqrt()) / i0b;
                (fc * sinc * w) as f32
            })
            .collect();
        let need = (max_out as f64 * ratio).ceil() as usize + 2 * half + 4;
        let cap = need.next_power_of_two();
        Self {
            ratio,
            half,
            per_sample,
            table,
            hist: [vec![0.0; cap], vec![0.0; cap]],
            mask: cap - 1,
            // The time origin every silent resampler of this ratio shares (`reanchor`).
            written: 2 * half as u64 + 1,
            pos: 0.0,
            max_out,
            zero_run: usize::MAX / 2,
        }
    }

    /// The kernel's half-width `R` in input samples for rates `fs_in` to `fs_out` (Hz): the
    /// latency of a resampler between them, known before it is built. Any thread.
    pub fn half_width(fs_in: f64, fs_out: f64) -> usize {
        let fc = CUTOFF * (fs_out / fs_in).min(1.0);
        (ZERO_CROSSINGS / fc).ceil() as usize
    }

    /// Latency in input (simulation) samples: output sample `j` is the input signal at time
    /// `j / fs_out + half / fs_in`, so the engine simulates `half` steps ahead and an event
    /// is heard `half / fs_in` after it is applied.
    pub fn latency_input(&self) -> usize {
        self.half
    }

    /// Largest output block.
    pub fn max_out(&self) -> usize {
        self.max_out
    }

    /// Input samples per output sample.
    pub fn ratio(&self) -> f64 {
        self.ratio
    }

    /// Largest number of input samples [`Self::input_needed`] can ask for (size of the
    /// engine's simulation scratch).
    pub fn max_input(&self) -> usize {
        (self.max_out as f64 * self.ratio).ceil() as usize + 2 * self.half + 2
    }

    /// Clears the history (silence) and puts the time origin where [`Self::reanchor`] puts
    /// it: a new or reset resampler and one that has been silent play the next sound alike,
    /// with the steady state's latency (an origin of no pushed inputs would put a sound's
    /// first `half` input samples left of the first output's kernel centre, cutting them from
    /// the attack). No allocation.
    pub fn reset(&mut self) {
        for h in &mut self.hist {
            h.fill(0.0);
        }
        self.written = 2 * self.half as u64 + 1;
        self.pos = 0.0;
        self.zero_run = usize::MAX / 2;
    }

    /// At silence ([`Self::is_silent`]), moves the time origin to the one every silent
    /// resampler of this ratio shares: history cleared, the next output's kernel at input 0,
    /// its `2 half + 1` inputs already pushed (zeros), so the next pushed input is heard
    /// `half + 1` inputs after the next output sample, as in the steady state (within one
    /// input sample: the fractional phase `pos` had accumulated is dropped). Two engines that
    /// have both been silent then resample the next sound bit for bit alike, whatever they
    /// played before. No effect (returns `false`) unless silent. Audio thread, O(history).
    pub fn reanchor(&mut self) -> bool {
        if !self.is_silent() {
            return false;
        }
        let anchored = 2 * self.half as u64 + 1;
        if self.pos == 0.0 && self.written == anchored {
            return true;
        }
        for h in &mut self.hist {
            h.fill(0.0);
        }
        self.pos = 0.0;
        self.written = anchored;
        self.zero_run = usize::MAX / 2;
        true
    }

    /// Whether every input sample the next output can read is zero (then the output is
    /// zero and [`Self::advance_silent`] may replace `push` + `produce`).
    pub fn is_silent(&self) -> bool {
        self.zero_run > 2 * self.half + 1
    }

    /// Advances as `push` of `n_in` zeros followed by `produce` of `n_out` samples would
    /// (the caller writes the zero outputs), in O(n_in) without the kernel sums.
    pub fn advance_silent(&mut self, n_out: usize, n_in: usize) {
        for _ in 0..n_in {
            let i = (self.written as usize) & self.mask;
            self.hist[0][i] = 0.0;
            self.hist[1][i] = 0.0;
            self.written += 1;
        }
        self.zero_run = self.zero_run.saturating_add(n_in);
        self.pos += n_out as f64 * self.ratio;
    }

    /// How many input samples must be pushed before `produce` can write `n` outputs.
    pub fn input_needed(&self, n: usize) -> usize {
        if n == 0 {
            return 0;
        }
        // Output j reads inputs up to floor(t_j) + 2 half with t_j the kernel's left edge.
        let last = self.pos + (n - 1) as f64 * self.ratio;
        let need = last.floor() as u64 + 2 * self.half as u64 + 1;
        need.saturating_sub(self.written) as usize
    }

    /// Appends input samples (left, right; equal lengths, at most the capacity left by the
    /// history). No allocation.
    pub fn push(&mut self, left: &[f32], right: &[f32]) {
        debug_assert_eq!(left.len(), right.len());
        for (&l, &r) in left.iter().zip(right) {
            let i = (self.written as usize) & self.mask;
            self.hist[0][i] = l;
            self.hist[1][i] = r;
            self.written += 1;
            if l == 0.0 && r == 0.0 {
                self.zero_run = self.zero_run.saturating_add(1);
            } else {
                self.zero_run = 0;
            }
        }
    }

    /// Writes `left.len()` (= `right.len()` ≤ `max_out`) output samples; the inputs they need
    /// ([`Self::input_needed`]) must have been pushed. No allocation.
    pub fn produce(&mut self, left: &mut [f32], right: &mut [f32]) {
        let two_half = 2 * self.half;
        for (ol, or) in left.iter_mut().zip(right.iter_mut()) {
            // Kernel centre at input time pos + half: inputs i0 ..= i0 + 2 half.
            let base = self.pos.floor();
            let frac = self.pos - base;
            let i0 = base as u64;
            let (mut al, mut ar) = (0.0f32, 0.0f32);
            for m in 0..=two_half {
                // Kernel argument τ - i = frac + half - m with τ = pos + half; table
                // position (τ - i + half) · per_sample.
                let t = (frac + (two_half - m) as f64) * self.per_sample;
                let ti = t as usize;
                if ti + 1 >= self.table.len() {
                    continue;
                }
                let w = (t - ti as f64) as f32;
                let k = self.table[ti] * (1.0 - w) + self.table[ti + 1] * w;
                let idx = (i0 as usize + m) & self.mask;
                al += k * self.hist[0][idx];
                ar += k * self.hist[1][idx];
            }
            *ol = al;
            *or = ar;
            self.pos += self.ratio;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sine well inside the passband comes out at the same frequency and amplitude, delayed
    /// by the stated latency: error below 2e-4 of the amplitude (the f32 table and its linear
    /// interpolation, about 1e-4 at 256 points per zero crossing, plus the Kaiser passband
    /// ripple), for up- and downsampling and odd block sizes.
    #[test]
    fn sine_through_resampler() {
        for (fs_in, fs_out, f) in [
            (32_000.0, 48_000.0, 1000.0),
            (96_000.0, 44_100.0, 3000.0),
            (16_000.0, 192_000.0, 2500.0),
        ] {
            let mut rs = Resampler::new(fs_in, fs_out, 64);
            // The first pushed input follows the 2 half + 1 zeros of the time origin.
            let lat = -(rs.latency_input() as f64 + 1.0) / fs_in;
            let mut n_in = 0usize;
            let mut worst: f64 = 0.0;
            let (mut inl, mut inr) = (vec![0.0f32; rs.max_input()], vec![0.0f32; rs.max_input()]);
            let mut j = 0usize;
            for block in (1..=64).cycle().take(400) {
                let need = rs.input_needed(block);
                for i in 0..need {
                    let t = (n_in + i) as f64 / fs_in;
                    inl[i] = (std::f64::consts::TAU * f * t).sin() as f32;
                    inr[i] = -inl[i];
                }
                n_in += need;
                rs.push(&inl[..need], &inr[..need]);
                let (mut ol, mut or) = (vec![0.0f32; block], vec![0.0f32; block]);
                rs.produce(&mut ol, &mut or);
                for k in 0..block {
                    let t = (j + k) as f64 / fs_out + lat;
                    if t > 0.005 {
                        let want = (std::f64::consts::TAU * f * t).sin();
                        worst = worst
                            .max((ol[k] as f64 - want).abs())
                            .max((or[k] as f64 + want).abs());
                    }
                }
                j += block;
            }
            assert!(worst < 2e-4, "{fs_in} -> {fs_out}: {worst}");
        }
    }
}
