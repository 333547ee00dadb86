//! Bank handover on the audio thread: a bank built by the worker is taken at a chunk boundary,
//! the replaced one fades out and is sent back to the worker to be dropped there, never on the
//! audio thread, and only when no thread of the voice pool can still reach it.
//!
//! Threads: audio thread (lock-free `try_recv` / `try_send`, no allocation, no drop).

use super::audio::Engine;
use super::bank::Bank;
impl Engine {
    /// Whether a bank may leave the audio thread: no worker of the voice pool can reach it.
    fn may_hand_away(&self, b: &Bank) -> bool {
        !b.lanes.any_busy() && self.jobs.pool.as_ref().is_none_or(|p| p.quiescent())
    }

    /// Sends a replaced bank back to the worker, or parks it until the queue has room and the
    /// voice pool is quiescent (new banks are accepted only when nothing is parked, so at most
    /// three banks are ever parked: the slots never overflow and no bank is dropped on the
    /// audio thread).
    pub(super) fn retire(&mut self, bank: Box<Bank>) {
        let sent = if self.may_hand_away(&bank) {
            self.handover
                .retire_tx
                .try_send(bank)
                .map_err(|e| e.into_inner())
        } else {
            Err(bank)
        };
        if let Err(b) = sent {
            if let Some(slot) = self.handover.pending_drop.iter_mut().find(|s| s.is_none()) {
                *slot = Some(b);
            } else {
                // Unreachable (see above); keep the bank alive rather than drop it here.
                self.handover.overflow = Some(b);
            }
        }
    }

    pub(super) fn swap_bank(&mut self) {
        for i in 0..self.handover.pending_drop.len() {
            if let Some(b) = self.handover.pending_drop[i].take() {
                let sent = if self.may_hand_away(&b) {
                    self.handover
                        .retire_tx
                        .try_send(b)
                        .map_err(|e| e.into_inner())
                } else {
                    Err(b)
                };
                if let Err(b) = sent {
                    self.handover.pending_drop[i] = Some(b);
                }
            }
        }
        let parked = self.handover.pending_drop.iter().any(|s| s.is_some())
            || self.handover.overflow.is_some();
        if parked || self.jobs.held.is_some() {
            return;
        }
        let Ok(new) = self.handover.bank_rx.try_recv() else {
            return;
        };
        if new.generation != self.generation || new.host_rate != self.host_rate {
            self.retire(new);
            return;
        }
        if let Some((old, _)) = self.handover.retiring.take() {
            self.retire(old);
        }
        if let Some(old) = self.bank.replace(new) {
            if old.voices.iter().any(|v| v.active) {
                self.handover.retiring = Some((old, 0));
            } else {
                self.retire(old);
            }
        }
        // Notes of the new bank take the current tuning at their start.
        self.notes.applied = (self.values, self.notes.bend);
        self.notes.tuning_applied = self.notes.tuning_seen;
    }
}
