//! The quantized-mesh water mask extension (id 2): which of a tile's
//! 256 x 256 mask cells are water, from polygons in longitude/latitude.
//!
//! A cell is water (255) when its centre is in (or on the boundary of) one
//! of the polygons, land (0) otherwise. Rows run north to south and columns
//! west to east, as the [spec](https://github.com/CesiumGS/quantized-mesh)
//! and Cesium's texture read them: cell (row `i`, column `j`) has its
//! centre at longitude `west + (j + 0.5) * (east - west) / 256` and
//! latitude `north - (i + 0.5) * (north - south) / 256`. A tile all land
//! or all water is the one-byte form (0 or 255).
//!
//! **How.** A scanline per row of centres: every ring edge that spans the
//! row's latitude (half-open, so a vertex on the row is crossed once) gives
//! a crossing; between pairs of crossings of one polygon (even-odd over its
//! rings, so holes are land) the centres are water. Each polygon is filled
//! on its own and the results are united, so overlapping polygons (an
//! `ST_Collect` of lakes) are water where any of them is. Edges are
//! straight in longitude/latitude, as PostGIS's `ST_Intersects` on the
//! polygons in EPSG:4326 sees them. The work is the edges plus the
//! crossings, not a point-in-polygon test per cell (the `geo` crate's
//! `Contains` would be one per cell and edge).
//!
//! ```
//! use tinmerge_core::serve::quantized_mesh::{water_mask, MASK_SIZE};
//! use tinmerge_core::serve::tiling::tile_bounds;
//! let tile = tile_bounds(1, 0, 0).unwrap(); // 180°W..90°W, 90°S..0°
//! // a lake over the tile's western half
//! let lake = vec![vec![[-180.0, -90.0], [-135.0, -90.0], [-135.0, 0.0], [-180.0, 0.0], [-180.0, -90.0]]];
//! let mask = water_mask(&tile, &[lake], &mut || Ok(())).unwrap();
//! assert_eq!(mask.len(), MASK_SIZE * MASK_SIZE);
//! assert_eq!((mask[0], mask[255]), (255, 0)); // north-west water, north-east land
//! let none = water_mask(&tile, &[], &mut || Ok(())).unwrap();
//! assert_eq!(none, vec![0]); // all land: one byte
//! ```

use crate::interrupt::Interrupt;
use crate::serve::tiling::TileBounds;
use crate::tin::TinError;

/// Cells of the mask on a side.
pub const MASK_SIZE: usize = 256;

/// A polygon: its rings (the outer first, then holes; closed or not) of
/// longitude/latitude points in degrees.
pub type WaterPolygon = Vec<Vec<[f64; 2]>>;

/// The tile's water mask: 65,536 bytes, or one byte (0 all land, 255 all
/// water).
pub fn water_mask(
    tile: &TileBounds,
    polygons: &[WaterPolygon],
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<u8>, TinError> {
    let n = MASK_SIZE;
    let (dx, dy) = (
        (tile.east - tile.west) / n as f64,
        (tile.north - tile.south) / n as f64,
    );
    let centre_y = |i: usize| tile.north - (i as f64 + 0.5) * dy;
    let mut mask = vec![0u8; n * n];
    let mut rows: Vec<Vec<f64>> = vec![Vec::new(); n];
    for poly in polygons {
        interrupt()?;
        let (mut s, mut no) = (f64::INFINITY, f64::NEG_INFINITY);
        let (mut w, mut e) = (f64::INFINITY, f64::NEG_INFINITY);
        for p in poly.iter().flatten() {
            w = w.min(p[0]);
            e = e.max(p[0]);
            s = s.min(p[1]);
            no = no.max(p[1]);
        }
        if !tile.intersects(&[w, s, e, no]) {
            continue;
        }
        for r in rows.iter_mut() {
            r.clear();
        }
        for ring in poly {
            if ring.len() < 2 {
                continue;
            }
            // the ring closed (a repeated first point adds a null edge)
            let m = ring.len();
            for k in 0..m {
                let (a, b) = (ring[k], ring[(k + 1) % m]);
                let (lo, hi) = if a[1] <= b[1] {
                    (a[1], b[1])
                } else {
                    (b[1], a[1])
                };
                if hi < tile.south || lo > tile.north || lo == hi {
                    continue;
                }
                // rows whose centre y is in [lo, hi): y_i = north - (i + 0.5) dy
                let first = (((tile.north - hi) / dy - 0.5).floor().max(0.0)) as usize;
                let last =
                    (((tile.north - lo) / dy - 0.5).ceil().min(n as f64 - 1.0)).max(0.0) as usize;
                for (i, row) in rows.iter_mut().enumerate().take(last + 1).skip(first) {
                    let y = centre_y(i);
                    if (a[1] <= y) != (b[1] <= y) {
                        row.push(a[0] + (y - a[1]) * (b[0] - a[0]) / (b[1] - a[1]));
                    }
                }
            }
        }
        for (i, xs) in rows.iter_mut().enumerate() {
            if xs.len() < 2 {
                continue;
            }
            xs.sort_by(f64::total_cmp);
            for pair in xs.chunks_exact(2) {
                // columns whose centre x is in [x0, x1]
                let j0 = ((pair[0] - tile.west) / dx - 0.5).ceil().max(0.0);
                let j1 = ((pair[1] - tile.west) / dx - 0.5)
                    .floor()
                    .min(n as f64 - 1.0);
                if j1 < j0 {
                    continue;
                }
                mask[i * n + j0 as usize..=i * n + j1 as usize].fill(255);
            }
        }
    }
    let first = mask[0];
    Ok(if mask.iter().all(|&c| c == first) {
        vec![first]
    } else {
        mask
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::serve::tiling::tile_bounds;

    /// Even-odd point in polygon, the brute force.
    fn inside(poly: &WaterPolygon, x: f64, y: f64) -> bool {
        let mut c = false;
        for ring in poly {
            let m = ring.len();
            for k in 0..m {
                let (a, b) = (ring[k], ring[(k + 1) % m]);
                if (a[1] <= y) != (b[1] <= y)
                    && x < a[0] + (y - a[1]) * (b[0] - a[0]) / (b[1] - a[1])
                {
                    c = !c;
                }
            }
        }
        c
    }

    #[test]
    fn holes_overlaps_and_the_one_byte_forms() {
        let t = tile_bounds(9, 190, 400).unwrap();
        let (w, s, e, n) = (t.west, t.south, t.east, t.north);
        let (dx, dy) = (e - w, n - s);
        let at = |fx: f64, fy: f64| [w + fx * dx, s + fy * dy];
        // a lake with an island, an overlapping second lake reaching past the tile
        let lake = vec![
            vec![at(0.1, 0.1), at(0.7, 0.13), at(0.6, 0.8), at(0.2, 0.9)],
            vec![
                at(0.3, 0.3),
                at(0.4, 0.3),
                at(0.4, 0.5),
                at(0.3, 0.5),
                at(0.3, 0.3),
            ],
        ];
        let bay = vec![vec![
            at(0.5, 0.5),
            at(1.5, 0.4),
            at(1.2, 1.7),
            at(0.55, 0.95),
        ]];
        let polys = vec![lake, bay];
        let m = water_mask(&t, &polys, &mut || Ok(())).unwrap();
        assert_eq!(m.len(), 65536);
        let mut water = 0;
        for i in 0..256 {
            for j in 0..256 {
                let x = w + (j as f64 + 0.5) * dx / 256.0;
                let y = n - (i as f64 + 0.5) * dy / 256.0;
                let want = polys.iter().any(|p| inside(p, x, y));
                assert_eq!(m[i * 256 + j] == 255, want, "cell ({i}, {j})");
                water += want as usize;
            }
        }
        assert!(water > 10_000 && water < 50_000, "{water}");
        // all water: a polygon holding the tile; all land: one far away
        let all = vec![vec![
            at(-1.0, -1.0),
            at(2.0, -1.0),
            at(2.0, 2.0),
            at(-1.0, 2.0),
        ]];
        assert_eq!(water_mask(&t, &[all], &mut || Ok(())).unwrap(), vec![255]);
        let far = vec![vec![at(3.0, 3.0), at(4.0, 3.0), at(4.0, 4.0)]];
        assert_eq!(water_mask(&t, &[far], &mut || Ok(())).unwrap(), vec![0]);
    }
}
