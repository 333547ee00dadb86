//! The bounded real-time soak (`noether::soak`, issue 7): a seeded random host drives the
//! engine for `NOETHER_SOAK_SECONDS` of wall time (default 30; the whole test stays under
//! about a minute on the loaded two-core machine) with automation of every parameter each
//! block, note storms, rebuild bursts (model, modes, rate, scheme, polyphony) and host rate
//! changes from 22.05 to 192 kHz with blocks of 1 to 8192 samples.
//!
//! The global allocator of this test binary aborts on any allocation inside
//! `assert_no_alloc` (debug assertions are on in the test profile), which wraps every
//! `process_events` call. The soak itself fails on non-finite output, output above
//! `soak::LEVEL_BOUND` times the gain (its derivation is in its doc), a rebuild that neither arrives nor is refused within
//! 30 s, or a failed activation. The block time over its real-time duration is printed, not
//! asserted (the machine is shared). The longer run: `cargo run --release --example soak`.

use assert_no_alloc::{assert_no_alloc, AllocDisabler};
use noether::soak::{self, SoakConfig};
use std::time::Duration;

#[global_allocator]
static A: AllocDisabler = AllocDisabler;

#[test]
fn soak_under_load() {
    let seconds = std::env::var("NOETHER_SOAK_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(30.0);
    let cfg = SoakConfig::quick(0x5eed_0007, Duration::from_secs_f64(seconds));
    let s = soak::run(&cfg, |e, ev, l, r| {
        assert_no_alloc(|| e.process_events(ev, l, r))
    })
    .unwrap_or_else(|f| panic!("{f}"));
    println!("{s}");
    // Every request resolved: the loop ends only between bursts.
    assert_eq!(
        s.rebuilds_requested,
        s.rebuilds_arrived + s.rebuilds_refused
    );
    // The run exercised what it claims (a 30 s run makes dozens of each).
    assert!(s.rebuilds_arrived >= 3, "{s}");
    assert!(s.rate_changes >= 2, "{s}");
    assert!(s.storm.note_ons >= 1000, "{s}");
}
