//! One tile of a tiled terrain built with keep_border: its samples on the
//! common lattice, its decisions made in its own frame, and the seam
//! samples it asks its neighbours to keep ([`Wanted`]). The grid of tiles
//! ([`super::tiles`]) and a tile over its data only
//! ([`super::tile_domain`]) both build on it.

use super::NONE;
#[cfg(doc)]
use super::build::build_lattice_window;
use super::build::{Border, BuildOptions, build_lattice_window_kept};
use super::dense::Dense;
use super::lattice::Lattice;
use super::surface::{GridReference, Reference};
use super::{Tin, TinError};
use crate::interrupt::Interrupt;

/// Build one tile's samples (column, row, value on `lattice`) with
/// keep_border, between the samples, its decisions made in the tile's own
/// frame (`origin`: its first pixel; [`build_lattice_window`]), so it is
/// the tin of that tile cut out in SQL up to the rounding of the vertices
/// put at grid-line crossings: `Ok(None)` when they cannot be triangulated
/// (fewer than three, or all on one line). Its seams hold the tolerance
/// at their samples only: [`build_tile_kept`] and [`Seams`](super::tiles::Seams) hold it in the
/// strips along them too.
pub fn build_tile(
    samples: Vec<[f64; 3]>,
    lattice: &Lattice,
    origin: (i64, i64),
    tolerances: &[f64],
    srid: i32,
    interrupt: &mut Interrupt<'_>,
) -> Result<Option<Tin>, TinError> {
    Ok(build_tile_kept(
        samples,
        lattice,
        origin,
        tolerances,
        srid,
        &Border::default(),
        interrupt,
    )?
    .map(|(tin, _)| tin))
}

/// Seam samples a tile asks for, per level (columns and rows on the
/// lattice): pixel centres on its hull at an end of a grid segment of the
/// one-pixel strip along the hull where an edge of that level crosses it
/// more than the level's tolerance from the raster's surface.
pub type Wanted = Vec<Vec<(i64, i64)>>;

/// [`build_tile`] keeping the hull samples `keep` (column and row on the
/// lattice, per level) as vertices, and the seam samples it asks for
/// ([`Wanted`]): kept by both tiles of the seam, they split the edges whose
/// crossings in the strip beside it the tile could not mend from inside.
pub fn build_tile_kept(
    samples: Vec<[f64; 3]>,
    lattice: &Lattice,
    origin: (i64, i64),
    tolerances: &[f64],
    srid: i32,
    keep: &Border,
    interrupt: &mut Interrupt<'_>,
) -> Result<Option<(Tin, Wanted)>, TinError> {
    if samples.len() < 3 {
        return Ok(None);
    }
    let opts = BuildOptions {
        keep_border: true,
        between_samples: true,
    };
    let heights = window_heights(&samples, origin);
    let mut wanted = Vec::new();
    match build_lattice_window_kept(
        samples,
        lattice,
        origin,
        tolerances,
        srid,
        opts,
        keep,
        &mut |tin| {
            if let Some(h) = &heights {
                wanted = strip_wanted(tin, h, origin);
            }
            Ok(())
        },
        interrupt,
    ) {
        Ok(tin) => Ok(Some((tin, wanted))),
        Err(TinError::Degenerate(_)) => Ok(None),
        Err(e) => Err(e),
    }
}

/// The samples' heights on their window (its frame: columns and rows less
/// `origin`), NaN without data ([`dense_of`](super::build::dense_of)); None
/// for a window much larger than its samples.
fn window_heights(samples: &[[f64; 3]], origin: (i64, i64)) -> Option<Dense> {
    let (c0, r0) = (origin.0 as f64, origin.1 as f64);
    let local: Vec<[f64; 3]> = samples
        .iter()
        .map(|p| [p[0] - c0, p[1] - r0, p[2]])
        .collect();
    super::build::dense_of(&local)
}

/// [`Wanted`] of a tin built on `d`'s window (its frame), measured as
/// [`super::check::over_tolerance`] does on every edge with an end within
/// 1.5 pixel of the hull (an edge crossing a grid segment of the strip
/// inside it ends in the strip or on the hull).
pub(crate) fn strip_wanted(tin: &Tin, d: &Dense, origin: (i64, i64)) -> Wanted {
    // the build's own hull of the window's samples
    let hull: Vec<(i64, i64)> = super::build::dense_hull(d)
        .into_iter()
        .map(|i| d.col_row(i))
        .collect();
    let n = hull.len();
    if n < 3 {
        return Vec::new();
    }
    let on_hull = |c: i64, r: i64| {
        (0..n).any(|i| {
            let (a, b) = (hull[i], hull[(i + 1) % n]);
            let cross =
                (b.0 - a.0) as i128 * (r - a.1) as i128 - (b.1 - a.1) as i128 * (c - a.0) as i128;
            cross == 0 && (c - a.0) * (c - b.0) <= 0 && (r - a.1) * (r - b.1) <= 0
        })
    };
    let near: Vec<bool> = tin
        .verts
        .iter()
        .map(|v| {
            (0..n).any(|i| {
                let (a, b) = (hull[i], hull[(i + 1) % n]);
                let (ax, ay, bx, by) = (a.0 as f64, a.1 as f64, b.0 as f64, b.1 as f64);
                let (dx, dy) = (bx - ax, by - ay);
                let len2 = dx * dx + dy * dy;
                let t = (((v[0] - ax) * dx + (v[1] - ay) * dy) / len2).clamp(0.0, 1.0);
                let (px, py) = (ax + t * dx - v[0], ay + t * dy - v[1]);
                px * px + py * py <= 2.25
            })
        })
        .collect();
    let reference = GridReference::on_lattice(d);
    let mut out: Wanted = Vec::with_capacity(tin.levels.len());
    for lv in &tin.levels {
        let limit = lv.tolerance * (1.0 + 1e-10);
        let mut want: Vec<(i64, i64)> = Vec::new();
        // (a tile over its data: its domain's triangles)
        let domain = lv.num_domain();
        for (t, (tri, nb)) in lv.tris[..domain].iter().zip(&lv.nbrs).enumerate() {
            for j in 0..3 {
                if nb[j] != NONE && (nb[j] as usize) < t {
                    continue;
                }
                let (u, w) = (tri[(j + 1) % 3] as usize, tri[(j + 2) % 3] as usize);
                if !(near[u] || near[w]) {
                    continue;
                }
                let (a, b) = (tin.verts[u], tin.verts[w]);
                reference.for_each_crossing(&a, &b, &mut |c| {
                    if c.error(&a, &b) <= limit {
                        return;
                    }
                    for z in c.seg {
                        let (zc, zr) = (z[0] as i64, z[1] as i64);
                        if on_hull(zc, zr) {
                            want.push((zc + origin.0, zr + origin.1));
                        }
                    }
                });
            }
        }
        want.sort_unstable();
        want.dedup();
        out.push(want);
    }
    out
}
