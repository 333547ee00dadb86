//! The instrument models selectable by parameter (the materials are the scenes' own
//! [`crate::models::plate::spec::Material`], with its named constants).

/// The model a voice bank plays ([`ParamId::Model`]). Plain `Copy` data, any thread.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ModelKind {
    /// Circular plate with a free edge (the lecture's gong, SEED.md 3.1).
    Gong,
    /// Circular plate with a clamped edge (a cymbal-like plate).
    Cymbal,
    /// Simply supported rectangular plate (lx = size, ly = aspect · size).
    RectPlate,
    /// Stiff string against a curved sitar bridge (SEED.md 3.2).
    Sitar,
    /// Stiff string against a point bridge near the end (the lecture's tanpura).
    Tanpura,
    /// The tanpura drone: four to six strings with their jivari on one moving bridge, tuned
    /// to Sa (the key held) and plucked in a cycle (`models::tanpura`).
    Drone,
    /// The sitar with its taraf: the played string on the curved jawari, 0 to 13
    /// sympathetic strings tuned to a thaat of Sa (the root key) and up to three chikari, on
    /// the two bridges' shared modes (`models::sitar`); a key is the played string's fret.
    SitarTaraf,
}

impl ModelKind {
    /// Every model, in parameter index order.
    pub const ALL: [ModelKind; 7] = [
        ModelKind::Gong,
        ModelKind::Cymbal,
        ModelKind::RectPlate,
        ModelKind::Sitar,
        ModelKind::Tanpura,
        ModelKind::Drone,
        ModelKind::SitarTaraf,
    ];

    /// The model at parameter index `i` (out-of-range indices give the gong; values that
    /// passed [`ParamInfo::check`](super::ParamInfo::check) are always in range).
    pub fn from_index(i: usize) -> Self {
        Self::ALL.get(i).copied().unwrap_or(ModelKind::Gong)
    }

    /// Whether this is a plate (von Kármán) model.
    pub fn is_plate(self) -> bool {
        matches!(self, Self::Gong | Self::Cymbal | Self::RectPlate)
    }

    /// Whether this is a circular plate (gong, cymbal).
    pub fn is_circular(self) -> bool {
        matches!(self, Self::Gong | Self::Cymbal)
    }

    /// Whether this is a single-string model (sitar, tanpura).
    pub fn is_string(self) -> bool {
        matches!(self, Self::Sitar | Self::Tanpura)
    }

    /// Whether this is the tanpura drone (strings on a moving bridge, a pluck cycle).
    pub fn is_drone(self) -> bool {
        self == Self::Drone
    }

    /// Whether this is the sitar with its taraf.
    pub fn is_sitar_taraf(self) -> bool {
        self == Self::SitarTaraf
    }

    /// Whether this is an instrument of strings on moving bridges (the drone, the sitar with
    /// its taraf): built and tuned by ear on the worker, with a preview tuned by tension.
    pub fn is_network(self) -> bool {
        matches!(self, Self::Drone | Self::SitarTaraf)
    }

    /// Stable names used in presets, in parameter index order.
    pub const KEYS: [&'static str; 7] = [
        "gong",
        "cymbal",
        "rect-plate",
        "sitar",
        "tanpura",
        "tanpura-drone",
        "sitar-taraf",
    ];

    /// Stable name used in presets ([`Self::KEYS`]).
    pub fn key(self) -> &'static str {
        Self::KEYS[self as usize]
    }
}
