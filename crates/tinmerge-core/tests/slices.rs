//! A tiled terrain built in slices of tile rows (`tin_tiles_from_table(...,
//! slice, slices)`): each slice plans the seams with `SLICE_HALO` rows of
//! tiles more on each side and keeps its own rows, and every tile is the
//! whole table's build of it, byte for byte, on both DEMs; without the halo
//! some are not (so the halo is what makes them equal).

use crate::common;
use tinmerge_core::tin::build::default_tolerances;
use tinmerge_core::tin::lattice::Lattice;
use tinmerge_core::tin::tiles::{Block, SLICE_HALO, place_tiles, slice_rows};

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
        let whole = common::table_build(&grid, &blocks, &tols, srid, 0..rows, 0..rows);
        let slices = 4;
        let (mut sliced, mut unhaloed) = (Vec::new(), Vec::new());
        for k in 0..slices {
            let (own, plan) = slice_rows(rows, k, slices);
            assert!(plan.start + SLICE_HALO <= own.start || plan.start == 0);
            sliced.extend(common::table_build(
                &grid,
                &blocks,
                &tols,
                srid,
                plan,
                own.clone(),
            ));
            unhaloed.extend(common::table_build(
                &grid,
                &blocks,
                &tols,
                srid,
                own.clone(),
                own,
            ));
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
