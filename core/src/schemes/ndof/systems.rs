//! Test systems implementing [`HamiltonianSystem`], and [`SystemSpec`], their serde
//! description, with the [`build_system`] factory.
//!
//! All systems use unit masses and are separable, `H = ½|p|² + V(q)`, so Störmer-Verlet applies
//! to each of them. The systems are immutable parameter holders: any thread may evaluate them,
//! the integrators call them from the thread that steps.

use serde::{Deserialize, Serialize};

use super::HamiltonianSystem;
use crate::error::{check_non_negative, check_positive, ParamError};

/// Largest number of masses a chain may have (bounds memory: the dense Jacobian has
/// `(2n)²` entries).
pub const MAX_CHAIN_MASSES: usize = 4096;

fn check_masses(field: &str, n: usize) -> Result<usize, ParamError> {
    if (1..=MAX_CHAIN_MASSES).contains(&n) {
        Ok(n)
    } else {
        Err(ParamError::new(
            field,
            n,
            format!("integer in [1, {MAX_CHAIN_MASSES}]"),
        ))
    }
}

/// Writes the canonical structure `q̇ = p` into the first `n` rows of the row-major `2n × 2n`
/// Jacobian and zeroes the rest; callers then fill the `∂ṗ/∂q` block.
fn separable_jacobian_frame(n: usize, jac: &mut [f64]) {
    let m = 2 * n;
    jac[..m * m].fill(0.0);
    for i in 0..n {
        jac[i * m + n + i] = 1.0;
    }
}

/// Fermi-Pasta-Ulam-Tsingou β-chain: `n` unit masses between fixed walls joined by `n + 1`
/// springs with potential `φ(x) = ½ k x² + ¼ β x⁴` on the elongations
/// `x_i = q_i - q_{i-1}`, `i = 1..n+1`, with `q_0 = q_{n+1} = 0` (HLW section I.5 uses the
/// α-variant; the β-chain is the classical FPU β model).
///
/// `H = ½|p|² + Σ_{i=1}^{n+1} φ(x_i)`.
#[derive(Debug, Clone, PartialEq)]
pub struct FpuChain {
    /// Number of moving masses `n` (1 to [`MAX_CHAIN_MASSES`]).
    n: usize,
    /// Linear spring stiffness `k > 0` (force per unit elongation, unit masses).
    k: f64,
    /// Cubic stiffness `β ≥ 0` (force per cubed elongation); 0 gives the linear chain.
    beta: f64,
}

impl FpuChain {
    /// Builds a chain; errors name `n` (in `[1, 4096]`), `k` (> 0) or `beta` (≥ 0: a negative
    /// quartic term makes the potential unbounded below).
    pub fn new(n: usize, k: f64, beta: f64) -> Result<Self, ParamError> {
        Ok(Self {
            n: check_masses("n", n)?,
            k: check_positive("k", k)?,
            beta: check_non_negative("beta", beta)?,
        })
    }

    /// Linear stiffness `k`.
    pub fn k(&self) -> f64 {
        self.k
    }

    /// Cubic stiffness `β`.
    pub fn beta(&self) -> f64 {
        self.beta
    }

    /// Elongation `x_i = q_i - q_{i-1}` of spring `i` in `0..=n` (0-based), walls fixed.
    #[inline]
    fn elongation(&self, q: &[f64], i: usize) -> f64 {
        let right = if i < self.n { q[i] } else { 0.0 };
        let left = if i > 0 { q[i - 1] } else { 0.0 };
        right - left
    }

    /// Spring tension `φ'(x) = k x + β x³`.
    #[inline]
    fn tension(&self, x: f64) -> f64 {
        x * (self.k + self.beta * x * x)
    }

    /// Spring stiffness `φ''(x) = k + 3β x²`.
    #[inline]
    fn stiffness(&self, x: f64) -> f64 {
        self.k + 3.0 * self.beta * x * x
    }

    fn force(&self, q: &[f64], f: &mut [f64]) {
        // f_i = φ'(x_{i+1}) - φ'(x_i) with springs numbered 0..=n (spring i is left of mass i).
        let mut left_tension = self.tension(self.elongation(q, 0));
        for (i, fi) in f.iter_mut().enumerate().take(self.n) {
            let right_tension = self.tension(self.elongation(q, i + 1));
            *fi = right_tension - left_tension;
            left_tension = right_tension;
        }
    }
}

impl HamiltonianSystem for FpuChain {
    fn name(&self) -> &'static str {
        "fpu"
    }

    fn degrees_of_freedom(&self) -> usize {
        self.n
    }

    fn hamiltonian(&self, y: &[f64]) -> f64 {
        let (q, p) = y.split_at(self.n);
        let kinetic: f64 = 0.5 * p.iter().map(|v| v * v).sum::<f64>();
        let potential: f64 = (0..=self.n)
            .map(|i| {
                let x = self.elongation(q, i);
                x * x * (0.5 * self.k + 0.25 * self.beta * x * x)
            })
            .sum();
        kinetic + potential
    }

    fn vector_field(&self, y: &[f64], dy: &mut [f64]) {
        let n = self.n;
        let (q, p) = y.split_at(n);
        let (dq, dp) = dy.split_at_mut(n);
        dq.copy_from_slice(&p[..n]);
        self.force(q, dp);
    }

    fn vector_field_jacobian(&self, y: &[f64], jac: &mut [f64]) {
        let n = self.n;
        let m = 2 * n;
        separable_jacobian_frame(n, jac);
        for i in 0..n {
            let row = (n + i) * m;
            let s_left = self.stiffness(self.elongation(y, i));
            let s_right = self.stiffness(self.elongation(y, i + 1));
            jac[row + i] = -s_left - s_right;
            if i > 0 {
                jac[row + i - 1] = s_left;
            }
            if i + 1 < n {
                jac[row + i + 1] = s_right;
            }
        }
    }

    fn separable_force(&self, q: &[f64], force: &mut [f64]) -> bool {
        self.force(q, force);
        true
    }
}

/// Linear chain: the FPU chain with `β = 0`, whose normal modes are known in closed form.
///
/// Mode `j = 1..n` has shape `φ_j(i) = sin(i j π / (n + 1))` (`i = 1..n`) and angular frequency
/// `ω_j = 2 √k sin(j π / (2(n + 1)))`. Its energy is a quadratic invariant, conserved by the
/// Gauss methods up to rounding (HLW Theorem IV.2.2).
#[derive(Debug, Clone, PartialEq)]
pub struct LinearChain {
    /// The underlying chain with `beta = 0`.
    chain: FpuChain,
}

impl LinearChain {
    /// Builds a chain; errors name `n` (in `[1, 4096]`) or `k` (> 0).
    pub fn new(n: usize, k: f64) -> Result<Self, ParamError> {
        Ok(Self {
            chain: FpuChain::new(n, k, 0.0)?,
        })
    }

    /// Normal-mode angular frequency `ω_j = 2 √k sin(j π / (2(n + 1)))` for `j` in `1..=n`
    /// (rad per time unit); `None` outside that range.
    pub fn mode_frequency(&self, j: usize) -> Option<f64> {
        let n = self.chain.n;
        (1..=n).contains(&j).then(|| {
            2.0 * self.chain.k.sqrt()
                * (j as f64 * std::f64::consts::PI / (2.0 * (n + 1) as f64)).sin()
        })
    }

    /// All normal-mode angular frequencies `ω_1 < … < ω_n` (allocates; not for the audio
    /// thread).
    pub fn mode_frequencies(&self) -> Vec<f64> {
        (1..=self.chain.n)
            .filter_map(|j| self.mode_frequency(j))
            .collect()
    }

    /// Exact solution: writes `y(t)` into `out` starting from `y0` (both length `2n`), by
    /// projection on the orthogonal mode shapes (`|φ_j|² = (n + 1) / 2`). `O(n²)` work, no
    /// allocation.
    pub fn exact_solution(&self, y0: &[f64], t: f64, out: &mut [f64]) {
        let n = self.chain.n;
        let (q0, p0) = y0.split_at(n);
        out[..2 * n].fill(0.0);
        let norm2 = 0.5 * (n + 1) as f64;
        let shape = |i: usize, j: usize| {
            ((i + 1) as f64 * j as f64 * std::f64::consts::PI / (n + 1) as f64).sin()
        };
        for j in 1..=n {
            let w = self.mode_frequency(j).unwrap_or(1.0);
            let (a, b) = (0..n).fold((0.0, 0.0), |(a, b), i| {
                (a + shape(i, j) * q0[i], b + shape(i, j) * p0[i])
            });
            let (a, b) = (a / norm2, b / norm2);
            let (s, c) = (w * t).sin_cos();
            let amp_q = a * c + b / w * s;
            let amp_p = -a * w * s + b * c;
            for i in 0..n {
                out[i] += amp_q * shape(i, j);
                out[n + i] += amp_p * shape(i, j);
            }
        }
    }
}

impl HamiltonianSystem for LinearChain {
    fn name(&self) -> &'static str {
        "linear-chain"
    }
    fn degrees_of_freedom(&self) -> usize {
        self.chain.n
    }
    fn hamiltonian(&self, y: &[f64]) -> f64 {
        self.chain.hamiltonian(y)
    }
    fn vector_field(&self, y: &[f64], dy: &mut [f64]) {
        self.chain.vector_field(y, dy)
    }
    fn vector_field_jacobian(&self, y: &[f64], jac: &mut [f64]) {
        self.chain.vector_field_jacobian(y, jac)
    }
    fn separable_force(&self, q: &[f64], force: &mut [f64]) -> bool {
        self.chain.separable_force(q, force)
    }
}

/// Mathematical pendulum `H = ½ p² - ω0² cos q` (HLW section I.1): one degree of freedom,
/// small-oscillation angular frequency `ω0`.
#[derive(Debug, Clone, PartialEq)]
pub struct Pendulum {
    /// Small-oscillation angular frequency `ω0 > 0` (rad per time unit).
    omega0: f64,
}

impl Pendulum {
    /// Builds a pendulum; the error names `omega0` (> 0).
    pub fn new(omega0: f64) -> Result<Self, ParamError> {
        Ok(Self {
            omega0: check_positive("omega0", omega0)?,
        })
    }
}

impl HamiltonianSystem for Pendulum {
    fn name(&self) -> &'static str {
        "pendulum"
    }
    fn degrees_of_freedom(&self) -> usize {
        1
    }
    fn hamiltonian(&self, y: &[f64]) -> f64 {
        0.5 * y[1] * y[1] - self.omega0 * self.omega0 * y[0].cos()
    }
    fn vector_field(&self, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[1];
        dy[1] = -self.omega0 * self.omega0 * y[0].sin();
    }
    fn vector_field_jacobian(&self, y: &[f64], jac: &mut [f64]) {
        jac[..4].copy_from_slice(&[0.0, 1.0, -self.omega0 * self.omega0 * y[0].cos(), 0.0]);
    }
    fn separable_force(&self, q: &[f64], force: &mut [f64]) -> bool {
        force[0] = -self.omega0 * self.omega0 * q[0].sin();
        true
    }
}

/// Kepler problem in the plane, `H = ½|p|² - μ / |q|`, `q, p ∈ ℝ²` (HLW section I.2).
///
/// Its angular momentum `L = q_1 p_2 - q_2 p_1` ([`Kepler::angular_momentum`]) is a quadratic
/// first integral of a nonlinear system. The field is singular at `q = 0` (collision): callers
/// choose orbits that stay away from it.
#[derive(Debug, Clone, PartialEq)]
pub struct Kepler {
    /// Gravitational parameter `μ > 0` (length³ per time²).
    mu: f64,
}

impl Kepler {
    /// Builds the problem; the error names `mu` (> 0).
    pub fn new(mu: f64) -> Result<Self, ParamError> {
        Ok(Self {
            mu: check_positive("mu", mu)?,
        })
    }

    /// Angular momentum `L = q_1 p_2 - q_2 p_1` of state `y = [q_1, q_2, p_1, p_2]`.
    pub fn angular_momentum(y: &[f64]) -> f64 {
        y[0] * y[3] - y[1] * y[2]
    }
}

impl HamiltonianSystem for Kepler {
    fn name(&self) -> &'static str {
        "kepler"
    }
    fn degrees_of_freedom(&self) -> usize {
        2
    }
    fn hamiltonian(&self, y: &[f64]) -> f64 {
        0.5 * (y[2] * y[2] + y[3] * y[3]) - self.mu / y[0].hypot(y[1])
    }
    fn vector_field(&self, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[2];
        dy[1] = y[3];
        self.separable_force(&y[..2], &mut dy[2..4]);
    }
    fn vector_field_jacobian(&self, y: &[f64], jac: &mut [f64]) {
        separable_jacobian_frame(2, jac);
        // ∂f/∂q = μ (3 q qᵀ - r² I) / r⁵ for f = -μ q / r³.
        let r2 = y[0] * y[0] + y[1] * y[1];
        let r5 = r2 * r2 * r2.sqrt();
        let c = self.mu / r5;
        jac[2 * 4] = c * (3.0 * y[0] * y[0] - r2);
        jac[2 * 4 + 1] = c * 3.0 * y[0] * y[1];
        jac[3 * 4] = c * 3.0 * y[0] * y[1];
        jac[3 * 4 + 1] = c * (3.0 * y[1] * y[1] - r2);
    }
    fn separable_force(&self, q: &[f64], force: &mut [f64]) -> bool {
        let r2 = q[0] * q[0] + q[1] * q[1];
        let c = -self.mu / (r2 * r2.sqrt());
        force[0] = c * q[0];
        force[1] = c * q[1];
        true
    }
}

/// Serde description of a test system, as written in configuration files, for example
/// `{"system": "fpu", "n": 8, "k": 1.0, "beta": 0.5}`. Unknown fields are rejected.
///
/// Parsed on the configuration thread; turned into a system by [`build_system`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "system", rename_all = "kebab-case", deny_unknown_fields)]
pub enum SystemSpec {
    /// [`FpuChain`].
    Fpu {
        /// Number of masses (1 to 4096).
        n: usize,
        /// Linear stiffness (> 0).
        k: f64,
        /// Cubic stiffness (≥ 0).
        beta: f64,
    },
    /// [`Pendulum`].
    Pendulum {
        /// Small-oscillation angular frequency (> 0, rad per time unit).
        omega0: f64,
    },
    /// [`LinearChain`].
    LinearChain {
        /// Number of masses (1 to 4096).
        n: usize,
        /// Stiffness (> 0).
        k: f64,
    },
    /// [`Kepler`].
    Kepler {
        /// Gravitational parameter (> 0).
        mu: f64,
    },
}

/// Builds the system a [`SystemSpec`] describes, validating every parameter (the error names
/// the field, its value and the allowed range).
pub fn build_system(spec: &SystemSpec) -> Result<Box<dyn HamiltonianSystem>, ParamError> {
    Ok(match *spec {
        SystemSpec::Fpu { n, k, beta } => Box::new(FpuChain::new(n, k, beta)?),
        SystemSpec::Pendulum { omega0 } => Box::new(Pendulum::new(omega0)?),
        SystemSpec::LinearChain { n, k } => Box::new(LinearChain::new(n, k)?),
        SystemSpec::Kepler { mu } => Box::new(Kepler::new(mu)?),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Central differences of `H` and of the vector field: error `O(δ²)` ≈ 1e-10 plus rounding
    /// `ε/δ` ≈ 1e-11 at `δ = 1e-5`, hence the 1e-7 tolerance (scaled by the entry size).
    fn check_derivatives(sys: &dyn HamiltonianSystem, y: &[f64]) {
        let m = y.len();
        let d = 1e-5;
        let mut f = vec![0.0; m];
        let mut jac = vec![0.0; m * m];
        sys.vector_field(y, &mut f);
        sys.vector_field_jacobian(y, &mut jac);
        let (mut yp, mut ym) = (y.to_vec(), y.to_vec());
        let (mut fp, mut fm) = (vec![0.0; m], vec![0.0; m]);
        for j in 0..m {
            yp[j] = y[j] + d;
            ym[j] = y[j] - d;
            // ẏ = J⁻¹∇H: q̇_i = ∂H/∂p_i, ṗ_i = -∂H/∂q_i.
            let dh = (sys.hamiltonian(&yp) - sys.hamiltonian(&ym)) / (2.0 * d);
            let n = m / 2;
            let expected = if j < n { -f[n + j] } else { f[j - n] };
            assert!(
                (dh - expected).abs() < 1e-7 * (1.0 + dh.abs()),
                "{}",
                sys.name()
            );
            sys.vector_field(&yp, &mut fp);
            sys.vector_field(&ym, &mut fm);
            for i in 0..m {
                let fd = (fp[i] - fm[i]) / (2.0 * d);
                let an = jac[i * m + j];
                assert!(
                    (fd - an).abs() < 1e-7 * (1.0 + an.abs()),
                    "{} J[{i}][{j}]",
                    sys.name()
                );
            }
            yp[j] = y[j];
            ym[j] = y[j];
        }
    }

    #[test]
    fn fields_and_jacobians_match_finite_differences() {
        let y5 = [0.3, -0.2, 0.5, 0.1, -0.4, 0.2, 0.7, -0.3, 0.05, 0.6];
        check_derivatives(&FpuChain::new(5, 1.3, 0.8).unwrap(), &y5);
        check_derivatives(&LinearChain::new(5, 2.0).unwrap(), &y5);
        check_derivatives(&Pendulum::new(1.7).unwrap(), &[1.1, -0.4]);
        check_derivatives(&Kepler::new(1.0).unwrap(), &[0.6, -0.5, 0.3, 1.1]);
        check_derivatives(&FpuChain::new(1, 1.0, 2.0).unwrap(), &[0.4, 0.3]);
    }

    #[test]
    fn linear_chain_modes_are_eigenvectors_with_their_frequencies() {
        // K φ_j = ω_j² φ_j exactly in exact arithmetic; 1e-12 allows rounding of sin sums.
        let chain = LinearChain::new(6, 2.5).unwrap();
        let n = 6;
        let mut f = vec![0.0; n];
        for j in 1..=n {
            let w = chain.mode_frequency(j).unwrap();
            let shape: Vec<f64> = (1..=n)
                .map(|i| (i as f64 * j as f64 * std::f64::consts::PI / 7.0).sin())
                .collect();
            assert!(chain.separable_force(&shape, &mut f));
            for i in 0..n {
                assert!((f[i] + w * w * shape[i]).abs() < 1e-12, "mode {j}");
            }
        }
        assert_eq!(chain.mode_frequency(0), None);
        assert_eq!(chain.mode_frequency(7), None);
        assert_eq!(chain.mode_frequencies().len(), 6);
    }

    #[test]
    fn spec_parses_and_rejects_unknown_fields_and_bad_values() {
        let spec: SystemSpec =
            serde_json::from_str(r#"{"system":"fpu","n":4,"k":1.0,"beta":0.5}"#).unwrap();
        assert_eq!(build_system(&spec).unwrap().degrees_of_freedom(), 4);
        let spec: SystemSpec =
            serde_json::from_str(r#"{"system":"linear-chain","n":3,"k":2.0}"#).unwrap();
        assert_eq!(build_system(&spec).unwrap().name(), "linear-chain");
        assert!(serde_json::from_str::<SystemSpec>(r#"{"system":"pendulum","omega":1}"#).is_err());
        assert!(serde_json::from_str::<SystemSpec>(r#"{"system":"spring","k":1}"#).is_err());
        let e = build_system(&SystemSpec::Pendulum { omega0: -1.0 })
            .err()
            .expect("must be rejected");
        assert_eq!(e.field, "omega0");
        let e = build_system(&SystemSpec::Fpu {
            n: 0,
            k: 1.0,
            beta: 0.0,
        })
        .err()
        .expect("must be rejected");
        assert_eq!(e.field, "n");
        let e = build_system(&SystemSpec::Fpu {
            n: 2,
            k: 1.0,
            beta: -1.0,
        })
        .err()
        .expect("must be rejected");
        assert_eq!(e.field, "beta");
        let e = build_system(&SystemSpec::Kepler { mu: f64::NAN })
            .err()
            .expect("must be rejected");
        assert_eq!(e.field, "mu");
    }
}
