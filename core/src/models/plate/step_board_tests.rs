//! Tests of the half-step protocol (`step_board.rs`): a toy coupling, helpers held or placed
//! at chosen points.

use super::*;
use std::cell::Cell;
use std::sync::atomic::AtomicBool;

thread_local! {
    static SLOW_HERE: Cell<bool> = const { Cell::new(false) };
}
/// Lets the kernels held on `SLOW_HERE` threads finish.
static RELEASE: AtomicBool = AtomicBool::new(false);

/// A coupling whose row-range kernel is a cheap deterministic function of its inputs
/// (`eta_l = (l + 1) Σ q`, `g_s = w_0 q_s Σ_rows (l + 1)`) and sleeps 50 ms on threads that
/// set `SLOW_HERE` (a pre-empted helper).
struct Toy;

impl ModalCoupling for Toy {
    fn n_phi(&self) -> usize {
        3
    }
    fn n_psi(&self) -> usize {
        4
    }
    fn contract_eta(&self, _: &[f64], _: &[f64], out: &mut [f64]) {
        out.fill(0.0);
    }
    fn apply_force(&self, _: &[f64], _: &[f64], out: &mut [f64]) {
        out.fill(0.0);
    }
    fn coupling_matrix(&self, _: &[f64], g: &mut [f64]) {
        g.fill(0.0);
    }
    fn quartic_gradient_rows(
        &self,
        rows: Range<usize>,
        q: &[f64],
        w: &[f64],
        eta: &mut [f64],
        grad: &mut [f64],
        _scratch: &mut [f64],
    ) -> bool {
        if SLOW_HERE.with(|s| s.get()) {
            while !RELEASE.load(Ordering::Acquire) {
                std::thread::sleep(Duration::from_millis(1));
            }
        }
        let sum: f64 = q.iter().sum();
        let weight: f64 = rows.clone().map(|l| (l + 1) as f64).sum();
        for (e, l) in eta.iter_mut().zip(rows) {
            *e = (l + 1) as f64 * sum;
        }
        for (g, &x) in grad.iter_mut().zip(q) {
            *g = w[0] * x * weight;
        }
        true
    }
}

fn job() -> Box<HalfJob> {
    HalfJob::new(&Arc::new(Toy), 2..4, 3, 4, 8)
}

/// The half computed here, for comparison: `(eta, g)`.
fn reference(job: &HalfJob, q: &[f64], w: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let (mut eta, mut g, mut y) = (vec![0.0; 2], vec![0.0; 3], vec![0.0; 8]);
    job.run_here(q, w, None, &mut eta, &mut g, &mut y);
    (eta, g)
}

/// Spins until the job leaves `POSTED` (a helper took it), at most 10 s.
fn until_taken(job: &HalfJob) {
    let t = Instant::now();
    while job.state.load(Ordering::Acquire) == POSTED && t.elapsed() < Duration::from_secs(10) {
        std::hint::spin_loop();
    }
}

/// A closed board takes no offer; an open one with no helper gives the half back to the
/// owner, who computes it (same result).
#[test]
fn without_a_helper_the_owner_runs_the_half() {
    let (board, job) = (StepBoard::new(), job());
    let (q, w) = ([1.0, 2.0, 3.0], [0.5, 0.0, 0.0, 0.0]);
    assert!(!job.offer(&board, &q, &w, None), "closed board");
    board.set_open(true);
    assert!(job.offer(&board, &q, &w, None));
    let (mut eta, mut g, mut y) = (vec![0.0; 2], vec![0.0; 3], vec![0.0; 8]);
    let out = job.finish(
        &board,
        Duration::ZERO,
        &q,
        &w,
        None,
        &mut eta,
        &mut g,
        &mut y,
    );
    assert_eq!(out, HalfOutcome::Own);
    assert_eq!((eta, g), reference(&job, &q, &w));
    assert_eq!(
        board.slot.load(Ordering::Relaxed),
        std::ptr::null_mut(),
        "withdrawn"
    );
}

/// A helper takes each posted half and its result is the owner's, bit for bit; the board
/// holds one job at a time.
#[test]
fn a_helper_runs_the_half_with_the_same_bits() {
    let board = Arc::new(StepBoard::new());
    board.set_open(true);
    let (job, other) = (job(), job());
    let stop = Arc::new(AtomicBool::new(false));
    let helper = {
        let (board, stop) = (board.clone(), stop.clone());
        std::thread::spawn(move || {
            while !stop.load(Ordering::Relaxed) {
                // SAFETY: both jobs outlive the helper (joined below).
                if !unsafe { board.help() } {
                    std::hint::spin_loop();
                }
            }
        })
    };
    for k in 0..200 {
        let q = [k as f64, 0.25 * k as f64, -1.0];
        let w = [1.0 + k as f64, 0.0, 0.0, 0.0];
        assert!(job.offer(&board, &q, &w, None));
        assert!(
            !other.offer(&board, &q, &w, None),
            "one job on the board at a time"
        );
        until_taken(&job);
        let (mut eta, mut g, mut y) = (vec![0.0; 2], vec![0.0; 3], vec![0.0; 8]);
        let out = job.finish(
            &board,
            Duration::from_secs(10),
            &q,
            &w,
            None,
            &mut eta,
            &mut g,
            &mut y,
        );
        assert_eq!(out, HalfOutcome::Shared, "step {k}");
        assert_eq!((eta, g), reference(&job, &q, &w), "step {k}");
    }
    assert_eq!(board.shared_halves(), 200);
    stop.store(true, Ordering::Relaxed);
    helper.join().unwrap();
}

/// A helper pre-empted in the middle of a half (held until released): the owner returns
/// after its bounded wait with the half computed itself (same result) while the helper
/// still holds the job, offers nothing until the helper is done, then offers again.
#[test]
fn a_late_helper_is_not_waited_for() {
    let board = Arc::new(StepBoard::new());
    board.set_open(true);
    let job = job();
    let (q, w) = ([1.0, -2.0, 0.5], [3.0, 0.0, 0.0, 0.0]);
    assert!(job.offer(&board, &q, &w, None));
    let job_ptr = &*job as *const HalfJob as usize;
    let helper = {
        let board = board.clone();
        std::thread::spawn(move || {
            SLOW_HERE.with(|s| s.set(true));
            // SAFETY: the job outlives the helper (joined below).
            while !unsafe { board.help() } {
                std::hint::spin_loop();
            }
            job_ptr
        })
    };
    until_taken(&job);
    let (mut eta, mut g, mut y) = (vec![0.0; 2], vec![0.0; 3], vec![0.0; 8]);
    let out = job.finish(
        &board,
        Duration::ZERO,
        &q,
        &w,
        None,
        &mut eta,
        &mut g,
        &mut y,
    );
    assert_eq!(out, HalfOutcome::Late);
    assert!(job.is_out(), "the owner did not wait for the held helper");
    assert_eq!((eta, g), reference(&job, &q, &w));
    assert_eq!(board.late_halves(), 1);
    assert!(!job.offer(&board, &q, &w, None), "the job is still out");
    RELEASE.store(true, Ordering::Release);
    helper.join().unwrap();
    assert!(!job.is_out());
    assert!(
        job.offer(&board, &q, &w, None),
        "the job is the owner's again"
    );
}

/// A helper that still holds a job's pointer from an earlier step (it reaches the job,
/// not the board) may take the job between the owner's post and its finding the board
/// held by another job. The owner must then wait for that half as for any taken offer,
/// not reset the job to rest under the helper. The helper's take is placed exactly there
/// (`STALE_TAKE`, on the owner's thread).
#[test]
fn a_helper_with_a_stale_pointer_is_waited_for() {
    let board = StepBoard::new();
    board.set_open(true);
    let (job, blocker) = (job(), job());
    let (q, w) = ([1.0, 2.0, 3.0], [0.5, 0.0, 0.0, 0.0]);
    assert!(
        blocker.offer(&board, &q, &w, None),
        "the board is held by another job"
    );
    STALE_TAKE.with(|s| s.set(true));
    let offered = job.offer(&board, &q, &w, None);
    STALE_TAKE.with(|s| s.set(false));
    assert!(offered, "a taken job must be finished, not given up");
    let (mut eta, mut g, mut y) = (vec![0.0; 2], vec![0.0; 3], vec![0.0; 8]);
    let out = job.finish(
        &board,
        Duration::ZERO,
        &q,
        &w,
        None,
        &mut eta,
        &mut g,
        &mut y,
    );
    assert_eq!(out, HalfOutcome::Shared);
    assert_eq!((eta, g), reference(&job, &q, &w));
}
