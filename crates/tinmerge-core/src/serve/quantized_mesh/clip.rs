//! A triangle of the level cut to the tile's rectangle, every point
//! knowing where it comes from.

use super::needed::Needed;
use crate::serve::tiling::TileBounds;
use crate::tin::TinError;

/// Where a point of a clipped polygon comes from.
#[derive(Clone, Copy, Debug)]
pub(super) enum Kind {
    Vertex(u32),
    /// On the level's edge between these vertices (canonical order).
    Edge(u32, u32),
    /// A tile corner inside this triangle.
    Inside(u32),
    /// A tile corner off the terrain (fill).
    Fill,
}

/// The line a polygon edge lies on: an edge of the level, or a tile side.
#[derive(Clone, Copy, Debug)]
enum Support {
    Edge(u32, u32),
    Side(u8),
}

#[derive(Clone, Copy, Debug)]
pub(super) struct Pt {
    pub(super) x: f64,
    pub(super) y: f64,
    pub(super) h: f64,
    pub(super) kind: Kind,
    /// The source (tin) the point comes from.
    pub(super) src: u32,
}

pub(super) struct Tile<'a> {
    pub(super) b: TileBounds,
    pub(super) need: &'a Needed,
    pub(super) geo: &'a [[f64; 2]],
    pub(super) src: u32,
}

/// One tin cut into a tile: what [`needed()`](super::needed::needed) found
/// at the level served (all the encoding reads of the tin), and the
/// geographic positions of [`Needed::points`]. A terrain stored as tiles
/// (tins sharing their seams, `tin::tiles`) is one source per tin.
#[derive(Clone, Copy)]
pub struct Source<'a> {
    pub need: &'a Needed,
    pub geo: &'a [[f64; 2]],
}

impl Tile<'_> {
    pub(super) fn inside(&self, p: &Pt, side: u8) -> bool {
        match side {
            0 => p.x >= self.b.west,
            1 => p.x <= self.b.east,
            2 => p.y >= self.b.south,
            _ => p.y <= self.b.north,
        }
    }

    pub(super) fn side_value(&self, side: u8) -> f64 {
        match side {
            0 => self.b.west,
            1 => self.b.east,
            2 => self.b.south,
            _ => self.b.north,
        }
    }

    pub(super) fn vertex(&self, v: u32) -> Result<Pt, TinError> {
        let g = self
            .need
            .index(v)
            .and_then(|i| self.geo.get(i))
            .filter(|g| g[0].is_finite() && g[1].is_finite())
            .ok_or_else(|| {
                TinError::InvalidParameter(format!(
                    "point {v} has no finite geographic position (transform to EPSG:4326 failed)"
                ))
            })?;
        let h = if v >= self.need.base {
            self.need.splits[(v - self.need.base) as usize].xyz[2]
        } else {
            self.need.height(v)?
        };
        Ok(Pt {
            x: g[0],
            y: g[1],
            h,
            kind: Kind::Vertex(v),
            src: self.src,
        })
    }

    /// Where the level's edge (a, b) crosses tile side `side`, computed
    /// from the edge's ends in canonical order.
    pub(super) fn crossing(&self, a: u32, b: u32, side: u8) -> Result<Pt, TinError> {
        let (pa, pb) = (self.vertex(a)?, self.vertex(b)?);
        let (p, q, ka, kb) = if (pa.x, pa.y) <= (pb.x, pb.y) {
            (pa, pb, a, b)
        } else {
            (pb, pa, b, a)
        };
        let s = self.side_value(side);
        let (x, y, t) = if side < 2 {
            let t = (s - p.x) / (q.x - p.x);
            (
                s,
                (p.y + t * (q.y - p.y)).clamp(p.y.min(q.y), p.y.max(q.y)),
                t,
            )
        } else {
            let t = (s - p.y) / (q.y - p.y);
            (
                (p.x + t * (q.x - p.x)).clamp(p.x.min(q.x), p.x.max(q.x)),
                s,
                t,
            )
        };
        let t = t.clamp(0.0, 1.0);
        Ok(Pt {
            x,
            y,
            h: p.h + t * (q.h - p.h),
            kind: Kind::Edge(ka, kb),
            src: self.src,
        })
    }

    /// The corner where tile sides `s1` and `s2` meet.
    pub(super) fn corner(&self, s1: u8, s2: u8) -> (f64, f64) {
        let (v, hz) = if s1 < 2 { (s1, s2) } else { (s2, s1) };
        (self.side_value(v), self.side_value(hz))
    }

    /// The triangle `tri` (vertex or split point ids, CCW; a piece of the
    /// level's triangle `t`) clipped to the tile: the polygon's points, CCW.
    pub(super) fn clip(&self, tri: [u32; 3], t: u32) -> Result<Vec<Pt>, TinError> {
        let c = [
            self.vertex(tri[0])?,
            self.vertex(tri[1])?,
            self.vertex(tri[2])?,
        ];
        let mut poly: Vec<(Pt, Support)> = (0..3)
            .map(|k| (c[k], Support::Edge(tri[k], tri[(k + 1) % 3])))
            .collect();
        for side in 0..4u8 {
            if poly.is_empty() {
                break;
            }
            let mut out = Vec::with_capacity(poly.len() + 2);
            for i in 0..poly.len() {
                let (cur, sup) = poly[i];
                let nxt = poly[(i + 1) % poly.len()].0;
                let (ci, ni) = (self.inside(&cur, side), self.inside(&nxt, side));
                if ci {
                    out.push((cur, sup));
                }
                if ci != ni {
                    let p = match sup {
                        Support::Edge(a, b) => self.crossing(a, b, side)?,
                        Support::Side(s2) => {
                            let (x, y) = self.corner(side, s2);
                            let h = plane(&c, x, y);
                            Pt {
                                x,
                                y,
                                h,
                                kind: Kind::Inside(t),
                                src: self.src,
                            }
                        }
                    };
                    if ci {
                        out.push((p, Support::Side(side)));
                    } else {
                        out.push((p, sup));
                    }
                }
            }
            poly = out;
        }
        let mut pts: Vec<Pt> = Vec::with_capacity(poly.len());
        for (p, _) in poly {
            if pts.last().is_none_or(|q: &Pt| (q.x, q.y) != (p.x, p.y)) {
                pts.push(p);
            }
        }
        while pts.len() > 1 && (pts[0].x, pts[0].y) == (pts[pts.len() - 1].x, pts[pts.len() - 1].y)
        {
            pts.pop();
        }
        Ok(pts)
    }
}

/// Height at (x, y) on the plane through the three points (longitude,
/// latitude, height).
fn plane(c: &[Pt; 3], x: f64, y: f64) -> f64 {
    let p = c.map(|p| [p.x, p.y, p.h]);
    crate::tin::interpolate(&p, x, y)
}

pub(super) fn orient(a: &Pt, b: &Pt, c: &Pt) -> f64 {
    robust::orient2d(
        robust::Coord { x: a.x, y: a.y },
        robust::Coord { x: b.x, y: b.y },
        robust::Coord { x: c.x, y: c.y },
    )
}
