//! The `f64` kernels of the block layout (`tensor/blocks.rs`, default storage): the register
//! kernel of blocks with up to 16 columns, and the dot products (with and without an axpy) of
//! wider ones and of the η sums.
//!
//! Threads: audio thread (called from the layout's kernels), allocation-free.

/// One block with `4 C` (padded) columns: `v_R += M x_C` and, off the diagonal
/// (`diag = false`), `v_C += Mᵀ x_R`, with `x_C` and the column sums held in `C` 4-lane
/// registers (no store-to-load chain through `v_C` from row to row). Rows of `m` are padded with
/// zeros to `4 C`, so the padded lanes read `x` past the class (times 0) and add exact zeros
/// to `v` past it: `x`, `v` must extend `4 C - nc` entries beyond `c0 + nc` (the scratch
/// padding of `PAD`).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn regs<const C: usize, const FMA: bool>(
    m: &[f64],
    x: &[f64],
    v: &mut [f64],
    r0: usize,
    nr: usize,
    c0: usize,
    diag: bool,
) {
    let mut xc = [[0.0f64; 4]; C];
    for (c, xs) in xc.iter_mut().enumerate() {
        xs.copy_from_slice(&x[c0 + 4 * c..c0 + 4 * c + 4]);
    }
    let mut acc = [[0.0f64; 4]; C];
    let rows = m.chunks_exact(4 * C).zip(&x[r0..r0 + nr]);
    for ((row, &s), o) in rows.zip(&mut v[r0..r0 + nr]) {
        let mut d = [0.0f64; 4];
        for c in 0..C {
            for k in 0..4 {
                let a = row[4 * c + k];
                d[k] = madd::<FMA>(a, xc[c][k], d[k]);
                acc[c][k] = madd::<FMA>(s, a, acc[c][k]);
            }
        }
        *o += (d[0] + d[1]) + (d[2] + d[3]);
    }
    if !diag {
        for (c, a) in acc.iter().enumerate() {
            for (o, &y) in v[c0 + 4 * c..c0 + 4 * c + 4].iter_mut().zip(a) {
                *o += y;
            }
        }
    }
}

/// Two disjoint sub-slices `x[a..a+na]` and `x[b..b+nb]` (`a + na ≤ b` or `b + nb ≤ a`).
#[inline(always)]
pub(super) fn two_mut(
    x: &mut [f64],
    a: usize,
    na: usize,
    b: usize,
    nb: usize,
) -> (&mut [f64], &mut [f64]) {
    if a < b {
        let (lo, hi) = x.split_at_mut(b);
        (&mut lo[a..a + na], &mut hi[..nb])
    } else {
        let (lo, hi) = x.split_at_mut(a);
        (&mut hi[..na], &mut lo[b..b + nb])
    }
}

/// `a b + c`, fused (one rounding) when `FMA` (only instantiated where the CPU has FMA).
#[inline(always)]
pub(super) fn madd<const FMA: bool>(a: f64, b: f64, c: f64) -> f64 {
    if FMA {
        a.mul_add(b, c)
    } else {
        a * b + c
    }
}

/// `Σ_k m_k x_k` with four independent sums (equal lengths). The `FMA` instantiation (run
/// only on CPUs with AVX2 and FMA) evaluates the same operations in the same order with AVX2
/// intrinsics ([`dot_avx2`]): bit-identical, without the lane shuffles the compiler emitted.
#[inline(always)]
pub(super) fn dot<const FMA: bool>(m: &[f64], x: &[f64]) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if FMA {
        // SAFETY: FMA instantiations run only on CPUs with AVX2 and FMA, inside the layout's
        // `avx2,fma` entry points.
        return unsafe { dot_avx2(m, x) };
    }
    dot_portable::<FMA>(m, x)
}

/// [`dot`]'s four lanes in one AVX2 register: lane `k` sums the elements `≡ k (mod 4)` with
/// fused multiply-adds, the tail (last `len mod 4`) in order, then
/// `(acc₀ + acc₁) + (acc₂ + acc₃) + tail`, exactly as [`dot_portable`].
///
/// # Safety
///
/// The CPU must have AVX2 and FMA and the caller be compiled with both enabled.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn dot_avx2(m: &[f64], x: &[f64]) -> f64 {
    use std::arch::x86_64::*;
    let n = m.len().min(x.len());
    let body = n - n % 4;
    let mut tail = 0.0;
    for k in body..n {
        tail = m[k].mul_add(x[k], tail);
    }
    let mut acc = _mm256_setzero_pd();
    let (mp, xp) = (m.as_ptr(), x.as_ptr());
    for k in (0..body).step_by(4) {
        // SAFETY: k + 4 <= body <= both lengths.
        acc = _mm256_fmadd_pd(_mm256_loadu_pd(mp.add(k)), _mm256_loadu_pd(xp.add(k)), acc);
    }
    let mut a = [0.0f64; 4];
    _mm256_storeu_pd(a.as_mut_ptr(), acc);
    (a[0] + a[1]) + (a[2] + a[3]) + tail
}

/// The portable [`dot`].
#[inline(always)]
pub(super) fn dot_portable<const FMA: bool>(m: &[f64], x: &[f64]) -> f64 {
    let mut acc = [0.0f64; 4];
    let (mc, xc) = (m.chunks_exact(4), x.chunks_exact(4));
    let mut tail = 0.0;
    for (a, b) in mc.remainder().iter().zip(xc.remainder()) {
        tail = madd::<FMA>(*a, *b, tail);
    }
    for (a, b) in mc.zip(xc) {
        acc[0] = madd::<FMA>(a[0], b[0], acc[0]);
        acc[1] = madd::<FMA>(a[1], b[1], acc[1]);
        acc[2] = madd::<FMA>(a[2], b[2], acc[2]);
        acc[3] = madd::<FMA>(a[3], b[3], acc[3]);
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// Returns `Σ_k m_k x_k` and does `y_k += s m_k`, one pass over `m` (equal lengths).
#[inline(always)]
pub(super) fn dot_axpy<const FMA: bool>(m: &[f64], x: &[f64], y: &mut [f64], s: f64) -> f64 {
    let mut acc = [0.0f64; 4];
    let (mc, xc, mut yc) = (m.chunks_exact(4), x.chunks_exact(4), y.chunks_exact_mut(4));
    let (mr, xr) = (mc.remainder(), xc.remainder());
    for ((a, b), c) in mc.zip(xc).zip(&mut yc) {
        acc[0] = madd::<FMA>(a[0], b[0], acc[0]);
        acc[1] = madd::<FMA>(a[1], b[1], acc[1]);
        acc[2] = madd::<FMA>(a[2], b[2], acc[2]);
        acc[3] = madd::<FMA>(a[3], b[3], acc[3]);
        c[0] = madd::<FMA>(s, a[0], c[0]);
        c[1] = madd::<FMA>(s, a[1], c[1]);
        c[2] = madd::<FMA>(s, a[2], c[2]);
        c[3] = madd::<FMA>(s, a[3], c[3]);
    }
    let mut tail = 0.0;
    for ((a, b), c) in mr.iter().zip(xr).zip(yc.into_remainder()) {
        tail = madd::<FMA>(*a, *b, tail);
        *c = madd::<FMA>(s, *a, *c);
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}
