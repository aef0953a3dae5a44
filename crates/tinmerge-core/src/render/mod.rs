//! Pictures of tins and merge results, pure Rust (no pgrx): SVG drawings of
//! a level ([`svg`]) and binary glTF meshes with an optional painted image
//! ([`gltf`]), coloured through [`palette`].
//! The SQL layer (`src/pg/render.rs`) only turns arrays and NULLs into
//! `svg::Fill`, reads features and texture bands, checks SRIDs and reserves
//! memory. Invariants the tests hold them to: one SVG polygon per triangle
//! with its id, corners the affine image of the vertices (0.1 px rounding); a
//! glb whose index buffer is the level's triangles as stored and whose
//! positions are the level's vertex prefix, y up around the bbox centre, so
//! viewers and the tin agree on triangle ids. A picture of a merge needs no
//! new Rust: aggregate the merge's output into `triangles` and `vals` or
//! `classes` in SQL (see `scripts/demo-pictures.sh`).
//!
pub mod gltf;
pub mod palette;
pub mod svg;
