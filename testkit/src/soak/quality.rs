//! Changes of the parameters that make the engine's worker rebuild the voice bank (model,
//! quality, positions, polyphony): drawn in bursts, like a knob being dragged, and closed by
//! a final step that sets the bank's signature (model, simulation rate, polyphony).
//!
//! A bank whose signature equals the final step's can only have been built from a key
//! containing the final step: the earlier steps of a burst never touch the signature
//! parameters, and the final signature always differs from the bank in use. So "the bank
//! in use has the requested signature" means "the requested rebuild arrived".
//!
//! Threads: driver thread, between blocks (writes [`SharedParams`], which is lock-free).

use super::draw::Draw;
use super::SoakConfig;
use noether_core::engine::{
    plate_sim_rate, Engine, ModelKind, ParamId, ParamInfo, ParamValues, SharedParams,
    DRONE_MIN_SIM_RATE, PARAMS, SCHEME_NAMES,
};
use noether_core::ParamError;

/// The properties of a voice bank the engine reports, which a burst's final step sets.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Signature {
    /// Model of the bank.
    pub model: ModelKind,
    /// Simulation rate (Hz).
    pub sim_rate: f64,
    /// Voices in the pool.
    pub polyphony: usize,
}

impl std::fmt::Display for Signature {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} at {:.0} Hz, {} voices",
            self.model.key(),
            self.sim_rate,
            self.polyphony
        )
    }
}

/// The signature of the bank `e` uses (`None` before the first bank).
pub(super) fn signature(e: &Engine) -> Option<Signature> {
    Some(Signature {
        model: e.model()?,
        sim_rate: e.sim_rate()?,
        polyphony: e.polyphony(),
    })
}

/// The parameters of a burst's final step (the signature and the quality).
const FINAL: [ParamId; 9] = [
    ParamId::Model,
    ParamId::DroneEar,
    ParamId::Jivari,
    ParamId::SimRate,
    ParamId::BandLimit,
    ParamId::Polyphony,
    ParamId::Modes,
    ParamId::InPlaneModes,
    ParamId::Scheme,
];

/// Strings of the largest drone (each stepped every step).
const DRONE_MAX_STRINGS: usize = 6;

/// In-plane modes of the gong a split-step burst asks for ([`finish_split`]).
const SPLIT_IN_PLANE: usize = 15;

/// The taraf of a sitar burst (each string 48 modes).
const SITAR_SOAK_TARAF: usize = 3;

/// The modes a sitar burst steps: the played string's fewest (32), the taraf and one chikari
/// (at most 40 modes, at the lowest Sa).
const SITAR_SOAK_MODES: usize = 32 + SITAR_SOAK_TARAF * 48 + 40;

/// The jivari (mm) of a drone burst: at 30 mm the drone's strings need only 49 modes.
const DRONE_JIVARI: f32 = 30.0;

/// The modes of each string of a drone at [`DRONE_JIVARI`] (`engine::drone_modes`).
const DRONE_STRING_MODES: usize = 49;

/// Whether a change of `p` needs a new bank when the parameters hold `v`: the table's flag,
/// for the string models the size (the string's length sets the grid) and for the string
/// networks (the drone, the sitar with its taraf) the root key (where it is tuned; see [`ParamValues::rebuild_key`]). The driver automates every
/// other parameter each block.
pub fn needs_rebuild(p: &ParamInfo, v: &ParamValues) -> bool {
    let model = v.model();
    p.rebuild
        || (p.id == ParamId::Size && model.is_string())
        || (p.id == ParamId::RootKey && model.is_network())
}

/// One intermediate step of a burst: each rebuild parameter outside the final step's set is
/// redrawn over its whole range with probability ½. Returns the number of writes.
pub fn step(d: &mut Draw, params: &SharedParams) -> Result<u64, ParamError> {
    let v = params.snapshot();
    let mut writes = 0;
    for p in PARAMS
        .iter()
        .filter(|p| needs_rebuild(p, &v) && !FINAL.contains(&p.id))
    {
        if d.chance(0.5) {
            params.set(p.id, d.value(p))?;
            writes += 1;
        }
    }
    Ok(writes)
}

/// The final step of a burst: a model, a simulation rate log-uniform over the whole range
/// (8 kHz to 400 kHz unless `cfg` lowers it) and a band limit log-uniform over its range (a
/// plate bank runs at the higher of the two rates, see [`plate_sim_rate`]), a scheme, and modes, in-plane modes and
/// polyphony within `cfg`'s limits, reduced until `modes · polyphony · sim_rate` fits the
/// load budget `cfg.budget` (mode-steps per second of audio; the soak stays bounded in wall
/// time). For a string model its length (the `size` parameter) is drawn here too. The
/// simulation rate is moved by 1 % and the band by 2.5 % if the draw equals `current`'s, so
/// the signature always changes. One burst in `1 / cfg.split_chance` asks instead for a gong
/// whose voice splits its steps ([`finish_split`]). Returns the requested signature and
/// whether the plate must stay flat while that bank plays (`dome` and `boss` at 0: only a
/// flat plate runs the fused kernel that splits).
pub fn finish(
    d: &mut Draw,
    params: &SharedParams,
    cfg: &SoakConfig,
    current: Option<Signature>,
) -> Result<(Signature, bool), ParamError> {
    if d.chance(cfg.split_chance) {
        return Ok((finish_split(d, params, current)?, true));
    }
    let model = d.below(ModelKind::ALL.len() as u64) as usize;
    let info = |id: ParamId| id.info();
    let rate_hi = cfg.max_sim_rate.min(info(ParamId::SimRate).max as f64);
    let rate_lo = info(ParamId::SimRate).min as f64;
    let mut sim_rate = match d.unit() {
        u if u < 0.1 => rate_lo,
        u if u < 0.2 => rate_hi,
        _ => d.log_between(rate_lo, rate_hi),
    }
    .round();
    let mut modes = d.log_between(4.0, cfg.max_modes as f64 + 1.0).floor() as usize;
    let mut poly = 1 + d.below(cfg.max_polyphony as u64) as usize;
    let band_range = info(ParamId::BandLimit);
    let mut band = d
        .log_between(band_range.min as f64, band_range.max as f64)
        .round();
    let kind = ModelKind::from_index(model);
    if kind.is_drone() {
        // The drone runs at least at its floor; it steps every string's modes, so its rate is
        // kept within the budget for the largest drone, one voice.
        let cap = cfg.budget / (DRONE_MAX_STRINGS * DRONE_STRING_MODES) as f64;
        sim_rate = sim_rate.min(cap).max(DRONE_MIN_SIM_RATE).round();
        modes = 4;
        poly = 1;
    }
    if kind.is_sitar_taraf() {
        // The sitar steps every string: a played string of its fewest modes, a small taraf
        // and one chikari, at a rate within the budget, one voice.
        let cap = cfg.budget / SITAR_SOAK_MODES as f64;
        sim_rate = sim_rate.min(cap).max(DRONE_MIN_SIM_RATE).round();
        modes = 4;
        poly = 1;
    }
    let scheme = d.value(info(ParamId::Scheme));
    let in_plane = if d.chance(0.2) {
        0
    } else {
        d.below(cfg.max_in_plane as u64 + 1) as usize
    };
    // The rate the bank will run at (the parameters are `f32`).
    let rate_of = |sim_rate: f64, band: f64| {
        let sim = sim_rate as f32 as f64;
        if kind.is_plate() {
            plate_sim_rate(band as f32 as f64, sim, scheme as usize, in_plane)
        } else {
            sim
        }
    };
    while (modes * poly) as f64 * rate_of(sim_rate, band) > cfg.budget && (poly > 1 || modes > 4) {
        if poly > 1 {
            poly -= 1;
        } else {
            modes -= 1;
        }
    }
    if current.is_some_and(|c| c.sim_rate == rate_of(sim_rate, band)) {
        // 2.5 % moves a band-derived rate (≥ 8 kHz, rounded to 100 Hz) by at least 200 Hz.
        let nudge = |x: f64, hi: f64, by: f64| {
            if x * by <= hi {
                (x * by).round()
            } else {
                (x / by).round()
            }
        };
        sim_rate = nudge(sim_rate, rate_hi, 1.01);
        band = nudge(band, band_range.max as f64, 1.025);
    }
    if !kind.is_plate() {
        params.set(ParamId::Size, d.value(info(ParamId::Size)))?;
    }
    // The drone is never tuned by ear in the soak (seconds of the worker's time per build)
    // and keeps its coarsest grid.
    params.set(ParamId::DroneEar, 0.0)?;
    params.set(ParamId::Jivari, DRONE_JIVARI)?;
    params.set(ParamId::TarafStrings, SITAR_SOAK_TARAF as f32)?;
    params.set(ParamId::ChikariStrings, 1.0)?;
    params.set(ParamId::Scheme, scheme)?;
    params.set(ParamId::Modes, modes as f32)?;
    params.set(ParamId::InPlaneModes, in_plane as f32)?;
    params.set(ParamId::Polyphony, poly as f32)?;
    params.set(ParamId::SimRate, sim_rate as f32)?;
    params.set(ParamId::BandLimit, band as f32)?;
    params.set(ParamId::Model, model as f32)?;
    Ok((
        Signature {
            model: kind,
            sim_rate: rate_of(sim_rate, band),
            polyphony: poly,
        },
        false,
    ))
}

/// The final step of a burst that asks for split steps: a gong on the `sav` scheme with 15
/// in-plane modes, `modes` 800 and a band of 11.5 to 12 kHz, so that most notes (whatever
/// the automated size and thickness) keep all 800 strike-mirror modes, a coupling tensor of
/// about 1.6e5 entries, above `SPLIT_MIN_ENTRIES`; one voice, the simulation rate from the
/// band. Returns the requested signature (changed from
/// `current`: the band moves by 2.5 % if the rate would not).
fn finish_split(
    d: &mut Draw,
    params: &SharedParams,
    current: Option<Signature>,
) -> Result<Signature, ParamError> {
    let sav = SCHEME_NAMES
        .iter()
        .position(|n| n.starts_with("SAV") || n.starts_with("sav"))
        .expect("the sav scheme") as f32;
    let floor = ParamId::SimRate.info().min as f64;
    let poly = 1;
    let mut band = d.between(11_500.0, 12_000.0).round();
    let rate = |band: f64| {
        plate_sim_rate(
            band as f32 as f64,
            floor as f32 as f64,
            sav as usize,
            SPLIT_IN_PLANE,
        )
    };
    if current.is_some_and(|c| c.sim_rate == rate(band)) {
        band = (band * 1.025).round();
    }
    params.set(ParamId::Scheme, sav)?;
    params.set(ParamId::Modes, 800.0)?;
    params.set(ParamId::InPlaneModes, SPLIT_IN_PLANE as f32)?;
    params.set(ParamId::Polyphony, poly as f32)?;
    params.set(ParamId::SimRate, floor as f32)?;
    params.set(ParamId::BandLimit, band as f32)?;
    params.set(ParamId::Model, 0.0)?;
    Ok(Signature {
        model: ModelKind::Gong,
        sim_rate: rate(band),
        polyphony: poly,
    })
}
