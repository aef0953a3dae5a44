//! The pure core of tinmerge: adaptive hierarchical triangulations and their
//! merges with points, lines, polygons, rasters and other TINs (the seed
//! method). No PostgreSQL: `cargo test -p tinmerge-core` runs without it, and
//! the extension crate (`src/pg/`) is the only one that depends on pgrx.
//!
//! - [`tin`]: the hierarchy (data model, build, storage layout, grid index,
//!   point location, invariant checks);
//! - [`merge`]: one module per merge;
//! - [`analysis`]: the surface on its own (contours, slope and aspect);
//! - [`io`]: PostGIS wire formats (EWKB, GSERIALIZED, WKB raster);
//! - [`render`]: pictures (SVG, glTF); [`serve`]: Cesium quantized-mesh tiles;
//! - [`geom`]: the geometric primitives all of them use; [`interrupt`]: how
//!   long work is cancelled.
#![deny(clippy::undocumented_unsafe_blocks)]
pub mod analysis;
pub mod geom;
pub mod interrupt;
pub mod io;
pub mod merge;
pub mod render;
pub mod serve;
pub mod tin;
