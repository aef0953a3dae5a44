//! Values stored by format version 1 stay readable: fixtures written once by
//! the version-1 writer (`tests/data/format-v1/`, made by the ignored
//! `write_fixtures`) must decode and validate, hold what they were built
//! from (every vertex of the tin is a sample of the DEM window it was built
//! from, read independently with the `tiff` crate; the linetree holds the
//! fixture line's points), and be written back byte for byte: a change of
//! the stored format must come with a new format version and keep reading
//! these.

use crate::common;

use common::{data_path, read_dem};
use tinmerge_core::merge::line::tree;
use tinmerge_core::tin::build::{build, default_tolerances};
use tinmerge_core::tin::layout;

const ROWS: std::ops::Range<usize> = 100..124;
const COLS: std::ops::Range<usize> = 200..224;
const LINE: [[f64; 2]; 4] = [
    [741000.0, 4061000.0],
    [742500.5, 4060200.25],
    [743100.0, 4062000.0],
    [741000.0, 4061000.0],
];

fn window_samples() -> Vec<[f64; 3]> {
    let dem = read_dem("jacksboro_fault_dem_utm16n.tif");
    let mut out = Vec::new();
    for r in ROWS {
        for c in COLS {
            let v = dem.values[r * dem.width + c];
            if v.is_nan() || Some(v) == dem.nodata {
                continue;
            }
            let (x, y) = dem.centre(c, r);
            out.push([x, y, v]);
        }
    }
    out
}

fn fixture(name: &str) -> String {
    data_path(&format!("format-v1/{name}"))
}

#[test]
fn tin_stored_by_format_1_still_reads() {
    let stored = std::fs::read(fixture("window.tin")).expect("fixture");
    let h = layout::read_header(&stored).unwrap();
    assert_eq!(h.num_levels(), 3);
    let tin = layout::decode(&stored).unwrap();
    tin.sanity_check().unwrap();
    assert_eq!(tin.srid, 32616);
    let samples = window_samples();
    let mut keys: Vec<(u64, u64, u64)> = samples
        .iter()
        .map(|p| (p[0].to_bits(), p[1].to_bits(), p[2].to_bits()))
        .collect();
    keys.sort_unstable();
    for v in &tin.verts {
        let k = (v[0].to_bits(), v[1].to_bits(), v[2].to_bits());
        assert!(
            keys.binary_search(&k).is_ok(),
            "vertex {v:?} is not a sample of the window"
        );
    }
    assert_eq!(
        layout::encode_v1(&tin),
        stored,
        "the writer no longer writes format 1 as it did"
    );
    // the same tin in format 3 (blocked, every block checksummed) and in
    // the current format (compact groups): each decodes to the same value
    let v3 = layout::encode_v3(&tin);
    assert_eq!(layout::read_header(&v3).unwrap().version, layout::VERSION_3);
    assert_eq!(layout::decode(&v3).unwrap(), tin);
    let v4 = layout::encode(&tin);
    assert_eq!(layout::read_header(&v4).unwrap().version, layout::VERSION);
    assert_eq!(layout::decode(&v4).unwrap(), tin);
    assert!(v4.len() * 3 < v3.len(), "{} vs {}", v4.len(), v3.len());
}

#[test]
fn linetree_stored_by_format_1_still_reads() {
    let stored = std::fs::read(fixture("line.linetree")).expect("fixture");
    let v = tree::View::new(&stored).unwrap();
    v.validate().unwrap();
    assert_eq!(v.header.srid, 32616);
    assert_eq!(v.header.num_points as usize, LINE.len());
    for (i, p) in LINE.iter().enumerate() {
        let q = v.point(i as u32).unwrap();
        assert_eq!((q[0], q[1]), (p[0], p[1]));
    }
    let again = tree::encode(32616, &[LINE.to_vec()]).unwrap();
    assert_eq!(
        again, stored,
        "the writer no longer writes format 1 as it did"
    );
}

/// Writes the format-1 fixtures where they are missing, by the format-1
/// writers (`layout::encode_v1`; the linetree's format is still 1), never
/// over the stored ones: `cargo test --release --test core format:: -- --ignored`.
/// (It wrote the current tin format into `format-v1/` before.)
#[test]
#[ignore]
fn write_fixtures() {
    let tin = build(
        window_samples(),
        &default_tolerances(1.0, 3).unwrap(),
        32616,
        &mut || Ok(()),
    )
    .unwrap();
    let write_new = |name: &str, bytes: Vec<u8>| {
        let path = fixture(name);
        if std::path::Path::new(&path).exists() {
            eprintln!("{path} is there: left as it is");
        } else {
            std::fs::write(path, bytes).unwrap();
        }
    };
    write_new("window.tin", layout::encode_v1(&tin));
    write_new(
        "line.linetree",
        tree::encode(32616, &[LINE.to_vec()]).unwrap(),
    );
}
