//! Breaklines and boundary rings in a build: the network, the samples
//! they drop, each soft segment's profile, level 0's constraint edges.

use super::builder::*;
use super::common::*;
use crate::interrupt::Interrupt;
use crate::polygon::{Area, Where};
use crate::tin::TinError;
use crate::tin::breaklines::{Breakline, Network, clip_to_hull, drops_sample, network, profile};
use crate::tin::samples::{SampleGrid, Samples, c2};
use crate::tin::sides::choose_border;
use crate::tin::surface::Reference;
use robust::orient2d;
use spade::handles::FixedVertexHandle;
use spade::{FloatTriangulation, Point2, Triangulation};

/// The samples' height at (x, y): linear in the Delaunay triangulation of
/// the samples around it (a box grown until it holds the point), None
/// outside the samples' hull.
pub(super) fn sample_height(grid: &SampleGrid, x: f64, y: f64) -> Option<f64> {
    let mut r = 2.0 * grid.cell_area().sqrt();
    if !(r.is_finite() && r > 0.0) {
        r = 1.0;
    }
    let spacing = r / 2.0;
    for _ in 0..64 {
        let mut dt = Dt::new();
        let mut zs = Vec::new();
        let mut n = 0usize;
        grid.for_each_in_box(x - r, y - r, x + r, y + r, |_, p| {
            n += 1;
            if let Ok(h) = dt.insert(Point2::new(p[0], p[1]))
                && h.index() == zs.len()
            {
                zs.push(p[2]);
            }
        });
        if dt.num_vertices() >= 3 {
            let z = dt
                .barycentric()
                .interpolate(|v| zs[v.fix().index()], Point2::new(x, y));
            if z.is_some() {
                return z;
            }
            // a point outside the hull of the samples around it by less
            // than a sample spacing: a line cut at the samples' hull, whose
            // long edges (a rotated raster's border) run up to a pixel
            // beside the outermost samples, or a boundary's corner beside
            // them. The height at the nearest point of that hull: the
            // samples' own, where growing the box would reach a far hull
            // vertex and a sliver across the whole raster
            if let Some(z) = near_hull_edge(&dt, &zs, x, y, spacing) {
                return Some(z);
            }
        }
        if n == grid.len() {
            return None;
        }
        r *= 2.0;
    }
    None
}

/// The height at (x, y) along the edge of `dt`'s convex hull nearest to
/// it, when that edge is within `eps` (linear along the edge).
pub(super) fn near_hull_edge(dt: &Dt, zs: &[f64], x: f64, y: f64, eps: f64) -> Option<f64> {
    let mut best: Option<(f64, f64)> = None;
    for e in dt.convex_hull() {
        let [a, b] = e.vertices();
        let (pa, pb) = (a.position(), b.position());
        let (dx, dy) = (pb.x - pa.x, pb.y - pa.y);
        let l2 = dx * dx + dy * dy;
        if l2 == 0.0 {
            continue;
        }
        let t = (((x - pa.x) * dx + (y - pa.y) * dy) / l2).clamp(0.0, 1.0);
        let (qx, qy) = (pa.x + t * dx, pa.y + t * dy);
        let d = ((x - qx).powi(2) + (y - qy).powi(2)).sqrt();
        if d <= eps && best.is_none_or(|(bd, _)| d < bd) {
            let (za, zb) = (zs[a.fix().index()], zs[b.fix().index()]);
            best = Some((d, za + t * (zb - za)));
        }
    }
    best.map(|(_, z)| z)
}

/// The samples of a build with breaklines, their network and each
/// segment's profile ([`with_breaklines`]).
pub(super) type WithBreaklines = (Vec<[f64; 3]>, Network, Vec<Vec<[f64; 3]>>);

/// The breaklines as a network ([`crate::tin::breaklines::network`]), the
/// samples of a build with them (those not on a line, the network's
/// vertices and the soft segments' profiles, prepared
/// ([`prepare_samples`])) and each segment's profile
/// ([`crate::tin::breaklines::profile`]; empty for a hard one).
pub(super) fn with_breaklines(
    pts: Vec<[f64; 3]>,
    lines: &[Breakline],
    boundaries: &[&Area],
    tol: f64,
    reference: Option<&dyn Reference>,
    seams: Option<&SeamLines<'_>>,
    interrupt: &mut Interrupt<'_>,
) -> Result<WithBreaklines, TinError> {
    let hull: Vec<[f64; 3]> = convex_hull(&pts).into_iter().map(|k| pts[k]).collect();
    if hull.len() < 3 {
        return Err(TinError::Degenerate(
            "all samples are collinear: a tin needs at least 3 non-collinear samples".into(),
        ));
    }
    // the parts of the lines outside the samples' extent are cut off
    crate::tin::breaklines::validate(lines)?;
    // the boundary's rings: soft lines (heights from the samples), first,
    // so that where a point of a line falls within a millimetre of one of
    // theirs (the network snaps them together, keeping the first) the
    // domain keeps its own (a soft line cut at the hull beside a ring's
    // cut took the ring's corner with it, 1.4e-4 pixel across: the domain
    // fell short by that sliver, harness seed 4000301)
    let mut all: Vec<Breakline> = Vec::new();
    for area in boundaries {
        all.extend(area.rings.iter().map(|r| Breakline {
            pts: r.iter().map(|p| [p[0], p[1], 0.0]).collect(),
            hard: false,
        }));
    }
    all.extend_from_slice(lines);
    let lines = clip_to_hull(&all, &hull);
    let grid = SampleGrid::new(pts, 1.0);
    // heights along soft lines: the reference's where it has them (the
    // samples' whole Delaunay triangulation), else the samples around
    let height = |x: f64, y: f64| {
        seams
            .and_then(|s| (s.height)(x, y))
            .or_else(|| reference.and_then(|r| r.height_at(x, y)))
            .or_else(|| sample_height(&grid, x, y))
    };
    let net = network(&lines, tol, &height, interrupt)?;
    drop(lines);
    for v in &net.verts {
        if (0..hull.len())
            .any(|k| orient2d(c2(&hull[k]), c2(&hull[(k + 1) % hull.len()]), c2(v)) < 0.0)
        {
            return Err(TinError::Degenerate(format!(
                "internal: breakline point ({} {}) outside the samples' extent after clipping",
                v[0], v[1]
            )));
        }
    }
    let (mut dropped, on_segment) = samples_on_segments(
        &grid,
        &net,
        reference.is_some() || seams.is_some(),
        interrupt,
    )?;
    let profiles = soft_profiles(
        &net,
        grid.cell_area().sqrt(),
        &height,
        reference,
        seams,
        on_segment,
        interrupt,
    )?;
    // the samples outside the boundary: no vertex of the domain
    for area in boundaries {
        for (k, p) in grid.pts.iter().enumerate() {
            if k % 65536 == 0 {
                interrupt()?;
            }
            if area.locate([p[0], p[1]]) == Where::Outside {
                dropped[k] = true;
            }
        }
    }
    let mut kept: Vec<[f64; 3]> = grid
        .pts
        .iter()
        .zip(&dropped)
        .filter(|(_, d)| !**d)
        .map(|(p, _)| *p)
        .collect();
    drop(grid);
    kept.extend_from_slice(&net.verts);
    kept.extend(profiles.iter().flatten());
    Ok((prepare_samples(kept)?, net, profiles))
}

/// Points along one segment of the network, in order.
type Profile = Vec<[f64; 3]>;

/// The samples of `grid` on a segment of the network up to rounding
/// ([`drops_sample`]): flagged as dropped (the line stands for them), and,
/// for a soft segment when `keep_on_soft` (a build with a reference), kept
/// per segment as points of its profile with their own heights.
fn samples_on_segments(
    grid: &SampleGrid,
    net: &Network,
    keep_on_soft: bool,
    interrupt: &mut Interrupt<'_>,
) -> Result<(Vec<bool>, Vec<Profile>), TinError> {
    let mut dropped = vec![false; grid.len()];
    // with a reference, a soft segment's samples (dropped: the profile
    // stands for them) are points of its profile, their own heights
    let mut on_segment: Vec<Vec<[f64; 3]>> = vec![Vec::new(); net.segs.len()];
    for (k, s) in net.segs.iter().enumerate() {
        if k % 256 == 0 {
            interrupt()?;
        }
        let (a, b) = (net.verts[s[0] as usize], net.verts[s[1] as usize]);
        let keep_on = keep_on_soft && !net.hard[k];
        let m = 1e-9 * (a[0].abs().max(a[1].abs()).max(b[0].abs()).max(b[1].abs()) + 1.0);
        grid.for_each_in_box(
            a[0].min(b[0]) - m,
            a[1].min(b[1]) - m,
            a[0].max(b[0]) + m,
            a[1].max(b[1]) + m,
            |i, p| {
                if drops_sample(&a, &b, p) {
                    if keep_on && p[..2] != a[..2] && p[..2] != b[..2] {
                        on_segment[k].push(*p);
                    }
                    dropped[i] = true;
                }
            },
        );
    }
    Ok((dropped, on_segment))
}

/// Each segment's profile: empty for a hard one; for a soft one points
/// about `step` apart with `height`'s heights ([`profile`]), with the
/// `reference`'s grid-line crossings and the samples `on_segment` it
/// dropped ([`with_crossings`]) when there is a reference.
fn soft_profiles(
    net: &Network,
    step: f64,
    height: &dyn Fn(f64, f64) -> Option<f64>,
    reference: Option<&dyn Reference>,
    seams: Option<&SeamLines<'_>>,
    mut on_segment: Vec<Vec<[f64; 3]>>,
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<Vec<[f64; 3]>>, TinError> {
    let mut profiles = Vec::with_capacity(net.segs.len());
    let mut total = 0usize;
    for (k, s) in net.segs.iter().enumerate() {
        interrupt()?;
        let (a, b) = (net.verts[s[0] as usize], net.verts[s[1] as usize]);
        let prof = if net.hard[k] {
            Vec::new()
        } else if seams.is_some_and(|sl| sl.holds(&a, &b)) {
            // a tile's seam: its samples alone, as the tile beside it
            // sees them (on an axis, so exactly on it)
            let mut on = std::mem::take(&mut on_segment[k]);
            let along = |p: &[f64; 3]| (p[0] - a[0]).abs() + (p[1] - a[1]).abs();
            on.sort_by(|p, q| along(p).total_cmp(&along(q)));
            on
        } else {
            let even = profile(&a, &b, step, height, interrupt)?;
            match reference {
                Some(r) => {
                    with_crossings(&a, &b, even, r, step, std::mem::take(&mut on_segment[k]))
                }
                None => even,
            }
        };
        total += prof.len();
        if total > crate::tin::breaklines::MAX_PROFILE_POINTS {
            return Err(TinError::TooLarge(format!(
                "soft breaklines hold more than {} sample spacings",
                crate::tin::breaklines::MAX_PROFILE_POINTS
            )));
        }
        profiles.push(prof);
    }
    Ok(profiles)
}

/// A soft segment's profile `even` (points about `step` apart from `a` to
/// `b`, heights from the samples) with the segment's crossings of the
/// `reference`'s grid segments (heights the reference's) and the samples
/// `on` it (within rounding, their own heights) among them, in order; an
/// even point within a thousandth of `step` of one of those left out. The
/// profile's vertices, chosen level by level as a seam's are
/// ([`plan_side`](crate::tin::sides::plan_side)), then hold the tolerance at every crossing of the line
/// and every pixel on it: a boundary's ring on the samples' hull (no
/// parent beside it measures it) as well as inside, and a line along a
/// pixel row.
pub(super) fn with_crossings(
    a: &[f64; 3],
    b: &[f64; 3],
    even: Vec<[f64; 3]>,
    reference: &dyn Reference,
    step: f64,
    on: Vec<[f64; 3]>,
) -> Vec<[f64; 3]> {
    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
    if len.is_nan() || len <= 0.0 {
        return even;
    }
    let along =
        |p: &[f64; 3]| ((p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1])) / len;
    let mut cross: Vec<(f64, [f64; 3])> = on.into_iter().map(|p| (along(&p), p)).collect();
    reference.for_each_crossing(a, b, &mut |c| cross.push((c.t * len, c.p)));
    if cross.is_empty() {
        return even;
    }
    cross.sort_by(|u, v| u.0.total_cmp(&v.0));
    let near = step * 1e-3;
    let mut out: Vec<(f64, [f64; 3])> = even
        .into_iter()
        .map(|p| (along(&p), p))
        .filter(|(d, _)| {
            let k = cross.partition_point(|c| c.0 < *d);
            let gap = |i: usize| cross.get(i).map_or(f64::INFINITY, |c| (c.0 - d).abs());
            gap(k).min(if k > 0 { gap(k - 1) } else { f64::INFINITY }) > near
        })
        .collect();
    out.extend(cross);
    out.sort_by(|u, v| u.0.total_cmp(&v.0));
    out.into_iter().map(|(_, p)| p).collect()
}

/// Level 0's constraint edges: the network's vertices inserted (they are
/// samples of `b`'s grid), then each segment with a profile (`sides[k]`:
/// its samples from end to end, or empty) split at the profile samples
/// [`choose_border`] picks at `tol` (a tile's `seam`: [`seam_split`])
/// after the `kept`
/// positions (a tile's seam samples, [`Border`]) (inserted before the
/// constraints, so
/// each piece is an edge of its own: they lie on the segment only up to
/// rounding), and every piece added as a constraint.
pub(super) fn add_network<S: Samples>(
    b: &mut Builder<'_, S, Cdt>,
    net: &Network,
    sides: &[Vec<usize>],
    seam: &[bool],
    tol: f64,
    kept: &[[f64; 2]],
    find: &dyn Fn(f64, f64) -> Option<usize>,
) -> Result<(), TinError> {
    let kept: rustc_hash::FxHashSet<(u64, u64)> = kept
        .iter()
        .map(|p| (p[0].to_bits(), p[1].to_bits()))
        .collect();
    let mut ends = Vec::with_capacity(net.verts.len());
    let mut handle: rustc_hash::FxHashMap<usize, FixedVertexHandle> = Default::default();
    let mut hint = None;
    for v in &net.verts {
        let i = find(v[0], v[1])
            .ok_or_else(|| TinError::Degenerate("internal: a breakline vertex was lost".into()))?;
        let h = b.insert_sample(i, hint)?;
        hint = Some(h);
        handle.insert(i, h);
        ends.push(i);
    }
    for (k, s) in net.segs.iter().enumerate() {
        let (p, q) = (ends[s[0] as usize], ends[s[1] as usize]);
        if p == q {
            continue;
        }
        let chain: Vec<usize> = match sides.get(k) {
            Some(side) if side.len() > 2 => {
                let grid = b.grid;
                let mut new = Vec::new();
                let mut chosen: Vec<bool> = (0..side.len())
                    .map(|j| {
                        let p = grid.point(side[j]);
                        let keep = kept.contains(&(p[0].to_bits(), p[1].to_bits()));
                        if keep && j > 0 && j + 1 < side.len() {
                            new.push(side[j]);
                        }
                        j == 0 || j + 1 == side.len() || keep
                    })
                    .collect();
                let split = seam_split(tol, seam.get(k).copied().unwrap_or(false));
                choose_border(&|i| grid.point(i), side, &mut chosen, split, &mut new);
                for i in new {
                    let h = b.insert_sample(i, handle.get(&p).copied())?;
                    handle.insert(i, h);
                }
                side.iter()
                    .zip(&chosen)
                    .filter(|(_, c)| **c)
                    .map(|(&i, _)| i)
                    .collect()
            }
            _ => vec![p, q],
        };
        for w in chain.windows(2) {
            let (Some(&hp), Some(&hq)) = (handle.get(&w[0]), handle.get(&w[1])) else {
                return Err(TinError::Degenerate(
                    "internal: a breakline vertex was not inserted".into(),
                ));
            };
            if b.dt.try_add_constraint(hp, hq).is_empty() {
                let a = b.grid.point(w[0]);
                return Err(TinError::InvalidParameter(format!(
                    "breakline segment from ({} {}) cannot be an edge: it crosses another within rounding; snap the breaklines (ST_Snap, ST_Node) first",
                    a[0], a[1]
                )));
            }
        }
    }
    Ok(())
}
