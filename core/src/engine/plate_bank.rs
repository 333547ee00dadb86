//! The plate voices of a bank: the basis (strike-mirror for circular plates), its tier
//! truncations, the strike and pickup frame, and one model per tier per voice.
//!
//! The simulation rate of a plate bank follows from the band limit `B`: the modes a note keeps
//! lie under `B`, and a mode is heard below [`HEARD_FRACTION`]` fs`, so `fs = B / 0.45` rounded
//! up to 100 Hz (13.4 kHz for the default 6 kHz band) for a linear plate. A nonlinear plate
//! runs at least at `B /` [`NONLINEAR_BAND_FRACTION`] (16.7 kHz for 6 kHz), so the in-plane
//! stress cannot pump the modes under the band through the time step's aliasing (see the
//! constant; a note's modes above it are overdamped, `engine/voice/plate/kept.rs`).
//! The `sim_rate` parameter, if higher, oversamples (for accuracy studies of the time step).
//!
//! Worker thread (allocates; seconds for large bases on a cold modal cache).

use super::cost_trial::{plate_prices, Jobs};
use super::governor::PRIOR_SECONDS_PER_UNIT;
use super::kinds::ModelKind;
use super::memory::{cap_bytes, fit_tiers, FitReason, ModesFitted};
use super::model_spec::{plate_spec, position};
use super::params::{ParamId, ParamValues};
use super::telemetry::SNAPSHOT_POINTS;
use super::voice::{
    band_fraction, hand_radius, tier_ladder, AboveModes, Frame, PlateData, PlateVoice, Voice,
    VoiceModel,
};
#[cfg(doc)]
use super::voice::{HEARD_FRACTION, NONLINEAR_BAND_FRACTION};
use crate::error::ParamError;
use crate::modal::TensorStorage;
use crate::models::plate::basis::{shared_tier, ModalCache, PlateBasis};
use crate::models::plate::blueprint::PlateBlueprint;
use crate::models::plate::rest_shape::ShapePart;
use crate::models::plate::spec::{PlateSpec, Position};
use crate::models::plate::{
    LinearSolve, PickupKind, PickupWeights, PlateModel, PlateParams, StepBoard, SPLIT_MIN_ENTRIES,
};
use std::f64::consts::{PI, TAU};
use std::sync::Arc;

/// Largest `ω h` of a mode at the band limit for the scheme without an exact linear part
/// (the conservative θ = 1 scheme, stable for `ω h < 2`): 1.5 leaves room for a note bent up
/// by 4 semitones (`1.5 · 2^(4/12) = 1.89`).
const THETA1_OMEGA_H: f64 = 1.5;

/// Simulation rate (Hz) of a plate bank with band limit `band_hz`, rate floor `floor_hz`,
/// scheme `scheme` (the `scheme` parameter's index) and `in_plane_modes` (0: linear): `band /
/// 0.45` rounded up to 100 Hz (module doc), `band / 0.36` for a nonlinear plate
/// ([`NONLINEAR_BAND_FRACTION`]), and for the conservative θ = 1 scheme (index 0),
/// conditionally stable, at least `2π band / 1.5` (so every mode under the band has
/// `ω h ≤ 1.5`).
pub fn plate_sim_rate(band_hz: f64, floor_hz: f64, scheme: usize, in_plane_modes: usize) -> f64 {
    let heard = band_hz / band_fraction(in_plane_modes == 0);
    let stable = if scheme == 0 {
        2.0 * PI * band_hz / THETA1_OMEGA_H
    } else {
        0.0
    };
    ((heard.max(stable) / 100.0).ceil() * 100.0).max(floor_hz)
}

/// `Φ̂_s` of every mode at the snapshot points (row-major `[point][mode]`): along the diameter
/// through angle 0 (circular; the strike's diameter in a mirror basis) or the diagonal
/// (rectangle), ends excluded.
fn snapshot_rows(kind: ModelKind, basis: &PlateBasis) -> Vec<f64> {
    let mut snapshot = Vec::with_capacity(SNAPSHOT_POINTS * basis.n_phi());
    for p in 0..SNAPSHOT_POINTS {
        let x = -0.95 + 1.9 * p as f64 / (SNAPSHOT_POINTS - 1) as f64;
        let (r, ang) = if kind == ModelKind::RectPlate {
            // ξ = η = ½ + ½ x (the diagonal), since r √2 · cos(π/4) = |x|.
            (
                x.abs() * std::f64::consts::SQRT_2,
                if x < 0.0 { 1.25 * PI } else { 0.25 * PI },
            )
        } else {
            (x.abs(), if x < 0.0 { PI } else { 0.0 })
        };
        snapshot.extend(basis.phi_all(&position(kind, r, ang)));
    }
    snapshot
}

/// The strike and pickup frame of `basis` for the parameters `v` (module doc of the voice).
fn frame(kind: ModelKind, basis: &PlateBasis, v: &ParamValues) -> Frame {
    let pickup = |r: ParamId, a: ParamId| (v.get(r) as f64, v.get(a) as f64);
    let pickups = [
        pickup(ParamId::PickupLeftPos, ParamId::PickupLeftAngle),
        pickup(ParamId::PickupRightPos, ParamId::PickupRightAngle),
    ];
    let strike_radius = v.get(ParamId::StrikeRadius) as f64;
    let orders: Option<Vec<u32>> = (0..basis.n_phi()).map(|s| basis.cosine_order(s)).collect();
    match orders {
        Some(orders) if kind != ModelKind::RectPlate => Frame::Mirror {
            basis: basis.clone(),
            strike_radius,
            pickup_radii: pickups.map(|(r, _)| r),
            orders,
            strike: basis.phi_all(&position(kind, strike_radius, 0.0)),
            hand: basis.phi_all(&position(kind, hand_radius(strike_radius), 0.0)),
            pickups: pickups.map(|(r, _)| basis.phi_all(&position(kind, r, 0.0))),
            pickup_angles: pickups.map(|(_, a)| a),
        },
        _ => Frame::Fixed {
            basis: basis.clone(),
            strike_radius,
            pickups: pickups.map(|(r, a)| basis.phi_all(&position(kind, r, a))),
            pickup_points: pickups,
        },
    }
}

/// The rest shapes per unit rise on the unit plate, `(dome, boss)`, projected on every mode of
/// the blueprint's basis ([`PlateBlueprint::rest_shape`] at size 1 and rise 1: a note of size
/// `L` and thickness `h` takes `a = L h (dome · â_dome + boss · â_boss)` with the rises in
/// thicknesses): the spherical cap `1 - r²` and the boss `cos²(π r / 2b)` of the
/// `boss_radius` parameter's `b` on circular plates (both axisymmetric: the strike-mirror
/// basis holds them exactly); the dome `16 ξ(1-ξ) η(1-η)` and no boss (zeros) on the
/// rectangle. Worker thread.
fn unit_shapes(kind: ModelKind, plate: &PlateBlueprint, v: &ParamValues) -> (Vec<f64>, Vec<f64>) {
    if kind == ModelKind::RectPlate {
        let dome = plate.rest_shape(&[ShapePart::Dome { rise: 1.0 }], Some(1.0));
        return (dome, vec![0.0; plate.basis.n_phi()]);
    }
    let cap = ShapePart::Spherical {
        rise: Some(1.0),
        curvature_radius: None,
    };
    let boss = ShapePart::Boss {
        rise: 1.0,
        radius: v.get(ParamId::BossRadius) as f64,
    };
    (
        plate.rest_shape(&[cap], Some(1.0)),
        plate.rest_shape(&[boss], Some(1.0)),
    )
}

/// The left and right pickup positions of `frame` in its own convention, for the band above:
/// `(r_p, 0)` in a mirror frame (rotated per note), the points themselves otherwise.
fn above_points(kind: ModelKind, frame: &Frame) -> [Position; 2] {
    match frame {
        Frame::Mirror { pickup_radii, .. } => pickup_radii.map(|r| position(kind, r, 0.0)),
        Frame::Fixed { pickup_points, .. } => pickup_points.map(|(r, a)| position(kind, r, a)),
    }
}

/// The strike position of `frame` for the band above: `(r_s, 0)` in a mirror frame, the
/// point of the bank's strike radius at `angle` (rad, the strike angle parameter) otherwise.
fn above_strike(kind: ModelKind, frame: &Frame, angle: f64) -> Position {
    match frame {
        Frame::Mirror { strike_radius, .. } => position(kind, *strike_radius, 0.0),
        Frame::Fixed { strike_radius, .. } => position(kind, *strike_radius, angle),
    }
}

/// The top mode's frequency (Hz) of the plate `spec` on its blueprint's basis at the root key:
/// the band above lists the modes past it ([`PlateBlueprint::modes_above`]). Worker thread.
fn top_mode_hz(spec: &PlateSpec, plate: &PlateBlueprint) -> f64 {
    let top = plate.basis.lambda2().last().copied().unwrap_or(0.0) * spec.pulsation_scale();
    top / TAU
}

/// Builds `voices_n` plate voices of `kind` for `v` at `sim_rate`, their bands above at
/// `above_rate` (see the module doc).
pub(crate) fn plate_voices(
    kind: ModelKind,
    v: &ParamValues,
    jobs: Jobs,
    voices_n: usize,
    cache: &mut ModalCache,
    board: &Arc<StepBoard>,
    share: Option<f64>,
) -> Result<(Vec<Voice>, Option<ModesFitted>), ParamError> {
    let (sim_rate, above_rate) = (jobs.sim, jobs.above);
    let wanted = v.index_of(ParamId::Modes).max(1);
    let wanted_psi = v.index_of(ParamId::InPlaneModes);
    // The plate as a scene would give it (`engine/model_spec.rs`); its counts are fitted next.
    let asked = plate_spec(kind, v, wanted, wanted_psi, sim_rate);
    // The memory cap (`engine/memory.rs`): the top tiers come off until the predicted tensors
    // fit, before anything is built.
    let key_of = |n: usize, m_psi: usize| asked.basis_key_for(n, m_psi);
    let ladder = tier_ladder(wanted, wanted_psi);
    let (modes, fitted_psi) = fit_tiers(&ladder, cap_bytes(v.get(ParamId::MemoryCap)), key_of)?[0];
    // A linear plate (no in-plane modes) stays linear: its ladder's one in-plane slot is the
    // basis's, not a mode it simulates.
    let n_psi = if wanted_psi == 0 { 0 } else { fitted_psi };
    let fitted = (modes < wanted).then_some(ModesFitted {
        wanted: wanted as u32,
        built: modes as u32,
        reason: FitReason::Memory,
    });
    let spec = PlateSpec {
        n_phi: modes,
        n_psi,
        ..asked
    };
    let plate = PlateBlueprint::new(&spec, cache)?;
    let (key, basis) = (&plate.key, &plate.basis);
    let tiers = tier_ladder(basis.n_phi(), n_psi.min(basis.zeta4().len()));
    let (shape_dome, shape_boss) = unit_shapes(kind, &plate, v);
    let frame = frame(kind, basis, v);
    let above = AboveModes::new(
        plate.modes_above(top_mode_hz(&spec, &plate)),
        above_points(kind, &frame),
        above_strike(kind, &frame, v.get(ParamId::StrikeAngle) as f64),
    );
    let scheme = spec.scheme;
    // One sub-tensor per tier, shared by the voices, in single storage: the values rounded to
    // `f32` once and every layout rebuilt from them, so the voice's discrete energy is that of
    // the rounded tensor and still conserved to `f64` round-off (tests/plates, single storage),
    // while the kernels stream half the bytes.
    // The tiers are shared with the other engines of the process that hold them
    // (`models::plate::basis::shared_tier`).
    let full = &basis.coupling;
    let single = shared_tier(key, (full.n_phi(), full.n_psi()), || {
        full.with_storage(TensorStorage::Single)
    })?;
    let couplings = tiers
        .iter()
        .map(|&(n, m)| {
            if (n, m) == (single.n_phi(), single.n_psi()) {
                Ok(single.clone())
            } else {
                shared_tier(key, (n, m), || single.truncated(n, m))
            }
        })
        .collect::<Result<Vec<_>, _>>()?;
    // The governor's prior price of a step per tier: the stored tensor entries (the kernels'
    // multiply-adds) plus the modes (the linear part and the pickups), at the prior price of
    // a unit; measured below when the governor is on.
    let tier_price = tiers
        .iter()
        .zip(&couplings)
        .map(|(&(n, _), c)| PRIOR_SECONDS_PER_UNIT * (c.nnz() + n) as f64)
        .collect();
    let tensor_bytes = single.heap_bytes()
        + couplings
            .iter()
            .filter(|c| !Arc::ptr_eq(c, &single))
            .map(|c| c.heap_bytes())
            .sum::<usize>();
    let data = Arc::new(PlateData {
        lambda2: basis.lambda2().to_vec(),
        zeta4: basis.zeta4().to_vec(),
        linear: n_psi == 0,
        frame,
        above,
        snapshot: snapshot_rows(kind, basis),
        poisson: spec.material.poisson,
        tiers: tiers.clone(),
        tier_price,
        band_hz: v.get(ParamId::BandLimit) as f64,
        tensor_bytes,
        shape_dome,
        shape_boss,
    });
    let mut voices = Vec::with_capacity(voices_n);
    for _ in 0..voices_n {
        let mut models = Vec::with_capacity(tiers.len());
        for (&(n, m), coupling) in tiers.iter().zip(&couplings) {
            // Built with neutral coefficients (the exact scheme accepts any ω); every note
            // retunes them in place before it sounds.
            let params = PlateParams {
                omega: vec![1.0; n],
                zeta4: vec![1.0; m],
                rho_h: 1.0,
                e_h: 1.0,
                coupling_scale: 0.0,
                fs: sim_rate,
                damping: vec![0.0; n],
                scheme,
                solve: LinearSolve::Auto,
            };
            let pickups = vec![
                PickupWeights::new(vec![0.0; n], PickupKind::VelocityBackward)?,
                PickupWeights::new(vec![0.0; n], PickupKind::VelocityBackward)?,
            ];
            let mut model = PlateModel::new(&params, coupling.clone(), vec![0.0; n], pickups)?;
            if coupling.nnz() >= SPLIT_MIN_ENTRIES {
                model.set_step_board(Some(board.clone()));
            }
            models.push(model);
        }
        voices.push(Voice::new(VoiceModel::Plate(Box::new(PlateVoice::new(
            models,
            data.clone(),
            sim_rate,
            above_rate,
        )))));
    }
    // Under the CPU governor the tiers are priced by trials of the first voice
    // (`engine/cost_trial.rs`), and every voice shares the measured prices.
    if let (Some(share), Some(first)) = (share, voices.first_mut()) {
        if let Some(prices) = plate_prices(first, v, jobs, share) {
            let measured = Arc::new(PlateData {
                tier_price: prices,
                ..(*data).clone()
            });
            for voice in &mut voices {
                if let VoiceModel::Plate(pv) = &mut voice.model {
                    pv.data = measured.clone();
                }
            }
        }
    }
    Ok((voices, fitted))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The default 6 kHz band: 13.4 kHz for a linear plate, 16.7 kHz for a nonlinear one (the
    /// top mode's alias of the parametric resonance then lies at `fs - 2B` = 4.7 kHz, not
    /// 1.4 kHz), the `sim_rate` floor when higher, and the θ = 1 scheme's stability bound
    /// (`2π · 6000 / 1.5` = 25.13 kHz) when that is higher still. Exact: rounded to 100 Hz.
    #[test]
    fn a_nonlinear_plate_runs_at_its_band_over_0_36() {
        assert_eq!(plate_sim_rate(6000.0, 8000.0, 3, 0), 13_400.0);
        assert_eq!(plate_sim_rate(6000.0, 8000.0, 3, 15), 16_700.0);
        assert_eq!(plate_sim_rate(6000.0, 31_200.0, 3, 15), 31_200.0);
        assert_eq!(plate_sim_rate(6000.0, 8000.0, 0, 15), 25_200.0);
    }
}
