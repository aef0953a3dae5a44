//! Build benchmark (not a test): `tin_from_raster`'s core build on the
//! bundled DEM and on it upsampled 4x (nearest neighbour, the case of issue
//! 25: 1.89 million samples), 2 m at the finest of 5 levels, on 1 and 2
//! threads: wall time (median of 3), samples per second, the counting
//! allocator's peak heap per sample (input samples included) and the
//! triangles made.
//! `cargo bench --bench build`.
#[path = "../tests/common/mod.rs"]
mod common;

use std::time::Instant;
use tinmerge_core::tin::build::{build_lattice, default_tolerances, BuildOptions};
use tinmerge_core::tin::{memory, par};

#[global_allocator]
static ALLOCATOR: memory::Counting = memory::Counting;

fn main() {
    let d = common::read_dem("jacksboro_fault_dem_utm16n.tif");
    println!("| raster | samples | levels | threads | finest triangles | ms (median of 3) | samples/s | peak heap B/sample |");
    println!("|---|---:|---:|---:|---:|---:|---:|---:|");
    for (f, threads) in [(1usize, 1usize), (4, 1), (4, 2)] {
        par::set_threads(threads);
        let (gt, w, h, values) = d.upsampled(f);
        let lat = tinmerge_core::tin::lattice::Lattice {
            ip_x: gt.ip_x + gt.scale_x / 2.0,
            ip_y: gt.ip_y + gt.scale_y / 2.0,
            scale_x: gt.scale_x,
            scale_y: gt.scale_y,
            skew_x: 0.0,
            skew_y: 0.0,
        };
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
        let n = samples().len();
        let tols = default_tolerances(2.0, 5).unwrap();
        let mut times = Vec::new();
        let mut peak = 0usize;
        let mut tris = 0usize;
        for _ in 0..3 {
            let s = samples();
            let base = memory::live() - s.len() * 24;
            memory::reset_peak();
            let t0 = Instant::now();
            let tin = build_lattice(s, &lat, &tols, 32616, BuildOptions::default(), &mut || {
                Ok(())
            })
            .unwrap();
            times.push(t0.elapsed().as_secs_f64() * 1e3);
            peak = memory::peak() - base;
            tris = tin.levels.last().unwrap().tris.len();
        }
        times.sort_by(f64::total_cmp);
        let ms = times[times.len() / 2];
        println!(
            "| DEM x{f} | {n} | 5 | {threads} | {tris} | {ms:.0} | {:.0} | {:.0} |",
            n as f64 / ms * 1e3,
            peak as f64 / n as f64
        );
    }
}
