//! Progress of long statements (issue 75): builds and builds of tiles
//! report what is done of what total, the rate and the time left
//! ([`tinmerge_core::progress`]), as NOTICE lines to their own client every
//! `tinmerge.progress_interval` seconds (0: none), and to every session
//! through a small file per backend, `pg_stat_tmp/tinmerge_progress.<pid>`
//! in the data directory, rewritten (a new file renamed over the old) at
//! most once a second, which `_tin_progress()` reads and the view
//! `tin_progress` joins with `pg_stat_activity`. Files work without
//! `shared_preload_libraries` (shared memory would need it), and a file
//! left by a statement that ended without removing it is not shown: a row
//! is shown only while its backend runs the statement that wrote it (same
//! pid, backend start and statement start, state active). The files of
//! backends that no longer exist are removed when a backend starts to
//! report.

use std::cell::RefCell;
use std::path::PathBuf;
use std::time::Duration;

use pgrx::prelude::*;
use pgrx::{GucContext, GucFlags, GucRegistry, GucSetting};

use tinmerge_core::progress::{Meter, Report};

/// `tinmerge.progress_interval`, seconds between NOTICE lines (0: none).
pub static INTERVAL: GucSetting<i32> = GucSetting::<i32>::new(10);

pub fn define_guc() {
    GucRegistry::define_int_guc(
        c"tinmerge.progress_interval",
        c"Seconds between the NOTICE lines a long tinmerge build reports its progress in; 0 turns them off.",
        c"Builds and builds of tiles (tin_tiles_from_table, tin_overviews, tin_tiles, tin_from_raster, tin_from_points) that run longer than this report what is done of what total, the rate and the time left. Other sessions see the same in the view tin_progress whatever this is set to.",
        &INTERVAL,
        0,
        3600,
        GucContext::Userset,
        GucFlags::UNIT_S,
    );
}

/// How often the file other sessions read is rewritten.
const FILE_EVERY: Duration = Duration::from_secs(1);
/// The files' names: this prefix and the backend's pid.
const PREFIX: &str = "tinmerge_progress.";
/// A file longer than this is not one of ours.
const MAX_FILE: u64 = 4096;

/// The statement now reporting, and when it last gave a NOTICE (its
/// start before the first).
struct Current {
    statement_start: pg_sys::TimestampTz,
    last_notice: pg_sys::TimestampTz,
}

thread_local! {
    static CURRENT: RefCell<Option<Current>> = const { RefCell::new(None) };
}

fn dir() -> Option<PathBuf> {
    // SAFETY: DataDir is set at backend start and never changed after;
    // a null pointer is checked
    let data = unsafe { pg_sys::DataDir };
    if data.is_null() {
        return None;
    }
    // SAFETY: DataDir is a NUL-terminated C string (checked non-null)
    let data = unsafe { std::ffi::CStr::from_ptr(data) };
    Some(PathBuf::from(data.to_string_lossy().into_owned()).join("pg_stat_tmp"))
}

fn own_file() -> Option<PathBuf> {
    Some(dir()?.join(format!("{PREFIX}{}", std::process::id())))
}

/// Remove the files of backends that no longer exist.
fn sweep_dead() {
    let Some(d) = dir() else { return };
    let Ok(entries) = std::fs::read_dir(&d) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name();
        let Some(pid) = name.to_str().and_then(|n| n.strip_prefix(PREFIX)) else {
            continue;
        };
        if pid.parse::<u32>().is_ok() && !std::path::Path::new("/proc").join(pid).exists() {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

/// One line of a file: what `_tin_progress()` returns of it.
fn line(func: &str, r: &Report, statement_start: pg_sys::TimestampTz) -> String {
    let clean = |s: &str| s.replace(['\t', '\n', '\r'], " ");
    // SAFETY: plain reads of the backend's own start time and clock
    let (backend_start, now) = unsafe { (pg_sys::MyStartTimestamp, pg_sys::GetCurrentTimestamp()) };
    format!(
        "1\t{backend_start}\t{statement_start}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{now}\n",
        clean(func),
        clean(&r.phase),
        clean(r.unit),
        r.done,
        r.total,
        r.elapsed,
        r.rate,
        r.left.map(|l| l.to_string()).unwrap_or_default(),
    )
}

/// Publish `r`, a report of `func`'s work: the file rewritten, and a
/// NOTICE when `tinmerge.progress_interval` has passed since the last one
/// of this statement (or since the statement began).
pub fn publish(func: &str, r: &Report) {
    // SAFETY: reads the current statement's start time
    let statement_start = unsafe { pg_sys::GetCurrentStatementStartTimestamp() };
    // SAFETY: reads the clock
    let now = unsafe { pg_sys::GetCurrentTimestamp() };
    let notice = CURRENT.with(|c| {
        let mut c = c.borrow_mut();
        let cur = match c.as_mut() {
            Some(cur) if cur.statement_start == statement_start => cur,
            _ => {
                sweep_dead();
                c.insert(Current {
                    statement_start,
                    last_notice: statement_start,
                })
            }
        };
        // the first NOTICE once the interval has passed since the
        // statement began, then one an interval
        let every = i64::from(INTERVAL.get()) * 1_000_000;
        let due = every > 0 && now - cur.last_notice >= every;
        if due {
            cur.last_notice = now;
        }
        due
    });
    if let Some(path) = own_file() {
        // best effort: progress never fails the work
        let tmp = path.with_extension(format!("{}.new", std::process::id()));
        if std::fs::write(&tmp, line(func, r, statement_start)).is_ok() {
            let _ = std::fs::rename(&tmp, &path);
        }
    }
    if notice {
        pgrx::notice!("{func}: {r}");
    }
}

/// This backend's progress file removed (its work ended).
pub fn clear() {
    let reported = CURRENT.with(|c| c.borrow_mut().take().is_some());
    if let Some(path) = own_file().filter(|_| reported) {
        let _ = std::fs::remove_file(path);
    }
}

/// A meter of work the SQL layer loops over itself (tiles of a table),
/// publishing at most once a second; the file is removed when it is
/// dropped.
pub struct Tracker {
    func: &'static str,
    /// the phase, its total and its meter
    meter: Option<(String, u64, Meter)>,
}

impl Tracker {
    pub fn new(func: &'static str) -> Tracker {
        Tracker { func, meter: None }
    }

    /// `done` of `total` units of `phase` done.
    pub fn set(&mut self, phase: &str, unit: &'static str, done: u64, total: u64) {
        let same = matches!(&self.meter, Some((p, t, _)) if p == phase && *t == total);
        if !same {
            let m = Meter::new(phase, unit, total, FILE_EVERY);
            self.meter = Some((phase.to_string(), total, m));
        }
        if let Some(r) = self.meter.as_mut().and_then(|(_, _, m)| m.set(done)) {
            publish(self.func, &r);
        }
    }

    /// The work ended: the file removed.
    pub fn finish(&mut self) {
        if self.meter.take().is_some() {
            clear();
        }
    }
}

impl Drop for Tracker {
    fn drop(&mut self) {
        self.finish();
    }
}

/// Runs a core build of `func` with its steps
/// ([`tinmerge_core::progress::step`]) published; the file is removed after.
pub fn track<R>(func: &'static str, work: impl FnOnce() -> R) -> R {
    let mut tracker = Tracker::new(func);
    // (the tracker is dropped with the sink when the work ends, and
    // removes the file)
    tinmerge_core::progress::scoped(
        Box::new(move |phase, unit, done, total| tracker.set(phase, unit, done, total)),
        work,
    )
}

/// A file's fields, checked; None for anything else.
type Row = (
    i32,
    pg_sys::TimestampTz,
    pg_sys::TimestampTz,
    String,
    String,
    String,
    i64,
    i64,
    f64,
    f64,
    Option<f64>,
    pg_sys::TimestampTz,
);

fn parse(pid: i32, text: &str) -> Option<Row> {
    let f: Vec<&str> = text.strip_suffix('\n')?.split('\t').collect();
    if f.len() != 12 || f[0] != "1" {
        return None;
    }
    let count = |s: &str| s.parse::<i64>().ok().filter(|v| *v >= 0);
    let real = |s: &str| s.parse::<f64>().ok().filter(|v| v.is_finite() && *v >= 0.0);
    let left = if f[10].is_empty() {
        None
    } else {
        Some(real(f[10])?)
    };
    Some((
        pid,
        f[1].parse().ok()?,
        f[2].parse().ok()?,
        f[3].to_string(),
        f[4].to_string(),
        f[5].to_string(),
        count(f[6])?,
        count(f[7])?,
        real(f[8])?,
        real(f[9])?,
        left,
        f[11].parse().ok()?,
    ))
}

fn stamp(t: pg_sys::TimestampTz) -> Option<TimestampWithTimeZone> {
    TimestampWithTimeZone::try_from(t).ok()
}

/// `_tin_progress()`: every progress file, checked (what `tin_progress`
/// shows of the statements still running).
#[allow(clippy::type_complexity)]
#[pg_extern(volatile, parallel_safe, requires = ["tin_type"])]
fn _tin_progress() -> TableIterator<
    'static,
    (
        name!(pid, i32),
        name!(backend_start, Option<TimestampWithTimeZone>),
        name!(query_start, Option<TimestampWithTimeZone>),
        name!(function, String),
        name!(phase, String),
        name!(unit, String),
        name!(done, i64),
        name!(total, i64),
        name!(elapsed, f64),
        name!(rate, f64),
        name!(time_left, Option<f64>),
        name!(updated, Option<TimestampWithTimeZone>),
    ),
> {
    let mut rows = Vec::new();
    if let Some(entries) = dir().and_then(|d| std::fs::read_dir(d).ok()) {
        for e in entries.flatten() {
            let name = e.file_name();
            let Some(pid) = name
                .to_str()
                .and_then(|n| n.strip_prefix(PREFIX))
                .and_then(|p| p.parse::<i32>().ok())
            else {
                continue;
            };
            let small = e.metadata().map(|m| m.is_file() && m.len() <= MAX_FILE);
            if !small.unwrap_or(false) {
                continue;
            }
            let Ok(text) = std::fs::read_to_string(e.path()) else {
                continue;
            };
            if let Some(r) = parse(pid, &text) {
                rows.push((
                    r.0,
                    stamp(r.1),
                    stamp(r.2),
                    r.3,
                    r.4,
                    r.5,
                    r.6,
                    r.7,
                    r.8,
                    r.9,
                    r.10,
                    stamp(r.11),
                ));
            }
        }
    }
    rows.sort_by_key(|r| r.0);
    TableIterator::new(rows)
}

extension_sql!(
    r#"
COMMENT ON FUNCTION _tin_progress() IS 'Internal: use the view tin_progress.';
CREATE VIEW tin_progress AS
SELECT p.pid, a.datname, a.usename, p.function, p.phase, p.done, p.total, p.unit,
       round((100.0 * p.done / nullif(p.total, 0))::numeric, 1) AS percent,
       round(p.rate::numeric, 2) AS rate,
       make_interval(secs => round(p.elapsed::numeric, 1)::float8) AS phase_elapsed,
       make_interval(secs => round(p.time_left::numeric, 1)::float8) AS time_left,
       now() - a.query_start AS statement_elapsed,
       p.updated, a.query
FROM _tin_progress() p
JOIN pg_catalog.pg_stat_activity a
  ON a.pid = p.pid AND a.backend_start = p.backend_start AND a.query_start = p.query_start
 AND a.state = 'active'
WHERE pg_catalog.pg_has_role(a.usesysid, 'USAGE')
   OR pg_catalog.pg_has_role('pg_read_all_stats', 'USAGE');
COMMENT ON VIEW tin_progress IS 'The progress of every tinmerge build running now (tin_tiles_from_table, tin_overviews, tin_tiles, tin_from_raster, tin_from_points) that has run for a second or more, one row per session: the phase of its work, done of total units (percent), the rate in units per second, the phase''s time so far and the time left at that rate, the whole statement''s time so far, when the row was last updated (about every second) and the query. Rows of other roles'' sessions need pg_read_all_stats, as in pg_stat_activity. Works without shared_preload_libraries (each backend writes a small file in pg_stat_tmp).';
"#,
    name = "tin_progress_view",
    requires = [_tin_progress]
);
