//! `tin_from_raster`'s build of a whole raster band ([`build_raster`]):
//! which of the builds it is (on the pixel lattice over the valid pixels'
//! hull, or in world coordinates over their squares, a boundary or with
//! breaklines), the footprint of the valid pixels and the heights in place,
//! decided here once for the SQL function and for the tests that check it.

use super::{
    boundary_holds_all, build_domain_raster, domain_raster_build_bytes, lattice_build_bytes,
};
use crate::interrupt::Interrupt;
use crate::polygon::Area;
use crate::tin::breaklines::Breakline;
use crate::tin::dense::Dense;
use crate::tin::domain::{cell_outline, outline_area};
use crate::tin::lattice::Lattice;
use crate::tin::{Tin, TinError};

/// One raster band: its heights row by row (`NaN` where it has no data),
/// its size in pixels and its pixel lattice.
pub struct RasterBand {
    pub z: Vec<f64>,
    pub width: usize,
    pub height: usize,
    pub lattice: Lattice,
}

impl RasterBand {
    /// The valid pixels' own squares (holes included) as a boundary, when
    /// they leave out part of the valid pixel centres' hull (the band has
    /// nodata beside its data); None when a build over the hull is a
    /// build over the valid pixels.
    pub fn footprint(&self) -> Option<Area> {
        self.footprint_of(&self.world_samples())
    }

    /// [`RasterBand::footprint`] given the band's samples in world
    /// coordinates ([`RasterBand::world_samples`]).
    fn footprint_of(&self, pts: &[[f64; 3]]) -> Option<Area> {
        let (w, h, z) = (self.width, self.height, &self.z);
        if z.iter().all(|v| !v.is_nan()) {
            return None;
        }
        let rings = cell_outline(w, h, &|c, r| !z[r * w + c].is_nan());
        let area = outline_area(&rings, &|c, r| {
            let (x, y) = self.lattice.centre(c - 0.5, r - 0.5);
            [x, y]
        });
        (!boundary_holds_all(&area, pts)).then_some(area)
    }

    /// The valid pixels as samples in world coordinates, row by row.
    fn world_samples(&self) -> Vec<[f64; 3]> {
        let w = self.width;
        (0..self.z.len())
            .filter(|&i| !self.z[i].is_nan())
            .map(|i| {
                let (x, y) = self.lattice.centre((i % w) as f64, (i / w) as f64);
                [x, y, self.z[i]]
            })
            .collect()
    }

    /// The valid pixels as lattice samples `(col, row, z)`, row by row.
    pub fn samples(&self) -> Vec<[f64; 3]> {
        let w = self.width;
        (0..self.z.len())
            .filter(|&i| !self.z[i].is_nan())
            .map(|i| [(i % w) as f64, (i / w) as f64, self.z[i]])
            .collect()
    }
}

/// What a raster build adds to the band: breaklines, a boundary (in the
/// raster's coordinates) and whether it fills the gaps between the valid
/// pixels (the samples' hull) or keeps to the valid pixels' squares.
pub struct RasterBuild<'a> {
    pub lines: &'a [Breakline],
    pub boundary: Option<Area>,
    pub fill_gaps: bool,
}

/// The build of `tin_from_raster` (without `keep_border`), in world
/// coordinates: on the pixel lattice (build engine 2,
/// [`crate::tin::construct::build_band`], between the samples) when it
/// covers the hull of the valid pixels (no nodata, or `fill_gaps`) and has
/// no lines or boundary that leaves out a sample;
/// otherwise over the valid pixels' squares (holes included), the boundary
/// and the lines in world coordinates ([`build_domain_raster`]).
/// `reserve(samples, bytes)` is told the build's memory estimate before it
/// starts (the SQL layer's `tinmerge.max_memory`). An error for a band
/// without valid pixels.
pub fn build_raster(
    band: RasterBand,
    with: RasterBuild<'_>,
    tolerances: &[f64],
    srid: i32,
    reserve: &mut dyn FnMut(usize, usize) -> Result<(), TinError>,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    let (w, h, lattice) = (band.width, band.height, band.lattice);
    let valid = band.z.iter().filter(|v| !v.is_nan()).count();
    if valid == 0 {
        return Err(TinError::InvalidParameter(
            "the band has no valid pixels (every pixel is nodata)".into(),
        ));
    }
    let mut on_lattice =
        |band: RasterBand, reserve: &mut dyn FnMut(usize, usize) -> Result<(), TinError>| {
            reserve(valid, lattice_build_bytes(valid, tolerances.len(), true))?;
            crate::tin::construct::build_band(
                &band.z,
                band.width,
                band.height,
                &lattice,
                tolerances,
                srid,
                interrupt,
            )
        };
    let RasterBuild {
        lines,
        boundary,
        fill_gaps,
    } = with;
    if lines.is_empty() && boundary.is_none() && (fill_gaps || valid == w * h) {
        return on_lattice(band, reserve);
    }
    let pts = band.world_samples();
    let footprint = if fill_gaps {
        None
    } else {
        band.footprint_of(&pts)
    };
    // a boundary holding the whole raster: the build without it
    let areas: Vec<Area> = boundary
        .into_iter()
        .filter(|a| !boundary_holds_all(a, &pts))
        .chain(footprint)
        .collect();
    if lines.is_empty() && areas.is_empty() {
        drop(pts);
        return on_lattice(band, reserve);
    }
    reserve(
        pts.len(),
        domain_raster_build_bytes(pts.len(), w * h, tolerances.len()),
    )?;
    let heights = Dense {
        c0: 0,
        r0: 0,
        width: w,
        height: h,
        z: band.z,
    };
    let areas: Vec<&Area> = areas.iter().collect();
    build_domain_raster(
        pts, lines, &areas, tolerances, srid, &heights, &lattice, interrupt,
    )
}
