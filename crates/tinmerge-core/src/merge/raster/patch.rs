//! What the raster merges read of one level: the triangles to hand pixels
//! to, their corners and their hull edges ([`RasterLevel`]). Either the
//! whole level of a decoded [`Tin`] ([`TinLevel`]), or only the triangles
//! of any [`Indexed`] mesh that meet a window around the raster
//! ([`Patch`]): a stored terrain read in slices then costs the groups under
//! the raster, not the whole value.
//!
//! The merges index what they keep by *position* (`0..count()`, in
//! increasing triangle id) and report `id(position)`, so the rows, their
//! order and every sum are the same for a patch as for the whole level:
//! a triangle outside the window owns no pixel centre and overlaps no
//! pixel, and dropping it from the sweep's cut changes no run.
//!
//! ```
//! use tinmerge_core::merge::raster::patch::{Patch, RasterLevel, TinLevel};
//! use tinmerge_core::tin::build::build;
//! // a bumpy 10 x 10 grid: every sample is a vertex at tolerance 0
//! let pts: Vec<[f64; 3]> = (0..100).map(|i| [(i % 10) as f64, (i / 10) as f64, ((i * 7919) % 13) as f64]).collect();
//! let tin = build(pts, &[0.0], 0, &mut || Ok(())).unwrap();
//! let whole = TinLevel::new(&tin, 0).unwrap();
//! // the triangles meeting the square (1, 1)-(3, 3)
//! let patch = Patch::new(&tin, 0, [1.0, 1.0, 3.0, 3.0], &mut || Ok(())).unwrap();
//! assert!(patch.count() > 0 && patch.count() < whole.count());
//! assert!((0..patch.count()).all(|k| patch.corners(k) == whole.corners(patch.id(k) as usize)));
//! ```

use crate::geom::xy;
use crate::interrupt::Interrupt;
use crate::merge::area::{Method, sweep};
use crate::polygon::Area;
use crate::tin::mesh::Indexed;
use crate::tin::{NONE, Tin, TinError};

/// A hull edge of the domain among the triangles of a [`RasterLevel`]:
/// the triangle's position, the edge's vertex ids and positions, the
/// domain on its left.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HullEdge {
    pub k: u32,
    pub u: u32,
    pub v: u32,
    pub pu: [f64; 2],
    pub pv: [f64; 2],
}

/// The triangles of one level a raster merge works on.
pub trait RasterLevel: Sync {
    /// Number of triangles (positions `0..count()`).
    fn count(&self) -> usize;
    /// Id at its level of the triangle at position `k` (increasing in `k`).
    fn id(&self, k: usize) -> u32;
    /// Corners (x, y) of the triangle at position `k`, counter-clockwise.
    fn corners(&self, k: usize) -> [[f64; 2]; 3];
    /// The hull edges of these triangles, by position then corner.
    fn hull_edges(&self) -> Result<Vec<HullEdge>, TinError>;
}

/// The hull edges of triangle `k` with vertex ids `tri` and neighbours
/// `nb`, by corner.
fn push_hull(
    out: &mut Vec<HullEdge>,
    k: usize,
    tri: [u32; 3],
    nb: [u32; 3],
    vert: &mut dyn FnMut(u32) -> Result<[f64; 2], TinError>,
) -> Result<(), TinError> {
    for j in 0..3 {
        if nb[j] == NONE {
            let (u, v) = (tri[(j + 1) % 3], tri[(j + 2) % 3]);
            out.push(HullEdge {
                k: k as u32,
                u,
                v,
                pu: vert(u)?,
                pv: vert(v)?,
            });
        }
    }
    Ok(())
}

/// Neighbours with the void ones (ids `num_domain..`) as [`NONE`]: the
/// domain's boundary is its hull for the sweep.
fn off_domain(nb: [u32; 3], num_domain: usize) -> [u32; 3] {
    nb.map(|n| if n as usize >= num_domain { NONE } else { n })
}

/// A whole level of a decoded tin (positions are ids).
pub struct TinLevel<'a> {
    tin: &'a Tin,
    level: usize,
}

impl<'a> TinLevel<'a> {
    /// Level `level` of `tin`; an error for a level it lacks.
    pub fn new(tin: &'a Tin, level: usize) -> Result<TinLevel<'a>, TinError> {
        if level >= tin.levels.len() {
            return Err(TinError::Corrupt("raster merge: level".into()));
        }
        Ok(TinLevel { tin, level })
    }
}

impl RasterLevel for TinLevel<'_> {
    #[inline]
    fn count(&self) -> usize {
        // the void triangles are the last ones: outside the domain, they
        // own no pixel
        self.tin.levels[self.level].num_domain()
    }
    #[inline]
    fn id(&self, k: usize) -> u32 {
        k as u32
    }
    #[inline]
    fn corners(&self, k: usize) -> [[f64; 2]; 3] {
        self.tin.corners(self.level, k as u32).map(|v| xy(&v))
    }
    fn hull_edges(&self) -> Result<Vec<HullEdge>, TinError> {
        let lv = &self.tin.levels[self.level];
        let verts = &self.tin.verts;
        let mut vert = |i: u32| {
            verts
                .get(i as usize)
                .map(xy)
                .ok_or_else(|| TinError::Corrupt("raster sweep: vertex id".into()))
        };
        let mut out = Vec::new();
        let n = lv.num_domain();
        for (k, (tri, nb)) in lv.tris[..n].iter().zip(&lv.nbrs[..n]).enumerate() {
            push_hull(&mut out, k, *tri, off_domain(*nb, n), &mut vert)?;
        }
        Ok(out)
    }
}

/// The triangles of one level of a mesh that meet the inside of a window,
/// with what the merges read of them, copied out (so a patch of a stored
/// terrain read in slices can be swept on threads).
#[derive(Clone, Debug, Default)]
pub struct Patch {
    ids: Vec<u32>,
    cs: Vec<[[f64; 2]; 3]>,
    hull: Vec<HullEdge>,
}

impl Patch {
    /// The triangles of `level` meeting the inside of the rectangle
    /// `[min x, min y, max x, max y]`, found by the area merge's sweep at
    /// that level alone: the groups of a stored terrain read are those
    /// under the window and along the walk to it.
    pub fn new<M: Indexed>(
        m: &M,
        level: usize,
        window: [f64; 4],
        interrupt: &mut Interrupt<'_>,
    ) -> Result<Patch, TinError>
    where
        TinError: From<M::Err>,
    {
        let [x0, y0, x1, y1] = window;
        if !(x0 < x1 && y0 < y1) {
            return Ok(Patch::default());
        }
        let area = Area::new(vec![vec![vec![
            [x0, y0],
            [x1, y0],
            [x1, y1],
            [x0, y1],
            [x0, y0],
        ]]]);
        let s = sweep(m, level, &area, Method::Flat, interrupt)?;
        let mut ids: Vec<u32> = s.inside.get(level).cloned().unwrap_or_default();
        ids.extend_from_slice(&s.boundary);
        ids.sort_unstable();
        ids.dedup();
        let mut cs = Vec::with_capacity(ids.len());
        let mut hull = Vec::new();
        let mut vert = |i: u32| -> Result<[f64; 2], TinError> { Ok(xy(&m.vert(i)?)) };
        for (k, &t) in ids.iter().enumerate() {
            let tri = m.tri(level, t)?;
            cs.push([vert(tri[0])?, vert(tri[1])?, vert(tri[2])?]);
            let n = m.num_domain(level);
            push_hull(
                &mut hull,
                k,
                tri,
                off_domain(m.nbrs(level, t)?, n),
                &mut vert,
            )?;
            if k % 4096 == 4095 {
                interrupt()?;
            }
        }
        Ok(Patch { ids, cs, hull })
    }
}

impl RasterLevel for Patch {
    #[inline]
    fn count(&self) -> usize {
        self.ids.len()
    }
    #[inline]
    fn id(&self, k: usize) -> u32 {
        self.ids[k]
    }
    #[inline]
    fn corners(&self, k: usize) -> [[f64; 2]; 3] {
        self.cs[k]
    }
    fn hull_edges(&self) -> Result<Vec<HullEdge>, TinError> {
        Ok(self.hull.clone())
    }
}

/// Either kind of [`RasterLevel`], for a caller that decides at run time
/// (the SQL layer: a decoded value, or a stored one read in slices).
pub enum AnyLevel<'a> {
    Whole(TinLevel<'a>),
    Patch(Patch),
}

impl RasterLevel for AnyLevel<'_> {
    #[inline]
    fn count(&self) -> usize {
        match self {
            AnyLevel::Whole(l) => l.count(),
            AnyLevel::Patch(p) => p.count(),
        }
    }
    #[inline]
    fn id(&self, k: usize) -> u32 {
        match self {
            AnyLevel::Whole(l) => l.id(k),
            AnyLevel::Patch(p) => p.id(k),
        }
    }
    #[inline]
    fn corners(&self, k: usize) -> [[f64; 2]; 3] {
        match self {
            AnyLevel::Whole(l) => l.corners(k),
            AnyLevel::Patch(p) => p.corners(k),
        }
    }
    fn hull_edges(&self) -> Result<Vec<HullEdge>, TinError> {
        match self {
            AnyLevel::Whole(l) => l.hull_edges(),
            AnyLevel::Patch(p) => p.hull_edges(),
        }
    }
}
