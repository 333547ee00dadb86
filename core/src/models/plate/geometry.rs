//! The plate's geometry and boundary conditions (`plate.shape`): a leaf type that the scene
//! table, the rest shapes and the modal bases share.

use serde::{Deserialize, Serialize};

/// Plate geometry and boundary conditions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PlateShape {
    /// Circular plate, free edge (gong); in-plane Airy modes of clamped type.
    CircularFree,
    /// Circular plate, clamped edge (cymbal-like plate held at its rim).
    CircularClamped,
    /// Rectangular plate, simply supported, in-plane edges free of stress.
    RectSs,
}

impl PlateShape {
    /// Whether the shape is circular (positions given as `r`, `angle`).
    pub fn is_circular(self) -> bool {
        !matches!(self, PlateShape::RectSs)
    }
}
