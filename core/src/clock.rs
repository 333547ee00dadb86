//! CPU-time clocks of the calling thread and of the whole process (POSIX `clock_gettime` with
//! `CLOCK_THREAD_CPUTIME_ID` / `CLOCK_PROCESS_CPUTIME_ID`): the engine's telemetry, the
//! benchmarks, the examples and the reports of `noether play` measure with them, because wall
//! time on a shared machine counts other processes' time too.
//!
//! Threads: any, the audio thread included: a read is one system call (a vDSO call on Linux),
//! with no allocation, lock or I/O.

use std::time::Duration;

/// CPU time the calling thread has used so far, or `None` where the platform has no thread
/// clock (not Unix) or the call fails.
pub fn thread_cpu_time() -> Option<Duration> {
    #[cfg(unix)]
    return read(libc::CLOCK_THREAD_CPUTIME_ID);
    #[cfg(not(unix))]
    return None;
}

/// CPU time every thread of the process has used so far, or `None` where the platform has no
/// process clock (not Unix) or the call fails.
pub fn process_cpu_time() -> Option<Duration> {
    #[cfg(unix)]
    return read(libc::CLOCK_PROCESS_CPUTIME_ID);
    #[cfg(not(unix))]
    return None;
}

/// Reads `clock`.
#[cfg(unix)]
fn read(clock: libc::clockid_t) -> Option<Duration> {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec, and both clock ids exist on every supported
    // Unix (Linux since 2.6.12, macOS since 10.12); the call fails only for an invalid clock
    // or pointer, reported by its return value.
    let rc = unsafe { libc::clock_gettime(clock, &mut ts) };
    (rc == 0).then(|| Duration::new(ts.tv_sec as u64, ts.tv_nsec as u32))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both clocks advance while the thread works, and the thread's CPU time cannot exceed the
    /// process's (the process counts this thread too).
    #[test]
    #[cfg(unix)]
    fn clocks_advance_with_work() {
        let (t0, p0) = (thread_cpu_time().unwrap(), process_cpu_time().unwrap());
        let mut x = 0u64;
        let start = std::time::Instant::now();
        while start.elapsed() < Duration::from_millis(20) {
            x = std::hint::black_box(x.wrapping_mul(6364136223846793005).wrapping_add(1));
        }
        let (t1, p1) = (thread_cpu_time().unwrap(), process_cpu_time().unwrap());
        assert!(t1 > t0 && p1 > p0, "{t0:?} {t1:?} {p0:?} {p1:?}");
        assert!(t1 <= p1, "thread {t1:?} beyond process {p1:?}");
    }
}
