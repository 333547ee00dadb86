//! The one conversion from the instrument's parameter values to the models' specifications:
//! a plate's [`PlateSpec`], a string's [`StringSpec`], the drone's [`TanpuraSpec`] and the
//! sitar's [`SitarSpec`], the same tables a scene's `[plate]`, `[string]`, `[tanpura]` and
//! `[sitar]` give. The banks build their voices from them (`engine/plate_bank.rs`,
//! `engine/string_bank.rs`) through the models' own builders, so a plate or a string is named,
//! keyed, placed and shaped one way whether a scene or the instrument plays it.
//!
//! A spec describes the root key's note struck at full velocity: the notes retune it per key
//! (`engine/voice/mapping.rs`), and the exciter's strength follows the velocity.
//!
//! Worker thread (allocates).

use super::kinds::ModelKind;
use super::params::{ParamId, ParamValues};
use super::voice::{mallet_law, MALLET_LOSS};
use crate::models::plate::mallet_heads::MalletHead;
use crate::models::plate::spec::{
    Damping, Excitation, Pickup, PlateScheme, PlateShape, PlateSpec, Position, ShapePart, Symmetry,
    TensorStorage,
};
use crate::models::quantity::Quantity;
use crate::models::sitar::{SitarSpec, Thaat};
use crate::models::string::spec::{
    StringContact, StringExcitation, StringObstacle, StringOutput, StringSpec,
};
use crate::models::string::{Readout, ValetteLosses};
use crate::models::tanpura::{Pattern, TanpuraSpec, Tuning};

/// Largest onset shift of the drone's cycle at full human variation, ms.
const DRONE_MAX_TIMING_JITTER_MS: f64 = 20.0;

/// Largest relative change of a drone pluck's strength at full human variation.
const DRONE_MAX_STRENGTH_JITTER: f64 = 0.2;

/// Steel density used to derive a string's diameter from its linear density (air losses).
const STRING_STEEL_DENSITY: f64 = 7850.0;

/// A polar parameter pair `(r, angle)` as a position: circular plates read it as it is;
/// rectangles as `(ξ, η) = (½ + ½ r cos θ, ½ + ½ r sin θ)` (fractions of the sides).
pub(crate) fn position(kind: ModelKind, r: f64, angle: f64) -> Position {
    if kind == ModelKind::RectPlate {
        Position {
            x: Some(0.5 + 0.5 * r * angle.cos()),
            y: Some(0.5 + 0.5 * r * angle.sin()),
            ..Position::default()
        }
    } else {
        Position {
            r: Some(r),
            angle: Some(angle),
            ..Position::default()
        }
    }
}

/// The geometry and modal subspace of a plate model: the rectangle simply supported in the
/// full basis, the cymbal clamped and the gongs free, both in the strike-mirror subspace.
pub(crate) fn plate_shape(kind: ModelKind) -> (PlateShape, Symmetry) {
    match kind {
        ModelKind::RectPlate => (PlateShape::RectSs, Symmetry::Full),
        ModelKind::Cymbal => (PlateShape::CircularClamped, Symmetry::StrikeMirror),
        _ => (PlateShape::CircularFree, Symmetry::StrikeMirror),
    }
}

/// The instrument's plate for `v` with `n_phi` transverse and `n_psi` in-plane modes (0: a
/// linear plate) at `sim_rate` (Hz), as a scene's `[plate]` table (module doc): the size is
/// the radius, or `lx` with `ly = aspect · lx`; the damping law `scale · (a ω^b + c0)`; the
/// strike at the strike position and angle, a pulse of the strike force or the mallet at its
/// speed; the dome and the boss in thicknesses as rises in metres; two velocity pickups.
///
/// The parameter table's ranges are the instrument's, and a few reach past a scene's (the
/// damping scale multiplies `a` up to 20 times): validate the spec before a scene renders it.
pub(crate) fn plate_spec(
    kind: ModelKind,
    v: &ParamValues,
    n_phi: usize,
    n_psi: usize,
    sim_rate: f64,
) -> PlateSpec {
    let get = |id: ParamId| v.get(id) as f64;
    let (shape, symmetry) = plate_shape(kind);
    let size = get(ParamId::Size);
    let rect = kind == ModelKind::RectPlate;
    let h = get(ParamId::Thickness);
    let scale = get(ParamId::DampingScale);
    let at = position(kind, get(ParamId::StrikeRadius), get(ParamId::StrikeAngle));
    let excitation = if v.index_of(ParamId::Exciter) == 1 {
        let (mass, stiffness, exponent, loss, head) = match v.index_of(ParamId::MalletHead) {
            0 => {
                let (k, alpha) = mallet_law(get(ParamId::MalletHardness));
                (
                    Some(get(ParamId::MalletMass)),
                    Some(k),
                    Some(alpha),
                    Some(MALLET_LOSS),
                    None,
                )
            }
            i => (
                None,
                None,
                None,
                None,
                Some(MalletHead::ALL[(i - 1).min(MalletHead::ALL.len() - 1)]),
            ),
        };
        Excitation::Mallet {
            at,
            head,
            mass,
            stiffness,
            exponent,
            speed: get(ParamId::MalletSpeed),
            loss,
        }
    } else {
        Excitation::Strike {
            at,
            duration: get(ParamId::StrikeDuration),
            peak_force: get(ParamId::StrikeForce),
        }
    };
    let mut imperfection = Vec::new();
    let (dome, boss) = (get(ParamId::Dome), get(ParamId::Boss));
    if dome > 0.0 {
        imperfection.push(if rect {
            ShapePart::Dome { rise: dome * h }
        } else {
            ShapePart::Spherical {
                rise: Some(dome * h),
                curvature_radius: None,
            }
        });
    }
    if boss > 0.0 && !rect {
        imperfection.push(ShapePart::Boss {
            rise: boss * h,
            radius: get(ParamId::BossRadius),
        });
    }
    let pickup = |r: ParamId, a: ParamId| Pickup {
        at: position(kind, get(r), get(a)),
        quantity: Quantity::Velocity,
    };
    PlateSpec {
        shape,
        radius: (!rect).then_some(size),
        lx: rect.then_some(size),
        ly: rect.then_some(size * get(ParamId::Aspect)),
        thickness: h,
        material: v.material(),
        n_phi,
        n_psi,
        symmetry,
        sim_rate,
        scheme: PlateScheme::ALL
            .get(v.index_of(ParamId::Scheme))
            .copied()
            .unwrap_or(PlateScheme::SavExact),
        sav_relaxation: crate::models::plate::spec::default_sav_relaxation(),
        closure: get(ParamId::Closure),
        band_above: v.index_of(ParamId::BandAbove) == 1,
        strike_above: v.index_of(ParamId::StrikeAbove) == 1,
        // The bank's tiers share one tensor rounded to `f32` (`engine/plate_bank.rs`).
        tensor_storage: TensorStorage::Single,
        damping: Damping::Power {
            a: scale * get(ParamId::DampingA),
            b: get(ParamId::DampingB),
            c0: scale * get(ParamId::DampingC0),
        },
        excitation,
        imperfection,
        pickups: vec![
            pickup(ParamId::PickupLeftPos, ParamId::PickupLeftAngle),
            pickup(ParamId::PickupRightPos, ParamId::PickupRightAngle),
        ],
    }
}

/// The instrument's string for `v` with `modes` modes at `sim_rate` (Hz), as a scene's
/// `[string]` table. Worker thread.
pub(crate) fn string_spec(
    kind: ModelKind,
    v: &ParamValues,
    modes: usize,
    sim_rate: f64,
) -> StringSpec {
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

/// Lowest Sa (Hz) the drone is built at: a root key below it builds the drone there and
/// its keys retune it from there (`engine/voice/drone.rs`).
pub(crate) const DRONE_SA_MIN: f64 = 32.0;

/// Highest Sa (Hz) the drone is built at (as [`DRONE_SA_MIN`]).
pub(crate) const DRONE_SA_MAX: f64 = 1000.0;

/// Fewest modes per drone string.
pub(crate) const DRONE_MIN_MODES: usize = 32;

/// Lowest simulation rate of the drone (Hz): the `sim_rate` parameter is a floor under it.
pub const DRONE_MIN_SIM_RATE: f64 = 16_000.0;

/// Speaking length of the drone's strings (m): the scenes' default.
const DRONE_LENGTH: f64 = 1.0;

/// The modes per string of the drone for `v`: the `modes` parameter, at least
/// [`DRONE_MIN_MODES`], and at least as many as put the jivari 1.5 grid steps beyond the seat
/// (`Δx = L/(N + 1) ≤ j/1.5`: 499 modes for 3 mm, 299 for 5 mm, 49 for 30 mm), so every
/// position of the parameter's range builds. Any thread.
pub fn drone_modes(v: &ParamValues) -> usize {
    let jivari = f64::from(v.get(ParamId::Jivari)) * 1e-3;
    let for_jivari = (1.5 * DRONE_LENGTH / jivari).ceil() as usize - 1;
    v.index_of(ParamId::Modes)
        .max(DRONE_MIN_MODES)
        .max(for_jivari)
}

/// The root key's pitch in 12-TET at A4 = 440 Hz (`440 · 2^((root - 69)/12)`, Hz): where
/// `voice::mapping::pitch_ratio` is 1 at the 440 Hz reference. Any thread.
pub(crate) fn root_hz(v: &ParamValues) -> f64 {
    440.0 * ((f64::from(v.get(ParamId::RootKey)) - 69.0) / 12.0).exp2()
}

/// The Sa (Hz) the drone of `v` is built and tuned at: the root key's pitch ([`root_hz`]),
/// within [`DRONE_SA_MIN`] to [`DRONE_SA_MAX`]. Any thread.
pub(crate) fn drone_sa(v: &ParamValues) -> f64 {
    root_hz(v).clamp(DRONE_SA_MIN, DRONE_SA_MAX)
}

/// The drone's cycle pattern in `v` (`drone_pattern`: 0 classic, 1 even). Any thread.
pub(crate) fn drone_pattern(v: &ParamValues) -> Pattern {
    if v.index_of(ParamId::DronePattern) == 1 {
        Pattern::Even
    } else {
        Pattern::Classic
    }
}

/// The cycle's variation at the `drone_variation` value `variation` (0 to 1): the largest
/// onset shift (ms) and the largest relative change of a pluck's strength. Any thread.
pub(crate) fn drone_jitter(variation: f64) -> (f64, f64) {
    (
        DRONE_MAX_TIMING_JITTER_MS * variation,
        DRONE_MAX_STRENGTH_JITTER * variation,
    )
}

/// The instrument's tanpura drone for `v` at `sim_rate` (Hz; at least
/// [`DRONE_MIN_SIM_RATE`]), as a scene's `[tanpura]` table: Sa at [`drone_sa`] (the notes
/// retune it to their own pitch), the tuning, strings, jivari and cycle parameters, tuned by
/// ear or not (`drone_ear`), [`drone_modes`] per string; the pluck's shape and the strings'
/// dimensions at the scene's defaults. Not validated here (the drone's builder validates).
/// Worker thread.
pub(crate) fn drone_spec(v: &ParamValues, sim_rate: f64) -> TanpuraSpec {
    let (timing_jitter_ms, strength_jitter) =
        drone_jitter(f64::from(v.get(ParamId::DroneVariation)));
    TanpuraSpec {
        tuning: Tuning::ALL[v.index_of(ParamId::DroneTuning).min(Tuning::ALL.len() - 1)],
        strings: v.index_of(ParamId::DroneStrings),
        length: DRONE_LENGTH,
        modes: drone_modes(v),
        // Whole hertz: a host's normalised value of the rate comes back a few ulps off
        // (47999.996 Hz), which would tune a drone of its own instead of sharing the tuning
        // of the drone at 48 kHz.
        sim_rate: sim_rate.max(DRONE_MIN_SIM_RATE).round(),
        cycle_seconds: v.get(ParamId::DroneCycle) as f64,
        pattern: drone_pattern(v),
        timing_jitter_ms,
        strength_jitter,
        jivari_mm: vec![v.get(ParamId::Jivari) as f64],
        tune_by_ear: v.index_of(ParamId::DroneEar) == 1,
        alias_free: true,
        ..TanpuraSpec::at(drone_sa(v))
    }
}

/// Lowest Sa (Hz) the sitar with its taraf is built at (the scenes' range): a root key
/// below it builds the sitar there and its keys fret it from there.
pub(crate) const SITAR_SA_MIN: f64 = 100.0;

/// Highest Sa (Hz) the sitar with its taraf is built at (as [`SITAR_SA_MIN`]).
pub(crate) const SITAR_SA_MAX: f64 = 600.0;

/// Fewest modes of the sitar's played string.
pub(crate) const SITAR_MIN_MODES: usize = 32;

/// The Sa (Hz) the sitar of `v` is built and tuned at: the root key's pitch ([`root_hz`]),
/// within [`SITAR_SA_MIN`] to [`SITAR_SA_MAX`]. Any thread.
pub(crate) fn sitar_sa(v: &ParamValues) -> f64 {
    root_hz(v).clamp(SITAR_SA_MIN, SITAR_SA_MAX)
}

/// The instrument's sitar with its taraf for `v` at `sim_rate` (Hz; at least
/// [`DRONE_MIN_SIM_RATE`], as the drone), as a scene's `[sitar]` table without a phrase: Sa
/// and the played string's open note at [`sitar_sa`] (the keys fret it), the thaat, the taraf
/// and chikari strings, the `modes` parameter (at least [`SITAR_MIN_MODES`]) for the played
/// string, tuned by ear or not (`drone_ear`); the taraf's modes, the pluck and the strings'
/// dimensions at the scene's defaults. Not validated here (the sitar's builder validates).
/// Worker thread.
pub(crate) fn sitar_spec(v: &ParamValues, sim_rate: f64) -> SitarSpec {
    let sa = sitar_sa(v);
    SitarSpec {
        thaat: Thaat::ALL[v.index_of(ParamId::SitarThaat).min(Thaat::ALL.len() - 1)],
        taraf: v.index_of(ParamId::TarafStrings),
        chikari: v.index_of(ParamId::ChikariStrings),
        modes: v.index_of(ParamId::Modes).max(SITAR_MIN_MODES),
        // Whole hertz, as the drone's (a host's value comes back a few ulps off).
        sim_rate: sim_rate.max(DRONE_MIN_SIM_RATE).round(),
        tune_by_ear: v.index_of(ParamId::DroneEar) == 1,
        ..SitarSpec::at(sa, sa)
    }
}
