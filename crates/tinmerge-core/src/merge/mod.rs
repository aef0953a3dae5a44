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
