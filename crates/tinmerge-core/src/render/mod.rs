//! Pictures of tins and merge results, pure Rust (no pgrx): SVG drawings of
//! a level ([`svg`]) and binary glTF meshes with an optional painted image
//! ([`gltf`]), coloured through [`palette`].
pub mod gltf;
pub mod palette;
pub mod svg;
