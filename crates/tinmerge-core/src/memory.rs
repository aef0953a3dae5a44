//! Heap accounting: a counting wrapper around the system allocator, so the
//! SQL layer can bound the memory one call uses (`tinmerge.max_memory`) and
//! tests can measure the peak memory of a build or a merge.
//!
//! Every Rust allocation of the process goes through [`Counting`]
//! (installed as the global allocator by the extension's crate root, and by
//! any test binary that measures); the counters are
//! two relaxed atomics, a few nanoseconds per allocation. PostgreSQL's own
//! `palloc` memory is not counted.
//!
//! The estimates a request is checked against *before* it allocates live
//! next to the algorithm they estimate (`build::build_bytes`,
//! `layout::decode_bytes`, `io::raster::raster_bytes`,
//! `merge::overlay::overlay_bytes`, `render::svg::svg_bytes`,
//! `render::gltf::glb_bytes`, `Tin::heap_bytes`); `tests/memory.rs` measures
//! the real peaks on the DEM and checks each estimate is an upper bound
//! (build, decode, raster) or, for the overlay whose output size depends on
//! how many edges cross, a lower bound that the running check completes.
//!
//! ```
//! use tinmerge_core::tin::memory;
//!
//! #[global_allocator]
//! static ALLOCATOR: memory::Counting = memory::Counting;
//!
//! fn main() {
//!     let before = memory::live();
//!     let v = std::hint::black_box(vec![1u8; 1 << 20]);
//!     assert!(memory::live() >= before + (1 << 20));
//!     drop(v);
//! }
//! ```

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicIsize, AtomicUsize, Ordering::Relaxed};

/// The system allocator, counting live bytes and their peak.
pub struct Counting;

/// Live bytes as the threads last reported them (a thread frees what
/// another allocated, so one thread's report can be negative for a while).
static LIVE: AtomicIsize = AtomicIsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

/// Bytes a thread allocates or frees before it reports them to the shared
/// counters: two threads updating the same two atomics on every allocation
/// made a build on 2 threads slower than on 1 (each parent of a lattice
/// build allocates a few small buffers). The counts are therefore exact to
/// within this much per thread.
pub const SLACK: isize = 64 * 1024;

thread_local! {
    /// This thread's bytes not yet reported.
    static UNREPORTED: Cell<isize> = const { Cell::new(0) };
}

#[inline]
fn moved(n: isize) {
    // a thread being torn down has no slot left: it reports at once
    let report = UNREPORTED
        .try_with(|u| {
            let v = u.get() + n;
            if v.abs() < SLACK {
                u.set(v);
                0
            } else {
                u.set(0);
                v
            }
        })
        .unwrap_or(n);
    if report != 0 {
        let now = LIVE.fetch_add(report, Relaxed) + report;
        if report > 0 {
            PEAK.fetch_max(now.max(0) as usize, Relaxed);
        }
    }
}

#[inline]
fn grew(n: usize) {
    moved(n as isize);
}

#[inline]
fn shrank(n: usize) {
    moved(-(n as isize));
}

// SAFETY: every call is forwarded unchanged to `System`; the counters are
// only updated when the system allocator succeeded.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's arguments, under GlobalAlloc's contract.
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's arguments, under GlobalAlloc's contract.
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: the caller's arguments, under GlobalAlloc's contract.
        unsafe { System.dealloc(ptr, layout) };
        shrank(layout.size());
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: the caller's arguments, under GlobalAlloc's contract.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            if new_size >= layout.size() {
                grew(new_size - layout.size());
            } else {
                shrank(layout.size() - new_size);
            }
        }
        p
    }
}

/// Bytes of Rust heap live in this process now (to within [`SLACK`] a
/// thread).
pub fn live() -> usize {
    LIVE.load(Relaxed).max(0) as usize
}

/// Highest [`live`] since the last [`reset_peak`].
pub fn peak() -> usize {
    PEAK.load(Relaxed)
}

/// This process's private resident memory in bytes (resident minus shared
/// pages, `/proc/self/statm`): the heap with what the allocator holds
/// beside it, without the shared buffers and files a PostgreSQL backend
/// maps. None where there is no `/proc`.
pub fn private_resident() -> Option<usize> {
    let s = std::fs::read_to_string("/proc/self/statm").ok()?;
    let mut f = s.split_ascii_whitespace().skip(1);
    let resident: usize = f.next()?.parse().ok()?;
    let shared: usize = f.next()?.parse().ok()?;
    // SAFETY: sysconf reads a constant of the system.
    let page = unsafe { libc::sysconf(libc::_SC_PAGESIZE) };
    let page = usize::try_from(page).ok().filter(|&p| p > 0)?;
    Some(resident.saturating_sub(shared).saturating_mul(page))
}

/// Start measuring a new peak from the current [`live`].
pub fn reset_peak() {
    PEAK.store(live(), Relaxed);
}
