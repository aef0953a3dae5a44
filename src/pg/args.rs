//! Checks shared by the functions that take PostGIS geometries: SRIDs and
//! geometry types, with messages that say what was received.

use pgrx::prelude::*;

use super::{raise, OrRaise};
use crate::io::ewkb;

/// ERROR unless the SRIDs agree (0 on either side means "unknown": accepted).
pub fn check_srid(geom_srid: i32, tin_srid: i32, func: &str) {
    if geom_srid != 0 && tin_srid != 0 && geom_srid != tin_srid {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!(
                "{func}: geometry has SRID {geom_srid} but the tin has SRID {tin_srid}; transform it first, e.g. ST_Transform(geom, {tin_srid})"
            ),
        );
    }
}

/// The x, y of a POINT argument (None for `POINT EMPTY`), after the SRID
/// check; an ERROR naming the type for anything but a point.
pub fn point_xy(bytes: &[u8], tin_srid: i32, func: &str) -> Option<[f64; 2]> {
    if let Some((srid, xy)) = ewkb::read_point(bytes) {
        check_srid(srid, tin_srid, func);
        return xy;
    }
    let g = ewkb::read(bytes).or_raise();
    check_srid(g.srid, tin_srid, func);
    raise(
        PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
        format!(
            "{func} takes a POINT, got a {}{}",
            g.geom.type_name(),
            match g.geom {
                ewkb::Geom::MultiPoint(_) => " (use tin_drape for MULTIPOINT, or ST_Dump it)",
                _ => "",
            }
        ),
    )
}
