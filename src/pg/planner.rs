//! The size the planner gives a terrain table that was never analyzed.
//!
//! PostgreSQL sizes a table that no VACUUM or ANALYZE has seen (its
//! `reltuples` is -1) as if it had at least ten pages of rows of the
//! estimated width: a one-row terrain table made by `CREATE TABLE ... AS
//! SELECT tin_from_raster(...)` is planned as about 1,270 rows. Autovacuum
//! never analyzes it (a table of a few rows stays under its thresholds).
//! The comma join users write, `FROM wells w, terrain t`, is then planned
//! with the points outside and the terrain materialized inside, and its
//! estimated 1,270 rows per point push the plan over `jit_above_cost`: a
//! join of 1,000 points took 2.8 ms against 0.3 ms once the table was
//! analyzed (docs/performance.md).
//!
//! [`relation_info_hook`] (PostgreSQL's `get_relation_info_hook`, which
//! exists to let a plugin correct "the assumed relation size") corrects
//! exactly that case: a heap table or materialized view with a `tin`
//! column, never analyzed, under the ten pages PostgreSQL assumes. Its rows
//! are counted (at most ten pages read, under the query's snapshot) and
//! its pages are its real ones. Every other relation keeps PostgreSQL's
//! own estimate. The hook is installed by `_PG_init`; every function that
//! takes a `tin` names [`_tin_plan_support`] as its planner support, which
//! PostgreSQL calls before it sizes the query's tables, so a session's
//! first query that names a tinmerge function loads tinmerge in time.
//!
//! The SQL builders that take no `tin` (`tin_from_raster`, `tin_tiles`,
//! `tin_from_points`, `tin_linetree`) name it too, for a second reason:
//! loaded at plan time in the session, tinmerge is loaded by each parallel
//! worker before the worker takes the session's settings. Loaded first
//! inside a worker (by the worker's first call), its `_PG_init` would turn
//! a `tinmerge.*` setting made before the load (postgresql.conf, `ALTER
//! DATABASE ... SET`, `PGOPTIONS`) into its variable in parallel mode, and
//! PostgreSQL warns 'parameter "tinmerge..." cannot be set during a parallel
//! operation' (found by `make installcheck` with `PGOPTIONS=-c
//! tinmerge.progress_interval=0`, pg_regress as_raster and bands).

use pgrx::pg_sys;
use pgrx::prelude::*;
use pgrx::Internal;

/// The heuristic's floor: a never-analyzed table of fewer pages is sized
/// as this many (PostgreSQL's `estimate_rel_size`).
const ASSUMED_PAGES: pg_sys::BlockNumber = 10;

static mut PREV_HOOK: pg_sys::get_relation_info_hook_type = None;

/// Install the hook (once per process, from `_PG_init`), after any hook
/// installed before it, which it calls first.
pub(crate) fn init() {
    // SAFETY: _PG_init runs once per process, before any query is planned
    // in it, on the process's only thread; the previous hook is kept and
    // called first.
    unsafe {
        PREV_HOOK = pg_sys::get_relation_info_hook;
        pg_sys::get_relation_info_hook = Some(relation_info_hook);
    }
}

#[pg_guard]
unsafe extern "C-unwind" fn relation_info_hook(
    root: *mut pg_sys::PlannerInfo,
    relid: pg_sys::Oid,
    inhparent: bool,
    rel: *mut pg_sys::RelOptInfo,
) {
    // SAFETY: PREV_HOOK is written only by init, before any planning.
    if let Some(prev) = unsafe { PREV_HOOK } {
        // SAFETY: the planner's own arguments, passed on unchanged.
        unsafe { prev(root, relid, inhparent, rel) };
    }
    if inhparent || rel.is_null() {
        return;
    }
    // SAFETY: rel is the planner's RelOptInfo of relid, which the planner
    // holds a lock on while it plans.
    unsafe { size_unanalyzed(relid, rel) };
}

/// `rel`'s pages and rows made its real ones when it is a never-analyzed
/// table with a `tin` column under [`ASSUMED_PAGES`] pages.
///
/// # Safety
/// `rel` is the planner's RelOptInfo of the locked relation `relid`.
unsafe fn size_unanalyzed(relid: pg_sys::Oid, rel: *mut pg_sys::RelOptInfo) {
    // SAFETY: relid is locked by the planner; the reference taken here is
    // given back below (or by the resource owner on an error).
    let r = unsafe { pg_sys::RelationIdGetRelation(relid) };
    if r.is_null() {
        return;
    }
    // SAFETY: r is an open relcache entry; rd_rel is its pg_class row.
    let form = unsafe { &*(*r).rd_rel };
    let candidate = form.reltuples < 0.0
        && (form.relkind == pg_sys::RELKIND_RELATION as core::ffi::c_char
            || form.relkind == pg_sys::RELKIND_MATVIEW as core::ffi::c_char)
        && form.relam == pg_sys::HEAP_TABLE_AM_OID;
    // SAFETY: r is open (above).
    if candidate && unsafe { has_tin_column(r) } {
        // SAFETY: r is an open heap relation.
        let pages =
            unsafe { pg_sys::RelationGetNumberOfBlocksInFork(r, pg_sys::ForkNumber::MAIN_FORKNUM) };
        if pages < ASSUMED_PAGES {
            // SAFETY: r is an open heap relation locked by the planner.
            if let Some(rows) = unsafe { count_rows(r) } {
                // SAFETY: rel is the planner's RelOptInfo (caller).
                unsafe {
                    (*rel).pages = pages;
                    (*rel).tuples = rows.max(1) as f64;
                }
            }
        }
    }
    // SAFETY: the reference taken above.
    unsafe { pg_sys::RelationClose(r) };
}

/// Whether the open relation `r` has a column of tinmerge's `tin` type:
/// a type whose input function is this library's `tin_in` (so a type of
/// that name from elsewhere is not taken for it, and a `tin` type in any
/// schema is).
///
/// # Safety
/// `r` is an open relcache entry.
unsafe fn has_tin_column(r: pg_sys::Relation) -> bool {
    // SAFETY: r is open; rd_att is its tuple descriptor, natts attributes
    // long.
    let attrs = unsafe {
        let desc = (*r).rd_att;
        (*desc).attrs.as_slice((*desc).natts as usize)
    };
    attrs
        .iter()
        .filter(|a| !a.attisdropped && a.atttypid.to_u32() >= pg_sys::FirstNormalObjectId)
        .any(|a| is_tin_type(a.atttypid))
}

/// Whether `typ`'s input function is this library's `tin_in`.
fn is_tin_type(typ: pg_sys::Oid) -> bool {
    let mut input = pg_sys::InvalidOid;
    let mut ioparam = pg_sys::InvalidOid;
    // SAFETY: catalog lookups of an existing type (an attribute's) and of
    // its input function; fmgr_info fills the FmgrInfo in place, its
    // allocations in the current (planner's) memory context.
    unsafe {
        pg_sys::getTypeInputInfo(typ, &mut input, &mut ioparam);
        let mut f: pg_sys::FmgrInfo = std::mem::zeroed();
        pg_sys::fmgr_info(input, &mut f);
        let ours = super::tin_type::tin_in_wrapper as *const ();
        f.fn_addr
            .is_some_and(|a| std::ptr::eq(a as *const (), ours))
    }
}

/// The rows of `r` visible to the query's snapshot (None when no snapshot
/// is active).
///
/// # Safety
/// `r` is an open heap relation the planner holds a lock on.
unsafe fn count_rows(r: pg_sys::Relation) -> Option<u64> {
    // SAFETY: reading whether a snapshot is active has no preconditions;
    // the active snapshot stays active while the planner runs, which is
    // longer than the scan.
    let snapshot = unsafe {
        if !pg_sys::ActiveSnapshotSet() {
            return None;
        }
        pg_sys::GetActiveSnapshot()
    };
    let flags = pg_sys::ScanOptions::SO_TYPE_SEQSCAN
        | pg_sys::ScanOptions::SO_ALLOW_STRAT
        | pg_sys::ScanOptions::SO_ALLOW_SYNC
        | pg_sys::ScanOptions::SO_ALLOW_PAGEMODE;
    let mut n = 0u64;
    // SAFETY: a sequential scan of the open heap relation r under an active
    // snapshot, read to its end and ended; at most ASSUMED_PAGES pages.
    unsafe {
        let scan = pg_sys::heap_beginscan(
            r,
            snapshot,
            0,
            std::ptr::null_mut(),
            std::ptr::null_mut(),
            flags,
        );
        while !pg_sys::heap_getnext(scan, pg_sys::ScanDirection::ForwardScanDirection).is_null() {
            n += 1;
        }
        pg_sys::heap_endscan(scan);
    }
    Some(n)
}

/// The planner support function of the functions that take a `tin`
/// (`SUPPORT _tin_plan_support`). It answers no request: their COST and
/// ROWS stand. That it is called at all is its purpose. PostgreSQL calls a
/// function's support function while it simplifies the query's
/// expressions, before it sizes the query's tables, so a session's first
/// query that names a tinmerge function loads tinmerge, and with it
/// [`relation_info_hook`], in time to size that query's terrain table.
#[pg_extern(immutable, strict, parallel_safe)]
pub(crate) fn _tin_plan_support(_request: Internal) -> Internal {
    // a NULL pointer, not an SQL NULL: "no answer" to any request
    Internal::from(Some(pg_sys::Datum::from(0usize)))
}

extension_sql!(
    r#"
COMMENT ON FUNCTION _tin_plan_support(internal) IS 'Planner support of the functions taking a tin: answers no request; calling it loads tinmerge before the planner sizes the query''s tables, so a terrain table never analyzed is sized by its rows (docs/scaling.md).';
"#,
    name = "tin_plan_support_sql",
    requires = [_tin_plan_support]
);
