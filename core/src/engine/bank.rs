//! The voice bank: every voice of the pool, built for one parameter set (model, quality,
//! positions, polyphony) and one host rate, plus the bank's resampler and simulation scratch.
//!
//! Built on the worker thread ([`Bank::build`], which may take seconds for large bases: modal
//! data come from the on-disk cache of [`crate::modal`] and an in-memory [`ModalCache`]);
//! moved to the audio thread through the bank queue; the replaced bank goes back to the worker
//! to be dropped.

use super::above_mix::{above_rate, AboveMix};
use super::governor::CostModel;
use super::kinds::ModelKind;
use super::params::{ParamId, ParamValues};
use super::plate_bank::{plate_sim_rate, plate_voices};
use super::pool::Lanes;
use super::resample::Resampler;
use super::voice::{StringVoice, Voice, VoiceModel};
use crate::error::ParamError;
pub use crate::models::plate::basis::ModalCache;
use crate::models::plate::StepBoard;
use crate::models::string::spec::{
    StringContact, StringExcitation, StringObstacle, StringOutput, StringQuantity, StringReadout,
    StringSpec,
};
use crate::models::string::{StiffString, ValetteLosses};
use std::sync::Arc;

/// Host-rate samples per internal chunk: events, parameter reads and bank swaps happen on
/// chunk boundaries at the latest, and the simulation scratch is sized for one chunk.
pub const CHUNK: usize = 64;

/// Output normalisation of plates: the pickups read velocity (m/s), divided by this
/// reference (measured by `tests/engine/engine.rs::presets_sound_and_decay`, key 60, velocity 1:
/// gong-40N peaks at 0.58, gong-80N at 0.87, rect-plate at 0.33 full scale).
pub const PLATE_VELOCITY_REF: f64 = 1.0;

/// Output normalisation of strings (m/s), as [`PLATE_VELOCITY_REF`] (the buzzing sitar preset
/// at key 60, velocity 1 peaks at 3.9 m/s: 0.97 full scale, 0.49 after its -6 dB gain).
pub const STRING_VELOCITY_REF: f64 = 4.0;

/// Steel density used to derive a string's diameter from its linear density (air losses).
const STRING_STEEL_DENSITY: f64 = 7850.0;

/// A bank of voices for one parameter set and host rate.
pub(crate) struct Bank {
    /// Identifier (increments with every build).
    pub id: u64,
    pub kind: ModelKind,
    /// Simulation rate (Hz).
    pub sim_rate: f64,
    /// Host rate it was built for (Hz).
    pub host_rate: f64,
    pub voices: Vec<Voice>,
    pub resampler: Resampler,
    /// The chunk's mix, left (simulation rate; audio thread).
    pub sim_l: Vec<f32>,
    /// The chunk's mix, right.
    pub sim_r: Vec<f32>,
    /// One job lane per voice (same index): the voice's output for the current chunk
    /// (simulation rate), written by whichever thread of the voice pool runs the voice and
    /// added to `sim_l`/`sim_r` by the audio thread, in voice order, only if the voice stayed
    /// within [`super::VOICE_CEILING`] (a runaway voice's partial chunk is dropped with it).
    pub lanes: Box<Lanes>,
    /// Output scale (1 / velocity reference).
    pub norm: f64,
    /// The chunk's mix of the voices' bands above the simulation (host rate, audio thread).
    pub above: AboveMix,
    /// The parameters it was built from (the last good model when a later set is refused).
    pub values: ParamValues,
    /// The engine activation it was built for (see `handle::BuildRequest`).
    pub generation: u64,
    /// The CPU governor's cost of a work unit for this bank's voices (audio thread).
    pub cost: CostModel,
}

impl Bank {
    /// Builds the bank for `v` at `host_rate` (worker thread; allocates, may take seconds).
    /// Plate voices whose coupling tensor has at least [`crate::models::plate::SPLIT_MIN_ENTRIES`] entries offer
    /// the second half of each step on `board` (the voice pool's helpers take it).
    pub fn build(
        v: &ParamValues,
        host_rate: f64,
        cache: &mut ModalCache,
        board: &Arc<StepBoard>,
        id: u64,
    ) -> Result<Bank, ParamError> {
        crate::error::check_positive("host_rate", host_rate)?;
        let kind = ModelKind::from_params(v);
        let voices_n = v.index_of(ParamId::Polyphony).max(1);
        let modes = v.index_of(ParamId::Modes).max(1);
        let mut voices = Vec::with_capacity(voices_n);
        let norm;
        let sim_rate = Self::sim_rate_of(v);
        if kind.is_plate() {
            norm = 1.0 / PLATE_VELOCITY_REF;
            voices = plate_voices(
                kind,
                v,
                (sim_rate, above_rate(host_rate)),
                voices_n,
                cache,
                board,
            )?;
        } else {
            norm = 1.0 / STRING_VELOCITY_REF;
            let length = v.get(ParamId::Size) as f64;
            let mu = v.get(ParamId::LinearDensity) as f64;
            // The instrument's string as a specification, validated and built as a scene's
            // `[string]` table is (one vocabulary, one table of ranges).
            let losses = ValetteLosses::default();
            // The contact law `f = K [η]_+^α` is a force per unit length. The sitar's curved
            // bridge spans several nodes, so its force converges as the grid refines. The
            // tanpura's point bridge sits on the nodes within `POINT_WIDTH` of its position (at
            // least the nearest one): a force density on those nodes alone would make the
            // bridge's total stiffness `K n Δx` follow the mode count. It is scaled to the
            // stiffness of a contact patch `POINT_WIDTH` long, `K · POINT_WIDTH`, at every grid:
            // 1 mm is the lecture's tanpura grid spacing (1 m / 1008), whose one-node contact
            // is that patch, so on that grid the scale is 1.
            const POINT_WIDTH: f64 = 1e-3;
            let k_contact = v.get(ParamId::ContactStiffness) as f64;
            let dx = length / (modes + 1) as f64;
            let (obstacle, k_contact) = if kind == ModelKind::Sitar {
                // The grid resolves the curved bridge on the nodes it spans; one shorter than
                // a grid spacing acts on the first node (as the tanpura's point bridge acts
                // on the nearest node), so every bridge length builds at every mode count.
                let bridge = StringObstacle::Sitar {
                    position: 0.0,
                    curvature: v.get(ParamId::BridgeCurvature) as f64,
                    height: 0.0,
                    extent: (v.get(ParamId::BridgePosition) as f64 * length).max(dx),
                };
                (bridge, k_contact)
            } else {
                let position = v.get(ParamId::BridgePosition) as f64 * length;
                let on_patch = (1..=modes)
                    .filter(|&i| (i as f64 * dx - position).abs() <= 0.5 * POINT_WIDTH)
                    .count()
                    .max(1);
                let bridge = StringObstacle::Point {
                    position,
                    height: 0.0,
                    width: POINT_WIDTH,
                };
                (bridge, k_contact * POINT_WIDTH / (on_patch as f64 * dx))
            };
            // Pickups read the modal sum, exact at any grid (linear interpolation between
            // nodes would low-pass the bridge's high partials by an amount that depends on the
            // mode count).
            let pickup = |id: ParamId| StringOutput::Pickup {
                position: v.get(id) as f64 * length,
                quantity: StringQuantity::Velocity,
                readout: StringReadout::Modal,
            };
            let spec = StringSpec {
                length,
                diameter: (4.0 * mu / (std::f64::consts::PI * STRING_STEEL_DENSITY)).sqrt(),
                tension: v.get(ParamId::Tension) as f64,
                linear_density: mu,
                inharmonicity: Some(v.get(ParamId::Inharmonicity) as f64),
                bending_stiffness: None,
                modes,
                sim_rate,
                losses: losses.into(),
                obstacle,
                contact: StringContact {
                    stiffness: k_contact,
                    exponent: v.get(ParamId::ContactAlpha) as f64,
                },
                contact_scheme: "newton".into(),
                sav_relaxation: crate::models::string::spec::default_contact_relaxation(),
                excitation: StringExcitation::Pluck {
                    position: v.get(ParamId::PluckPosition) as f64 * length,
                    amplitude: v.get(ParamId::PluckAmplitude) as f64,
                },
                outputs: vec![
                    pickup(ParamId::PickupLeftPos),
                    pickup(ParamId::PickupRightPos),
                ],
                snapshots: Vec::new(),
            };
            spec.validate()?;
            let config = spec.config();
            for _ in 0..voices_n {
                let model = StiffString::new(&config)?;
                voices.push(Voice::new(VoiceModel::String(Box::new(StringVoice::new(
                    model, losses,
                )))));
            }
        }
        let resampler = Resampler::new(sim_rate, host_rate, CHUNK);
        let max_in = resampler.max_input();
        // The band above is delayed to the resampler's latency, to sound with the band below.
        let latency = (resampler.latency_input() as f64 * host_rate / sim_rate).round() as usize;
        let above = AboveMix::new(host_rate, CHUNK, latency);
        Ok(Bank {
            id,
            kind,
            sim_rate,
            host_rate,
            voices,
            resampler,
            sim_l: vec![0.0; max_in],
            sim_r: vec![0.0; max_in],
            lanes: Lanes::new(voices_n, max_in, above.max_input()),
            above,
            norm,
            values: *v,
            generation: 0,
            cost: CostModel::default(),
        })
    }

    /// Builds a bank for `wanted`, or when the models refuse it, for `last_good` (the parameters
    /// of the bank that was playing) or the table's defaults: returns the bank and the refusal.
    /// Worker thread (allocates). `Err` only if no candidate builds.
    pub fn build_playable(
        wanted: ParamValues,
        last_good: Option<ParamValues>,
        host_rate: f64,
        cache: &mut ModalCache,
        board: &Arc<StepBoard>,
        id: u64,
    ) -> Result<(Box<Self>, Option<ParamError>), ParamError> {
        let refused = match Self::build(&wanted, host_rate, cache, board, id) {
            Ok(bank) => return Ok((Box::new(bank), None)),
            Err(e) => e,
        };
        for fallback in last_good.into_iter().chain([ParamValues::defaults()]) {
            // Keep the current non-rebuild values (gain, tuning, ...): only the model's
            // rebuild parameters fall back.
            let mut v = wanted;
            v.take_rebuild_values(&fallback);
            if let Ok(bank) = Self::build(&v, host_rate, cache, board, id) {
                return Ok((Box::new(bank), Some(refused)));
            }
            if let Ok(bank) = Self::build(&fallback, host_rate, cache, board, id) {
                return Ok((Box::new(bank), Some(refused)));
            }
        }
        Err(refused)
    }

    /// The simulation rate (Hz) a bank of the parameters `v` runs at: a plate's from its band
    /// limit and scheme ([`plate_sim_rate`]), a string's the `sim_rate` parameter. Any thread.
    pub fn sim_rate_of(v: &ParamValues) -> f64 {
        if ModelKind::from_params(v).is_plate() {
            plate_sim_rate(
                v.get(ParamId::BandLimit) as f64,
                v.get(ParamId::SimRate) as f64,
                v.index_of(ParamId::Scheme),
            )
        } else {
            v.get(ParamId::SimRate) as f64
        }
    }

    /// Latency of the bank in host samples (the resampler's half-width).
    pub fn latency_host(&self) -> f64 {
        self.resampler.latency_input() as f64 * self.host_rate / self.sim_rate
    }
}
