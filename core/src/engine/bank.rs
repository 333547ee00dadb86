//! The voice bank: every voice of the pool, built for one parameter set (model, quality,
//! positions, polyphony) and one host rate, plus the bank's resampler and simulation scratch.
//!
//! Built on the worker thread ([`Bank::build`], which may take seconds for large bases: modal
//! data come from the on-disk cache of [`crate::modal`] and an in-memory [`ModalCache`]);
//! moved to the audio thread through the bank queue; the replaced bank goes back to the worker
//! to be dropped.

use super::above_mix::{above_rate, AboveMix};
use super::cost_trial::Jobs;
use super::drone_bank::{drone_preview, drone_voices};
use super::drone_tuning::DroneTuning;
use super::governor::CostModel;
use super::kinds::ModelKind;
use super::memory::ModesFitted;
use super::model_spec::DRONE_MIN_SIM_RATE;
use super::params::{ParamId, ParamValues};
use super::plate_bank::{plate_sim_rate, plate_voices};
use super::pool::Lanes;
use super::resample::Resampler;
use super::sitar_bank::{sitar_preview, sitar_voices};
use super::string_bank::string_voices;
use super::voice::{Voice, VoiceModel, DRONE_FORCE_REF, SITAR_FORCE_REF};
use crate::error::ParamError;
pub use crate::models::plate::basis::ModalCache;
use crate::models::plate::StepBoard;
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

/// Transverse modes of a preview bank (`Bank::preview_of`): a plate this small builds in a
/// fraction of a second from a cold cache.
pub const PREVIEW_MODES: usize = 64;

/// In-plane modes of a preview bank.
pub const PREVIEW_IN_PLANE: usize = 8;

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
    /// The mode count the worker lowered to fit a string voice to the CPU budget
    /// (`string_bank`), if it did.
    pub fitted: Option<ModesFitted>,
    /// The voice share a string bank was fitted to (`None`: built without the governor).
    pub share: Option<f64>,
    /// Heap bytes of the coupling tensors the voices share (0 for strings, whose state is a
    /// few vectors of `N`).
    pub tensor_bytes: usize,
    /// A preview: the small model a live host plays while the full one builds
    /// ([`Self::preview_of`]).
    pub preview: bool,
    /// How a string network's strings were tuned (the drone's, the sitar's; `None` for the
    /// other models).
    pub drone_tuning: Option<DroneTuning>,
}

impl Bank {
    /// Builds the bank for `v` at `host_rate` (worker thread; allocates, may take seconds).
    /// `share` (seconds of work per second of audio), when the CPU governor is on, is the
    /// most one voice may cost: the worker prices the voices by trials
    /// (`engine/cost_trial.rs`) and fits a string's mode count to it (`string_bank`).
    /// Plate voices whose coupling tensor has at least [`crate::models::plate::SPLIT_MIN_ENTRIES`] entries offer
    /// the second half of each step on `board` (the voice pool's helpers take it).
    pub fn build(
        v: &ParamValues,
        host_rate: f64,
        cache: &mut ModalCache,
        board: &Arc<StepBoard>,
        id: u64,
        share: Option<f64>,
    ) -> Result<Bank, ParamError> {
        Self::build_as(v, host_rate, cache, board, id, share, false)
    }

    /// [`Self::build`]; `quick` builds a drone or a sitar without tuning it by ear (its preview,
    /// `engine/drone_bank.rs`). Worker thread.
    fn build_as(
        v: &ParamValues,
        host_rate: f64,
        cache: &mut ModalCache,
        board: &Arc<StepBoard>,
        id: u64,
        share: Option<f64>,
        quick: bool,
    ) -> Result<Bank, ParamError> {
        crate::error::check_positive("host_rate", host_rate)?;
        let kind = v.model();
        let voices_n = v.index_of(ParamId::Polyphony).max(1);
        let voices;
        let fitted;
        let mut drone_tuning = None;
        let sim_rate = Self::sim_rate_of(v);
        // The pickups' scale: a plate's and a string's velocity, the drone's bridge force.
        let norm = 1.0
            / if kind.is_plate() {
                PLATE_VELOCITY_REF
            } else if kind.is_drone() {
                DRONE_FORCE_REF
            } else if kind.is_sitar_taraf() {
                SITAR_FORCE_REF
            } else {
                STRING_VELOCITY_REF
            };
        let jobs = Jobs {
            host: host_rate,
            sim: sim_rate,
            // Only plates have a band above their simulation.
            above: if kind.is_plate() {
                above_rate(host_rate)
            } else {
                0.0
            },
            chunk: CHUNK,
            gain: norm,
        };
        if kind.is_plate() {
            (voices, fitted) = plate_voices(kind, v, jobs, voices_n, cache, board, share)?;
        } else if kind.is_drone() {
            voices = if quick {
                drone_tuning = Some(DroneTuning::Tensions { asked: false });
                drone_preview(v, jobs, voices_n)?
            } else {
                let (built, tuning) = drone_voices(v, jobs, voices_n, share)?;
                drone_tuning = Some(tuning);
                built
            };
            fitted = None;
        } else if kind.is_sitar_taraf() {
            voices = if quick {
                drone_tuning = Some(DroneTuning::Tensions { asked: false });
                sitar_preview(v, jobs, voices_n)?
            } else {
                let (built, tuning) = sitar_voices(v, jobs, voices_n, share)?;
                drone_tuning = Some(tuning);
                built
            };
            fitted = None;
        } else {
            (voices, fitted) = string_voices(kind, v, jobs, voices_n, share)?;
        }
        let tensor_bytes = match voices.first().map(|v| &v.model) {
            Some(VoiceModel::Plate(pv)) => pv.data.tensor_bytes,
            _ => 0,
        };
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
            fitted,
            share,
            tensor_bytes,
            preview: false,
            drone_tuning,
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
        share: Option<f64>,
    ) -> Result<(Box<Self>, Option<ParamError>), ParamError> {
        let refused = match Self::build(&wanted, host_rate, cache, board, id, share) {
            Ok(bank) => return Ok((Box::new(bank), None)),
            Err(e) => e,
        };
        for fallback in last_good.into_iter().chain([ParamValues::defaults()]) {
            // Keep the current non-rebuild values (gain, tuning, ...): only the model's
            // rebuild parameters fall back.
            let mut v = wanted;
            v.take_rebuild_values(&fallback);
            if let Ok(bank) = Self::build(&v, host_rate, cache, board, id, share) {
                return Ok((Box::new(bank), Some(refused)));
            }
            if let Ok(bank) = Self::build(&fallback, host_rate, cache, board, id, share) {
                return Ok((Box::new(bank), Some(refused)));
            }
        }
        Err(refused)
    }

    /// The preview of `v` a live host plays while the full model builds, if it has one (see
    /// [`Self::preview_of`] for plates; a drone's preview is the same drone tuned by its
    /// tensions alone, `engine/drone_bank.rs`). `None`: no preview, or it was refused (the
    /// full build reports the refusal). Worker thread.
    pub fn build_preview(
        v: &ParamValues,
        host_rate: f64,
        cache: &mut ModalCache,
        board: &Arc<StepBoard>,
        id: u64,
    ) -> Option<Bank> {
        let (values, quick) = if v.model().is_network() {
            (*v, true)
        } else {
            (Self::preview_of(v)?, false)
        };
        let mut bank = Self::build_as(&values, host_rate, cache, board, id, None, quick).ok()?;
        bank.preview = true;
        Some(bank)
    }

    /// The parameters of the preview of `v`: the same plate with at most [`PREVIEW_MODES`]
    /// transverse and [`PREVIEW_IN_PLANE`] in-plane modes (same band limit, so the same
    /// simulation rate and latency), played by a live host while the full model builds on a
    /// cold cache. `None` for strings (they build in milliseconds), the drone (whose preview
    /// has the same parameters, [`Self::build_preview`]) and plates already that small. Any
    /// thread.
    pub fn preview_of(v: &ParamValues) -> Option<ParamValues> {
        if !v.model().is_plate() || v.index_of(ParamId::Modes) <= PREVIEW_MODES {
            return None;
        }
        let mut p = *v;
        p.0[ParamId::Modes.index()] = PREVIEW_MODES as f32;
        let in_plane = v.index_of(ParamId::InPlaneModes).min(PREVIEW_IN_PLANE);
        p.0[ParamId::InPlaneModes.index()] = in_plane as f32;
        Some(p)
    }

    /// The simulation rate (Hz) a bank of the parameters `v` runs at: a plate's from its band
    /// limit and scheme ([`plate_sim_rate`]), a string's or the drone's the `sim_rate`
    /// parameter. Any thread.
    pub fn sim_rate_of(v: &ParamValues) -> f64 {
        if v.model().is_plate() {
            plate_sim_rate(
                v.get(ParamId::BandLimit) as f64,
                v.get(ParamId::SimRate) as f64,
                v.index_of(ParamId::Scheme),
                v.index_of(ParamId::InPlaneModes),
            )
        } else if v.model().is_network() {
            (v.get(ParamId::SimRate) as f64)
                .max(DRONE_MIN_SIM_RATE)
                .round()
        } else {
            v.get(ParamId::SimRate) as f64
        }
    }

    /// Latency of the bank in host samples (the resampler's half-width).
    pub fn latency_host(&self) -> f64 {
        self.resampler.latency_input() as f64 * self.host_rate / self.sim_rate
    }
}
