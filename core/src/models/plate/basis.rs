//! The one place a plate's dimensionless modal data are obtained, for scenes and the engine
//! alike: transverse `λ²` and in-plane `ζ⁴` of the unit plate, the coupling tensor, and the
//! mode shapes at a point, for circular (free or clamped, full or strike-mirror basis) and
//! simply supported rectangular plates.
//!
//! Circular bases come from the on-disk cache of [`crate::modal`]; a [`ModalCache`] also keeps
//! the last circular and rectangular basis in memory, so a worker that rebuilds voices for a
//! new position or material reuses them. Worker or main thread (allocates, may take seconds).

use super::spec::{PlateShape, Position, Symmetry};
use crate::error::ParamError;
use crate::modal::rect::{RectModes, RectSpec};
use crate::modal::{
    default_cache_dir, CacheOutcome, CircularEdge, CircularPlateSpec, Coordinates, CouplingTensor,
    ModalBasis, PlateModes, TensorStorage, UnitPoint,
};
use std::sync::Arc;

/// What selects a basis: the shape's modal problem and the mode counts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BasisKey {
    /// A circular plate (edge, Poisson ratio, counts, full or mirror subspace).
    Circular(CircularPlateSpec),
    /// A simply supported rectangle with aspect `ly/lx`, `N_Φ` and `N_Ψ`.
    Rect {
        /// `ly / lx`.
        aspect: f64,
        /// Transverse modes.
        n_phi: usize,
        /// In-plane modes (≥ 1).
        n_psi: usize,
    },
}

impl BasisKey {
    /// The key of `shape` with Poisson ratio `nu` (circular plates), aspect `ly/lx`
    /// (rectangles), `n_phi` transverse and `n_psi` in-plane modes (0 is built as 1: a linear
    /// plate ignores the tensor) and the modal subspace.
    pub fn new(
        shape: PlateShape,
        nu: f64,
        aspect: f64,
        n_phi: usize,
        n_psi: usize,
        symmetry: Symmetry,
    ) -> Result<Self, ParamError> {
        Ok(match shape {
            PlateShape::CircularFree | PlateShape::CircularClamped => {
                let edge = if shape == PlateShape::CircularFree {
                    CircularEdge::Free
                } else {
                    CircularEdge::Clamped
                };
                let spec = CircularPlateSpec::new(edge, nu, n_phi, n_psi.max(1), None)?;
                BasisKey::Circular(match symmetry {
                    Symmetry::Full => spec,
                    Symmetry::StrikeMirror => spec.mirror_symmetric(),
                })
            }
            PlateShape::RectSs => BasisKey::Rect {
                aspect,
                n_phi,
                n_psi: n_psi.max(1),
            },
        })
    }
}

/// Dimensionless modal data of a plate of unit size (`a = 1` or `lx = 1`, `D = ρh = 1`).
///
/// Read-only once built; shared (`Arc`) between the voices of a bank.
#[derive(Debug, Clone)]
pub struct PlateBasis {
    /// The coupling tensor `Ĥ^l_{i,j}`.
    pub coupling: Arc<CouplingTensor>,
    /// What the caches did (`hit`, `built and saved`, `memory`, ...), for reports.
    pub cache: String,
    shapes: Arc<dyn ModalBasis>,
}

impl PlateBasis {
    /// The basis of `modes` (any shape), with its tensor shared as `coupling` and the cache
    /// report `cache`.
    fn new(modes: Arc<dyn ModalBasis>, coupling: Arc<CouplingTensor>, cache: String) -> Self {
        Self {
            coupling,
            cache,
            shapes: modes,
        }
    }

    /// This basis with its coupling tensor in `storage` ([`CouplingTensor::with_storage`]:
    /// for [`TensorStorage::Single`] every value rounded to `f32` once and every layout
    /// rebuilt from the rounded values, so the model sees one tensor). Call it once per build,
    /// before the [`super::PlateModel`]s that share the tensor are made; the returned basis
    /// shares its new tensor (`Arc`) like the old one. No copy when the tensor already has
    /// `storage`. Worker thread (allocates a copy of the tensor and rebuilds its layouts:
    /// `O(nnz)`, milliseconds for 10⁵ entries). Errors: a tensor value outside the `f32` range.
    pub fn with_tensor_storage(mut self, storage: TensorStorage) -> Result<Self, ParamError> {
        if self.coupling.storage() != storage {
            self.coupling = Arc::new(self.coupling.with_storage(storage)?);
        }
        Ok(self)
    }

    /// `λ_s²` of each transverse mode (`ω_s = λ_s² √(D/ρh) / a²`).
    pub fn lambda2(&self) -> &[f64] {
        self.shapes.lambda2()
    }

    /// `ζ_l⁴` of each in-plane mode.
    pub fn zeta4(&self) -> &[f64] {
        self.shapes.zeta4()
    }

    /// `Φ_s` of the unit plate at `p`: `(r, angle)` on circular plates, the angle in the
    /// basis's own frame (a mirror basis has its strike at angle 0); `(x, y)` as fractions of
    /// the sides on rectangles. Missing coordinates read as 0 (r, angle) or ½ (x, y).
    pub fn phi_at(&self, mode: usize, p: &Position) -> f64 {
        let point = match self.shapes.coordinates() {
            Coordinates::Polar => UnitPoint::polar(p.r.unwrap_or(0.0), p.angle.unwrap_or(0.0)),
            Coordinates::Sides => UnitPoint::sides(p.x.unwrap_or(0.5), p.y.unwrap_or(0.5)),
        };
        self.shapes.phi_at(mode, point)
    }

    /// `Φ_s(p)` of every transverse mode.
    pub fn phi_all(&self, p: &Position) -> Vec<f64> {
        (0..self.n_phi()).map(|s| self.phi_at(s, p)).collect()
    }

    /// The angular order `n_s` of a cosine mode `R_s(r) cos(n_s θ)` of a circular basis
    /// (`None` otherwise): see [`ModalBasis::cosine_order`].
    pub fn cosine_order(&self, mode: usize) -> Option<u32> {
        self.shapes.cosine_order(mode)
    }

    /// Number of transverse modes.
    pub fn n_phi(&self) -> usize {
        self.shapes.n_phi()
    }
}

/// A rectangle kept in memory: (aspect bits, N_Φ, N_Ψ), modes, tensor.
type RectEntry = ((u64, usize, usize), Arc<RectModes>, Arc<CouplingTensor>);

/// The last circular and rectangular basis built, kept in memory between builds (worker
/// thread). A fresh cache still reads circular bases from the disk cache.
#[derive(Default)]
pub struct ModalCache {
    circular: Option<(CircularPlateSpec, Arc<PlateModes>, Arc<CouplingTensor>)>,
    rect: Option<RectEntry>,
}

impl std::fmt::Debug for ModalCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ModalCache")
            .field("circular", &self.circular.as_ref().map(|c| c.0))
            .field("rect", &self.rect.as_ref().map(|r| r.0))
            .finish()
    }
}

impl ModalCache {
    /// The basis for `key`: from memory when it is the last one built for its shape, else from
    /// the disk cache (circular) or computed (rectangles build faster than their tensor reads
    /// back, so they are not cached on disk).
    pub fn basis(&mut self, key: &BasisKey) -> Result<PlateBasis, ParamError> {
        match *key {
            BasisKey::Circular(spec) => {
                let (modes, coupling, cache) = match &self.circular {
                    Some((s, m, c)) if *s == spec => (m.clone(), c.clone(), "memory".to_string()),
                    _ => {
                        let (modes, outcome) =
                            PlateModes::load_or_build(&spec, &default_cache_dir())?;
                        let cache = match outcome {
                            CacheOutcome::Hit => "hit".to_string(),
                            CacheOutcome::Built => "built and saved".to_string(),
                            CacheOutcome::Rebuilt(why) => format!("rebuilt ({why})"),
                            CacheOutcome::NotSaved(why) => format!("built, not saved ({why})"),
                        };
                        let coupling = Arc::new(modes.coupling.clone());
                        let modes = Arc::new(modes);
                        self.circular = Some((spec, modes.clone(), coupling.clone()));
                        (modes, coupling, cache)
                    }
                };
                Ok(PlateBasis::new(modes, coupling, cache))
            }
            BasisKey::Rect {
                aspect,
                n_phi,
                n_psi,
            } => {
                let k = (aspect.to_bits(), n_phi, n_psi);
                let (modes, coupling, cache) = match &self.rect {
                    Some((kk, m, c)) if *kk == k => (m.clone(), c.clone(), "memory".to_string()),
                    _ => {
                        let modes = RectModes::build(&RectSpec::new(aspect, n_phi, n_psi))
                            .map_err(|e| {
                                ParamError::new("modes", n_phi, format!("a buildable basis ({e})"))
                            })?;
                        let coupling = Arc::new(modes.coupling.clone());
                        let modes = Arc::new(modes);
                        self.rect = Some((k, modes.clone(), coupling.clone()));
                        (modes, coupling, "not cached (built directly)".to_string())
                    }
                };
                Ok(PlateBasis::new(modes, coupling, cache))
            }
        }
    }
}
