//! The shape figure of a one-dimensional model: the displacement along the string at chosen
//! instants, overlaid, with the obstacle drawn (as on the lecture's sitar and tanpura slides);
//! a second panel zooms on the obstacle's region.
//!
//! Runs on the offline render thread after the run (allocates).

use super::source::ShapeSnapshot;
use crate::error::Error;
use crate::plot::{write_png, Mark, Panel, Series};
use std::path::Path;

/// Writes the shape figure of `shapes` to `path` (PNG). Displacements are drawn in mm.
pub fn write_shape_png(path: &Path, title: &str, shapes: &[ShapeSnapshot]) -> Result<(), Error> {
    let Some(first) = shapes.first() else {
        return Err(Error::Empty {
            what: "shape snapshots to plot",
        });
    };
    let length = first.x.last().copied().unwrap_or(1.0);
    let obstacle = &first.obstacle;
    // Zoom: three times the obstacle's far edge, at least 2 % of the string, when the obstacle
    // covers only part of the string; the whole string otherwise.
    let far = obstacle.iter().map(|o| o.0).fold(0.0, f64::max);
    let zoom = if obstacle.is_empty() || far > 0.5 * length {
        None
    } else {
        Some((3.0 * far).max(0.02 * length).min(length))
    };
    let panel = |title: &str, x_max: f64| {
        let mut p = Panel::new(title, "x (m)", "u (mm)");
        let keep = |x: f64| x <= x_max;
        for s in shapes {
            let (x, u): (Vec<f64>, Vec<f64>) =
                s.x.iter()
                    .zip(&s.u)
                    .filter(|(x, _)| keep(**x))
                    .map(|(x, u)| (*x, u * 1e3))
                    .unzip();
            p = p.push(Series::line(format!("t = {:.2} ms", s.time * 1e3), x, u));
        }
        if !obstacle.is_empty() {
            let (x, g): (Vec<f64>, Vec<f64>) = obstacle
                .iter()
                .filter(|o| keep(o.0))
                .map(|o| (o.0, o.1 * 1e3))
                .unzip();
            let mark = if x.len() > 1 {
                Mark::LinePoints
            } else {
                Mark::Points
            };
            p = p.push(Series::line("obstacle g(x)", x, g).with_mark(mark));
        }
        p
    };
    let mut panels = vec![panel("whole string", length)];
    if let Some(z) = zoom {
        panels.push(panel(
            &format!("near the obstacle (x < {:.1} mm)", z * 1e3),
            z,
        ));
    }
    Ok(write_png(path, title, &panels, 1, (1100, 380))?)
}
