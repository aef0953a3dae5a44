//! A polygon cut to the domain of a level and draped: what `tin_drape`
//! does with a polygon that is not wholly on the terrain (a tin with void
//! triangles has holes and bays; any tin has a hull), as PostGIS's
//! `ST_Intersection` with the domain would, with heights from the surface.
//!
//! The cut is geo's boolean intersection (i_overlay) of the polygon with
//! the domain, whose rings are chained from the level's boundary edges
//! (a domain triangle's edge on the hull or to a void triangle, domain on
//! the left), rings far from the polygon left out. i_overlay computes on
//! an integer grid (about 1e-9 of the extent), so its output is put back
//! where it belongs before draping:
//! - an output vertex within `eps` of a vertex of the polygon or of the
//!   domain's boundary is that vertex, exactly;
//! - any other vertex off the domain (a crossing rounded outwards) is
//!   moved onto the nearest boundary edge, with the edge's height there;
//! - each edge is draped alone; where it leaves the domain by rounding
//!   (a stretch along the boundary), the gap is closed with the boundary
//!   vertices on it, so the draped ring follows the boundary's heights.
//!   A gap that is not along the boundary is an error (a bug), never a
//!   silent jump.

use geo::{BooleanOps, Contains, Coord, LineString, MultiPolygon, Point, Polygon};
use rustc_hash::FxHashMap;

use super::{Part, pieces, runs};
use crate::geom::{bbox2, point_segment_nearest, xy};
use crate::merge::point;
use crate::tin::{Tin, TinError};

/// A boundary edge of the level (domain on its left), its ends with heights.
type Edge = [[f64; 3]; 2];

fn line(r: impl Iterator<Item = [f64; 2]>) -> LineString<f64> {
    LineString::new(r.map(|p| Coord { x: p[0], y: p[1] }).collect())
}

/// Exact vertices to put i_overlay's rounded output back on: a hash grid
/// of cell `eps`.
struct Snap {
    eps: f64,
    cells: FxHashMap<(i64, i64), Vec<[f64; 3]>>,
}

impl Snap {
    fn key(&self, x: f64, y: f64) -> (i64, i64) {
        ((x / self.eps).floor() as i64, (y / self.eps).floor() as i64)
    }
    fn add(&mut self, p: [f64; 3]) {
        let k = self.key(p[0], p[1]);
        self.cells.entry(k).or_default().push(p);
    }
    /// The nearest exact vertex within eps (z NaN: a polygon vertex,
    /// whose height is the surface's).
    fn near(&self, x: f64, y: f64) -> Option<[f64; 3]> {
        let (kx, ky) = self.key(x, y);
        let mut best: Option<(f64, [f64; 3])> = None;
        for dx in -1..=1 {
            for dy in -1..=1 {
                for p in self.cells.get(&(kx + dx, ky + dy)).into_iter().flatten() {
                    let d = (p[0] - x).hypot(p[1] - y);
                    if d <= self.eps && best.is_none_or(|b| d < b.0) {
                        best = Some((d, *p));
                    }
                }
            }
        }
        best.map(|b| b.1)
    }
}

/// Whether a polygon whose rings are all on the terrain still holds part
/// of the domain's boundary inside it (a hole of the domain, or void
/// around an island of it, wholly within the polygon): then it is not all
/// terrain and must be cut too. Only a level with void triangles can; only
/// the outline's rings whose box meets the polygon's are read.
pub(crate) fn encloses_void(tin: &Tin, level: usize, rings: &[Vec<[f64; 3]>]) -> bool {
    if tin.levels[level].num_void == 0 || rings.is_empty() {
        return false;
    }
    let outline = tin.outline(level);
    let pb = bbox2(rings.iter().flatten().map(|p| [p[0], p[1]]));
    let closed = |r: &Vec<[f64; 3]>| line(r.iter().chain(r.first()).map(|p| [p[0], p[1]]));
    let poly = Polygon::new(closed(&rings[0]), rings[1..].iter().map(closed).collect());
    outline.rings_meeting(&pb).any(|i| {
        outline.rings[i].iter().any(|&v| {
            let p = tin.verts[v as usize];
            p[0] > pb[0]
                && p[0] < pb[2]
                && p[1] > pb[1]
                && p[1] < pb[3]
                && poly.contains(&Point::new(p[0], p[1]))
        })
    })
}

/// `rings` (a polygon: shell, then holes) cut to the domain of `level` and
/// draped: the polygons left (none when the polygon misses the domain).
/// The domain's rings near the polygon are gathered from the level's
/// outline ([`Cut::new`], [`Tin::outline`]), the
/// polygon intersected with them ([`Cut::intersection`]), and each ring of
/// the result draped ([`Cut::drape_ring`]).
pub(crate) fn drape_clipped(
    tin: &Tin,
    level: usize,
    rings: &[Vec<[f64; 3]>],
) -> Result<Vec<Vec<Vec<[f64; 3]>>>, TinError> {
    if let Some(p) = rings
        .iter()
        .flatten()
        .find(|p| !(p[0].is_finite() && p[1].is_finite()))
    {
        return Err(TinError::InvalidParameter(format!(
            "tin_drape: a polygon has a vertex ({} {}) that is not finite",
            p[0], p[1]
        )));
    }
    let Some(cut) = Cut::new(tin, level, rings) else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for pg in &cut.intersection(rings) {
        let mut rs = Vec::new();
        for ring in std::iter::once(pg.exterior()).chain(pg.interiors()) {
            if let Some(d) = cut.drape_ring(ring)? {
                rs.push(d);
            }
        }
        if !rs.is_empty() {
            out.push(rs);
        }
    }
    Ok(out)
}

fn same(a: &[f64; 3], b: &[f64; 3]) -> bool {
    a[0] == b[0] && a[1] == b[1]
}

/// One polygon's cut with the domain of a level: the domain's rings that
/// can change the answer, their edges, the snapping distance and the
/// points output vertices snap to.
struct Cut<'a> {
    tin: &'a Tin,
    level: usize,
    /// the domain's rings whose box meets the polygon's, as vertex ids
    kept: Vec<Vec<u32>>,
    edges: Vec<Edge>,
    eps: f64,
    snap: Snap,
}

impl<'a> Cut<'a> {
    /// None when the polygon's box is not finite or no domain ring's box
    /// meets it. Rings whose box misses the polygon's cannot change the
    /// answer: an outer ring holding the polygon, and the holes inside
    /// that ring, have boxes that meet it.
    fn new(tin: &'a Tin, level: usize, rings: &[Vec<[f64; 3]>]) -> Option<Cut<'a>> {
        let pb = bbox2(rings.iter().flatten().map(xy));
        if !(pb[0].is_finite() && pb[1].is_finite() && pb[2].is_finite() && pb[3].is_finite()) {
            return None;
        }
        let v = |i: u32| tin.verts[i as usize];
        let outline = tin.outline(level);
        let kept: Vec<Vec<u32>> = outline
            .rings_meeting(&pb)
            .map(|i| outline.rings[i].clone())
            .collect();
        if kept.is_empty() {
            return None;
        }
        let edges: Vec<Edge> = kept
            .iter()
            .flat_map(|r| (0..r.len()).map(|k| [v(r[k]), v(r[(k + 1) % r.len()])]))
            .collect();
        let db = bbox2(kept.iter().flatten().map(|&i| xy(&v(i))));
        let ub = [
            pb[0].min(db[0]),
            pb[1].min(db[1]),
            pb[2].max(db[2]),
            pb[3].max(db[3]),
        ];
        let mag = ub.iter().fold(0.0f64, |m, c| m.max(c.abs()));
        // i_overlay's grid is 2^-29 of the half extent; a few of its steps
        let eps = ((ub[2] - ub[0]).max(ub[3] - ub[1]) * 1e-7).max(mag * 1e-12);
        let mut snap = Snap {
            eps,
            cells: FxHashMap::default(),
        };
        for r in rings {
            for p in r {
                snap.add([p[0], p[1], f64::NAN]);
            }
        }
        for r in &kept {
            for &i in r {
                snap.add(v(i));
            }
        }
        Some(Cut {
            tin,
            level,
            kept,
            edges,
            eps,
            snap,
        })
    }

    /// The polygon `rings` intersected with the kept domain rings (geo's
    /// boolean operations, even-odd).
    fn intersection(&self, rings: &[Vec<[f64; 3]>]) -> MultiPolygon<f64> {
        let v = |i: u32| self.tin.verts[i as usize];
        let domain = MultiPolygon::new(
            self.kept
                .iter()
                .map(|r| Polygon::new(line(r.iter().chain(r.first()).map(|&i| xy(&v(i)))), vec![]))
                .collect(),
        );
        let closed = |r: &Vec<[f64; 3]>| line(r.iter().chain(r.first()).map(xy));
        let poly = Polygon::new(closed(&rings[0]), rings[1..].iter().map(closed).collect());
        poly.intersection(&domain)
    }

    /// A point of the output with its height: exact vertices first, then
    /// the surface, then the nearest boundary edge.
    fn lift(&self, x: f64, y: f64) -> Result<[f64; 3], TinError> {
        let (x, y) = match self.snap.near(x, y) {
            Some(p) if !p[2].is_nan() => return Ok(p),
            Some(p) => (p[0], p[1]),
            None => (x, y),
        };
        if let Some(h) = point::height(self.tin, self.level, x, y) {
            return Ok([x, y, h]);
        }
        let mut best: Option<(f64, [f64; 3])> = None;
        for e in &self.edges {
            let (d, t) = point_segment_nearest([x, y], xy(&e[0]), xy(&e[1]));
            if best.is_none_or(|b| d < b.0) {
                let q = [
                    e[0][0] + t * (e[1][0] - e[0][0]),
                    e[0][1] + t * (e[1][1] - e[0][1]),
                    e[0][2] + t * (e[1][2] - e[0][2]),
                ];
                best = Some((d, q));
            }
        }
        match best {
            Some((d, q)) if d <= self.eps => Ok(q),
            _ => Err(TinError::InvalidParameter(format!(
                "tin_drape: cutting the polygon to the domain left a vertex ({x} {y}) off the terrain"
            ))),
        }
    }

    /// The boundary vertices on the stretch `p` -> `q` (strictly between),
    /// in order; an error when the stretch is not along the boundary.
    fn along_boundary(&self, p: [f64; 3], q: [f64; 3]) -> Result<Vec<[f64; 3]>, TinError> {
        let mid = [(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0];
        let on = point::height(self.tin, self.level, mid[0], mid[1]).is_some()
            || self
                .edges
                .iter()
                .any(|e| point_segment_nearest(mid, xy(&e[0]), xy(&e[1])).0 <= self.eps);
        if !on {
            return Err(TinError::InvalidParameter(format!(
                "tin_drape: cutting the polygon to the domain left an edge from ({} {}) to ({} {}) off the terrain",
                p[0], p[1], q[0], q[1]
            )));
        }
        let mut w: Vec<(f64, [f64; 3])> = self
            .edges
            .iter()
            .map(|e| e[0])
            .filter_map(|b| {
                let (d, t) = point_segment_nearest(xy(&b), xy(&p), xy(&q));
                (d <= self.eps && t > 0.0 && t < 1.0).then_some((t, b))
            })
            .collect();
        w.sort_by(|a, b| a.0.total_cmp(&b.0));
        Ok(w.into_iter().map(|x| x.1).collect())
    }

    /// One ring of the intersection draped, closed exactly on its first
    /// point (None when it collapses).
    fn drape_ring(&self, ring: &LineString<f64>) -> Result<Option<Vec<[f64; 3]>>, TinError> {
        let mut pts: Vec<[f64; 3]> = Vec::new();
        for c in ring.coords() {
            let p = self.lift(c.x, c.y)?;
            if pts.last().is_none_or(|l| !same(l, &p)) {
                pts.push(p);
            }
        }
        while pts.len() > 1 && same(&pts[0], &pts[pts.len() - 1]) {
            pts.pop();
        }
        if pts.len() < 3 {
            return Ok(None);
        }
        let mut d: Vec<[f64; 3]> = vec![pts[0]];
        for k in 0..pts.len() {
            self.drape_edge(pts[k], pts[(k + 1) % pts.len()], &mut d)?;
        }
        let f = d[0];
        if let Some(l) = d.last_mut() {
            *l = f;
        }
        Ok((d.len() >= 4).then_some(d))
    }

    /// The edge `a` -> `b` draped onto `d` (which ends at `a`): its runs on
    /// the surface, the gaps between them closed along the boundary.
    fn drape_edge(&self, a: [f64; 3], b: [f64; 3], d: &mut Vec<[f64; 3]>) -> Result<(), TinError> {
        let ps = pieces(self.tin, self.level, &[Part::new(vec![xy(&a), xy(&b)])])?;
        let mut last = a;
        for (_, run, _) in runs(&ps) {
            let Some(first) = run.first() else {
                continue;
            };
            if !same(&last, first) {
                d.extend(self.along_boundary(last, *first)?);
                if d.last().is_none_or(|l| !same(l, first)) {
                    d.push(*first);
                }
            }
            for p in &run[1..] {
                if d.last().is_none_or(|l| !same(l, p)) {
                    d.push(*p);
                }
            }
            last = *run.last().unwrap_or(first);
        }
        if !same(&last, &b) {
            d.extend(self.along_boundary(last, b)?);
        }
        if d.last().is_none_or(|l| !same(l, &b)) {
            d.push(b);
        }
        Ok(())
    }
}
