//! Readers and writers for PostGIS wire formats. Pure Rust (no pgrx).
//! - [`ewkb`]: geometry as (E)WKB, read through the `wkb` crate, written by hand
//!   (the crate writes ISO WKB only, without SRID);
//! - [`raster`]: the WKB raster format (PostGIS RFC2), read by hand.

pub mod ewkb;
pub mod gserialized;
pub mod raster;

use thiserror::Error;

/// Errors reading or interpreting input values (SQLSTATE 22023 / XX000 by kind).
#[derive(Debug, Error, Clone, PartialEq)]
pub enum IoError {
    #[error("invalid geometry: {0}")]
    Geometry(String),
    #[error("invalid raster: {0}")]
    Raster(String),
    #[error("{0}")]
    Unsupported(String),
}
