//! A plate built from a scene's `[plate]` table: modal data (cached), physical scaling, losses,
//! excitation and pickups, driven as a [`RenderSource`].
//!
//! Scaling (modes normalised to `∫_S Φ² dS = ∫_S Ψ² dS = 1` on the plate of unit size `a = 1`,
//! `D = ρh = 1`): on a plate of size `a`, `ω_s = λ_s² √(D/ρh)/a²`, `ζ_l⁴ → ζ_l⁴/a⁴`, mode values
//! `Φ_s(x) → Φ_s(x/a)/a` and the coupling tensor `H → H/a⁵` (passed to the model as
//! `coupling_scale = a⁻⁵`). Size, thickness and material therefore change only these scalars:
//! the dimensionless basis and tensor are reused as they are.

use super::basis::ModalCache;
use super::blueprint::PlateBlueprint;
use super::contact_residual::ContactResidual;
use super::excitation::{damping_law, PickupKind, PickupWeights, RaisedCosine};
use super::extension::{ceiling_hz, BandExtension};
use super::spec::{Damping, Excitation, PlateSpec, Position, Quantity};
use super::{LinearSolve, Mallet, PlateModel, PlateParams};
use crate::error::ParamError;
use crate::modal::scaling::{flexural_rigidity, in_plane_divisor};
use crate::modal::CouplingTensor;
use crate::models::sav_relaxation::SavRelaxation;
use crate::models::source::{EnergyTerms, ModelDetails, PlateDetails, RenderSource};

/// The force applied at the excitation point, sample by sample.
#[derive(Debug, Clone)]
enum ForceSignal {
    /// Raised-cosine pulse.
    Strike(RaisedCosine),
    /// A mallet, launched at build time, its force solved with each step.
    Mallet(Mallet),
    /// No force during the run (an impulse is applied as the initial velocity).
    None,
}

/// A plate voice ready to render: the model, its excitation and what it was built from.
///
/// Built on a worker (or the CLI's main) thread; `process` runs on the render or audio thread.
pub struct PlateVoice {
    model: PlateModel<CouplingTensor>,
    /// The band above the simulation (`plate.band_above`), fed by the closure.
    above: Option<BandExtension>,
    force: ForceSignal,
    /// Steps taken since the start.
    step: u64,
    fs: f64,
    /// Figures for the report.
    info: PlateDetails,
}

/// Names a model-level field (`n_phi`, `force_weights`) as the scene's dotted field.
fn scoped(mut e: ParamError) -> ParamError {
    e.field = format!("plate.{}", e.field);
    e
}

impl PlateVoice {
    /// Builds the voice for `scene` (validated), computing or loading its modal data.
    ///
    /// Errors name the field (dotted, as in the scene: `plate.…`), its value and the allowed
    /// range.
    pub fn build(scene: &PlateSpec) -> Result<Self, ParamError> {
        scene.validate()?;
        let start = std::time::Instant::now();
        let linear_only = scene.n_psi == 0;
        // The key's own errors name the scene's field.
        scene.basis_key().map_err(scoped)?;
        let mut blueprint = PlateBlueprint::new(scene, &mut ModalCache::default())?;
        blueprint.basis = blueprint
            .basis
            .with_tensor_storage(scene.tensor_storage)
            .map_err(scoped)?;
        let (basis, a) = (&blueprint.basis, blueprint.length);
        let phi_at = |s: usize, p: &Position| basis.phi_at(s, &blueprint.in_frame(p));
        let (lambda2, zeta4) = (basis.lambda2(), basis.zeta4());
        let cache = basis.cache.clone();
        let modal_seconds = start.elapsed().as_secs_f64();
        let omega_scale = scene.pulsation_scale();
        let a4 = in_plane_divisor(a);
        let omega: Vec<f64> = lambda2.iter().map(|l2| l2 * omega_scale).collect();
        let damping_of = |omega: &[f64]| -> Result<Vec<f64>, ParamError> {
            Ok(match scene.damping {
                Damping::None => vec![0.0; omega.len()],
                Damping::Power { a, b, c0 } => damping_law(omega, a, b, c0)?,
                Damping::Q { q } => omega.iter().map(|w| w / q).collect(),
                Damping::T60 { seconds } => vec![2.0 * 1000f64.ln() / seconds; omega.len()],
            })
        };
        let damping = damping_of(&omega)?;
        let scheme = scene.scheme;
        let params = PlateParams {
            omega: omega.clone(),
            zeta4: zeta4.iter().map(|z| z / a4).collect(),
            rho_h: scene.surface_density(),
            e_h: scene.material.youngs_modulus * scene.thickness,
            coupling_scale: if linear_only { 0.0 } else { a.powi(-5) },
            fs: scene.sim_rate,
            damping,
            scheme,
            solve: LinearSolve::Auto,
        };
        let weights = |p: &Position| {
            (0..omega.len())
                .map(|s| phi_at(s, p) / a)
                .collect::<Vec<f64>>()
        };
        let (at, force) = match scene.excitation {
            Excitation::Strike {
                at,
                duration,
                peak_force,
            } => (
                at,
                ForceSignal::Strike(RaisedCosine::new(duration, peak_force)?),
            ),
            Excitation::Impulse { at, .. } => (at, ForceSignal::None),
            Excitation::Mallet { at, .. } => {
                let law = scene.excitation.mallet_law()?;
                let m = Mallet::new(
                    law.mass,
                    law.stiffness,
                    law.exponent,
                    law.loss,
                    1.0 / scene.sim_rate,
                )
                .map_err(|e| ParamError {
                    field: format!("plate.excitation.{}", e.field),
                    ..e
                })?;
                (at, ForceSignal::Mallet(m))
            }
            // No force: the strike weights are unused (the centre is a valid placeholder).
            Excitation::Initial { .. } => (
                Position {
                    r: Some(0.0),
                    x: Some(0.5),
                    y: Some(0.5),
                    ..Position::default()
                },
                ForceSignal::None,
            ),
        };
        let pickup_points = scene.effective_pickups();
        let pickups = pickup_points
            .iter()
            .map(|p| {
                let kind = match p.quantity {
                    Quantity::Displacement => PickupKind::Displacement,
                    Quantity::Velocity => PickupKind::VelocityBackward,
                };
                PickupWeights::new(weights(&p.at), kind)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let nnz = basis.coupling.nnz();
        let strike_weights = weights(&at);
        // A Dirac impulse J at x0 is the initial velocity q̇_s(0) = J Φ_s(x0) / ρh.
        let initial_state: Option<(Vec<f64>, Vec<f64>)> = match scene.excitation {
            Excitation::Impulse { impulse, .. } => Some((
                vec![0.0; strike_weights.len()],
                strike_weights
                    .iter()
                    .map(|w| impulse * w / scene.surface_density())
                    .collect(),
            )),
            Excitation::Initial {
                mode,
                displacement,
                velocity,
            } => {
                let mut q0 = vec![0.0; strike_weights.len()];
                let mut v0 = q0.clone();
                q0[mode - 1] = displacement;
                v0[mode - 1] = velocity;
                Some((q0, v0))
            }
            Excitation::Strike { .. } | Excitation::Mallet { .. } => None,
        };
        let mut model = PlateModel::new(&params, basis.coupling.clone(), strike_weights, pickups)
            .map_err(scoped)?;
        model.set_sav_relaxation(SavRelaxation::from_scene(scene.sav_relaxation, model.h()));
        model.set_closure(scene.closure).map_err(scoped)?;
        if !scene.imperfection.is_empty() && !linear_only {
            let rest = blueprint.rest_shape(&scene.imperfection, None);
            model.set_rest_shape(&rest).map_err(scoped)?;
        }
        if let Some((q0, v0)) = initial_state {
            model.set_state(&q0, &v0)?;
        }
        let mut force = force;
        if let (ForceSignal::Mallet(m), Excitation::Mallet { speed, .. }) =
            (&mut force, scene.excitation)
        {
            model.launch_mallet(m, speed).map_err(scoped)?;
        }
        let two_pi = std::f64::consts::TAU;
        // The band above: the listed modes past the basis, under the ceiling, with the
        // scene's damping law and pickups (in the basis's frame).
        let above = if scene.band_above {
            let top_hz = omega.iter().fold(0.0f64, |m, &w| m.max(w)) / two_pi;
            let list = blueprint.modes_above(top_hz);
            let ceiling = two_pi * ceiling_hz(scene.sim_rate);
            let omega_above: Vec<f64> = list.lambda2[omega.len().min(list.len())..]
                .iter()
                .map(|l2| l2 * omega_scale)
                .take_while(|&w| w < ceiling)
                .collect();
            let mut x = BandExtension::new(omega_above.len());
            x.retune(
                &omega_above,
                &damping_of(&omega_above)?,
                scene.surface_density(),
                1.0 / scene.sim_rate,
            );
            for (c, p) in pickup_points.iter().enumerate().take(2) {
                let at = blueprint.in_frame(&p.at);
                for (e, w) in x.pickup_weights_mut(c).iter_mut().enumerate() {
                    *w = list.phi_at(omega.len() + e, &at) / a;
                }
            }
            // Where the strike reaches them (`extension.rs`, "The strike"), and the mallet's
            // contact feels them (`contact_residual.rs`).
            let struck_at = blueprint.in_frame(&at);
            let phi: Vec<f64> = (0..omega_above.len())
                .map(|e| list.phi_at(omega.len() + e, &struck_at))
                .collect();
            x.set_strike(&phi);
            if let (true, ForceSignal::Mallet(_), Some(&top)) =
                (scene.strike_above, &force, omega.last())
            {
                let d = flexural_rigidity(
                    scene.material.youngs_modulus,
                    scene.thickness,
                    scene.material.poisson,
                );
                let (k, r) =
                    ContactResidual::for_plate(d, scene.surface_density(), top).map_err(scoped)?;
                model.set_contact_residual(k, r).map_err(scoped)?;
            }
            Some(x)
        } else {
            None
        };
        let info = PlateDetails {
            n_phi: omega.len(),
            n_psi: if linear_only { 0 } else { zeta4.len() },
            f_max: omega.iter().fold(0.0f64, |m, &w| m.max(w)) / two_pi,
            f_min: omega.iter().fold(f64::INFINITY, |m, &w| m.min(w)) / two_pi,
            tensor_nonzeros: if linear_only { 0 } else { nnz },
            cache,
            modal_seconds,
            scheme: scene.scheme.name().into(),
            symmetry: scene.symmetry.name().into(),
            imperfection: if linear_only {
                Vec::new()
            } else {
                scene.imperfection.clone()
            },
        };
        Ok(Self {
            model,
            above,
            force,
            step: 0,
            fs: scene.sim_rate,
            info,
        })
    }

    /// What the voice was built from.
    pub fn info(&self) -> &PlateDetails {
        &self.info
    }

    /// The underlying model.
    pub fn model(&self) -> &PlateModel<CouplingTensor> {
        &self.model
    }

    /// The band above the simulation (`plate.band_above`), if on.
    pub fn band_above(&self) -> Option<&BandExtension> {
        self.above.as_ref()
    }

    /// Shares each SAV step between two jobs run by `join`
    /// ([`PlateModel::set_step_join`]); returns whether the split is in use. Worker thread.
    pub fn set_step_join(&mut self, join: Option<std::sync::Arc<dyn super::StepJoin>>) -> bool {
        self.model.set_step_join(join)
    }

    fn force_at(&self, n: u64) -> f64 {
        match &self.force {
            ForceSignal::Strike(s) => s.force(n as f64 / self.fs),
            ForceSignal::Mallet(_) | ForceSignal::None => 0.0,
        }
    }

    /// The mallet, for a `kind = "mallet"` excitation.
    pub fn mallet(&self) -> Option<&Mallet> {
        match &self.force {
            ForceSignal::Mallet(m) => Some(m),
            _ => None,
        }
    }
}

impl RenderSource for PlateVoice {
    fn sim_rate(&self) -> f64 {
        self.fs
    }

    fn channels(&self) -> usize {
        self.model.outputs().len()
    }

    fn process(&mut self, out: &mut [Vec<f64>], frames: usize) {
        for i in 0..frames {
            // A diverged model keeps reporting its (non-finite) outputs; the renderer counts
            // them and the report says so.
            let _ = match &mut self.force {
                ForceSignal::Mallet(m) => self.model.step_with_mallet(m),
                _ => {
                    let f = self.force_at(self.step);
                    self.model.step(f)
                }
            };
            self.step += 1;
            for (c, &y) in out.iter_mut().zip(self.model.outputs()) {
                c[i] = y;
            }
            if let Some(x) = &mut self.above {
                let struck = self.model.take_struck();
                x.run(self.model.take_absorbed(), struck, 1, |_, y| {
                    for (c, y) in out.iter_mut().zip(y) {
                        c[i] += y;
                    }
                });
            }
        }
    }

    fn energy(&self) -> EnergyTerms {
        let mut e: EnergyTerms = self.model.energy().into();
        if let Some(m) = self.mallet() {
            // The joint energy of plate, mallet and felt (`MalletEnergy::joint_balance`): the
            // mallet's kinetic energy with the plate's, the felt's potential with the
            // nonlinear one, the felt loss with the modal losses; the launch is the work put
            // in, and the mallet's work on the plate is internal.
            let me = m.energy();
            e.kinetic += me.kinetic;
            e.nonlinear += me.contact;
            e.dissipated += me.dissipated;
            e.work += me.launched - me.work_on_plate;
        }
        if let Some(x) = &self.above {
            x.energy().fold_into(&mut e);
        }
        e
    }

    fn is_conservative(&self) -> bool {
        self.model.scheme().is_conservative()
    }

    fn linear_partials(&self) -> Vec<crate::analysis::dispersion::LinearPartial> {
        self.model.linear_partials()
    }

    fn details(&self) -> ModelDetails {
        ModelDetails::Plate(self.info.clone())
    }
}
