//! Bessel functions of integer order: `J_n(x)` and the exponentially scaled `e^{-x} I_n(x)`,
//! with first derivatives, for `x ≥ 0`.
//!
//! Method: Miller's backward recurrence (J. C. P. Miller, 1952; see Abramowitz & Stegun 1964,
//! §9.12 ex. 1 and §9.12 ex. 2, and W. Gautschi, "Computational aspects of three-term recurrence
//! relations", SIAM Review 9, 1967). The minimal solution of the three-term recurrence is run
//! downwards from an order `m` far above both `n` and `x` and normalised with the Neumann sums
//! `1 = J_0 + 2 Σ_{k≥1} J_{2k}` and `e^x = I_0 + 2 Σ_{k≥1} I_k` (A&S 9.1.46 and 9.6.37).
//! Both sums have no catastrophic cancellation, so the result has a small *absolute* error for
//! `J_n` (about 1e-16 times `max|J|`) and a small *relative* error for `I_n`, for every order and
//! argument the plate modes need (n up to a few hundred, x up to a few hundred). The
//! starting order is chosen so that the neglected tail is below 1e-17 (see [`start_order`]);
//! accuracy is checked against 30-digit mpmath values in this module's tests.
//!
//! These functions never allocate: they run on whichever thread calls them (build worker
//! threads, and [`crate::modal::PlateModes::phi_at`] on any thread).

/// Rescaling threshold for the backward recurrence (values are divided by this when exceeded).
const BIG: f64 = 1e250;

/// Starting order of the backward recurrence for order `n` and argument `x`: above
/// `max(n, x)` by a margin `25 + 13 x^{1/3}` (from the Debye/transition-region decay
/// `J_m(x) ~ exp(-(2√2/3)(m-x)^{3/2}/√x)`, which is below 1e-17 there), and by at least
/// `2√(40 x)` for the `I_n` Neumann sum whose terms decay like `exp(-k²/2x)`.
fn start_order(n: u32, x: f64) -> u32 {
    let big = (n as f64).max(x);
    let m = big + 25.0 + 13.0 * x.cbrt() + 2.0 * (40.0 * x).sqrt();
    let m = m.ceil() as u32;
    m + (m % 2) // even, so the J Neumann sum ends on an even order
}

/// Values `J_{n-1}(x), J_n(x), J_{n+1}(x)` by Miller's algorithm (`x > 0`), with
/// `J_{-1} = -J_1`.
fn j_triplet(n: u32, x: f64) -> (f64, f64, f64) {
    let m = start_order(n + 1, x);
    let (mut fp, mut f) = (0.0_f64, 1e-30_f64); // f_{k+1}, f_k with k = m
    let (mut jm, mut j0, mut jp) = (0.0, 0.0, 0.0);
    let mut sum = 0.0; // J_0 + 2 Σ J_{2k} of the unnormalised sequence
    let mut k = m;
    loop {
        if k == n + 1 {
            jp = f;
        } else if k == n {
            j0 = f;
        } else if n >= 1 && k == n - 1 {
            jm = f;
        }
        if k == 0 {
            sum += f;
            break;
        }
        if k % 2 == 0 {
            sum += 2.0 * f;
        }
        let fm = (2.0 * k as f64 / x) * f - fp;
        fp = f;
        f = fm;
        k -= 1;
        if f.abs() > BIG {
            let s = 1.0 / BIG;
            f *= s;
            fp *= s;
            sum *= s;
            jm *= s;
            j0 *= s;
            jp *= s;
        }
    }
    if n == 0 {
        // J_{-1} = -J_1
        jm = -jp;
    }
    (jm / sum, j0 / sum, jp / sum)
}

/// Values `Î_{n-1}, Î_n, Î_{n+1}` with `Î_k(x) = e^{-x} I_k(x)` by Miller's algorithm
/// (`x > 0`), with `I_{-1} = I_1`.
fn i_triplet_scaled(n: u32, x: f64) -> (f64, f64, f64) {
    let m = start_order(n + 1, x);
    let (mut fp, mut f) = (0.0_f64, 1e-30_f64);
    let (mut im, mut i0, mut ip) = (0.0, 0.0, 0.0);
    let mut sum = 0.0; // I_0 + 2 Σ I_k of the unnormalised sequence
    let mut k = m;
    loop {
        if k == n + 1 {
            ip = f;
        } else if k == n {
            i0 = f;
        } else if n >= 1 && k == n - 1 {
            im = f;
        }
        if k == 0 {
            sum += f;
            break;
        }
        sum += 2.0 * f;
        let fm = (2.0 * k as f64 / x) * f + fp;
        fp = f;
        f = fm;
        k -= 1;
        if f.abs() > BIG {
            let s = 1.0 / BIG;
            f *= s;
            fp *= s;
            sum *= s;
            im *= s;
            i0 *= s;
            ip *= s;
        }
    }
    if n == 0 {
        im = ip;
    }
    (im / sum, i0 / sum, ip / sum)
}

/// Leading term of the power series, used for tiny arguments where the recurrence would
/// overflow in one step: `(x/2)^n / n!` (exact to double precision for `x < 1e-20`).
fn tiny_series(n: u32, x: f64) -> f64 {
    let mut v = 1.0;
    for k in 1..=n {
        v *= 0.5 * x / k as f64;
    }
    v
}

/// `(J_n(x), J_n'(x))` for `x ≥ 0` (dimensionless). Absolute error about 1e-16 relative to
/// `max_x |J_n|`; no allocation.
pub fn bessel_j(n: u32, x: f64) -> (f64, f64) {
    debug_assert!(x >= 0.0 && x.is_finite());
    if x < 1e-20 {
        let v = tiny_series(n, x);
        let d = if n == 0 {
            -0.5 * x
        } else {
            0.5 * tiny_series(n - 1, x)
        };
        return (v, d);
    }
    let (jm, j, jp) = j_triplet(n, x);
    (j, 0.5 * (jm - jp))
}

/// `(e^{-x} I_n(x), e^{-x} I_n'(x))` for `x ≥ 0` (dimensionless). Relative error about
/// 1e-15; no allocation.
pub fn bessel_i_scaled(n: u32, x: f64) -> (f64, f64) {
    debug_assert!(x >= 0.0 && x.is_finite());
    if x < 1e-20 {
        let v = tiny_series(n, x);
        let d = if n == 0 {
            0.5 * x
        } else {
            0.5 * tiny_series(n - 1, x)
        };
        return (v, d);
    }
    let (im, i, ip) = i_triplet_scaled(n, x);
    (i, 0.5 * (im + ip))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reference values from mpmath 1.3.0 at 30 digits (`besselj(n,x)`, `besseli(n,x)*exp(-x)`
    /// and their derivatives via `besselj(n,x,1)`), rounded to the nearest double (Python `repr(float(..))`).
    /// Columns: n, x, J_n, J_n', e^-x I_n, e^-x I_n'.
    const REF: &[(u32, f64, f64, f64, f64, f64)] = &include!("bessel_ref.in");

    #[test]
    fn matches_mpmath_reference_values() {
        // Tolerance: J has absolute accuracy ~1e-16 · max|J| (values near a zero are small),
        // so we check |err| <= 5e-15 · max(|ref|, typical magnitude sqrt(2/(πx))); I is
        // positive and checked relatively to 1e-14 (recurrence over a few hundred steps
        // accumulates a few hundred ulps at worst). Measured: about 1e-15 for both.
        let (mut worst_j, mut worst_i) = (0.0f64, 0.0f64);
        for &(n, x, j, dj, i, di) in REF {
            let (gj, gdj) = bessel_j(n, x);
            let (gi, gdi) = bessel_i_scaled(n, x);
            let scale = (2.0 / (std::f64::consts::PI * x.max(1.0)))
                .sqrt()
                .max(j.abs());
            worst_j = worst_j.max((gj - j).abs().max((gdj - dj).abs()) / scale.max(dj.abs()));
            worst_i = worst_i.max(((gi - i) / i).abs().max(((gdi - di) / di).abs()));
            assert!((gj - j).abs() <= 5e-15 * scale, "J_{n}({x}): {gj} vs {j}");
            let dscale = scale.max(dj.abs());
            assert!(
                (gdj - dj).abs() <= 5e-15 * dscale,
                "J'_{n}({x}): {gdj} vs {dj}"
            );
            assert!((gi - i).abs() <= 1e-14 * i.abs(), "I_{n}({x}): {gi} vs {i}");
            assert!(
                (gdi - di).abs() <= 1e-14 * di.abs(),
                "I'_{n}({x}): {gdi} vs {di}"
            );
        }
        eprintln!("Bessel vs mpmath: J scaled abs err {worst_j:e}, I rel err {worst_i:e}");
    }
}
