//! Progress of long work: what is done of what total, the rate and the
//! time left.
//!
//! A [`Meter`] counts the units of one phase of work (tiles of a table,
//! parent triangles of a level) and says when a report is due, at most
//! every so often, so a caller can show it (the SQL layer: NOTICE lines and
//! a file other sessions read, `tin_progress`). Work deep in the core that
//! has no caller-supplied meter (a level of a build refined parent by
//! parent) reports its steps with [`step`] to the sink the caller set for
//! the current thread with [`scoped`]; without one, [`step`] does nothing.
//!
//! ```
//! use std::time::Duration;
//! use tinmerge_core::progress::{Meter, Report};
//! let mut m = Meter::new("building tiles", "tiles", 400, Duration::ZERO);
//! let r: Report = m.advance(100).unwrap();
//! assert_eq!((r.done, r.total), (100, 400));
//! assert!(r.to_string().starts_with("building tiles: 100 of 400 tiles (25 %)"));
//! ```

use std::cell::RefCell;
use std::fmt;
use std::time::{Duration, Instant};

/// What a [`Meter`] or a [`step`] reports.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// The phase of work ("building tiles", "level 3 of 5").
    pub phase: String,
    /// What is counted ("tiles", "triangles").
    pub unit: &'static str,
    pub done: u64,
    /// 0 when unknown.
    pub total: u64,
    /// Seconds since the phase began.
    pub elapsed: f64,
    /// Units per second so far (0 before any).
    pub rate: f64,
    /// Seconds left at that rate, when the total is known and a unit done.
    pub left: Option<f64>,
}

impl Report {
    /// The report of `done` of `total` units after `elapsed` seconds.
    pub fn new(phase: &str, unit: &'static str, done: u64, total: u64, elapsed: f64) -> Report {
        let rate = if elapsed > 0.0 {
            done as f64 / elapsed
        } else {
            0.0
        };
        let left =
            (total > 0 && done > 0 && rate > 0.0).then(|| total.saturating_sub(done) as f64 / rate);
        Report {
            phase: phase.to_string(),
            unit,
            done,
            total,
            elapsed,
            rate,
            left,
        }
    }

    /// Percent done (0 to 100), when the total is known.
    pub fn percent(&self) -> Option<f64> {
        (self.total > 0).then(|| 100.0 * (self.done.min(self.total) as f64) / self.total as f64)
    }
}

/// A duration in seconds as people read it: "42 s", "3 min 05 s", "2 h 07 min".
pub fn duration_text(s: f64) -> String {
    let s = s.max(0.0).round() as u64;
    if s < 60 {
        format!("{s} s")
    } else if s < 3600 {
        format!("{} min {:02} s", s / 60, s % 60)
    } else {
        format!("{} h {:02} min", s / 3600, (s % 3600) / 60)
    }
}

impl fmt::Display for Report {
    /// `building tiles: 120 of 400 tiles (30 %), 2.1 tiles/s, 2 min 13 s left`
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.phase, self.done)?;
        if let Some(p) = self.percent() {
            write!(f, " of {} {} ({p:.0} %)", self.total, self.unit)?;
        } else {
            write!(f, " {}", self.unit)?;
        }
        let digits = if self.rate >= 100.0 { 0 } else { 1 };
        write!(f, ", {:.*} {}/s", digits, self.rate, self.unit)?;
        if let Some(left) = self.left {
            write!(f, ", {} left", duration_text(left))?;
        }
        write!(f, " ({} so far)", duration_text(self.elapsed))
    }
}

/// Counts the units of one phase of work and says when a report is due:
/// at most once per `every`, and never for the first `every` (a call that
/// ends sooner reports nothing).
pub struct Meter {
    phase: String,
    unit: &'static str,
    total: u64,
    done: u64,
    start: Instant,
    last: Instant,
    every: Duration,
}

impl Meter {
    pub fn new(phase: &str, unit: &'static str, total: u64, every: Duration) -> Meter {
        let now = Instant::now();
        Meter {
            phase: phase.to_string(),
            unit,
            total,
            done: 0,
            start: now,
            last: now,
            every,
        }
    }

    /// `n` more units done; the report when one is due.
    pub fn advance(&mut self, n: u64) -> Option<Report> {
        self.set(self.done.saturating_add(n))
    }

    /// `done` units done so far; the report when one is due.
    pub fn set(&mut self, done: u64) -> Option<Report> {
        self.done = done;
        let now = Instant::now();
        if now.duration_since(self.last) < self.every {
            return None;
        }
        self.last = now;
        Some(self.report())
    }

    /// The report now, due or not.
    pub fn report(&self) -> Report {
        Report::new(
            &self.phase,
            self.unit,
            self.done,
            self.total,
            self.start.elapsed().as_secs_f64(),
        )
    }

    pub fn done(&self) -> u64 {
        self.done
    }
}

/// Where [`step`]s of this thread go, set by [`scoped`].
type Sink = Box<dyn FnMut(&str, &'static str, u64, u64)>;

thread_local! {
    static SINK: RefCell<Option<Sink>> = const { RefCell::new(None) };
}

/// Runs `work` with `sink` receiving this thread's [`step`]s (phase,
/// unit, done, total); the sink that was set before is set again after,
/// also when `work` panics.
pub fn scoped<R>(sink: Sink, work: impl FnOnce() -> R) -> R {
    let _restore = Restore(SINK.with(|s| s.borrow_mut().replace(sink)));
    work()
}

/// The sink to set again when a [`scoped`] or [`quiet`] run ends.
struct Restore(Option<Sink>);

impl Drop for Restore {
    fn drop(&mut self) {
        let before = self.0.take();
        SINK.with(|s| *s.borrow_mut() = before);
    }
}

/// Runs `work` with no sink for this thread's [`step`]s: work that is
/// one unit of a larger one (a tile of a tiled build) does not report its
/// own steps between the larger one's.
pub fn quiet<R>(work: impl FnOnce() -> R) -> R {
    let _restore = Restore(SINK.with(|s| s.borrow_mut().take()));
    work()
}

/// `done` of `total` units of `phase` done (total 0: unknown), to the sink
/// [`scoped`] set for this thread, if any. Called from the thread that
/// runs the work (not from `par`'s workers), between pieces of work.
pub fn step(phase: &str, unit: &'static str, done: u64, total: u64) {
    SINK.with(|s| {
        // a sink that steps again (it should not) is not entered twice
        if let Ok(mut s) = s.try_borrow_mut()
            && let Some(f) = s.as_mut()
        {
            f(phase, unit, done, total);
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::rc::Rc;

    #[test]
    fn rate_and_time_left() {
        let r = Report::new("p", "tiles", 30, 120, 10.0);
        assert_eq!(r.rate, 3.0);
        assert_eq!(r.left, Some(30.0));
        assert_eq!(r.percent(), Some(25.0));
        assert_eq!(
            r.to_string(),
            "p: 30 of 120 tiles (25 %), 3.0 tiles/s, 30 s left (10 s so far)"
        );
        // unknown total: no percent, no time left
        let r = Report::new("p", "triangles", 5000, 0, 2.0);
        assert_eq!(r.left, None);
        assert_eq!(
            r.to_string(),
            "p: 5000 triangles, 2500 triangles/s (2 s so far)"
        );
        // nothing done yet: no rate, no time left
        assert_eq!(Report::new("p", "tiles", 0, 10, 5.0).left, None);
        assert_eq!(duration_text(185.0), "3 min 05 s");
        assert_eq!(duration_text(7625.0), "2 h 07 min");
    }

    #[test]
    fn reports_at_most_every() {
        let mut m = Meter::new("p", "tiles", 10, Duration::from_secs(3600));
        assert!(m.advance(1).is_none());
        assert!(m.advance(1).is_none());
        assert_eq!(m.done(), 2);
        assert_eq!(m.report().done, 2);
        let mut m = Meter::new("p", "tiles", 10, Duration::ZERO);
        assert_eq!(m.advance(4).map(|r| r.done), Some(4));
        assert_eq!(m.set(7).map(|r| r.done), Some(7));
    }

    #[test]
    fn steps_reach_the_scoped_sink_only() {
        let got = Rc::new(RefCell::new(Vec::new()));
        step("before", "t", 1, 2); // no sink: nothing
        let g = got.clone();
        scoped(
            Box::new(move |p, _, d, t| g.borrow_mut().push((p.to_string(), d, t))),
            || {
                step("a", "t", 1, 4);
                step("a", "t", 3, 4);
            },
        );
        step("after", "t", 1, 2);
        assert_eq!(
            *got.borrow(),
            vec![("a".to_string(), 1, 4), ("a".to_string(), 3, 4)]
        );
        // restored after a panic too
        let r = std::panic::catch_unwind(|| {
            scoped(Box::new(|_, _, _, _| {}), || panic!("in the work"))
        });
        assert!(r.is_err());
        assert!(SINK.with(|s| s.borrow().is_none()));
    }
}
