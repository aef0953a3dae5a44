//! Build engine 2 against the build it replaces (issue 74): the same band
//! built by the old engine (`build_lattice` between the samples, what
//! `build_raster` called over the valid pixels' hull until 0.26.0) and by
//! `construct::build_band` (engine 2, what it calls now), one level and
//! five, 2 m and 5 m, on both bundled DEMs: wall time (median of 3),
//! triangles and vertices at the finest level, peak heap per pixel.
//! `cargo bench --bench engine`; with `TERRACES=8`, engine 2 alone on
//! the DEMs made terraces of 8 x 8 pixels a pixel ([`terraces_run`]).
#[path = "../tests/common/mod.rs"]
mod common;

use std::time::Instant;
use tinmerge_core::tin::Tin;
use tinmerge_core::tin::build::{BuildOptions, build_lattice, default_tolerances};
use tinmerge_core::tin::construct::build_band;
use tinmerge_core::tin::memory;

#[global_allocator]
static ALLOCATOR: memory::Counting = memory::Counting;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// Each pixel made `k` x `k` pixels of the same height (nearest
/// neighbour at 1/k of the pixel: terraces).
fn terraces(z: &[f64], w: usize, h: usize, k: usize) -> Vec<f64> {
    let mut out = Vec::with_capacity(w * h * k * k);
    for r in 0..h * k {
        for c in 0..w * k {
            out.push(z[(r / k) * w + c / k]);
        }
    }
    out
}

/// A bundled DEM and its heights, `NaN` where no data.
fn heights(name: &str) -> (common::Dem, Vec<f64>) {
    let d = common::read_dem(name);
    let z = d
        .values
        .iter()
        .map(|&v| {
            if Some(v) == d.nodata || !v.is_finite() {
                f64::NAN
            } else {
                v
            }
        })
        .collect();
    (d, z)
}

/// `TERRACES=k`: engine 2 alone on both DEMs made terraces of `k` x `k`
/// pixels a pixel (8: the UTM DEM at 11.25 m, 7.56 M valid pixels, the
/// issue's big case), 2 m, one level and five, one run each.
fn terraces_run(k: usize) {
    println!(
        "| DEM x{k} | pixels (valid) | tolerance | levels | ms | finest triangles | finest vertices | peak heap B/pixel | triangles by level |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---|");
    for name in ["jacksboro_fault_dem_utm16n.tif", "jacksboro_fault_dem.tif"] {
        let (d, z) = heights(name);
        let (w, h) = (d.width * k, d.height * k);
        let z = terraces(&z, d.width, d.height, k);
        let valid = z.iter().filter(|v| !v.is_nan()).count();
        let mut lattice = d.lattice();
        lattice.scale_x /= k as f64;
        lattice.scale_y /= k as f64;
        for levels in [1, 5] {
            let tols = default_tolerances(2.0, levels).unwrap();
            memory::reset_peak();
            let base = memory::live();
            let t0 = Instant::now();
            let tin = build_band(&z, w, h, &lattice, &tols, 0, &mut || Ok(())).expect("build");
            let ms = t0.elapsed().as_secs_f64() * 1e3;
            let peak = memory::peak().saturating_sub(base);
            let f = tin.levels.last().unwrap();
            let by: Vec<String> = tin
                .levels
                .iter()
                .map(|l| l.tris.len().to_string())
                .collect();
            println!(
                "| {} | {} ({valid}) | 2 | {levels} | {ms:.0} | {} | {} | {:.0} | {} |",
                name.trim_end_matches(".tif"),
                w * h,
                f.tris.len(),
                f.num_vertices,
                peak as f64 / (w * h) as f64,
                by.join(", ")
            );
        }
    }
}

fn main() {
    if let Some(k) = std::env::var("TERRACES").ok().and_then(|v| v.parse().ok()) {
        terraces_run(k);
        return;
    }
    let only: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .collect();
    println!(
        "| DEM | pixels (valid) | tolerance | levels | engine | ms (median of 3) | finest triangles | finest vertices | peak heap B/pixel |"
    );
    println!("|---|---:|---:|---:|---|---:|---:|---:|---:|");
    for name in ["jacksboro_fault_dem_utm16n.tif", "jacksboro_fault_dem.tif"] {
        let (d, z) = heights(name);
        let valid = z.iter().filter(|v| !v.is_nan()).count();
        let lattice = d.lattice();
        // tolerances in the DEM's units of height (metres for both)
        for (tol, levels) in [(2.0, 1), (5.0, 1), (2.0, 5), (5.0, 5)] {
            let tols = default_tolerances(tol, levels).unwrap();
            for engine in ["old engine", "engine 2"] {
                if !only.is_empty() && !only.iter().any(|o| engine.contains(o.as_str())) {
                    continue;
                }
                let mut times = Vec::new();
                let mut last: Option<Tin> = None;
                let mut peak = 0usize;
                for _ in 0..3 {
                    memory::reset_peak();
                    let base = memory::live();
                    let t0 = Instant::now();
                    let tin = if engine == "engine 2" {
                        build_band(&z, d.width, d.height, &lattice, &tols, 0, &mut || Ok(()))
                    } else {
                        let w = d.width;
                        let pts: Vec<[f64; 3]> = (0..z.len())
                            .filter(|&i| !z[i].is_nan())
                            .map(|i| [(i % w) as f64, (i / w) as f64, z[i]])
                            .collect();
                        let opts = BuildOptions {
                            keep_border: false,
                            between_samples: true,
                        };
                        build_lattice(pts, &lattice, &tols, 0, opts, &mut || Ok(()))
                    };
                    times.push(t0.elapsed().as_secs_f64() * 1e3);
                    peak = peak.max(memory::peak().saturating_sub(base));
                    last = Some(tin.expect("build"));
                }
                let t = last.unwrap();
                let f = t.levels.last().unwrap();
                println!(
                    "| {} | {} ({}) | {} | {} | {} | {:.0} | {} | {} | {:.0} |",
                    name.trim_end_matches(".tif"),
                    d.width * d.height,
                    valid,
                    tol,
                    levels,
                    engine,
                    median(times),
                    f.tris.len(),
                    f.num_vertices,
                    peak as f64 / (d.width * d.height) as f64
                );
            }
        }
    }
}
