//! Viewsheds against the brute force of `visibility.rs` at every cell
//! centre: the sight segment from the eye to the point above the cell's
//! centre clipped to every domain triangle near the eye, blocked where it
//! goes below a triangle's plane. The three terrains of
//! `common::terrains`, coarse, middle and finest levels, two grids (the
//! DEM's own, whose centres are the tin's vertices, and an odd grid with a
//! fractional origin), eyes low and high, targets on the ground and above
//! it, two eyes counted together, and the earth's curvature.
use crate::common;
use crate::visibility::oracle_in;

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use tinmerge_core::analysis::rasterize::aligned_grid;
use tinmerge_core::analysis::viewshed::{Eye, NODATA, viewshed, viewshed_with};
use tinmerge_core::analysis::visibility::EARTH_RADIUS;
use tinmerge_core::io::raster::GeoTransform;
use tinmerge_core::merge::point::height;
use tinmerge_core::tin::Tin;

struct Tally {
    cells: usize,
    differ: Vec<(String, f64)>,
    graze_max: f64,
    /// differing cells whose sight line is not grazing
    far: usize,
}

/// The domain triangles within `radius` of an eye, by square buckets of
/// their bounding boxes.
struct Buckets {
    x0: f64,
    y0: f64,
    size: f64,
    n: usize,
    lists: Vec<Vec<u32>>,
}

impl Buckets {
    fn new(tin: &Tin, level: usize, e: &Eye, radius: f64) -> Buckets {
        let n = 48usize;
        let size = 2.0 * radius / n as f64;
        let (x0, y0) = (e.x - radius, e.y - radius);
        let mut lists = vec![Vec::new(); n * n];
        let cell = |v: f64| ((v / size).floor().max(0.0) as usize).min(n - 1);
        for t in 0..tin.levels[level].num_domain() as u32 {
            let co = tin.corners(level, t);
            let (mut a, mut b) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
            for p in co {
                for k in 0..2 {
                    a[k] = a[k].min(p[k]);
                    b[k] = b[k].max(p[k]);
                }
            }
            if b[0] < x0 || b[1] < y0 || a[0] > x0 + 2.0 * radius || a[1] > y0 + 2.0 * radius {
                continue;
            }
            for i in cell(a[0] - x0)..=cell(b[0] - x0) {
                for j in cell(a[1] - y0)..=cell(b[1] - y0) {
                    lists[j * n + i].push(t);
                }
            }
        }
        Buckets {
            x0,
            y0,
            size,
            n,
            lists,
        }
    }

    /// The triangles of the buckets around points every half bucket along
    /// the segment `a`-`b` (each once: `stamp` marks those taken in
    /// `round`).
    fn along(&self, a: [f64; 2], b: [f64; 2], stamp: &mut [u32], round: u32) -> Vec<u32> {
        let len = (b[0] - a[0]).hypot(b[1] - a[1]);
        let steps = (2.0 * len / self.size).ceil() as usize + 1;
        let mut out = Vec::new();
        for k in 0..=steps {
            let t = k as f64 / steps as f64;
            let (x, y) = (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]));
            let (i, j) = (
                ((x - self.x0) / self.size).floor() as i64,
                ((y - self.y0) / self.size).floor() as i64,
            );
            for di in -1..=1 {
                for dj in -1..=1 {
                    let (p, q) = (i + di, j + dj);
                    if p < 0 || q < 0 || p >= self.n as i64 || q >= self.n as i64 {
                        continue;
                    }
                    for &tri in &self.lists[q as usize * self.n + p as usize] {
                        if stamp[tri as usize] != round {
                            stamp[tri as usize] = round;
                            out.push(tri);
                        }
                    }
                }
            }
        }
        out
    }
}

/// Check every cell of one viewshed against the oracle.
#[allow(clippy::too_many_arguments)]
fn check(
    what: &str,
    tin: &Tin,
    level: usize,
    eyes: &[Eye],
    th: f64,
    radius: f64,
    gt: &GeoTransform,
    w: usize,
    h: usize,
    tally: &mut Tally,
) {
    let v = viewshed(tin, level, eyes, th, radius, gt, w, h, &mut || Ok(())).unwrap();
    let lv = &tin.levels[level];
    // the domain triangles that can meet a sight line of each eye, in
    // buckets: a sight line needs only those of the buckets it crosses
    let near: Vec<Buckets> = eyes
        .iter()
        .map(|e| Buckets::new(tin, level, e, radius))
        .collect();
    let mut stamp = vec![0u32; lv.num_triangles()];
    let mut round = 0u32;
    let relief = (tin.bbox.max_z - tin.bbox.min_z).max(1.0);
    for r in 0..h {
        for c in 0..w {
            let (x, y) = (
                gt.ip_x + (c as f64 + 0.5) * gt.scale_x,
                gt.ip_y + (r as f64 + 0.5) * gt.scale_y,
            );
            let got = v.counts[r * w + c];
            let z = height(tin, level, x, y);
            let in_reach: Vec<usize> = (0..eyes.len())
                .filter(|&i| (x - eyes[i].x).hypot(y - eyes[i].y) <= radius)
                .collect();
            let (Some(z), false) = (z, in_reach.is_empty()) else {
                assert_eq!(got, NODATA, "{what}: cell ({c}, {r}) should be nodata");
                continue;
            };
            assert_ne!(got, NODATA, "{what}: cell ({c}, {r}) has nodata");
            let mut want = 0u16;
            let mut graze = f64::INFINITY;
            for &i in &in_reach {
                let e = eyes[i];
                let (dx, dy) = (x - e.x, y - e.y);
                if dx == 0.0 && dy == 0.0 {
                    want += 1;
                    continue;
                }
                let c2 = match e.curvature {
                    None => 0.0,
                    Some((k, [mx, my])) => {
                        let d = dx.hypot(dy);
                        (1.0 - k) * ((mx * dx / d).powi(2) + (my * dy / d).powi(2))
                            / (2.0 * EARTH_RADIUS)
                    }
                };
                round += 1;
                let tris = near[i].along([e.x, e.y], [x, y], &mut stamp, round);
                let (vis, _, g) = oracle_in(tin, level, &tris, [e.x, e.y, e.z], [x, y, z + th], c2);
                want += u16::from(vis);
                graze = graze.min(g);
            }
            tally.cells += 1;
            if got != want {
                tally.graze_max = tally.graze_max.max(graze);
                tally.differ.push((format!(
                    "{what}: cell ({c}, {r}) at ({x}, {y}) sees {got}, the oracle {want}; sight line {graze:.3e} from the ground"
                ), graze));
                if graze >= 1e-6 * relief {
                    tally.far += 1;
                }
            }
        }
    }
}

/// An eye `up` above a random point of the level's surface.
fn eye_on(tin: &Tin, level: usize, rng: &mut StdRng, up: f64) -> Eye {
    let b = tin.bbox;
    let (cx, cy) = (0.5 * (b.min_x + b.max_x), 0.5 * (b.min_y + b.max_y));
    let (hx, hy) = (0.3 * (b.max_x - b.min_x), 0.3 * (b.max_y - b.min_y));
    loop {
        let (x, y) = (
            rng.random_range(cx - hx..cx + hx),
            rng.random_range(cy - hy..cy + hy),
        );
        if let Some(z) = height(tin, level, x, y) {
            return Eye {
                x,
                y,
                z: z + up,
                curvature: None,
            };
        }
    }
}

#[test]
fn viewshed_against_a_sight_line_per_cell() {
    let mut tally = Tally {
        cells: 0,
        differ: Vec::new(),
        graze_max: 0.0,
        far: 0,
    };
    let mut seen = 0usize;
    for terrain in common::terrains() {
        let tin = &terrain.tin;
        let dem = common::read_dem(terrain.file);
        let own = (dem.geotransform(), dem.width, dem.height);
        // a third of the tin's width, in its units
        let radius = 0.18 * (tin.bbox.max_x - tin.bbox.min_x);
        let px = dem.scale_x;
        let b = [
            tin.bbox.min_x,
            tin.bbox.min_y,
            tin.bbox.max_x,
            tin.bbox.max_y,
        ];
        let odd = aligned_grid(
            &b,
            0.813 * px,
            0.967 * px,
            b[0] + 0.31 * px,
            b[1] - 0.77 * px,
        )
        .unwrap();
        let n = tin.num_levels();
        let mut rng = StdRng::seed_from_u64(11);
        for level in [0, n - 1] {
            for (gname, (gt, w, h)) in [("own grid", own), ("odd grid", odd)] {
                for (up, th) in [(1.7, 0.0), (30.0, 2.0)] {
                    if gname == "odd grid" && up > 2.0 {
                        continue;
                    }
                    let eye = eye_on(tin, level, &mut rng, up);
                    let what = format!(
                        "{} level {level} {gname} eye {up} m target {th} m",
                        terrain.name
                    );
                    check(&what, tin, level, &[eye], th, radius, &gt, w, h, &mut tally);
                    seen += 1;
                }
                // two eyes counted together
                let eyes = [
                    eye_on(tin, level, &mut rng, 10.0),
                    eye_on(tin, level, &mut rng, 2.0),
                ];
                let what = format!("{} level {level} {gname} two eyes", terrain.name);
                check(&what, tin, level, &eyes, 0.0, radius, &gt, w, h, &mut tally);
            }
        }
        let _ = seen;
    }
    let share = tally.differ.len() as f64 / tally.cells as f64;
    eprintln!(
        "viewshed: {} cells, {} differ from the oracle ({:.4} %), {} not grazing; largest |g| {:.2e}",
        tally.cells,
        tally.differ.len(),
        100.0 * share,
        tally.far,
        tally.graze_max
    );
    tally.differ.sort_by(|a, b| b.1.total_cmp(&a.1));
    for (d, _) in tally.differ.iter().take(20) {
        eprintln!("  {d}");
    }
    assert!(tally.cells > 100_000, "{} cells", tally.cells);
    // the promise: 99.9 % the same, the rest at grazing sight
    // lines (here: a few where a narrow rise between the two rays of the
    // cell's wedge blocks its own ray, or a notch lets it through)
    assert!(
        share <= 0.001,
        "{} cells differ of {}",
        tally.differ.len(),
        tally.cells
    );
    assert!(
        tally.far as f64 <= 1e-4 * tally.cells as f64,
        "{} cells differ by more than grazing",
        tally.far
    );
}

#[test]
fn viewshed_with_the_earths_curvature() {
    // the UTM DEM, an eye 20 m up, 15 km: the curvature hides a few metres
    let tin = common::dem_tin();
    let level = tin.num_levels() - 1;
    let mut rng = StdRng::seed_from_u64(5);
    let mut tally = Tally {
        cells: 0,
        differ: Vec::new(),
        graze_max: 0.0,
        far: 0,
    };
    let dem = common::read_dem("jacksboro_fault_dem_utm16n.tif");
    let (gt, w, h) = (dem.geotransform(), dem.width, dem.height);
    let mut flat_differs = 0;
    for _ in 0..2 {
        let mut eye = eye_on(&tin, level, &mut rng, 20.0);
        eye.curvature = Some((0.13, [1.0, 1.0]));
        check(
            "curvature",
            &tin,
            level,
            &[eye],
            0.0,
            15_000.0,
            &gt,
            w,
            h,
            &mut tally,
        );
        let run = |eye: Eye| {
            viewshed(
                &tin,
                level,
                &[eye],
                0.0,
                15_000.0,
                &gt,
                w,
                h,
                &mut || Ok(()),
            )
            .unwrap()
        };
        let curved = run(eye);
        eye.curvature = None;
        let flat = run(eye);
        flat_differs += curved
            .counts
            .iter()
            .zip(&flat.counts)
            .filter(|(a, b)| a != b)
            .count();
    }
    assert!(
        flat_differs > 20,
        "the curvature changed {flat_differs} cells"
    );
    assert!(
        tally.differ.len() as f64 <= 0.001 * tally.cells as f64,
        "{:?}",
        &tally.differ[..tally.differ.len().min(10)]
    );
}

#[test]
fn pruning_changes_nothing_and_saves_work() {
    let tin = common::dem_tin();
    let level = tin.num_levels() - 1;
    let dem = common::read_dem("jacksboro_fault_dem_utm16n.tif");
    let (gt, w, h) = (dem.geotransform(), dem.width, dem.height);
    let mut rng = StdRng::seed_from_u64(3);
    let mut saved = Vec::new();
    for _ in 0..3 {
        let eye = eye_on(&tin, level, &mut rng, 1.7);
        let run = |prune| {
            viewshed_with(
                &tin,
                level,
                &[eye],
                0.0,
                12_000.0,
                &gt,
                w,
                h,
                prune,
                &mut || Ok(()),
            )
            .unwrap()
        };
        let t0 = std::time::Instant::now();
        let p = run(true);
        let t1 = t0.elapsed();
        let q = run(false);
        eprintln!(
            "viewshed: {} cells in {t1:?} ({} rays, {} fine pieces, {} exact, {} local); without pruning {:?}",
            p.cells,
            p.rays,
            p.fine_pieces,
            p.exact_cells,
            p.local_cells,
            t0.elapsed() - t1
        );
        assert_eq!(p.counts, q.counts, "pruning changed the answer");
        assert!(p.pruned > 0 && q.pruned == 0);
        saved.push(1.0 - p.fine_pieces as f64 / q.fine_pieces as f64);
    }
    eprintln!("viewshed: coarse levels skip {saved:?} of the finest level's stretches");
    assert!(saved.iter().all(|&s| s > 0.2), "{saved:?}");
}

#[test]
fn threads_give_identical_viewsheds() {
    // the heights are swept in bands of rows and the fan's sectors run on
    // the pool: one thread and two must give the same cells, and the same
    // work counted
    use tinmerge_core::tin::par;
    let tin = common::dem_tin();
    let level = tin.num_levels() - 1;
    let dem = common::read_dem("jacksboro_fault_dem_utm16n.tif");
    let (gt, w, h) = (dem.geotransform(), dem.width, dem.height);
    let mut rng = StdRng::seed_from_u64(8);
    let eyes = [
        eye_on(&tin, level, &mut rng, 1.7),
        eye_on(&tin, level, &mut rng, 25.0),
    ];
    let before = par::threads();
    let mut out = Vec::new();
    for n in [1, 2] {
        par::set_threads(n);
        out.push(viewshed(&tin, level, &eyes, 0.0, 9_000.0, &gt, w, h, &mut || Ok(())).unwrap());
    }
    par::set_threads(before);
    assert!(out[0].cells > 10_000);
    assert_eq!(out[0], out[1], "two threads changed the viewshed");
}
