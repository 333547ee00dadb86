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
//! - [`models`]: physical models built on the schemes (modal von Kármán plate);
//! - [`analysis`]: measurements on simulated signals (frequency, cents, energy drift) and the
//!   closed-form solutions the schemes are checked against;
//! - [`lab`]: the lecture's experiments as runnable, reportable configurations;
//! - [`modal`]: dimensionless modal bases of plates (Φ, Ψ) and their coupling tensors;
//! - [`models`]: the instrument models (modal von Kármán plate, stiff string with contact);
//! - [`scene`], [`render`]: scene files and the offline render loop (WAV, resampling);
//! - [`plot`]: PNG figures (waveforms, energies, phase portraits, spectrograms);
//! - [`modal_rect`]: modal data of the simply supported rectangular von Kármán plate (closed-form
//!   transverse modes, Rayleigh-Ritz Airy modes, coupling tensor);
//! - [`stress`]: sweeps of every model and scheme over extreme parameters (`tests/extremes.rs`,
//!   `noether stress`);
//! - [`soak`]: the real-time soak, a seeded random host driving the engine (`tests/soak.rs`,
//!   `examples/soak.rs`);
//! - [`error`]: the parameter error type every constructor returns.
//!
//! Threading: everything here is plain data and `&mut self` methods; steppers never allocate in
//! `step`, so they can run on an audio thread once built.

pub mod analysis;
pub mod engine;
pub mod error;
pub mod lab;
pub mod modal;
pub mod modal_rect;
pub mod models;
pub mod plot;
pub mod render;
pub mod scene;
pub mod schemes;
pub mod soak;
pub mod stress;

pub use error::ParamError;
