//! The candidate ladder of `quality = "auto"`: from a plate scene (its full model, strike,
//! pickups' output rate, scheme) decide the basis symmetry and list the reduced models worth
//! verifying, cheapest first, each choice with its reason. Nothing is rendered here
//! ([`super::verify`] does that).
//!
//! Runs on the thread that selects the model (CLI main thread); allocates.

use super::size::ModelSize;
use super::spectrum::{band_of, count_below, mirror_in_plane_count, strike_band, transverse};
use crate::error::Error;
use crate::scene::plate::{Excitation, PlateScheme, PlateSpec, ShapePart, Symmetry};
use crate::scene::Scene;

pub use super::ladder::{divisor_rate, Candidate, Plan, HEARING_LIMIT};

/// Fractions of the heard transverse band tried (of `min(f_max, f_hear)`).
pub const BAND_FRACTIONS: [f64; 4] = [0.25, 0.5, 0.75, 1.0];
/// Fractions of the full model's in-plane mode count tried.
pub const PSI_FRACTIONS: [f64; 3] = [1.0 / 6.0, 1.0 / 3.0, 1.0];
/// Simulation steps per strike length required by the rate rule (`fs ≥ 20 / T`).
pub const STEPS_PER_STRIKE: f64 = 20.0;
/// Simulation steps per period of the highest mode kept (`fs ≥ 4 f_max`).
pub const STEPS_PER_PERIOD: f64 = 4.0;
/// Stored coupling entries per `N_Φ² N_Ψ / 2`, measured on the default gong's tensors
/// (README, strike-mirror: full 100 × 30 has 9 544 entries, mirror 53 × 17 has 2 824). Used
/// only to order candidates by estimated cost.
const DENSITY_FULL: f64 = 0.064;
/// As [`DENSITY_FULL`], for the strike-mirror basis.
const DENSITY_MIRROR: f64 = 0.118;

/// Estimated work per simulated second (see [`Candidate::estimated_cost`]).
pub fn estimated_cost(s: &ModelSize) -> f64 {
    let d = match s.symmetry {
        Symmetry::Full => DENSITY_FULL,
        Symmetry::StrikeMirror => DENSITY_MIRROR,
    };
    let n = s.n_phi as f64;
    s.sim_rate * (n + d * n * n * s.n_psi as f64 / 2.0)
}

/// Whether a scheme's linear part is exact (no dispersion, no stability bound).
fn exact_linear(scheme: PlateScheme) -> bool {
    !matches!(scheme, PlateScheme::ConservativeTheta1)
}

/// Decides the symmetry and returns it with its reason.
fn choose_symmetry(p: &PlateSpec) -> (Symmetry, String) {
    if p.symmetry == Symmetry::StrikeMirror {
        return (
            Symmetry::StrikeMirror,
            "symmetry: strike-mirror, as the scene gives it".into(),
        );
    }
    if !p.shape.is_circular() {
        return (
            Symmetry::Full,
            "symmetry: full (a rectangle has no strike-mirror basis)".into(),
        );
    }
    if p.imperfection
        .iter()
        .any(|part| matches!(part, ShapePart::Modal { .. }))
    {
        return (
            Symmetry::Full,
            "symmetry: full: the rest shape has modal coefficients, which need not be even \
             about the strike's diameter (the mirror basis holds only for rest shapes even about \
             it; the axisymmetric ones are)"
                .into(),
        );
    }
    let shape_note = if p.imperfection.is_empty() {
        ""
    } else {
        "; the rest shape is axisymmetric, so even about every diameter, and the mirror basis \
         still holds exactly"
    };
    match p.excitation {
        Excitation::Strike { at, .. }
        | Excitation::Impulse { at, .. }
        | Excitation::Mallet { at, .. } => (
            Symmetry::StrikeMirror,
            format!(
                "symmetry: strike-mirror: the only excitation is a point force at angle {} rad \
                 on a circular plate, so the motion stays even about that diameter and the \
                 mirror basis is the full model restricted to it, exactly (README \
                 \"strike-mirror\"; tests/plates/plate_mirror.rs: equal to 1e-9 of the peak); it \
                 keeps the cos n(θ - θ_strike) modes only{shape_note}",
                at.angle.unwrap_or(0.0)
            ),
        ),
        Excitation::Initial { .. } => (
            Symmetry::Full,
            "symmetry: full (an initial modal state is not a strike on a diameter)".into(),
        ),
    }
}

/// Builds the ladder for `scene` (a validated plate or string scene; strings go to
/// [`super::plan_string::plan_string`]).
pub fn plan(scene: &Scene) -> Result<Plan, Error> {
    if scene.string.is_some() {
        return super::plan_string::plan_string(scene);
    }
    let p = scene.plate.as_ref().ok_or(Error::WrongModel(
        "quality = \"auto\" is implemented for plate scenes only",
    ))?;
    let given_mirror = p.symmetry == Symmetry::StrikeMirror;
    // The scene's basis, in its own symmetry.
    let all = transverse(
        p,
        if given_mirror {
            2 * p.n_phi + 2
        } else {
            p.n_phi
        },
    );
    let basis: Vec<_> = all
        .into_iter()
        .filter(|m| m.even || !given_mirror)
        .take(p.n_phi)
        .collect();
    let f_full = band_of(&basis, p.n_phi, false);
    let full = ModelSize {
        string: false,
        n_phi: p.n_phi,
        n_psi: p.n_psi,
        symmetry: p.symmetry,
        sim_rate: p.sim_rate,
        f_max_hz: f_full,
    };
    let (symmetry, why_symmetry) = choose_symmetry(p);
    let mirror = symmetry == Symmetry::StrikeMirror;
    let psi_full = if mirror && !given_mirror && p.n_psi > 0 {
        mirror_in_plane_count(p, p.n_psi)
    } else {
        p.n_psi
    };
    let f_hear = (0.5 * scene.output.sample_rate as f64).min(HEARING_LIMIT);
    let mut reasons = vec![why_symmetry];
    reasons.push(format!(
        "heard band: f_hear = min(output Nyquist {:.0} Hz, 20 kHz) = {f_hear:.0} Hz; the full \
         model's transverse band reaches {f_full:.0} Hz ({} modes)",
        0.5 * scene.output.sample_rate as f64,
        p.n_phi
    ));
    let strike = match p.excitation {
        Excitation::Strike { duration, .. } => {
            reasons.push(format!(
                "strike: raised cosine of {:.2} ms, its spectrum 80 dB below its peak above \
                 {:.0} Hz (the nonlinear cascade can carry energy higher: verified below)",
                duration * 1e3,
                strike_band(duration)
            ));
            Some(duration)
        }
        _ => None,
    };
    // Transverse band ladder, in the chosen basis.
    let top = f_full.min(f_hear);
    let mut cuts: Vec<f64> = BAND_FRACTIONS.iter().map(|f| f * top).collect();
    if f_full > f_hear {
        cuts.push(f_full);
    }
    let mut bands: Vec<(f64, usize)> = Vec::new();
    for &c in &cuts {
        let n = count_below(&basis, c, mirror);
        if bands.last().is_none_or(|&(_, m)| m != n) {
            bands.push((c / top, n));
        }
    }
    reasons.push(format!(
        "transverse ladder: 1/4, 1/2, 3/4 and all of min(f_max, f_hear) = {top:.0} Hz{} -> \
         n_phi in {:?} ({} basis)",
        if f_full > f_hear {
            ", and the whole band"
        } else {
            ""
        },
        bands.iter().map(|b| b.1).collect::<Vec<_>>(),
        if mirror { "mirror" } else { "full" }
    ));
    let mut psis: Vec<(f64, usize)> = Vec::new();
    for &f in &PSI_FRACTIONS {
        let n = if psi_full == 0 {
            0
        } else {
            ((f * psi_full as f64).ceil() as usize).max(1)
        };
        if psis.last().is_none_or(|&(_, m)| m != n) {
            psis.push((f, n));
        }
    }
    reasons.push(format!(
        "in-plane ladder: 1/6, 1/3 and all of the full model's {psi_full} in-plane modes{} -> \
         n_psi in {:?} ({}: docs/ACCURACY.md)",
        if psi_full != p.n_psi {
            format!(" ({} in the full basis)", p.n_psi)
        } else {
            String::new()
        },
        psis.iter().map(|b| b.1).collect::<Vec<_>>(),
        if p.imperfection.is_empty() {
            "they shape the nonlinear stiffening only"
        } else {
            "they shape the nonlinear terms and, on this curved plate, the linear frequencies"
        }
    ));
    if !p.imperfection.is_empty() {
        reasons.push(
            "curved plate: the rest shape's stiffness raises the modes with nodal circles above \
             the flat bands listed here and acts through the in-plane modes, so n_psi also sets \
             those linear frequencies (docs/models.md, \"Curved plates\"); the verification \
             below measures both against the full model"
                .into(),
        );
    }
    let modal_len = p
        .imperfection
        .iter()
        .map(|part| match part {
            ShapePart::Modal { coefficients } => coefficients.len(),
            _ => 0,
        })
        .max()
        .unwrap_or(0);
    if modal_len > 0 {
        reasons.push(format!(
            "rest shape: its {modal_len} modal coefficients need n_phi >= {modal_len}; smaller \
             candidates are left out"
        ));
    }
    let exact = exact_linear(p.scheme);
    reasons.push(if exact {
        format!(
            "rate: the scheme's linear part is exact (no dispersion), so the rate only has to \
             resolve the band and the strike: fs >= max({STEPS_PER_PERIOD} f_max, \
             {STEPS_PER_STRIKE} / strike length), the lowest divisor of {} Hz meeting it, and \
             the scene's rate",
            p.sim_rate
        )
    } else {
        format!(
            "rate: the theta = 1 scheme detunes every partial by (2/h) asin(h ω / 2) - ω, \
             which depends on the rate only, so the scene's {} Hz is kept (the kept partials \
             are then the full model's)",
            p.sim_rate
        )
    });
    let mut candidates = Vec::new();
    for &(bf, n_phi) in bands.iter().filter(|b| b.1 >= modal_len) {
        let f_max = band_of(&basis, n_phi, mirror);
        let mut rates = vec![p.sim_rate];
        if exact {
            let need = (STEPS_PER_PERIOD * f_max).max(strike.map_or(0.0, |t| STEPS_PER_STRIKE / t));
            let low = divisor_rate(p.sim_rate, need);
            if low < p.sim_rate {
                rates.insert(0, low);
            }
        }
        for &(pf, n_psi) in &psis {
            for &rate in &rates {
                let size = ModelSize {
                    string: false,
                    n_phi,
                    n_psi,
                    symmetry,
                    sim_rate: rate,
                    f_max_hz: f_max,
                };
                let same_as_full = symmetry == p.symmetry
                    && n_phi == p.n_phi
                    && n_psi == p.n_psi
                    && rate == p.sim_rate;
                if !same_as_full {
                    candidates.push(Candidate {
                        estimated_cost: estimated_cost(&size),
                        size,
                        band_fraction: bf,
                        psi_fraction: pf,
                    });
                }
            }
        }
    }
    candidates.sort_by(|a, b| a.estimated_cost.total_cmp(&b.estimated_cost));
    Ok(Plan {
        full,
        symmetry,
        f_hear,
        reasons,
        candidates,
    })
}
