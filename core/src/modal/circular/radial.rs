//! Eigenproblems of the circular Kirchhoff plate in dimensionless form (radius 1,
//! `D = ρh = 1`): `ΔΔΦ = λ⁴ Φ` with `ω = λ²`, and the in-plane (Airy) problem
//! `ΔΔΨ = ζ⁴ Ψ`. Separated solutions `R(r)·{cos nθ, sin nθ}` with
//! `R(r) = J_n(λr) + c · I_n(λr)/I_n(λ)` (Leissa, "Vibration of Plates", NASA SP-160, 1969, §2.1).
//!
//! Edge conditions at `r = 1`:
//! - clamped (`R = R' = 0`): `J_n(λ) I_n'(λ) - J_n'(λ) I_n(λ) = 0` (Leissa eq. 2.9), `c = -J_n(λ)`;
//!   the in-plane functions Ψ of a plate whose edge is free of in-plane stress solve the same
//!   problem (`Ψ = ∂Ψ/∂r = 0`, SEED "Facts"; Ducceschi & Touzé, JSV 344, 2015, §2);
//! - free (zero radial moment `M_r` and Kirchhoff shear `V_r`): with `x = λ`,
//!   `P_J = x² J_n + (1-ν)(x J_n' - n² J_n)`, `P_I = x² I_n - (1-ν)(x I_n' - n² I_n)`,
//!   `Q_J = x³ J_n' + (1-ν) n² (x J_n' - J_n)`, `Q_I = x³ I_n' - (1-ν) n² (x I_n' - I_n)`,
//!   characteristic equation `P_J Q_I - P_I Q_J = 0` (Leissa eq. 2.14; Touzé, Thomas & Chaigne,
//!   JSV 258(4), 2002, eq. 7). For `R = J_n(λr) + C I_n(λr)` the edge moment is
//!   `M_r ∝ R'' + ν(R' - n²R) = -P_J + C P_I` (and `V_r ∝ -Q_J + C Q_I`), so
//!   `c = C I_n(λ) = P_J I_n(λ)/P_I`.
//!
//! Everything here runs on the worker thread that builds a basis, except
//! [`RadialFunction::eval`] which is allocation-free and may run on any thread.

use super::bessel::{bessel_i_scaled, bessel_j};

/// Edge condition of the transverse problem of a circular plate.
///
/// Plain data, shared by every thread.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CircularEdge {
    /// Free edge (`M_r = V_r = 0`); its three rigid-body modes are excluded from every basis.
    Free,
    /// Clamped edge (`w = ∂w/∂r = 0`).
    Clamped,
}

impl CircularEdge {
    /// Short lowercase name (`"free"` or `"clamped"`), used in cache file names.
    pub fn name(self) -> &'static str {
        match self {
            CircularEdge::Free => "free",
            CircularEdge::Clamped => "clamped",
        }
    }
}

/// Characteristic function at `x = λ > 0` for order `n`, together with a magnitude scale:
/// returns `(f, s)` where the root condition is `f = 0` and `|f|/s` is the relative residual
/// (`s` is the sum of the magnitudes of the two products whose difference is `f`). The
/// `I_n` terms are scaled by `e^{-x}`, which multiplies `f` by a positive factor only.
pub fn characteristic(edge: CircularEdge, nu: f64, n: u32, x: f64) -> (f64, f64) {
    let (j, dj) = bessel_j(n, x);
    let (i, di) = bessel_i_scaled(n, x);
    match edge {
        CircularEdge::Clamped => {
            let (a, b) = (j * di, dj * i);
            (a - b, a.abs() + b.abs())
        }
        CircularEdge::Free => {
            let (pj, pi, qj, qi) = free_rows(nu, n, x, j, dj, i, di);
            let (a, b) = (pj * qi, pi * qj);
            (a - b, a.abs() + b.abs())
        }
    }
}

/// The four entries `(P_J, P_I, Q_J, Q_I)` of the free-edge boundary matrix (see module docs),
/// each divided by `x²` (P row) or `x³` (Q row) to stay of order one.
fn free_rows(nu: f64, n: u32, x: f64, j: f64, dj: f64, i: f64, di: f64) -> (f64, f64, f64, f64) {
    let n2 = (n as f64) * (n as f64);
    let m = 1.0 - nu;
    let x2 = x * x;
    let x3 = x2 * x;
    let pj = (x2 * j + m * (x * dj - n2 * j)) / x2;
    let pi = (x2 * i - m * (x * di - n2 * i)) / x2;
    let qj = (x3 * dj + m * n2 * (x * dj - j)) / x3;
    let qi = (x3 * di - m * n2 * (x * di - i)) / x3;
    (pj, pi, qj, qi)
}

/// Step of the sign-change scan of the characteristic equation (consecutive roots of one order
/// are at least about 2.5 apart, so the scan cannot step over a pair).
const SCAN_STEP: f64 = 0.05;

/// A resumable scan for the roots `λ` of the characteristic equation of order `n`, increasing,
/// to full double precision (bisection to a bracket of relative width 2⁻⁵² after a sign-change
/// scan with step [`SCAN_STEP`]). The scan starts at `max(1, 0.5 n)`: every elastic root is
/// above it (the lowest, free (2,0), is λ ≈ 2.3; roots of order n exceed about 0.99 n), and
/// the free plate's rigid-body roots at λ = 0 are thereby excluded.
///
/// The grid `lo + k · step` (accumulated step by step) is the same however far each call
/// scans, so the roots found below any `λ` and their values do not depend on the calls before:
/// a scan can be kept and continued (`modes.rs` keeps them for the process). Worker thread.
#[derive(Debug, Clone)]
pub struct RootScan {
    edge: CircularEdge,
    nu: f64,
    n: u32,
    /// The scan's next grid point and the characteristic there.
    a: f64,
    fa: f64,
    /// The roots found so far, increasing.
    roots: Vec<f64>,
}

impl RootScan {
    /// A scan of order `n` that has not started.
    pub fn new(edge: CircularEdge, nu: f64, n: u32) -> Self {
        let lo = (0.5 * n as f64).max(1.0);
        Self {
            edge,
            nu,
            n,
            a: lo,
            fa: characteristic(edge, nu, n, lo).0,
            roots: Vec::new(),
        }
    }

    /// Scans on until the grid passes `hi`: every root below `hi` is then in [`Self::roots`]
    /// (and perhaps one just above it).
    pub fn scan_to(&mut self, hi: f64) {
        let (edge, nu, n) = (self.edge, self.nu, self.n);
        while self.a < hi {
            let b = self.a + SCAN_STEP;
            let fb = characteristic(edge, nu, n, b).0;
            if self.fa == 0.0 {
                self.roots.push(self.a);
            } else if self.fa.signum() != fb.signum() && fb != 0.0 {
                self.roots.push(bisect(edge, nu, n, self.a, b, self.fa));
            }
            self.a = b;
            self.fa = fb;
        }
    }

    /// The roots found so far, increasing.
    pub fn roots(&self) -> &[f64] {
        &self.roots
    }
}

/// All roots `λ` of the characteristic equation of order `n` below `hi`, increasing (a
/// [`RootScan`] to `hi`). Worker thread; allocates.
pub fn roots(edge: CircularEdge, nu: f64, n: u32, hi: f64) -> Vec<f64> {
    let mut scan = RootScan::new(edge, nu, n);
    scan.scan_to(hi);
    scan.roots.retain(|&r| r < hi);
    scan.roots
}

/// Bisection on a sign-changing bracket `[a, b]` down to adjacent floating-point numbers.
fn bisect(edge: CircularEdge, nu: f64, n: u32, mut a: f64, mut b: f64, mut fa: f64) -> f64 {
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        if m <= a || m >= b {
            break;
        }
        let fm = characteristic(edge, nu, n, m).0;
        if fm == 0.0 {
            return m;
        }
        if fm.signum() == fa.signum() {
            a = m;
            fa = fm;
        } else {
            b = m;
        }
    }
    0.5 * (a + b)
}

/// One normalised radial profile `R(r) = N · (J_n(λr) + c · I_n(λr)/I_n(λ))` on `0 ≤ r ≤ 1`,
/// with `N` chosen so that `∫_0^1 R² r dr · ∫_0^{2π} cos²(nθ) dθ = 1`, i.e. the full mode
/// `R(r) cos nθ` (or `sin nθ`) has unit `L²` norm on the unit disc (area π).
///
/// Built on the worker thread; [`RadialFunction::eval`] is allocation-free (any thread).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RadialFunction {
    /// Angular order `n` (number of nodal diameters).
    pub n: u32,
    /// Eigenvalue `λ` (dimensionless wavenumber; the pulsation is `λ²` in units
    /// `√(D/ρh)/a²`).
    pub lambda: f64,
    /// Coefficient `c` of `I_n(λr)/I_n(λ)` (dimensionless).
    pub c: f64,
    /// Normalisation factor `N` (dimensionless, > 0).
    pub norm: f64,
}

impl RadialFunction {
    /// Builds the normalised profile of the root `lambda` of order `n` for the given edge.
    pub fn new(edge: CircularEdge, nu: f64, n: u32, lambda: f64) -> Self {
        let x = lambda;
        let (j, dj) = bessel_j(n, x);
        let (i, di) = bessel_i_scaled(n, x);
        let c = match edge {
            CircularEdge::Clamped => -j,
            CircularEdge::Free => {
                let (pj, pi, qj, qi) = free_rows(nu, n, x, j, dj, i, di);
                // Use the better-conditioned row (larger I coefficient relative to the row).
                if pi.abs() / (pj.abs() + pi.abs()) >= qi.abs() / (qj.abs() + qi.abs()) {
                    pj * i / pi
                } else {
                    qj * i / qi
                }
            }
        };
        // Lommel integrals (Watson 1944, §5.11; checked against mpmath):
        // ∫ J² r = ½[J'² + (1 - n²/x²) J²], ∫ I² r = ½[(1 + n²/x²) I² - I'²],
        // ∫ J I r = (J I' - J' I)/(2x), all at r = 1, with I terms divided by I_n(x).
        let n2x2 = (n as f64 * n as f64) / (x * x);
        let rho = di / i; // I_n'/I_n
        let jj = 0.5 * (dj * dj + (1.0 - n2x2) * j * j);
        let ii = 0.5 * ((1.0 + n2x2) - rho * rho);
        let ji = (j * rho - dj) / (2.0 * x);
        let radial = jj + 2.0 * c * ji + c * c * ii;
        let angular = if n == 0 {
            2.0 * std::f64::consts::PI
        } else {
            std::f64::consts::PI
        };
        Self {
            n,
            lambda,
            c,
            norm: 1.0 / (radial * angular).sqrt(),
        }
    }

    /// `(R(r), R'(r), R''(r))` at `0 ≤ r ≤ 1` (derivatives with respect to `r`).
    /// Allocation-free; second derivative from Bessel's equation.
    pub fn eval(&self, r: f64) -> [f64; 3] {
        let lam = self.lambda;
        let x = lam * r;
        let nf = self.n as f64;
        let (j, dj) = bessel_j(self.n, x);
        let (i, di) = bessel_i_scaled(self.n, x);
        let (i1, _) = bessel_i_scaled(self.n, lam);
        // I_n(λr)/I_n(λ) = e^{λ(r-1)} Î_n(λr)/Î_n(λ)
        let g = self.c * (lam * (r - 1.0)).exp() / i1;
        let (d2j, d2i) = if x > 0.0 {
            (
                -dj / x - (1.0 - nf * nf / (x * x)) * j,
                -di / x + (1.0 + nf * nf / (x * x)) * i,
            )
        } else {
            // limits at the centre: J_0''(0) = -1/2, I_0''(0) = 1/2, J_2''(0) = I_2''(0) = 1/4,
            // zero for every other order
            match self.n {
                0 => (-0.5, 0.5),
                2 => (0.25, 0.25),
                _ => (0.0, 0.0),
            }
        };
        let r0 = j + g * i;
        let r1 = lam * (dj + g * di);
        let r2 = lam * lam * (d2j + g * d2i);
        [self.norm * r0, self.norm * r1, self.norm * r2]
    }
}
