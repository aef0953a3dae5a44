//! The finer levels, parent by parent ([`refine_by_parents`]): each
//! parent's sides planned from their own samples and crossings, then
//! refined on the lattice or as scattered samples.

use super::builder::*;
use super::common::*;
use super::general::*;
use crate::interrupt::Interrupt;
use crate::tin::dense::Dense;
use crate::tin::hierarchy::compute_neighbours;
use crate::tin::samples::{SampleGrid, Samples};
use crate::tin::sides::{Forced, Pt, SideKey, SidePlan, plan_side, sample_key, side_key};
use crate::tin::surface::Reference;
use crate::tin::{NONE, TinError};

/// The samples with data on the segment between samples `a` and `b` of a
/// lattice, both ends included, in the segment's canonical order (from its
/// end smaller in (x, y)), as [`hull_sides`] gives them.
pub(super) fn lattice_side(d: &Dense, a: usize, b: usize) -> Vec<usize> {
    let mut side = vec![a];
    d.on_segment(a, b, &mut side);
    side.push(b);
    if d.col_row(b) < d.col_row(a) {
        side.reverse();
    }
    side
}

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
        let plans = lattice_plans(d, corners, free, reference, forced, tol);
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
            let tris = b.snapshot();
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
/// side's samples found by gcd steps ([`lattice_side`]) and its crossings,
/// split by [`plan_side`].
fn lattice_plans(
    d: &Dense,
    corners: [u32; 3],
    free: [bool; 3],
    reference: Option<&dyn Reference>,
    forced: &Forced,
    tol: f64,
) -> Vec<SidePlan> {
    (0..3)
        .filter(|&k| !free[k])
        .map(|k| {
            let side = lattice_side(d, corners[k] as usize, corners[(k + 1) % 3] as usize);
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
                tol,
            )
        })
        .collect()
}

/// Samples' worth of parents handed to a thread at once.
pub(super) const GROUP_SAMPLES: f64 = 16384.0;

/// The levels after the first, each refined parent by parent. A triangle of level `l` holds exactly the triangles of level
/// `l + 1` inside it, and no edge of level `l` crosses it, so its
/// refinement depends only on its own samples once the vertices on its
/// three edges are fixed. Those are chosen from each edge's own profile
/// ([`plan_side`]: its samples, exactly on it on a lattice, on it up to
/// rounding for scattered samples, see [`refine_parent_general`], and its
/// grid-line crossings with the `reference`), in the edge's canonical
/// order, so the two triangles sharing an edge choose the same vertices on
/// it without knowing of each other; the samples on the convex hull's
/// sides stay candidates of the greedy refinement (as in level 0) unless
/// `keep_border`. Parents are refined on `tin::par`'s threads, and their
/// vertices numbered in parent order (a vertex shared with an earlier
/// parent keeps its number: a sample by its slot, a vertex at a crossing by
/// its position, which both parents compute bit for bit), so the result
/// does not depend on the thread count. `vsample` is the slot of each
/// vertex in `verts`: a sample, or `d.slots() + k` for `extras[k]`.
#[allow(clippy::too_many_arguments)]
pub(super) fn refine_by_parents<P: ParentSamples>(
    d: &P,
    reference: Option<&dyn Reference>,
    verts: &mut Vec<[f64; 3]>,
    mut vsample: Vec<u32>,
    raw: &mut Vec<RawLevel>,
    tolerances: &[f64],
    keep_border: bool,
    border: &[Vec<[f64; 2]>],
    interrupt: &mut Interrupt<'_>,
) -> Result<(), TinError> {
    let slots = d.slots();
    // vertices at grid-line crossings (sides split at the crossings), slot
    // `slots + k`
    let mut extras: Vec<[f64; 3]> = Vec::new();
    let mut vertex_of = vec![NONE; slots];
    for (v, &s) in vsample.iter().enumerate() {
        vertex_of[s as usize] = v as u32;
    }
    let key = |p: &[f64; 3]| (p[0].to_bits(), p[1].to_bits());
    let mut extra_slot: rustc_hash::FxHashMap<(u64, u64), usize> = Default::default();
    for (li, &tol) in tolerances.iter().enumerate() {
        let Some((prev, prev_void)) = raw.last().map(|r| (&r.tris, &r.void)) else {
            return Err(TinError::Degenerate("internal: no level to refine".into()));
        };
        // the hull sides' edges, whose samples stay greedy candidates
        // (bit k of a triangle: its edge from corner k to k + 1)
        // (and under keep_border, sides only their own samples decide);
        // a void parent's: its sides shared with the domain ([`Void`])
        let nbrs = if keep_border && reference.is_none() && prev_void.is_empty() {
            Vec::new()
        } else {
            compute_neighbours(prev)?
        };
        let hull: Vec<u8> = if keep_border && reference.is_none() {
            Vec::new()
        } else {
            nbrs.iter()
                .map(|n| {
                    (0..3)
                        .filter(|&k| n[(k + 2) % 3] == NONE)
                        .fold(0, |m, k| m | 1 << k)
                })
                .collect()
        };
        let is_void = |t: usize| prev_void.get(t).copied().unwrap_or(false);
        let void_of = |t: usize| -> Void {
            is_void(t).then(|| {
                [0, 1, 2].map(|k| {
                    let n = nbrs[t][(k + 2) % 3];
                    n != NONE && !is_void(n as usize)
                })
            })
        };
        let corner_samples = vsample.clone();
        let corner_extras = extras.clone();
        // a corner's position, from its slot (no borrow of `verts`, which
        // the merge grows)
        let corner_pos = |slot: u32| -> [f64; 3] {
            let s = slot as usize;
            if s < slots {
                d.sample(s)
            } else {
                corner_extras[s - slots]
            }
        };
        let free_of = |t: usize| {
            [0, 1, 2].map(|k| !keep_border && reference.is_none() && hull[t] & (1 << k) != 0)
        };
        // the parents `ts` in groups of about GROUP_SAMPLES samples
        let groups_of = |ts: &[usize]| -> Vec<std::ops::Range<usize>> {
            let mut groups = Vec::new();
            let (mut start, mut acc) = (0usize, 0.0f64);
            for (i, &t) in ts.iter().enumerate() {
                let [a, b, c] = prev[t].map(|v| corner_pos(corner_samples[v as usize]));
                // about the samples inside
                acc += ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])).abs()
                    / 2.0
                    / d.cell_area()
                    + 1.0;
                if acc >= GROUP_SAMPLES {
                    groups.push(start..i + 1);
                    (start, acc) = (i + 1, 0.0);
                }
            }
            if start < ts.len() {
                groups.push(start..ts.len());
            }
            groups
        };
        // those parents refined (in order, on threads), their sides split
        // at `forced` crossings too, each batch's outputs handed to `take`
        let run = |ts: &[usize],
                   groups: &[std::ops::Range<usize>],
                   forced: &Forced,
                   last_resort: &[bool],
                   interrupt: &mut Interrupt<'_>,
                   take: &mut dyn FnMut(ParentOut) -> Result<(), TinError>|
         -> Result<(), TinError> {
            crate::par::map_batched(
                groups,
                |g| {
                    let mut scratch = Scratch::default();
                    ts[g.clone()]
                        .iter()
                        .map(|&t| {
                            let job = Job {
                                reference,
                                extras: &corner_extras,
                                forced,
                                parent: t as u32,
                                corners: prev[t].map(|v| corner_samples[v as usize]),
                                free: free_of(t),
                                void: void_of(t),
                                tol,
                                last_resort: last_resort.get(t).copied().unwrap_or(false),
                            };
                            d.refine_parent(&job, &mut scratch)
                        })
                        .collect::<Result<Vec<_>, TinError>>()
                },
                interrupt,
                &mut |o: Result<Vec<ParentOut>, TinError>| {
                    for p in o? {
                        take(p)?;
                    }
                    Ok(())
                },
            )
        };
        let all: Vec<usize> = (0..prev.len()).collect();
        let all_groups = groups_of(&all);
        let mut tris: Vec<[u32; 3]> = Vec::new();
        let mut parents: Vec<u32> = Vec::new();
        let mut max_error = 0.0f64;
        let mut merge = |o: ParentOut| -> Result<(), TinError> {
            max_error = max_error.max(o.err);
            let ids: Vec<u32> = o
                .verts
                .iter()
                .map(|&src| {
                    let (slot, p) = if src & AT_FLAG == 0 {
                        (src as usize, None)
                    } else {
                        let p = o.at[(src & !AT_FLAG) as usize];
                        let slot = *extra_slot.entry(key(&p)).or_insert_with(|| {
                            extras.push(p);
                            vertex_of.push(NONE);
                            slots + extras.len() - 1
                        });
                        (slot, Some(p))
                    };
                    let v = &mut vertex_of[slot];
                    if *v == NONE {
                        *v = verts.len() as u32;
                        verts.push(p.unwrap_or_else(|| d.sample(slot)));
                        vsample.push(slot as u32);
                    }
                    *v
                })
                .collect();
            tris.extend(o.tris.iter().map(|t| t.map(|k| ids[k as usize])));
            parents.extend(std::iter::repeat_n(o.parent, o.tris.len()));
            Ok(())
        };
        if reference.is_none() {
            // measured at the samples only: each batch merged as it comes
            // (no level's parents held at once)
            run(
                &all,
                &all_groups,
                &Forced::default(),
                &[],
                interrupt,
                &mut merge,
            )?;
        } else {
            let mut forced = Forced::default();
            // under keep_border a hull side is a tile's seam: its vertices
            // are its own samples' choice, the same in the tile beside it,
            // so nothing is forced onto it
            let seams: rustc_hash::FxHashSet<SideKey> = if keep_border {
                (0..prev.len())
                    .flat_map(|t| (0..3).map(move |k| (t, k)))
                    .filter(|&(t, k)| hull[t] & (1 << k) != 0)
                    .map(|(t, k)| {
                        let c = prev[t].map(|v| corner_pos(corner_samples[v as usize]));
                        side_key(&c[k], &c[(k + 1) % 3])
                    })
                    .collect()
            } else {
                Default::default()
            };
            // the seam samples this level must keep ([`Border`]): forced
            // onto the hull side they lie strictly inside
            if let Some(keep) = border.get(li).filter(|k| keep_border && !k.is_empty()) {
                for (t, k) in (0..prev.len())
                    .flat_map(|t| (0..3).map(move |k| (t, k)))
                    .filter(|&(t, k)| hull[t] & (1 << k) != 0)
                {
                    let c = prev[t].map(|v| corner_pos(corner_samples[v as usize]));
                    let (a, b) = (c[k], c[(k + 1) % 3]);
                    for p in keep {
                        let on = (b[0] - a[0]) * (p[1] - a[1]) == (b[1] - a[1]) * (p[0] - a[0])
                            && (p[0] - a[0]) * (p[0] - b[0]) + (p[1] - a[1]) * (p[1] - b[1]) < 0.0;
                        if on {
                            let key = sample_key(&[p[0], p[1], 0.0]);
                            let v = forced.entry(side_key(&a, &b)).or_default();
                            if !v.contains(&key) {
                                v.push(key);
                            }
                        }
                    }
                }
            }
            let mut outs: Vec<ParentOut> = Vec::with_capacity(prev.len());
            // which parents are refined as a last resort (below)
            let mut resort = vec![false; prev.len()];
            run(&all, &all_groups, &forced, &resort, interrupt, &mut |o| {
                outs.push(o);
                Ok(())
            })?;
            // a crossing inside a parent that no pixel could mend, in the
            // strip between a free edge and a side whose grid segment
            // crosses the side: that side is split where the segment
            // crosses it, in both its parents, and they are refined again
            // (until no side is split: each round redoes only the parents
            // of the sides it split). Parents still over the tolerance
            // then (a crossing no pixel mends and no side's split
            // reaches) are refined again with vertices at such crossings
            // as a last resort (raster builds;
            // [`Builder::refine`](super::builder::Builder::refine)), and
            // what those leave unmended is forced in turn: a vertex at a
            // crossing beside a side, or a parent that is a needle between
            // two sides split at nearly the same place, leaves edges
            // running beside a side's vertex that only a split of the
            // other side mends. Not for tiles (keep_border): there the
            // parents over are those of the strip along a seam, whose
            // crossings it cannot mend, and vertices beside the seam moved
            // the worst error onto it
            let limit = tol * (1.0 + 1e-9);
            for _ in 0..LAST_RESORT_PASSES {
                for _ in 0..FORCING_ROUNDS {
                    let mut touched: rustc_hash::FxHashSet<SideKey> = Default::default();
                    for o in &outs {
                        for (side, seg) in &o.unmended {
                            if seams.contains(side) {
                                continue;
                            }
                            let v = forced.entry(*side).or_default();
                            if !v.contains(seg) {
                                v.push(*seg);
                                touched.insert(*side);
                            }
                        }
                    }
                    if touched.is_empty() {
                        break;
                    }
                    let redo: Vec<usize> = (0..prev.len())
                        .filter(|&t| {
                            let c = prev[t].map(|v| corner_pos(corner_samples[v as usize]));
                            (0..3).any(|k| touched.contains(&side_key(&c[k], &c[(k + 1) % 3])))
                        })
                        .collect();
                    let redo_groups = groups_of(&redo);
                    let mut k = 0;
                    run(&redo, &redo_groups, &forced, &resort, interrupt, &mut |o| {
                        outs[redo[k]] = o;
                        k += 1;
                        Ok(())
                    })?;
                }
                let over: Vec<usize> = if keep_border {
                    Vec::new()
                } else {
                    (0..prev.len())
                        .filter(|&t| outs[t].err > limit && !resort[t])
                        .collect()
                };
                if over.is_empty() {
                    break;
                }
                for &t in &over {
                    resort[t] = true;
                }
                let over_groups = groups_of(&over);
                let mut k = 0;
                run(&over, &over_groups, &forced, &resort, interrupt, &mut |o| {
                    outs[over[k]] = o;
                    k += 1;
                    Ok(())
                })?;
            }
            drop(forced);
            for o in outs {
                merge(o)?;
            }
        }
        drop(hull);
        drop(nbrs);
        tris.shrink_to_fit();
        parents.shrink_to_fit();
        // a child is void when its parent is
        let void: Vec<bool> = if prev_void.is_empty() {
            Vec::new()
        } else {
            parents.iter().map(|&p| is_void(p as usize)).collect()
        };
        raw.push(RawLevel {
            tolerance: tol,
            max_error,
            num_vertices: verts.len() as u32,
            tris,
            parents,
            void,
        });
    }
    Ok(())
}

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
    /// ([`Void`]).
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
