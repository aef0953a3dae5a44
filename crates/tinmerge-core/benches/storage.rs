//! Storage benchmark (not a test): sizes of formats 3 and 4, encode and
//! whole-decode times on 1 and 2 threads, and cold sliced reads (a point,
//! a 2 km line and a 1 km square read from a fresh reader: groups and
//! bytes fetched, time including their checks and decoding) against the
//! same queries on a warm reader. Medians; `cargo bench --bench storage`.
//! Both bundled DEMs, built on their pixel lattice as `tin_from_raster`
//! does, so vertices are stored as lattice indices.
#[path = "../tests/common/mod.rs"]
mod common;

use std::cell::Cell;
use std::hint::black_box;
use std::time::Instant;
use tinmerge_core::merge::area::polygon::Area;
use tinmerge_core::merge::area::surface::stats;
use tinmerge_core::merge::area::{Method, sweep};
use tinmerge_core::merge::line::{Part, pieces_in};
use tinmerge_core::merge::point::height_in;
use tinmerge_core::tin::build::{BuildOptions, build_lattice, default_tolerances};
use tinmerge_core::tin::lattice::Lattice;
use tinmerge_core::tin::layout::{self, HEADER_LEN};
use tinmerge_core::tin::sliced::SlicedTin;
use tinmerge_core::tin::{Tin, TinError, par};

/// TOAST chunk of 8 KB pages: what `pg_detoast_datum_slice` reads.
const TOAST_CHUNK: u64 = 1996;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Median ms of `f` over `runs` runs.
fn ms(runs: usize, mut f: impl FnMut()) -> f64 {
    median(
        (0..runs)
            .map(|_| {
                let t0 = Instant::now();
                f();
                t0.elapsed().as_secs_f64() * 1e3
            })
            .collect(),
    )
}

/// A DEM built as `tin_from_raster(rast, tol, levels)` builds it.
fn raster_tin(name: &str, tol: f64, levels: usize) -> (Tin, Lattice) {
    let d = common::read_dem(name);
    let lat = d.lattice();
    let mut pts = Vec::new();
    for r in 0..d.height {
        for c in 0..d.width {
            let v = d.values[r * d.width + c];
            if !(v.is_nan() || Some(v) == d.nodata) {
                pts.push([c as f64, r as f64, v]);
            }
        }
    }
    let srid = if name.contains("utm") { 32616 } else { 4326 };
    let tin = build_lattice(
        pts,
        &lat,
        &default_tolerances(tol, levels as i32).unwrap(),
        srid,
        BuildOptions::default(),
        &mut || Ok(()),
    )
    .unwrap();
    (tin, lat)
}

/// One query on a reader: what it reads.
enum Query {
    Point([f64; 2]),
    Line(Vec<Part>),
    Square(Area),
}

fn run(q: &Query, r: &tinmerge_core::tin::sliced::Reader<'_>, level: usize) {
    match q {
        Query::Point(p) => {
            black_box(height_in(r, level, p[0], p[1]).unwrap());
        }
        Query::Line(parts) => {
            black_box(pieces_in(r, level, parts, &mut || Ok(())).unwrap().len());
        }
        Query::Square(a) => {
            let sw = sweep(r, level, a, Method::Flat, &mut || Ok(())).unwrap();
            black_box(stats(r, a, &sw, &mut || Ok(())).unwrap());
        }
    }
}

/// Per kind of group: how many, mean coded and packed bytes, and mean
/// microseconds to check, unpack (zstd) and decode one.
fn group_costs(v4: &[u8]) {
    use tinmerge_core::tin::compact::{self, Stream};
    let h = layout::read_header(v4).unwrap();
    let plan = layout::plan(&h);
    let ranges = layout::group_ranges(v4, &plan).unwrap();
    let hh = layout::stored_header_hash(v4);
    let mut rows: std::collections::BTreeMap<&str, [f64; 6]> = Default::default();
    for (s, first, n, k) in plan.groups() {
        let kind = match s {
            Stream::Verts => "vertices",
            Stream::Tris(_) => "triangles",
            Stream::Nbrs(_) => "neighbours",
            Stream::Parents(_) => "parents",
            Stream::Cells(_) => "cells",
        };
        let raw = &v4[ranges[k as usize].clone()];
        let t0 = Instant::now();
        let packed = layout::check_group(hh, k, raw).unwrap();
        let t1 = Instant::now();
        let coded = compact::unpack(packed, compact::max_coded(s, n)).unwrap();
        let t2 = Instant::now();
        black_box(
            compact::decode_group(packed, s, first, n, h.vertex_coding, h.lattice.as_ref())
                .unwrap(),
        );
        let t3 = Instant::now();
        let r = rows.entry(kind).or_default();
        r[0] += 1.0;
        r[1] += coded.len() as f64;
        r[2] += packed.len() as f64;
        r[3] += (t1 - t0).as_secs_f64() * 1e6;
        r[4] += (t2 - t1).as_secs_f64() * 1e6;
        r[5] += (t3 - t2).as_secs_f64() * 1e6 - (t2 - t1).as_secs_f64() * 1e6;
    }
    println!();
    println!(
        "| group kind | groups | mean coded bytes | mean packed bytes | check us | unpack us | decode us (after unpack) |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|");
    for (kind, r) in rows {
        let n = r[0];
        println!(
            "| {kind} | {n} | {:.0} | {:.0} | {:.1} | {:.1} | {:.1} |",
            r[1] / n,
            r[2] / n,
            r[3] / n,
            r[4] / n,
            r[5] / n
        );
    }
}

fn main() {
    println!("threads available: {}", par::cores());
    let terrains = [
        (
            "UTM DEM, tolerance 2 m, 5 levels",
            "jacksboro_fault_dem_utm16n.tif",
            2.0,
        ),
        (
            "geographic DEM, tolerance 2 m, 5 levels",
            "jacksboro_fault_dem.tif",
            2.0,
        ),
    ];
    println!();
    println!(
        "| terrain | finest triangles | format 3 bytes | format 4 bytes | format 4 bytes per finest triangle | encode 3 ms | encode 4 ms (1 thread) | decode 3 ms | decode 4 ms, 1 thread | decode 4 ms, 2 threads |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    let mut cold_rows = Vec::new();
    for (label, file, tol) in terrains {
        let (tin, lat) = raster_tin(file, tol, 5);
        let finest = tin.levels.last().map_or(0, |l| l.tris.len());
        par::set_threads(1);
        let v3 = layout::encode_v3(&tin);
        let v4 = layout::encode_on(&tin, Some(&lat));
        let e3 = ms(5, || {
            black_box(layout::encode_v3(&tin));
        });
        let e4 = ms(5, || {
            black_box(layout::encode_on(&tin, Some(&lat)));
        });
        let d3 = ms(7, || {
            black_box(layout::decode(&v3).unwrap());
        });
        let d4 = ms(7, || {
            black_box(layout::decode(&v4).unwrap());
        });
        par::set_threads(2);
        let d4_2 = ms(7, || {
            black_box(layout::decode(&v4).unwrap());
        });
        par::set_threads(1);
        assert_eq!(layout::decode(&v4).unwrap(), tin);
        println!(
            "| {label} | {finest} | {} | {} | {:.1} | {e3:.1} | {e4:.1} | {d3:.1} | {d4:.1} | {d4_2:.1} |",
            v3.len(),
            v4.len(),
            v4.len() as f64 / finest as f64
        );
        if !file.contains("utm") {
            continue;
        }
        group_costs(&v4);
        // the queries of scripts/bench-cold.sh
        let level = tin.levels.len() - 1;
        let queries = [
            ("point", Query::Point([758000.3, 4052000.7])),
            (
                "2 km line",
                Query::Line(vec![Part::new(vec![
                    [757000.0, 4052000.0],
                    [759000.0, 4052100.0],
                ])]),
            ),
            (
                "1 km square",
                Query::Square(Area::new(vec![vec![vec![
                    [757500.0, 4051500.0],
                    [758500.0, 4051500.0],
                    [758500.0, 4052500.0],
                    [757500.0, 4052500.0],
                ]]])),
            ),
        ];
        let configs = [
            ("format 3", &v3, 0, 0),
            ("format 4", &v4, 0, 0),
            ("format 3", &v3, TOAST_CHUNK, 0),
            ("format 4", &v4, TOAST_CHUNK, 0),
            ("format 4", &v4, TOAST_CHUNK, 1),
            ("format 4", &v4, TOAST_CHUNK, 3),
            ("format 4", &v4, TOAST_CHUNK, 7),
        ];
        for (fmt, stored, unit, ahead) in configs {
            for (qname, q) in &queries {
                let fetches = Cell::new(0usize);
                let bytes = Cell::new(0usize);
                let mut groups = 0;
                let cold = ms(15, || {
                    fetches.set(0);
                    bytes.set(0);
                    let s = SlicedTin::new(&stored[..HEADER_LEN])
                        .unwrap()
                        .unwrap()
                        .with_units(unit, ahead);
                    let mut fetch = |at: u64, len: usize| -> Result<Vec<u8>, TinError> {
                        fetches.set(fetches.get() + 1);
                        bytes.set(bytes.get() + len);
                        Ok(stored[at as usize..at as usize + len].to_vec())
                    };
                    let r = s.reader(&mut fetch);
                    run(q, &r, level);
                    groups = s.blocks().0;
                });
                let s = SlicedTin::new(&stored[..HEADER_LEN]).unwrap().unwrap();
                let mut fetch = |at: u64, len: usize| -> Result<Vec<u8>, TinError> {
                    Ok(stored[at as usize..at as usize + len].to_vec())
                };
                let r = s.reader(&mut fetch);
                run(q, &r, level);
                let warm = ms(15, || run(q, &r, level));
                cold_rows.push(format!(
                    "| {fmt} | {} | {qname} | {groups} | {} | {} | {cold:.3} | {warm:.3} |",
                    if unit == 0 {
                        "exact".to_string()
                    } else {
                        format!("{unit} B units, {ahead} ahead")
                    },
                    fetches.get(),
                    bytes.get()
                ));
            }
        }
    }
    println!();
    println!(
        "UTM DEM, finest level, in memory (no TOAST): a fresh reader (cold) and the same reader again (warm)"
    );
    println!(
        "| format | reads | query | groups held | fetches | bytes fetched | cold ms | warm ms |"
    );
    println!("|---|---|---|---:|---:|---:|---:|---:|");
    for r in cold_rows {
        println!("{r}");
    }
}
