//! # noether-core
//!
//! The real-time core of Noether: physical-model sound synthesis with energy-conserving time
//! integrators, after C. Touzé's lecture "Intégrateurs temporels numériques conservatifs pour la
//! dynamique non linéaire" (2016; digest in `docs/SEED.md`).
//!
//! Layers, each depending only on those above it (checked, with the absence of import cycles
//! between files, by `scripts/check-layers.py`):
//!
//! - [`error`]: the parameter error type every constructor returns;
//! - [`schemes`]: time steppers for one oscillator (θ-family, exact, Duffing, impact) and for
//!   N-degree-of-freedom Hamiltonian systems (Störmer-Verlet, Runge-Kutta from Butcher tableaus,
//!   Gauss methods);
//! - [`analysis`]: closed-form solutions, the schemes' dispersion, frequency and energy-drift
//!   measurements;
//! - [`modal`]: dimensionless modal bases of plates (Φ, Ψ) behind one trait
//!   ([`modal::ModalBasis`]): `modal::circular`, `modal::rect`, and their coupling tensor with
//!   the streaming kernels (`modal::tensor`);
//! - [`models`]: the instrument models (modal von Kármán plate, stiff string with contact), their
//!   typed specifications (`spec`) and the [`models::source::RenderSource`] trait;
//! - [`engine`]: the real-time engine (voices, banks built on a worker thread, parameters,
//!   presets, the audio-thread loop).
//!
//! No CLI, plotting, WAV or audio-device dependency: the offline tool (`noether`), the plugin
//! and the test kit build on this crate.
//!
//! Threading: everything here is plain data and `&mut self` methods; steppers never allocate in
//! `step`, so they can run on an audio thread once built.

pub mod analysis;
pub mod clock;
pub mod engine;
pub mod error;
pub mod modal;
pub mod models;
pub mod schemes;

pub use error::ParamError;
