//! A tiled terrain built in slices of tile rows (`tin_tiles_from_table(...,
//! slice, slices)`): each slice plans the seams with `SLICE_HALO` rows of
//! tiles more on each side and keeps its own rows, and every tile is the
//! whole table's build of it, byte for byte, on both DEMs; without the halo
//! some are not (so the halo is what makes them equal).

use crate::common;
use tinmerge_core::tin::build::default_tolerances;
use tinmerge_core::tin::lattice::Lattice;
use tinmerge_core::tin::tiles::{
    Block, SEAM_ROUNDS, SLICE_HALO, Seams, TableGrid, build_tile_kept, keep_border_samples,
    place_tiles, slice_rows,
};

/// The planning rounds of `tin_tiles_from_table` over the tiles whose row
/// is in `plan` (tiles outside are not there: as a table without them),
/// then the encoded tins of the tiles in `own` rows, by (tx, ty).
fn build_rows(
    grid: &TableGrid,
    blocks: &[Block],
    tols: &[f64],
    srid: i32,
    plan: std::ops::Range<usize>,
    own: std::ops::Range<usize>,
) -> Vec<((usize, usize), Vec<u8>)> {
    let local: Vec<usize> = (0..blocks.len())
        .filter(|&k| plan.contains(&blocks[k].place.ty))
        .collect();
    let index: std::collections::HashMap<(usize, usize), usize> = local
        .iter()
        .map(|&k| ((blocks[k].place.tx, blocks[k].place.ty), k))
        .collect();
    let at = |tx: usize, ty: usize| index.get(&(tx, ty)).map(|&k| &blocks[k]);
    let build = |k: usize, seams: &Seams| {
        let b = &blocks[k];
        let (tx, ty, p) = (b.place.tx, b.place.ty, b.place);
        let s = keep_border_samples(b, at(tx + 1, ty), at(tx, ty + 1), at(tx + 1, ty + 1));
        let keep = seams.border(
            p.col..p.col + p.width as i64 + 1,
            p.row..p.row + p.height as i64 + 1,
        );
        build_tile_kept(
            s,
            &grid.lattice,
            (p.col, p.row),
            tols,
            srid,
            &keep,
            &mut || Ok(()),
        )
        .unwrap()
    };
    let mut seams = Seams::default();
    let mut todo = local.clone();
    for _ in 0..SEAM_ROUNDS {
        let asked: Vec<_> = todo
            .iter()
            .filter_map(|&k| build(k, &seams).map(|(_, w)| w))
            .collect();
        let mut again: Vec<usize> = Vec::new();
        for w in &asked {
            for (c, r) in seams.add(w) {
                for t in grid.tiles_holding(c, r) {
                    again.extend(index.get(&t).copied());
                }
            }
        }
        again.sort_by_key(|&k| (blocks[k].place.ty, blocks[k].place.tx));
        again.dedup();
        if again.is_empty() {
            break;
        }
        todo = again;
    }
    let mut out: Vec<((usize, usize), Vec<u8>)> = local
        .iter()
        .filter(|&&k| own.contains(&blocks[k].place.ty))
        .filter_map(|&k| {
            let p = blocks[k].place;
            build(k, &seams).map(|(t, _)| ((p.tx, p.ty), tinmerge_core::tin::layout::encode(&t)))
        })
        .collect();
    out.sort_by_key(|o| o.0);
    out
}

#[test]
fn slices_of_a_table_build_the_whole_tables_tiles() {
    let n = 8;
    for (name, file, tol, srid) in [
        ("utm", "jacksboro_fault_dem_utm16n.tif", 2.0, 32616),
        ("geographic", "jacksboro_fault_dem.tif", 0.00002, 4326),
    ] {
        let d = common::read_dem(file);
        let valid = |v: f64| !v.is_nan() && Some(v) != d.nodata;
        let tols = default_tolerances(tol, 3).unwrap();
        let table = common::table_of(&d, n);
        let metas: Vec<(Lattice, usize, usize)> = table.iter().map(|t| (t.0, t.1, t.2)).collect();
        let grid = place_tiles(&metas).unwrap();
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
        let rows = grid.counts().1;
        let whole = build_rows(&grid, &blocks, &tols, srid, 0..rows, 0..rows);
        let slices = 4;
        let (mut sliced, mut unhaloed) = (Vec::new(), Vec::new());
        for k in 0..slices {
            let (own, plan) = slice_rows(rows, k, slices);
            assert!(plan.start + SLICE_HALO <= own.start || plan.start == 0);
            sliced.extend(build_rows(&grid, &blocks, &tols, srid, plan, own.clone()));
            unhaloed.extend(build_rows(&grid, &blocks, &tols, srid, own.clone(), own));
        }
        sliced.sort_by_key(|o| o.0);
        unhaloed.sort_by_key(|o| o.0);
        assert_eq!(sliced.len(), whole.len(), "{name}: every tile once");
        for (a, b) in sliced.iter().zip(&whole) {
            assert!(
                a == b,
                "{name}: tile {:?} of a slice differs from the whole table's",
                a.0
            );
        }
        let differ = unhaloed.iter().zip(&whole).filter(|(a, b)| a != b).count();
        eprintln!(
            "{name}: {} tiles in {rows} rows, {slices} slices: all the same with the halo, {differ} differ without it",
            whole.len()
        );
        assert!(differ > 0, "{name}: the slices' edges should need the halo");
    }
}
