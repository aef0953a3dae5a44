//! Draping: any geometry with heights from the surface, and a vertex added
//! wherever a line or a ring crosses a triangle edge (what ArcGIS's
//! Interpolate Shape and H2GIS's `ST_Drape` do).
//!
//! - points outside the domain are dropped;
//! - lines keep their stretches inside the domain: a line that leaves and
//!   comes back becomes several lines (a LINESTRING may become a
//!   MULTILINESTRING);
//! - polygons must lie inside the domain, their edges too (a domain with
//!   void triangles has holes and bays; an error names the way to clip
//!   them): cutting a polygon to the domain is an area operation;
//! - collections are draped member by member; members with nothing left are
//!   dropped, and `None` means nothing at all is left.

use super::{pieces, runs, Part};
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

fn drape_ring(tin: &Tin, level: usize, ring: &[[f64; 3]]) -> Result<Vec<[f64; 3]>, TinError> {
    const CLIP: &str = "clip the polygon to the domain first, e.g. ST_Intersection(geom, (SELECT ST_Union(geom) FROM tin_triangles(t, 0)))";
    if let Some(p) = ring
        .iter()
        .find(|p| point::locate(tin, level, p[0], p[1]).is_none())
    {
        return Err(TinError::InvalidParameter(format!(
            "tin_drape: a polygon ring has a vertex ({} {}) outside the tin's domain; {CLIP}",
            p[0], p[1]
        )));
    }
    let mut lines = drape_lines(tin, level, &[ring.to_vec()])?;
    // Every vertex is in the domain; on a domain with void triangles (a
    // boundary, nodata) an edge may still cross a hole or a bay, and the
    // ring comes back as several runs: refused, not cut to one of them.
    if lines.len() > 1 {
        let p = lines[0].last().copied().unwrap_or_default();
        return Err(TinError::InvalidParameter(format!(
            "tin_drape: a polygon ring leaves the tin's domain near ({} {}) (it crosses a hole or a bay of the domain); {CLIP}",
            p[0], p[1]
        )));
    }
    let mut r = lines.pop().unwrap_or_default();
    if let (Some(f), Some(l)) = (r.first().copied(), r.last_mut()) {
        // closed exactly (the two ends may be interpolated in different
        // triangles)
        *l = f;
    }
    Ok(r)
}

fn drape_polygon(
    tin: &Tin,
    level: usize,
    rings: &[Vec<[f64; 3]>],
) -> Result<Vec<Vec<[f64; 3]>>, TinError> {
    rings.iter().map(|r| drape_ring(tin, level, r)).collect()
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
        Geom::Polygon(rs) => Some(Geom::Polygon(drape_polygon(tin, level, rs)?)),
        Geom::MultiPolygon(ps) => {
            let v = ps
                .iter()
                .filter(|p| !p.is_empty())
                .map(|p| drape_polygon(tin, level, p))
                .collect::<Result<Vec<_>, _>>()?;
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
