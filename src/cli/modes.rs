//! `noether modes`: list a plate's transverse modes with labels, dimensionless eigenvalues and
//! frequencies for a given material and size.

use clap::{Args, ValueEnum};
use noether::modal::rect::transverse_modes;
use noether::modal::{circular_modes, omega_scale, CircularEdge, Parity};
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
    let rows: Vec<Row> = match a.plate {
        PlateArg::CircularFree | PlateArg::CircularClamped => {
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
        PlateArg::RectSs => {
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
