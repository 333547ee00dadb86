//! A bank's mix of its voices' bands above the simulation ([`crate::models::plate::extension`]),
//! at the host rate, delayed by the bank resampler's latency so that it sounds with the
//! simulated band it continues.
//!
//! Threads: built on the worker thread with its bank; used on the audio thread without
//! allocation.

/// The chunk's sum of the voices' bands above and the delay line after it.
pub(crate) struct AboveMix {
    /// The chunk's sum, left and right (host rate, one chunk).
    sum: [Vec<f32>; 2],
    /// The delay line, left and right (`delay` samples each) and its position.
    ring: [Vec<f32>; 2],
    pos: usize,
}

impl AboveMix {
    /// A silent mix of chunks of at most `chunk` host samples, delayed by `delay`. Worker
    /// thread; allocates.
    pub fn new(delay: usize, chunk: usize) -> Self {
        Self {
            sum: [vec![0.0; chunk], vec![0.0; chunk]],
            ring: [vec![0.0; delay], vec![0.0; delay]],
            pos: 0,
        }
    }

    /// Starts a chunk of `n` samples (at most the chunk size).
    pub fn clear(&mut self, n: usize) {
        for s in &mut self.sum {
            s[..n].fill(0.0);
        }
    }

    /// Adds a voice's band above (`x`, left and right) at gains `(gl, gr)`.
    pub fn add(&mut self, (gl, gr): (f32, f32), x: [&[f32]; 2]) {
        for (s, (g, x)) in self.sum.iter_mut().zip([(gl, x[0]), (gr, x[1])]) {
            for (s, &x) in s.iter_mut().zip(x) {
                *s += g * x;
            }
        }
    }

    /// Whether the delay line holds only zeros (nothing left to sound).
    pub fn is_silent(&self) -> bool {
        self.ring.iter().all(|r| r.iter().all(|&x| x == 0.0))
    }

    /// Adds the chunk's sum, delayed, into `left` and `right` (`n` samples, as cleared).
    pub fn mix_into(&mut self, left: &mut [f32], right: &mut [f32]) {
        let d = self.ring[0].len();
        let n = left.len().min(right.len()).min(self.sum[0].len());
        if d == 0 {
            for (o, s) in left.iter_mut().zip(&self.sum[0][..n]) {
                *o += s;
            }
            for (o, s) in right.iter_mut().zip(&self.sum[1][..n]) {
                *o += s;
            }
            return;
        }
        for k in 0..n {
            let p = self.pos;
            for (c, o) in [&mut left[k], &mut right[k]].into_iter().enumerate() {
                *o += self.ring[c][p];
                self.ring[c][p] = self.sum[c][k];
            }
            self.pos = (p + 1) % d;
        }
    }

    /// Empties the delay line. No allocation.
    pub fn reset(&mut self) {
        for r in &mut self.ring {
            r.fill(0.0);
        }
        self.pos = 0;
    }
}
