//! A table of raster tiles (`raster2pgsql -t`, `ST_Tile`) as a source of
//! tiles: where each lies on the table's common lattice (its headers
//! only), and the bands of any of them read again on demand, by `ctid` or
//! by place. `tin_tiles_from_table` and `tin_overviews` build from it
//! ([`super::table_tiles`]); an overview layer also reads its base table's
//! tiles under its nodata pixels ([`tinmerge_core::tin::cover`]).

use pgrx::pg_sys;
use pgrx::prelude::*;

use super::build::raster_band;
use super::errors::raise;
use super::memory;
use tinmerge_core::io::raster;
use tinmerge_core::tin::lattice::Lattice;
use tinmerge_core::tin::tiles::TableGrid;

/// A table of raster tiles: its tiles' places and how to read them.
pub(super) struct TableSource {
    /// `FROM` item and column, quoted.
    pub(super) from: String,
    pub(super) column: String,
    pub(super) band: i32,
    /// The tiles' SRID (0 without tiles).
    pub(super) srid: i32,
    pub(super) grid: TableGrid,
    /// Each tile's name (its `ctid` when `by_ctid`, which reads it back
    /// by that; otherwise its upper-left corner), lattice and size.
    pub(super) names: Vec<String>,
    by_ctid: bool,
    pub(super) metas: Vec<TileSize>,
    /// The SQL function building, for its messages.
    pub(super) func: &'static str,
}

impl TableSource {
    /// The tiles of `tab`'s raster column `column` (band `band` must be in
    /// each), placed on their common lattice.
    pub(super) fn open(
        func: &'static str,
        tab: pg_sys::Oid,
        column: &str,
        band: i32,
    ) -> TableSource {
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
            TableGrid {
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
            tinmerge_core::tin::tiles::place_tiles(&metas).unwrap_or_else(|e| {
                raise(
                    PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
                    format!("{func}: the tiles of {from}: {e}"),
                )
            })
        };
        TableSource {
            from,
            column: quoted,
            band,
            srid: srids.first().copied().unwrap_or(0),
            grid,
            names,
            by_ctid,
            metas,
            func,
        }
    }

    /// Tile `k`'s box `[xmin, ymin, xmax, ymax]`: its pixels' squares and
    /// `ring` more pixels all round.
    pub(super) fn tile_box(&self, k: usize, ring: usize) -> [f64; 4] {
        let (l, w, h) = self.metas[k];
        let mut b = [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ];
        let g = ring as f64;
        for (c, r) in [(0, 0), (w, 0), (0, h), (w, h)] {
            let (c, r) = (
                c as f64 + if c == 0 { -g } else { g },
                r as f64 + if r == 0 { -g } else { g },
            );
            let (x, y) = l.centre(c - 0.5, r - 0.5);
            b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
        }
        b
    }

    /// The tiles whose boxes overlap `b` (more than touch it).
    pub(super) fn meeting(&self, b: [f64; 4]) -> Vec<usize> {
        (0..self.metas.len())
            .filter(|&k| {
                let t = self.tile_box(k, 0);
                t[0] < b[2] && b[0] < t[2] && t[1] < b[3] && b[1] < t[3]
            })
            .collect()
    }

    /// The bands of tiles `want` (indexes into `grid.tiles`), each read
    /// once, in any order; an ERROR when a tile changed or went away.
    pub(super) fn read(&self, want: &[usize]) -> Vec<(usize, raster::Band)> {
        let func = self.func;
        if want.is_empty() {
            return Vec::new();
        }
        let px: usize = want
            .iter()
            .map(|&k| self.grid.tiles[k].width * self.grid.tiles[k].height)
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
            for &k in want {
                let t = self.tile_box(k, 0);
                b = [
                    b[0].min(t[0]),
                    b[1].min(t[1]),
                    b[2].max(t[2]),
                    b[3].max(t[3]),
                ];
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
        got
    }
}

/// The table's name as a `FROM` item and the raster column quoted, after
/// checking that the column exists and is a raster; and whether its rows
/// can be read again by `ctid` (a table or materialized view without
/// children: a `ctid` names one row). Partitioned tables, tables with
/// inheritance children, foreign tables and views are read by place
/// instead ([`TableSource::read`]): their `ctid`s repeat between
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
pub(super) type TileSize = (Lattice, usize, usize);

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

/// Every tile's name ([`TableSource::names`]), lattice and size (PostGIS
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
