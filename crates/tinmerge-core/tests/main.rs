//! The core's integration tests on real data, as one test binary (one link
//! instead of one per file: the suite's build is a third shorter). Each
//! module is one subject; `cargo test --release -p tinmerge-core --test core
//! <module>::` runs one of them. memory.rs is a binary of its own: its
//! counting allocator measures the whole process.

mod common;

mod analysis;
mod area;
mod boundary;
mod breaklines;
mod cancel;
mod cover;
mod exactness;
mod format;
mod fuzz;
mod harness;
mod hierarchy;
mod line;
mod overlay;
mod point;
mod points_surface;
mod progress;
mod quantized_mesh;
mod raster;
mod rasterize;
mod render;
mod sliced;
mod slices;
mod storage;
mod surface;
mod tile_domain;
mod tiles;
mod validate;
mod viewshed;
mod visibility;
mod whole;
