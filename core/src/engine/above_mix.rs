//! A bank's mix of its voices' bands above the simulation ([`crate::models::plate::extension`]):
//! the bands run at the bank's "above rate", the host rate up to [`ABOVE_MAX_RATE`] and an
//! integer fraction of it beyond (44.1 or 48 kHz: the band above ends at 20 kHz, so a higher
//! rate would only multiply its cost), are summed, resampled to the host rate when the rates
//! differ, and delayed so that the band sounds with the simulated band it continues (whose own
//! resampler has its latency).
//!
//! Threads: built on the worker thread with its bank; used on the audio thread without
//! allocation.

use super::resample::Resampler;

/// The highest rate a band above runs at (Hz): hosts above it get it at `host / k`, `k` the
/// smallest integer that brings it under (96 kHz → 48, 88.2 → 44.1, 192 → 48).
pub const ABOVE_MAX_RATE: f64 = 48_000.0;

/// The rate (Hz) a band above runs at for `host_rate` (module doc).
pub fn above_rate(host_rate: f64) -> f64 {
    host_rate / (host_rate / ABOVE_MAX_RATE).ceil().max(1.0)
}

/// The chunk's sum of the voices' bands above, its resampler and the delay line after it.
pub(crate) struct AboveMix {
    /// The chunk's sum, left and right (above rate, `max_in` samples), and its length.
    sum: [Vec<f32>; 2],
    len: usize,
    /// Above rate → host rate, when they differ.
    resampler: Option<Resampler>,
    /// The resampled chunk (host rate, one chunk).
    host: [Vec<f32>; 2],
    /// The delay line, left and right (host rate) and its position.
    ring: [Vec<f32>; 2],
    pos: usize,
}

impl AboveMix {
    /// A silent mix for chunks of at most `chunk` host samples at `host_rate` (Hz), the bands
    /// running at [`above_rate`], delayed to total `latency` host samples (the simulated
    /// band's). Worker thread; allocates.
    pub fn new(host_rate: f64, chunk: usize, latency: usize) -> Self {
        let rate = above_rate(host_rate);
        let resampler = (rate != host_rate).then(|| Resampler::new(rate, host_rate, chunk));
        let (max_in, own) = match &resampler {
            Some(r) => (
                r.max_input(),
                (r.latency_input() as f64 * host_rate / rate).round() as usize,
            ),
            None => (chunk, 0),
        };
        let delay = latency.saturating_sub(own);
        Self {
            sum: [vec![0.0; max_in], vec![0.0; max_in]],
            len: 0,
            resampler,
            host: [vec![0.0; chunk], vec![0.0; chunk]],
            ring: [vec![0.0; delay], vec![0.0; delay]],
            pos: 0,
        }
    }

    /// Band-above samples the voices run for `n` host samples. No allocation.
    pub fn input_needed(&self, n: usize) -> usize {
        self.resampler.as_ref().map_or(n, |r| r.input_needed(n))
    }

    /// The most band-above samples a chunk needs (the lanes' buffers).
    pub fn max_input(&self) -> usize {
        self.sum[0].len()
    }

    /// Starts a chunk of `n` band-above samples ([`Self::input_needed`]).
    pub fn clear(&mut self, n: usize) {
        self.len = n.min(self.sum[0].len());
        for s in &mut self.sum {
            s[..self.len].fill(0.0);
        }
    }

    /// Adds a voice's band above (`x`, left and right) at gains `(gl, gr)`.
    pub fn add(&mut self, (gl, gr): (f32, f32), x: [&[f32]; 2]) {
        for (s, (g, x)) in self.sum.iter_mut().zip([(gl, x[0]), (gr, x[1])]) {
            for (s, &x) in s[..self.len].iter_mut().zip(x) {
                *s += g * x;
            }
        }
    }

    /// Whether nothing is left to sound (the resampler reads only zeros, the delay line holds
    /// only zeros).
    pub fn is_silent(&self) -> bool {
        self.resampler.as_ref().is_none_or(|r| r.is_silent())
            && self.ring.iter().all(|r| r.iter().all(|&x| x == 0.0))
    }

    /// Adds the chunk's sum, resampled and delayed, into `left` and `right` (the chunk's host
    /// samples, at most one chunk).
    pub fn mix_into(&mut self, left: &mut [f32], right: &mut [f32]) {
        let n = left.len().min(right.len()).min(self.host[0].len());
        let [hl, hr] = &mut self.host;
        match &mut self.resampler {
            Some(r) => {
                r.push(&self.sum[0][..self.len], &self.sum[1][..self.len]);
                r.produce(&mut hl[..n], &mut hr[..n]);
            }
            None => {
                let m = n.min(self.len);
                hl[..m].copy_from_slice(&self.sum[0][..m]);
                hr[..m].copy_from_slice(&self.sum[1][..m]);
                hl[m..n].fill(0.0);
                hr[m..n].fill(0.0);
            }
        }
        let d = self.ring[0].len();
        for k in 0..n {
            let x = [self.host[0][k], self.host[1][k]];
            let out = [&mut left[k], &mut right[k]];
            if d == 0 {
                for (o, x) in out.into_iter().zip(x) {
                    *o += x;
                }
                continue;
            }
            let p = self.pos;
            for (c, o) in out.into_iter().enumerate() {
                *o += self.ring[c][p];
                self.ring[c][p] = x[c];
            }
            self.pos = (p + 1) % d;
        }
    }

    /// Empties the resampler and the delay line (a new engine's state). No allocation.
    pub fn reset(&mut self) {
        if let Some(r) = &mut self.resampler {
            r.reset();
        }
        for r in &mut self.ring {
            r.fill(0.0);
        }
        self.pos = 0;
    }

    /// At rest (silent), puts the resampler back at a new engine's time origin
    /// ([`Resampler::reanchor`]) and the delay line at its start. No allocation.
    pub fn reanchor(&mut self) {
        if self.is_silent() {
            if let Some(r) = &mut self.resampler {
                r.reanchor();
            }
            self.pos = 0;
        }
    }
}
