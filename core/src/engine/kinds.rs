//! The instrument models and plate materials selectable by parameter.

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
}

impl ModelKind {
    /// Every model, in parameter index order.
    pub const ALL: [ModelKind; 5] = [
        ModelKind::Gong,
        ModelKind::Cymbal,
        ModelKind::RectPlate,
        ModelKind::Sitar,
        ModelKind::Tanpura,
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

    /// Whether this is a string model (sitar, tanpura).
    pub fn is_string(self) -> bool {
        !self.is_plate()
    }

    /// Stable names used in presets, in parameter index order.
    pub const KEYS: [&'static str; 5] = ["gong", "cymbal", "rect-plate", "sitar", "tanpura"];

    /// Stable name used in presets ([`Self::KEYS`]).
    pub fn key(self) -> &'static str {
        Self::KEYS[self as usize]
    }
}

/// Elastic constants of a plate material. Plain `Copy` data.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Young's modulus `E` in Pa.
    pub youngs_modulus: f64,
    /// Density `ρ` in kg/m³.
    pub density: f64,
    /// Poisson ratio `ν`.
    pub poisson: f64,
}

impl Material {
    /// Steel: E = 200 GPa, ρ = 7860 kg/m³, ν = 0.3 (the lecture's gong).
    pub const STEEL: Material = Material {
        youngs_modulus: 2.0e11,
        density: 7860.0,
        poisson: 0.3,
    };
    /// Bell bronze (CuSn20): E = 104 GPa, ρ = 8600 kg/m³, ν = 0.34 (handbook values).
    pub const BRONZE: Material = Material {
        youngs_modulus: 1.04e11,
        density: 8600.0,
        poisson: 0.34,
    };
    /// Brass (CuZn37): E = 110 GPa, ρ = 8440 kg/m³, ν = 0.34.
    pub const BRASS: Material = Material {
        youngs_modulus: 1.1e11,
        density: 8440.0,
        poisson: 0.34,
    };
    /// Aluminium alloy: E = 70 GPa, ρ = 2700 kg/m³, ν = 0.33.
    pub const ALUMINIUM: Material = Material {
        youngs_modulus: 7.0e10,
        density: 2700.0,
        poisson: 0.33,
    };
}
