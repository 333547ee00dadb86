//! The string model's real-time methods (`set_contact_scheme`, `pluck`, `strike`, `reset`,
//! `process`, `energy`) must not allocate, under both contact schemes (Newton and quadratised):
//! the test binary's global allocator (`noether_testkit::alloc::Guard`) counts allocations made
//! by the current thread. Fails on any allocation, so it cannot pass vacuously (the counter is
//! checked with a deliberate `Vec` allocation first).

use noether::models::string::{
    ContactLaw, ContactScheme, Losses, Obstacle, OutputChannel, Quantity, Readout, StiffString,
    StrikeForce, StringConfig, StringParams, TrianglePluck, ValetteLosses,
};
use noether::render::source::RenderSource;

/// Allocations made by the current thread while `f` runs (the binary's global allocator is
/// `noether_testkit::alloc::Guard`).
fn counted(f: impl FnOnce()) -> usize {
    noether_testkit::alloc::count_allocations(f).1 as usize
}

#[test]
fn real_time_methods_do_not_allocate() {
    assert!(counted(|| drop(std::hint::black_box(vec![1u8; 16]))) > 0);
    for scheme in ContactScheme::ALL {
        check_scheme(scheme);
    }
}

fn check_scheme(scheme: ContactScheme) {
    let mut s = StiffString::new(&StringConfig {
        params: StringParams::lecture_guitar(256, 48_000.0),
        losses: Losses::Valette(ValetteLosses::default()),
        obstacle: Obstacle::seed_sitar(),
        contact: ContactLaw::lecture(),
        outputs: vec![
            OutputChannel::Pickup {
                position: 0.37,
                quantity: Quantity::Displacement,
                readout: Readout::Grid,
            },
            OutputChannel::Pickup {
                position: 0.2,
                quantity: Quantity::Velocity,
                readout: Readout::Modal,
            },
            OutputChannel::ObstacleForce,
        ],
    })
    .unwrap();
    let mut out = vec![vec![0.0; 512]; 3];
    let mut touched = 0;
    let n = counted(|| {
        s.set_contact_scheme(scheme);
        s.pluck(&TrianglePluck {
            position: 0.3,
            amplitude: 1e-3,
        })
        .unwrap();
        for _ in 0..20 {
            s.process(&mut out, 512);
        }
        s.strike(&StrikeForce {
            position: 0.25,
            duration: 2e-3,
            peak: -3.0,
        })
        .unwrap();
        for _ in 0..4 {
            s.process(&mut out, 512);
        }
        std::hint::black_box(s.energy());
        touched = s.contact_stats().contact_steps;
        s.reset();
        s.process(&mut out, 512);
    });
    assert!(
        s.contact_stats().contact_steps == 0,
        "reset clears the counters"
    );
    assert!(touched > 0, "the string never touched its bridge");
    assert_eq!(s.contact_scheme(), scheme);
    assert_eq!(
        n,
        0,
        "allocations on the real-time path ({})",
        scheme.name()
    );
}
