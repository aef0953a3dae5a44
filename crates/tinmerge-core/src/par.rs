//! Threads inside one call: a rayon pool for the pure-Rust parts of big
//! builds and merges, sized by a process-wide setting (the SQL layer sets it
//! from `tinmerge.threads` before each call; 1, the default here, runs
//! everything on the calling thread and never touches rayon).
//!
//! Rules the callers keep:
//! - work handed to the pool is plain Rust on borrowed data: no PostgreSQL
//!   call, no interrupt check (those stay on the calling thread, between
//!   batches: see [`map_batched`]);
//! - results are combined in input order, so an answer does not depend on
//!   the number of threads (the tests compare 1 and 2 threads bit for bit).
//!
//! The pool is built once per thread count and kept. Its threads are
//! started with every signal blocked, so the signals PostgreSQL sends a
//! backend (cancel, terminate, latch wake-ups) keep going to the backend's
//! own thread.
//!
//! ```
//! use tinmerge_core::tin::par;
//! let squares = par::map(&[1u64, 2, 3], |x| x * x);
//! assert_eq!(squares, vec![1, 4, 9]);
//! ```

use crate::interrupt::Interrupt;
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};
use std::sync::{Arc, Mutex};

use crate::error::TinError;

static THREADS: AtomicUsize = AtomicUsize::new(1);

/// Most threads a call may use.
pub const MAX_THREADS: usize = 64;

/// Set the number of threads calls use from now on (clamped to
/// `1..=MAX_THREADS`).
pub fn set_threads(n: usize) {
    THREADS.store(n.clamp(1, MAX_THREADS), Relaxed);
}

/// The number of threads calls use.
pub fn threads() -> usize {
    THREADS.load(Relaxed)
}

/// Cores this process may run on (the default of `tinmerge.threads`, read
/// by every backend when it loads the library): its CPU affinity mask, one
/// system call. `std::thread::available_parallelism` also reads the cgroup
/// CPU quota files, which made loading the library 85 us slower.
pub fn cores() -> usize {
    #[cfg(target_os = "linux")]
    {
        // SAFETY: a zeroed cpu_set_t is a valid empty set, and the kernel
        // writes at most size_of::<cpu_set_t>() bytes into it.
        let n = unsafe {
            let mut set: libc::cpu_set_t = std::mem::zeroed();
            if libc::sched_getaffinity(0, std::mem::size_of::<libc::cpu_set_t>(), &mut set) == 0 {
                libc::CPU_COUNT(&set)
            } else {
                0
            }
        };
        if n > 0 {
            return n as usize;
        }
    }
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

static POOL: Mutex<Option<(usize, Arc<rayon::ThreadPool>)>> = Mutex::new(None);

/// The pool for `n` threads (built on first use), or None when threads
/// cannot be started (the caller then runs serially).
fn pool(n: usize) -> Option<Arc<rayon::ThreadPool>> {
    let mut slot = POOL.lock().ok()?;
    if let Some((k, p)) = slot.as_ref()
        && *k == n
    {
        return Some(p.clone());
    }
    let p = Arc::new(with_signals_blocked(|| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .thread_name(|i| format!("tinmerge-{i}"))
            .build()
            .ok()
    })?);
    *slot = Some((n, p.clone()));
    Some(p)
}

/// Run `f` with every signal blocked on this thread (threads started inside
/// inherit the mask), then restore the mask.
#[cfg(unix)]
fn with_signals_blocked<R>(f: impl FnOnce() -> R) -> R {
    // SAFETY: sigset_t is plain data initialised by sigfillset/sigemptyset;
    // pthread_sigmask only reads `all` and writes `old`.
    unsafe {
        let mut all: libc::sigset_t = std::mem::zeroed();
        let mut old: libc::sigset_t = std::mem::zeroed();
        libc::sigfillset(&mut all);
        libc::sigemptyset(&mut old);
        let blocked = libc::pthread_sigmask(libc::SIG_BLOCK, &all, &mut old) == 0;
        let r = f();
        if blocked {
            libc::pthread_sigmask(libc::SIG_SETMASK, &old, std::ptr::null_mut());
        }
        r
    }
}

#[cfg(not(unix))]
fn with_signals_blocked<R>(f: impl FnOnce() -> R) -> R {
    f()
}

/// `f` over `items`, results in input order: on the pool when more than
/// one thread is set and there is more than one item, else in a loop.
pub fn map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync + Send) -> Vec<R> {
    let n = threads();
    if n > 1
        && items.len() > 1
        && let Some(p) = pool(n)
    {
        return p.install(|| items.par_iter().map(&f).collect());
    }
    items.iter().map(f).collect()
}

/// [`map`] in batches of a few items per thread, calling `interrupt` on the
/// calling thread before each batch and handing each batch's results, in
/// order, to `consume`. Items should be small pieces of work (a few
/// milliseconds each) so a cancel is seen within one batch.
pub fn map_batched<T: Sync, R: Send>(
    items: &[T],
    f: impl Fn(&T) -> R + Sync + Send,
    interrupt: &mut Interrupt<'_>,
    consume: &mut dyn FnMut(R) -> Result<(), TinError>,
) -> Result<(), TinError> {
    let per = 4 * threads();
    for batch in items.chunks(per) {
        interrupt()?;
        for r in map(batch, &f) {
            consume(r)?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn order_kept_with_threads() {
        set_threads(2);
        let v: Vec<u32> = (0..1000).collect();
        let out = map(&v, |x| x * 3);
        assert_eq!(out, v.iter().map(|x| x * 3).collect::<Vec<_>>());
        let mut got = Vec::new();
        let mut calls = 0;
        map_batched(
            &v,
            |x| x + 1,
            &mut || {
                calls += 1;
                Ok(())
            },
            &mut |r| {
                got.push(r);
                Ok(())
            },
        )
        .unwrap();
        assert_eq!(got, (1..=1000).collect::<Vec<_>>());
        assert_eq!(calls, 1000usize.div_ceil(8));
        set_threads(1);
    }

    #[test]
    fn interrupt_stops_between_batches() {
        let v: Vec<u32> = (0..100).collect();
        let mut seen = 0;
        let mut calls = 0;
        let r = map_batched(
            &v,
            |x| *x,
            &mut || {
                calls += 1;
                if calls == 3 {
                    Err(TinError::Interrupted)
                } else {
                    Ok(())
                }
            },
            &mut |_| {
                seen += 1;
                Ok(())
            },
        );
        assert!(matches!(r, Err(TinError::Interrupted)));
        // two whole batches (of 4 or 8 items: another test may set 2 threads)
        assert!(seen == 8 || seen == 16, "{seen}");
    }
}
