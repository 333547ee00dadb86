//! The banks on their way in and out of the audio thread ([`Handover`]): the channels from
//! and to the worker, the bank fading out, the banks parked until they may leave. The
//! hand-over itself is `handover.rs`.
//!
//! Threads: the audio thread (the engine's main thread between activations).

use super::bank::Bank;
use crossbeam_channel::{Receiver, Sender};

/// The banks on their way in and out of the audio thread. Audio thread (the engine's main
/// thread between activations).
pub(super) struct Handover {
    /// New banks from the worker (capacity 1).
    pub bank_rx: Receiver<Box<Bank>>,
    /// Replaced banks back to the worker, dropped there (capacity 4).
    pub retire_tx: Sender<Box<Bank>>,
    /// The replaced bank fading out, and the host samples of its fade done.
    pub retiring: Option<(Box<Bank>, usize)>,
    /// Replaced banks that could not leave yet (the queue full or a pool worker still
    /// reaching them): sent at a later chunk.
    pub pending_drop: [Option<Box<Bank>>; 3],
    /// A bank kept when every slot was taken (unreachable; never dropped here).
    pub overflow: Option<Box<Bank>>,
}

impl Handover {
    /// The audio side of the two channels, nothing in flight.
    pub fn new(bank_rx: Receiver<Box<Bank>>, retire_tx: Sender<Box<Bank>>) -> Self {
        Self {
            bank_rx,
            retire_tx,
            retiring: None,
            pending_drop: [None, None, None],
            overflow: None,
        }
    }

    /// Drops every bank in flight: those still queued (an earlier generation's), the one
    /// fading out and the parked ones. Main thread, between activations (the voice pool is
    /// stopped, so no worker reaches them; this drops, so never on the audio thread).
    pub fn drop_in_flight(&mut self) {
        while self.bank_rx.try_recv().is_ok() {}
        self.retiring = None;
        self.pending_drop = [None, None, None];
        self.overflow = None;
    }
}
