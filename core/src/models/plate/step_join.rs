//! Sharing one time step between two threads: the hook through which a plate's SAV step runs
//! the two halves of its coupling kernel ([`super::ModalCoupling::quartic_gradient_rows`]) at
//! once.
//!
//! The split is fixed by the tensor (its [`super::ModalCoupling::split_row`]), and the two
//! partial gradients are always added in the same order, so a render gives the same bits
//! whether the two halves run on one thread ([`Sequential`]) or on two.
//!
//! Threads: the model calls [`StepJoin::join`] from the thread that steps it; an
//! implementation may run `b` on another thread but must return only when both are done.

/// Runs the two jobs of one step and returns when both have finished.
pub trait StepJoin: Send + Sync {
    /// Runs `a` and `b` (in any order, possibly at once on two threads); returns after both.
    fn join(&self, a: &mut (dyn FnMut() + Send), b: &mut (dyn FnMut() + Send));
}

/// Both jobs on the calling thread, `a` then `b` (the reference the threaded joins are tested
/// against).
#[derive(Debug, Clone, Copy, Default)]
pub struct Sequential;

impl StepJoin for Sequential {
    fn join(&self, a: &mut (dyn FnMut() + Send), b: &mut (dyn FnMut() + Send)) {
        a();
        b();
    }
}
