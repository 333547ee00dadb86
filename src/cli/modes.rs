//! `noether modes`: list a plate's transverse modes with labels, dimensionless eigenvalues and
//! frequencies for a given material and size; with `--rise` or `--curvature-radius`, those of a
//! shallow spherical shell (a curved free plate, `noether_core::modal::shell`).

use clap::{Args, ValueEnum};
use noether::modal::rect::transverse_modes;
use noether::modal::shell::{shell_modes, CapCoupling, Imperfection};
use noether::modal::{
    circular_modes, omega_scale, CircularEdge, CircularPlateSpec, Parity, PlateModes,
};
use noether::{Error, ParamError};
use serde::Serialize;

/// Plate families.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum PlateArg {
    /// Circular plate, free edge.
    CircularFree,
    /// Circular plate, clamped edge.
    CircularClamped,
    /// Rectangular plate, simply supported (sides lx and lx * aspect).
    RectSs,
}

/// Arguments of `noether modes`.
#[derive(Debug, Args)]
#[command(allow_negative_numbers = true)]
pub struct ModesArgs {
    /// Plate geometry and boundary condition.
    #[arg(long, value_enum)]
    pub plate: PlateArg,
    /// Number of modes to list (1 to 20000).
    #[arg(long, default_value_t = 20)]
    pub count: usize,
    /// Poisson's ratio nu (0 to 0.5).
    #[arg(long, default_value_t = 0.3)]
    pub nu: f64,
    /// Rectangle: side ratio ly / lx (0.05 to 20).
    #[arg(long, default_value_t = 1.5)]
    pub aspect: f64,
    /// Rectangle: side lx in m.
    #[arg(long, default_value_t = 0.4)]
    pub lx: f64,
    /// Radius (circular plates) in m.
    #[arg(long, default_value_t = 0.4)]
    pub radius: f64,
    /// Thickness in m.
    #[arg(long, default_value_t = 0.001)]
    pub thickness: f64,
    /// Young's modulus in Pa.
    #[arg(long = "youngs-modulus", default_value_t = 2e11)]
    pub youngs_modulus: f64,
    /// Density in kg/m^3.
    #[arg(long, default_value_t = 7860.0)]
    pub density: f64,
    /// Circular free plate curved into a spherical cap of this rise in m (a shallow shell;
    /// 0 to 500 thicknesses).
    #[arg(long, conflicts_with = "curvature_radius")]
    pub rise: Option<f64>,
    /// Circular free plate curved into a spherical cap of this curvature radius in m.
    #[arg(long = "curvature-radius")]
    pub curvature_radius: Option<f64>,
    /// Shell: transverse modes of the flat basis (40 to 2000); the in-plane problem is solved
    /// in closed form (`CapCoupling::InPlaneExact`). More is more accurate and slower: the
    /// default gives every listed mode to 1e-8 or better for κ up to 50 (docs/models.md,
    /// "Curved plates: linear modes").
    #[arg(long = "shell-basis", default_value_t = 320)]
    pub shell_basis: usize,
    /// Print JSON (one array of objects) instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// One listed mode.
#[derive(Debug, Serialize)]
struct Row {
    index: usize,
    label: String,
    /// λ² = ω a² √(ρh/D) (a: radius, or lx for rectangles).
    lambda2: f64,
    frequency_hz: f64,
}

/// Runs `noether modes`.
pub fn run(a: ModesArgs) -> Result<(), Error> {
    if !(1..=20_000).contains(&a.count) {
        return Err(ParamError::new("--count", a.count, "1 to 20000").into());
    }
    if !(0.0..=0.5).contains(&a.nu) {
        return Err(ParamError::new("--nu", a.nu, "[0, 0.5]").into());
    }
    let shell = match (a.rise, a.curvature_radius) {
        (Some(rise), _) => Some(
            Imperfection::from_rise(rise, a.radius, a.thickness)
                .map_err(|e| rename(e, "--rise"))?,
        ),
        (_, Some(r)) => Some(
            Imperfection::from_curvature_radius(r, a.radius, a.thickness)
                .map_err(|e| rename(e, "--curvature-radius"))?,
        ),
        _ => None,
    };
    let rows: Vec<Row> = match (a.plate, shell) {
        (PlateArg::CircularFree, Some(shell)) => shell_rows(&a, &shell)?,
        (_, Some(_)) => {
            return Err(ParamError::new(
                "--plate",
                format!("{:?}", a.plate),
                "circular-free with --rise or --curvature-radius",
            )
            .into())
        }
        (PlateArg::CircularFree | PlateArg::CircularClamped, None) => {
            let edge = if matches!(a.plate, PlateArg::CircularFree) {
                CircularEdge::Free
            } else {
                CircularEdge::Clamped
            };
            let scale = omega_scale(a.radius, a.thickness, a.youngs_modulus, a.density, a.nu)?;
            circular_modes(edge, a.nu, a.count)
                .iter()
                .enumerate()
                .map(|(i, m)| {
                    let l2 = m.radial.lambda * m.radial.lambda;
                    let p = match m.parity {
                        Parity::Cos => "cos",
                        Parity::Sin => "sin",
                    };
                    Row {
                        index: i + 1,
                        label: format!("({},{}) {p}", m.n, m.k),
                        lambda2: l2,
                        frequency_hz: l2 * scale / std::f64::consts::TAU,
                    }
                })
                .collect()
        }
        (PlateArg::RectSs, None) => {
            if !(a.aspect.is_finite() && (0.05..=20.0).contains(&a.aspect)) {
                return Err(ParamError::new("--aspect", a.aspect, "[0.05, 20]").into());
            }
            // Same scaling as the circle with the radius replaced by lx.
            let scale = omega_scale(a.lx, a.thickness, a.youngs_modulus, a.density, a.nu)?;
            let (labels, lambda2) = transverse_modes(a.aspect, a.count);
            labels
                .iter()
                .zip(lambda2)
                .enumerate()
                .map(|(i, (&(m, n), l2))| Row {
                    index: i + 1,
                    label: format!("({m},{n})"),
                    lambda2: l2,
                    frequency_hz: l2 * scale / std::f64::consts::TAU,
                })
                .collect()
        }
    };
    if a.json {
        println!("{}", serde_json::to_string(&rows)?);
    } else {
        if let Some(shell) = shell {
            println!(
                "shallow spherical shell: kappa = a^2/(R h) = {:.6}, rise {:.6e} m; \
                 basis {} x {} (cosine modes; every n >= 1 mode has a sine twin at the same frequency)",
                shell.kappa(),
                0.5 * shell.kappa() * a.thickness,
                a.shell_basis,
                a.shell_basis / 2
            );
        }
        println!(
            "{:?} plate, nu = {}, size {} m, h = {} m, E = {} Pa, rho = {} kg/m^3",
            a.plate,
            a.nu,
            if matches!(a.plate, PlateArg::RectSs) {
                a.lx
            } else {
                a.radius
            },
            a.thickness,
            a.youngs_modulus,
            a.density
        );
        println!(
            "{:>6} {:>14} {:>16} {:>14}",
            "index", "label", "lambda^2", "f (Hz)"
        );
        for r in rows {
            println!(
                "{:>6} {:>14} {:>16.10} {:>14.4}",
                r.index, r.label, r.lambda2, r.frequency_hz
            );
        }
    }
    Ok(())
}

/// `e` with its field renamed to the command-line flag `flag` (the user typed the flag).
fn rename(e: ParamError, flag: &str) -> ParamError {
    ParamError {
        field: flag.to_string(),
        ..e
    }
}

/// The lowest `a.count` modes of the shell `shell` over a free circular plate of `a`'s
/// material and size: the strike-mirror (cosine) basis of `a.shell_basis` transverse and half
/// as many in-plane modes, the rest shape projected on it (`shell_modes`).
fn shell_rows(a: &ModesArgs, shell: &Imperfection) -> Result<Vec<Row>, Error> {
    if !(40..=2000).contains(&a.shell_basis) {
        return Err(ParamError::new("--shell-basis", a.shell_basis, "40 to 2000").into());
    }
    if a.count > a.shell_basis / 2 {
        return Err(ParamError::new(
            "--count",
            a.count,
            format!("at most half of --shell-basis ({})", a.shell_basis / 2),
        )
        .into());
    }
    let spec = CircularPlateSpec::new(CircularEdge::Free, a.nu, a.shell_basis, 1, None)?
        .mirror_symmetric();
    let modes = PlateModes::build(&spec)?;
    let scale = omega_scale(a.radius, a.thickness, a.youngs_modulus, a.density, a.nu)?;
    let mut list = shell_modes(&modes, shell, CapCoupling::InPlaneExact)?;
    list.sort_by(|x, y| x.lambda2.total_cmp(&y.lambda2));
    Ok(list
        .iter()
        .take(a.count)
        .enumerate()
        .map(|(i, m)| Row {
            index: i + 1,
            label: format!("({},{}) cos", m.n, m.k),
            lambda2: m.lambda2,
            frequency_hz: m.lambda2 * scale / std::f64::consts::TAU,
        })
        .collect())
}
