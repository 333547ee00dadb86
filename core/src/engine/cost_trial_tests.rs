//! Tests of `cost_trial.rs`: a governed bank's voices carry measured prices, an offline bank's
//! the prior ones. Worker-side code on the test thread.

use crate::clock::thread_cpu_time;
use crate::engine::bank::{Bank, ModalCache};
use crate::engine::governor::PRIOR_SECONDS_PER_UNIT;
use crate::engine::params::{ParamId, ParamValues};
use crate::engine::voice::VoiceModel;
use crate::models::plate::StepBoard;
use std::sync::Arc;

/// A bank for `v` at 48 kHz, governed with a voice share of 0.7 or not.
fn bank(v: &ParamValues, cache: &mut ModalCache, governed: bool) -> Bank {
    let share = governed.then_some(0.7);
    Bank::build(v, 48_000.0, cache, &Arc::new(StepBoard::new()), 1, share).unwrap()
}

fn plate_prices_of(b: &Bank) -> Vec<f64> {
    match &b.voices[0].model {
        VoiceModel::Plate(pv) => pv.data.tier_price.clone(),
        _ => unreachable!("a plate bank"),
    }
}

/// Off the governor a plate's tiers keep their prior prices (offline renders measure
/// nothing); under it every tier gets a measured price, the voices share it, and the
/// trial leaves every voice silent. The largest tier (64 modes, 8 in-plane, its tensor
/// many times the smallest's) costs more than the smallest (8 modes): a trial that
/// timed nothing, or timed the same tier each time, would price them alike.
#[test]
fn a_governed_plate_bank_is_priced_by_trials() {
    let mut v = ParamValues::defaults();
    v.0[ParamId::Modes.index()] = 64.0;
    v.0[ParamId::InPlaneModes.index()] = 8.0;
    v.0[ParamId::Polyphony.index()] = 2.0;
    let mut cache = ModalCache::default();
    let prior = plate_prices_of(&bank(&v, &mut cache, false));
    let b = bank(&v, &mut cache, true);
    let measured = plate_prices_of(&b);
    assert_eq!(prior.len(), measured.len());
    assert!(prior.windows(2).all(|w| w[0] > w[1]), "prior {prior:?}");
    // The prior is 2 ns per unit: the smallest tier's units are a whole number.
    let units = prior[prior.len() - 1] / PRIOR_SECONDS_PER_UNIT;
    assert!((units - units.round()).abs() < 1e-6, "{units}");
    if thread_cpu_time().is_none() {
        return; // no thread clock: nothing measured, the prior stays
    }
    assert_ne!(prior, measured);
    assert!(
        measured.iter().all(|p| p.is_finite() && *p > 0.0),
        "{measured:?}"
    );
    assert!(
        measured[0] > measured[measured.len() - 1],
        "largest tier {:.3e} s, smallest {:.3e} s",
        measured[0],
        measured[measured.len() - 1]
    );
    for voice in &b.voices {
        assert!(!voice.active, "the trial leaves the voice silent");
        let VoiceModel::Plate(pv) = &voice.model else {
            unreachable!()
        };
        assert_eq!(pv.data.tier_price, measured);
        assert_eq!(pv.trial_tier, None);
    }
}

/// A governed string bank's voices carry the trial's price, an offline bank's the prior
/// `2 ns · N²` (the factory tanpura, 166 modes: its step is `O(N log N)`, so the two differ
/// by orders of magnitude). The share here is 20 seconds of work per second, so that no
/// machine's load makes the trial fit the string (the fit is `governor.rs`'s test): this
/// test is about the price the voices carry, which a fit would change.
#[test]
fn a_governed_string_bank_carries_the_trials_price() {
    let mut v = crate::engine::preset::Preset::factory_named("tanpura")
        .expect("a factory preset")
        .values()
        .expect("valid");
    v.0[ParamId::Polyphony.index()] = 2.0;
    let mut cache = ModalCache::default();
    let price = |b: &Bank| match &b.voices[1].model {
        VoiceModel::String(sv) => sv.price,
        _ => unreachable!("a string bank"),
    };
    let prior = price(&bank(&v, &mut cache, false));
    let modes = v.index_of(ParamId::Modes) as f64;
    assert!((prior - PRIOR_SECONDS_PER_UNIT * modes * modes).abs() < 1e-15);
    if thread_cpu_time().is_none() {
        return;
    }
    let b = Bank::build(
        &v,
        48_000.0,
        &mut cache,
        &Arc::new(StepBoard::new()),
        1,
        Some(20.0),
    )
    .unwrap();
    assert!(b.fitted.is_none(), "the tanpura fits a share of 20");
    let measured = price(&b);
    assert!(
        measured.is_finite() && measured > 0.0 && measured != prior,
        "{measured:e}"
    );
    assert!(b.voices.iter().all(|v| !v.active));
}

/// Two voices of the factory `preset` with `sets` (tuned by their tensions, so the bank builds
/// at once) are priced by the prior estimate off the governor and by a trial under it: every
/// voice carries the trial's price (`price_of` reads it), which is positive and finite, and
/// differs from the prior (a trial that timed nothing would leave the prior, or 0).
fn assert_priced_by_its_trial(
    preset: &str,
    sets: &[(ParamId, f32)],
    price_of: fn(&VoiceModel) -> Option<f64>,
) {
    let mut v = crate::engine::Preset::factory_named(preset)
        .expect("factory preset")
        .values()
        .expect("valid");
    v.0[ParamId::Polyphony.index()] = 2.0;
    v.0[ParamId::DroneEar.index()] = 0.0;
    for &(id, x) in sets {
        v.0[id.index()] = x;
    }
    let mut cache = ModalCache::default();
    let prices = |b: &Bank| -> Vec<f64> {
        b.voices
            .iter()
            .map(|voice| price_of(&voice.model).expect("a voice of the preset's model"))
            .collect()
    };
    let prior = prices(&bank(&v, &mut cache, false));
    assert!(prior[0] > 0.0 && prior[0] == prior[1]);
    if thread_cpu_time().is_none() {
        return;
    }
    let measured = prices(&bank(&v, &mut cache, true));
    println!(
        "{preset} step: prior {:.2e} s, measured {:.2e} s",
        prior[0], measured[0]
    );
    assert!(measured[0].is_finite() && measured[0] > 0.0);
    assert_eq!(measured[0], measured[1]);
    assert_ne!(measured[0], prior[0]);
}

/// A drone bank is priced by its trial ([`assert_priced_by_its_trial`]).
#[test]
fn a_governed_drone_bank_carries_the_trials_price() {
    assert_priced_by_its_trial("tanpura-drone", &[], |m| match m {
        VoiceModel::Drone(dv) => Some(dv.price),
        _ => None,
    });
}

/// A sitar bank (three taraf strings at 48 kHz) is priced by its trial as the drone's.
#[test]
fn a_governed_sitar_bank_carries_the_trials_price() {
    let sets = [(ParamId::TarafStrings, 3.0), (ParamId::SimRate, 48_000.0)];
    assert_priced_by_its_trial("sitar-taraf", &sets, |m| match m {
        VoiceModel::Sitar(sv) => Some(sv.price),
        _ => None,
    });
}
