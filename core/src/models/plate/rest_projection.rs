//! The projection of a rest shape ([`super::rest_shape`]) on a plate's transverse modes,
//! `a_k = ∫_S w0 Φ_k dS` (m²), the coefficients [`super::PlateModel::set_rest_shape`] takes
//! (method and accuracy in [`super::rest_shape`]). Worker thread.

use super::basis::PlateBasis;
use super::geometry::PlateShape;
use super::rest_shape::ShapePart;
use super::spec::Position;
use crate::modal::quadrature::GaussLegendre;

/// `a_k = ∫_S w0 Φ_k dS` (m²) of the summed `parts` on `basis`, for a plate of size `length`
/// (radius or `lx`, m) and aspect `ly/lx` (rectangles). Worker thread.
pub fn project(
    parts: &[ShapePart],
    basis: &PlateBasis,
    shape: PlateShape,
    length: f64,
    aspect: f64,
) -> Vec<f64> {
    let n = basis.n_phi();
    let mut a = vec![0.0; n];
    let lam_max = basis.lambda2().iter().fold(0.0f64, |m, &l| m.max(l)).sqrt();
    let points = 16 + 2 * lam_max.ceil() as usize;
    let rule = GaussLegendre::new(points.min(GaussLegendre::MAX_POINTS)).expect("in range");
    let radial: Vec<&ShapePart> = parts
        .iter()
        .filter(|p| {
            matches!(
                p,
                ShapePart::Spherical { .. } | ShapePart::Boss { .. } | ShapePart::Profile { .. }
            )
        })
        .collect();
    if shape.is_circular() && !radial.is_empty() {
        let mut breaks: Vec<f64> = vec![0.0, 1.0];
        for p in &radial {
            breaks.extend(p.kinks());
        }
        breaks.sort_by(f64::total_cmp);
        breaks.dedup();
        let w0 = |r: f64| radial.iter().map(|p| p.height(r, length)).sum::<f64>();
        for (k, ak) in a.iter_mut().enumerate() {
            if basis.cosine_order(k) != Some(0) {
                continue; // ∫ cos nθ dθ = ∫ sin nθ dθ = 0 for n ≥ 1
            }
            let mut sum = 0.0;
            for pair in breaks.windows(2) {
                let (r0, r1) = (pair[0], pair[1]);
                for (&x, &w) in rule.nodes.iter().zip(&rule.weights) {
                    let r = r0 + (r1 - r0) * x;
                    let at = Position {
                        r: Some(r),
                        angle: Some(0.0),
                        ..Position::default()
                    };
                    sum += w * (r1 - r0) * w0(r) * basis.phi_at(k, &at) * r;
                }
            }
            *ak += std::f64::consts::TAU * length * sum;
        }
    }
    for part in parts {
        match part {
            ShapePart::Dome { rise } => {
                // ∫_Ŝ over the unit rectangle [0,1] × [0, aspect]: dŜ = aspect dξ dη.
                for (k, ak) in a.iter_mut().enumerate() {
                    let mut sum = 0.0;
                    for (&x, &wx) in rule.nodes.iter().zip(&rule.weights) {
                        for (&y, &wy) in rule.nodes.iter().zip(&rule.weights) {
                            let at = Position {
                                x: Some(x),
                                y: Some(y),
                                ..Position::default()
                            };
                            let h = 16.0 * rise * x * (1.0 - x) * y * (1.0 - y);
                            sum += wx * wy * h * basis.phi_at(k, &at);
                        }
                    }
                    *ak += length * aspect * sum;
                }
            }
            ShapePart::Modal { coefficients } => {
                // Φ̂ has ∫Φ̂² dŜ = 1 over the unit plate of area Ŝ, so Φ_rms = 1/√Ŝ on it and
                // w0 = c Φ̂ √Ŝ: a = L √Ŝ c (the physical Φ_rms is 1/(L√Ŝ)).
                let area = if shape.is_circular() {
                    std::f64::consts::PI
                } else {
                    aspect
                };
                for (ak, &c) in a.iter_mut().zip(coefficients) {
                    *ak += length * area.sqrt() * c;
                }
            }
            _ => {}
        }
    }
    a
}
