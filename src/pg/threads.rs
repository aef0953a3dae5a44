//! `tinmerge.threads`: how many threads one call may use for its pure-Rust
//! work (raster statistics, builds); default one per core, 1 disables.
//! The threads never call into PostgreSQL; interrupts are checked on the
//! backend's thread between batches (`tin::par`).

use pgrx::pg_sys;
use std::sync::atomic::{AtomicI32, Ordering::Relaxed};

use tinmerge_core::tin::par;

/// The setting's storage, written by PostgreSQL's GUC machinery on this
/// backend's thread (an atomic only to have a stable `*mut i32`).
static THREADS: AtomicI32 = AtomicI32::new(1);

pub fn define_guc() {
    let cores = par::cores().clamp(1, par::MAX_THREADS) as i32;
    THREADS.store(cores, Relaxed);
    // pgrx's GucSetting takes its boot value from a const; the default here
    // is the machine's core count, so the variable is defined directly.
    // SAFETY: the strings are 'static C strings and THREADS lives for the
    // process; PostgreSQL keeps the pointer and writes the value there.
    unsafe {
        pg_sys::DefineCustomIntVariable(
            c"tinmerge.threads".as_ptr(),
            c"Threads one tinmerge call may use (raster statistics, builds, decoding a stored value whole, tin_as_raster, tin_viewshed); 1 disables.".as_ptr(),
            c"Defaults to the number of cores. The work is split so that answers do not depend on it; cancel and statement_timeout are checked between batches.".as_ptr(),
            THREADS.as_ptr(),
            cores,
            1,
            par::MAX_THREADS as i32,
            pg_sys::GucContext::PGC_USERSET,
            0,
            None,
            None,
            None,
        );
    }
}

/// Hand the current setting to the core before a call that can use threads.
pub fn apply() {
    par::set_threads(THREADS.load(Relaxed).max(1) as usize);
}
