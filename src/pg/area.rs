//! SQL functions of the area merge: `tin_area_triangles`, `tin_area_stats`,
//! `tin_volume`. They take the `geometry` itself (read in PostGIS's
//! serialisation) and ask PostGIS's `ST_IsValidReason` for its verdict by
//! OID, so no SQL wrapper is planned per call (0.7.0; the first call of a
//! backend was 0.13 ms slower through the wrapper). `ST_IsValidReason` and
//! `spatial_ref_sys` are found in PostGIS's schema (`args::postgis`), so
//! they pin no search_path (since 0.27.0: a pinned one cost every call a
//! configuration change). Not
//! STRICT (a NULL level means finest): a NULL tin, polygon or base height
//! gives no rows. The `_tin_*` entry points of 0.6.0 and earlier (EWKB and
//! the verdict as arguments) are in [`super::compat`].

use pgrx::prelude::*;
use std::cell::RefCell;
use std::collections::HashMap;
use std::rc::Rc;

use super::args::{check_srid, GeomArg};
use super::cache;
use super::errors::{raise, OrRaise};
use super::interrupt::interrupt;
use super::tin_type::TinArg;
use tinmerge_core::geom::{is_strictly_convex_ring, Spheroid, Units};
use tinmerge_core::io::ewkb::{self, Ewkb, Geom};
use tinmerge_core::io::gserialized;
use tinmerge_core::merge::area::polygon::{Area, Where};
use tinmerge_core::merge::area::surface::{
    stats_with, volume_parts_with, SubtreeSums, SurfaceStats, VolumeParts,
};
use tinmerge_core::merge::area::whole;
use tinmerge_core::merge::area::{area_rows, sweep, Method, Sweep};
use tinmerge_core::tin::mesh::Indexed;
use tinmerge_core::tin::Bbox;
use tinmerge_core::tin::TinError;

/// The area of a POLYGON or MULTIPOLYGON argument: SRID checked, validity
/// (PostGIS's verdict, unless the polygon is one strictly convex ring)
/// checked, coordinates finite.
fn area_arg(g: Ewkb, validity: &dyn Fn() -> Option<String>, tin_srid: i32, func: &str) -> Area {
    check_srid(
        g.srid,
        tin_srid,
        func,
        "area",
        super::args::first_xy(&g.geom),
    );
    let polys = match g.geom {
        Geom::Polygon(p) => vec![p],
        Geom::MultiPolygon(ps) => ps,
        other => raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!(
                "{func} takes a POLYGON or MULTIPOLYGON, got a {}{}",
                other.type_name(),
                match other {
                    Geom::Collection(_) => " (use ST_CollectionExtract(geom, 3) for its polygons)",
                    Geom::LineString(_) | Geom::MultiLineString(_) =>
                        " (use ST_MakePolygon for a closed line, or tin_line_triangles)",
                    _ => "",
                }
            ),
        ),
    };
    // a polygon with one strictly convex ring is valid: PostGIS's verdict
    // (a GEOS call, a tenth of a millisecond on a backend's first call) is
    // asked for the others only
    let plainly_valid = matches!(&polys[..], [p] if p.len() == 1 && is_strictly_convex_ring(&p[0]));
    if let Some(reason) = (!plainly_valid).then(validity).flatten() {
        if reason != "Valid Geometry" {
            raise(
                PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
                format!("{func}: the polygon is not valid ({reason}); repair it with ST_MakeValid"),
            );
        }
    }
    for c in polys.iter().flatten().flatten() {
        tinmerge_core::tin::check_xy(format_args!("{func}: the polygon"), c[0], c[1]).or_raise();
    }
    Area::new(
        polys
            .into_iter()
            .map(|p| {
                p.into_iter()
                    .map(|r| r.into_iter().map(|c| [c[0], c[1]]).collect())
                    .collect()
            })
            .collect(),
    )
}

/// A polygon argument as it was passed ([`GeomArg::as_passed`]: its bytes,
/// compressed form or TOAST pointer), the transaction a TOAST pointer was
/// met in, the tin SRID it was checked against, and the area made of it.
type KeptArea = (Vec<u8>, Option<i64>, i32, Rc<Area>);

thread_local! {
    /// The polygons this backend read last, checked, as areas, keyed by
    /// the argument as passed, the most recent first: a join of one
    /// polygon with many tiles (a county over a tiled terrain) reads,
    /// checks and indexes it once, not once per tile (PostGIS's validity
    /// verdict on 4,000 vertices is a millisecond), and does not even
    /// detoast or decompress it again (12 % of a county's join); a plan
    /// that takes the tiles in the outer loop and the polygons in the inner
    /// (rows of a few polygons interleaved) finds each of them here too.
    static KEPT_AREAS: RefCell<Vec<KeptArea>> = const { RefCell::new(Vec::new()) };
}

/// At most this many polygons are kept by [`KEPT_AREAS`]...
const KEPT_AREAS_MAX: usize = 16;
/// ... passed in this many bytes together at most (a polygon passed in
/// more is not kept).
const KEPT_AREAS_BYTES: usize = 16 << 20;

/// A `geometry` argument read whole from PostGIS's serialisation, with
/// PostGIS's validity verdict asked for only once it is known to be polygonal
/// (an argument kept in [`KEPT_AREAS`] for the same SRID: the area checked
/// then, the same bits).
pub(super) fn geom_area(g: &GeomArg, tin_srid: i32, func: &str) -> Rc<Area> {
    let passed = g.as_passed();
    // a TOAST pointer names one value only within a transaction
    let key = passed.map(|(b, on_disk)| (b, on_disk.then(super::tin_type::transaction_epoch)));
    let held = key.and_then(|(b, epoch)| {
        KEPT_AREAS.with(|c| {
            let mut kept = c.borrow_mut();
            let i = kept.iter().position(|(kb, ke, srid, _)| {
                *srid == tin_srid && *ke == epoch && kb.as_slice() == b
            })?;
            // the most recent first
            kept[..=i].rotate_right(1);
            Some(kept[0].3.clone())
        })
    });
    if let Some(a) = held {
        return a;
    }
    let a = Rc::new(area_arg(
        gserialized::read(g.bytes()).or_raise(),
        &|| Some(g.postgis_validity()),
        tin_srid,
        func,
    ));
    if let Some((b, epoch)) = key.filter(|(b, _)| b.len() <= KEPT_AREAS_BYTES) {
        KEPT_AREAS.with(|c| {
            let mut kept = c.borrow_mut();
            kept.insert(0, (b.to_vec(), epoch, tin_srid, a.clone()));
            let mut bytes = 0;
            let keep = kept
                .iter()
                .take(KEPT_AREAS_MAX)
                .take_while(|k| {
                    bytes += k.0.len();
                    bytes <= KEPT_AREAS_BYTES
                })
                .count();
            kept.truncate(keep);
        });
    }
    a
}

/// An EWKB argument of the `_tin_*` entry points of 0.6.0 and earlier, with
/// the verdict their SQL wrapper computed.
pub(super) fn ewkb_area(
    bytes: &[u8],
    validity: Option<&str>,
    tin_srid: i32,
    func: &str,
) -> Rc<Area> {
    Rc::new(area_arg(
        ewkb::read(bytes).or_raise(),
        &|| validity.map(str::to_string),
        tin_srid,
        func,
    ))
}

/// The proj4text and srtext of `srid` in PostGIS's spatial_ref_sys (found
/// in PostGIS's schema, whatever the search_path), None when it has no row.
fn srs_text(srid: i32) -> Option<(String, String)> {
    let (schema, _) = super::args::postgis();
    let (proj4, srtext) = Spi::get_two_with_args::<String, String>(
        &format!(
            "SELECT (SELECT s.proj4text FROM {schema}.spatial_ref_sys s WHERE s.srid OPERATOR(pg_catalog.=) $1), \
                    (SELECT s.srtext FROM {schema}.spatial_ref_sys s WHERE s.srid OPERATOR(pg_catalog.=) $1)"
        ),
        &[srid.into()],
    )
    .unwrap_or_else(|e| {
        raise(
            PgSqlErrorCode::ERRCODE_UNDEFINED_TABLE,
            format!("could not read SRID {srid} from PostGIS's spatial_ref_sys: {e}"),
        )
    });
    (proj4.is_some() || srtext.is_some())
        .then(|| (proj4.unwrap_or_default(), srtext.unwrap_or_default()))
}

thread_local! {
    /// SRIDs this backend has looked up in spatial_ref_sys, and whether
    /// each is geographic (PostGIS, too, keeps what it has read of an SRID
    /// for the backend's life).
    static GEOGRAPHIC: RefCell<HashMap<i32, bool>> = RefCell::new(HashMap::new());
}

/// Whether the tin's SRID is geographic, for the functions that measure in
/// its units: `given` when the caller says, never for an extent that cannot
/// be in degrees (|x| > 540 or |y| > 90: a projected terrain, decided with
/// no look-up), otherwise whether spatial_ref_sys describes the SRID as
/// longitude/latitude (read once per SRID and backend, in PostGIS's
/// schema).
pub(super) fn srid_is_geographic(given: Option<bool>, srid: i32, b: &Bbox) -> bool {
    if let Some(g) = given {
        return g;
    }
    let could_be_degrees = b.min_x.abs() <= 540.0
        && b.max_x.abs() <= 540.0
        && b.min_y.abs() <= 90.0
        && b.max_y.abs() <= 90.0;
    if srid == 0 || !could_be_degrees {
        return false;
    }
    if let Some(g) = GEOGRAPHIC.with(|c| c.borrow().get(&srid).copied()) {
        return g;
    }
    let g = srs_text(srid).is_some_and(|(proj4, srtext)| {
        proj4.contains("+proj=longlat")
            || srtext.starts_with("GEOGCS")
            || srtext.starts_with("GEOGCRS")
    });
    GEOGRAPHIC.with(|c| c.borrow_mut().insert(srid, g));
    g
}

thread_local! {
    /// The spheroid of each geographic SRID this backend has measured on.
    static SPHEROIDS: RefCell<HashMap<i32, Spheroid>> = RefCell::new(HashMap::new());
}

/// How the area functions measure a tin of `srid`: in its own units, or,
/// when the SRID is geographic ([`srid_is_geographic`]), in metres on its
/// spheroid (from spatial_ref_sys's proj4text, read once per SRID and
/// backend; WGS84 when it names none). An error for a spheroid the core
/// does not know.
pub(super) fn area_units(geographic: Option<bool>, srid: i32, bbox: &Bbox, func: &str) -> Units {
    if !srid_is_geographic(geographic, srid, bbox) {
        return Units::Planar;
    }
    if let Some(s) = SPHEROIDS.with(|c| c.borrow().get(&srid).copied()) {
        return Units::Degrees(s);
    }
    let def = srs_text(srid).map(|(proj4, _)| proj4).unwrap_or_default();
    let Some(s) = Spheroid::from_proj4(&def) else {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!(
                "{func}: the spheroid of SRID {srid} ('{def}') is not one tinmerge knows; give it in spatial_ref_sys.proj4text as +a= and +rf="
            ),
        );
    };
    SPHEROIDS.with(|c| c.borrow_mut().insert(srid, s));
    Units::Degrees(s)
}

type TriRow = (i32, i32, String, f64);

/// The rows of `tin_area_triangles` for a polygon read by `area`.
pub(super) fn triangles_rows(
    t: &TinArg,
    level: Option<i32>,
    compact: bool,
    area: &dyn Fn(i32) -> Rc<Area>,
) -> Vec<TriRow> {
    let rows = with_mesh!(t, level, |m, l, srid| {
        let area = area(srid);
        let s = sweep(m, l, &area, Method::Hierarchy, &mut interrupt).or_raise();
        area_rows(m, &area, &s, compact, &mut interrupt).or_raise()
    });
    rows.into_iter()
        .map(|r| {
            (
                r.triangle as i32,
                r.level as i32,
                r.relation.as_str().to_string(),
                r.coverage,
            )
        })
        .collect()
}

#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn tin_area_triangles(
    t: Option<TinArg>,
    area: Option<GeomArg>,
    level: default!(Option<i32>, "NULL"),
    compact: default!(Option<bool>, "false"),
) -> TableIterator<
    'static,
    (
        name!(triangle, i32),
        name!(level, i32),
        name!(relation, String),
        name!(coverage, f64),
    ),
> {
    let (Some(t), Some(g)) = (t, area) else {
        return TableIterator::new(Vec::new());
    };
    TableIterator::new(triangles_rows(
        &t,
        level,
        compact.unwrap_or(false),
        &|srid| geom_area(&g, srid, "tin_area_triangles"),
    ))
}

extension_sql!(
    r#"
ALTER FUNCTION tin_area_triangles(tin, geometry, int, boolean) ROWS 1000;
COMMENT ON FUNCTION tin_area_triangles(tin, geometry, int, boolean) IS
'Triangles of a level (NULL = finest) on and inside a POLYGON or MULTIPOLYGON, by the hierarchical polygonal sweep: relation ''inside'' (wholly inside, touching the boundary allowed; coverage 1) or ''boundary'' (the polygon''s boundary crosses the triangle; coverage = fraction of the triangle''s area inside). With compact => true, inside triangles are reported at the coarsest level whose triangle is wholly inside (the level column says which), covering the same region. Parts outside the domain are ignored; an invalid polygon is an error (repair it with ST_MakeValid).';
"#,
    name = "tin_area_triangles_sql",
    requires = [tin_area_triangles]
);

pub(super) type StatsRow = (
    f64,
    f64,
    Option<f64>,
    Option<f64>,
    Option<f64>,
    Option<f64>,
    Option<f64>,
);

/// A value's identity for the subtree sums kept by the cache: its content
/// hash and length (what the decoded-value cache is keyed by).
fn value_key(t: &TinArg) -> (u64, u64) {
    let h = t.header();
    (h.hash, h.total_len)
}

/// The polygon swept at level `l` for statistics (the hierarchical sweep:
/// the coarsest triangles wholly inside), with the value's subtree sums
/// when the cache holds them or they are due ([`cache::sums_due`]: the
/// target level's triangles this polygon would sum one by one, each coarse
/// triangle inside standing for its share of them, added to what earlier
/// ones summed, reach a quarter of the level), so those count in O(1).
/// With or without them the statistics are the same bits
/// (`surface::stats_with`): what a backend has cached never changes an
/// answer.
fn swept<M: Indexed>(
    key: (u64, u64),
    m: &M,
    l: usize,
    area: &Area,
    units: Units,
) -> (Sweep, Option<std::sync::Arc<SubtreeSums>>)
where
    TinError: From<M::Err>,
{
    let s = sweep(m, l, area, Method::Hierarchy, &mut interrupt).or_raise();
    if let Some(sums) = cache::subtree_sums(key.0, key.1, l) {
        return (s, Some(sums));
    }
    let triangles = m.num_triangles(l) as u64;
    let work: f64 = s
        .inside
        .iter()
        .enumerate()
        .map(|(k, v)| v.len() as f64 * triangles as f64 / m.num_triangles(k).max(1) as f64)
        .sum();
    if !cache::sums_due(key.0, key.1, l, work as u64, triangles) {
        return (s, None);
    }
    let coarse: usize = (0..l).map(|k| m.num_triangles(k)).sum();
    let bytes = coarse * std::mem::size_of::<tinmerge_core::merge::area::surface::SurfaceStats>();
    let sums = cache::make_sums(key.0, key.1, l, bytes, || {
        SubtreeSums::build(m, l, units, &mut interrupt)
    });
    (s, sums)
}

/// The polygon read by `area` in the tin's SRID, and what the header
/// answers without reading a triangle (`merge::area::whole::box_side`):
/// `nothing` when the polygon leaves the whole terrain out (a tile met by
/// the polygon's bounding box only); when it holds the whole terrain and
/// the header stores each level's sums (format 6 or 7) in the units the
/// tin is measured in (its own: not a geographic SRID), what `from_header`
/// makes of the level's sums (a tile wholly inside a county).
fn with_header<T>(
    t: &TinArg,
    level: Option<i32>,
    geographic: Option<bool>,
    area: &dyn Fn(i32) -> Rc<Area>,
    func: &str,
    nothing: impl FnOnce() -> T,
    from_header: impl Fn(&tinmerge_core::tin::layout::Header, usize) -> Option<T>,
) -> (Rc<Area>, Option<T>) {
    let h = t.header();
    let a = area(h.srid);
    let side = whole::box_side(&h, &a);
    if side == Some(Where::Outside) {
        // (the level and a geographic SRID's spheroid are still checked,
        // as the triangles' path does)
        tinmerge_core::tin::resolve_level(level, h.levels.len()).or_raise();
        area_units(geographic, h.srid, &h.bbox, func);
        return (a, Some(nothing()));
    }
    if side != Some(Where::Inside)
        || h.sums.is_empty()
        || srid_is_geographic(geographic, h.srid, &h.bbox)
    {
        return (a, None);
    }
    let l = tinmerge_core::tin::resolve_level(level, h.levels.len()).or_raise();
    let got = from_header(&h, l);
    (a, got)
}

/// The row of `tin_area_stats` for a polygon read by `area`.
pub(super) fn stats_row(
    t: &TinArg,
    level: Option<i32>,
    geographic: Option<bool>,
    area: &dyn Fn(i32) -> Rc<Area>,
) -> StatsRow {
    let key = value_key(t);
    let (area, got) = with_header(
        t,
        level,
        geographic,
        area,
        "tin_area_stats",
        SurfaceStats::empty,
        whole::level_stats,
    );
    let st = got.unwrap_or_else(|| {
        with_mesh!(t, level, |m, l, srid| {
            let units = area_units(geographic, srid, m.bbox(), "tin_area_stats");
            let (s, sums) = swept(key, m, l, &area, units);
            stats_with(m, &area, &s, sums.as_deref(), units, &mut interrupt).or_raise()
        })
    });
    let some = |v: f64| (st.area2d > 0.0).then_some(v);
    (
        st.area2d,
        st.area3d,
        some(st.min_z),
        some(st.max_z),
        some(st.mean_z()),
        some(st.mean_slope()),
        some(st.max_slope),
    )
}

#[allow(clippy::type_complexity)]
#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn tin_area_stats(
    t: Option<TinArg>,
    area: Option<GeomArg>,
    level: default!(Option<i32>, "NULL"),
) -> TableIterator<
    'static,
    (
        name!(area2d, f64),
        name!(area3d, f64),
        name!(min_z, Option<f64>),
        name!(max_z, Option<f64>),
        name!(mean_z, Option<f64>),
        name!(mean_slope, Option<f64>),
        name!(max_slope, Option<f64>),
    ),
> {
    let (Some(t), Some(g)) = (t, area) else {
        return TableIterator::new(Vec::<StatsRow>::new());
    };
    TableIterator::new(vec![stats_row(&t, level, None, &|srid| {
        geom_area(&g, srid, "tin_area_stats")
    })])
}

extension_sql!(
    r#"
ALTER FUNCTION tin_area_stats(tin, geometry, int) ROWS 1;
COMMENT ON FUNCTION tin_area_stats(tin, geometry, int) IS
'Statistics of the surface of a level (NULL = finest) clipped exactly to a POLYGON or MULTIPOLYGON: planar area, surface area, min/max height, area-weighted mean height and slope (degrees), steepest slope. Heights are NULL when the polygon misses the domain. A tin in a geographic SRID (degrees, heights in metres) answers in metres on the SRID''s spheroid: areas in square metres, slopes with the metres a degree spans at each part''s latitude.';
"#,
    name = "tin_area_stats_sql",
    requires = [tin_area_stats]
);

/// `tin_surface_area`: the area3d of `tin_area_stats` as a scalar, a Rust
/// function since 0.26.0 (an SQL wrapper before, which the planner could
/// not inline: each call ran the SQL function executor).
#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn tin_surface_area(
    t: Option<TinArg>,
    area: Option<GeomArg>,
    level: default!(Option<i32>, "NULL"),
) -> Option<f64> {
    let (Some(t), Some(g)) = (t, area) else {
        return None;
    };
    Some(
        stats_row(&t, level, None, &|srid| {
            geom_area(&g, srid, "tin_surface_area")
        })
        .1,
    )
}

extension_sql!(
    r#"
COMMENT ON FUNCTION tin_surface_area(tin, geometry, int) IS
'Surface (3D) area of a level (NULL = finest) clipped exactly to a POLYGON or MULTIPOLYGON: the area3d of tin_area_stats as a scalar (0 when the polygon misses the domain; NULL when an argument other than level is NULL), so it can be used where a set-returning call cannot, e.g. pushed down to a postgres_fdw shard. A tin in a geographic SRID answers in square metres on the SRID''s spheroid.';
"#,
    name = "tin_surface_area_sql",
    requires = [tin_surface_area]
);

/// Cut and fill of a polygon read by `area` against `base`.
pub(super) fn volume_row(
    t: &TinArg,
    base: f64,
    level: Option<i32>,
    geographic: Option<bool>,
    area: &dyn Fn(i32) -> Rc<Area>,
) -> (f64, f64) {
    if !base.is_finite() {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!("tin_volume: base_z must be a finite height, got {base}"),
        );
    }
    let key = value_key(t);
    let (area, got) = with_header(
        t,
        level,
        geographic,
        area,
        "tin_volume",
        VolumeParts::default,
        |h, l| VolumeParts::of_subtree(&whole::level_stats(h, l)?, base),
    );
    let v = got.unwrap_or_else(|| {
        with_mesh!(t, level, |m, l, srid| {
            let units = area_units(geographic, srid, m.bbox(), "tin_volume");
            let (s, sums) = swept(key, m, l, &area, units);
            volume_parts_with(m, &area, &s, base, sums.as_deref(), units, &mut interrupt).or_raise()
        })
    });
    (v.cut, v.fill)
}

#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn tin_volume(
    t: Option<TinArg>,
    area: Option<GeomArg>,
    base_z: Option<f64>,
    level: default!(Option<i32>, "NULL"),
) -> TableIterator<'static, (name!(cut, f64), name!(fill, f64))> {
    let (Some(t), Some(g), Some(base)) = (t, area, base_z) else {
        return TableIterator::new(Vec::new());
    };
    TableIterator::new(vec![volume_row(&t, base, level, None, &|srid| {
        geom_area(&g, srid, "tin_volume")
    })])
}

extension_sql!(
    r#"
ALTER FUNCTION tin_volume(tin, geometry, float8, int) ROWS 1;
COMMENT ON FUNCTION tin_volume(tin, geometry, float8, int) IS
'Volumes inside a POLYGON or MULTIPOLYGON between the surface of a level (NULL = finest) and the height base_z: cut = volume of surface above base_z, fill = volume of the space below base_z down to the surface (as a cut-and-fill or ArcGIS Surface Volume), exact for the linear surface. A tin in a geographic SRID (degrees, heights in metres) answers in cubic metres on the SRID''s spheroid.';
"#,
    name = "tin_volume_sql",
    requires = [tin_volume]
);

/// The sweep's work for the benchmark: triangles examined by a method
/// ('hierarchy', 'flat' or 'scan') and the rows it gives. Only in builds
/// with the `bench` feature (`make bench` installs one); never in an install.
#[cfg(feature = "bench")]
#[pg_extern(immutable, parallel_safe, requires = ["tin_type"])]
fn _tin_area_examined(
    t: TinArg,
    area: &[u8],
    level: Option<i32>,
    method: &str,
) -> TableIterator<'static, (name!(examined, i64), name!(rows, i64))> {
    let (tin, l) = super::tin_type::tin_level(&t, level);
    let tin: &tinmerge_core::tin::Tin = &tin;
    let area = ewkb_area(area, None, tin.srid, "_tin_area_examined");
    let m = match method {
        "hierarchy" => Method::Hierarchy,
        "flat" => Method::Flat,
        "scan" => Method::Scan,
        other => raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!("method must be 'hierarchy', 'flat' or 'scan', got '{other}'"),
        ),
    };
    let s = sweep(tin, l, &area, m, &mut interrupt).or_raise();
    let rows = area_rows(tin, &area, &s, m == Method::Hierarchy, &mut interrupt).or_raise();
    TableIterator::new(vec![(s.examined as i64, rows.len() as i64)])
}

#[cfg(feature = "bench")]
extension_sql!(
    r#"
ALTER FUNCTION _tin_area_examined(tin, bytea, integer, text) COST 10000 ROWS 1;
COMMENT ON FUNCTION _tin_area_examined(tin, bytea, integer, text) IS 'Internal (benchmark builds only): triangles examined and rows given by the area sweep with method hierarchy, flat or scan.';
"#,
    name = "tin_area_examined_comment",
    requires = [_tin_area_examined]
);
