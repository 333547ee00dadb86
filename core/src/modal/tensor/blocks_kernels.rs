//! The three non-fused kernels of the plate schemes on the block layout of
//! `tensor/blocks.rs`: `η_l = qa · H^l qb` ([`BlockLayout::contract_eta`]),
//! `out = Σ_l w_l H^l q` ([`BlockLayout::apply_force`]) and the coupling matrix
//! `G_{s,l} = (H^l q)_s` ([`BlockLayout::coupling_matrix`]). Each row `l` is one block
//! mat-vec `v = H^l x` (the same `row_apply` as the fused SAV kernel, on permuted
//! vectors), followed by a dot product, an axpy, or a write of `v` into column `l` of `G`
//! on the classes row `l` touches (every other `(H^l x)_s` is an exact zero by the selection
//! rule). Vectors are permuted in and out once per call (`O(N_Φ)`).
//!
//! Scratch: `3 N_Φ + 2 PAD` values (`x` and `v` padded for the 4-lane register kernel, plus
//! one `N_Φ` vector), the same as the fused kernel, owned by the caller.
//!
//! Threads: audio thread, allocation-free; AVX2 + FMA instantiation when the CPU has both
//! (detected when the layout was built).

use super::{BlockLayout, PAD};

/// Which of the three kernels a call runs (one body, one `target_feature` wrapper).
enum Op<'a> {
    /// `out[l] = qa · H^l qb` (`qa` is the kernel's first vector argument).
    Eta { qa: &'a [f64], out: &'a mut [f64] },
    /// `out = Σ_l w_l H^l q`.
    Force { w: &'a [f64], out: &'a mut [f64] },
    /// `g[s * N_Ψ + l] = (H^l q)_s`.
    Matrix { g: &'a mut [f64] },
}

impl BlockLayout {
    /// `out[l] = Σ_{ij} H^l_{ij} qa_i qb_j` (length `N_Ψ`, overwritten). Scratch as the module
    /// docs. Audio thread, allocation-free.
    pub(crate) fn contract_eta(&self, qa: &[f64], qb: &[f64], out: &mut [f64], scr: &mut [f64]) {
        self.dispatch(qb, Op::Eta { qa, out }, scr);
    }

    /// `out[s] = Σ_l w_l Σ_k H^l_{s,k} q_k` (length `N_Φ`, overwritten). Audio thread,
    /// allocation-free.
    pub(crate) fn apply_force(&self, q: &[f64], w: &[f64], out: &mut [f64], scr: &mut [f64]) {
        self.dispatch(q, Op::Force { w, out }, scr);
    }

    /// `g[s * N_Ψ + l] = Σ_k H^l_{s,k} q_k` (row-major `N_Φ × N_Ψ`, overwritten). Audio
    /// thread, allocation-free.
    pub(crate) fn coupling_matrix(&self, q: &[f64], g: &mut [f64], scr: &mut [f64]) {
        self.dispatch(q, Op::Matrix { g }, scr);
    }

    /// Runs [`Self::body`] in its AVX2 + FMA instantiation when the CPU has both.
    fn dispatch(&self, x: &[f64], op: Op<'_>, scr: &mut [f64]) {
        #[cfg(target_arch = "x86_64")]
        if self.avx2_fma {
            // SAFETY: `avx2_fma` is set only when the running CPU reports both features.
            unsafe { self.body_avx2(x, op, scr) };
            return;
        }
        self.body::<false>(x, op, scr);
    }

    /// [`Self::body`] compiled for AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn body_avx2(&self, x: &[f64], op: Op<'_>, scr: &mut [f64]) {
        self.body::<true>(x, op, scr);
    }

    /// The kernels: `v = H^l x` per row (permuted), then the operation's use of `v`.
    #[inline(always)]
    fn body<const FMA: bool>(&self, x: &[f64], op: Op<'_>, scr: &mut [f64]) {
        let n = self.n_phi;
        let (xp, rest) = scr.split_at_mut(n + PAD);
        let (v, rest) = rest.split_at_mut(n + PAD);
        let yp = &mut rest[..n];
        for (p, &o) in xp.iter_mut().zip(&self.orig) {
            *p = x[o as usize];
        }
        xp[n..].fill(0.0);
        let n_psi = self.row_blocks.len() - 1;
        match op {
            Op::Eta { qa, out } => {
                for (p, &o) in yp.iter_mut().zip(&self.orig) {
                    *p = qa[o as usize];
                }
                for (l, el) in out.iter_mut().enumerate().take(n_psi) {
                    self.row_apply::<FMA>(l, xp, v);
                    let mut e = 0.0;
                    for &(a, b) in self.touched(l) {
                        let r = a as usize..b as usize;
                        e += super::dot::<FMA>(&yp[r.clone()], &v[r]);
                    }
                    *el = e;
                }
            }
            Op::Force { w, out } => {
                yp.fill(0.0);
                for (l, &wl) in w.iter().enumerate().take(n_psi) {
                    if wl == 0.0 {
                        continue;
                    }
                    self.row_apply::<FMA>(l, xp, v);
                    for &(a, b) in self.touched(l) {
                        let r = a as usize..b as usize;
                        for (y, &z) in yp[r.clone()].iter_mut().zip(&v[r]) {
                            *y = super::madd::<FMA>(wl, z, *y);
                        }
                    }
                }
                for (&y, &o) in yp.iter().zip(&self.orig) {
                    out[o as usize] = y;
                }
            }
            Op::Matrix { g } => {
                g.fill(0.0);
                for l in 0..n_psi {
                    self.row_apply::<FMA>(l, xp, v);
                    for &(a, b) in self.touched(l) {
                        let r = a as usize..b as usize;
                        for (&z, &o) in v[r.clone()].iter().zip(&self.orig[r]) {
                            g[o as usize * n_psi + l] = z;
                        }
                    }
                }
            }
        }
    }
}
