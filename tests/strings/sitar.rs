//! The sitar's taraf (`noether::models::sitar`): after a 1 s note on the played string at a
//! taraf string's pitch, that string holds far more energy than after a note a semitone away;
//! and the thaat table gives the taraf's tuning.

use noether::models::sitar::{Sitar, SitarSpec, Thaat};

/// Energy (J) of taraf string `k` (1-based among the strings) after `seconds` of the note.
fn taraf_energy_after(spec: &SitarSpec, k: usize, seconds: f64) -> (f64, Sitar) {
    let mut sitar = Sitar::build(spec).unwrap();
    let steps = (seconds * spec.sim_rate) as usize;
    for _ in 0..steps {
        sitar.step();
    }
    (sitar.network().string_energy(k).total(), sitar)
}

/// Sympathy (Bilawal taraf on Sa = 277.18 Hz, 11 strings): the played string sounds Ga
/// (346.5 Hz, taraf string 3) for 1 s, then a semitone above; taraf string 3 holds at least
/// 100 times more energy after the note at its pitch (measured 875 times, docs/models.md). The
/// network's own tests show that nothing rings on a bridge that does not move.
#[test]
fn a_taraf_string_rings_with_its_note_and_not_a_semitone_away() {
    let sa = 277.18;
    let ga = sa * 5.0 / 4.0;
    let spec = SitarSpec::at(sa, ga);
    assert_eq!(spec.targets()[3], ga, "taraf string 3 is Ga");
    let (tuned, sitar) = taraf_energy_after(&spec, 3, 1.0);
    let off_spec = SitarSpec::at(sa, ga * 2f64.powf(1.0 / 12.0));
    let (off, _) = taraf_energy_after(&off_spec, 3, 1.0);
    let stats = sitar.network().stats();
    eprintln!(
        "taraf Ga after 1 s: {tuned:.3e} J at its pitch, {off:.3e} J a semitone above (ratio {:.0}); \
         bridge Newton mean {:.2}, cap hits {}",
        tuned / off,
        stats.iterations as f64 / stats.steps as f64,
        stats.cap_hits
    );
    assert!(tuned > 100.0 * off, "tuned {tuned:e}, semitone {off:e}");
    assert_eq!(stats.cap_hits, 0);
}

/// The thaat table: Bilawal is the just major scale; Todi's degrees; 13 taraf strings run into
/// the next octave.
#[test]
fn thaats_give_the_taraf_tuning() {
    assert_eq!(
        Thaat::Bilawal.degrees(),
        [
            1.0,
            9.0 / 8.0,
            5.0 / 4.0,
            4.0 / 3.0,
            3.0 / 2.0,
            5.0 / 3.0,
            15.0 / 8.0
        ]
    );
    assert_eq!(
        Thaat::Todi.degrees(),
        [
            1.0,
            16.0 / 15.0,
            6.0 / 5.0,
            45.0 / 32.0,
            3.0 / 2.0,
            8.0 / 5.0,
            15.0 / 8.0
        ]
    );
    let t = Thaat::Kafi.taraf(13);
    assert_eq!(t.len(), 13);
    assert_eq!(t[7], 2.0);
    assert_eq!(t[12], 2.0 * 5.0 / 3.0); // Dha of the next octave
    let mut spec = SitarSpec::at(277.18, 346.5);
    spec.taraf = 14;
    assert_eq!(spec.validate().unwrap_err().field, "sitar.taraf");
}
