//! Each level's statistics over its whole surface, kept in the header of a
//! stored value (formats 6 and 7, [`LevelSums`]), so a polygon that holds
//! the whole terrain (a tile wholly inside a county) is answered from the
//! header alone: no triangle is read.
//!
//! The sums are what [`stats_with`] makes of a polygon around the terrain:
//! the hierarchical sweep finds every level-0 triangle wholly inside, and
//! each adds its descendants' sums in order. So a polygon that holds the
//! terrain's bounding box ([`Area::contains_box`]) gets the same bits from
//! the header as from the triangles (tests/whole.rs checks it on both
//! bundled DEMs, with nodata, and on tiles, at every level). They are in the tin's own
//! units: a tin in a geographic SRID, measured in metres on its spheroid,
//! sums its triangles instead.
//!
//! ```
//! use tinmerge_core::tin::build::build;
//! use tinmerge_core::merge::area::polygon::Area;
//! use tinmerge_core::merge::area::whole::{level_sums, stats_from_header};
//! use tinmerge_core::tin::layout::{encode_with_sums, read_header};
//! let mut pts = Vec::new();
//! for i in 0..5 { for j in 0..5 { pts.push([i as f64, j as f64, (i + j) as f64]); } }
//! let tin = build(pts, &[1.0, 0.0], 0, &mut || Ok(())).unwrap();
//! let sums = level_sums(&tin, &mut || Ok(())).unwrap();
//! let stored = encode_with_sums(&tin, None, &sums);
//! let h = read_header(&stored).unwrap();
//! let big = Area::new(vec![vec![vec![[-1.0, -1.0], [5.0, -1.0], [5.0, 5.0], [-1.0, 5.0]]]]);
//! let st = stats_from_header(&h, 1, &big).unwrap();
//! assert_eq!(st.area2d, 16.0);
//! assert!((st.mean_z() - 4.0).abs() < 1e-12);
//! // a polygon that cuts the terrain is not answered from the header
//! let small = Area::new(vec![vec![vec![[1.0, 1.0], [5.0, 1.0], [5.0, 5.0], [1.0, 5.0]]]]);
//! assert!(stats_from_header(&h, 1, &small).is_none());
//! ```

use crate::geom::Units;
use crate::interrupt::Interrupt;
use crate::merge::area::surface::{SubtreeSums, SurfaceStats, VolumeParts, stats_with};
use crate::merge::area::{Method, sweep};
use crate::polygon::{Area, Where};
use crate::tin::TinError;
use crate::tin::layout::{Header, LevelSums};
use crate::tin::mesh::Indexed;

/// Each level's sums over its whole surface, in the tin's own units: the
/// statistics of a rectangle around its bounding box, made as
/// [`stats_with`] makes them.
pub fn level_sums<M: Indexed>(
    tin: &M,
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<LevelSums>, TinError>
where
    TinError: From<M::Err>,
{
    let b = *tin.bbox();
    // a margin of a tenth of the extent (and 1 unit), so no ring touches
    // the terrain
    let m = (b.max_x - b.min_x).max(b.max_y - b.min_y) * 0.1 + 1.0;
    let (x0, y0, x1, y1) = (b.min_x - m, b.min_y - m, b.max_x + m, b.max_y + m);
    let around = Area::new(vec![vec![vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]]]]);
    let mut out = Vec::with_capacity(tin.num_levels());
    for l in 0..tin.num_levels() {
        let s = sweep(tin, l, &around, Method::Hierarchy, interrupt)?;
        if !s.boundary.is_empty() {
            return Err(TinError::Internal(format!(
                "level {l}: a rectangle around the terrain crosses {} of its triangles",
                s.boundary.len()
            )));
        }
        let sums = if l > 0 {
            Some(SubtreeSums::build(tin, l, Units::Planar, interrupt)?)
        } else {
            None
        };
        out.push(stats_with(
            tin,
            &around,
            &s,
            sums.as_ref(),
            Units::Planar,
            interrupt,
        )?);
    }
    Ok(out)
}

/// The stored sums of `level` as statistics, when the header has them and
/// `area` holds the terrain's bounding box (then the polygon clips
/// nothing). Planar units only: the caller measures a geographic tin
/// itself.
pub fn stats_from_header(h: &Header, level: usize, area: &Area) -> Option<SurfaceStats> {
    let s = level_stats(h, level)?;
    (box_side(h, area) == Some(Where::Inside)).then_some(s)
}

/// Which side of `area` the open inside of the header's bounding box lies
/// on, when no ring meets it ([`Area::box_relation`]): `Outside` when the
/// polygon leaves out the whole terrain (a tile met by the polygon's
/// bounding box only: every statistic is that of nothing, in any units, no
/// triangle read), `Inside` when it holds it (then [`level_stats`]); None
/// when a ring crosses it.
pub fn box_side(h: &Header, area: &Area) -> Option<Where> {
    let b = &h.bbox;
    area.box_relation([b.min_x, b.min_y, b.max_x, b.max_y])
}

/// The stored sums of `level` as statistics, when the header has them:
/// the answer for a polygon that holds the terrain ([`box_side`]).
pub fn level_stats(h: &Header, level: usize) -> Option<SurfaceStats> {
    h.level_sums(level).copied()
}

/// Cut and fill against `base` from the header, when
/// [`stats_from_header`] answers and the level lies wholly above or wholly
/// below the base (otherwise the triangles that reach it must be read).
pub fn volume_from_header(h: &Header, level: usize, area: &Area, base: f64) -> Option<VolumeParts> {
    VolumeParts::of_subtree(&stats_from_header(h, level, area)?, base)
}
