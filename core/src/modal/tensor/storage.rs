//! Single-precision storage of the coupling tensor: [`CouplingTensor::with_storage`] (the
//! [`TensorStorage`] enumeration is defined beside the tensor).
//!
//! The time schemes' kernels stream the tensor once per step; on the gong's tensors (10⁵ to
//! 10⁶ entries) that stream is the step's cost. Single storage keeps the block values in `f32`
//! (half the bytes; `tensor/panels.rs` widens them to `f64` and accumulates in `f64`).
//!
//! # One tensor
//!
//! The model must see one tensor: the conservative schemes' discrete energy
//! `Σ_l u_l Ĥ(q(n), q(n-1))_l²` is an identity only when the energy and the update use the same
//! coefficients `Ĥ`. So single storage does not merely store the blocks in `f32`: it rounds
//! every value of the tensor to `f32` once (`value`, round to nearest) and rebuilds the run and
//! block layouts from the rounded values, so the CSR arrays, the runs (`f64` holding `f32`
//! values, halved on the diagonal exactly) and the `f32` blocks all hold the same numbers.
//! The model then conserves its energy to `f64` round-off as with double storage; what
//! changes is the tensor itself, by a relative `2⁻²⁴` per entry (a perturbation of the
//! physics far below the modal truncation's, measured in `docs/models.md`).
//!
//! Threads: [`CouplingTensor::with_storage`] runs on a worker thread (allocates, `O(nnz)` plus
//! the block layout's build); the result is read-only like any tensor.

use super::{CouplingTensor, TensorStorage};
use crate::error::ParamError;

impl CouplingTensor {
    /// How this tensor stores its values ([`TensorStorage::Double`] for every tensor built by
    /// [`Self::from_parts`]).
    pub fn storage(&self) -> TensorStorage {
        self.storage
    }

    /// This tensor with `storage`: for [`TensorStorage::Single`], every value rounded to the
    /// nearest `f32` and every layout rebuilt from the rounded values (module docs); for
    /// [`TensorStorage::Double`], the current values (already rounded when `self` is single)
    /// in the `f64` layouts. Returns a clone when `storage` is already `self`'s.
    ///
    /// Errors: a value outside the `f32` range (±3.4e38), named by its index. Worker thread;
    /// allocates a full copy.
    pub fn with_storage(&self, storage: TensorStorage) -> Result<Self, ParamError> {
        if storage == self.storage {
            return Ok(self.clone());
        }
        let value: Vec<f64> = match storage {
            TensorStorage::Double => self.value.clone(),
            TensorStorage::Single => self.value.iter().map(|&x| f64::from(x as f32)).collect(),
        };
        if let Some(e) = value.iter().position(|x| !x.is_finite()) {
            return Err(ParamError::new(
                format!("coupling.value[{e}]"),
                self.value[e],
                "within ±3.4e38 (the f32 range) for single storage",
            ));
        }
        Ok(Self::assemble(
            self.n_phi,
            self.n_psi,
            self.row_start.clone(),
            self.i.clone(),
            self.j.clone(),
            value,
            storage,
        ))
    }
}

#[cfg(test)]
#[path = "storage_tests.rs"]
mod tests;
