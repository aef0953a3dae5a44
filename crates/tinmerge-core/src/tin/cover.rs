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
//! A tin stops short of its pixels' squares: over the hull of its samples
//! at its outer pixel centres, up to half an overview pixel short of
//! finer data in the same pixel. So [`Cover::apply`] also gives every
//! pixel with no data under it, but finer data under one of its eight
//! neighbours, the mean of the valid finer pixels under the 3 x 3 pixels
//! around it. Then every overview pixel holding finer data has its eight
//! neighbours valid, and a tin over the valid pixels, over their hull or
//! their squares, covers its whole square. Every value given is a
//! function of the finer data alone, so two tiles of a seam give a pixel
//! they share the same value.
//!
//! ```
//! use tinmerge_core::io::raster::Band;
//! use tinmerge_core::tin::cover::Cover;
//! use tinmerge_core::tin::lattice::Lattice;
//! let l = |s: f64| Lattice { ip_x: 0.0, ip_y: 4.0, scale_x: s, scale_y: -s, skew_x: 0.0, skew_y: 0.0 };
//! // a 2 x 2 overview of a 4 x 4 raster, its top-left pixel nodata
//! let coarse = Band { pixel_type: 10, nodata: Some(-1.0), all_nodata: false, values: vec![-1.0, 5.0, 5.0, 5.0] };
//! let mut fine = vec![-1.0; 16];
//! fine[1] = 10.0; // row 0, column 1: under the coarse top-left pixel
//! fine[4] = 20.0; // row 1, column 0: too
//! let fine = Band { pixel_type: 10, nodata: Some(-1.0), all_nodata: false, values: fine };
//! let mut cover = Cover::new(&l(2.0), 2, 2).unwrap();
//! cover.add(&l(1.0), 4, 4, &fine);
//! let mut b = coarse.clone();
//! assert_eq!(cover.apply(&mut b), 1);
//! assert_eq!(b.values, [15.0, 5.0, 5.0, 5.0]);
//! // only the bottom-right finer pixel valid: the top-left overview pixel,
//! // nodata with no data under it, takes it: it is beside data
//! let mut fine = vec![-1.0; 16];
//! fine[15] = 7.0;
//! let fine = Band { values: fine, ..coarse.clone() };
//! let mut cover = Cover::new(&l(2.0), 2, 2).unwrap();
//! cover.add(&l(1.0), 4, 4, &fine);
//! let mut b = coarse.clone();
//! assert_eq!(cover.apply(&mut b), 1);
//! assert_eq!(b.values, [7.0, 5.0, 5.0, 5.0]);
//! ```

use super::lattice::Lattice;
use crate::io::raster::Band;

/// The sums and counts of valid finer pixels falling in each pixel of one
/// overview tile and of the ring of pixels around it, gathered from as
/// many finer tiles as meet them.
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
        let n = width.checked_add(2)?.checked_mul(height.checked_add(2)?)?;
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

    /// The index in the sums (the tile and its ring of pixels: pixel
    /// (column, row) at `(row + 1) * (width + 2) + column + 1`) of the
    /// pixel holding world point (x, y), if any.
    fn pixel_of(&self, x: f64, y: f64) -> Option<usize> {
        let (c, r) = self.lattice.index_of(x, y);
        let (c, r) = ((c + 0.5).floor() + 1.0, (r + 0.5).floor() + 1.0);
        if !(c >= 0.0 && r >= 0.0 && c < (self.width + 2) as f64 && r < (self.height + 2) as f64) {
            return None;
        }
        Some(r as usize * (self.width + 2) + c as usize)
    }

    /// Count the valid pixels of a finer `width x height` raster tile on
    /// `lattice` into the overview pixels their centres fall in (the
    /// tile's, and the ring around it).
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
    /// has valid finer pixels in it, their mean; each with no finer data
    /// in it but some under its 3 x 3 pixels, the mean of those. Returns how many pixels were given a value. A band
    /// flagged all nodata loses the flag when one is given (its other
    /// pixels become NaN, which is not data either).
    pub fn apply(self, band: &mut Band) -> usize {
        let (w, h) = (self.width, self.height);
        if band.values.len() != w * h {
            return 0;
        }
        let at = |c: usize, r: usize| (r + 1) * (w + 2) + c + 1;
        let mean_of = |ks: &mut dyn Iterator<Item = usize>| -> Option<f64> {
            let (mut s, mut n) = (0.0, 0u64);
            for k in ks {
                s += self.sum[k];
                n += u64::from(self.count[k]);
            }
            (n > 0).then(|| s / n as f64)
        };
        let mut filled = 0;
        let was_all = band.all_nodata;
        let mut given = vec![false; w * h];
        for r in 0..h {
            for c in 0..w {
                let v = &mut band.values[r * w + c];
                if !was_all && band_valid(band.nodata, *v) {
                    continue;
                }
                // rows r - 1 ..= r + 1 of the tile are r ..= r + 2 of the
                // sums, columns likewise
                let mut around =
                    (r..r + 3).flat_map(|rr| (c..c + 3).map(move |cc| rr * (w + 2) + cc));
                let Some(mean) =
                    mean_of(&mut std::iter::once(at(c, r))).or_else(|| mean_of(&mut around))
                else {
                    continue;
                };
                // a mean that happens to be the nodata value is one ulp off
                *v = if band.nodata == Some(mean) {
                    mean.next_up()
                } else {
                    mean
                };
                given[r * w + c] = true;
                filled += 1;
            }
        }
        if was_all && filled > 0 {
            band.all_nodata = false;
            for (k, v) in band.values.iter_mut().enumerate() {
                if !given[k] {
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
