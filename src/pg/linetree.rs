//! The `linetree` SQL type (a multi-scale line tree stored flat, see
//! [`tinmerge_core::merge::line::tree`]) and the line-merge functions taking it.
//! Values are read in place: a merge detoasts the value, checks its header,
//! size and hash, and reads only the nodes and points it visits.

use pgrx::callconv::{BoxRet, FcInfo};
use pgrx::datum::Datum as RetDatum;
use pgrx::pg_sys;
use pgrx::prelude::*;
use pgrx::IntoDatum;
use std::ffi::{CStr, CString};

use super::args::check_srid;
use super::errors::{raise, OrRaise};
use super::interrupt::interrupt;
use super::line::{check_width, part_offsets, profile, seq_rows};
use super::tin_type::TinArg;
use std::sync::Arc;
use tinmerge_core::io::ewkb::{self, Geom};
use tinmerge_core::merge::line::tree::{self, near_tree, walk_tree, View};
use tinmerge_core::merge::line::{PieceSink, TriangleSink};
use tinmerge_core::tin::Tin;

raw_datum_arg!(
    /// A `linetree` argument as the raw Datum.
    LineTreeArg,
    "linetree"
);

impl LineTreeArg {
    fn bytes(&self) -> &[u8] {
        // SAFETY: self.0 is a non-NULL linetree Datum of this call; the detoasted
        // copy lives in the current memory context, beyond the borrow.
        unsafe {
            let v = pg_sys::pg_detoast_datum_packed(self.0.cast_mut_ptr());
            pgrx::varlena::varlena_to_byte_slice(v)
        }
    }
    /// The value, header, size and hash checked.
    fn view(&self) -> View<'_> {
        View::new(self.bytes()).or_raise()
    }
}

/// A `linetree` result.
pub struct LineTreeOut(pub Vec<u8>);

impl IntoDatum for LineTreeOut {
    fn into_datum(self) -> Option<pg_sys::Datum> {
        Some(super::varlena::varlena_datum(&self.0, "linetree"))
    }
    fn type_oid() -> pg_sys::Oid {
        pg_sys::InvalidOid
    }
}

// SAFETY: box_into returns the Datum of into_datum (a palloc'd linetree
// varlena), or NULL.
unsafe impl BoxRet for LineTreeOut {
    unsafe fn box_into<'fcx>(self, fcinfo: &mut FcInfo<'fcx>) -> RetDatum<'fcx> {
        match self.into_datum() {
            // SAFETY: d is a complete palloc'd linetree varlena.
            Some(d) => unsafe { fcinfo.return_raw_datum(d) },
            None => fcinfo.return_null(),
        }
    }
}

pgrx::pgrx_sql_entity_graph::impl_sql_translatable!(LineTreeOut, "linetree");

fn validated(bytes: Vec<u8>, code: PgSqlErrorCode) -> LineTreeOut {
    if let Err(e) = View::new(&bytes).and_then(|v| v.validate()) {
        raise(code, e.to_string());
    }
    LineTreeOut(bytes)
}

#[pg_extern(immutable, strict, parallel_safe, requires = ["tin_shell"])]
fn linetree_in(input: &CStr) -> LineTreeOut {
    let bytes = super::varlena::hex_input(input, "linetree");
    validated(bytes, PgSqlErrorCode::ERRCODE_INVALID_TEXT_REPRESENTATION)
}

extension_sql!(
    r#"
COMMENT ON FUNCTION linetree_in(cstring) IS 'Text input of linetree: hex of the binary form, fully validated (every error bound recomputed).';
"#,
    name = "linetree_in_sql",
    requires = [linetree_in]
);

#[pg_extern(immutable, strict, parallel_safe, requires = ["tin_shell"])]
fn linetree_out(t: LineTreeArg) -> CString {
    CString::new(tinmerge_core::tin::layout::to_hex(t.bytes())).unwrap_or_default()
}

extension_sql!(
    r#"
COMMENT ON FUNCTION linetree_out(linetree) IS 'Text output of linetree: hex of the binary form.';
"#,
    name = "linetree_out_sql",
    requires = [linetree_out]
);

#[pg_extern(immutable, strict, parallel_safe, requires = ["tin_shell"])]
fn linetree_recv(mut buf: pgrx::datum::Internal) -> LineTreeOut {
    let bytes = super::varlena::recv_bytes(&mut buf, "linetree");
    validated(bytes, PgSqlErrorCode::ERRCODE_INVALID_BINARY_REPRESENTATION)
}

extension_sql!(
    r#"
COMMENT ON FUNCTION linetree_recv(internal) IS 'Binary input of linetree, fully validated.';
"#,
    name = "linetree_recv_sql",
    requires = [linetree_recv]
);

#[pg_extern(immutable, strict, parallel_safe, requires = ["tin_shell"])]
fn linetree_send(t: LineTreeArg) -> Vec<u8> {
    t.bytes().to_vec()
}

extension_sql!(
    r#"
COMMENT ON FUNCTION linetree_send(linetree) IS 'Binary output of linetree.';
"#,
    name = "linetree_send_sql",
    requires = [linetree_send]
);

extension_sql!(
    r#"
CREATE TYPE linetree (
    INPUT = linetree_in,
    OUTPUT = linetree_out,
    RECEIVE = linetree_recv,
    SEND = linetree_send,
    INTERNALLENGTH = VARIABLE,
    ALIGNMENT = double,
    STORAGE = external
);
COMMENT ON TYPE linetree IS 'A line (LINESTRING or MULTILINESTRING) with its multi-scale line tree: generalisations with an error bound per segment, so merges with a tin skip the stretches that cannot leave a triangle. Build with tin_linetree(geometry). Text form: hex of the binary form.';
"#,
    name = "linetree_type",
    requires = [linetree_in, linetree_out, linetree_recv, linetree_send]
);

#[pg_extern(immutable, strict, parallel_safe, cost = 500, requires = ["linetree_type"])]
fn _tin_linetree(geom: &[u8]) -> Option<LineTreeOut> {
    let g = ewkb::read(geom).or_raise();
    let lines: Vec<&Vec<[f64; 3]>> = match &g.geom {
        Geom::LineString(l) => vec![l],
        Geom::MultiLineString(ls) => ls.iter().collect(),
        other => raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!(
                "tin_linetree takes a LINESTRING or MULTILINESTRING, got a {}",
                other.type_name()
            ),
        ),
    };
    let parts: Vec<Vec<[f64; 2]>> = lines
        .into_iter()
        .filter(|l| !l.is_empty())
        .map(|l| l.iter().map(|c| [c[0], c[1]]).collect())
        .collect();
    if parts.is_empty() {
        return None;
    }
    Some(LineTreeOut(tree::encode(g.srid, &parts).or_raise()))
}

extension_sql!(
    r#"
COMMENT ON FUNCTION _tin_linetree(bytea) IS 'Internal: use tin_linetree(geometry).';
"#,
    name = "tin_linetree_sql",
    requires = [_tin_linetree]
);

#[pg_extern(immutable, strict, parallel_safe, requires = ["linetree_type"])]
fn tin_linetree_info(t: LineTreeArg) -> pgrx::JsonB {
    let v = t.view();
    let h = v.header;
    pgrx::JsonB(serde_json::json!({
        "srid": h.srid,
        "parts": h.num_parts,
        "points": h.num_points,
        "nodes": h.num_nodes,
        "length": h.length,
        "bytes": t.bytes().len(),
    }))
}

extension_sql!(
    r#"
COMMENT ON FUNCTION tin_linetree_info(linetree) IS 'SRID, parts, points, tree nodes, planar length and size in bytes of a linetree.';
"#,
    name = "tin_linetree_info_sql",
    requires = [tin_linetree_info]
);

fn tin_level_tree<'a>(
    t: &TinArg,
    lt: &'a LineTreeArg,
    level: Option<i32>,
    func: &str,
) -> (Arc<Tin>, usize, View<'a>) {
    let tin = t.tin();
    let l = tin.level_index(level).or_raise();
    let v = lt.view();
    check_srid(v.header.srid, tin.srid, func, "line", None);
    (tin, l, v)
}

#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, cost = 10000, requires = ["linetree_type", "tin_type"])]
fn tin_line_triangles(
    t: Option<TinArg>,
    line: Option<LineTreeArg>,
    level: default!(Option<i32>, "NULL"),
    width: default!(Option<f64>, "0"),
) -> TableIterator<'static, (name!(seq, i32), name!(triangle, i32))> {
    let (Some(t), Some(line)) = (t, line) else {
        return TableIterator::new(Vec::new());
    };
    let width = check_width(width.unwrap_or(0.0));
    let (tin, l, v) = tin_level_tree(&t, &line, level, "tin_line_triangles");
    let tris = if width > 0.0 {
        near_tree(&tin, l, &v, width / 2.0, &mut interrupt).or_raise()
    } else {
        let mut sink = TriangleSink::default();
        walk_tree(&tin, l, &v, &mut sink, &mut |_, _| {}, &mut interrupt).or_raise();
        sink.tris
    };
    TableIterator::new(seq_rows(tris))
}

extension_sql!(
    r#"
ALTER FUNCTION tin_line_triangles(tin, linetree, int, float8) ROWS 100;
COMMENT ON FUNCTION tin_line_triangles(tin, linetree, int, float8) IS 'tin_line_triangles through a stored line tree: the same rows as for its geometry, visiting only the stretches near triangle edges.';
"#,
    name = "tin_line_triangles_tree_sql",
    requires = [tin_line_triangles]
);

#[pg_extern(immutable, parallel_safe, cost = 500, requires = ["linetree_type", "tin_type"])]
fn _tin_line_segments_tree(
    t: Option<TinArg>,
    line: Option<LineTreeArg>,
    level: default!(Option<i32>, "NULL"),
) -> TableIterator<
    'static,
    (
        name!(seq, i32),
        name!(triangle, i32),
        name!(geom, Vec<u8>),
        name!(length2d, f64),
        name!(length3d, f64),
        name!(rise, f64),
    ),
> {
    let (Some(t), Some(line)) = (t, line) else {
        return TableIterator::new(Vec::new());
    };
    let (tin, l, v) = tin_level_tree(&t, &line, level, "tin_line_segments");
    let tin: &Tin = &tin;
    let rows = super::line::segment_rows(tin, tin.srid, l, |sink| {
        walk_tree(tin, l, &v, sink, &mut |s, i| s.part = i, &mut interrupt)
    });
    TableIterator::new(rows)
}

extension_sql!(
    r#"
ALTER FUNCTION _tin_line_segments_tree(tin, linetree, int) ROWS 100;
COMMENT ON FUNCTION _tin_line_segments_tree(tin, linetree, int) IS 'Internal: use tin_line_segments(tin, linetree, int).';
"#,
    name = "tin_line_segments_tree_sql",
    requires = [_tin_line_segments_tree]
);

fn tree_profile(
    t: &TinArg,
    lt: &LineTreeArg,
    level: Option<i32>,
    func: &str,
) -> (Vec<(f64, f64)>, Option<f64>) {
    use tinmerge_core::merge::line::Polyline;
    let (tin, l, v) = tin_level_tree(t, lt, level, func);
    let tin: &Tin = &tin;
    let mut sink = PieceSink::new(tin, l);
    walk_tree(
        tin,
        l,
        &v,
        &mut sink,
        &mut |s, i| s.part = i,
        &mut interrupt,
    )
    .or_raise();
    let lengths: Vec<f64> = (0..v.header.num_parts)
        .map(|i| {
            let p = v.part_line(i)?;
            p.cum(p.len() - 1)
        })
        .collect::<Result<_, _>>()
        .or_raise();
    profile(
        &sink.finish().or_raise(),
        &part_offsets(lengths.into_iter()),
    )
}

#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, cost = 10000, requires = ["linetree_type", "tin_type"])]
fn tin_line_profile(
    t: Option<TinArg>,
    line: Option<LineTreeArg>,
    level: default!(Option<i32>, "NULL"),
) -> TableIterator<'static, (name!(distance, f64), name!(z, f64))> {
    let (Some(t), Some(line)) = (t, line) else {
        return TableIterator::new(Vec::new());
    };
    TableIterator::new(tree_profile(&t, &line, level, "tin_line_profile").0)
}

extension_sql!(
    r#"
ALTER FUNCTION tin_line_profile(tin, linetree, int) ROWS 100;
COMMENT ON FUNCTION tin_line_profile(tin, linetree, int) IS 'tin_line_profile through a stored line tree: the same rows as for its geometry.';
"#,
    name = "tin_line_profile_tree_sql",
    requires = [tin_line_profile]
);

#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, cost = 10000, requires = ["linetree_type", "tin_type"])]
fn tin_line_climb(
    t: Option<TinArg>,
    line: Option<LineTreeArg>,
    level: default!(Option<i32>, "NULL"),
) -> Option<f64> {
    let (t, line) = (t?, line?);
    tree_profile(&t, &line, level, "tin_line_climb").1
}

extension_sql!(
    r#"
COMMENT ON FUNCTION tin_line_climb(tin, linetree, int) IS 'tin_line_climb through a stored line tree: the same value as for its geometry.';
"#,
    name = "tin_line_climb_tree_sql",
    requires = [tin_line_climb]
);
