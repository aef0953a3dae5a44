//! Samples kept from the greedy refinement and made vertices in an order
//! of their own: a kept hull side's ([`super::super::kept`]).

use super::super::measure::{Fix, RESERVED, Source};
use super::super::mesh::{NONE, next, prev};
use super::Greedy;
use crate::tin::TinError;

/// The smallest altitude (in pixels: a band is built in its lattice's
/// frame) a triangle made by splitting an edge beside a kept side may
/// have: a crossing nearer than that to a corner is left stuck, since a
/// vertex there would stand a hair from another one (the randomized
/// harness found one 5e-7 of a pixel from a sample on a 1/9" grid).
const MIN_ALTITUDE: f64 = 1e-4;

/// Triangle a, b, c's smallest altitude (twice its area over its longest
/// side); 0 for a degenerate one.
fn altitude(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> f64 {
    let cross = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
    let side = |u: &[f64; 3], v: &[f64; 3]| (u[0] - v[0]).hypot(u[1] - v[1]);
    let longest = side(a, b).max(side(b, c)).max(side(c, a));
    if longest > 0.0 {
        cross.abs() / longest
    } else {
        0.0
    }
}

impl<S: Source + ?Sized> Greedy<'_, S> {
    /// Keep samples `ids` from the greedy refinement: no vertex is made at
    /// them, and neither they nor the grid segments ending at them are
    /// measured ([`RESERVED`]), until [`Greedy::insert_kept`].
    pub(in crate::tin::construct) fn reserve(&mut self, ids: &[u32]) {
        for &id in ids {
            if self.vid[id as usize] == NONE {
                self.vid[id as usize] = RESERVED;
            }
        }
    }

    /// Make vertices of samples `ids` (on the hull, or reserved), in order,
    /// then measure every triangle again (what a reserved sample hid is
    /// measured now).
    pub(in crate::tin::construct) fn insert_kept(&mut self, ids: &[u32]) -> Result<(), TinError> {
        for &id in ids {
            let v = self.vid[id as usize];
            if v != NONE && v != RESERVED {
                continue;
            }
            if self.aligned && self.bisect_to(id)? {
                continue;
            }
            self.vid[id as usize] = NONE;
            self.insert_sample(0, id)?;
        }
        self.touched.clear();
        for t in 0..self.m.triangles() {
            self.rescan(t);
        }
        Ok(())
    }

    /// Mend edge `h`'s crossing of the grid segment from sample `a` to
    /// `b`, one of them reserved (a kept side's, no vertex may be made at
    /// it) and the other a vertex: split the edge where it crosses, the
    /// surface there exact (the segment from the reserved sample to that
    /// point is then within the side's error). Where that split would make
    /// a triangle nearly flat or smaller across than [`MIN_ALTITUDE`], the
    /// segment is left stuck: a triangle whose worst it is is not queued,
    /// and the tile asks for the sample ([`crate::tin::tile::Wanted`]).
    pub(super) fn split_beside_kept(&mut self, h: u32, a: u32, b: u32) -> Result<(), TinError> {
        let x = self.measured_crossing(h, a, b)?;
        if self.thin_split(h, &x, true) || self.small_split(h, &x) {
            self.stuck.insert((a, b));
            return Ok(());
        }
        self.split_edge_at(h, x).map(|_| ())
    }

    /// Whether splitting edge `h` at `p` would make a triangle (on either
    /// side) less than [`MIN_ALTITUDE`] across.
    fn small_split(&self, h: u32, p: &[f64; 3]) -> bool {
        let (a, b) = (self.m.at(h), self.m.at(next(h)));
        let small = |c: &[f64; 3]| altitude(a, p, c).min(altitude(p, b, c)) < MIN_ALTITUDE;
        let g = self.m.twin[h as usize];
        small(self.m.at(prev(h))) || (g != NONE && small(self.m.at(prev(g))))
    }

    /// Whether `fix` is a crossing of a stuck segment.
    pub(super) fn is_stuck(&self, fix: &Fix) -> bool {
        match fix {
            Fix::Crossing { a, b, .. } => !self.stuck.is_empty() && self.stuck.contains(&(*a, *b)),
            _ => false,
        }
    }
}
