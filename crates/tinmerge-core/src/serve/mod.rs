//! Serving the terrain to 3D globes: Cesium's geographic tiling scheme and
//! `layer.json` ([`tiling`]), and quantized-mesh 1.0 tiles clipped exactly
//! to a tile ([`quantized_mesh`]).

pub mod quantized_mesh;
pub mod tiling;
