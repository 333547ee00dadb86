//! Measurements on simulated signals and the closed forms they are checked against.
//!
//! - [`frequency`]: oscillation frequency from zero crossings, cents;
//! - [`dispersion`]: closed-form frequencies of the schemes' linear partials;
//! - [`energy`]: energy-drift statistics;
//! - [`analytic`]: exact solutions (linear damped oscillator, Duffing via Jacobi `cn`) and the
//!   closed-form numerical frequency of the θ-family.

pub mod analytic;
pub mod dispersion;
pub mod energy;
pub mod frequency;
