//! The circular plate's modal basis (dimensionless: radius `a = 1`, `D = ρh = 1`):
//! transverse modes Φ with `λ²`, in-plane (Airy) modes Ψ with `ΔΔΨ_l = ζ_l⁴ Ψ_l`, and the
//! coupling tensor assembled by quadrature.
//!
//! - [`basis`]: [`PlateModes`] (modes, eigenvalues, tensor, `phi_at`) and [`CircularPlateSpec`];
//! - [`modes`]: the circular plate's modes ([`Mode`]) enumerated in frequency order
//!   ([`circular_modes`]);
//! - [`radial`]: characteristic equations and radial profiles (Leissa 1969);
//! - [`assemble`]: tensor assembly (analytic angular integrals, Gauss-Legendre radial
//!   quadrature, scoped threads);
//! - [`cache`]: on-disk cache (`PlateModes::load_or_build`);
//! - [`bessel`], [`angular`]: numerical building blocks (the quadrature rule, shared with the
//!   rectangle, is [`crate::modal::quadrature`]).
//!
//! Threads: building (modes, tensor, cache) runs on a worker thread; `phi_at` and the Bessel
//! functions never allocate and may run on the audio thread.

pub mod angular;
pub mod assemble;
pub mod basis;
pub mod bessel;
pub mod cache;
pub mod modes;
pub mod radial;

pub use angular::Parity;
pub use basis::{omega_scale, CircularPlateSpec, PlateModes};
pub use cache::{default_cache_dir, CacheOutcome};
pub use modes::{circular_modes, circular_modes_with, Mode};
pub use radial::{CircularEdge, RadialFunction};
