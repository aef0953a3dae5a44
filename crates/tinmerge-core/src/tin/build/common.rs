//! The build's shared pieces: the triangulation types, tolerances, the
//! samples prepared, the hull's sides, one level before assembly.

use crate::interrupt::Interrupt;
use crate::tin::samples::c2;

use crate::tin::lattice::Lattice;
use crate::tin::{MAX_LEVELS, Tin, TinError};
use robust::orient2d;
use spade::{ConstrainedDelaunayTriangulation, DelaunayTriangulation, Point2, Triangulation};

/// Most samples one build accepts (bounds memory: about 100 bytes a sample).
pub const MAX_SAMPLES: usize = 50_000_000;

pub(super) type Dt = DelaunayTriangulation<Point2<f64>>;
/// Level 0 of a build with breaklines: their segments are constraint edges.
pub(super) type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;

/// The triangulations a [`Builder`](super::builder::Builder) runs on: spade's Delaunay one, or the
/// constrained one for a level 0 with breaklines.
pub(super) trait Tri: Triangulation<Vertex = Point2<f64>> + Default + Sync {
    /// Whether an edge is a constraint (its vertices are chosen from its
    /// own profile, never measured as a free edge).
    fn is_constraint(&self, e: spade::handles::FixedUndirectedEdgeHandle) -> bool;
}
impl Tri for Dt {
    fn is_constraint(&self, _: spade::handles::FixedUndirectedEdgeHandle) -> bool {
        false
    }
}
impl Tri for Cdt {
    fn is_constraint(&self, e: spade::handles::FixedUndirectedEdgeHandle) -> bool {
        self.is_constraint_edge(e)
    }
}
pub(super) type FaceHandle = spade::handles::FixedFaceHandle<spade::handles::InnerTag>;

/// Samples under the faces around a new vertex above which they are
/// measured on threads.
pub(super) const PAR_SAMPLES: f64 = 32768.0;

/// Per-level tolerances `tolerance * 2^(levels-1-i)`, checked.
pub fn default_tolerances(tolerance: f64, levels: i32) -> Result<Vec<f64>, TinError> {
    if !(1..=MAX_LEVELS as i32).contains(&levels) {
        return Err(TinError::InvalidParameter(format!(
            "levels must be between 1 and {MAX_LEVELS}, got {levels}"
        )));
    }
    check_tolerance(tolerance)?;
    Ok((0..levels)
        .map(|i| tolerance * 2f64.powi(levels - 1 - i))
        .collect())
}

pub(super) fn check_tolerance(t: f64) -> Result<(), TinError> {
    if !t.is_finite() || t < 0.0 {
        return Err(TinError::InvalidParameter(format!(
            "tolerance must be a finite number >= 0, got {t}"
        )));
    }
    Ok(())
}

/// Check an explicit tolerance list (coarsest first, strictly decreasing).
pub fn check_tolerances(tols: &[f64]) -> Result<(), TinError> {
    if tols.is_empty() || tols.len() > MAX_LEVELS {
        return Err(TinError::InvalidParameter(format!(
            "tolerances must have between 1 and {MAX_LEVELS} elements, got {}",
            tols.len()
        )));
    }
    for &t in tols {
        check_tolerance(t)?;
    }
    for w in tols.windows(2) {
        if w[1] >= w[0] {
            return Err(TinError::InvalidParameter(format!(
                "tolerances must be strictly decreasing (level 0 = coarsest first), got {} then {}",
                w[0], w[1]
            )));
        }
    }
    Ok(())
}

/// Sort samples by (x, y), merge equal (x, y) by averaging z, reject non-finite.
pub fn prepare_samples(mut pts: Vec<[f64; 3]>) -> Result<Vec<[f64; 3]>, TinError> {
    if pts.len() > MAX_SAMPLES {
        return Err(TinError::TooLarge(format!(
            "{} samples exceed the limit of {MAX_SAMPLES} for one tin; split the terrain into tiles",
            pts.len()
        )));
    }
    if let Some(p) = pts.iter().find(|p| !p.iter().all(|c| c.is_finite())) {
        return Err(TinError::InvalidParameter(format!(
            "sample coordinates must be finite, got ({}, {}, {})",
            p[0], p[1], p[2]
        )));
    }
    for p in &pts {
        crate::tin::check_xy("a sample", p[0], p[1])?;
    }
    // unstable: no buffer of half the samples (deterministic all the same)
    pts.sort_unstable_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    // merged in place: `w` samples kept so far
    let mut w = 0usize;
    let mut run = 1.0;
    for i in 0..pts.len() {
        let p = pts[i];
        if w > 0 && pts[w - 1][0] == p[0] && pts[w - 1][1] == p[1] {
            // running mean of z over the duplicates
            run += 1.0;
            pts[w - 1][2] += (p[2] - pts[w - 1][2]) / run;
        } else {
            run = 1.0;
            pts[w] = p;
            w += 1;
        }
    }
    pts.truncate(w);
    Ok(pts)
}

/// Convex hull (counter-clockwise, no collinear points) by Andrew's monotone
/// chain on samples sorted by (x, y); returns sample indices.
pub(crate) fn convex_hull(pts: &[[f64; 3]]) -> Vec<usize> {
    let n = pts.len();
    let mut h: Vec<usize> = Vec::with_capacity(64);
    let turn = |h: &Vec<usize>, i: usize| {
        orient2d(
            c2(&pts[h[h.len() - 2]]),
            c2(&pts[h[h.len() - 1]]),
            c2(&pts[i]),
        )
    };
    for i in 0..n {
        while h.len() >= 2 && turn(&h, i) <= 0.0 {
            h.pop();
        }
        h.push(i);
    }
    let lower = h.len() + 1;
    for i in (0..n.saturating_sub(1)).rev() {
        while h.len() >= lower && turn(&h, i) <= 0.0 {
            h.pop();
        }
        h.push(i);
    }
    h.pop();
    h
}

/// The sides of the convex hull `hull`: for each edge, every sample exactly
/// on it, both corners included, ordered along it from its corner that is
/// smaller in (x, y) order. Two tiles sharing a seam list the seam's samples
/// in the same order whichever way round their hulls go.
pub(super) fn hull_sides(
    pts: &[[f64; 3]],
    hull: &[usize],
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<Vec<usize>>, TinError> {
    let mut out = Vec::with_capacity(hull.len());
    for k in 0..hull.len() {
        interrupt()?;
        let (ia, ib) = (hull[k], hull[(k + 1) % hull.len()]);
        let (a, b) = (&pts[ia], &pts[ib]);
        let (x0, x1) = (a[0].min(b[0]), a[0].max(b[0]));
        let (y0, y1) = (a[1].min(b[1]), a[1].max(b[1]));
        let mut on: Vec<(f64, usize)> = vec![(0.0, ia)];
        for (i, p) in pts.iter().enumerate() {
            if p[0] < x0 || p[0] > x1 || p[1] < y0 || p[1] > y1 {
                continue;
            }
            if orient2d(c2(a), c2(b), c2(p)) == 0.0 && p[..2] != a[..2] && p[..2] != b[..2] {
                let d = (p[0] - a[0]).abs() + (p[1] - a[1]).abs();
                on.push((d, i));
            }
        }
        on.push((f64::INFINITY, ib));
        on.sort_by(|u, v| u.0.total_cmp(&v.0));
        let mut side: Vec<usize> = on.into_iter().map(|(_, i)| i).collect();
        if (b[0], b[1]) < (a[0], a[1]) {
            side.reverse();
        }
        out.push(side);
    }
    Ok(out)
}

/// Choices of a build beyond samples and tolerances.
#[derive(Clone, Copy, Debug, Default)]
pub struct BuildOptions {
    /// Decide the vertices on each side of the convex hull from that side's
    /// samples alone: at every level, a Douglas-Peucker split of the side's
    /// height profile to the level's tolerance (`choose_border`), and no
    /// other sample of the side. Tiles of one raster that share a border
    /// row or column of samples then have the same vertices along it at
    /// every level, so the very same surface there: heights are continuous
    /// across tile seams. (Until 0.7.0 every sample of the hull's sides was
    /// a vertex of every level: the coarse levels were fans of slivers from
    /// the border, whose edges persisted into the finest level and made its
    /// surface steep and jagged.)
    pub keep_border: bool,
    /// Hold the tolerance between the samples too (issue 43; what
    /// `tin_from_raster` asks for on the pixel lattice, tiles aside): every
    /// free edge of every level is measured where it
    /// crosses a grid segment between two valid pixel centres (the raster's
    /// own surface there, [`crate::tin::surface`]), mended by inserting a pixel
    /// beside the crossing, and the sides of each parent are split at the
    /// next level from their own profile of samples and crossings
    /// ([`plan_side`](crate::tin::sides::plan_side)), so a coarse edge is refined where it is too far
    /// from the surface instead of persisting with its coarse heights.
    /// Vertices then lie at grid-line crossings as well as at pixel centres.
    pub between_samples: bool,
}

/// Samples on the convex hull's sides that a keep_border build must keep
/// as vertices, per level (positions in the build's frame): a tile's seam
/// samples that the tiles beside it asked for, so that the one-pixel strip
/// along the seam holds the tolerance between the samples too
/// ([`crate::tin::tiles`]). Both tiles of a seam are given the same ones and
/// take them before their own Douglas-Peucker choice, so they still agree.
/// A position that is no sample of a hull side is ignored.
#[derive(Clone, Debug, Default)]
pub struct Border {
    pub levels: Vec<Vec<[f64; 2]>>,
}

impl Border {
    /// The positions level `l` must keep (none past the last given).
    pub fn at(&self, l: usize) -> &[[f64; 2]] {
        self.levels.get(l).map(|v| v.as_slice()).unwrap_or(&[])
    }
}

/// The seam lines of a tile built over its data only
/// ([`crate::tin::tiles`], `fill_gaps => false`), in its window's frame:
/// columns `0` and `last[0]`, rows `0` and `last[1]`. A soft segment of the
/// boundary lying on one is a seam: its profile is its samples alone, in
/// canonical order, with the [`Border`] the tiles agreed on, so the tile
/// beside it (built the same way, or on the lattice with keep_border, whose
/// hull side is then the same samples) chooses the same vertices on it.
/// `height` gives a point on a seam line its height from the samples of that
/// line alone.
pub struct SeamLines<'a> {
    pub last: [f64; 2],
    pub height: &'a dyn Fn(f64, f64) -> Option<f64>,
}

impl SeamLines<'_> {
    /// Whether the segment `a`-`b` lies on a seam line.
    pub fn holds(&self, a: &[f64; 3], b: &[f64; 3]) -> bool {
        let on = |u: f64, last: f64| u == 0.0 || u == last;
        (a[0] == b[0] && on(a[0], self.last[0])) || (a[1] == b[1] && on(a[1], self.last[1]))
    }
}

/// One level of the build before [`assemble`](super::assemble::assemble).
pub(crate) struct RawLevel {
    pub(crate) tolerance: f64,
    /// measured
    pub(crate) max_error: f64,
    /// vertices of this level and the coarser ones (a prefix of all)
    pub(crate) num_vertices: u32,
    /// counter-clockwise, by vertex index
    pub(crate) tris: Vec<[u32; 3]>,
    /// each triangle's parent, by index in the previous level's `tris`;
    /// (empty at level 0)
    pub(crate) parents: Vec<u32>,
    /// which triangles are void (outside the domain; empty: none): at
    /// level 0 by [`mark_void`](super::levels::mark_void), at the finer ones as their parents
    pub(crate) void: Vec<bool>,
}

/// Whether a parent is outside the domain (a build's boundary, a hole in
/// it), and then which of its sides border a parent inside: `Some(domain)`,
/// side `k` (corner `k` to `k + 1`) shared with a parent in the domain when
/// `domain[k]`. No merge reads a void triangle's surface, so a void parent
/// is split only where it must meet its neighbours: its sides shared with
/// the domain take the vertices the parent inside plans there (the same
/// plan, against the same reference), its other sides and its inside stay
/// as they are (but for samples in a sliver, which every triangulation
/// takes). Refining it against the reference, as before, grew crossings on
/// needles between a boundary's ring and the samples' hull that lay within
/// rounding of the needle's other side: holes and cracks at the finer
/// levels. `None`: a parent in the domain.
pub(super) type Void = Option<[bool; 3]>;

/// The tolerance of a void parent: nothing is inserted but the samples in
/// a sliver (their error is `f64::MAX`).
pub(super) const VOID_TOL: f64 = f64::MAX / 4.0;

/// [`ParentOut::verts`](super::general::ParentOut::verts): the vertex is a point of [`ParentOut::at`](super::general::ParentOut::at).
pub(super) const AT_FLAG: u32 = 1 << 31;

/// The tolerance a side is planned at: the level's `tol`, or half of it
/// for a tile's `seam` (keep_border's hull side, between samples). A seam held to the level's
/// tolerance left the one-pixel strips beside it over the tolerance where
/// edges from its vertices cross them, so the tiles asked their
/// neighbours for seam samples ([`crate::tin::tile::Wanted`]) and both
/// were built again, round after round. Measured (docs/performance.md,
/// 2026-12-07), the 105-Mpixel terrain of `scripts/bench-big.sh` (1 m, 5
/// levels, 1,582 tiles): 228 s and 1,249,543 finest vertices at the
/// level's tolerance; 83 s and 1,226,952 at half; 79 s and 1,332,410 at
/// 0.3; 88 s and 1,859,944 at a tenth (its rough seams then take nearly
/// every pixel). On the bundled UTM DEM in 96-pixel tiles, 47 builds of
/// 16 tiles at the level's tolerance, 28 at half, 18 at a tenth. Both
/// tiles of a seam plan it alike, so it still agrees.
pub(crate) fn seam_tolerance(tol: f64, seam: bool) -> f64 {
    if seam { tol * SEAM_TOLERANCE } else { tol }
}

/// How a side is split ([`crate::tin::sides::choose_border`]): a tile's
/// seam at [`seam_tolerance`], its gaps of a power of two steps halved;
/// any other side at `tol`.
pub(crate) fn seam_split(tol: f64, seam: bool) -> crate::tin::sides::Split {
    crate::tin::sides::Split {
        tol: seam_tolerance(tol, seam),
        halve: seam,
    }
}

/// [`seam_tolerance`]'s fraction of the level's tolerance.
pub(crate) const SEAM_TOLERANCE: f64 = 0.5;

/// The convex hull (counter-clockwise, no collinear points) of the valid
/// pixels of a `width` x `height` lattice (`valid` by pixel index, row by
/// row), as pixel indices: only each row's first and last valid pixel can
/// be on it.
pub(crate) fn lattice_hull(
    width: usize,
    height: usize,
    valid: &dyn Fn(usize) -> bool,
) -> Vec<usize> {
    let mut ends: Vec<usize> = Vec::new();
    for r in 0..height {
        let row = r * width..(r + 1) * width;
        let first = row.clone().find(|&i| valid(i));
        let last = row.rev().find(|&i| valid(i));
        if let (Some(a), Some(b)) = (first, last) {
            ends.push(a);
            if b != a {
                ends.push(b);
            }
        }
    }
    let col_row = |i: usize| (i % width, i / width);
    ends.sort_by_key(|&i| col_row(i));
    let pts: Vec<[f64; 3]> = ends
        .iter()
        .map(|&i| [col_row(i).0 as f64, col_row(i).1 as f64, 0.0])
        .collect();
    convex_hull(&pts).into_iter().map(|k| ends[k]).collect()
}

/// A tin built in a window's frame put on the lattice: its vertices moved
/// by `origin` (whole pixels: exact) and mapped to world coordinates.
pub(crate) fn on_lattice(
    mut tin: Tin,
    lattice: &Lattice,
    origin: (i64, i64),
) -> Result<Tin, TinError> {
    let (c0, r0) = (origin.0 as f64, origin.1 as f64);
    for v in &mut tin.verts {
        v[0] += c0;
        v[1] += r0;
    }
    let tin = lattice.to_world(tin);
    for v in &tin.verts {
        crate::tin::check_xy("a pixel centre", v[0], v[1])?;
    }
    Ok(tin)
}

/// The kept seam samples (on the lattice) in a window's frame (`origin`
/// its first pixel).
pub(crate) fn in_frame(keep: &Border, origin: (i64, i64)) -> Border {
    let (c0, r0) = (origin.0 as f64, origin.1 as f64);
    Border {
        levels: keep
            .levels
            .iter()
            .map(|l| l.iter().map(|p| [p[0] - c0, p[1] - r0]).collect())
            .collect(),
    }
}
