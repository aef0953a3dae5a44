//! Line merge (Scarlatos §6.4), the plain walk: follow a polyline through the
//! triangles of one level, cutting it wherever it crosses a triangle edge.
//!
//! Every decision is an exact orientation test (`robust::orient2d`) on the
//! line's own vertices and the triangles' corners, never on a computed
//! crossing point, so the sequence of triangles is exact; crossing points are
//! computed on the edge they cross (so both triangles agree on their height).
//!
//! Where the choice would be ambiguous the rules are:
//! - a line running along an edge is in the triangle with the smaller id of
//!   the two sharing that edge;
//! - a line through a vertex continues in the triangle of the vertex's fan
//!   that holds the next stretch of the line;
//! - a piece that starts on an edge or a vertex belongs to the triangle the
//!   line goes into, not to the one it touches.
//!
//! Parts of the line outside the (convex) domain are skipped; a line that
//! leaves and comes back starts a new run of pieces.
//!
//! The walk reports to a [`Sink`]: every point of the cut line with the
//! triangle of the piece it belongs to (a crossing point is reported twice:
//! as the end of one piece and the start of the next) and its distance along
//! the line. [`crate::merge::line::tree`] drives the same walker from a
//! multi-scale line tree and skips the stretches that cannot leave a
//! triangle.
//!
//! ```
//! use tinmerge_core::tin::build::build;
//! use tinmerge_core::merge::line::{pieces, Part};
//! // a plane z = x sampled on a 3 x 3 grid: 8 triangles
//! let mut pts = Vec::new();
//! for i in 0..3 {
//!     for j in 0..3 {
//!         pts.push([i as f64, j as f64, i as f64]);
//!     }
//! }
//! let tin = build(pts, &[0.0], 0, &mut || Ok(())).unwrap();
//! let line = Part::new(vec![[0.1, 0.3], [1.9, 0.3]]);
//! let cut = pieces(&tin, 0, &[line]).unwrap();
//! // the line is cut at every edge it crosses; the lengths add up
//! let total: f64 = cut.iter().map(|p| p.length2d()).sum();
//! assert!((total - 1.8).abs() < 1e-12);
//! assert!(cut.len() >= 2);
//! // heights come from the surface: z = x
//! for p in &cut {
//!     for q in &p.points {
//!         assert!((q[2] - q[0]).abs() < 1e-12);
//!     }
//! }
//! ```

pub mod clip_domain;
pub mod drape;
mod sinks;
pub mod tree;
mod walk;
pub mod widened;

pub use self::sinks::{Piece, PieceSink, TriangleSink, pieces, pieces_in, runs, triangles};
pub use self::walk::{Part, Polyline, Sink, Walker, walk_parts};
