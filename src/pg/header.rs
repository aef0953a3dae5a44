//! Functions answered from the fixed header alone (a prefix slice of the
//! stored value, never the triangles): SRID, counts, tolerances, `tin_info`,
//! the envelope.

use pgrx::prelude::*;
use pgrx::JsonB;
use serde_json::json;

use super::errors::OrRaise;
use super::tin_type::TinArg;
use tinmerge_core::io::ewkb;
use tinmerge_core::tin::resolve_level;

#[pg_extern(support = _tin_plan_support, immutable, strict, parallel_safe, requires = ["tin_type"])]
fn tin_srid(t: TinArg) -> i32 {
    t.header().srid
}

extension_sql!(
    r#"
COMMENT ON FUNCTION tin_srid(tin) IS 'SRID of the tin (header only).';
"#,
    name = "tin_srid_sql",
    requires = [tin_srid]
);

#[pg_extern(support = _tin_plan_support, immutable, strict, parallel_safe, requires = ["tin_type"])]
fn tin_num_levels(t: TinArg) -> i32 {
    t.header().num_levels() as i32
}

extension_sql!(
    r#"
COMMENT ON FUNCTION tin_num_levels(tin) IS 'Number of levels of detail (header only).';
"#,
    name = "tin_num_levels_sql",
    requires = [tin_num_levels]
);

/// The header's record for a level (None = finest).
fn level_info(t: &TinArg, level: Option<i32>) -> tinmerge_core::tin::layout::LevelInfo {
    let h = t.header();
    let l = resolve_level(level, h.num_levels()).or_raise();
    h.levels[l]
}

#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, requires = ["tin_type"])]
fn tin_num_triangles(t: Option<TinArg>, level: default!(Option<i32>, "NULL")) -> Option<i32> {
    t.map(|t| {
        let li = level_info(&t, level);
        (li.num_triangles - li.num_void) as i32
    })
}

extension_sql!(
    r#"
COMMENT ON FUNCTION tin_num_triangles(tin, int) IS 'Triangles at a level (NULL = finest; header only), in the domain: the void triangles outside a boundary are not counted.';
"#,
    name = "tin_num_triangles_sql",
    requires = [tin_num_triangles]
);

#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, requires = ["tin_type"])]
fn tin_num_vertices(t: Option<TinArg>, level: default!(Option<i32>, "NULL")) -> Option<i32> {
    t.map(|t| level_info(&t, level).num_vertices as i32)
}

extension_sql!(
    r#"
COMMENT ON FUNCTION tin_num_vertices(tin, int) IS 'Vertices used by a level (NULL = finest; header only).';
"#,
    name = "tin_num_vertices_sql",
    requires = [tin_num_vertices]
);

#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, requires = ["tin_type"])]
fn tin_tolerance(t: Option<TinArg>, level: default!(Option<i32>, "NULL")) -> Option<f64> {
    t.map(|t| level_info(&t, level).tolerance)
}

extension_sql!(
    r#"
COMMENT ON FUNCTION tin_tolerance(tin, int) IS 'Vertical error bound a level was built to (NULL = finest; header only).';
"#,
    name = "tin_tolerance_sql",
    requires = [tin_tolerance]
);

#[pg_extern(support = _tin_plan_support, immutable, strict, parallel_safe, requires = ["tin_type"])]
fn tin_info(t: TinArg) -> JsonB {
    let h = t.header();
    let b = h.bbox;
    let levels: Vec<_> = h
        .levels
        .iter()
        .enumerate()
        .map(|(i, l)| {
            json!({
                "level": i,
                "tolerance": l.tolerance,
                "triangles": l.num_triangles,
                "vertices": l.num_vertices,
                "max_error": l.max_error,
            })
        })
        .collect();
    JsonB(json!({
        "srid": h.srid,
        "bbox": [b.min_x, b.min_y, b.max_x, b.max_y],
        "z_range": [b.min_z, b.max_z],
        "bytes": h.total_len,
        "format": h.version,
        "num_levels": h.num_levels(),
        "num_vertices": h.num_vertices,
        "levels": levels,
    }))
}

extension_sql!(
    r#"
COMMENT ON FUNCTION tin_info(tin) IS 'SRID, bounding box, size in bytes, storage format version and per level: tolerance, triangles, vertices and the largest error measured when built: at the source samples and, for a raster build (since 0.11.0; with a boundary or soft breaklines since 0.12.0, with hard breaklines since 0.13.0, the grid segments they cut left out), also between them where edges cross the grid lines between valid pixel centres (header only; tin_validate(tin, raster) measures a value against a raster).';
"#,
    name = "tin_info_sql",
    requires = [tin_info]
);

#[pg_extern(immutable, strict, parallel_safe, requires = ["tin_type"])]
fn _tin_envelope(t: TinArg) -> Vec<u8> {
    let h = t.header();
    let b = h.bbox;
    let ring = vec![
        [b.min_x, b.min_y, 0.0],
        [b.min_x, b.max_y, 0.0],
        [b.max_x, b.max_y, 0.0],
        [b.max_x, b.min_y, 0.0],
        [b.min_x, b.min_y, 0.0],
    ];
    ewkb::Writer::write(h.srid, false, &ewkb::Geom::Polygon(vec![ring]))
}

extension_sql!(
    r#"
COMMENT ON FUNCTION _tin_envelope(tin) IS 'Internal: use tin_envelope(tin).';
"#,
    name = "tin_envelope_sql",
    requires = [_tin_envelope]
);
