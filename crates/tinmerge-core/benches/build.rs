//! Build benchmark (not a test): `tin_from_raster`'s core build on the
//! bundled DEM and on it upsampled 4x (nearest neighbour, the case of issue
//! 25: 1.89 million samples), 2 m at the finest of 5 levels, on 1 and 2
//! threads, and measured between the samples (issue 43,
//! `BuildOptions::between_samples`) or not: wall time (median of 3),
//! samples per second, the counting
//! allocator's peak heap per sample (input samples included) and the
//! triangles made. Then `tin_from_points`' core build on point clouds made
//! from the DEM: every pixel cut into `f x f` sub-pixels, one ground return
//! in each at a seeded random place, its height interpolated bilinearly
//! between the DEM's pixel centres (f = 4: 1.9 million points; f = 9: 9.6
//! million, issue 25's "10 million points a tile"). Between the two, the
//! build over the valid pixels (`tin_from_raster`'s default on a raster
//! with nodata), at the samples and between them (whose heap includes the
//! raster's heights, 8 bytes a pixel).
//! `cargo bench --bench build` (`-- valid_pixels`: the build over the
//! valid pixels alone).
#[path = "../tests/common/mod.rs"]
mod common;

use std::time::Instant;
use tinmerge_core::tin::build::{BuildOptions, build, build_lattice, default_tolerances};
use tinmerge_core::tin::{memory, par};

#[global_allocator]
static ALLOCATOR: memory::Counting = memory::Counting;

fn main() {
    let d = common::read_dem("jacksboro_fault_dem_utm16n.tif");
    if std::env::args().any(|a| a == "valid_pixels") {
        // `cargo bench --bench build -- valid_pixels`: that table alone
        valid_pixels(&d);
        return;
    }
    if std::env::args().any(|a| a == "levels") {
        // `cargo bench --bench build -- levels`: that table alone
        levels_table();
        return;
    }
    if std::env::args().any(|a| a == "tiles") {
        // `cargo bench --bench build -- tiles [x1]`: that table alone (of
        // the DEM alone)
        tiles(&d);
        return;
    }
    println!(
        "| raster | between samples | samples | levels | threads | finest triangles | ms (median of 3) | samples/s | peak heap B/sample |"
    );
    println!("|---|---|---:|---:|---:|---:|---:|---:|---:|");
    for (f, threads, levels, between) in [
        (1usize, 1usize, 5, false),
        (1, 1, 5, true),
        (1, 1, 1, true),
        (4, 1, 5, false),
        (4, 1, 5, true),
        (4, 2, 5, false),
        (4, 1, 1, false),
        (4, 1, 1, true),
    ] {
        par::set_threads(threads);
        let (gt, w, h, values) = d.upsampled(f);
        let lat = lattice_of(&gt);
        let samples = || -> Vec<[f64; 3]> {
            let mut out = Vec::new();
            for r in 0..h {
                for c in 0..w {
                    let v = values[r * w + c];
                    if !(v.is_nan() || Some(v) == d.nodata) {
                        out.push([c as f64, r as f64, v]);
                    }
                }
            }
            out
        };
        let tols = default_tolerances(2.0, levels).unwrap();
        let (n, ms, peak, tris) = measure(3, &samples, |s| {
            let opts = BuildOptions {
                keep_border: false,
                between_samples: between,
            };
            build_lattice(s, &lat, &tols, 32616, opts, &mut || Ok(())).unwrap()
        });
        println!(
            "| DEM x{f} | {between} | {n} | {levels} | {threads} | {tris} | {ms:.0} | {:.0} | {:.0} |",
            n as f64 / ms * 1e3,
            peak as f64 / n as f64
        );
    }
    valid_pixels(&d);
    tiles(&d);
    cloud(&d);
}

/// Issue 43's before/after table: `tin_from_raster`'s lattice build of
/// both bundled DEMs and of the UTM one upsampled 4x (nearest neighbour),
/// 2 m at the finest of 5 levels, one thread: at the samples only (before)
/// and between them (after). Per level: triangles, and the largest error on
/// the grid lines between valid pixel centres over the level's tolerance
/// (`tin_validate(tin, raster)`'s measure, `check::over_tolerance`: the
/// level's worst place when it is over, else at most 1x); per build: one
/// run's time and heap peak per sample.
fn levels_table() {
    use tinmerge_core::tin::check::over_tolerance;
    use tinmerge_core::tin::dense::Dense;
    println!(
        "| raster | build | level | tolerance | triangles | largest error on grid lines / tolerance | build s | peak heap B/sample |"
    );
    println!("|---|---|---:|---:|---:|---:|---:|---:|");
    par::set_threads(1);
    for (name, file, f) in [
        ("UTM DEM", "jacksboro_fault_dem_utm16n.tif", 1usize),
        ("geographic DEM", "jacksboro_fault_dem.tif", 1),
        ("UTM DEM x4", "jacksboro_fault_dem_utm16n.tif", 4),
    ] {
        let d = common::read_dem(file);
        let (gt, w, h, values) = d.upsampled(f);
        let lat = lattice_of(&gt);
        let z: Vec<f64> = values
            .iter()
            .map(|&v| {
                if v.is_nan() || Some(v) == d.nodata {
                    f64::NAN
                } else {
                    v
                }
            })
            .collect();
        let tols = default_tolerances(2.0, 5).unwrap();
        for between in [false, true] {
            let samples: Vec<[f64; 3]> = (0..h)
                .flat_map(|r| (0..w).map(move |c| (c, r)))
                .filter(|&(c, r)| !z[r * w + c].is_nan())
                .map(|(c, r)| [c as f64, r as f64, z[r * w + c]])
                .collect();
            let n = samples.len();
            let base = memory::live() - n * 24;
            memory::reset_peak();
            let t0 = Instant::now();
            let opts = BuildOptions {
                keep_border: false,
                between_samples: between,
            };
            let tin = build_lattice(samples, &lat, &tols, 32616, opts, &mut || Ok(())).unwrap();
            let secs = t0.elapsed().as_secs_f64();
            let peak = (memory::peak() - base) as f64 / n as f64;
            let heights = Dense {
                c0: 0,
                r0: 0,
                width: w,
                height: h,
                z: z.clone(),
            };
            let over = over_tolerance(&tin, &heights, &lat, &[], &mut || Ok(())).unwrap();
            for (l, lv) in tin.levels.iter().enumerate() {
                let worst = over
                    .iter()
                    .find(|p| p.level == l)
                    .and_then(|p| {
                        p.detail
                            .strip_prefix("error ")?
                            .split(' ')
                            .next()?
                            .parse::<f64>()
                            .ok()
                    })
                    .map_or("≤ 1".to_string(), |e| format!("{:.2}", e / lv.tolerance));
                println!(
                    "| {name} | {} | {l} | {} | {} | {worst}x | {} | {} |",
                    if between {
                        "between samples"
                    } else {
                        "at the samples"
                    },
                    lv.tolerance,
                    lv.tris.len(),
                    if l == 0 {
                        format!("{secs:.1}")
                    } else {
                        String::new()
                    },
                    if l == 0 {
                        format!("{peak:.0}")
                    } else {
                        String::new()
                    },
                );
            }
        }
    }
}

/// `tin_tiles`' build of the DEM (and of it upsampled 4x) in 256-pixel
/// tiles at 2 m, 5 levels, on 2 threads: every tile built once on its own
/// (`build_tile`, what `tin_from_raster(tile, ..., keep_border => true)`
/// gives, and `tin_tiles` before 0.14.0: the strips along the seams held at
/// the samples only), against `build_tiles`' rounds (the seam samples a
/// tile asks for kept by both tiles, the tiles holding them built again).
/// Wall time (median of 3), tile builds, seam samples kept, finest
/// triangles.
fn tiles(d: &common::Dem) {
    use tinmerge_core::tin::seam_rounds::{InMemory, SeamRounds, build_tiles};
    use tinmerge_core::tin::tile::build_tile;
    use tinmerge_core::tin::tiles::{tile_counts, tile_window};
    println!();
    println!(
        "| raster | tiles | build | tile builds | seam samples kept | finest triangles | ms (median of 3) |"
    );
    println!("|---|---:|---|---:|---:|---:|---:|");
    par::set_threads(2);
    let tols = default_tolerances(2.0, 5).unwrap();
    let n: usize = std::env::var("TILE_PX")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(256);
    let scales: &[usize] = if std::env::args().any(|a| a == "x1") {
        &[1]
    } else {
        &[1, 4]
    };
    for &f in scales {
        let (gt, w, h, values) = d.upsampled(f);
        let lat = lattice_of(&gt);
        let valid = |v: f64| !(v.is_nan() || Some(v) == d.nodata);
        let (nx, ny) = tile_counts(w, h, n);
        let finest = |t: &tinmerge_core::tin::Tin| t.levels.last().map_or(0, |l| l.tris.len());
        let median = |mut v: Vec<f64>| {
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        // each tile once, on its own
        let (mut times, mut tris, mut count) = (Vec::new(), 0, 0);
        for _ in 0..3 {
            let t0 = Instant::now();
            let all: Vec<(usize, usize)> = (0..ny)
                .flat_map(|ty| (0..nx).map(move |tx| (tx, ty)))
                .collect();
            let built = par::map(&all, |&(tx, ty)| {
                let (cols, rows) = tile_window(w, h, n, tx, ty);
                let mut s = Vec::new();
                for r in rows.clone() {
                    for c in cols.clone() {
                        let v = values[r * w + c];
                        if valid(v) {
                            s.push([c as f64, r as f64, v]);
                        }
                    }
                }
                build_tile(
                    s,
                    &lat,
                    (cols.start as i64, rows.start as i64),
                    &tols,
                    32616,
                    &mut || Ok(()),
                )
                .unwrap()
                .map(|t| finest(&t))
            });
            times.push(t0.elapsed().as_secs_f64() * 1e3);
            count = built.iter().flatten().count();
            tris = built.iter().flatten().sum::<usize>();
        }
        println!(
            "| DEM x{f} | {count} | each tile on its own | {count} | 0 | {tris} | {:.0} |",
            median(times)
        );
        // build_tiles' rounds
        let builds = std::sync::atomic::AtomicUsize::new(0);
        let (mut times, mut tris, mut kept, mut count) = (Vec::new(), 0, 0, 0);
        for _ in 0..3 {
            builds.store(0, std::sync::atomic::Ordering::Relaxed);
            let mut out = Vec::new();
            let t0 = Instant::now();
            let seams = build_tiles(
                &values,
                w,
                h,
                &valid,
                &lat,
                n,
                &tols,
                true,
                32616,
                &mut || Ok(()),
                &|_, _, t| {
                    builds.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    finest(&t)
                },
                &mut |k| {
                    out.push(k);
                    Ok(())
                },
            )
            .unwrap();
            times.push(t0.elapsed().as_secs_f64() * 1e3);
            kept = seams.len();
            count = out.len();
            tris = out.iter().sum::<usize>();
        }
        println!(
            "| DEM x{f} | {count} | build_tiles (seam rounds, each tile's last build held) | {} | {kept} | {tris} | {:.0} |",
            builds.load(std::sync::atomic::Ordering::Relaxed),
            median(times)
        );
        // the same rounds streamed: every tile built once more at the end
        // (what `tin_tiles_from_table` does past its memory for results)
        let grid = tinmerge_core::tin::tiles::TableGrid {
            lattice: lat,
            tile_width: n,
            tile_height: n,
            tiles: (0..ny)
                .flat_map(|ty| (0..nx).map(move |tx| (tx, ty)))
                .map(|(tx, ty)| tinmerge_core::tin::tiles::Placed {
                    tx,
                    ty,
                    col: (tx * n) as i64,
                    row: (ty * n) as i64,
                    width: n.min(w - tx * n),
                    height: n.min(h - ty * n),
                })
                .collect(),
        };
        let (mut times, mut tris, mut count) = (Vec::new(), 0, 0);
        for _ in 0..3 {
            builds.store(0, std::sync::atomic::Ordering::Relaxed);
            let mut reader = InMemory {
                values: &values,
                width: w,
                valid: &valid,
                grid: &grid,
            };
            let mut rounds = SeamRounds::rows(&grid, tols.clone(), 32616, true, 0..ny, 0..ny);
            let mut out = Vec::new();
            let t0 = Instant::now();
            while let Some(b) = rounds
                .next_batch(&grid, &mut reader, &|_, _, t| finest(&t), &mut |s| {
                    builds.fetch_add(s.tiles, std::sync::atomic::Ordering::Relaxed);
                    Ok(())
                })
                .unwrap()
            {
                out.extend(b);
            }
            times.push(t0.elapsed().as_secs_f64() * 1e3);
            count = out.len();
            tris = out.iter().sum::<usize>();
        }
        println!(
            "| DEM x{f} | {count} | the same rounds streamed (every tile built once more at the end) | {} | | {tris} | {:.0} |",
            builds.load(std::sync::atomic::Ordering::Relaxed),
            median(times)
        );
    }
}

/// `tin_from_raster`'s default on a raster with nodata: the build over the
/// valid pixels (their squares as the boundary, samples in world
/// coordinates), at the samples only (`build_domain`, as before issue 43)
/// or between them (`build_domain_raster`, what SQL runs since).
fn valid_pixels(d: &common::Dem) {
    use tinmerge_core::tin::build::{build_domain, build_domain_raster};
    use tinmerge_core::tin::dense::Dense;
    use tinmerge_core::tin::domain::{cell_outline, outline_area};
    println!();
    println!(
        "| raster, over its valid pixels | between samples | samples | levels | finest triangles | ms (median of 3) | peak heap B/sample |"
    );
    println!("|---|---|---:|---:|---:|---:|---:|");
    par::set_threads(1);
    for (f, between) in [(1usize, false), (1, true), (4, false), (4, true)] {
        let (gt, w, h, values) = d.upsampled(f);
        let lat = lattice_of(&gt);
        let z: Vec<f64> = values
            .iter()
            .map(|&v| if Some(v) == d.nodata { f64::NAN } else { v })
            .collect();
        let rings = cell_outline(w, h, &|c, r| !z[r * w + c].is_nan());
        let area = outline_area(&rings, &|c, r| {
            let (x, y) = lat.centre(c - 0.5, r - 0.5);
            [x, y]
        });
        let heights = Dense {
            c0: 0,
            r0: 0,
            width: w,
            height: h,
            z: z.clone(),
        };
        let samples = || -> Vec<[f64; 3]> {
            let mut out = Vec::new();
            for r in 0..h {
                for c in 0..w {
                    let v = z[r * w + c];
                    if !v.is_nan() {
                        let (x, y) = lat.centre(c as f64, r as f64);
                        out.push([x, y, v]);
                    }
                }
            }
            out
        };
        let tols = default_tolerances(2.0, 5).unwrap();
        let (n, ms, peak, tris) = measure(3, &samples, |s| {
            if between {
                build_domain_raster(s, &[], &[&area], &tols, 32616, &heights, &lat, &mut || {
                    Ok(())
                })
                .unwrap()
            } else {
                build_domain(s, &[], &[&area], &tols, 32616, &mut || Ok(())).unwrap()
            }
        });
        println!(
            "| DEM x{f} | {between} | {n} | 5 | {tris} | {ms:.0} | {:.0} |",
            (peak + if between { w * h * 8 } else { 0 }) as f64 / n as f64
        );
    }
}

/// The lattice the builds here take the upsampled DEM on.
fn lattice_of(
    gt: &tinmerge_core::io::raster::GeoTransform,
) -> tinmerge_core::tin::lattice::Lattice {
    tinmerge_core::tin::lattice::Lattice {
        ip_x: gt.ip_x + gt.scale_x / 2.0,
        ip_y: gt.ip_y + gt.scale_y / 2.0,
        scale_x: gt.scale_x,
        scale_y: gt.scale_y,
        skew_x: 0.0,
        skew_y: 0.0,
    }
}

/// `runs` builds of fresh `input()`: the samples, the median wall time
/// (ms), the heap's peak above what was live before the input was made
/// (the input included) and the finest level's triangles.
fn measure(
    runs: usize,
    input: &dyn Fn() -> Vec<[f64; 3]>,
    build: impl Fn(Vec<[f64; 3]>) -> tinmerge_core::tin::Tin,
) -> (usize, f64, usize, usize) {
    let mut times = Vec::new();
    let (mut n, mut peak, mut tris) = (0usize, 0usize, 0usize);
    for _ in 0..runs {
        let s = input();
        n = s.len();
        let base = memory::live() - n * 24;
        memory::reset_peak();
        let t0 = Instant::now();
        let tin = build(s);
        times.push(t0.elapsed().as_secs_f64() * 1e3);
        peak = memory::peak() - base;
        tris = tin.levels.last().map_or(0, |l| l.tris.len());
    }
    times.sort_by(f64::total_cmp);
    (n, times[times.len() / 2], peak, tris)
}

/// The DEM's height at (x, y) interpolated bilinearly between its four
/// nearest pixel centres, None where one of them has no data.
fn bilinear(d: &common::Dem, x: f64, y: f64) -> Option<f64> {
    let c = (x - d.origin_x) / d.scale_x - 0.5;
    let r = (d.origin_y - y) / d.scale_y - 0.5;
    let (c0, r0) = (c.floor(), r.floor());
    if c0 < 0.0 || r0 < 0.0 || c0 as usize + 1 >= d.width || r0 as usize + 1 >= d.height {
        return None;
    }
    let (fc, fr) = (c - c0, r - r0);
    let (c0, r0) = (c0 as usize, r0 as usize);
    let v = |cc: usize, rr: usize| {
        let v = d.values[rr * d.width + cc];
        (!(v.is_nan() || Some(v) == d.nodata)).then_some(v)
    };
    let (a, b) = (v(c0, r0)?, v(c0 + 1, r0)?);
    let (e, g) = (v(c0, r0 + 1)?, v(c0 + 1, r0 + 1)?);
    Some((a * (1.0 - fc) + b * fc) * (1.0 - fr) + (e * (1.0 - fc) + g * fc) * fr)
}

fn cloud(d: &common::Dem) {
    println!();
    println!(
        "| point cloud | points | levels | threads | finest triangles | ms | points/s | peak heap B/point |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|");
    for (f, threads, runs) in [(4usize, 1usize, 3usize), (4, 2, 3), (9, 2, 1)] {
        par::set_threads(threads);
        let points = || -> Vec<[f64; 3]> {
            let mut seed = 0x9e3779b97f4a7c15u64;
            let mut next = || {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                (seed >> 11) as f64 / (1u64 << 53) as f64
            };
            let (sx, sy) = (d.scale_x / f as f64, d.scale_y / f as f64);
            let mut out = Vec::new();
            for r in 0..d.height * f {
                for c in 0..d.width * f {
                    let x = d.origin_x + (c as f64 + next()) * sx;
                    let y = d.origin_y - (r as f64 + next()) * sy;
                    if let Some(z) = bilinear(d, x, y) {
                        out.push([x, y, z]);
                    }
                }
            }
            out
        };
        let tols = default_tolerances(2.0, 5).unwrap();
        let (n, ms, peak, tris) = measure(runs, &points, |s| {
            build(s, &tols, 32616, &mut || Ok(())).unwrap()
        });
        println!(
            "| DEM, {f}x{f} returns a pixel | {n} | 5 | {threads} | {tris} | {ms:.0} | {:.0} | {:.0} |",
            n as f64 / ms * 1e3,
            peak as f64 / n as f64
        );
    }
}
