//! Test support: read the bundled GeoTIFF DEMs with the `tiff` crate (an
//! independent reader: the extension itself never parses TIFF).
#![allow(dead_code)]

pub mod grids;

use std::fs::File;
use tiff::decoder::{Decoder, DecodingResult};
use tiff::tags::Tag;

/// The lattice frame itself: pixel (col, row) at (col, row), so a tin
/// built on it by `build_lattice` is in the samples' own coordinates.
pub const IDENTITY: tinmerge_core::tin::lattice::Lattice = tinmerge_core::tin::lattice::Lattice {
    ip_x: -0.5,
    ip_y: -0.5,
    scale_x: 1.0,
    scale_y: 1.0,
    skew_x: 0.0,
    skew_y: 0.0,
};

pub struct Dem {
    pub width: usize,
    pub height: usize,
    pub origin_x: f64,
    pub origin_y: f64,
    pub scale_x: f64,
    pub scale_y: f64,
    pub nodata: Option<f64>,
    pub values: Vec<f64>,
}

impl Dem {
    /// The DEM on an `f` times finer grid (each pixel `f x f` sub-pixels
    /// with its value): geotransform, width, height, values (row-major).
    pub fn upsampled(
        &self,
        f: usize,
    ) -> (
        tinmerge_core::io::raster::GeoTransform,
        usize,
        usize,
        Vec<f64>,
    ) {
        let d = self.window_finer(0, 0, self.width, self.height, f);
        (d.geotransform(), d.width, d.height, d.values)
    }

    /// The window of `w x h` pixels from column `c0`, row `r0`, on an `f`
    /// times finer grid (nearest neighbour: each pixel `f x f` sub-pixels
    /// with its value, so flat blocks with one-sub-pixel steps between).
    pub fn window_finer(&self, c0: usize, r0: usize, w: usize, h: usize, f: usize) -> Dem {
        let (fw, fh) = (w * f, h * f);
        let mut values = Vec::with_capacity(fw * fh);
        for row in 0..fh {
            for col in 0..fw {
                values.push(self.values[(r0 + row / f) * self.width + c0 + col / f]);
            }
        }
        Dem {
            width: fw,
            height: fh,
            origin_x: self.origin_x + c0 as f64 * self.scale_x,
            origin_y: self.origin_y - r0 as f64 * self.scale_y,
            scale_x: self.scale_x / f as f64,
            scale_y: self.scale_y / f as f64,
            nodata: self.nodata,
            values,
        }
    }

    /// The DEM's geotransform (north up).
    pub fn geotransform(&self) -> tinmerge_core::io::raster::GeoTransform {
        tinmerge_core::io::raster::GeoTransform {
            scale_x: self.scale_x,
            scale_y: -self.scale_y,
            ip_x: self.origin_x,
            ip_y: self.origin_y,
            skew_x: 0.0,
            skew_y: 0.0,
        }
    }

    /// The DEM's pixel lattice (north up), as `tin_from_raster` builds on.
    pub fn lattice(&self) -> tinmerge_core::tin::lattice::Lattice {
        tinmerge_core::tin::lattice::Lattice {
            ip_x: self.origin_x,
            ip_y: self.origin_y,
            scale_x: self.scale_x,
            scale_y: -self.scale_y,
            skew_x: 0.0,
            skew_y: 0.0,
        }
    }

    pub fn centre(&self, col: usize, row: usize) -> (f64, f64) {
        (
            self.origin_x + (col as f64 + 0.5) * self.scale_x,
            self.origin_y - (row as f64 + 0.5) * self.scale_y,
        )
    }

    /// Valid samples (x, y, z) at pixel centres.
    pub fn samples(&self) -> Vec<[f64; 3]> {
        let mut out = Vec::new();
        for r in 0..self.height {
            for c in 0..self.width {
                let v = self.values[r * self.width + c];
                if v.is_nan() || Some(v) == self.nodata {
                    continue;
                }
                let (x, y) = self.centre(c, r);
                out.push([x, y, v]);
            }
        }
        out
    }
}

pub fn data_path(name: &str) -> String {
    format!("{}/../../tests/data/{}", env!("CARGO_MANIFEST_DIR"), name)
}

pub fn read_dem(name: &str) -> Dem {
    let f = File::open(data_path(name)).expect("open DEM");
    let mut d = Decoder::new(f).expect("tiff decoder");
    let (w, h) = d.dimensions().expect("dimensions");
    let scale = d
        .get_tag_f64_vec(Tag::ModelPixelScaleTag)
        .expect("pixel scale");
    let tie = d.get_tag_f64_vec(Tag::ModelTiepointTag).expect("tiepoint");
    let nodata = d
        .get_tag_ascii_string(Tag::GdalNodata)
        .ok()
        .and_then(|s| s.trim_matches(char::from(0)).trim().parse::<f64>().ok());
    let values: Vec<f64> = match d.read_image().expect("read image") {
        DecodingResult::F32(v) => v.into_iter().map(|x| x as f64).collect(),
        DecodingResult::F64(v) => v,
        _ => panic!("unexpected sample format"),
    };
    Dem {
        width: w as usize,
        height: h as usize,
        origin_x: tie[3] - tie[0] * scale[0],
        origin_y: tie[4] + tie[1] * scale[1],
        scale_x: scale[0],
        scale_y: scale[1],
        nodata,
        values,
    }
}

/// The UTM DEM as a tin: tolerance 2 m at the finest of 5 levels (the
/// extension's own build: tests of the merges start from it).
pub fn dem_tin() -> tinmerge_core::tin::Tin {
    use tinmerge_core::tin::build::{build, default_tolerances};
    let dem = read_dem("jacksboro_fault_dem_utm16n.tif");
    build(
        dem.samples(),
        &default_tolerances(2.0, 5).unwrap(),
        32616,
        &mut || Ok(()),
    )
    .unwrap()
}

/// The geographic bundled DEM (EPSG:4326) built at 4 levels, the finest at
/// `tolerance`: the second terrain of [`terrains`].
pub fn geo_tin(tolerance: f64) -> tinmerge_core::tin::Tin {
    use tinmerge_core::tin::build::{build, default_tolerances};
    let dem = read_dem("jacksboro_fault_dem.tif");
    build(
        dem.samples(),
        &default_tolerances(tolerance, 4).unwrap(),
        4326,
        &mut || Ok(()),
    )
    .unwrap()
}

/// The terrains the per-element oracles (point location and heights,
/// footprints, line clipping, area relation and coverage, raster pixel
/// ownership) run on: the UTM DEM (5 levels, metres), the geographic DEM
/// (4 levels, degrees: a grid whose pixels are not square in its own
/// units), and the geographic DEM over its valid cells with a 30 x 20 pixel
/// nodata hole (void triangles around and inside the domain).
pub struct Terrain {
    /// for the messages
    pub name: &'static str,
    /// the bundled DEM it is built from (`read_dem`)
    pub file: &'static str,
    pub tin: tinmerge_core::tin::Tin,
}

#[allow(dead_code)]
pub fn terrains() -> Vec<Terrain> {
    vec![
        Terrain {
            name: "UTM DEM",
            file: "jacksboro_fault_dem_utm16n.tif",
            tin: dem_tin(),
        },
        Terrain {
            name: "geographic DEM",
            file: "jacksboro_fault_dem.tif",
            tin: geo_tin(2.0),
        },
        Terrain {
            name: "geographic DEM with a nodata hole",
            file: "jacksboro_fault_dem.tif",
            tin: data_tin("jacksboro_fault_dem.tif", 4326, 2.0),
        },
    ]
}

/// A bundled DEM built over where it has data (its valid cells' outline,
/// as `tin_from_raster`'s default), with a 30 x 20 pixel nodata hole cut
/// into it: a tin with void triangles around and inside its domain, at 4
/// levels, the finest at `tolerance`.
#[allow(dead_code)]
pub fn data_tin(name: &str, srid: i32, tolerance: f64) -> tinmerge_core::tin::Tin {
    use tinmerge_core::tin::build::{build_domain, default_tolerances};
    use tinmerge_core::tin::domain::{cell_outline, outline_area};
    let mut d = read_dem(name);
    let nodata = d.nodata.unwrap_or(-9999.0);
    d.nodata = Some(nodata);
    for r in 150..170 {
        for c in 200..230 {
            d.values[r * d.width + c] = nodata;
        }
    }
    let ok = |v: f64| !(v.is_nan() || v == nodata);
    let (w, h) = (d.width, d.height);
    let rings = cell_outline(w, h, &|c, r| ok(d.values[r * w + c]));
    let area = outline_area(&rings, &|c, r| {
        [d.origin_x + c * d.scale_x, d.origin_y - r * d.scale_y]
    });
    build_domain(
        d.samples(),
        &[],
        &[&area],
        &default_tolerances(tolerance, 4).unwrap(),
        srid,
        &mut || Ok(()),
    )
    .unwrap()
}

/// A DEM cut into `n`-pixel tiles with `build_tiles` (each tile's tin with
/// its neighbours' border samples, keep_border), as (tx, ty, tin) in the
/// order built.
/// The DEM cut as `raster2pgsql -t n x n` cuts it (row by row, each tile
/// its own origin, the last column and row narrower): each tile's own
/// lattice, width, height and values.
#[allow(dead_code)]
pub fn table_of(
    d: &Dem,
    n: usize,
) -> Vec<(tinmerge_core::tin::lattice::Lattice, usize, usize, Vec<f64>)> {
    let lat = d.lattice();
    let mut table = Vec::new();
    for r0 in (0..d.height).step_by(n) {
        for c0 in (0..d.width).step_by(n) {
            let (w, h) = (n.min(d.width - c0), n.min(d.height - r0));
            let own = tinmerge_core::tin::lattice::Lattice {
                ip_x: lat.ip_x + c0 as f64 * lat.scale_x + r0 as f64 * lat.skew_x,
                ip_y: lat.ip_y + c0 as f64 * lat.skew_y + r0 as f64 * lat.scale_y,
                ..lat
            };
            let vals = (r0..r0 + h)
                .flat_map(|r| d.values[r * d.width + c0..r * d.width + c0 + w].to_vec())
                .collect();
            table.push((own, w, h, vals));
        }
    }
    table
}

#[allow(dead_code)]
/// The planning rounds of `tin_tiles_from_table` (the core's
/// `SeamRounds`, which the SQL function runs) over the tiles whose row is
/// in `plan` (tiles outside are not there: as a table without them), then
/// the encoded tins of the tiles in `own` rows, by (tx, ty).
pub fn table_build(
    grid: &tinmerge_core::tin::tiles::TableGrid,
    blocks: &[tinmerge_core::tin::tiles::Block],
    tols: &[f64],
    srid: i32,
    plan: std::ops::Range<usize>,
    own: std::ops::Range<usize>,
) -> Vec<((usize, usize), Vec<u8>)> {
    table_rounds(
        grid,
        blocks,
        tinmerge_core::tin::seam_rounds::SeamRounds::rows(
            grid,
            tols.to_vec(),
            srid,
            true,
            own,
            plan,
        ),
        None,
    )
}

/// The tiles of `blocks` (placed on `grid`) built by `rounds`, encoded, in
/// (tx, ty) order: what `tin_tiles_from_table` returns. With `held`, each
/// tile's last build held up to that many bytes of encoded tins (past
/// them, dropped and every tile built once more at the end), as
/// `tin_tiles_from_table` holds them; whether they were dropped.
#[allow(dead_code)]
pub fn table_rounds(
    grid: &tinmerge_core::tin::tiles::TableGrid,
    blocks: &[tinmerge_core::tin::tiles::Block],
    rounds: tinmerge_core::tin::seam_rounds::SeamRounds,
    held: Option<usize>,
) -> Vec<((usize, usize), Vec<u8>)> {
    table_rounds_held(grid, blocks, rounds, held).0
}

/// Encoded tins by (tx, ty).
pub type Encoded = Vec<((usize, usize), Vec<u8>)>;

/// [`table_rounds`] and whether what was held was dropped.
#[allow(dead_code)]
pub fn table_rounds_held(
    grid: &tinmerge_core::tin::tiles::TableGrid,
    blocks: &[tinmerge_core::tin::tiles::Block],
    mut rounds: tinmerge_core::tin::seam_rounds::SeamRounds,
    held: Option<usize>,
) -> (Encoded, bool) {
    use tinmerge_core::io::raster::Band;
    use tinmerge_core::tin::TinError;
    use tinmerge_core::tin::seam_rounds::TileReader;
    // the blocks as bands, nodata NaN, read as SPI reads them: only the
    // tiles asked for
    struct Memory<'a>(&'a [tinmerge_core::tin::tiles::Block<'a>]);
    impl TileReader for Memory<'_> {
        fn read(&mut self, want: &[usize]) -> Result<Vec<(usize, Band)>, TinError> {
            Ok(want
                .iter()
                .map(|&k| {
                    let b = &self.0[k];
                    let values = b
                        .values
                        .iter()
                        .map(|&v| if (b.valid)(v) { v } else { f64::NAN })
                        .collect();
                    let band = Band {
                        pixel_type: 11,
                        nodata: None,
                        all_nodata: false,
                        values,
                    };
                    (k, band)
                })
                .collect())
        }
    }
    // the blocks in the grid's order
    let mut by_place: Vec<Option<&tinmerge_core::tin::tiles::Block>> = vec![None; grid.tiles.len()];
    for b in blocks {
        if let Some(k) = grid
            .tiles
            .iter()
            .position(|p| (p.tx, p.ty) == (b.place.tx, b.place.ty))
        {
            by_place[k] = Some(b);
        }
    }
    let ordered: Vec<tinmerge_core::tin::tiles::Block> = by_place
        .into_iter()
        .map(|b| {
            let b = b.expect("a block for every tile of the grid");
            tinmerge_core::tin::tiles::Block {
                place: b.place,
                values: b.values,
                valid: b.valid,
            }
        })
        .collect();
    let mut reader = Memory(&ordered);
    let mut out = Vec::new();
    type Out = ((usize, usize), Vec<u8>);
    let mut hold =
        tinmerge_core::tin::seam_rounds::Held::new(held.unwrap_or(0), |o: &Out| o.1.len());
    if held.is_some() {
        rounds.hold();
    }
    while let Some(batch) = rounds
        .next_held(
            &mut hold,
            grid,
            &mut reader,
            &|tx, ty, t| ((tx, ty), tinmerge_core::tin::layout::encode(&t)),
            &mut |_| Ok(()),
        )
        .unwrap()
    {
        out.extend(batch);
    }
    let n = out.len();
    out.sort_by_key(|o| o.0);
    out.dedup_by_key(|o| o.0);
    assert_eq!(out.len(), n, "a tile handed out twice");
    (out, hold.dropped())
}

#[allow(dead_code)]
pub fn tiles_of(
    d: &Dem,
    n: usize,
    tols: &[f64],
    srid: i32,
) -> Vec<(usize, usize, tinmerge_core::tin::Tin)> {
    tiles_and_seams_of(d, n, tols, srid).0
}

/// [`tiles_of`] and the seam samples the tiles kept.
#[allow(dead_code)]
pub fn tiles_and_seams_of(
    d: &Dem,
    n: usize,
    tols: &[f64],
    srid: i32,
) -> (
    Vec<(usize, usize, tinmerge_core::tin::Tin)>,
    tinmerge_core::tin::tiles::Seams,
) {
    let valid = |v: f64| !v.is_nan() && Some(v) != d.nodata;
    let mut tiles = Vec::new();
    let seams = tinmerge_core::tin::seam_rounds::build_tiles(
        &d.values,
        d.width,
        d.height,
        &valid,
        &d.lattice(),
        n,
        tols,
        true,
        srid,
        &mut || Ok(()),
        &|tx, ty, t| (tx, ty, t),
        &mut |t| {
            tiles.push(t);
            Ok(())
        },
    )
    .unwrap();
    (tiles, seams)
}

/// Convex polygon clipped to the left of the line a -> b (Sutherland-Hodgman
/// step): the tests' own clipper, independent of the extension's.
pub fn clip_half(poly: &[[f64; 2]], a: [f64; 2], b: [f64; 2]) -> Vec<[f64; 2]> {
    // keep the side left of a->b
    // exact signs, values up to a rounding: a crossing is then where the
    // exact one is up to a rounding of its parameter
    let co = |p: [f64; 2]| robust::Coord { x: p[0], y: p[1] };
    let side = |p: [f64; 2]| robust::orient2d(co(a), co(b), co(p));
    let mut out = Vec::with_capacity(poly.len() + 1);
    for i in 0..poly.len() {
        let (p, q) = (poly[i], poly[(i + 1) % poly.len()]);
        let (sp, sq) = (side(p), side(q));
        if sp >= 0.0 {
            out.push(p);
        }
        if (sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0) {
            let t = sp / (sp - sq);
            out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
        }
    }
    out
}

/// Parameter of p along a-b and its distance from the line, in units of
/// the segment's length.
pub fn along(a: &[f64; 3], b: &[f64; 3], p: &[f64; 3]) -> (f64, f64) {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let t = ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2;
    let d = ((p[0] - a[0]) * dy - (p[1] - a[1]) * dx).abs() / l2;
    (t, d)
}

/// Whether edge p-q lies on segment a-b (both ends on its line within
/// `eps` of its length, inside its extent).
pub fn edge_on(
    a: &[f64; 3],
    b: &[f64; 3],
    p: &[f64; 3],
    q: &[f64; 3],
    eps: f64,
) -> Option<(f64, f64)> {
    let (tp, dp) = along(a, b, p);
    let (tq, dq) = along(a, b, q);
    (dp <= eps && dq <= eps && tp.min(tq) >= -eps && tp.max(tq) <= 1.0 + eps)
        .then(|| (tp.min(tq), tp.max(tq)))
}

/// The height at `(x, y)` of the plane through a triangle's three corners,
/// by the normal of their cross product: the tests' own interpolation (no
/// code of the extension's), for the oracles.
#[allow(dead_code)]
pub fn plane_height(c: &[[f64; 3]; 3], x: f64, y: f64) -> f64 {
    let n = normal(c);
    c[0][2] - (n[0] * (x - c[0][0]) + n[1] * (y - c[0][1])) / n[2]
}

/// The cross product of a triangle's sides from its first corner: its
/// normal, twice its area long (z up for a counter-clockwise triangle).
#[allow(dead_code)]
pub fn normal(c: &[[f64; 3]; 3]) -> [f64; 3] {
    let u = [c[1][0] - c[0][0], c[1][1] - c[0][1], c[1][2] - c[0][2]];
    let v = [c[2][0] - c[0][0], c[2][1] - c[0][1], c[2][2] - c[0][2]];
    [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ]
}
