//! Stability at the extremes: every model and scheme on main swept over extreme
//! parameters (see `noether::stress` for the grids). Each case: no NaN/Inf, no panic (caught
//! and counted), conservative schemes close their power balance to
//! `noether::stress::ENERGY_TOLERANCE` (1e-8 relative to the largest energy of the run, see its
//! doc for why; the oscillators to a tighter per-family `c ε n`, see `noether::stress::oscillators`), and conditionally stable settings are refused at construction with a
//! `ParamError` naming field, value and range (a refusal where the case does not expect one is
//! a failure). Prints the summary table; fails on any failure. The longer, denser sweep is
//! `noether stress`.

use noether::stress::{self, Density, Status};

fn sweep(cases: Vec<stress::Case>, what: &str) {
    noether_testkit::env::test_cache_dir();
    let start = std::time::Instant::now();
    let (outcomes, summary) = stress::run(cases, |_, _| {});
    eprintln!(
        "{what}: {} cases in {:.1} s\n{}",
        outcomes.len(),
        start.elapsed().as_secs_f64(),
        summary.table()
    );
    for o in &outcomes {
        match &o.status {
            Status::Refused(why) => {
                eprintln!("refused (expected) [{}] {}: {why}", o.family, o.label)
            }
            Status::Diverged(why) => {
                eprintln!("diverged (detected) [{}] {}: {why}", o.family, o.label)
            }
            _ => {}
        }
    }
    assert!(!outcomes.is_empty());
    assert_eq!(summary.failure_count(), 0, "{}", summary.table());
}

#[test]
fn oscillators_at_the_extremes() {
    sweep(stress::oscillators::cases(Density::Quick), "oscillators");
}

#[test]
fn plates_at_the_extremes() {
    sweep(stress::plate::cases(Density::Quick), "plates");
}

#[test]
fn strings_at_the_extremes() {
    sweep(stress::string::cases(Density::Quick), "strings");
}
