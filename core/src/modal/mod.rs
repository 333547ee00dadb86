//! Modal data of thin plates for the von Kármán modal model (SEED §3.1): transverse modes
//! Φ_k with pulsations ω_k, in-plane (Airy) modes Ψ_l with `ΔΔΨ_l = ζ_l⁴ Ψ_l`, and the
//! coupling tensor `H^l_{ij} = ∫_S Ψ_l L(Φ_i, Φ_j) dS` (with `E^s_{i,j} = H^j_{s,i}`).
//!
//! Everything is dimensionless: radius `a = 1`, `D = ρh = 1` (so `ω = λ²`), modes normalised
//! to `∫_S Φ² dS = ∫_S Ψ² dS = 1` over the unit disc (area π). Physical pulsations are
//! `λ² · omega_scale(a, h, E, ρ, ν)` ([`basis::omega_scale`]).
//!
//! - [`basis`]: [`PlateModes`] (modes, eigenvalues, tensor, `phi_at`) and [`CircularPlateSpec`];
//! - [`modes`]: the circular plate's modes ([`Mode`]) enumerated in frequency order
//!   ([`circular_modes`]);
//! - [`circular`]: characteristic equations and radial profiles (Leissa 1969);
//! - [`coupling`]: the geometry-independent sparse tensor [`CouplingTensor`] and its
//!   allocation-free kernels (`contract_eta`, `apply_force`, `coupling_matrix`,
//!   `quartic_gradient`): the time schemes call the dense selection-rule block versions
//!   (`coupling_blocks.rs`, `coupling_blocks_kernels.rs`, with caller-owned scratch); the run
//!   layout (`coupling_runs.rs`) is kept as the reference implementation the tests compare with;
//! - [`assemble`]: tensor assembly for the circular plate (analytic angular integrals,
//!   Gauss-Legendre radial quadrature, scoped threads);
//! - [`cache`]: on-disk cache (`PlateModes::load_or_build`);
//! - [`bessel`], [`quadrature`], [`angular`]: numerical building blocks.
//!
//! References: A. W. Leissa, Vibration of Plates, NASA SP-160, 1969; M. Ducceschi & C. Touzé,
//! JSV 344, 313-331, 2015; C. Touzé, O. Thomas & A. Chaigne, JSV 258(4), 649-676, 2002;
//! O. Thomas & S. Bilbao, JSV 315, 569-590, 2008.
//!
//! Threads: building (modes, tensor, cache) runs on a worker thread; `phi_at`, the Bessel
//! functions and the tensor kernels never allocate and may run on the audio thread.

pub mod angular;
pub mod assemble;
pub mod basis;
pub mod bessel;
pub mod cache;
pub mod circular;
pub mod coupling;
mod coupling_blocks;
mod coupling_runs;
pub mod modes;
pub mod quadrature;

pub use angular::Parity;
pub use basis::{omega_scale, CircularPlateSpec, PlateModes};
pub use cache::{default_cache_dir, CacheOutcome};
pub use circular::{CircularEdge, RadialFunction};
pub use coupling::CouplingTensor;
pub use modes::{circular_modes, circular_modes_with, Mode};
