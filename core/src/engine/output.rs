//! The engine's output stage at the host rate, after the output gain: a low cut that removes
//! sub-audio motion, a transparent look-ahead peak limiter, and a last guard that no host can
//! receive a sample above 0 dBFS or a non-finite one.
//!
//! - **Low cut**: a second-order Butterworth high-pass at the `low_cut` parameter (default
//!   20 Hz), from the bilinear transform with frequency prewarping (RBJ "Audio EQ Cookbook",
//!   high-pass with `Q = 1/√2`), direct form I in f64. Plates' pickups read velocity, which
//!   carries the strike's slow rigid-like motion of the lowest modes; the filter keeps it off
//!   the speakers.
//! - **Limiter** (the `limiter` parameter, on by default): stereo-linked, look-ahead
//!   `L` = 1.5 ms. The gain each frame needs, `r = min(1, c / max(|l|, |r|))` with the ceiling
//!   `c` = -0.3 dBFS, goes through a sliding minimum over `L + 1` frames, an exponential release
//!   (100 ms time constant) that may only lower it, and a moving average over `L` frames; the
//!   result multiplies the input delayed by `L`. Every sample of the window that meets a peak
//!   is at most that peak's `r`, so the averaged gain is too: the limited output never passes
//!   the ceiling, and its gain moves in ramps of at least `L` (no clicks, no distortion of
//!   signals under the ceiling, which pass unchanged). The approach is the one of
//!   G. Sherwood / Signalsmith Audio ("Designing a look-ahead limiter", 2022).
//! - **Guard**: a non-finite sample becomes 0 and every sample is bounded to ±1 (0 dBFS),
//!   limiter on or off. With the limiter on the bound never acts; with it off it is a hard
//!   clip. Voices themselves are silenced when their output passes
//!   [`super::VOICE_CEILING`] or is not finite (see [`super::voice`]).
//!
//! The look-ahead delay stays in the path when the limiter is off, so the plugin's latency
//! does not depend on a parameter. Buffers are allocated in [`OutputStage::new`] (main
//! thread, at activation); [`OutputStage::process`] never allocates (audio thread).

/// Look-ahead of the limiter (s).
pub const LOOKAHEAD: f64 = 0.0015;
/// Longest look-ahead in samples (see [`OutputStage::new`]).
const MAX_LOOKAHEAD_SAMPLES: usize = 1 << 16;
/// Limiter ceiling (full scale): -0.3 dBFS.
pub const CEILING: f32 = 0.966_050_9;
/// Level under which the low cut's decaying tail after silent input is set to 0 (-200 dBFS).
const SILENT: f64 = 1e-10;
/// Release time constant of the limiter's gain (s).
const RELEASE: f64 = 0.1;

/// Second-order Butterworth high-pass, direct form I, one state per channel.
#[derive(Debug, Clone)]
struct LowCut {
    b: [f64; 3],
    a: [f64; 2],
    /// Per channel: x[n-1], x[n-2], y[n-1], y[n-2].
    z: [[f64; 4]; 2],
    cutoff: f32,
}

impl LowCut {
    fn new() -> Self {
        Self {
            b: [1.0, 0.0, 0.0],
            a: [0.0, 0.0],
            z: [[0.0; 4]; 2],
            cutoff: f32::NAN,
        }
    }

    /// Sets the cutoff (Hz) at host rate `fs`: RBJ cookbook high-pass, `Q = 1/√2`. Cutoffs at
    /// or above 0.45 `fs` are held at 0.45 `fs` (the filter's prewarping needs `f < fs/2`).
    fn tune(&mut self, cutoff: f32, fs: f64) {
        if cutoff == self.cutoff {
            return;
        }
        self.cutoff = cutoff;
        let f = (cutoff as f64).min(0.45 * fs);
        let w0 = std::f64::consts::TAU * f / fs;
        let (s, c) = w0.sin_cos();
        let alpha = s / (2.0 * std::f64::consts::FRAC_1_SQRT_2);
        let a0 = 1.0 + alpha;
        self.b = [(1.0 + c) / 2.0 / a0, -(1.0 + c) / a0, (1.0 + c) / 2.0 / a0];
        self.a = [-2.0 * c / a0, (1.0 - alpha) / a0];
    }

    fn run(&mut self, ch: usize, x: f64) -> f64 {
        let z = &mut self.z[ch];
        let y = self.b[0] * x + self.b[1] * z[0] + self.b[2] * z[1]
            - self.a[0] * z[2]
            - self.a[1] * z[3];
        if x == 0.0 && z[0] == 0.0 && z[1] == 0.0 && y.abs() < SILENT && z[2].abs() < SILENT {
            // The tail after silent input is 200 dB down: end it, so silence in gives exact
            // zeros out (and no denormals).
            *z = [0.0; 4];
            return 0.0;
        }
        *z = [x, z[0], y, z[2]];
        y
    }
}

/// The output stage (see the module doc). Built at activation for one host rate.
#[derive(Debug, Clone)]
pub struct OutputStage {
    fs: f64,
    low_cut: LowCut,
    /// Look-ahead in frames (`L`, at least 1).
    lookahead: usize,
    /// Delayed input, one ring per channel, `L` frames.
    delay: [Vec<f32>; 2],
    /// Needed gains of the last `L + 1` frames (ring), for the sliding minimum.
    needed: Vec<f32>,
    /// Sliding-minimum deque over `needed`: frame indices, their gains increasing.
    deque: Vec<u64>,
    /// Deque head and length (ring over `deque`).
    head: usize,
    len: usize,
    /// Gains after the release, last `L` frames (ring), and their running sum.
    smooth: Vec<f64>,
    sum: f64,
    /// Released gain of the previous frame.
    released: f64,
    /// Per-frame release step factor `1 - exp(-1 / (RELEASE fs))`.
    release_k: f64,
    /// Frames processed.
    frame: u64,
    /// Smallest gain applied since the last [`Self::take_min_gain`] (1: no limiting).
    min_gain: f32,
    /// Samples the guard bounded or zeroed since the start.
    guarded: u64,
}

impl OutputStage {
    /// A stage for host rate `fs` (Hz). Main thread (allocates).
    pub fn new(fs: f64) -> Self {
        // At most 2^16 samples: above 43.7 MHz the look-ahead shortens (the guard still
        // bounds every sample) rather than allocate without bound.
        let lookahead = ((LOOKAHEAD * fs).round() as usize).clamp(1, MAX_LOOKAHEAD_SAMPLES);
        Self {
            fs,
            low_cut: LowCut::new(),
            lookahead,
            delay: [vec![0.0; lookahead], vec![0.0; lookahead]],
            needed: vec![1.0; lookahead + 1],
            deque: vec![0; lookahead + 1],
            head: 0,
            len: 0,
            smooth: vec![1.0; lookahead],
            sum: lookahead as f64,
            released: 1.0,
            release_k: 1.0 - (-1.0 / (RELEASE * fs)).exp(),
            frame: 0,
            min_gain: 1.0,
            guarded: 0,
        }
    }

    /// The stage's latency in host frames (the limiter's look-ahead, limiter on or off).
    pub fn latency(&self) -> usize {
        self.lookahead
    }

    /// Clears every state (silence in, silence out). Audio thread.
    pub fn reset(&mut self) {
        self.low_cut.z = [[0.0; 4]; 2];
        for d in &mut self.delay {
            d.fill(0.0);
        }
        self.needed.fill(1.0);
        self.head = 0;
        self.len = 0;
        self.smooth.fill(1.0);
        self.sum = self.lookahead as f64;
        self.released = 1.0;
        self.frame = 0;
    }

    /// Whether the stage holds only silence: its look-ahead and low-cut filter state are all
    /// exactly zero (then [`Self::reset`] changes no output sample still to come, only the
    /// limiter's release state, which silence leaves a few ulps from 1). Audio thread,
    /// O(look-ahead).
    pub fn is_at_rest(&self) -> bool {
        self.low_cut.z.iter().flatten().all(|&z| z == 0.0)
            && self.delay.iter().flatten().all(|&x| x == 0.0)
    }

    /// The smallest limiter gain since the last call (1: no limiting), then resets it.
    /// Audio thread (telemetry).
    pub fn take_min_gain(&mut self) -> f32 {
        std::mem::replace(&mut self.min_gain, 1.0)
    }

    /// Samples the guard had to bound or zero since this stage was built (0 with the limiter
    /// on and finite voices). Written by [`Self::process`] (audio thread); the engine's total
    /// over activations is `Engine::guarded_samples`.
    pub fn guarded(&self) -> u64 {
        self.guarded
    }

    /// Runs the stage in place on one block: low cut at `low_cut` Hz, the limiter if
    /// `limit`, the guard. Audio thread; no allocation.
    pub fn process(&mut self, left: &mut [f32], right: &mut [f32], low_cut: f32, limit: bool) {
        self.low_cut.tune(low_cut, self.fs);
        let la = self.lookahead;
        for (l, r) in left.iter_mut().zip(right.iter_mut()) {
            let x = [
                self.low_cut.run(0, f64::from(*l)) as f32,
                self.low_cut.run(1, f64::from(*r)) as f32,
            ];
            // A non-finite input must not poison the filter's state.
            if !(x[0].is_finite() && x[1].is_finite()) {
                self.low_cut.z = [[0.0; 4]; 2];
            }
            let peak = x[0].abs().max(x[1].abs());
            let need = if peak > CEILING { CEILING / peak } else { 1.0 };
            let need = if need.is_finite() { need } else { 0.0 };
            let g = self.gain_for(need);
            let slot = (self.frame % la as u64) as usize;
            let out = [self.delay[0][slot], self.delay[1][slot]];
            self.delay[0][slot] = x[0];
            self.delay[1][slot] = x[1];
            self.frame += 1;
            let g = if limit { g } else { 1.0 };
            self.min_gain = self.min_gain.min(g);
            *l = self.guard(out[0] * g);
            *r = self.guard(out[1] * g);
        }
    }

    /// Pushes this frame's needed gain; returns the smoothed gain for the frame leaving the
    /// delay line now (see the module doc).
    fn gain_for(&mut self, need: f32) -> f32 {
        let cap = self.deque.len();
        let n = self.frame;
        // Sliding minimum over frames n - L ..= n (monotonic deque of frame indices).
        self.needed[(n % cap as u64) as usize] = need;
        while self.len > 0 {
            let back = self.deque[(self.head + self.len - 1) % cap];
            if self.needed[(back % cap as u64) as usize] >= need {
                self.len -= 1;
            } else {
                break;
            }
        }
        self.deque[(self.head + self.len) % cap] = n;
        self.len += 1;
        if self.deque[self.head] + (self.lookahead as u64) < n {
            self.head = (self.head + 1) % cap;
            self.len -= 1;
        }
        let min = f64::from(self.needed[(self.deque[self.head] % cap as u64) as usize]);
        // Release: rise towards 1 at most exponentially, never above the minimum.
        let rel = (self.released + (1.0 - self.released) * self.release_k).min(min);
        self.released = rel;
        // Moving average over the last L released gains. The running sum is recomputed
        // every L frames (O(1) a frame): its rounding drift, about ε·L a frame, would
        // otherwise grow relative to gains of 1e-6 and under (inputs of 1e6 and over).
        let slot = (n % self.lookahead as u64) as usize;
        self.sum += rel - self.smooth[slot];
        self.smooth[slot] = rel;
        if slot == 0 {
            self.sum = self.smooth.iter().sum();
        }
        // The frame leaving the delay line now is n - L; every averaged gain is at most its
        // need, so this bound acts only on the average's rounding and makes the ceiling exact
        // (up to the f32 product's rounding).
        let own = if n >= self.lookahead as u64 {
            f64::from(self.needed[((n - self.lookahead as u64) % cap as u64) as usize])
        } else {
            1.0
        };
        (self.sum / self.lookahead as f64).clamp(0.0, own.min(1.0)) as f32
    }

    fn guard(&mut self, x: f32) -> f32 {
        if x.is_finite() && x.abs() <= 1.0 {
            x
        } else {
            self.guarded += 1;
            if x.is_finite() {
                x.clamp(-1.0, 1.0)
            } else {
                0.0
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(stage: &mut OutputStage, l: &mut [f32], r: &mut [f32], limit: bool) {
        // Odd block sizes: the stage must not depend on them.
        let mut pos = 0;
        for (k, n) in [1usize, 7, 64, 333].iter().cycle().enumerate() {
            if pos >= l.len() || k > 1_000_000 {
                break;
            }
            let end = (pos + n).min(l.len());
            stage.process(&mut l[pos..end], &mut r[pos..end], 10.0, limit);
            pos = end;
        }
    }

    /// A signal under the ceiling passes unchanged except for the delay and the low cut:
    /// a 1 kHz sine at -6 dBFS through a 10 Hz low cut comes out as the input delayed by the
    /// look-ahead, within 1e-2: the filter's phase at 1 kHz, √2 · 10 / 1000 = 0.014 rad, moves a
    /// 0.5 sine by at most 7e-3 and its gain differs from 1 by 1e-4; a limiter acting would
    /// lower the level by more (and `take_min_gain` would be under 1).
    #[test]
    fn quiet_signals_pass() {
        let fs = 48_000.0;
        let mut s = OutputStage::new(fs);
        let n = 48_000;
        let x: Vec<f32> = (0..n)
            .map(|i| 0.5 * (std::f64::consts::TAU * 1000.0 * i as f64 / fs).sin() as f32)
            .collect();
        let (mut l, mut r) = (x.clone(), x.clone());
        run(&mut s, &mut l, &mut r, true);
        let d = s.latency();
        assert_eq!(d, 72);
        let err = (24_000..n)
            .map(|i| (l[i] - x[i - d]).abs())
            .fold(0.0, f32::max);
        assert!(err < 1e-2, "error {err}");
        assert_eq!(s.take_min_gain(), 1.0);
    }

    /// Bursts up to +40 dBFS and non-finite samples at every host rate: with the limiter the
    /// output never passes the ceiling (before the guard: `guarded` stays 0 for finite
    /// input); without it the guard bounds it to 0 dBFS; NaN and infinities become finite.
    #[test]
    fn the_output_never_passes_full_scale() {
        for fs in [8_000.0, 44_100.0, 384_000.0] {
            let n = (fs * 0.5) as usize;
            let x: Vec<f32> = (0..n)
                .map(|i| {
                    let t = i as f64 / fs;
                    let level = if (t * 10.0) as usize % 2 == 1 {
                        100.0
                    } else {
                        0.3
                    };
                    (level * (std::f64::consts::TAU * 440.0 * t).sin()) as f32
                })
                .collect();
            let mut s = OutputStage::new(fs);
            let (mut l, mut r) = (x.clone(), x.clone());
            run(&mut s, &mut l, &mut r, true);
            let peak = l.iter().chain(&r).fold(0.0f32, |m, v| m.max(v.abs()));
            assert!(peak <= CEILING * 1.000_001, "{fs}: peak {peak}");
            assert!(peak > 0.9 * CEILING, "{fs}: over-limited, peak {peak}");
            assert_eq!(s.guarded(), 0);
            assert!(s.take_min_gain() < 0.02);
            let mut s = OutputStage::new(fs);
            let (mut l, mut r) = (x.clone(), x);
            l[100] = f32::NAN;
            r[200] = f32::INFINITY;
            run(&mut s, &mut l, &mut r, false);
            assert!(l.iter().chain(&r).all(|v| v.is_finite() && v.abs() <= 1.0));
            assert!(s.guarded() > 0);
        }
    }

    /// The ceiling holds over a huge range with the limiter toggled block by block: random
    /// blocks of 1 to 64 frames at 192 kHz, half of them white noise up to 1e8 (a voice near
    /// its ceiling times +60 dB of gain), half up to 1, the limiter on in a random half and
    /// the low cut moved each block. Every block with the limiter on peaks at most at the
    /// ceiling (times 1 + 1e-6: `f32` rounding of the gain product, about 16 ulps). Before
    /// the average's sum was recomputed and bounded, its drift let such blocks reach the
    /// guard's clip at 1.0.
    #[test]
    fn the_ceiling_holds_over_a_huge_range_with_the_limiter_toggled() {
        let mut s = OutputStage::new(192_000.0);
        let mut seed = 12345u64;
        let mut rnd = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut l, mut r) = (vec![0.0f32; 64], vec![0.0f32; 64]);
        for b in 0..100_000 {
            let n = 1 + (rnd() * 64.0) as usize;
            let amp = if rnd() < 0.5 { 1e8 * rnd() } else { rnd() };
            for i in 0..n {
                l[i] = (amp * (2.0 * rnd() - 1.0)) as f32;
                r[i] = (amp * (2.0 * rnd() - 1.0)) as f32;
            }
            let limit = rnd() < 0.5;
            let cut = (20.0 + 400.0 * rnd()) as f32;
            let guarded = s.guarded();
            s.process(&mut l[..n], &mut r[..n], cut, limit);
            if limit {
                let p = l[..n]
                    .iter()
                    .chain(&r[..n])
                    .fold(0.0f32, |m, v| m.max(v.abs()));
                assert!(p <= CEILING * 1.000_001, "block {b}: peak {p}");
                assert_eq!(s.guarded(), guarded, "block {b}");
            }
        }
    }

    /// The low cut: -3 dB at its cutoff, -40 dB at a tenth of it (second order: 12 dB per
    /// octave well below the cutoff, so 1/100 at f_c / 10 within a few percent).
    #[test]
    fn low_cut_response() {
        let fs = 48_000.0;
        for (f, want) in [(20.0, std::f64::consts::FRAC_1_SQRT_2), (2.0, 0.01)] {
            let mut s = OutputStage::new(fs);
            let n = (fs * 20.0 / f).max(fs) as usize * 2;
            let mut l: Vec<f32> = (0..n)
                .map(|i| 0.1 * (std::f64::consts::TAU * f * i as f64 / fs).sin() as f32)
                .collect();
            let mut r = l.clone();
            s.process(&mut l, &mut r, 20.0, true);
            let peak = l[n / 2..].iter().fold(0.0f32, |m, v| m.max(v.abs())) as f64 / 0.1;
            assert!(
                (peak / want - 1.0).abs() < 0.03,
                "{f} Hz: gain {peak}, want {want}"
            );
        }
    }
}
