//! Surface statistics and volumes over the terrain clipped exactly to a
//! polygon (`tin_area_stats`, `tin_volume`), from the area sweep.
//!
//! Inside triangles count whole (their descendants at the target level, for
//! inside triangles found at coarser levels); boundary triangles count
//! through their boundary pieces ([`crate::merge::area::clip`]). The surface is
//! linear on each triangle, so every integral is exact up to rounding: the
//! integral of z over a region of a triangle is its area times the plane's
//! value at its centroid (from the first moments), and the volume above or
//! below a base height is the same integral over the part of the region on
//! that side of the line where the plane meets the base.
//!
//! ```
//! use tinmerge_core::tin::build::build;
//! use tinmerge_core::merge::area::{sweep, Method};
//! use tinmerge_core::merge::area::polygon::Area;
//! use tinmerge_core::merge::area::surface::{stats, volume, volume_parts};
//! // the plane z = x on a 3 x 3 grid
//! let mut pts = Vec::new();
//! for i in 0..3 { for j in 0..3 { pts.push([i as f64, j as f64, i as f64]); } }
//! let tin = build(pts, &[0.0], 0, &mut || Ok(())).unwrap();
//! let a = Area::new(vec![vec![vec![[0.5, 0.5], [1.5, 0.5], [1.5, 1.5], [0.5, 1.5]]]]);
//! let s = sweep(&tin, 0, &a, Method::Hierarchy, &mut || Ok(())).unwrap();
//! let st = stats(&tin, &a, &s, &mut || Ok(())).unwrap();
//! assert!((st.area2d - 1.0).abs() < 1e-12);
//! assert!((st.mean_z() - 1.0).abs() < 1e-12);
//! assert!((st.max_slope - 45.0).abs() < 1e-9);
//! let (cut, fill) = volume(&tin, &a, &s, 1.0, &mut || Ok(())).unwrap();
//! assert!((cut - 0.125).abs() < 1e-12 && (fill - 0.125).abs() < 1e-12);
//! let v = volume_parts(&tin, &a, &s, 1.0, &mut || Ok(())).unwrap();
//! assert!((v.area_above - 0.5).abs() < 1e-12 && (v.area_below - 0.5).abs() < 1e-12);
//! ```

use crate::geom::{P2, Units};
use crate::interrupt::{Interrupt, Ticker};
use crate::merge::area::Sweep;
use crate::merge::area::clip::{Chain, Moments, clip_chains, clip_convex, clipped_moments};
use crate::polygon::{Area, Where};
use crate::tin::TinError;
use crate::tin::layout::LevelSums;
use crate::tin::mesh::Mesh;

/// Statistics of the clipped surface: the record a stored value keeps for
/// each level's whole surface ([`LevelSums`], in the storage layer below
/// this one, so one definition serves both).
pub type SurfaceStats = LevelSums;

impl SurfaceStats {
    /// Nothing yet: no area, extremes at their identities.
    pub fn empty() -> SurfaceStats {
        SurfaceStats {
            area2d: 0.0,
            area3d: 0.0,
            min_z: f64::INFINITY,
            max_z: f64::NEG_INFINITY,
            z_integral: 0.0,
            slope_integral: 0.0,
            max_slope: f64::NEG_INFINITY,
        }
    }

    /// A triangle wholly inside: its corners' heights, and its area,
    /// integrals and slope unless it has no area (as the clipped parts
    /// count them), in `units`.
    pub fn of_triangle(cs: &[[f64; 3]; 3], units: Units) -> SurfaceStats {
        let mut st = SurfaceStats::empty();
        for v in cs {
            st.min_z = st.min_z.min(v[2]);
            st.max_z = st.max_z.max(v[2]);
        }
        let c2: [P2; 3] = cs.map(|v| [v[0], v[1]]);
        let (z0, gx, gy) = plane(cs);
        st.add_part(c2[0], &Moments::of_polygon(c2[0], &c2), (z0, gx, gy), units);
        st
    }

    /// A region of one triangle's plane (z0, gx, gy, relative to the
    /// moments' origin `o`) with moments `m` (nothing when it has no
    /// area), measured in `units` at the region's centroid.
    fn add_part(&mut self, o: P2, m: &Moments, (z0, gx, gy): (f64, f64, f64), units: Units) {
        if m.a <= 0.0 {
            return;
        }
        let (k, mx, my) = units.local(o[1] + m.my / m.a, gx, gy);
        // (the gradient's length squared: no overflow or underflow to
        // guard against at slopes a terrain has, which hypot's care costs)
        let g2 = mx * mx + my * my;
        let slope = g2.sqrt().atan().to_degrees();
        self.area2d += k * m.a;
        self.area3d += k * m.a * (1.0 + g2).sqrt();
        self.z_integral += k * m.linear(z0, gx, gy);
        self.slope_integral += k * m.a * slope;
        self.max_slope = self.max_slope.max(slope);
    }

    /// `o` added: sums summed, extremes combined.
    pub fn add(&mut self, o: &SurfaceStats) {
        self.area2d += o.area2d;
        self.area3d += o.area3d;
        self.z_integral += o.z_integral;
        self.slope_integral += o.slope_integral;
        self.min_z = self.min_z.min(o.min_z);
        self.max_z = self.max_z.max(o.max_z);
        self.max_slope = self.max_slope.max(o.max_slope);
    }

    /// Area-weighted mean height (NaN for an empty area).
    pub fn mean_z(&self) -> f64 {
        self.z_integral / self.area2d
    }
    /// Area-weighted mean slope in degrees (NaN for an empty area).
    pub fn mean_slope(&self) -> f64 {
        self.slope_integral / self.area2d
    }
}

/// The plane of a triangle relative to its first corner: (z0, dz/dx,
/// dz/dy).
pub fn plane(c: &[[f64; 3]; 3]) -> (f64, f64, f64) {
    let (ax, ay, az) = (c[1][0] - c[0][0], c[1][1] - c[0][1], c[1][2] - c[0][2]);
    let (bx, by, bz) = (c[2][0] - c[0][0], c[2][1] - c[0][1], c[2][2] - c[0][2]);
    let d = ax * by - bx * ay;
    let gx = (az * by - bz * ay) / d;
    let gy = (ax * bz - bx * az) / d;
    (c[0][2], gx, gy)
}

/// What [`boundary_parts`] hands each boundary triangle to: its corners and
/// its pieces of the polygon's boundary.
type PartFn<'f> = dyn FnMut([[f64; 3]; 3], &[Chain]) -> Result<(), TinError> + 'f;

/// Visit every boundary triangle of the target level with its pieces of
/// the polygon's boundary, in order.
fn boundary_parts<M: Mesh>(
    tin: &M,
    s: &Sweep,
    tk: &mut Ticker<'_, '_>,
    f: &mut PartFn<'_>,
) -> Result<(), TinError>
where
    TinError: From<M::Err>,
{
    let mut k = 0;
    for &t in &s.boundary {
        tk.tick()?;
        f(tin.corners(s.level, t)?, s.chains_of(t, &mut k))?;
    }
    Ok(())
}

/// What a subtree walk hands back for each triangle it finishes: its level,
/// its id, its sums and its volume parts (against `base`, when given).
type Finished<'f> = dyn FnMut(usize, u32, &SurfaceStats, &VolumeParts) + 'f;

/// The triangles of the target level `leaves` (a contiguous range, all
/// descendants of one triangle of level `top`, or a whole level) walked in
/// order, each triangle of the levels `top..level` between them finished as
/// soon as its last descendant is passed: its sums are its children's added
/// in order to [`SurfaceStats::empty`] (as [`SubtreeSums::build`] adds
/// them, so the same bits), its volume parts taken whole from its sums when
/// its descendants are all strictly above or below `base`, otherwise its
/// children's added in order. Reads each leaf and its parent links
/// (sequential on a value read in slices), never a triangle's children.
fn walk_leaves<M: Mesh>(
    tin: &M,
    level: usize,
    top: usize,
    leaves: std::ops::Range<u32>,
    Measure { units, base }: Measure,
    tk: &mut Ticker<'_, '_>,
    finished: &mut Finished<'_>,
) -> Result<(), TinError>
where
    TinError: From<M::Err>,
{
    // the open triangles, one per level top..level: id, sums, volume parts
    let mut open: Vec<(u32, SurfaceStats, VolumeParts)> = Vec::with_capacity(level - top);
    let close = |open: &mut Vec<(u32, SurfaceStats, VolumeParts)>, finished: &mut Finished<'_>| {
        if let Some((id, a, v)) = open.pop() {
            let v = base
                .and_then(|b| VolumeParts::of_subtree(&a, b))
                .unwrap_or(v);
            finished(top + open.len(), id, &a, &v);
            if let Some(up) = open.last_mut() {
                up.1.add(&a);
                up.2.add(&v);
            }
        }
    };
    let mut path: Vec<u32> = vec![0; level - top];
    for i in leaves {
        tk.tick()?;
        // the leaf's ancestors, from its parent up, as far as they differ
        // from the open ones
        let mut k = level;
        let mut id = i;
        let mut same = 0;
        while k > top {
            id = tin.parent(k, id)?;
            k -= 1;
            path[k - top] = id;
            if open.get(k - top).is_some_and(|o| o.0 == id) {
                same = k - top + 1;
                break;
            }
        }
        while open.len() > same {
            close(&mut open, finished);
        }
        for &p in &path[same..] {
            open.push((p, SurfaceStats::empty(), VolumeParts::default()));
        }
        let cs = tin.corners(level, i)?;
        let a = SurfaceStats::of_triangle(&cs, units);
        let v = base.map_or_else(VolumeParts::default, |b| {
            VolumeParts::of_part(&cs, None, b, units)
        });
        if let Some(up) = open.last_mut() {
            up.1.add(&a);
            up.2.add(&v);
        }
    }
    while !open.is_empty() {
        close(&mut open, finished);
    }
    Ok(())
}

/// The descendants of triangle `t` of level `l` at level `level`: a
/// contiguous range (triangles are sorted by parent), from the children of
/// its first and last descendant at each level.
fn leaf_range<M: Mesh>(
    tin: &M,
    level: usize,
    (l, t): (usize, u32),
) -> Result<std::ops::Range<u32>, TinError>
where
    TinError: From<M::Err>,
{
    let mut r = t..t + 1;
    for k in l..level {
        if r.is_empty() {
            break;
        }
        let first = tin.children(k, r.start)?.start;
        let last = tin.children(k, r.end - 1)?.end;
        r = first..last.max(first);
    }
    Ok(r)
}

/// Triangle `t` of level `l` (< `level`) over its descendants: its sums
/// and its volume parts against `base`, by [`walk_leaves`].
fn walk_subtree<M: Mesh>(
    tin: &M,
    level: usize,
    (l, t): (usize, u32),
    how: Measure,
    tk: &mut Ticker<'_, '_>,
) -> Result<(SurfaceStats, VolumeParts), TinError>
where
    TinError: From<M::Err>,
{
    let mut out = (SurfaceStats::empty(), VolumeParts::default());
    let leaves = leaf_range(tin, level, (l, t))?;
    walk_leaves(tin, level, l, leaves, how, tk, &mut |k, id, a, v| {
        if k == l && id == t {
            out = (*a, *v);
        }
    })?;
    Ok(out)
}

/// Triangle `t` of level `l`, wholly inside, over its descendants at the
/// target level: from `sums` when they hold it, otherwise summed over its
/// leaves by [`walk_leaves`], as [`SubtreeSums::build`] sums them, so both
/// give the same bits.
fn subtree<M: Mesh>(
    tin: &M,
    level: usize,
    (l, t): (usize, u32),
    sums: Option<&SubtreeSums>,
    units: Units,
    tk: &mut Ticker<'_, '_>,
) -> Result<SurfaceStats, TinError>
where
    TinError: From<M::Err>,
{
    if l == level {
        tk.tick()?;
        return Ok(SurfaceStats::of_triangle(&tin.corners(level, t)?, units));
    }
    match sums.and_then(|u| u.of(l, t)) {
        Some(a) => Ok(*a),
        None => Ok(walk_subtree(tin, level, (l, t), Measure { units, base: None }, tk)?.0),
    }
}

/// What a walk over leaves measures: in which units, and volumes against
/// which base (none: sums only).
#[derive(Clone, Copy)]
struct Measure {
    units: Units,
    base: Option<f64>,
}

/// Statistics of the surface clipped to the area.
pub fn stats<M: Mesh>(
    tin: &M,
    area: &Area,
    s: &Sweep,
    interrupt: &mut Interrupt<'_>,
) -> Result<SurfaceStats, TinError>
where
    TinError: From<M::Err>,
{
    stats_with(tin, area, s, None, Units::Planar, interrupt)
}

/// [`stats`], a coarse triangle wholly inside taken whole from `sums`
/// (when they are of the sweep's level) in O(1) instead of triangle by
/// triangle. The same bits with or without them: a coarse triangle inside
/// is always summed over its subtree as the sums are made, then added;
/// then the boundary triangles' parts, in order. Measured in `units`
/// (the sums are used only when made in the same).
pub fn stats_with<M: Mesh>(
    tin: &M,
    area: &Area,
    s: &Sweep,
    sums: Option<&SubtreeSums>,
    units: Units,
    interrupt: &mut Interrupt<'_>,
) -> Result<SurfaceStats, TinError>
where
    TinError: From<M::Err>,
{
    let sums = sums.filter(|u| u.level() == s.level && u.units == units);
    let mut tk = Ticker::new(interrupt);
    let mut st = SurfaceStats::empty();
    for (l, ts) in s.inside.iter().enumerate() {
        for &t in ts {
            st.add(&subtree(tin, s.level, (l, t), sums, units, &mut tk)?);
        }
    }
    // where each point tested lies, kept for the call: a boundary
    // triangle's corners are its neighbours' too
    let mut located: rustc_hash::FxHashMap<[u64; 2], Where> =
        rustc_hash::FxHashMap::with_capacity_and_hasher(2 * s.boundary.len(), Default::default());
    let mut locate = |q: P2| {
        *located
            .entry([q[0].to_bits(), q[1].to_bits()])
            .or_insert_with(|| area.locate(q))
    };
    boundary_parts(tin, s, &mut tk, &mut |cs, ch| {
        let c2: [P2; 3] = cs.map(|v| [v[0], v[1]]);
        let o = c2[0];
        let (z0, gx, gy) = plane(&cs);
        let zat = |q: P2| z0 + gx * (q[0] - o[0]) + gy * (q[1] - o[1]);
        // extremes of a linear function over the clipped region lie at its
        // vertices: boundary points and corners in the area
        for q in ch.iter().flat_map(|c| c.pts.iter()) {
            let z = zat(*q);
            st.min_z = st.min_z.min(z);
            st.max_z = st.max_z.max(z);
        }
        for v in &cs {
            if locate([v[0], v[1]]) != Where::Outside {
                st.min_z = st.min_z.min(v[2]);
                st.max_z = st.max_z.max(v[2]);
            }
        }
        let m = clipped_moments(&c2, o, ch, &mut locate);
        st.add_part(o, &m, (z0, gx, gy), units);
        Ok(())
    })?;
    Ok(st)
}

/// Volume between the clipped surface and the height `base`: (cut, fill) =
/// (volume of surface above base, volume of space below base down to the
/// surface).
pub fn volume<M: Mesh>(
    tin: &M,
    area: &Area,
    s: &Sweep,
    base: f64,
    interrupt: &mut Interrupt<'_>,
) -> Result<(f64, f64), TinError>
where
    TinError: From<M::Err>,
{
    let v = volume_parts(tin, area, s, base, interrupt)?;
    Ok((v.cut, v.fill))
}

/// The parts of [`volume`]: both volumes and the planar areas where the
/// surface is above and below the base.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VolumeParts {
    pub cut: f64,
    pub fill: f64,
    /// Planar area where the surface is above the base.
    pub area_above: f64,
    /// Planar area where it is below.
    pub area_below: f64,
}

impl VolumeParts {
    fn add(&mut self, o: &VolumeParts) {
        self.cut += o.cut;
        self.fill += o.fill;
        self.area_above += o.area_above;
        self.area_below += o.area_below;
    }

    /// A subtree whose descendants are all strictly above or all strictly
    /// below `base`, from its sums; None when they reach the base.
    pub fn of_subtree(a: &SurfaceStats, base: f64) -> Option<VolumeParts> {
        if a.min_z > base {
            Some(VolumeParts {
                cut: (a.z_integral - base * a.area2d).max(0.0),
                area_above: a.area2d,
                ..VolumeParts::default()
            })
        } else if a.max_z < base {
            Some(VolumeParts {
                fill: (base * a.area2d - a.z_integral).max(0.0),
                area_below: a.area2d,
                ..VolumeParts::default()
            })
        } else {
            None
        }
    }

    /// One triangle of the target level: wholly inside (`cut` None) or its
    /// part inside the area through its pieces of the area's boundary, in
    /// `units` (each side of the base measured at its own centroid).
    fn of_part(
        cs: &[[f64; 3]; 3],
        cut: Option<(&[Chain], &Area)>,
        base: f64,
        units: Units,
    ) -> VolumeParts {
        let mut out = VolumeParts::default();
        let c2: [P2; 3] = cs.map(|v| [v[0], v[1]]);
        let o = c2[0];
        let (z0, gx, gy) = plane(cs);
        for sign in [1.0, -1.0] {
            // h >= 0 where the surface is on this side of the base
            let h = |q: P2| sign * (z0 + gx * (q[0] - o[0]) + gy * (q[1] - o[1]) - base);
            if cs.iter().all(|v| sign * (v[2] - base) <= 0.0) {
                // wholly on the other side (or on the base): nothing here
                continue;
            }
            let side = if cs.iter().all(|v| sign * (v[2] - base) >= 0.0) {
                c2.to_vec()
            } else {
                clip_convex(&c2, &h)
            };
            if side.len() < 3 {
                continue;
            }
            let m = match cut {
                None => Moments::of_polygon(o, &side),
                Some((ch, area)) => {
                    let cut_chains = clip_chains(ch, &h);
                    clipped_moments(&side, o, &cut_chains, &mut |q| area.locate(q))
                }
            };
            if m.a <= 0.0 {
                continue;
            }
            let k = units.area_scale(o[1] + m.my / m.a);
            let v = k * sign * m.linear(z0 - base, gx, gy);
            if sign > 0.0 {
                out.cut += v.max(0.0);
                out.area_above += k * m.a;
            } else {
                out.fill += v.max(0.0);
                out.area_below += k * m.a;
            }
        }
        out
    }
}

/// Triangle `t` of level `l`, wholly inside: its sums over its descendants
/// (as [`subtree`]) and its volume parts, taken whole from the sums when
/// its descendants are all strictly above or below the base, otherwise
/// the sum of its children's parts in order. Computed depth first; with
/// `sums`, a subtree whose sums settle it is not entered: the same bits.
fn subtree_volume<M: Mesh>(
    tin: &M,
    level: usize,
    (l, t): (usize, u32),
    base: f64,
    sums: Option<&SubtreeSums>,
    units: Units,
    tk: &mut Ticker<'_, '_>,
) -> Result<(SurfaceStats, VolumeParts), TinError>
where
    TinError: From<M::Err>,
{
    if l == level {
        tk.tick()?;
        let cs = tin.corners(level, t)?;
        return Ok((
            SurfaceStats::of_triangle(&cs, units),
            VolumeParts::of_part(&cs, None, base, units),
        ));
    }
    let Some(a) = sums.and_then(|u| u.of(l, t)) else {
        let how = Measure {
            units,
            base: Some(base),
        };
        return walk_subtree(tin, level, (l, t), how, tk);
    };
    if let Some(v) = VolumeParts::of_subtree(a, base) {
        return Ok((*a, v));
    }
    // reaching the base: into its children (whose sums may settle them)
    let (mut a, mut v) = (SurfaceStats::empty(), VolumeParts::default());
    for c in tin.children(l, t)? {
        let (ac, vc) = subtree_volume(tin, level, (l + 1, c), base, sums, units, tk)?;
        a.add(&ac);
        v.add(&vc);
    }
    let v = VolumeParts::of_subtree(&a, base).unwrap_or(v);
    Ok((a, v))
}

/// [`volume`] with the areas on either side of the base.
pub fn volume_parts<M: Mesh>(
    tin: &M,
    area: &Area,
    s: &Sweep,
    base: f64,
    interrupt: &mut Interrupt<'_>,
) -> Result<VolumeParts, TinError>
where
    TinError: From<M::Err>,
{
    volume_parts_with(tin, area, s, base, None, Units::Planar, interrupt)
}

/// [`volume_parts`], a coarse triangle wholly inside and with all its
/// descendants strictly above (or below) the base taken whole from `sums`
/// (when they are of the sweep's level) in O(1); one whose descendants
/// reach the base is looked into, child by child. The same bits with or
/// without them ([`subtree_volume`]). Measured in `units` (the sums are
/// used only when made in the same).
pub fn volume_parts_with<M: Mesh>(
    tin: &M,
    area: &Area,
    s: &Sweep,
    base: f64,
    sums: Option<&SubtreeSums>,
    units: Units,
    interrupt: &mut Interrupt<'_>,
) -> Result<VolumeParts, TinError>
where
    TinError: From<M::Err>,
{
    let sums = sums.filter(|u| u.level() == s.level && u.units == units);
    let mut tk = Ticker::new(interrupt);
    let mut out = VolumeParts::default();
    for (l, ts) in s.inside.iter().enumerate() {
        for &t in ts {
            out.add(&subtree_volume(tin, s.level, (l, t), base, sums, units, &mut tk)?.1);
        }
    }
    boundary_parts(tin, s, &mut tk, &mut |cs, ch| {
        out.add(&VolumeParts::of_part(&cs, Some((ch, area)), base, units));
        Ok(())
    })?;
    Ok(out)
}

/// Each coarse triangle's [`SurfaceStats`] over its descendants at one
/// target level, so a triangle wholly inside a polygon counts in O(1)
/// ([`stats_with`], [`volume_parts_with`]): the area merge's statistics at
/// the cost of the boundary (issue 76). Made in one pass over the target
/// level's triangles, bottom-up (each coarser level from its children,
/// which are contiguous); 56 bytes per triangle of the coarser levels.
///
/// ```
/// use tinmerge_core::tin::build::build;
/// use tinmerge_core::merge::area::{sweep, Method};
/// use tinmerge_core::merge::area::polygon::Area;
/// use tinmerge_core::merge::area::surface::{stats, stats_with, SubtreeSums};
/// use tinmerge_core::geom::Units;
/// let mut pts = Vec::new();
/// for i in 0..40 { for j in 0..40 {
///     let (x, y) = (i as f64, j as f64);
///     pts.push([x, y, (x * 0.3).sin() * 4.0 + (y * 0.2).cos() * 3.0]);
/// } }
/// let tin = build(pts, &[2.0, 0.5, 0.1], 0, &mut || Ok(())).unwrap();
/// let a = Area::new(vec![vec![vec![[3.3, 2.1], [36.0, 5.5], [30.2, 35.7], [4.4, 30.0]]]]);
/// let s = sweep(&tin, 2, &a, Method::Hierarchy, &mut || Ok(())).unwrap();
/// let sums = SubtreeSums::build(&tin, 2, Units::Planar, &mut || Ok(())).unwrap();
/// let flat = stats(&tin, &a, &s, &mut || Ok(())).unwrap();
/// let fast = stats_with(&tin, &a, &s, Some(&sums), Units::Planar, &mut || Ok(())).unwrap();
/// // the same bits, with or without the sums
/// assert_eq!(flat, fast);
/// ```
pub struct SubtreeSums {
    level: usize,
    units: Units,
    /// `coarse[l][t]`: triangle t of level l < `level`, over its
    /// descendants at `level`.
    coarse: Vec<Vec<SurfaceStats>>,
}

impl SubtreeSums {
    /// The sums of every triangle of the levels coarser than `level`: one
    /// walk over the level's triangles in order ([`walk_leaves`]), each
    /// coarser triangle finished as its last descendant is passed (its
    /// children's sums added in order to [`SurfaceStats::empty`]).
    pub fn build<M: Mesh>(
        tin: &M,
        level: usize,
        units: Units,
        interrupt: &mut Interrupt<'_>,
    ) -> Result<SubtreeSums, TinError>
    where
        TinError: From<M::Err>,
    {
        if level >= tin.num_levels() {
            return Err(TinError::InvalidParameter(format!(
                "level {level} of a tin of {} levels",
                tin.num_levels()
            )));
        }
        let mut tk = Ticker::new(interrupt);
        let mut coarse: Vec<Vec<SurfaceStats>> = (0..level)
            .map(|l| vec![SurfaceStats::empty(); tin.num_triangles(l)])
            .collect();
        if level > 0 {
            let n = tin.num_triangles(level) as u32;
            let mut bad = None;
            walk_leaves(
                tin,
                level,
                0,
                0..n,
                Measure { units, base: None },
                &mut tk,
                &mut |l, t, a, _| match coarse.get_mut(l).and_then(|c| c.get_mut(t as usize)) {
                    Some(slot) => *slot = *a,
                    None => bad = Some((l, t)),
                },
            )?;
            if let Some((l, t)) = bad {
                return Err(TinError::corrupt(format!(
                    "triangle {t} of level {l} out of range"
                )));
            }
        }
        Ok(SubtreeSums {
            level,
            units,
            coarse,
        })
    }

    /// The target level.
    pub fn level(&self) -> usize {
        self.level
    }

    /// Triangle `t` of level `l` over its descendants at the target level
    /// (None at the target level or finer, or for no such triangle).
    pub fn of(&self, l: usize, t: u32) -> Option<&SurfaceStats> {
        self.coarse.get(l)?.get(t as usize)
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.coarse.iter().map(|v| v.len()).sum::<usize>() * std::mem::size_of::<SurfaceStats>()
    }
}
