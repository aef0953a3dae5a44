//! Samples kept from the greedy refinement and made vertices in an order
//! of their own: a kept hull side's ([`super::super::kept`]).

use super::super::measure::{Fix, RESERVED, Source};
use super::super::mesh::NONE;
use super::Greedy;
use crate::tin::TinError;

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
    /// a triangle nearly flat, the segment is left stuck: a triangle whose worst it is
    /// is not queued, and the tile asks for the sample
    /// ([`crate::tin::tile::Wanted`]).
    pub(super) fn split_beside_kept(&mut self, h: u32, a: u32, b: u32) -> Result<(), TinError> {
        let x = self.measured_crossing(h, a, b)?;
        if self.thin_split(h, &x, true) {
            self.stuck.insert((a, b));
            return Ok(());
        }
        self.split_edge_at(h, x).map(|_| ())
    }

    /// Whether `fix` is a crossing of a stuck segment.
    pub(super) fn is_stuck(&self, fix: &Fix) -> bool {
        match fix {
            Fix::Crossing { a, b, .. } => !self.stuck.is_empty() && self.stuck.contains(&(*a, *b)),
            _ => false,
        }
    }
}
