//! The pixel lattice of a raster: where raster builds decide topology.
//!
//! Pixel centres computed in world coordinates (`origin + (col + 0.5) *
//! size`) are rounded, so three centres that are collinear on the pixel grid
//! are usually not exactly collinear as doubles (any geographic grid with a
//! non-dyadic pixel size, any projected grid with a fractional origin). An
//! exact predicate then sees a sample that lies on a coarse edge a hair
//! beside it, the edge is not split, and a near-zero-area triangle fills the
//! gap: a crack in the surface with a vertical wall across it.
//!
//! Raster builds therefore run in lattice coordinates, `(col, row)` as exact
//! small integers, where collinear pixel centres are exactly collinear, and
//! map to world coordinates only at the end, with the one formula every
//! part of tinmerge uses for a pixel centre ([`Lattice::centre`]).
//!
//! ```
//! use tinmerge_core::tin::lattice::Lattice;
//! let l = Lattice { ip_x: 10.0, ip_y: 20.0, scale_x: 2.0, scale_y: -2.0, skew_x: 0.0, skew_y: 0.0 };
//! assert_eq!(l.centre(0.0, 0.0), (11.0, 19.0));
//! assert!(l.flips());            // rows run down: orientation flips
//! ```

use super::{Bbox, Tin, grid};
use crate::io::raster::GeoTransform;

/// Affine map of a raster: pixel (col, row)'s upper-left corner is
/// `(ip_x + col*scale_x + row*skew_x, ip_y + col*skew_y + row*scale_y)`
/// (PostGIS / GDAL geotransform).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lattice {
    pub ip_x: f64,
    pub ip_y: f64,
    pub scale_x: f64,
    pub scale_y: f64,
    pub skew_x: f64,
    pub skew_y: f64,
}

impl Lattice {
    /// World coordinates of the centre of pixel (col, row): the only place
    /// this is computed (raster reads, builds, tests of the SQL layer).
    #[inline]
    pub fn centre(&self, col: f64, row: f64) -> (f64, f64) {
        let (c, r) = (col + 0.5, row + 0.5);
        (
            self.ip_x + c * self.scale_x + r * self.skew_x,
            self.ip_y + c * self.skew_y + r * self.scale_y,
        )
    }

    /// The (fractional) column and row whose [`Lattice::centre`] is world
    /// point (x, y): pixel (c, r)'s square holds the points at `c - 0.5 ..
    /// c + 0.5`, `r - 0.5 .. r + 0.5`.
    #[inline]
    pub fn index_of(&self, x: f64, y: f64) -> (f64, f64) {
        let (dx, dy) = (x - self.ip_x, y - self.ip_y);
        let det = self.det();
        (
            (dx * self.scale_y - dy * self.skew_x) / det - 0.5,
            (self.scale_x * dy - self.skew_y * dx) / det - 0.5,
        )
    }

    /// Determinant of the linear part: area of one pixel, signed.
    pub fn det(&self) -> f64 {
        self.scale_x * self.scale_y - self.skew_x * self.skew_y
    }

    /// Whether the map reverses orientation (rows running down, as in
    /// north-up rasters): counter-clockwise lattice triangles become
    /// clockwise in world coordinates.
    pub fn flips(&self) -> bool {
        self.det() < 0.0
    }

    /// Size of a pixel along its shorter side (for thresholds in pixels).
    pub fn pixel_size(&self) -> f64 {
        let a = self.scale_x.hypot(self.skew_y);
        let b = self.skew_x.hypot(self.scale_y);
        a.min(b)
    }

    /// Whether the map is usable: finite and not degenerate.
    pub fn is_valid(&self) -> bool {
        [
            self.ip_x,
            self.ip_y,
            self.scale_x,
            self.scale_y,
            self.skew_x,
            self.skew_y,
        ]
        .iter()
        .all(|v| v.is_finite())
            && self.det() != 0.0
            && self.det().is_finite()
    }

    /// A tin built in lattice coordinates, in world coordinates: vertices
    /// mapped by [`Lattice::centre`], triangles kept counter-clockwise (two
    /// corners swapped when the map flips, with their neighbour links),
    /// bounding box and grid indexes recomputed. Topology, parents and
    /// children are unchanged.
    pub fn to_world(&self, mut tin: Tin) -> Tin {
        for v in tin.verts.iter_mut() {
            let (x, y) = self.centre(v[0], v[1]);
            v[0] = x;
            v[1] = y;
        }
        if self.flips() {
            for lv in tin.levels.iter_mut() {
                for (t, n) in lv.tris.iter_mut().zip(lv.nbrs.iter_mut()) {
                    t.swap(1, 2);
                    n.swap(1, 2);
                }
            }
        }
        tin.bbox = Bbox::of(&tin.verts);
        for l in 0..tin.levels.len() {
            let g = grid::build_grid(&tin.verts, &tin.bbox, &tin.levels[l]);
            tin.levels[l].grid = g;
        }
        tin
    }
}

/// A raster's georeference as its pixel lattice (an inherent impl kept
/// here, with [`Lattice`], so `io` needs nothing of `tin`).
impl GeoTransform {
    /// Centre of pixel (col, row) ([`Lattice::centre`], the one formula).
    pub fn centre(&self, col: usize, row: usize) -> (f64, f64) {
        self.lattice().centre(col as f64, row as f64)
    }

    /// The pixel lattice this geotransform maps to the world.
    pub fn lattice(&self) -> Lattice {
        Lattice {
            ip_x: self.ip_x,
            ip_y: self.ip_y,
            scale_x: self.scale_x,
            scale_y: self.scale_y,
            skew_x: self.skew_x,
            skew_y: self.skew_y,
        }
    }
}
