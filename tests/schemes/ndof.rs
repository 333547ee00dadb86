//! Shared harness over every N-degree-of-freedom method of the factory (SEED.md section 2):
//! measured convergence orders, conservation of quadratic invariants by the Gauss methods,
//! symplecticity of the one-step map, long-run energy behaviour, and rejected inputs.
//!
//! Each property is checked for every method from one table ([`CASES`]); what each method is
//! expected to do comes from the table (order, symplectic or not), not from copy-pasted tests.

use noether::schemes::ndof::gauss::{ImplicitRungeKutta, StageSolver};
use noether::schemes::ndof::systems::{FpuChain, Kepler, LinearChain, Pendulum};
use noether::schemes::ndof::verlet::StormerVerlet;
use noether::schemes::ndof::{
    build_method, build_method_for_system, build_system, butcher, HamiltonianSystem, OneStepMethod,
    SystemSpec, METHOD_NAMES,
};

use noether_testkit::alloc::allocations;

/// One row of the harness: a factory name and what the literature says about the method.
struct Case {
    /// Factory name.
    name: &'static str,
    /// Classical order (HLW chapter II).
    order: u32,
    /// Symplectic (HLW chapter VI): Störmer-Verlet and the Gauss methods.
    symplectic: bool,
}

const CASES: &[Case] = &[
    Case {
        name: "stormer-verlet",
        order: 2,
        symplectic: true,
    },
    Case {
        name: "midpoint",
        order: 2,
        symplectic: false,
    },
    Case {
        name: "heun",
        order: 2,
        symplectic: false,
    },
    Case {
        name: "rk4",
        order: 4,
        symplectic: false,
    },
    Case {
        name: "rk38",
        order: 4,
        symplectic: false,
    },
    Case {
        name: "gauss1",
        order: 2,
        symplectic: true,
    },
    Case {
        name: "gauss2",
        order: 4,
        symplectic: true,
    },
];

/// `step` never allocates: after building (which allocates the scratch), 100 steps of every
/// method on the FPU chain (n = 4) and on Kepler must not call the allocator at all. Exact count:
/// no tolerance. The count is checked to work by allocating a `Vec` in between.
#[test]
fn step_does_not_allocate() {
    let fpu = FpuChain::new(4, 1.0, 0.5).unwrap();
    let kepler = Kepler::new(1.0).unwrap();
    for c in CASES {
        let mut m = build_method(c.name, 4).unwrap();
        let mut y = [0.1, -0.2, 0.3, 0.0, 0.2, 0.1, -0.1, 0.3];
        let mut mk = build_method(c.name, 2).unwrap();
        let mut yk = [0.5, 0.0, 0.0, 1.7];
        let before = allocations();
        integrate(m.as_mut(), &fpu, 0.05, 100, &mut y);
        integrate(mk.as_mut(), &kepler, 0.01, 100, &mut yk);
        assert_eq!(allocations(), before, "{} allocated in step", c.name);
        let v = std::hint::black_box(vec![1.0_f64; 3]);
        assert!(
            allocations() > before && v.len() == 3,
            "the counter must see allocations"
        );
    }
}

/// Runs `steps` steps of size `h` from `y` in place.
fn integrate(
    m: &mut dyn OneStepMethod,
    sys: &dyn HamiltonianSystem,
    h: f64,
    steps: usize,
    y: &mut [f64],
) {
    for _ in 0..steps {
        m.step(sys, h, y);
    }
}

/// Formats numbers in scientific notation for diagnostics.
fn sci(v: &[f64]) -> String {
    v.iter()
        .map(|x| format!("{x:.2e}"))
        .collect::<Vec<_>>()
        .join(" ")
}

fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0, |acc, (x, y)| acc.max((x - y).abs()))
}

#[test]
fn table_matches_factory_and_method_metadata() {
    // The harness must cover exactly the factory's names, with the metadata each method reports.
    let names: Vec<&str> = CASES.iter().map(|c| c.name).collect();
    assert_eq!(names, METHOD_NAMES);
    for c in CASES {
        let m = build_method(c.name, 3).unwrap();
        assert_eq!(m.name(), c.name);
        assert_eq!(m.order(), c.order, "{}", c.name);
        assert_eq!(m.is_symplectic(), c.symplectic, "{}", c.name);
    }
}

/// (a) Convergence orders on a smooth nonlinear problem: FPU β-chain, n = 3, k = 1, β = 1, at
/// T = 4, errors (max norm over the state) against Gauss2 with step h/64 for h = 0.1, 0.05,
/// 0.025. The reference error is ≈ (64)^-4 ≈ 6e-8 times Gauss2's own error at h, below 1e-13,
/// far under the smallest measured error (~1e-8 for order 4 at h = 0.025). Expected orders within
/// ±0.15 (the brief's tolerance: at these step sizes the leading error term dominates, higher
/// terms shift log2 ratios by O(h) ≈ a few hundredths).
#[test]
fn measured_convergence_orders() {
    let sys = FpuChain::new(3, 1.0, 1.0).unwrap();
    let y0 = [0.5, -0.3, 0.2, 0.1, 0.4, -0.2];
    let t_end = 4.0;
    let h0 = 0.1;
    let reference = {
        let mut m = build_method("gauss2", 3).unwrap();
        let mut y = y0;
        integrate(m.as_mut(), &sys, h0 / 64.0, 40 * 64, &mut y);
        y
    };
    for c in CASES {
        let mut errors = [0.0; 3];
        for (level, e) in errors.iter_mut().enumerate() {
            let refine = 1 << level;
            let mut m = build_method(c.name, 3).unwrap();
            let mut y = y0;
            integrate(m.as_mut(), &sys, h0 / refine as f64, 40 * refine, &mut y);
            assert!((40 * refine) as f64 * h0 / refine as f64 - t_end < 1e-12);
            *e = max_abs_diff(&y, &reference);
        }
        let p1 = (errors[0] / errors[1]).log2();
        let p2 = (errors[1] / errors[2]).log2();
        eprintln!(
            "order {:>15}: errors {} -> orders {p1:.3}, {p2:.3}",
            c.name,
            sci(&errors)
        );
        for p in [p1, p2] {
            assert!(
                (p - c.order as f64).abs() <= 0.15,
                "{}: measured order {p}, expected {}",
                c.name,
                c.order
            );
        }
    }
}

/// (b) Gauss methods conserve quadratic invariants up to the solver tolerance (1e-14 relative
/// per step) and rounding (HLW Theorem IV.2.2): the linear chain's energy (quadratic) over
/// 20 000 steps, and the angular momentum of the (nonlinear) Kepler problem over 20 000 steps.
/// Rounding accumulates like a random walk, ~ √20000 · 1e-16 ≈ 1e-14, hence the 1e-13
/// relative bound. The explicit methods, for contrast, must violate the same invariants by more
/// than 1e-9 (their local errors are O(h^{p+1}) ≈ 1e-5 to 1e-10 at these step sizes).
#[test]
fn gauss_methods_conserve_quadratic_invariants() {
    let chain = LinearChain::new(8, 1.0).unwrap();
    let y_chain: Vec<f64> = (0..16).map(|i| ((i * 7 % 5) as f64 - 2.0) * 0.3).collect();
    let e0 = chain.hamiltonian(&y_chain);
    let kepler = Kepler::new(1.0).unwrap();
    let ecc = 0.5_f64;
    let y_kepler = [1.0 - ecc, 0.0, 0.0, ((1.0 + ecc) / (1.0 - ecc)).sqrt()];
    let l0 = Kepler::angular_momentum(&y_kepler);
    for c in CASES.iter().filter(|c| c.name != "stormer-verlet") {
        let mut m = build_method(c.name, 8).unwrap();
        let mut y = y_chain.clone();
        let mut chain_err = 0.0_f64;
        for _ in 0..20_000 {
            m.step(&chain, 0.1, &mut y);
            chain_err = chain_err.max(((chain.hamiltonian(&y) - e0) / e0).abs());
        }
        let mut m = build_method(c.name, 2).unwrap();
        let mut y = y_kepler;
        let mut l_err = 0.0_f64;
        for _ in 0..20_000 {
            m.step(&kepler, 0.01, &mut y);
            l_err = l_err.max(((Kepler::angular_momentum(&y) - l0) / l0).abs());
        }
        eprintln!(
            "invariants {:>8}: chain energy {chain_err:.2e}, Kepler L {l_err:.2e}",
            c.name
        );
        if c.symplectic {
            assert!(
                chain_err < 1e-13 && l_err < 1e-13,
                "{}: {chain_err:e} {l_err:e}",
                c.name
            );
            assert_eq!(m.stats().solver_failures, 0, "{}", c.name);
        } else {
            assert!(
                chain_err > 1e-9 && l_err > 1e-9,
                "{}: {chain_err:e} {l_err:e}",
                c.name
            );
        }
    }
    // The fixed-point solver conserves them too (same stage equations, same tolerance).
    let mut m =
        ImplicitRungeKutta::with_solver(&butcher::GAUSS2, 2, StageSolver::FixedPoint, 1e-14, 50)
            .unwrap();
    let mut y = y_kepler;
    integrate(&mut m, &kepler, 0.01, 20_000, &mut y);
    let l_err = ((Kepler::angular_momentum(&y) - l0) / l0).abs();
    eprintln!(
        "invariants gauss2 fixed-point: Kepler L {l_err:.2e}, {:?}",
        m.stats()
    );
    assert!(l_err < 1e-13, "{l_err:e}");
}

/// Non-separable Hamiltonian `H = ½ p² (1 + q²) + ½ q²` (one degree of freedom): Gauss methods
/// stay symplectic on it, Störmer-Verlet must refuse it.
struct NonSeparable;

impl HamiltonianSystem for NonSeparable {
    fn name(&self) -> &'static str {
        "non-separable"
    }
    fn degrees_of_freedom(&self) -> usize {
        1
    }
    fn hamiltonian(&self, y: &[f64]) -> f64 {
        0.5 * y[1] * y[1] * (1.0 + y[0] * y[0]) + 0.5 * y[0] * y[0]
    }
    fn vector_field(&self, y: &[f64], dy: &mut [f64]) {
        let (q, p) = (y[0], y[1]);
        dy[0] = p * (1.0 + q * q);
        dy[1] = -(p * p * q + q);
    }
    fn vector_field_jacobian(&self, y: &[f64], jac: &mut [f64]) {
        let (q, p) = (y[0], y[1]);
        jac[..4].copy_from_slice(&[2.0 * p * q, 1.0 + q * q, -(p * p + 1.0), -2.0 * p * q]);
    }
}

/// Symplecticity defect `max |Φ'ᵀ J Φ' - J|` of one step, with `Φ'` by central differences
/// (step δ = 1e-5 per coordinate).
fn symplectic_defect(name: &str, sys: &dyn HamiltonianSystem, h: f64, y0: &[f64]) -> f64 {
    let m = y0.len();
    let n = m / 2;
    let mut method = build_method_for_system(name, sys).unwrap();
    let delta = 1e-5;
    let mut jac = vec![0.0; m * m]; // Φ' row-major.
    for j in 0..m {
        let (mut yp, mut ym) = (y0.to_vec(), y0.to_vec());
        yp[j] += delta;
        ym[j] -= delta;
        method.step(sys, h, &mut yp);
        method.step(sys, h, &mut ym);
        for i in 0..m {
            jac[i * m + j] = (yp[i] - ym[i]) / (2.0 * delta);
        }
    }
    // J = [[0, I], [-I, 0]]: (J x)_i = x_{n+i}, (J x)_{n+i} = -x_i.
    let j_entry = |r: usize, c: usize| -> f64 {
        if r < n && c == r + n {
            1.0
        } else if r >= n && c + n == r {
            -1.0
        } else {
            0.0
        }
    };
    let mut worst = 0.0_f64;
    for r in 0..m {
        for c in 0..m {
            // (Φ'ᵀ J Φ')_{rc} = Σ_{k,l} Φ'_{kr} J_{kl} Φ'_{lc}.
            let mut s = 0.0;
            for k in 0..m {
                for l in 0..m {
                    s += jac[k * m + r] * j_entry(k, l) * jac[l * m + c];
                }
            }
            worst = worst.max((s - j_entry(r, c)).abs());
        }
    }
    worst
}

/// (c) Symplecticity of Φ_h on the pendulum (h = 0.3, large amplitude), the FPU chain (n = 2,
/// h = 0.2) and, for the Gauss methods, a non-separable system. Central differences with
/// δ = 1e-5 have truncation error ~ δ² |Φ'''| ≈ 1e-10 and rounding ~ ε/δ ≈ 1e-11 (plus the
/// Newton tolerance 1e-14 / δ ≈ 1e-9 in the worst case), so symplectic maps must give a defect
/// below 1e-8 (measured: 4e-13 to 2e-11). The non-symplectic methods' defects are
/// O(h^{p+1}) (measured: 6e-6 to 4e-2); we require > 1e-6, 100× the symplectic bound.
#[test]
fn symplecticity_of_the_one_step_map() {
    let pendulum = Pendulum::new(1.0).unwrap();
    let fpu = FpuChain::new(2, 1.0, 1.5).unwrap();
    for c in CASES {
        let d_pend = symplectic_defect(c.name, &pendulum, 0.3, &[0.5, 0.3]);
        let d_fpu = symplectic_defect(c.name, &fpu, 0.2, &[0.6, -0.4, 0.3, 0.5]);
        eprintln!(
            "symplectic defect {:>15}: pendulum {d_pend:.2e}, fpu {d_fpu:.2e}",
            c.name
        );
        if c.symplectic {
            assert!(
                d_pend < 1e-8 && d_fpu < 1e-8,
                "{}: {d_pend:e} {d_fpu:e}",
                c.name
            );
        } else {
            assert!(
                d_pend > 1e-6 && d_fpu > 1e-6,
                "{}: {d_pend:e} {d_fpu:e}",
                c.name
            );
        }
    }
    for name in ["gauss1", "gauss2"] {
        let d = symplectic_defect(name, &NonSeparable, 0.4, &[0.7, 0.4]);
        eprintln!("symplectic defect {name:>15}: non-separable {d:.2e}");
        assert!(d < 1e-8, "{name}: {d:e}");
    }
    let d = symplectic_defect("rk4", &NonSeparable, 0.4, &[0.7, 0.4]);
    eprintln!("symplectic defect {:>15}: non-separable {d:.2e}", "rk4");
    assert!(d > 1e-6, "rk4 non-separable: {d:e}");
}

/// Windows of a long run: max of |H - H0| / |H0| over each of `WINDOWS` consecutive windows.
const WINDOWS: usize = 8;

/// (d) Long runs on the pendulum (q0 = 2 rad, p0 = 0, h = 0.1, 20 000 steps ≈ 240 periods).
/// Symplectic methods: the energy error stays bounded (HLW Theorem IX.8.1): the max over the
/// second half is at most 2× the max over the first half (it oscillates with the same envelope).
/// Non-symplectic methods drift: |ΔH| per window grows monotonically and the last window is at
/// least 4× the first. On the linearised problem `|R(ihω)|² = 1 - (hω)⁶/72 + …` for RK4 (and
/// the 3/8 rule: same stability polynomial) and `1 + (hω)⁴/4` for the explicit order-2 methods,
/// so each step loses or gains a fixed fraction of energy and the error accumulates linearly
/// (measured: Störmer-Verlet flat at 6.5e-3, RK4 from 6e-5 to 5e-4).
#[test]
fn long_run_energy_bounded_for_symplectic_drifting_otherwise() {
    let sys = Pendulum::new(1.0).unwrap();
    let y0 = [2.0, 0.0];
    let h0 = sys.hamiltonian(&y0);
    let steps = 20_000;
    for c in CASES {
        let mut m = build_method(c.name, 1).unwrap();
        let mut y = y0;
        let mut window_max = [0.0_f64; WINDOWS];
        for s in 0..steps {
            m.step(&sys, 0.1, &mut y);
            let err = ((sys.hamiltonian(&y) - h0) / h0).abs();
            let w = s * WINDOWS / steps;
            window_max[w] = window_max[w].max(err);
        }
        let first: f64 = window_max[..WINDOWS / 2].iter().fold(0.0, |a, &b| a.max(b));
        let second: f64 = window_max[WINDOWS / 2..].iter().fold(0.0, |a, &b| a.max(b));
        eprintln!("energy {:>15}: windows {}", c.name, sci(&window_max));
        if c.symplectic {
            assert!(
                second <= 2.0 * first,
                "{}: {first:e} then {second:e}",
                c.name
            );
        } else {
            assert!(
                window_max.windows(2).all(|w| w[1] > w[0]),
                "{}: not monotone {}",
                c.name,
                sci(&window_max)
            );
            assert!(
                window_max[WINDOWS - 1] > 4.0 * window_max[0],
                "{}: {}",
                c.name,
                sci(&window_max)
            );
        }
    }
}

/// (e) Bad inputs are rejected with a `ParamError` naming the field, the value and the allowed
/// range; a non-separable system makes Störmer-Verlet's constructor fail.
#[test]
fn bad_inputs_are_rejected() {
    let e = build_method("euler", 2).err().expect("unknown name");
    assert_eq!(e.field, "method");
    let msg = e.to_string();
    assert!(msg.contains("euler"), "{msg}");
    for name in METHOD_NAMES {
        assert!(msg.contains(name), "{msg}");
        let e = build_method(name, 0).err().expect("zero dof");
        assert_eq!(e.field, "degrees_of_freedom");
    }
    let e = build_method("gauss2", 10_000)
        .err()
        .expect("too large for Gauss");
    assert_eq!(e.field, "degrees_of_freedom");
    let e = build_method_for_system("stormer-verlet", &NonSeparable)
        .err()
        .expect("non-separable");
    assert_eq!(
        (e.field.as_str(), e.value.as_str()),
        ("system", "non-separable")
    );
    assert!(StormerVerlet::for_system(&NonSeparable).is_err());
    assert!(build_method_for_system("gauss1", &NonSeparable).is_ok());
    let bad_specs = [
        (
            SystemSpec::Fpu {
                n: 0,
                k: 1.0,
                beta: 0.1,
            },
            "n",
        ),
        (
            SystemSpec::Fpu {
                n: 3,
                k: 0.0,
                beta: 0.1,
            },
            "k",
        ),
        (
            SystemSpec::Fpu {
                n: 3,
                k: 1.0,
                beta: f64::NAN,
            },
            "beta",
        ),
        (SystemSpec::LinearChain { n: 5000, k: 1.0 }, "n"),
        (
            SystemSpec::Pendulum {
                omega0: f64::INFINITY,
            },
            "omega0",
        ),
        (SystemSpec::Kepler { mu: -1.0 }, "mu"),
    ];
    for (spec, field) in bad_specs {
        let e = build_system(&spec).err().expect("bad spec");
        assert_eq!(e.field, field, "{spec:?}");
    }
    assert!(serde_json::from_str::<SystemSpec>(
        r#"{"system":"fpu","n":3,"k":1,"beta":0,"gamma":1}"#
    )
    .is_err());
}

/// Störmer-Verlet built without seeing the system panics with a clear message on a
/// non-separable one (its `step` cannot return an error).
#[test]
#[should_panic(expected = "not separable")]
fn stormer_verlet_step_panics_on_non_separable_system() {
    let mut m = build_method("stormer-verlet", 1).unwrap();
    let mut y = [0.1, 0.2];
    m.step(&NonSeparable, 0.1, &mut y);
}

/// Against the exact solution of the linear chain (normal modes, n = 5, k = 1, T = 10), the
/// measured order between h = 0.05 and h = 0.025 is the expected one within ±0.15 (same reason
/// as in `measured_convergence_orders`; here there is no reference-solution error at all). This
/// also cross-checks `LinearChain::exact_solution` (at t = 0 it must return y0 to rounding).
#[test]
fn linear_chain_exact_solution_gives_expected_orders() {
    let chain = LinearChain::new(5, 1.0).unwrap();
    let y0 = [0.3, -0.1, 0.2, 0.0, 0.4, 0.1, 0.0, -0.2, 0.3, 0.1];
    let mut exact = [0.0; 10];
    chain.exact_solution(&y0, 10.0, &mut exact);
    let mut at_zero = [0.0; 10];
    chain.exact_solution(&y0, 0.0, &mut at_zero);
    assert!(max_abs_diff(&at_zero, &y0) < 1e-14);
    for c in CASES {
        let mut errors = [0.0; 2];
        for (level, e) in errors.iter_mut().enumerate() {
            let refine = 1 << level;
            let mut m = build_method(c.name, 5).unwrap();
            let mut y = y0;
            integrate(
                m.as_mut(),
                &chain,
                0.05 / refine as f64,
                200 * refine,
                &mut y,
            );
            *e = max_abs_diff(&y, &exact);
        }
        let p = (errors[0] / errors[1]).log2();
        eprintln!(
            "linear chain {:>15}: errors {} -> order {p:.3}",
            c.name,
            sci(&errors)
        );
        assert!((p - c.order as f64).abs() <= 0.15, "{}: order {p}", c.name);
    }
}
