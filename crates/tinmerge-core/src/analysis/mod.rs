//! Analyses of the terrain surface itself (no second dataset): exact
//! contour lines ([`contour`]) and per-triangle slope and aspect
//! ([`slope`]), on one level at a time.

pub mod contour;
pub mod slope;
