//! Factory of one-step methods by command-line name.
//!
//! Called on the configuration thread; the returned method is then owned by the thread that
//! steps it.

use super::butcher::{EXPLICIT_MIDPOINT, GAUSS1, GAUSS2, HEUN, RK38, RK4};
use super::gauss::ImplicitRungeKutta;
use super::runge_kutta::ExplicitRungeKutta;
use super::verlet::StormerVerlet;
use super::{HamiltonianSystem, OneStepMethod};
use crate::error::ParamError;

/// Names accepted by [`build_method`], in presentation order.
pub const METHOD_NAMES: &[&str] = &[
    "stormer-verlet",
    "midpoint",
    "heun",
    "rk4",
    "rk38",
    "gauss1",
    "gauss2",
];

/// Builds the method called `name` for `degrees_of_freedom = n` positions (state length `2n`).
///
/// Errors: field `method` listing [`METHOD_NAMES`] for an unknown name; `degrees_of_freedom`
/// outside `[1, 2^20]` (explicit methods) or `[1, 256]` (Gauss methods). Störmer-Verlet built
/// here cannot check separability (it panics in `step` on a non-separable system); use
/// [`build_method_for_system`] to get that check as an error.
pub fn build_method(
    name: &str,
    degrees_of_freedom: usize,
) -> Result<Box<dyn OneStepMethod>, ParamError> {
    Ok(match name {
        "stormer-verlet" => Box::new(StormerVerlet::new(degrees_of_freedom)?),
        "midpoint" => Box::new(ExplicitRungeKutta::new(
            &EXPLICIT_MIDPOINT,
            degrees_of_freedom,
        )?),
        "heun" => Box::new(ExplicitRungeKutta::new(&HEUN, degrees_of_freedom)?),
        "rk4" => Box::new(ExplicitRungeKutta::new(&RK4, degrees_of_freedom)?),
        "rk38" => Box::new(ExplicitRungeKutta::new(&RK38, degrees_of_freedom)?),
        "gauss1" => Box::new(ImplicitRungeKutta::new(&GAUSS1, degrees_of_freedom)?),
        "gauss2" => Box::new(ImplicitRungeKutta::new(&GAUSS2, degrees_of_freedom)?),
        _ => {
            return Err(ParamError::new(
                "method",
                name,
                format!("one of {}", METHOD_NAMES.join(", ")),
            ))
        }
    })
}

/// Like [`build_method`] with the dimension taken from `system`, and for `stormer-verlet` a
/// separability check (error field `system`, see [`StormerVerlet::for_system`]).
pub fn build_method_for_system(
    name: &str,
    system: &dyn HamiltonianSystem,
) -> Result<Box<dyn OneStepMethod>, ParamError> {
    if name == "stormer-verlet" {
        Ok(Box::new(StormerVerlet::for_system(system)?))
    } else {
        build_method(name, system.degrees_of_freedom())
    }
}
