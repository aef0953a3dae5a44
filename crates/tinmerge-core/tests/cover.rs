//! Overviews that cover their data (`tin::cover`, used by `tin_overviews`):
//! on both DEMs (the UTM one with nodata on its rotated border, the
//! geographic one with holes), on their own grids, on a fractional origin
//! and on a skewed lattice, for factors 2, 3 and 4, overview tiles that do
//! not line up with the finer tiles.
//!
//! Oracle, the test's own: index arithmetic. Overview pixel (i, j) of
//! factor f holds finer pixels (f i .. f i + f - 1, f j .. f j + f - 1); an
//! overview pixel that was nodata must end as the mean of the valid ones
//! among them, a valid one unchanged, so every valid finer pixel lies in a
//! valid overview pixel; a nodata pixel with none under it must end as the
//! mean of those under its 3 x 3 pixels (nodata when there are none), so
//! the eight neighbours of every overview pixel holding finer data are
//! valid.
use crate::common;

use tinmerge_core::io::raster::Band;
use tinmerge_core::tin::cover::Cover;
use tinmerge_core::tin::lattice::Lattice;

/// The lattice `l` with pixels `f` times larger (the same origin).
fn coarser(l: &Lattice, f: usize) -> Lattice {
    let f = f as f64;
    Lattice {
        scale_x: l.scale_x * f,
        scale_y: l.scale_y * f,
        skew_x: l.skew_x * f,
        skew_y: l.skew_y * f,
        ..*l
    }
}

/// Pixel (c, r)'s upper-left corner on `l` as the origin of a tile there.
fn at(l: &Lattice, c: usize, r: usize) -> Lattice {
    let (x, y) = l.centre(c as f64 - 0.5, r as f64 - 0.5);
    Lattice {
        ip_x: x,
        ip_y: y,
        ..*l
    }
}

/// `l` with a fractional origin, and `l` skewed: the lattices besides the
/// DEMs' own that the tests run on.
fn shifted_and_skewed(l: &Lattice) -> [Lattice; 2] {
    [
        Lattice {
            ip_x: l.ip_x + 0.37,
            ip_y: l.ip_y - 12.625,
            ..*l
        },
        Lattice {
            skew_x: 0.1 * l.scale_x,
            skew_y: -0.05 * l.scale_x,
            ..*l
        },
    ]
}

/// The window of a band (row-major values) as a band of its own.
fn window(b: &Band, width: usize, c0: usize, r0: usize, w: usize, h: usize) -> Band {
    let mut values = Vec::with_capacity(w * h);
    for r in r0..r0 + h {
        values.extend_from_slice(&b.values[r * width + c0..r * width + c0 + w]);
    }
    Band {
        values,
        ..b.clone()
    }
}

fn check(name: &str, fine_l: &Lattice, w: usize, h: usize, fine: &Band, f: usize) {
    // the overview: nearest neighbour as GDAL and PostGIS take it (the
    // finer pixel under the overview pixel's centre)
    let (cw, ch) = (w.div_ceil(f), h.div_ceil(f));
    let nd = fine.nodata.unwrap_or(f64::NAN);
    let pick = |i: usize, j: usize| {
        let (c, r) = ((i * f + f / 2).min(w - 1), (j * f + f / 2).min(h - 1));
        fine.values[r * w + c]
    };
    let coarse_l = coarser(fine_l, f);
    let mut coarse: Vec<f64> = (0..ch)
        .flat_map(|j| (0..cw).map(move |i| (i, j)))
        .map(|(i, j)| pick(i, j))
        .collect();
    let before = coarse.clone();
    // finer tiles of 47 px, overview tiles of 29 px: their edges do not meet
    let (ft, ct) = (47, 29);
    let mut filled = 0;
    for j0 in (0..ch).step_by(ct) {
        for i0 in (0..cw).step_by(ct) {
            let (tw, th) = (ct.min(cw - i0), ct.min(ch - j0));
            let mut band = window(
                &Band {
                    values: coarse.clone(),
                    ..fine.clone()
                },
                cw,
                i0,
                j0,
                tw,
                th,
            );
            let needed = Cover::needed(&band);
            let mut cover = Cover::new(&at(&coarse_l, i0, j0), tw, th).unwrap();
            for r0 in (0..h).step_by(ft) {
                for c0 in (0..w).step_by(ft) {
                    let (fw, fh) = (ft.min(w - c0), ft.min(h - r0));
                    cover.add(
                        &at(fine_l, c0, r0),
                        fw,
                        fh,
                        &window(fine, w, c0, r0, fw, fh),
                    );
                }
            }
            let n = cover.apply(&mut band);
            assert!(
                needed || n == 0,
                "{name} x{f}: a tile without nodata was filled"
            );
            filled += n;
            for r in 0..th {
                coarse[(j0 + r) * cw + i0..(j0 + r) * cw + i0 + tw]
                    .copy_from_slice(&band.values[r * tw..(r + 1) * tw]);
            }
        }
    }
    let valid = |v: f64| !v.is_nan() && v != nd;
    // the valid finer pixels under overview pixels i0..i1 x j0..j1
    let under = |i0: usize, i1: usize, j0: usize, j1: usize| -> Vec<f64> {
        (j0 * f..(j1 * f).min(h))
            .flat_map(|r| (i0 * f..(i1 * f).min(w)).map(move |c| (c, r)))
            .map(|(c, r)| fine.values[r * w + c])
            .filter(|&v| valid(v))
            .collect()
    };
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let (mut want_filled, mut covered) = (0, 0);
    for j in 0..ch {
        for i in 0..cw {
            let k = j * cw + i;
            let own = under(i, i + 1, j, j + 1);
            let around = under(i.saturating_sub(1), i + 2, j.saturating_sub(1), j + 2);
            let want = if !own.is_empty() {
                Some(mean(&own))
            } else if !around.is_empty() {
                Some(mean(&around))
            } else {
                None
            };
            if valid(before[k]) {
                assert_eq!(
                    coarse[k], before[k],
                    "{name} x{f}: valid pixel ({i}, {j}) changed"
                );
            } else if let Some(m) = want {
                assert!(
                    (coarse[k] - m).abs() <= 1e-9 * m.abs().max(1.0),
                    "{name} x{f}: pixel ({i}, {j}) is {} not {m}",
                    coarse[k]
                );
                want_filled += 1;
            } else {
                assert!(
                    !valid(coarse[k]),
                    "{name} x{f}: pixel ({i}, {j}) with no data under it or around it was filled"
                );
            }
            if !own.is_empty() {
                assert!(
                    valid(coarse[k]),
                    "{name} x{f}: data under pixel ({i}, {j}) left uncovered"
                );
                covered += own.len();
                // its eight neighbours (within the overview) are valid
                for jj in j.saturating_sub(1)..(j + 2).min(ch) {
                    for ii in i.saturating_sub(1)..(i + 2).min(cw) {
                        assert!(
                            valid(coarse[jj * cw + ii]),
                            "{name} x{f}: pixel ({ii}, {jj}) beside data under ({i}, {j}) is nodata"
                        );
                    }
                }
            }
        }
    }
    assert_eq!(filled, want_filled, "{name} x{f}");
    let fine_valid = fine.values.iter().filter(|&&v| valid(v)).count();
    assert_eq!(
        covered, fine_valid,
        "{name} x{f}: every valid finer pixel under a valid overview pixel"
    );
    assert!(want_filled > 0, "{name} x{f}: the test must fill pixels");
    eprintln!("{name} x{f}: {cw} x {ch} overview pixels, {want_filled} filled");
}

#[test]
fn overview_pixels_cover_every_valid_finer_pixel() {
    let utm = common::read_dem("jacksboro_fault_dem_utm16n.tif");
    let mut geo = common::read_dem("jacksboro_fault_dem.tif");
    // holes in the geographic DEM (it has no nodata of its own)
    geo.nodata = Some(-9999.0);
    for r in 0..geo.height {
        for c in 0..geo.width {
            let (dc, dr) = (c as f64 - 120.0, r as f64 - 90.0);
            if dc * dc + dr * dr <= 23.0 * 23.0 || (c * 7 + r * 13) % 11 == 0 && c > 200 {
                geo.values[r * geo.width + c] = -9999.0;
            }
        }
    }
    let band = |d: &common::Dem| Band {
        pixel_type: 10,
        nodata: d.nodata,
        all_nodata: false,
        values: d.values.clone(),
    };
    let utm_l = utm.lattice();
    let [shifted, skewed] = shifted_and_skewed(&utm_l);
    for f in [2, 3, 4] {
        check("utm", &utm_l, utm.width, utm.height, &band(&utm), f);
        check(
            "utm, fractional origin",
            &shifted,
            utm.width,
            utm.height,
            &band(&utm),
            f,
        );
        check(
            "utm, skewed",
            &skewed,
            utm.width,
            utm.height,
            &band(&utm),
            f,
        );
        check(
            "geographic",
            &geo.lattice(),
            geo.width,
            geo.height,
            &band(&geo),
            f,
        );
    }
}

#[test]
fn a_tile_flagged_all_nodata_is_given_the_data_under_it() {
    let l = |s: f64| Lattice {
        ip_x: 100.5,
        ip_y: 7.25,
        scale_x: s,
        scale_y: -s,
        skew_x: 0.0,
        skew_y: 0.0,
    };
    let mut coarse = Band {
        pixel_type: 10,
        nodata: Some(0.0),
        all_nodata: true,
        values: vec![0.0; 16],
    };
    // a 4 x 4 tile over 8 x 8 finer pixels, one of them valid, under the
    // coarse pixel (3, 0); its value is the nodata value's neighbour, so
    // the mean must not become nodata
    let mut fine = Band {
        pixel_type: 10,
        nodata: Some(-1.0),
        all_nodata: false,
        values: vec![-1.0; 64],
    };
    fine.values[7] = 0.0;
    let mut cover = Cover::new(&l(0.5), 4, 4).unwrap();
    cover.add(&l(0.25), 8, 8, &fine);
    // the pixel and its three neighbours in the tile
    assert_eq!(cover.apply(&mut coarse), 4);
    assert!(!coarse.all_nodata);
    for (k, &v) in coarse.values.iter().enumerate() {
        let near = [2, 3, 6, 7].contains(&k);
        assert_eq!(coarse.is_valid(v), near, "pixel {k}: {v}");
        assert!(!near || v.abs() < 1e-300, "pixel {k}: {v}");
    }
}

/// `TableGrid::short_of`: an overview's frame stops short of its table's
/// outer pixel centres on the left and top always, on the right and bottom
/// when its last pixel's centre is short of the table's last. Oracle:
/// index arithmetic (overview pixel i's centre is finer pixel index
/// f i + (f - 1) / 2), on both DEMs' sizes, a fractional origin and a
/// skewed lattice, the table as 47-px tiles and the overview as 29-px ones.
#[test]
fn an_overview_frame_grows_where_its_table_reaches_past_it() {
    use tinmerge_core::tin::tiles::{Pad, place_tiles};
    let tiles = |l: &Lattice, w: usize, h: usize, px: usize| {
        let mut metas = Vec::new();
        for r0 in (0..h).step_by(px) {
            for c0 in (0..w).step_by(px) {
                metas.push((at(l, c0, r0), px.min(w - c0), px.min(h - r0)));
            }
        }
        place_tiles(&metas).unwrap()
    };
    let utm = common::read_dem("jacksboro_fault_dem_utm16n.tif").lattice();
    let geo = common::read_dem("jacksboro_fault_dem.tif").lattice();
    let [shifted, skewed] = shifted_and_skewed(&utm);
    let mut seen = std::collections::HashSet::new();
    for l in [utm, geo, shifted, skewed] {
        for (w, h) in [(344, 363), (403, 344), (96, 97)] {
            let base = tiles(&l, w, h, 47);
            assert_eq!(
                base.short_of(&base),
                Pad::default(),
                "a table is not short of itself"
            );
            for f in [2, 3, 4] {
                let (cw, ch) = (w.div_ceil(f), h.div_ceil(f));
                let over = tiles(&coarser(&l, f), cw, ch, 29);
                // twice the centres' indexes, in finer pixels
                let short = |n: usize, cn: usize| 2 * f * (cn - 1) + f - 1 < 2 * (n - 1);
                let want = Pad {
                    left: true,
                    top: true,
                    right: short(w, cw),
                    bottom: short(h, ch),
                };
                assert_eq!(over.short_of(&base), want, "{w} x {h}, x{f}");
                seen.insert((want.right, want.bottom));
            }
        }
    }
    assert_eq!(seen.len(), 4, "both answers on both sides");
}
