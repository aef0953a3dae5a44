//! Viewshed benchmark (not a test): `analysis::viewshed` on the 105-Mpixel
//! benchmark terrain (`scripts/make-big-dem.py 29`: 9,976 x 10,527 pixels
//! of 3.10 m; the tin of the 10 km window around its centre at 1 m and 6
//! levels, as `tin_from_raster` builds it)
//! against `gdal_viewshed` on the raster itself: the same eye (1.7 m above
//! the ground at the terrain's centre), 10 km, targets on the ground, the
//! raster's own 3.10 m cells over the radius's window. Prints a table of
//! medians (5 runs for the core on 1 and 2 threads, 3 for the gdal process)
//! and the work counters of the last run, and how many cells the two call
//! the same; then `gdal_viewshed` on the tin's own heights at the cells
//! (`rasterize`), and how many of its verdicts are the exact viewshed's.
//! The DEM and the tin are made once into `target/bench-viewshed`.
//! `cargo bench --bench viewshed`. Profile modes (one thread, nothing else
//! timed): `TINMERGE_VIEWSHED_PROFILE=1` the viewshed, `=sweep`
//! `triangles_at`; `TINMERGE_RUNS=n` runs (0: the set-up alone, to subtract
//! under callgrind).

use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;
use tinmerge_core::analysis::rasterize::{aligned_grid, rasterize, triangles_at};
use tinmerge_core::analysis::viewshed::{Eye, NODATA, VISIBLE, viewshed};
use tinmerge_core::io::raster::GeoTransform;
use tinmerge_core::merge::point::height;
use tinmerge_core::tin::build::{BuildOptions, build_lattice, default_tolerances};
use tinmerge_core::tin::lattice::Lattice;
use tinmerge_core::tin::layout::{decode, encode};
use tinmerge_core::tin::{Tin, par};

const FACTOR: usize = 29;
const RADIUS: f64 = 10_000.0;
const EYE_UP: f64 = 1.7;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Runs of a profile mode: `TINMERGE_RUNS`, else `default` (0 times the
/// set-up alone, for instruction counts under callgrind).
fn profile_runs(default: usize) -> usize {
    std::env::var("TINMERGE_RUNS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The VRT's size and georeference (written by make-big-dem.py).
fn vrt_grid(vrt: &Path) -> (usize, usize, [f64; 6]) {
    let s = std::fs::read_to_string(vrt).expect("the VRT");
    let attr = |k: &str| -> usize {
        let i = s.find(k).expect(k) + k.len() + 2;
        s[i..].split('"').next().unwrap().parse().unwrap()
    };
    let g0 = s.find("<GeoTransform>").unwrap() + "<GeoTransform>".len();
    let g1 = s.find("</GeoTransform>").unwrap();
    let g: Vec<f64> = s[g0..g1]
        .split(',')
        .map(|v| v.trim().parse().unwrap())
        .collect();
    (
        attr("rasterXSize"),
        attr("rasterYSize"),
        [g[0], g[1], g[2], g[3], g[4], g[5]],
    )
}

fn main() {
    let dir = root().join("target/bench-viewshed");
    std::fs::create_dir_all(&dir).unwrap();
    let vrt = dir.join("big.vrt");
    if !vrt.exists() {
        eprintln!("making the 105-Mpixel DEM (make-big-dem.py {FACTOR})");
        let ok = Command::new(root().join("scripts/python.sh"))
            .arg(root().join("scripts/make-big-dem.py"))
            .arg(FACTOR.to_string())
            .arg(&vrt)
            .status()
            .expect("scripts/python.sh")
            .success();
        assert!(ok, "make-big-dem.py failed");
    }
    let (w, h, g) = vrt_grid(&vrt);
    let lattice = Lattice {
        ip_x: g[0],
        ip_y: g[3],
        scale_x: g[1],
        scale_y: g[5],
        skew_x: 0.0,
        skew_y: 0.0,
    };
    let tin_file = dir.join("window-1m-6.tin");
    let tin: Tin = if tin_file.exists() {
        decode(&std::fs::read(&tin_file).unwrap()).unwrap()
    } else {
        eprintln!("building its tin (1 m, 6 levels; minutes)");
        // the pixels of the eye's window (one tin holds at most 50 M
        // samples): the radius and a pixel around the centre
        let raw = std::fs::read(dir.join("big.raw")).unwrap();
        let r = (RADIUS / g[1]).ceil() as usize + 1;
        let (c0, c1) = ((w / 2).saturating_sub(r), (w / 2 + r + 1).min(w));
        let (r0, r1) = ((h / 2).saturating_sub(r), (h / 2 + r + 1).min(h));
        let mut pts = Vec::with_capacity((c1 - c0) * (r1 - r0));
        for row in r0..r1 {
            for col in c0..c1 {
                let i = 4 * (row * w + col);
                let v = f32::from_le_bytes([raw[i], raw[i + 1], raw[i + 2], raw[i + 3]]);
                if v != -9999.0 && v.is_finite() {
                    pts.push([col as f64, row as f64, f64::from(v)]);
                }
            }
        }
        drop(raw);
        par::set_threads(2);
        let t0 = Instant::now();
        let tin = build_lattice(
            pts,
            &lattice,
            &default_tolerances(1.0, 6).unwrap(),
            32616,
            BuildOptions {
                keep_border: false,
                between_samples: true,
            },
            &mut || Ok(()),
        )
        .unwrap();
        eprintln!("built in {:.1} s", t0.elapsed().as_secs_f64());
        std::fs::write(&tin_file, encode(&tin)).unwrap();
        tin
    };
    let finest = tin.num_levels() - 1;
    // the eye over the terrain's centre, on the raster's grid's window of
    // the radius
    let (ex, ey) = (
        g[0] + 0.5 * w as f64 * g[1] + 0.25 * g[1],
        g[3] + 0.5 * h as f64 * g[5] + 0.25 * g[5],
    );
    let ground = height(&tin, finest, ex, ey).expect("the eye over the surface");
    let eye = Eye {
        x: ex,
        y: ey,
        z: ground + EYE_UP,
        curvature: None,
    };
    let ext = [
        (ex - RADIUS).max(g[0]),
        (ey - RADIUS).max(g[3] + h as f64 * g[5]),
        (ex + RADIUS).min(g[0] + w as f64 * g[1]),
        (ey + RADIUS).min(g[3]),
    ];
    let (gt, gw, gh) = aligned_grid(&ext, g[1], -g[5], g[0], g[3]).unwrap();
    println!(
        "terrain: {w} x {h} pixels of {:.2} m; tin {} levels, {} triangles at the finest; grid {gw} x {gh} cells; eye ({ex:.1}, {ey:.1}) {EYE_UP} m up, {RADIUS} m",
        g[1],
        tin.num_levels(),
        tin.levels[finest].num_triangles()
    );
    if std::env::var("TINMERGE_VIEWSHED_PROFILE").as_deref() == Ok("sweep") {
        // for perf: the sweep alone, five runs on one thread
        par::set_threads(1);
        for _ in 0..profile_runs(5) {
            let t0 = Instant::now();
            black_box(triangles_at(&tin, finest, &gt, gw, gh, &mut || Ok(())).unwrap());
            println!("triangles_at {:.0} ms", t0.elapsed().as_secs_f64() * 1e3);
        }
        return;
    }
    if std::env::var_os("TINMERGE_VIEWSHED_PROFILE").is_some() {
        // for perf: three runs on one thread, nothing else
        let sizes: Vec<usize> = tin.levels.iter().map(|l| l.num_triangles()).collect();
        println!("triangles per level: {sizes:?}");
        par::set_threads(1);
        for _ in 0..profile_runs(3) {
            let t0 = Instant::now();
            let v = black_box(
                viewshed(&tin, finest, &[eye], 0.0, RADIUS, &gt, gw, gh, &mut || {
                    Ok(())
                })
                .unwrap(),
            );
            println!(
                "{:.0} ms: rays {}, fine pieces {}, pruned {}, whole walks {}, last stretches {}",
                t0.elapsed().as_secs_f64() * 1e3,
                v.rays,
                v.fine_pieces,
                v.pruned,
                v.exact_cells,
                v.local_cells
            );
        }
        return;
    }
    println!("| | 1 thread ms | 2 threads ms |");
    println!("|---|---:|---:|");
    let mut times = [0.0; 2];
    let mut last = None;
    for (k, n) in [1, 2].into_iter().enumerate() {
        par::set_threads(n);
        let mut v = Vec::new();
        for _ in 0..5 {
            let t0 = Instant::now();
            let r = viewshed(&tin, finest, &[eye], 0.0, RADIUS, &gt, gw, gh, &mut || {
                Ok(())
            })
            .unwrap();
            v.push(t0.elapsed().as_secs_f64() * 1e3);
            last = Some(black_box(r));
        }
        times[k] = median(v);
    }
    par::set_threads(1);
    println!("| analysis::viewshed | {:.0} | {:.0} |", times[0], times[1]);
    // of which: the triangle under each cell (the sweep); and the same
    // sweep giving heights, as tin_as_raster runs it
    for what in [
        "of which the triangle under each cell (triangles_at)",
        "the heights on the same grid (rasterize, tin_as_raster's sweep)",
    ] {
        let mut ms = [0.0; 2];
        for (k, n) in [1, 2].into_iter().enumerate() {
            par::set_threads(n);
            let mut v = Vec::new();
            for _ in 0..5 {
                let t0 = Instant::now();
                if what.starts_with("of which") {
                    black_box(triangles_at(&tin, finest, &gt, gw, gh, &mut || Ok(())).unwrap());
                } else {
                    black_box(rasterize(&tin, finest, &gt, gw, gh, &mut || Ok(())).unwrap());
                }
                v.push(t0.elapsed().as_secs_f64() * 1e3);
            }
            ms[k] = median(v);
        }
        println!(
            "| {what}, {:.1} Mpx | {:.0} | {:.0} |",
            (gw * gh) as f64 / 1e6,
            ms[0],
            ms[1]
        );
    }
    par::set_threads(1);
    let v = last.unwrap();
    // gdal_viewshed on the raster, the same window (-md), as ENVI bytes
    let gdal = |dem: &Path, out: &Path| {
        let t0 = Instant::now();
        let ok = Command::new("gdal_viewshed")
            .args(["-q", "-of", "ENVI", "-vv", "1", "-iv", "0", "-ov", "255"])
            // no curvature, as the eye here has none (said, not left to
            // the default)
            .args(["-cc", "0"])
            .args(["-ox", &ex.to_string(), "-oy", &ey.to_string()])
            .args(["-oz", &EYE_UP.to_string(), "-tz", "0"])
            .args(["-md", &RADIUS.to_string()])
            .arg(dem)
            .arg(out)
            .status()
            .expect("gdal_viewshed")
            .success();
        assert!(ok, "gdal_viewshed failed");
        t0.elapsed().as_secs_f64() * 1e3
    };
    let out = dir.join("gdal.envi");
    let gv: Vec<f64> = (0..3).map(|_| gdal(&vrt, &out)).collect();
    println!(
        "| gdal_viewshed (process, one thread) | {:.0} | |",
        median(gv)
    );
    // and on the tin's own heights at the cells (tin_as_raster): how its
    // method, not the data, compares with the exact answer
    par::set_threads(2);
    let z = rasterize(&tin, finest, &gt, gw, gh, &mut || Ok(())).unwrap();
    par::set_threads(1);
    let bytes: Vec<u8> = z
        .iter()
        .flat_map(|v| (if v.is_nan() { -9999.0f32 } else { *v as f32 }).to_le_bytes())
        .collect();
    std::fs::write(dir.join("tin.raw"), bytes).unwrap();
    std::fs::write(
        dir.join("tin.vrt"),
        format!(
            r#"<VRTDataset rasterXSize="{gw}" rasterYSize="{gh}"><SRS>EPSG:32616</SRS><GeoTransform>{}, {}, 0, {}, 0, {}</GeoTransform><VRTRasterBand dataType="Float32" band="1" subClass="VRTRawRasterBand"><NoDataValue>-9999</NoDataValue><SourceFilename relativetoVRT="1">tin.raw</SourceFilename><ImageOffset>0</ImageOffset><PixelOffset>4</PixelOffset><LineOffset>{}</LineOffset><ByteOrder>LSB</ByteOrder></VRTRasterBand></VRTDataset>"#,
            gt.ip_x,
            gt.scale_x,
            gt.ip_y,
            gt.scale_y,
            4 * gw
        ),
    )
    .unwrap();
    let on_tin = dir.join("gdal-tin.envi");
    let ms = gdal(&dir.join("tin.vrt"), &on_tin);
    println!(
        "gdal_viewshed on the tin's heights at the cells: {ms:.0} ms, agrees with the exact viewshed at {}",
        gdal_agreement(&on_tin, &v.counts, &gt, gw, gh)
    );
    let agree = gdal_agreement(&out, &v.counts, &gt, gw, gh);
    let seen = v.counts.iter().filter(|&&c| c == VISIBLE).count();
    println!(
        "cells decided {}, seen {} ({:.1} %); rays {}; fine pieces {}; coarse triangles pruned {}; cells walked on their own ray: {} whole, {} last stretch; agree with gdal_viewshed {agree}",
        v.cells,
        seen,
        100.0 * seen as f64 / v.cells as f64,
        v.rays,
        v.fine_pieces,
        v.pruned,
        v.exact_cells,
        v.local_cells
    );
}

/// The share of the cells decided by both whose verdicts match, as text.
fn gdal_agreement(envi: &Path, counts: &[u16], gt: &GeoTransform, gw: usize, gh: usize) -> String {
    let hdr = std::fs::read_to_string(envi.with_extension("hdr")).unwrap_or_default();
    let field = |k: &str| -> Option<String> {
        let l = hdr.lines().find(|l| l.trim_start().starts_with(k))?;
        Some(l.split('=').nth(1)?.trim().to_string())
    };
    let (Some(sw), Some(sh), Some(map)) = (field("samples"), field("lines"), field("map info"))
    else {
        return "(gdal's output unread)".into();
    };
    let (sw, sh): (usize, usize) = (sw.parse().unwrap(), sh.parse().unwrap());
    // map info = {UTM, 1, 1, ulx, uly, px, py, ...}
    let m: Vec<&str> = map
        .trim_matches(|c| c == '{' || c == '}')
        .split(',')
        .collect();
    let (ulx, uly, px): (f64, f64, f64) = (
        m[3].trim().parse().unwrap(),
        m[4].trim().parse().unwrap(),
        m[5].trim().parse().unwrap(),
    );
    let bytes = std::fs::read(envi).unwrap();
    let (c0, r0) = (
        ((gt.ip_x - ulx) / px).round() as i64,
        ((uly - gt.ip_y) / px).round() as i64,
    );
    let (mut n, mut same) = (0u64, 0u64);
    for r in 0..gh {
        for c in 0..gw {
            let t = counts[r * gw + c];
            let (gc, gr) = (c as i64 + c0, r as i64 + r0);
            if t == NODATA || gc < 0 || gr < 0 || gc >= sw as i64 || gr >= sh as i64 {
                continue;
            }
            let gval = bytes[gr as usize * sw + gc as usize];
            if gval == 255 {
                continue;
            }
            n += 1;
            same += u64::from((gval == 1) == (t == VISIBLE));
        }
    }
    format!("{:.2} % of {n}", 100.0 * same as f64 / n.max(1) as f64)
}
