//! A stored value read in slices answers exactly as the decoded value does,
//! reads a small part of it, and reports a damaged block instead of
//! answering from it. Both bundled DEMs (UTM and geographic), every level,
//! points inside, outside, on vertices and on edges.
use crate::common;

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use std::cell::Cell;
use tinmerge_core::merge::point::{height, height_in};
use tinmerge_core::tin::layout::{self, HEADER_LEN};
use tinmerge_core::tin::locate::{locate, locate_in};
use tinmerge_core::tin::sliced::SlicedTin;
use tinmerge_core::tin::{Tin, TinError};

/// The value in the current format (4), read exactly and in whole TOAST
/// chunks with one read ahead (as the extension reads it), and in format 3
/// (0.5.0's), which is read in slices too: (name, bytes, read unit).
fn formats(tin: &Tin) -> Vec<(&'static str, Vec<u8>, u64)> {
    let v4 = layout::encode(tin);
    let sums = tinmerge_core::merge::area::whole::level_sums(tin, &mut || Ok(())).unwrap();
    vec![
        ("v4", v4.clone(), 0),
        ("v4 in 1,996-byte chunks", v4, 1996),
        (
            "v6 in 1,996-byte chunks",
            layout::encode_with_sums(tin, None, &sums),
            1996,
        ),
        ("v3", layout::encode_v3(tin), 0),
    ]
}

/// A reader of `stored` from its header, reading in units of `unit` bytes
/// (0: exactly what a group needs).
fn open(stored: &[u8], unit: u64) -> SlicedTin {
    SlicedTin::new(&stored[..HEADER_LEN])
        .unwrap()
        .unwrap()
        .with_units(unit, 1)
}

fn tins() -> Vec<(&'static str, Tin)> {
    vec![
        ("utm", common::dem_tin()),
        ("geographic", common::geo_tin(0.00002)),
    ]
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

/// A fetch from `stored` adding the bytes it reads to `fetched`.
fn counting_fetch<'a>(
    stored: &'a [u8],
    fetched: &'a Cell<usize>,
) -> impl FnMut(u64, usize) -> Result<Vec<u8>, TinError> + 'a {
    move |at, len| {
        fetched.set(fetched.get() + len);
        Ok(stored[at as usize..at as usize + len].to_vec())
    }
}

#[test]
fn sliced_reads_answer_as_the_decoded_value() {
    let mut r = StdRng::seed_from_u64(0x511ce);
    for (tname, tin) in tins() {
        for (fmt, stored, unit) in formats(&tin) {
            let name = format!("{tname} {fmt}");
            let s = open(&stored, unit);
            let fetched = Cell::new(0usize);
            let mut fetch = counting_fetch(&stored, &fetched);
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
                "{name}: {} points x {} levels read {held} of {total} groups ({} bytes held, {} fetched)",
                pts.len(),
                tin.levels.len(),
                s.cached_bytes(),
                fetched.get()
            );
        }
    }
}

/// Places to damage: (byte offset, what the error names) for about 40
/// groups of a format-4 or -6 value or blocks of a format-3 one.
fn damage_sites(stored: &[u8]) -> Vec<(usize, String)> {
    let h = layout::read_header(stored).unwrap();
    if h.version == layout::VERSION || h.version == layout::VERSION_6 {
        let ranges = layout::group_ranges(stored, &layout::plan(&h)).unwrap();
        let step = ranges.len() / 40 + 1;
        (0..ranges.len())
            .step_by(step)
            .map(|k| ((ranges[k].start + ranges[k].end) / 2, format!("group {k}")))
            .collect()
    } else {
        let hl = layout::HEADER_LEN_V3;
        let nblocks = (stored.len() - hl).div_ceil(layout::BLOCK_LEN);
        (0..nblocks)
            .step_by(nblocks / 40 + 1)
            .map(|k| (hl + k * layout::BLOCK_LEN + 100, format!("block {k}")))
            .collect()
    }
}

#[test]
fn a_damaged_block_is_an_error_never_an_answer() {
    let tin = common::dem_tin();
    let mut r = StdRng::seed_from_u64(7);
    let pts = points(&tin, &mut r);
    for (fmt, stored, unit) in formats(&tin) {
        let (mut errors, mut answers) = (0, 0);
        for (at, label) in damage_sites(&stored) {
            let mut bad = stored.clone();
            bad[at] ^= 0x40;
            let s = open(&bad, unit);
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
                            assert!(m.contains(&label), "{m}");
                        }
                        Err(e) => panic!("{e}"),
                    }
                }
            }
        }
        eprintln!(
            "{fmt}: damaged groups or blocks: {errors} errors, {answers} right answers, no wrong one"
        );
        assert!(errors > 0 && answers > 0);
    }
}

#[test]
fn format_1_is_not_read_in_slices() {
    let tin = common::dem_tin();
    let v1 = layout::encode_v1(&tin);
    assert!(SlicedTin::new(&v1[..HEADER_LEN]).unwrap().is_none());
    // a damaged header is an error before any block is read
    for (_, mut v, _) in formats(&tin) {
        v[60] ^= 1;
        assert!(matches!(
            SlicedTin::new(&v[..HEADER_LEN]),
            Err(TinError::Corrupt(_))
        ));
    }
}

#[test]
fn lines_read_in_slices_cut_as_on_the_decoded_value() {
    use tinmerge_core::merge::line::{Part, TriangleSink, pieces, pieces_in, walk_parts};
    let mut r = StdRng::seed_from_u64(0x11e5);
    for (tname, tin) in tins() {
        for (fmt, stored, unit) in formats(&tin) {
            let name = format!("{tname} {fmt}");
            let b = tin.bbox;
            let (w, h) = (b.max_x - b.min_x, b.max_y - b.min_y);
            // random polylines, some starting or ending outside the domain, and
            // one through vertices and along edges (grid-aligned steps from a
            // vertex)
            let mut lines: Vec<Vec<Part>> = (0..30)
                .map(|_| {
                    let n = 2 + r.random_range(0..6);
                    vec![Part::new(
                        (0..n)
                            .map(|_| {
                                [
                                    b.min_x - 0.05 * w + r.random::<f64>() * 1.1 * w,
                                    b.min_y - 0.05 * h + r.random::<f64>() * 1.1 * h,
                                ]
                            })
                            .collect(),
                    )]
                })
                .collect();
            let c = tin.corners(tin.levels.len() - 1, 17);
            lines.push(vec![Part::new(vec![
                [c[0][0], c[0][1]],
                [c[1][0], c[1][1]],
                [c[2][0], c[2][1]],
                [b.max_x + 1.0, c[2][1]],
            ])]);
            for l in 0..tin.levels.len() {
                for parts in &lines {
                    let s = open(&stored, unit);
                    let mut fetch = |at: u64, len: usize| -> Result<Vec<u8>, TinError> {
                        Ok(stored[at as usize..at as usize + len].to_vec())
                    };
                    let reader = s.reader(&mut fetch);
                    let got = pieces_in(&reader, l, parts, &mut || Ok(())).unwrap();
                    let want = pieces(&tin, l, parts).unwrap();
                    assert_eq!(got.len(), want.len(), "{name} level {l}");
                    for (a, b) in got.iter().zip(&want) {
                        assert_eq!(a.triangle, b.triangle);
                        let bits = |p: &Vec<[f64; 3]>| {
                            p.iter()
                                .flat_map(|c| c.map(f64::to_bits))
                                .collect::<Vec<_>>()
                        };
                        assert_eq!(bits(&a.points), bits(&b.points), "{name} level {l}");
                    }
                    let mut ts = TriangleSink::default();
                    walk_parts(&reader, l, parts, &mut ts, &mut |_, _| {}, &mut || Ok(())).unwrap();
                    let mut td = TriangleSink::default();
                    walk_parts(&tin, l, parts, &mut td, &mut |_, _| {}, &mut || Ok(())).unwrap();
                    assert_eq!(ts.tris, td.tris);
                }
            }
            // a 2 km line inside the UTM domain reads a small part of the value
            if tname == "utm" {
                let s = open(&stored, unit);
                let fetched = Cell::new(0usize);
                let mut fetch = counting_fetch(&stored, &fetched);
                let reader = s.reader(&mut fetch);
                let line = [Part::new(vec![
                    [757000.0, 4052000.0],
                    [759000.0, 4052100.0],
                ])];
                let n = pieces_in(&reader, tin.levels.len() - 1, &line, &mut || Ok(()))
                    .unwrap()
                    .len();
                eprintln!(
                    "{name}: 2 km line, finest level: {n} pieces, {} of {} bytes read",
                    fetched.get(),
                    stored.len()
                );
                assert!(n > 20 && fetched.get() * 10 < stored.len());
            }
        }
    }
}

#[test]
fn areas_read_in_slices_sweep_as_on_the_decoded_value() {
    use tinmerge_core::merge::area::polygon::Area;
    use tinmerge_core::merge::area::surface::{stats, volume};
    use tinmerge_core::merge::area::{Method, area_rows, sweep};
    let mut r = StdRng::seed_from_u64(0xa4ea);
    for (tname, tin) in tins() {
        for (fmt, stored, unit) in formats(&tin) {
            let name = format!("{tname} {fmt}");
            let b = tin.bbox;
            let (w, h) = (b.max_x - b.min_x, b.max_y - b.min_y);
            // star polygons with a hole, some crossing the domain's edge
            let polys: Vec<Area> = (0..8)
                .map(|i| {
                    let c = [
                        b.min_x + r.random::<f64>() * w,
                        b.min_y + r.random::<f64>() * h,
                    ];
                    let rad = (0.03 + 0.2 * r.random::<f64>()) * w.min(h);
                    let ring = |scale: f64, rev: bool, r: &mut StdRng| {
                        let n = 7 + (i % 5);
                        let mut pts: Vec<[f64; 2]> = (0..n)
                            .map(|k| {
                                let a = k as f64 / n as f64 * std::f64::consts::TAU;
                                let rr = scale * rad * (0.6 + 0.4 * r.random::<f64>());
                                [c[0] + rr * a.cos(), c[1] + rr * a.sin()]
                            })
                            .collect();
                        if rev {
                            pts.reverse();
                        }
                        pts
                    };
                    let outer = ring(1.0, false, &mut r);
                    let hole = ring(0.2, true, &mut r);
                    Area::new(vec![vec![outer, hole]])
                })
                .collect();
            for l in 0..tin.levels.len() {
                for (pi, a) in polys.iter().enumerate() {
                    let s = open(&stored, unit);
                    let mut fetch = |at: u64, len: usize| -> Result<Vec<u8>, TinError> {
                        Ok(stored[at as usize..at as usize + len].to_vec())
                    };
                    let reader = s.reader(&mut fetch);
                    let sw_s = sweep(&reader, l, a, Method::Hierarchy, &mut || Ok(())).unwrap();
                    let sw_d = sweep(&tin, l, a, Method::Hierarchy, &mut || Ok(())).unwrap();
                    assert_eq!(sw_s.inside, sw_d.inside, "{name} level {l} polygon {pi}");
                    assert_eq!(sw_s.boundary, sw_d.boundary);
                    for compact in [false, true] {
                        let rs = area_rows(&reader, a, &sw_s, compact, &mut || Ok(())).unwrap();
                        let rd = area_rows(&tin, a, &sw_d, compact, &mut || Ok(())).unwrap();
                        assert_eq!(rs, rd, "{name} level {l} polygon {pi} compact {compact}");
                    }
                    // statistics and volumes, bit-identical read in slices or
                    // decoded, over both sweeps (the extension runs the flat
                    // one for them)
                    let fs = sweep(&reader, l, a, Method::Flat, &mut || Ok(())).unwrap();
                    let fd = sweep(&tin, l, a, Method::Flat, &mut || Ok(())).unwrap();
                    assert_eq!(fs.inside, fd.inside, "{name} level {l} polygon {pi} flat");
                    assert_eq!(fs.boundary, sw_d.boundary);
                    for (ws, wd) in [(&sw_s, &sw_d), (&fs, &fd)] {
                        let ss = stats(&reader, a, ws, &mut || Ok(())).unwrap();
                        let sd = stats(&tin, a, wd, &mut || Ok(())).unwrap();
                        assert_eq!(format!("{ss:?}"), format!("{sd:?}"));
                        let vs = volume(&reader, a, ws, 500.0, &mut || Ok(())).unwrap();
                        let vd = volume(&tin, a, wd, 500.0, &mut || Ok(())).unwrap();
                        assert_eq!(vs.0.to_bits(), vd.0.to_bits());
                        assert_eq!(vs.1.to_bits(), vd.1.to_bits());
                    }
                }
            }
        }
    }
}

/// Rasters over parts of a terrain: the DEM's own grid shifted by whole
/// pixels over its south-west edge (centres on vertices and on the hull), a
/// window of odd pixels with a fractional origin in the middle, and one
/// half outside the domain across its north-east corner; values with
/// nodata and NaN holes.
fn rasters(
    tin: &Tin,
    dem: &common::Dem,
) -> Vec<(
    &'static str,
    tinmerge_core::io::raster::GeoTransform,
    usize,
    usize,
    Vec<f64>,
)> {
    use tinmerge_core::io::raster::GeoTransform;
    let b = tin.bbox;
    let (w, h) = (b.max_x - b.min_x, b.max_y - b.min_y);
    let values = |n: usize| -> Vec<f64> {
        (0..n)
            .map(|i| match i % 97 {
                5 => -9999.0,
                11 => f64::NAN,
                k => ((k * 31) % 23) as f64 * 0.5,
            })
            .collect()
    };
    let (sx, sy) = (dem.scale_x, dem.scale_y);
    let own = GeoTransform {
        scale_x: sx,
        scale_y: -sy,
        ip_x: dem.origin_x - 7.0 * sx,
        ip_y: dem.origin_y - (dem.height as f64 - 60.0) * sy,
        skew_x: 0.0,
        skew_y: 0.0,
    };
    let (ow, oh) = (70, 67);
    let odd = GeoTransform {
        scale_x: w / 173.3,
        scale_y: -h / 181.7,
        ip_x: b.min_x + 0.41 * w + 0.123,
        ip_y: b.min_y + 0.58 * h - 0.0457 * h,
        skew_x: 0.0,
        skew_y: 0.0,
    };
    let corner = GeoTransform {
        scale_x: w / 97.1,
        scale_y: -h / 89.9,
        ip_x: b.max_x - 0.1 * w,
        ip_y: b.max_y + 0.1 * h,
        skew_x: 0.0,
        skew_y: 0.0,
    };
    vec![
        (
            "the DEM's grid over its south-west edge",
            own,
            ow,
            oh,
            values(ow * oh),
        ),
        (
            "odd pixels, fractional origin, inside",
            odd,
            29,
            33,
            values(29 * 33),
        ),
        (
            "across the north-east corner",
            corner,
            19,
            21,
            values(19 * 21),
        ),
    ]
}

#[test]
fn rasters_read_in_slices_merge_as_on_the_decoded_value() {
    use tinmerge_core::merge::raster::patch::{Patch, RasterLevel, TinLevel};
    use tinmerge_core::merge::raster::stats::{paint, weighted_stats, zonal_stats};
    use tinmerge_core::merge::raster::{PixelGrid, sweep};
    let dems = [
        common::read_dem("jacksboro_fault_dem_utm16n.tif"),
        common::read_dem("jacksboro_fault_dem.tif"),
    ];
    let mut none = || Ok(());
    for ((tname, tin), dem) in tins().into_iter().zip(&dems) {
        let stored = layout::encode(&tin);
        for (rname, gt, w, h, vals) in rasters(&tin, dem) {
            let g = PixelGrid::new(&gt, w, h).unwrap();
            let window = [
                gt.ip_x - gt.scale_x,
                gt.ip_y + (h as f64 + 1.0) * gt.scale_y,
                gt.ip_x + (w as f64 + 1.0) * gt.scale_x,
                gt.ip_y - gt.scale_y,
            ];
            let nd = Some(-9999.0);
            for l in 0..tin.levels.len() {
                let name = format!("{tname}, {rname}, level {l}");
                let s = open(&stored, 1996);
                let fetched = Cell::new(0usize);
                let mut fetch = counting_fetch(&stored, &fetched);
                let reader = s.reader(&mut fetch);
                let patch = Patch::new(&reader, l, window, &mut none).unwrap();
                let whole = TinLevel::new(&tin, l).unwrap();
                assert!(patch.count() > 0, "{name}: no triangle under the raster");
                if l + 1 == tin.levels.len() {
                    assert!(
                        fetched.get() * 4 < stored.len(),
                        "{name}: read {} of {} bytes",
                        fetched.get(),
                        stored.len()
                    );
                }
                // the pixels each triangle owns, in raster order
                // a run of pixels: (triangle, row, c0, c1)
                type Span<'a> = &'a mut dyn FnMut(u32, usize, usize, usize);
                let spans = |lv: &dyn Fn(u32) -> u32, run: &mut dyn FnMut(Span<'_>)| {
                    let mut out = Vec::new();
                    run(&mut |k, r, c0, c1| out.push((lv(k), r, c0, c1)));
                    out
                };
                let a = spans(&|k| patch.id(k as usize), &mut |f| {
                    sweep(&patch, &g, true, &mut || Ok(()), f).unwrap()
                });
                let b = spans(&|k| k, &mut |f| {
                    sweep(&whole, &g, true, &mut || Ok(()), f).unwrap()
                });
                assert_eq!(a, b, "{name}: pixels");
                assert!(!a.is_empty(), "{name}: no pixel handed over");
                assert_eq!(
                    zonal_stats(&patch, &g, &vals, nd, true, &mut none).unwrap(),
                    zonal_stats(&whole, &g, &vals, nd, true, &mut none).unwrap(),
                    "{name}: statistics"
                );
                assert_eq!(
                    weighted_stats(&patch, &gt, w, h, &vals, nd, true, &mut none).unwrap(),
                    weighted_stats(&whole, &gt, w, h, &vals, nd, true, &mut none).unwrap(),
                    "{name}: weighted statistics"
                );
                let bands = [&vals[..], &vals[..], &vals[..]];
                let nds = [nd, None, Some(0.0)];
                assert_eq!(
                    paint(&patch, &g, bands, nds, &mut none).unwrap(),
                    paint(&whole, &g, bands, nds, &mut none).unwrap(),
                    "{name}: paint"
                );
            }
        }
    }
}

#[test]
fn tiles_read_in_slices_encode_as_on_the_decoded_value() {
    use tinmerge_core::serve::quantized_mesh::{
        NeedOptions, Source, TileOptions, encode, needed, needed_in,
    };
    use tinmerge_core::serve::tiling::tile_bounds;
    let mut r = StdRng::seed_from_u64(0x711e);
    for (tname, tin) in tins() {
        let b = tin.bbox;
        let (w, h) = (b.max_x - b.min_x, b.max_y - b.min_y);
        // the tin's box mapped affinely into a degree square of the
        // western root tile: any finite positions do for the comparison
        let geo = |p: &[f64; 2]| [-100.0 + (p[0] - b.min_x) / w, 30.0 + (p[1] - b.min_y) / h];
        let tb = tile_bounds(0, 0, 0).unwrap();
        for (fmt, stored, unit) in formats(&tin) {
            for l in 0..tin.levels.len() {
                for k in 0..6 {
                    // a rectangle somewhere, one past the domain's edge
                    let (x0, y0) = (
                        b.min_x - 0.1 * w + r.random::<f64>() * w,
                        b.min_y - 0.1 * h + r.random::<f64>() * h,
                    );
                    let f = [x0, y0, x0 + 0.2 * w, y0 + 0.15 * h];
                    let opts = NeedOptions {
                        normals: k % 2 == 1,
                        fill: false,
                        max_len: (k >= 3).then_some(0.05 * w),
                    };
                    let s = open(&stored, unit);
                    let mut fetch = |at: u64, len: usize| -> Result<Vec<u8>, TinError> {
                        Ok(stored[at as usize..at as usize + len].to_vec())
                    };
                    let reader = s.reader(&mut fetch);
                    let ns = needed_in(&reader, l, Some(f), opts, &[], &mut || Ok(())).unwrap();
                    let nd = needed(&tin, l, Some(f), opts, &mut || Ok(())).unwrap();
                    let what = format!("{tname} {fmt} level {l} rectangle {k}");
                    assert_eq!(ns.triangles, nd.triangles, "{what}");
                    assert_eq!(ns.ring, nd.ring, "{what}");
                    assert_eq!(ns.vertices, nd.vertices, "{what}");
                    assert_eq!(ns.coords, nd.coords, "{what}");
                    assert_eq!(ns.splits.len(), nd.splits.len(), "{what}");
                    // the decoded value's own coordinates, independently
                    for (v, c) in nd.vertices.iter().zip(&nd.coords) {
                        assert_eq!(tin.verts[*v as usize], *c);
                    }
                    let to = TileOptions {
                        normals: opts.normals,
                        fill: None,
                    };
                    let gs: Vec<[f64; 2]> = ns.points().iter().map(geo).collect();
                    let gd: Vec<[f64; 2]> = nd.points().iter().map(geo).collect();
                    let bs = encode(
                        Source {
                            need: &ns,
                            geo: &gs,
                        },
                        &tb,
                        to,
                        &mut || Ok(()),
                    )
                    .unwrap();
                    let bd = encode(
                        Source {
                            need: &nd,
                            geo: &gd,
                        },
                        &tb,
                        to,
                        &mut || Ok(()),
                    )
                    .unwrap();
                    assert_eq!(bs, bd, "{what}");
                    assert_eq!(bd.is_some(), !nd.triangles.is_empty(), "{what}");
                }
            }
        }
    }
}
