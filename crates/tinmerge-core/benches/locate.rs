//! Core point-location benchmark (not a test): nanoseconds per query on
//! random points for TINs of about 1k, 100k and 1M triangles, comparing
//! - the per-level grid index + exact walk (`merge::point::locate`),
//! - the top-down hierarchy search (level 0 grid, then children),
//! - spade's own `locate` with its `HierarchyHintGenerator`, on the very same
//!   triangulation (a CDT bulk-loaded with every edge of the level),
//! - locate + interpolate (`merge::point::height`).
//!
//! Prints a markdown table of medians over 5 runs. `cargo bench --bench locate`.
#[path = "../tests/common/mod.rs"]
mod common;

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use spade::{
    ConstrainedDelaunayTriangulation, HierarchyHintGenerator, Point2, PositionInTriangulation,
    Triangulation,
};
use std::hint::black_box;
use std::time::Instant;
use tinmerge_core::merge::point::{height, locate, locate_descend};
use tinmerge_core::tin::Tin;
use tinmerge_core::tin::build::{build, default_tolerances};

type SpadeCdt =
    ConstrainedDelaunayTriangulation<Point2<f64>, (), (), (), HierarchyHintGenerator<f64>>;

/// Deterministic synthetic terrain on an n x n grid of 1 m cells: two
/// smooth waves plus hashed noise of +-2 m, so a small tolerance keeps
/// nearly every sample.
pub fn synthetic(n: usize) -> Vec<[f64; 3]> {
    let mut out = Vec::with_capacity(n * n);
    for i in 0..n {
        for j in 0..n {
            let h = (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
                ^ (j as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
            let h = (h ^ (h >> 31)).wrapping_mul(0x94D0_49BB_1331_11EB);
            let noise = ((h >> 11) as f64 / (1u64 << 53) as f64) * 4.0 - 2.0;
            let (x, y) = (i as f64, j as f64);
            let z =
                50.0 * (x / 37.0).sin() * (y / 53.0).cos() + 20.0 * ((x + y) / 17.0).sin() + noise;
            out.push([x, y, z]);
        }
    }
    out
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Median ns per call of `f` over `pts`, 5 runs.
fn time(pts: &[(f64, f64)], mut f: impl FnMut(f64, f64) -> u64) -> f64 {
    let mut runs = Vec::new();
    for _ in 0..5 {
        let t0 = Instant::now();
        let mut acc = 0u64;
        for &(x, y) in pts {
            acc = acc.wrapping_add(f(x, y));
        }
        black_box(acc);
        runs.push(t0.elapsed().as_nanos() as f64 / pts.len() as f64);
    }
    median(runs)
}

fn spade_of(tin: &Tin, level: usize) -> SpadeCdt {
    let lv = &tin.levels[level];
    let verts: Vec<Point2<f64>> = tin.verts[..lv.num_vertices as usize]
        .iter()
        .map(|v| Point2::new(v[0], v[1]))
        .collect();
    let mut edges = Vec::with_capacity(lv.tris.len() * 3 / 2 + 8);
    for (t, tri) in lv.tris.iter().enumerate() {
        for j in 0..3 {
            let nb = lv.nbrs[t][j];
            // each interior edge once (from its lower-id triangle); hull edges once
            if nb == u32::MAX || (nb as usize) > t {
                edges.push([tri[(j + 1) % 3] as usize, tri[(j + 2) % 3] as usize]);
            }
        }
    }
    SpadeCdt::bulk_load_cdt(verts, edges).expect("spade bulk load")
}

fn main() {
    let dem = common::read_dem("jacksboro_fault_dem_utm16n.tif");
    let t0 = Instant::now();
    let cases: Vec<(&str, Tin)> = vec![
        (
            "DEM, 250 m, 3 levels",
            build(
                dem.samples(),
                &default_tolerances(250.0, 3).unwrap(),
                32616,
                &mut || Ok(()),
            )
            .unwrap(),
        ),
        (
            "DEM, 4 m, 5 levels",
            build(
                dem.samples(),
                &default_tolerances(4.0, 5).unwrap(),
                32616,
                &mut || Ok(()),
            )
            .unwrap(),
        ),
        (
            "synthetic 720 x 720, 0.25 m, 5 levels",
            build(
                synthetic(720),
                &default_tolerances(0.25, 5).unwrap(),
                0,
                &mut || Ok(()),
            )
            .unwrap(),
        ),
    ];
    eprintln!(
        "built the three tins in {:.1} s",
        t0.elapsed().as_secs_f64()
    );
    println!(
        "| tin | finest triangles | grid + walk ns | top-down ns | spade (hierarchy hint) ns | locate + interpolate ns | locate + interpolate, Morton-ordered points ns | spade / grid |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|");
    let mut rng = StdRng::seed_from_u64(42);
    for (name, tin) in &cases {
        let l = tin.levels.len() - 1;
        let b = tin.bbox;
        // 1M points uniform over the domain's bounding box, inside the domain
        let mut pts = Vec::with_capacity(1_000_000);
        while pts.len() < 1_000_000 {
            let x = b.min_x + rng.random::<f64>() * (b.max_x - b.min_x);
            let y = b.min_y + rng.random::<f64>() * (b.max_y - b.min_y);
            if locate(tin, l, x, y).is_some() {
                pts.push((x, y));
            }
        }
        let sp = spade_of(tin, l);
        assert_eq!(
            sp.num_inner_faces(),
            tin.levels[l].tris.len(),
            "same triangulation"
        );
        let grid = time(&pts, |x, y| locate(tin, l, x, y).map_or(0, |t| t as u64));
        let down = time(&pts, |x, y| {
            locate_descend(tin, l, x, y).map_or(0, |t| t as u64)
        });
        let spade = time(&pts, |x, y| match sp.locate(Point2::new(x, y)) {
            PositionInTriangulation::OnFace(f) => f.index() as u64,
            PositionInTriangulation::OnEdge(e) => e.index() as u64,
            PositionInTriangulation::OnVertex(v) => v.index() as u64,
            _ => 0,
        });
        let h = time(&pts, |x, y| height(tin, l, x, y).map_or(0, |z| z.to_bits()));
        // the same points in Morton order (as a spatially clustered table or
        // a sorted batch gives them): the walk then reads memory it just read
        let key = |&(x, y): &(f64, f64)| {
            let q = |v: f64, lo: f64, hi: f64| ((v - lo) / (hi - lo) * 65535.0) as u32;
            let (mut a, mut c) = (q(x, b.min_x, b.max_x), q(y, b.min_y, b.max_y));
            let mut m = 0u64;
            for i in 0..16 {
                m |= ((a & 1) as u64) << (2 * i) | ((c & 1) as u64) << (2 * i + 1);
                a >>= 1;
                c >>= 1;
            }
            m
        };
        let mut sorted = pts.clone();
        sorted.sort_by_key(key);
        let hs = time(&sorted, |x, y| {
            height(tin, l, x, y).map_or(0, |z| z.to_bits())
        });
        println!(
            "| {name} | {} | {grid:.0} | {down:.0} | {spade:.0} | {h:.0} | {hs:.0} | {:.1}x |",
            tin.levels[l].tris.len(),
            spade / grid
        );
    }
}
