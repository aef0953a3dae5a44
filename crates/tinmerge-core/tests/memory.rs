//! The memory estimates that `tinmerge.max_memory` checks requests against
//! (`tin::memory`), against the peak heap each request really uses on the
//! real DEM, measured by the counting allocator: builds, decoding a stored
//! value and reading a raster band must stay under their estimate (else a
//! request passing the check could still exceed the limit), and the
//! estimate must not be so loose that it refuses requests using a quarter of
//! it. The overlay's estimate is a lower bound (its output grows with the
//! crossings, checked while it runs), so its real peak must be above it.
//!
//! One test function: the counters are process-wide, so nothing else may
//! allocate while a peak is measured.

mod common;

use common::read_dem;
use tinmerge_core::io::raster;
use tinmerge_core::merge::overlay::overlay;
use tinmerge_core::tin::build::{
    BuildOptions, build, build_domain_raster, build_lattice, default_tolerances,
};
use tinmerge_core::tin::dense::Dense;
use tinmerge_core::tin::domain::{cell_outline, outline_area};
use tinmerge_core::tin::{layout, memory};

/// The extension installs the counting allocator in its crate root; this
/// test binary links only the core, so it installs it here.
#[global_allocator]
static ALLOCATOR: memory::Counting = memory::Counting;

/// Peak heap above the current level while `f` runs, and its result.
fn peak_of<T>(f: impl FnOnce() -> T) -> (usize, T) {
    let base = memory::live();
    memory::reset_peak();
    let out = f();
    (memory::peak().saturating_sub(base), out)
}

/// A one-band float64 WKB raster (little endian), as PostGIS sends it.
fn wkb_raster(gt: &raster::GeoTransform, w: usize, h: usize, values: &[f64]) -> Vec<u8> {
    let mut b = vec![1u8];
    b.extend_from_slice(&0u16.to_le_bytes());
    b.extend_from_slice(&1u16.to_le_bytes());
    for v in [
        gt.scale_x, gt.scale_y, gt.ip_x, gt.ip_y, gt.skew_x, gt.skew_y,
    ] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b.extend_from_slice(&32616i32.to_le_bytes());
    b.extend_from_slice(&(w as u16).to_le_bytes());
    b.extend_from_slice(&(h as u16).to_le_bytes());
    b.push(0x40 | 11); // 64BF, has nodata
    b.extend_from_slice(&(-9999.0f64).to_le_bytes());
    for v in values {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b
}

fn row(what: &str, input: String, peak: usize, estimate: usize) {
    println!(
        "{what:<28} {input:>34} {:>9.1} MB {:>9.1} MB {:>6.2}",
        peak as f64 / 1e6,
        estimate as f64 / 1e6,
        estimate as f64 / peak.max(1) as f64
    );
}

/// `tin_from_raster`'s default build over the valid pixels only: their
/// centres in world coordinates inside the valid cells' outline, the
/// raster's heights held between the samples. `samples` are
/// `[col, row, z]` on `lat`; the peak heap while building (the heights are
/// part of the request, as the samples are: the caller adds both).
fn valid_pixels_build(
    samples: Vec<[f64; 3]>,
    w: usize,
    h: usize,
    lat: &tinmerge_core::tin::lattice::Lattice,
    tols: &[f64],
) -> (usize, tinmerge_core::tin::Tin) {
    let mut z = vec![f64::NAN; w * h];
    for p in &samples {
        z[p[1] as usize * w + p[0] as usize] = p[2];
    }
    let rings = cell_outline(w, h, &|c, r| !z[r * w + c].is_nan());
    let area = outline_area(&rings, &|c, r| {
        let (x, y) = lat.centre(c - 0.5, r - 0.5);
        [x, y]
    });
    let world: Vec<[f64; 3]> = samples
        .iter()
        .map(|p| {
            let (x, y) = lat.centre(p[0], p[1]);
            [x, y, p[2]]
        })
        .collect();
    drop(samples);
    peak_of(move || {
        let heights = Dense {
            c0: 0,
            r0: 0,
            width: w,
            height: h,
            z,
        };
        build_domain_raster(
            world,
            &[],
            &[&area],
            tols,
            32616,
            &heights,
            lat,
            &mut || Ok(()),
        )
        .unwrap()
    })
}

/// A typical estimate ([`lattice_build_bytes`] between samples) on a
/// rougher input: the running check stops a build that passes the limit,
/// so the estimate may be below the peak, but not by more than 16x (white
/// noise, every sample a vertex of every level, is 15x): an estimate
/// further below says nothing.
///
/// [`lattice_build_bytes`]: tinmerge_core::tin::build::lattice_build_bytes
fn typical(what: &str, peak: usize, estimate: usize) {
    assert!(
        16 * estimate >= peak,
        "{what}: peak {peak} bytes over 16x the estimate {estimate}"
    );
    assert!(
        estimate <= 4 * peak.max(1 << 20),
        "{what}: estimate {estimate} bytes is over 4x the peak {peak}"
    );
}

fn upper_bound(what: &str, peak: usize, estimate: usize) {
    assert!(
        peak <= estimate,
        "{what}: peak {peak} bytes above the estimate {estimate}"
    );
    assert!(
        estimate <= 4 * peak.max(1 << 20),
        "{what}: estimate {estimate} bytes is over 4x the peak {peak}"
    );
}

#[test]
fn estimates_bound_the_measured_peaks() {
    let dem = read_dem("jacksboro_fault_dem_utm16n.tif");
    println!(
        "{:<28} {:>34} {:>12} {:>12} {:>6}",
        "request", "input", "peak", "estimate", "ratio"
    );

    // builds: the samples are part of the request (the SQL layer reserves
    // the estimate minus the samples it already holds)
    // a terrain finer than its relief, as LiDAR DEMs are: the DEM 4x finer
    // by bilinear resampling of its pixel centres (1376 x 1452): the
    // typical estimate of a raster build between samples bounds its peak
    {
        let f = 4usize;
        let (w, h) = (dem.width * f, dem.height * f);
        let at = |c: usize, r: usize| {
            let v = dem.values[r.min(dem.height - 1) * dem.width + c.min(dem.width - 1)];
            (!v.is_nan() && Some(v) != dem.nodata).then_some(v)
        };
        let mut samples = Vec::with_capacity(w * h);
        for r in 0..h {
            for c in 0..w {
                // the fine centre in coarse pixel units, about the centres
                let (x, y) = (
                    ((c as f64 + 0.5) / f as f64 - 0.5).max(0.0),
                    ((r as f64 + 0.5) / f as f64 - 0.5).max(0.0),
                );
                let (c0, r0) = (x.floor() as usize, y.floor() as usize);
                let (fx, fy) = (x - c0 as f64, y - r0 as f64);
                if let (Some(a), Some(b), Some(cc), Some(d)) = (
                    at(c0, r0),
                    at(c0 + 1, r0),
                    at(c0, r0 + 1),
                    at(c0 + 1, r0 + 1),
                ) {
                    let z =
                        (a * (1.0 - fx) + b * fx) * (1.0 - fy) + (cc * (1.0 - fx) + d * fx) * fy;
                    samples.push([c as f64, r as f64, z]);
                }
            }
        }
        let mut lat = dem.lattice();
        lat.scale_x /= f as f64;
        lat.scale_y /= f as f64;
        let n = samples.len();
        let tols = default_tolerances(2.0, 5).unwrap();
        let copy = samples.clone();
        let (peak, tin) = peak_of(|| {
            build_lattice(
                copy,
                &lat,
                &tols,
                32616,
                BuildOptions {
                    keep_border: false,
                    between_samples: true,
                },
                &mut || Ok(()),
            )
            .unwrap()
        });
        let peak = peak + n * 24;
        let est = tinmerge_core::tin::build::lattice_build_bytes(n, 5, true);
        let what = "typical: DEM 4x, bilinear";
        row(
            what,
            format!("{n} samples, {} verts, 5 lv", tin.verts.len()),
            peak,
            est,
        );
        upper_bound(what, peak, est);
        drop(tin);
        // the same over the valid pixels only (tin_from_raster's default
        // where the raster has nodata)
        let (peak, tin) = valid_pixels_build(samples, w, h, &lat, &tols);
        let peak = peak + n * 24 + w * h * 8;
        let est = tinmerge_core::tin::build::domain_raster_build_bytes(n, w * h, 5);
        let what = "typical, valid pixels";
        row(
            what,
            format!("{n} samples, {} verts, 5 lv", tin.verts.len()),
            peak,
            est,
        );
        upper_bound(what, peak, est);
    }

    let mut tins = Vec::new();
    // (1: DEM, 0: DEM + noise; levels; tolerance): tolerance 0.01 on noisy samples
    // makes nearly every sample a vertex of the finest levels (worst case)
    for (f, levels, tol) in [(1usize, 1usize, 2.0), (1, 5, 2.0), (0, 5, 0.01)] {
        let samples: Vec<[f64; 3]> = if f == 1 {
            dem.samples()
        } else {
            dem.samples()
                .into_iter()
                .enumerate()
                .map(|(i, p)| [p[0], p[1], p[2] + ((i * 7919) % 13) as f64 * 0.37])
                .collect()
        };
        let n = samples.len();
        let tols = default_tolerances(tol, levels as i32).unwrap();
        let (peak, tin) = peak_of(move || build(samples, &tols, 32616, &mut || Ok(())).unwrap());
        let peak = peak + n * 24;
        let est = tinmerge_core::tin::build::build_bytes(n, levels);
        let verts = tin.verts.len();
        row(
            "build",
            format!("{n} samples, {verts} verts, {levels} lv"),
            peak,
            est,
        );
        upper_bound("build", peak, est);
        if f == 1 && levels == 5 {
            tins.push(tin);
        }
        // the same samples on their pixel lattice: tin_from_raster's build,
        // the finer levels refined parent by parent
        let lattice_samples: Vec<[f64; 3]> = (0..dem.height)
            .flat_map(|r| (0..dem.width).map(move |c| (c, r)))
            .filter_map(|(c, r)| {
                let v = dem.values[r * dem.width + c];
                let noise = if f == 1 {
                    0.0
                } else {
                    ((r * dem.width + c) * 7919 % 13) as f64 * 0.37
                };
                (!v.is_nan() && Some(v) != dem.nodata).then_some([c as f64, r as f64, v + noise])
            })
            .collect();
        let n = lattice_samples.len();
        let tols = default_tolerances(tol, levels as i32).unwrap();
        let lat = dem.lattice();
        for between_samples in [false, true] {
            let lattice_samples = lattice_samples.clone();
            let (peak, tin) = peak_of(|| {
                build_lattice(
                    lattice_samples,
                    &lat,
                    &tols,
                    32616,
                    BuildOptions {
                        keep_border: false,
                        between_samples,
                    },
                    &mut || Ok(()),
                )
                .unwrap()
            });
            let peak = peak + n * 24;
            let est = tinmerge_core::tin::build::lattice_build_bytes(n, levels, between_samples);
            let verts = tin.verts.len();
            let what = if between_samples {
                "lattice, between samples"
            } else {
                "build on the lattice"
            };
            row(
                what,
                format!("{n} samples, {verts} verts, {levels} lv"),
                peak,
                est,
            );
            if between_samples {
                // a typical estimate: the DEM at its own 90 m is rougher
                // than typical, and the running check stops what passes
                typical(what, peak, est);
            } else {
                upper_bound(what, peak, est);
            }
        }
        // tin_from_raster's default over the valid pixels only: their
        // centres in world coordinates inside the valid cells' outline,
        // the raster's heights held between the samples (the heights are
        // part of the request, as the samples are)
        let (w, h) = (dem.width, dem.height);
        let (peak, tin) = valid_pixels_build(lattice_samples, w, h, &lat, &tols);
        let peak = peak + n * 24 + w * h * 8;
        let est = tinmerge_core::tin::build::domain_raster_build_bytes(n, w * h, levels);
        let verts = tin.verts.len();
        row(
            "valid pixels, between samples",
            format!("{n} samples, {verts} verts, {levels} lv"),
            peak,
            est,
        );
        typical("valid pixels, between samples", peak, est);
    }

    // decoding a stored value
    let stored = layout::encode(&tins[0]);
    let (peak, decoded) = peak_of(|| layout::decode(&stored).unwrap());
    let est = layout::decode_bytes_of(&stored);
    row("decode", format!("{} bytes", stored.len()), peak, est);
    upper_bound("decode", peak, est);
    drop(decoded);

    // reading a raster band
    for f in [1usize, 4] {
        let (gt, w, h, v) = dem.upsampled(f);
        let wkb = wkb_raster(&gt, w, h, &v);
        drop(v);
        let (peak, r) = peak_of(|| raster::read(&wkb, Some(1)).unwrap());
        assert_eq!(r.width * r.height, w * h);
        let est = raster::raster_bytes(w, h);
        row("raster band", format!("{w} x {h} px"), peak, est);
        upper_bound("raster", peak, est);
    }

    // overlay: the estimate is the least it can need
    let dem_s = dem.samples();
    let other = build(
        dem_s.iter().map(|p| [p[0], p[1], p[2] + 0.5]).collect(),
        &default_tolerances(3.0, 5).unwrap(),
        32616,
        &mut || Ok(()),
    )
    .unwrap();
    for l in [1usize, 2] {
        let (na, nb) = (tins[0].levels[l].tris.len(), other.levels[l].tris.len());
        let (peak, o) = peak_of(|| overlay(&tins[0], l, &other, l, &mut || Ok(())).unwrap());
        let est = tinmerge_core::merge::overlay::overlay_bytes(na, nb);
        row(
            "overlay (estimate = least)",
            format!("{na} + {nb} tris"),
            peak,
            est,
        );
        assert!(!o.tris.is_empty());
        assert!(
            est <= peak,
            "overlay: least estimate {est} above the peak {peak}"
        );
    }
}
