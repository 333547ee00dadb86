//! The string model's real-time methods (`set_contact_scheme`, `pluck`, `strike`, `reset`,
//! `process`, `energy`) must not allocate, under both contact schemes (Newton and quadratised): a counting global allocator (this test binary only) counts allocations made
//! by the current thread while armed. Fails on any allocation, so it cannot pass vacuously
//! (the arming is checked with a deliberate `Vec` allocation first).

use noether::models::string::{
    ContactLaw, ContactScheme, Losses, Obstacle, OutputChannel, Quantity, Readout, SitarBridge,
    StiffString, StrikeForce, StringConfig, StringParams, TrianglePluck, ValetteLosses,
};
use noether::render::source::RenderSource;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;

static ALLOCS: AtomicUsize = AtomicUsize::new(0);
thread_local! {
    static ARMED: Cell<bool> = const { Cell::new(false) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if ARMED.with(|a| a.get()) {
            ALLOCS.fetch_add(1, Ordering::SeqCst);
        }
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if ARMED.with(|a| a.get()) {
            ALLOCS.fetch_add(1, Ordering::SeqCst);
        }
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn counted(f: impl FnOnce()) -> usize {
    let before = ALLOCS.load(Ordering::SeqCst);
    ARMED.with(|a| a.set(true));
    f();
    ARMED.with(|a| a.set(false));
    ALLOCS.load(Ordering::SeqCst) - before
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
        obstacle: Obstacle::Sitar(SitarBridge {
            position: 0.0,
            curvature: 0.2,
            height: 0.0,
            extent: 0.02,
        }),
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
