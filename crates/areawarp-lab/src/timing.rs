//! Per-thread CPU time, for timings on a shared machine.
//!
//! Wall-clock time counts the moments the thread waits for a core another
//! process holds; on a loaded machine that inflated per-sample costs 7× in
//! one run and not in the next. The thread's CPU time
//! (`CLOCK_THREAD_CPUTIME_ID`) counts only the time the thread ran, so it
//! moves far less with load (it still sees cache and memory contention,
//! hence the repeated, interleaved rounds of the studies that use it and
//! the minimum over rounds).

use std::time::Instant;

/// The calling thread's CPU time in nanoseconds (an arbitrary origin; take
/// differences). Falls back to a monotonic wall clock where the per-thread
/// clock is not available.
pub fn thread_cpu_ns() -> u64 {
    #[cfg(unix)]
    {
        let mut ts = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: `ts` is a valid, writable `timespec`; the call writes
        // only into it and reports failure by its return value.
        let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
        if rc == 0 {
            return ts.tv_sec as u64 * 1_000_000_000 + ts.tv_nsec as u64;
        }
    }
    wall_ns()
}

/// Nanoseconds of a process-wide monotonic clock (the fallback).
fn wall_ns() -> u64 {
    use std::sync::OnceLock;
    static ORIGIN: OnceLock<Instant> = OnceLock::new();
    ORIGIN.get_or_init(Instant::now).elapsed().as_nanos() as u64
}

/// Whether [`thread_cpu_ns`] measures CPU time here (else wall time).
pub fn is_cpu_time() -> bool {
    cfg!(unix)
}

/// Runs `f` and returns its result with the thread CPU time it took (ns).
pub fn cpu_timed<R>(f: impl FnOnce() -> R) -> (R, f64) {
    let t = thread_cpu_ns();
    let r = f();
    (r, thread_cpu_ns().saturating_sub(t) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cpu_time_advances_with_work_and_not_with_sleep() {
        let (_, busy) = cpu_timed(|| {
            let mut x = 0u64;
            for i in 0..3_000_000u64 {
                x = x.wrapping_mul(6364136223846793005).wrapping_add(i);
            }
            std::hint::black_box(x)
        });
        assert!(busy > 0.0);
        if is_cpu_time() {
            let (_, slept) = cpu_timed(|| std::thread::sleep(std::time::Duration::from_millis(30)));
            // 30 ms of sleep costs (almost) no CPU time.
            assert!(slept < 10e6, "{slept} ns of CPU time while sleeping");
        }
    }
}
