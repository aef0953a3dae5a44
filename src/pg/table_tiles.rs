//! `tin_tiles_from_table`: a table of raster tiles built tile by tile, rows
//! of tiles read through SPI as they are needed.

use pgrx::prelude::*;

use super::errors::{raise, OrRaise};
use super::memory;
use super::tin_type::TinOut;
use pgrx::pg_sys;

use super::table_source::TableSource;
use tinmerge_core::io::raster;
use tinmerge_core::tin::build::default_tolerances;
use tinmerge_core::tin::cover::Cover;

/// A table of raster tiles (`raster2pgsql -t`, `ST_Tile`) being built
/// tile by tile: `tin_tiles_from_table(tiles regclass, ...)`. Rows
/// of tiles are read through SPI as they are needed (a tile row and the one
/// below it held at once), tiles are built `tinmerge.threads` at a time,
/// and each result is handed out before the next batch is built, so the
/// call's memory is bounded by two rows of tiles and one batch of builds,
/// whatever the table's size.
pub(super) struct TableTiles {
    /// The table's tiles.
    src: std::sync::Arc<TableSource>,
    /// An overview layer's base table: its tiles under the overview's
    /// nodata pixels give them data ([`tinmerge_core::tin::cover`]).
    cover: Option<std::sync::Arc<TableSource>>,
    tols: Vec<f64>,
    /// Tiles in (ty, tx) order, and the next to build.
    order: Vec<usize>,
    next: usize,
    /// Tile index by (tx, ty).
    at: std::collections::HashMap<(usize, usize), usize>,
    /// Bands read, by tile index.
    loaded: std::collections::HashMap<usize, raster::Band>,
    ready: std::collections::VecDeque<(i32, i32, TinOut)>,
    /// Seam samples kept so far (`tin::tiles::Seams`): rounds of planning
    /// (`round`, while `planning`) build the tiles whose seams gained
    /// samples and keep only what they ask for (`asked`), as `tin_tiles`
    /// does; then every tile is built once more, with them, and returned.
    seams: tinmerge_core::tin::tiles::Seams,
    asked: Vec<tinmerge_core::tin::tile::Wanted>,
    round: usize,
    planning: bool,
    /// The rows of tiles returned (the slice's own, `slice_rows`) and
    /// the rows planned with (theirs and the halo): the tiles outside
    /// `plan` are left out as if the table had none there.
    own: std::ops::Range<usize>,
    plan: std::ops::Range<usize>,
    /// Tiles over the hull of their samples (true), or over their valid
    /// pixels' squares only (`tin::tile_domain`).
    fill_gaps: bool,
    /// The sides of the frame where an overview layer's tiles are grown by
    /// a pixel (`tin::tiles::pad_samples`) to reach its base's outer pixel
    /// centres (none for a table built as it is), and the frame, found
    /// once (`TableGrid::frame`).
    pad: (tinmerge_core::tin::tiles::Pad, [i64; 4]),
    /// Progress reported (`super::progress`), its phases named after
    /// `label` (an overview layer's).
    tracker: super::progress::Tracker,
    label: String,
}

impl TableTiles {
    /// The table's tiles placed on their common lattice.
    pub(super) fn grid(&self) -> &tinmerge_core::tin::tiles::TableGrid {
        &self.src.grid
    }

    /// The tiles' SRID (0 without tiles).
    pub(super) fn srid(&self) -> i32 {
        self.src.srid
    }

    /// The table as a `FROM` item.
    pub(super) fn from(&self) -> &str {
        &self.src.from
    }

    /// The table's tiles, to share (an overview layer's base).
    pub(super) fn source(&self) -> std::sync::Arc<TableSource> {
        self.src.clone()
    }

    /// This layer with its progress reported as `label`'s.
    pub(super) fn labelled(mut self, label: String) -> TableTiles {
        self.label = label;
        self
    }

    /// This layer, an overview of `base`, with its nodata pixels given
    /// the data of `base`'s pixels under them
    /// ([`tinmerge_core::tin::cover`]): its tins cover every valid pixel
    /// of `base`.
    pub(super) fn covering(mut self, base: std::sync::Arc<TableSource>) -> TableTiles {
        if let Some(frame) = self.src.grid.frame() {
            self.pad = (self.src.grid.short_of(&base.grid), frame);
        }
        self.cover = Some(base);
        self
    }

    #[allow(clippy::too_many_arguments)]
    pub(super) fn open(
        func: &'static str,
        tab: pg_sys::Oid,
        column: &str,
        tolerance: f64,
        levels: i32,
        band: i32,
        (slice, slices): (i32, i32),
        fill_gaps: bool,
    ) -> TableTiles {
        use tinmerge_core::tin::tiles::slice_rows;
        if band < 1 {
            raise(
                PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
                format!("{func}: band must be 1 or more (bands are numbered from 1), got {band}"),
            );
        }
        if slices < 1 || !(0..slices).contains(&slice) {
            raise(
                PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
                format!("{func}: slice must be from 0 to slices - 1 and slices at least 1, got slice {slice} of {slices}"),
            );
        }
        let tols = default_tolerances(tolerance, levels).or_raise();
        let src = TableSource::open(func, tab, column, band);
        let grid = &src.grid;
        let (own, plan) = slice_rows(grid.counts().1, slice as usize, slices as usize);
        let mut order: Vec<usize> = (0..grid.tiles.len())
            .filter(|&k| plan.contains(&grid.tiles[k].ty))
            .collect();
        order.sort_by_key(|&k| (grid.tiles[k].ty, grid.tiles[k].tx));
        let at = order
            .iter()
            .map(|&k| ((grid.tiles[k].tx, grid.tiles[k].ty), k))
            .collect();
        super::threads::apply();
        TableTiles {
            src: std::sync::Arc::new(src),
            cover: None,
            tols,
            order,
            next: 0,
            at,
            loaded: Default::default(),
            ready: Default::default(),
            seams: Default::default(),
            asked: Vec::new(),
            round: 0,
            planning: true,
            own,
            plan,
            fill_gaps,
            pad: Default::default(),
            tracker: super::progress::Tracker::new(func),
            label: String::new(),
        }
    }

    /// The end of a round of planning: the seam samples asked for taken,
    /// and the tiles that hold new ones to build in the next round; or,
    /// when there are none (or after `SEAM_ROUNDS` rounds), every tile, to
    /// return.
    fn end_round(&mut self) {
        use tinmerge_core::tin::tiles::SEAM_ROUNDS;
        let mut again: Vec<usize> = Vec::new();
        for w in std::mem::take(&mut self.asked) {
            for (c, r) in self.seams.add(&w) {
                again.extend(
                    self.src
                        .grid
                        .tiles_holding(c, r)
                        .into_iter()
                        .filter_map(|t| self.at.get(&t).copied()),
                );
            }
        }
        self.round += 1;
        let grid = &self.src.grid;
        if again.is_empty() || self.round >= SEAM_ROUNDS {
            // the tiles to return: the slice's own rows
            self.planning = false;
            again = (0..grid.tiles.len())
                .filter(|&k| self.own.contains(&grid.tiles[k].ty))
                .collect();
        }
        again.sort_by_key(|&k| (grid.tiles[k].ty, grid.tiles[k].tx));
        again.dedup();
        self.order = again;
        self.next = 0;
        self.loaded.clear();
    }

    /// Read the bands of tile rows `rows` not read yet (an overview's
    /// nodata pixels given the data under them), and forget the rows
    /// above the first.
    fn load_rows(&mut self, rows: std::ops::RangeInclusive<usize>) {
        let grid = &self.src.grid;
        self.loaded
            .retain(|&k, _| grid.tiles[k].ty >= *rows.start());
        let want: Vec<usize> = (0..grid.tiles.len())
            .filter(|&k| {
                let ty = grid.tiles[k].ty;
                rows.contains(&ty) && self.plan.contains(&ty) && !self.loaded.contains_key(&k)
            })
            .collect();
        let mut got = self.src.read(&want);
        if let Some(base) = &self.cover {
            for (k, band) in got.iter_mut() {
                if Cover::needed(band) {
                    cover(&self.src, *k, band, base);
                }
            }
        }
        self.loaded.extend(got);
    }

    /// Build the next batch of tiles (one per thread) into `ready`.
    fn build_batch(&mut self) {
        let func = self.src.func;
        use tinmerge_core::tin::tile_domain::build_tile_window;
        use tinmerge_core::tin::tiles::{
            keep_border_samples, keep_border_window, pad_samples, Block,
        };
        let threads = tinmerge_core::tin::par::threads().max(1);
        let batch: Vec<usize> =
            self.order[self.next..(self.next + threads).min(self.order.len())].to_vec();
        self.next += batch.len();
        let (first, last) = (
            self.src.grid.tiles[batch[0]].ty,
            self.src.grid.tiles[batch[batch.len() - 1]].ty,
        );
        self.load_rows(first..=last + 1);
        let per_tile = (self.src.grid.tile_width + 1) * (self.src.grid.tile_height + 1);
        memory::reserve(
            tinmerge_core::tin::build::lattice_build_bytes(per_tile, self.tols.len(), true)
                .saturating_mul(batch.len()),
            || {
                format!(
                    "{func}: building {} tiles of {per_tile} samples at {} levels at once",
                    batch.len(),
                    self.tols.len()
                )
            },
        );
        let valids: std::collections::HashMap<usize, Box<dyn Fn(f64) -> bool + Sync + '_>> = self
            .loaded
            .iter()
            .map(|(&k, b)| {
                (
                    k,
                    Box::new(move |v: f64| b.is_valid(v)) as Box<dyn Fn(f64) -> bool + Sync>,
                )
            })
            .collect();
        let block = |tx: usize, ty: usize| -> Option<Block> {
            let k = *self.at.get(&(tx, ty))?;
            Some(Block {
                place: self.src.grid.tiles[k],
                values: &self.loaded.get(&k)?.values,
                valid: valids.get(&k)?.as_ref(),
            })
        };
        let (lattice, tols, srid) = (self.src.grid.lattice, &self.tols, self.src.srid);
        let (seams, planning, fill_gaps) = (&self.seams, self.planning, self.fill_gaps);
        let built = tinmerge_core::tin::par::map(&batch, |&k| {
            let p = self.src.grid.tiles[k];
            let own = block(p.tx, p.ty)?;
            let (right, below) = (block(p.tx + 1, p.ty), block(p.tx, p.ty + 1));
            let mut s = keep_border_samples(
                &own,
                right.as_ref(),
                below.as_ref(),
                block(p.tx + 1, p.ty + 1).as_ref(),
            );
            let size = keep_border_window(&own, right.as_ref(), below.as_ref());
            let pad = self.pad.0.of_tile(self.pad.1, &p);
            let (origin, size) = pad_samples(&mut s, (p.col, p.row), size, pad);
            let keep = seams.border(
                origin.0..p.col + p.width as i64 + 1 + i64::from(pad.right),
                origin.1..p.row + p.height as i64 + 1 + i64::from(pad.bottom),
            );
            let tile = build_tile_window(
                s,
                &lattice,
                origin,
                size,
                tols,
                srid,
                &keep,
                fill_gaps,
                &mut || Ok(()),
            );
            Some(tile.map(|t| {
                t.map(|(t, wanted)| {
                    if planning {
                        (None, wanted)
                    } else {
                        let out = TinOut::from_tin_on(&t, &lattice);
                        (Some((p.tx as i32, p.ty as i32, out)), Vec::new())
                    }
                })
            }))
        });
        for r in built {
            let Some(r) = r else {
                raise(
                    PgSqlErrorCode::ERRCODE_INTERNAL_ERROR,
                    format!("{}: a tile of the batch was not read", self.src.func),
                );
            };
            if let Some((row, wanted)) = r.or_raise() {
                self.ready.extend(row);
                self.asked.push(wanted);
            }
        }
    }
}

/// Give overview tile `k` of `src` (its band read) the data of `base`'s
/// pixels under its nodata pixels and under their neighbours ([`Cover`]):
/// the base tiles meeting it and the ring of pixels around it are read
/// sixteen at a time.
fn cover(src: &TableSource, k: usize, band: &mut raster::Band, base: &TableSource) {
    let (lattice, w, h) = src.metas[k];
    let Some(mut c) = Cover::new(&lattice, w, h) else {
        return;
    };
    for chunk in base.meeting(src.tile_box(k, 1)).chunks(16) {
        pgrx::check_for_interrupts!();
        for (j, b) in base.read(chunk) {
            let (l, bw, bh) = base.metas[j];
            c.add(&l, bw, bh, &b);
        }
    }
    c.apply(band);
}

impl Iterator for TableTiles {
    type Item = (i32, i32, TinOut);
    fn next(&mut self) -> Option<Self::Item> {
        loop {
            if let Some(r) = self.ready.pop_front() {
                return Some(r);
            }
            if self.next >= self.order.len() {
                if !self.planning {
                    self.tracker.finish();
                    return None;
                }
                self.end_round();
                continue;
            }
            pgrx::check_for_interrupts!();
            let phase = if self.planning {
                format!(
                    "{}planning the seams (round {}): building tiles",
                    self.label,
                    self.round + 1
                )
            } else {
                format!("{}building tiles", self.label)
            };
            let (done, total) = (self.next as u64, self.order.len() as u64);
            self.tracker.set(&phase, "tiles", done, total);
            self.build_batch();
        }
    }
}

/// `tin_tiles_from_table(tiles regclass, tolerance, levels, rast_column, band,
/// slice, slices, fill_gaps)`: every raster tile of a table (of slice `slice` of
/// `slices`: its rows of tiles) built as a tin with its neighbours' border
/// pixels (the SQL wrapper passes the table's OID and the column's name).
#[allow(clippy::too_many_arguments)]
#[pg_extern(stable, strict, parallel_restricted, cost = 100000, requires = ["tin_type"])]
fn _tin_tiles_table(
    tab: pg_sys::Oid,
    column: &str,
    tolerance: f64,
    levels: i32,
    band: i32,
    slice: i32,
    slices: i32,
    fill_gaps: bool,
) -> TableIterator<'static, (name!(tx, i32), name!(ty, i32), name!(t, TinOut))> {
    TableIterator::new(TableTiles::open(
        "tin_tiles_from_table",
        tab,
        column,
        tolerance,
        levels,
        band,
        (slice, slices),
        fill_gaps,
    ))
}

extension_sql!(
    r#"
ALTER FUNCTION _tin_tiles_table(oid, text, float8, int, int, int, int, boolean) ROWS 100;
COMMENT ON FUNCTION _tin_tiles_table(oid, text, float8, int, int, int, int, boolean) IS 'Internal: use tin_tiles_from_table(regclass, float8, int, name, int, int, int, boolean).';
"#,
    name = "tin_tiles_table_sql",
    requires = [_tin_tiles_table]
);
