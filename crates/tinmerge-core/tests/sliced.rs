//! A stored value read in slices answers exactly as the decoded value does,
//! reads a small part of it, and reports a damaged block instead of
//! answering from it. Both bundled DEMs (UTM and geographic), every level,
//! points inside, outside, on vertices and on edges.
mod common;

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use std::cell::Cell;
use tinmerge_core::merge::point::{height, height_in};
use tinmerge_core::tin::build::{build, default_tolerances};
use tinmerge_core::tin::layout::{self, HEADER_LEN};
use tinmerge_core::tin::locate::{locate, locate_in};
use tinmerge_core::tin::sliced::SlicedTin;
use tinmerge_core::tin::{Tin, TinError};

fn tins() -> Vec<(&'static str, Tin)> {
    let geo = common::read_dem("jacksboro_fault_dem.tif");
    let geo_tin = build(
        geo.samples(),
        &default_tolerances(0.00002, 4).unwrap(),
        4326,
        &mut || Ok(()),
    )
    .unwrap();
    vec![("utm", common::dem_tin()), ("geographic", geo_tin)]
}

/// Points: random in and around the box, every vertex of some triangles,
/// midpoints of their edges.
fn points(t: &Tin, r: &mut StdRng) -> Vec<[f64; 2]> {
    let b = t.bbox;
    let (w, h) = (b.max_x - b.min_x, b.max_y - b.min_y);
    let mut out: Vec<[f64; 2]> = (0..400)
        .map(|_| {
            [
                b.min_x - 0.05 * w + r.random::<f64>() * 1.1 * w,
                b.min_y - 0.05 * h + r.random::<f64>() * 1.1 * h,
            ]
        })
        .collect();
    let lv = t.levels.last().unwrap();
    for _ in 0..100 {
        let c = t.corners(t.levels.len() - 1, r.random_range(0..lv.tris.len()) as u32);
        out.push([c[0][0], c[0][1]]);
        out.push([(c[0][0] + c[1][0]) / 2.0, (c[0][1] + c[1][1]) / 2.0]);
    }
    out
}

#[test]
fn sliced_reads_answer_as_the_decoded_value() {
    let mut r = StdRng::seed_from_u64(0x511ce);
    for (name, tin) in tins() {
        let stored = layout::encode(&tin);
        let s = SlicedTin::new(&stored[..HEADER_LEN]).unwrap().unwrap();
        let fetched = Cell::new(0usize);
        let mut fetch = |at: u64, len: usize| -> Result<Vec<u8>, TinError> {
            fetched.set(fetched.get() + len);
            Ok(stored[at as usize..at as usize + len].to_vec())
        };
        let reader = s.reader(&mut fetch);
        let pts = points(&tin, &mut r);
        // the first point, finest level: a few blocks of a large value
        let fin = tin.levels.len() - 1;
        let c = tin.bbox;
        let mid = [(c.min_x + c.max_x) / 2.0, (c.min_y + c.max_y) / 2.0];
        assert_eq!(
            height_in(&reader, fin, mid[0], mid[1]).unwrap(),
            height(&tin, fin, mid[0], mid[1])
        );
        let first = fetched.get();
        eprintln!(
            "{name}: value {} bytes, first point at the finest level read {first} bytes",
            stored.len()
        );
        assert!(
            first * 50 < stored.len(),
            "{name}: read {first} of {}",
            stored.len()
        );
        for l in 0..tin.levels.len() {
            for p in &pts {
                let want_t = locate(&tin, l, p[0], p[1]);
                assert_eq!(
                    locate_in(&reader, l, p[0], p[1]).unwrap(),
                    want_t,
                    "{name} level {l} {p:?}"
                );
                let want_z = height(&tin, l, p[0], p[1]);
                let got_z = height_in(&reader, l, p[0], p[1]).unwrap();
                assert_eq!(
                    got_z.map(f64::to_bits),
                    want_z.map(f64::to_bits),
                    "{name} level {l} {p:?}"
                );
            }
        }
        let (held, total) = s.blocks();
        eprintln!(
            "{name}: {} points x {} levels read {held} of {total} blocks ({} bytes held)",
            pts.len(),
            tin.levels.len(),
            s.cached_bytes()
        );
    }
}

#[test]
fn a_damaged_block_is_an_error_never_an_answer() {
    let tin = common::dem_tin();
    let stored = layout::encode(&tin);
    let nblocks = (stored.len() - HEADER_LEN).div_ceil(layout::BLOCK_LEN);
    let mut r = StdRng::seed_from_u64(7);
    let pts = points(&tin, &mut r);
    let (mut errors, mut answers) = (0, 0);
    for k in (0..nblocks).step_by(nblocks / 40 + 1) {
        let mut bad = stored.clone();
        let at = HEADER_LEN + k * layout::BLOCK_LEN + 100;
        bad[at] ^= 0x40;
        let s = SlicedTin::new(&bad[..HEADER_LEN]).unwrap().unwrap();
        for l in 0..tin.levels.len() {
            for p in pts.iter().take(60) {
                let mut fetch = |at: u64, len: usize| -> Result<Vec<u8>, TinError> {
                    Ok(bad[at as usize..at as usize + len].to_vec())
                };
                let reader = s.reader(&mut fetch);
                match height_in(&reader, l, p[0], p[1]) {
                    Ok(z) => {
                        answers += 1;
                        let want = height(&tin, l, p[0], p[1]);
                        assert_eq!(z.map(f64::to_bits), want.map(f64::to_bits));
                    }
                    Err(TinError::Corrupt(m)) => {
                        errors += 1;
                        assert!(m.contains(&format!("block {k}")), "{m}");
                    }
                    Err(e) => panic!("{e}"),
                }
            }
        }
    }
    eprintln!("damaged blocks: {errors} errors, {answers} right answers, no wrong one");
    assert!(errors > 0 && answers > 0);
}

#[test]
fn format_1_is_not_read_in_slices() {
    let tin = common::dem_tin();
    let v1 = layout::encode_v1(&tin);
    assert!(SlicedTin::new(&v1[..HEADER_LEN]).unwrap().is_none());
    // a damaged header is an error before any block is read
    let mut v3 = layout::encode(&tin);
    v3[60] ^= 1;
    assert!(matches!(
        SlicedTin::new(&v3[..HEADER_LEN]),
        Err(TinError::Corrupt(_))
    ));
}
