//! Modal bases of thin plates for the von Kármán modal model (SEED §3.1): transverse modes
//! Φ_k with eigenvalues `λ_k²`, in-plane (Airy) modes Ψ_l with `ΔΔΨ_l = ζ_l⁴ Ψ_l`, and the
//! coupling tensor `H^l_{ij} = ∫_S Ψ_l L(Φ_i, Φ_j) dS` (with `E^s_{i,j} = H^j_{s,i}`).
//!
//! Everything is dimensionless: unit plate (radius `a = 1`, or `Lx = 1`), `D = ρh = 1` (so the
//! transverse pulsation is `λ²`), modes normalised to `∫_S Φ² dS = ∫_S Ψ² dS = 1`.
//!
//! - [`ModalBasis`] ([`basis`]): what every shape offers (`λ²`, `ζ⁴`, `Φ` at a [`UnitPoint`],
//!   the coupling tensor), implemented by [`PlateModes`] and [`rect::RectModes`];
//! - [`circular`]: the circular plate (free or clamped; Bessel functions, angular integrals,
//!   tensor assembly, the on-disk cache): [`PlateModes`], [`CircularPlateSpec`];
//! - [`rect`]: the simply supported rectangle (closed-form Φ, Rayleigh-Ritz Ψ, its tensor):
//!   [`rect::RectModes`], [`rect::RectSpec`];
//! - [`shell`]: linear modes of a shallow spherical shell (a curved free plate) by projection of
//!   its rest shape on the flat basis ([`shell::Imperfection`], [`shell::shell_modes`]);
//! - [`tensor`]: the geometry-independent sparse tensor [`CouplingTensor`] and its
//!   allocation-free kernels (dense selection-rule blocks with SIMD kernels, the run layout
//!   kept as the reference);
//! - [`quadrature`]: Gauss-Legendre rules (both shapes);
//! - [`error`]: [`ModalError`] (parameters, numerical failures, cache and I/O).
//!
//! References: A. W. Leissa, Vibration of Plates, NASA SP-160, 1969; M. Ducceschi & C. Touzé,
//! JSV 344, 313-331, 2015; C. Touzé, O. Thomas & A. Chaigne, JSV 258(4), 649-676, 2002;
//! O. Thomas & S. Bilbao, JSV 315, 569-590, 2008.
//!
//! Threads: building (modes, tensor, cache) runs on a worker thread; `phi_at`, the Bessel
//! functions and the tensor kernels never allocate and may run on the audio thread.

pub mod basis;
pub mod circular;
pub mod error;
pub mod quadrature;
pub mod rect;
pub mod scaling;
pub mod shell;
pub mod tensor;

pub use basis::{Coordinates, ModalBasis, UnitPoint};
pub use circular::{
    circular_modes, circular_modes_with, default_cache_dir, omega_scale, CacheOutcome,
    CircularEdge, CircularPlateSpec, Mode, Parity, PlateModes, RadialFunction,
};
pub use error::{CacheReject, ModalError};
pub use tensor::{CouplingTensor, TensorStorage};
