//! WKB raster (PostGIS RFC2) reader, written by hand: no maintained crate
//! reads it. Layout: u8 endianness; u16 version (0); u16 band count; f64
//! scaleX, scaleY, ipX, ipY, skewX, skewY; i32 SRID; u16 width, height; then
//! per band: u8 flags (0x80 out-db, 0x40 has nodata, 0x20 all nodata, low 4
//! bits pixel type), nodata value in the pixel type, then width x height
//! pixels row-major (out-db bands carry a band number and a path instead).

use super::IoError;

/// Georeferencing of a raster: pixel (col, row) corner is
/// `(ip_x + col*scale_x + row*skew_x, ip_y + col*skew_y + row*scale_y)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GeoTransform {
    pub scale_x: f64,
    pub scale_y: f64,
    pub ip_x: f64,
    pub ip_y: f64,
    pub skew_x: f64,
    pub skew_y: f64,
}

/// One band, converted to f64, with its nodata value.
#[derive(Clone, Debug, PartialEq)]
pub struct Band {
    pub pixel_type: u8,
    pub nodata: Option<f64>,
    /// The band is flagged as all nodata.
    pub all_nodata: bool,
    /// Row-major values.
    pub values: Vec<f64>,
}

impl Band {
    /// Whether a value counts as data (not nodata, not NaN).
    #[inline]
    pub fn is_valid(&self, v: f64) -> bool {
        !self.all_nodata && !v.is_nan() && self.nodata != Some(v)
    }
}

/// A parsed raster holding the one band asked for.
#[derive(Clone, Debug, PartialEq)]
pub struct Raster {
    pub srid: i32,
    pub width: usize,
    pub height: usize,
    pub num_bands: usize,
    pub gt: GeoTransform,
    pub band: Option<Band>,
}

/// The size in bytes of a known pixel type (0 for an unknown one).
fn pixel_type_size(t: u8) -> usize {
    pixel_type(t).map_or(0, |(_, size)| size)
}

/// Pixel type name and size in bytes, as PostGIS numbers them.
pub fn pixel_type(t: u8) -> Option<(&'static str, usize)> {
    Some(match t {
        0 => ("1BB", 1),
        1 => ("2BUI", 1),
        2 => ("4BUI", 1),
        3 => ("8BSI", 1),
        4 => ("8BUI", 1),
        5 => ("16BSI", 2),
        6 => ("16BUI", 2),
        7 => ("32BSI", 4),
        8 => ("32BUI", 4),
        10 => ("32BF", 4),
        11 => ("64BF", 8),
        _ => return None,
    })
}

struct Rd<'a> {
    b: &'a [u8],
    pos: usize,
    le: bool,
}

impl<'a> Rd<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], IoError> {
        match self.pos.checked_add(n).filter(|&e| e <= self.b.len()) {
            Some(e) => {
                let s = &self.b[self.pos..e];
                self.pos = e;
                Ok(s)
            }
            None => Err(IoError::Raster(format!(
                "truncated: {} bytes needed at offset {}, raster has {}",
                n,
                self.pos,
                self.b.len()
            ))),
        }
    }
    fn arr<const N: usize>(&mut self) -> Result<[u8; N], IoError> {
        let mut a = [0u8; N];
        a.copy_from_slice(self.take(N)?);
        if !self.le {
            a.reverse();
        }
        Ok(a)
    }
    fn u8(&mut self) -> Result<u8, IoError> {
        Ok(self.take(1)?[0])
    }
    fn u16(&mut self) -> Result<u16, IoError> {
        Ok(u16::from_le_bytes(self.arr()?))
    }
    fn i32(&mut self) -> Result<i32, IoError> {
        Ok(i32::from_le_bytes(self.arr()?))
    }
    fn f64(&mut self) -> Result<f64, IoError> {
        Ok(f64::from_le_bytes(self.arr()?))
    }
    fn value(&mut self, t: u8) -> Result<f64, IoError> {
        Ok(match t {
            0..=2 | 4 => self.u8()? as f64,
            3 => self.u8()? as i8 as f64,
            5 => i16::from_le_bytes(self.arr()?) as f64,
            6 => u16::from_le_bytes(self.arr()?) as f64,
            7 => i32::from_le_bytes(self.arr()?) as f64,
            8 => u32::from_le_bytes(self.arr()?) as f64,
            10 => f32::from_le_bytes(self.arr()?) as f64,
            11 => f64::from_le_bytes(self.arr()?),
            _ => return Err(IoError::Raster(format!("unknown pixel type {t}"))),
        })
    }
}

/// Parse WKB raster bytes, keeping band `band` (1-based). `band` beyond the
/// band count is an error unless the raster has no bands and `band` is None.
pub fn read(b: &[u8], band: Option<usize>) -> Result<Raster, IoError> {
    let mut r = Rd {
        b,
        pos: 0,
        le: true,
    };
    r.le = match r.u8()? {
        0 => false,
        1 => true,
        x => return Err(IoError::Raster(format!("bad byte order marker {x}"))),
    };
    let version = r.u16()?;
    if version != 0 {
        return Err(IoError::Raster(format!(
            "WKB raster version {version} is not supported"
        )));
    }
    let nb = r.u16()? as usize;
    let gt = GeoTransform {
        scale_x: r.f64()?,
        scale_y: r.f64()?,
        ip_x: r.f64()?,
        ip_y: r.f64()?,
        skew_x: r.f64()?,
        skew_y: r.f64()?,
    };
    let srid = r.i32()?;
    let width = r.u16()? as usize;
    let height = r.u16()? as usize;
    let g = [
        gt.scale_x, gt.scale_y, gt.ip_x, gt.ip_y, gt.skew_x, gt.skew_y,
    ];
    if !g.iter().all(|v| v.is_finite()) {
        return Err(IoError::Raster(
            "georeference has a non-finite value".into(),
        ));
    }
    let mut out = Raster {
        srid,
        width,
        height,
        num_bands: nb,
        gt,
        band: None,
    };
    let Some(want) = band else { return Ok(out) };
    if want == 0 || want > nb {
        return Err(IoError::Unsupported(format!(
            "band {want} does not exist: the raster has {nb} band(s), numbered from 1"
        )));
    }
    let npix = width * height;
    for i in 1..=nb {
        let flags = r.u8()?;
        let t = flags & 0x0f;
        let (_, size) = pixel_type(t)
            .ok_or_else(|| IoError::Raster(format!("band {i}: unknown pixel type {t}")))?;
        let nodata_raw = r.value(t)?;
        let has_nodata = flags & 0x40 != 0;
        if flags & 0x80 != 0 {
            if i == want {
                return Err(IoError::Unsupported(format!(
                    "band {i} is an out-db band (stored outside the database); load it in-db with raster2pgsql without -R"
                )));
            }
            r.u8()?;
            while r.u8()? != 0 {}
            continue;
        }
        if i != want {
            r.take(
                npix.checked_mul(size)
                    .ok_or_else(|| IoError::Raster("size overflow".into()))?,
            )?;
            continue;
        }
        // Check the length before allocating.
        let need = npix
            .checked_mul(size)
            .ok_or_else(|| IoError::Raster("size overflow".into()))?;
        if r.pos + need > b.len() {
            return Err(IoError::Raster(format!(
                "truncated: band {i} needs {need} bytes of pixels, {} remain",
                b.len() - r.pos
            )));
        }
        let mut values = Vec::with_capacity(npix);
        for _ in 0..npix {
            values.push(r.value(t)?);
        }
        out.band = Some(Band {
            pixel_type: t,
            nodata: has_nodata.then_some(nodata_raw),
            all_nodata: flags & 0x20 != 0,
            values,
        });
        return Ok(out);
    }
    Err(IoError::Raster("band not found".into()))
}

/// The float pixel types a raster can be written in, by their PostGIS
/// names: `32BF` and `64BF`.
pub fn float_pixel_type(name: &str) -> Result<u8, IoError> {
    match name.trim().to_ascii_uppercase().as_str() {
        "32BF" => Ok(10),
        "64BF" => Ok(11),
        _ => Err(IoError::Unsupported(format!(
            "pixel type '{name}' is not supported here: use '32BF' or '64BF' (heights are written as floats; ST_Reclass or ST_MapAlgebra turn them into integers)"
        ))),
    }
}

/// WKB raster (little-endian) of one band of `values` (row-major, from the
/// top row) in the float pixel type `pixel_type` ([`float_pixel_type`]),
/// with `nodata` as its nodata value and written for every NaN. A raster
/// with no pixels is written without bands, as `ST_MakeEmptyRaster` makes
/// it. The reverse of [`read`]; `ST_RastFromWKB` takes it.
pub fn write_float(
    srid: i32,
    gt: &GeoTransform,
    width: usize,
    height: usize,
    pixel_type: u8,
    nodata: f64,
    values: &[f64],
) -> Result<Vec<u8>, IoError> {
    let (w, h) = sides(width, height)?;
    let size = match pixel_type {
        10 | 11 => pixel_type_size(pixel_type),
        t => {
            return Err(IoError::Unsupported(format!(
                "pixel type {t} is not a float type"
            )));
        }
    };
    let n = width * height;
    if values.len() != n {
        return Err(IoError::Raster(format!(
            "{} values for {width} x {height} pixels",
            values.len()
        )));
    }
    if !nodata.is_finite() {
        return Err(IoError::Unsupported(format!(
            "nodata value {nodata}: it must be finite"
        )));
    }
    let mut b = Vec::with_capacity(61 + 1 + size + n * size);
    header(&mut b, srid, gt, w, h, n > 0);
    if n == 0 {
        return Ok(b);
    }
    let all_nodata = values.iter().all(|v| v.is_nan());
    b.push(pixel_type | 0x40 | if all_nodata { 0x20 } else { 0 });
    if size == 4 {
        let nd = nodata as f32;
        b.extend_from_slice(&nd.to_le_bytes());
        for &v in values {
            b.extend_from_slice(&(if v.is_nan() { nd } else { v as f32 }).to_le_bytes());
        }
    } else {
        b.extend_from_slice(&nodata.to_le_bytes());
        for &v in values {
            b.extend_from_slice(&(if v.is_nan() { nodata } else { v }).to_le_bytes());
        }
    }
    Ok(b)
}

/// WKB raster (little-endian) of one band of unsigned counts (row-major,
/// from the top row), `nodata` where a value is [`u16::MAX`]: in `8BUI`
/// (nodata 255) when `byte` (every other value must then be below 255),
/// else in `16BUI` (nodata 65535). As [`write_float`] otherwise.
pub fn write_counts(
    srid: i32,
    gt: &GeoTransform,
    width: usize,
    height: usize,
    byte: bool,
    values: &[u16],
) -> Result<Vec<u8>, IoError> {
    let (w, h) = sides(width, height)?;
    let n = width * height;
    if values.len() != n {
        return Err(IoError::Raster(format!(
            "{} values for {width} x {height} pixels",
            values.len()
        )));
    }
    if byte && values.iter().any(|&v| v != u16::MAX && v > 254) {
        return Err(IoError::Unsupported(
            "a count above 254 does not fit in 8BUI".into(),
        ));
    }
    let size = if byte { 1 } else { 2 };
    let mut b = Vec::with_capacity(61 + 1 + size + n * size);
    header(&mut b, srid, gt, w, h, n > 0);
    if n == 0 {
        return Ok(b);
    }
    let all_nodata = values.iter().all(|&v| v == u16::MAX);
    let flags = 0x40 | if all_nodata { 0x20 } else { 0 };
    if byte {
        b.push(4 | flags);
        b.push(255);
        b.extend(
            values
                .iter()
                .map(|&v| if v == u16::MAX { 255 } else { v as u8 }),
        );
    } else {
        b.push(6 | flags);
        b.extend_from_slice(&u16::MAX.to_le_bytes());
        for &v in values {
            b.extend_from_slice(&v.to_le_bytes());
        }
    }
    Ok(b)
}

/// A raster's width and height as its header's 16-bit fields.
fn sides(width: usize, height: usize) -> Result<(u16, u16), IoError> {
    let side = |n: usize| {
        u16::try_from(n).map_err(|_| {
            IoError::Unsupported(format!(
                "a raster of {width} x {height} pixels: PostGIS rasters have at most 65535 a side"
            ))
        })
    };
    Ok((side(width)?, side(height)?))
}

/// The WKB raster header: endianness, version, band count, georeference,
/// SRID and size.
fn header(b: &mut Vec<u8>, srid: i32, gt: &GeoTransform, w: u16, h: u16, band: bool) {
    b.push(1u8);
    b.extend_from_slice(&0u16.to_le_bytes());
    b.extend_from_slice(&u16::from(band).to_le_bytes());
    for v in [
        gt.scale_x, gt.scale_y, gt.ip_x, gt.ip_y, gt.skew_x, gt.skew_y,
    ] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b.extend_from_slice(&srid.to_le_bytes());
    b.extend_from_slice(&w.to_le_bytes());
    b.extend_from_slice(&h.to_le_bytes());
}

/// Heap needed to read one band of a `width` x `height` raster (values as
/// f64) and hand its pixels to triangles.
pub fn raster_bytes(width: usize, height: usize) -> usize {
    width
        .saturating_mul(height)
        .saturating_mul(9)
        .saturating_add(1 << 16)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_written_float_raster_reads_back() {
        let gt = GeoTransform {
            scale_x: 2.5,
            scale_y: -2.5,
            ip_x: 100.25,
            ip_y: 200.75,
            skew_x: 0.0,
            skew_y: 0.0,
        };
        let vals = [1.5, f64::NAN, -3.25, 1e6 + 0.1];
        for t in [10u8, 11] {
            let b = write_float(4326, &gt, 2, 2, t, -9999.0, &vals).unwrap();
            let r = read(&b, Some(1)).unwrap();
            assert_eq!((r.srid, r.width, r.height, r.gt), (4326, 2, 2, gt));
            let band = r.band.unwrap();
            assert_eq!(
                (band.pixel_type, band.nodata, band.all_nodata),
                (t, Some(-9999.0), false)
            );
            let want: Vec<f64> = if t == 11 {
                vec![1.5, -9999.0, -3.25, 1e6 + 0.1]
            } else {
                vec![1.5, -9999.0, -3.25, f64::from((1e6 + 0.1) as f32)]
            };
            assert_eq!(band.values, want);
        }
        let empty = write_float(0, &gt, 0, 3, 11, 0.0, &[]).unwrap();
        assert_eq!(read(&empty, None).unwrap().num_bands, 0);
        assert!(write_float(0, &gt, 70000, 1, 11, 0.0, &[]).is_err());
        assert!(write_float(0, &gt, 1, 1, 11, f64::NAN, &[0.0]).is_err());
        assert!(float_pixel_type("16BSI").is_err());
        assert_eq!(float_pixel_type("32bf").unwrap(), 10);
    }

    fn sample(le: bool) -> Vec<u8> {
        // 2 x 2, 16BSI, nodata -1, values 1 2 -1 4
        let mut b = vec![if le { 1 } else { 0 }];
        let put = |b: &mut Vec<u8>, v: &[u8]| {
            let mut v = v.to_vec();
            if !le {
                v.reverse();
            }
            b.extend_from_slice(&v);
        };
        put(&mut b, &0u16.to_le_bytes());
        put(&mut b, &1u16.to_le_bytes());
        for v in [10.0f64, -10.0, 100.0, 200.0, 0.0, 0.0] {
            put(&mut b, &v.to_le_bytes());
        }
        put(&mut b, &32616i32.to_le_bytes());
        put(&mut b, &2u16.to_le_bytes());
        put(&mut b, &2u16.to_le_bytes());
        b.push(0x40 | 5);
        put(&mut b, &(-1i16).to_le_bytes());
        for v in [1i16, 2, -1, 4] {
            put(&mut b, &v.to_le_bytes());
        }
        b
    }

    #[test]
    fn reads_both_byte_orders() {
        for le in [true, false] {
            let r = read(&sample(le), Some(1)).unwrap();
            assert_eq!((r.width, r.height, r.srid), (2, 2, 32616));
            let band = r.band.unwrap();
            assert_eq!(band.values, vec![1.0, 2.0, -1.0, 4.0]);
            assert!(!band.is_valid(-1.0));
            assert_eq!(r.gt.centre(1, 1), (115.0, 185.0));
        }
    }

    #[test]
    fn truncation_and_missing_band() {
        let b = sample(true);
        for n in 0..b.len() {
            assert!(read(&b[..n], Some(1)).is_err(), "prefix {n} accepted");
        }
        assert!(read(&b, Some(2)).is_err());
        assert!(read(&b, Some(0)).is_err());
    }
}
