//! Generated rasters for the tests of every grid: fractional origins,
//! geographic and projected pixel sizes, both row directions, nodata holes
//! and rotated nodata borders (the rough terrain of waves, a ridge and
//! noise), seeded.
#![allow(dead_code)]

use rand::Rng;
use rand::rngs::StdRng;
use tinmerge_core::tin::lattice::Lattice;

/// A generated raster: lattice, size, values (NaN = nodata).
pub struct Grid {
    pub name: String,
    pub lat: Lattice,
    pub w: usize,
    pub h: usize,
    pub z: Vec<f64>,
}

impl Grid {
    /// The test's own pixel-centre formula (GDAL's: origin + (i + 0.5) * size).
    pub fn centre(&self, c: i64, r: i64) -> (f64, f64) {
        let (c, r) = (c as f64 + 0.5, r as f64 + 0.5);
        (
            self.lat.ip_x + c * self.lat.scale_x,
            self.lat.ip_y + r * self.lat.scale_y,
        )
    }
    pub fn valid(&self) -> Vec<(i64, i64, f64)> {
        let mut v = Vec::new();
        for r in 0..self.h {
            for c in 0..self.w {
                let z = self.z[r * self.w + c];
                if !z.is_nan() {
                    v.push((c as i64, r as i64, z));
                }
            }
        }
        v
    }
}

const SIZES: &[(&str, f64, bool)] = &[
    ("1/3600 deg", 1.0 / 3600.0, true),
    ("1/1200 deg", 1.0 / 1200.0, true),
    ("1/3 arc-second", 1.0 / 10800.0, true),
    ("0.3 m", 0.3, false),
    ("30 m", 30.0, false),
    ("800 m", 800.0, false),
];

pub fn generate(rng: &mut StdRng, k: usize) -> Grid {
    let (sname, size, geographic) = SIZES[k % SIZES.len()];
    let w = rng.random_range(24..90usize);
    let h = rng.random_range(24..90usize);
    let (ox, oy) = if geographic {
        (
            rng.random_range(-179.0..170.0) + rng.random::<f64>(),
            rng.random_range(-80.0..80.0) + rng.random::<f64>(),
        )
    } else {
        (
            49_072.339_790_118_44 + rng.random_range(0.0..600000.0),
            4060000.0 + rng.random_range(0.0..1e6) + rng.random::<f64>(),
        )
    };
    // rows running down (north-up, the usual) or up
    let down = k % 4 != 3;
    let lat = Lattice {
        ip_x: ox,
        ip_y: oy,
        scale_x: size,
        scale_y: if down { -size } else { size },
        skew_x: 0.0,
        skew_y: 0.0,
    };
    // a rough terrain: waves, a ridge and noise, in metres
    let (fa, fb, ph) = (
        rng.random_range(0.05..0.4),
        rng.random_range(0.05..0.4),
        rng.random::<f64>() * 6.0,
    );
    let mut z = vec![0.0; w * h];
    for r in 0..h {
        for c in 0..w {
            let (x, y) = (c as f64, r as f64);
            z[r * w + c] = 300.0
                + 40.0 * (fa * x + ph).sin() * (fb * y).cos()
                + 25.0 * (-(x - y * 0.7 - 10.0).abs() / 6.0).exp()
                + rng.random::<f64>() * 3.0;
        }
    }
    // nodata: a rotated border on some grids (diagonal hull edges), holes
    let mut border = String::new();
    if !k.is_multiple_of(3) {
        let (cx, cy) = (w as f64 / 2.0, h as f64 / 2.0);
        let a: f64 = rng.random_range(0.2..0.9);
        let (s, co) = a.sin_cos();
        let (hw, hh) = (w as f64 * 0.42, h as f64 * 0.42);
        for r in 0..h {
            for c in 0..w {
                let (dx, dy) = (c as f64 - cx, r as f64 - cy);
                if (dx * co + dy * s).abs() > hw || (-dx * s + dy * co).abs() > hh {
                    z[r * w + c] = f64::NAN;
                }
            }
        }
        border = format!(", border rotated {a:.2}");
    }
    let holes = rng.random_range(0..4);
    for _ in 0..holes {
        let (hx, hy, rad) = (
            rng.random_range(0.0..w as f64),
            rng.random_range(0.0..h as f64),
            rng.random_range(1.0..5.0),
        );
        for r in 0..h {
            for c in 0..w {
                if (c as f64 - hx).hypot(r as f64 - hy) < rad {
                    z[r * w + c] = f64::NAN;
                }
            }
        }
    }
    Grid {
        name: format!(
            "grid {k}: {w}x{h}, {sname}, origin ({ox}, {oy}), rows {}{border}, {holes} holes",
            if down { "down" } else { "up" }
        ),
        lat,
        w,
        h,
        z,
    }
}
