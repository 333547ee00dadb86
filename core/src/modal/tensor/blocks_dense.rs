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
/// padding of `PAD`). The `FMA` instantiation (run only on CPUs with AVX2 and FMA) is
/// [`regs_avx2`], bit-identical to the portable code ([`regs_portable`]).
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
    #[cfg(target_arch = "x86_64")]
    if FMA {
        // SAFETY: FMA instantiations run only on CPUs with AVX2 and FMA, inside the layout's
        // `avx2,fma` entry points.
        unsafe {
            if diag {
                regs_avx2::<C, true>(m, x, v, r0, nr, c0);
            } else {
                regs_avx2::<C, false>(m, x, v, r0, nr, c0);
            }
        }
        return;
    }
    regs_portable::<C, FMA>(m, x, v, r0, nr, c0, diag);
}

/// The portable [`regs`].
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn regs_portable<const C: usize, const FMA: bool>(
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

/// [`regs`]'s `FMA` instantiation in AVX2 intrinsics: [`regs_portable`]'s fused multiply-adds
/// in the same order per lane (`d` the row's four lane sums, `acc[c]` column group `c`), the row sum
/// as `(d₀ + d₁) + (d₂ + d₃)` and the column sums added lane by lane, so the results are
/// bit-identical to the portable code; on diagonal blocks (`DIAG`) the column sums, which
/// [`regs`] computes and drops, are not computed.
///
/// # Safety
///
/// The CPU must have AVX2 and FMA and the caller be compiled with both enabled.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn regs_avx2<const C: usize, const DIAG: bool>(
    m: &[f64],
    x: &[f64],
    v: &mut [f64],
    r0: usize,
    nr: usize,
    c0: usize,
) {
    use std::arch::x86_64::*;
    let n = (r0 + nr).max(c0 + 4 * C);
    assert!(
        m.len() >= 4 * C * nr && x.len() >= n && v.len() >= n,
        "regs: lengths"
    );
    let (mp, xp, vp) = (m.as_ptr(), x.as_ptr(), v.as_mut_ptr());
    let mut xc = [_mm256_setzero_pd(); C];
    for (c, b) in xc.iter_mut().enumerate() {
        // SAFETY: c0 + 4c + 4 <= c0 + 4C <= x.len() (asserted).
        *b = _mm256_loadu_pd(xp.add(c0 + 4 * c));
    }
    let mut acc = [_mm256_setzero_pd(); C];
    for r in 0..nr {
        // SAFETY: r < nr: row r of m and entry r0 + r of x and v are inside (asserted).
        let row = mp.add(4 * C * r);
        let s = _mm256_set1_pd(*xp.add(r0 + r));
        let mut d = _mm256_setzero_pd();
        for c in 0..C {
            let a = _mm256_loadu_pd(row.add(4 * c));
            d = _mm256_fmadd_pd(a, xc[c], d);
            if !DIAG {
                acc[c] = _mm256_fmadd_pd(s, a, acc[c]);
            }
        }
        let pair = _mm_hadd_pd(_mm256_castpd256_pd128(d), _mm256_extractf128_pd::<1>(d));
        *vp.add(r0 + r) += _mm_cvtsd_f64(pair) + _mm_cvtsd_f64(_mm_unpackhi_pd(pair, pair));
    }
    if !DIAG {
        for (c, a) in acc.iter().enumerate() {
            // SAFETY: as for `xc` above, in v.
            let out = vp.add(c0 + 4 * c);
            _mm256_storeu_pd(out, _mm256_add_pd(_mm256_loadu_pd(out), *a));
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

/// Returns `Σ_k m_k x_k` and does `y_k += s m_k`, one pass over `m` (equal lengths). The `FMA`
/// instantiation (run only on CPUs with AVX2 and FMA) is [`dot_axpy_avx2`], bit-identical.
#[inline(always)]
pub(super) fn dot_axpy<const FMA: bool>(m: &[f64], x: &[f64], y: &mut [f64], s: f64) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if FMA {
        // SAFETY: FMA instantiations run only on CPUs with AVX2 and FMA, inside the layout's
        // `avx2,fma` entry points.
        return unsafe { dot_axpy_avx2(m, x, y, s) };
    }
    dot_axpy_portable::<FMA>(m, x, y, s)
}

/// [`dot_axpy`]'s `FMA` instantiation in AVX2 intrinsics: lane `k` of the sum and each `y`
/// update with the same fused multiply-adds as [`dot_axpy_portable`], the tail in order, the
/// same final sum: bit-identical.
///
/// # Safety
///
/// The CPU must have AVX2 and FMA and the caller be compiled with both enabled.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn dot_axpy_avx2(m: &[f64], x: &[f64], y: &mut [f64], s: f64) -> f64 {
    use std::arch::x86_64::*;
    let n = m.len().min(x.len()).min(y.len());
    let body = n - n % 4;
    let (mp, xp, yp) = (m.as_ptr(), x.as_ptr(), y.as_mut_ptr());
    let (mut acc, sv) = (_mm256_setzero_pd(), _mm256_set1_pd(s));
    for k in (0..body).step_by(4) {
        // SAFETY: k + 4 <= body <= every length.
        let a = _mm256_loadu_pd(mp.add(k));
        acc = _mm256_fmadd_pd(a, _mm256_loadu_pd(xp.add(k)), acc);
        let out = yp.add(k);
        _mm256_storeu_pd(out, _mm256_fmadd_pd(sv, a, _mm256_loadu_pd(out)));
    }
    let mut tail = 0.0;
    for k in body..n {
        tail = m[k].mul_add(x[k], tail);
        y[k] = s.mul_add(m[k], y[k]);
    }
    let mut a = [0.0f64; 4];
    _mm256_storeu_pd(a.as_mut_ptr(), acc);
    (a[0] + a[1]) + (a[2] + a[3]) + tail
}

/// The portable [`dot_axpy`].
#[inline(always)]
pub(super) fn dot_axpy_portable<const FMA: bool>(
    m: &[f64],
    x: &[f64],
    y: &mut [f64],
    s: f64,
) -> f64 {
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
