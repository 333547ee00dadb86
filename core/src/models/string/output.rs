//! Output channels of the string model: displacement or velocity at any point (interpolated
//! from the grid or summed from the modes), and the total force on the obstacle.
//!
//! Descriptions are validated and resolved (weights, mode-shape vectors allocated) on the
//! control thread at build time; [`ResolvedOutput::read`] runs on the audio thread without
//! allocating.

use super::params::StringParams;
use crate::error::ParamError;
use serde::{Deserialize, Serialize};

pub use crate::models::quantity::Quantity;

/// How a pickup evaluates the field between nodes (scenes: `readout = "grid"` or `"modal"`).
///
/// Read on the control thread at build time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Readout {
    /// Linear interpolation between the two nearest grid values (`u_0 = u_N = 0`); O(1) a step.
    #[default]
    Grid,
    /// Modal sum `Σ_j q_j φ_j(x)`: exact for the modal field; O(N) a step.
    Modal,
}

/// One output channel.
///
/// Read on the control thread at build time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OutputChannel {
    /// A pickup at `position` (m, `0 < position < L`).
    Pickup {
        /// Position in m.
        position: f64,
        /// Displacement or velocity.
        quantity: Quantity,
        /// Grid interpolation or modal sum.
        readout: Readout,
    },
    /// Total force the string exerts on the obstacle, `Δx Σ_i f_i^n` in N (≥ 0, directed towards
    /// `-u`; the obstacle pushes the string with the opposite force).
    ObstacleForce,
}

/// An output channel resolved for one grid.
///
/// Built on the control thread; read on the audio thread.
#[derive(Debug, Clone, PartialEq)]
pub enum ResolvedOutput {
    /// Linear interpolation: value = `(1-w) v[left] + w v[left+1]` over the node values with the
    /// boundary zeros; `left` is a node number `0..N-1` (node 0 is the end `x = 0`).
    Grid {
        /// Node number `i` of the left neighbour (0..=N-1).
        left: usize,
        /// Weight `w ∈ [0, 1)` of the right neighbour.
        weight: f64,
        /// Displacement or velocity.
        quantity: Quantity,
    },
    /// Modal sum with `shape[j-1] = φ_j(x)` (m^-1/2).
    Modal {
        /// Mode shapes at the pickup.
        shape: Vec<f64>,
        /// Displacement or velocity.
        quantity: Quantity,
    },
    /// Total obstacle force.
    ObstacleForce,
}

/// The state an output reads: interior grid values and modal coordinates at `n+1` and their
/// increments since `n`.
pub struct FieldView<'a> {
    /// `u^{n+1}` at nodes `1..N-1` (m).
    pub u_now: &'a [f64],
    /// `u^n` at nodes `1..N-1` (m).
    pub u_prev: &'a [f64],
    /// `q^{n+1}` (m^3/2).
    pub q: &'a [f64],
    /// `Δ^{n+1} = q^{n+1} - q^n` (m^3/2).
    pub dq: &'a [f64],
    /// Time step in s.
    pub h: f64,
    /// Total obstacle force of the last step (N).
    pub obstacle_force: f64,
}

impl OutputChannel {
    /// Validates against the string `p` and precomputes weights or mode shapes (allocates).
    pub fn resolve(&self, p: &StringParams, index: usize) -> Result<ResolvedOutput, ParamError> {
        match *self {
            OutputChannel::ObstacleForce => Ok(ResolvedOutput::ObstacleForce),
            OutputChannel::Pickup {
                position,
                quantity,
                readout,
            } => {
                let x = p.check_position(&format!("outputs[{index}].position"), position)?;
                Ok(match readout {
                    Readout::Grid => {
                        let s = x / p.dx();
                        let left = (s.floor() as usize).min(p.intervals - 1);
                        ResolvedOutput::Grid {
                            left,
                            weight: s - left as f64,
                            quantity,
                        }
                    }
                    Readout::Modal => ResolvedOutput::Modal {
                        shape: (1..=p.modes()).map(|j| p.mode_shape(j, x)).collect(),
                        quantity,
                    },
                })
            }
        }
    }
}

impl ResolvedOutput {
    /// Interior indices (`i - 1`) of the grid nodes this channel reads (none for modal sums and
    /// the obstacle force; the boundary nodes `0` and `N` are always zero and never listed).
    pub fn grid_nodes(&self, intervals: usize) -> impl Iterator<Item = usize> {
        let left = match self {
            ResolvedOutput::Grid { left, .. } => Some(*left),
            _ => None,
        };
        left.into_iter()
            .flat_map(|l| [l, l + 1])
            .filter(move |&i| i >= 1 && i < intervals)
            .map(|i| i - 1)
    }

    /// The channel's value for the current state.
    pub fn read(&self, v: &FieldView<'_>) -> f64 {
        let node = |a: &[f64], i: usize| if i == 0 || i > a.len() { 0.0 } else { a[i - 1] };
        match self {
            ResolvedOutput::ObstacleForce => v.obstacle_force,
            ResolvedOutput::Grid {
                left,
                weight,
                quantity,
            } => {
                let at = |a: &[f64]| (1.0 - weight) * node(a, *left) + weight * node(a, left + 1);
                match quantity {
                    Quantity::Displacement => at(v.u_now),
                    Quantity::Velocity => (at(v.u_now) - at(v.u_prev)) / v.h,
                }
            }
            ResolvedOutput::Modal { shape, quantity } => {
                let coords = match quantity {
                    Quantity::Displacement => v.q,
                    Quantity::Velocity => v.dq,
                };
                let s = crate::models::dot(shape, coords);
                match quantity {
                    Quantity::Displacement => s,
                    Quantity::Velocity => s / v.h,
                }
            }
        }
    }
}
