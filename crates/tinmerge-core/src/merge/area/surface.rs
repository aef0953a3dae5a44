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

use crate::geom::P2;
use crate::interrupt::{Interrupt, Ticker};
use crate::merge::area::Sweep;
use crate::merge::area::clip::{Chain, Moments, clip_chains, clip_convex, clipped_moments};
use crate::polygon::{Area, Where};
use crate::tin::TinError;
use crate::tin::mesh::Mesh;

/// Statistics of the clipped surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceStats {
    /// Planar area.
    pub area2d: f64,
    /// Surface area.
    pub area3d: f64,
    pub min_z: f64,
    pub max_z: f64,
    /// Integral of z over the planar area.
    pub z_integral: f64,
    /// Integral of the slope (degrees) over the planar area.
    pub slope_integral: f64,
    /// Steepest triangle with some area inside, degrees.
    pub max_slope: f64,
}

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
    /// count them).
    pub fn of_triangle(cs: &[[f64; 3]; 3]) -> SurfaceStats {
        let mut st = SurfaceStats::empty();
        for v in cs {
            st.min_z = st.min_z.min(v[2]);
            st.max_z = st.max_z.max(v[2]);
        }
        let c2: [P2; 3] = cs.map(|v| [v[0], v[1]]);
        let (z0, gx, gy) = plane(cs);
        st.add_part(&Moments::of_polygon(c2[0], &c2), z0, gx, gy);
        st
    }

    /// A region of one triangle's plane (z0, gx, gy, relative to the
    /// moments' origin) with moments `m` (nothing when it has no area).
    fn add_part(&mut self, m: &Moments, z0: f64, gx: f64, gy: f64) {
        if m.a <= 0.0 {
            return;
        }
        let grad = gx.hypot(gy);
        let slope = grad.atan().to_degrees();
        self.area2d += m.a;
        self.area3d += m.a * (1.0 + grad * grad).sqrt();
        self.z_integral += m.linear(z0, gx, gy);
        self.slope_integral += m.a * slope;
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

/// One triangle's part of the clipped region: the triangle's corners and
/// chains (None: wholly inside).
struct Part<'a> {
    corners: [[f64; 3]; 3],
    chains: Option<&'a [Chain]>,
}

/// Visit every triangle of the target level with area inside: inside ones
/// (descendants of coarser inside ones included; with `sums`, a coarser
/// inside triangle is handed to `whole` instead, which says whether it
/// took it whole, or its descendants are to be visited) and boundary ones.
fn each_part<M: Mesh>(
    tin: &M,
    s: &Sweep,
    whole: &mut dyn FnMut(usize, u32) -> bool,
    interrupt: &mut Interrupt<'_>,
    f: &mut dyn FnMut(Part) -> Result<(), TinError>,
) -> Result<(), TinError>
where
    TinError: From<M::Err>,
{
    let mut tk = Ticker::new(interrupt);
    let mut stack: Vec<(usize, u32)> = Vec::new();
    for (l, ts) in s.inside.iter().enumerate() {
        for &t in ts {
            stack.push((l, t));
            while let Some((l, t)) = stack.pop() {
                tk.tick()?;
                if l == s.level {
                    f(Part {
                        corners: tin.corners(s.level, t)?,
                        chains: None,
                    })?;
                } else if !whole(l, t) {
                    stack.extend(tin.children(l, t)?.rev().map(|c| (l + 1, c)));
                }
            }
        }
    }
    let mut k = 0;
    let mut owned: Vec<Chain> = Vec::new();
    for &t in &s.boundary {
        tk.tick()?;
        while k < s.chains.len() && s.chains[k].0 < t {
            k += 1;
        }
        owned.clear();
        while k < s.chains.len() && s.chains[k].0 == t {
            owned.push(s.chains[k].1.clone());
            k += 1;
        }
        f(Part {
            corners: tin.corners(s.level, t)?,
            chains: Some(&owned),
        })?;
    }
    Ok(())
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
    stats_with(tin, area, s, None, interrupt)
}

/// [`stats`], a coarse triangle wholly inside taken whole from `sums`
/// (when they are of the sweep's level) in O(1) instead of triangle by
/// triangle: the same sums up to rounding, at the cost of the boundary.
pub fn stats_with<M: Mesh>(
    tin: &M,
    area: &Area,
    s: &Sweep,
    sums: Option<&SubtreeSums>,
    interrupt: &mut Interrupt<'_>,
) -> Result<SurfaceStats, TinError>
where
    TinError: From<M::Err>,
{
    let sums = sums.filter(|u| u.level() == s.level);
    let st = std::cell::RefCell::new(SurfaceStats::empty());
    let mut whole = |l: usize, t: u32| match sums.and_then(|u| u.of(l, t)) {
        Some(a) => {
            st.borrow_mut().add(a);
            true
        }
        None => false,
    };
    each_part(tin, s, &mut whole, interrupt, &mut |p| {
        let mut st = st.borrow_mut();
        let cs = p.corners;
        let c2: [P2; 3] = cs.map(|v| [v[0], v[1]]);
        let o = c2[0];
        let (z0, gx, gy) = plane(&cs);
        let zat = |q: P2| z0 + gx * (q[0] - o[0]) + gy * (q[1] - o[1]);
        match p.chains {
            None => st.add(&SurfaceStats::of_triangle(&cs)),
            Some(ch) => {
                // extremes of a linear function over the clipped region lie
                // at its vertices: boundary points and corners in the area
                for q in ch.iter().flat_map(|c| c.pts.iter()) {
                    let z = zat(*q);
                    st.min_z = st.min_z.min(z);
                    st.max_z = st.max_z.max(z);
                }
                for v in &cs {
                    if area.locate([v[0], v[1]]) != Where::Outside {
                        st.min_z = st.min_z.min(v[2]);
                        st.max_z = st.max_z.max(v[2]);
                    }
                }
                let m = clipped_moments(&c2, o, ch, &mut |q| area.locate(q));
                st.add_part(&m, z0, gx, gy);
            }
        }
        Ok(())
    })?;
    Ok(st.into_inner())
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
    volume_parts_with(tin, area, s, base, None, interrupt)
}

/// [`volume_parts`], a coarse triangle wholly inside and with all its
/// descendants strictly above (or below) the base taken whole from `sums`
/// (when they are of the sweep's level) in O(1); one whose descendants
/// reach the base is looked into, child by child.
pub fn volume_parts_with<M: Mesh>(
    tin: &M,
    area: &Area,
    s: &Sweep,
    base: f64,
    sums: Option<&SubtreeSums>,
    interrupt: &mut Interrupt<'_>,
) -> Result<VolumeParts, TinError>
where
    TinError: From<M::Err>,
{
    let sums = sums.filter(|u| u.level() == s.level);
    let out = std::cell::RefCell::new(VolumeParts::default());
    let mut whole = |l: usize, t: u32| {
        let Some(a) = sums.and_then(|u| u.of(l, t)) else {
            return false;
        };
        let mut out = out.borrow_mut();
        if a.min_z > base {
            out.cut += (a.z_integral - base * a.area2d).max(0.0);
            out.area_above += a.area2d;
        } else if a.max_z < base {
            out.fill += (base * a.area2d - a.z_integral).max(0.0);
            out.area_below += a.area2d;
        } else {
            return false;
        }
        true
    };
    each_part(tin, s, &mut whole, interrupt, &mut |p| {
        let mut out = out.borrow_mut();
        let cs = p.corners;
        let c2: [P2; 3] = cs.map(|v| [v[0], v[1]]);
        let o = c2[0];
        let (z0, gx, gy) = plane(&cs);
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
            let m = match p.chains {
                None => Moments::of_polygon(o, &side),
                Some(ch) => {
                    let cut_chains = clip_chains(ch, &h);
                    clipped_moments(&side, o, &cut_chains, &mut |q| area.locate(q))
                }
            };
            let v = sign * m.linear(z0 - base, gx, gy);
            if sign > 0.0 {
                out.cut += v.max(0.0);
                out.area_above += m.a.max(0.0);
            } else {
                out.fill += v.max(0.0);
                out.area_below += m.a.max(0.0);
            }
        }
        Ok(())
    })?;
    Ok(out.into_inner())
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
/// let mut pts = Vec::new();
/// for i in 0..40 { for j in 0..40 {
///     let (x, y) = (i as f64, j as f64);
///     pts.push([x, y, (x * 0.3).sin() * 4.0 + (y * 0.2).cos() * 3.0]);
/// } }
/// let tin = build(pts, &[2.0, 0.5, 0.1], 0, &mut || Ok(())).unwrap();
/// let a = Area::new(vec![vec![vec![[3.3, 2.1], [36.0, 5.5], [30.2, 35.7], [4.4, 30.0]]]]);
/// let s = sweep(&tin, 2, &a, Method::Hierarchy, &mut || Ok(())).unwrap();
/// let sums = SubtreeSums::build(&tin, 2, &mut || Ok(())).unwrap();
/// let flat = stats(&tin, &a, &s, &mut || Ok(())).unwrap();
/// let fast = stats_with(&tin, &a, &s, Some(&sums), &mut || Ok(())).unwrap();
/// assert!((flat.area2d - fast.area2d).abs() < 1e-9 * flat.area2d);
/// assert!((flat.z_integral - fast.z_integral).abs() < 1e-9 * flat.z_integral.abs());
/// assert_eq!((flat.min_z, flat.max_z, flat.max_slope), (fast.min_z, fast.max_z, fast.max_slope));
/// ```
pub struct SubtreeSums {
    level: usize,
    /// `coarse[l][t]`: triangle t of level l < `level`, over its
    /// descendants at `level`.
    coarse: Vec<Vec<SurfaceStats>>,
}

impl SubtreeSums {
    /// The sums of every triangle of the levels coarser than `level`.
    pub fn build<M: Mesh>(
        tin: &M,
        level: usize,
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
        let mut coarse: Vec<Vec<SurfaceStats>> = vec![Vec::new(); level];
        for l in (0..level).rev() {
            let n = tin.num_triangles(l);
            let mut here = Vec::with_capacity(n);
            for t in 0..n as u32 {
                let mut a = SurfaceStats::empty();
                for c in tin.children(l, t)? {
                    tk.tick()?;
                    if l + 1 == level {
                        a.add(&SurfaceStats::of_triangle(&tin.corners(level, c)?));
                    } else {
                        let below = coarse[l + 1].get(c as usize).ok_or_else(|| {
                            TinError::corrupt(format!("child {c} of triangle {t} at level {l}"))
                        })?;
                        a.add(below);
                    }
                }
                here.push(a);
            }
            coarse[l] = here;
        }
        Ok(SubtreeSums { level, coarse })
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
