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
use tinmerge_core::tin::seam_rounds::{Held, SeamRounds, Step, TileReader};
use tinmerge_core::tin::TinError;

/// A table of raster tiles (`raster2pgsql -t`, `ST_Tile`) being built
/// tile by tile: `tin_tiles_from_table(tiles regclass, ...)`, its seam
/// rounds run by the core ([`SeamRounds`]). Rows of tiles are read through
/// SPI as they are needed (a tile row and the one below it held at once),
/// tiles are built `tinmerge.threads` at a time, and each tile's last
/// build is held ([`SeamRounds::hold`]) while the results fit in a quarter
/// of `tinmerge.max_memory`: the stored tins, about 100 MB for a billion pixels.
/// Past that they are dropped and every tile is built once more at the
/// end, each result handed out before the next batch is built, so the
/// call's memory stays bounded by two rows of tiles and one batch of
/// builds, whatever the table's size.
pub(super) struct TableTiles {
    /// The table's tiles.
    src: std::sync::Arc<TableSource>,
    /// An overview layer's base table: its tiles under the overview's
    /// nodata pixels give them data ([`tinmerge_core::tin::cover`]).
    cover: Option<std::sync::Arc<TableSource>>,
    rounds: SeamRounds,
    ready: std::collections::VecDeque<(i32, i32, TinOut)>,
    /// Each tile's last build, while held.
    held: Held<(i32, i32, TinOut)>,
    done: bool,
    /// Progress reported (`super::progress`), its phases named after
    /// `label` (an overview layer's).
    tracker: super::progress::Tracker,
    label: String,
}

/// A table's tiles read through SPI, an overview's nodata pixels given
/// the data of its base's pixels under them.
struct Reader<'a> {
    src: &'a TableSource,
    cover: Option<&'a TableSource>,
}

impl TileReader for Reader<'_> {
    fn read(&mut self, want: &[usize]) -> Result<Vec<(usize, raster::Band)>, TinError> {
        let mut got = self.src.read(want);
        if let Some(base) = self.cover {
            for (k, band) in got.iter_mut() {
                if Cover::needed(band) {
                    cover(self.src, *k, band, base);
                }
            }
        }
        Ok(got)
    }
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
        self.rounds.covering(&self.src.grid, &base.grid);
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
        let mut rounds = SeamRounds::new(
            &src.grid,
            tols,
            src.srid,
            fill_gaps,
            (slice as usize, slices as usize),
        );
        rounds.hold();
        super::threads::apply();
        TableTiles {
            src: std::sync::Arc::new(src),
            cover: None,
            rounds,
            ready: Default::default(),
            held: Held::new(memory::limit().map_or(usize::MAX, |l| l / 4), |r| {
                r.2 .0.len()
            }),
            done: false,
            tracker: super::progress::Tracker::new(func),
            label: String::new(),
        }
    }

    /// Build the next batch of tiles into `ready`; `done` after the last.
    fn build_batch(&mut self) {
        let (src, label, tracker) = (&self.src, &self.label, &mut self.tracker);
        let mut reader = Reader {
            src,
            cover: self.cover.as_deref(),
        };
        let lattice = src.grid.lattice;
        let per_tile = (src.grid.tile_width + 1) * (src.grid.tile_height + 1);
        let levels = self.rounds.tolerances().len();
        let (holding, let_go) = (self.rounds.holding(), self.held.dropped());
        let mut before = |s: Step| {
            pgrx::check_for_interrupts!();
            let phase = if holding && s.round == 0 {
                format!("{label}building tiles")
            } else if holding {
                format!(
                    "{label}building tiles again with their seams' samples (round {})",
                    s.round
                )
            } else if s.planning {
                format!(
                    "{label}planning the seams (round {}): building tiles",
                    s.round + 1
                )
            } else if let_go {
                format!("{label}building tiles once more (their builds were past a quarter of tinmerge.max_memory)")
            } else {
                format!("{label}building tiles")
            };
            tracker.set(&phase, "tiles", s.done as u64, s.total as u64);
            memory::reserve(
                tinmerge_core::tin::build::lattice_build_bytes(per_tile, levels, true)
                    .saturating_mul(s.tiles),
                || {
                    format!(
                        "{}: building {} tiles of {per_tile} samples at {levels} levels at once",
                        src.func, s.tiles
                    )
                },
            );
            Ok(())
        };
        let each = |tx: usize, ty: usize, t: tinmerge_core::tin::Tin| {
            (tx as i32, ty as i32, TinOut::from_tin_on(&t, &lattice))
        };
        match self
            .rounds
            .next_held(&mut self.held, &src.grid, &mut reader, &each, &mut before)
            .or_raise()
        {
            Some(rows) => self.ready.extend(rows),
            None => self.done = true,
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
            if self.done {
                self.tracker.finish();
                return None;
            }
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
