//! The hierarchy built from the real Jacksboro DEM satisfies every property,
//! checked with oracles independent of the build: errors by a brute-force
//! scan of every valid pixel against every triangle, plus the invariant
//! checker and an encode/decode round trip.
use crate::common;

use std::time::Instant;
use tinmerge_core::tin::build::{BuildOptions, build, build_lattice, default_tolerances};
use tinmerge_core::tin::{Tin, layout, locate};

/// Brute-force max |surface - sample| per level over all samples, by
/// rasterising each triangle's bbox over the sample list sorted into rows.
fn brute_force_errors(tin: &Tin, samples: &[[f64; 3]]) -> Vec<(f64, usize)> {
    let mut out = Vec::new();
    // bucket samples by exact y (pixel rows) for speed
    let mut rows: std::collections::BTreeMap<u64, Vec<[f64; 3]>> = Default::default();
    for s in samples {
        rows.entry(s[1].to_bits()).or_default().push(*s);
    }
    let mut ys: Vec<f64> = rows.keys().map(|k| f64::from_bits(*k)).collect();
    ys.sort_by(f64::total_cmp);
    for (l, lv) in tin.levels.iter().enumerate() {
        let mut best: Vec<f64> = vec![f64::NAN; samples.len()];
        let mut idx: std::collections::HashMap<(u64, u64), usize> = Default::default();
        for (i, s) in samples.iter().enumerate() {
            idx.insert((s[0].to_bits(), s[1].to_bits()), i);
        }
        for t in 0..lv.tris.len() {
            let c = tin.corners(l, t as u32);
            let (x0, x1) = (
                c.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min),
                c.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max),
            );
            let (y0, y1) = (
                c.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min),
                c.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max),
            );
            let lo = ys.partition_point(|&y| y < y0);
            let hi = ys.partition_point(|&y| y <= y1);
            for y in &ys[lo..hi] {
                for s in &rows[&y.to_bits()] {
                    if s[0] < x0 || s[0] > x1 {
                        continue;
                    }
                    // independent inside test: barycentric with a tiny slack
                    let d = (c[1][0] - c[0][0]) * (c[2][1] - c[0][1])
                        - (c[2][0] - c[0][0]) * (c[1][1] - c[0][1]);
                    let u = ((s[0] - c[0][0]) * (c[2][1] - c[0][1])
                        - (c[2][0] - c[0][0]) * (s[1] - c[0][1]))
                        / d;
                    let v = ((c[1][0] - c[0][0]) * (s[1] - c[0][1])
                        - (s[0] - c[0][0]) * (c[1][1] - c[0][1]))
                        / d;
                    if u < -1e-12 || v < -1e-12 || u + v > 1.0 + 1e-12 {
                        continue;
                    }
                    let z = c[0][2] * (1.0 - u - v) + c[1][2] * u + c[2][2] * v;
                    let i = idx[&(s[0].to_bits(), s[1].to_bits())];
                    let e = (z - s[2]).abs();
                    best[i] = if best[i].is_nan() { e } else { best[i].min(e) };
                }
            }
        }
        let uncovered = best.iter().filter(|e| e.is_nan()).count();
        let max = best
            .iter()
            .filter(|e| !e.is_nan())
            .fold(0.0f64, |a, &b| a.max(b));
        out.push((max, uncovered));
    }
    out
}

/// A band's valid pixels as lattice samples (col, row, z).
fn lattice_samples(values: &[f64], w: usize, nodata: Option<f64>) -> Vec<[f64; 3]> {
    values
        .iter()
        .enumerate()
        .filter(|(_, v)| !v.is_nan() && Some(**v) != nodata)
        .map(|(i, &v)| [(i % w) as f64, (i / w) as f64, v])
        .collect()
}

#[test]
fn jacksboro_utm_tolerance_2m_5_levels() {
    let dem = common::read_dem("jacksboro_fault_dem_utm16n.tif");
    check_dem_build(dem.samples(), false);
    // tin_from_raster's build: on the lattice, finer levels parent by parent
    check_dem_build(lattice_samples(&dem.values, dem.width, dem.nodata), true);
}

/// The geographic DEM (odd pixel sizes, a nodata border) on its lattice.
#[test]
fn geographic_dem_on_its_lattice() {
    let dem = common::read_dem("jacksboro_fault_dem.tif");
    check_dem_build(lattice_samples(&dem.values, dem.width, dem.nodata), true);
}

/// Lattice samples too sparse for their window (here 1 pixel in 60 of a
/// 2,408 x 2,541 window) are built in one triangulation, as scattered
/// samples are: the same guarantees.
#[test]
fn sparse_lattice_builds() {
    let dem = common::read_dem("jacksboro_fault_dem_utm16n.tif");
    let (_, w, _, values) = dem.upsampled(7);
    let sparse: Vec<[f64; 3]> = lattice_samples(&values, w, dem.nodata)
        .into_iter()
        .enumerate()
        .filter(|(i, _)| (i * 7919) % 60 == 0)
        .map(|(_, p)| p)
        .collect();
    // sparser than the build reads in place (8 pixels a sample + 2^20)
    let h = values.len() / w;
    assert!(
        sparse.len() * 8 + (1 << 20) < w * h,
        "{} samples",
        sparse.len()
    );
    check_dem_build(sparse, true);
}

/// Build `samples` (lattice samples on `IDENTITY` when `on_lattice`), and
/// check the invariants, the errors at every sample by brute force, the
/// storage round trip and point location.
fn check_dem_build(samples: Vec<[f64; 3]>, on_lattice: bool) {
    assert!(samples.len() > 20_000, "{} valid samples", samples.len());
    let tols = default_tolerances(2.0, 5).unwrap();
    let t0 = Instant::now();
    let tin = if on_lattice {
        build_lattice(
            samples.clone(),
            &common::IDENTITY,
            &tols,
            32616,
            BuildOptions::default(),
            &mut || Ok(()),
        )
        .unwrap()
    } else {
        build(samples.clone(), &tols, 32616, &mut || Ok(())).unwrap()
    };
    let dt = t0.elapsed();
    tin.sanity_check().unwrap();
    let counts: Vec<usize> = tin.levels.iter().map(|l| l.tris.len()).collect();
    eprintln!(
        "levels {:?} tolerances {:?} triangles {:?} build {:?}",
        tin.levels.len(),
        tols,
        counts,
        dt
    );
    // coarse to fine: more triangles at every level
    assert!(counts.windows(2).all(|w| w[0] < w[1]), "{counts:?}");
    let errs = brute_force_errors(&tin, &samples);
    for (l, (max, uncovered)) in errs.iter().enumerate() {
        eprintln!(
            "level {l}: tolerance {} brute-force max error {max:.4} (stored {:.4})",
            tols[l], tin.levels[l].max_error
        );
        assert_eq!(*uncovered, 0, "level {l}: samples outside every triangle");
        assert!(
            *max <= tols[l] + 1e-6,
            "level {l}: error {max} > {}",
            tols[l]
        );
        assert!((max - tin.levels[l].max_error).abs() < 1e-6);
    }
    // storage round trip is exact and validated
    let bytes = layout::encode(&tin);
    let back = layout::decode(&bytes).unwrap();
    assert_eq!(back, tin);
    // every sample is located at every level, inside the triangle found
    for s in samples.iter().step_by(97) {
        for l in 0..tin.levels.len() {
            let t = locate::locate(&tin, l, s[0], s[1]).expect("sample inside domain");
            assert!(locate::contains(&tin, l, t, s[0], s[1]));
        }
    }
}

#[test]
fn geographic_dem_builds_too_scattered() {
    let dem = common::read_dem("jacksboro_fault_dem.tif");
    let tin = build(
        dem.samples(),
        &default_tolerances(4.0, 3).unwrap(),
        4326,
        &mut || Ok(()),
    )
    .unwrap();
    tin.sanity_check().unwrap();
}

/// `tinmerge.threads`: a build on 2 threads (faces measured, parents found
/// on the pool) stores the very same bytes as a build on 1, for the UTM DEM
/// and for the 3x finer copy (1.07M samples: the first insertions of each
/// level re-measure faces large enough to go to the threads), scattered
/// and on the lattice (parents refined on the pool).
#[test]
fn threads_build_identical_values() {
    use tinmerge_core::tin::par;
    let dem = common::read_dem("jacksboro_fault_dem_utm16n.tif");
    let (gt, w, h, values) = dem.upsampled(3);
    let mut fine = Vec::new();
    for row in 0..h {
        for col in 0..w {
            let v = values[row * w + col];
            if !v.is_nan() && Some(v) != dem.nodata {
                let x = gt.ip_x + (col as f64 + 0.5) * gt.scale_x;
                let y = gt.ip_y + (row as f64 + 0.5) * gt.scale_y;
                fine.push([x, y, v]);
            }
        }
    }
    let fine_lattice = lattice_samples(&values, w, dem.nodata);
    let coarse_lattice = lattice_samples(&dem.values, dem.width, dem.nodata);
    for (samples, tol, levels, on_lattice) in [
        (dem.samples(), 2.0, 5, false),
        (fine, 4.0, 3, false),
        (coarse_lattice, 2.0, 5, true),
        (fine_lattice, 1.0, 5, true),
    ] {
        let tols = default_tolerances(tol, levels).unwrap();
        let mut bytes = Vec::new();
        for n in [1, 2] {
            par::set_threads(n);
            let t0 = Instant::now();
            let tin = if on_lattice {
                let opts = BuildOptions::default();
                build_lattice(
                    samples.clone(),
                    &common::IDENTITY,
                    &tols,
                    32616,
                    opts,
                    &mut || Ok(()),
                )
            } else {
                build(samples.clone(), &tols, 32616, &mut || Ok(()))
            }
            .unwrap();
            eprintln!("{} samples, {n} threads: {:?}", samples.len(), t0.elapsed());
            bytes.push(layout::encode(&tin));
        }
        par::set_threads(1);
        assert!(
            bytes[0] == bytes[1],
            "{} samples: values differ",
            samples.len()
        );
    }
}
