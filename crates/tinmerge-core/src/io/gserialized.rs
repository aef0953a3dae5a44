//! PostGIS's own serialisation of a `geometry` (GSERIALIZED, versions 1 and
//! 2), read and written without a conversion to WKB:
//! - [`peek`]: the SRID, the type, and for a POINT its coordinates (the
//!   per-row point functions read their argument this way);
//! - [`read`] and [`write()`]: the whole geometry as [`Geom`], for the types
//!   [`super::ewkb`] reads (`tin_drape`, whose per-row form is common, reads
//!   and returns geometries this way; the other merges take EWKB).
//!
//! Layout (after the 4-byte varlena header, which the caller strips): 3 bytes
//! of SRID (21 bits, sign-extended), 1 byte of flags (Z 0x01, M 0x02, bbox
//! 0x04, geodetic 0x08, version-2 marker 0x40, and in version 2 extended
//! flags 0x10 adding 8 bytes), an optional float4 bounding box (x, y, then z
//! and m when present, each min then max; 3 dimensions when geodetic), then
//! the geometry in machine byte order: u32 type, u32 count, then the
//! coordinates (points, lines), the ring point counts padded to 8 bytes and
//! the rings (polygons), or the members, each with its own type and count
//! (multi types and collections).
//!
//! [`write()`] produces what PostGIS 3 writes for the same geometry (version
//! 2; a bounding box unless PostGIS leaves it out: points, lines of at most
//! two points, one-point multipoints, one-line multilines of at most two
//! points, empty geometries; float4 bounds rounded outwards, computed from
//! the outer rings of polygons): tests/pg_regress/sql/line.sql compares its
//! bytes with PostGIS's own through pageinspect.

use super::IoError;
use super::ewkb::{Coord3, Ewkb, Geom};

/// What [`peek`] found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Peek {
    pub srid: i32,
    /// liblwgeom type number (1 = POINT, 2 = LINESTRING, ...).
    pub type_code: u32,
    pub has_z: bool,
    pub has_m: bool,
    /// For a POINT: `Some(None)` when empty, else its x and y.
    pub point: Option<Option<[f64; 2]>>,
}

/// PostGIS's name of a liblwgeom type number.
pub fn type_name(code: u32) -> &'static str {
    match code {
        1 => "POINT",
        2 => "LINESTRING",
        3 => "POLYGON",
        4 => "MULTIPOINT",
        5 => "MULTILINESTRING",
        6 => "MULTIPOLYGON",
        7 => "GEOMETRYCOLLECTION",
        8 => "CIRCULARSTRING",
        9 => "COMPOUNDCURVE",
        10 => "CURVEPOLYGON",
        11 => "MULTICURVE",
        12 => "MULTISURFACE",
        13 => "POLYHEDRALSURFACE",
        14 => "TRIANGLE",
        15 => "TIN",
        _ => "unknown geometry type",
    }
}

fn bad(msg: &str) -> IoError {
    IoError::Geometry(format!("malformed geometry value: {msg}"))
}

/// Where the geometry starts after the header with these flags: past the
/// extended flags (version 2) and the float4 bounding box, if present.
fn payload_offset(flags: u8) -> usize {
    let (has_z, has_m) = (flags & 0x01 != 0, flags & 0x02 != 0);
    let mut at = 4;
    if flags & 0x40 != 0 && flags & 0x10 != 0 {
        at += 8;
    }
    if flags & 0x04 != 0 {
        at += if flags & 0x08 != 0 {
            6 * 4
        } else {
            4 * (4 + 2 * has_z as usize + 2 * has_m as usize)
        };
    }
    at
}

/// Read the header, the type, and a point's coordinates from `b`, the bytes
/// of a `geometry` value after its varlena header.
pub fn peek(b: &[u8]) -> Result<Peek, IoError> {
    if b.len() < 4 {
        return Err(bad("shorter than its header"));
    }
    let raw = ((b[0] as u32) << 16) | ((b[1] as u32) << 8) | b[2] as u32;
    let srid = ((raw << 11) as i32) >> 11;
    let flags = b[3];
    let (has_z, has_m) = (flags & 0x01 != 0, flags & 0x02 != 0);
    let at = payload_offset(flags);
    let word = |i: usize| -> Result<u32, IoError> {
        let s = b.get(i..i + 4).ok_or_else(|| bad("truncated"))?;
        Ok(u32::from_ne_bytes([s[0], s[1], s[2], s[3]]))
    };
    let type_code = word(at)?;
    let point = if type_code == 1 {
        let n = word(at + 4)?;
        match n {
            0 => Some(None),
            1 => {
                let c = at + 8;
                let f = |i: usize| -> Result<f64, IoError> {
                    let s = b
                        .get(c + 8 * i..c + 8 * i + 8)
                        .ok_or_else(|| bad("truncated point"))?;
                    let mut a = [0u8; 8];
                    a.copy_from_slice(s);
                    Ok(f64::from_ne_bytes(a))
                };
                Some(Some([f(0)?, f(1)?]))
            }
            _ => return Err(bad("a POINT with more than one coordinate")),
        }
    } else {
        None
    };
    Ok(Peek {
        srid,
        type_code,
        has_z,
        has_m,
        point,
    })
}

/// Nesting limit of collections in collections (as the `wkb` crate's).
const MAX_DEPTH: usize = 64;

/// Sequential reader of the payload, every access length-checked.
struct Cursor<'a> {
    b: &'a [u8],
    at: usize,
    /// Doubles per coordinate (2 + Z + M).
    stride: usize,
    has_z: bool,
}

impl Cursor<'_> {
    fn u32(&mut self) -> Result<u32, IoError> {
        let s = self
            .b
            .get(self.at..self.at + 4)
            .ok_or_else(|| bad("truncated"))?;
        self.at += 4;
        Ok(u32::from_ne_bytes([s[0], s[1], s[2], s[3]]))
    }

    /// `n` coordinates, after checking they fit in what is left.
    fn coords(&mut self, n: u32) -> Result<Vec<Coord3>, IoError> {
        let len = (n as usize)
            .checked_mul(8 * self.stride)
            .filter(|&l| l <= self.b.len().saturating_sub(self.at))
            .ok_or_else(|| bad("a point count runs past the end of the value"))?;
        let s = &self.b[self.at..self.at + len];
        self.at += len;
        let f = |i: usize| {
            let mut a = [0u8; 8];
            a.copy_from_slice(&s[8 * i..8 * i + 8]);
            f64::from_ne_bytes(a)
        };
        Ok((0..n as usize)
            .map(|k| {
                let o = k * self.stride;
                [f(o), f(o + 1), if self.has_z { f(o + 2) } else { f64::NAN }]
            })
            .collect())
    }

    /// A count of members, each taking at least 8 bytes (type and count).
    fn count(&mut self, each: usize) -> Result<u32, IoError> {
        let n = self.u32()?;
        if (n as usize).saturating_mul(each) > self.b.len().saturating_sub(self.at) {
            return Err(bad("a member count runs past the end of the value"));
        }
        Ok(n)
    }

    fn point(&mut self) -> Result<Option<Coord3>, IoError> {
        match self.u32()? {
            0 => Ok(None),
            1 => {
                // PostGIS's EWKB of POINT EMPTY is NaN NaN: read it as empty
                // here too, as ewkb::read does
                let c = self.coords(1)?[0];
                Ok(Some(c).filter(|c| !(c[0].is_nan() && c[1].is_nan())))
            }
            _ => Err(bad("a POINT with more than one coordinate")),
        }
    }

    fn polygon(&mut self) -> Result<Vec<Vec<Coord3>>, IoError> {
        let nrings = self.count(4)?;
        let mut counts = Vec::with_capacity(nrings as usize);
        for _ in 0..nrings {
            counts.push(self.u32()?);
        }
        if nrings % 2 == 1 {
            self.at += 4; // padding to 8 bytes
        }
        counts.into_iter().map(|n| self.coords(n)).collect()
    }

    /// A member of a multi type: its own type word (which must be `want`).
    fn member(&mut self, want: u32) -> Result<(), IoError> {
        let t = self.u32()?;
        if t != want {
            return Err(bad(&format!(
                "a {} inside a {}",
                type_name(t),
                match want {
                    1 => "MULTIPOINT",
                    2 => "MULTILINESTRING",
                    _ => "MULTIPOLYGON",
                }
            )));
        }
        Ok(())
    }

    fn geom(&mut self, depth: usize) -> Result<Geom, IoError> {
        if depth > MAX_DEPTH {
            return Err(bad("collections nested too deeply"));
        }
        let t = self.u32()?;
        Ok(match t {
            1 => Geom::Point(self.point()?),
            2 => {
                let n = self.u32()?;
                Geom::LineString(self.coords(n)?)
            }
            3 => Geom::Polygon(self.polygon()?),
            4 => {
                let n = self.count(8)?;
                let mut ps = Vec::new();
                for _ in 0..n {
                    self.member(1)?;
                    ps.extend(self.point()?);
                }
                Geom::MultiPoint(ps)
            }
            5 => {
                let n = self.count(8)?;
                let mut ls = Vec::with_capacity(n as usize);
                for _ in 0..n {
                    self.member(2)?;
                    let k = self.u32()?;
                    ls.push(self.coords(k)?);
                }
                Geom::MultiLineString(ls)
            }
            6 => {
                let n = self.count(8)?;
                let mut ps = Vec::with_capacity(n as usize);
                for _ in 0..n {
                    self.member(3)?;
                    ps.push(self.polygon()?);
                }
                Geom::MultiPolygon(ps)
            }
            7 => {
                let n = self.count(8)?;
                let mut gs = Vec::with_capacity(n as usize);
                for _ in 0..n {
                    gs.push(self.geom(depth + 1)?);
                }
                Geom::Collection(gs)
            }
            8..=15 => {
                return Err(IoError::Unsupported(format!(
                    "unsupported geometry type {}",
                    type_name(t)
                )));
            }
            _ => return Err(bad(&format!("unknown geometry type number {t}"))),
        })
    }
}

/// Read a whole geometry from `b`, the bytes of a `geometry` value after its
/// varlena header. Geometries with M are refused (as [`super::ewkb::read`]
/// does); curves, TIN, TRIANGLE and POLYHEDRALSURFACE are `Unsupported`.
/// Every count is checked against the bytes left, so a damaged value is an
/// error, never a panic or a huge allocation.
pub fn read(b: &[u8]) -> Result<Ewkb, IoError> {
    let p = peek(b)?;
    if p.has_m {
        return Err(IoError::Unsupported(
            "geometries with M coordinates are not supported; use ST_Force3DZ or ST_Force2D".into(),
        ));
    }
    let mut c = Cursor {
        b,
        at: payload_offset(b[3]),
        stride: 2 + p.has_z as usize,
        has_z: p.has_z,
    };
    let geom = c.geom(0)?;
    if c.at != b.len() {
        return Err(bad("bytes left over after the geometry"));
    }
    Ok(Ewkb {
        srid: p.srid,
        has_z: p.has_z,
        geom,
    })
}

/// Whether PostGIS stores a bounding box for `g` (liblwgeom's
/// `lwgeom_needs_bbox`, and never for an empty geometry).
fn needs_bbox(g: &Geom) -> bool {
    match g {
        Geom::Point(_) => false,
        Geom::LineString(l) => l.len() > 2,
        Geom::MultiPoint(ps) => ps.len() != 1,
        Geom::MultiLineString(ls) => !(ls.len() == 1 && ls[0].len() <= 2),
        _ => true,
    }
}

/// x, y, z bounds (min, max each) as liblwgeom computes them: every point,
/// but only the outer ring of a polygon.
fn bounds(g: &Geom, b: &mut [[f64; 2]; 3]) {
    let mut add = |c: &Coord3| {
        for (k, v) in c.iter().enumerate() {
            b[k][0] = b[k][0].min(*v);
            b[k][1] = b[k][1].max(*v);
        }
    };
    match g {
        Geom::Point(p) => p.iter().for_each(&mut add),
        Geom::LineString(l) | Geom::MultiPoint(l) => l.iter().for_each(&mut add),
        Geom::MultiLineString(ls) => ls.iter().flatten().for_each(&mut add),
        Geom::Polygon(rs) => rs.iter().take(1).flatten().for_each(&mut add),
        Geom::MultiPolygon(ps) => ps
            .iter()
            .flat_map(|rs| rs.iter().take(1))
            .flatten()
            .for_each(&mut add),
        Geom::Collection(gs) => gs.iter().for_each(|g| bounds(g, b)),
    }
}

/// liblwgeom's `next_float_down`: the largest float4 <= d.
fn float_down(d: f64) -> f32 {
    if d > f32::MAX as f64 {
        return f32::MAX;
    }
    if d <= -(f32::MAX as f64) {
        return -f32::MAX;
    }
    let r = d as f32;
    if r as f64 <= d { r } else { r.next_down() }
}

/// liblwgeom's `next_float_up`: the smallest float4 >= d.
fn float_up(d: f64) -> f32 {
    if d >= f32::MAX as f64 {
        return f32::MAX;
    }
    if d < -(f32::MAX as f64) {
        return -f32::MAX;
    }
    let r = d as f32;
    if r as f64 >= d { r } else { r.next_up() }
}

/// Serialise `g` (with Z when `z`; a missing Z is written as NaN) as PostGIS
/// 3 does: the bytes after the varlena header, which the caller adds.
pub fn write(srid: i32, z: bool, g: &Geom) -> Vec<u8> {
    let s = (srid as u32) & 0x1f_ffff;
    let bbox = needs_bbox(g) && !g.is_empty();
    let mut out = vec![
        (s >> 16) as u8,
        (s >> 8) as u8,
        s as u8,
        0x40 | z as u8 | if bbox { 0x04 } else { 0 },
    ];
    if bbox {
        let mut b = [[f64::INFINITY, f64::NEG_INFINITY]; 3];
        bounds(g, &mut b);
        for d in b.iter().take(2 + z as usize) {
            out.extend_from_slice(&float_down(d[0]).to_ne_bytes());
            out.extend_from_slice(&float_up(d[1]).to_ne_bytes());
        }
    }
    let mut w = Out { out, z };
    w.geom(g);
    w.out
}

struct Out {
    out: Vec<u8>,
    z: bool,
}

impl Out {
    fn u32(&mut self, v: u32) {
        self.out.extend_from_slice(&v.to_ne_bytes());
    }

    fn coords(&mut self, cs: &[Coord3]) {
        for c in cs {
            let n = if self.z { 3 } else { 2 };
            for v in &c[..n] {
                self.out.extend_from_slice(&v.to_ne_bytes());
            }
        }
    }

    fn line(&mut self, t: u32, l: &[Coord3]) {
        self.u32(t);
        self.u32(l.len() as u32);
        self.coords(l);
    }

    fn polygon(&mut self, rs: &[Vec<Coord3>]) {
        self.u32(3);
        self.u32(rs.len() as u32);
        for r in rs {
            self.u32(r.len() as u32);
        }
        if rs.len() % 2 == 1 {
            self.u32(0);
        }
        rs.iter().for_each(|r| self.coords(r));
    }

    fn geom(&mut self, g: &Geom) {
        match g {
            Geom::Point(p) => self.line(1, p.as_slice()),
            Geom::LineString(l) => self.line(2, l),
            Geom::Polygon(rs) => self.polygon(rs),
            Geom::MultiPoint(ps) => {
                self.u32(4);
                self.u32(ps.len() as u32);
                ps.iter()
                    .for_each(|p| self.line(1, std::slice::from_ref(p)));
            }
            Geom::MultiLineString(ls) => {
                self.u32(5);
                self.u32(ls.len() as u32);
                ls.iter().for_each(|l| self.line(2, l));
            }
            Geom::MultiPolygon(ps) => {
                self.u32(6);
                self.u32(ps.len() as u32);
                ps.iter().for_each(|p| self.polygon(p));
            }
            Geom::Collection(gs) => {
                self.u32(7);
                self.u32(gs.len() as u32);
                gs.iter().for_each(|g| self.geom(g));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v2_point(srid: i32, z: bool, xy: Option<[f64; 2]>) -> Vec<u8> {
        let s = (srid as u32) & 0x1f_ffff;
        let mut b = vec![(s >> 16) as u8, (s >> 8) as u8, s as u8, 0x40 | z as u8];
        b.extend_from_slice(&1u32.to_ne_bytes());
        match xy {
            None => b.extend_from_slice(&0u32.to_ne_bytes()),
            Some([x, y]) => {
                b.extend_from_slice(&1u32.to_ne_bytes());
                b.extend_from_slice(&x.to_ne_bytes());
                b.extend_from_slice(&y.to_ne_bytes());
                if z {
                    b.extend_from_slice(&7.0f64.to_ne_bytes());
                }
            }
        }
        b
    }

    #[test]
    fn points_and_srids() {
        let p = peek(&v2_point(32616, true, Some([1.5, -2.0]))).unwrap();
        assert_eq!((p.srid, p.type_code, p.has_z), (32616, 1, true));
        assert_eq!(p.point, Some(Some([1.5, -2.0])));
        assert_eq!(peek(&v2_point(0, false, None)).unwrap().point, Some(None));
        assert_eq!(peek(&v2_point(-1, false, None)).unwrap().srid, -1);
        // every truncation is an error, never a panic
        let b = v2_point(4326, true, Some([1.0, 2.0]));
        for n in 0..20 {
            assert!(peek(&b[..n]).is_err(), "{n}");
        }
    }

    #[test]
    fn skips_bbox_and_extended_flags() {
        let mut b = vec![0, 0x7f, 0x68, 0x40 | 0x10 | 0x04];
        b.extend_from_slice(&[0u8; 8]); // extended flags
        b.extend_from_slice(&[0u8; 16]); // 2D float4 bbox
        b.extend_from_slice(&2u32.to_ne_bytes());
        b.extend_from_slice(&2u32.to_ne_bytes());
        let p = peek(&b).unwrap();
        assert_eq!((p.srid, p.type_code, p.point), (32616, 2, None));
        assert_eq!(type_name(p.type_code), "LINESTRING");
    }

    fn samples() -> Vec<Geom> {
        let c = |x: f64, y: f64, z: f64| [x, y, z];
        let ring = vec![c(0., 0., 1.), c(4., 0., 2.), c(0., 3., 3.), c(0., 0., 1.)];
        let hole = vec![c(1., 1., 0.), c(1., 2., 0.), c(2., 1., 0.), c(1., 1., 0.)];
        vec![
            Geom::Point(Some(c(1.5, -2.0, 7.0))),
            Geom::Point(None),
            Geom::LineString(vec![c(0., 0., 0.), c(1e7 + 0.1, -3.3, 2.5)]),
            Geom::LineString(vec![c(0., 0., 0.), c(1., 1., 1.), c(2.000001, 0.3, -1e-9)]),
            Geom::Polygon(vec![ring.clone()]),
            Geom::Polygon(vec![ring.clone(), hole.clone()]),
            Geom::MultiPoint(vec![c(1., 2., 3.)]),
            Geom::MultiPoint(vec![c(1., 2., 3.), c(-1., 5., 0.)]),
            Geom::MultiLineString(vec![vec![c(0., 0., 0.), c(1., 1., 1.)]]),
            Geom::MultiLineString(vec![
                vec![c(0., 0., 0.), c(1., 1., 1.)],
                vec![c(5., 5., 5.), c(6., 7., 8.)],
            ]),
            Geom::MultiPolygon(vec![vec![ring.clone(), hole], vec![ring.clone()]]),
            Geom::Collection(vec![
                Geom::Point(Some(c(9., 9., 9.))),
                Geom::Collection(vec![Geom::LineString(vec![
                    c(0., 0., 0.),
                    c(-1., -1., -1.),
                ])]),
                Geom::Polygon(vec![ring]),
            ]),
            Geom::Collection(vec![]),
            Geom::MultiPolygon(vec![]),
        ]
    }

    #[test]
    fn write_then_read_gives_the_geometry_back() {
        for g in samples() {
            for srid in [0, 4326, 32616, 999999] {
                let b = write(srid, true, &g);
                let r = read(&b).unwrap_or_else(|e| panic!("{g:?}: {e}"));
                assert_eq!((r.srid, r.has_z), (srid, true));
                assert_eq!(r.geom, g);
                let p = peek(&b).unwrap();
                assert_eq!(type_name(p.type_code), g.type_name());
            }
        }
    }

    #[test]
    fn every_prefix_and_trailing_garbage_is_an_error() {
        for g in samples() {
            let b = write(32616, true, &g);
            for n in 0..b.len() {
                assert!(
                    read(&b[..n]).is_err(),
                    "{g:?}: prefix of {n} bytes accepted"
                );
            }
            let mut long = b.clone();
            long.extend_from_slice(&[0; 8]);
            assert!(read(&long).is_err());
        }
    }

    #[test]
    fn bbox_bounds_contain_the_coordinates() {
        // a line of three points has a box; its float4 bounds enclose the doubles
        let g = Geom::LineString(vec![
            [0.1, 0.2, 0.3],
            [1e7 + 0.1, -3.3, 2.5],
            [7.0, 8.0, 9.0],
        ]);
        let b = write(0, true, &g);
        assert_eq!(b[3], 0x40 | 0x04 | 0x01);
        let f = |i: usize| {
            f32::from_ne_bytes([b[4 + 4 * i], b[5 + 4 * i], b[6 + 4 * i], b[7 + 4 * i]]) as f64
        };
        assert!(
            f(0) <= 0.1
                && f(1) >= 1e7 + 0.1
                && f(2) <= -3.3
                && f(3) >= 8.0
                && f(4) <= 0.3
                && f(5) >= 9.0
        );
        assert!(f(1) > 1e7 && f(1) - (1e7 + 0.1) < 1.0);
        assert_eq!(float_down(f64::MAX), f32::MAX);
        assert_eq!(float_up(-f64::MAX), -f32::MAX);
        // a point has none: 4 header bytes + type + count + 3 doubles
        assert_eq!(
            write(0, true, &Geom::Point(Some([1.0, 2.0, 3.0]))).len(),
            4 + 8 + 24
        );
    }

    #[test]
    fn m_and_curves_are_refused() {
        let mut b = write(0, true, &Geom::Point(Some([1.0, 2.0, 3.0])));
        b[3] = 0x40 | 0x02;
        assert!(matches!(read(&b), Err(IoError::Unsupported(_))));
        let mut c = vec![0, 0, 0, 0x40];
        c.extend_from_slice(&8u32.to_ne_bytes());
        c.extend_from_slice(&0u32.to_ne_bytes());
        assert!(matches!(read(&c), Err(IoError::Unsupported(_))));
    }
}
