//! Exact angular integrals of products of three trigonometric functions on `[0, 2π]`, used
//! by the coupling tensors of axisymmetric geometries (selection rules of the circular plate:
//! Touzé, Thomas & Chaigne, JSV 258(4), 2002, §3; Thomas, Touzé & Chaigne, IJSS 2005).
//!
//! Each factor is written with exponentials, `cos nθ = (e^{inθ} + e^{-inθ})/2`,
//! `sin nθ = (e^{inθ} - e^{-inθ})/(2i)`; the integral keeps the sign choices with
//! `s₁n₁ + s₂n₂ + s₃n₃ = 0`, each weighing `2π/8` times a sign. The result is an exact multiple
//! of `π/4` and is exactly `0.0` when the selection rule fails (no angular order matches, or an
//! odd number of sine factors). Pure functions; run on the build worker thread.

/// Angular dependence of one mode: `cos(nθ)` or `sin(nθ)`.
///
/// Plain data, any thread.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Parity {
    /// `cos(nθ)` (the only one for `n = 0`).
    Cos,
    /// `sin(nθ)` (only for `n ≥ 1`).
    Sin,
}

/// `∫_0^{2π} a(θ) b(θ) c(θ) dθ` for `a = {cos|sin}(n_a θ)` etc. Exact (multiples of π/4).
pub fn triple(a: (u32, Parity), b: (u32, Parity), c: (u32, Parity)) -> f64 {
    let f = [a, b, c];
    let n_sin = f.iter().filter(|t| t.1 == Parity::Sin).count();
    if n_sin % 2 == 1 {
        return 0.0; // odd in θ → -θ
    }
    let mut acc = 0i64;
    for mask in 0..8u32 {
        let mut total = 0i64;
        let mut sign = 1i64;
        for (k, &(n, p)) in f.iter().enumerate() {
            let s = if mask & (1 << k) != 0 { -1i64 } else { 1 };
            total += s * n as i64;
            if p == Parity::Sin {
                sign *= s;
            }
        }
        if total == 0 {
            // (1/i)^2 = -1 for two sines
            acc += if n_sin == 2 { -sign } else { sign };
        }
    }
    acc as f64 * (2.0 * std::f64::consts::PI / 8.0)
}

/// Angular factors `(T1, T2)` of the polar form of `L` for the triple (l; i, j):
/// `T1 = ∫ a_l a_i a_j dθ`, `T2 = ∫ a_l a_i' a_j' dθ` with `' = d/dθ`
/// (`(cos nθ)' = -n sin nθ`, `(sin nθ)' = n cos nθ`). Both exact.
pub fn factors(l: (u32, Parity), i: (u32, Parity), j: (u32, Parity)) -> (f64, f64) {
    let t1 = triple(l, i, j);
    let t2 = if i.0 == 0 || j.0 == 0 {
        0.0
    } else {
        let d = |t: (u32, Parity)| match t.1 {
            Parity::Cos => (-(t.0 as f64), (t.0, Parity::Sin)),
            Parity::Sin => (t.0 as f64, (t.0, Parity::Cos)),
        };
        let (si, ti) = d(i);
        let (sj, tj) = d(j);
        si * sj * triple(l, ti, tj)
    };
    (t1, t2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use Parity::{Cos, Sin};

    /// Trapezoid rule with 64 points: exact for trigonometric polynomials of degree < 64.
    fn numeric(a: (u32, Parity), b: (u32, Parity), c: (u32, Parity)) -> f64 {
        let m = 64;
        let ev = |t: (u32, Parity), th: f64| match t.1 {
            Cos => (t.0 as f64 * th).cos(),
            Sin => (t.0 as f64 * th).sin(),
        };
        (0..m)
            .map(|k| {
                let th = 2.0 * std::f64::consts::PI * k as f64 / m as f64;
                ev(a, th) * ev(b, th) * ev(c, th)
            })
            .sum::<f64>()
            * 2.0
            * std::f64::consts::PI
            / m as f64
    }

    #[test]
    fn matches_trapezoid_and_selection_rule() {
        // Tolerance 1e-13: the trapezoid sum of 64 terms has rounding ~1e-15; the exact
        // formula's zeros must be exactly 0.0 whenever the selection rule fails.
        for na in 0..6u32 {
            for nb in 0..6u32 {
                for nc in 0..12u32 {
                    for pa in [Cos, Sin] {
                        for pb in [Cos, Sin] {
                            for pc in [Cos, Sin] {
                                let (a, b, c) = ((na, pa), (nb, pb), (nc, pc));
                                let e = triple(a, b, c);
                                let x = numeric(a, b, c);
                                assert!((e - x).abs() < 1e-13, "{a:?} {b:?} {c:?}: {e} {x}");
                                let rule = nc == na + nb || nc + na == nb || nc + nb == na;
                                if !rule {
                                    assert_eq!(e, 0.0);
                                }
                            }
                        }
                    }
                }
            }
        }
        assert_eq!(
            triple((0, Cos), (0, Cos), (0, Cos)),
            2.0 * std::f64::consts::PI
        );
    }
}
