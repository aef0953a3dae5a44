//! Breaklines: lines the triangulation must have as edges at every level
//! (roads, dam crests, shorelines, ridge lines).
//!
//! A **hard** breakline carries its own heights: the surface along it is
//! the line itself (its Z interpolated along each segment). A **soft**
//! breakline only says where the edges go: its vertices take their heights
//! from the samples (linear interpolation in the Delaunay triangulation of
//! the samples around each vertex).
//!
//! [`network`] makes the lines one planar straight-line graph: equal points
//! merged, crossings and touchings made vertices of both lines (a vertex of
//! one line lying on another, up to rounding, splits that one), segments
//! split there. Its vertices become samples of the build and level 0 holds
//! every segment as a constraint edge ([`super::build`]); parent-by-parent
//! refinement keeps a coarse edge a union of finer ones, so every breakline
//! is a union of edges at every level.
//!
//! Samples lying on a breakline up to rounding ([`drops_sample`]) are left
//! out of the build: a sample a hair beside an edge that cannot flip would
//! make a sliver. A hard line's heights replace them; along a soft line its
//! [`profile`] does: points about one sample spacing apart with the
//! samples' heights, chosen level by level like the samples of a tile's
//! seam, so the surface along a soft line follows the terrain rather than
//! running straight between the line's own vertices.
//!
//! ```
//! use tinmerge_core::tin::breaklines::{network, Breakline};
//! // two hard lines crossing at (5, 5)
//! let lines = vec![
//!     Breakline { pts: vec![[0.0, 0.0, 10.0], [10.0, 10.0, 20.0]], hard: true },
//!     Breakline { pts: vec![[0.0, 10.0, 15.0], [10.0, 0.0, 15.0]], hard: true },
//! ];
//! let net = network(&lines, 0.5, &|_, _| None, &mut || Ok(())).unwrap();
//! assert_eq!(net.verts.len(), 5);
//! assert_eq!(net.segs.len(), 4);
//! assert!(net.verts.iter().any(|v| v[0] == 5.0 && v[1] == 5.0 && v[2] == 15.0));
//! ```

mod clip;
mod graph;

pub use clip::clip_to_hull;
pub use graph::{
    Breakline, MAX_BREAKLINE_VERTICES, MAX_PROFILE_POINTS, Network, drops_sample, hard_segments,
    network, profile, validate,
};
