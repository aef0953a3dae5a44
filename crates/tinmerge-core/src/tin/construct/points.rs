//! Scattered samples as engine 2's source (`tin_from_points`): the
//! samples in a triangle come from their buckets ([`SampleGrid`]), and the
//! surface between them is their Delaunay triangulation
//! ([`DelaunayReference`]), whose edges are the segments a level's edges
//! are measured at where they cross them.

use super::measure::{Fix, Plane, Source, Worst};
use super::mesh::NONE;
use crate::geom::{is_sliver, left_or_on_rounded, max_abs_xy};
use crate::tin::TinError;
use crate::tin::build::common::convex_hull;
use crate::tin::delaunay_ref::DelaunayReference;
use crate::tin::samples::SampleGrid;

/// Samples bucketed, numbered in their buckets' order, and their Delaunay
/// triangulation.
pub(super) struct Scattered {
    grid: SampleGrid,
    reference: DelaunayReference,
    hull: Vec<u32>,
}

impl Scattered {
    /// `samples`: [`crate::tin::build::prepare_samples`]'s (finite,
    /// distinct in x, y, sorted by x then y).
    pub(super) fn new(samples: Vec<[f64; 3]>) -> Result<Scattered, TinError> {
        if samples.len() < 3 {
            return Err(TinError::Degenerate(format!(
                "need at least 3 samples with distinct x,y to build a tin, got {}",
                samples.len()
            )));
        }
        let mut hull: Vec<[f64; 3]> = convex_hull(&samples)
            .into_iter()
            .map(|k| samples[k])
            .collect();
        // a corner on the line of its neighbours up to rounding (pixel
        // centres along a geographic grid's diagonal, harness seed 98240)
        // would make the first triangles slivers: left to be inserted
        // later, on the side the neighbours make
        while hull.len() > 3 {
            let n = hull.len();
            let Some(k) =
                (0..n).find(|&k| is_sliver(&hull[(k + n - 1) % n], &hull[k], &hull[(k + 1) % n]))
            else {
                break;
            };
            hull.remove(k);
        }
        if hull.len() < 3 || (hull.len() == 3 && is_sliver(&hull[0], &hull[1], &hull[2])) {
            return Err(TinError::Degenerate(
                "all samples are collinear: a tin needs at least 3 non-collinear samples".into(),
            ));
        }
        let grid = SampleGrid::new(samples, 2.0);
        let hull = hull
            .iter()
            .map(|p| grid.find(p[0], p[1]).map(|i| i as u32))
            .collect::<Option<Vec<u32>>>()
            .ok_or_else(|| TinError::Internal("lost a hull corner in its bucket".into()))?;
        let reference = DelaunayReference::new(&grid.pts)?;
        if reference.num_samples() != grid.pts.len() {
            return Err(TinError::Internal(format!(
                "the samples' Delaunay triangulation holds {} of {} samples",
                reference.num_samples(),
                grid.pts.len()
            )));
        }
        Ok(Scattered {
            grid,
            reference,
            hull,
        })
    }
}

impl Source for Scattered {
    fn count(&self) -> usize {
        self.grid.pts.len()
    }

    fn point(&self, id: u32) -> [f64; 3] {
        self.grid.pts[id as usize]
    }

    fn hull(&self) -> Result<Vec<u32>, TinError> {
        Ok(self.hull.clone())
    }

    fn worst_sample(&self, c: &[[f64; 3]; 3], vid: &[u32]) -> Worst {
        let plane = Plane::of(c);
        let mut worst = Worst::NONE;
        // in the triangle up to rounding, as a raster band's centres are:
        // a sample a rounding outside the hull's side that a sample on it
        // up to rounding made (`Greedy::locate`) is still measured
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in c {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let pad = 1e-12 * max_abs_xy(&c[0], &c[1], &c[2]);
        let inside = |p: &[f64; 3]| (0..3).all(|k| left_or_on_rounded(&c[k], &c[(k + 1) % 3], p));
        let (x0, y0, x1, y1) = (lo[0] - pad, lo[1] - pad, hi[0] + pad, hi[1] + pad);
        self.grid.for_each_in_box(x0, y0, x1, y1, |i, p| {
            if vid[i] != NONE || !inside(p) {
                return;
            }
            let e = (p[2] - plane.z(p[0], p[1])).abs();
            if e > worst.err {
                worst = Worst {
                    err: e,
                    fix: Fix::Sample(i as u32),
                };
            }
        });
        worst
    }

    /// The crossing walked again: the point the walk measured, found by
    /// its ends (a line crosses a segment once).
    fn crossing_point(&self, p: &[f64; 3], q: &[f64; 3], a: u32, b: u32) -> Option<[f64; 3]> {
        let mut found = None;
        self.reference.for_each_crossing_of(p, q, &mut |x, ends| {
            if ends == [a as usize, b as usize] {
                found = Some(x.p);
            }
        });
        found
    }

    fn worst_crossing(&self, p: &[f64; 3], q: &[f64; 3]) -> Worst {
        let mut worst = Worst::NONE;
        self.reference.for_each_crossing_of(p, q, &mut |x, ends| {
            // through a sample up to rounding: that sample, measured as
            // itself (a vertex there would stand beside it)
            if is_sliver(p, q, &x.seg[0]) || is_sliver(p, q, &x.seg[1]) {
                return;
            }
            let e = x.error(p, q);
            if e > worst.err {
                worst = Worst {
                    err: e,
                    fix: Fix::Crossing {
                        k: 0,
                        a: ends[0] as u32,
                        b: ends[1] as u32,
                    },
                };
            }
        });
        worst
    }
}
