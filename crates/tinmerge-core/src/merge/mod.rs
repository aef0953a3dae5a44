//! The merges of the seed method (section 6): one module per kind of data
//! merged with the terrain. Pure Rust over [`crate::tin::Tin`]: never imports
//! pgrx. Each function takes the level to work at as an index already
//! resolved with [`crate::tin::Tin::level_index`].

pub mod area;
pub mod clip;
pub mod coverage;
pub mod drape;
pub mod faces;
pub mod line;
pub mod linetree;
pub mod overlay;
pub mod point;
pub mod polygon;
pub mod raster;
pub mod surface;
pub mod widened;

use crate::tin::TinError;

/// Calls the caller's interrupt check every 4096 ticks of a long loop.
pub(crate) struct Ticker<'a> {
    pub(crate) n: u32,
    pub(crate) f: &'a mut dyn FnMut() -> Result<(), TinError>,
}

impl Ticker<'_> {
    #[inline]
    pub(crate) fn tick(&mut self) -> Result<(), TinError> {
        self.n = self.n.wrapping_add(1);
        if self.n.is_multiple_of(4096) {
            (self.f)()?;
        }
        Ok(())
    }
}
