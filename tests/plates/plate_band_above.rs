//! The band above the simulation in scenes (`plate.band_above`): the plate's linear modes past
//! its basis receive exactly the energy the truncation closure absorbs, the joint power
//! balance of plate, mallet and band above closes to round-off, the simulated band is not
//! touched (the band above does not act back), and a scene it cannot serve is refused by name.

use noether::error::SceneError;
use noether::models::plate::voice::PlateVoice;
use noether::models::source::RenderSource;
use noether::scene::Scene;

/// The closure's test plate (`plate_closure.rs`) in its strike-mirror subspace, the closure at
/// 10 times its calibrated strength, with the band above `band_above` and the `pickups` tables.
fn scene(scheme: &str, band_above: bool, pickups: &str) -> Result<Scene, SceneError> {
    let extra = format!("symmetry = \"strike-mirror\"\nband_above = {band_above}\n{pickups}");
    super::plate_closure::scene_with(scheme, 10.0, &extra)
}

/// Renders `n` samples; returns the voice and its outputs.
fn render(s: &Scene, n: usize) -> (PlateVoice, Vec<Vec<f64>>) {
    let mut voice = PlateVoice::build(s.plate.as_ref().unwrap()).unwrap();
    let mut out = vec![vec![0.0; n]; voice.channels()];
    voice.process(&mut out, n);
    (voice, out)
}

/// For the conservative-exact and SAV schemes, the closure at 10 times its calibrated strength
/// (it takes about half the strike's energy from this 40-mode plate):
/// - the band above received exactly what the closure absorbed (relative 1e-12: the same
///   sums, taken step by step);
/// - the band holds it, pending or stored, or lost it to its own damping, to round-off
///   (its balance within 1e-12 of what it received);
/// - the joint balance of plate, mallet and band (the report's energy terms, with the
///   closure's share of the plate's dissipation moved to the band) stays within 1e-11 of the
///   launch energy, as without the band (6e-13 and 4e-15 measured there);
/// - the band sounds: its modes hold energy and the output differs from the render without
///   it, while the plate's own state is bit-identical (the band does not act back).
///
/// Feeding the band a different energy than the closure absorbed fails the first and third
/// checks.
#[test]
fn the_band_above_carries_exactly_the_absorbed_energy() {
    for scheme in ["conservative-exact", "sav"] {
        let n = 14_400;
        let (voice, out) = render(&scene(scheme, true, "").unwrap(), n);
        let (plain, plain_out) = render(&scene(scheme, false, "").unwrap(), n);
        let e = voice.model().energy();
        let x = voice.band_above().expect("band above on").energy();
        let launched = voice.mallet().unwrap().energy().launched;
        let joint = voice.energy().balance();
        println!(
            "{scheme}: {} modes above, closure {:.4e} J, received {:.4e} J, stored {:.3e} J, \
             band balance {:.2e} J, joint balance {joint:.2e} J of {launched:.3e} J",
            voice.band_above().unwrap().len(),
            e.closure,
            x.received,
            x.stored,
            x.balance()
        );
        assert!(
            voice.band_above().unwrap().len() > 100,
            "too few modes above"
        );
        assert!(
            e.closure > 1e-3 * launched,
            "{scheme}: the closure took little"
        );
        assert!(
            (x.received - e.closure).abs() <= 1e-12 * e.closure,
            "{scheme}: received {:e} of {:e} absorbed",
            x.received,
            e.closure
        );
        assert!(x.balance().abs() <= 1e-12 * x.received, "{x:?}");
        assert!(
            joint.abs() < 1e-11 * launched,
            "{scheme}: joint balance {joint:e}"
        );
        assert!(x.stored > 1e-3 * x.received, "{x:?}");
        assert_eq!(voice.model().q(), plain.model().q(), "the plate moved");
        assert_ne!(out, plain_out, "the band above is silent");
    }
}

/// The band above has two outputs: a scene with three pickups and `band_above = true` is
/// refused naming `plate.band_above`; `false` is accepted.
#[test]
fn three_pickups_are_refused_by_name() {
    let three = r#"
[[plate.pickups]]
at = { r = 0.5, angle = 0.0 }
[[plate.pickups]]
at = { r = 0.6, angle = 1.0 }
[[plate.pickups]]
at = { r = 0.7, angle = 2.0 }
"#;
    let e = scene("sav", true, three).unwrap_err().to_string();
    assert!(
        e.contains("plate.band_above") && e.contains("3 pickups"),
        "{e}"
    );
    assert!(scene("sav", false, three).is_ok());
}

/// `strike_above` in a scene (the same plate and mallet, the closure off so the band above
/// hears only the strike), for the conservative-exact and SAV schemes:
/// - the band above was struck with a fair part of the strike (more than 1e-3 of the launch
///   energy; 14 % measured on this 40-mode plate), and its own balance closes to 1e-12;
/// - the joint balance of plate, mallet, residual and band stays within 1e-11 of the launch
///   energy (measured 5e-14 to 1.2e-13): the residual's spring, loss and the mallet's work on
///   it are in the report's terms, and the band received exactly what the dashpot took
///   (any other energy moves the joint balance by the difference);
/// - without it the band above stays silent (nothing feeds it).
#[test]
fn the_strike_above_rings_the_band_with_the_contacts_energy() {
    for scheme in ["conservative-exact", "sav"] {
        let n = 9_600;
        let build = |strike_above: bool| {
            let extra = format!(
                "symmetry = \"strike-mirror\"\nband_above = true\nstrike_above = {strike_above}"
            );
            super::plate_closure::scene_with(scheme, 0.0, &extra).unwrap()
        };
        let (voice, _) = render(&build(true), n);
        let (plain, _) = render(&build(false), n);
        let x = voice.band_above().expect("band above on").energy();
        let e = voice.model().energy();
        let launched = voice.mallet().unwrap().energy().launched;
        let joint = voice.energy().balance();
        println!(
            "{scheme}: struck {:.4e} J of {launched:.3e} J launched, stored {:.3e} J, joint \
             balance {joint:.2e} J; without: struck {:.1e} J",
            x.struck,
            x.stored,
            plain.band_above().unwrap().energy().struck
        );
        assert!(x.struck > 1e-3 * launched, "{scheme}: {x:?}");
        assert!(x.balance().abs() <= 1e-12 * x.struck, "{x:?}");
        assert!(e.closure == 0.0, "the closure is off");
        assert!(
            joint.abs() < 1e-11 * launched,
            "{scheme}: joint balance {joint:e}"
        );
        let off = plain.band_above().unwrap().energy();
        assert!(off.struck == 0.0 && off.stored == 0.0, "{off:?}");
    }
}
