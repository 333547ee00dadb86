//! Obstacle profiles `g(x)` and their sampling on the grid.
//!
//! Convention (Issanchou et al. 2017, SEED.md 3.2): the obstacle lies below the string, at
//! height `g(x)` (m, same axis as `u`); the string penetrates it where `η = g - u > 0`, and the
//! contact force density `f = K [η]_+^α` (N/m) is then positive, pushing the string towards
//! `+u`, away from the obstacle. Nodes where a profile is not defined have no obstacle and are
//! left out of the contact solve entirely.
//!
//! Profiles are plain data built on the control thread; [`Obstacle::sample`] turns one into the
//! list of `(node, g)` pairs the model keeps (allocated at build time).

use super::params::StringParams;
use crate::error::{check_finite, check_non_negative, ParamError};

/// A curved (jawari-like) bridge near the end `x = 0`:
/// `g(x) = height - curvature·(x - position)²` for `0 < x ≤ extent`, no obstacle beyond.
///
/// The lecture's sitar bridge `g(x) = a x²` is `position = 0`, `height = 0`,
/// `curvature = -a`; a crest that touches the string's rest line at the termination and falls
/// away from it (so the string wraps onto it when it moves towards `-u`) has `curvature > 0`.
/// Read on the control thread.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SitarBridge {
    /// Abscissa of the parabola's apex in m (finite, may be 0, the termination).
    pub position: f64,
    /// Curvature in m⁻¹ (finite, any sign; see the type's doc for the lecture's sign).
    pub curvature: f64,
    /// Apex height in m (finite).
    pub height: f64,
    /// The bridge covers `0 < x ≤ extent`, in m (`0 < extent < L`).
    pub extent: f64,
}

/// An obstacle description, sampled on the grid when the model is built.
///
/// Read on the control thread.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Obstacle {
    /// No obstacle: the model is linear.
    #[default]
    None,
    /// Curved sitar bridge.
    Sitar(SitarBridge),
    /// Tanpura-like point bridge: flat top at `height` (m) around `position` (m); `width` (m,
    /// ≥ 0) is the top's length — `0` puts the obstacle on the single node nearest to
    /// `position`, otherwise every node with `|x - position| ≤ width/2` (at least the nearest).
    /// The lecture's tanpura is `position = 6e-3`, a point contact 6 mm from the end.
    Point {
        /// Centre of the contact in m (`0 < position < L`).
        position: f64,
        /// Height of the contact in m (finite).
        height: f64,
        /// Length of the flat top in m (≥ 0).
        width: f64,
    },
    /// Flat fretboard under the whole string at `g = -distance` (m, ≥ 0 below the rest line).
    Fretboard {
        /// Distance below the rest line in m (≥ 0).
        distance: f64,
    },
    /// Point contacts `(position m, height m)`, each on the node nearest to its position; where
    /// two share a node the higher obstacle wins.
    Points(Vec<(f64, f64)>),
    /// Arbitrary profile on the interior nodes: `profile[i-1]` is `g` at `x_i = iΔx` in m, or
    /// `None` for no obstacle at that node (length `N - 1`).
    Profile(Vec<Option<f64>>),
}

/// Index (0-based interior index `i - 1`) of the node nearest to `x`, clamped to the interior.
fn nearest_node(p: &StringParams, x: f64) -> usize {
    let i = (x / p.dx()).round() as usize;
    i.clamp(1, p.intervals - 1) - 1
}

impl SitarBridge {
    /// The bridge of the lecture's sitar scene (`assets/scenes/seed-sitar.toml`, SEED.md 3.2:
    /// `g(x) = a x²` with our `a = -0.2` m⁻¹ over the first 20 mm, 80 µm below the rest line at
    /// its far edge).
    pub fn seed() -> Self {
        Self {
            position: 0.0,
            curvature: 0.2,
            height: 0.0,
            extent: 0.02,
        }
    }
}

impl Obstacle {
    /// The lecture's sitar scene's bridge ([`SitarBridge::seed`]).
    pub fn seed_sitar() -> Self {
        Obstacle::Sitar(SitarBridge::seed())
    }

    /// The tanpura bridge of the lecture: a single-node point contact 6 mm from the end, at the
    /// string's rest height.
    pub fn tanpura() -> Self {
        Obstacle::Point {
            position: 6e-3,
            height: 0.0,
            width: 0.0,
        }
    }

    /// Samples the profile on the grid of `p`: returns `(interior index i-1, g_i)` for every node
    /// that has an obstacle, sorted by index, without duplicates. Validates the description.
    pub fn sample(&self, p: &StringParams) -> Result<Vec<(usize, f64)>, ParamError> {
        let m = p.modes();
        let x = |k: usize| (k + 1) as f64 * p.dx();
        let mut out: Vec<(usize, f64)> = Vec::new();
        match self {
            Obstacle::None => {}
            Obstacle::Sitar(s) => {
                check_finite("obstacle.position", s.position)?;
                check_finite("obstacle.curvature", s.curvature)?;
                check_finite("obstacle.height", s.height)?;
                p.check_position("obstacle.extent", s.extent)?;
                for k in 0..m {
                    if x(k) <= s.extent {
                        let d = x(k) - s.position;
                        out.push((k, s.height - s.curvature * d * d));
                    }
                }
                if out.is_empty() {
                    return Err(ParamError::new(
                        "obstacle.extent",
                        s.extent,
                        format!("at least one grid spacing ({} m)", p.dx()),
                    ));
                }
            }
            Obstacle::Point {
                position,
                height,
                width,
            } => {
                p.check_position("obstacle.position", *position)?;
                check_finite("obstacle.height", *height)?;
                check_non_negative("obstacle.width", *width)?;
                let near = nearest_node(p, *position);
                for k in 0..m {
                    if k == near || (x(k) - position).abs() <= 0.5 * width {
                        out.push((k, *height));
                    }
                }
            }
            Obstacle::Fretboard { distance } => {
                check_non_negative("obstacle.distance", *distance)?;
                out.extend((0..m).map(|k| (k, -distance)));
            }
            Obstacle::Points(list) => {
                for (n, &(pos, g)) in list.iter().enumerate() {
                    p.check_position(&format!("obstacle.points[{n}].position"), pos)?;
                    check_finite(&format!("obstacle.points[{n}].height"), g)?;
                    out.push((nearest_node(p, pos), g));
                }
                out.sort_by(|a, b| a.0.cmp(&b.0).then(b.1.total_cmp(&a.1)));
                out.dedup_by_key(|e| e.0);
            }
            Obstacle::Profile(g) => {
                if g.len() != m {
                    return Err(ParamError::new(
                        "obstacle.profile.len",
                        g.len(),
                        format!("exactly N - 1 = {m} values"),
                    ));
                }
                for (k, v) in g.iter().enumerate() {
                    if let Some(v) = v {
                        check_finite(&format!("obstacle.profile[{}]", k + 1), *v)?;
                        out.push((k, *v));
                    }
                }
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tanpura_lands_on_the_node_at_6_mm_when_the_grid_has_one() {
        let p = StringParams::lecture_guitar(500, 48_000.0); // Δx = 2 mm
        let s = Obstacle::tanpura().sample(&p).unwrap();
        assert_eq!(s, vec![(2, 0.0)]); // node i = 3, x = 6 mm
        let pts = Obstacle::Points(vec![(0.5, -1e-3), (0.5005, -2e-3), (0.1, 0.0)]);
        assert_eq!(pts.sample(&p).unwrap(), vec![(49, 0.0), (249, -1e-3)]);
    }
}
