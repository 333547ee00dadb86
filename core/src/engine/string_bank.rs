//! The string voices of a bank: the instrument's string as a scene's `[string]` specification
//! (one vocabulary, one table of ranges), and, under the CPU governor, the mode count that
//! keeps one voice within its share of real time.
//!
//! **Fitting a string to the budget.** A plate's note can start on a narrower tier of its
//! bank; a string voice is one model, so its cost is fitted when the bank is built. The worker
//! times a trial voice (`engine/cost_trial.rs`: the root key plucked at full strength, the
//! attack's contact included, in windows of about a host block, in thread CPU time). Its load
//! (seconds of work per second of audio) must stay within the voice's share, on average and
//! within [`WORST_WINDOW`] times it in the worst window; if not, the mode count comes down in
//! proportion (the step is `O(N log N)` or `O(N · rows)`, nearly linear in `N`) with a margin
//! and the trial runs again, at most [`FIT_ATTEMPTS`] trials. The reduction is reported with
//! the bank ([`ModesFitted`]), and the last trial's price per step goes with every voice (the
//! governor's note-on check, `engine/governor.rs`). Off the governor (offline renders) the
//! string keeps every mode it asks for.
//!
//! Worker thread (allocates; a trial takes at most `TRIAL_CPU_LIMIT · TRIAL_SECONDS` of CPU
//! time, so a fit at most a second or so).

use super::cost_trial::{time_note, Jobs};
use super::kinds::ModelKind;
use super::memory::{FitReason, ModesFitted};
use super::params::{ParamId, ParamValues};
use super::voice::{StringVoice, Voice, VoiceModel};
use crate::error::ParamError;
use crate::models::quantity::Quantity;
use crate::models::string::spec::{
    StringContact, StringExcitation, StringObstacle, StringOutput, StringSpec,
};
use crate::models::string::{Readout, StiffString, StringConfig, ValetteLosses};

/// Steel density used to derive a string's diameter from its linear density (air losses).
const STRING_STEEL_DENSITY: f64 = 7850.0;

/// The worst window may cost this many times the voice's share (the governor's target: no
/// block above twice real time).
pub(crate) const WORST_WINDOW: f64 = 2.0;

/// Trials at most (each after a reduction).
pub(crate) const FIT_ATTEMPTS: usize = 5;

/// Share of the proportional reduction kept as margin (the cost is not exactly linear in
/// the mode count).
const FIT_MARGIN: f64 = 0.85;

/// Fewest modes a fitted string keeps.
pub(crate) const MIN_FITTED_MODES: usize = 16;

/// The string voices of a bank of `kind` for the parameters `v` at `jobs.sim` (Hz), and the
/// fitted mode count if `share` (the largest load of one voice, seconds per second) made the
/// worker reduce it. Worker thread.
pub(super) fn string_voices(
    kind: ModelKind,
    v: &ParamValues,
    jobs: Jobs,
    voices_n: usize,
    share: Option<f64>,
) -> Result<(Vec<Voice>, Option<ModesFitted>), ParamError> {
    let sim_rate = jobs.sim;
    let wanted = v.index_of(ParamId::Modes).max(1);
    let mut modes = wanted;
    let mut config = string_config(kind, v, modes, sim_rate)?;
    // The measured price of a step of the string as built (`None`: not measured).
    let mut price = None;
    if let Some(share) = share {
        for attempt in 1..=FIT_ATTEMPTS {
            let mut trial = string_voice(&config)?;
            let Some(load) = time_note(&mut trial, v, jobs) else {
                break;
            };
            price = Some(load.price);
            let scale = (share / load.mean).min(WORST_WINDOW * share / load.worst);
            if scale >= 1.0 || modes <= MIN_FITTED_MODES || attempt == FIT_ATTEMPTS {
                break;
            }
            modes = ((modes as f64 * scale * FIT_MARGIN) as usize).max(MIN_FITTED_MODES);
            config = string_config(kind, v, modes, sim_rate)?;
        }
    }
    let mut voices = Vec::with_capacity(voices_n);
    for _ in 0..voices_n {
        let mut voice = string_voice(&config)?;
        if let (Some(price), VoiceModel::String(sv)) = (price, &mut voice.model) {
            sv.price = price;
        }
        voices.push(voice);
    }
    let fitted = (modes < wanted).then_some(ModesFitted {
        wanted: wanted as u32,
        built: modes as u32,
        reason: FitReason::Cpu,
    });
    Ok((voices, fitted))
}

/// A silent string voice of `config`. Worker thread.
fn string_voice(config: &StringConfig) -> Result<Voice, ParamError> {
    let model = StiffString::new(config)?;
    Ok(Voice::new(VoiceModel::String(Box::new(StringVoice::new(
        model,
        ValetteLosses::default(),
    )))))
}

/// The instrument's string for `v` with `modes` modes at `sim_rate`, validated.
fn string_config(
    kind: ModelKind,
    v: &ParamValues,
    modes: usize,
    sim_rate: f64,
) -> Result<StringConfig, ParamError> {
    let spec = string_spec(kind, v, modes, sim_rate);
    spec.validate()?;
    Ok(spec.config())
}

/// The instrument's string as a specification.
fn string_spec(kind: ModelKind, v: &ParamValues, modes: usize, sim_rate: f64) -> StringSpec {
    let length = v.get(ParamId::Size) as f64;
    let mu = v.get(ParamId::LinearDensity) as f64;
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
        quantity: Quantity::Velocity,
        readout: Readout::Modal,
    };
    StringSpec {
        length,
        diameter: (4.0 * mu / (std::f64::consts::PI * STRING_STEEL_DENSITY)).sqrt(),
        tension: v.get(ParamId::Tension) as f64,
        linear_density: mu,
        inharmonicity: Some(v.get(ParamId::Inharmonicity) as f64),
        bending_stiffness: None,
        modes,
        sim_rate,
        losses: ValetteLosses::default().into(),
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
    }
}
