//! The lines as one planar straight-line graph ([`network`]), and what a
//! build asks of single lines: their validity, hard segments, samples
//! they drop and soft profiles.

use crate::geom::{crossing, is_sliver, orient, param_along, within_roundings, z_along};
use crate::interrupt::Interrupt;
use crate::tin::TinError;
use rustc_hash::FxHashMap;

/// One breakline: its points in order (z ignored for a soft one).
#[derive(Clone, Debug)]
pub struct Breakline {
    pub pts: Vec<[f64; 3]>,
    pub hard: bool,
}

/// The breaklines as one planar graph.
#[derive(Clone, Debug, Default)]
pub struct Network {
    /// x, y and the height of every vertex
    pub verts: Vec<[f64; 3]>,
    /// segments by vertex index, no two crossing or overlapping
    pub segs: Vec<[u32; 2]>,
    /// whether each segment is part of a hard breakline
    pub hard: Vec<bool>,
}

/// Most vertices of all breaklines of one build.
pub const MAX_BREAKLINE_VERTICES: usize = 1_000_000;

/// Position of `p` along segment `a`–`b`, 0 at `a`, 1 at `b`.
fn param(a: &[f64; 3], b: &[f64; 3], p: &[f64; 3]) -> f64 {
    param_along(a, b, [p[0], p[1]])
}

/// Whether `p` lies on the open segment `a`–`b` up to rounding (not at
/// either end).
fn on_open_segment(a: &[f64; 3], b: &[f64; 3], p: &[f64; 3]) -> bool {
    if p[..2] == a[..2] || p[..2] == b[..2] || !is_sliver(a, b, p) {
        return false;
    }
    let t = param(a, b, p);
    t > 0.0 && t < 1.0
}

/// Whether a sample at `p` is left out of a build with segment `a`–`b`:
/// on the closed segment up to rounding. A hard line's heights stand for
/// it; along a soft line, the line's [`profile`] does.
pub fn drops_sample(a: &[f64; 3], b: &[f64; 3], p: &[f64; 3]) -> bool {
    if p[..2] == a[..2] || p[..2] == b[..2] {
        return true;
    }
    if !is_sliver(a, b, p) {
        return false;
    }
    let t = param(a, b, p);
    let slack = 1e-9;
    (-slack..=1.0 + slack).contains(&t)
}

/// The segments of the hard lines among `lines`, in x and y: where a
/// build's reference leaves the surface to the lines' own heights
/// ([`crate::tin::surface::GridReference::cut_by`],
/// [`crate::tin::delaunay_ref::DelaunayReference::cut_by`]).
///
/// ```
/// use tinmerge_core::tin::breaklines::{hard_segments, Breakline};
/// let lines = [
///     Breakline { pts: vec![[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 2.0]], hard: true },
///     Breakline { pts: vec![[5.0, 5.0, 0.0], [6.0, 5.0, 0.0]], hard: false },
/// ];
/// assert_eq!(hard_segments(&lines), [([0.0, 0.0], [1.0, 0.0]), ([1.0, 0.0], [1.0, 1.0])]);
/// ```
pub fn hard_segments(lines: &[Breakline]) -> Vec<([f64; 2], [f64; 2])> {
    lines
        .iter()
        .filter(|l| l.hard)
        .flat_map(|l| {
            l.pts
                .windows(2)
                .map(|w| ([w[0][0], w[0][1]], [w[1][0], w[1][1]]))
        })
        .collect()
}

/// Two points of the lines closer than this times the magnitude of their
/// coordinates (in x and in y) are one point: about 2e-10, a millimetre at
/// UTM northings, far below any survey and far above the rounding of a
/// computed crossing or cut.
pub(super) const SNAP: f64 = 1e6 * f64::EPSILON;

/// Most profile points of all soft breaklines of one build.
pub const MAX_PROFILE_POINTS: usize = 4_000_000;

/// The profile of soft segment `a`–`b`: points along it (its ends left
/// out) about `step` apart, each with the samples' height there
/// (`soft_z`). The build holds them as the segment's own samples and
/// chooses among them level by level (a Douglas-Peucker split of the
/// profile, as for a tile's seam), so the surface along a soft breakline
/// follows the samples within each level's tolerance instead of running
/// straight between the line's own vertices.
///
/// ```
/// use tinmerge_core::tin::breaklines::profile;
/// let p = profile(&[0.0, 0.0, 0.0], &[10.0, 0.0, 0.0], 2.5, &|x, _| Some(x * x), &mut || Ok(()))
///     .unwrap();
/// assert_eq!(p.len(), 3);
/// assert_eq!(p[1], [5.0, 0.0, 25.0]);
/// ```
pub fn profile(
    a: &[f64; 3],
    b: &[f64; 3],
    step: f64,
    soft_z: &dyn Fn(f64, f64) -> Option<f64>,
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<[f64; 3]>, TinError> {
    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
    let n = (len / step).floor();
    if !(n.is_finite() && n >= 2.0) {
        return Ok(Vec::new());
    }
    if n > MAX_PROFILE_POINTS as f64 {
        return Err(TinError::TooLarge(format!(
            "a soft breakline segment of length {len} holds more than {MAX_PROFILE_POINTS} sample spacings"
        )));
    }
    let n = n as usize;
    let mut out = Vec::with_capacity(n - 1);
    for k in 1..n {
        if k % 4096 == 0 {
            interrupt()?;
        }
        let t = k as f64 / n as f64;
        let (x, y) = (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]));
        let z = soft_z(x, y).ok_or_else(|| {
            TinError::InvalidParameter(format!(
                "soft breakline point ({x} {y}) is outside the samples: a soft breakline takes its heights from the samples around it"
            ))
        })?;
        out.push([x, y, z]);
    }
    Ok(out)
}

/// A coarse bucketing of segments by their boxes, so each pair of nearby
/// segments (or a point and the segments near it) is found without looking
/// at all of them.
struct Buckets {
    x0: f64,
    y0: f64,
    cell: f64,
    nx: usize,
    ny: usize,
    cells: Vec<Vec<u32>>,
}

impl Buckets {
    fn new(verts: &[[f64; 3]], segs: &[[u32; 2]]) -> Buckets {
        let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
        for v in verts {
            x0 = x0.min(v[0]);
            y0 = y0.min(v[1]);
            x1 = x1.max(v[0]);
            y1 = y1.max(v[1]);
        }
        let n = (segs.len() as f64).sqrt().ceil().clamp(1.0, 1024.0);
        let cell = ((x1 - x0).max(y1 - y0) / n).max(f64::MIN_POSITIVE) * (1.0 + 1e-9);
        let nx = (((x1 - x0) / cell) as usize + 1).min(1024);
        let ny = (((y1 - y0) / cell) as usize + 1).min(1024);
        let mut b = Buckets {
            x0,
            y0,
            cell,
            nx,
            ny,
            cells: vec![Vec::new(); nx * ny],
        };
        for (k, s) in segs.iter().enumerate() {
            let (p, q) = (verts[s[0] as usize], verts[s[1] as usize]);
            let (c0, r0) = b.cell_of(p[0].min(q[0]), p[1].min(q[1]));
            let (c1, r1) = b.cell_of(p[0].max(q[0]), p[1].max(q[1]));
            for r in r0..=r1 {
                for c in c0..=c1 {
                    b.cells[r * nx + c].push(k as u32);
                }
            }
        }
        b
    }

    /// The cell of a point, one cell of margin either way (rounding).
    fn cell_of(&self, x: f64, y: f64) -> (usize, usize) {
        let c = ((x - self.x0) / self.cell).floor().max(0.0) as usize;
        let r = ((y - self.y0) / self.cell).floor().max(0.0) as usize;
        (c.min(self.nx - 1), r.min(self.ny - 1))
    }

    /// Segments whose cells meet the box around `p` and `q`, each once.
    fn near(&self, p: &[f64; 3], q: &[f64; 3], out: &mut Vec<u32>) {
        out.clear();
        let (c0, r0) = self.cell_of(p[0].min(q[0]), p[1].min(q[1]));
        let (c1, r1) = self.cell_of(p[0].max(q[0]), p[1].max(q[1]));
        for r in r0.saturating_sub(1)..=(r1 + 1).min(self.ny - 1) {
            for c in c0.saturating_sub(1)..=(c1 + 1).min(self.nx - 1) {
                out.extend_from_slice(&self.cells[r * self.nx + c]);
            }
        }
        out.sort_unstable();
        out.dedup();
    }
}

/// Height of a point along a hard segment.
fn along(a: &[f64; 3], b: &[f64; 3], p: &[f64; 3]) -> f64 {
    z_along(a, b, [p[0], p[1]])
}

/// Vertices of the network under construction: equal (x, y), or within
/// `snap` of each other, merged; a
/// hard height, where one is known, per vertex.
struct Verts {
    pts: Vec<[f64; 3]>,
    hard_z: Vec<Option<f64>>,
    index: FxHashMap<(u64, u64), u32>,
    tol: f64,
    /// Two points closer than this (in x and in y) are one vertex: about
    /// 2e-10 of the largest coordinate, a millimetre at UTM northings. The
    /// same crossing computed from two lines that overlap up to rounding
    /// (a hard and a soft line along one diagonal of a geographic grid)
    /// comes out a few ulps apart; kept apart, the two would leave a crack
    /// between the triangles on either side.
    snap: f64,
    /// Vertices by cell of side `2 * snap`.
    cells: FxHashMap<(i64, i64), Vec<u32>>,
}

impl Verts {
    fn new(lines: &[Breakline], tol: f64) -> Verts {
        let m = lines
            .iter()
            .flat_map(|l| l.pts.iter())
            .map(|p| p[0].abs().max(p[1].abs()))
            .fold(1.0f64, f64::max);
        Verts {
            pts: Vec::new(),
            hard_z: Vec::new(),
            index: FxHashMap::default(),
            tol,
            snap: SNAP * m,
            cells: FxHashMap::default(),
        }
    }

    fn cell(&self, x: f64, y: f64) -> (i64, i64) {
        let c = 2.0 * self.snap;
        ((x / c).floor() as i64, (y / c).floor() as i64)
    }

    fn add(&mut self, x: f64, y: f64, z: Option<f64>) -> Result<u32, TinError> {
        self.add_where(x, y, z, &|_| true)
    }

    /// [`Verts::add`], merged only with a vertex within `snap` that `ok`
    /// accepts.
    fn add_where(
        &mut self,
        x: f64,
        y: f64,
        z: Option<f64>,
        ok: &dyn Fn(&[f64; 3]) -> bool,
    ) -> Result<u32, TinError> {
        let key = (x.to_bits(), y.to_bits());
        if let Some(&k) = self.index.get(&key) {
            self.set_z(k, z)?;
            return Ok(k);
        }
        let (cx, cy) = self.cell(x, y);
        let mut near = None;
        for i in cx - 1..=cx + 1 {
            for j in cy - 1..=cy + 1 {
                for &k in self.cells.get(&(i, j)).into_iter().flatten() {
                    let p = self.pts[k as usize];
                    if (p[0] - x).abs() <= self.snap && (p[1] - y).abs() <= self.snap && ok(&p) {
                        near = Some(near.map_or(k, |n: u32| n.min(k)));
                    }
                }
            }
        }
        if let Some(k) = near {
            self.index.insert(key, k);
            self.set_z(k, z)?;
            return Ok(k);
        }
        if self.pts.len() >= MAX_BREAKLINE_VERTICES {
            return Err(TinError::TooLarge(format!(
                "breaklines have more than {MAX_BREAKLINE_VERTICES} vertices"
            )));
        }
        let k = self.pts.len() as u32;
        self.index.insert(key, k);
        self.cells.entry((cx, cy)).or_default().push(k);
        self.pts.push([x, y, z.unwrap_or(f64::NAN)]);
        self.hard_z.push(z);
        Ok(k)
    }

    /// Give vertex `k` the hard height `z`: an ERROR where it already has
    /// another one (two hard breaklines meeting at different heights: a
    /// bridge, which a surface cannot hold).
    fn set_z(&mut self, k: u32, z: Option<f64>) -> Result<(), TinError> {
        let Some(z) = z else { return Ok(()) };
        match self.hard_z[k as usize] {
            None => {
                self.hard_z[k as usize] = Some(z);
                self.pts[k as usize][2] = z;
            }
            Some(old) if (old - z).abs() > self.tol => {
                let p = self.pts[k as usize];
                return Err(TinError::InvalidParameter(format!(
                    "hard breaklines meet at ({} {}) at different heights, {old} and {z}: a surface has one height there (a bridge over a road cannot be both; leave one out or make it soft)",
                    p[0], p[1]
                )));
            }
            Some(_) => {}
        }
        Ok(())
    }
}

/// Every point of every line finite and within the coordinate range, a
/// hard line's heights finite, and at least two distinct points a line.
pub fn validate(lines: &[Breakline]) -> Result<(), TinError> {
    for (li, line) in lines.iter().enumerate() {
        for p in &line.pts {
            if !(p[0].is_finite() && p[1].is_finite()) {
                return Err(TinError::InvalidParameter(format!(
                    "breakline {} has a point that is not finite: ({} {})",
                    li + 1,
                    p[0],
                    p[1]
                )));
            }
            crate::tin::check_xy("a breakline point", p[0], p[1])?;
            if line.hard && !p[2].is_finite() {
                return Err(TinError::InvalidParameter(format!(
                    "hard breakline {} has no finite Z at ({} {}): hard breaklines carry their heights (LINESTRING Z); pass lines without heights as soft_breaklines",
                    li + 1,
                    p[0],
                    p[1]
                )));
            }
        }
        if line.pts.iter().all(|p| p[..2] == line.pts[0][..2]) {
            return Err(TinError::InvalidParameter(format!(
                "breakline {} has fewer than two distinct points",
                li + 1
            )));
        }
    }
    Ok(())
}

/// The breaklines as one planar graph (see the module docs). `tol`: the
/// finest level's tolerance, how far apart two hard heights may be where
/// lines meet; `soft_z(x, y)`: the samples' height at a point (None where
/// the samples say nothing, an ERROR then). In phases: the lines' points
/// and segments ([`segments`]), the cuts at crossings ([`cut_at_crossings`])
/// and at vertices on segments ([`cut_at_vertices`]), the segments split
/// at their cuts ([`split`]), a check that nothing left crosses
/// ([`check_uncrossed`]), the heights ([`heights`]).
pub fn network(
    lines: &[Breakline],
    tol: f64,
    soft_z: &dyn Fn(f64, f64) -> Option<f64>,
    interrupt: &mut Interrupt<'_>,
) -> Result<Network, TinError> {
    validate(lines)?;
    let mut v = Verts::new(lines, tol);
    let segs = segments(lines, &mut v, interrupt)?;
    if segs.is_empty() {
        return Ok(Network::default());
    }
    let plain: Vec<[u32; 2]> = segs.iter().map(|s| s.0).collect();
    let buckets = Buckets::new(&v.pts, &plain);
    let mut cuts = cut_at_crossings(&segs, &buckets, &mut v, interrupt)?;
    cut_at_vertices(&segs, &buckets, &v, &mut cuts, interrupt)?;
    let out = split(&segs, &cuts, &mut v)?;
    check_uncrossed(&out, &v)?;
    let verts = heights(v, soft_z)?;
    Ok(Network {
        verts,
        segs: out.iter().map(|s| s.0).collect(),
        hard: out.iter().map(|s| s.1).collect(),
    })
}

/// A segment of the network by vertex ids, and whether it is hard.
type Seg = ([u32; 2], bool);

/// Every line's points as vertices of `v` and its segments between
/// distinct ones, in order.
fn segments(
    lines: &[Breakline],
    v: &mut Verts,
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<Seg>, TinError> {
    let mut segs: Vec<Seg> = Vec::new();
    for (li, line) in lines.iter().enumerate() {
        interrupt()?;
        let mut prev: Option<u32> = None;
        let before = segs.len();
        for p in &line.pts {
            let k = v.add(p[0], p[1], line.hard.then_some(p[2]))?;
            if let Some(j) = prev
                && j != k
            {
                segs.push(([j, k], line.hard));
            }
            prev = Some(k);
        }
        if segs.len() == before {
            return Err(TinError::InvalidParameter(format!(
                "breakline {} has fewer than two distinct points",
                li + 1
            )));
        }
    }
    Ok(segs)
}

/// How many roundings ([`crate::geom::orient_slack`]) off both segments
/// a vertex may be for a crossing of theirs within `snap` of it to be
/// that vertex.
const MERGE: f64 = 256.0;

/// Crossings: a new vertex on both segments (each segment's cuts).
fn cut_at_crossings(
    segs: &[Seg],
    buckets: &Buckets,
    v: &mut Verts,
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<Vec<u32>>, TinError> {
    let mut near = Vec::new();
    let mut cuts: Vec<Vec<u32>> = vec![Vec::new(); segs.len()];
    for i in 0..segs.len() {
        if i % 1024 == 0 {
            interrupt()?;
        }
        let [a, b] = segs[i].0.map(|k| v.pts[k as usize]);
        buckets.near(&a, &b, &mut near);
        for &j in near.iter().filter(|&&j| j as usize > i) {
            let j = j as usize;
            let [c, d] = segs[j].0.map(|k| v.pts[k as usize]);
            // a proper crossing: each segment's ends strictly on either side
            // of the other, none of them on it up to rounding
            let (o1, o2) = (orient(&a, &b, &c), orient(&a, &b, &d));
            let (o3, o4) = (orient(&c, &d, &a), orient(&c, &d, &b));
            if !(o1 * o2 < 0.0 && o3 * o4 < 0.0) {
                continue;
            }
            if [c, d].iter().any(|p| is_sliver(&a, &b, p))
                || [a, b].iter().any(|p| is_sliver(&c, &d, p))
            {
                continue;
            }
            // canonical order of the two segments, so the point is the
            // same whichever is asked first
            let x = crossing([a[0], a[1]], [b[0], b[1]], [c[0], c[1]], [d[0], d[1]]);
            let p = [x[0], x[1], 0.0];
            let zi = segs[i].1.then(|| along(&a, &b, &p));
            let zj = segs[j].1.then(|| along(&c, &d, &p));
            // the crossing is merged with a vertex within `snap` of it
            // only where that vertex is on both segments up to rounding
            // (the same crossing computed from
            // lines that overlap up to rounding): a line's end 1.3 mm
            // beyond a boundary ring (cut at the samples' hull, which runs
            // outside the valid pixels' squares there) is within `snap`
            // of the crossing at 8.9e6 m northings, and the ring bent
            // through it took that sliver of nodata into the domain
            // (harness seed 151551)
            let on_both = |q: &[f64; 3]| {
                within_roundings(&a, &b, q, MERGE) && within_roundings(&c, &d, q, MERGE)
            };
            let k = v.add_where(x[0], x[1], zi, &on_both)?;
            v.set_z(k, zj)?;
            cuts[i].push(k);
            cuts[j].push(k);
        }
    }
    Ok(cuts)
}

/// Every vertex on a segment (up to rounding, strictly inside) splits it:
/// each vertex against the segments bucketed near it (crossings lie on
/// their segments, so inside the buckets' extent).
fn cut_at_vertices(
    segs: &[Seg],
    buckets: &Buckets,
    v: &Verts,
    cuts: &mut [Vec<u32>],
    interrupt: &mut Interrupt<'_>,
) -> Result<(), TinError> {
    let mut near = Vec::new();
    for (k, p) in v.pts.iter().enumerate() {
        if k % 1024 == 0 {
            interrupt()?;
        }
        buckets.near(p, p, &mut near);
        for &i in &near {
            let i = i as usize;
            let [a, b] = segs[i].0.map(|k| v.pts[k as usize]);
            if on_open_segment(&a, &b, p) && !cuts[i].contains(&(k as u32)) {
                cuts[i].push(k as u32);
            }
        }
    }
    Ok(())
}

/// The segments split at their cuts (a hard segment's cut vertices get
/// its heights), each piece once; a piece of a hard and of a soft line is
/// hard.
fn split(segs: &[Seg], cuts: &[Vec<u32>], v: &mut Verts) -> Result<Vec<Seg>, TinError> {
    let mut out: Vec<Seg> = Vec::with_capacity(segs.len());
    for (i, (s, hard)) in segs.iter().enumerate() {
        let [a, b] = s.map(|k| v.pts[k as usize]);
        let mut on: Vec<(f64, u32)> = cuts[i]
            .iter()
            .map(|&k| (param(&a, &b, &v.pts[k as usize]), k))
            .collect();
        on.sort_by(|x, y| x.0.total_cmp(&y.0));
        let mut chain = vec![s[0]];
        chain.extend(on.iter().map(|&(_, k)| k));
        chain.push(s[1]);
        for &k in &chain[1..chain.len() - 1] {
            if *hard {
                let z = along(&a, &b, &v.pts[k as usize]);
                v.set_z(k, Some(z))?;
            }
        }
        for w in chain.windows(2) {
            if w[0] != w[1] {
                let e = if w[0] < w[1] {
                    [w[0], w[1]]
                } else {
                    [w[1], w[0]]
                };
                out.push((e, *hard));
            }
        }
    }
    out.sort_unstable();
    out.dedup_by(|later, first| {
        if later.0 == first.0 {
            first.1 |= later.1;
            true
        } else {
            false
        }
    });
    Ok(out)
}

/// What is left must not cross (it cannot, unless lines run within
/// rounding of each other without touching): an ERROR if it does.
fn check_uncrossed(out: &[Seg], v: &Verts) -> Result<(), TinError> {
    let plain: Vec<[u32; 2]> = out.iter().map(|s| s.0).collect();
    let buckets = Buckets::new(&v.pts, &plain);
    let mut near = Vec::new();
    for (i, s) in plain.iter().enumerate() {
        let [a, b] = s.map(|k| v.pts[k as usize]);
        buckets.near(&a, &b, &mut near);
        for &j in near.iter().filter(|&&j| j as usize > i) {
            let t = plain[j as usize];
            if t.contains(&s[0]) || t.contains(&s[1]) {
                continue;
            }
            let [c, d] = t.map(|k| v.pts[k as usize]);
            let touch = [c, d]
                .iter()
                .any(|p| is_sliver(&a, &b, p) && (0.0..=1.0).contains(&param(&a, &b, p)))
                || [a, b]
                    .iter()
                    .any(|p| is_sliver(&c, &d, p) && (0.0..=1.0).contains(&param(&c, &d, p)));
            let (o1, o2) = (orient(&a, &b, &c), orient(&a, &b, &d));
            let (o3, o4) = (orient(&c, &d, &a), orient(&c, &d, &b));
            if touch || (o1 * o2 < 0.0 && o3 * o4 < 0.0) {
                return Err(TinError::InvalidParameter(format!(
                    "breaklines run within rounding of each other near ({} {}) without meeting at a vertex; snap them (ST_Snap, ST_Node) first",
                    a[0], a[1]
                )));
            }
        }
    }
    Ok(())
}

/// The vertices' heights: hard where known, the samples' elsewhere.
fn heights(v: Verts, soft_z: &dyn Fn(f64, f64) -> Option<f64>) -> Result<Vec<[f64; 3]>, TinError> {
    let mut verts = v.pts;
    for (k, p) in verts.iter_mut().enumerate() {
        p[2] = match v.hard_z[k] {
            Some(z) => z,
            None => soft_z(p[0], p[1]).ok_or_else(|| {
                TinError::InvalidParameter(format!(
                    "soft breakline point ({} {}) is outside the samples: a soft breakline takes its heights from the samples around it",
                    p[0], p[1]
                ))
            })?,
        };
    }
    Ok(verts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tin::breaklines::clip_to_hull;

    fn net(lines: Vec<Breakline>) -> Result<Network, TinError> {
        network(&lines, 0.1, &|x, y| Some(x + y), &mut || Ok(()))
    }

    #[test]
    fn t_junction_splits_the_line_it_touches() {
        let n = net(vec![
            Breakline {
                pts: vec![[0.0, 0.0, 0.0], [10.0, 0.0, 10.0]],
                hard: true,
            },
            Breakline {
                pts: vec![[4.0, 0.0, f64::NAN], [4.0, 5.0, f64::NAN]],
                hard: false,
            },
        ])
        .unwrap();
        assert_eq!(n.segs.len(), 3);
        // the soft line's end on the hard line takes the hard height
        let k = n
            .verts
            .iter()
            .position(|p| p[0] == 4.0 && p[1] == 0.0)
            .unwrap();
        assert_eq!(n.verts[k][2], 4.0);
        // the other end: the samples' height
        let k = n
            .verts
            .iter()
            .position(|p| p[0] == 4.0 && p[1] == 5.0)
            .unwrap();
        assert_eq!(n.verts[k][2], 9.0);
    }

    #[test]
    fn a_line_ending_within_snap_beyond_a_ring_leaves_the_ring_straight() {
        // harness seed 151551: at 8.9e6 m northings `snap` is 2 mm; a hard
        // line cut at the samples' hull ends 1.3 mm beyond a footprint
        // ring's side. Its crossing with that side is a vertex of its own
        // on the side, not the line's end (which bent the ring through it)
        let y = 8921199.903360482f64;
        let ring = Breakline {
            pts: vec![
                [409010.0, y, f64::NAN],
                [409030.0, y, f64::NAN],
                [409030.0, y + 20.0, f64::NAN],
                [409010.0, y + 20.0, f64::NAN],
                [409010.0, y, f64::NAN],
            ],
            hard: false,
        };
        let end = [409017.5144042035, y - 1.334e-3, 541.0];
        let line = Breakline {
            pts: vec![[409007.0, y + 10.0, 500.0], end],
            hard: true,
        };
        let n = net(vec![ring, line]).unwrap();
        // every vertex on the ring's bottom side is on its line exactly
        // or is the line's end, which is apart from it
        let on_side: Vec<_> = n
            .verts
            .iter()
            .filter(|p| (p[1] - y).abs() < 0.01 && p[0] > 409010.0 && p[0] < 409030.0)
            .collect();
        assert_eq!(on_side.len(), 2, "{on_side:?}");
        assert!(on_side.iter().any(|p| p[1] == y), "{on_side:?}");
        assert!(
            on_side.iter().any(|p| p[0] == end[0] && p[1] == end[1]),
            "{on_side:?}"
        );
        // and the ring's side runs through the crossing, not the line's end
        let k = |q: &[f64; 3]| {
            let at = n.verts.iter().position(|p| p[0] == q[0] && p[1] == q[1]);
            at.expect("a vertex there") as u32
        };
        let cross = **on_side.iter().find(|p| p[1] == y).unwrap();
        let (kc, ke) = (k(&cross), k(&end));
        let (kl, kr) = (k(&[409010.0, y, 0.0]), k(&[409030.0, y, 0.0]));
        let has = |a: u32, b: u32| n.segs.contains(&[a.min(b), a.max(b)]);
        assert!(has(kl, kc) && has(kc, kr), "{:?}", n.segs);
        assert!(has(kc, ke), "{:?}", n.segs);
    }

    #[test]
    fn vertices_a_rounding_inside_the_hull_give_no_sliver_of_a_piece() {
        // gdal_contour's contour 623 of the bundled DEM: it comes in from
        // outside the pixel centres' hull to a vertex one ulp inside its
        // south side, goes round, and leaves the same way at the same y.
        // Each cut a hair before such a vertex made a piece of a few ulps
        // that every segment at that y lay "on" up to rounding: an ERROR.
        let y = 4036601.162225269f64;
        let up = f64::from_bits(y.to_bits() + 1);
        let hull = [
            [731000.0, y, 0.0],
            [733000.0, y, 0.0],
            [733000.0, y + 2000.0, 0.0],
            [731000.0, y + 2000.0, 0.0],
        ];
        let line = Breakline {
            pts: vec![
                [732661.582519865, y - 45.0, 500.0],
                [732661.582519865, up, 500.0],
                [732604.219465799, y + 47.6, 500.0],
                [732498.954976564, up, 500.0],
                [732498.954976564, y - 45.0, 500.0],
            ],
            hard: true,
        };
        let parts = clip_to_hull(&[line], &hull);
        assert_eq!(parts.len(), 1, "{parts:?}");
        assert_eq!(parts[0].pts.len(), 3, "{parts:?}");
        assert!(network(&parts, 0.1, &|_, _| Some(0.0), &mut || Ok(())).is_ok());
    }

    #[test]
    fn bridge_is_an_error() {
        let e = net(vec![
            Breakline {
                pts: vec![[0.0, 0.0, 0.0], [10.0, 10.0, 0.0]],
                hard: true,
            },
            Breakline {
                pts: vec![[0.0, 10.0, 5.0], [10.0, 0.0, 5.0]],
                hard: true,
            },
        ]);
        assert!(e.unwrap_err().to_string().contains("different heights"));
    }

    #[test]
    fn overlapping_lines_share_their_segments() {
        let n = net(vec![
            Breakline {
                pts: vec![[0.0, 0.0, 0.0], [10.0, 0.0, 0.0]],
                hard: true,
            },
            Breakline {
                pts: vec![[5.0, 0.0, f64::NAN], [15.0, 0.0, f64::NAN]],
                hard: false,
            },
        ])
        .unwrap();
        // 0-5 hard, 5-10 both (hard), 10-15 soft
        assert_eq!(n.segs.len(), 3);
        assert_eq!(n.hard.iter().filter(|&&h| h).count(), 2);
    }

    #[test]
    fn hard_line_without_z_is_an_error() {
        let e = net(vec![Breakline {
            pts: vec![[0.0, 0.0, f64::NAN], [1.0, 0.0, 1.0]],
            hard: true,
        }]);
        assert!(e.unwrap_err().to_string().contains("no finite Z"));
    }
}
