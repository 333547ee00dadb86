//! Tests of the preset state against a fake host ([`FakeHost`]).

use super::*;
use crate::fake_host::FakeHost;
use crate::preset_state::{Origin, INIT_NAME};
use crate::user_presets::tests::random_values;
use noether_core::engine::ParamId;
use noether_core::engine::Preset;

fn bits(v: &ParamValues) -> Vec<u32> {
    v.0.iter().map(|x| x.to_bits()).collect()
}

/// What the host holds after setting `v` (plain values rounded through the normalized form).
fn host_values(params: &NoetherParams, host: &FakeHost, v: &ParamValues) -> ParamValues {
    apply(params, &ParamSetter::new(host), v);
    host.take();
    params.plain_values()
}

/// The start-up preset: named, not edited on a fresh instance (the host's defaults differ from
/// the table's by the skewed ranges' rounding only).
#[test]
fn start_up_preset_is_named_and_clean() {
    let params = NoetherParams::default();
    let state = params.preset.read().unwrap();
    assert!(!state.current.name.is_empty());
    assert_eq!(state.current.reference, Some(ParamValues::defaults()));
    match &state.current.origin {
        Origin::Init => assert_eq!(state.current.name, INIT_NAME),
        Origin::Factory(stem) => {
            let p = Preset::factory_named(stem).unwrap();
            assert_eq!(p.values().unwrap(), ParamValues::defaults());
        }
        other => panic!("start-up origin {other:?}"),
    }
    assert_eq!(state.current.display(&params), state.current.name);
}

/// Loading a factory preset: gestures in begin/set/end order, the name shown clean; moving a
/// parameter marks it edited ("name *"), moving it back clears the mark; a step of an integer
/// or a float above the tolerance marks it, a sub-tolerance wobble does not.
#[test]
fn edited_mark_follows_the_values() {
    let params = NoetherParams::default();
    let host = FakeHost::default();
    let setter = ParamSetter::new(&host);
    let (stem, preset) = Preset::factory()
        .into_iter()
        .find(|(s, _)| *s == "sitar")
        .unwrap();
    let values = preset.values().unwrap();
    let mut state = PresetState::default();
    state.load(
        &params,
        &setter,
        CurrentPreset::new(&preset.name, Origin::Factory(stem.into()), values),
        &values,
    );
    let log = host.take();
    assert!(!log.is_empty());
    for g in log.chunks(3) {
        assert_eq!(
            [g[0].0, g[1].0, g[2].0],
            ['b', 's', 'e'],
            "{g:?}: not one gesture"
        );
        assert!(g[0].1 == g[1].1 && g[1].1 == g[2].1);
    }
    assert_eq!(state.current.display(&params), preset.name);

    let Slot::Float(size) = params.slot(ParamId::Size) else {
        panic!("size is a float")
    };
    let n0 = size.unmodulated_normalized_value();
    for (dn, edited) in [
        (0.01, true),
        (2.0 * NORMALIZED_TOLERANCE, true),
        (0.0, false),
    ] {
        setter.set_parameter_normalized(size, n0 + dn);
        assert_eq!(
            state.current.is_edited(&params),
            edited,
            "size moved by {dn}"
        );
    }
    assert_eq!(state.current.display(&params), preset.name);
    setter.set_parameter_normalized(size, n0 + 0.01);
    assert_eq!(state.current.display(&params), format!("{} *", preset.name));
    setter.set_parameter_normalized(size, n0);

    let Slot::Int(modes) = params.slot(ParamId::Modes) else {
        panic!("modes is an integer")
    };
    let m0 = modes.unmodulated_plain_value();
    setter.set_parameter(modes, m0 + 1);
    assert!(state.current.is_edited(&params));
    setter.set_parameter(modes, m0);
    assert!(!state.current.is_edited(&params));

    // No reference (an older state's name only): never marked.
    state.current.reference = None;
    setter.set_parameter(modes, m0 + 1);
    assert!(!state.current.is_edited(&params));
}

/// A/B: switching restores each slot's host values bit for bit (for 20 random pairs), keeps
/// each slot's preset and edited mark, the first switch copies; copying makes both equal.
#[test]
fn ab_swap_restores_values_exactly() {
    let params = NoetherParams::default();
    let host = FakeHost::default();
    let setter = ParamSetter::new(&host);
    let mut state = PresetState::default();
    let start = params.plain_values();
    // First switch to B: B starts as a copy of A, nothing changes.
    state.switch_to(AbSlot::B, &params, &setter);
    assert_eq!(state.active, AbSlot::B);
    assert!(
        host.take().is_empty(),
        "switching to a fresh copy moved parameters"
    );
    assert_eq!(bits(&params.plain_values()), bits(&start));
    state.switch_to(AbSlot::A, &params, &setter);

    let sets = random_values(40, 0xab);
    for pair in sets.chunks(2) {
        let a = host_values(&params, &host, &pair[0]);
        state.current = CurrentPreset::new("a", Origin::User("a".into()), a);
        state.copy_to_other(&params);
        state.switch_to(AbSlot::B, &params, &setter);
        let b = host_values(&params, &host, &pair[1]);
        state.current = CurrentPreset::new("b", Origin::User("b".into()), pair[1]);
        for _ in 0..3 {
            state.switch_to(AbSlot::A, &params, &setter);
            assert_eq!(bits(&params.plain_values()), bits(&a), "A not restored");
            assert_eq!(state.current.display(&params), "a");
            let log = host.take();
            assert!(log.iter().all(|(k, _)| "bse".contains(*k)) && log.len() % 3 == 0);
            state.switch_to(AbSlot::B, &params, &setter);
            assert_eq!(bits(&params.plain_values()), bits(&b), "B not restored");
            assert_eq!(state.current.display(&params), "b");
        }
        state.switch_to(AbSlot::A, &params, &setter);
    }
    // Switching to the active slot does nothing.
    host.take();
    state.switch_to(AbSlot::A, &params, &setter);
    assert!(host.take().is_empty());
}

/// The persisted state comes back equal through nice-plug's field serialisation (values bit
/// for bit), and an older state's factory name gets that preset's values.
#[test]
fn state_persists() {
    let params = NoetherParams::default();
    let host = FakeHost::default();
    let setter = ParamSetter::new(&host);
    {
        let mut state = params.preset.write().unwrap();
        let v = random_values(1, 7)[0];
        state.current = CurrentPreset::new("mine", Origin::User("mine".into()), v);
        state.copy_to_other(&params);
        state.switch_to(AbSlot::B, &params, &setter);
    }
    let fields = params.serialize_fields();
    let other = NoetherParams::default();
    other.deserialize_fields(&fields);
    let (a, b) = (params.preset.read().unwrap(), other.preset.read().unwrap());
    assert_eq!(*a, *b);
    assert_eq!(b.active, AbSlot::B);
    let ra = a.other.as_ref().unwrap().values.unwrap();
    let rb = b.other.as_ref().unwrap().values.unwrap();
    assert_eq!(bits(&ra), bits(&rb));

    // An older state: the name only.
    let (stem, preset) = Preset::factory().into_iter().nth(1).unwrap();
    let mut old = std::collections::BTreeMap::new();
    old.insert(
        "preset".to_string(),
        nice_plug::params::persist::serialize_field(&preset.name).unwrap(),
    );
    let p = NoetherParams::default();
    p.deserialize_fields(&old);
    let s = p.preset.read().unwrap();
    assert_eq!(s.current.origin, Origin::Factory(stem.into()));
    assert_eq!(s.current.reference, Some(preset.values().unwrap()));
    // The file stem, as the plugin's CI state blobs write it, finds the preset too.
    let mut by_stem = std::collections::BTreeMap::new();
    by_stem.insert(
        "preset".to_string(),
        nice_plug::params::persist::serialize_field(&stem).unwrap(),
    );
    let q = NoetherParams::default();
    q.deserialize_fields(&by_stem);
    assert_eq!(q.preset.read().unwrap().current, s.current);
    // A corrupt preset state is ignored (the name is used).
    old.insert("preset_state".into(), "{not json".into());
    let p = NoetherParams::default();
    p.deserialize_fields(&old);
    assert_eq!(p.preset.read().unwrap().current.name, preset.name);
}
