//! One raster built as a grid of tins in one call: the keep_border pattern
//! of docs/scaling.md ("tiled terrains") without cutting the raster in SQL.
//!
//! Tile `(tx, ty)` holds the pixels of columns `tx * n .. (tx + 1) * n` and
//! rows `ty * n .. (ty + 1) * n` of an `n`-pixel tiling, *plus the first
//! column of its right neighbour and the first row of the one below* (where
//! they exist), and is built with `keep_border`, so the vertices on each
//! side of its hull are chosen from that side's samples alone, level by
//! level. Two neighbouring tiles then share a column (or row) of samples
//! and choose the same vertices on it, and their surfaces are the same
//! along the seam at every level.
//!
//! Every tile is measured between its samples and makes its decisions in
//! its own frame (its samples numbered from its first pixel, as in the same
//! tile cut out in SQL with `ST_Tile` or `raster2pgsql -t`), so the
//! vertices it puts where edges cross grid lines are the ones
//! `tin_from_raster(tile, ..., keep_border => true)` puts, up to rounding.
//! It is then placed on the raster's own pixel lattice with the pixels'
//! whole-raster column and row numbers, so a shared pixel centre is the
//! very same point (bit for bit) in both tiles and in a tin of the whole
//! raster. Nothing is put on a seam but its own samples.
//!
//! ```
//! use tinmerge_core::tin::lattice::Lattice;
//! use tinmerge_core::tin::seam_rounds::build_tiles;
//! use tinmerge_core::tin::tiles::tile_window;
//! // a 5 x 4 raster of 1 m pixels, cut into 2-pixel tiles: 3 x 2 tiles
//! let values: Vec<f64> = (0..20).map(|i| ((i * 7) % 5) as f64).collect();
//! let lat = Lattice { ip_x: 0.0, ip_y: 4.0, scale_x: 1.0, scale_y: -1.0, skew_x: 0.0, skew_y: 0.0 };
//! assert_eq!(tile_window(5, 4, 2, 1, 0), (2..5, 0..3)); // its own 2 columns, then the neighbours'
//! assert_eq!(tile_window(5, 4, 2, 2, 1), (4..5, 2..4)); // the last column and row: nothing to add
//! let mut tiles = Vec::new();
//! build_tiles(&values, 5, 4, &|_| true, &lat, 2, &[0.0], true, 0, &mut || Ok(()),
//!             &|tx, ty, tin| (tx, ty, tin.levels[0].tris.len()), &mut |t| { tiles.push(t); Ok(()) }).unwrap();
//! // the last column of tiles is one pixel wide plus nothing: too thin to
//! // triangulate, so it gives no tin
//! assert_eq!(tiles.iter().map(|t| (t.0, t.1)).collect::<Vec<_>>(), [(0, 0), (1, 0), (0, 1), (1, 1)]);
//! ```

use super::TinError;
use super::build::Border;
use super::lattice::Lattice;
use super::tile::Wanted;
#[cfg(doc)]
use super::tile::build_tile_kept;
use std::ops::Range;

/// Number of tiles across and down for `width x height` pixels in tiles of
/// `tile_px`.
pub fn tile_counts(width: usize, height: usize, tile_px: usize) -> (usize, usize) {
    if tile_px == 0 {
        return (0, 0);
    }
    (width.div_ceil(tile_px), height.div_ceil(tile_px))
}

/// Pixel columns and rows of tile `(tx, ty)`: its own, plus the first
/// column of the tile to its right and the first row of the one below when
/// there is one.
pub fn tile_window(
    width: usize,
    height: usize,
    tile_px: usize,
    tx: usize,
    ty: usize,
) -> (Range<usize>, Range<usize>) {
    let c0 = (tx * tile_px).min(width);
    let r0 = (ty * tile_px).min(height);
    (
        c0..(c0 + tile_px + 1).min(width),
        r0..(r0 + tile_px + 1).min(height),
    )
}

/// Rounds of building again the tiles whose seams gained samples that a
/// tile beside them asked for ([`build_tiles`](super::seam_rounds::build_tiles)).
pub const SEAM_ROUNDS: usize = 8;

/// Rows of tiles above and below a slice that its build plans with
/// ([`slice_rows`]).
///
/// A tile's build reads only the seam samples kept in its window (its own
/// pixels and its neighbours' first column and row), and asks only for
/// samples there; a sample there is held by the tile and by the one before
/// it. So what a round keeps can differ from the whole table's only one row
/// of tiles further in than the round before: a row missing beyond the
/// halo's edge (a tile built without its neighbour, or a neighbour that
/// never asks) reaches at most [`SEAM_ROUNDS`] rows in, plus the row whose
/// first pixel row a tile of the slice holds. Two more rows than the rounds
/// keep every tile of the slice, and every sample its window holds, as the
/// whole table's build makes them, bit for bit.
pub const SLICE_HALO: usize = SEAM_ROUNDS + 2;

/// Slice `k` of `n` of a grid of `rows` rows of tiles: its own rows
/// (`k * rows / n ..` up to the next slice's), which it returns, and the
/// rows it plans the seams with (its own and [`SLICE_HALO`] more on each
/// side, within the grid). The slices `0..n` hold every row once.
///
/// ```
/// use tinmerge_core::tin::tiles::{slice_rows, SLICE_HALO};
/// assert_eq!(slice_rows(100, 1, 4), (25..50, 25 - SLICE_HALO..50 + SLICE_HALO));
/// assert_eq!(slice_rows(100, 0, 4).1, 0..25 + SLICE_HALO);
/// assert_eq!(slice_rows(7, 3, 4).0, 5..7);
/// ```
pub fn slice_rows(rows: usize, k: usize, n: usize) -> (Range<usize>, Range<usize>) {
    let n = n.max(1);
    let k = k.min(n - 1);
    let own = k * rows / n..(k + 1) * rows / n;
    let plan = own.start.saturating_sub(SLICE_HALO)..(own.end + SLICE_HALO).min(rows);
    (own, plan)
}

/// The tiles (columns, or rows) whose window holds pixel column (or row)
/// `c` of `n` tiles of `tile_px` pixels: its own, and the one before when
/// it is that tile's added first column.
fn tiles_holding(c: i64, tile_px: usize, n: usize) -> impl Iterator<Item = usize> {
    let px = tile_px as i64;
    let own = c.div_euclid(px);
    let before = (c.rem_euclid(px) == 0).then_some(own - 1);
    [Some(own), before]
        .into_iter()
        .flatten()
        .filter(move |&t| t >= 0 && (t as usize) < n)
        .map(|t| t as usize)
}

/// The seam samples every tile of a grid keeps, per level (columns and rows
/// on the common lattice): what the tiles asked for ([`Wanted`]), each at
/// the coarsest level it was asked at (a vertex stays one at the finer
/// levels).
#[derive(Clone, Debug, Default)]
pub struct Seams {
    levels: Vec<rustc_hash::FxHashSet<(i64, i64)>>,
}

impl Seams {
    /// Take what a tile asked for; the positions new at their level and
    /// every coarser one (the tiles holding them must be built again).
    pub fn add(&mut self, wanted: &Wanted) -> Vec<(i64, i64)> {
        let mut added = Vec::new();
        for (l, w) in wanted.iter().enumerate() {
            if self.levels.len() <= l {
                self.levels.resize_with(l + 1, Default::default);
            }
            for &p in w {
                if self.levels[..=l].iter().all(|s| !s.contains(&p)) {
                    self.levels[l].insert(p);
                    added.push(p);
                }
            }
        }
        added
    }

    /// Number of seam samples kept, at all levels.
    pub fn len(&self) -> usize {
        self.levels.iter().map(|s| s.len()).sum()
    }

    /// Whether no seam sample is kept.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The kept samples within a tile's window (`cols` x `rows`), as a
    /// build takes them ([`build_tile_kept`]).
    pub fn border(&self, cols: Range<i64>, rows: Range<i64>) -> Border {
        let inside = |&&(c, r): &&(i64, i64)| cols.contains(&c) && rows.contains(&r);
        Border {
            levels: self
                .levels
                .iter()
                .map(|s| {
                    let mut v: Vec<(i64, i64)> = s.iter().filter(inside).copied().collect();
                    v.sort_unstable();
                    v.into_iter().map(|(c, r)| [c as f64, r as f64]).collect()
                })
                .collect(),
        }
    }
}

/// A raster tile of a table of tiles (`raster2pgsql -t`, `ST_Tile`) placed
/// on the table's common pixel lattice.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Placed {
    /// Tile column and row in the table's grid (from 0, west to east and
    /// north to south on a north-up raster).
    pub tx: usize,
    pub ty: usize,
    /// Its first pixel's column and row on the common lattice.
    pub col: i64,
    pub row: i64,
    pub width: usize,
    pub height: usize,
}

/// Where every tile of a table lies: the common lattice (the top-left
/// tile's own, or the first tile's when there is no tile there), the
/// grid's tile size in pixels, and each tile's place, in input order.
#[derive(Clone, Debug, PartialEq)]
pub struct TableGrid {
    pub lattice: Lattice,
    pub tile_width: usize,
    pub tile_height: usize,
    pub tiles: Vec<Placed>,
}

impl TableGrid {
    /// Number of tile columns and rows.
    pub fn counts(&self) -> (usize, usize) {
        let nx = self.tiles.iter().map(|p| p.tx + 1).max().unwrap_or(0);
        let ny = self.tiles.iter().map(|p| p.ty + 1).max().unwrap_or(0);
        (nx, ny)
    }

    /// The extent `[xmin, ymin, xmax, ymax]` of the tiles' pixels (their
    /// squares' corners) in the lattice's coordinates; None without tiles.
    pub fn extent(&self) -> Option<[f64; 4]> {
        let mut b: Option<[f64; 4]> = None;
        for p in &self.tiles {
            for (c, r) in [(0, 0), (p.width, 0), (0, p.height), (p.width, p.height)] {
                let (x, y) = self.lattice.centre(
                    (p.col + c as i64) as f64 - 0.5,
                    (p.row + r as i64) as f64 - 0.5,
                );
                b = Some(match b {
                    None => [x, y, x, y],
                    Some(b) => [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)],
                });
            }
        }
        b
    }

    /// The places (tile column, row) whose window ([`keep_border_samples`]:
    /// own pixels, the next tile's first column and row) holds pixel
    /// `(c, r)` of the common lattice: the tiles a seam sample kept there
    /// ([`Seams`]) must be built with.
    pub fn tiles_holding(&self, c: i64, r: i64) -> Vec<(usize, usize)> {
        let Some(p) = self.tiles.first() else {
            return Vec::new();
        };
        let (oc, or) = (
            p.col - (p.tx * self.tile_width) as i64,
            p.row - (p.ty * self.tile_height) as i64,
        );
        let (nx, ny) = self.counts();
        // a pixel before the first column or row (a frame grown by
        // [`pad_samples`]) is in the first tiles' windows
        tiles_holding((c - oc).max(0), self.tile_width, nx)
            .flat_map(|tx| {
                tiles_holding((r - or).max(0), self.tile_height, ny).map(move |ty| (tx, ty))
            })
            .collect()
    }

    /// The sides of this grid's frame that stop short of `finer`'s (a
    /// finer layer of the same terrain, on a lattice of the same
    /// orientation): where `finer`'s outer pixel centres lie past this
    /// grid's, as they do on the left and top of an overview, its pixels'
    /// centres (f - 1) / 2 finer pixels inside its first square's edge.
    pub fn short_of(&self, finer: &TableGrid) -> Pad {
        let (Some(me), Some(them)) = (self.frame(), finer.frame()) else {
            return Pad::default();
        };
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for (c, r) in [
            (them[0], them[1]),
            (them[2], them[1]),
            (them[0], them[3]),
            (them[2], them[3]),
        ] {
            let (x, y) = finer.lattice.centre(c as f64, r as f64);
            let (c, r) = self.lattice.index_of(x, y);
            for (i, v) in [c, r].into_iter().enumerate() {
                lo[i] = lo[i].min(v);
                hi[i] = hi[i].max(v);
            }
        }
        // an outer centre on one of this grid's own (up to rounding) is
        // not past it
        let eps = 1e-9;
        Pad {
            left: lo[0] < me[0] as f64 - eps,
            top: lo[1] < me[1] as f64 - eps,
            right: hi[0] > me[2] as f64 + eps,
            bottom: hi[1] > me[3] as f64 + eps,
        }
    }

    /// The first and last pixel columns and rows of the tiles:
    /// `[col0, row0, col1, row1]`; None without tiles.
    pub fn frame(&self) -> Option<[i64; 4]> {
        let t = &self.tiles;
        Some([
            t.iter().map(|p| p.col).min()?,
            t.iter().map(|p| p.row).min()?,
            t.iter().map(|p| p.col + p.width as i64 - 1).max()?,
            t.iter().map(|p| p.row + p.height as i64 - 1).max()?,
        ])
    }
}

/// Sides of a frame: left (the first column), top (the first row), right
/// and bottom.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Pad {
    pub left: bool,
    pub top: bool,
    pub right: bool,
    pub bottom: bool,
}

impl Pad {
    /// The sides of these (of a grid's `frame`, [`TableGrid::frame`]) tile
    /// `p` lies on.
    pub fn of_tile(self, frame: [i64; 4], p: &Placed) -> Pad {
        let [c0, r0, c1, r1] = frame;
        Pad {
            left: self.left && p.col == c0,
            top: self.top && p.row == r0,
            right: self.right && p.col + p.width as i64 - 1 == c1,
            bottom: self.bottom && p.row + p.height as i64 - 1 == r1,
        }
    }
}

/// Grow a tile's window (`origin`, `size` in pixels, its `samples` on the
/// common lattice) by one pixel past the sides `pad`, each pixel added a
/// copy of the sample beside it inside the window (a corner added, of the
/// corner sample): an overview's tins then reach past its outer pixel
/// centres, as far as its table's ([`TableGrid::short_of`]). Two tiles of
/// a seam that both grow on one side add the same pixels to it (copies of
/// its own samples). Returns the grown window's origin and size.
///
/// ```
/// use tinmerge_core::tin::tiles::{pad_samples, Pad};
/// // a 2 x 2 window at (0, 0) with three samples, grown on the left
/// let mut s = vec![[0.0, 0.0, 1.0], [1.0, 0.0, 2.0], [0.0, 1.0, 3.0]];
/// let pad = Pad { left: true, top: true, ..Pad::default() };
/// assert_eq!(pad_samples(&mut s, (0, 0), (2, 2), pad), ((-1, -1), (3, 3)));
/// s.sort_by(|a, b| a.partial_cmp(b).unwrap());
/// assert_eq!(s, [[-1.0, -1.0, 1.0], [-1.0, 0.0, 1.0], [-1.0, 1.0, 3.0], [0.0, -1.0, 1.0],
///                [0.0, 0.0, 1.0], [0.0, 1.0, 3.0], [1.0, -1.0, 2.0], [1.0, 0.0, 2.0]]);
/// ```
pub fn pad_samples(
    samples: &mut Vec<[f64; 3]>,
    origin: (i64, i64),
    size: (usize, usize),
    pad: Pad,
) -> ((i64, i64), (usize, usize)) {
    let (c0, r0) = (origin.0 as f64, origin.1 as f64);
    let (c1, r1) = (c0 + size.0 as f64 - 1.0, r0 + size.1 as f64 - 1.0);
    let n = samples.len();
    for k in 0..n {
        let [c, r, v] = samples[k];
        let cs = [
            Some(c),
            (pad.left && c == c0).then_some(c - 1.0),
            (pad.right && c == c1).then_some(c + 1.0),
        ];
        let rs = [
            Some(r),
            (pad.top && r == r0).then_some(r - 1.0),
            (pad.bottom && r == r1).then_some(r + 1.0),
        ];
        for (i, nc) in cs.iter().enumerate() {
            for (j, nr) in rs.iter().enumerate() {
                if let (Some(nc), Some(nr)) = (nc, nr)
                    && (i, j) != (0, 0)
                {
                    samples.push([*nc, *nr, v]);
                }
            }
        }
    }
    let (l, t) = (i64::from(pad.left), i64::from(pad.top));
    (
        (origin.0 - l, origin.1 - t),
        (
            size.0 + usize::from(pad.left) + usize::from(pad.right),
            size.1 + usize::from(pad.top) + usize::from(pad.bottom),
        ),
    )
}

/// Place the tiles of a table given each tile's own lattice (its
/// geotransform) and size. They must share one pixel grid: the same pixel
/// size and skew, bit for bit (as `raster2pgsql -t` and `ST_Tile` write
/// them), and origins a whole number of pixels apart (within 1e-6 of a
/// pixel, the rounding of origins computed as `origin + k * size`); tiles
/// are cut at multiples of the largest width and height, and no two tiles
/// take the same place.
///
/// ```
/// use tinmerge_core::tin::lattice::Lattice;
/// use tinmerge_core::tin::tiles::place_tiles;
/// let l = |x: f64, y: f64| Lattice { ip_x: x, ip_y: y, scale_x: 2.0, scale_y: -2.0, skew_x: 0.0, skew_y: 0.0 };
/// // three 10 x 10 tiles and a 4-pixel-wide one on the right
/// let g = place_tiles(&[(l(100.0, 50.0), 10, 10), (l(120.0, 50.0), 10, 10), (l(140.0, 50.0), 4, 10), (l(100.0, 30.0), 10, 10)]).unwrap();
/// assert_eq!((g.tile_width, g.tile_height), (10, 10));
/// assert_eq!(g.tiles.iter().map(|p| (p.tx, p.ty, p.col, p.row)).collect::<Vec<_>>(),
///            [(0, 0, 0, 0), (1, 0, 10, 0), (2, 0, 20, 0), (0, 1, 0, 10)]);
/// assert!(place_tiles(&[(l(100.0, 50.0), 10, 10), (l(101.0, 50.0), 10, 10)]).is_err()); // half a pixel off
/// ```
pub fn place_tiles(tiles: &[(Lattice, usize, usize)]) -> Result<TableGrid, TinError> {
    let bad = |s: String| Err(TinError::InvalidParameter(s));
    let Some(&(first, _, _)) = tiles.first() else {
        return bad("the table has no raster tiles".into());
    };
    if !first.is_valid() {
        return bad(
            "the first tile's geotransform is not usable (not finite, or degenerate)".into(),
        );
    }
    let det = first.det();
    let mut at: Vec<(i64, i64)> = Vec::with_capacity(tiles.len());
    for (k, &(l, w, h)) in tiles.iter().enumerate() {
        if w == 0 || h == 0 {
            return bad(format!("tile {k} is empty ({w} x {h} pixels)"));
        }
        if (l.scale_x, l.scale_y, l.skew_x, l.skew_y)
            != (first.scale_x, first.scale_y, first.skew_x, first.skew_y)
        {
            return bad(format!(
                "tile {k} has pixel size ({}, {}) and skew ({}, {}), the first tile ({}, {}) and ({}, {}): the tiles must share one pixel grid (ST_SameAlignment)",
                l.scale_x,
                l.scale_y,
                l.skew_x,
                l.skew_y,
                first.scale_x,
                first.scale_y,
                first.skew_x,
                first.skew_y
            ));
        }
        // the tile's origin in pixels of the first tile's lattice
        let (dx, dy) = (l.ip_x - first.ip_x, l.ip_y - first.ip_y);
        let c = (first.scale_y * dx - first.skew_x * dy) / det;
        let r = (first.scale_x * dy - first.skew_y * dx) / det;
        let (ci, ri) = (c.round(), r.round());
        if !c.is_finite()
            || !r.is_finite()
            || (c - ci).abs() > 1e-6
            || (r - ri).abs() > 1e-6
            || ci.abs() > 1e15
            || ri.abs() > 1e15
        {
            return bad(format!(
                "tile {k} starts {} columns and {} rows from the first tile: tiles must be a whole number of pixels apart (ST_SameAlignment)",
                c + 0.0,
                r + 0.0
            ));
        }
        at.push((ci as i64, ri as i64));
    }
    let min_c = at.iter().map(|a| a.0).min().unwrap_or(0);
    let min_r = at.iter().map(|a| a.1).min().unwrap_or(0);
    let tile_width = tiles.iter().map(|t| t.1).max().unwrap_or(1);
    let tile_height = tiles.iter().map(|t| t.2).max().unwrap_or(1);
    // the common lattice: the top-left tile's own when there is one, so a
    // table cut from one raster is built on that raster's lattice
    let (lattice, base) = match at.iter().position(|&a| a == (min_c, min_r)) {
        Some(k) => (tiles[k].0, (min_c, min_r)),
        None => (first, (0, 0)),
    };
    let mut placed = Vec::with_capacity(tiles.len());
    let mut seen = std::collections::HashMap::with_capacity(tiles.len());
    for (k, (&(c, r), &(_, w, h))) in at.iter().zip(tiles).enumerate() {
        let (oc, or) = ((c - min_c) as u64, (r - min_r) as u64);
        if oc % tile_width as u64 != 0 || or % tile_height as u64 != 0 {
            return bad(format!(
                "tile {k} starts at pixel column {oc}, row {or} of the table: not on the grid of {tile_width} x {tile_height} pixel tiles (cut every tile but the last of a row or column to the same size, as raster2pgsql -t does)"
            ));
        }
        let (tx, ty) = (
            (oc / tile_width as u64) as usize,
            (or / tile_height as u64) as usize,
        );
        if let Some(j) = seen.insert((tx, ty), k) {
            return bad(format!(
                "tiles {j} and {k} take the same place (tile column {tx}, row {ty})"
            ));
        }
        placed.push(Placed {
            tx,
            ty,
            col: c - base.0,
            row: r - base.1,
            width: w,
            height: h,
        });
    }
    Ok(TableGrid {
        lattice,
        tile_width,
        tile_height,
        tiles: placed,
    })
}

/// The pixels of one placed tile: row-major values and which count as data.
pub struct Block<'a> {
    pub place: Placed,
    pub values: &'a [f64],
    pub valid: &'a (dyn Fn(f64) -> bool + Sync),
}

/// The samples (common-lattice column, row, value) a tile of a table is
/// built from: its own valid pixels, the first column of the tile to its
/// right and the first row of the one below (each when that tile is there
/// and adjoins it), and the first pixel of the one below-right when all
/// three are, as [`build_tiles`](super::seam_rounds::build_tiles) takes them from one raster. A missing
/// tile leaves a hole its neighbours do not reach into.
pub fn keep_border_samples(
    own: &Block,
    right: Option<&Block>,
    below: Option<&Block>,
    corner: Option<&Block>,
) -> Vec<[f64; 3]> {
    let p = own.place;
    let (w, h) = (p.width as i64, p.height as i64);
    let mut out = Vec::with_capacity((p.width + 1) * (p.height + 1));
    let adjoins =
        |b: &&Block, dc: i64, dr: i64| b.place.col == p.col + dc && b.place.row == p.row + dr;
    let right = right.filter(|b| adjoins(b, w, 0));
    let below = below.filter(|b| adjoins(b, 0, h));
    // the corner joins the border column to the border row: only with both
    let corner = corner.filter(|b| right.is_some() && below.is_some() && adjoins(b, w, h));
    let mut push = |b: &Block, c: usize, r: usize| {
        if let Some(&v) = b.values.get(r * b.place.width + c)
            && (b.valid)(v)
        {
            out.push([
                (b.place.col + c as i64) as f64,
                (b.place.row + r as i64) as f64,
                v,
            ]);
        }
    };
    for r in 0..p.height {
        for c in 0..p.width {
            push(own, c, r);
        }
        if let Some(b) = right
            && r < b.place.height
        {
            push(b, 0, r);
        }
    }
    if let Some(b) = below {
        for c in 0..p.width.min(b.place.width) {
            push(b, c, 0);
        }
    }
    if let Some(b) = corner {
        push(b, 0, 0);
    }
    out
}

/// The window [`keep_border_samples`] takes a tile's samples from, in
/// pixels: its own, one column more with a tile to its right and one row
/// more with one below (when they adjoin it).
pub fn keep_border_window(
    own: &Block,
    right: Option<&Block>,
    below: Option<&Block>,
) -> (usize, usize) {
    let p = own.place;
    let adjoins = |b: &&Block, dc: usize, dr: usize| {
        b.place.col == p.col + dc as i64 && b.place.row == p.row + dr as i64
    };
    (
        p.width + usize::from(right.filter(|b| adjoins(b, p.width, 0)).is_some()),
        p.height + usize::from(below.filter(|b| adjoins(b, 0, p.height)).is_some()),
    )
}
