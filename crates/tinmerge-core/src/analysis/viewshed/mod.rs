//! Viewsheds over the surface of a level (`tin_viewshed`): which cells of a
//! grid an observer sees, for one observer or, counted, for several.
//!
//! A cell is *visible* when the sight line from the observer's eye to the
//! point `target_height` above the surface at the cell's centre does not
//! go below the surface (the verdict of
//! [`line_of_sight`](super::visibility::line_of_sight), with the same
//! earth's curvature). Written as angles: with `f(u) = (z(u) - c u² - z₀)
//! / u` the elevation of the ground at distance `u` along the cell's ray
//! (`z₀` the eye's height), the cell at distance `d` with target elevation
//! `A` is visible when `max f(u), 0 < u < d` is at most `A` (up to
//! 1e-9 of the heights over `d`: touching is seeing).
//!
//! **How, without a line of sight per cell.** A fan of rays leaves the
//! eye, spaced at most half a cell apart at the farthest cell. Each ray is
//! walked once through the hierarchy ([`RayWalk`]): a coarse triangle whose
//! whole stretch of ray cannot raise the ray's running horizon (its plane
//! plus the most the level's surface rises above it, [`Bounds`]) is skipped
//! whole, without visiting its descendants; the rest are descended into
//! down to the level's triangles, where the surface along the ray is
//! linear and the running maximum of `f` exact. The running horizon is
//! kept as the walk's stretches ([`Horizon`]): its value at any distance
//! is exact, not sampled. Each cell lies in the wedge of two neighbouring
//! rays; the cells of a sector of up to 64 wedges are enumerated once,
//! column by column (row by row) outward, their wedge estimated from
//! their angle and settled by exact side tests. The rays' horizons four cells before the cell decide
//! the terrain behind it: where both are above its target elevation (by
//! more than they differ) it is hidden; where both are below it, the last
//! four cells of its own ray are walked exactly (the rays' own nearby
//! ground, half a cell to the side, is not the cell's), back from the
//! level's triangle under the cell ([`triangles_at`] gives it) across the
//! edges the ray enters by; where they disagree (the cell is near the edge
//! of what is seen) its whole ray is walked exactly from the eye, pruned
//! the same way against its own target. So a cell costs two look-ups in
//! its rays' stretches, most of the hidden ground is skipped at coarse
//! levels, and the exact walks are short or few.
//!
//! ```
//! use tinmerge_core::analysis::rasterize::aligned_grid;
//! use tinmerge_core::analysis::viewshed::{viewshed, Eye, HIDDEN, NODATA, VISIBLE};
//! use tinmerge_core::tin::build::build;
//! // flat ground at 0 with a wall 10 m high along x = 50
//! let mut pts = vec![[0.0, 0.0, 0.0], [100.0, 0.0, 0.0], [100.0, 100.0, 0.0], [0.0, 100.0, 0.0]];
//! pts.extend([[49.0, 0.0, 0.0], [49.0, 100.0, 0.0], [50.0, 0.0, 10.0], [50.0, 100.0, 10.0],
//!             [51.0, 0.0, 0.0], [51.0, 100.0, 0.0]]);
//! let tin = build(pts, &[0.0], 0, &mut || Ok(())).unwrap();
//! let (gt, w, h) = aligned_grid(&[0.0, 0.0, 100.0, 100.0], 10.0, 10.0, 0.0, 0.0).unwrap();
//! let eye = Eye { x: 25.0, y: 55.0, z: 1.7, curvature: None };
//! let v = viewshed(&tin, 0, &[eye], 0.0, 1000.0, &gt, w, h, &mut || Ok(())).unwrap();
//! // row 4 (centres at y = 55): the ground before the wall is seen, behind it hidden
//! let row: Vec<u16> = v.counts[4 * w..5 * w].to_vec();
//! assert_eq!(&row[..5], &[VISIBLE; 5]);
//! assert_eq!(&row[5..], &[HIDDEN; 5]);
//! // nothing is past a radius of 1 km, and every cell is on the surface
//! assert!(!v.counts.contains(&NODATA));
//! ```

use crate::analysis::rasterize::triangles_at;
use crate::analysis::visibility::EARTH_RADIUS;
use crate::error::TinError;
use crate::interrupt::{Interrupt, Ticker};
use crate::io::raster::GeoTransform;
use crate::tin::{Tin, locate};

mod ray;
use ray::{Bounds, Check, Horizon, RaySink, RayWalk, clear_back, plane};

/// A cell seen (by one observer: with several, the count of observers).
pub const VISIBLE: u16 = 1;
/// A cell hidden from every observer.
pub const HIDDEN: u16 = 0;
/// A cell off the surface (off the domain, on a void triangle) or past
/// the radius of every observer.
pub const NODATA: u16 = u16::MAX;

/// Most observers one call counts (their count must stay below
/// [`NODATA`]).
pub const MAX_OBSERVERS: usize = 65_534;

/// An observer: the eye's position and absolute height, and the earth's
/// curvature as seen from it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Eye {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    /// `Some((refraction, [mx, my]))`: distant ground lowered by
    /// `(1 - refraction) d² / (2 R)`, with `d` in metres: `mx`, `my` metres
    /// per horizontal unit along x and y (1, 1 for a projected SRID in
    /// metres; for degrees, `mx` shrinks with the cosine of the latitude).
    pub curvature: Option<(f64, [f64; 2])>,
}

impl Eye {
    /// The drop per squared horizontal unit along the unit direction `dir`.
    fn drop(&self, dir: [f64; 2]) -> f64 {
        match self.curvature {
            None => 0.0,
            Some((k, [mx, my])) => {
                let m2 = (mx * dir[0]).powi(2) + (my * dir[1]).powi(2);
                (1.0 - k) * m2 / (2.0 * EARTH_RADIUS)
            }
        }
    }
}

/// What [`viewshed`] found, and how much work it took.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Viewshed {
    /// Per cell, row-major from the top row: how many observers see it
    /// ([`VISIBLE`] or [`HIDDEN`] for one), or [`NODATA`].
    pub counts: Vec<u16>,
    /// Rays of the fans walked, over all observers.
    pub rays: u64,
    /// Stretches of ray crossing a triangle of the level itself (the finest
    /// work).
    pub fine_pieces: u64,
    /// Coarse triangles skipped whole (their stretch could not raise the
    /// horizon, or could not block the cell checked).
    pub pruned: u64,
    /// Cells whose two rays disagreed, walked exactly on their own ray.
    pub exact_cells: u64,
    /// Cells seen past the terrain behind them, whose last stretch was
    /// walked on their own ray.
    pub local_cells: u64,
    /// Cells decided (in reach of an observer and on the surface), over
    /// all observers.
    pub cells: u64,
}

/// The viewshed of `eyes` over `level` on the `width` x `height` north-up
/// grid `gt`: for each cell, how many eyes see the point `target_height`
/// above the surface at its centre within `radius` (horizontal, in the
/// tin's units) of them; [`NODATA`] off the surface or out of every eye's
/// reach. The eyes must be over the tin's hull.
#[allow(clippy::too_many_arguments)]
pub fn viewshed(
    tin: &Tin,
    level: usize,
    eyes: &[Eye],
    target_height: f64,
    radius: f64,
    gt: &GeoTransform,
    width: usize,
    height: usize,
    interrupt: &mut Interrupt<'_>,
) -> Result<Viewshed, TinError> {
    viewshed_with(
        tin,
        level,
        eyes,
        target_height,
        radius,
        gt,
        width,
        height,
        true,
        interrupt,
    )
}

/// [`viewshed`], with the coarse levels' pruning turned off when `prune` is
/// false (to measure what it saves; the answer is the same).
#[allow(clippy::too_many_arguments)]
pub fn viewshed_with(
    tin: &Tin,
    level: usize,
    eyes: &[Eye],
    target_height: f64,
    radius: f64,
    gt: &GeoTransform,
    width: usize,
    height: usize,
    prune: bool,
    interrupt: &mut Interrupt<'_>,
) -> Result<Viewshed, TinError> {
    if level >= tin.levels.len() {
        return Err(TinError::LevelOutOfRange {
            level: level as i64,
            num_levels: tin.levels.len(),
        });
    }
    if eyes.len() > MAX_OBSERVERS {
        return Err(TinError::InvalidParameter(format!(
            "{} observers, at most {MAX_OBSERVERS} are counted",
            eyes.len()
        )));
    }
    if !(target_height.is_finite() && radius.is_finite() && radius > 0.0) {
        return Err(TinError::InvalidParameter(format!(
            "target height must be finite and radius positive and finite, not {target_height} and {radius}"
        )));
    }
    if gt.skew_x != 0.0 || gt.skew_y != 0.0 {
        return Err(TinError::InvalidParameter(
            "the grid must be north-up: rotated or skewed grids are not supported".into(),
        ));
    }
    let tris = triangles_at(tin, level, gt, width, height, interrupt)?;
    let mut counts = vec![NODATA; tris.len()];
    let mut out = Viewshed::default();
    let bounds = if prune {
        // only where the eyes' rays go: no farther than the radius and a
        // step (half a cell) past the farthest cell, so boxes of the radius
        // and two cells
        let r = radius + 2.0 * gt.scale_x.abs().max(gt.scale_y.abs());
        let boxes: Vec<[f64; 4]> = eyes
            .iter()
            .map(|e| [e.x - r, e.y - r, e.x + r, e.y + r])
            .collect();
        Bounds::new(tin, level, Some(&boxes), interrupt)?
    } else {
        // nothing rises above +inf: nothing is ever skipped
        Bounds {
            up: (0..level)
                .map(|l| vec![f64::INFINITY; tin.levels[l].num_triangles()])
                .collect(),
        }
    };
    for e in eyes {
        if ![e.x, e.y, e.z].iter().all(|v| v.is_finite()) {
            return Err(TinError::InvalidParameter(
                "the observer must be finite".into(),
            ));
        }
        if locate::locate_hull(tin, 0, e.x, e.y).is_none() {
            return Err(TinError::InvalidParameter(format!(
                "the observer ({}, {}) is off the tin's hull",
                e.x, e.y
            )));
        }
        one_eye(
            tin,
            level,
            &bounds,
            e,
            target_height,
            radius,
            gt,
            width,
            height,
            &tris,
            &mut counts,
            &mut out,
            interrupt,
        )?;
    }
    out.counts = counts;
    Ok(out)
}

/// What one eye's wedges found: the cells seen (their indices) and the
/// work done.
#[derive(Default)]
struct Found {
    seen: Vec<u32>,
    stats: Viewshed,
}

/// One eye's view of the grid: what every wedge of the fan needs.
struct Fan<'a> {
    tin: &'a Tin,
    level: usize,
    bounds: &'a Bounds,
    e: Eye,
    th: f64,
    radius: f64,
    gt: &'a GeoTransform,
    width: usize,
    height: usize,
    /// The level's triangle at each cell's centre (`u32::MAX` off the
    /// surface), and each triangle's plane as seen from the eye: the
    /// height at offset `(vx, vy)` from it is `p + gx vx + gy vy`.
    tris: &'a [u32],
    planes: &'a [[f64; 3]],
    /// Horizontal distance covered by the rays.
    reach: f64,
    /// Rays in the fan, the angle between two, and the first one's.
    k: usize,
    dtheta: f64,
    offset: f64,
    /// The last stretch before a cell walked on its own ray.
    behind: f64,
    near: f64,
    tol: f64,
}

impl Fan<'_> {
    fn dir(&self, i: usize) -> [f64; 2] {
        let a = self.offset + (i % self.k) as f64 * self.dtheta;
        [a.cos(), a.sin()]
    }

    fn cx(&self, c: usize) -> f64 {
        self.gt.ip_x + (c as f64 + 0.5) * self.gt.scale_x
    }

    fn cy(&self, r: usize) -> f64 {
        self.gt.ip_y + (r as f64 + 0.5) * self.gt.scale_y
    }

    fn walk(&self, d: [f64; 2], from: f64, len: f64, sink: &mut dyn RaySink, st: &mut Viewshed) {
        let mut w = RayWalk {
            tin: self.tin,
            level: self.level,
            bounds: self.bounds,
            o: [self.e.x, self.e.y],
            dir: d,
            len,
            near: self.near,
            pieces: 0,
            pruned: 0,
            kids: Vec::with_capacity(64),
        };
        w.run(from, sink);
        st.fine_pieces += w.pieces;
        st.pruned += w.pruned;
    }

    /// The running horizon of the ray along `d`, into `h`.
    fn profile(&self, d: [f64; 2], h: &mut Horizon, st: &mut Viewshed) {
        h.reset(self.e.drop(d), self.e.z);
        self.walk(d, 0.0, self.reach + self.near, h, st);
        st.rays += 1;
    }

    /// Whether the surface stays below `limit` (in `f`) along `u` from
    /// `from` to `len`: the exact walk of one cell's own ray.
    fn clear(&self, u: [f64; 2], from: f64, len: f64, limit: f64, st: &mut Viewshed) -> bool {
        let mut chk = Check {
            c: self.e.drop(u),
            z0: self.e.z,
            limit,
            blocked: false,
        };
        self.walk(u, from, len, &mut chk, st);
        !chk.blocked
    }

    /// The rows (columns) whose centres lie between the coordinates `a`
    /// and `b`, a hair wider (the wedge test decides), within `0..n`.
    fn between(a: f64, b: f64, ip: f64, scale: f64, n: usize) -> (i64, i64) {
        let (pa, pb) = ((a - ip) / scale - 0.5, (b - ip) / scale - 0.5);
        let (lo, hi) = (pa.min(pb) - 1e-6, pa.max(pb) + 1e-6);
        // ceil and floor of numbers >= -1 by truncation (faster than the
        // library calls on the baseline x86-64 target)
        let (lo, hi) = (lo.max(-1.0) + 1.0, hi.clamp(-1.0, n as f64) + 1.0);
        let lo_i = lo as i64 + i64::from(lo.fract() > 0.0);
        (lo_i - 1, hi as i64 - 1)
    }

    /// The cells whose centres are in the sector from ray `dirs[0]`
    /// (included) to its last ray (excluded) and within the radius, each
    /// given to `cell` with its distance, its offset from the eye and the
    /// wedge `p` it is in (between `dirs[p]`, included, and `dirs[p + 1]`).
    /// The sector is less than a half-turn wide.
    fn sector_cells(&self, dirs: &[[f64; 2]], mut cell: impl FnMut(usize, f64, f64, f64, usize)) {
        let (e, gt) = (&self.e, self.gt);
        let (w, h) = (self.width, self.height);
        let cross = |d: [f64; 2], vx: f64, vy: f64| d[0] * vy - d[1] * vx;
        let (d0, d1) = (dirs[0], dirs[dirs.len() - 1]);
        let last = dirs.len() - 2;
        let inv_dtheta = 1.0 / self.dtheta;
        let mut consider = |c: i64, r: i64| {
            if c < 0 || r < 0 || c >= w as i64 || r >= h as i64 {
                return;
            }
            let (c, r) = (c as usize, r as usize);
            let (vx, vy) = (self.cx(c) - e.x, self.cy(r) - e.y);
            if cross(d0, vx, vy) >= 0.0 && cross(d1, vx, vy) < 0.0 {
                let dist = (vx * vx + vy * vy).sqrt();
                if dist <= self.radius {
                    // the wedge: estimated from the angle to the first ray
                    // (its tangent, then the arctangent's series: a sector
                    // is at most a sixteenth of a turn), then settled by
                    // the exact tests either way
                    let x = cross(d0, vx, vy) / (d0[0] * vx + d0[1] * vy);
                    let est = (x - x * x * x * (1.0 / 3.0)) * inv_dtheta;
                    let mut p = (est.max(0.0) as usize).min(last);
                    while p < last && cross(dirs[p + 1], vx, vy) >= 0.0 {
                        p += 1;
                    }
                    while p > 0 && cross(dirs[p], vx, vy) < 0.0 {
                        p -= 1;
                    }
                    cell(r * w + c, dist, vx, vy, p);
                }
            }
        };
        // along the sector's major axis a (0: x, the columns; 1: y, the
        // rows) on its side of the eye, and in each column (row) the cells
        // between the two rays along the other axis b
        let mid = [d0[0] + d1[0], d0[1] + d1[1]];
        let a = usize::from(mid[0].abs() < mid[1].abs());
        let b = 1 - a;
        let (eye, ip, sc, n) = (
            [e.x, e.y],
            [gt.ip_x, gt.ip_y],
            [gt.scale_x, gt.scale_y],
            [w, h],
        );
        let sgn = mid[a].signum();
        let (i0, i1) = Self::between(
            eye[a] - sgn * sc[a].abs(),
            eye[a] + sgn * (self.reach + sc[a].abs()),
            ip[a],
            sc[a],
            n[a],
        );
        for i in i0.max(0)..=i1.min(n[a] as i64 - 1) {
            let da = ip[a] + (i as f64 + 0.5) * sc[a] - eye[a];
            if da * sgn < 0.0 {
                continue;
            }
            let (pa, pb) = (eye[b] + da * d0[b] / d0[a], eye[b] + da * d1[b] / d1[a]);
            let (j0, j1) = Self::between(pa, pb, ip[b], sc[b], n[b]);
            for j in j0..=j1 {
                if a == 0 {
                    consider(i, j)
                } else {
                    consider(j, i)
                }
            }
        }
    }

    /// The wedges `i0..i1` of the fan: the cells they see.
    fn wedges(&self, i0: usize, i1: usize) -> Found {
        let mut f = Found::default();
        let st = &mut f.stats;
        let dirs: Vec<[f64; 2]> = (i0..=i1).map(|i| self.dir(i)).collect();
        let mut hz: Vec<Horizon> = dirs
            .iter()
            .map(|&d| {
                let mut h = Horizon::new();
                self.profile(d, &mut h, st);
                h
            })
            .collect();
        let mut seen = Vec::new();
        self.sector_cells(&dirs, |idx, dist, vx, vy, p| {
            let t = self.tris[idx];
            let Some(&[pz, gx, gy]) = self.planes.get(t as usize) else {
                return;
            };
            let zc = pz + gx * vx + gy * vy;
            st.cells += 1;
            let inv = 1.0 / dist;
            let u = [vx * inv, vy * inv];
            let c = self.e.drop(u);
            let limit = (zc + self.th - c * dist * dist - self.e.z + self.tol) * inv;
            // the horizon of the terrain more than `behind` before the
            // cell, from its two rays (at most half a cell apart there):
            // decided where both agree by more than they differ; the last
            // `behind` walked exactly on the cell's own ray
            let far = dist - self.behind;
            let visible = if far <= self.near {
                st.exact_cells += 1;
                self.clear(u, 0.0, dist, limit, st)
            } else {
                let (ha, hb) = (hz[p].at(far), hz[p + 1].at(far));
                let band = (ha - hb).abs();
                if limit < ha.min(hb) - band {
                    false
                } else if limit >= ha.max(hb) + band {
                    st.local_cells += 1;
                    let o = [self.e.x, self.e.y];
                    let back =
                        clear_back(self.tin, self.level, t, o, u, far, dist, c, self.e.z, limit);
                    back.unwrap_or_else(|| self.clear(u, far, dist, limit, st))
                } else {
                    st.exact_cells += 1;
                    self.clear(u, 0.0, dist, limit, st)
                }
            };
            if visible {
                seen.push(idx as u32);
            }
        });
        f.seen = seen;
        f
    }
}

#[allow(clippy::too_many_arguments)]
fn one_eye(
    tin: &Tin,
    level: usize,
    bounds: &Bounds,
    e: &Eye,
    th: f64,
    radius: f64,
    gt: &GeoTransform,
    width: usize,
    height: usize,
    tris: &[u32],
    counts: &mut [u16],
    out: &mut Viewshed,
    interrupt: &mut Interrupt<'_>,
) -> Result<(), TinError> {
    if width == 0 || height == 0 {
        return Ok(());
    }
    let (sx, sy) = (gt.scale_x.abs(), gt.scale_y.abs());
    let cell = sx.min(sy);
    let cx = |c: usize| gt.ip_x + (c as f64 + 0.5) * gt.scale_x;
    let cy = |r: usize| gt.ip_y + (r as f64 + 0.5) * gt.scale_y;
    // every cell on the surface and in reach is hidden until seen; the
    // farthest one is how far the rays go
    let mut reach = 0.0f64;
    let mut ticker = Ticker::new(interrupt);
    let r2 = radius * radius;
    for r in 0..height {
        ticker.check()?;
        let dy = cy(r) - e.y;
        let rest = r2 - dy * dy;
        if rest < 0.0 {
            continue;
        }
        // the columns within the radius, a column wider each way (the
        // test below decides)
        let half = rest.sqrt();
        let (a, b) = (
            (e.x - half - gt.ip_x) / gt.scale_x - 0.5,
            (e.x + half - gt.ip_x) / gt.scale_x - 0.5,
        );
        let (lo, hi) = (a.min(b) - 1.0, a.max(b) + 1.0);
        if hi < 0.0 || lo > width as f64 {
            continue;
        }
        let (c0, c1) = (lo.max(0.0) as usize, (hi as usize + 1).min(width));
        let (ts, cs) = (
            &tris[r * width..(r + 1) * width],
            &mut counts[r * width..(r + 1) * width],
        );
        for c in c0..c1 {
            let dx = cx(c) - e.x;
            let d2 = dx * dx + dy * dy;
            if d2 <= r2 && ts[c] != u32::MAX {
                reach = reach.max(d2);
                if cs[c] == NODATA {
                    cs[c] = HIDDEN;
                }
            }
        }
    }
    let reach = reach.sqrt();
    let zscale = tin
        .bbox
        .max_z
        .abs()
        .max(tin.bbox.min_z.abs())
        .max(e.z.abs())
        .max(1.0);
    // rays at most half a cell apart at the farthest cell
    let k = ((std::f64::consts::TAU * reach / (0.5 * cell)).ceil() as usize).max(16);
    let dtheta = std::f64::consts::TAU / k as f64;
    // every triangle's plane as seen from the eye (offsets from it keep
    // the sums small)
    let lv = &tin.levels[level];
    let planes: Vec<[f64; 3]> = (0..lv.num_domain() as u32)
        .map(|t| {
            if lv.is_void(t) {
                return [f64::NAN; 3];
            }
            plane(&tin.corners(level, t), [e.x, e.y])
        })
        .collect();
    let fan = Fan {
        tin,
        level,
        bounds,
        e: *e,
        th,
        radius,
        gt,
        width,
        height,
        tris,
        planes: &planes,
        reach,
        k,
        dtheta,
        // off the axes and the diagonals, where grid vertices line up
        offset: 0.381_966_011_250_105 * dtheta,
        behind: 4.0 * cell,
        near: 1e-9 * cell,
        tol: 1e-9 * (zscale + th.abs()),
    };
    // the wedges in chunks (sectors of at most an eighth of a turn), on
    // the pool
    let per = (k / 16).clamp(1, 64);
    let chunks: Vec<(usize, usize)> = (0..k).step_by(per).map(|i| (i, (i + per).min(k))).collect();
    let mut seen_total = Vec::new();
    crate::par::map_batched(
        &chunks,
        |&(i0, i1)| fan.wedges(i0, i1),
        ticker.callback(),
        &mut |f: Found| {
            seen_total.push(f.seen);
            let s = f.stats;
            out.rays += s.rays;
            out.fine_pieces += s.fine_pieces;
            out.pruned += s.pruned;
            out.exact_cells += s.exact_cells;
            out.local_cells += s.local_cells;
            out.cells += s.cells;
            Ok(())
        },
    )?;
    for list in seen_total {
        for i in list {
            counts[i as usize] += 1;
        }
    }
    // the cell under the eye, in no wedge: seen
    let (c, r) = (
        ((e.x - gt.ip_x) / gt.scale_x).floor(),
        ((e.y - gt.ip_y) / gt.scale_y).floor(),
    );
    if c >= 0.0 && r >= 0.0 && (c as usize) < width && (r as usize) < height {
        let (c, r) = (c as usize, r as usize);
        let i = r * width + c;
        if cx(c) == e.x && cy(r) == e.y && tris[i] != u32::MAX {
            out.cells += 1;
            counts[i] += 1;
        }
    }
    Ok(())
}
