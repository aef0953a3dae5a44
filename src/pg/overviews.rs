//! `tin_overviews`: one terrain from zoom 0 to the finest, as a pyramid of
//! tiled terrains. The table of raster tiles and each of its PostGIS
//! overviews (`raster_overviews`: `raster2pgsql -l`, `ST_CreateOverview`)
//! is built as `tin_tiles_from_table` builds it (an overview of factor
//! `f` with `f` times the tolerance), and each layer's rows
//! carry the zooms it serves (`serve::tiling::pyramid_zooms`: the
//! coarsest layer whose pixels are as fine as the detail Cesium expects
//! of the zoom), so a quantized-mesh tile reads the tins of one layer
//! only, at most 2 x 2 of them when they are 128 pixels a side or more.

use pgrx::pg_sys;
use pgrx::prelude::*;

use super::errors::raise;
use super::table_tiles::TableTiles;
use super::tin_type::TinOut;
use tinmerge_core::serve::tiling::pyramid_zooms;

/// The layers of the pyramid being built, finest first, each with its
/// overview factor (1: the table itself) and zooms; the layer being
/// returned is the first.
struct Pyramid {
    layers: std::collections::VecDeque<(i32, (i32, i32), TableTiles)>,
}

/// The overviews PostGIS lists for `tab`'s raster column `column`
/// (`raster_overviews`), as (table, its raster column, factor), by factor.
fn overviews_of(tab: pg_sys::Oid, column: &str) -> Vec<(pg_sys::Oid, String, i32)> {
    Spi::connect(|c| {
        let mut out = Vec::new();
        let rows = c.select(
            "SELECT pg_catalog.format('%I.%I', o.o_table_schema, o.o_table_name)::regclass::oid, o.o_raster_column::text, o.overview_factor \
             FROM raster_overviews o, pg_catalog.pg_class k, pg_catalog.pg_namespace n \
             WHERE k.oid = $1 AND n.oid = k.relnamespace AND o.r_table_schema = n.nspname AND o.r_table_name = k.relname \
               AND o.r_raster_column = $2 AND o.overview_factor > 1 \
             ORDER BY o.overview_factor",
            None,
            &[tab.into(), column.into()],
        )?;
        for row in rows {
            if let (Some(oid), Some(col), Some(f)) = (
                row.get::<pg_sys::Oid>(1)?,
                row.get::<String>(2)?,
                row.get::<i32>(3)?,
            ) {
                out.push((oid, col, f));
            }
        }
        Ok::<_, pgrx::spi::Error>(out)
    })
    .unwrap_or_else(|e| {
        raise(
            PgSqlErrorCode::ERRCODE_INTERNAL_ERROR,
            format!("tin_overviews: reading raster_overviews: {e}"),
        )
    })
}

/// The size in degrees of a layer's pixels: its tiles' extent through
/// PostGIS's `ST_Transform` (segmentized, so curved edges count) over its
/// pixel columns and rows, the larger; None without tiles.
fn pixel_degrees(layer: &TableTiles) -> Option<f64> {
    let grid = layer.grid();
    let b = grid.extent()?;
    let cols = grid.tiles.iter().map(|p| p.col + p.width as i64).max()?
        - grid.tiles.iter().map(|p| p.col).min()?;
    let rows = grid.tiles.iter().map(|p| p.row + p.height as i64).max()?
        - grid.tiles.iter().map(|p| p.row).min()?;
    let srid = layer.srid();
    if srid <= 0 {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!(
                "tin_overviews: the tiles of {} have no SRID: the zooms a layer serves are measured in degrees",
                layer.from()
            ),
        );
    }
    let d = Spi::connect(|c| {
        let row = c
            .select(
                "SELECT ST_XMin(g), ST_YMin(g), ST_XMax(g), ST_YMax(g) FROM (SELECT ST_Transform(ST_Segmentize(ST_MakeEnvelope($1, $2, $3, $4, $5), greatest($3 - $1, $4 - $2) / 64), 4326) AS g) s",
                None,
                &[b[0].into(), b[1].into(), b[2].into(), b[3].into(), srid.into()],
            )?
            .first();
        Ok::<_, pgrx::spi::Error>([
            row.get::<f64>(1)?,
            row.get::<f64>(2)?,
            row.get::<f64>(3)?,
            row.get::<f64>(4)?,
        ])
    })
    .unwrap_or_else(|e| {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!("tin_overviews: the extent of {} in degrees: {e}", layer.from()),
        )
    });
    let [Some(w), Some(s), Some(e), Some(n)] = d else {
        return None;
    };
    Some(((e - w) / cols.max(1) as f64).max((n - s) / rows.max(1) as f64))
}

impl Iterator for Pyramid {
    type Item = (i32, i32, i32, i32, i32, TinOut);
    fn next(&mut self) -> Option<Self::Item> {
        loop {
            let (factor, (lo, hi), layer) = self.layers.front_mut()?;
            if let Some((tx, ty, t)) = layer.next() {
                return Some((*factor, *lo, *hi, tx, ty, t));
            }
            self.layers.pop_front();
        }
    }
}

/// `tin_overviews(tiles regclass, tolerance, levels, rast_column, band,
/// slice, slices, fill_gaps)`: the table and each overview PostGIS lists
/// for it, built as `tin_tiles_from_table` builds a table, with the zooms
/// each layer serves (the SQL wrapper passes the table's OID and the
/// column's name).
#[allow(clippy::too_many_arguments)]
#[pg_extern(stable, strict, parallel_restricted, cost = 100000, requires = ["tin_type"])]
fn _tin_overviews(
    tab: pg_sys::Oid,
    column: &str,
    tolerance: f64,
    levels: i32,
    band: i32,
    slice: i32,
    slices: i32,
    fill_gaps: bool,
) -> TableIterator<
    'static,
    (
        name!(factor, i32),
        name!(minzoom, i32),
        name!(maxzoom, i32),
        name!(tx, i32),
        name!(ty, i32),
        name!(t, TinOut),
    ),
> {
    let mut layers: Vec<(i32, f64, TableTiles)> = Vec::new();
    let mut sources = vec![(tab, column.to_string(), 1)];
    sources.extend(overviews_of(tab, column));
    let mut base: Option<std::sync::Arc<super::table_source::TableSource>> = None;
    for (oid, col, factor) in sources {
        // a layer of pixels `factor` times larger holds `factor` times the
        // tolerance: the same ratio of error to pixel size, which is what
        // the zooms it serves ask of it
        let mut layer = TableTiles::open(
            "tin_overviews",
            oid,
            &col,
            tolerance * factor as f64,
            levels,
            band,
            (slice, slices),
            fill_gaps,
        );
        // an overview's nodata pixels with data of the table under them
        // take it, so that every layer covers the table's data
        if factor == 1 {
            base = Some(layer.source());
        } else if let Some(base) = &base {
            layer = layer.covering(base.clone());
        }
        let layer = layer.labelled(format!("layer x{factor}: "));
        if let Some(d) = pixel_degrees(&layer) {
            let first = layers.first().map(|l| (l.2.srid(), l.2.from().to_string()));
            if let Some((srid, from)) = first.filter(|f| f.0 != layer.srid()) {
                raise(
                    PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
                    format!(
                        "tin_overviews: the overview {} has SRID {}, its table {from} has SRID {srid}",
                        layer.from(),
                        layer.srid(),
                    ),
                );
            }
            layers.push((factor, d, layer));
        }
    }
    // finest first (by the size of their pixels, whatever the factors say)
    layers.sort_by(|a, b| a.1.total_cmp(&b.1));
    let zooms = pyramid_zooms(&layers.iter().map(|l| l.1).collect::<Vec<_>>());
    let layers = layers
        .into_iter()
        .zip(zooms)
        .filter_map(|((factor, _, layer), z)| Some((factor, z?, layer)))
        .collect();
    TableIterator::new(Pyramid { layers })
}

extension_sql!(
    r#"
ALTER FUNCTION _tin_overviews(oid, text, float8, int, int, int, int, boolean) ROWS 100;
COMMENT ON FUNCTION _tin_overviews(oid, text, float8, int, int, int, int, boolean) IS 'Internal: use tin_overviews(regclass, float8, int, name, int, int, int, boolean).';
"#,
    name = "tin_overviews_sql",
    requires = [_tin_overviews]
);
