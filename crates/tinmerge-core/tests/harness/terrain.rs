//! Random real terrain for the harness: a window of one of the bundled
//! DEMs, as it is or upsampled (bilinear, or nearest neighbour: terraces)
//! or with its heights rounded to integers, with nodata holes and a ragged
//! border, put on a random lattice (geographic 1", 1/3", 1/9" pixels or
//! projected ones of 0.5 to 100 m, origins with many digits, rows up or
//! down, square or not). Each carries the SQL that makes the same raster
//! from the pg_regress tables (`dem`: the UTM DEM, `dem_geo`: the
//! geographic one).

use crate::common::{self, Dem};
use rand::Rng;
use rand::rngs::StdRng;
use std::sync::OnceLock;
use tinmerge_core::tin::lattice::Lattice;

/// A raster for one trial: heights row by row (NaN: nodata), its lattice
/// and SRID, and how it was made.
pub struct Raster {
    pub z: Vec<f64>,
    pub w: usize,
    pub h: usize,
    pub lat: Lattice,
    pub srid: i32,
    /// what it is, for the messages
    pub desc: String,
    /// a SQL expression of type raster that makes it from the pg_regress
    /// tables, and whether it makes it bit for bit (an upsampled window is
    /// PostGIS's own bilinear or nearest neighbour, not the harness's)
    pub sql: String,
    pub sql_exact: bool,
}

impl Raster {
    /// Valid pixels.
    pub fn valid(&self) -> usize {
        self.z.iter().filter(|v| !v.is_nan()).count()
    }
    pub fn at(&self, c: i64, r: i64) -> Option<f64> {
        if c < 0 || r < 0 || c >= self.w as i64 || r >= self.h as i64 {
            return None;
        }
        let v = self.z[r as usize * self.w + c as usize];
        (!v.is_nan()).then_some(v)
    }
    /// World position of lattice point (col, row): the test's own affine
    /// map (GDAL's pixel centre: origin + (i + 0.5) * size).
    pub fn world(&self, c: f64, r: f64) -> [f64; 2] {
        let l = &self.lat;
        [
            l.ip_x + (c + 0.5) * l.scale_x + (r + 0.5) * l.skew_x,
            l.ip_y + (c + 0.5) * l.skew_y + (r + 0.5) * l.scale_y,
        ]
    }
    /// Lattice coordinates of a world point (the inverse of [`Raster::world`]).
    pub fn lattice_of(&self, p: &[f64]) -> [f64; 2] {
        let l = &self.lat;
        let (x, y) = (p[0] - l.ip_x, p[1] - l.ip_y);
        let det = l.scale_x * l.scale_y - l.skew_x * l.skew_y;
        [
            (l.scale_y * x - l.skew_x * y) / det - 0.5,
            (-l.skew_y * x + l.scale_x * y) / det - 0.5,
        ]
    }
    /// One pixel's area in world units.
    pub fn pixel_area(&self) -> f64 {
        let l = &self.lat;
        (l.scale_x * l.scale_y - l.skew_x * l.skew_y).abs()
    }
    /// The smaller side of a pixel in world units.
    pub fn pixel(&self) -> f64 {
        self.lat.scale_x.abs().min(self.lat.scale_y.abs())
    }
}

fn dems() -> &'static [(Dem, &'static str, i32); 2] {
    static D: OnceLock<[(Dem, &'static str, i32); 2]> = OnceLock::new();
    D.get_or_init(|| {
        [
            (
                common::read_dem("jacksboro_fault_dem_utm16n.tif"),
                "dem",
                32616,
            ),
            (common::read_dem("jacksboro_fault_dem.tif"), "dem_geo", 4326),
        ]
    })
}

/// A number with many digits in `lo..hi`.
fn digits(rng: &mut StdRng, lo: f64, hi: f64) -> f64 {
    rng.random_range(lo..hi) + rng.random::<f64>() * 1e-3
}

/// A ring as WKT, closed, every coordinate to the bit (`{:?}`).
pub fn wkt(ring: &[[f64; 2]]) -> String {
    let pts: Vec<String> = ring
        .iter()
        .chain(ring.first())
        .map(|p| format!("{:?} {:?}", p[0], p[1]))
        .collect();
    format!("({})", pts.join(","))
}

/// Crossing-number point in polygon.
pub fn inside(ring: &[[f64; 2]], p: [f64; 2]) -> bool {
    let mut c = false;
    let n = ring.len();
    for i in 0..n {
        let (a, b) = (ring[i], ring[(i + 1) % n]);
        if (a[1] > p[1]) != (b[1] > p[1])
            && p[0] < a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0])
        {
            c = !c;
        }
    }
    c
}

/// A random terrain (see the module doc).
pub fn terrain(rng: &mut StdRng) -> Raster {
    let which = rng.random_range(0..2usize);
    let (dem, table, src_srid) = &dems()[which];
    // the window, in the DEM's pixels
    // mostly small windows (many trials), a fifth up to 170 pixels (long
    // sides, deep hierarchies)
    let most = if rng.random_bool(0.2) { 170 } else { 100 };
    let (mut w, mut h) = (rng.random_range(12..=most), rng.random_range(12..=most));
    let kind = rng.random_range(0..10u32);
    let f = match kind {
        6 | 7 => rng.random_range(2..=3usize),
        _ => 1,
    };
    if f > 1 {
        w = w.min(150 / f);
        h = h.min(150 / f);
    }
    let (c0, r0) = (
        rng.random_range(0..=dem.width - w),
        rng.random_range(0..=dem.height - h),
    );
    let px = dem.scale_x;
    let at = |c: usize, r: usize| {
        let v = dem.values[(r0 + r) * dem.width + c0 + c];
        if v.is_nan() || Some(v) == dem.nodata {
            f64::NAN
        } else {
            v
        }
    };
    // the window cut with ST_Clip on an envelope a quarter pixel inside it
    let (x0, y1) = (
        dem.origin_x + c0 as f64 * px,
        dem.origin_y - r0 as f64 * dem.scale_y,
    );
    let (x1, y0) = (x0 + w as f64 * px, y1 - h as f64 * dem.scale_y);
    let q = 0.25 * px;
    let mut sql = format!(
        "ST_Clip(rast, ST_MakeEnvelope({}, {}, {}, {}, {src_srid}))",
        x0 + q,
        y0 + q,
        x1 - q,
        y1 - q
    );
    let mut sql_exact = true;
    let mut desc = format!("{table} window {w}x{h} at col {c0}, row {r0}");
    // values: as they are, upsampled, or rounded
    let (fw, fh) = (w * f, h * f);
    let mut z = vec![f64::NAN; fw * fh];
    match kind {
        6 => {
            // nearest neighbour: terraces
            for r in 0..fh {
                for c in 0..fw {
                    z[r * fw + c] = at(c / f, r / f);
                }
            }
            sql = format!(
                "ST_Rescale({sql}, {}, {}, 'NearestNeighbour')",
                px / f as f64,
                -dem.scale_y / f as f64
            );
            desc += &format!(", nearest neighbour x{f}");
        }
        7 => {
            // bilinear between the window's pixel centres (nodata where a
            // corner is)
            for r in 0..fh {
                for c in 0..fw {
                    let (u, v) = (
                        ((c as f64 + 0.5) / f as f64 - 0.5).clamp(0.0, (w - 1) as f64),
                        ((r as f64 + 0.5) / f as f64 - 0.5).clamp(0.0, (h - 1) as f64),
                    );
                    let (i, j) = ((u as usize).min(w - 2), (v as usize).min(h - 2));
                    let (s, t) = (u - i as f64, v - j as f64);
                    z[r * fw + c] = (1.0 - t) * ((1.0 - s) * at(i, j) + s * at(i + 1, j))
                        + t * ((1.0 - s) * at(i, j + 1) + s * at(i + 1, j + 1));
                }
            }
            sql = format!(
                "ST_Rescale({sql}, {}, {}, 'Bilinear')",
                px / f as f64,
                -dem.scale_y / f as f64
            );
            sql_exact = false;
            desc += &format!(", bilinear x{f}");
        }
        8 => {
            for r in 0..fh {
                for c in 0..fw {
                    z[r * fw + c] = at(c, r).round_ties_even();
                }
            }
            sql = format!("ST_MapAlgebra({sql}, 1, NULL, 'round([rast])')");
            desc += ", heights rounded to integers";
        }
        _ => {
            for r in 0..fh {
                for c in 0..fw {
                    z[r * fw + c] = at(c, r);
                }
            }
        }
    }
    let (w, h, fpx, fpy) = (fw, fh, px / f as f64, dem.scale_y / f as f64);
    let centre = |c: usize, r: usize| [x0 + (c as f64 + 0.5) * fpx, y1 - (r as f64 + 0.5) * fpy];
    // nodata: a ragged border (the pixels outside a polygon cutting the
    // window's corners) and round holes, by their centres (ST_Clip's rule)
    let mut keep: Vec<Vec<[f64; 2]>> = Vec::new();
    let mut holes: Vec<Vec<[f64; 2]>> = Vec::new();
    if rng.random_bool(0.3) {
        let (cx, cy, rx, ry) = (
            (x0 + x1) / 2.0,
            (y0 + y1) / 2.0,
            (x1 - x0) / 2.0,
            (y1 - y0) / 2.0,
        );
        let n = rng.random_range(5..12);
        let ring: Vec<[f64; 2]> = (0..n)
            .map(|k| {
                let a = std::f64::consts::TAU * (k as f64 + rng.random_range(0.0..0.8)) / n as f64;
                let s = rng.random_range(0.75..1.3);
                [cx + s * rx * a.cos(), cy + s * ry * a.sin()]
            })
            .collect();
        keep.push(ring);
    }
    for _ in 0..rng.random_range(0..3) {
        if rng.random_bool(0.6) {
            continue;
        }
        let (hx, hy) = (rng.random_range(x0..x1), rng.random_range(y0..y1));
        let rad = rng.random_range(0.8..4.0) * px;
        holes.push(
            (0..12)
                .map(|k| {
                    let a = std::f64::consts::TAU * k as f64 / 12.0;
                    [hx + rad * a.cos(), hy + rad * a.sin()]
                })
                .collect(),
        );
    }
    if !keep.is_empty() || !holes.is_empty() {
        for r in 0..h {
            for c in 0..w {
                let p = centre(c, r);
                if keep.iter().any(|k| !inside(k, p)) || holes.iter().any(|k| inside(k, p)) {
                    z[r * w + c] = f64::NAN;
                }
            }
        }
        let shell = keep.first().map(|k| wkt(k)).unwrap_or_else(|| {
            wkt(&[
                [x0 - px, y0 - px],
                [x1 + px, y0 - px],
                [x1 + px, y1 + px],
                [x0 - px, y1 + px],
            ])
        });
        let inner: Vec<String> = holes.iter().map(|k| wkt(k)).collect();
        let poly = std::iter::once(shell)
            .chain(inner)
            .collect::<Vec<_>>()
            .join(",");
        sql = format!("ST_Clip({sql}, 'SRID={src_srid};POLYGON({poly})'::geometry)");
        desc += &format!(
            ", {}{} holes",
            if keep.is_empty() {
                ""
            } else {
                "ragged border, "
            },
            holes.len()
        );
    }
    // the lattice it is put on
    let (scale_x, geographic, lname) = match rng.random_range(0..7u32) {
        0 => (1.0 / 3600.0, true, "1\""),
        1 => (1.0 / 10800.0, true, "1/3\""),
        2 | 3 => (1.0 / 32400.0, true, "1/9\""),
        _ => {
            let s = if rng.random_bool(0.5) {
                [0.5, 1.0, 2.0, 3.0, 10.0, 30.0, 90.0, 100.0][rng.random_range(0..8)]
            } else {
                (rng.random_range(0.5f64.ln()..100f64.ln())).exp()
            };
            (s, false, "projected")
        }
    };
    let sy = if rng.random_bool(0.25) {
        scale_x * rng.random_range(0.5..2.0)
    } else {
        scale_x
    };
    let down = !rng.random_bool(0.15);
    let (ox, oy, srid) = if geographic {
        (digits(rng, -179.0, 170.0), digits(rng, -80.0, 75.0), 4326)
    } else {
        (digits(rng, 1e5, 9e5), digits(rng, 1e6, 9e6), 32616)
    };
    let lat = Lattice {
        ip_x: ox,
        ip_y: oy,
        scale_x,
        scale_y: if down { -sy } else { sy },
        skew_x: 0.0,
        skew_y: 0.0,
    };
    sql = format!(
        "ST_SetSRID(ST_SetScale(ST_SetUpperLeft({sql}, {ox:?}, {oy:?}), {:?}, {:?}), {srid})",
        lat.scale_x, lat.scale_y
    );
    desc += &format!(
        ", on {lname} pixels {} x {}, origin ({ox}, {oy}), rows {}",
        lat.scale_x,
        lat.scale_y,
        if down { "down" } else { "up" }
    );
    Raster {
        z,
        w,
        h,
        lat,
        srid,
        desc,
        sql,
        sql_exact,
    }
}
