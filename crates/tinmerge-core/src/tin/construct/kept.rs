//! A band built with `keep_border` (a tile of `tin_tiles`,
//! `tin_tiles_from_table`, `tin_overviews`; `tin_from_raster(...,
//! keep_border => true)`): the vertices on each side of the valid pixel
//! centres' hull are chosen from that side's samples alone, level by
//! level, so two tiles sharing a column (or row) of samples choose the
//! same ones and their surfaces are the same along it at every level.
//!
//! Each level, before the greedy refinement ([`super::greedy`]) runs to
//! its tolerance, each side's profile (its valid samples from its end
//! smaller in (column, row) to the other) is split by
//! [`choose_border`] at [`seam_split`] from what the coarser levels
//! chose and the samples the tiles agreed to keep ([`Border`]), exactly as
//! the parent-by-parent build does (a tile built over its data only,
//! beside one built here, plans the shared column the same way). The
//! side's other samples stay [`RESERVED`](super::measure::RESERVED): the
//! greedy refinement makes no vertex of them. An edge crossing a grid
//! segment from one to a vertex over the tolerance is split where it
//! crosses ([`super::greedy`]'s `reserve::split_beside_kept`), exact there,
//! so the strip along the hull is mended from inside; only where that split
//! would make a nearly flat triangle is the segment left stuck (not
//! queued again), and what stays over the tolerance there is what the tile
//! asks of its seams ([`Wanted`](crate::tin::tile::Wanted)): the seam
//! rounds ([`crate::tin::seam_rounds`]) keep those samples in both tiles.
//!
//! The coarse levels run along the lattice ([`super::aligned`]) as a whole
//! band's do, but keep off the hull: no triangle of the first cover has a
//! corner on a side (but the hull's corners), and none is bisected at a
//! side but at a vertex the side's profile chose. A whole tile side
//! (2^k pixels) is halved where it needs a vertex ([`choose_border`]
//! splits a gap of a power of two steps at its middle), so each vertex it
//! chooses is the middle of a hypotenuse the bisection reaches: it is made
//! by bisecting the triangles there ([`Greedy::bisect_to`]), and the
//! triangles inside stay right isosceles along the lattice. (Inserted
//! freely before, the sides' vertices left no coarse triangle aligned:
//! every coarse level was made by insertion and the finest paid about 265
//! splits of locked edges at crossings a tile. On the 105-Mpixel terrain,
//! 16 tiles of 256 pixels at three places, 1 m, 5 levels: 15,362, 13,577
//! and 15,844 finest vertices against 18,016, 17,853 and 17,505; built
//! alone without kept sides, 13,869, 12,241 and 14,674.) On the bundled UTM DEM in 96-pixel tiles at 2 m, 5 levels, the
//! finest levels have 205,573 triangles together (277,508 parent by
//! parent; 314,350 with Delaunay coarse levels, whose edges cross grid
//! lines), and the seam rounds build each of its 16 tiles once (28 builds
//! before).
//!
//! A side along no lattice line (across nodata) has samples only where
//! lattice points fall on it; the greedy refinement splits its pieces
//! where they cross grid segments, always at a piece's worst crossing
//! (a triangle's worst error bounds its sides'), so those splits too
//! depend on the side alone.

use super::greedy::Greedy;
use super::measure::{Heights, Source};
use crate::interrupt::Interrupt;
use crate::tin::TinError;
use crate::tin::build::common::{Border, RawLevel, seam_split};
use crate::tin::dense::Dense;
use crate::tin::sides::{Split, choose_border};
use rustc_hash::FxHashSet;

/// The hull's sides: each one's valid samples in canonical order (its end
/// smaller in (column, row) first, as the parent-by-parent build orders
/// them) and which of them are chosen so far.
struct Sides {
    sides: Vec<Vec<u32>>,
    chosen: Vec<Vec<bool>>,
}

impl Sides {
    fn new(d: &Dense, hull: &[u32]) -> Sides {
        let sides: Vec<Vec<u32>> = (0..hull.len())
            .map(|k| {
                let (a, b) = (hull[k], hull[(k + 1) % hull.len()]);
                d.side(a as usize, b as usize)
                    .into_iter()
                    .map(|i| i as u32)
                    .collect()
            })
            .collect();
        let chosen = sides
            .iter()
            .map(|s| (0..s.len()).map(|k| k == 0 || k + 1 == s.len()).collect())
            .collect();
        Sides { sides, chosen }
    }

    /// The samples strictly inside the sides, none chosen yet.
    fn inner(&self) -> Vec<u32> {
        self.sides
            .iter()
            .flat_map(|s| s.get(1..s.len().saturating_sub(1)).unwrap_or(&[]))
            .copied()
            .collect()
    }

    /// One level's choice at `tol` (a seam's): the `kept` samples first,
    /// then the Douglas-Peucker split of each side. The samples newly
    /// chosen, in order, and the worst error left along the sides.
    fn plan(&mut self, g: &Heights<'_>, kept: &FxHashSet<u32>, split: Split) -> (Vec<u32>, f64) {
        let mut new_ids = Vec::new();
        let mut err = 0.0f64;
        for (side, chosen) in self.sides.iter().zip(&mut self.chosen) {
            for (k, &id) in side.iter().enumerate() {
                if !chosen[k] && kept.contains(&id) {
                    chosen[k] = true;
                    new_ids.push(id);
                }
            }
            let mut picked = Vec::new();
            err = err.max(choose_border(
                &|k| g.point(side[k]),
                &(0..side.len()).collect::<Vec<usize>>(),
                chosen,
                split,
                &mut picked,
            ));
            new_ids.extend(picked.into_iter().map(|k| side[k]));
        }
        (new_ids, err)
    }
}

/// Every level of the lattice samples `d` with its hull's sides kept, the
/// samples of `border` (column and row in `d`'s window's frame, per level)
/// kept on them: its vertices (in that frame) and levels.
pub(super) fn levels(
    d: &Dense,
    tolerances: &[f64],
    border: &Border,
    interrupt: &mut Interrupt<'_>,
) -> Result<(Vec<[f64; 3]>, Vec<RawLevel>), TinError> {
    let g = &Heights {
        z: &d.z,
        width: d.width,
        height: d.height,
    };
    let floor = tolerances.last().copied().unwrap_or(0.0);
    // coarse levels along the lattice, off the sides
    let mut s = Greedy::new(g, floor, tolerances.len() > 1, true)?;
    let mut sides = Sides::new(d, &g.hull()?);
    s.reserve(&sides.inner());
    let mut raw = Vec::with_capacity(tolerances.len());
    for (l, &tol) in tolerances.iter().enumerate() {
        interrupt()?;
        if l + 1 == tolerances.len() {
            s.finest();
        }
        let kept: FxHashSet<u32> = border
            .at(l)
            .iter()
            .filter_map(|p| {
                let (c, r) = (p[0], p[1]);
                let inside = c == c.trunc()
                    && r == r.trunc()
                    && (0.0..g.width as f64).contains(&c)
                    && (0.0..g.height as f64).contains(&r);
                inside.then(|| (r as usize * g.width + c as usize) as u32)
            })
            .collect();
        let (new_ids, side_err) = sides.plan(g, &kept, seam_split(tol, true));
        s.insert_kept(&new_ids)?;
        let phase = format!("building level {} of {}", l + 1, tolerances.len());
        s.run(tol, &phase, interrupt)?;
        let mut level = s.finish_level(tol, l == 0, l + 1 == tolerances.len());
        level.max_error = level.max_error.max(side_err);
        raw.push(level);
    }
    Ok((s.into_points(), raw))
}
