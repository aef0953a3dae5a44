//! Tables of raster tiles as `tin_tiles_from_table` builds them, and the
//! overview layers `tin_overviews` builds over a table, through the
//! core's seam rounds (`SeamRounds`: what both SQL functions run), each
//! tile read from memory as SPI reads it; and the oracle of what an
//! overview layer promises: its tins cover every valid pixel of the
//! finer raster ([`check_covers`]).

use super::terrain::Raster;
use tinmerge_core::io::raster::Band;
use tinmerge_core::tin::cover::Cover;
use tinmerge_core::tin::lattice::Lattice;
use tinmerge_core::tin::seam_rounds::{Held, SeamRounds, TileReader};
use tinmerge_core::tin::tiles::{TableGrid, place_tiles};
use tinmerge_core::tin::{Tin, TinError};

/// A raster cut as `raster2pgsql -t n x n` cuts it: each tile its own
/// lattice, size and values.
pub type Tiles = Vec<(Lattice, usize, usize, Vec<f64>)>;

pub fn cut(r: &Raster, n: usize) -> Tiles {
    let mut table = Vec::new();
    for r0 in (0..r.h).step_by(n) {
        for c0 in (0..r.w).step_by(n) {
            let (w, h) = (n.min(r.w - c0), n.min(r.h - r0));
            let own = Lattice {
                ip_x: r.lat.ip_x + c0 as f64 * r.lat.scale_x + r0 as f64 * r.lat.skew_x,
                ip_y: r.lat.ip_y + r0 as f64 * r.lat.scale_y + c0 as f64 * r.lat.skew_y,
                ..r.lat
            };
            let vals: Vec<f64> = (r0..r0 + h)
                .flat_map(|y| r.z[y * r.w + c0..y * r.w + c0 + w].to_vec())
                .collect();
            table.push((own, w, h, vals));
        }
    }
    table
}

pub fn grid_of(tiles: &Tiles) -> Result<TableGrid, TinError> {
    let metas: Vec<(Lattice, usize, usize)> = tiles.iter().map(|t| (t.0, t.1, t.2)).collect();
    place_tiles(&metas)
}

fn band(values: Vec<f64>) -> Band {
    Band {
        pixel_type: 11,
        nodata: None,
        all_nodata: false,
        values,
    }
}

/// A table's tiles in memory; an overview's (`base` its finer raster)
/// with its nodata pixels covered as the SQL layer covers them.
pub struct Reader<'a> {
    pub tiles: &'a Tiles,
    pub base: Option<&'a Raster>,
}

impl TileReader for Reader<'_> {
    fn read(&mut self, want: &[usize]) -> Result<Vec<(usize, Band)>, TinError> {
        Ok(want
            .iter()
            .map(|&k| {
                let (lat, w, h, v) = &self.tiles[k];
                let mut b = band(v.clone());
                if let Some(base) = self.base
                    && Cover::needed(&b)
                    && let Some(mut c) = Cover::new(lat, *w, *h)
                {
                    c.add(&base.lat, base.w, base.h, &band(base.z.clone()));
                    c.apply(&mut b);
                }
                (k, b)
            })
            .collect())
    }
}

/// Every tile `rounds` returns, in (ty, tx) order: with `held`, each
/// tile's last build held up to that many of its vertices
/// (`SeamRounds::next_held`; past them dropped, and every tile built once
/// more), as `tin_tiles_from_table` holds its results; without, every
/// tile built once more at the end.
pub fn run(
    grid: &TableGrid,
    mut rounds: SeamRounds,
    reader: &mut Reader<'_>,
    held: Option<usize>,
) -> Result<Vec<Tin>, TinError> {
    let mut out = Vec::new();
    let mut hold = Held::new(held.unwrap_or(0), |o: &(usize, usize, Tin)| o.2.verts.len());
    if held.is_some() {
        rounds.hold();
    }
    while let Some(batch) = rounds.next_held(
        &mut hold,
        grid,
        reader,
        &|tx, ty, t| (ty, tx, t),
        &mut |_| Ok(()),
    )? {
        out.extend(batch);
    }
    out.sort_by_key(|o| (o.0, o.1));
    let n = out.len();
    out.dedup_by_key(|o| (o.0, o.1));
    if out.len() != n {
        return Err(TinError::Internal("a tile was handed out twice".into()));
    }
    Ok(out.into_iter().map(|o| o.2).collect())
}

/// An overview of `r`, `f` times coarser, as `ST_CreateOverview` makes it
/// by nearest neighbour: each pixel the finer pixel under its centre
/// (the last row and column of a raster not a multiple of `f` take the
/// last finer ones).
pub fn overview(r: &Raster, f: usize) -> Raster {
    let (w, h) = (r.w.div_ceil(f), r.h.div_ceil(f));
    let pick = |i: usize, n: usize| (i * f + f / 2).min(n - 1);
    let z = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| r.z[pick(y, r.h) * r.w + pick(x, r.w)])
        .collect();
    let k = f as f64;
    Raster {
        z,
        w,
        h,
        lat: Lattice {
            scale_x: r.lat.scale_x * k,
            scale_y: r.lat.scale_y * k,
            skew_x: r.lat.skew_x * k,
            skew_y: r.lat.skew_y * k,
            ..r.lat
        },
        srid: r.srid,
        desc: format!("{}, its overview x{f}", r.desc),
        sql: r.sql.clone(),
        sql_exact: false,
    }
}

/// The overview `o` of `base` with its nodata pixels covered (the values
/// its tiles were built from: each a function of the finer data alone, so
/// the same covered whole as tile by tile).
pub fn covered(o: &Raster, base: &Raster) -> Raster {
    let mut tiles = vec![(o.lat, o.w, o.h, o.z.clone())];
    let got = Reader {
        tiles: &tiles,
        base: Some(base),
    }
    .read(&[0])
    .unwrap_or_default();
    if let Some((_, b)) = got.into_iter().next() {
        tiles[0].3 = b.values;
    }
    Raster {
        z: tiles.swap_remove(0).3,
        desc: o.desc.clone(),
        sql: o.sql.clone(),
        ..*o
    }
}

/// Every valid pixel centre of `base` (world coordinates by the harness's
/// own map) lies in a triangle of some tile at the first and the last
/// level, up to rounding (exact orientations): the tins cover the finer
/// data. The number of centres checked.
pub fn check_covers(tiles: &[Tin], base: &Raster) -> Result<usize, String> {
    let Some(last) = tiles.iter().map(|t| t.levels.len()).min() else {
        return Ok(0);
    };
    let mut checked = 0;
    for l in [0, last.saturating_sub(1)] {
        let tris: Vec<[[f64; 2]; 3]> = tiles
            .iter()
            .flat_map(|t| {
                let lv = &t.levels[l];
                let n = lv.tris.len() - lv.num_void as usize;
                lv.tris[..n].iter().map(move |tri| {
                    tri.map(|v| {
                        let p = t.verts[v as usize];
                        [p[0], p[1]]
                    })
                })
            })
            .collect();
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for c in &tris {
            for p in c {
                for k in 0..2 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
        }
        let nb = 64usize;
        let size = [(hi[0] - lo[0]) / nb as f64, (hi[1] - lo[1]) / nb as f64];
        let cell = |v: f64, k: usize| (((v - lo[k]) / size[k]).max(0.0) as usize).min(nb - 1);
        let mut buckets: Vec<Vec<u32>> = vec![Vec::new(); nb * nb];
        for (i, c) in tris.iter().enumerate() {
            let (x0, x1) = (
                c.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min),
                c.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max),
            );
            let (y0, y1) = (
                c.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min),
                c.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max),
            );
            for by in cell(y0, 1)..=cell(y1, 1) {
                for bx in cell(x0, 0)..=cell(x1, 0) {
                    buckets[by * nb + bx].push(i as u32);
                }
            }
        }
        let orient = |a: [f64; 2], b: [f64; 2], q: [f64; 2]| {
            robust::orient2d(
                robust::Coord { x: a[0], y: a[1] },
                robust::Coord { x: b[0], y: b[1] },
                robust::Coord { x: q[0], y: q[1] },
            )
        };
        // on an edge up to a few roundings of the coordinates
        let m = lo[0]
            .abs()
            .max(hi[0].abs())
            .max(lo[1].abs())
            .max(hi[1].abs());
        let slack = |a: [f64; 2], b: [f64; 2]| {
            64.0 * f64::EPSILON * m * ((b[0] - a[0]).abs() + (b[1] - a[1]).abs())
        };
        for row in 0..base.h {
            for col in 0..base.w {
                if base.at(col as i64, row as i64).is_none() {
                    continue;
                }
                let q = base.world(col as f64, row as f64);
                let inside = |c: &[[f64; 2]; 3]| {
                    let s = if orient(c[0], c[1], c[2]) > 0.0 {
                        1.0
                    } else {
                        -1.0
                    };
                    (0..3).all(|k| {
                        s * orient(c[k], c[(k + 1) % 3], q) >= -slack(c[k], c[(k + 1) % 3])
                    })
                };
                // its bucket, then those around (a point a rounding
                // outside a triangle may fall in the next)
                let (bx, by) = (cell(q[0], 0), cell(q[1], 1));
                let near = |r: usize| {
                    (by.saturating_sub(r)..=(by + r).min(nb - 1)).any(|y| {
                        (bx.saturating_sub(r)..=(bx + r).min(nb - 1)).any(|x| {
                            buckets[y * nb + x]
                                .iter()
                                .any(|&i| inside(&tris[i as usize]))
                        })
                    })
                };
                let found = near(0) || near(1);
                if !found {
                    return Err(format!(
                        "level {l}: the valid finer pixel ({col}, {row}) at ({}, {}) is in no tile's triangle",
                        q[0], q[1]
                    ));
                }
                checked += 1;
            }
        }
    }
    Ok(checked)
}
