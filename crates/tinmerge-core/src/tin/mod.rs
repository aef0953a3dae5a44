//! The adaptive hierarchical triangulation: data model, construction, storage
//! layout, grid index and point location. Pure Rust: never imports pgrx.
//!
//! Invariants of a [`Tin`] (checked by [`Tin::sanity_check`] and, for values
//! read from disk or the wire, by [`layout::decode`]):
//! - vertices are one array shared by every level; level `i` uses the prefix
//!   `0..levels[i].num_vertices` (vertices are appended as levels get finer);
//! - each level is a conforming triangulation of the same convex domain, with
//!   counter-clockwise triangles and symmetric neighbour links;
//! - every triangle of level `i+1` lies inside its parent at level `i`, and the
//!   triangles of level `i+1` are sorted by parent, so the children of a parent
//!   are a contiguous range (`Level::child_start`);
//! - every edge of level `i` is a union of edges of level `i+1`.

pub use crate::error::TinError;
pub use crate::{memory, par};

pub mod breaklines;
pub mod build;
pub mod check;
pub mod compact;
pub mod construct;
pub mod cover;
pub mod delaunay_ref;
pub mod dense;
pub mod domain;
pub mod grid;
pub mod hierarchy;
pub mod lattice;
pub mod layout;
pub mod locate;
pub mod mesh;
pub mod outline;
pub mod samples;
pub mod seam_rounds;
pub mod sides;
pub mod sliced;
pub mod surface;
pub mod tile;
pub mod tile_domain;
pub mod tiles;

/// Marks "no triangle" in neighbour and parent arrays.
pub const NONE: u32 = u32::MAX;
/// Most levels a `tin` may have.
pub const MAX_LEVELS: usize = 16;
/// Largest coordinate magnitude accepted for x and y: the exact predicates
/// multiply differences of coordinates, which must not overflow `f64`
/// (real coordinates are below 1e8 in every projection).
pub const MAX_COORD: f64 = 1e100;

/// `Ok` for a usable x, y; otherwise an `InvalidParameter` error saying what
/// (`what`: "the polygon", "sample") had which coordinate. `what` is
/// formatted only for the error, so a per-row caller can pass
/// `format_args!(..)` at no cost.
///
/// ```
/// use tinmerge_core::tin::check_xy;
/// assert!(check_xy("the line", 740000.0, 4060000.0).is_ok());
/// assert!(check_xy("the line", f64::NAN, 0.0).is_err());
/// assert!(check_xy("the line", 1e300, 0.0).is_err());
/// ```
pub fn check_xy(what: impl std::fmt::Display, x: f64, y: f64) -> Result<(), TinError> {
    if !(x.is_finite() && y.is_finite()) {
        return Err(TinError::InvalidParameter(format!(
            "{what} has a non-finite coordinate ({x} {y})"
        )));
    }
    if x.abs() > MAX_COORD || y.abs() > MAX_COORD {
        return Err(TinError::InvalidParameter(format!(
            "{what} has a coordinate beyond ±1e100 ({x:e} {y:e}): exact geometric predicates cannot use it"
        )));
    }
    Ok(())
}

/// Axis-aligned bounding box of the vertices (x, y and z).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bbox {
    pub min_x: f64,
    pub min_y: f64,
    pub max_x: f64,
    pub max_y: f64,
    pub min_z: f64,
    pub max_z: f64,
}

impl Bbox {
    /// Whether the two boxes share no point in the plane (x, y; touching
    /// boxes are not disjoint).
    pub(crate) fn disjoint_xy(&self, o: &Bbox) -> bool {
        self.max_x < o.min_x || o.max_x < self.min_x || self.max_y < o.min_y || o.max_y < self.min_y
    }

    /// Bounding box of a non-empty vertex list.
    pub fn of(verts: &[[f64; 3]]) -> Bbox {
        let mut b = Bbox {
            min_x: f64::INFINITY,
            min_y: f64::INFINITY,
            max_x: f64::NEG_INFINITY,
            max_y: f64::NEG_INFINITY,
            min_z: f64::INFINITY,
            max_z: f64::NEG_INFINITY,
        };
        for v in verts {
            b.min_x = b.min_x.min(v[0]);
            b.min_y = b.min_y.min(v[1]);
            b.max_x = b.max_x.max(v[0]);
            b.max_y = b.max_y.max(v[1]);
            b.min_z = b.min_z.min(v[2]);
            b.max_z = b.max_z.max(v[2]);
        }
        b
    }
}

/// Regular grid over the bounding box mapping each cell to one triangle near
/// (usually containing) the cell centre: the start of a point-location walk.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// Cell edge length (same horizontally and vertically).
    pub cell: f64,
    pub nx: u32,
    pub ny: u32,
    /// Row-major, `nx * ny` triangle ids.
    pub cells: Vec<u32>,
}

/// The outline of a level's domain: its boundary edges chained into
/// rings, with their boxes ([`outline`], [`Tin::outline`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Outline {
    /// The boundary edges as vertex pairs, in [`Level::boundary_edges`]'s
    /// order.
    pub edges: Vec<[u32; 2]>,
    /// The edges chained into closed rings of vertex ids (at a vertex where
    /// two rings touch, any pairing: use the rings with the even-odd rule).
    pub rings: Vec<Vec<u32>>,
    /// Each ring's bounding box, `[min x, min y, max x, max y]`.
    pub boxes: Vec<[f64; 4]>,
}

/// A value derived from a decoded level on first use and kept with it. It
/// is not part of the value: clones start empty and derive it again, and
/// it never makes two levels differ.
#[derive(Default)]
pub struct Derived<T>(std::sync::OnceLock<T>);

impl<T> Derived<T> {
    /// The value, derived by `f` on the first call.
    pub fn get_or_init(&self, f: impl FnOnce() -> T) -> &T {
        self.0.get_or_init(f)
    }
}

impl<T> Clone for Derived<T> {
    fn clone(&self) -> Self {
        Derived(std::sync::OnceLock::new())
    }
}

impl<T> PartialEq for Derived<T> {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl<T> std::fmt::Debug for Derived<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(if self.0.get().is_some() {
            "Derived(kept)"
        } else {
            "Derived(not yet)"
        })
    }
}

/// One level of detail.
#[derive(Clone, Debug, PartialEq)]
pub struct Level {
    /// Vertical error bound this level was built to.
    pub tolerance: f64,
    /// Largest vertical error measured at the source samples when built.
    pub max_error: f64,
    /// This level uses vertices `0..num_vertices`.
    pub num_vertices: u32,
    /// The last `num_void` triangles are *void*: outside the domain (a
    /// build's `boundary`, a hole in it). Each level still triangulates the
    /// samples' convex hull, so walks and neighbours work as on any tin,
    /// but no merge answers on a void triangle: a point there has no
    /// height, a line or an area has no piece there, a pixel there no
    /// owner. A child is void exactly when its parent is (checked on
    /// decode), so the void ones are the last of every level. 0 for a
    /// domain that is the whole hull.
    pub num_void: u32,
    /// Vertex ids of each triangle, counter-clockwise.
    pub tris: Vec<[u32; 3]>,
    /// `nbrs[t][j]` is the triangle across the edge opposite vertex `j`
    /// (edge `tris[t][j+1] -> tris[t][j+2]`), or [`NONE`] on the hull.
    pub nbrs: Vec<[u32; 3]>,
    /// Parent triangle at the previous (coarser) level; [`NONE`] at level 0.
    pub parent: Vec<u32>,
    /// Children of triangle `t` at the next level are
    /// `child_start[t]..child_start[t+1]`; empty at the finest level.
    /// Derived from the next level's `parent` (not stored on disk).
    pub child_start: Vec<u32>,
    pub grid: Grid,
    /// The domain's outline, derived on first use ([`Tin::outline`]);
    /// `Default::default()` when making a level.
    pub outline: Derived<Outline>,
    /// The hull edges, derived on first use ([`mesh::Mesh::hull_edges`]);
    /// `Default::default()` when making a level.
    pub hull: Derived<Vec<HullEdge>>,
}

/// An edge of a level's hull (a triangle's edge with no neighbour), as a
/// line walk entering the terrain from outside reads it: triangle `t`'s
/// edge opposite corner `j`, from `a` to `b` (the triangle on its left),
/// and its bounding box (min x, min y, max x, max y).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HullEdge {
    pub t: u32,
    pub j: usize,
    pub a: [f64; 2],
    pub b: [f64; 2],
    pub bbox: [f64; 4],
}

impl HullEdge {
    /// Edge `j` of triangle `t` with corners `cs`.
    pub fn new(t: u32, j: usize, cs: &[[f64; 3]; 3]) -> HullEdge {
        let (a, b) = (cs[(j + 1) % 3], cs[(j + 2) % 3]);
        HullEdge {
            t,
            j,
            a: [a[0], a[1]],
            b: [b[0], b[1]],
            bbox: [
                a[0].min(b[0]),
                a[1].min(b[1]),
                a[0].max(b[0]),
                a[1].max(b[1]),
            ],
        }
    }
}

impl Level {
    pub fn num_triangles(&self) -> usize {
        self.tris.len()
    }

    /// Triangles in the domain: `0..num_domain()` (the rest are void).
    pub fn num_domain(&self) -> usize {
        self.tris.len().saturating_sub(self.num_void as usize)
    }

    /// Whether triangle `t` is void ([`Level::num_void`]).
    #[inline]
    pub fn is_void(&self, t: u32) -> bool {
        t as usize >= self.num_domain()
    }

    /// The domain's boundary edges as vertex pairs, the domain on their
    /// left: a domain triangle's edge on the hull or to a void triangle
    /// (the outline of the domain, its holes included).
    pub fn boundary_edges(&self) -> impl Iterator<Item = [u32; 2]> + '_ {
        (0..self.num_domain()).flat_map(move |t| {
            let (tri, nb) = (self.tris[t], self.nbrs[t]);
            (0..3)
                .filter(move |&j| nb[j] == NONE || self.is_void(nb[j]))
                .map(move |j| [tri[(j + 1) % 3], tri[(j + 2) % 3]])
        })
    }
}

/// A terrain surface as an adaptive hierarchical triangulation.
#[derive(Clone, Debug, PartialEq)]
pub struct Tin {
    pub srid: i32,
    pub bbox: Bbox,
    pub verts: Vec<[f64; 3]>,
    pub levels: Vec<Level>,
}

impl Tin {
    /// Approximate heap size of a decoded value (what a cache of decoded
    /// values counts against its bound).
    pub fn heap_bytes(&self) -> usize {
        let mut n = self.verts.len() * 24;
        for l in &self.levels {
            n += l.tris.len() * 28 + l.child_start.len() * 4 + l.grid.cells.len() * 4;
        }
        n
    }

    pub fn num_levels(&self) -> usize {
        self.levels.len()
    }

    /// Resolve an optional SQL level (None = finest) to an index.
    pub fn level_index(&self, level: Option<i32>) -> Result<usize, TinError> {
        resolve_level(level, self.levels.len())
    }

    /// The three corners of triangle `t` at `level`.
    #[inline]
    pub fn corners(&self, level: usize, t: u32) -> [[f64; 3]; 3] {
        let tri = self.levels[level].tris[t as usize];
        [
            self.verts[tri[0] as usize],
            self.verts[tri[1] as usize],
            self.verts[tri[2] as usize],
        ]
    }
}

/// Resolve an optional level (None = finest) against a level count.
pub fn resolve_level(level: Option<i32>, num_levels: usize) -> Result<usize, TinError> {
    match level {
        None => Ok(num_levels - 1),
        Some(l) if l >= 0 && (l as usize) < num_levels => Ok(l as usize),
        Some(l) => Err(TinError::LevelOutOfRange {
            level: l as i64,
            num_levels,
        }),
    }
}

/// Height at (x, y) on the plane through triangle `c`, by barycentric weights.
#[inline]
pub fn interpolate(c: &[[f64; 3]; 3], x: f64, y: f64) -> f64 {
    let [a, b, cc] = c;
    let d = (b[0] - a[0]) * (cc[1] - a[1]) - (cc[0] - a[0]) * (b[1] - a[1]);
    let wb = ((x - a[0]) * (cc[1] - a[1]) - (cc[0] - a[0]) * (y - a[1])) / d;
    let wc = ((b[0] - a[0]) * (y - a[1]) - (x - a[0]) * (b[1] - a[1])) / d;
    a[2] + wb * (b[2] - a[2]) + wc * (cc[2] - a[2])
}
