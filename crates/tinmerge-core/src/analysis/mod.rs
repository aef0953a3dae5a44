//! Analyses of the terrain surface itself (no second dataset): exact
//! contour lines ([`contour`]), per-triangle slope and aspect ([`slope`])
//! and the surface sampled at pixel centres ([`rasterize`]), on one level
//! at a time.

pub mod contour;
pub mod rasterize;
pub mod slope;
pub mod viewshed;
pub mod visibility;
