//! Fuzz smoke run (a property-test stand-in for `cargo fuzz`, runnable in
//! CI in well under a minute): every decoder of bytes from disk or the
//! wire gets mutated valid values, and every merge gets random (often
//! nonsensical) geometry. The property is the same everywhere: an `Ok` or
//! an `Err`, never a panic, and a value that decodes is safe to use.
//!
//! Seeded, so a failure reproduces. `TINMERGE_FUZZ_ITERS` (default 4000
//! per target) sets the length of a run; `TINMERGE_FUZZ_SEED` the seed.
//! A long run: `TINMERGE_FUZZ_ITERS=200000 cargo test --release --test core fuzz::`.
use crate::common;

use rand::rngs::StdRng;
use rand::{Rng as _, SeedableRng};
use std::panic::{AssertUnwindSafe, catch_unwind};
use tinmerge_core::io::ewkb::{self, Geom};
use tinmerge_core::io::{gserialized, raster};
use tinmerge_core::merge::area::polygon::Area;
use tinmerge_core::merge::area::{Method, sweep};
use tinmerge_core::merge::line::drape;
use tinmerge_core::merge::line::tree::{self, View};
use tinmerge_core::merge::line::{self, Part};
use tinmerge_core::merge::overlay;
use tinmerge_core::tin::build::build;
use tinmerge_core::tin::{Tin, check_xy, layout, locate};

/// The mutation source: `rand`'s seeded `StdRng` (reproducible: the seed is
/// `TINMERGE_FUZZ_SEED`, default 0x5eed, mixed with a per-target salt).
struct Rng(StdRng);

impl Rng {
    fn new(salt: u64) -> Rng {
        let seed = std::env::var("TINMERGE_FUZZ_SEED")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(0x5eed_u64);
        Rng(StdRng::seed_from_u64(
            seed ^ salt.wrapping_mul(0x9e37_79b9_7f4a_7c15),
        ))
    }
    fn next(&mut self) -> u64 {
        self.0.random()
    }
    fn below(&mut self, n: usize) -> usize {
        self.0.random_range(0..n.max(1))
    }
    fn unit(&mut self) -> f64 {
        self.0.random()
    }
    /// A coordinate: mostly inside [lo, hi], sometimes far outside or not
    /// finite.
    fn coord(&mut self, lo: f64, hi: f64) -> f64 {
        match self.below(40) {
            0 => f64::NAN,
            1 => f64::INFINITY,
            2 => -1e300,
            3 => lo, // on the bbox edge
            4 => hi,
            _ => lo + (hi - lo) * (self.unit() * 1.2 - 0.1),
        }
    }
}

/// Panics that the code under test catches on purpose (the `wkb` crate's
/// unwraps on malformed values, turned into errors by `ewkb::read`) are
/// not printed; every other panic goes to the default hook.
fn quiet_expected_panics() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            let from_wkb = info.location().is_some_and(|l| l.file().contains("/wkb-"));
            if !from_wkb {
                default(info);
            }
        }));
    });
}

fn iters() -> usize {
    quiet_expected_panics();
    std::env::var("TINMERGE_FUZZ_ITERS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(4000)
}

/// One random change of a byte string: bit flips, special byte values,
/// 4- and 8-byte fields overwritten with boundary values (huge counts,
/// NaN, infinities), truncation, extension, a duplicated slice.
fn mutate(r: &mut Rng, b: &mut Vec<u8>) {
    for _ in 0..1 + r.below(3) {
        if b.is_empty() {
            b.push(r.next() as u8);
            continue;
        }
        let i = r.below(b.len());
        match r.below(8) {
            0 | 1 => b[i] ^= 1 << r.below(8),
            2 => b[i] = [0x00, 0xff, 0x7f, 0x80][r.below(4)],
            3 => {
                let v: [u8; 4] =
                    [0u32, u32::MAX, 0x7fff_ffff, 0x8000_0000, 1 << 20][r.below(5)].to_le_bytes();
                let n = 4.min(b.len() - i);
                b[i..i + n].copy_from_slice(&v[..n]);
            }
            4 => {
                let v = [f64::NAN, f64::INFINITY, -0.0, 1e308, -1e-310][r.below(5)].to_le_bytes();
                let n = 8.min(b.len() - i);
                b[i..i + n].copy_from_slice(&v[..n]);
            }
            5 => b.truncate(i),
            6 => {
                for _ in 0..1 + r.below(16) {
                    b.push(r.next() as u8);
                }
            }
            _ => {
                let j = (i + 1 + r.below(32)).min(b.len());
                let s = b[i..j].to_vec();
                b.splice(i..i, s);
            }
        }
    }
}

/// Runs `f` on `n` mutants of each of the `valid` values; a panic fails the
/// test with the seed and iteration to reproduce it. Returns (accepted,
/// rejected) counts.
fn run(
    name: &str,
    salt: u64,
    valid: &[Vec<u8>],
    n: usize,
    f: &mut dyn FnMut(&[u8]) -> bool,
) -> (usize, usize) {
    let mut r = Rng::new(salt);
    let (mut ok, mut err) = (0, 0);
    for it in 0..n {
        let mut m = valid[it % valid.len()].clone();
        mutate(&mut r, &mut m);
        match catch_unwind(AssertUnwindSafe(|| f(&m))) {
            Ok(true) => ok += 1,
            Ok(false) => err += 1,
            Err(_) => panic!("{name}: panic on mutant {it} (salt {salt}): {m:02x?}"),
        }
    }
    eprintln!("{name}: {n} mutants, {ok} accepted, {err} rejected");
    // a target that accepts everything or rejects everything tests nothing:
    // its mutations never reach the checks, or never get past them
    assert!(
        ok > 0 && err > 0,
        "{name}: {ok} of {n} mutants accepted and {err} rejected; both must happen"
    );
    (ok, err)
}

/// A small real TIN (a window of the DEM, 3 levels).
fn small_tin() -> Tin {
    let d = common::read_dem("jacksboro_fault_dem_utm16n.tif");
    let all = d.samples();
    let (x0, y0) = (all[0][0], all[0][1]);
    // a 40 x 40 pixel window starting at the first valid sample
    let (sx, sy) = (d.scale_x.abs() * 40.0, d.scale_y.abs() * 40.0);
    let samples: Vec<[f64; 3]> = all
        .into_iter()
        .filter(|p| (p[0] - x0).abs() <= sx && (p[1] - y0).abs() <= sy)
        .collect();
    build(samples, &[8.0, 4.0, 2.0], 32616, &mut || Ok(())).unwrap()
}

fn random_line(r: &mut Rng, t: &Tin) -> Vec<[f64; 2]> {
    let b = &t.bbox;
    (0..1 + r.below(8))
        .map(|_| [r.coord(b.min_x, b.max_x), r.coord(b.min_y, b.max_y)])
        .collect()
}

#[test]
fn tin_values() {
    let t = small_tin();
    let valid = vec![layout::encode(&t), layout::encode_v3(&t)];
    let (ok, err) = run("tin", 1, &valid, iters(), &mut |m| {
        // mutants with a recomputed hash reach the structural checks
        let mut m = m.to_vec();
        if m.len() >= 40 && m[m.len() / 2] & 1 == 0 {
            layout::reseal(&mut m);
        }
        // read in slices: an error or an answer, never a panic
        if m.len() >= layout::HEADER_LEN
            && let Ok(Some(s)) =
                tinmerge_core::tin::sliced::SlicedTin::new(&m[..layout::HEADER_LEN])
        {
            let mut fetch = |at: u64, len: usize| {
                m.get(at as usize..at as usize + len)
                    .map(|b| b.to_vec())
                    .ok_or_else(|| tinmerge_core::tin::TinError::Corrupt("past the end".into()))
            };
            let reader = s.reader(&mut fetch);
            let b = t.bbox;
            for l in 0..t.levels.len() {
                for k in 0..4 {
                    let f = k as f64 / 3.0;
                    let _ = tinmerge_core::merge::point::height_in(
                        &reader,
                        l,
                        b.min_x + f * (b.max_x - b.min_x),
                        b.min_y + (1.0 - f) * (b.max_y - b.min_y),
                    );
                }
            }
        }
        match layout::decode(&m) {
            Ok(t) => {
                for l in 0..t.levels.len() {
                    let _ = locate::locate(&t, l, t.bbox.min_x + 55.0, t.bbox.min_y + 77.0);
                }
                true
            }
            Err(_) => false,
        }
    });
    assert!(err > ok, "most mutants must be rejected");
}

#[test]
fn linetree_values() {
    let t = small_tin();
    let mut r = Rng::new(2);
    let valid: Vec<Vec<u8>> = (0..8)
        .map(|_| {
            let parts: Vec<Vec<[f64; 2]>> = (0..1 + r.below(3))
                .map(|_| {
                    let mut l = random_line(&mut r, &t);
                    for p in &mut l {
                        if check_xy("", p[0], p[1]).is_err() {
                            *p = [t.bbox.min_x, t.bbox.min_y];
                        }
                    }
                    if l.len() < 2 {
                        l.push([t.bbox.max_x, t.bbox.max_y]);
                    }
                    l
                })
                .collect();
            tree::encode(32616, &parts).unwrap()
        })
        .collect();
    run("linetree", 3, &valid, iters(), &mut |m| {
        let mut m = m.to_vec();
        if r.below(2) == 0 {
            tree::rehash(&mut m);
        }
        let Ok(v) = View::new(&m) else { return false };
        if v.validate().is_err() {
            return false;
        }
        // a tree that validates is walked through the tin
        let mut sink = line::TriangleSink::default();
        let _ = tree::walk_tree(&t, 1, &v, &mut sink, &mut |_, _| {}, &mut || Ok(()));
        true
    });
}

#[test]
fn ewkb_values_and_drape() {
    let t = small_tin();
    let b = &t.bbox;
    let c = |x: f64, y: f64| {
        [
            b.min_x + x * (b.max_x - b.min_x),
            b.min_y + y * (b.max_y - b.min_y),
            1.0,
        ]
    };
    let ring = vec![c(0.1, 0.1), c(0.9, 0.2), c(0.5, 0.9), c(0.1, 0.1)];
    let geoms = [
        Geom::Point(Some(c(0.5, 0.5))),
        Geom::Point(None),
        Geom::LineString(vec![c(-0.1, 0.3), c(1.1, 0.6)]),
        Geom::Polygon(vec![ring.clone()]),
        Geom::MultiPoint(vec![c(0.2, 0.2), c(0.8, 0.8)]),
        Geom::MultiLineString(vec![vec![c(0.0, 0.0), c(1.0, 1.0)], vec![]]),
        Geom::MultiPolygon(vec![vec![ring.clone()], vec![]]),
        Geom::Collection(vec![
            Geom::Point(Some(c(0.3, 0.3))),
            Geom::Polygon(vec![ring]),
        ]),
    ];
    let valid: Vec<Vec<u8>> = geoms
        .iter()
        .flat_map(|g| {
            [
                ewkb::Writer::write(32616, true, g),
                ewkb::Writer::write(0, false, g),
            ]
        })
        .collect();
    run("ewkb", 4, &valid, iters(), &mut |m| match ewkb::read(m) {
        Ok(e) => {
            for l in 0..t.levels.len() {
                let _ = drape::drape(&t, l, &e.geom);
            }
            true
        }
        Err(_) => false,
    });
    // the same geometries in PostGIS's own serialisation (tin_drape reads
    // and writes it): every accepted mutant drapes and writes back
    let valid: Vec<Vec<u8>> = geoms
        .iter()
        .flat_map(|g| {
            [
                gserialized::write(32616, true, g),
                gserialized::write(0, false, g),
            ]
        })
        .collect();
    run(
        "gserialized-read",
        6,
        &valid,
        iters(),
        &mut |m| match gserialized::read(m) {
            Ok(e) => {
                for l in 0..t.levels.len() {
                    if let Ok(Some(d)) = drape::drape(&t, l, &e.geom) {
                        let _ = gserialized::write(e.srid, true, &d);
                    }
                }
                true
            }
            Err(_) => false,
        },
    );
}

#[test]
fn gserialized_headers() {
    let point = |srid: u32, z: bool| {
        let s = srid & 0x1f_ffff;
        let mut b = vec![(s >> 16) as u8, (s >> 8) as u8, s as u8, 0x40 | z as u8];
        b.extend_from_slice(&1u32.to_ne_bytes());
        b.extend_from_slice(&1u32.to_ne_bytes());
        for v in [740000.5f64, 4060000.25, 7.0] {
            b.extend_from_slice(&v.to_ne_bytes());
        }
        b
    };
    let valid = vec![point(32616, true), point(0, false), point(4326, false)];
    run("gserialized", 5, &valid, iters(), &mut |m| {
        gserialized::peek(m).is_ok()
    });
}

#[test]
fn raster_values() {
    // 3 x 2 little-endian rasters of several pixel types with nodata
    let make = |pt: u8, size: usize| {
        let mut b = vec![1u8];
        b.extend_from_slice(&0u16.to_le_bytes());
        b.extend_from_slice(&1u16.to_le_bytes());
        for v in [10.0f64, -10.0, 100.0, 200.0, 0.0, 0.0] {
            b.extend_from_slice(&v.to_le_bytes());
        }
        b.extend_from_slice(&32616i32.to_le_bytes());
        b.extend_from_slice(&3u16.to_le_bytes());
        b.extend_from_slice(&2u16.to_le_bytes());
        b.push(0x40 | pt);
        b.extend(std::iter::repeat_n(0u8, size)); // nodata 0
        for i in 0..6u8 {
            b.extend(std::iter::repeat_n(i, size));
        }
        b
    };
    let valid = vec![make(4, 1), make(5, 2), make(7, 4), make(10, 4), make(11, 8)];
    run(
        "raster",
        6,
        &valid,
        iters(),
        &mut |m| match raster::read(m, Some(1)) {
            Ok(r) => {
                let _ =
                    r.gt.centre(r.width.saturating_sub(1), r.height.saturating_sub(1));
                true
            }
            Err(_) => false,
        },
    );
}

#[test]
fn merges_on_random_geometry() {
    let t = small_tin();
    let mut r = Rng::new(7);
    let b = t.bbox;
    for it in 0..iters() / 10 {
        let level = r.below(t.levels.len());
        let parts: Vec<Part> = (0..1 + r.below(3))
            .map(|_| Part::new(random_line(&mut r, &t)))
            .collect();
        let polys: Vec<Vec<Vec<[f64; 2]>>> = (0..1 + r.below(2))
            .map(|_| {
                (0..1 + r.below(2))
                    .map(|_| {
                        let mut ring: Vec<[f64; 2]> = (0..r.below(7))
                            .map(|_| [r.coord(b.min_x, b.max_x), r.coord(b.min_y, b.max_y)])
                            .collect();
                        if let Some(&f) = ring.first() {
                            ring.push(f);
                        }
                        ring
                    })
                    .collect()
            })
            .collect();
        let res = catch_unwind(AssertUnwindSafe(|| {
            let _ = line::pieces(&t, level, &parts);
            let _ = line::triangles(&t, level, &parts);
            let area = Area::new(polys.clone());
            for m in [Method::Hierarchy, Method::Flat] {
                let _ = sweep(&t, level, &area, m, &mut || Ok(()));
            }
        }));
        assert!(
            res.is_ok(),
            "merge panic at iteration {it}: {parts:?} {polys:?}"
        );
    }
    // overlays of the tin with random small tins over it
    for it in 0..(iters() / 300).max(3) {
        let pts: Vec<[f64; 3]> = (0..3 + r.below(60))
            .map(|_| {
                [
                    b.min_x + (b.max_x - b.min_x) * (r.unit() * 1.4 - 0.2),
                    b.min_y + (b.max_y - b.min_y) * (r.unit() * 1.4 - 0.2),
                    r.unit() * 100.0,
                ]
            })
            .collect();
        let Ok(o) = build(pts, &[0.0], 32616, &mut || Ok(())) else {
            continue;
        };
        for (la, lb) in [(0, 0), (2, 0)] {
            let res = catch_unwind(AssertUnwindSafe(|| {
                overlay::overlay(&t, la, &o, lb, &mut || Ok(())).map(|x| x.tris.len())
            }));
            assert!(res.is_ok(), "overlay panic at iteration {it}");
        }
    }
}
