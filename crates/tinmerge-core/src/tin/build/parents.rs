//! One parent's refinement ([`ParentSamples::refine_parent`]): its sides
//! planned from their own samples and crossings, then refined on the
//! lattice or as scattered samples. The level loop around it is
//! [`refine_by_parents`](super::finer::refine_by_parents).

use super::builder::*;
use super::general::*;
use crate::tin::TinError;
use crate::tin::dense::Dense;
use crate::tin::samples::{SampleGrid, Samples};
use crate::tin::sides::{Forced, Pt, SidePlan, plan_side};
use crate::tin::surface::Reference;

/// Rounds of forcing crossings onto sides per level, at most (a round
/// refines again only the parents of the sides it split; the rounds end
/// when one splits none).
pub(super) const FORCING_ROUNDS: usize = 32;

/// Passes of forcing rounds, each followed by the last resort for the
/// parents still over the tolerance that were not one yet.
pub(super) const LAST_RESORT_PASSES: usize = 3;

/// Refine the triangle of [`Dense`] samples `corners` (counter-clockwise;
/// slots past the lattice are `extras`) to `tol`. When its corners are
/// pixels and its sides are split at pixels only, on the window of the
/// lattice around it: the vertices on each edge `k` (corner `k` to `k + 1`,
/// its samples found by gcd steps) planned by [`plan_side`] unless `free[k]`
/// (a hull side without keep_border, whose samples are the greedy
/// refinement's candidates), then greedy insertion of the samples inside,
/// in a Delaunay triangulation of the triangle's own samples. Otherwise
/// (a corner or a side's vertex at a grid-line crossing) as scattered
/// samples are ([`refine_parent_general`]).
pub(super) fn refine_parent(
    d: &Dense,
    job: &Job<'_>,
    scratch: &mut Scratch,
) -> Result<ParentOut, TinError> {
    let Job {
        reference,
        extras,
        forced,
        parent,
        corners,
        free,
        seam,
        void,
        tol,
        last_resort,
    } = *job;
    let n = d.z.len();
    let pos = |s: u32| -> [f64; 3] {
        let s = s as usize;
        if s < n {
            d.point(s)
        } else {
            extras.get(s - n).copied().unwrap_or([f64::NAN; 3])
        }
    };
    let c = corners.map(pos);
    // (a last resort is refined as scattered samples are: its vertices at
    // crossings are no pixels)
    if void.is_none() && !last_resort && corners.iter().all(|&s| (s as usize) < n) {
        let plans = lattice_plans(d, corners, free, seam, reference, forced, tol);
        if plans
            .iter()
            .all(|p| p.chosen.iter().all(|q| matches!(q, Pt::Sample(_))))
        {
            let cr = corners.map(|s| d.col_row(s as usize));
            let (c0, c1) = (
                cr.iter().map(|p| p.0).min().unwrap_or(0),
                cr.iter().map(|p| p.0).max().unwrap_or(0),
            );
            let (r0, r1) = (
                cr.iter().map(|p| p.1).min().unwrap_or(0),
                cr.iter().map(|p| p.1).max().unwrap_or(0),
            );
            let win = d.window(c0, r0, (c1 - c0 + 1) as usize, (r1 - r0 + 1) as usize);
            let wn = win.len();
            let local = |p: &Pt| match *p {
                Pt::Sample(g) => Pt::Sample(win.local(g)),
                at => at,
            };
            let plans: Vec<SidePlan> = plans
                .into_iter()
                .map(|p| SidePlan {
                    reserve: p.reserve.iter().map(|&g| win.local(g)).collect(),
                    chosen: p.chosen.iter().map(local).collect(),
                    order: p.order.iter().map(local).collect(),
                    err: p.err,
                })
                .collect();
            let mut b = scratch.builder(&win, wn, !free.iter().all(|&f| f));
            b.reference = reference;
            let (err, _) = b.refine_parent(corners.map(|s| win.local(s as usize)), &plans, tol)?;
            let unmended = b.unmended(tol, &c, free);
            let (tris, dropped) = b.snapshot_dropping();
            // a sliver dropped at a corner leaves a gap for the level to mend
            let gap =
                dropped && super::mend::leaves_gap(&tris, &|u, v| b.same_side(u, v, &c, free));
            let verts = b
                .vsample
                .iter()
                .map(|&k| win.global(k as usize) as u32)
                .collect();
            scratch.keep(b);
            return Ok(ParentOut {
                parent,
                verts,
                at: Vec::new(),
                tris,
                err,
                unmended,
                gap,
            });
        }
    }
    let gather = |x0: f64, y0: f64, x1: f64, y1: f64, f: &mut dyn FnMut(u32, &[f64; 3])| {
        let (cl, ch) = (
            x0.ceil().max(d.c0 as f64),
            x1.floor().min((d.c0 + d.width as i64 - 1) as f64),
        );
        let (rl, rh) = (
            y0.ceil().max(d.r0 as f64),
            y1.floor().min((d.r0 + d.height as i64 - 1) as f64),
        );
        if !(cl <= ch && rl <= rh) {
            return;
        }
        for r in rl as i64..=rh as i64 {
            for cc in cl as i64..=ch as i64 {
                let i = d.index(cc, r);
                if d.valid(i) {
                    f(i as u32, &d.point(i));
                }
            }
        }
    };
    let is_sample = corners.map(|s| (s as usize) < n);
    refine_parent_general(&gather, job, scratch, c, is_sample)
}

/// The plans of a lattice parent's fixed sides (`free[k]` false): each
/// side's samples found by gcd steps ([`Dense::side`]) and its crossings,
/// split by [`plan_side`].
fn lattice_plans(
    d: &Dense,
    corners: [u32; 3],
    free: [bool; 3],
    seam: [bool; 3],
    reference: Option<&dyn Reference>,
    forced: &Forced,
    tol: f64,
) -> Vec<SidePlan> {
    (0..3)
        .filter(|&k| !free[k])
        .map(|k| {
            let side = d.side(corners[k] as usize, corners[(k + 1) % 3] as usize);
            let on: Vec<(usize, [f64; 3])> = side[1..side.len() - 1]
                .iter()
                .map(|&g| (g, d.point(g)))
                .collect();
            let (a, b) = (side[0], side[side.len() - 1]);
            plan_side(
                [Pt::Sample(a), Pt::Sample(b)],
                &d.point(a),
                &d.point(b),
                &on,
                reference,
                forced,
                super::common::seam_split(tol, seam[k]),
            )
        })
        .collect()
}

/// Samples' worth of parents handed to a thread at once.
pub(super) const GROUP_SAMPLES: f64 = 16384.0;

/// The samples a build refined parent by parent reads: a raster's lattice
/// in place ([`Dense`]) or bucketed scattered samples ([`SampleGrid`]).
pub(super) trait ParentSamples: Sync {
    /// Sample numbers are `0..slots()`.
    fn slots(&self) -> usize;
    /// Sample `s`: x, y, z.
    fn sample(&self, s: usize) -> [f64; 3];
    /// Area holding about one sample.
    fn cell_area(&self) -> f64;
    /// Refine the triangle of samples `corners` (counter-clockwise; slot
    /// `slots() + k` is `extras[k]`) to `tol`: its edges `k` (corner `k` to
    /// `k + 1`) not `free[k]` keep the vertices [`plan_side`] picks from the
    /// edge's own profile. `void`: the triangle is outside the domain
    /// ([`Void`](super::common::Void)).
    fn refine_parent(&self, job: &Job<'_>, scratch: &mut Scratch) -> Result<ParentOut, TinError>;
}

impl ParentSamples for Dense {
    fn slots(&self) -> usize {
        self.z.len()
    }
    fn sample(&self, s: usize) -> [f64; 3] {
        self.point(s)
    }
    fn cell_area(&self) -> f64 {
        1.0
    }
    fn refine_parent(&self, job: &Job<'_>, scratch: &mut Scratch) -> Result<ParentOut, TinError> {
        refine_parent(self, job, scratch)
    }
}

impl ParentSamples for SampleGrid {
    fn slots(&self) -> usize {
        self.pts.len()
    }
    fn sample(&self, s: usize) -> [f64; 3] {
        self.pts[s]
    }
    fn cell_area(&self) -> f64 {
        SampleGrid::cell_area(self)
    }
    fn refine_parent(&self, job: &Job<'_>, scratch: &mut Scratch) -> Result<ParentOut, TinError> {
        let (corners, extras) = (job.corners, job.extras);
        let n = self.pts.len();
        let c = corners.map(|s| {
            let s = s as usize;
            if s < n {
                self.pts[s]
            } else {
                extras.get(s - n).copied().unwrap_or([f64::NAN; 3])
            }
        });
        let gather = |x0: f64, y0: f64, x1: f64, y1: f64, f: &mut dyn FnMut(u32, &[f64; 3])| {
            self.for_each_in_box(x0, y0, x1, y1, |i, p| f(i as u32, p));
        };
        let is_sample = corners.map(|s| (s as usize) < n);
        refine_parent_general(&gather, job, scratch, c, is_sample)
    }
}
