//! SQL functions that draw: `tin_as_svg` (an SVG picture of a level,
//! coloured by height, by a value per triangle or by a class per triangle,
//! features on top) and `tin_as_gltf` (a binary glTF mesh, optionally with a
//! raster painted on it). Not STRICT: a NULL level means the finest and the
//! colouring arguments are optional; a NULL tin gives NULL.

use pgrx::prelude::*;

use super::args::check_srid;
use super::errors::{raise, OrRaise};
use super::interrupt::interrupt;
use super::memory;
use super::raster::check_raster_srid;
use super::tin_type::tin_level;
use super::tin_type::TinArg;
use tinmerge_core::io::{ewkb, raster};
use tinmerge_core::render::gltf::{tin_glb, GlbOptions, Texture};
use tinmerge_core::render::svg::{tin_svg, Fill, SvgOptions};

fn no_nulls<T: Copy>(a: &[Option<T>], what: &str) -> Vec<T> {
    a.iter()
        .map(|v| {
            v.unwrap_or_else(|| {
                raise(
                    PgSqlErrorCode::ERRCODE_NULL_VALUE_NOT_ALLOWED,
                    format!("tin_as_svg: {what} must not contain NULL"),
                )
            })
        })
        .collect()
}

#[allow(clippy::too_many_arguments)]
#[pg_extern(immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn _tin_as_svg(
    t: Option<TinArg>,
    level: Option<i32>,
    triangles: Option<Vec<Option<i32>>>,
    vals: Option<Vec<Option<f64>>>,
    classes: Option<Vec<Option<String>>>,
    features: Option<&[u8]>,
    legend: Option<String>,
    width: Option<i32>,
) -> Option<String> {
    let t = t?;
    let (tin, l) = tin_level(&t, level);
    let ids = triangles.as_deref().map(|a| no_nulls(a, "triangles"));
    let values: Option<Vec<f64>> =
        vals.map(|a| a.into_iter().map(|v| v.unwrap_or(f64::NAN)).collect());
    let names: Option<Vec<String>> = classes.map(|a| {
        a.into_iter()
            .map(|v| v.unwrap_or_else(|| "NULL".to_string()))
            .collect()
    });
    // triangles alone: highlight them as one class
    let selected: Vec<String>;
    let fill = match (&ids, &values, &names) {
        (None, None, None) => Fill::Height,
        (Some(ids), Some(values), None) => Fill::Values {
            triangles: ids,
            values,
        },
        (Some(ids), None, Some(classes)) => Fill::Classes {
            triangles: ids,
            classes,
        },
        (Some(ids), None, None) => {
            selected = vec!["selected".to_string(); ids.len()];
            Fill::Classes {
                triangles: ids,
                classes: &selected,
            }
        }
        (None, _, _) => raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            "tin_as_svg: vals or classes need triangles (the triangle id of each value)",
        ),
        (Some(_), Some(_), Some(_)) => raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            "tin_as_svg: give vals or classes, not both",
        ),
    };
    let g = features.map(|b| {
        let g = ewkb::read(b).or_raise();
        check_srid(
            g.srid,
            tin.srid,
            "tin_as_svg",
            "features",
            super::args::first_xy(&g.geom),
        );
        g
    });
    let width = width.unwrap_or(800);
    let opts = SvgOptions {
        fill,
        features: g.as_ref().map(|g| &g.geom),
        legend: legend.as_deref(),
        width: u32::try_from(width).unwrap_or(0),
    };
    memory::reserve(
        tinmerge_core::render::svg::svg_bytes(tin.levels[l].num_triangles()),
        || format!("drawing {} triangles", tin.levels[l].num_triangles()),
    );
    Some(tin_svg(&tin, l, &opts, &mut interrupt).or_raise())
}

extension_sql!(
    r#"
COMMENT ON FUNCTION _tin_as_svg(tin, int, int[], float8[], text[], bytea, text, int) IS 'Internal: use tin_as_svg(tin, ...).';
"#,
    name = "tin_as_svg_sql",
    requires = [_tin_as_svg]
);

#[pg_extern(immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn _tin_as_gltf(
    t: Option<TinArg>,
    level: Option<i32>,
    texture: Option<&[u8]>,
    z_factor: Option<f64>,
) -> Option<Vec<u8>> {
    let t = t?;
    let (tin, l) = tin_level(&t, level);
    let tex = texture.map(|b| {
        let head = raster::read(b, None).or_raise();
        check_raster_srid(head.srid, tin.srid, "tin_as_gltf");
        memory::reserve(
            tinmerge_core::io::raster::raster_bytes(head.width, head.height)
                * head.num_bands.max(1),
            || format!("reading a {} x {} texture", head.width, head.height),
        );
        let bands: Vec<_> = (1..=head.num_bands)
            .map(|i| raster::read(b, Some(i)).or_raise())
            .collect();
        Texture::from_bands(&bands).or_raise()
    });
    let opts = GlbOptions {
        texture: tex.as_ref(),
        z_factor: z_factor.unwrap_or(1.0),
    };
    memory::reserve(
        tinmerge_core::render::gltf::glb_bytes(
            tin.levels[l].num_vertices as usize,
            tin.levels[l].num_triangles(),
        ),
        || format!("a glTF of {} triangles", tin.levels[l].num_triangles()),
    );
    Some(tin_glb(&tin, l, &opts).or_raise())
}

extension_sql!(
    r#"
COMMENT ON FUNCTION _tin_as_gltf(tin, int, bytea, float8) IS 'Internal: use tin_as_gltf(tin, ...).';
"#,
    name = "tin_as_gltf_sql",
    requires = [_tin_as_gltf]
);
