//! What a pickup measures, for every model: one vocabulary for the plates' and the strings'
//! outputs, in scenes (`quantity = "velocity"`), the engine's banks and the models.
//!
//! Plain `Copy` data, read at build time.

use serde::{Deserialize, Serialize};

/// What a pickup measures at its point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Quantity {
    /// Transverse displacement (m): a plate's `w`, a string's `u^{n+1}(x)`.
    Displacement,
    /// Transverse velocity (m/s), the velocity of the model's energy: a plate's `δ_{t-} w`
    /// (see `PickupKind::VelocityBackward`), a string's `δ_{t-} u^{n+1}(x)`.
    #[default]
    Velocity,
}
