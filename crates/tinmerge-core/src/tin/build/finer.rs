//! The levels after the first ([`refine_by_parents`]): each level's parents
//! refined on threads ([`Parents::run`]), then, when the tolerance is held
//! between samples, the forcing rounds and the last resort
//! ([`Parents::refine_forced`]), then the children numbered in parent order
//! ([`Numbering`]).

use std::ops::Range;

use rustc_hash::{FxHashMap, FxHashSet};

use super::builder::*;
use super::common::*;
use super::general::*;
use super::parents::{FORCING_ROUNDS, GROUP_SAMPLES, LAST_RESORT_PASSES, ParentSamples};
use crate::interrupt::Interrupt;
use crate::tin::hierarchy::compute_neighbours;
use crate::tin::sides::{Forced, SideKey, sample_key, side_key};
use crate::tin::surface::Reference;
use crate::tin::{NONE, TinError};

/// What the levels after the first are refined from and to.
pub(super) struct ByParents<'a, P: ParentSamples> {
    /// the samples
    pub(super) src: &'a P,
    /// the surface whose grid-line crossings the tolerance holds at (none:
    /// at the samples only)
    pub(super) reference: Option<&'a dyn Reference>,
    /// one per level to refine
    pub(super) tolerances: &'a [f64],
    /// the hull's sides are tile seams: their vertices are their own
    /// samples' choice
    pub(super) keep_border: bool,
    /// the seam samples each level must keep ([`Border`])
    pub(super) border: &'a [Vec<[f64; 2]>],
}

/// The levels after the first, each refined parent by parent. A triangle of
/// level `l` holds exactly the triangles of level `l + 1` inside it, and no
/// edge of level `l` crosses it, so its refinement depends only on its own
/// samples once the vertices on its three edges are fixed. Those are chosen
/// from each edge's own profile
/// ([`plan_side`](crate::tin::sides::plan_side): its samples, exactly on it
/// on a lattice, on it up to rounding for scattered samples, see
/// [`refine_parent_general`], and its grid-line crossings with the
/// `reference`), in the edge's canonical order, so the two triangles
/// sharing an edge choose the same vertices on it without knowing of each
/// other; the samples on the convex hull's sides stay candidates of the
/// greedy refinement (as in level 0) unless `keep_border`. Parents are
/// refined on `crate::par`'s threads, and their vertices numbered in parent
/// order ([`Numbering`]), so the result does not depend on the thread
/// count. `vsample` is the slot of each vertex in `verts`: a sample, or
/// `src.slots() + k` for the `k`th vertex at a crossing.
pub(super) fn refine_by_parents<P: ParentSamples>(
    spec: &ByParents<'_, P>,
    verts: &mut Vec<[f64; 3]>,
    vsample: Vec<u32>,
    raw: &mut Vec<RawLevel>,
    interrupt: &mut Interrupt<'_>,
) -> Result<(), TinError> {
    let mut numbering = Numbering::new(spec.src.slots(), verts, vsample);
    for (li, &tol) in spec.tolerances.iter().enumerate() {
        let Some(prev) = raw.last() else {
            return Err(TinError::Degenerate("internal: no level to refine".into()));
        };
        let mut level = Parents::new(spec, prev, &numbering, tol)?;
        level.phase = format!(
            "refining a level parent by parent ({} of {})",
            li + 1,
            spec.tolerances.len()
        );
        // the memory limit sees what the level set up, and what merging
        // its children adds, as it grows
        interrupt()?;
        let mut out = Children::default();
        let all: Vec<usize> = (0..prev.tris.len()).collect();
        if spec.reference.is_none() {
            // measured at the samples only: each batch merged as it comes
            // (no level's parents held at once)
            level.run(
                &level.phase,
                &all,
                &Forced::default(),
                &[],
                interrupt,
                &mut |o| {
                    numbering.merge(spec.src, o, &mut out);
                    Ok(())
                },
            )?;
        } else {
            let outs = level.refine_forced(spec.border.get(li), interrupt)?;
            for (i, o) in outs.into_iter().enumerate() {
                // (a parent's children are up to thousands of triangles)
                if i % 64 == 63 {
                    interrupt()?;
                }
                numbering.merge(spec.src, o, &mut out);
            }
        }
        // a child is void when its parent is
        let void: Vec<bool> = if prev.void.is_empty() {
            Vec::new()
        } else {
            out.parents
                .iter()
                .map(|&p| level.is_void(p as usize))
                .collect()
        };
        drop(level);
        let gap = out.gap;
        out.tris.shrink_to_fit();
        out.parents.shrink_to_fit();
        let mut level = RawLevel {
            tolerance: tol,
            max_error: out.max_error,
            num_vertices: numbering.verts.len() as u32,
            tris: out.tris,
            parents: out.parents,
            void,
        };
        // only a level a parent left a gap in is searched
        if gap {
            super::mend::mend_sliver_holes(numbering.verts, &mut level);
        }
        raw.push(level);
    }
    Ok(())
}

/// One level's children as the parents' outputs are merged.
#[derive(Default)]
struct Children {
    tris: Vec<[u32; 3]>,
    parents: Vec<u32>,
    max_error: f64,
    /// a parent left a gap ([`ParentOut::gap`])
    gap: bool,
}

/// The vertices of every level so far, numbered in the order parents hand
/// them over: a vertex shared with an earlier parent keeps its number (a
/// sample by its slot, a vertex at a crossing by its position, which both
/// parents compute bit for bit).
struct Numbering<'v> {
    verts: &'v mut Vec<[f64; 3]>,
    /// each vertex's slot: a sample, or `slots + k` for `extras[k]`
    vsample: Vec<u32>,
    slots: usize,
    /// vertices at grid-line crossings (sides split at the crossings)
    extras: Vec<[f64; 3]>,
    /// each slot's vertex, or NONE
    vertex_of: Vec<u32>,
    /// each crossing's slot, by its position's bits
    extra_slot: FxHashMap<(u64, u64), usize>,
}

impl<'v> Numbering<'v> {
    fn new(slots: usize, verts: &'v mut Vec<[f64; 3]>, vsample: Vec<u32>) -> Self {
        let mut vertex_of = vec![NONE; slots];
        for (v, &s) in vsample.iter().enumerate() {
            vertex_of[s as usize] = v as u32;
        }
        Numbering {
            verts,
            vsample,
            slots,
            extras: Vec::new(),
            vertex_of,
            extra_slot: FxHashMap::default(),
        }
    }

    /// The vertex of slot `slot` (at `at` for a crossing), numbered now if
    /// it is new.
    fn vertex<P: ParentSamples>(&mut self, src: &P, slot: usize, at: Option<[f64; 3]>) -> u32 {
        let v = &mut self.vertex_of[slot];
        if *v == NONE {
            *v = self.verts.len() as u32;
            self.verts.push(at.unwrap_or_else(|| src.sample(slot)));
            self.vsample.push(slot as u32);
        }
        *v
    }

    /// One parent's children added to `out`, their vertices numbered.
    fn merge<P: ParentSamples>(&mut self, src: &P, o: ParentOut, out: &mut Children) {
        out.max_error = out.max_error.max(o.err);
        out.gap |= o.gap;
        let ids: Vec<u32> = o
            .verts
            .iter()
            .map(|&v| {
                if v & AT_FLAG == 0 {
                    return self.vertex(src, v as usize, None);
                }
                let p = o.at[(v & !AT_FLAG) as usize];
                let slot = match self.extra_slot.get(&(p[0].to_bits(), p[1].to_bits())) {
                    Some(&s) => s,
                    None => {
                        self.extras.push(p);
                        self.vertex_of.push(NONE);
                        let s = self.slots + self.extras.len() - 1;
                        self.extra_slot.insert((p[0].to_bits(), p[1].to_bits()), s);
                        s
                    }
                };
                self.vertex(src, slot, Some(p))
            })
            .collect();
        out.tris
            .extend(o.tris.iter().map(|t| t.map(|k| ids[k as usize])));
        out.parents
            .extend(std::iter::repeat_n(o.parent, o.tris.len()));
    }
}

/// One level's parents (the triangles of the level above) and what
/// refining each needs.
struct Parents<'a, P: ParentSamples> {
    spec: &'a ByParents<'a, P>,
    prev: &'a [[u32; 3]],
    prev_void: &'a [bool],
    /// the parents' neighbours (empty when neither the hull nor a void is
    /// asked of them)
    nbrs: Vec<[u32; 3]>,
    /// bit k of a parent: its edge from corner k to k + 1 is on the hull
    /// (empty under keep_border without a reference)
    hull: Vec<u8>,
    /// the slot of each vertex of the levels above
    corner_samples: Vec<u32>,
    /// the vertices at crossings of the levels above, by slot past the
    /// samples
    corner_extras: Vec<[f64; 3]>,
    tol: f64,
    /// what [`crate::progress::step`] calls this level's refinement
    phase: String,
}

impl<'a, P: ParentSamples> Parents<'a, P> {
    fn new(
        spec: &'a ByParents<'a, P>,
        prev: &'a RawLevel,
        numbering: &Numbering<'_>,
        tol: f64,
    ) -> Result<Self, TinError> {
        let unbordered = spec.keep_border && spec.reference.is_none();
        // the hull sides' edges, whose samples stay greedy candidates (and
        // under keep_border, sides only their own samples decide); a void
        // parent's: its sides shared with the domain ([`Void`])
        let nbrs = if unbordered && prev.void.is_empty() {
            Vec::new()
        } else {
            compute_neighbours(&prev.tris)?
        };
        let hull: Vec<u8> = if unbordered {
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
        Ok(Parents {
            spec,
            prev: &prev.tris,
            prev_void: &prev.void,
            nbrs,
            hull,
            corner_samples: numbering.vsample.clone(),
            corner_extras: numbering.extras.clone(),
            tol,
            phase: String::new(),
        })
    }

    /// A corner's position, from its slot.
    fn corner_pos(&self, slot: u32) -> [f64; 3] {
        let (s, slots) = (slot as usize, self.spec.src.slots());
        if s < slots {
            self.spec.src.sample(s)
        } else {
            self.corner_extras[s - slots]
        }
    }

    /// Parent `t`'s corners.
    fn corners(&self, t: usize) -> [[f64; 3]; 3] {
        self.prev[t].map(|v| self.corner_pos(self.corner_samples[v as usize]))
    }

    /// Parent `t`'s side `k` (corner `k` to `k + 1`).
    fn side(&self, t: usize, k: usize) -> SideKey {
        let c = self.corners(t);
        side_key(&c[k], &c[(k + 1) % 3])
    }

    fn is_void(&self, t: usize) -> bool {
        self.prev_void.get(t).copied().unwrap_or(false)
    }

    /// Which of a void parent's sides it shares with the domain.
    fn void_of(&self, t: usize) -> Void {
        self.is_void(t).then(|| {
            [0, 1, 2].map(|k| {
                let n = self.nbrs[t][(k + 2) % 3];
                n != NONE && !self.is_void(n as usize)
            })
        })
    }

    /// The sides whose samples are the greedy refinement's candidates.
    fn free_of(&self, t: usize) -> [bool; 3] {
        let spec = self.spec;
        [0, 1, 2]
            .map(|k| !spec.keep_border && spec.reference.is_none() && self.hull[t] & (1 << k) != 0)
    }

    /// The sides that are a tile's seam (keep_border's hull sides).
    fn seam_of(&self, t: usize) -> [bool; 3] {
        let keep = self.spec.keep_border;
        [0, 1, 2].map(|k| keep && self.hull.get(t).is_some_and(|h| h & (1 << k) != 0))
    }

    /// The hull sides, as (parent, side).
    fn hull_sides(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        (0..self.prev.len())
            .flat_map(|t| (0..3).map(move |k| (t, k)))
            .filter(|&(t, k)| self.hull.get(t).is_some_and(|h| h & (1 << k) != 0))
    }

    /// The parents `ts` in groups of about [`GROUP_SAMPLES`] samples.
    fn groups_of(&self, ts: &[usize]) -> Vec<Range<usize>> {
        let mut groups = Vec::new();
        let (mut start, mut acc) = (0usize, 0.0f64);
        for (i, &t) in ts.iter().enumerate() {
            let [a, b, c] = self.corners(t);
            // about the samples inside
            acc += ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])).abs()
                / 2.0
                / self.spec.src.cell_area()
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
    }

    /// Parents `ts` refined (in order, on threads), their sides split at
    /// `forced` crossings too, those `last_resort` as a last resort, each
    /// output handed to `take` in the order of `ts`.
    fn run(
        &self,
        phase: &str,
        ts: &[usize],
        forced: &Forced,
        last_resort: &[bool],
        interrupt: &mut Interrupt<'_>,
        take: &mut dyn FnMut(ParentOut) -> Result<(), TinError>,
    ) -> Result<(), TinError> {
        let groups = self.groups_of(ts);
        let (mut done, total) = (0u64, ts.len() as u64);
        crate::par::map_batched(
            &groups,
            |g| {
                let mut scratch = Scratch::default();
                ts[g.clone()]
                    .iter()
                    .map(|&t| {
                        let job = Job {
                            reference: self.spec.reference,
                            extras: &self.corner_extras,
                            forced,
                            parent: t as u32,
                            corners: self.prev[t].map(|v| self.corner_samples[v as usize]),
                            free: self.free_of(t),
                            seam: self.seam_of(t),
                            void: self.void_of(t),
                            tol: self.tol,
                            last_resort: last_resort.get(t).copied().unwrap_or(false),
                        };
                        self.spec.src.refine_parent(&job, &mut scratch)
                    })
                    .collect::<Result<Vec<_>, TinError>>()
            },
            interrupt,
            &mut |o: Result<Vec<ParentOut>, TinError>| {
                for p in o? {
                    take(p)?;
                    done += 1;
                }
                crate::progress::step(phase, "triangles", done, total);
                Ok(())
            },
        )
    }

    /// Parents `ts` refined again, their outputs replacing theirs in `outs`.
    fn redo(
        &self,
        ts: &[usize],
        forced: &Forced,
        resort: &[bool],
        interrupt: &mut Interrupt<'_>,
        outs: &mut [ParentOut],
    ) -> Result<(), TinError> {
        let mut k = 0;
        let phase = format!("{}, parents refined again", self.phase);
        self.run(&phase, ts, forced, resort, interrupt, &mut |o| {
            outs[ts[k]] = o;
            k += 1;
            Ok(())
        })
    }

    /// Under keep_border a hull side is a tile's seam: its vertices are its
    /// own samples' choice, the same in the tile beside it, so nothing is
    /// forced onto it.
    fn seams(&self) -> FxHashSet<SideKey> {
        if !self.spec.keep_border {
            return FxHashSet::default();
        }
        self.hull_sides().map(|(t, k)| self.side(t, k)).collect()
    }

    /// The seam samples this level must keep ([`Border`]), forced onto the
    /// hull side they lie strictly inside.
    fn force_border(&self, keep: &[[f64; 2]], forced: &mut Forced) {
        for (t, k) in self.hull_sides() {
            let c = self.corners(t);
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

    /// Every parent refined with the tolerance held between samples. A
    /// crossing inside a parent that no pixel could mend, in the strip
    /// between a free edge and a side whose grid segment crosses the side:
    /// that side is split where the segment crosses it, in both its
    /// parents, and they are refined again (until no side is split: each
    /// round redoes only the parents of the sides it split). Parents still
    /// over the tolerance then (a crossing no pixel mends and no side's
    /// split reaches) are refined again with vertices at such crossings as
    /// a last resort (raster builds;
    /// [`Builder::refine`](super::builder::Builder::refine)), and what those
    /// leave unmended is forced in turn: a vertex at a crossing beside a
    /// side, or a parent that is a needle between two sides split at nearly
    /// the same place, leaves edges running beside a side's vertex that
    /// only a split of the other side mends. Not for tiles (keep_border):
    /// there the parents over are those of the strip along a seam, whose
    /// crossings it cannot mend, and vertices beside the seam moved the
    /// worst error onto it.
    fn refine_forced(
        &self,
        keep: Option<&Vec<[f64; 2]>>,
        interrupt: &mut Interrupt<'_>,
    ) -> Result<Vec<ParentOut>, TinError> {
        let mut forced = Forced::default();
        let seams = self.seams();
        if let Some(keep) = keep.filter(|k| self.spec.keep_border && !k.is_empty()) {
            self.force_border(keep, &mut forced);
        }
        let all: Vec<usize> = (0..self.prev.len()).collect();
        let mut outs: Vec<ParentOut> = Vec::with_capacity(self.prev.len());
        // (counted as soon as it is reserved, before it is written: the
        // memory limit refuses it here)
        interrupt()?;
        // which parents are refined as a last resort
        let mut resort = vec![false; self.prev.len()];
        self.run(&self.phase, &all, &forced, &resort, interrupt, &mut |o| {
            outs.push(o);
            Ok(())
        })?;
        let limit = self.tol * (1.0 + 1e-9);
        for _ in 0..LAST_RESORT_PASSES {
            self.forcing_rounds(&seams, &mut forced, &resort, interrupt, &mut outs)?;
            let over: Vec<usize> = if self.spec.keep_border {
                Vec::new()
            } else {
                (0..self.prev.len())
                    .filter(|&t| outs[t].err > limit && !resort[t])
                    .collect()
            };
            if over.is_empty() {
                break;
            }
            for &t in &over {
                resort[t] = true;
            }
            self.redo(&over, &forced, &resort, interrupt, &mut outs)?;
        }
        Ok(outs)
    }

    /// Up to [`FORCING_ROUNDS`] rounds, each forcing the crossings the
    /// parents left unmended onto the sides their grid segments cross (but
    /// `seams`) and refining again the parents of the sides it split; they
    /// end when a round splits none.
    fn forcing_rounds(
        &self,
        seams: &FxHashSet<SideKey>,
        forced: &mut Forced,
        resort: &[bool],
        interrupt: &mut Interrupt<'_>,
        outs: &mut [ParentOut],
    ) -> Result<(), TinError> {
        for _ in 0..FORCING_ROUNDS {
            let mut touched: FxHashSet<SideKey> = FxHashSet::default();
            for o in outs.iter() {
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
            let redo: Vec<usize> = (0..self.prev.len())
                .filter(|&t| (0..3).any(|k| touched.contains(&self.side(t, k))))
                .collect();
            self.redo(&redo, forced, resort, interrupt, outs)?;
        }
        Ok(())
    }
}
