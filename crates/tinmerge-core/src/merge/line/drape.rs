//! Draping: any geometry with heights from the surface, and a vertex added
//! wherever a line or a ring crosses a triangle edge (what ArcGIS's
//! Interpolate Shape and H2GIS's `ST_Drape` do).
//!
//! - points outside the domain are dropped;
//! - lines keep their stretches inside the domain: a line that leaves and
//!   comes back becomes several lines (a LINESTRING may become a
//!   MULTILINESTRING);
//! - polygons keep their intersection with the domain (a domain with void
//!   triangles has holes and bays): a polygon partly off it is cut there
//!   ([`super::clip_domain`]) and may become several (a POLYGON may become a
//!   MULTIPOLYGON), its new edges along the domain's boundary;
//! - collections are draped member by member; members with nothing left are
//!   dropped, and `None` means nothing at all is left.

use super::clip_domain::{drape_clipped, encloses_void};
use super::{Part, pieces, runs};
use crate::io::ewkb::Geom;
use crate::merge::point;
use crate::tin::{Tin, TinError};

fn parts_of(lines: &[Vec<[f64; 3]>]) -> Vec<Part> {
    lines
        .iter()
        .map(|l| Part::new(l.iter().map(|c| [c[0], c[1]]).collect()))
        .collect()
}

/// Draped lines: the runs of all parts, in order.
fn drape_lines(
    tin: &Tin,
    level: usize,
    lines: &[Vec<[f64; 3]>],
) -> Result<Vec<Vec<[f64; 3]>>, TinError> {
    let ps = pieces(tin, level, &parts_of(lines))?;
    Ok(runs(&ps)
        .into_iter()
        .map(|(_, pts, _)| pts)
        .filter(|pts| !pts.is_empty())
        .map(|mut pts| {
            // a single point left (a line that never moves) stays a line
            if pts.len() == 1 {
                pts.push(pts[0]);
            }
            pts
        })
        .collect())
}

/// The ring draped whole, or None when it is not wholly in the domain (a
/// vertex off it, or an edge crossing a hole, a bay or the hull).
fn drape_ring(
    tin: &Tin,
    level: usize,
    ring: &[[f64; 3]],
) -> Result<Option<Vec<[f64; 3]>>, TinError> {
    if ring
        .iter()
        .any(|p| point::locate(tin, level, p[0], p[1]).is_none())
    {
        return Ok(None);
    }
    let mut lines = drape_lines(tin, level, &[ring.to_vec()])?;
    if lines.len() != 1 {
        return Ok(None);
    }
    let mut r = lines.pop().unwrap_or_default();
    if let (Some(f), Some(l)) = (r.first().copied(), r.last_mut()) {
        // closed exactly (the two ends may be interpolated in different
        // triangles)
        *l = f;
    }
    Ok(Some(r))
}

/// A polygon draped: itself when wholly in the domain, else the polygons
/// of its intersection with the domain ([`super::clip_domain`]).
fn drape_polygon(
    tin: &Tin,
    level: usize,
    rings: &[Vec<[f64; 3]>],
) -> Result<Vec<Vec<Vec<[f64; 3]>>>, TinError> {
    let mut whole = Vec::with_capacity(rings.len());
    for r in rings {
        match drape_ring(tin, level, r)? {
            Some(d) => whole.push(d),
            None => return drape_clipped(tin, level, rings),
        }
    }
    if encloses_void(tin, level, rings) {
        return drape_clipped(tin, level, rings);
    }
    Ok(vec![whole])
}

/// The geometry draped on the surface of `level`; None when nothing is left.
pub fn drape(tin: &Tin, level: usize, g: &Geom) -> Result<Option<Geom>, TinError> {
    let z = |p: &[f64; 3]| point::height(tin, level, p[0], p[1]).map(|z| [p[0], p[1], z]);
    Ok(match g {
        Geom::Point(p) => p.as_ref().and_then(z).map(|p| Geom::Point(Some(p))),
        Geom::MultiPoint(ps) => {
            let v: Vec<[f64; 3]> = ps.iter().filter_map(z).collect();
            (!v.is_empty()).then_some(Geom::MultiPoint(v))
        }
        Geom::LineString(l) => {
            let mut ls = drape_lines(tin, level, std::slice::from_ref(l))?;
            match ls.len() {
                0 => None,
                1 => ls.pop().map(Geom::LineString),
                _ => Some(Geom::MultiLineString(ls)),
            }
        }
        Geom::MultiLineString(ls) => {
            let v = drape_lines(tin, level, ls)?;
            (!v.is_empty()).then_some(Geom::MultiLineString(v))
        }
        Geom::Polygon(rs) if rs.is_empty() => None,
        Geom::Polygon(rs) => {
            let mut v = drape_polygon(tin, level, rs)?;
            match v.len() {
                0 => None,
                1 => v.pop().map(Geom::Polygon),
                _ => Some(Geom::MultiPolygon(v)),
            }
        }
        Geom::MultiPolygon(ps) => {
            let mut v = Vec::new();
            for p in ps.iter().filter(|p| !p.is_empty()) {
                v.extend(drape_polygon(tin, level, p)?);
            }
            (!v.is_empty()).then_some(Geom::MultiPolygon(v))
        }
        Geom::Collection(gs) => {
            let mut v = Vec::new();
            for m in gs {
                if let Some(d) = drape(tin, level, m)? {
                    v.push(d);
                }
            }
            (!v.is_empty()).then_some(Geom::Collection(v))
        }
    })
}
