//! How a string network's strings were tuned, reported with the bank (`engine/drone_bank.rs`
//! decides it for the drone within [`DRONE_TUNING_BUDGET`], `engine/sitar_bank.rs` for the
//! sitar within [`SITAR_TUNING_BUDGET`]). Plain `Copy` data, any thread.

/// The most CPU time (s, at the prior price of a step) the worker spends tuning a drone by
/// ear: the factory drone's full tuning (25 keys) takes about 55 s. A drone whose full tuning would
/// take longer (more strings, modes or rate) is tuned at its root only, and one whose root
/// alone would is tuned by its tensions, so every build ends in bounded time; the bank says
/// which ([`DroneTuning`]).
pub const DRONE_TUNING_BUDGET: f64 = 60.0;

/// The most CPU time (s, at the prior price of a step) the worker spends tuning a sitar by
/// ear; a sitar whose full tuning would take longer is tuned at its open notes only, and one
/// whose open notes alone would is tuned by its tensions, so every build ends in bounded
/// time; the bank says which ([`DroneTuning`]). The factory sitar's full tuning is estimated
/// at 75 s (it measures 70-80 s of CPU, 40 s of wall on two threads).
pub const SITAR_TUNING_BUDGET: f64 = 120.0;

/// How a drone's or a sitar's strings were tuned (reported with the bank).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DroneTuning {
    /// By ear at the root and at every anchor key (`engine::DRONE_ANCHORS`,
    /// `engine::SITAR_ANCHORS`).
    ByEar,
    /// By ear at the root only: the full tuning was over [`DRONE_TUNING_BUDGET`] (keys away
    /// from the root drift by up to a few cents).
    RootOnly,
    /// By the tensions alone, as asked (`drone_ear` off) or because tuning at the root alone
    /// was over [`DRONE_TUNING_BUDGET`] (within a few cents).
    Tensions {
        /// Whether tuning by ear was asked for (and over the budget).
        asked: bool,
    },
}

impl std::fmt::Display for DroneTuning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DroneTuning::ByEar => write!(f, "tuned by ear at the root and at keys up to 12 semitones around it"),
            DroneTuning::RootOnly => write!(
                f,
                "tuned by ear at the root only (a full tuning would take over the worker's budget: {DRONE_TUNING_BUDGET} s of CPU for a drone, {SITAR_TUNING_BUDGET} s for a sitar)"
            ),
            DroneTuning::Tensions { asked: true } => write!(
                f,
                "tuned by the tensions alone (tuning by ear would take over the worker's budget: {DRONE_TUNING_BUDGET} s of CPU for a drone, {SITAR_TUNING_BUDGET} s for a sitar)"
            ),
            DroneTuning::Tensions { asked: false } => {
                write!(f, "tuned by the tensions alone (tuning by ear off)")
            }
        }
    }
}
