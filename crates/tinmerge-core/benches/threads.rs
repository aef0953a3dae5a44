//! `tinmerge.threads` benchmark (not a test): the raster statistics and the
//! build on 1 and 2 threads (`tin::par`), medians of 5, with the speed-up.
//! Answers are identical whatever the thread count (tests/raster.rs and
//! tests/hierarchy.rs check that); this only times them.
//! `cargo bench --bench threads`.
#[path = "../tests/common/mod.rs"]
mod common;

use std::hint::black_box;
use std::time::Instant;
use tinmerge_core::merge::raster::PixelGrid;
use tinmerge_core::merge::raster::patch::TinLevel;
use tinmerge_core::merge::raster::stats::{weighted_stats, zonal_stats};
use tinmerge_core::tin::build::{build, default_tolerances};
use tinmerge_core::tin::par;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Median ms of `f` over `runs` runs on 1 and on 2 threads.
fn time(runs: usize, mut f: impl FnMut()) -> (f64, f64) {
    let mut out = [0.0; 2];
    for (k, n) in [1, 2].into_iter().enumerate() {
        par::set_threads(n);
        let mut v = Vec::new();
        for _ in 0..runs {
            let t0 = Instant::now();
            f();
            v.push(t0.elapsed().as_secs_f64() * 1e3);
        }
        out[k] = median(v);
    }
    par::set_threads(1);
    (out[0], out[1])
}

fn row(what: &str, (one, two): (f64, f64)) {
    println!("| {what} | {one:.1} | {two:.1} | {:.2} |", one / two);
}

fn main() {
    println!(
        "threads available: {} (rows: 1 thread ms | 2 threads ms | speed-up)",
        par::cores()
    );
    println!("| work | 1 thread ms | 2 threads ms | speed-up |");
    println!("|---|---:|---:|---:|");
    let tin = common::dem_tin();
    let d = common::read_dem("jacksboro_fault_dem_utm16n.tif");
    for f in [4usize, 8] {
        let (gt, w, h, values) = d.upsampled(f);
        let g = PixelGrid::new(&gt, w, h).unwrap();
        let mpx = (w * h) as f64 / 1e6;
        for level in [0, 4] {
            let nt = tin.levels[level].tris.len();
            let what = format!("DEM x{f} ({mpx:.2} Mpx), level {level} ({nt} triangles)");
            row(
                &format!("zonal mean: {what}"),
                time(5, || {
                    black_box(
                        zonal_stats(
                            &TinLevel::new(&tin, level).unwrap(),
                            &g,
                            &values,
                            d.nodata,
                            false,
                            &mut || Ok(()),
                        )
                        .unwrap(),
                    );
                }),
            );
            row(
                &format!("zonal mean + mode: {what}"),
                time(5, || {
                    black_box(
                        zonal_stats(
                            &TinLevel::new(&tin, level).unwrap(),
                            &g,
                            &values,
                            d.nodata,
                            true,
                            &mut || Ok(()),
                        )
                        .unwrap(),
                    );
                }),
            );
            row(
                &format!("weighted mean: {what}"),
                time(5, || {
                    black_box(
                        weighted_stats(
                            &TinLevel::new(&tin, level).unwrap(),
                            &gt,
                            w,
                            h,
                            &values,
                            d.nodata,
                            false,
                            &mut || Ok(()),
                        )
                        .unwrap(),
                    );
                }),
            );
        }
    }
    let samples = d.samples();
    let tols = default_tolerances(2.0, 5).unwrap();
    row(
        &format!("build: DEM, {} samples, 2 m, 5 levels", samples.len()),
        time(3, || {
            black_box(build(samples.clone(), &tols, 32616, &mut || Ok(())).unwrap());
        }),
    );
}
