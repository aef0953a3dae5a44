//! Heap accounting: a counting wrapper around the system allocator, so the
//! SQL layer can bound the memory one call uses (`tinmerge.max_memory`) and
//! tests can measure the peak memory of a build or a merge.
//!
//! Every Rust allocation of the process goes through [`Counting`]
//! (installed as the global allocator at the crate root); the counters are
//! two relaxed atomics, a few nanoseconds per allocation. PostgreSQL's own
//! `palloc` memory is not counted.
//!
//! The estimates ([`build_bytes`], [`decode_bytes`], [`overlay_bytes`],
//! [`raster_bytes`]) are what a request is checked against *before* it
//! allocates; `tests/memory.rs` measures the real peaks on the DEM and checks
//! each estimate is an upper bound (build, decode, raster) or, for the
//! overlay whose output size depends on how many edges cross, a lower bound
//! that the running check completes.
//!
//! ```
//! use tinmerge::tin::memory;
//! let before = memory::live();
//! let v = std::hint::black_box(vec![1u8; 1 << 20]);
//! assert!(memory::live() >= before + (1 << 20));
//! drop(v);
//! ```

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};

/// The system allocator, counting live bytes and their peak.
pub struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

#[inline]
fn grew(n: usize) {
    let now = LIVE.fetch_add(n, Relaxed) + n;
    PEAK.fetch_max(now, Relaxed);
}

#[inline]
fn shrank(n: usize) {
    LIVE.fetch_sub(n, Relaxed);
}

// SAFETY: every call is forwarded unchanged to `System`; the counters are
// only updated when the system allocator succeeded.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) };
        shrank(layout.size());
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
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

/// Bytes of Rust heap live in this process now.
pub fn live() -> usize {
    LIVE.load(Relaxed)
}

/// Highest [`live`] since the last [`reset_peak`].
pub fn peak() -> usize {
    PEAK.load(Relaxed)
}

/// Start measuring a new peak from the current [`live`].
pub fn reset_peak() {
    PEAK.store(LIVE.load(Relaxed), Relaxed);
}

/// Upper bound of the heap a build from `samples` points with `levels`
/// levels uses at its peak, input samples included (measured on the DEM
/// with `tests/memory.rs`: 255-350 bytes per sample at a 2 m tolerance, 1-6
/// levels, up to 560 when nearly every sample becomes a vertex).
pub fn build_bytes(samples: usize, levels: usize) -> usize {
    samples
        .saturating_mul(512 + 64 * levels)
        .saturating_add(1 << 20)
}

/// Upper bound of the heap used to decode a stored value of `len` bytes
/// (the decoded arrays and the grid index are about the stored size).
pub fn decode_bytes(len: usize) -> usize {
    len.saturating_mul(2).saturating_add(1 << 16)
}

/// Heap needed to read one band of a `width` x `height` raster (values as
/// f64) and hand its pixels to triangles.
pub fn raster_bytes(width: usize, height: usize) -> usize {
    width
        .saturating_mul(height)
        .saturating_mul(9)
        .saturating_add(1 << 16)
}

/// Least heap an overlay of `tris_a` and `tris_b` triangles needs: the
/// output has at least one triangle per input triangle met, each with its
/// vertices, labels and heights. Crossing edges make it larger; that part is
/// bounded while the overlay runs, not here.
pub fn overlay_bytes(tris_a: usize, tris_b: usize) -> usize {
    tris_a.saturating_add(tris_b).saturating_mul(96)
}

/// Working memory of an SVG picture of `triangles` triangles (the text,
/// about 100 bytes per triangle, plus colours).
pub fn svg_bytes(triangles: usize) -> usize {
    triangles.saturating_mul(112).saturating_add(1 << 16)
}

/// Working memory of a glTF mesh: per vertex the f32 attributes, the f64
/// normal sums and the copies into the binary chunk and the output; per
/// triangle the indices, twice.
pub fn glb_bytes(vertices: usize, triangles: usize) -> usize {
    vertices
        .saturating_mul(136)
        .saturating_add(triangles.saturating_mul(36))
        .saturating_add(1 << 16)
}
