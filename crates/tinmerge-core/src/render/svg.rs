//! One level of a tin as an SVG picture: every triangle filled by its height,
//! by a value per triangle (a merge's statistics) or by a class per triangle
//! (an area merge's inside/boundary triangles), features drawn on top, and
//! a legend below.
//!
//! ```
//! use tinmerge_core::render::svg::{tin_svg, Fill, SvgOptions};
//! use tinmerge_core::tin::build::build;
//! let pts = vec![[0.0, 0.0, 1.0], [10.0, 0.0, 2.0], [0.0, 10.0, 3.0], [10.0, 10.0, 9.0]];
//! let t = build(pts, &[0.0], 0, &mut || Ok(())).unwrap();
//! let svg = tin_svg(&t, 0, &SvgOptions::default(), &mut || Ok(())).unwrap();
//! assert_eq!(svg.matches("<polygon").count(), 2);
//! ```

use crate::interrupt::{Interrupt, Ticker};
use std::collections::HashMap;
use std::fmt::Write;

use super::palette::{CLASSES, Ramp, Rgb, hex};
use crate::io::ewkb::{Coord3, Geom};
use crate::tin::{Tin, TinError};

/// What fills the triangles.
#[derive(Clone, Copy, Debug, Default)]
pub enum Fill<'a> {
    /// Mean height of the corners, hypsometric tints.
    #[default]
    Height,
    /// `values[i]` for triangle `triangles[i]` (viridis); other triangles and
    /// NaN values are light grey.
    Values {
        triangles: &'a [i32],
        values: &'a [f64],
    },
    /// `classes[i]` for triangle `triangles[i]`, one colour per distinct
    /// class (in order of first appearance); other triangles light grey.
    Classes {
        triangles: &'a [i32],
        classes: &'a [String],
    },
}

/// Options of [`tin_svg`].
#[derive(Clone, Copy, Debug)]
pub struct SvgOptions<'a> {
    pub fill: Fill<'a>,
    /// Drawn on top: lines and polygon outlines in black, points as dots.
    pub features: Option<&'a Geom>,
    /// Caption of the legend (default "height" or "value" or "class").
    pub legend: Option<&'a str>,
    /// Width of the picture in pixels (16..=16384).
    pub width: u32,
}

impl Default for SvgOptions<'_> {
    fn default() -> Self {
        SvgOptions {
            fill: Fill::Height,
            features: None,
            legend: None,
            width: 800,
        }
    }
}

/// Most distinct classes a picture can tell apart.
pub const MAX_CLASSES: usize = 20;
const NO_VALUE: Rgb = [225, 225, 225];
const MARGIN: f64 = 10.0;
const LEGEND_HEIGHT: f64 = 64.0;

/// Escape text for XML content and attributes.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace('\'', "&#39;")
}

/// Four significant digits, no trailing noise.
fn num(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let digits = (3 - v.abs().log10().floor() as i32).max(0) as usize;
    format!("{v:.digits$}")
}

/// Triangle id -> index into the value arrays, checking ids and lengths.
fn index_of(
    level: usize,
    n: usize,
    triangles: &[i32],
    len: usize,
    what: &str,
) -> Result<HashMap<u32, usize>, TinError> {
    if triangles.len() != len {
        return Err(TinError::InvalidParameter(format!(
            "triangles has {} elements but {what} has {len}: give one {what} element per triangle",
            triangles.len()
        )));
    }
    let mut m = HashMap::with_capacity(triangles.len());
    for (i, &t) in triangles.iter().enumerate() {
        if t < 0 || t as usize >= n {
            return Err(TinError::InvalidParameter(format!(
                "triangle id {t} is out of range: level {level} has triangles 0..{}",
                n.saturating_sub(1)
            )));
        }
        if m.insert(t as u32, i).is_some() {
            return Err(TinError::InvalidParameter(format!(
                "triangle id {t} appears more than once in triangles"
            )));
        }
    }
    Ok(m)
}

/// Per-triangle colours and the legend's content.
enum Legend {
    Ramp {
        ramp: Ramp,
        lo: f64,
        hi: f64,
        caption: String,
    },
    Classes {
        names: Vec<String>,
        caption: String,
    },
    None,
}

fn colours(tin: &Tin, level: usize, opts: &SvgOptions) -> Result<(Vec<Rgb>, Legend), TinError> {
    let lv = &tin.levels[level];
    let n = lv.num_domain();
    let caption = |d: &str| opts.legend.unwrap_or(d).to_string();
    match opts.fill {
        Fill::Height => {
            let (lo, hi) = (tin.bbox.min_z, tin.bbox.max_z);
            let cols = (0..n as u32)
                .map(|t| {
                    let c = tin.corners(level, t);
                    Ramp::Terrain.colour((c[0][2] + c[1][2] + c[2][2]) / 3.0, lo, hi)
                })
                .collect();
            Ok((
                cols,
                Legend::Ramp {
                    ramp: Ramp::Terrain,
                    lo,
                    hi,
                    caption: caption("height"),
                },
            ))
        }
        Fill::Values { triangles, values } => {
            let idx = index_of(level, n, triangles, values.len(), "values")?;
            let finite = values.iter().copied().filter(|v| v.is_finite());
            let lo = finite.clone().fold(f64::INFINITY, f64::min);
            let hi = finite.fold(f64::NEG_INFINITY, f64::max);
            let cols = (0..n as u32)
                .map(|t| match idx.get(&t).map(|&i| values[i]) {
                    Some(v) if v.is_finite() => Ramp::Viridis.colour(v, lo, hi),
                    _ => NO_VALUE,
                })
                .collect();
            let legend = if lo <= hi {
                Legend::Ramp {
                    ramp: Ramp::Viridis,
                    lo,
                    hi,
                    caption: caption("value"),
                }
            } else {
                Legend::None
            };
            Ok((cols, legend))
        }
        Fill::Classes { triangles, classes } => {
            let idx = index_of(level, n, triangles, classes.len(), "classes")?;
            let mut names: Vec<String> = Vec::new();
            let mut class_of = Vec::with_capacity(classes.len());
            for c in classes {
                let k = match names.iter().position(|x| x == c) {
                    Some(k) => k,
                    None => {
                        if names.len() == MAX_CLASSES {
                            return Err(TinError::InvalidParameter(format!(
                                "more than {MAX_CLASSES} distinct classes: a picture cannot tell them apart; use values instead"
                            )));
                        }
                        names.push(c.clone());
                        names.len() - 1
                    }
                };
                class_of.push(k);
            }
            let cols = (0..n as u32)
                .map(|t| match idx.get(&t) {
                    Some(&i) => CLASSES[class_of[i] % CLASSES.len()],
                    None => NO_VALUE,
                })
                .collect();
            Ok((
                cols,
                Legend::Classes {
                    names,
                    caption: caption("class"),
                },
            ))
        }
    }
}

/// Maps world coordinates to picture pixels (y down).
struct View {
    min_x: f64,
    max_y: f64,
    scale: f64,
}

impl View {
    fn px(&self, c: &[f64]) -> (f64, f64) {
        (
            MARGIN + (c[0] - self.min_x) * self.scale,
            MARGIN + (self.max_y - c[1]) * self.scale,
        )
    }
}

fn path_of(out: &mut String, v: &View, pts: &[Coord3], close: bool) {
    for (i, p) in pts.iter().enumerate() {
        let (x, y) = v.px(p);
        let _ = write!(out, "{}{x:.2} {y:.2}", if i == 0 { "M" } else { " L" });
    }
    if close {
        out.push('Z');
    }
}

fn features_svg(out: &mut String, v: &View, g: &Geom) {
    let mut d = String::new();
    let mut dots = String::new();
    let mut fill = String::new();
    let mut dot = |p: &Coord3| {
        let (x, y) = v.px(p);
        let _ = write!(dots, "<circle cx=\"{x:.2}\" cy=\"{y:.2}\" r=\"3\"/>");
    };
    let mut polygon = |rings: &Vec<Vec<Coord3>>, fill: &mut String| {
        for r in rings {
            path_of(fill, v, r, true);
        }
    };
    fn walk(
        g: &Geom,
        d: &mut String,
        fill: &mut String,
        v: &View,
        dot: &mut dyn FnMut(&Coord3),
        polygon: &mut dyn FnMut(&Vec<Vec<Coord3>>, &mut String),
    ) {
        match g {
            Geom::Point(p) => p.iter().for_each(dot),
            Geom::MultiPoint(ps) => ps.iter().for_each(dot),
            Geom::LineString(l) => path_of(d, v, l, false),
            Geom::MultiLineString(ls) => ls.iter().for_each(|l| path_of(d, v, l, false)),
            Geom::Polygon(rs) => polygon(rs, fill),
            Geom::MultiPolygon(ps) => ps.iter().for_each(|rs| polygon(rs, fill)),
            Geom::Collection(gs) => gs.iter().for_each(|g| walk(g, d, fill, v, dot, polygon)),
        }
    }
    walk(g, &mut d, &mut fill, v, &mut dot, &mut polygon);
    out.push_str("<g class=\"features\">");
    if !fill.is_empty() {
        let _ = write!(
            out,
            "<path d=\"{fill}\" fill=\"#000000\" fill-opacity=\"0.12\" fill-rule=\"evenodd\" stroke=\"#000000\" stroke-width=\"1.5\"/>"
        );
    }
    if !d.is_empty() {
        let _ = write!(
            out,
            "<path d=\"{d}\" fill=\"none\" stroke=\"#000000\" stroke-width=\"1.5\"/>"
        );
    }
    if !dots.is_empty() {
        let _ = write!(out, "<g fill=\"#000000\">{dots}</g>");
    }
    out.push_str("</g>");
}

fn legend_svg(out: &mut String, legend: &Legend, top: f64, width: f64) {
    let _ = write!(
        out,
        "<g class=\"legend\" font-family=\"sans-serif\" font-size=\"12\" transform=\"translate({MARGIN} {top:.2})\">"
    );
    match legend {
        Legend::Ramp {
            ramp,
            lo,
            hi,
            caption,
        } => {
            out.push_str("<defs><linearGradient id=\"ramp\">");
            for k in 0..=10 {
                let t = k as f64 / 10.0;
                let c = ramp.colour(lo + (hi - lo) * t, *lo, *hi);
                let _ = write!(out, "<stop offset=\"{t:.1}\" stop-color=\"{}\"/>", hex(c));
            }
            out.push_str("</linearGradient></defs>");
            let w = (width - 2.0 * MARGIN).clamp(1.0, 240.0);
            let _ = write!(
                out,
                "<text x=\"0\" y=\"14\">{}</text><rect x=\"0\" y=\"22\" width=\"{w:.0}\" height=\"14\" fill=\"url(#ramp)\" stroke=\"#444444\" stroke-width=\"0.5\"/><text x=\"0\" y=\"52\">{}</text><text x=\"{w:.0}\" y=\"52\" text-anchor=\"end\">{}</text>",
                esc(caption),
                num(*lo),
                num(*hi)
            );
        }
        Legend::Classes { names, caption } => {
            let _ = write!(out, "<text x=\"0\" y=\"14\">{}</text>", esc(caption));
            let (mut x, mut y) = (0.0, 22.0);
            for (k, name) in names.iter().enumerate() {
                let w = 22.0 + 7.0 * name.chars().count() as f64;
                if x > 0.0 && x + w > width - 2.0 * MARGIN {
                    x = 0.0;
                    y += 18.0;
                }
                let _ = write!(
                    out,
                    "<rect x=\"{x:.0}\" y=\"{y:.0}\" width=\"12\" height=\"12\" fill=\"{}\"/><text x=\"{:.0}\" y=\"{:.0}\">{}</text>",
                    hex(CLASSES[k % CLASSES.len()]),
                    x + 16.0,
                    y + 11.0,
                    esc(name)
                );
                x += w;
            }
        }
        Legend::None => {}
    }
    out.push_str("</g>");
}

/// The SVG document of one level. Triangles are `<polygon>` elements with
/// their id in `data-t`, inside `<g class="triangles">`, corners rounded to
/// 0.1 pixel; edges are drawn when triangles are large enough on screen to
/// see them (otherwise `crispEdges` keeps antialiasing seams out).
pub fn tin_svg(
    tin: &Tin,
    level: usize,
    opts: &SvgOptions,
    interrupt: &mut Interrupt<'_>,
) -> Result<String, TinError> {
    if !(16..=16384).contains(&opts.width) {
        return Err(TinError::InvalidParameter(format!(
            "width {} is out of range: pictures are 16 to 16384 pixels wide",
            opts.width
        )));
    }
    let lv = tin.levels.get(level).ok_or(TinError::LevelOutOfRange {
        level: level as i64,
        num_levels: tin.levels.len(),
    })?;
    let (cols, legend) = colours(tin, level, opts)?;
    // the frame: the domain's triangles (a tin with void triangles has
    // vertices off its domain)
    let domain_box;
    let b = if lv.num_void == 0 {
        &tin.bbox
    } else {
        let used: Vec<[f64; 3]> = lv.tris[..lv.num_domain()]
            .iter()
            .flatten()
            .map(|&v| tin.verts[v as usize])
            .collect();
        domain_box = crate::tin::Bbox::of(&used);
        &domain_box
    };
    let width = opts.width as f64;
    let scale = (width - 2.0 * MARGIN) / (b.max_x - b.min_x);
    let map_h = (b.max_y - b.min_y) * scale;
    let height = (MARGIN + map_h + MARGIN + LEGEND_HEIGHT).ceil();
    let view = View {
        min_x: b.min_x,
        max_y: b.max_y,
        scale,
    };
    let n = lv.num_domain();
    let edges = (width - 2.0 * MARGIN) * map_h / n.max(1) as f64 > 40.0;
    let mut out = String::with_capacity(200 + n * 96);
    let _ = write!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width:.0}\" height=\"{height:.0}\" viewBox=\"0 0 {width:.0} {height:.0}\">\
<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>"
    );
    let _ = write!(
        out,
        "<g class=\"triangles\" data-level=\"{level}\" stroke-linejoin=\"round\" {}>",
        if edges {
            "stroke=\"#000000\" stroke-opacity=\"0.35\" stroke-width=\"0.5\""
        } else {
            "shape-rendering=\"crispEdges\""
        }
    );
    let mut tk = Ticker::new(interrupt);
    for t in 0..n as u32 {
        tk.tick()?;
        let c = tin.corners(level, t);
        let p: Vec<(f64, f64)> = c.iter().map(|q| view.px(q)).collect();
        let _ = write!(
            out,
            "<polygon data-t=\"{t}\" points=\"{:.1},{:.1} {:.1},{:.1} {:.1},{:.1}\" fill=\"{}\"/>",
            p[0].0,
            p[0].1,
            p[1].0,
            p[1].1,
            p[2].0,
            p[2].1,
            hex(cols[t as usize])
        );
    }
    out.push_str("</g>");
    if let Some(g) = opts.features {
        features_svg(&mut out, &view, g);
    }
    legend_svg(&mut out, &legend, MARGIN + map_h + MARGIN, width);
    out.push_str("</svg>\n");
    Ok(out)
}

/// Working memory of an SVG picture of `triangles` triangles (the text,
/// about 100 bytes per triangle, plus colours).
pub fn svg_bytes(triangles: usize) -> usize {
    triangles.saturating_mul(112).saturating_add(1 << 16)
}
