//! Pictures of the real DEM's tin, read back by independent readers: the
//! `gltf` crate (with the `image` crate decoding the embedded PNG) for the
//! glb meshes, `roxmltree` for the SVG documents.
use crate::common;

use tinmerge_core::io::ewkb::Geom;
use tinmerge_core::io::raster::{Band, GeoTransform, Raster};
use tinmerge_core::render::gltf::{GlbOptions, Texture, tin_glb};
use tinmerge_core::render::svg::{Fill, SvgOptions, tin_svg};
use tinmerge_core::tin::{Tin, TinError};

fn ok() -> Result<(), TinError> {
    Ok(())
}

type Glb = (
    Vec<[f64; 3]>,
    Vec<[u32; 3]>,
    gltf::Document,
    Vec<gltf::image::Data>,
);

/// Positions (in the tin's own coordinates, undoing the glTF axes and the
/// origin from the node's extras) and triangles of a glb, as `gltf` reads
/// them.
fn read_glb(glb: &[u8]) -> Glb {
    let (doc, buffers, images) = gltf::import_slice(glb).expect("gltf crate reads the glb");
    let node = doc.nodes().next().expect("a node");
    let extras: serde_json::Value =
        serde_json::from_str(node.extras().as_ref().expect("extras").get()).expect("extras json");
    let o: Vec<f64> = extras["origin"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let zf = extras["z_factor"].as_f64().unwrap();
    let mesh = doc.meshes().next().expect("a mesh");
    let prim = mesh.primitives().next().expect("a primitive");
    let r = prim.reader(|b| Some(&buffers[b.index()]));
    let pos = r
        .read_positions()
        .expect("positions")
        .map(|p| {
            [
                p[0] as f64 + o[0],
                -(p[2] as f64) + o[1],
                p[1] as f64 / zf + o[2],
            ]
        })
        .collect();
    let idx: Vec<u32> = r.read_indices().expect("indices").into_u32().collect();
    let tris = idx.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
    (pos, tris, doc, images)
}

#[test]
fn glb_holds_the_level_exactly_as_built() {
    let t = common::dem_tin();
    for level in [0, t.num_levels() - 1] {
        let lv = &t.levels[level];
        let glb = tin_glb(
            &t,
            level,
            &GlbOptions {
                texture: None,
                z_factor: 2.5,
            },
        )
        .unwrap();
        let (pos, tris, doc, _) = read_glb(&glb);
        assert_eq!(pos.len(), lv.num_vertices as usize);
        assert_eq!(tris, lv.tris, "level {level}: triangles as stored");
        let worst = pos
            .iter()
            .zip(&t.verts)
            .map(|(p, v)| (0..3).map(|k| (p[k] - v[k]).abs()).fold(0.0, f64::max))
            .fold(0.0, f64::max);
        // single precision around the centre: ~1 mm on a 30 km terrain
        assert!(worst < 0.01, "level {level}: a vertex moved by {worst} m");
        let prim = doc.meshes().next().unwrap().primitives().next().unwrap();
        assert!(
            prim.get(&gltf::Semantic::Colors(0)).is_some(),
            "height colours without a texture"
        );
        // normals: unit length, pointing up (y) everywhere on a height field
        let (_, buffers, _) = gltf::import_slice(&glb).unwrap();
        let r = prim.reader(|b| Some(&buffers[b.index()]));
        for n in r.read_normals().expect("normals") {
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            assert!((len - 1.0).abs() < 1e-5 && n[1] > 0.0, "normal {n:?}");
        }
        // every triangle faces up (counter-clockwise seen from +y)
        for tri in &tris {
            let p = tri.map(|i| pos[i as usize]);
            let cross = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
            assert!(cross > 0.0);
        }
    }
}

/// A north-up RGB raster over the DEM's extent, colours from the pixel
/// indices, with one nodata pixel.
fn rgb_rasters(t: &Tin) -> Vec<Raster> {
    let (w, h) = (37usize, 29usize);
    let gt = GeoTransform {
        scale_x: (t.bbox.max_x - t.bbox.min_x) / w as f64,
        scale_y: -(t.bbox.max_y - t.bbox.min_y) / h as f64,
        ip_x: t.bbox.min_x,
        ip_y: t.bbox.max_y,
        skew_x: 0.0,
        skew_y: 0.0,
    };
    (0..3)
        .map(|k| {
            let values = (0..w * h)
                .map(|p| {
                    if p == 40 && k == 1 {
                        0.0
                    } else {
                        ((p % w) * 7 + (p / w) * 3 + k * 50) as f64 % 250.0 + 1.0
                    }
                })
                .collect();
            Raster {
                srid: t.srid,
                width: w,
                height: h,
                num_bands: 3,
                gt,
                band: Some(Band {
                    pixel_type: 4,
                    nodata: Some(0.0),
                    all_nodata: false,
                    values,
                }),
            }
        })
        .collect()
}

#[test]
fn glb_texture_is_the_raster_and_every_vertex_points_at_its_pixel() {
    let t = common::dem_tin();
    let rasters = rgb_rasters(&t);
    let tex = Texture::from_bands(&rasters).unwrap();
    let glb = tin_glb(
        &t,
        1,
        &GlbOptions {
            texture: Some(&tex),
            z_factor: 1.0,
        },
    )
    .unwrap();
    let (pos, _, doc, images) = read_glb(&glb);
    assert_eq!(images.len(), 1);
    let img = &images[0];
    assert_eq!((img.width as usize, img.height as usize), (37, 29));
    assert_eq!(img.format, gltf::image::Format::R8G8B8A8);
    let (w, h) = (37usize, 29usize);
    for p in 0..w * h {
        let px = &img.pixels[p * 4..p * 4 + 4];
        let want: Vec<u8> = (0..3)
            .map(|k| rasters[k].band.as_ref().unwrap().values[p] as u8)
            .collect();
        if p == 40 {
            assert_eq!(px[3], 0, "nodata pixel is transparent");
        } else {
            assert_eq!(&px[..3], &want[..], "pixel {p}");
            assert_eq!(px[3], 255);
        }
    }
    let prim = doc.meshes().next().unwrap().primitives().next().unwrap();
    let (_, buffers, _) = gltf::import_slice(&glb).unwrap();
    let r = prim.reader(|b| Some(&buffers[b.index()]));
    let uvs: Vec<[f32; 2]> = r
        .read_tex_coords(0)
        .expect("texcoords")
        .into_f32()
        .collect();
    assert_eq!(uvs.len(), pos.len());
    let gt = rasters[0].gt;
    let mut checked = 0;
    for (uv, v) in uvs.iter().zip(&t.verts) {
        // the pixel of the vertex, from the geotransform
        let col = ((v[0] - gt.ip_x) / gt.scale_x).floor();
        let row = ((v[1] - gt.ip_y) / gt.scale_y).floor();
        let (u, vv) = (uv[0] as f64 * w as f64, uv[1] as f64 * h as f64);
        if (u - u.round()).abs() < 1e-3 || (vv - vv.round()).abs() < 1e-3 {
            continue; // on a pixel edge: either side is right
        }
        assert_eq!((u.floor(), vv.floor()), (col, row));
        checked += 1;
    }
    assert!(checked > 1000, "{checked} vertices checked");
}

#[test]
fn bad_render_arguments_are_errors() {
    let t = common::dem_tin();
    assert!(
        tin_glb(
            &t,
            0,
            &GlbOptions {
                texture: None,
                z_factor: 0.0
            }
        )
        .is_err()
    );
    assert!(
        tin_glb(
            &t,
            0,
            &GlbOptions {
                texture: None,
                z_factor: f64::NAN
            }
        )
        .is_err()
    );
    assert!(matches!(
        tin_glb(&t, 99, &GlbOptions::default()),
        Err(TinError::LevelOutOfRange { .. })
    ));
    let mut r = rgb_rasters(&t);
    assert!(Texture::from_bands(&r[..2]).is_err(), "2 bands");
    r[0].gt.skew_x = 1.0;
    assert!(Texture::from_bands(&r).is_err(), "skewed");
    let vals = [1.0, 2.0];
    let value_error = |ids: &[i32]| {
        let fill = Fill::Values {
            triangles: ids,
            values: &vals,
        };
        let opts = SvgOptions {
            fill,
            ..SvgOptions::default()
        };
        tin_svg(&t, 0, &opts, &mut ok).unwrap_err().to_string()
    };
    for (ids, says) in [
        (&[0, 1, 2][..], "3 elements"),
        (&[0, -1], "out of range"),
        (&[4, 4], "more than once"),
    ] {
        let e = value_error(ids);
        assert!(e.contains(says), "{e}");
    }
    let opts = |fill| SvgOptions {
        fill,
        ..SvgOptions::default()
    };
    let many: Vec<String> = (0..21).map(|i| format!("c{i}")).collect();
    let ids: Vec<i32> = (0..21).collect();
    assert!(
        tin_svg(
            &t,
            0,
            &opts(Fill::Classes {
                triangles: &ids,
                classes: &many
            }),
            &mut ok
        )
        .is_err()
    );
    let wide = SvgOptions {
        width: 10,
        ..SvgOptions::default()
    };
    assert!(tin_svg(&t, 0, &wide, &mut ok).is_err());
}

fn parse_points(s: &str) -> Vec<(f64, f64)> {
    s.split_whitespace()
        .map(|p| {
            let (x, y) = p.split_once(',').unwrap();
            (x.parse().unwrap(), y.parse().unwrap())
        })
        .collect()
}

#[test]
fn svg_draws_every_triangle_where_it_is() {
    let t = common::dem_tin();
    let level = 2;
    let lv = &t.levels[level];
    let width = 1000;
    let svg = tin_svg(
        &t,
        level,
        &SvgOptions {
            width,
            ..SvgOptions::default()
        },
        &mut ok,
    )
    .unwrap();
    let doc = roxmltree::Document::parse(&svg).expect("well-formed XML");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "svg");
    let polys: Vec<_> = doc
        .descendants()
        .filter(|n| n.has_tag_name("polygon"))
        .collect();
    assert_eq!(polys.len(), lv.num_triangles());
    // the drawing maps x, y by one scale and offset (y flipped): fit it from
    // the bounding box and check every corner of every triangle
    let scale = (width as f64 - 20.0) / (t.bbox.max_x - t.bbox.min_x);
    let mut worst: f64 = 0.0;
    let mut seen = vec![false; lv.num_triangles()];
    for p in &polys {
        let id: usize = p.attribute("data-t").unwrap().parse().unwrap();
        seen[id] = true;
        let pts = parse_points(p.attribute("points").unwrap());
        for (q, c) in pts.iter().zip(t.corners(level, id as u32)) {
            let x = 10.0 + (c[0] - t.bbox.min_x) * scale;
            let y = 10.0 + (t.bbox.max_y - c[1]) * scale;
            worst = worst.max((q.0 - x).abs()).max((q.1 - y).abs());
        }
        assert!(p.attribute("fill").unwrap().starts_with('#'));
    }
    assert!(seen.iter().all(|&s| s));
    assert!(worst <= 0.051, "corners off by {worst} px");
    let legend = doc
        .descendants()
        .find(|n| n.attribute("class") == Some("legend"))
        .expect("legend");
    let texts: Vec<&str> = legend.descendants().filter_map(|n| n.text()).collect();
    assert!(texts.contains(&"height"), "{texts:?}");
}

#[test]
fn svg_colours_values_and_classes() {
    let t = common::dem_tin();
    let level = 1;
    let n = t.levels[level].num_triangles();
    let ids: Vec<i32> = (0..n as i32).step_by(3).collect();
    let vals: Vec<f64> = ids.iter().map(|&i| i as f64 * 0.5 - 7.0).collect();
    let line = Geom::LineString(vec![
        [t.bbox.min_x, t.bbox.min_y, f64::NAN],
        [t.bbox.max_x, t.bbox.max_y, f64::NAN],
    ]);
    let opts = SvgOptions {
        fill: Fill::Values {
            triangles: &ids,
            values: &vals,
        },
        features: Some(&line),
        legend: Some("mean <height> & more"),
        width: 600,
    };
    let svg = tin_svg(&t, level, &opts, &mut ok).unwrap();
    let doc = roxmltree::Document::parse(&svg).expect("well-formed XML (escaped legend)");
    let fill_of = |id: usize| {
        doc.descendants()
            .find(|n| n.has_tag_name("polygon") && n.attribute("data-t") == Some(&id.to_string()))
            .and_then(|n| n.attribute("fill"))
            .unwrap()
            .to_string()
    };
    // smallest value: first viridis stop; largest: last; no value: grey
    assert_eq!(fill_of(0), "#440154");
    assert_eq!(fill_of(*ids.last().unwrap() as usize), "#fde725");
    assert_eq!(fill_of(1), "#e1e1e1");
    let texts: Vec<&str> = doc.descendants().filter_map(|n| n.text()).collect();
    assert!(texts.contains(&"mean <height> & more"));
    assert!(texts.contains(&"-7.000"), "{texts:?}");
    let paths: Vec<_> = doc
        .descendants()
        .filter(|n| n.has_tag_name("path") && n.attribute("fill") == Some("none"))
        .collect();
    assert_eq!(paths.len(), 1, "the line");
    let d = paths[0].attribute("d").unwrap();
    assert!(
        d.starts_with("M10.00 ") && d.contains(" L590.00 10.00"),
        "{d}"
    );

    // classes: distinct colours per class, legend in order of appearance
    let classes: Vec<String> = (0..ids.len())
        .map(|k| ["inside", "boundary", "compact"][k % 3].to_string())
        .collect();
    let opts = SvgOptions {
        fill: Fill::Classes {
            triangles: &ids,
            classes: &classes,
        },
        ..SvgOptions::default()
    };
    let svg = tin_svg(&t, level, &opts, &mut ok).unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let mut by_class = std::collections::HashMap::new();
    for (id, c) in ids.iter().zip(&classes) {
        let f = doc
            .descendants()
            .find(|n| n.has_tag_name("polygon") && n.attribute("data-t") == Some(&id.to_string()))
            .and_then(|n| n.attribute("fill"))
            .unwrap();
        assert_eq!(
            *by_class.entry(c.clone()).or_insert(f),
            f,
            "one colour per class"
        );
    }
    let colours: std::collections::HashSet<_> = by_class.values().collect();
    assert_eq!(colours.len(), 3);
    let legend = doc
        .descendants()
        .find(|n| n.attribute("class") == Some("legend"))
        .unwrap();
    let names: Vec<&str> = legend
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text())
        .collect();
    assert_eq!(names, ["class", "inside", "boundary", "compact"]);
}
