//! Source samples bucketed on a regular grid, so that the samples inside a
//! triangle can be enumerated by scanning only the buckets it overlaps.

use robust::{Coord, orient2d};

/// Where a build's samples come from: the bucketed scattered samples
/// ([`SampleGrid`]) or a window of a raster's pixel lattice
/// ([`super::dense::DenseWindow`]). Samples are numbered `0..len()`.
pub trait Samples: Sync {
    /// Number of sample slots (a window's nodata pixels included).
    fn len(&self) -> usize;
    /// Whether there are no sample slots.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Sample `i`: x, y, z.
    fn point(&self, i: usize) -> [f64; 3];
    /// Area holding about one sample.
    fn cell_area(&self) -> f64;
    /// The sample at exactly `(x, y)`, if there is one.
    fn find(&self, x: f64, y: f64) -> Option<usize>;
    /// Calls `f(index, sample)` for every sample in the closed triangle
    /// `a, b, c` (counter-clockwise), decided exactly.
    fn for_each_in_triangle(
        &self,
        a: &[f64; 3],
        b: &[f64; 3],
        c: &[f64; 3],
        f: impl FnMut(usize, &[f64; 3]),
    );
}

impl Samples for SampleGrid {
    fn len(&self) -> usize {
        self.pts.len()
    }
    fn point(&self, i: usize) -> [f64; 3] {
        self.pts[i]
    }
    fn cell_area(&self) -> f64 {
        SampleGrid::cell_area(self)
    }
    fn find(&self, x: f64, y: f64) -> Option<usize> {
        SampleGrid::find(self, x, y)
    }
    fn for_each_in_triangle(
        &self,
        a: &[f64; 3],
        b: &[f64; 3],
        c: &[f64; 3],
        f: impl FnMut(usize, &[f64; 3]),
    ) {
        SampleGrid::for_each_in_triangle(self, a, b, c, f)
    }
}

/// Samples sorted into square buckets (CSR layout). Indices used by callers
/// refer to the bucket-sorted order in [`SampleGrid::pts`]; `ids`, when
/// given ([`SampleGrid::with_ids`]), is each sample's number in the
/// caller's own numbering, in the same order.
pub struct SampleGrid {
    pub pts: Vec<[f64; 3]>,
    pub ids: Vec<u32>,
    ox: f64,
    oy: f64,
    cell: f64,
    nx: usize,
    ny: usize,
    start: Vec<u32>,
}

#[inline]
pub(crate) fn c2(p: &[f64; 3]) -> Coord<f64> {
    Coord { x: p[0], y: p[1] }
}

impl SampleGrid {
    /// Bucket `pts` (finite, at least one) with about `per_bucket` samples
    /// per bucket, sorted in place (no copy of the samples is made).
    pub fn new(pts: Vec<[f64; 3]>, per_bucket: f64) -> SampleGrid {
        SampleGrid::with_ids(pts, Vec::new(), per_bucket)
    }

    /// [`SampleGrid::new`] carrying a number for each sample (`ids`, as
    /// long as `pts`, or empty), permuted with it.
    pub fn with_ids(mut pts: Vec<[f64; 3]>, mut ids: Vec<u32>, per_bucket: f64) -> SampleGrid {
        let b = super::Bbox::of(&pts);
        let w = (b.max_x - b.min_x).max(0.0);
        let h = (b.max_y - b.min_y).max(0.0);
        let n = pts.len().max(1) as f64;
        let mut cell = ((w * h) * per_bucket / n).sqrt();
        if !(cell.is_finite() && cell > 0.0) {
            cell = (w.max(h) / n).max(1e-9);
        }
        // Keep the bucket count proportional to the sample count.
        let max_buckets = (4.0 * n + 16.0).min(1e8);
        while ((w / cell).floor() + 1.0) * ((h / cell).floor() + 1.0) > max_buckets {
            cell *= 1.5;
        }
        let nx = (w / cell).floor() as usize + 1;
        let ny = (h / cell).floor() as usize + 1;
        let mut g = SampleGrid {
            pts: Vec::new(),
            ids: Vec::new(),
            ox: b.min_x,
            oy: b.min_y,
            cell,
            nx,
            ny,
            start: vec![0; nx * ny + 1],
        };
        for p in &pts {
            let k = g.bucket_of(p[0], p[1]);
            g.start[k + 1] += 1;
        }
        for i in 0..nx * ny {
            g.start[i + 1] += g.start[i];
        }
        // in-place counting sort: each sample swapped straight to the next
        // free place of its bucket
        let with_ids = ids.len() == pts.len() && !ids.is_empty();
        let mut fill: Vec<u32> = g.start[..nx * ny].to_vec();
        for k in 0..nx * ny {
            let end = g.start[k + 1];
            while fill[k] < end {
                let i = fill[k] as usize;
                let kk = g.bucket_of(pts[i][0], pts[i][1]);
                if kk == k {
                    fill[k] += 1;
                } else {
                    let j = fill[kk] as usize;
                    pts.swap(i, j);
                    if with_ids {
                        ids.swap(i, j);
                    }
                    fill[kk] += 1;
                }
            }
        }
        g.pts = pts;
        g.ids = if with_ids { ids } else { Vec::new() };
        g
    }

    /// The sample at exactly `(x, y)`, if there is one.
    pub fn find(&self, x: f64, y: f64) -> Option<usize> {
        let k = self.bucket_of(x, y);
        let (s, e) = (self.start[k] as usize, self.start[k + 1] as usize);
        (s..e).find(|&i| self.pts[i][0] == x && self.pts[i][1] == y)
    }

    /// Calls `f(index, sample)` for every sample in the closed box
    /// `x0..=x1`, `y0..=y1`.
    pub(crate) fn for_each_in_box(
        &self,
        x0: f64,
        y0: f64,
        x1: f64,
        y1: f64,
        mut f: impl FnMut(usize, &[f64; 3]),
    ) {
        if !(x0 <= x1 && y0 <= y1) {
            return;
        }
        let (c0, c1) = (self.col(x0), self.col(x1));
        for r in self.row(y0)..=self.row(y1) {
            let s = self.start[r * self.nx + c0] as usize;
            let e = self.start[r * self.nx + c1 + 1] as usize;
            for (i, p) in self.pts[s..e].iter().enumerate() {
                if p[0] >= x0 && p[0] <= x1 && p[1] >= y0 && p[1] <= y1 {
                    f(s + i, p);
                }
            }
        }
    }

    #[inline]
    fn col(&self, x: f64) -> usize {
        let c = ((x - self.ox) / self.cell).floor();
        if c <= 0.0 {
            0
        } else {
            (c as usize).min(self.nx - 1)
        }
    }

    #[inline]
    fn row(&self, y: f64) -> usize {
        let r = ((y - self.oy) / self.cell).floor();
        if r <= 0.0 {
            0
        } else {
            (r as usize).min(self.ny - 1)
        }
    }

    #[inline]
    fn bucket_of(&self, x: f64, y: f64) -> usize {
        self.row(y) * self.nx + self.col(x)
    }

    /// Area of one bucket (about one sample each).
    pub(crate) fn cell_area(&self) -> f64 {
        self.cell * self.cell
    }

    /// Calls `f(index, sample)` for every sample in the closed triangle
    /// `a, b, c` (counter-clockwise), decided with exact predicates.
    pub fn for_each_in_triangle(
        &self,
        a: &[f64; 3],
        b: &[f64; 3],
        c: &[f64; 3],
        mut f: impl FnMut(usize, &[f64; 3]),
    ) {
        let (ca, cb, cc) = (c2(a), c2(b), c2(c));
        let ymin = a[1].min(b[1]).min(c[1]);
        let ymax = a[1].max(b[1]).max(c[1]);
        let (r0, r1) = (self.row(ymin), self.row(ymax));
        let corners = [a, b, c];
        for r in r0..=r1 {
            // x-extent of the triangle within this row's band (slightly widened
            // so rounding never drops a bucket; membership is decided exactly).
            let lo = self.oy + r as f64 * self.cell;
            let hi = lo + self.cell;
            let (blo, bhi) = (lo.max(ymin), hi.min(ymax));
            let mut xmin = f64::INFINITY;
            let mut xmax = f64::NEG_INFINITY;
            for p in corners {
                if p[1] >= blo && p[1] <= bhi {
                    xmin = xmin.min(p[0]);
                    xmax = xmax.max(p[0]);
                }
            }
            for i in 0..3 {
                let p = corners[i];
                let q = corners[(i + 1) % 3];
                for yy in [blo, bhi] {
                    if (p[1] - yy) * (q[1] - yy) <= 0.0 && p[1] != q[1] {
                        let t = (yy - p[1]) / (q[1] - p[1]);
                        let x = p[0] + t * (q[0] - p[0]);
                        xmin = xmin.min(x);
                        xmax = xmax.max(x);
                    }
                }
            }
            if xmin > xmax {
                // Band touched only through rounding: fall back to the bbox.
                xmin = a[0].min(b[0]).min(c[0]);
                xmax = a[0].max(b[0]).max(c[0]);
            }
            let pad = self.cell * 1e-9;
            let (c0, c1) = (self.col(xmin - pad), self.col(xmax + pad));
            let s = self.start[r * self.nx + c0] as usize;
            let e = self.start[r * self.nx + c1 + 1] as usize;
            for (i, p) in self.pts[s..e].iter().enumerate() {
                let cp = c2(p);
                if orient2d(ca, cb, cp) >= 0.0
                    && orient2d(cb, cc, cp) >= 0.0
                    && orient2d(cc, ca, cp) >= 0.0
                {
                    f(s + i, p);
                }
            }
        }
    }
}
