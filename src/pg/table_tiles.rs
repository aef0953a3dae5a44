//! `tin_tiles_from_table`: a table of raster tiles built tile by tile, rows
//! of tiles read through SPI as they are needed.

use pgrx::prelude::*;

use super::errors::{raise, OrRaise};
use super::memory;
use super::tin_type::TinOut;
use pgrx::pg_sys;

use super::build::raster_band;
use tinmerge_core::io::raster;
use tinmerge_core::tin::build::default_tolerances;
use tinmerge_core::tin::lattice::Lattice;

/// A table of raster tiles (`raster2pgsql -t`, `ST_Tile`) being built
/// tile by tile: `tin_tiles_from_table(tiles regclass, ...)`. Rows
/// of tiles are read through SPI as they are needed (a tile row and the one
/// below it held at once), tiles are built `tinmerge.threads` at a time,
/// and each result is handed out before the next batch is built, so the
/// call's memory is bounded by two rows of tiles and one batch of builds,
/// whatever the table's size.
pub(super) struct TableTiles {
    /// `FROM` item and column, quoted.
    from: String,
    column: String,
    band: i32,
    tols: Vec<f64>,
    srid: i32,
    grid: tinmerge_core::tin::tiles::TableGrid,
    /// Each tile's name (its `ctid` when `by_ctid`, which reads it back
    /// by that; otherwise its upper-left corner), lattice and size.
    names: Vec<String>,
    by_ctid: bool,
    metas: Vec<TileSize>,
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
    /// The SQL function building, for its messages.
    func: &'static str,
}

/// The table's name as a `FROM` item and the raster column quoted, after
/// checking that the column exists and is a raster; and whether its rows
/// can be read again by `ctid` (a table or materialized view without
/// children: a `ctid` names one row). Partitioned tables, tables with
/// inheritance children, foreign tables and views are read by place
/// instead ([`TableTiles::load_rows`]): their `ctid`s repeat between
/// partitions, or they have none.
fn raster_column(func: &str, tab: pg_sys::Oid, column: &str) -> (String, String, bool) {
    let (from, quoted, is_raster, by_ctid) = Spi::connect(|c| {
        let r = c
            .select(
                "SELECT $1::regclass::text, quote_ident($2), (SELECT a.atttypid = 'raster'::regtype FROM pg_attribute a WHERE a.attrelid = $1 AND a.attname = $2 AND a.attnum > 0 AND NOT a.attisdropped), (SELECT k.relkind IN ('r', 'm') AND NOT EXISTS (SELECT 1 FROM pg_inherits i WHERE i.inhparent = k.oid) FROM pg_class k WHERE k.oid = $1)",
                None,
                &[tab.into(), column.into()],
            )?
            .first();
        Ok::<_, pgrx::spi::Error>((
            r.get::<String>(1)?.unwrap_or_default(),
            r.get::<String>(2)?.unwrap_or_default(),
            r.get::<bool>(3)?,
            r.get::<bool>(4)?.unwrap_or(false),
        ))
    })
    .unwrap_or_else(|e| raise(PgSqlErrorCode::ERRCODE_UNDEFINED_TABLE, format!("{func}: {e}")));
    match is_raster {
        None => raise(
            PgSqlErrorCode::ERRCODE_UNDEFINED_COLUMN,
            format!("{func}: column \"{column}\" of relation {from} does not exist"),
        ),
        Some(false) => raise(
            PgSqlErrorCode::ERRCODE_DATATYPE_MISMATCH,
            format!("{func}: column \"{column}\" of relation {from} is not of type raster"),
        ),
        Some(true) => {}
    }
    (from, quoted, by_ctid)
}

/// A tile's pixel lattice, width and height.
type TileSize = (Lattice, usize, usize);

/// The relations of `tab`'s tree that hold rows (itself, or its
/// partitions and inheritance children, recursively), as `FROM` items.
fn leaves(func: &str, tab: pg_sys::Oid) -> Vec<String> {
    Spi::connect(|c| {
        let mut out = Vec::new();
        for row in c.select(
            "WITH RECURSIVE t(r) AS (SELECT $1::oid UNION SELECT i.inhrelid FROM pg_inherits i JOIN t ON i.inhparent = t.r) \
             SELECT CASE WHEN EXISTS (SELECT 1 FROM pg_inherits i WHERE i.inhparent = t.r) THEN 'ONLY ' ELSE '' END || t.r::regclass::text \
             FROM t JOIN pg_class k ON k.oid = t.r WHERE k.relkind <> 'p'",
            None,
            &[tab.into()],
        )? {
            out.push(row.get::<String>(1)?.unwrap_or_default());
        }
        Ok::<_, pgrx::spi::Error>(out)
    })
    .unwrap_or_else(|e| raise(PgSqlErrorCode::ERRCODE_INTERNAL_ERROR, format!("{func}: {e}")))
}

/// Every tile's name ([`TableTiles::names`]), lattice and size (PostGIS
/// reads the headers only) and SRID, refusing a tile without band `band`. Read by place
/// (`!by_ctid`), the headers come from each relation holding rows in
/// arrays, one aggregate each: postgres_fdw computes such an aggregate on
/// the remote node (with `postgis_raster` in the server's `extensions`),
/// where a plain select would fetch every raster whole.
fn tile_headers(
    func: &str,
    tab: pg_sys::Oid,
    from: &str,
    quoted: &str,
    band: i32,
    by_ctid: bool,
) -> (Vec<String>, Vec<TileSize>, Vec<i32>) {
    // every tile's geotransform and size (PostGIS reads the header only)
    let q = if by_ctid {
        format!(
            "SELECT ctid::text, (m).upperleftx, (m).upperlefty, (m).width, (m).height, (m).scalex, (m).scaley, (m).skewx, (m).skewy, (m).srid, (m).numbands FROM (SELECT ctid, ST_MetaData({quoted}) AS m FROM {from} WHERE {quoted} IS NOT NULL) s"
        )
    } else {
        let fs = [
            "ST_UpperLeftX",
            "ST_UpperLeftY",
            "ST_Width",
            "ST_Height",
            "ST_ScaleX",
            "ST_ScaleY",
            "ST_SkewX",
            "ST_SkewY",
            "ST_SRID",
            "ST_NumBands",
        ];
        let aggs: Vec<String> = fs
            .iter()
            .enumerate()
            .map(|(i, f)| format!("array_agg({f}({quoted})) AS a{i}"))
            .collect();
        let cols: Vec<String> = (0..fs.len()).map(|i| format!("s.a{i}")).collect();
        let leaves = leaves(func, tab);
        if leaves.is_empty() {
            // a partitioned table without partitions: no tiles
            return (Vec::new(), Vec::new(), Vec::new());
        }
        leaves
            .iter()
            .map(|leaf| {
                format!(
                    "SELECT NULL::text, u.* FROM (SELECT {} FROM {leaf} WHERE {quoted} IS NOT NULL) s, unnest({}) u",
                    aggs.join(", "),
                    cols.join(", ")
                )
            })
            .collect::<Vec<_>>()
            .join(" UNION ALL ")
    };
    let mut names = Vec::new();
    let mut metas = Vec::new();
    let mut srids = Vec::new();
    Spi::connect(|c| {
        for row in c.select(&q, None, &[])? {
            let f = |i: usize| row.get::<f64>(i).map(|v| v.unwrap_or(f64::NAN));
            let n = |i: usize| row.get::<i32>(i).map(|v| v.unwrap_or(0));
            let ctid = row.get::<String>(1)?.unwrap_or_default();
            let lattice = Lattice {
                ip_x: f(2)?,
                ip_y: f(3)?,
                scale_x: f(6)?,
                scale_y: f(7)?,
                skew_x: f(8)?,
                skew_y: f(9)?,
            };
            let (w, h, nb) = (n(4)?, n(5)?, n(11)?);
            let name = if by_ctid {
                ctid
            } else {
                format!("upper-left ({}, {})", lattice.ip_x, lattice.ip_y)
            };
            if nb < band {
                raise(
                    PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
                    format!(
                        "{func}: the tile at {name} of {from} has {nb} band(s), no band {band}"
                    ),
                );
            }
            metas.push((lattice, w.max(0) as usize, h.max(0) as usize));
            srids.push(n(10)?);
            names.push(name);
        }
        Ok::<_, pgrx::spi::Error>(())
    })
    .unwrap_or_else(|e| {
        raise(
            PgSqlErrorCode::ERRCODE_INTERNAL_ERROR,
            format!("{func}: reading {from}: {e}"),
        )
    });
    (names, metas, srids)
}

impl TableTiles {
    /// The table's tiles placed on their common lattice.
    pub(super) fn grid(&self) -> &tinmerge_core::tin::tiles::TableGrid {
        &self.grid
    }

    /// The tiles' SRID (0 without tiles).
    pub(super) fn srid(&self) -> i32 {
        self.srid
    }

    /// The table as a `FROM` item.
    pub(super) fn from(&self) -> &str {
        &self.from
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
        use tinmerge_core::tin::tiles::{place_tiles, slice_rows};
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
        let (from, quoted, by_ctid) = raster_column(func, tab, column);
        let (names, metas, srids) = tile_headers(func, tab, &from, &quoted, band, by_ctid);
        if let Some(k) = srids.iter().position(|&s| s != srids[0]) {
            raise(
                PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
                format!(
                    "{func}: the tiles of {from} have different SRIDs ({} at {}, {} at {})",
                    srids[0], names[0], srids[k], names[k]
                ),
            );
        }
        let grid = if metas.is_empty() {
            tinmerge_core::tin::tiles::TableGrid {
                lattice: Lattice {
                    ip_x: 0.0,
                    ip_y: 0.0,
                    scale_x: 1.0,
                    scale_y: -1.0,
                    skew_x: 0.0,
                    skew_y: 0.0,
                },
                tile_width: 1,
                tile_height: 1,
                tiles: Vec::new(),
            }
        } else {
            place_tiles(&metas).unwrap_or_else(|e| {
                raise(
                    PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
                    format!("{func}: the tiles of {from}: {e}"),
                )
            })
        };
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
            from,
            column: quoted,
            band,
            tols,
            srid: srids.first().copied().unwrap_or(0),
            grid,
            names,
            by_ctid,
            metas,
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
            func,
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
                    self.grid
                        .tiles_holding(c, r)
                        .into_iter()
                        .filter_map(|t| self.at.get(&t).copied()),
                );
            }
        }
        self.round += 1;
        let grid = &self.grid;
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

    /// Read the bands of tile rows `rows` not read yet, and forget the
    /// rows above the first.
    fn load_rows(&mut self, rows: std::ops::RangeInclusive<usize>) {
        let func = self.func;
        let grid = &self.grid;
        self.loaded
            .retain(|&k, _| grid.tiles[k].ty >= *rows.start());
        let want: Vec<usize> = (0..grid.tiles.len())
            .filter(|&k| {
                let ty = grid.tiles[k].ty;
                rows.contains(&ty) && self.plan.contains(&ty) && !self.loaded.contains_key(&k)
            })
            .collect();
        if want.is_empty() {
            return;
        }
        let px: usize = want
            .iter()
            .map(|&k| grid.tiles[k].width * grid.tiles[k].height)
            .sum();
        memory::reserve(px.saturating_mul(8), || {
            format!(
                "{func}: reading {} tiles of {} ({px} pixels)",
                want.len(),
                self.from
            )
        });
        // the wanted tiles by the key each row read gives: its ctid, or its
        // upper-left corner (bit for bit the header's: the same raster's)
        let key = |k: usize| {
            if self.by_ctid {
                self.names[k].clone()
            } else {
                let l = &self.metas[k].0;
                format!("{:016x}{:016x}", l.ip_x.to_bits(), l.ip_y.to_bits())
            }
        };
        let wanted: std::collections::HashMap<String, usize> =
            want.iter().map(|&k| (key(k), k)).collect();
        let (q, args): (String, Vec<pgrx::datum::DatumWithOid>) = if self.by_ctid {
            let ctids: Vec<String> = want.iter().map(|&k| self.names[k].clone()).collect();
            (
                format!(
                    "SELECT ctid::text, {c}::bytea FROM {f} WHERE ctid = ANY($1::text[]::tid[])",
                    c = self.column,
                    f = self.from
                ),
                vec![ctids.into()],
            )
        } else {
            // the box of the wanted tiles, a quarter pixel inside on a
            // north-up grid (so tiles that only touch it are not read;
            // rows of a skewed grid's other tiles met are passed over)
            let mut b = [
                f64::INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::NEG_INFINITY,
            ];
            for &k in &want {
                let (l, w, h) = self.metas[k];
                // the tile's corners: pixel centres half a pixel back
                for (c, r) in [(0, 0), (w, 0), (0, h), (w, h)] {
                    let (x, y) = l.centre(c as f64 - 0.5, r as f64 - 0.5);
                    b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
                }
            }
            let l = &self.grid.lattice;
            if l.skew_x == 0.0 && l.skew_y == 0.0 {
                let (qx, qy) = (0.25 * l.scale_x.abs(), 0.25 * l.scale_y.abs());
                b = [b[0] + qx, b[1] + qy, b[2] - qx, b[3] - qy];
            }
            (
                format!(
                    "SELECT encode(float8send((m).upperleftx), 'hex') || encode(float8send((m).upperlefty), 'hex'), r FROM (SELECT ST_MetaData({c}) AS m, {c}::bytea AS r FROM {f} WHERE {c} && ST_MakeEnvelope($1, $2, $3, $4, $5)) s",
                    c = self.column,
                    f = self.from
                ),
                vec![b[0].into(), b[1].into(), b[2].into(), b[3].into(), self.srid.into()],
            )
        };
        let mut got = Vec::with_capacity(want.len());
        let mut read = std::collections::HashSet::with_capacity(want.len());
        Spi::connect(|c| {
            let mut table = c.select(&q, None, &args)?;
            while table.next().is_some() {
                let name = table.get::<String>(1)?.unwrap_or_default();
                let Some(&k) = wanted.get(name.as_str()) else {
                    continue;
                };
                // The raw datum, detoasted here in SPI's own memory context
                // (freed by SPI_finish at the end of this batch): `get::<&[u8]>`
                // would copy every tile's bytes into the parent context,
                // which lives as long as the transaction (the whole raster
                // held by the end of the call: 650 MB for 100 million pixels).
                let Some(datum) = table.get_datum_by_ordinal(2)? else {
                    continue;
                };
                // SAFETY: a non-NULL bytea of the SPI tuple table, valid
                // until SPI_finish; the slice is only read inside this closure.
                let bytes: &[u8] = unsafe {
                    pgrx::varlena::varlena_to_byte_slice(pg_sys::pg_detoast_datum_packed(
                        datum.cast_mut_ptr(),
                    ))
                };
                let (r, b) = raster_band(bytes, self.band);
                let p = &self.grid.tiles[k];
                if (r.width, r.height) != (p.width, p.height) || !read.insert(k) {
                    raise(
                        PgSqlErrorCode::ERRCODE_OBJECT_NOT_IN_PREREQUISITE_STATE,
                        format!(
                            "{func}: the tile at {} of {} changed during the build",
                            self.names[k], self.from
                        ),
                    );
                }
                got.push((k, b));
            }
            Ok::<_, pgrx::spi::Error>(())
        })
        .unwrap_or_else(|e| {
            raise(
                PgSqlErrorCode::ERRCODE_INTERNAL_ERROR,
                format!("{func}: reading {}: {e}", self.from),
            )
        });
        if got.len() != want.len() {
            raise(
                PgSqlErrorCode::ERRCODE_OBJECT_NOT_IN_PREREQUISITE_STATE,
                format!(
                    "{func}: tiles of {} changed during the build (read {} of {})",
                    self.from,
                    got.len(),
                    want.len()
                ),
            );
        }
        self.loaded.extend(got);
    }

    /// Build the next batch of tiles (one per thread) into `ready`.
    fn build_batch(&mut self) {
        let func = self.func;
        use tinmerge_core::tin::tile_domain::build_tile_window;
        use tinmerge_core::tin::tiles::{keep_border_samples, keep_border_window, Block};
        let threads = tinmerge_core::tin::par::threads().max(1);
        let batch: Vec<usize> =
            self.order[self.next..(self.next + threads).min(self.order.len())].to_vec();
        self.next += batch.len();
        let (first, last) = (
            self.grid.tiles[batch[0]].ty,
            self.grid.tiles[batch[batch.len() - 1]].ty,
        );
        self.load_rows(first..=last + 1);
        let per_tile = (self.grid.tile_width + 1) * (self.grid.tile_height + 1);
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
                place: self.grid.tiles[k],
                values: &self.loaded.get(&k)?.values,
                valid: valids.get(&k)?.as_ref(),
            })
        };
        let (lattice, tols, srid) = (self.grid.lattice, &self.tols, self.srid);
        let (seams, planning, fill_gaps) = (&self.seams, self.planning, self.fill_gaps);
        let built = tinmerge_core::tin::par::map(&batch, |&k| {
            let p = self.grid.tiles[k];
            let own = block(p.tx, p.ty)?;
            let (right, below) = (block(p.tx + 1, p.ty), block(p.tx, p.ty + 1));
            let s = keep_border_samples(
                &own,
                right.as_ref(),
                below.as_ref(),
                block(p.tx + 1, p.ty + 1).as_ref(),
            );
            let keep = seams.border(
                p.col..p.col + p.width as i64 + 1,
                p.row..p.row + p.height as i64 + 1,
            );
            let size = keep_border_window(&own, right.as_ref(), below.as_ref());
            let tile = build_tile_window(
                s,
                &lattice,
                (p.col, p.row),
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
                    format!("{}: a tile of the batch was not read", self.func),
                );
            };
            if let Some((row, wanted)) = r.or_raise() {
                self.ready.extend(row);
                self.asked.push(wanted);
            }
        }
    }
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
                    return None;
                }
                self.end_round();
                continue;
            }
            pgrx::check_for_interrupts!();
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
