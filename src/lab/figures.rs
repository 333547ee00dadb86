//! The lecture's illustrations (SEED.md 1.1-1.4 and 2) as named experiments, so each one is
//! reproduced by `noether lab figure NAME`.

use super::{Duration, NdofExperiment, OscillatorExperiment};
use crate::schemes::ndof::SystemSpec;
use crate::schemes::OscillatorSpec;

/// A named experiment.
#[derive(Debug, Clone)]
pub enum Experiment {
    /// A one-oscillator run.
    Oscillator(OscillatorExperiment),
    /// An N-degree-of-freedom run.
    Ndof(NdofExperiment),
}

/// A lecture illustration: name, what it shows, and the experiment.
#[derive(Debug, Clone)]
pub struct Figure {
    /// Identifier used on the command line.
    pub name: &'static str,
    /// What the lecture shows with it.
    pub caption: &'static str,
    /// The run.
    pub experiment: Experiment,
}

fn osc(spec: OscillatorSpec, h: f64, u0: f64, duration: Duration) -> Experiment {
    Experiment::Oscillator(OscillatorExperiment {
        spec,
        h,
        u0,
        v0: 0.0,
        duration,
    })
}

fn theta(theta: f64, periods: f64) -> Experiment {
    osc(
        OscillatorSpec::Theta { omega0: 1.0, theta },
        0.125,
        1.0,
        Duration::Periods(periods),
    )
}

fn exact(xi: f64, h: f64, periods: f64) -> Experiment {
    osc(
        OscillatorSpec::Exact { omega0: 1.0, xi },
        h,
        1.0,
        Duration::Periods(periods),
    )
}

fn ndof(system: SystemSpec, method: &str, h: f64, amplitude: f64, periods: f64) -> Experiment {
    Experiment::Ndof(NdofExperiment {
        system,
        method: method.into(),
        h,
        amplitude,
        momentum: 0.0,
        duration: Duration::Periods(periods),
    })
}

/// Every illustration, in lecture order.
pub fn all() -> Vec<Figure> {
    let duffing = |theta1, theta2| OscillatorSpec::DuffingConservative {
        omega0: 1.0,
        gamma: 5.0,
        theta1,
        theta2,
    };
    let fpu = SystemSpec::Fpu {
        n: 8,
        k: 1.0,
        beta: 1.0,
    };
    let mut v = vec![
        Figure { name: "theta1-150", caption: "1.1: theta = 1 (explicit), h = 0.125 (~50 points/period), after 150 periods", experiment: theta(1.0, 150.0) },
        Figure { name: "theta0-50", caption: "1.1: theta = 0 (implicit), h = 0.125, after 50 periods", experiment: theta(0.0, 50.0) },
        Figure { name: "theta1-200", caption: "1.1: frequency error after 200 periods, theta = 1 (over-estimates omega0)", experiment: theta(1.0, 200.0) },
        Figure { name: "theta0-200", caption: "1.1: frequency error after 200 periods, theta = 0 (under-estimates omega0)", experiment: theta(0.0, 200.0) },
        Figure { name: "theta0.8-200", caption: "1.1: frequency error after 200 periods, theta = 0.8", experiment: theta(0.8, 200.0) },
        Figure { name: "exact-h0.31", caption: "1.2: exact scheme, h = 0.31: omega_d = omega0", experiment: exact(0.0, 0.31, 50.0) },
        Figure { name: "exact-h1.25", caption: "1.2: exact scheme, h = 1.25: omega_d = omega0", experiment: exact(0.0, 1.25, 50.0) },
        Figure { name: "exact-h10", caption: "1.2: exact scheme, h = 10 (1.6 steps per period, samples still exact)", experiment: exact(0.0, 10.0, 200.0) },
        Figure { name: "exact-damped-h2", caption: "1.2: damped exact scheme, omega0 = 1, u0 = 1, h = 2, xi = 0.1", experiment: exact(0.1, 2.0, 10.0) },
        Figure { name: "exact-critical-h2", caption: "1.2: damped exact scheme at critical damping xi = 1, h = 2", experiment: exact(1.0, 2.0, 3.0) },
        Figure { name: "exact-overdamped-h2", caption: "1.2: damped exact scheme, over-damped xi = 2, h = 2", experiment: exact(2.0, 2.0, 3.0) },
        Figure { name: "duffing-verlet", caption: "1.3: Stormer-Verlet on Duffing (omega0 = 1, gamma = 5, h = 0.0628): energy not conserved", experiment: osc(OscillatorSpec::DuffingVerlet { omega0: 1.0, gamma: 5.0 }, 0.0628, 1.0, Duration::Periods(100.0)) },
        Figure { name: "duffing-explicit", caption: "1.3: conservative Duffing scheme, theta1 = 0.8, theta2 = 1 (explicit), h = 0.0628", experiment: osc(duffing(0.8, 1.0), 0.0628, 1.0, Duration::Periods(100.0)) },
        Figure { name: "duffing-implicit", caption: "1.3: conservative Duffing scheme, theta1 = 1, theta2 = 0 (cubic solved each step), h = 0.0628", experiment: osc(duffing(1.0, 0.0), 0.0628, 1.0, Duration::Periods(100.0)) },
        Figure {
            name: "impact",
            caption: "1.4: impact oscillator, K = 1e13, alpha = 1.5, wall at d = 0.5, u0 = 0, v0 = 1 (hits the wall every period), theta = 0.5",
            experiment: Experiment::Oscillator(OscillatorExperiment {
                spec: OscillatorSpec::Impact { mass: 1.0, stiffness: 1.0, contact_stiffness: 1e13, alpha: 1.5, gap: 0.5, theta: 0.5 },
                h: 1e-3,
                u0: 0.0,
                v0: 1.0,
                duration: Duration::Periods(20.0),
            }),
        },
    ];
    for method in ["stormer-verlet", "rk4", "gauss2"] {
        v.push(Figure {
            name: match method {
                "stormer-verlet" => "fpu-stormer-verlet",
                "rk4" => "fpu-rk4",
                _ => "fpu-gauss2",
            },
            caption: "2: FPU chain (8 masses, cubic springs): symplectic methods keep a bounded energy error, RK4 drifts",
            experiment: ndof(fpu.clone(), method, 0.5, 1.0, 300.0),
        });
    }
    v.push(Figure {
        name: "pendulum-gauss1",
        caption: "2: pendulum with the implicit midpoint rule (Gauss 1 stage)",
        experiment: ndof(
            SystemSpec::Pendulum { omega0: 1.0 },
            "gauss1",
            0.2,
            2.0,
            50.0,
        ),
    });
    v
}

/// The illustration called `name`, if any.
pub fn find(name: &str) -> Option<Figure> {
    all().into_iter().find(|f| f.name == name)
}
