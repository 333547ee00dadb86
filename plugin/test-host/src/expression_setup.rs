//! What the `expression` cases (`expression.rs`) and their polyphonic-modulation cases
//! (`polymod.rs`) share: the host rate and block, the instance set-up, and what `--break`
//! leaves out (the negative controls).

use crate::conform_render::{load_state, Session};
use crate::host::{activate_started, Started};

/// Host rate of the renders (Hz).
pub(crate) const RATE: f64 = 48_000.0;
/// Block size (frames).
pub(crate) const BLOCK: usize = 256;
/// What `--break` leaves out.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Break {
    /// The CLAP tuning expressions.
    Tuning,
    /// The CLAP volume expression.
    Volume,
    /// The MPE Configuration Message.
    MpeConfig,
    /// The member-channel bends.
    MemberBend,
    /// The polyphonic modulation (`polymod.rs`).
    PolyMod,
    /// The note-offs (`polymod.rs`: no note may end).
    NoteOff,
    /// The CLAP pressure expression (`polymod.rs`).
    Pressure,
}

/// A fresh instance of `s` with `blob` loaded, activated at [`RATE`] for blocks of 1 to
/// [`BLOCK`] frames and processing (the `expression` cases' set-up).
pub(crate) fn started(s: &Session, blob: &[u8]) -> Result<Started, String> {
    let mut inst = s.instance()?;
    load_state(&mut inst, blob)?;
    activate_started(inst, RATE, BLOCK as u32)
}
