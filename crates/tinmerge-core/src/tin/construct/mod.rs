//! Build engine 2 (issue 74): the hierarchy of a raster band
//! ([`build_band`]) or of scattered samples ([`build_points`]) by
//! greedy insertion into one triangulation, exact by construction.
//!
//! - [`mesh`]: the triangulation (flat half-edges, locked edges, splits
//!   and flips);
//! - [`measure`]: a triangle's worst error at the samples in it and where
//!   its edges cross segments of the surface between them, through a
//!   [`measure::Source`] (a band's [`Heights`]: the valid pixel centres
//!   and the grid segments between them);
//! - [`points`]: scattered samples as a source, with their Delaunay
//!   triangulation as the surface between them;
//! - [`aligned`]: coarse levels along the pixel lattice (right isosceles
//!   triangles split at their longest edge's middle), for a band without
//!   nodata: their edges meet grid lines only at pixel centres, so the
//!   levels below never split them at a crossing;
//! - [`greedy`]: the driver, level after level in the same triangulation;
//! - [`kept`]: a band with `keep_border` (a tile): each hull side's
//!   vertices chosen from its own samples, level by level, before the
//!   driver refines inside ([`build_dense_kept`]).
//!
//! Every vertex is a sample (a pixel centre: whole lattice numbers, so
//! every test of which side is exact; a scattered sample, on an edge when
//! it is on it up to rounding) or the point where a locked edge crosses a
//! segment of the surface, made by splitting that edge: no vertex is ever
//! placed "near" an edge, so no level can have a crack. Free edges are
//! Delaunay, but for the segments a level makes edges of (and locks)
//! where an edge crossed one too far from the surface with both its
//! samples already vertices: the levels are constrained Delaunay
//! triangulations, their constraints the coarser levels' edges and those
//! segments, so
//! [`Tin::sanity_check`](crate::tin::Tin::sanity_check)'s Delaunay test
//! does not apply to them.
//!
//! ```
//! use tinmerge_core::tin::construct::build_band;
//! use tinmerge_core::tin::lattice::Lattice;
//! let (w, h) = (40, 30);
//! let z: Vec<f64> = (0..w * h)
//!     .map(|i| ((i % w) as f64 * 0.3).sin() * 10.0 + (i / w) as f64)
//!     .collect();
//! let lattice = Lattice { ip_x: 500.0, ip_y: 900.0, scale_x: 10.0, scale_y: -10.0, skew_x: 0.0, skew_y: 0.0 };
//! let tin = build_band(&z, w, h, &lattice, &[4.0, 1.0, 0.25], 32616, &mut || Ok(())).unwrap();
//! assert_eq!(tin.levels.len(), 3);
//! assert!(tin.levels[2].max_error <= 0.25);
//! tinmerge_core::tin::check::validate_structure(&tin).unwrap();
//! ```

mod aligned;
mod greedy;
mod kept;
mod measure;
mod mesh;
mod points;
mod queue;

pub use measure::Heights;

use super::build::assemble::assemble_verified;
use super::build::common::{
    Border, RawLevel, check_tolerances, in_frame, on_lattice, prepare_samples,
};
use super::dense::Dense;
use super::lattice::Lattice;
use super::{Tin, TinError};
use crate::interrupt::Interrupt;

/// The levels of a band in lattice coordinates (column, row): vertices
/// and raw levels, before they are assembled.
pub(crate) fn band_levels(
    g: &Heights<'_>,
    tolerances: &[f64],
    interrupt: &mut Interrupt<'_>,
) -> Result<(Vec<[f64; 3]>, Vec<RawLevel>), TinError> {
    check_tolerances(tolerances)?;
    if g.z.len() != g.width * g.height {
        return Err(TinError::InvalidParameter(format!(
            "{} heights for a band of {} x {} pixels",
            g.z.len(),
            g.width,
            g.height
        )));
    }
    greedy::levels(g, tolerances, interrupt)
}

/// The hierarchy of a raster band (`z` row by row, `NaN` where no data)
/// over its valid pixel centres' hull, on `lattice`, one level a
/// tolerance (coarsest first), every level within its tolerance at every
/// valid pixel centre and where its edges cross the grid segments between
/// them. Verified before it is returned.
pub fn build_band(
    z: &[f64],
    width: usize,
    height: usize,
    lattice: &Lattice,
    tolerances: &[f64],
    srid: i32,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    let g = Heights { z, width, height };
    let (pts, raw) = band_levels(&g, tolerances, interrupt)?;
    let tin = assemble_verified(pts, raw, srid, false, interrupt)?;
    on_lattice(tin, lattice, (0, 0))
}

/// The hierarchy of the lattice samples `d` (in their window's frame)
/// with `keep_border` ([`kept`]): every hull side's vertices chosen from
/// its own samples, keeping `border`'s (in the same frame), every level
/// within its tolerance at every valid pixel centre and where its edges
/// cross the grid segments between them but those ending at a side's
/// sample it did not choose (the strip along the hull, which the seam
/// rounds mend). Verified before it is returned, in `d`'s frame.
pub(crate) fn build_dense_kept(
    d: &Dense,
    tolerances: &[f64],
    srid: i32,
    border: &Border,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    check_tolerances(tolerances)?;
    let local = in_frame(border, (d.c0, d.r0));
    let (mut pts, raw) = kept::levels(d, tolerances, &local, interrupt)?;
    let (c0, r0) = (d.c0 as f64, d.r0 as f64);
    for p in &mut pts {
        p[0] += c0;
        p[1] += r0;
    }
    assemble_verified(pts, raw, srid, false, interrupt)
}

/// The hierarchy of scattered samples (x, y, z; what `tin_from_points`
/// builds), one level a tolerance (coarsest first), every level within
/// its tolerance at every sample and where its edges cross the edges of
/// the samples' Delaunay triangulation (the surface between them, as
/// every tool triangulates them). Duplicates in x, y are merged (their
/// mean height). Verified before it is returned. What `tin_from_points`
/// and its aggregate build; with lines or a boundary, the old engine's
/// [`crate::tin::build::build_points_domain`].
///
/// ```
/// use tinmerge_core::tin::construct::build_points;
/// let pts: Vec<[f64; 3]> = (0..900)
///     .map(|i| {
///         let (x, y) = ((i % 30) as f64 + 0.3 * ((i * 7) % 11) as f64 / 11.0, (i / 30) as f64);
///         [x, y, (x * 0.3).sin() * 5.0 + y * 0.1]
///     })
///     .collect();
/// let tin = build_points(pts, &[1.0, 0.25], 0, &mut || Ok(())).unwrap();
/// assert!(tin.levels[1].max_error <= 0.25);
/// tinmerge_core::tin::check::validate_structure(&tin).unwrap();
/// ```
pub fn build_points(
    samples: Vec<[f64; 3]>,
    tolerances: &[f64],
    srid: i32,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    check_tolerances(tolerances)?;
    let samples = prepare_samples(samples)?;
    interrupt()?;
    let source = points::Scattered::new(samples)?;
    interrupt()?;
    let (pts, raw) = greedy::levels(&source, tolerances, interrupt)?;
    drop(source);
    assemble_verified(pts, raw, srid, true, interrupt)
}
