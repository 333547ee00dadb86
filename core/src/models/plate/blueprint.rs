//! What every plate build derives from its [`PlateSpec`] before it builds a model: the basis's
//! key and the basis itself (through a [`ModalCache`]), the frame the basis is written in, the
//! mode values at the spec's positions, the rest shape's projection and the plate's modes
//! continued past the basis for the band above.
//!
//! The scene's voice ([`super::voice::PlateVoice::build`]) and the instrument's bank
//! (`engine/plate_bank.rs`, which first turns its parameter values into a `PlateSpec`) both
//! start here, so a plate is named, keyed, placed and shaped one way whichever path plays it.
//!
//! **Frame.** A circular basis in the strike-mirror subspace holds the cosine modes
//! `Φ_s = R_s(r) cos(n_s θ)`, symmetric about the strike's diameter: the strike is put at angle 0
//! and every other angle is read relative to the strike's ([`PlateBlueprint::in_frame`]).
//!
//! Threads: worker (or the CLI's main) thread; allocates.

use super::basis::{BasisKey, ModalCache, PlateBasis};
use super::mode_list::ModeList;
use super::rest_projection::project;
use super::rest_shape::ShapePart;
use super::spec::{Excitation, PlateShape, PlateSpec, Position, Symmetry};
use crate::error::ParamError;

impl PlateSpec {
    /// The aspect ratio `ly/lx` (rectangles; 1 for circular plates).
    pub fn aspect(&self) -> f64 {
        self.ly.unwrap_or(1.0) / self.lx.unwrap_or(1.0)
    }

    /// The key of this plate's basis with `n_phi` transverse and `n_psi` in-plane modes (the
    /// engine's memory fit asks for several counts before it builds one).
    pub fn basis_key_for(&self, n_phi: usize, n_psi: usize) -> Result<BasisKey, ParamError> {
        BasisKey::new(
            self.shape,
            self.material.poisson,
            self.aspect(),
            n_phi,
            n_psi,
            self.symmetry,
        )
    }

    /// The key of this plate's basis (its own mode counts).
    pub fn basis_key(&self) -> Result<BasisKey, ParamError> {
        self.basis_key_for(self.n_phi, self.n_psi)
    }

    /// Angle (rad) of the excitation point on a circular plate; 0 for initial conditions
    /// (whose modes are given in the basis's own frame) and on rectangles.
    pub fn excitation_angle(&self) -> f64 {
        match self.excitation {
            Excitation::Strike { at, .. }
            | Excitation::Impulse { at, .. }
            | Excitation::Mallet { at, .. } => at.angle.unwrap_or(0.0),
            Excitation::Initial { .. } => 0.0,
        }
    }
}

/// A plate's basis in its frame, with what its spec places on it (module doc).
#[derive(Debug, Clone)]
pub struct PlateBlueprint {
    /// The basis's key (shape, `ν`, aspect, mode counts, subspace).
    pub key: BasisKey,
    /// The dimensionless basis of the unit plate (`a = 1`, `D = ρh = 1`).
    pub basis: PlateBasis,
    /// The strike's angle (rad) that the frame puts at 0: the excitation's angle on a circular
    /// strike-mirror basis, 0 otherwise.
    pub theta0: f64,
    /// Geometry: circular or rectangular, the edge.
    pub shape: PlateShape,
    /// Length scale `a` (m): the radius, or `lx` for rectangles.
    pub length: f64,
    /// Aspect ratio `ly/lx` (rectangles; 1 otherwise).
    pub aspect: f64,
}

impl PlateBlueprint {
    /// The basis of `spec` (its own mode counts), computed or taken from `cache`. `spec` is
    /// assumed validated ([`PlateSpec::validate`]). Errors name the field of the key.
    pub fn new(spec: &PlateSpec, cache: &mut ModalCache) -> Result<Self, ParamError> {
        let key = spec.basis_key()?;
        let basis = cache.basis(&key)?;
        let theta0 = if spec.shape.is_circular() && spec.symmetry == Symmetry::StrikeMirror {
            spec.excitation_angle()
        } else {
            0.0
        };
        Ok(Self {
            key,
            basis,
            theta0,
            shape: spec.shape,
            length: spec.length_scale(),
            aspect: spec.aspect(),
        })
    }

    /// `p` in the basis's frame: on a circular plate every angle is taken relative to the
    /// strike's ([`Self::theta0`]); rectangles are unchanged.
    pub fn in_frame(&self, p: &Position) -> Position {
        if self.shape.is_circular() {
            Position {
                angle: Some(p.angle.unwrap_or(0.0) - self.theta0),
                ..*p
            }
        } else {
            *p
        }
    }

    /// `Φ̂_s` of every mode of the unit plate at `p` (given in the plate's own frame; 1/m on a
    /// plate of size `a` after dividing by `a`).
    pub fn values_at(&self, p: &Position) -> Vec<f64> {
        self.basis.phi_all(&self.in_frame(p))
    }

    /// `a_k = ∫_S w0 Φ_k dS` (m²) of the summed rest-shape `parts` at the plate's size
    /// ([`project`]); `length` overrides the size (the engine projects per unit size and
    /// rise, and scales per note).
    pub fn rest_shape(&self, parts: &[ShapePart], length: Option<f64>) -> Vec<f64> {
        project(
            parts,
            &self.basis,
            self.shape,
            length.unwrap_or(self.length),
            self.aspect,
        )
    }

    /// The plate's modes continued past the basis, as many as reach `top_hz` at the density
    /// of the band above ([`super::extension::mode_count`]), in the basis's subspace and
    /// order. Worker thread; seconds for large lists on a cold start.
    pub fn modes_above(&self, top_hz: f64) -> ModeList {
        ModeList::build(
            &self.key,
            super::extension::mode_count(self.basis.n_phi(), top_hz),
        )
    }
}
