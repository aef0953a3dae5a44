//! Overview rasters that cover their data.
//!
//! PostGIS makes an overview (`ST_CreateOverview`, `raster2pgsql -l`) by
//! resampling: each of its pixels takes the value of one pixel of the finer
//! raster (nearest neighbour by default). Along the edge of the data, an
//! overview pixel whose chosen finer pixel is nodata is nodata, though
//! finer pixels under it hold data: a tin built over the overview's valid
//! pixels then leaves a ring of the data uncovered, up to one overview
//! pixel wide. [`Cover`] gives each such pixel the mean of the valid finer
//! pixels whose centres lie in it, so the overview's valid pixels cover
//! every valid finer pixel (their squares nest when the grids are aligned,
//! as overviews are); pixels that were valid keep their values.
//!
//! ```
//! use tinmerge_core::io::raster::Band;
//! use tinmerge_core::tin::cover::Cover;
//! use tinmerge_core::tin::lattice::Lattice;
//! let l = |s: f64| Lattice { ip_x: 0.0, ip_y: 4.0, scale_x: s, scale_y: -s, skew_x: 0.0, skew_y: 0.0 };
//! // a 2 x 2 overview of a 4 x 4 raster, its top-left pixel nodata
//! let mut coarse = Band { pixel_type: 10, nodata: Some(-1.0), all_nodata: false, values: vec![-1.0, 5.0, 5.0, 5.0] };
//! let mut fine = vec![-1.0; 16];
//! fine[1] = 10.0; // row 0, column 1: under the coarse top-left pixel
//! fine[4] = 20.0; // row 1, column 0: too
//! let fine = Band { pixel_type: 10, nodata: Some(-1.0), all_nodata: false, values: fine };
//! let mut cover = Cover::new(&l(2.0), 2, 2).unwrap();
//! cover.add(&l(1.0), 4, 4, &fine);
//! assert_eq!(cover.apply(&mut coarse), 1);
//! assert_eq!(coarse.values, [15.0, 5.0, 5.0, 5.0]);
//! ```

use super::lattice::Lattice;
use crate::io::raster::Band;

/// The sums and counts of valid finer pixels falling in each pixel of one
/// overview tile, gathered from as many finer tiles as meet it.
pub struct Cover {
    lattice: Lattice,
    width: usize,
    height: usize,
    sum: Vec<f64>,
    count: Vec<u32>,
}

impl Cover {
    /// An empty cover of a `width x height` overview tile on `lattice`;
    /// None when the lattice is degenerate.
    pub fn new(lattice: &Lattice, width: usize, height: usize) -> Option<Cover> {
        if !lattice.is_valid() {
            return None;
        }
        let n = width.checked_mul(height)?;
        Some(Cover {
            lattice: *lattice,
            width,
            height,
            sum: vec![0.0; n],
            count: vec![0; n],
        })
    }

    /// Whether a band has a pixel that is not data (so it may need a cover).
    pub fn needed(band: &Band) -> bool {
        band.all_nodata || band.values.iter().any(|&v| !band.is_valid(v))
    }

    /// The overview pixel (column, row) holding world point (x, y), if any.
    fn pixel_of(&self, x: f64, y: f64) -> Option<usize> {
        let l = &self.lattice;
        let (dx, dy) = (x - l.ip_x, y - l.ip_y);
        let det = l.det();
        let c = ((dx * l.scale_y - dy * l.skew_x) / det).floor();
        let r = ((l.scale_x * dy - l.skew_y * dx) / det).floor();
        if c < 0.0 || r < 0.0 || c >= self.width as f64 || r >= self.height as f64 {
            return None;
        }
        Some(r as usize * self.width + c as usize)
    }

    /// Count the valid pixels of a finer `width x height` raster tile on
    /// `lattice` into the overview pixels their centres fall in.
    pub fn add(&mut self, lattice: &Lattice, width: usize, height: usize, band: &Band) {
        if band.all_nodata || band.values.len() != width.saturating_mul(height) {
            return;
        }
        for r in 0..height {
            for c in 0..width {
                let v = band.values[r * width + c];
                if !band.is_valid(v) {
                    continue;
                }
                let (x, y) = lattice.centre(c as f64, r as f64);
                if let Some(k) = self.pixel_of(x, y) {
                    self.sum[k] += v;
                    self.count[k] += 1;
                }
            }
        }
    }

    /// Give each pixel of `band` (the overview tile) that is not data, but
    /// has valid finer pixels in it, their mean; returns how many pixels
    /// were given one. A band flagged all nodata loses the flag when one is
    /// given (its other pixels become NaN, which is not data either).
    pub fn apply(self, band: &mut Band) -> usize {
        if band.values.len() != self.sum.len() {
            return 0;
        }
        let mut filled = 0;
        let was_all = band.all_nodata;
        for (k, v) in band.values.iter_mut().enumerate() {
            if (was_all || !band_valid(band.nodata, *v)) && self.count[k] > 0 {
                let mean = self.sum[k] / self.count[k] as f64;
                // a mean that happens to be the nodata value is one ulp off
                *v = if band.nodata == Some(mean) {
                    mean.next_up()
                } else {
                    mean
                };
                filled += 1;
            }
        }
        if was_all && filled > 0 {
            band.all_nodata = false;
            for (k, v) in band.values.iter_mut().enumerate() {
                if self.count[k] == 0 {
                    *v = f64::NAN;
                }
            }
        }
        filled
    }
}

/// [`Band::is_valid`] without the band (its values are being changed).
fn band_valid(nodata: Option<f64>, v: f64) -> bool {
    !v.is_nan() && nodata != Some(v)
}
