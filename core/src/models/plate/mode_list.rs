//! The transverse modes of a plate beyond its simulated basis, without a coupling tensor:
//! frequencies and mode shapes only, for the linear band above the simulation
//! ([`super::extension`]).
//!
//! The list is the basis's own enumeration continued (the same sorting, the same subspace):
//! its first `N_Φ` modes are the basis's, so a voice can take the modes past its truncation
//! from index `N_Φ` on. Worker thread (allocates; milliseconds for a few thousand modes).

use super::basis::BasisKey;
use super::spec::Position;
use crate::modal::circular::{circular_modes_with, Mode, Parity};
use crate::modal::rect::{transverse_modes, transverse_phi};

/// The mode shapes of a [`ModeList`].
#[derive(Debug, Clone)]
enum Shapes {
    /// Circular plate modes (radial function times `cos nθ` or `sin nθ`).
    Circular(Vec<Mode>),
    /// Simply supported rectangle of aspect `ly/lx`: the labels `(m, n)`.
    Rect {
        aspect: f64,
        labels: Vec<(u32, u32)>,
    },
}

/// The first `len` transverse modes of the unit plate of a [`BasisKey`], tensor-free.
///
/// Read-only once built; shared by the voices of a bank.
#[derive(Debug, Clone)]
pub struct ModeList {
    /// `λ_s²` (dimensionless pulsations of the unit plate, `ω_s = λ_s² √(D/ρh)/a²`),
    /// increasing.
    pub lambda2: Vec<f64>,
    shapes: Shapes,
}

impl ModeList {
    /// The first `count` modes of the plate `key` (its subspace, edge and aspect; its mode
    /// counts are ignored). Worker thread.
    pub fn build(key: &BasisKey, count: usize) -> Self {
        match *key {
            BasisKey::Circular(spec) => {
                let modes = circular_modes_with(spec.edge, spec.nu, count, spec.mirror);
                Self {
                    lambda2: modes.iter().map(|m| m.radial.lambda.powi(2)).collect(),
                    shapes: Shapes::Circular(modes),
                }
            }
            BasisKey::Rect { aspect, .. } => {
                let (labels, lambda2) = transverse_modes(aspect, count);
                Self {
                    lambda2,
                    shapes: Shapes::Rect { aspect, labels },
                }
            }
        }
    }

    /// Number of modes.
    pub fn len(&self) -> usize {
        self.lambda2.len()
    }

    /// Whether the list is empty.
    pub fn is_empty(&self) -> bool {
        self.lambda2.is_empty()
    }

    /// `Φ_s` of the unit plate at `p`, as [`super::basis::PlateBasis::phi_at`] reads it.
    /// Allocation-free; any thread.
    pub fn phi_at(&self, mode: usize, p: &Position) -> f64 {
        match &self.shapes {
            Shapes::Circular(m) => m[mode].eval(p.r.unwrap_or(0.0), p.angle.unwrap_or(0.0)),
            Shapes::Rect { aspect, labels } => transverse_phi(
                *aspect,
                labels[mode],
                p.x.unwrap_or(0.5),
                p.y.unwrap_or(0.5),
            ),
        }
    }

    /// The angular order `n_s` of a cosine mode of a circular plate (`None` otherwise).
    pub fn cosine_order(&self, mode: usize) -> Option<u32> {
        match &self.shapes {
            Shapes::Circular(m) => (m[mode].parity == Parity::Cos).then_some(m[mode].n),
            Shapes::Rect { .. } => None,
        }
    }
}
