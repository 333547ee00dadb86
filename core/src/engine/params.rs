//! The engine's parameters: a static metadata table ([`PARAMS`], indexed by [`ParamId`]) and
//! [`SharedParams`], one `AtomicU32` (the bits of an `f32`) per parameter.
//!
//! Threads: the host and the GUI write [`SharedParams`] (any thread, lock-free, wait-free);
//! the audio thread reads every value once per block ([`SharedParams::snapshot`]); the
//! engine's worker thread reads the values that trigger a rebuild.
//!
//! Ranges of physical quantities come from the one table [`crate::models::ranges`] (the
//! instrument's playable part of each). Values are stored in their physical units (the `unit`
//! column). Enumerations and integers are stored as `f32` holding an integer (`Model` 0..=4
//! and so on). [`SharedParams::set`]
//! refuses out-of-range or non-finite values with a [`ParamError`] naming the parameter, the
//! value and the range: the host layer clamps and reports, the engine never clamps silently.

use super::kinds::ModelKind;
use super::param_meta::{ParamGroup, Reads, Shown};
use super::tuning::SharedTuning;
use crate::error::ParamError;
use crate::models::plate::spec::Material;
use crate::models::ranges as r;
use std::sync::atomic::{AtomicU32, AtomicU64, Ordering};

/// How a parameter's value is interpreted (for host and GUI layers).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParamKind {
    /// A continuous value; `log` suggests a logarithmic control (positive range).
    Float {
        /// Whether the range spans decades (a logarithmic knob suits it).
        log: bool,
    },
    /// An integer in `[min, max]`.
    Int,
    /// An enumeration: the value is an index into `names` (`min = 0`, `max = names.len() - 1`).
    Enum {
        /// Display names, in index order.
        names: &'static [&'static str],
        /// Preset and state names (stable, never renamed), in index order.
        keys: &'static [&'static str],
    },
}

/// Metadata of one parameter (a row of [`PARAMS`]); static, read by any thread.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParamInfo {
    /// The parameter.
    pub id: ParamId,
    /// Stable identifier (snake case): preset keys, plugin parameter ids. Never renamed.
    pub key: &'static str,
    /// Display name.
    pub name: &'static str,
    /// Unit of the stored value (empty for dimensionless and enumerations).
    pub unit: &'static str,
    /// Smallest allowed value.
    pub min: f32,
    /// Largest allowed value.
    pub max: f32,
    /// Default value (the default preset: the gong).
    pub default: f32,
    /// Continuous, integer or enumeration.
    pub kind: ParamKind,
    /// Whether a change makes the worker rebuild the voice bank (new modal basis, grid,
    /// rate or voice count). `false`: applied on the audio thread without a rebuild.
    pub rebuild: bool,
    /// The instruments that read it (the others ignore it).
    pub reads: Reads,
    /// The group it belongs to (host groups, remote-control pages).
    pub group: ParamGroup,
    /// How its value is shown and typed.
    pub shown: Shown,
    /// One-line description, including which models read it.
    pub help: &'static str,
}

pub use super::param_names::*;

macro_rules! params {
    ($( $id:ident, $key:literal, $name:literal, $unit:literal, $min:expr, $max:expr, $def:expr,
        $kind:expr, $rebuild:expr, $group:ident, $reads:ident, $shown:expr, $help:literal; )*) => {
        /// Identifier of an engine parameter; `id as usize` indexes [`PARAMS`].
        ///
        /// Plain `Copy` data used on every thread. New parameters are appended at the end, so
        /// existing indices and keys stay stable.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        #[repr(u16)]
        pub enum ParamId {
            $(
                #[doc = $help]
                $id,
            )*
        }

        /// The parameter table, one row per [`ParamId`], in index order.
        pub const PARAMS: &[ParamInfo] = {
            use Shown::*;
            &[
            $( ParamInfo {
                id: ParamId::$id,
                key: $key,
                name: $name,
                unit: $unit,
                min: $min,
                max: $max,
                default: $def,
                kind: $kind,
                rebuild: $rebuild,
                group: ParamGroup::$group,
                reads: Reads::$reads,
                shown: $shown,
                help: $help,
            }, )*
        ]};

        impl ParamId {
            /// Every parameter, in index order.
            pub const ALL: &'static [ParamId] = &[ $( ParamId::$id, )* ];
        }
    };
}

const F: ParamKind = ParamKind::Float { log: false };
const LOG: ParamKind = ParamKind::Float { log: true };
const INT: ParamKind = ParamKind::Int;

params! {
    Model, "model", "Model", "", 0.0, 6.0, 0.0, ParamKind::Enum { names: MODEL_NAMES, keys: MODEL_KEYS }, true, ModelAndMaterial, All, Plain(""),
        "Instrument model: gong, cymbal, rectangular plate, sitar, tanpura (one string), tanpura drone (its strings on a moving bridge, plucked in a cycle), sitar with taraf (the played string, its sympathetic strings and chikari on two bridges).";
    Size, "size", "Size", "m", r::PLATE_SIZE.play_min as f32, r::PLATE_SIZE.play_max as f32, 0.4, LOG, false, ModelAndMaterial, Bodies, Length,
        "Plates: radius (circular) or the side lx (rectangle), a rescale; strings: length, which rebuilds the grid.";
    Thickness, "thickness", "Thickness", "m", r::PLATE_THICKNESS.play_min as f32, r::PLATE_THICKNESS.play_max as f32, 1.0e-3, LOG, false, ModelAndMaterial, Plates, Length,
        "Plate thickness h (plates only); pitch f is proportional to h / a^2.";
    Aspect, "aspect", "Aspect ratio", "", r::PLATE_ASPECT.play_min as f32, r::PLATE_ASPECT.play_max as f32, 1.5, F, true, ModelAndMaterial, RectPlate, Plain(""),
        "Rectangular plate: ly / lx (new modal basis).";
    Material, "material", "Material", "", 0.0, 4.0, 0.0, ParamKind::Enum { names: MATERIAL_NAMES, keys: MATERIAL_NAMES }, true, ModelAndMaterial, Plates, Plain(""),
        "Plate material preset; 'custom' uses Young's modulus, density and Poisson ratio below.";
    YoungsModulus, "youngs_modulus", "Young's modulus", "Pa", r::YOUNGS_MODULUS.play_min as f32, r::YOUNGS_MODULUS.play_max as f32, 2.0e11, LOG, false, ModelAndMaterial, CustomMaterial, Modulus,
        "E of the custom material (plates).";
    Density, "density", "Density", "kg/m^3", r::DENSITY.play_min as f32, r::DENSITY.play_max as f32, 7860.0, LOG, false, ModelAndMaterial, CustomMaterial, Plain("kg/m³"),
        "rho of the custom material (plates).";
    Poisson, "poisson", "Poisson ratio", "", r::POISSON.play_min as f32, r::POISSON.play_max as f32, 0.3, F, true, ModelAndMaterial, CustomMaterial, Plain(""),
        "nu of the custom material (plates; the free-edge basis depends on it).";
    DampingScale, "damping_scale", "Damping", "", 0.0, 20.0, 1.0, F, false, DampingAndRelease, All, Plain("×"),
        "Multiplies every modal damping coefficient (0: lossless). Plates: the power law below; strings: Issanchou/Valette losses.";
    DampingA, "damping_a", "Damping a", "s^(b-1)", r::DAMPING_A.play_min as f32, r::DAMPING_A.play_max as f32, 0.005, F, false, DampingAndRelease, Plates, Plain("s^(b−1)"),
        "Plate damping law c_s = a omega_s^b + c0: coefficient a.";
    DampingB, "damping_b", "Damping b", "", r::DAMPING_B.play_min as f32, r::DAMPING_B.play_max as f32, 0.6, F, false, DampingAndRelease, Plates, Plain(""),
        "Plate damping law exponent b.";
    DampingC0, "damping_c0", "Damping c0", "1/s", r::DAMPING_C0.play_min as f32, r::DAMPING_C0.play_max as f32, 0.0, F, false, DampingAndRelease, Plates, Plain("1/s"),
        "Plate damping law constant c0.";
    StrikeRadius, "strike_radius", "Strike position", "", 0.0, 0.99, 0.92, F, true, Excitation, Plates, Percent,
        "Plate strike point: fraction of the radius (circular) or of the half-diagonal from the centre (rectangle).";
    StrikeAngle, "strike_angle", "Strike angle", "rad", 0.0, 6.2831855, 0.0, F, false, Excitation, Plates, Angle,
        "Plate strike point: polar angle, taken by each new note (a circular plate rotates its pickups instead: no rebuild).";
    StrikeDuration, "strike_duration", "Strike duration", "s", r::STRIKE_DURATION.play_min as f32, r::STRIKE_DURATION.play_max as f32, 0.01, LOG, false, Excitation, Pulse, Time,
        "Raised-cosine strike length (mallet hardness: shorter is harder); plates.";
    StrikeForce, "strike_force", "Strike force", "N", r::STRIKE_FORCE.play_min as f32, r::STRIKE_FORCE.play_max as f32, 40.0, LOG, false, Excitation, Pulse, Plain("N"),
        "Peak strike force at velocity 1 (plates).";
    VelocityCurve, "velocity_curve", "Velocity curve", "", 0.0, 4.0, 1.0, F, false, Excitation, All, Plain(""),
        "Force (or pluck amplitude) = value at velocity 1 times velocity^curve.";
    PickupLeftPos, "pickup_left_pos", "Left pickup position", "", 0.01, 0.99, 0.896, F, true, Pickups, Bodies, Percent,
        "Left output point: fraction of the radius / half-diagonal (plates) or of the length (strings).";
    PickupLeftAngle, "pickup_left_angle", "Left pickup angle", "rad", 0.0, 6.2831855, 0.519, F, true, Pickups, Plates, Angle,
        "Left output point: polar angle (plates).";
    PickupRightPos, "pickup_right_pos", "Right pickup position", "", 0.01, 0.99, 0.7, F, true, Pickups, Bodies, Percent,
        "Right output point: fraction of the radius / half-diagonal (plates) or of the length (strings).";
    PickupRightAngle, "pickup_right_angle", "Right pickup angle", "rad", 0.0, 6.2831855, 2.5, F, true, Pickups, Plates, Angle,
        "Right output point: polar angle (plates).";
    Tension, "tension", "Tension", "N", r::STRING_TENSION.play_min as f32, r::STRING_TENSION.play_max as f32, 180.5, LOG, false, StringAndBridge, Strings, Plain("N"),
        "String tension T at the root key (strings).";
    LinearDensity, "linear_density", "Linear density", "kg/m", r::STRING_LINEAR_DENSITY.play_min as f32, r::STRING_LINEAR_DENSITY.play_max as f32, 1.17e-3, LOG, true, StringAndBridge, Strings, LinearDensity,
        "String linear mass density mu (strings).";
    Inharmonicity, "inharmonicity", "Inharmonicity B", "", r::STRING_INHARMONICITY.play_min as f32, r::STRING_INHARMONICITY.play_max as f32, 2.0e-5, F, false, StringAndBridge, Strings, Plain(""),
        "String inharmonicity B = pi^2 EI / (T L^2) at the root key (strings; 0: ideal string).";
    BridgeCurvature, "bridge_curvature", "Bridge curvature", "1/m", r::BRIDGE_CURVATURE.play_min as f32, r::BRIDGE_CURVATURE.play_max as f32, 1.0, F, true, StringAndBridge, Sitar, Plain("1/m"),
        "Sitar bridge g(x) = -curvature x^2 near x = 0 (the lecture's a).";
    BridgePosition, "bridge_fraction", "Bridge position", "", 1.0e-3, 0.2, 6.0e-3, LOG, true, StringAndBridge, Strings, Percent,
        "Tanpura: distance of the point bridge from the end; sitar: length of the curved bridge; both as a fraction of the string's length.";
    ContactStiffness, "contact_k", "Contact stiffness K", "N/m^(alpha+1)", r::CONTACT_STIFFNESS.play_min as f32, r::CONTACT_STIFFNESS.play_max as f32, 1.0e13, LOG, true, StringAndBridge, Strings, Plain("N/m^α"),
        "Penalty contact law K [eta]_+^alpha (strings).";
    ContactAlpha, "contact_alpha", "Contact exponent alpha", "", r::CONTACT_EXPONENT.play_min as f32, r::CONTACT_EXPONENT.play_max as f32, 1.5, F, true, StringAndBridge, Strings, Plain(""),
        "Penalty contact exponent (strings).";
    PluckPosition, "pluck_position", "Pluck position", "", 0.02, 0.98, 0.25, F, false, Excitation, Strings, Percent,
        "Triangular pluck apex as a fraction of the length (strings).";
    PluckAmplitude, "pluck_amplitude", "Pluck amplitude", "m", r::PLUCK_AMPLITUDE.play_min as f32, r::PLUCK_AMPLITUDE.play_max as f32, 1.0e-3, LOG, false, Excitation, Plucked, Length,
        "Triangular pluck apex displacement at velocity 1 (strings, and every pluck of the drone; the drone is tuned by ear at 1 mm, and plucked harder its pitch rises with the jawari, as a real one).";
    Modes, "modes", "Modes", "", r::PLATE_MODES.play_min as f32, r::PLATE_MODES.play_max as f32, 510.0, INT, true, Quality, All, Plain(""),
        "Quality and CPU budget: the most transverse modes a plate note may simulate (a note stops earlier at the band limit), or the string modes N - 1 (the tanpura drone: per string, at least 32 and as many as its jivari needs).";
    InPlaneModes, "in_plane_modes", "In-plane modes", "", r::PLATE_IN_PLANE_MODES.play_min as f32, r::PLATE_IN_PLANE_MODES.play_max as f32, 15.0, INT, true, Quality, Plates, Plain(""),
        "Quality: in-plane modes N_Psi of plates (0: linear plate).";
    SimRate, "sim_rate", "Simulation rate", "Hz", r::PLATE_SIM_RATE.play_min as f32, r::PLATE_SIM_RATE.play_max as f32, 8000.0, LOG, true, Quality, All, Frequency,
        "Quality: the models' own time-step rate, resampled to the host rate. Plates run at least at band limit / 0.45 (13.4 kHz for 6 kHz), nonlinear ones (in-plane modes above 0) at band limit / 0.36 (16.7 kHz) and the tanpura drone at least at 16 kHz: for them this is a floor, to oversample.";
    Scheme, "scheme", "Scheme", "", 0.0, 3.0, 3.0, ParamKind::Enum { names: SCHEME_NAMES, keys: SCHEME_KEYS }, true, Quality, Plates, Plain(""),
        "Quality: plate time scheme.";
    Polyphony, "polyphony", "Polyphony", "voices", 1.0, 16.0, 4.0, INT, true, Quality, All, Count("voice", "voices"),
        "Voices in the pool (a rebuild allocates them); the quietest or oldest is stolen.";
    Gain, "gain", "Output gain", "dB", -60.0, 60.0, 0.0, F, false, TuningAndOutput, All, Plain("dB"),
        "Output gain applied after the pickups' normalisation.";
    TuningA4, "tuning_a4", "A4 reference", "Hz", 400.0, 480.0, 440.0, F, false, TuningAndOutput, All, Frequency,
        "Tuning reference: all notes scale by tuning_a4 / 440.";
    RootKey, "root_key", "Root key", "", 0.0, 127.0, 60.0, INT, false, TuningAndOutput, All, Key,
        "MIDI key at which the model has its nominal parameters; other keys scale thickness (plates) or tension (strings).";
    PitchBendRange, "pitch_bend_range", "Pitch bend range", "semitones", 0.0, 24.0, 2.0, F, false, TuningAndOutput, All, Plain("st"),
        "Full pitch-bend deflection in semitones.";
    ModWheelDepth, "mod_wheel_depth", "Mod wheel depth", "", 0.0, 1.0, 0.5, F, false, TuningAndOutput, All, Percent,
        "Mod wheel scales the strike force (plates) or pluck amplitude (strings) by 1 + depth * (2 wheel - 1).";
    ReleaseT60, "release_t60", "Release T60", "s", 0.02, 60.0, 2.0, LOG, false, DampingAndRelease, All, Time,
        "After note-off (and sustain release) every mode decays at least this fast (60 dB in this time).";
    BandLimit, "band_limit", "Band limit", "Hz", r::PLATE_BAND_LIMIT.play_min as f32, r::PLATE_BAND_LIMIT.play_max as f32, 6000.0, LOG, true, Quality, Plates, Frequency,
        "Quality (plates): each note keeps the transverse modes up to this frequency after its pitch scaling (at most 'modes', the CPU budget); the simulation rate follows from it.";
    Threads, "threads", "Threads", "", 0.0, 16.0, 0.0, INT, false, Quality, All, Threads,
        "Threads sharing the voices' work (0: every core of the machine; 1: the audio thread alone).";
    LowCut, "low_cut", "Low cut", "Hz", 10.0, 1000.0, 20.0, LOG, false, TuningAndOutput, All, Frequency,
        "Output high-pass (second-order Butterworth) removing sub-audio motion; 10 Hz leaves nearly everything.";
    Limiter, "limiter", "Limiter", "", 0.0, 1.0, 1.0, ParamKind::Enum { names: ON_OFF_NAMES, keys: ON_OFF_NAMES }, false, TuningAndOutput, All, Plain(""),
        "Output limiter at -0.3 dBFS (1.5 ms look-ahead, transparent below it). Off: a hard clip at 0 dBFS remains.";
    KeyLevel, "key_level", "Level key tracking", "dB/oct", -12.0, 12.0, 0.0, F, false, TuningAndOutput, All, Plain("dB/oct"),
        "Each note's output level changes by this many dB per octave above the root key (below it, the opposite), evening out the models' loudness over the keyboard.";
    Exciter, "exciter", "Exciter", "", 0.0, 1.0, 0.0, ParamKind::Enum { names: EXCITER_NAMES, keys: EXCITER_NAMES }, false, Excitation, Plates, Plain(""),
        "Plates: 'pulse' strikes with the raised-cosine force (velocity scales its peak: the level); 'mallet' throws a mass through a felt at the plate (velocity sets its speed: level and timbre).";
    MalletMass, "mallet_mass", "Mallet mass", "kg", 0.01, 2.0, 0.2, LOG, false, Excitation, CustomMallet, Plain("kg"),
        "Plates, exciter 'mallet': the mallet head's mass M (0.2 kg: a gong beater).";
    MalletHardness, "mallet_hardness", "Mallet hardness", "", 0.0, 1.0, 0.5, F, false, Excitation, CustomMallet, Percent,
        "Plates, exciter 'mallet': 0 soft felt (K = 1e6 N/m^alpha, alpha = 2.5) to 1 hard (K = 1e9, alpha = 1.5, Hertz), log K and alpha linear in between.";
    MalletSpeed, "mallet_speed", "Mallet speed", "m/s", 0.1, 10.0, 2.0, LOG, false, Excitation, Mallet, Plain("m/s"),
        "Plates, exciter 'mallet': impact speed at velocity 1; speed = value times velocity^curve (and the mod wheel as for the force).";
    MalletHead, "mallet_head", "Mallet head", "", 0.0, 5.0, 0.0, ParamKind::Enum { names: MALLET_HEAD_NAMES, keys: MALLET_HEAD_NAMES }, false, Excitation, Mallet, Plain(""),
        "Plates, exciter 'mallet': 'custom' uses the mass and hardness above; a factory head (soft felt, hard felt, rubber, wood, metal) brings its own mass, contact law and felt loss (docs/models.md, factory mallets).";
    Dome, "dome", "Dome rise", "thicknesses", 0.0, 50.0, 0.0, F, false, ModelAndMaterial, Plates, Plain("× thickness"),
        "Plates: the rest shape's dome, its rise in plate thicknesses h (0: flat). Circular: a spherical cap w0 = rise (1 - r^2), curvature kappa = a^2/(R h) = 2 rise/h; rectangle: 16 rise x(1-x) y(1-y). Raises the modes with nodal circles and makes the sound soften (pitch rises as it decays); needs in-plane modes, and the conservative-exact scheme integrates it accurately.";
    Boss, "boss", "Boss height", "thicknesses", 0.0, 50.0, 0.0, F, false, ModelAndMaterial, CircularPlates, Plain("× thickness"),
        "Circular plates: a raised centre boss (a gong's boss, a cymbal's bell) of this height in plate thicknesses, w0 = height cos^2(pi r / 2b) inside the boss radius b; 0: none. Added to the dome.";
    BossRadius, "boss_radius", "Boss radius", "", 0.05, 0.6, 0.2, F, true, ModelAndMaterial, CircularPlates, Percent,
        "Circular plates: the boss's base radius b as a fraction of the plate's radius (the boss's projection on the modes is rebuilt).";
    Closure, "closure", "Cascade closure", "", 0.0, 4.0, 0.0, F, false, Quality, Plates, Plain("×"),
        "Plates: how strongly the top half-octave of simulated modes is damped when a loud strike's cascade piles energy up there, as the modes above the band would carry it away (1: the strength calibrated on the crash cymbal against its resolved model; 0: the plain truncation).";
    BandAbove, "band_above", "Band above", "", 0.0, 1.0, 1.0, ParamKind::Enum { names: ON_OFF_NAMES, keys: ON_OFF_NAMES }, false, Quality, Plates, Plain(""),
        "Plates: the linear modes of the plate above its simulated band, up to 20 kHz (or 0.45 of the host rate), sounding with exactly the energy the cascade closure absorbs (silent while the closure is off or idle). Off: nothing sounds above the band.";
    CpuBudget, "cpu_budget", "CPU budget", "cores", 0.0, 64.0, 0.0, F, false, Quality, All, Auto("cores"),
        "Live play (the plugin in a real-time host): the voices' measured work may use this many cores' time (0: 70 % of the machine's). A note that would pass it starts with a narrower band (fewer modes), and when even that does not fit, or blocks overrun, the quietest voice ends; every reduction is counted and shown. Offline renders ignore it.";
    MemoryCap, "memory_cap", "Memory cap", "MB", 0.0, 262144.0, 0.0, F, true, Quality, All, Auto("MB"),
        "Plates: the most memory one instance's coupling tensors may take, in MB (0: a quarter of the machine's memory, at most 4096 MB). A plate whose tensors would need more is built with fewer modes, a tier at a time (each 1/sqrt(2) of the modes, the in-plane modes in proportion), and the reduction is shown; it is never built at full size first.";
    DroneTuning, "drone_tuning", "Drone tuning", "", 0.0, 3.0, 0.0, ParamKind::Enum { names: DRONE_TUNING_NAMES, keys: DRONE_TUNING_KEYS }, true, StringAndBridge, Drone, Plain(""),
        "Tanpura drone: the first string's note against Sa (the key held), in just intonation: Pa 3/4, Ma 2/3, Ni 15/16 or the lower Sa 1/2; the others are Sa, Sa and the lower Sa (bronze for the low ones, steel for the others). The worker tunes every string by ear.";
    DroneStrings, "drone_strings", "Drone strings", "strings", 4.0, 6.0, 4.0, INT, true, StringAndBridge, Drone, Count("string", "strings"),
        "Tanpura drone: its strings (five adds a third middle Sa, six also a second lower Sa).";
    Jivari, "jivari", "Jivari", "mm", 3.0, 30.0, 5.0, F, true, StringAndBridge, Drone, Plain("mm"),
        "Tanpura drone: the thread under every string, its distance from the bridge's back edge in mm, where the string grazes the bridge and buzzes (nearer the edge, brighter). Resolved to the nearest grid node, at least 1.5 grid steps beyond the seat: the strings get as many modes as that needs (499 at 3 mm, 299 at 5 mm).";
    DroneCycle, "drone_cycle", "Cycle period", "s", 0.5, 30.0, 4.0, LOG, false, Excitation, Drone, Time,
        "Tanpura drone: the period of the pluck cycle (every string plucked once per period); a change takes over at the next cycle.";
    DronePattern, "drone_pattern", "Cycle pattern", "", 0.0, 1.0, 0.0, ParamKind::Enum { names: DRONE_PATTERN_NAMES, keys: DRONE_PATTERN_KEYS }, false, Excitation, Drone, Plain(""),
        "Tanpura drone: the cycle's rhythm, the strings at equal gaps then a pause of two gaps (the usual), or evenly over the period.";
    DroneVariation, "drone_variation", "Human variation", "", 0.0, 1.0, 0.0, F, false, Excitation, Drone, Percent,
        "Tanpura drone: how freely the player's hand keeps the cycle: each onset moves by up to 20 ms and each pluck's strength by up to 20 % at 1 (0: the pattern exactly; a seeded variation, the same every time).";
    DroneEar, "drone_ear", "Tune by ear", "", 0.0, 1.0, 1.0, ParamKind::Enum { names: ON_OFF_NAMES, keys: ON_OFF_NAMES }, true, Quality, Networks, Plain(""),
        "Tanpura drone and sitar with taraf: on, the worker tunes every string by ear when the instrument is built (the drone at the root and at every key within an octave of it, about 30 s for the factory drone; the sitar's strings at the root and its played string at every key within an octave of it, about 40 s; kept in the cache so each is tuned once); until it is done the strings play tuned by their tensions alone, which is off by the seat's, the bridge's and the jawari's pull (up to 4 cents). Off: tensions alone, built at once.";
    DroneSync, "drone_sync", "Follow the tempo", "", 0.0, 1.0, 0.0, ParamKind::Enum { names: ON_OFF_NAMES, keys: ON_OFF_NAMES }, false, Excitation, Drone, Plain(""),
        "Tanpura drone: on, the cycle lasts 'cycle beats' of the host's tempo (from the next cycle whenever the tempo changes) instead of the cycle period; without a tempo from the host the cycle period holds.";
    DroneBeats, "drone_beats", "Cycle beats", "beats", 1.0, 32.0, 8.0, INT, false, Excitation, Drone, Count("beat", "beats"),
        "Tanpura drone with 'follow the tempo' on: the cycle's length in beats of the host's tempo (8 beats at 120 bpm: 4 s), within the cycle period's range of 0.5 to 30 s.";
    DroneLatch, "drone_latch", "Latch", "", 0.0, 1.0, 0.0, ParamKind::Enum { names: ON_OFF_NAMES, keys: ON_OFF_NAMES }, false, Excitation, Drone, Plain(""),
        "Tanpura drone: on, the drone keeps plucking after the key is let go, until another key is played or the latch is turned off (then it releases).";
    SitarThaat, "sitar_thaat", "Taraf thaat", "", 0.0, 9.0, 0.0, ParamKind::Enum { names: THAAT_NAMES, keys: THAAT_KEYS }, true, StringAndBridge, SitarTaraf, Plain(""),
        "Sitar with taraf: the thaat the taraf is tuned to, its seven notes in just intonation upwards from Sa (the root key) and on into the next octave.";
    TarafStrings, "taraf_strings", "Taraf strings", "strings", 0.0, 13.0, 11.0, INT, true, StringAndBridge, SitarTaraf, Count("string", "strings"),
        "Sitar with taraf: its sympathetic strings on their small bridge (a sitar has 11 to 13), ringing when the played string sounds their notes.";
    ChikariStrings, "chikari_strings", "Chikari", "strings", 0.0, 3.0, 2.0, INT, true, StringAndBridge, SitarTaraf, Count("string", "strings"),
        "Sitar with taraf: the high drone strings beside the played string on the main bridge's jawari: the upper Sa, the Sa above it, then Pa.";
    ChikariStroke, "chikari_stroke", "Chikari stroke", "", 0.0, 1.0, 0.0, F, false, Excitation, SitarTaraf, Percent,
        "Sitar with taraf: each note also strokes the chikari at this fraction of its pluck (the jhala's da-ra on the drone strings; 0: the chikari only ring in sympathy).";
    StrikeAbove, "strike_above", "Strike above", "", 0.0, 1.0, 0.0, ParamKind::Enum { names: ON_OFF_NAMES, keys: ON_OFF_NAMES }, false, Quality, Plates, Plain(""),
        "Plates, exciter 'mallet', with the band above on: the mallet's contact feels the plate's modes above the simulated band (their point resistance 8 sqrt(D rho h) and their static compliance), and the energy it gives them sounds in the band above. A hard stick then rings the cymbal to 20 kHz even struck softly, and no longer overfills the top of the band. Off: the contact sees the simulated modes only (docs/models.md, the contact residual).";
}

/// Number of parameters (rows of [`PARAMS`]).
pub const PARAM_COUNT: usize = ParamId::ALL.len();

impl ParamId {
    /// Index into [`PARAMS`] and [`ParamValues`].
    pub const fn index(self) -> usize {
        self as usize
    }

    /// The metadata row of this parameter.
    pub fn info(self) -> &'static ParamInfo {
        &PARAMS[self.index()]
    }

    /// The parameter with stable key `key`, if any.
    pub fn from_key(key: &str) -> Option<ParamId> {
        PARAMS.iter().find(|p| p.key == key).map(|p| p.id)
    }

    /// The parameter at index `i`, if any.
    pub fn from_index(i: usize) -> Option<ParamId> {
        ParamId::ALL.get(i).copied()
    }
}

impl ParamInfo {
    /// The index of the enumeration value named `name`: its preset key (exactly, then
    /// ignoring case) or its display name (ignoring case), surrounding spaces ignored; `None`
    /// for other names and for parameters that are not enumerations. The one name lookup of
    /// presets, plugin states and typed values.
    pub fn enum_index(&self, name: &str) -> Option<usize> {
        let ParamKind::Enum { names, keys } = self.kind else {
            return None;
        };
        let name = name.trim();
        keys.iter()
            .position(|k| *k == name)
            .or_else(|| keys.iter().position(|k| k.eq_ignore_ascii_case(name)))
            .or_else(|| names.iter().position(|n| n.eq_ignore_ascii_case(name)))
    }

    /// Checks `value` against this row: finite, within `[min, max]`, integral for integer
    /// and enumeration parameters. Any thread; no allocation on success.
    pub fn check(&self, value: f32) -> Result<f32, ParamError> {
        let integral = !matches!(self.kind, ParamKind::Float { .. });
        if value.is_finite()
            && value >= self.min
            && value <= self.max
            && (!integral || value.fract() == 0.0)
        {
            Ok(value)
        } else {
            let what = if integral { "integer" } else { "finite number" };
            Err(ParamError::new(
                self.key,
                value,
                format!("{what} in [{}, {}] {}", self.min, self.max, self.unit),
            ))
        }
    }
}

/// A copy of every parameter value (index with [`ParamId::index`] or [`ParamValues::get`]).
/// Plain data: the audio thread keeps one on its stack or in the engine.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParamValues(pub [f32; PARAM_COUNT]);

impl ParamValues {
    /// The table's defaults.
    pub fn defaults() -> Self {
        let mut v = [0.0; PARAM_COUNT];
        for p in PARAMS {
            v[p.id.index()] = p.default;
        }
        Self(v)
    }

    /// The value of `id`.
    pub fn get(&self, id: ParamId) -> f32 {
        self.0[id.index()]
    }

    /// The value of `id` as an index (enumerations and integers).
    pub fn index_of(&self, id: ParamId) -> usize {
        self.0[id.index()].max(0.0) as usize
    }

    /// The model selected (`model`).
    pub fn model(&self) -> ModelKind {
        ModelKind::from_index(self.index_of(ParamId::Model))
    }

    /// The plate material selected (`material`): a preset, or the custom E, ρ, ν parameters.
    pub fn material(&self) -> Material {
        match self.index_of(ParamId::Material) {
            0 => Material::STEEL,
            1 => Material::BRONZE,
            2 => Material::BRASS,
            3 => Material::ALUMINIUM,
            _ => Material {
                youngs_modulus: self.get(ParamId::YoungsModulus) as f64,
                density: self.get(ParamId::Density) as f64,
                poisson: self.get(ParamId::Poisson) as f64,
            },
        }
    }

    /// Whether the instrument these values describe reads `id` (the table's `reads` column):
    /// a parameter it does not read changes nothing in its sound.
    pub fn reads(&self, id: ParamId) -> bool {
        let model = self.model();
        let plate = model.is_plate();
        let mallet = plate && self.index_of(ParamId::Exciter) == 1;
        match id.info().reads {
            Reads::All => true,
            Reads::Bodies => !model.is_network(),
            Reads::Plates => plate,
            Reads::CircularPlates => model.is_circular(),
            Reads::RectPlate => model == ModelKind::RectPlate,
            Reads::Strings => model.is_string(),
            Reads::Plucked => model.is_string() || model.is_network(),
            Reads::Sitar => model == ModelKind::Sitar,
            Reads::Drone => model.is_drone(),
            Reads::SitarTaraf => model.is_sitar_taraf(),
            Reads::Networks => model.is_network(),
            Reads::CustomMaterial => {
                plate && self.index_of(ParamId::Material) + 1 == MATERIAL_NAMES.len()
            }
            Reads::Pulse => plate && !mallet,
            Reads::Mallet => mallet,
            Reads::CustomMallet => mallet && self.index_of(ParamId::MalletHead) == 0,
        }
    }

    /// Sets `id` after [`ParamInfo::check`].
    pub fn set(&mut self, id: ParamId, value: f32) -> Result<(), ParamError> {
        self.0[id.index()] = id.info().check(value)?;
        Ok(())
    }

    /// The values of the parameters that trigger a rebuild, in table order, with the others
    /// zeroed: two snapshots need the same bank iff their rebuild keys are equal. For the
    /// string models the size (the string's length, which sets the grid) is
    /// part of the key, and for the string networks (the drone, the sitar with its taraf) the
    /// root key (where they are tuned by ear).
    pub fn rebuild_key(&self) -> ParamValues {
        let mut k = *self;
        let string = self.model().is_string();
        let drone = self.model().is_network();
        for p in PARAMS {
            if !(p.rebuild || string && p.id == ParamId::Size || drone && p.id == ParamId::RootKey)
            {
                k.0[p.id.index()] = 0.0;
            }
        }
        k
    }

    /// Copies from `other` every value that is part of [`Self::rebuild_key`] (the model's
    /// structure), keeping this set's playing values (gain, tuning, damping, ...).
    pub fn take_rebuild_values(&mut self, other: &ParamValues) {
        let string = other.model().is_string();
        let drone = other.model().is_network();
        for p in PARAMS {
            if p.rebuild || string && p.id == ParamId::Size || drone && p.id == ParamId::RootKey {
                self.0[p.id.index()] = other.0[p.id.index()];
            }
        }
    }
}

impl Default for ParamValues {
    fn default() -> Self {
        Self::defaults()
    }
}

/// Parameter values shared by host, GUI, worker and audio thread: one `AtomicU32` holding the
/// bits of an `f32` per parameter, plus a change counter, and the key table ([`Self::tuning`]).
///
/// Share it as `Arc<SharedParams>`. All methods are lock-free and allocation-free (except the
/// error path of [`Self::set`]); relaxed ordering suffices per value, the counter is
/// incremented with release ordering after each write.
#[derive(Debug)]
pub struct SharedParams {
    values: [AtomicU32; PARAM_COUNT],
    generation: AtomicU64,
    tuning: SharedTuning,
}

impl SharedParams {
    /// Every parameter at its default.
    pub fn new() -> Self {
        Self::from_values(&ParamValues::defaults())
    }

    /// Every parameter from `v` (not checked: build `v` with [`ParamValues::set`]).
    pub fn from_values(v: &ParamValues) -> Self {
        Self {
            values: std::array::from_fn(|i| AtomicU32::new(v.0[i].to_bits())),
            generation: AtomicU64::new(0),
            tuning: SharedTuning::default(),
        }
    }

    /// The key table (12-TET until a host or GUI thread publishes another with
    /// [`SharedTuning::set`]; the audio thread reads it lock-free at each block start).
    pub fn tuning(&self) -> &SharedTuning {
        &self.tuning
    }

    /// The current value of `id`. Any thread, wait-free.
    pub fn get(&self, id: ParamId) -> f32 {
        f32::from_bits(self.values[id.index()].load(Ordering::Relaxed))
    }

    /// Sets `id` to `value` after [`ParamInfo::check`]; the value is unchanged on error.
    /// Host or GUI thread (any thread), wait-free.
    pub fn set(&self, id: ParamId, value: f32) -> Result<(), ParamError> {
        let v = id.info().check(value)?;
        self.values[id.index()].store(v.to_bits(), Ordering::Relaxed);
        self.generation.fetch_add(1, Ordering::Release);
        Ok(())
    }

    /// Copies every value (audio thread once per block; worker thread when polling).
    pub fn snapshot(&self) -> ParamValues {
        // Acquire pairs with the release increment of `set`.
        let _ = self.generation.load(Ordering::Acquire);
        ParamValues(std::array::from_fn(|i| {
            f32::from_bits(self.values[i].load(Ordering::Relaxed))
        }))
    }

    /// Writes every value of `v` (checked first: nothing is written on error).
    pub fn set_all(&self, v: &ParamValues) -> Result<(), ParamError> {
        for p in PARAMS {
            p.check(v.get(p.id))?;
        }
        for (slot, x) in self.values.iter().zip(v.0) {
            slot.store(x.to_bits(), Ordering::Relaxed);
        }
        self.generation.fetch_add(1, Ordering::Release);
        Ok(())
    }

    /// Number of writes so far (a cheap change detector).
    pub fn generation(&self) -> u64 {
        self.generation.load(Ordering::Acquire)
    }
}

impl Default for SharedParams {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_is_consistent() {
        for (i, p) in PARAMS.iter().enumerate() {
            assert_eq!(p.id.index(), i, "{}", p.key);
            assert!(p.min <= p.default && p.default <= p.max, "{}", p.key);
            p.check(p.default).unwrap();
            assert_eq!(ParamId::from_key(p.key), Some(p.id));
            if let ParamKind::Enum { names, keys } = p.kind {
                assert_eq!(p.min, 0.0);
                assert_eq!(p.max as usize + 1, names.len(), "{}", p.key);
                assert_eq!(keys.len(), names.len(), "{}", p.key);
            }
        }
    }

    /// Enumeration names: the preset key exactly, then ignoring case, then the display name
    /// ignoring case; anything else, and non-enumerations, give nothing.
    #[test]
    fn enumeration_names_are_looked_up_once() {
        let model = ParamId::Model.info();
        assert_eq!(model.enum_index("rect-plate"), Some(2));
        assert_eq!(model.enum_index(" Tanpura "), Some(4));
        assert_eq!(model.enum_index("GONG (circular, free edge)"), Some(0));
        assert_eq!(model.enum_index("harp"), None);
        assert_eq!(ParamId::Scheme.info().enum_index("sav"), Some(3));
        assert_eq!(ParamId::Exciter.info().enum_index("mallet"), Some(1));
        assert_eq!(ParamId::Size.info().enum_index("gong"), None);
    }

    #[test]
    fn set_refuses_out_of_range() {
        let s = SharedParams::new();
        let e = s.set(ParamId::Size, 10.0).unwrap_err();
        assert_eq!(e.field, "size");
        assert!(s.set(ParamId::Gain, f32::NAN).is_err());
        assert!(s.set(ParamId::Model, 1.5).is_err());
        s.set(ParamId::Model, 3.0).unwrap();
        assert_eq!(s.snapshot().index_of(ParamId::Model), 3);
        assert_eq!(s.generation(), 1);
    }
}
