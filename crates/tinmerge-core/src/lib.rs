//! The pure core of tinmerge: adaptive hierarchical triangulations and their
//! merges with points, lines, polygons, rasters and other TINs (Scarlatos's
//! method, docs/architecture.md). No PostgreSQL: `cargo test -p tinmerge-core` runs without it, and
//! the extension crate (`src/pg/`) is the only one that depends on pgrx.
//!
//! - [`tin`]: the hierarchy (data model, build, storage layout, grid index,
//!   point location, invariant checks);
//! - [`merge`]: one module per merge;
//! - [`analysis`]: the surface on its own (contours, slope and aspect,
//!   rasters out, viewsheds and lines of sight);
//! - [`io`]: PostGIS wire formats (EWKB, GSERIALIZED, WKB raster);
//! - [`render`]: pictures (SVG, glTF); [`serve`]: Cesium quantized-mesh tiles;
//! - [`geom`]: the geometric primitives all of them use; [`interrupt`]: how
//!   long work is cancelled; [`progress`]: how far it is; [`error`]: [`TinError`];
//!   [`polygon`]: polygonal areas; [`par`] and [`memory`]: threads and the
//!   counting allocator.
//!
//! They stand in layers, each using only its own and those below:
//! `error`, `geom`, `interrupt`, `progress`, `par`, `memory`, `polygon`; then `io`;
//! `tin`; `merge` and `analysis`; `serve` and `render`
//! (`scripts/check-cycles.py` enforces it; docs/architecture.md).
//!
//! The entry points are re-exported here: [`Tin`], [`TinError`], the builds
//! ([`build`], [`build_lattice`], [`build_points`] with [`BuildOptions`]),
//! and a call per merge ([`height`], [`pieces`], [`area_sweep`] and
//! [`area_rows`], [`raster_sweep`], [`overlay`]). Everything else a module
//! exports is its own detail; a function used only inside the crate is
//! `pub(crate)`, so `dead_code` finds what nothing uses.
#![deny(clippy::undocumented_unsafe_blocks)]
pub mod analysis;
pub mod error;
pub mod geom;
pub mod interrupt;
pub mod io;
pub mod memory;
pub mod merge;
pub mod par;
pub mod polygon;
pub mod progress;
pub mod render;
pub mod serve;
pub mod tin;

// The entry points, as spade re-exports its triangulations: the value and
// its error, the builds, one call per merge.
pub use crate::error::TinError;
pub use crate::interrupt::Interrupt;
pub use crate::merge::area::{area_rows, sweep as area_sweep};
pub use crate::merge::line::{pieces, triangles as line_triangles};
pub use crate::merge::overlay::{Overlay, overlay};
pub use crate::merge::point::{footprint, height};
pub use crate::merge::raster::sweep as raster_sweep;
pub use crate::polygon::Area;
pub use crate::tin::Tin;
pub use crate::tin::build::{BuildOptions, build, build_lattice};
pub use crate::tin::construct::build_points;
pub use crate::tin::sliced::SlicedTin;
