//! A parent's refinement where "on the edge" is decided up to rounding
//! ([`refine_parent_general`]): scattered samples, and lattice parents
//! with a vertex at a grid-line crossing.

use super::builder::*;
use super::common::*;
use crate::tin::samples::SampleGrid;
use crate::tin::sides::{Forced, Pt, SegKey, SideKey, SidePlan, Split, close_chains, plan_side};
use crate::tin::surface::Reference;
use crate::tin::{NONE, TinError};
use spade::handles::FixedVertexHandle;

/// Calls `f(slot, sample)` for every sample in a closed box
/// (`x0, y0, x1, y1`).
pub(super) type Gather<'a> = dyn Fn(f64, f64, f64, f64, &mut dyn FnMut(u32, &[f64; 3])) + 'a;

/// One parent to refine at the level being built: the reference surface
/// (None: at the samples only), the vertices at crossings of the levels
/// before (slot `slots() + k` is `extras[k]`), the crossings forced onto
/// sides, the parent's number and corner slots (counter-clockwise), which
/// sides are free ([`refine_parent`](super::parents::refine_parent)), whether it is void ([`Void`]), the
/// level's tolerance and whether this is the last resort (vertices at
/// crossings no pixel mends).
#[derive(Clone, Copy)]
pub(super) struct Job<'a> {
    pub(super) reference: Option<&'a dyn Reference>,
    pub(super) extras: &'a [[f64; 3]],
    pub(super) forced: &'a Forced,
    pub(super) parent: u32,
    pub(super) corners: [u32; 3],
    pub(super) free: [bool; 3],
    /// the sides on a tile's seam (keep_border's hull), planned at
    /// [`seam_tolerance`]
    pub(super) seam: [bool; 3],
    pub(super) void: Void,
    pub(super) tol: f64,
    pub(super) last_resort: bool,
}

/// A parent's refinement where "on the edge" is decided up to rounding:
/// scattered samples, and on a lattice a parent with a corner or a side's
/// vertex at a grid-line crossing. No lattice decides which samples lie on
/// an edge: a sample within rounding of it (the triangle it makes with the
/// edge is a sliver, [`crate::geom::is_sliver`]), on either side, between
/// its ends, is the edge's sample. Both triangles sharing the edge find the
/// same ones (the test is symmetric and exact) and list them in the same
/// order (along the edge's longer axis from its canonical end), so
/// [`plan_side`] picks the same vertices there in both. The triangle's own
/// samples, its edges' and their chosen crossings are triangulated alone;
/// slivers along an edge are dropped ([`Builder::snapshot`]) and a triangle
/// whose side skips chosen vertices of the edge (they lie a rounding
/// outside it) is split into a fan through them, so both sides of the edge
/// meet at exactly the same vertices: no crack and no T-junction.
/// `corners`: slots, at `c`; `is_sample[k]`: corner `k` is a sample (else a
/// vertex at a crossing). In phases: the parent's samples gathered
/// ([`Own::gather`]), its fixed sides planned ([`Own::plan_sides`]), the
/// samples bucketed and the plans renumbered ([`Own::local`]), the greedy
/// refinement, and its output in slots ([`parent_out`]).
pub(super) fn refine_parent_general(
    gather: &Gather<'_>,
    job: &Job<'_>,
    scratch: &mut Scratch,
    c: [[f64; 3]; 3],
    is_sample: [bool; 3],
) -> Result<ParentOut, TinError> {
    let Job {
        reference,
        parent,
        free,
        void,
        tol,
        last_resort,
        ..
    } = *job;
    let mut own = Own::gather(gather, job, c, is_sample);
    let plans = own.plan_sides(job, &c)?;
    let (local, plans) = own.local(plans);
    let n = local.grid.pts.len();
    let mut b = scratch.builder(&local.grid, n, free.iter().any(|f| !f));
    b.reference = if void.is_some() { None } else { reference };
    // vertices at crossings: anywhere no sample mends one for the samples'
    // Delaunay; on a raster only as a last resort ([`Builder::refine`])
    b.at_budget = match b.reference {
        Some(r) if r.mends_at_crossings() || last_resort => 4 * n + 64,
        _ => 0,
    };
    let local_corners = [0, 1, 2].map(|k| local.pos[k]);
    let (err, chains) = b.refine_parent(
        local_corners,
        &plans,
        if void.is_some() { VOID_TOL } else { tol },
    )?;
    // a void parent's error is no level's
    let err = if void.is_some() { 0.0 } else { err };
    let unmended = b.unmended(tol, &c, free);
    let (mut tris, dropped) = b.snapshot_dropping();
    if chains.iter().any(|ch| ch.len() > 2) {
        tris = close_chains(tris, &chains, &b.vsample, &|v| {
            b.vert3(FixedVertexHandle::from_index(v))
        });
    }
    // a sliver dropped at a corner leaves a gap for the level to mend
    let gap = dropped && super::mend::leaves_gap(&tris, &|u, v| b.same_side(u, v, &c, free));
    let (verts, at) = parent_out(&b, &local.grid, &own.gid);
    scratch.keep(b);
    Ok(ParentOut {
        parent,
        verts,
        at,
        tris,
        err,
        unmended,
        gap,
    })
}

/// A parent's own points: its corners, the samples in it or on its fixed
/// sides up to rounding, and the crossings its side plans chose.
struct Own {
    /// corners first, then in the order found
    pts: Vec<[f64; 3]>,
    /// each point's sample slot (NONE: a corner or crossing that is none)
    gid: Vec<u32>,
    /// edge k's samples as (position along it, x, y, index in `pts`)
    on: [Vec<(f64, f64, f64, u32)>; 3],
    /// each edge from its canonical end (the smaller in (x, y))
    ends: [(usize, usize); 3],
}

/// [`Own`]'s points bucketed for the refinement.
struct LocalSamples {
    grid: SampleGrid,
    /// the local sample of each point of [`Own::pts`]
    pos: Vec<usize>,
}

impl Own {
    /// The samples of the parent at `c` (of `job`), from `gather`: those
    /// inside it, and those on a fixed side up to rounding (a sliver with
    /// it, strictly between its ends).
    fn gather(gather: &Gather<'_>, job: &Job<'_>, c: [[f64; 3]; 3], is_sample: [bool; 3]) -> Own {
        let (corners, free) = (job.corners, job.free);
        let ends: [(usize, usize); 3] = [0, 1, 2].map(|k| {
            let (i, j) = (k, (k + 1) % 3);
            if (c[j][0], c[j][1]) < (c[i][0], c[i][1]) {
                (j, i)
            } else {
                (i, j)
            }
        });
        // the band of a sliver is within about 128 ulps of the largest
        // coordinate of an edge: the box searched is wider
        let m = crate::geom::max_abs_xy(&c[0], &c[1], &c[2]).max(f64::MIN_POSITIVE);
        let pad = 1024.0 * f64::EPSILON * m;
        let x0 = c.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min) - pad;
        let x1 = c.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max) + pad;
        let y0 = c.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min) - pad;
        let y1 = c.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max) + pad;
        let mut own = Own {
            pts: c.to_vec(),
            gid: (0..3)
                .map(|k| if is_sample[k] { corners[k] } else { NONE })
                .collect(),
            on: Default::default(),
            ends,
        };
        gather(x0, y0, x1, y1, &mut |i, p| {
            if (0..3).any(|k| is_sample[k] && corners[k] == i) {
                return;
            }
            let mut keep = (0..3).all(|k| crate::geom::orient(&c[k], &c[(k + 1) % 3], p) >= 0.0);
            for k in 0..3 {
                if free[k] {
                    continue;
                }
                let (a, b) = (&c[ends[k].0], &c[ends[k].1]);
                if !crate::geom::is_sliver(a, b, p) {
                    continue;
                }
                // strictly between the ends along the edge's longer axis
                let ax = if (b[0] - a[0]).abs() >= (b[1] - a[1]).abs() {
                    0
                } else {
                    1
                };
                let (lo, hi) = (a[ax].min(b[ax]), a[ax].max(b[ax]));
                if p[ax] > lo && p[ax] < hi {
                    own.on[k].push(((p[ax] - a[ax]).abs(), p[0], p[1], own.pts.len() as u32));
                    keep = true;
                }
            }
            if keep {
                own.pts.push(*p);
                own.gid.push(i);
            }
        });
        own
    }

    /// Each fixed side's plan, by index in `pts`; its chosen crossings
    /// become points of `pts` too (no sample: `gid` NONE).
    fn plan_sides(&mut self, job: &Job<'_>, c: &[[f64; 3]; 3]) -> Result<Vec<SidePlan>, TinError> {
        let mut plans: Vec<SidePlan> = Vec::new();
        for k in 0..3 {
            if job.free[k] {
                continue;
            }
            self.on[k].sort_by(|u, v| {
                u.0.total_cmp(&v.0)
                    .then(u.1.total_cmp(&v.1))
                    .then(u.2.total_cmp(&v.2))
            });
            let side: Vec<(usize, [f64; 3])> = self.on[k]
                .iter()
                .map(|e| (e.3 as usize, self.pts[e.3 as usize]))
                .collect();
            let (ea, eb) = self.ends[k];
            // a void parent's side between two void parents: left whole
            let (side_reference, split) = match job.void {
                Some(domain) if !domain[k] => (None, Split::at(VOID_TOL)),
                _ => (
                    job.reference,
                    super::common::seam_split(job.tol, job.seam[k]),
                ),
            };
            let mut plan = plan_side(
                [Pt::Sample(ea), Pt::Sample(eb)],
                &c[ea],
                &c[eb],
                &side,
                side_reference,
                job.forced,
                split,
            );
            for q in &mut plan.chosen {
                if let Pt::At(p) = *q {
                    *q = Pt::Sample(self.pts.len());
                    self.pts.push(p);
                    self.gid.push(NONE);
                }
            }
            // the same points in the split's order: the crossings by the
            // index just given them
            for q in &mut plan.order {
                if let Pt::At(p) = *q {
                    let k = (0..self.pts.len())
                        .rev()
                        .find(|&k| self.gid[k] == NONE && self.pts[k][..2] == p[..2])
                        .ok_or_else(|| {
                            TinError::Degenerate("internal: a chosen crossing was lost".into())
                        })?;
                    *q = Pt::Sample(k);
                }
            }
            plans.push(plan);
        }
        Ok(plans)
    }

    /// The points bucketed, and the `plans` renumbered to their local
    /// samples.
    fn local(&mut self, mut plans: Vec<SidePlan>) -> (LocalSamples, Vec<SidePlan>) {
        let n = self.pts.len();
        let grid =
            SampleGrid::with_ids(std::mem::take(&mut self.pts), (0..n as u32).collect(), 1.0);
        let mut pos = vec![0usize; n];
        for (l, &k) in grid.ids.iter().enumerate() {
            pos[k as usize] = l;
        }
        for plan in &mut plans {
            for s in &mut plan.reserve {
                *s = pos[*s];
            }
            for q in plan.chosen.iter_mut().chain(plan.order.iter_mut()) {
                if let Pt::Sample(s) = q {
                    *s = pos[*s];
                }
            }
        }
        (LocalSamples { grid, pos }, plans)
    }
}

/// A refined parent's vertices as [`ParentOut::verts`] and
/// [`ParentOut::at`]: a sample by its slot (`gid` of its point in
/// `local`), any other vertex at its position.
fn parent_out(
    b: &Builder<'_, SampleGrid>,
    local: &SampleGrid,
    gid: &[u32],
) -> (Vec<u32>, Vec<[f64; 3]>) {
    let mut at: Vec<[f64; 3]> = Vec::new();
    let verts = b
        .vsample
        .iter()
        .enumerate()
        .map(
            |(v, &l)| match local.ids.get(l as usize).map_or(NONE, |&k| gid[k as usize]) {
                NONE => {
                    at.push(b.vert3(FixedVertexHandle::from_index(v)));
                    AT_FLAG | (at.len() - 1) as u32
                }
                g => g,
            },
        )
        .collect();
    (verts, at)
}

/// One parent's refinement: its vertices (samples by slot, or points at
/// grid-line crossings; its corners first), its triangles by index into
/// them, the worst error left.
pub(super) struct ParentOut {
    pub(super) parent: u32,
    /// a sample's slot, or `AT_FLAG | k` for the point `at[k]`
    pub(super) verts: Vec<u32>,
    pub(super) at: Vec<[f64; 3]>,
    pub(super) tris: Vec<[u32; 3]>,
    pub(super) err: f64,
    /// crossings over the tolerance that no pixel could mend, by the side
    /// their grid segment crosses ([`Builder::unmended`])
    pub(super) unmended: Vec<(SideKey, SegKey)>,
    /// whether the refinement dropped a sliver at a corner, leaving a gap
    /// ([`super::mend::leaves_gap`]) the level mends after it is refined
    /// ([`super::mend`])
    pub(super) gap: bool,
}
