//! The `plate.imperfection` of a scene: the plate's static rest shape `w0` (a dome, a centre
//! boss, a radial profile or modal coefficients, summed), its validation and heights; its
//! projection on the plate's transverse modes, `a_k = ∫_S w0 Φ_k dS`, which
//! [`super::PlateModel::set_rest_shape`] takes, is in [`super::rest_projection`].
//!
//! Units: heights in m, radii as fractions of the plate's radius. On a plate of size `L`
//! (radius or `lx`) with the unit plate's modes `Φ̂_k`, `Φ_k(x) = Φ̂_k(x/L)/L` and
//! `dS = L² dŜ`, so `a_k = L ∫_Ŝ w0 Φ̂_k dŜ` (m²).
//!
//! Circular plates: every shape but `modal` is axisymmetric, so only the modes without nodal
//! diameters (`cos 0θ`) receive a coefficient, `a_k = 2π L ∫₀¹ w0(r) Φ̂_k(r) r dr`, computed by
//! composite Gauss-Legendre quadrature with a panel break at every kink of the profile (a
//! boss's edge, a profile's points), `16 + 2⌈λ_max⌉` points per panel (the integrand
//! oscillates at most like `Φ̂` of the top mode; doubling it changes `a` by round-off,
//! tested). On a free edge the projection drops the rigid-body part of `w0` (the free modes
//! are orthogonal to 1, `r cos θ`, `r sin θ`), which the coupling does not see anyway (`L`
//! annihilates affine functions: `crate::modal::shell`). Axisymmetric shapes are symmetric
//! about every diameter, so the strike-mirror basis represents them exactly.
//!
//! Rectangles (simply supported): a `dome` `w0 = 16 H ξ(1-ξ) η(1-η)` (zero on the supported
//! edges) or modal coefficients; 2-D Gauss-Legendre quadrature.
//!
//! Threads: validation and projection run on the worker (build) thread.

use super::geometry::PlateShape;
use crate::error::{check_closed, ParamError};
use serde::{Deserialize, Deserializer, Serialize};

/// Largest rise of a shape, in plate thicknesses (a cap of rise `H` has the curvature
/// parameter `κ = 2H/h`; 500 thicknesses is `κ = 1000`, far beyond real gongs and cymbals,
/// whose `κ` is a few tens).
pub const MAX_RISE_THICKNESSES: f64 = 500.0;

/// One part of a rest shape (the parts of `plate.imperfection` add up).
///
/// Plain data read from scenes and presets (any thread).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum ShapePart {
    /// A spherical cap, shallow form `w0 = H (1 - r²)` (circular plates): give its `rise` H
    /// (m) or its `curvature_radius` R (m, `H = a²/2R`).
    Spherical {
        /// Rise H of the centre above the rim in m (0 to 500 thicknesses).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        rise: Option<f64>,
        /// Radius of curvature R in m (at least `a²/(1000 h)`).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        curvature_radius: Option<f64>,
    },
    /// A raised centre boss (Thai and Burmese gongs, a cymbal's bell):
    /// `w0 = H cos²(π r / 2b)` for `r < b`, 0 beyond (circular plates).
    Boss {
        /// Height H of the boss in m (0 to 500 thicknesses).
        rise: f64,
        /// Radius b of the boss's base as a fraction of the plate's radius (0.02 to 1).
        radius: f64,
    },
    /// A radial profile through `points = [[r, height], ...]` (r fractions of the radius from
    /// 0 to 1, increasing; heights in m), linear between points (circular plates).
    Profile {
        /// `[r, height]` pairs, 2 to 256 of them, `r` from 0 to 1.
        points: Vec<[f64; 2]>,
    },
    /// A dome over a rectangle, `w0 = 16 H ξ(1-ξ) η(1-η)` (zero on the supported edges).
    Dome {
        /// Height H at the centre in m (0 to 500 thicknesses).
        rise: f64,
    },
    /// Modal coefficients: `w0 = Σ_k c_k Φ_k / Φ_rms`, each mode (in the plate's modal order,
    /// the strike-mirror basis's on a mirror plate) scaled to unit root-mean-square height over
    /// the plate; `c_k` in m.
    Modal {
        /// `c_k` in m, at most `n_phi` of them (each within ±500 thicknesses).
        coefficients: Vec<f64>,
    },
}

/// Reads `plate.imperfection` as one table or an array of tables.
pub fn one_or_many<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<ShapePart>, D::Error> {
    #[derive(Deserialize)]
    #[serde(untagged)]
    enum OneOrMany {
        One(ShapePart),
        Many(Vec<ShapePart>),
    }
    Ok(match OneOrMany::deserialize(d)? {
        OneOrMany::One(p) => vec![p],
        OneOrMany::Many(v) => v,
    })
}

impl ShapePart {
    /// The shape's name in scenes.
    pub fn kind(&self) -> &'static str {
        match self {
            ShapePart::Spherical { .. } => "spherical",
            ShapePart::Boss { .. } => "boss",
            ShapePart::Profile { .. } => "profile",
            ShapePart::Dome { .. } => "dome",
            ShapePart::Modal { .. } => "modal",
        }
    }

    /// Checks the part against the plate (`shape`, size `length` m, `thickness` m, `n_phi`
    /// modes); `field` is the dotted name used in errors (`plate.imperfection[0]`).
    pub fn validate(
        &self,
        shape: PlateShape,
        length: f64,
        thickness: f64,
        n_phi: usize,
        field: &str,
    ) -> Result<(), ParamError> {
        let max_rise = MAX_RISE_THICKNESSES * thickness;
        let rise_ok =
            |name: &str, v: f64| check_closed(&format!("{field}.{name}"), v, 0.0, max_rise);
        let circular_only = matches!(
            self,
            ShapePart::Spherical { .. } | ShapePart::Boss { .. } | ShapePart::Profile { .. }
        );
        if circular_only && !shape.is_circular() {
            return Err(ParamError::new(
                format!("{field}.kind"),
                self.kind(),
                "\"dome\" or \"modal\" on rectangular plates",
            ));
        }
        if matches!(self, ShapePart::Dome { .. }) && shape.is_circular() {
            return Err(ParamError::new(
                format!("{field}.kind"),
                "dome",
                "\"spherical\", \"boss\", \"profile\" or \"modal\" on circular plates",
            ));
        }
        match self {
            ShapePart::Spherical {
                rise,
                curvature_radius,
            } => match (rise, curvature_radius) {
                (Some(h), None) => {
                    rise_ok("rise", *h)?;
                }
                (None, Some(r)) => {
                    let min = length * length / (2.0 * max_rise);
                    check_closed(&format!("{field}.curvature_radius"), *r, min, f64::MAX)?;
                }
                _ => {
                    return Err(ParamError::new(
                        format!("{field}.rise"),
                        if rise.is_some() {
                            "given with curvature_radius"
                        } else {
                            "missing"
                        },
                        "exactly one of rise (m) and curvature_radius (m)",
                    ))
                }
            },
            ShapePart::Boss { rise, radius } => {
                rise_ok("rise", *rise)?;
                check_closed(&format!("{field}.radius"), *radius, 0.02, 1.0)?;
            }
            ShapePart::Dome { rise } => {
                rise_ok("rise", *rise)?;
            }
            ShapePart::Profile { points } => {
                if !(2..=256).contains(&points.len()) {
                    return Err(ParamError::new(
                        format!("{field}.points"),
                        format!("{} points", points.len()),
                        "2 to 256 [r, height] pairs",
                    ));
                }
                for (i, p) in points.iter().enumerate() {
                    check_closed(&format!("{field}.points[{i}].r"), p[0], 0.0, 1.0)?;
                    check_closed(
                        &format!("{field}.points[{i}].height"),
                        p[1],
                        -max_rise,
                        max_rise,
                    )?;
                    if i > 0 && p[0] <= points[i - 1][0] {
                        return Err(ParamError::new(
                            format!("{field}.points[{i}].r"),
                            p[0],
                            format!("greater than the previous point's r = {}", points[i - 1][0]),
                        ));
                    }
                }
                let (first, last) = (points[0], points[points.len() - 1]);
                if first[0] != 0.0 || last[0] != 1.0 {
                    return Err(ParamError::new(
                        format!("{field}.points"),
                        format!("r from {} to {}", first[0], last[0]),
                        "r from 0 (the centre) to 1 (the rim)",
                    ));
                }
                if shape == PlateShape::CircularClamped && last[1] != 0.0 {
                    return Err(ParamError::new(
                        format!("{field}.points[{}].height", points.len() - 1),
                        last[1],
                        "0 at r = 1 on a clamped plate (the rim is held)",
                    ));
                }
            }
            ShapePart::Modal { coefficients } => {
                if coefficients.is_empty() || coefficients.len() > n_phi {
                    return Err(ParamError::new(
                        format!("{field}.coefficients"),
                        format!("{} values", coefficients.len()),
                        format!("1 to n_phi = {n_phi} values"),
                    ));
                }
                for (i, &c) in coefficients.iter().enumerate() {
                    check_closed(
                        &format!("{field}.coefficients[{i}]"),
                        c,
                        -max_rise,
                        max_rise,
                    )?;
                }
            }
        }
        Ok(())
    }

    /// The radial height `w0(r)` in m at the fraction `r` of the radius (axisymmetric parts;
    /// 0 for the others), on a plate of radius `radius` (m).
    pub fn height(&self, r: f64, radius: f64) -> f64 {
        match self {
            ShapePart::Spherical {
                rise,
                curvature_radius,
            } => {
                let h = rise.unwrap_or_else(|| {
                    radius * radius / (2.0 * curvature_radius.unwrap_or(f64::INFINITY))
                });
                h * (1.0 - r * r)
            }
            ShapePart::Boss { rise, radius: b } => {
                if r < *b {
                    rise * (std::f64::consts::FRAC_PI_2 * r / b).cos().powi(2)
                } else {
                    0.0
                }
            }
            ShapePart::Profile { points } => {
                let i = points
                    .partition_point(|p| p[0] <= r)
                    .clamp(1, points.len() - 1);
                let (p0, p1) = (points[i - 1], points[i]);
                p0[1] + (p1[1] - p0[1]) * (r - p0[0]) / (p1[0] - p0[0])
            }
            ShapePart::Dome { .. } | ShapePart::Modal { .. } => 0.0,
        }
    }

    /// The radii (fractions) where the profile has a kink: panel breaks of the quadrature.
    pub fn kinks(&self) -> Vec<f64> {
        match self {
            ShapePart::Boss { radius, .. } => vec![*radius],
            ShapePart::Profile { points } => points.iter().map(|p| p[0]).collect(),
            _ => Vec::new(),
        }
    }

    /// The part's largest height in m (for reports), on a plate of radius/size `length` m.
    pub fn peak(&self, length: f64) -> f64 {
        match self {
            ShapePart::Spherical { .. } | ShapePart::Boss { .. } => self.height(0.0, length).abs(),
            ShapePart::Profile { points } => points.iter().fold(0.0, |m, p| m.max(p[1].abs())),
            ShapePart::Dome { rise } => rise.abs(),
            ShapePart::Modal { coefficients } => coefficients.iter().map(|c| c.abs()).sum(),
        }
    }
}

/// Checks every part of `parts` (the scene's `plate.imperfection`).
pub fn validate_parts(
    parts: &[ShapePart],
    shape: PlateShape,
    length: f64,
    thickness: f64,
    n_phi: usize,
) -> Result<(), ParamError> {
    if parts.len() > 16 {
        return Err(ParamError::new(
            "plate.imperfection",
            format!("{} parts", parts.len()),
            "0 to 16 parts",
        ));
    }
    for (i, p) in parts.iter().enumerate() {
        p.validate(
            shape,
            length,
            thickness,
            n_phi,
            &format!("plate.imperfection[{i}]"),
        )?;
    }
    Ok(())
}
