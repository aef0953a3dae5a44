//! Construction of the adaptive hierarchical triangulation.
//!
//! Level 0 is built by greedy insertion (Garland & Heckbert): start from the
//! convex hull of the samples, repeatedly insert the sample with the largest
//! vertical error in the worst triangle, keep the triangulation Delaunay
//! (spade), stop when every triangle is within tolerance 0. Errors are
//! measured exactly at every sample inside each triangle.
//!
//! A level 0 of more than 65,536 vertices is itself finished parent by
//! parent, over the triangles the greedy insertion had at that count.
//!
//! Every finer level is refined parent by parent ([`refine_by_parents`](finer::refine_by_parents)): a
//! triangle of level `i` holds exactly its children at level `i+1`, so it
//! is refined alone, in a small triangulation of its own samples, after the
//! vertices on its edges are chosen from each edge's own samples by a
//! Douglas-Peucker split (so the two triangles sharing an edge agree without
//! knowing of each other, and coarse edges persist as unions of finer
//! ones). No triangulation of the whole finest level is ever alive. A
//! raster's build (samples on the pixel lattice, [`build_lattice`]) reads
//! the heights in place ([`super::dense`]), where the samples on an edge
//! are exactly on it; scattered samples are bucketed ([`SampleGrid`](super::samples::SampleGrid)) and an
//! edge's samples are those on it up to rounding
//! ([`refine_parent_general`](general::refine_parent_general)). On the DEM upsampled 4x (1.9 million
//! samples, 5 levels) the peak heap is about 100 bytes a sample against 220
//! in one triangulation of every level (0.6.0's build), and the build over
//! 2x faster on one core.
//!
//! ```
//! use tinmerge_core::tin::build::build;
//! // a 20 x 20 grid of samples of a tilted plane with one bump
//! let mut pts = Vec::new();
//! for i in 0..20 {
//!     for j in 0..20 {
//!         let (x, y) = (i as f64, j as f64);
//!         let bump = if i == 10 && j == 10 { 5.0 } else { 0.0 };
//!         pts.push([x, y, 0.5 * x + bump]);
//!     }
//! }
//! let tin = build(pts, &[4.0, 0.0], 0, &mut || Ok(())).unwrap();
//! assert_eq!(tin.levels.len(), 2);
//! assert!(tin.levels[1].max_error <= 1e-9);
//! tin.sanity_check().unwrap();
//! ```

pub(crate) mod assemble;
mod builder;
pub(crate) mod common;
mod crossings;
mod finer;
mod general;
mod levels;
mod lines;
mod mend;
mod parents;
pub mod raster;
mod window;

use self::assemble::*;
pub use self::common::{
    Border, BuildOptions, MAX_SAMPLES, check_tolerances, default_tolerances, prepare_samples,
};
pub(crate) use self::common::{RawLevel, convex_hull};
use self::common::{in_frame, on_lattice};
use self::levels::*;
pub(crate) use self::levels::{dense_hull, dense_of};
pub use self::window::build_lattice_window_domain;
use super::breaklines::{Breakline, clip_to_hull};
use super::delaunay_ref::DelaunayReference;
use super::dense::Dense;
use super::lattice::Lattice;

use super::surface::{GridReference, Reference};
use super::{Tin, TinError};
use crate::interrupt::Interrupt;
use crate::polygon::{Area, Where};

/// Build a hierarchy from samples (x, y, z) with one tolerance per level
/// (coarsest first, strictly decreasing). `interrupt` is called regularly and
/// may abort the build by returning an error.
pub fn build(
    samples: Vec<[f64; 3]>,
    tolerances: &[f64],
    srid: i32,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    build_with(
        samples,
        tolerances,
        srid,
        BuildOptions::default(),
        interrupt,
    )
}

/// [`build`] with [`BuildOptions`].
pub fn build_with(
    samples: Vec<[f64; 3]>,
    tolerances: &[f64],
    srid: i32,
    opts: BuildOptions,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    build_inner(samples, &Spec::new(tolerances, srid, opts), interrupt)
}

/// [`build_domain`] of points, measured between the samples against
/// their whole Delaunay triangulation as
/// [`build_points`](crate::tin::construct::build_points) is: soft lines
/// and boundary rings take their heights from it, and the edges of it a
/// hard line cuts are left out ([`DelaunayReference::cut_by`]: the surface
/// there is the line's).
pub fn build_points_domain(
    samples: Vec<[f64; 3]>,
    lines: &[Breakline],
    boundaries: &[&Area],
    tolerances: &[f64],
    srid: i32,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    check_tolerances(tolerances)?;
    let samples = prepare_samples(samples)?;
    interrupt()?;
    // hard lines' heights are their own: the samples' edges they cut are
    // no measure of the build
    let cuts = super::breaklines::hard_segments(lines);
    let reference = DelaunayReference::new(&samples)?.cut_by(&cuts);
    drop(cuts);
    interrupt()?;
    build_domain_with(
        samples,
        lines,
        boundaries,
        tolerances,
        srid,
        Some(&reference),
        interrupt,
    )
}

/// [`build`] with breaklines ([`super::breaklines`]): every line a union of
/// edges at every level, hard lines' heights along them, the samples on a
/// line up to rounding left out ([`super::breaklines::drops_sample`]).
/// The parts of the lines outside the samples' convex hull are cut off
/// ([`super::breaklines::clip_to_hull`]).
///
/// ```
/// use tinmerge_core::tin::breaklines::Breakline;
/// use tinmerge_core::tin::build::build_breaklines;
/// let mut pts = Vec::new();
/// for i in 0..20 {
///     for j in 0..20 {
///         pts.push([i as f64, j as f64, (i * j) as f64 * 0.1]);
///     }
/// }
/// // a road at 3 m from (2.5, 2.5) to (16.5, 12.5): an edge at level 0
/// let road = Breakline { pts: vec![[2.5, 2.5, 3.0], [16.5, 12.5, 3.0]], hard: true };
/// let tin = build_breaklines(pts, &[road], &[100.0, 0.5], 0, &mut || Ok(())).unwrap();
/// let (a, b) = ([2.5, 2.5], [16.5, 12.5]);
/// let l0 = &tin.levels[0];
/// let has_edge = l0.tris.iter().any(|t| {
///     let xy = |k: u32| [tin.verts[k as usize][0], tin.verts[k as usize][1]];
///     (0..3).any(|j| {
///         let (p, q) = (xy(t[j]), xy(t[(j + 1) % 3]));
///         (p == a && q == b) || (p == b && q == a)
///     })
/// });
/// assert!(has_edge);
/// tin.sanity_check().unwrap();
/// ```
pub fn build_breaklines(
    samples: Vec<[f64; 3]>,
    lines: &[Breakline],
    tolerances: &[f64],
    srid: i32,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    build_domain(samples, lines, &[], tolerances, srid, interrupt)
}

/// The `boundary` of a build ([`build_domain`]) from polygons given as
/// rings of (x, y) (the first ring of each polygon its shell, the others
/// holes): finite coordinates, and valid as OGC polygons are (rings
/// simple, holes inside their shell, polygons not overlapping), checked
/// with `geo`'s validation; an error says what is wrong.
pub fn boundary(polygons: Vec<Vec<Vec<[f64; 2]>>>) -> Result<Area, TinError> {
    use geo::algorithm::Validation;
    use geo::{Coord, LineString, MultiPolygon, Polygon};
    if let Some(p) = polygons
        .iter()
        .flatten()
        .flatten()
        .find(|p| !(p[0].is_finite() && p[1].is_finite()))
    {
        return Err(TinError::InvalidParameter(format!(
            "boundary coordinates must be finite, got ({} {})",
            p[0], p[1]
        )));
    }
    if polygons.iter().all(|p| p.is_empty()) {
        return Err(TinError::InvalidParameter("boundary is empty".into()));
    }
    let ring =
        |r: &Vec<[f64; 2]>| LineString::new(r.iter().map(|p| Coord { x: p[0], y: p[1] }).collect());
    let mp = MultiPolygon::new(
        polygons
            .iter()
            .filter(|p| !p.is_empty())
            .map(|p| Polygon::new(ring(&p[0]), p[1..].iter().map(ring).collect()))
            .collect(),
    );
    if let Err(e) = mp.check_validation() {
        return Err(TinError::InvalidParameter(format!(
            "boundary is not a valid polygon: {e} (ST_MakeValid repairs it)"
        )));
    }
    Ok(Area::new(polygons))
}

/// Whether `area` holds the samples' whole convex hull (no ring enters
/// it, no sample is outside): a build with it as boundary is the build
/// without ([`build_domain`] would give the same triangles; a raster
/// build then stays on its lattice).
pub fn boundary_holds_all(area: &Area, samples: &[[f64; 3]]) -> bool {
    if samples
        .iter()
        .any(|p| area.locate([p[0], p[1]]) == Where::Outside)
    {
        return false;
    }
    let hull: Vec<[f64; 3]> = convex_hull(samples)
        .into_iter()
        .map(|k| samples[k])
        .collect();
    if hull.len() < 3 {
        return true;
    }
    let rings: Vec<Breakline> = area
        .rings
        .iter()
        .map(|r| Breakline {
            pts: r.iter().map(|p| [p[0], p[1], 0.0]).collect(),
            hard: false,
        })
        .collect();
    clip_to_hull(&rings, &hull).is_empty()
}

/// [`build_breaklines`] with a `boundary`: the domain is the boundary's
/// area clipped to the samples' convex hull, holes and concave parts
/// included. Its rings within the hull are edges at every level, like soft
/// breaklines (heights from the samples on both sides); the samples
/// outside it are left out; the triangles outside it (between the rings
/// and the hull, in the holes) are void ([`super::Level::num_void`]), so
/// every level still triangulates the hull of what is left and no merge
/// answers there. Breaklines outside the domain shape only void triangles.
///
/// ```
/// use tinmerge_core::merge::area::polygon::Area;
/// use tinmerge_core::tin::build::build_domain;
/// let mut pts = Vec::new();
/// for i in 0..=20 {
///     for j in 0..=20 {
///         pts.push([i as f64, j as f64, (i * j) as f64 * 0.1]);
///     }
/// }
/// // an L-shaped boundary with a square hole, reaching past the samples
/// let shell = vec![[-5.0, -5.0], [12.0, -5.0], [12.0, 10.0], [25.0, 10.0],
///                  [25.0, 25.0], [-5.0, 25.0], [-5.0, -5.0]];
/// let hole = vec![[2.0, 12.0], [6.0, 12.0], [6.0, 16.0], [2.0, 16.0], [2.0, 12.0]];
/// let b = Area::new(vec![vec![shell, hole]]);
/// let tin = build_domain(pts, &[], &[&b], &[5.0, 0.5], 0, &mut || Ok(())).unwrap();
/// tin.sanity_check().unwrap();
/// for l in &tin.levels {
///     // the domain: the square 0..20 less the corner 12..20 x 0..10 and the hole
///     let area: f64 = (0..l.num_domain())
///         .map(|t| {
///             let [a, b, c] = l.tris[t].map(|v| tin.verts[v as usize]);
///             ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])) / 2.0
///         })
///         .sum();
///     assert!((area - (400.0 - 80.0 - 16.0)).abs() < 1e-9);
/// }
/// ```
pub fn build_domain(
    samples: Vec<[f64; 3]>,
    lines: &[Breakline],
    boundaries: &[&Area],
    tolerances: &[f64],
    srid: i32,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    build_domain_with(
        samples, lines, boundaries, tolerances, srid, None, interrupt,
    )
}

/// [`build_domain`] measured against a `reference` surface too (None: at
/// the samples only).
fn build_domain_with(
    samples: Vec<[f64; 3]>,
    lines: &[Breakline],
    boundaries: &[&Area],
    tolerances: &[f64],
    srid: i32,
    reference: Option<&dyn Reference>,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    let spec = Spec {
        lines,
        boundaries,
        reference,
        ..Spec::new(tolerances, srid, BuildOptions::default())
    };
    build_inner(samples, &spec, interrupt)
}

/// [`build_domain`] for a raster's valid pixel centres in world
/// coordinates (`lat.centre(col, row)`, as `tin_from_raster` builds over
/// its data, with a boundary or with breaklines): every free edge of every
/// level is also measured where it crosses a grid segment between two valid
/// pixel centres, against the raster's `heights` ([`super::surface`]), and
/// coarse edges are split at those crossings level by level. Hard
/// breaklines keep heights of their own, not the raster's: the grid
/// segments they cut (within [`super::surface::CUT_SLACK`] pixel) are left
/// out ([`GridReference::cut_by`]), every other one is measured.
#[allow(clippy::too_many_arguments)]
pub fn build_domain_raster(
    samples: Vec<[f64; 3]>,
    lines: &[Breakline],
    boundaries: &[&Area],
    tolerances: &[f64],
    srid: i32,
    heights: &Dense,
    lat: &Lattice,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    // hard lines' heights are their own: the grid segments they cut are
    // no measure of the build
    let cuts = super::breaklines::hard_segments(lines);
    let reference = GridReference::in_world(heights, *lat).cut_by(&cuts);
    drop(cuts);
    build_domain_with(
        samples,
        lines,
        boundaries,
        tolerances,
        srid,
        lat.is_valid().then_some(&reference as &dyn Reference),
        interrupt,
    )
}

/// Build a hierarchy from raster samples given on the pixel lattice,
/// `(col, row, z)` with integer `col`, `row`: topology is decided there,
/// where pixel centres on one line are exactly collinear, and the result is
/// mapped to world coordinates by `lattice` (see [`super::lattice`]).
pub fn build_lattice(
    samples: Vec<[f64; 3]>,
    lattice: &Lattice,
    tolerances: &[f64],
    srid: i32,
    opts: BuildOptions,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    build_lattice_window(samples, lattice, (0, 0), tolerances, srid, opts, interrupt)
}

/// [`build_lattice`] of a window of a raster (a tile), its decisions made
/// in the window's own frame: `samples` are numbered on `lattice`, and the
/// build runs on them renumbered from `origin` (the window's first pixel),
/// so every vertex it puts where an edge crosses a grid line is computed,
/// and rounds, as in a build of the window cut out as a raster of its own
/// (its first pixel at 0, 0). The tin is then put back on `lattice`
/// (vertices at `origin` + their window coordinates, samples exactly),
/// so a pixel centre two windows share is the same point in both.
pub fn build_lattice_window(
    samples: Vec<[f64; 3]>,
    lattice: &Lattice,
    origin: (i64, i64),
    tolerances: &[f64],
    srid: i32,
    opts: BuildOptions,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    build_lattice_window_kept(
        samples,
        lattice,
        origin,
        tolerances,
        srid,
        opts,
        &Border::default(),
        &mut |_| Ok(()),
        interrupt,
    )
}

/// [`build_lattice_window`] with keep_border's hull samples that each level
/// must keep (`keep`: column and row on `lattice`, as the samples), and
/// `local` shown the tin in the window's own frame (pixel centres at their
/// column and row less `origin`) before it is put on the lattice
/// ([`crate::tin::tiles`] measures the seam strips there).
#[allow(clippy::too_many_arguments)]
pub fn build_lattice_window_kept(
    mut samples: Vec<[f64; 3]>,
    lattice: &Lattice,
    origin: (i64, i64),
    tolerances: &[f64],
    srid: i32,
    opts: BuildOptions,
    keep: &Border,
    local: &mut dyn FnMut(&Tin) -> Result<(), TinError>,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    let (c0, r0) = (origin.0 as f64, origin.1 as f64);
    if !(c0.abs() <= 1e9 && r0.abs() <= 1e9) {
        return Err(TinError::InvalidParameter(format!(
            "window origin ({}, {}) is too far from the raster's",
            origin.0, origin.1
        )));
    }
    for s in &mut samples {
        // whole numbers (checked below as the window's): exact
        s[0] -= c0;
        s[1] -= r0;
    }
    window::check_lattice(lattice)?;
    if let Some(p) = samples.iter().find(|p| {
        p[0] != p[0].trunc() || p[1] != p[1].trunc() || p[0].abs() > 1e9 || p[1].abs() > 1e9
    }) {
        return Err(TinError::InvalidParameter(format!(
            "lattice samples need whole column and row numbers, got ({}, {})",
            p[0] + c0,
            p[1] + r0
        )));
    }
    let keep = in_frame(keep, origin);
    let spec = Spec {
        on_lattice: true,
        border: &keep,
        ..Spec::new(tolerances, srid, opts)
    };
    let tin = build_inner(samples, &spec, interrupt)?;
    local(&tin)?;
    on_lattice(tin, lattice, origin)
}

/// A single-level tin from a triangulation given as vertices and
/// counter-clockwise triangles (an overlay, for instance). Tolerance and
/// maximum error of the level are 0: the triangles are the surface.
pub fn from_triangles(
    verts: Vec<[f64; 3]>,
    tris: Vec<[u32; 3]>,
    srid: i32,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    from_triangles_void(verts, tris, Vec::new(), srid, interrupt)
}

/// [`from_triangles`] with the triangles that are void (`void[t]`; empty:
/// none): the overlay of tins with void triangles.
pub fn from_triangles_void(
    verts: Vec<[f64; 3]>,
    tris: Vec<[u32; 3]>,
    void: Vec<bool>,
    srid: i32,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    if !void.is_empty() && void.len() != tris.len() {
        return Err(TinError::InvalidParameter(
            "internal: void flags and triangles differ in number".into(),
        ));
    }
    if !void.is_empty() && void.iter().all(|&v| v) {
        return Err(TinError::Degenerate("no triangles to make a tin of".into()));
    }
    if tris.is_empty() {
        return Err(TinError::Degenerate("no triangles to make a tin of".into()));
    }
    let n = verts.len();
    if tris.iter().flatten().any(|&v| v as usize >= n) {
        return Err(TinError::InvalidParameter(
            "a triangle refers to a vertex that does not exist".into(),
        ));
    }
    let level = RawLevel {
        tolerance: 0.0,
        max_error: 0.0,
        num_vertices: n as u32,
        tris,
        parents: Vec::new(),
        void,
    };
    assemble(verts, vec![level], srid, true, interrupt)
}

/// Upper bound of the heap a build from `samples` points with `levels`
/// levels uses at its peak, input samples included. The finer levels are
/// refined parent by parent, so the peak is level 0's triangulation or the
/// finished tin (measured on the DEM with `tests/memory.rs`: 209 bytes a
/// sample at one level of 2 m, 149 at 5 levels, 430 when nearly every
/// sample is a vertex of every level; `cargo bench --bench build`: 38-50
/// on point clouds of 1.9 and 9.5 million points).
pub fn build_bytes(samples: usize, levels: usize) -> usize {
    samples
        .saturating_mul(330 + 40 * levels)
        .saturating_add(1 << 20)
}

/// [`build_bytes`] for a build on a pixel lattice ([`build_lattice`]),
/// whose heights are read in place (8 bytes a pixel): the peak is level 0's triangulation or
/// the finished tin with the last level's arrays being made (measured with
/// `tests/memory.rs` on the DEM: 187 bytes a sample at 1 level, 135 at 5
/// levels and 2 m, 408 when nearly every sample is a vertex of every level;
/// `cargo bench --bench build` on the DEM upsampled 4x: 97 at 5 levels, 42
/// at one).
///
/// Between samples ([`BuildOptions::between_samples`], what
/// `tin_from_raster` builds) the estimate is the *typical* peak with a
/// margin, not the worst case: the peak follows the vertices (about 450
/// bytes each), which no one knows before the build. A terrain finer than
/// its relief (the DEM 4x finer by bilinear resampling, as LiDAR DEMs are
/// at 1 m) peaks at 48 bytes a sample on the heap (`tests/memory.rs`;
/// the backend's peak resident size grows 90 bytes a pixel building the
/// DEM 8x finer over its 7.6 million valid pixels, `tests/memory.sh`); the
/// estimate, 60 + 10 a level,
/// is 110 at 5 levels. Rough rasters need more (the DEM at its own 90 m:
/// 548 bytes a sample; white noise: 1,700), and the running check of
/// `tinmerge.max_memory` stops them as they pass the limit. The worst-case
/// estimate (1,000 + 40 a level) refused that build under the default 1 GB
/// limit, which it fits in.
pub fn lattice_build_bytes(samples: usize, levels: usize, between_samples: bool) -> usize {
    let per = if between_samples {
        60 + 10 * levels
    } else {
        300 + 40 * levels
    };
    samples.saturating_mul(per).saturating_add(1 << 20)
}

/// [`build_bytes`] for [`build_points`](crate::tin::construct::build_points) and [`build_points_domain`]: the
/// reference triangulation of all the samples
/// ([`DelaunayReference::BYTES_PER_SAMPLE`]) held through the build, whose
/// vertices at crossings cost as a raster's between samples do.
pub fn points_build_bytes(samples: usize, levels: usize) -> usize {
    samples
        .saturating_mul(1000 + DelaunayReference::BYTES_PER_SAMPLE + 40 * levels)
        .saturating_add(1 << 20)
}

/// [`build_bytes`] for [`build_domain_raster`] over `samples` valid pixels
/// of a raster of `pixels` (whose heights, 8 bytes a pixel, are part of
/// the request): the typical cost between samples, as
/// [`lattice_build_bytes`] (`tests/memory.rs`: the DEM 4x finer, bilinear,
/// over its valid pixels; the DEM at its own 90 m, rougher, needs about
/// 5x the estimate, and the running check of `tinmerge.max_memory` stops
/// such builds as they pass the limit).
pub fn domain_raster_build_bytes(samples: usize, pixels: usize, levels: usize) -> usize {
    lattice_build_bytes(samples, levels, true).saturating_add(pixels.saturating_mul(8))
}
