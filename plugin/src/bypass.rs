//! The host's bypass (CLAP's and VST3's bypass flag on the `bypass` parameter): the output
//! fades to silence over [`FADE`] and back, so switching never clicks. The engine keeps
//! running underneath (notes start and end as the host sends them), so un-bypassing resumes
//! the instrument as it is; the plugin's latency does not change (silence needs none).
//!
//! Threads: audio thread (the gain state); `set_rate` on the main thread in `activate`.

/// Stable key of the bypass parameter.
pub const BYPASS_KEY: &str = "bypass";

/// Keys of the parameters the plugin adds to the engine's table (kept by state repair).
pub const PLUGIN_ONLY_KEYS: [&str; 1] = [BYPASS_KEY];

/// Fade time of a bypass switch (s).
pub const FADE: f64 = 0.010;

/// The bypass gain ramp (audio thread; no allocation).
#[derive(Debug, Clone)]
pub struct BypassFade {
    /// Current gain, 1 (playing) to 0 (bypassed).
    gain: f32,
    /// Gain change per sample, `1 / (FADE · rate)`.
    step: f32,
}

impl Default for BypassFade {
    fn default() -> Self {
        let mut f = Self {
            gain: 1.0,
            step: 1.0,
        };
        f.set_rate(48_000.0);
        f
    }
}

impl BypassFade {
    /// Sets the host rate (Hz, positive; main thread, at activation).
    pub fn set_rate(&mut self, rate: f64) {
        self.step = (1.0 / (FADE * rate).max(1.0)) as f32;
    }

    /// Jumps to the state `bypassed` without a fade (reset: nothing is sounding).
    pub fn reset(&mut self, bypassed: bool) {
        self.gain = if bypassed { 0.0 } else { 1.0 };
    }

    /// Applies the ramp toward `bypassed` to a stereo block (equal lengths). At unity and not
    /// bypassed it touches nothing; fully bypassed it writes exact zeros.
    pub fn apply(&mut self, bypassed: bool, left: &mut [f32], right: &mut [f32]) {
        let target = if bypassed { 0.0 } else { 1.0 };
        if self.gain == target {
            if bypassed {
                left.fill(0.0);
                right.fill(0.0);
            }
            return;
        }
        for (l, r) in left.iter_mut().zip(right.iter_mut()) {
            self.gain = if bypassed {
                (self.gain - self.step).max(0.0)
            } else {
                (self.gain + self.step).min(1.0)
            };
            *l *= self.gain;
            *r *= self.gain;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bypassing fades a full-scale signal to exact zeros within the fade (10 ms at 48 kHz:
    /// 480 samples), each step at most `1/480` of full scale (no click); un-bypassing returns to
    /// the signal bit for bit after the fade.
    #[test]
    fn fades_out_to_exact_silence_and_back_without_steps() {
        let mut f = BypassFade::default();
        f.set_rate(48_000.0);
        let n = 1000;
        let (mut l, mut r) = (vec![1.0f32; n], vec![-1.0f32; n]);
        f.apply(true, &mut l, &mut r);
        assert!(l[..480]
            .windows(2)
            .all(|w| (w[0] - w[1]).abs() <= 1.0 / 480.0 + 1e-6));
        assert!(l[480..].iter().chain(&r[480..]).all(|&x| x == 0.0));
        let (mut l, mut r) = (vec![0.5f32; n], vec![0.5f32; n]);
        f.apply(true, &mut l, &mut r);
        assert!(
            l.iter().chain(&r).all(|&x| x == 0.0),
            "bypassed: exact zeros"
        );
        let (mut l, mut r) = (vec![0.5f32; n], vec![0.5f32; n]);
        f.apply(false, &mut l, &mut r);
        assert!(l[480..].iter().all(|&x| x == 0.5), "back to the signal");
        assert!(l[0] < 0.01, "fades in from silence: {}", l[0]);
        // At any rate, even 1 Hz, the ramp is finite and ends.
        f.set_rate(1.0);
        let (mut l, mut r) = (vec![1.0f32; 2], vec![1.0f32; 2]);
        f.apply(true, &mut l, &mut r);
        assert_eq!(l, [0.0, 0.0]);
    }
}
