//! PostGIS EWKB in and out.
//!
//! Reading goes through the `wkb` crate (length-checked, bounded nesting);
//! the SRID, which that crate skips, is read from the EWKB header here.
//! Writing produces little-endian EWKB with the SRID flag, which PostGIS's
//! `bytea::geometry` cast accepts.

use super::IoError;
use geo_traits::{
    CoordTrait, GeometryCollectionTrait, GeometryTrait, GeometryType, LineStringTrait,
    MultiLineStringTrait, MultiPointTrait, MultiPolygonTrait, PointTrait, PolygonTrait,
};

pub type Coord3 = [f64; 3];

/// A geometry with optional Z (missing Z reads as NaN).
#[derive(Clone, Debug, PartialEq)]
pub enum Geom {
    /// `None` for `POINT EMPTY`.
    Point(Option<Coord3>),
    LineString(Vec<Coord3>),
    Polygon(Vec<Vec<Coord3>>),
    MultiPoint(Vec<Coord3>),
    MultiLineString(Vec<Vec<Coord3>>),
    MultiPolygon(Vec<Vec<Vec<Coord3>>>),
    Collection(Vec<Geom>),
}

/// A decoded EWKB value.
#[derive(Clone, Debug, PartialEq)]
pub struct Ewkb {
    /// SRID from the header (0 when absent).
    pub srid: i32,
    pub has_z: bool,
    pub geom: Geom,
}

impl Geom {
    /// PostGIS type name, as `GeometryType()` prints it.
    pub fn type_name(&self) -> &'static str {
        match self {
            Geom::Point(_) => "POINT",
            Geom::LineString(_) => "LINESTRING",
            Geom::Polygon(_) => "POLYGON",
            Geom::MultiPoint(_) => "MULTIPOINT",
            Geom::MultiLineString(_) => "MULTILINESTRING",
            Geom::MultiPolygon(_) => "MULTIPOLYGON",
            Geom::Collection(_) => "GEOMETRYCOLLECTION",
        }
    }

    /// Whether the geometry has no coordinates at all.
    pub fn is_empty(&self) -> bool {
        let mut any = false;
        self.for_each_coord(&mut |_| any = true);
        !any
    }

    /// Visit every coordinate.
    pub fn for_each_coord(&self, f: &mut dyn FnMut(&Coord3)) {
        match self {
            Geom::Point(p) => p.iter().for_each(&mut *f),
            Geom::LineString(l) | Geom::MultiPoint(l) => l.iter().for_each(&mut *f),
            Geom::Polygon(rs) | Geom::MultiLineString(rs) => rs.iter().flatten().for_each(&mut *f),
            Geom::MultiPolygon(ps) => ps.iter().flatten().flatten().for_each(&mut *f),
            Geom::Collection(gs) => gs.iter().for_each(|g| g.for_each_coord(f)),
        }
    }
}

fn coord<C: CoordTrait<T = f64>>(c: &C, has_z: bool) -> Coord3 {
    let z = if has_z {
        c.nth(2).unwrap_or(f64::NAN)
    } else {
        f64::NAN
    };
    [c.x(), c.y(), z]
}

fn line<L: LineStringTrait<T = f64>>(l: &L, z: bool) -> Vec<Coord3> {
    l.coords().map(|c| coord(&c, z)).collect()
}

fn poly<P: PolygonTrait<T = f64>>(p: &P, z: bool) -> Vec<Vec<Coord3>> {
    let mut rings = Vec::new();
    if let Some(e) = p.exterior() {
        rings.push(line(&e, z));
        rings.extend(p.interiors().map(|r| line(&r, z)));
    }
    rings
}

fn point<P: PointTrait<T = f64>>(p: &P, z: bool) -> Option<Coord3> {
    p.coord()
        .map(|c| coord(&c, z))
        .filter(|c| !(c[0].is_nan() && c[1].is_nan()))
}

fn convert<G: GeometryTrait<T = f64>>(g: &G, z: bool) -> Result<Geom, IoError> {
    Ok(match g.as_type() {
        GeometryType::Point(p) => Geom::Point(point(p, z)),
        GeometryType::LineString(l) => Geom::LineString(line(l, z)),
        GeometryType::Polygon(p) => Geom::Polygon(poly(p, z)),
        GeometryType::MultiPoint(m) => {
            Geom::MultiPoint(m.points().filter_map(|p| point(&p, z)).collect())
        }
        GeometryType::MultiLineString(m) => {
            Geom::MultiLineString(m.line_strings().map(|l| line(&l, z)).collect())
        }
        GeometryType::MultiPolygon(m) => {
            Geom::MultiPolygon(m.polygons().map(|p| poly(&p, z)).collect())
        }
        GeometryType::GeometryCollection(c) => Geom::Collection(
            c.geometries()
                .map(|g| convert(&g, z))
                .collect::<Result<Vec<_>, _>>()?,
        ),
        _ => return Err(IoError::Unsupported("unsupported geometry type".into())),
    })
}

/// Read EWKB or ISO WKB bytes (as PostGIS's `geometry::bytea` cast gives).
pub fn read(b: &[u8]) -> Result<Ewkb, IoError> {
    if b.len() < 5 {
        return Err(IoError::Geometry(format!(
            "EWKB too short ({} bytes)",
            b.len()
        )));
    }
    let le = match b[0] {
        0 => false,
        1 => true,
        x => return Err(IoError::Geometry(format!("bad EWKB byte order marker {x}"))),
    };
    let word = |s: &[u8]| {
        let a = [s[0], s[1], s[2], s[3]];
        if le {
            u32::from_le_bytes(a)
        } else {
            u32::from_be_bytes(a)
        }
    };
    let ty = word(&b[1..5]);
    let srid = if ty & 0x2000_0000 != 0 {
        if b.len() < 9 {
            return Err(IoError::Geometry("EWKB truncated in its SRID".into()));
        }
        word(&b[5..9]) as i32
    } else {
        0
    };
    let base = ty & 0x0fff_ffff;
    if ty & 0x4000_0000 != 0 || matches!(base / 1000, 2 | 3) {
        // refuse rather than misread XYM as XYZ
        return Err(IoError::Unsupported(
            "geometries with M coordinates are not supported; use ST_Force3DZ or ST_Force2D".into(),
        ));
    }
    // the wkb crate reads lazily and unwraps some length checks while
    // iterating (a malformed MULTIPOINT panics in `point_unchecked`): a
    // panic there is a malformed value, not a bug of ours
    std::panic::catch_unwind(|| {
        let w = wkb::reader::read_wkb(b).map_err(|e| IoError::Geometry(e.to_string()))?;
        let has_z = matches!(
            w.dim(),
            geo_traits::Dimensions::Xyz | geo_traits::Dimensions::Xyzm
        );
        let geom = convert(&w, has_z)?;
        Ok(Ewkb { srid, has_z, geom })
    })
    .unwrap_or_else(|_| {
        Err(IoError::Geometry(
            "malformed WKB (a count or length runs past the end of the value)".into(),
        ))
    })
}

/// Little-endian EWKB writer.
pub struct Writer {
    pub buf: Vec<u8>,
    srid: i32,
    z: bool,
}

const T_POINT: u32 = 1;
const T_LINE: u32 = 2;
const T_POLY: u32 = 3;
const T_MPOINT: u32 = 4;
const T_MLINE: u32 = 5;
const T_MPOLY: u32 = 6;
const T_COLL: u32 = 7;
const T_TIN: u32 = 16;
const T_TRIANGLE: u32 = 17;

impl Writer {
    pub fn new(srid: i32, z: bool) -> Writer {
        Writer {
            buf: Vec::with_capacity(64),
            srid,
            z,
        }
    }

    fn head(&mut self, ty: u32, top: bool) {
        let mut t = ty;
        if self.z {
            t |= 0x8000_0000;
        }
        let srid = top && self.srid != 0;
        if srid {
            t |= 0x2000_0000;
        }
        self.buf.push(1);
        self.buf.extend_from_slice(&t.to_le_bytes());
        if srid {
            self.buf.extend_from_slice(&self.srid.to_le_bytes());
        }
    }

    fn u32(&mut self, v: u32) {
        self.buf.extend_from_slice(&v.to_le_bytes());
    }

    fn c(&mut self, c: &Coord3) {
        self.buf.extend_from_slice(&c[0].to_le_bytes());
        self.buf.extend_from_slice(&c[1].to_le_bytes());
        if self.z {
            self.buf.extend_from_slice(&c[2].to_le_bytes());
        }
    }

    fn ring(&mut self, r: &[Coord3]) {
        self.u32(r.len() as u32);
        r.iter().for_each(|c| self.c(c));
    }

    fn geom(&mut self, g: &Geom, top: bool) {
        match g {
            Geom::Point(p) => {
                self.head(T_POINT, top);
                match p {
                    Some(c) => self.c(c),
                    None => {
                        let n = if self.z { 3 } else { 2 };
                        for _ in 0..n {
                            self.buf.extend_from_slice(&f64::NAN.to_le_bytes());
                        }
                    }
                }
            }
            Geom::LineString(l) => {
                self.head(T_LINE, top);
                self.ring(l);
            }
            Geom::Polygon(rs) => {
                self.head(T_POLY, top);
                self.u32(rs.len() as u32);
                rs.iter().for_each(|r| self.ring(r));
            }
            Geom::MultiPoint(ps) => {
                self.head(T_MPOINT, top);
                self.u32(ps.len() as u32);
                for p in ps {
                    self.geom(&Geom::Point(Some(*p)), false);
                }
            }
            Geom::MultiLineString(ls) => {
                self.head(T_MLINE, top);
                self.u32(ls.len() as u32);
                for l in ls {
                    self.head(T_LINE, false);
                    self.ring(l);
                }
            }
            Geom::MultiPolygon(ps) => {
                self.head(T_MPOLY, top);
                self.u32(ps.len() as u32);
                for p in ps {
                    self.geom(&Geom::Polygon(p.clone()), false);
                }
            }
            Geom::Collection(gs) => {
                self.head(T_COLL, top);
                self.u32(gs.len() as u32);
                for g in gs {
                    self.geom(g, false);
                }
            }
        }
    }

    /// Encode a geometry.
    pub fn write(srid: i32, z: bool, g: &Geom) -> Vec<u8> {
        let mut w = Writer::new(srid, z);
        w.geom(g, true);
        w.buf
    }

    /// A closed triangle ring `a b c a` as POLYGON.
    pub fn triangle_polygon(srid: i32, c: &[Coord3; 3]) -> Vec<u8> {
        let mut w = Writer::new(srid, true);
        w.head(T_POLY, true);
        w.u32(1);
        w.ring(&[c[0], c[1], c[2], c[0]]);
        w.buf
    }

    /// A PostGIS TIN Z of triangles.
    pub fn tin(srid: i32, tris: impl ExactSizeIterator<Item = [Coord3; 3]>) -> Vec<u8> {
        let mut w = Writer::new(srid, true);
        w.head(T_TIN, true);
        w.u32(tris.len() as u32);
        for c in tris {
            w.head(T_TRIANGLE, false);
            w.u32(1);
            w.ring(&[c[0], c[1], c[2], c[0]]);
        }
        w.buf
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roundtrip_through_wkb_crate() {
        let g = Geom::MultiPolygon(vec![vec![vec![
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 2.0],
            [0.0, 1.0, 3.0],
            [0.0, 0.0, 1.0],
        ]]]);
        let b = Writer::write(32616, true, &g);
        let r = read(&b).unwrap();
        assert_eq!(r.srid, 32616);
        assert!(r.has_z);
        assert_eq!(r.geom, g);
    }

    #[test]
    fn postgis_ewkb_point_z_with_srid() {
        // SELECT 'SRID=4326;POINT Z (1 2 3)'::geometry::bytea
        let hex = "01010000a0e6100000000000000000f03f00000000000000400000000000000840";
        let b: Vec<u8> = (0..hex.len() / 2)
            .map(|i| u8::from_str_radix(&hex[2 * i..2 * i + 2], 16).unwrap())
            .collect();
        let r = read(&b).unwrap();
        assert_eq!(r.srid, 4326);
        assert_eq!(r.geom, Geom::Point(Some([1.0, 2.0, 3.0])));
    }

    #[test]
    fn truncated_and_garbage_are_errors() {
        let g = Writer::write(0, true, &Geom::LineString(vec![[0.0, 0.0, 0.0]; 4]));
        for n in 0..g.len() {
            assert!(read(&g[..n]).is_err(), "prefix of {n} bytes accepted");
        }
        assert!(read(&[7, 1, 2, 3, 4, 5]).is_err());
    }
}
