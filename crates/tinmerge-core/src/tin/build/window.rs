//! A window of a raster (a tile) built over its valid cells only: the
//! tiles of `tin_tiles(..., fill_gaps => false)` whose data does not fill
//! the hull of their samples ([`crate::tin::tiles`]).

use super::common::*;
use super::levels::*;
use crate::interrupt::Interrupt;
use crate::polygon::Area;
use crate::tin::dense::Dense;
use crate::tin::lattice::Lattice;
use crate::tin::surface::GridReference;
use crate::tin::{Tin, TinError};

/// The height of `(x, y)` on a line of the window `d` (its frame): a column
/// `x` or a row `y`, from that line's samples alone. A sample's own height;
/// between two valid neighbours on the line, linear between them; else the
/// height of the valid pixel whose square holds the point (the end of a run
/// of data, half a pixel past its last sample: what `ST_Value` answers
/// there). None off the line or without data there.
pub(crate) fn line_height(d: &Dense, x: f64, y: f64, on_column: bool) -> Option<f64> {
    let (fixed, t) = if on_column { (x, y) } else { (y, x) };
    if fixed != fixed.trunc() {
        return None;
    }
    let at = |u: f64| -> Option<f64> {
        let (c, r) = if on_column { (fixed, u) } else { (u, fixed) };
        let (c, r) = (c as i64 - d.c0, r as i64 - d.r0);
        if c < 0 || r < 0 || c as usize >= d.width || r as usize >= d.height {
            return None;
        }
        let z = d.z[r as usize * d.width + c as usize];
        (!z.is_nan()).then_some(z)
    };
    let lo = t.floor();
    if t == lo {
        return at(t);
    }
    match (at(lo), at(lo + 1.0)) {
        (Some(a), Some(b)) => Some(a + (t - lo) * (b - a)),
        (Some(a), None) if t - lo <= 0.5 => Some(a),
        (None, Some(b)) if t - lo >= 0.5 => Some(b),
        _ => None,
    }
}

/// Build a window of a raster over its valid cells only: its `heights`
/// (in the window's own frame, `c0 = r0 = 0`, NaN without data; its first
/// pixel is `origin` on `lattice`) as scattered samples in that frame, with
/// `boundary` (in that frame: the valid pixels' squares clipped to the
/// window's outer pixel centres) as the domain, measured between the
/// samples on their grid. The boundary's segments on the window's outer
/// columns and rows are its seams ([`SeamLines`]): chosen from their
/// samples alone, keeping `keep` (positions on `lattice`), as a tile beside
/// it built either way chooses them. `local` sees the tin in the frame
/// before it is put on the lattice.
#[allow(clippy::too_many_arguments)]
pub fn build_lattice_window_domain(
    heights: &Dense,
    lattice: &Lattice,
    origin: (i64, i64),
    boundary: &Area,
    tolerances: &[f64],
    srid: i32,
    keep: &Border,
    local: &mut dyn FnMut(&Tin) -> Result<(), TinError>,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    let d = heights;
    let (w, h) = (d.width, d.height);
    let framed = d.c0 == 0 && d.r0 == 0 && d.z.len() == w.saturating_mul(h);
    if !framed || origin.0.abs() > 1_000_000_000 || origin.1.abs() > 1_000_000_000 || w < 1 || h < 1
    {
        return Err(TinError::InvalidParameter(format!(
            "window at ({}, {}) of {w} x {h} pixels is out of range",
            origin.0, origin.1
        )));
    }
    check_lattice(lattice)?;
    let mut local_samples = Vec::new();
    for (i, &z) in d.z.iter().enumerate() {
        if z.is_nan() {
            continue;
        }
        let (c, r) = ((i % w) as f64, (i / w) as f64);
        if !z.is_finite() {
            return Err(TinError::InvalidParameter(format!(
                "window sample ({}, {}, {z}) is not finite",
                c + origin.0 as f64,
                r + origin.1 as f64
            )));
        }
        local_samples.push([c, r, z]);
    }
    let last = [(w - 1) as f64, (h - 1) as f64];
    let height = |x: f64, y: f64| {
        if (x == 0.0 || x == last[0])
            && let Some(z) = line_height(d, x, y, true)
        {
            return Some(z);
        }
        if y == 0.0 || y == last[1] {
            return line_height(d, x, y, false);
        }
        None
    };
    let seams = SeamLines {
        last,
        height: &height,
    };
    let reference = GridReference::on_lattice(d);
    let keep = in_frame(keep, origin);
    let boundaries = [boundary];
    let spec = Spec {
        boundaries: &boundaries,
        reference: Some(&reference),
        border: &keep,
        seams: Some(&seams),
        ..Spec::new(
            tolerances,
            srid,
            BuildOptions {
                keep_border: true,
                between_samples: true,
            },
        )
    };
    let tin = build_inner(local_samples, &spec, interrupt)?;
    local(&tin)?;
    on_lattice(tin, lattice, origin)
}

/// An error for a lattice that cannot place a build (degenerate or not
/// finite).
pub(super) fn check_lattice(lattice: &Lattice) -> Result<(), TinError> {
    if lattice.is_valid() {
        return Ok(());
    }
    Err(TinError::InvalidParameter(format!(
        "raster georeference is degenerate or not finite (scale {} x {}, skew {} x {})",
        lattice.scale_x, lattice.scale_y, lattice.skew_x, lattice.skew_y
    )))
}
