//! A raster band's samples as they come: heights on the pixel lattice,
//! row-major, NaN where there is no data. A build on the lattice reads them
//! in place through windows ([`DenseWindow`]): the samples inside a
//! triangle are found row by row with exact integer arithmetic (a pixel
//! centre is inside the closed triangle iff it is on the inner side of or
//! on each edge, decided by `floor`/`ceil` of exact rationals), and the
//! samples on a segment between two pixel centres are the lattice points
//! at its gcd steps. Eight bytes a pixel, against about 30 a sample for
//! bucketed scattered samples, and no predicate per sample.
//!
//! ```
//! use tinmerge_core::tin::dense::Dense;
//! use tinmerge_core::tin::samples::Samples;
//! // 4 x 3 pixels, one without data
//! let mut z = vec![1.0; 12];
//! z[5] = f64::NAN;
//! let d = Dense { c0: 10, r0: 20, width: 4, height: 3, z };
//! let w = d.window(10, 20, 4, 3);
//! let mut inside = Vec::new();
//! // the closed triangle (10,20) (13,20) (10,22) holds 4 + 2 + 1 pixel
//! // centres, one of them (11,21) without data
//! w.for_each_in_triangle(&[10.0, 20.0, 0.0], &[13.0, 20.0, 0.0], &[10.0, 22.0, 0.0], |_, p| {
//!     inside.push((p[0], p[1]));
//! });
//! assert_eq!(inside, [(10.0, 20.0), (11.0, 20.0), (12.0, 20.0), (13.0, 20.0), (10.0, 21.0), (10.0, 22.0)]);
//! // the samples strictly between (10,20) and (13,20)
//! let mut on = Vec::new();
//! d.on_segment(d.index(10, 20), d.index(13, 20), &mut on);
//! assert_eq!(on, [d.index(11, 20), d.index(12, 20)]);
//! ```

use super::samples::Samples;

/// Heights on the pixel lattice: pixel `(col, row)` of the window
/// `c0 .. c0 + width`, `r0 .. r0 + height` is `z[(row - r0) * width + col - c0]`,
/// NaN without data.
pub struct Dense {
    pub c0: i64,
    pub r0: i64,
    pub width: usize,
    pub height: usize,
    pub z: Vec<f64>,
}

impl Dense {
    /// The column and row of sample `i`.
    #[inline]
    pub(crate) fn col_row(&self, i: usize) -> (i64, i64) {
        (
            self.c0 + (i % self.width) as i64,
            self.r0 + (i / self.width) as i64,
        )
    }

    /// The sample at column `c`, row `r` (inside the window).
    #[inline]
    pub fn index(&self, c: i64, r: i64) -> usize {
        (r - self.r0) as usize * self.width + (c - self.c0) as usize
    }

    /// Whether sample `i` has data.
    #[inline]
    pub fn valid(&self, i: usize) -> bool {
        !self.z[i].is_nan()
    }

    /// A window of the lattice: columns `c0 .. c0 + w`, rows `r0 .. r0 + h`
    /// (inside this one).
    pub fn window(&self, c0: i64, r0: i64, w: usize, h: usize) -> DenseWindow<'_> {
        DenseWindow {
            d: self,
            c0,
            r0,
            width: w,
            height: h,
        }
    }

    /// Sample `i`'s column, row and height.
    #[inline]
    pub fn point(&self, i: usize) -> [f64; 3] {
        let (c, r) = self.col_row(i);
        [c as f64, r as f64, self.z[i]]
    }

    /// The samples with data strictly between samples `a` and `b` on the
    /// segment joining them, from `a` towards `b`, pushed to `out`.
    pub fn on_segment(&self, a: usize, b: usize, out: &mut Vec<usize>) {
        let ((ca, ra), (cb, rb)) = (self.col_row(a), self.col_row(b));
        let (dc, dr) = (cb - ca, rb - ra);
        let g = gcd(dc.unsigned_abs(), dr.unsigned_abs()) as i64;
        for k in 1..g {
            let i = self.index(ca + dc / g * k, ra + dr / g * k);
            if self.valid(i) {
                out.push(i);
            }
        }
    }

    /// The samples with data on the segment between samples `a` and `b`,
    /// both ends included, in the segment's canonical order (from its end
    /// smaller in (column, row)), as the builds order a hull side's
    /// samples: a hull side or a parent's side, planned from its own
    /// samples.
    pub fn side(&self, a: usize, b: usize) -> Vec<usize> {
        let mut side = vec![a];
        self.on_segment(a, b, &mut side);
        side.push(b);
        if self.col_row(b) < self.col_row(a) {
            side.reverse();
        }
        side
    }
}

fn gcd(mut a: u64, mut b: u64) -> u64 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// A rectangle of a [`Dense`] lattice with its own sample numbers (row-major
/// in the rectangle), so a build on it sizes its flags by the rectangle.
pub struct DenseWindow<'a> {
    pub d: &'a Dense,
    pub c0: i64,
    pub r0: i64,
    pub width: usize,
    pub height: usize,
}

impl DenseWindow<'_> {
    /// The [`Dense`] sample of this window's sample `i`.
    #[inline]
    pub fn global(&self, i: usize) -> usize {
        let (c, r) = (
            self.c0 + (i % self.width) as i64,
            self.r0 + (i / self.width) as i64,
        );
        self.d.index(c, r)
    }

    /// This window's sample of the [`Dense`] sample `g` (inside it).
    #[inline]
    pub fn local(&self, g: usize) -> usize {
        let (c, r) = self.d.col_row(g);
        (r - self.r0) as usize * self.width + (c - self.c0) as usize
    }
}

/// `floor(n / d)` and `ceil(n / d)` for `d > 0`.
#[inline]
fn floor_div(n: i128, d: i128) -> i128 {
    n.div_euclid(d)
}
#[inline]
fn ceil_div(n: i128, d: i128) -> i128 {
    -(-n).div_euclid(d)
}

impl Samples for DenseWindow<'_> {
    fn len(&self) -> usize {
        self.width * self.height
    }

    fn point(&self, i: usize) -> [f64; 3] {
        self.d.point(self.global(i))
    }

    fn cell_area(&self) -> f64 {
        1.0
    }

    fn find(&self, x: f64, y: f64) -> Option<usize> {
        let (c, r) = (x as i64, y as i64);
        if c as f64 != x
            || r as f64 != y
            || c < self.c0
            || r < self.r0
            || c >= self.c0 + self.width as i64
            || r >= self.r0 + self.height as i64
        {
            return None;
        }
        let i = (r - self.r0) as usize * self.width + (c - self.c0) as usize;
        self.d.valid(self.global(i)).then_some(i)
    }

    fn for_each_in_triangle(
        &self,
        a: &[f64; 3],
        b: &[f64; 3],
        c: &[f64; 3],
        mut f: impl FnMut(usize, &[f64; 3]),
    ) {
        // corners are pixel centres: whole numbers, exactly
        let v = [a, b, c].map(|p| (p[0] as i128, p[1] as i128));
        let (wc0, wr0) = (self.c0 as i128, self.r0 as i128);
        let (wc1, wr1) = (wc0 + self.width as i128 - 1, wr0 + self.height as i128 - 1);
        let ymin = v.iter().map(|p| p.1).min().unwrap_or(0).max(wr0);
        let ymax = v.iter().map(|p| p.1).max().unwrap_or(-1).min(wr1);
        let xmin = v.iter().map(|p| p.0).min().unwrap_or(0).max(wc0);
        let xmax = v.iter().map(|p| p.0).max().unwrap_or(-1).min(wc1);
        for y in ymin..=ymax {
            // each edge p -> q (counter-clockwise) keeps the side where
            // (q - p) x (s - p) >= 0: dx (y - py) - dy (x - px) >= 0
            let (mut lo, mut hi) = (xmin, xmax);
            for k in 0..3 {
                let (p, q) = (v[k], v[(k + 1) % 3]);
                let (dx, dy) = (q.0 - p.0, q.1 - p.1);
                let rhs = dx * (y - p.1); // dy (x - px) <= rhs
                if dy > 0 {
                    hi = hi.min(p.0 + floor_div(rhs, dy));
                } else if dy < 0 {
                    lo = lo.max(p.0 + ceil_div(-rhs, -dy));
                } else if rhs < 0 {
                    lo = hi + 1;
                }
            }
            if lo > hi {
                continue;
            }
            let row = (y - wr0) as usize * self.width;
            let grow = self.d.index(lo as i64, y as i64);
            for (k, x) in (lo..=hi).enumerate() {
                let z = self.d.z[grow + k];
                if !z.is_nan() {
                    f(row + (x - wc0) as usize, &[x as f64, y as f64, z]);
                }
            }
        }
    }
}
