//! Sums over the modes that do not wait on each other: the `O(N_Φ)` reductions of a plate step
//! (divergence check, pickups, power, energy, the SAV rank-one solve).
//!
//! A loop `acc += f(s)` with one accumulator chains every addition on the previous one (about
//! four cycles each), and the compiler may not reorder floating-point sums, so it neither
//! vectorises nor overlaps them: over 1000 modes each such loop costs about 1.5 µs, a fifth of a
//! full-band gong's step besides its coupling kernel. [`lane_sums`] keeps [`LANES`] partial
//! sums (independent chains the compiler can put in SIMD registers) and adds them in a fixed
//! tree, so a run gives the same bits every time; only the rounding differs from the
//! one-accumulator order (relative `O(ε log N_Φ)`).
//!
//! Threads: pure functions, any thread; no allocation.

/// Interleaved partial sums per reduction.
pub(crate) const LANES: usize = 8;

/// `[Σ_{s<n} f(s)_k]_k` for `K` reductions at once, over [`LANES`] interleaved partial sums
/// added in a fixed tree, then the remainder `n mod LANES` in order. `f` is called once per
/// `s`, in increasing `s` (it may write per-mode outputs).
#[inline(always)]
pub(crate) fn lane_sums<const K: usize>(
    n: usize,
    mut f: impl FnMut(usize) -> [f64; K],
) -> [f64; K] {
    // acc[j][k]: lane j of reduction k.
    let mut acc = [[0.0; K]; LANES];
    let full = n - n % LANES;
    let mut s = 0;
    while s < full {
        for (j, lane) in acc.iter_mut().enumerate() {
            for (a, v) in lane.iter_mut().zip(f(s + j)) {
                *a += v;
            }
        }
        s += LANES;
    }
    let mut out = [0.0; K];
    for (k, o) in out.iter_mut().enumerate() {
        let a = |j: usize| acc[j][k];
        *o = ((a(0) + a(4)) + (a(1) + a(5))) + ((a(2) + a(6)) + (a(3) + a(7)));
    }
    for s in full..n {
        for (o, v) in out.iter_mut().zip(f(s)) {
            *o += v;
        }
    }
    out
}

/// `Σ_{s<n} f(s)` ([`lane_sums`] with one reduction).
#[inline(always)]
pub(crate) fn lane_sum(n: usize, mut f: impl FnMut(usize) -> f64) -> f64 {
    lane_sums::<1>(n, |s| [f(s)])[0]
}

/// Whether every entry of `x` is finite: `Σ 0·x_s` is `0` for finite entries and NaN as soon
/// as one is infinite or NaN (`0·∞` is NaN), one vectorisable pass without branches.
#[inline]
pub(crate) fn all_finite(x: &[f64]) -> bool {
    lane_sum(x.len(), |s| 0.0 * x[s]) == 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Integer-valued terms are summed exactly in any order, so every length (full lanes and
    /// remainders) must give the exact total.
    #[test]
    fn sums_match_the_exact_total_for_every_length() {
        for n in 0..40usize {
            let [a, b] = lane_sums::<2>(n, |s| [s as f64, (s * s) as f64]);
            let exact_a = (0..n).sum::<usize>() as f64;
            let exact_b = (0..n).map(|s| s * s).sum::<usize>() as f64;
            assert_eq!((a, b), (exact_a, exact_b), "n = {n}");
            assert_eq!(lane_sum(n, |s| s as f64), exact_a);
        }
    }

    /// `f` sees each index once, in order (callers write per-mode outputs from it).
    #[test]
    fn visits_each_index_once_in_order() {
        let mut seen = Vec::new();
        lane_sum(21, |s| {
            seen.push(s);
            0.0
        });
        assert_eq!(seen, (0..21).collect::<Vec<_>>());
    }

    /// Round-off of a real sum stays within the bound of a pairwise-like order:
    /// `|error| ≤ (N/LANES + 3) ε Σ|x|` (a generous bound; the one-accumulator order's is `N ε Σ|x|`).
    #[test]
    fn rounding_is_within_the_sum_bound() {
        let x: Vec<f64> = (0..1015)
            .map(|s| ((s as f64) * 0.37).sin() / (1.0 + s as f64))
            .collect();
        let exact: f64 = {
            // Kahan-compensated reference.
            let (mut sum, mut c) = (0.0f64, 0.0f64);
            for &v in &x {
                let y = v - c;
                let t = sum + y;
                c = (t - sum) - y;
                sum = t;
            }
            sum
        };
        let abs: f64 = x.iter().map(|v| v.abs()).sum();
        let got = lane_sum(x.len(), |s| x[s]);
        let bound = (x.len() as f64 / LANES as f64 + 3.0) * f64::EPSILON * abs;
        assert!(
            (got - exact).abs() <= bound,
            "{got} vs {exact}, bound {bound}"
        );
    }

    /// Any infinite or NaN entry is caught, wherever it sits; finite vectors pass.
    #[test]
    fn all_finite_catches_every_position() {
        let mut x = vec![1.0e300; 19];
        assert!(all_finite(&x));
        for bad in [f64::INFINITY, f64::NEG_INFINITY, f64::NAN] {
            for s in 0..x.len() {
                let keep = x[s];
                x[s] = bad;
                assert!(!all_finite(&x), "{bad} at {s}");
                x[s] = keep;
            }
        }
        assert!(all_finite(&[]));
    }
}
