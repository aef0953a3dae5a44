//! The seam rounds of a table of raster tiles: what `tin_tiles_from_table`
//! and each layer of `tin_overviews` run, one driver whatever reads the
//! tiles ([`TileReader`]: SPI in the SQL layer, memory in the tests).
//!
//! Tiles are built a batch at a time (one per thread), in rows, each with
//! its neighbours' border pixels ([`keep_border_samples`]) and the seam
//! samples kept so far ([`Seams`]). Rounds of *planning* build the tiles
//! whose seams gained samples and keep only what they ask for
//! ([`Wanted`]); when a round asks for nothing new (or after
//! [`SEAM_ROUNDS`]), every tile of the slice's own rows is built once
//! more, with them, and returned. A caller that can keep every tile's
//! result ([`SeamRounds::hold`]: `tin_tiles`, whose band is in memory,
//! [`build_tiles`]; `tin_tiles_from_table` while they fit in a quarter of
//! `tinmerge.max_memory`) is handed every build of the own rows instead
//! and keeps each tile's last: no pass is spent building every tile once
//! more, only the tiles whose seams gained samples are built again. Only
//! the rows a batch needs are read (its rows and the one below), so
//! besides the results held the memory is bounded by two rows of tiles
//! and one batch of builds.
//!
//! ```
//! use tinmerge_core::io::raster::Band;
//! use tinmerge_core::tin::lattice::Lattice;
//! use tinmerge_core::tin::seam_rounds::{SeamRounds, TileReader};
//! use tinmerge_core::tin::tiles::place_tiles;
//! use tinmerge_core::tin::TinError;
//! // a 40 x 30 raster cut into 20 x 15 tiles
//! let z = |c: usize, r: usize| ((c as f64) * 0.3).sin() * 8.0 + r as f64;
//! let l = |c: usize, r: usize| Lattice { ip_x: 500.0 + 10.0 * c as f64, ip_y: 900.0 - 10.0 * r as f64,
//!                                        scale_x: 10.0, scale_y: -10.0, skew_x: 0.0, skew_y: 0.0 };
//! let mut tiles = Vec::new();
//! for (c0, r0) in [(0, 0), (20, 0), (0, 15), (20, 15)] {
//!     let values = (r0..r0 + 15).flat_map(|r| (c0..c0 + 20).map(move |c| z(c, r))).collect();
//!     tiles.push((l(c0, r0), Band { pixel_type: 10, nodata: None, all_nodata: false, values }));
//! }
//! let grid = place_tiles(&tiles.iter().map(|t| (t.0, 20, 15)).collect::<Vec<_>>()).unwrap();
//! struct Memory(Vec<(Lattice, Band)>);
//! impl TileReader for Memory {
//!     fn read(&mut self, want: &[usize]) -> Result<Vec<(usize, Band)>, TinError> {
//!         Ok(want.iter().map(|&k| (k, self.0[k].1.clone())).collect())
//!     }
//! }
//! let mut rounds = SeamRounds::new(&grid, vec![2.0, 0.5], 32616, true, (0, 1));
//! let mut reader = Memory(tiles);
//! let mut out = Vec::new();
//! while let Some(batch) = rounds.next_batch(&grid, &mut reader, &|tx, ty, t| (tx, ty, t), &mut |_| Ok(())).unwrap() {
//!     out.extend(batch);
//! }
//! assert_eq!(out.iter().map(|t| (t.0, t.1)).collect::<Vec<_>>(), [(0, 0), (1, 0), (0, 1), (1, 1)]);
//! ```

use std::collections::HashMap;
use std::ops::Range;

use super::lattice::Lattice;
use super::tile::Wanted;
use super::tile_domain::build_tile_window;
use super::tiles::{
    Block, Pad, Placed, SEAM_ROUNDS, Seams, TableGrid, keep_border_samples, keep_border_window,
    pad_samples, slice_rows, tile_counts,
};
use super::{Tin, TinError};
use crate::interrupt::Interrupt;
use crate::io::raster::Band;

/// Where a table's tiles come from.
pub trait TileReader {
    /// The bands of the grid's tiles `want` (indexes into
    /// [`TableGrid::tiles`]), in any order, every one of them (one left
    /// out is an internal error). An overview layer's reader gives its
    /// nodata pixels over data the data under them
    /// ([`super::cover::Cover`]).
    fn read(&mut self, want: &[usize]) -> Result<Vec<(usize, Band)>, TinError>;
}

/// The tiles of one band in memory (`values` row-major, `width` a row,
/// `valid` telling data from nodata), placed on `grid`: what
/// [`build_tiles`] reads.
pub struct InMemory<'a> {
    pub values: &'a [f64],
    pub width: usize,
    pub valid: &'a (dyn Fn(f64) -> bool + Sync),
    pub grid: &'a TableGrid,
}

impl TileReader for InMemory<'_> {
    fn read(&mut self, want: &[usize]) -> Result<Vec<(usize, Band)>, TinError> {
        want.iter()
            .map(|&k| {
                let p = self
                    .grid
                    .tiles
                    .get(k)
                    .ok_or_else(|| TinError::Internal(format!("no tile {k} in the grid")))?;
                let (c0, r0) = (p.col as usize, p.row as usize);
                let mut values = Vec::with_capacity(p.width * p.height);
                for r in r0..r0 + p.height {
                    let row = self
                        .values
                        .get(r * self.width + c0..r * self.width + c0 + p.width)
                        .ok_or_else(|| TinError::Internal(format!("tile {k} is off the band")))?;
                    values.extend(
                        row.iter()
                            .map(|&v| if (self.valid)(v) { v } else { f64::NAN }),
                    );
                }
                let band = Band {
                    pixel_type: 11,
                    nodata: None,
                    all_nodata: false,
                    values,
                };
                Ok((k, band))
            })
            .collect()
    }
}

/// The batch [`SeamRounds::next_batch`] is about to build: for progress,
/// interrupts and a check of the memory it needs.
#[derive(Clone, Copy, Debug)]
pub struct Step {
    /// a round of planning the seams (its tiles are not returned)
    pub planning: bool,
    /// the round, from 0
    pub round: usize,
    /// tiles of the round built so far, and in all
    pub done: usize,
    pub total: usize,
    /// tiles in this batch
    pub tiles: usize,
}

/// Each tile's last build, held by [`SeamRounds::next_held`] while their
/// size (as `size` counts it) is within a budget.
pub struct Held<R> {
    /// by (ty, tx)
    last: std::collections::BTreeMap<(usize, usize), R>,
    bytes: usize,
    budget: usize,
    size: fn(&R) -> usize,
    dropped: bool,
}

impl<R> Held<R> {
    /// Nothing held yet; at most `budget` of `size`.
    pub fn new(budget: usize, size: fn(&R) -> usize) -> Held<R> {
        Held {
            last: Default::default(),
            bytes: 0,
            budget,
            size,
            dropped: false,
        }
    }

    /// Whether what was held passed the budget and was dropped.
    pub fn dropped(&self) -> bool {
        self.dropped
    }
}

/// A table's tiles being built in seam rounds (module docs).
pub struct SeamRounds {
    tols: Vec<f64>,
    srid: i32,
    fill_gaps: bool,
    /// the sides of the frame an overview layer's tiles are grown on
    /// ([`pad_samples`]), and the frame
    pad: (Pad, [i64; 4]),
    /// the round's tiles in (ty, tx) order, and the next to build
    order: Vec<usize>,
    next: usize,
    /// tile index by (tx, ty), of the planned rows
    at: HashMap<(usize, usize), usize>,
    loaded: HashMap<usize, Band>,
    seams: Seams,
    asked: Vec<Wanted>,
    round: usize,
    planning: bool,
    /// the rows of tiles returned (the slice's own) and planned with
    /// (theirs and the halo, [`slice_rows`])
    own: Range<usize>,
    plan: Range<usize>,
    /// every build's result kept ([`SeamRounds::run_held`])
    hold: bool,
}

impl SeamRounds {
    /// The tiles of `grid` in slice `slice` of `slices` (rows of tiles),
    /// one tin each at `tols`; over the hull of their samples with
    /// `fill_gaps`, else over their valid pixels' squares.
    pub fn new(
        grid: &TableGrid,
        tols: Vec<f64>,
        srid: i32,
        fill_gaps: bool,
        (slice, slices): (usize, usize),
    ) -> SeamRounds {
        let (own, plan) = slice_rows(grid.counts().1, slice, slices);
        SeamRounds::rows(grid, tols, srid, fill_gaps, own, plan)
    }

    /// [`SeamRounds::new`] returning the tiles of rows `own`, the seams
    /// planned with rows `plan` (holding `own`; a slice's are
    /// [`slice_rows`]'s, its own and a halo).
    pub fn rows(
        grid: &TableGrid,
        tols: Vec<f64>,
        srid: i32,
        fill_gaps: bool,
        own: Range<usize>,
        plan: Range<usize>,
    ) -> SeamRounds {
        let mut order: Vec<usize> = (0..grid.tiles.len())
            .filter(|&k| plan.contains(&grid.tiles[k].ty))
            .collect();
        order.sort_by_key(|&k| (grid.tiles[k].ty, grid.tiles[k].tx));
        let at = order
            .iter()
            .map(|&k| ((grid.tiles[k].tx, grid.tiles[k].ty), k))
            .collect();
        SeamRounds {
            tols,
            srid,
            fill_gaps,
            pad: Default::default(),
            order,
            next: 0,
            at,
            loaded: HashMap::new(),
            seams: Seams::default(),
            asked: Vec::new(),
            round: 0,
            planning: true,
            own,
            plan,
            hold: false,
        }
    }

    /// This layer (on `grid`) as an overview of `base`: its frame's tiles
    /// grown by a pixel where `base`'s outer pixel centres lie past its
    /// own ([`TableGrid::short_of`]).
    pub fn covering(&mut self, grid: &TableGrid, base: &TableGrid) {
        if let Some(frame) = grid.frame() {
            self.pad = (grid.short_of(base), frame);
        }
    }

    /// The tolerances, coarsest first.
    pub fn tolerances(&self) -> &[f64] {
        &self.tols
    }

    /// The next batch of tiles of `grid` built, `each(tx, ty, tin)` of
    /// those returned (on the build's threads: encode there), an empty
    /// batch while planning; `None` when every tile has been returned.
    /// `before` sees each batch first (and may refuse it).
    pub fn next_batch<R: Send>(
        &mut self,
        grid: &TableGrid,
        reader: &mut dyn TileReader,
        each: &(dyn Fn(usize, usize, Tin) -> R + Sync),
        before: &mut dyn FnMut(Step) -> Result<(), TinError>,
    ) -> Result<Option<Vec<R>>, TinError> {
        while self.next >= self.order.len() {
            if !self.planning {
                return Ok(None);
            }
            self.end_round(grid);
        }
        let batch: Vec<usize> = self.order
            [self.next..(self.next + super::par::threads().max(1)).min(self.order.len())]
            .to_vec();
        before(Step {
            planning: self.planning,
            round: self.round,
            done: self.next,
            total: self.order.len(),
            tiles: batch.len(),
        })?;
        self.next += batch.len();
        let (first, last) = (
            grid.tiles[batch[0]].ty,
            grid.tiles[batch[batch.len() - 1]].ty,
        );
        self.load_rows(grid, reader, first..=last + 1)?;
        self.build(grid, &batch, each).map(Some)
    }

    /// From now on every build of a tile of the own rows is handed out
    /// (`each`'s result), in the rounds of planning too, and the caller
    /// keeps the last of each tile: a tile is built again only when its
    /// seams gain samples, and no pass is spent building every tile once
    /// more at the end. The caller that cannot keep them all any longer
    /// calls [`SeamRounds::let_go`].
    pub fn hold(&mut self) {
        self.hold = true;
    }

    /// Whether the builds are handed out as they are made
    /// ([`SeamRounds::hold`]).
    pub fn holding(&self) -> bool {
        self.hold
    }

    /// The caller has dropped every result it held: as without
    /// [`SeamRounds::hold`], every tile of the own rows is built once more
    /// when the seams are planned (at once, if they are).
    pub fn let_go(&mut self) {
        if !self.hold {
            return;
        }
        self.hold = false;
        if !self.planning {
            self.order = self.own_tiles();
            self.next = 0;
        }
    }

    /// [`SeamRounds::next_batch`] holding each tile's last build in
    /// `held` ([`SeamRounds::hold`] first): batches are empty while they
    /// are held, and the held ones come out at the end, in (ty, tx) order.
    /// Once they pass `held`'s budget they are dropped
    /// ([`SeamRounds::let_go`]) and the batches hand out their tiles as
    /// without holding.
    pub fn next_held<R: Send>(
        &mut self,
        held: &mut Held<R>,
        grid: &TableGrid,
        reader: &mut dyn TileReader,
        each: &(dyn Fn(usize, usize, Tin) -> R + Sync),
        before: &mut dyn FnMut(Step) -> Result<(), TinError>,
    ) -> Result<Option<Vec<R>>, TinError> {
        let holding = self.hold;
        let keyed = |tx: usize, ty: usize, t: Tin| ((ty, tx), each(tx, ty, t));
        let Some(batch) = self.next_batch(grid, reader, &keyed, before)? else {
            return Ok((!held.last.is_empty())
                .then(|| std::mem::take(&mut held.last).into_values().collect()));
        };
        if !holding {
            return Ok(Some(batch.into_iter().map(|b| b.1).collect()));
        }
        for (k, r) in batch {
            held.bytes += (held.size)(&r);
            if let Some(old) = held.last.insert(k, r) {
                held.bytes -= (held.size)(&old);
            }
        }
        if held.bytes > held.budget {
            held.last.clear();
            held.bytes = 0;
            held.dropped = true;
            self.let_go();
        }
        Ok(Some(Vec::new()))
    }

    /// Every tile of the own rows built, each one's last build kept
    /// (`each`'s result, on the build's threads; [`SeamRounds::hold`]):
    /// where the results may all be held (tiles in memory: `tin_tiles`).
    /// In (ty, tx) order, with the seam samples kept.
    pub fn run_held<R: Send>(
        mut self,
        grid: &TableGrid,
        reader: &mut dyn TileReader,
        each: &(dyn Fn(usize, usize, Tin) -> R + Sync),
        before: &mut dyn FnMut(Step) -> Result<(), TinError>,
    ) -> Result<(Vec<R>, Seams), TinError> {
        self.hold();
        let mut held = Held::new(usize::MAX, |_| 0);
        let mut out = Vec::new();
        while let Some(batch) = self.next_held(&mut held, grid, reader, each, before)? {
            out.extend(batch);
        }
        Ok((out, self.seams))
    }

    /// The end of a round of planning: the seam samples asked for taken,
    /// and the tiles that hold new ones to build in the next round; or,
    /// when there are none (or after [`SEAM_ROUNDS`] rounds), every tile
    /// of the slice's own rows, to return.
    fn end_round(&mut self, grid: &TableGrid) {
        let mut again: Vec<usize> = Vec::new();
        for w in std::mem::take(&mut self.asked) {
            for (c, r) in self.seams.add(&w) {
                again.extend(
                    grid.tiles_holding(c, r)
                        .into_iter()
                        .filter_map(|t| self.at.get(&t).copied()),
                );
            }
        }
        self.round += 1;
        if again.is_empty() || self.round >= SEAM_ROUNDS {
            self.planning = false;
            // every tile to return; holding every build's result, only
            // those whose seams gained samples since their last build
            if self.hold {
                again.retain(|&k| self.own.contains(&grid.tiles[k].ty));
            } else {
                again = self.own_tiles();
            }
        }
        again.sort_by_key(|&k| (grid.tiles[k].ty, grid.tiles[k].tx));
        again.dedup();
        self.order = again;
        self.next = 0;
        self.loaded.clear();
    }

    /// The tiles of the own rows, in (ty, tx) order.
    fn own_tiles(&self) -> Vec<usize> {
        let mut own: Vec<((usize, usize), usize)> = self
            .at
            .iter()
            .filter(|(p, _)| self.own.contains(&p.1))
            .map(|(&(tx, ty), &k)| ((ty, tx), k))
            .collect();
        own.sort_unstable();
        own.into_iter().map(|o| o.1).collect()
    }

    /// Read the bands of tile rows `rows` not read yet, and forget the
    /// rows above the first.
    fn load_rows(
        &mut self,
        grid: &TableGrid,
        reader: &mut dyn TileReader,
        rows: std::ops::RangeInclusive<usize>,
    ) -> Result<(), TinError> {
        self.loaded
            .retain(|&k, _| grid.tiles[k].ty >= *rows.start());
        let want: Vec<usize> = (0..grid.tiles.len())
            .filter(|&k| {
                let ty = grid.tiles[k].ty;
                rows.contains(&ty) && self.plan.contains(&ty) && !self.loaded.contains_key(&k)
            })
            .collect();
        if !want.is_empty() {
            let got = reader.read(&want)?;
            self.loaded.extend(got);
        }
        Ok(())
    }

    /// Build tiles `batch` (their rows and the next loaded), one per
    /// thread: while planning, keep what they ask of their seams.
    fn build<R: Send>(
        &mut self,
        grid: &TableGrid,
        batch: &[usize],
        each: &(dyn Fn(usize, usize, Tin) -> R + Sync),
    ) -> Result<Vec<R>, TinError> {
        type Valid<'a> = Box<dyn Fn(f64) -> bool + Sync + 'a>;
        let valids: HashMap<usize, Valid<'_>> = self
            .loaded
            .iter()
            .map(|(&k, b)| (k, Box::new(move |v: f64| b.is_valid(v)) as Valid<'_>))
            .collect();
        let block = |tx: usize, ty: usize| -> Option<Block> {
            let k = *self.at.get(&(tx, ty))?;
            Some(Block {
                place: grid.tiles[k],
                values: &self.loaded.get(&k)?.values,
                valid: valids.get(&k)?.as_ref(),
            })
        };
        let (lattice, tols, srid) = (grid.lattice, &self.tols, self.srid);
        let (seams, planning, fill_gaps, pad, hold, own_rows) = (
            &self.seams,
            self.planning,
            self.fill_gaps,
            self.pad,
            self.hold,
            &self.own,
        );
        let built = super::par::map(batch, |&k| {
            let p = grid.tiles[k];
            let Some(own) = block(p.tx, p.ty) else {
                return Err(TinError::Internal(format!(
                    "tile ({}, {}) of the batch was not read",
                    p.tx, p.ty
                )));
            };
            let (right, below) = (block(p.tx + 1, p.ty), block(p.tx, p.ty + 1));
            let mut s = keep_border_samples(
                &own,
                right.as_ref(),
                below.as_ref(),
                block(p.tx + 1, p.ty + 1).as_ref(),
            );
            let size = keep_border_window(&own, right.as_ref(), below.as_ref());
            let grow = pad.0.of_tile(pad.1, &p);
            let (origin, size) = pad_samples(&mut s, (p.col, p.row), size, grow);
            let keep = seams.border(
                origin.0..p.col + p.width as i64 + 1 + i64::from(grow.right),
                origin.1..p.row + p.height as i64 + 1 + i64::from(grow.bottom),
            );
            let tile = crate::progress::quiet(|| {
                build_tile_window(
                    s,
                    &lattice,
                    origin,
                    size,
                    tols,
                    srid,
                    &keep,
                    fill_gaps,
                    &mut || Ok(()),
                )
            });
            tile.map(|t| {
                t.map(|(t, wanted)| {
                    let wanted = if planning { wanted } else { Vec::new() };
                    let out = !planning || (hold && own_rows.contains(&p.ty));
                    (out.then(|| each(p.tx, p.ty, t)), wanted)
                })
            })
        });
        let mut out = Vec::new();
        for r in built {
            if let Some((row, wanted)) = r? {
                out.extend(row);
                self.asked.push(wanted);
            }
        }
        Ok(out)
    }
}

/// Build every tile of a band (`values` row-major, `width x height`,
/// `valid` telling data from nodata) on `lattice`, with `tolerances` per
/// level and keep_border; over the valid pixels' squares only unless
/// `fill_gaps` ([`super::tile_domain`]). Every tile holds its tolerances between the
/// samples, the one-pixel strips along its seams included: the seam samples
/// a tile asks for ([`Wanted`]) are kept by both tiles of the seam, which
/// are built again, for up to [`SEAM_ROUNDS`] rounds ([`Seams`]).
/// `each(tx, ty, tin)` runs on the build's thread (on `tin::par`'s threads
/// when there are several: encode there), and `consume` gets the results of
/// the last round on the calling thread in row-major tile order. A tile
/// without three non-collinear valid samples (nodata, or a last row or
/// column one pixel thick) gives nothing. Interrupts are checked between
/// tiles (on threads, between rounds of one tile per thread; a tile's own
/// build is not interrupted). The seam samples kept.
#[allow(clippy::too_many_arguments)]
pub fn build_tiles<R: Send>(
    values: &[f64],
    width: usize,
    height: usize,
    valid: &(dyn Fn(f64) -> bool + Sync),
    lattice: &Lattice,
    tile_px: usize,
    tolerances: &[f64],
    fill_gaps: bool,
    srid: i32,
    interrupt: &mut Interrupt<'_>,
    each: &(dyn Fn(usize, usize, Tin) -> R + Sync),
    consume: &mut dyn FnMut(R) -> Result<(), TinError>,
) -> Result<Seams, TinError> {
    if tile_px < 2 {
        return Err(TinError::InvalidParameter(format!(
            "tile_px must be at least 2 pixels, got {tile_px}"
        )));
    }
    if values.len() != width * height {
        return Err(TinError::InvalidParameter(format!(
            "raster band has {} values for {width} x {height} pixels",
            values.len()
        )));
    }
    let (nx, ny) = tile_counts(width, height, tile_px);
    let grid = TableGrid {
        lattice: *lattice,
        tile_width: tile_px,
        tile_height: tile_px,
        tiles: (0..ny)
            .flat_map(|ty| (0..nx).map(move |tx| (tx, ty)))
            .map(|(tx, ty)| {
                let (c0, r0) = (tx * tile_px, ty * tile_px);
                Placed {
                    tx,
                    ty,
                    col: c0 as i64,
                    row: r0 as i64,
                    width: tile_px.min(width - c0),
                    height: tile_px.min(height - r0),
                }
            })
            .collect(),
    };
    let mut reader = InMemory {
        values,
        width,
        valid,
        grid: &grid,
    };
    let rounds = SeamRounds::rows(&grid, tolerances.to_vec(), srid, fill_gaps, 0..ny, 0..ny);
    // each phase's last step is all its tiles
    let mut phase: Option<(String, u64)> = None;
    let mut before = |s: Step| {
        let name = if s.round == 0 {
            "building tiles".to_string()
        } else {
            format!(
                "building tiles again with their seams' samples (round {})",
                s.round
            )
        };
        if let Some((p, n)) = phase.take().filter(|p| p.0 != name) {
            crate::progress::step(&p, "tiles", n, n);
        }
        crate::progress::step(&name, "tiles", s.done as u64, s.total as u64);
        phase = Some((name, s.total as u64));
        interrupt()
    };
    // (a tile's own levels are not reported between the tiles)
    let (results, seams) = rounds.run_held(&grid, &mut reader, each, &mut before)?;
    if let Some((p, n)) = phase {
        crate::progress::step(&p, "tiles", n, n);
    }
    for r in results {
        interrupt()?;
        consume(r)?;
    }
    Ok(seams)
}
