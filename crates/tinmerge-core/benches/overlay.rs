//! Core overlay benchmark (not a test): two TINs built from the bundled DEM
//! (the tests' TIN at tolerance 2 m, and one at other tolerances or from a
//! copy shifted by a fraction of a pixel), overlaid level by level,
//! single-threaded, against the naive method (all edges of both inserted
//! into one spade CDT with splitting at crossings). Prints a markdown table
//! of medians. `cargo bench --bench overlay`.
#[path = "../tests/common/mod.rs"]
mod common;

use std::hint::black_box;
use std::time::Instant;
use tinmerge_core::merge::overlay::constrained::naive;
use tinmerge_core::merge::overlay::{difference, overlay, overlay_constrained};
use tinmerge_core::tin::build::{build, default_tolerances};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let a = common::dem_tin();
    let d = common::read_dem("jacksboro_fault_dem_utm16n.tif");
    let other = build(
        d.samples(),
        &default_tolerances(1.5, 5).unwrap(),
        32616,
        &mut || Ok(()),
    )
    .unwrap();
    let shifted_samples: Vec<[f64; 3]> = d
        .samples()
        .into_iter()
        .map(|p| [p[0] + 0.37 * d.scale_x, p[1] - 0.61 * d.scale_y, p[2]])
        .collect();
    let shifted = build(
        shifted_samples,
        &default_tolerances(2.0, 5).unwrap(),
        32616,
        &mut || Ok(()),
    )
    .unwrap();
    if std::env::var_os("OVERLAY_PROFILE").is_some() {
        // for a profiler: the faces path alone at level 3, other tolerances
        // (OVERLAY_PROFILE=shifted: the shifted copy)
        for _ in 0..5 {
            let t0 = Instant::now();
            let b = if std::env::var("OVERLAY_PROFILE").as_deref() == Ok("shifted") {
                &shifted
            } else {
                &other
            };
            black_box(overlay(&a, 3, b, 3, &mut || Ok(())).unwrap());
            eprintln!("{:?}", t0.elapsed());
        }
        return;
    }
    println!(
        "| B | level | triangles A | triangles B | crossings K | output triangles | overlay ms | path | M input triangles/s | + difference ms | constrained path ms | naive CDT ms | naive / overlay |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|");
    for (name, b) in [
        ("other tolerances (1.5 m)", &other),
        ("shifted copy (0.37, 0.61 px)", &shifted),
    ] {
        for level in [1usize, 2, 3, 4] {
            let (mut to, mut td) = (Vec::new(), Vec::new());
            let mut last = None;
            for _ in 0..3 {
                let t0 = Instant::now();
                let o = overlay(&a, level, b, level, &mut || Ok(())).unwrap();
                to.push(t0.elapsed().as_secs_f64());
                let t0 = Instant::now();
                black_box(difference(&o));
                td.push(t0.elapsed().as_secs_f64());
                last = Some(o);
            }
            let o = last.unwrap();
            let mut tc = Vec::new();
            for _ in 0..3 {
                let t0 = Instant::now();
                black_box(overlay_constrained(&a, level, b, level, &mut || Ok(())).unwrap());
                tc.push(t0.elapsed().as_secs_f64());
            }
            // the naive method can hit one of spade's assertions when two
            // crossings fall very near each other: reported as "failed"
            let t0 = Instant::now();
            let ok = naive(&a, level, b, level).is_ok();
            let tn = if ok {
                t0.elapsed().as_secs_f64()
            } else {
                f64::NAN
            };
            let (na, nb) = (a.levels[level].tris.len(), b.levels[level].tris.len());
            let mo = median(to);
            println!(
                "| {name} | {level} | {na} | {nb} | {} | {} | {:.1} | {} | {:.2} | {:.1} | {:.1} | {} | {} |",
                o.crossings,
                o.tris.len(),
                mo * 1e3,
                o.fallback.as_deref().unwrap_or("faces"),
                (na + nb) as f64 / mo / 1e6,
                median(td) * 1e3,
                median(tc) * 1e3,
                if ok {
                    format!("{:.1}", tn * 1e3)
                } else {
                    "failed (spade assertion)".into()
                },
                if ok {
                    format!("{:.1}x", tn / mo)
                } else {
                    "-".into()
                }
            );
        }
    }
}
