//! What point location reads of a triangulation, as a trait, so the same
//! exact walk runs on a decoded [`Tin`], on one level being built
//! ([`LevelRef`]), and on a stored value read block by block
//! ([`super::sliced::SlicedTin`], whose reads can fail on a damaged block).
//!
//! A decoded value never fails (`Err = Infallible`), and its accessors are
//! the same array reads as before, so the decoded path costs nothing extra.

use super::{Bbox, HullEdge, Level, NONE, Tin};
use std::borrow::Cow;
use std::convert::Infallible;

/// Triangles, neighbours and vertices of the levels of a triangulation.
pub trait Mesh {
    type Err;
    fn num_levels(&self) -> usize;
    fn num_triangles(&self, level: usize) -> usize;
    /// Triangles of `level` in the domain: the first ones; the rest are
    /// void ([`super::Level::num_void`]).
    fn num_domain(&self, level: usize) -> usize;
    /// Whether `t` is void: outside the domain.
    #[inline]
    fn is_void(&self, level: usize, t: u32) -> bool {
        t as usize >= self.num_domain(level)
    }
    /// Vertices of all levels (level ids index a prefix).
    fn num_vertices(&self) -> usize;
    /// Vertex ids of triangle `t`, counter-clockwise.
    fn tri(&self, level: usize, t: u32) -> Result<[u32; 3], Self::Err>;
    /// Neighbours of `t` (across the edge opposite each corner; `NONE` on
    /// the hull).
    fn nbrs(&self, level: usize, t: u32) -> Result<[u32; 3], Self::Err>;
    fn vert(&self, v: u32) -> Result<[f64; 3], Self::Err>;
    /// Parent of `t` at the previous level (`NONE` at level 0).
    fn parent(&self, level: usize, t: u32) -> Result<u32, Self::Err>;
    /// Children of `t` at the next level (contiguous: triangles are sorted
    /// by parent).
    fn children(&self, level: usize, t: u32) -> Result<std::ops::Range<u32>, Self::Err>;
    /// The three corners of triangle `t`.
    #[inline]
    fn corners(&self, level: usize, t: u32) -> Result<[[f64; 3]; 3], Self::Err> {
        let [a, b, c] = self.tri(level, t)?;
        Ok([self.vert(a)?, self.vert(b)?, self.vert(c)?])
    }
    /// The hull edges of `level`, by increasing triangle id (found by
    /// reading every triangle's neighbours; a decoded [`Tin`] keeps them).
    fn hull_edges(&self, level: usize) -> Result<Cow<'_, [HullEdge]>, Self::Err>
    where
        Self: Sized,
    {
        hull_of(self, level).map(Cow::Owned)
    }
}

/// The hull edges of `level` of `m`, by increasing triangle id: every
/// triangle's neighbours read ([`Mesh::hull_edges`] keeps them for a
/// decoded [`Tin`]).
pub fn hull_of<M: Mesh>(m: &M, level: usize) -> Result<Vec<HullEdge>, M::Err> {
    let mut h = Vec::new();
    for t in 0..m.num_triangles(level) as u32 {
        for (j, &x) in m.nbrs(level, t)?.iter().enumerate() {
            if x == NONE {
                h.push(HullEdge::new(t, j, &m.corners(level, t)?));
            }
        }
    }
    Ok(h)
}

/// A [`Mesh`] with the bounding box and the grid index (what
/// [`super::locate::locate_in`] starts from).
pub trait Indexed: Mesh {
    fn bbox(&self) -> &Bbox;
    /// Cell size, columns and rows of the grid of `level` (0 columns: no
    /// grid).
    fn grid(&self, level: usize) -> (f64, u32, u32);
    /// Start triangle of grid cell `i` (row-major).
    fn cell(&self, level: usize, i: u32) -> Result<u32, Self::Err>;
}

/// Unwrap a result that cannot be an error.
#[inline]
pub(crate) fn infallible<T>(r: Result<T, Infallible>) -> T {
    match r {
        Ok(v) => v,
        Err(e) => match e {},
    }
}

impl Mesh for Tin {
    type Err = Infallible;
    #[inline]
    fn num_levels(&self) -> usize {
        self.levels.len()
    }
    #[inline]
    fn num_triangles(&self, level: usize) -> usize {
        self.levels[level].tris.len()
    }
    #[inline]
    fn num_domain(&self, level: usize) -> usize {
        self.levels[level].num_domain()
    }
    #[inline]
    fn tri(&self, level: usize, t: u32) -> Result<[u32; 3], Infallible> {
        Ok(self.levels[level].tris[t as usize])
    }
    #[inline]
    fn nbrs(&self, level: usize, t: u32) -> Result<[u32; 3], Infallible> {
        Ok(self.levels[level].nbrs[t as usize])
    }
    #[inline]
    fn vert(&self, v: u32) -> Result<[f64; 3], Infallible> {
        Ok(self.verts[v as usize])
    }
    #[inline]
    fn num_vertices(&self) -> usize {
        self.verts.len()
    }
    #[inline]
    fn parent(&self, level: usize, t: u32) -> Result<u32, Infallible> {
        Ok(self.levels[level].parent[t as usize])
    }
    #[inline]
    fn children(&self, level: usize, t: u32) -> Result<std::ops::Range<u32>, Infallible> {
        // validated values have a child range for every triangle but the
        // finest level's
        let cs = &self.levels[level].child_start;
        Ok(match (cs.get(t as usize), cs.get(t as usize + 1)) {
            (Some(&s), Some(&e)) if s <= e => s..e,
            _ => 0..0,
        })
    }
    fn hull_edges(&self, level: usize) -> Result<Cow<'_, [HullEdge]>, Infallible> {
        Ok(Cow::Borrowed(
            self.levels[level]
                .hull
                .get_or_init(|| infallible(hull_of(self, level))),
        ))
    }
}

impl Indexed for Tin {
    #[inline]
    fn bbox(&self) -> &Bbox {
        &self.bbox
    }
    #[inline]
    fn grid(&self, level: usize) -> (f64, u32, u32) {
        let g = &self.levels[level].grid;
        if g.cells.is_empty() {
            (g.cell, 0, 0)
        } else {
            (g.cell, g.nx, g.ny)
        }
    }
    #[inline]
    fn cell(&self, level: usize, i: u32) -> Result<u32, Infallible> {
        Ok(self.levels[level].grid.cells[i as usize])
    }
}

/// One level and its vertex array, outside a [`Tin`] (while building); the
/// `level` arguments are ignored.
pub struct LevelRef<'a> {
    pub verts: &'a [[f64; 3]],
    pub level: &'a Level,
}

impl Mesh for LevelRef<'_> {
    type Err = Infallible;
    #[inline]
    fn num_levels(&self) -> usize {
        1
    }
    #[inline]
    fn num_triangles(&self, _: usize) -> usize {
        self.level.tris.len()
    }
    #[inline]
    fn num_domain(&self, _: usize) -> usize {
        self.level.num_domain()
    }
    #[inline]
    fn tri(&self, _: usize, t: u32) -> Result<[u32; 3], Infallible> {
        Ok(self.level.tris[t as usize])
    }
    #[inline]
    fn nbrs(&self, _: usize, t: u32) -> Result<[u32; 3], Infallible> {
        Ok(self.level.nbrs[t as usize])
    }
    #[inline]
    fn vert(&self, v: u32) -> Result<[f64; 3], Infallible> {
        Ok(self.verts[v as usize])
    }
    #[inline]
    fn num_vertices(&self) -> usize {
        self.verts.len()
    }
    #[inline]
    fn parent(&self, _: usize, t: u32) -> Result<u32, Infallible> {
        Ok(self.level.parent.get(t as usize).copied().unwrap_or(NONE))
    }
    #[inline]
    fn children(&self, _: usize, _: u32) -> Result<std::ops::Range<u32>, Infallible> {
        Ok(0..0)
    }
}
