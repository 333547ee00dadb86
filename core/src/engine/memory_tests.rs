//! Tests of `memory.rs`: the prediction against the built tensors, the cap, and the sharing of
//! tensors between engines through the process's registry. Worker-side code on the test thread.

use super::memory::*;
use crate::engine::bank::{Bank, ModalCache};
use crate::engine::params::{ParamId, ParamValues};
use crate::engine::voice::VoiceModel;
use crate::error::ParamError;
use crate::models::plate::basis::BasisKey;
use crate::models::plate::StepBoard;
use std::sync::Arc;

/// A gong of `modes` × `in_plane` modes, two voices, memory cap `mb`.
fn gong(modes: f32, in_plane: f32, mb: f32) -> ParamValues {
    let mut v = ParamValues::defaults();
    v.0[ParamId::Modes.index()] = modes;
    v.0[ParamId::InPlaneModes.index()] = in_plane;
    v.0[ParamId::Polyphony.index()] = 2.0;
    v.0[ParamId::MemoryCap.index()] = mb;
    v
}

fn build(v: &ParamValues, cache: &mut ModalCache) -> Result<Bank, ParamError> {
    Bank::build(v, 48_000.0, cache, &Arc::new(StepBoard::new()), 1, None)
}

/// The tensor of the voice in `slot`'s current tier.
fn tensor(bank: &Bank, slot: usize) -> *const crate::modal::CouplingTensor {
    match &bank.voices[slot].model {
        VoiceModel::Plate(pv) => Arc::as_ptr(pv.model().coupling()),
        _ => std::ptr::null(),
    }
}

/// The prediction bounds what is built: the bank's tier tensors and the cache's basis.
#[test]
fn the_prediction_bounds_the_built_tensors() {
    let v = gong(300.0, 30.0, 0.0);
    let mut cache = ModalCache::default();
    let bank = build(&v, &mut cache).unwrap();
    assert_eq!(bank.fitted, None);
    let held = (bank.tensor_bytes + cache.heap_bytes()) as u64;
    let key = BasisKey::new(
        crate::models::plate::spec::PlateShape::CircularFree,
        v.material().poisson,
        1.0,
        300,
        30,
        crate::models::plate::spec::Symmetry::StrikeMirror,
    )
    .unwrap();
    let tiers = crate::engine::voice::tier_ladder(300, 30);
    let predicted = predicted_bytes(&key, &tiers);
    assert!(
        predicted >= held && (predicted as f64) < 2.0 * held as f64,
        "predicted {predicted} bytes, held {held}"
    );
}

/// A cap below the model's prediction builds it a tier or more smaller, says so, and
/// holds at most the cap; a cap below the smallest tier refuses, naming the cap.
#[test]
fn a_plate_over_the_cap_is_built_smaller() {
    let mut cache = ModalCache::default();
    let full = build(&gong(300.0, 30.0, 0.0), &mut cache).unwrap();
    let full_bytes = full.tensor_bytes + cache.heap_bytes();
    let cap_mb = (full_bytes as f64 / 1048576.0 / 2.0) as f32;
    let mut cache = ModalCache::default();
    let small = build(&gong(300.0, 30.0, cap_mb), &mut cache).unwrap();
    let f = small.fitted.expect("reduced");
    assert_eq!((f.wanted, f.reason), (300, FitReason::Memory));
    assert!(f.built < 300);
    let held = small.tensor_bytes + cache.heap_bytes();
    assert!(
        (held as f64) <= f64::from(cap_mb) * 1048576.0,
        "{held} bytes held under a cap of {cap_mb} MB"
    );
    let mut cache = ModalCache::default();
    let err = build(&gong(300.0, 30.0, 0.001), &mut cache)
        .err()
        .expect("not even the smallest tier fits in 1 kB");
    assert_eq!(err.field, "memory_cap");
}

/// Two engines' banks of the same plate (each with its own modal cache) share their tier
/// tensors and basis through the process's registry; a bank of another plate does not.
#[test]
fn banks_of_the_same_plate_share_their_tensors() {
    let v = gong(120.0, 12.0, 0.0);
    let (mut c1, mut c2) = (ModalCache::default(), ModalCache::default());
    let a = build(&v, &mut c1).unwrap();
    let b = build(&v, &mut c2).unwrap();
    assert_eq!(tensor(&a, 0), tensor(&b, 0));
    assert_eq!(
        tensor(&a, 0),
        tensor(&a, 1),
        "the voices of a bank share it"
    );
    let mut other = v;
    other.0[ParamId::InPlaneModes.index()] = 11.0;
    let c = build(&other, &mut ModalCache::default()).unwrap();
    assert_ne!(tensor(&a, 0), tensor(&c, 0));
}
