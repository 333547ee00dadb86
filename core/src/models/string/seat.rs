//! The seat of a string on a moving bridge: where and how stiffly the string is tied to the
//! bridge under it ([`crate::models::network`]; the string's side of the coupled step is in
//! `model/seat_solve.rs`).

use crate::error::{check_positive, ParamError};
use crate::models::string::params::StringParams;

/// Where and how stiffly a string sits on its bridge.
///
/// Read on the control thread when the string is built.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeatSpec {
    /// Position of the seat along the string in m (`0 < position < L`; the nearest grid node
    /// is used, which must not carry the obstacle).
    pub position: f64,
    /// Spring stiffness `K` in N/m (> 0). Stiff enough that the string's node follows the
    /// bridge below its lowest partials; the scheme is stable for any value.
    pub stiffness: f64,
}

impl SeatSpec {
    /// The 0-based interior node of the seat; validates the spec against the string and its
    /// obstacle nodes `samples`.
    pub(crate) fn node(
        &self,
        p: &StringParams,
        samples: &[(usize, f64)],
    ) -> Result<usize, ParamError> {
        check_positive("seat.stiffness", self.stiffness)?;
        let x = p.check_position("seat.position", self.position)?;
        let node = ((x / p.dx()).round() as usize).clamp(1, p.intervals - 1) - 1;
        if samples.iter().any(|s| s.0 == node) {
            return Err(ParamError::new(
                "seat.position",
                self.position,
                format!(
                    "a node without obstacle (the nearest node, x = {} m, carries the obstacle)",
                    (node + 1) as f64 * p.dx()
                ),
            ));
        }
        Ok(node)
    }
}

/// The built seat (audio thread).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Seat {
    /// 0-based interior node.
    pub(crate) node: usize,
    /// Its row among the stored rows (right after the obstacle nodes' rows).
    pub(crate) row: usize,
    /// `K` in N/m.
    pub(crate) stiffness: f64,
    /// The seat force of the last step as a density at its node, `P/Δx` in N/m.
    pub(crate) force: f64,
}

impl Seat {
    /// The seat at `node`, its row after the `obstacle_nodes` obstacle rows.
    pub(crate) fn new(spec: &SeatSpec, node: usize, obstacle_nodes: usize) -> Self {
        Self {
            node,
            row: obstacle_nodes,
            stiffness: spec.stiffness,
            force: 0.0,
        }
    }
}
