//! The `tin_from_points_agg` aggregates: every vertex of the rows gathered
//! in the aggregate's memory context, built by the final function as
//! `tin_from_points` builds.

use pgrx::prelude::*;

use super::errors::{raise, OrRaise};
use super::interrupt::interrupt;
use super::memory;
use super::tin_type::TinOut;
use pgrx::{pg_sys, Internal, PgMemoryContexts};

use super::args::GeomArg;
use super::build::{boundary_of, breaklines_of, build_points_domain, reserve_build_bytes};
use tinmerge_core::io::gserialized;
use tinmerge_core::tin::build::{default_tolerances, points_build_bytes};
use tinmerge_core::tin::construct::build_points;

/// The state of the `tin_from_points_agg` aggregate: every vertex (with Z)
/// of the rows so far, their SRID, and the build's arguments (from the
/// first row), kept in the aggregate's memory context and dropped with it.
#[derive(Default)]
struct PointsAgg {
    samples: Vec<[f64; 3]>,
    srid: Option<i32>,
    args: Option<(f64, i32)>,
    /// The breaklines, soft breaklines and boundary of the first row (the
    /// six-argument form; PostGIS's aggregates also take such arguments
    /// from the first row), in PostGIS's serialisation.
    domain: Option<[Option<Vec<u8>>; 3]>,
}

/// Transition function of `tin_from_points_agg(geometry, float8, int)`:
/// adds the row's vertices (NULL and empty geometries add nothing).
#[pg_extern(immutable, parallel_safe, requires = ["tin_type"])]
fn _tin_points_agg_step(
    mut state: Internal,
    pt: Option<GeomArg>,
    tolerance: Option<f64>,
    levels: Option<i32>,
    fcinfo: pg_sys::FunctionCallInfo,
) -> Internal {
    let st = points_agg_state(&mut state, fcinfo, "_tin_points_agg_step");
    points_agg_add(st, pt, tolerance, levels);
    state
}

/// The aggregate's state, made in its memory context on the first row;
/// an ERROR when `func` is called outside an aggregate.
fn points_agg_state<'a>(
    state: &'a mut Internal,
    fcinfo: pg_sys::FunctionCallInfo,
    func: &str,
) -> &'a mut PointsAgg {
    let mut agg: pg_sys::MemoryContext = std::ptr::null_mut();
    // SAFETY: fcinfo is this call's; AggCheckCallContext only reads it.
    if unsafe { pg_sys::AggCheckCallContext(fcinfo, &mut agg) } == 0 || agg.is_null() {
        raise(
            PgSqlErrorCode::ERRCODE_FEATURE_NOT_SUPPORTED,
            format!("{func} is the transition function of tin_from_points_agg; it cannot be called on its own"),
        );
    }
    // SAFETY: the state is only ever a PointsAgg made here, in the
    // aggregate's context (dropped when that context goes).
    unsafe { PgMemoryContexts::For(agg).switch_to(|_| state.get_or_insert_default::<PointsAgg>()) }
}

/// Transition function of `tin_from_points_agg(geometry, float8, int,
/// geometry, geometry, geometry)`: as [`_tin_points_agg_step`], and the
/// breaklines, soft breaklines and boundary taken from the first row (read
/// once: later rows' values are not even detoasted).
#[allow(clippy::too_many_arguments)]
#[pg_extern(immutable, parallel_safe, requires = ["tin_type"])]
fn _tin_points_agg_domain_step(
    mut state: Internal,
    pt: Option<GeomArg>,
    tolerance: Option<f64>,
    levels: Option<i32>,
    breaklines: Option<GeomArg>,
    soft_breaklines: Option<GeomArg>,
    boundary: Option<GeomArg>,
    fcinfo: pg_sys::FunctionCallInfo,
) -> Internal {
    let st = points_agg_state(&mut state, fcinfo, "_tin_points_agg_domain_step");
    if st.domain.is_none() {
        let own = |g: &Option<GeomArg>| g.as_ref().map(|g| g.bytes().to_vec());
        st.domain = Some([own(&breaklines), own(&soft_breaklines), own(&boundary)]);
    }
    points_agg_add(st, pt, tolerance, levels);
    state
}

/// One row of `tin_from_points_agg`: the arguments checked, the vertices
/// added.
fn points_agg_add(
    st: &mut PointsAgg,
    pt: Option<GeomArg>,
    tolerance: Option<f64>,
    levels: Option<i32>,
) {
    let (Some(tolerance), Some(levels)) = (tolerance, levels) else {
        raise(
            PgSqlErrorCode::ERRCODE_NULL_VALUE_NOT_ALLOWED,
            "tin_from_points_agg: tolerance and levels must not be NULL",
        );
    };
    match st.args {
        None => {
            default_tolerances(tolerance, levels).or_raise();
            st.args = Some((tolerance, levels));
        }
        Some((t, l)) if t.to_bits() != tolerance.to_bits() || l != levels => raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!(
                "tin_from_points_agg: tolerance and levels must be the same in every row (first {t} and {l}, then {tolerance} and {levels})"
            ),
        ),
        Some(_) => {}
    }
    let Some(pt) = pt else { return };
    let g = gserialized::read(pt.bytes()).or_raise();
    if g.geom.is_empty() {
        return;
    }
    match st.srid {
        None => st.srid = Some(g.srid),
        Some(s) if s != g.srid => raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!(
                "tin_from_points_agg: rows have SRIDs {s} and {}; transform them to one SRID first",
                g.srid
            ),
        ),
        Some(_) => {}
    }
    if !g.has_z {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!(
                "tin_from_points_agg: a {} has no Z coordinate: a tin needs 3D samples (ST_Force3DZ adds Z = 0)",
                g.geom.type_name()
            ),
        );
    }
    let before = st.samples.capacity();
    g.geom.for_each_coord(&mut |c| st.samples.push(*c));
    let grown = st.samples.capacity().saturating_sub(before);
    if grown > 0 {
        let n = st.samples.len();
        memory::reserve(0, || {
            format!("tin_from_points_agg: holding {n} samples ({grown} more places)")
        });
    }
}

/// Final function of `tin_from_points_agg`: the tin of every vertex
/// gathered (NULL when no row gave one).
#[pg_extern(immutable, parallel_safe, requires = ["tin_type"])]
fn _tin_points_agg_final(mut state: Internal) -> Option<TinOut> {
    // SAFETY: the state is only ever a PointsAgg (see the step function).
    // FINALFUNC_MODIFY = READ_WRITE: the samples are handed to the build,
    // not copied (PostgreSQL does not use the state after this call).
    let st = unsafe { state.get_mut::<PointsAgg>() }?;
    let (tolerance, levels) = st.args?;
    if st.samples.is_empty() {
        return None;
    }
    let tols = default_tolerances(tolerance, levels).or_raise();
    reserve_build_bytes(
        "tin_from_points_agg",
        st.samples.len(),
        tols.len(),
        points_build_bytes(st.samples.len(), tols.len()),
    );
    // the places the doubling left unused handed back before the build
    let mut samples = std::mem::take(&mut st.samples);
    samples.shrink_to_fit();
    let srid = st.srid.unwrap_or(0);
    let tin = match &st.domain {
        Some(d) if d.iter().any(Option::is_some) => {
            const F: &str = "tin_from_points_agg";
            let read = |b: &Option<Vec<u8>>| b.as_ref().map(|b| gserialized::read(b).or_raise());
            let lines = breaklines_of(F, read(&d[0]), read(&d[1]), srid);
            let area = read(&d[2]).and_then(|g| boundary_of(F, g, srid));
            build_points_domain(samples, &lines, area, &tols, srid)
        }
        _ => super::progress::track("tin_from_points_agg", || {
            build_points(samples, &tols, srid, &mut interrupt)
        })
        .or_raise(),
    };
    Some(TinOut::from_tin(&tin))
}

extension_sql!(
    r#"
COMMENT ON FUNCTION _tin_points_agg_step(internal, geometry, float8, int) IS 'Internal: the transition function of tin_from_points_agg(geometry, float8, int).';
COMMENT ON FUNCTION _tin_points_agg_final(internal) IS 'Internal: the final function of tin_from_points_agg(geometry, float8, int).';
CREATE AGGREGATE tin_from_points_agg(pt geometry, tolerance float8, levels int) (
    SFUNC = _tin_points_agg_step,
    STYPE = internal,
    FINALFUNC = _tin_points_agg_final,
    FINALFUNC_MODIFY = READ_WRITE,
    PARALLEL = SAFE
);
COMMENT ON AGGREGATE tin_from_points_agg(geometry, float8, int) IS
'Builds a tin from every vertex (with Z) of the rows aggregated, as tin_from_points(ST_Collect(pt), tolerance, levels) does but without building one collection geometry (which PostgreSQL caps at 1 GB): e.g. tin_from_points_agg(geom, 0.5, 5) FILTER (WHERE class = 2) over LiDAR returns keeps the ground. Points with equal x,y are merged (mean z); NULL and empty rows add nothing; no row gives NULL. All rows must have one SRID, and the same tolerance and levels.';
COMMENT ON FUNCTION _tin_points_agg_domain_step(internal, geometry, float8, int, geometry, geometry, geometry) IS 'Internal: the transition function of tin_from_points_agg(geometry, float8, int, geometry, geometry, geometry).';
CREATE AGGREGATE tin_from_points_agg(pt geometry, tolerance float8, levels int, breaklines geometry, soft_breaklines geometry, boundary geometry) (
    SFUNC = _tin_points_agg_domain_step,
    STYPE = internal,
    FINALFUNC = _tin_points_agg_final,
    FINALFUNC_MODIFY = READ_WRITE,
    PARALLEL = SAFE
);
COMMENT ON AGGREGATE tin_from_points_agg(geometry, float8, int, geometry, geometry, geometry) IS
'Builds a tin from every vertex (with Z) of the rows aggregated with breaklines, soft breaklines and a boundary (each NULL for none; aggregates take no named or default arguments), as tin_from_points(ST_Collect(pt), tolerance, levels, breaklines, soft_breaklines, boundary) does: e.g. tin_from_points_agg(geom, 0.5, 5, (SELECT ST_Collect(geom) FROM roads), NULL, (SELECT geom FROM survey_area)). The three geometries are taken from the first row, as PostGIS aggregates take their extra arguments (pass constants or scalar subqueries); the rest as tin_from_points_agg(geometry, float8, int).';
"#,
    name = "tin_from_points_agg_sql",
    requires = [
        _tin_points_agg_step,
        _tin_points_agg_domain_step,
        _tin_points_agg_final
    ]
);
