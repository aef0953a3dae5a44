//! `tinmerge.max_memory`: the most memory one call may use, in MB (-1: no
//! limit). Requests whose size is known up front (a build from N samples,
//! decoding a stored value, reading a raster band, an overlay's least
//! output) are refused before they allocate; the rest (output that grows
//! with the data, such as an overlay's crossings) is checked at every
//! interrupt check, by the Rust heap and, for large calls, by the
//! backend's private resident memory ([`check`]). Decoded values kept by
//! the per-backend cache are bounded by `tinmerge.cache_size` instead and
//! do not count.

use pgrx::prelude::*;
use pgrx::{GucContext, GucFlags, GucRegistry, GucSetting};

use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};

use super::errors::raise;
use tinmerge_core::tin::{memory, TinError};

/// `tinmerge.max_memory` in MB.
pub static MAX_MEMORY_MB: GucSetting<i32> = GucSetting::<i32>::new(1024);

pub fn define_guc() {
    GucRegistry::define_int_guc(
        c"tinmerge.max_memory",
        c"Most memory (MB) one tinmerge call may use for its work; -1 means no limit.",
        c"A build, merge or decode that would need more raises an ERROR (SQLSTATE 53400) before allocating, or as soon as its growing output passes the limit or the backend's private resident memory grows past seven eighths of it. Decoded values in the cache are bounded by tinmerge.cache_size instead.",
        &MAX_MEMORY_MB,
        -1,
        i32::MAX,
        GucContext::Userset,
        GucFlags::UNIT_MB,
    );
}

const MB: usize = 1024 * 1024;

/// The limit in bytes, or None when unlimited.
pub fn limit() -> Option<usize> {
    let mb = MAX_MEMORY_MB.get();
    (mb >= 0).then(|| (mb as usize).saturating_mul(MB))
}

/// Bytes of decoded values the backend cache holds (`cache` reports them
/// with [`set_cached`]; they are bounded by `tinmerge.cache_size` instead).
static CACHED: AtomicUsize = AtomicUsize::new(0);
/// Bytes of subtree sums the cache holds ([`set_cached_sums`]).
static CACHED_SUMS: AtomicUsize = AtomicUsize::new(0);

/// Called by the cache whenever what it holds changes.
pub fn set_cached(bytes: usize) {
    CACHED.store(bytes, Relaxed);
}

/// Called by the cache whenever the subtree sums it holds change.
pub fn set_cached_sums(bytes: usize) {
    CACHED_SUMS.store(bytes, Relaxed);
}

/// Heap in use for work: everything counted minus the cached values.
pub fn working() -> usize {
    memory::live()
        .saturating_sub(CACHED.load(Relaxed))
        .saturating_sub(CACHED_SUMS.load(Relaxed))
}

fn mb(bytes: usize) -> usize {
    bytes.div_ceil(MB)
}

/// Raise 53400 unless `bytes` more fit under `tinmerge.max_memory`.
/// `what` names the request ("tin_from_raster: building 1,900,000 samples
/// at 5 levels").
pub fn reserve(bytes: usize, what: impl FnOnce() -> String) {
    let Some(limit) = limit() else { return };
    let need = working().saturating_add(bytes);
    if need > limit {
        raise(
            PgSqlErrorCode::ERRCODE_CONFIGURATION_LIMIT_EXCEEDED,
            format!(
                "{} needs about {} MB, more than tinmerge.max_memory ({} MB) allows; raise it, e.g. SET tinmerge.max_memory = '{}MB'",
                what(),
                mb(need),
                mb(limit),
                mb(need).next_multiple_of(64)
            ),
        );
    }
}

/// Private resident bytes of the backend that are not the current call's
/// work, taken when the work's heap first passes a quarter of the limit
/// (usize::MAX: not taken since the heap was last below it).
static BESIDE: AtomicUsize = AtomicUsize::new(usize::MAX);

/// The running check (from every interrupt check): Err once the work of
/// this call has passed the limit. The backend holds more than the counted
/// heap: what the allocator keeps of freed memory (a white-noise build's
/// resident memory was up to 1.66x its live heap), PostgreSQL's own memory,
/// and what is allocated between two checks. So once the heap is past a
/// quarter of the limit, the check also reads the process's private
/// resident memory and stops the call when its growth (past what the
/// backend held beside the work, [`BESIDE`]) passes seven eighths of the
/// limit: the last eighth is for what grows between two checks.
pub fn check() -> Result<(), TinError> {
    let Some(limit) = limit() else { return Ok(()) };
    let used = working();
    let raise_to = |b: usize| mb(b.saturating_mul(2)).next_multiple_of(64);
    if used > limit {
        return Err(TinError::MemoryLimit(format!(
            "this call has used {} MB, more than tinmerge.max_memory ({} MB) allows; raise it (SET tinmerge.max_memory = '{}MB') or use a coarser level",
            mb(used),
            mb(limit),
            raise_to(used)
        )));
    }
    if used <= limit / 4 {
        BESIDE.store(usize::MAX, Relaxed);
        return Ok(());
    }
    let Some(resident) = memory::private_resident() else {
        return Ok(());
    };
    // what the backend held beside this work when the heap first passed a
    // quarter of the limit (PostgreSQL's own memory, the cached values):
    // the call's part is what grew past it
    let base = match BESIDE.load(Relaxed) {
        usize::MAX => {
            let b = resident.saturating_sub(used);
            BESIDE.store(b, Relaxed);
            b
        }
        b => b,
    };
    let grown = resident.saturating_sub(base);
    if grown > limit / 8 * 7 {
        return Err(TinError::MemoryLimit(format!(
            "this call has used {} MB of heap and grown the backend by {} MB (private resident memory), past seven eighths of tinmerge.max_memory ({} MB); raise it (SET tinmerge.max_memory = '{}MB') or use a coarser level",
            mb(used),
            mb(grown),
            mb(limit),
            raise_to(grown)
        )));
    }
    Ok(())
}

/// The Rust heap this backend has had live at its peak since the last reset,
/// in bytes, and the heap live now: what the large-terrain benchmark reports
/// as a build's peak memory (the counting allocator of
/// `tinmerge_core::tin::memory`; PostgreSQL's own `palloc` memory is not in
/// it). `reset => true` first starts a new peak from what is live now. Only
/// in builds with the `bench` feature (`make bench` installs one).
#[cfg(feature = "bench")]
#[pg_extern(volatile, parallel_unsafe)]
fn _tin_heap_peak(reset: bool) -> TableIterator<'static, (name!(peak, i64), name!(live, i64))> {
    if reset {
        memory::reset_peak();
    }
    let as_i64 = |b: usize| i64::try_from(b).unwrap_or(i64::MAX);
    TableIterator::once((as_i64(memory::peak()), as_i64(memory::live())))
}

#[cfg(feature = "bench")]
extension_sql!(
    r#"
COMMENT ON FUNCTION _tin_heap_peak(boolean) IS 'Internal (benchmark builds only): the peak and the live Rust heap of this backend in bytes since the last reset (reset => true starts a new peak).';
"#,
    name = "tin_heap_peak_comment",
    requires = [_tin_heap_peak]
);
