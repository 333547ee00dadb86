//! Memory in bounds: the bytes a plate bank's coupling tensors will take, predicted before
//! anything is built, and the cap (`memory_cap` parameter) that reduces a model over it.
//!
//! **What a plate holds.** Its basis's tensor in `f64` (kept by the worker's modal cache,
//! shared by the voices' tiers), and one single-storage tensor per tier of the bank
//! (`plate_bank`: the top tier's and its truncations, shared by the voices; polyphony adds
//! only voice states, vectors of modes). Every tensor keeps its entries three times (the
//! entry arrays, the runs and the dense blocks of `modal::tensor`). Measured with
//! `CouplingTensor::heap_bytes` on circular and rectangular bases from 40 × 8 to 800 × 100
//! (`models::plate::basis` tests): 37-61 bytes per entry in `f64`, 32-49 in single storage,
//! the most for the smallest bases (row and block overheads). The prediction takes
//! [`DOUBLE_BYTES_PER_ENTRY`] and [`SINGLE_BYTES_PER_ENTRY`] above both, times the entries
//! the selection rules give (`BasisKey::predicted_entries`), so it is an upper bound.
//!
//! **The cap.** When the prediction of the wanted tiers passes the cap, the top tier comes
//! off (the band comes down `1/√2` of the modes, the in-plane modes in proportion, as the CPU
//! governor narrows a note), until the prediction fits; the bank is built at that size and
//! the reduction reported (`ModesFitted`, reason [`FitReason::Memory`]). A basis that does
//! not fit even at its smallest tier is refused with a message naming the cap. The default
//! (`memory_cap` 0) is a quarter of the machine's memory, at most [`AUTO_CAP_MAX`].
//!
//! Worker thread (the prediction computes mode lists: milliseconds to a fraction of a
//! second; it is skipped when a quick bound already fits).

use crate::error::ParamError;
use crate::models::plate::basis::BasisKey;
use std::sync::Mutex;

/// Bytes per stored entry of an `f64` tensor, an upper bound of the measured 37-61.
pub const DOUBLE_BYTES_PER_ENTRY: u64 = 64;

/// Bytes per stored entry of a single-storage tensor, an upper bound of the measured 32-49.
pub const SINGLE_BYTES_PER_ENTRY: u64 = 52;

/// Largest default cap (bytes): 4 GiB.
pub const AUTO_CAP_MAX: u64 = 4 << 30;

/// Default cap where the machine's memory cannot be read (bytes): 2 GiB.
const AUTO_CAP_UNKNOWN: u64 = 2 << 30;

/// A bank built with fewer modes than its parameters ask, and why.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ModesFitted {
    /// Transverse modes the parameters ask for.
    pub wanted: u32,
    /// Transverse modes the bank was built with.
    pub built: u32,
    /// The CPU budget (a string voice) or the memory cap (a plate).
    pub reason: FitReason,
}

/// Why a bank was built with fewer modes than its parameters ask.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FitReason {
    /// One string voice would cost more than its share of the CPU budget (`string_bank`).
    Cpu,
    /// The plate's tensors would take more than the memory cap (this module).
    Memory,
}

/// The cap in bytes for the `memory_cap` value `mb` (0: a quarter of the machine's physical
/// memory, at most [`AUTO_CAP_MAX`]). Any thread.
pub fn cap_bytes(mb: f32) -> u64 {
    if mb > 0.0 {
        return (f64::from(mb) * 1048576.0) as u64;
    }
    physical_memory().map_or(AUTO_CAP_UNKNOWN, |b| (b / 4).min(AUTO_CAP_MAX))
}

/// The machine's physical memory in bytes, where the OS says (`sysconf`).
fn physical_memory() -> Option<u64> {
    #[cfg(unix)]
    {
        // SAFETY: sysconf reads system constants; no pointers.
        let (pages, size) = unsafe {
            (
                libc::sysconf(libc::_SC_PHYS_PAGES),
                libc::sysconf(libc::_SC_PAGESIZE),
            )
        };
        (pages > 0 && size > 0).then(|| pages as u64 * size as u64)
    }
    #[cfg(not(unix))]
    {
        None
    }
}

/// Predictions kept (a worker's rebuilds of one model, for a new strike position or material,
/// ask again: the circular mode lists of 2000 modes take 1.4 s here).
const REMEMBERED: usize = 32;

/// One remembered prediction: the basis, its tiers `(N_Φ, N_Ψ)` and the bytes.
type Prediction = (BasisKey, Vec<(usize, usize)>, u64);

/// The last predictions, newest last. Worker threads.
static PREDICTIONS: Mutex<Vec<Prediction>> = Mutex::new(Vec::new());

/// The predicted bytes of a plate of basis `key` built with `tiers` (`(N_Φ, N_Ψ)`, the top
/// first): the basis in `f64` plus every tier in single storage, from the counted entries.
/// Remembered for the last [`REMEMBERED`] keys.
pub fn predicted_bytes(key: &BasisKey, tiers: &[(usize, usize)]) -> u64 {
    let lock = || PREDICTIONS.lock().unwrap_or_else(|p| p.into_inner());
    if let Some(&(_, _, bytes)) = lock().iter().find(|(k, t, _)| k == key && t == tiers) {
        return bytes;
    }
    let entries = key.predicted_entries_of(tiers);
    let top = entries.first().copied().unwrap_or(0) as u64;
    let all: u64 = entries.iter().map(|&e| e as u64).sum();
    let bytes = top * DOUBLE_BYTES_PER_ENTRY + all * SINGLE_BYTES_PER_ENTRY;
    let mut memo = lock();
    if memo.len() >= REMEMBERED {
        memo.remove(0);
    }
    memo.push((*key, tiers.to_vec(), bytes));
    bytes
}

/// A quick upper bound of [`predicted_bytes`] without mode lists: every pair `j ≤ i` of every
/// in-plane row stored, the tiers' sum bounded by twice the top's (they fall as `2^{-3k/2}`).
pub fn quick_bound(n_phi: usize, n_psi: usize) -> u64 {
    let top = (n_psi.max(1) * n_phi * (n_phi + 1) / 2) as u64;
    top * (DOUBLE_BYTES_PER_ENTRY + 2 * SINGLE_BYTES_PER_ENTRY)
}

/// The tiers that fit under `cap` bytes: `ladder` (top first) with its top tiers taken off
/// until the prediction for `key_of(top)` fits. `Ok(ladder)` when it fits whole; `Err` names
/// the cap when not even the smallest tier fits.
pub fn fit_tiers(
    ladder: &[(usize, usize)],
    cap: u64,
    key_of: impl Fn(usize, usize) -> Result<BasisKey, ParamError>,
) -> Result<Vec<(usize, usize)>, ParamError> {
    for start in 0..ladder.len() {
        let tiers = &ladder[start..];
        let (n, m) = tiers[0];
        if quick_bound(n, m) <= cap || predicted_bytes(&key_of(n, m)?, tiers) <= cap {
            return Ok(tiers.to_vec());
        }
    }
    let smallest = ladder.last().copied().unwrap_or((0, 0));
    Err(ParamError::new(
        "memory_cap",
        format!("{} MB", cap >> 20),
        format!(
            "room for the coupling tensors of {} x {} modes at least",
            smallest.0, smallest.1
        ),
    ))
}
