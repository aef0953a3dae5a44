//! One level of a tin as a binary glTF 2.0 (`.glb`) mesh, optionally with
//! an image painted on the surface as a texture (Scarlatos's "painting an
//! image on the surface": every vertex gets the image coordinates of its
//! x, y, and the viewer interpolates the image across each triangle).
//!
//! Axes: glTF is y-up, so a vertex (x, y, z) is written as
//! `(x - cx, (z - cz) * z_factor, -(y - cy))` around the centre `c` of the
//! bounding box (single-precision floats keep centimetres that way); the
//! centre, SRID and z factor are in the node's `extras` to put the mesh
//! back in place. Without a texture, vertices carry colours by height.
//!
//! ```
//! use tinmerge_core::render::gltf::{tin_glb, GlbOptions};
//! use tinmerge_core::tin::build::build;
//! let pts = vec![[0.0, 0.0, 1.0], [10.0, 0.0, 2.0], [0.0, 10.0, 3.0], [10.0, 10.0, 9.0]];
//! let t = build(pts, &[0.0], 0, &mut || Ok(())).unwrap();
//! let glb = tin_glb(&t, 0, &GlbOptions::default()).unwrap();
//! assert_eq!(&glb[0..4], b"glTF");
//! ```

use serde_json::{Value, json};

use super::palette::Ramp;
use crate::io::raster::{Band, Raster};
use crate::tin::{Tin, TinError};

/// Largest texture side: what WebGL implementations reliably accept.
pub const MAX_TEXTURE: usize = 8192;

/// An RGBA image with its georeferencing (north-up: pixel (col, row) has
/// its top-left corner at `(ip_x + col * scale_x, ip_y + row * scale_y)`).
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    pub width: usize,
    pub height: usize,
    /// Row-major RGBA, `width * height * 4` bytes.
    pub rgba: Vec<u8>,
    pub ip_x: f64,
    pub ip_y: f64,
    pub scale_x: f64,
    pub scale_y: f64,
}

/// 0..255 for each value of a band: 8-bit unsigned bands as they are, any
/// other type stretched linearly from its smallest to its largest valid
/// value.
fn to_bytes(b: &Band) -> Vec<u8> {
    if b.pixel_type == 4 {
        return b
            .values
            .iter()
            .map(|&v| v.clamp(0.0, 255.0) as u8)
            .collect();
    }
    let valid = b.values.iter().copied().filter(|&v| b.is_valid(v));
    let lo = valid.clone().fold(f64::INFINITY, f64::min);
    let hi = valid.fold(f64::NEG_INFINITY, f64::max);
    b.values
        .iter()
        .map(|&v| {
            if !b.is_valid(v) || hi <= lo {
                0
            } else {
                ((v - lo) / (hi - lo) * 255.0).round().clamp(0.0, 255.0) as u8
            }
        })
        .collect()
}

impl Texture {
    /// The image of 1 band (grey), 3 bands (RGB) or 4 bands (RGBA) of one
    /// raster (`rasters[i]` holding band i+1). Pixels where any colour band
    /// is nodata are transparent.
    pub fn from_bands(rasters: &[Raster]) -> Result<Texture, TinError> {
        let bad = |m: String| Err(TinError::InvalidParameter(m));
        let Some(first) = rasters.first() else {
            return bad("texture raster has no bands".into());
        };
        if ![1, 3, 4].contains(&rasters.len()) {
            return bad(format!(
                "texture raster has {} bands: use 1 (grey), 3 (RGB) or 4 (RGBA)",
                rasters.len()
            ));
        }
        let (w, h, gt) = (first.width, first.height, first.gt);
        if w == 0 || h == 0 {
            return bad(format!("texture raster is empty ({w} x {h} pixels)"));
        }
        if w > MAX_TEXTURE || h > MAX_TEXTURE {
            return Err(TinError::TooLarge(format!(
                "texture raster is {w} x {h} pixels; at most {MAX_TEXTURE} on a side (resample it with ST_Resize)"
            )));
        }
        if gt.skew_x != 0.0 || gt.skew_y != 0.0 {
            return bad("texture raster is skewed or rotated: only north-up rasters can be painted (ST_Rescale or gdalwarp it first)".into());
        }
        if !(gt.scale_x.is_finite()
            && gt.scale_y.is_finite()
            && gt.scale_x != 0.0
            && gt.scale_y != 0.0)
        {
            return bad("texture raster has a zero or non-finite pixel size".into());
        }
        let mut bands = Vec::with_capacity(rasters.len());
        for (i, r) in rasters.iter().enumerate() {
            let Some(b) = &r.band else {
                return bad(format!("texture raster has no band {}", i + 1));
            };
            if b.values.len() != w * h {
                return bad(format!(
                    "texture band {} does not have {w} x {h} pixels",
                    i + 1
                ));
            }
            bands.push((to_bytes(b), b));
        }
        let colour = if bands.len() == 1 { 1 } else { 3 };
        let mut rgba = vec![0u8; w * h * 4];
        for p in 0..w * h {
            let opaque = bands[..colour].iter().all(|(_, b)| b.is_valid(b.values[p]));
            let px = &mut rgba[p * 4..p * 4 + 4];
            for k in 0..3 {
                px[k] = bands[k.min(colour - 1)].0[p];
            }
            px[3] = match (opaque, bands.get(3)) {
                (false, _) => 0,
                (true, Some((a, _))) => a[p],
                (true, None) => 255,
            };
        }
        Ok(Texture {
            width: w,
            height: h,
            rgba,
            ip_x: gt.ip_x,
            ip_y: gt.ip_y,
            scale_x: gt.scale_x,
            scale_y: gt.scale_y,
        })
    }

    /// Image coordinates (0..1 across the image) of a point.
    pub fn uv(&self, x: f64, y: f64) -> [f32; 2] {
        [
            ((x - self.ip_x) / (self.width as f64 * self.scale_x)) as f32,
            ((y - self.ip_y) / (self.height as f64 * self.scale_y)) as f32,
        ]
    }

    fn png(&self) -> Result<Vec<u8>, TinError> {
        let mut out = Vec::new();
        let err = |e: png::EncodingError| TinError::InvalidParameter(format!("texture: {e}"));
        let mut enc = png::Encoder::new(&mut out, self.width as u32, self.height as u32);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        let mut w = enc.write_header().map_err(err)?;
        w.write_image_data(&self.rgba).map_err(err)?;
        w.finish().map_err(err)?;
        Ok(out)
    }
}

/// Options of [`tin_glb`].
#[derive(Clone, Debug)]
pub struct GlbOptions<'a> {
    pub texture: Option<&'a Texture>,
    /// Vertical exaggeration (heights multiplied by it), finite and > 0.
    pub z_factor: f64,
}

impl Default for GlbOptions<'_> {
    fn default() -> Self {
        GlbOptions {
            texture: None,
            z_factor: 1.0,
        }
    }
}

const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;

/// The binary chunk being filled, with its buffer views and accessors.
#[derive(Default)]
struct Chunk {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Chunk {
    /// Append `bytes` (4-byte aligned) as a buffer view; its index.
    fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        pad4(&mut self.bin, 0);
        let mut v = json!({"buffer": 0, "byteOffset": offset, "byteLength": bytes.len()});
        if let Some(t) = target {
            v["target"] = json!(t);
        }
        self.views.push(v);
        self.views.len() - 1
    }

    fn accessor(&mut self, a: Value) -> usize {
        self.accessors.push(a);
        self.accessors.len() - 1
    }

    /// A vertex attribute of `count` elements of `kind` (VEC2, VEC3) as
    /// little-endian f32, with its bounds when given; the accessor's index.
    fn floats(
        &mut self,
        data: &[f32],
        count: usize,
        kind: &str,
        bounds: Option<(&[f32; 3], &[f32; 3])>,
    ) -> usize {
        let bytes: Vec<u8> = data.iter().flat_map(|x| x.to_le_bytes()).collect();
        let view = self.view(&bytes, Some(ARRAY_BUFFER));
        let mut a =
            json!({"bufferView": view, "componentType": 5126, "count": count, "type": kind});
        if let Some((lo, hi)) = bounds {
            a["min"] = json!(lo);
            a["max"] = json!(hi);
        }
        self.accessor(a)
    }
}

/// sRGB byte to linear (glTF vertex colours are linear).
fn linear(c: u8) -> f32 {
    let s = c as f64 / 255.0;
    (if s <= 0.04045 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }) as f32
}

/// Pad to a multiple of 4 bytes (glb chunks and buffer views are aligned).
fn pad4(b: &mut Vec<u8>, byte: u8) {
    b.resize(b.len().next_multiple_of(4), byte);
}

/// Area-weighted vertex normals of the triangles `tris` over the vertex
/// positions `pos`, of unit length (straight up where no triangle has area).
fn vertex_normals(pos: &[[f32; 3]], tris: &[[u32; 3]]) -> Vec<[f32; 3]> {
    // area-weighted vertex normals
    let mut nrm = vec![[0.0f64; 3]; pos.len()];
    for t in tris {
        let p = t.map(|i| pos[i as usize].map(f64::from));
        let e1 = [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]];
        let e2 = [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]];
        let n = [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ];
        for &i in t {
            for k in 0..3 {
                nrm[i as usize][k] += n[k];
            }
        }
    }
    nrm.iter()
        .map(|n| {
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            if len > 0.0 {
                n.map(|x| (x / len) as f32)
            } else {
                [0.0, 1.0, 0.0]
            }
        })
        .collect()
}

/// The binary glTF container (glb 2.0): the header, the JSON chunk `doc`
/// padded with spaces and the binary chunk `bin`.
fn glb(doc: &serde_json::Value, bin: &[u8]) -> Result<Vec<u8>, TinError> {
    let mut js = serde_json::to_vec(doc).map_err(|e| TinError::InvalidParameter(e.to_string()))?;
    pad4(&mut js, b' ');
    let total = 12 + 8 + js.len() + 8 + bin.len();
    let total32 = u32::try_from(total).map_err(|_| {
        TinError::TooLarge(format!(
            "the glTF would be {total} bytes; glb files hold at most 4 GB"
        ))
    })?;
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&total32.to_le_bytes());
    out.extend_from_slice(&(js.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&js);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(bin);
    Ok(out)
}

/// The `.glb` bytes of one level.
pub fn tin_glb(tin: &Tin, level: usize, opts: &GlbOptions) -> Result<Vec<u8>, TinError> {
    let lv = tin.levels.get(level).ok_or(TinError::LevelOutOfRange {
        level: level as i64,
        num_levels: tin.levels.len(),
    })?;
    if !(opts.z_factor.is_finite() && opts.z_factor > 0.0) {
        return Err(TinError::InvalidParameter(format!(
            "z_factor must be finite and greater than 0, got {}",
            opts.z_factor
        )));
    }
    let b = &tin.bbox;
    let c = [
        (b.min_x + b.max_x) / 2.0,
        (b.min_y + b.max_y) / 2.0,
        (b.min_z + b.max_z) / 2.0,
    ];
    let nv = lv.num_vertices as usize;
    let verts = &tin.verts[..nv];
    let pos: Vec<[f32; 3]> = verts
        .iter()
        .map(|v| {
            [
                (v[0] - c[0]) as f32,
                ((v[2] - c[2]) * opts.z_factor) as f32,
                (-(v[1] - c[1])) as f32,
            ]
        })
        .collect();
    // the domain's triangles (the void ones are the last)
    let tris = &lv.tris[..lv.num_domain()];
    let mut chunk = Chunk::default();
    let mut attributes = serde_json::Map::new();
    let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for p in &pos {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let a = chunk.floats(pos.as_flattened(), nv, "VEC3", Some((&lo, &hi)));
    attributes.insert("POSITION".into(), json!(a));
    let unit = vertex_normals(&pos, tris);
    let a = chunk.floats(unit.as_flattened(), nv, "VEC3", None);
    attributes.insert("NORMAL".into(), json!(a));
    let mut material = json!({
        "name": "surface",
        "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0},
        "doubleSided": true
    });
    let mut png_bytes = None;
    if let Some(tex) = opts.texture {
        let uv: Vec<[f32; 2]> = verts.iter().map(|v| tex.uv(v[0], v[1])).collect();
        let a = chunk.floats(uv.as_flattened(), nv, "VEC2", None);
        attributes.insert("TEXCOORD_0".into(), json!(a));
        material["pbrMetallicRoughness"]["baseColorTexture"] = json!({"index": 0});
        material["alphaMode"] = json!("MASK");
        png_bytes = Some(tex.png()?);
    } else {
        let cols: Vec<[f32; 3]> = verts
            .iter()
            .map(|v| Ramp::Terrain.colour(v[2], b.min_z, b.max_z).map(linear))
            .collect();
        let a = chunk.floats(cols.as_flattened(), nv, "VEC3", None);
        attributes.insert("COLOR_0".into(), json!(a));
    }
    let idx: Vec<u8> = tris
        .iter()
        .flatten()
        .flat_map(|i| i.to_le_bytes())
        .collect();
    let view = chunk.view(&idx, Some(ELEMENT_ARRAY_BUFFER));
    let ind = chunk.accessor(
        json!({"bufferView": view, "componentType": 5125, "count": tris.len() * 3, "type": "SCALAR"}),
    );
    let mut doc = json!({
        "asset": {"version": "2.0", "generator": "tinmerge"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": format!("tin level {level}"), "extras": {
            "srid": tin.srid, "origin": c, "z_factor": opts.z_factor, "level": level,
            "axes": "x = east - origin[0], y = (height - origin[2]) * z_factor, z = -(north - origin[1])"
        }}],
        "meshes": [{"name": "surface", "primitives": [{"attributes": attributes, "indices": ind, "material": 0, "mode": 4}]}],
        "materials": [material],
    });
    if let Some(png) = png_bytes {
        let view = chunk.view(&png, None);
        doc["images"] = json!([{"bufferView": view, "mimeType": "image/png"}]);
        doc["samplers"] =
            json!([{"magFilter": 9729, "minFilter": 9729, "wrapS": 33071, "wrapT": 33071}]);
        doc["textures"] = json!([{"sampler": 0, "source": 0}]);
    }
    let Chunk {
        bin,
        views,
        accessors,
    } = chunk;
    doc["accessors"] = json!(accessors);
    doc["bufferViews"] = json!(views);
    doc["buffers"] = json!([{"byteLength": bin.len()}]);
    glb(&doc, &bin)
}

/// Working memory of a glTF mesh: per vertex the f32 attributes, the f64
/// normal sums and the copies into the binary chunk and the output; per
/// triangle the indices, twice.
pub fn glb_bytes(vertices: usize, triangles: usize) -> usize {
    vertices
        .saturating_mul(136)
        .saturating_add(triangles.saturating_mul(36))
        .saturating_add(1 << 16)
}
