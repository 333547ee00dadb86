//! The one place a plate's dimensionless modal data are obtained, for scenes and the engine
//! alike: transverse `λ²` and in-plane `ζ⁴` of the unit plate, the coupling tensor, and the
//! mode shapes at a point, for circular (free or clamped, full or strike-mirror basis) and
//! simply supported rectangular plates.
//!
//! Circular bases come from the on-disk cache of [`crate::modal`]; a [`ModalCache`] also keeps
//! the last circular and rectangular basis in memory, so a worker that rebuilds voices for a
//! new position or material reuses them. Worker or main thread (allocates, may take seconds).

use super::shared::Registry;
use super::spec::{PlateShape, Position, Symmetry};
use crate::error::ParamError;
use crate::modal::circular::angular::{factors, Parity};
use crate::modal::circular::Mode;
use crate::modal::rect::{transverse_modes, RectModes, RectSpec};
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
/// What keys a rectangular basis: `(aspect bits, N_Φ, N_Ψ)`.
type RectKey = (u64, usize, usize);
type RectEntry = (RectKey, Arc<RectModes>, Arc<CouplingTensor>);

impl BasisKey {
    /// The coupling entries the basis of this key stores (`j ≤ i`), counted from the
    /// selection rules before anything is built, so a model over the memory cap can be
    /// reduced instead of built (`engine/memory.rs`). Circular plates: exact for the rule
    /// (`H^l_ij` is computed iff the angular factors do not both vanish, `modal::circular::
    /// assemble`), from the mode lists alone (Bessel roots, no integrals). Rectangles: an upper
    /// bound, every in-plane row counted with the largest of the four parity classes of
    /// pairs (`modal::rect::coupling`: `H^l_ij` vanishes unless the pair's parities in x and y
    /// equal `Ψ_l`'s). Worker thread; milliseconds (the circular mode lists: a fraction of a
    /// second for 2000 modes).
    pub fn predicted_entries(&self) -> usize {
        let counts = match *self {
            BasisKey::Circular(spec) => (spec.n_phi, spec.n_psi),
            BasisKey::Rect { n_phi, n_psi, .. } => (n_phi, n_psi),
        };
        self.predicted_entries_of(&[counts])[0]
    }

    /// [`Self::predicted_entries`] of the truncations `(N_Φ, N_Ψ)` of this basis to its first
    /// modes (a bank's tiers), one count each.
    pub fn predicted_entries_of(&self, tiers: &[(usize, usize)]) -> Vec<usize> {
        match *self {
            BasisKey::Circular(spec) => {
                let (phi, psi) = PlateModes::modes(&spec);
                tiers
                    .iter()
                    .map(|&(n, m)| {
                        circular_entries(&phi[..n.min(phi.len())], &psi[..m.min(psi.len())])
                    })
                    .collect()
            }
            BasisKey::Rect { aspect, n_phi, .. } => {
                let (labels, _) = transverse_modes(aspect, n_phi);
                tiers
                    .iter()
                    .map(|&(n, m)| rect_entries(&labels[..n.min(labels.len())], m))
                    .collect()
            }
        }
    }
}

/// Entries of a circular basis of transverse modes `phi` and in-plane modes `psi` by the
/// angular selection rule (module `modal::circular::assemble`).
fn circular_entries(phi: &[Mode], psi: &[Mode]) -> usize {
    // Transverse modes grouped by angular order and parity.
    let mut groups: Vec<((u32, Parity), usize)> = Vec::new();
    for m in phi {
        let g = (m.n, m.parity);
        match groups.iter_mut().find(|(k, _)| *k == g) {
            Some((_, c)) => *c += 1,
            None => groups.push((g, 1)),
        }
    }
    let mut total = 0;
    for l in psi {
        let gl = (l.n, l.parity);
        for (a, &(ga, ca)) in groups.iter().enumerate() {
            for &(gb, cb) in &groups[..=a] {
                if factors(gl, ga, gb) != (0.0, 0.0) {
                    total += if ga == gb { ca * (ca + 1) / 2 } else { ca * cb };
                }
            }
        }
    }
    total
}

/// An upper bound of the entries of a rectangle's basis of transverse modes `labels`
/// (`(m, n)`) and `n_psi` in-plane modes: each row counted with the largest parity class of
/// pairs (module `modal::rect::coupling`).
fn rect_entries(labels: &[(u32, u32)], n_psi: usize) -> usize {
    let mut class = [0usize; 4];
    for &(m, n) in labels {
        class[((m % 2) * 2 + n % 2) as usize] += 1;
    }
    // Pairs (j ≤ i) by the parities (x, y) of m_i + m_j and n_i + n_j.
    let mut pairs = [0usize; 4];
    for a in 0..4 {
        for b in 0..=a {
            pairs[a ^ b] += if a == b {
                class[a] * (class[a] + 1) / 2
            } else {
                class[a] * class[b]
            };
        }
    }
    n_psi * pairs.iter().copied().max().unwrap_or(0)
}

/// Circular bases other engines of the process hold (`shared`), by spec.
static CIRCULAR_MODES: Registry<CircularPlateSpec, PlateModes> = Registry::new();
/// Their tensors.
static CIRCULAR_TENSORS: Registry<CircularPlateSpec, CouplingTensor> = Registry::new();
/// Rectangular bases other engines hold, by (aspect bits, `N_Φ`, `N_Ψ`).
static RECT_MODES: Registry<RectKey, RectModes> = Registry::new();
/// Their tensors.
static RECT_TENSORS: Registry<RectKey, CouplingTensor> = Registry::new();
/// Tier tensors in single storage other engines' banks hold, by basis and `(N_Φ, N_Ψ)`.
static TIER_TENSORS: Registry<(BasisKey, usize, usize), CouplingTensor> = Registry::new();

/// The tier `(n_phi, n_psi)` of basis `key` in single storage, shared with every engine of
/// the process that holds it (`shared`), or built by `build` (the basis's tensor in single
/// storage, or a truncation of it): a plugin's instances of the same plate keep one copy of
/// each tier. Worker thread.
pub fn shared_tier(
    key: &BasisKey,
    (n_phi, n_psi): (usize, usize),
    build: impl FnOnce() -> Result<CouplingTensor, ParamError>,
) -> Result<Arc<CouplingTensor>, ParamError> {
    TIER_TENSORS.get_or_build((*key, n_phi, n_psi), build)
}

/// Moves the coupling tensor out of a freshly built basis `modes` (leaving an empty tensor of
/// no in-plane rows in it), so the cache and the voices share one copy instead of two
/// (`PlateBasis::coupling` is the tensor every user reads). Worker thread.
fn split_coupling<M>(
    mut modes: M,
    field: impl Fn(&mut M) -> &mut CouplingTensor,
) -> (Arc<M>, Arc<CouplingTensor>) {
    let slot = field(&mut modes);
    let empty = CouplingTensor::from_parts(slot.n_phi(), 0, vec![0], vec![], vec![], vec![]);
    let coupling = match empty {
        Ok(empty) => std::mem::replace(slot, empty),
        // Not reached (an empty tensor is valid); keep both copies rather than fail.
        Err(_) => slot.clone(),
    };
    (Arc::new(modes), Arc::new(coupling))
}

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
    /// Heap bytes of the coupling tensors the cache keeps. Any thread that owns it.
    pub fn heap_bytes(&self) -> usize {
        let circular = self
            .circular
            .as_ref()
            .map_or(0, |(_, m, c)| m.coupling.heap_bytes() + c.heap_bytes());
        let rect = self
            .rect
            .as_ref()
            .map_or(0, |(_, m, c)| m.coupling.heap_bytes() + c.heap_bytes());
        circular + rect
    }

    /// The basis for `key`: from memory when it is the last one built for its shape, else from
    /// the disk cache (circular) or computed (rectangles build faster than their tensor reads
    /// back, so they are not cached on disk).
    pub fn basis(&mut self, key: &BasisKey) -> Result<PlateBasis, ParamError> {
        let (modes, coupling, cache): (Arc<dyn ModalBasis>, _, _) = match *key {
            BasisKey::Circular(spec) => {
                let shared = (&CIRCULAR_MODES, &CIRCULAR_TENSORS);
                let (m, c, cache) = lookup(
                    &mut self.circular,
                    shared,
                    spec,
                    |m| &mut m.coupling,
                    || {
                        let (modes, outcome) =
                            PlateModes::load_or_build(&spec, &default_cache_dir())?;
                        let cache = match outcome {
                            CacheOutcome::Hit => "hit".to_string(),
                            CacheOutcome::Built => "built and saved".to_string(),
                            CacheOutcome::Rebuilt(why) => format!("rebuilt ({why})"),
                            CacheOutcome::NotSaved(why) => format!("built, not saved ({why})"),
                        };
                        Ok((modes, cache))
                    },
                )?;
                (m, c, cache)
            }
            BasisKey::Rect {
                aspect,
                n_phi,
                n_psi,
            } => {
                let k = (aspect.to_bits(), n_phi, n_psi);
                let shared = (&RECT_MODES, &RECT_TENSORS);
                let (m, c, cache) = lookup(
                    &mut self.rect,
                    shared,
                    k,
                    |m| &mut m.coupling,
                    || {
                        let modes = RectModes::build(&RectSpec::new(aspect, n_phi, n_psi))
                            .map_err(|e| {
                                ParamError::new("modes", n_phi, format!("a buildable basis ({e})"))
                            })?;
                        Ok((modes, "not cached (built directly)".to_string()))
                    },
                )?;
                (m, c, cache)
            }
        };
        Ok(PlateBasis::new(modes, coupling, cache))
    }
}

/// One shape's basis for `key` and the cache's report: the cache's own entry `own` when it is
/// for `key` ("memory"), else another engine's from the registries `shared` ("shared with
/// another engine"), else built by `build` (the basis and its report), its tensor moved out
/// of it ([`split_coupling`], `coupling_of` naming the field) and recorded in `own` and
/// `shared`. Worker thread.
fn lookup<K: PartialEq + Copy, M>(
    own: &mut Option<(K, Arc<M>, Arc<CouplingTensor>)>,
    shared: (&Registry<K, M>, &Registry<K, CouplingTensor>),
    key: K,
    coupling_of: impl Fn(&mut M) -> &mut CouplingTensor,
    build: impl FnOnce() -> Result<(M, String), ParamError>,
) -> Result<(Arc<M>, Arc<CouplingTensor>, String), ParamError> {
    if let Some((k, m, c)) = own.as_ref() {
        if *k == key {
            return Ok((m.clone(), c.clone(), "memory".to_string()));
        }
    }
    let (modes, coupling, cache) = match shared.0.get(&key).zip(shared.1.get(&key)) {
        Some((m, c)) => (m, c, "shared with another engine".to_string()),
        None => {
            let (modes, cache) = build()?;
            let (m, c) = split_coupling(modes, coupling_of);
            shared.0.insert(key, &m);
            shared.1.insert(key, &c);
            (m, c, cache)
        }
    };
    *own = Some((key, modes.clone(), coupling.clone()));
    Ok((modes, coupling, cache))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The count from the selection rules against the built tensors: exact for circular
    /// plates (free and clamped, full and mirror bases), an upper bound within 25 % for
    /// rectangles (the parity class of each in-plane row is not known before the Airy modes
    /// are built). Small bases (seconds at most, from the disk cache after the first run).
    #[test]
    fn predicted_entries_match_the_built_tensors() {
        let cases = [
            (PlateShape::CircularFree, 60, 10, Symmetry::StrikeMirror),
            (PlateShape::CircularFree, 40, 8, Symmetry::Full),
            (PlateShape::CircularClamped, 50, 12, Symmetry::StrikeMirror),
            (PlateShape::RectSs, 60, 10, Symmetry::Full),
            (PlateShape::RectSs, 400, 60, Symmetry::Full),
            (PlateShape::CircularFree, 500, 60, Symmetry::StrikeMirror),
            (
                PlateShape::CircularClamped,
                800,
                100,
                Symmetry::StrikeMirror,
            ),
        ];
        let mut cache = ModalCache::default();
        for (shape, n_phi, n_psi, sym) in cases {
            let key = BasisKey::new(shape, 0.3, 0.8, n_phi, n_psi, sym).unwrap();
            let predicted = key.predicted_entries();
            let basis = cache.basis(&key).unwrap();
            let built = basis.coupling.nnz();
            let single = basis.coupling.with_storage(TensorStorage::Single).unwrap();
            eprintln!(
                "{shape:?} {n_phi}x{n_psi}: nnz {built}, double {:.1} B/entry, single {:.1} B/entry",
                basis.coupling.heap_bytes() as f64 / built as f64,
                single.heap_bytes() as f64 / built as f64
            );
            match shape {
                PlateShape::RectSs => assert!(
                    built <= predicted && predicted as f64 <= 1.25 * built as f64,
                    "{shape:?}: predicted {predicted}, built {built}"
                ),
                _ => assert_eq!(predicted, built, "{shape:?} {sym:?}"),
            }
        }
    }
}
