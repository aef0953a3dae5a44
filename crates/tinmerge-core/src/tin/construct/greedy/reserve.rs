//! Samples kept from the greedy refinement and made vertices in an order
//! of their own: a kept hull side's ([`super::super::kept`]).

use super::super::measure::{RESERVED, Source};
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
}
