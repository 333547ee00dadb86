//! The single-storage block values of `tensor/blocks.rs`: each dense block `H^l[R, C]` stored
//! in `f32` as *row panels* (four rows of `R` side by side, one column of `C` at a time), with
//! a kernel that widens every value to `f64` and accumulates in `f64`.
//!
//! # Layout
//!
//! A block of `n_r` rows (padded with zero rows to `4 P`, `P = ⌈n_r/4⌉` panels) and `n_c`
//! columns is cut into column chunks of at most [`MAX_CHUNK`] columns ([`chunk`]: widths as
//! equal as possible). Chunk `t` (columns `s_t .. s_t + w_t`) stores, panel after panel, for
//! each of its columns the four values of the panel's rows: value `(i, j)` sits at
//! `4 P s_t + 4 w_t ⌊i/4⌋ + 4 (j - s_t) + i mod 4` from the block's offset. Off-diagonal
//! blocks take the larger class as rows (fewer chunks, more panels per chunk: the per-chunk
//! set-up and column sums are the kernel's overhead on blocks of ~10² values); diagonal
//! blocks (`R = C`) are stored full and symmetric.
//!
//! # Kernel
//!
//! For a panel `p` with rows `r .. r + 4` and a chunk of `W` columns:
//! `v[r .. r+4] += Σ_c M[p, c] x_c` (four lanes, the column values broadcast; no horizontal
//! sum per row) and, off the diagonal, `acc_c += M[p, c] ∘ x[r .. r+4]` (one four-lane
//! accumulator per column, reduced once per block: `v_c += Σ lanes`). Each stored value is
//! loaded once (4 bytes) and used in two multiply-adds, against one load of 8 bytes and the
//! same two multiply-adds plus a four-lane horizontal sum per row in the `f64` layout. Padded
//! rows hold zeros: they read `x` past the class (times 0) and add exact zeros to `v` there, so
//! `x` and `v` extend 3 entries past the last class (the scratch padding `PAD`).
//!
//! Threads: built on a worker thread with the tensor; the kernel runs on the audio thread
//! without allocating.

use super::madd;

/// Widest column chunk: `W` four-lane accumulators, the panel's sum, its `x` rows and the
/// value in flight stay within the 16 vector registers of AVX2 (measured: 8 spills nothing
/// the kernel notices, wider chunks do; see `docs/performance.md`, 2026-11-24).
pub(crate) const MAX_CHUNK: usize = 8;

/// Chunk `t` of a block with `nc` columns: `(first column, width)`, `⌈nc / MAX_CHUNK⌉` chunks
/// of widths differing by at most one.
#[inline(always)]
pub(crate) fn chunk(nc: usize, t: usize) -> (usize, usize) {
    let k = nc.div_ceil(MAX_CHUNK);
    let (base, extra) = (nc / k, nc % k);
    (t * base + t.min(extra), base + usize::from(t < extra))
}

/// Number of chunks of a block with `nc` columns.
#[inline(always)]
pub(crate) fn chunks(nc: usize) -> usize {
    nc.div_ceil(MAX_CHUNK)
}

/// Position of value `(i, j)` (row `i < 4 panels`, column `j < nc`) from the block's offset.
pub(crate) fn index(panels: usize, nc: usize, i: usize, j: usize) -> usize {
    let t = (0..chunks(nc))
        .find(|&t| {
            let (s, w) = chunk(nc, t);
            j < s + w
        })
        .expect("column inside the block");
    let (s, w) = chunk(nc, t);
    4 * panels * s + 4 * w * (i / 4) + 4 * (j - s) + i % 4
}

/// One column chunk of one block, as the kernel runs it: values `off..off + 4 panels w`, rows
/// `r0 .. r0 + 4 panels`, columns `c0 .. c0 + w` (permuted indices). Precomputed at build, so
/// that the kernel's per-chunk work is one descriptor load and a jump (measured: deriving the
/// chunks of each block at run time cost as many instructions as the multiply-adds of the
/// gong's ~10²-value blocks).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Chunk {
    off: u32,
    r0: u32,
    c0: u32,
    panels: u16,
    w: u8,
    diag: bool,
}

/// The single-storage blocks of every row: `f32` values and their column chunks.
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct Panels {
    /// `N_Φ`.
    n_phi: usize,
    /// Length the kernels' `x` and `v` must have at least: `N_Φ` plus the scratch padding.
    padded: usize,
    /// Block values (`H`, rounded to `f32` by the tensor's single storage).
    values: Vec<f32>,
    /// Column chunks of all rows, row after row.
    chunks: Vec<Chunk>,
    /// Row `l` owns chunks `row_chunks[l]..row_chunks[l + 1]`.
    row_chunks: Vec<u32>,
    /// Number of dense blocks (for the layout's statistics).
    blocks: usize,
}

impl Panels {
    /// Heap bytes held (the vectors' capacities). Any thread.
    pub(crate) fn heap_bytes(&self) -> usize {
        use crate::modal::tensor::runs::vec_bytes;
        vec_bytes(&self.values) + vec_bytes(&self.chunks) + vec_bytes(&self.row_chunks)
    }

    /// An empty layout for `n_phi` modes whose kernels get vectors of `n_phi + pad` values
    /// (`pad ≥ 3`: the padded rows of the last class), at the first row.
    pub(crate) fn new(n_phi: usize, pad: usize) -> Self {
        assert!(pad >= 3, "row panels need 3 values of padding");
        Self {
            n_phi,
            padded: n_phi + pad,
            row_chunks: vec![0],
            ..Self::default()
        }
    }

    /// Stored values (zero padding included).
    pub(crate) fn len(&self) -> usize {
        self.values.len()
    }

    /// Number of dense blocks.
    pub(crate) fn blocks(&self) -> usize {
        self.blocks
    }

    /// Appends a block of the current row: rows `r0..r0 + nr`, columns `c0..c0 + nc`
    /// (permuted; `diag` when they are the same class, then pass each `(r, c)` with `r ≥ c`
    /// once), entries `(row, column, value)` relative to `r0`, `c0`. Worker thread.
    pub(crate) fn push_block(
        &mut self,
        (r0, nr): (usize, usize),
        (c0, nc): (usize, usize),
        diag: bool,
        entries: impl Iterator<Item = (usize, usize, f32)>,
    ) {
        let panels = nr.div_ceil(4);
        let off = self.values.len();
        self.values.resize(off + 4 * panels * nc, 0.0);
        let m = &mut self.values[off..];
        for (r, c, x) in entries {
            m[index(panels, nc, r, c)] = x;
            if diag {
                m[index(panels, nc, c, r)] = x;
            }
        }
        assert!(
            self.values.len() <= u32::MAX as usize && panels <= u16::MAX as usize,
            "single-storage block values exceed u32 offsets"
        );
        assert!(r0 + 4 * panels <= self.padded && c0 + nc <= self.n_phi);
        for t in 0..chunks(nc) {
            let (s, w) = chunk(nc, t);
            self.chunks.push(Chunk {
                off: (off + 4 * panels * s) as u32,
                r0: r0 as u32,
                c0: (c0 + s) as u32,
                panels: panels as u16,
                w: w as u8,
                diag,
            });
        }
        self.blocks += 1;
    }

    /// Closes the current row (its blocks are the chunks pushed since the last call).
    pub(crate) fn end_row(&mut self) {
        self.row_chunks.push(self.chunks.len() as u32);
    }

    /// `v_R += M x_C` and, off the diagonal, `v_C += Mᵀ x_R` for every block of row `l`
    /// (permuted vectors `x`, `v` of length at least `N_Φ` + the padding). `FMA = true` is
    /// instantiated only where the CPU has AVX2 and FMA (the layout's dispatch); on x86-64 it
    /// runs [`chunk_avx2`]. Audio thread, allocation-free.
    #[inline(always)]
    pub(crate) fn row_apply<const FMA: bool>(&self, l: usize, x: &[f64], v: &mut [f64]) {
        let n = self.padded;
        assert!(x.len() >= n && v.len() >= n, "panel kernel: vector lengths");
        let chunks = &self.chunks[self.row_chunks[l] as usize..self.row_chunks[l + 1] as usize];
        for ch in chunks {
            let (r0, c0, panels) = (ch.r0 as usize, ch.c0 as usize, usize::from(ch.panels));
            let (off, len) = (ch.off as usize, 4 * panels * usize::from(ch.w));
            let m = &self.values[off..off + len];
            #[cfg(target_arch = "x86_64")]
            macro_rules! go {
                ($w:literal) => {
                    match (FMA, ch.diag) {
                        // SAFETY: FMA instantiations run only on CPUs with AVX2 and FMA, inside
                        // the layout's `avx2,fma` entry points; `push_block` checked
                        // `r0 + 4 panels <= padded` and `c0 + w <= N_Φ`, and `x`, `v` hold
                        // `padded` values (asserted above); `m` holds `4 panels w`.
                        (true, true) => unsafe { chunk_avx2::<$w, true>(m, x, v, r0, panels, c0) },
                        (true, false) => unsafe {
                            chunk_avx2::<$w, false>(m, x, v, r0, panels, c0)
                        },
                        (false, true) => chunk_apply::<$w, FMA, true>(m, x, v, r0, panels, c0),
                        (false, false) => chunk_apply::<$w, FMA, false>(m, x, v, r0, panels, c0),
                    }
                };
            }
            #[cfg(not(target_arch = "x86_64"))]
            macro_rules! go {
                ($w:literal) => {
                    if ch.diag {
                        chunk_apply::<$w, FMA, true>(m, x, v, r0, panels, c0)
                    } else {
                        chunk_apply::<$w, FMA, false>(m, x, v, r0, panels, c0)
                    }
                };
            }
            match ch.w {
                1 => go!(1),
                2 => go!(2),
                3 => go!(3),
                4 => go!(4),
                5 => go!(5),
                6 => go!(6),
                7 => go!(7),
                _ => go!(8),
            }
        }
    }
}

/// One chunk of `W` columns over `panels` row panels (module docs): `m` holds
/// `panels × W × 4` values, rows start at `r0`, columns at `c0` (permuted indices).
/// `DIAG`: a diagonal block (only `v_R += M x_C`, the block being symmetric and full).
#[inline(always)]
fn chunk_apply<const W: usize, const FMA: bool, const DIAG: bool>(
    m: &[f32],
    x: &[f64],
    v: &mut [f64],
    r0: usize,
    panels: usize,
    c0: usize,
) {
    let mut xc = [0.0f64; W];
    xc.copy_from_slice(&x[c0..c0 + W]);
    let mut acc = [[0.0f64; 4]; W];
    let rows = 4 * panels;
    let xr_all = &x[r0..r0 + rows];
    let vr_all = &mut v[r0..r0 + rows];
    for ((panel, xr), vr) in m
        .chunks_exact(4 * W)
        .zip(xr_all.chunks_exact(4))
        .zip(vr_all.chunks_exact_mut(4))
    {
        let mut s = [0.0f64; 4];
        for c in 0..W {
            for k in 0..4 {
                let a = f64::from(panel[4 * c + k]);
                s[k] = madd::<FMA>(a, xc[c], s[k]);
                if !DIAG {
                    acc[c][k] = madd::<FMA>(a, xr[k], acc[c][k]);
                }
            }
        }
        for k in 0..4 {
            vr[k] += s[k];
        }
    }
    if !DIAG {
        for (o, a) in v[c0..c0 + W].iter_mut().zip(&acc) {
            *o += (a[0] + a[1]) + (a[2] + a[3]);
        }
    }
}

/// [`chunk_apply`] with explicit AVX2 + FMA intrinsics (the compiler's vectorisation of the
/// portable version shuffles lanes and spills: measured slower than the `f64` kernel). The
/// column broadcasts and accumulators are `W` registers each. Inlined into the layout's
/// `avx2,fma` entry points (which enable the features for the intrinsics).
///
/// # Safety
///
/// The CPU must have AVX2 and FMA, and the caller must be compiled with both enabled;
/// `m` holds `panels × W × 4` values, `x` and `v` at least `max(r0 + 4 panels, c0 + W)`
/// values (not checked here: [`Panels::push_block`] and [`Panels::row_apply`] check them).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn chunk_avx2<const W: usize, const DIAG: bool>(
    m: &[f32],
    x: &[f64],
    v: &mut [f64],
    r0: usize,
    panels: usize,
    c0: usize,
) {
    use std::arch::x86_64::*;
    debug_assert!(m.len() >= 4 * panels * W);
    debug_assert!(x.len().min(v.len()) >= (r0 + 4 * panels).max(c0 + W));
    let (mp, xp, vp) = (m.as_ptr(), x.as_ptr(), v.as_mut_ptr());
    let mut xc = [_mm256_setzero_pd(); W];
    for (c, b) in xc.iter_mut().enumerate() {
        // SAFETY: c0 + c < c0 + W <= x.len() (the caller's contract).
        *b = _mm256_set1_pd(*xp.add(c0 + c));
    }
    let mut acc = [_mm256_setzero_pd(); W];
    for p in 0..panels {
        // SAFETY: p < panels, so every offset below is inside the caller's bounds.
        let base = mp.add(4 * W * p);
        let xr = _mm256_loadu_pd(xp.add(r0 + 4 * p));
        // Two partial row sums (even and odd columns): half the multiply-add chain per panel
        // (blocks have few panels, so the chain's latency shows).
        let (mut s0, mut s1) = (_mm256_setzero_pd(), _mm256_setzero_pd());
        for c in 0..W {
            let a = _mm256_cvtps_pd(_mm_loadu_ps(base.add(4 * c)));
            if c % 2 == 0 {
                s0 = _mm256_fmadd_pd(a, xc[c], s0);
            } else {
                s1 = _mm256_fmadd_pd(a, xc[c], s1);
            }
            if !DIAG {
                acc[c] = _mm256_fmadd_pd(a, xr, acc[c]);
            }
        }
        let out = vp.add(r0 + 4 * p);
        let s = _mm256_add_pd(s0, s1);
        _mm256_storeu_pd(out, _mm256_add_pd(_mm256_loadu_pd(out), s));
    }
    if !DIAG {
        // Each column's (a₀ + a₁) + (a₂ + a₃), as the portable kernel, four columns at a time:
        // hadd pairs the lanes of two columns, the 128-bit halves then add across.
        let mut c = 0;
        while c + 4 <= W {
            let t0 = _mm256_hadd_pd(acc[c], acc[c + 1]);
            let t1 = _mm256_hadd_pd(acc[c + 2], acc[c + 3]);
            let lo = _mm256_permute2f128_pd::<0x20>(t0, t1);
            let hi = _mm256_permute2f128_pd::<0x31>(t0, t1);
            // SAFETY: c + 4 <= W, inside the caller's bounds.
            let out = vp.add(c0 + c);
            _mm256_storeu_pd(
                out,
                _mm256_add_pd(_mm256_loadu_pd(out), _mm256_add_pd(lo, hi)),
            );
            c += 4;
        }
        while c < W {
            let lo = _mm256_castpd256_pd128(acc[c]);
            let hi = _mm256_extractf128_pd::<1>(acc[c]);
            let pair = _mm_hadd_pd(lo, hi);
            // SAFETY: c < W, inside the caller's bounds.
            *vp.add(c0 + c) += _mm_cvtsd_f64(pair) + _mm_cvtsd_f64(_mm_unpackhi_pd(pair, pair));
            c += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The scratch padding the layout's kernels use.
    const PAD: usize = 4;

    /// Chunks cover `0..nc` in order without gaps, none wider than [`MAX_CHUNK`], widths
    /// within one of each other; [`index`] is a bijection onto `0..4 P nc`.
    #[test]
    fn chunks_tile_the_columns_and_index_is_a_bijection() {
        for nc in 1..40 {
            let mut next = 0;
            let widths: Vec<usize> = (0..chunks(nc)).map(|t| chunk(nc, t).1).collect();
            for t in 0..chunks(nc) {
                let (s, w) = chunk(nc, t);
                assert_eq!(s, next, "nc {nc} chunk {t}");
                assert!((1..=MAX_CHUNK).contains(&w));
                next = s + w;
            }
            assert_eq!(next, nc);
            let (lo, hi) = (widths.iter().min().unwrap(), widths.iter().max().unwrap());
            assert!(hi - lo <= 1, "nc {nc}: {widths:?}");
            let panels = 3;
            let mut seen = vec![false; 4 * panels * nc];
            for i in 0..4 * panels {
                for j in 0..nc {
                    let k = index(panels, nc, i, j);
                    assert!(!seen[k], "nc {nc}: ({i}, {j}) collides");
                    seen[k] = true;
                }
            }
        }
    }

    /// Whether this CPU runs the `FMA` instantiation (AVX2 and FMA on x86-64).
    fn fma_cpu() -> bool {
        #[cfg(target_arch = "x86_64")]
        return is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma");
        #[cfg(not(target_arch = "x86_64"))]
        return true;
    }

    /// One off-diagonal and one diagonal block (one row each) against a dense product, every
    /// chunk width, in both instantiations (exact small-integer arithmetic, compared exactly).
    #[test]
    fn panels_match_dense_products() {
        let h = |i: usize, j: usize| ((i * 3 + j * 7) % 11) as f64 - 5.0;
        for nc in 1..=19 {
            // Rows 0..7 (padded to 8), columns at 8..8 + nc; x, v of length N_Φ + PAD.
            let n = 8 + nc;
            let x: Vec<f64> = (0..n + PAD).map(|s| (s % 5) as f64 - 2.0).collect();
            let mut p = Panels::new(n, PAD);
            let entries = (0..7).flat_map(|i| (0..nc).map(move |j| (i, j, h(i, j) as f32)));
            p.push_block((0, 7), (8, nc), false, entries);
            p.end_row();
            // Diagonal: a symmetric nc × nc block at 0 (each (r, c) with r ≥ c once).
            let hs = |i: usize, j: usize| h(i.max(j), i.min(j));
            let lower = (0..nc).flat_map(|i| (0..=i).map(move |j| (i, j, hs(i, j) as f32)));
            p.push_block((0, nc), (0, nc), true, lower);
            p.end_row();
            assert_eq!(p.blocks(), 2);
            for fma in [false, fma_cpu()] {
                let run = |l: usize| {
                    let mut v = vec![0.0; n + PAD];
                    if fma {
                        p.row_apply::<true>(l, &x, &mut v);
                    } else {
                        p.row_apply::<false>(l, &x, &mut v);
                    }
                    v
                };
                let v = run(0);
                for (i, &got) in v.iter().enumerate().take(7) {
                    let want: f64 = (0..nc).map(|j| h(i, j) * x[8 + j]).sum();
                    assert_eq!(got, want, "nc {nc} row {i}");
                }
                for j in 0..nc {
                    let want: f64 = (0..7).map(|i| h(i, j) * x[i]).sum();
                    assert_eq!(v[8 + j], want, "nc {nc} column {j}");
                }
                assert_eq!(v[7], 0.0, "padded row adds zero");
                let v = run(1);
                for (i, &got) in v.iter().enumerate().take(nc) {
                    let want: f64 = (0..nc).map(|j| hs(i, j) * x[j]).sum();
                    assert_eq!(got, want, "diag nc {nc} row {i}");
                }
            }
        }
    }
}
