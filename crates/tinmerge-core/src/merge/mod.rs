//! The merges of Scarlatos's method (§6, docs/architecture.md's references): one module per kind of data
//! merged with the terrain. Pure Rust over [`crate::tin::Tin`]: never imports
//! pgrx. Each function takes the level to work at as an index already
//! resolved with [`crate::tin::Tin::level_index`].

pub mod area;
pub mod line;
pub mod overlay;
pub mod point;
pub mod raster;
