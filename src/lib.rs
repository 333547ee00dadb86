//! # Noether
//!
//! Physical-model sound synthesis with energy-conserving time integrators, after C. Touzé's
//! lecture "Intégrateurs temporels numériques conservatifs pour la dynamique non linéaire"
//! (2016; digest in `shared/docs/SEED.md`).
//!
//! The crate is an engine library plus the `noether` command-line tool. It has no plugin, GUI
//! or audio-device dependency. Layout, by concept:
//!
//! - [`schemes`]: time steppers for one oscillator (θ-family, exact, Duffing, impact) and for
//!   N-degree-of-freedom Hamiltonian systems (Störmer-Verlet, Runge-Kutta from Butcher tableaus,
//!   Gauss methods);
//! - [`analysis`]: measurements on simulated signals (frequency, cents, energy drift) and the
//!   closed-form solutions the schemes are checked against;
//! - [`lab`]: the lecture's experiments as runnable, reportable configurations;
//! - [`plot`]: PNG figures (waveforms, energies, phase portraits);
//! - [`models`]: physical models run by the renderer (stiff string against an obstacle);
//! - [`error`]: the parameter error type every constructor returns.
//!
//! Threading: everything here is plain data and `&mut self` methods; steppers never allocate in
//! `step`, so they can run on an audio thread once built.

pub mod analysis;
pub mod error;
pub mod models;
pub mod plot;
pub mod render;
pub mod scene;
pub mod schemes;

pub use error::ParamError;
