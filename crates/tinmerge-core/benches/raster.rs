//! Core raster-merge benchmark (not a test): the scanline sweep handing the
//! pixels of the bundled DEM (and of 4x and 8x finer copies) to the
//! triangles of each level, with per-triangle count/sum/min/max (the mean),
//! single-threaded. Prints a markdown table of medians over 5 runs with
//! pixels per second. `cargo bench --bench raster`.
#[path = "../tests/common/mod.rs"]
mod common;

use std::hint::black_box;
use std::time::Instant;
use tinmerge_core::merge::raster::patch::TinLevel;
use tinmerge_core::merge::raster::stats::{weighted_stats, zonal_stats};
use tinmerge_core::merge::raster::{PixelGrid, sweep};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let tin = common::dem_tin();
    let d = common::read_dem("jacksboro_fault_dem_utm16n.tif");
    println!(
        "| raster | pixels | level | triangles | sweep only ms | Mpx/s | mean per triangle ms | Mpx/s | + mode ms | weighted mean ms | Mpx/s |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for f in [1usize, 4, 8] {
        let (gt, w, h, values) = d.upsampled(f);
        let g = PixelGrid::new(&gt, w, h).unwrap();
        for level in [0, 2, 4] {
            let (mut ts, mut tm, mut tmode, mut tw) =
                (Vec::new(), Vec::new(), Vec::new(), Vec::new());
            for _ in 0..5 {
                let t0 = Instant::now();
                let mut n = 0usize;
                sweep(
                    &TinLevel::new(&tin, level).unwrap(),
                    &g,
                    false,
                    &mut || Ok(()),
                    &mut |_, _, c0, c1| n += c1 - c0,
                )
                .unwrap();
                black_box(n);
                ts.push(t0.elapsed().as_secs_f64());
                let t0 = Instant::now();
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
                tm.push(t0.elapsed().as_secs_f64());
                let t0 = Instant::now();
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
                tmode.push(t0.elapsed().as_secs_f64());
                let t0 = Instant::now();
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
                tw.push(t0.elapsed().as_secs_f64());
            }
            let (s, m, mo, wt) = (median(ts), median(tm), median(tmode), median(tw));
            let px = (w * h) as f64;
            println!(
                "| DEM{} | {} | {} | {} | {:.2} | {:.0} | {:.2} | {:.0} | {:.2} | {:.2} | {:.0} |",
                if f == 1 {
                    String::new()
                } else {
                    format!(" x{f} finer")
                },
                w * h,
                level,
                tin.levels[level].tris.len(),
                s * 1e3,
                px / s / 1e6,
                m * 1e3,
                px / m / 1e6,
                mo * 1e3,
                wt * 1e3,
                px / wt / 1e6
            );
        }
    }
}
