//! Peek into PostGIS's own serialisation of a `geometry` (GSERIALIZED,
//! versions 1 and 2) without converting it to WKB: the SRID, the type, and
//! for a POINT its coordinates. The per-row point functions read their
//! argument this way, which saves the `geometry::bytea` conversion on every
//! row; everything else goes through EWKB ([`super::ewkb`]).
//!
//! Layout (after the 4-byte varlena header, which the caller strips): 3 bytes
//! of SRID (21 bits, sign-extended), 1 byte of flags (Z 0x01, M 0x02, bbox
//! 0x04, geodetic 0x08, version-2 marker 0x40, and in version 2 extended
//! flags 0x10 adding 8 bytes), an optional float4 bounding box, then the
//! geometry in machine byte order: u32 type, u32 count, coordinates.

use super::IoError;

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

/// Read the header, the type, and a point's coordinates from `b`, the bytes
/// of a `geometry` value after its varlena header.
pub fn peek(b: &[u8]) -> Result<Peek, IoError> {
    if b.len() < 4 {
        return Err(bad("shorter than its header"));
    }
    let raw = ((b[0] as u32) << 16) | ((b[1] as u32) << 8) | b[2] as u32;
    let srid = ((raw << 11) as i32) >> 11;
    let flags = b[3];
    let v2 = flags & 0x40 != 0;
    let (has_z, has_m) = (flags & 0x01 != 0, flags & 0x02 != 0);
    let mut at = 4;
    if v2 && flags & 0x10 != 0 {
        at += 8;
    }
    if flags & 0x04 != 0 {
        at += if flags & 0x08 != 0 {
            6 * 4
        } else {
            4 * (4 + 2 * has_z as usize + 2 * has_m as usize)
        };
    }
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
}
