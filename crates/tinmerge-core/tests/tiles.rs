//! Tiles of one terrain: two tiles of the DEM sharing one column of samples,
//! each built on its own with `keep_border`, have the same vertices on the
//! shared column at every level, so the same surface along it (heights
//! continuous across the seam at every level), within each level's
//! tolerance of the seam samples. Without `keep_border` each build refines
//! the straight hull edge along the seam in its own greedy order, and the
//! two surfaces agree only as far as the two builds happen to choose the
//! same seam vertices; the option makes the agreement a property of the
//! construction.
//! And it costs the surface nothing: until 0.7.0 the option made every seam
//! sample a vertex of every level, and the fans of slivers from the border
//! at the coarse levels persisted into the finest (3.6x the triangles of a
//! free build on the 105-megapixel benchmark's tiles, draped lines 1.65x as
//! long as on the raster); the test bounds the extra triangles.
use crate::common;

use tinmerge_core::merge::point::height;
use tinmerge_core::tin::Tin;
use tinmerge_core::tin::build::{BuildOptions, build_with, default_tolerances};

/// Samples of the columns `c0..=c1` of the DEM.
fn tile(d: &common::Dem, c0: usize, c1: usize) -> Vec<[f64; 3]> {
    let mut out = Vec::new();
    for r in 0..d.height {
        for c in c0..=c1 {
            let v = d.values[r * d.width + c];
            if !v.is_nan() && Some(v) != d.nodata {
                let (x, y) = d.centre(c, r);
                out.push([x, y, v]);
            }
        }
    }
    out
}

/// Largest |left - right| over the seam points both tiles cover (samples of
/// the seam column and the midpoints between consecutive ones), per level;
/// how many seam points were compared; and the largest |height - sample|
/// at the seam samples per level.
fn seam(d: &common::Dem, col: usize, a: &Tin, b: &Tin) -> (Vec<f64>, usize, Vec<f64>) {
    let mut worst = vec![0.0f64; a.levels.len()];
    let mut off = vec![0.0f64; a.levels.len()];
    let mut points = 0;
    for r in 0..d.height {
        let v = d.values[r * d.width + col];
        if v.is_nan() || Some(v) == d.nodata {
            continue;
        }
        let (x, y) = d.centre(col, r);
        let (_, y2) = d.centre(col, r + 1);
        for (py, exact) in [(y, Some(v)), ((y + y2) / 2.0, None)] {
            for l in 0..worst.len() {
                let (Some(ha), Some(hb)) = (height(a, l, x, py), height(b, l, x, py)) else {
                    continue;
                };
                points += 1;
                worst[l] = worst[l].max((ha - hb).abs());
                if let Some(v) = exact {
                    off[l] = off[l].max((ha - v).abs()).max((hb - v).abs());
                }
            }
        }
    }
    (worst, points, off)
}

/// The y of the vertices of level `l` on the vertical line x = `x`, sorted.
fn seam_vertices(t: &Tin, l: usize, x: f64) -> Vec<f64> {
    let mut ys: Vec<f64> = t.verts[..t.levels[l].num_vertices as usize]
        .iter()
        .filter(|v| v[0] == x)
        .map(|v| v[1])
        .collect();
    ys.sort_by(f64::total_cmp);
    ys
}

#[test]
fn shared_border_column_gives_a_continuous_surface() {
    let d = common::read_dem("jacksboro_fault_dem_utm16n.tif");
    let col = d.width / 2;
    let tols = default_tolerances(2.0, 3).unwrap();
    let keep = BuildOptions {
        keep_border: true,
        ..Default::default()
    };
    let left = build_with(tile(&d, 0, col), &tols, 32616, keep, &mut || Ok(())).unwrap();
    let right = build_with(tile(&d, col, d.width - 1), &tols, 32616, keep, &mut || {
        Ok(())
    })
    .unwrap();
    left.sanity_check().unwrap();
    right.sanity_check().unwrap();
    let (worst, points, off) = seam(&d, col, &left, &right);
    eprintln!(
        "keep_border: {points} seam points, worst |left - right| per level {worst:?}, worst |height - sample| {off:?}"
    );
    assert!(points > 500, "{points} seam points");
    let (x, _) = d.centre(col, 0);
    for (l, w) in worst.iter().enumerate() {
        let (a, b) = (seam_vertices(&left, l, x), seam_vertices(&right, l, x));
        assert!(a.len() >= 2, "level {l}: the seam's ends are vertices");
        assert_eq!(a, b, "level {l}: the two tiles' vertices on the seam");
        assert!(
            *w <= 1e-9,
            "level {l}: heights differ by {w} across the seam"
        );
        assert!(
            off[l] <= tols[l] + 1e-9,
            "level {l}: a seam sample is {} from the surface, tolerance {}",
            off[l],
            tols[l]
        );
    }
    // the coarse levels keep few seam vertices: the border is simplified
    // like the rest of the surface, not taken whole
    let column = (0..d.height)
        .filter(|&r| {
            let v = d.values[r * d.width + col];
            !v.is_nan() && Some(v) != d.nodata
        })
        .count();
    assert!(
        seam_vertices(&left, 0, x).len() * 2 < column,
        "level 0 keeps {} of the {column} seam samples",
        seam_vertices(&left, 0, x).len()
    );
    // without the option each build decides its seam vertices in its own
    // greedy order: on this DEM they come out the same (a seam sample's
    // error depends on the seam vertices only), but nothing makes them
    // (ties are broken by face order, and a sliver face of scattered
    // samples takes every sample in it)
    let free = BuildOptions::default();
    let l2 = build_with(tile(&d, 0, col), &tols, 32616, free, &mut || Ok(())).unwrap();
    let r2 = build_with(tile(&d, col, d.width - 1), &tols, 32616, free, &mut || {
        Ok(())
    })
    .unwrap();
    let apart = (0..tols.len())
        .filter(|&l| seam_vertices(&l2, l, x) != seam_vertices(&r2, l, x))
        .count();
    eprintln!("without keep_border: {apart} levels with different seam vertices");
    // and the option costs the surface little: triangles of the finest
    // level against the free builds'
    let finest = |t: &Tin| t.levels[t.levels.len() - 1].tris.len();
    let (kept, freed) = (finest(&left) + finest(&right), finest(&l2) + finest(&r2));
    eprintln!("finest triangles: keep_border {kept}, free {freed}");
    assert!(
        kept * 100 <= freed * 110,
        "keep_border makes {kept} finest triangles, free builds {freed}"
    );
    let count = |t: &Tin| t.levels.iter().map(|l| l.num_vertices).collect::<Vec<_>>();
    eprintln!(
        "vertices per level: kept {:?}/{:?}, free {:?}/{:?}",
        count(&left),
        count(&right),
        count(&l2),
        count(&r2)
    );
}

/// `build_tiles` on both DEMs (UTM and geographic, nodata around the
/// warped one), tiles of 97 pixels at 3 levels: each tile is the tin of
/// the samples the docs' keep_border pattern gives it (cut here by the
/// test's own rule and built on their own), every sample on a shared seam
/// (columns and rows) is a vertex of both tiles at every level, and
/// heights along the seams agree exactly from both sides.
#[test]
fn build_tiles_cuts_the_keep_border_pattern_and_its_seams_agree() {
    use tinmerge_core::merge::point::height;
    use tinmerge_core::tin::build::build_lattice_window_kept;
    let n = 97;
    for (name, file, tol, srid) in [
        ("utm", "jacksboro_fault_dem_utm16n.tif", 2.0, 32616),
        ("geographic", "jacksboro_fault_dem.tif", 0.00002, 4326),
    ] {
        let d = common::read_dem(file);
        let lat = d.lattice();
        let valid = |v: f64| !v.is_nan() && Some(v) != d.nodata;
        let tols = default_tolerances(tol, 3).unwrap();
        let (tiles, seams) = common::tiles_and_seams_of(&d, n, &tols, srid);
        let (nx, ny) = (d.width.div_ceil(n), d.height.div_ceil(n));
        // the test's own cut: own pixels plus one more column and row
        let mut expect = 0;
        for ty in 0..ny {
            for tx in 0..nx {
                // in the tile's own frame (numbered from its first pixel,
                // the origin moved there as PostGIS moves it), between samples
                let (c0, r0) = (tx * n, ty * n);
                let mut s = Vec::new();
                for r in r0..((ty + 1) * n + 1).min(d.height) {
                    for c in c0..((tx + 1) * n + 1).min(d.width) {
                        let v = d.values[r * d.width + c];
                        if valid(v) {
                            s.push([(c - c0) as f64, (r - r0) as f64, v]);
                        }
                    }
                }
                let own = tinmerge_core::tin::lattice::Lattice {
                    ip_x: lat.ip_x + c0 as f64 * lat.scale_x + r0 as f64 * lat.skew_x,
                    ip_y: lat.ip_y + c0 as f64 * lat.skew_y + r0 as f64 * lat.scale_y,
                    ..lat
                };
                let keep = BuildOptions {
                    keep_border: true,
                    between_samples: true,
                };
                let got = tiles.iter().find(|t| (t.0, t.1) == (tx, ty));
                // the seam samples the tiles kept (in this tile's own
                // frame); the rest is its own build
                let mut border = seams.border(
                    c0 as i64..((tx + 1) * n + 1) as i64,
                    r0 as i64..((ty + 1) * n + 1) as i64,
                );
                for l in &mut border.levels {
                    for p in l.iter_mut() {
                        *p = [p[0] - c0 as f64, p[1] - r0 as f64];
                    }
                }
                let Ok(want) = build_lattice_window_kept(
                    s,
                    &own,
                    (0, 0),
                    &tols,
                    srid,
                    keep,
                    &border,
                    &mut |_| Ok(()),
                    &mut || Ok(()),
                ) else {
                    continue;
                };
                let got = got.unwrap_or_else(|| panic!("{name}: tile {tx},{ty} missing"));
                // the same triangles with the same parents, the vertices the
                // same up to the rounding of the tile's origin (the tile is
                // placed on the raster's lattice, this build on the tile's
                // own); numbered maybe otherwise (the kept seam samples come
                // first in one build, as Douglas-Peucker picks them in the other)
                let px = lat.scale_x.abs().max(lat.scale_y.abs());
                assert_eq!(got.2.verts.len(), want.verts.len());
                assert_eq!(got.2.levels.len(), want.levels.len());
                for l in 0..want.levels.len() {
                    assert!(
                        shape(&got.2, l, px) == shape(&want, l, px),
                        "{name}: tile {tx},{ty} level {l} differs from its own build"
                    );
                }
                // (sanity_check is exact in the lattice frame only; in world
                // coordinates: valid, and no sliver hiding a crack)
                tinmerge_core::tin::check::validate_structure(&got.2).unwrap();
                assert!(
                    tinmerge_core::tin::check::problems(&got.2, &mut || Ok(()))
                        .unwrap()
                        .is_empty(),
                    "{name}: tile {tx},{ty} has slivers"
                );
                expect += 1;
            }
        }
        assert_eq!(tiles.len(), expect, "{name}: tiles");
        assert!(expect > 6, "{name}: {expect} tiles");
        // seams: the column (row) shared with the right (lower) neighbour
        let tile =
            |tx: usize, ty: usize| tiles.iter().find(|t| (t.0, t.1) == (tx, ty)).map(|t| &t.2);
        let (mut points, mut worst) = (0usize, 0.0f64);
        for &(tx, ty, ref a) in &tiles {
            for (dx, dy) in [(1, 0), (0, 1)] {
                let Some(b) = tile(tx + dx, ty + dy) else {
                    continue;
                };
                // the seam's pixels: a column of a's rows, or a row of a's columns
                let seam: Vec<(usize, usize)> = if dx == 1 {
                    let c = (tx + 1) * n;
                    (ty * n..((ty + 1) * n + 1).min(d.height))
                        .map(|r| (c, r))
                        .collect()
                } else {
                    let r = (ty + 1) * n;
                    (tx * n..((tx + 1) * n + 1).min(d.width))
                        .map(|c| (c, r))
                        .collect()
                };
                for w in seam.windows(2) {
                    let (c, r) = w[0];
                    let v = d.values[r * d.width + c];
                    let v2 = d.values[w[1].1 * d.width + w[1].0];
                    if !valid(v) || !valid(v2) {
                        continue;
                    }
                    let (px, py) = lat.centre(c as f64, r as f64);
                    let (qx, qy) = lat.centre(w[1].0 as f64, w[1].1 as f64);
                    let (p, q) = ([px, py], [qx, qy]);
                    let mid = [(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0];
                    for (l, &tol) in tols.iter().enumerate() {
                        let (ha, hb) = (height(a, l, p[0], p[1]), height(b, l, p[0], p[1]));
                        let (Some(ha), Some(hb)) = (ha, hb) else {
                            panic!(
                                "{name}: seam sample ({c}, {r}) level {l} outside a tile: {ha:?} {hb:?}"
                            );
                        };
                        assert!(
                            (ha - hb).abs() <= 1e-9 && (ha - v).abs() <= tol + 1e-9,
                            "{name}: seam sample ({c}, {r}) level {l}: {ha} / {hb}, sample {v}, tolerance {tol}"
                        );
                        let (ma, mb) = (height(a, l, mid[0], mid[1]), height(b, l, mid[0], mid[1]));
                        if let (Some(ma), Some(mb)) = (ma, mb) {
                            worst = worst.max((ma - mb).abs());
                        }
                        points += 1;
                    }
                }
            }
        }
        eprintln!(
            "{name}: {} tiles, {points} seam points, worst difference between midpoints {worst}",
            tiles.len()
        );
        assert!(points > 1000, "{name}: {points} seam points");
        assert!(worst <= 1e-9, "{name}: seams differ by {worst}");
    }
}

/// Level `l` of `t` as a sorted list of triangles, each its corners
/// (positions to a millionth of `px`, heights exact, sorted) and its
/// parent's: the same for two builds of one hierarchy however they number
/// their vertices.
#[allow(clippy::type_complexity)]
fn shape(t: &Tin, l: usize, px: f64) -> Vec<([(i64, i64, u64); 3], Option<[(i64, i64, u64); 3]>)> {
    // (offset from the half-millionths: a vertex where an edge crosses a
    // grid segment at a dyadic fraction of a pixel, 1/128 say, lies on one,
    // and the rounding of the two lattices then puts it either side)
    let key = |v: u32| {
        let p = t.verts[v as usize];
        (
            (p[0] / px * 1e6 + 0.2937).round() as i64,
            (p[1] / px * 1e6 + 0.2937).round() as i64,
            p[2].to_bits(),
        )
    };
    let tri = |l: usize, k: usize| {
        let mut c = t.levels[l].tris[k].map(key);
        c.sort_unstable();
        c
    };
    let lv = &t.levels[l];
    let mut out: Vec<_> = (0..lv.tris.len())
        .map(|k| {
            (
                tri(l, k),
                (l > 0).then(|| tri(l - 1, lv.parent[k] as usize)),
            )
        })
        .collect();
    out.sort_unstable();
    out
}

/// A table of raster tiles (cut as `raster2pgsql -t` cuts: each tile its
/// own origin `origin + k * size`, the last column and row narrower), given
/// in a shuffled order, placed by `place_tiles` and built from
/// `keep_border_samples` in the rounds of seam samples kept that
/// `tin_tiles_from_table` runs (`TableGrid::tiles_holding` finding the tiles
/// a kept sample touches), gives every tile of `build_tiles` on the whole
/// raster bit for bit (that path is checked against the test's own cut
/// above), on both DEMs. A table with a tile missing leaves its neighbours
/// without that border; misaligned tables are refused.
#[test]
fn a_table_of_tiles_builds_the_tiles_of_the_whole_raster() {
    use rand::{SeedableRng, seq::SliceRandom};
    use tinmerge_core::tin::lattice::Lattice;
    use tinmerge_core::tin::tiles::{Block, keep_border_samples, place_tiles};
    let n = 97;
    for (name, file, tol, srid) in [
        ("utm", "jacksboro_fault_dem_utm16n.tif", 2.0, 32616),
        ("geographic", "jacksboro_fault_dem.tif", 0.00002, 4326),
    ] {
        let d = common::read_dem(file);
        let lat = d.lattice();
        let valid = |v: f64| !v.is_nan() && Some(v) != d.nodata;
        let tols = default_tolerances(tol, 3).unwrap();
        let whole: Vec<(usize, usize, Vec<u8>)> = common::tiles_of(&d, n, &tols, srid)
            .into_iter()
            .map(|(tx, ty, t)| (tx, ty, tinmerge_core::tin::layout::encode(&t)))
            .collect();
        // the table: (own lattice, width, height, values), shuffled
        let mut table = common::table_of(&d, n);
        table.shuffle(&mut rand::rngs::StdRng::seed_from_u64(25));
        let metas: Vec<(Lattice, usize, usize)> = table.iter().map(|t| (t.0, t.1, t.2)).collect();
        let grid = place_tiles(&metas).unwrap();
        assert_eq!(
            grid.lattice, lat,
            "{name}: the top-left tile's lattice is the raster's"
        );
        assert_eq!(grid.counts(), (d.width.div_ceil(n), d.height.div_ceil(n)));
        let blocks: Vec<Block> = grid
            .tiles
            .iter()
            .zip(&table)
            .map(|(p, t)| Block {
                place: *p,
                values: &t.3,
                valid: &valid,
            })
            .collect();
        let at =
            |tx: usize, ty: usize| blocks.iter().find(|b| (b.place.tx, b.place.ty) == (tx, ty));
        // tin_tiles_from_table's rounds: every tile, then those holding the
        // seam samples a tile asked for, until none is new; each tile's
        // last build is its tin
        let rows = grid.counts().1;
        let got = common::table_build(&grid, &blocks, &tols, srid, 0..rows, 0..rows);
        let mut want: Vec<((usize, usize), Vec<u8>)> =
            whole.into_iter().map(|(tx, ty, t)| ((tx, ty), t)).collect();
        want.sort_by_key(|w| w.0);
        assert_eq!(
            got.len(),
            want.len(),
            "{name}: the same tiles as build_tiles'"
        );
        for (g, w) in got.iter().zip(&want) {
            assert!(g == w, "{name}: tile {:?} differs from build_tiles'", g.0);
        }
        assert!(got.len() > 6);
        // the same with each tile's last build held (as the SQL function
        // does), and held until they pass half their bytes, then dropped
        // and every tile built once more
        let bytes: usize = want.iter().map(|w| w.1.len()).sum();
        for (budget, dropped) in [(usize::MAX, false), (bytes / 2, true)] {
            let rounds = tinmerge_core::tin::seam_rounds::SeamRounds::rows(
                &grid,
                tols.clone(),
                srid,
                true,
                0..rows,
                0..rows,
            );
            let (held, was) = common::table_rounds_held(&grid, &blocks, rounds, Some(budget));
            assert_eq!(was, dropped, "{name}: held up to {budget} bytes");
            assert!(
                held == want,
                "{name}: held up to {budget} bytes, not build_tiles' tiles"
            );
        }
        // tile (1, 1) missing: (0, 1) gets no right column (nor the corner of
        // (1, 2)), (0, 0) no corner
        let without = |tx: usize, ty: usize| at(tx, ty).filter(|_| (tx, ty) != (1, 1));
        let s = keep_border_samples(
            at(0, 1).unwrap(),
            without(1, 1),
            without(0, 2),
            without(1, 2),
        );
        assert!(
            s.iter().all(|p| p[0] < n as f64),
            "{name}: no column from a missing tile"
        );
        let s = keep_border_samples(
            at(0, 0).unwrap(),
            without(1, 0),
            without(0, 1),
            without(1, 1),
        );
        assert!(
            !s.iter().any(|p| p[0] == n as f64 && p[1] == n as f64),
            "{name}: no corner"
        );
        assert!(s.iter().any(|p| p[0] == n as f64) && s.iter().any(|p| p[1] == n as f64));
        // refused: half a pixel off, another pixel size, two tiles in one place
        let mut off = metas.clone();
        off[1].0.ip_x += lat.scale_x / 2.0;
        assert!(place_tiles(&off).is_err());
        let mut size = metas.clone();
        size[2].0.scale_x *= 1.0 + 1e-12;
        assert!(place_tiles(&size).is_err());
        let mut twice = metas.clone();
        twice.push(metas[3]);
        let e = place_tiles(&twice).unwrap_err().to_string();
        assert!(e.contains("same place"), "{e}");
        let mut shifted = metas.clone();
        shifted[0].0.ip_x += lat.scale_x * 3.0;
        assert!(
            place_tiles(&shifted).is_err(),
            "{name}: a tile 3 pixels along is off the grid"
        );
    }
}

/// Every valid pixel centre of both DEMs, its coordinates computed as
/// PostGIS's `ST_PixelAsCentroids` computes them for a table of tiles
/// (from the pixel's own raster tile's upper-left corner, itself the
/// raster's origin moved by whole tiles), gets a height within the finest
/// tolerance from a tin of `build_tiles` that holds it (97-pixel tiles, 3
/// levels), through `height_near_in` (what `tin_height` answers). The
/// tiles are placed on the raster's own lattice, so such a centre can lie
/// an ulp or two off a tin's edge (the billion-pixel run found 5 of
/// 243,890 sampled centres without a height); the exact `height` is
/// counted too, to show where that happens.
#[test]
fn pixel_centres_computed_from_their_own_tile_all_get_a_height() {
    use tinmerge_core::merge::point::height_near_in;
    let n = 97;
    let mut off_total = 0;
    for (name, file, tol, srid) in [
        ("utm", "jacksboro_fault_dem_utm16n.tif", 2.0, 32616),
        ("geographic", "jacksboro_fault_dem.tif", 0.00002, 4326),
    ] {
        let d = common::read_dem(file);
        let lat = d.lattice();
        let tols = default_tolerances(tol, 3).unwrap();
        let fin = tols.len() - 1;
        let tiles = common::tiles_of(&d, n, &tols, srid);
        let at = |tx: usize, ty: usize| tiles.iter().find(|t| (t.0, t.1) == (tx, ty)).map(|t| &t.2);
        let (mut centres, mut unanswered, mut off_exact, mut worst) = (0, 0, 0, 0.0f64);
        for r in 0..d.height {
            for c in 0..d.width {
                let v = d.values[r * d.width + c];
                if v.is_nan() || Some(v) == d.nodata {
                    continue;
                }
                centres += 1;
                // PostGIS: the tile's corner, then the pixel in it
                let (c0, r0) = ((c / n) * n, (r / n) * n);
                let (ux, uy) = (
                    lat.ip_x + c0 as f64 * lat.scale_x,
                    lat.ip_y + r0 as f64 * lat.scale_y,
                );
                let (x, y) = (
                    ux + ((c - c0) as f64 + 0.5) * lat.scale_x,
                    uy + ((r - r0) as f64 + 0.5) * lat.scale_y,
                );
                // the tins whose window holds the pixel: its own tile's, and
                // the tile before it when it is that tile's added column or row
                let mut holders = vec![(c / n, r / n)];
                if c % n == 0 && c > 0 {
                    holders.push((c / n - 1, r / n));
                }
                if r % n == 0 && r > 0 {
                    holders.push((c / n, r / n - 1));
                }
                if c % n == 0 && c > 0 && r % n == 0 && r > 0 {
                    holders.push((c / n - 1, r / n - 1));
                }
                let tins: Vec<&Tin> = holders.iter().filter_map(|&(tx, ty)| at(tx, ty)).collect();
                if !tins.iter().any(|t| height(t, fin, x, y).is_some()) {
                    off_exact += 1;
                }
                let best = tins
                    .iter()
                    .filter_map(|t| height_near_in(*t, fin, x, y).unwrap())
                    .map(|h| (h - v).abs())
                    .reduce(f64::min);
                match best {
                    Some(e) => worst = worst.max(e),
                    None => unanswered += 1,
                }
            }
        }
        println!(
            "{name}: {centres} valid centres from their own tile's corner: {unanswered} unanswered, {off_exact} off every tin's exact hull, worst {worst:e} (tolerance {})",
            tols[fin]
        );
        assert_eq!(
            unanswered, 0,
            "{name}: valid pixel centres without a height"
        );
        assert!(
            worst <= tols[fin] * (1.0 + 1e-9),
            "{name}: {worst} beyond the tolerance"
        );
        off_total += off_exact;
    }
    println!("{off_total} centres answered only within rounding of a tin's edge");
}
