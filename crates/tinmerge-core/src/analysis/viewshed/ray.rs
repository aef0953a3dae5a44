//! The rays of a viewshed: each walked once through the hierarchy, coarse
//! triangles that cannot rise into view skipped whole ([`Bounds`]), the
//! running horizon kept as the walk's stretches ([`Horizon`]) or one
//! cell's own ray checked against its target ([`Check`]); the last stretch
//! before a cell walked back through the level's own triangles
//! ([`clear_back`]).

use crate::error::TinError;
use crate::interrupt::{Interrupt, Ticker};
use crate::tin::{NONE, Tin, interpolate, locate};

/// Per coarse triangle, the most the surface of the target level rises
/// above the triangle's plane anywhere in it: `up[l][t]` for levels
/// `l < level` (exact for piecewise linear surfaces nested in the
/// triangle: the largest difference is at a vertex).
pub struct Bounds {
    pub(super) up: Vec<Vec<f64>>,
}

impl Bounds {
    /// The bounds of every level coarser than `level`, from the finest up:
    /// of every triangle, or (`within`) only of the level-0 triangles whose
    /// box meets one of the rectangles `[min x, min y, max x, max y]` and
    /// of all their descendants (a walk within them descends into no
    /// other; the others' bounds are +inf, which never skips).
    pub fn new(
        tin: &Tin,
        level: usize,
        within: Option<&[[f64; 4]]>,
        interrupt: &mut Interrupt<'_>,
    ) -> Result<Bounds, TinError> {
        let mut up: Vec<Vec<f64>> = vec![Vec::new(); level];
        let mut ticker = Ticker::new(interrupt);
        // which triangles' bounds are needed, from level 0 down
        let mut need: Vec<Vec<bool>> = Vec::with_capacity(level);
        for l in 0..level {
            let lv = &tin.levels[l];
            let n = lv.num_domain();
            let mut nd = vec![false; lv.num_triangles()];
            if l == 0 {
                for (t, x) in nd.iter_mut().enumerate().take(n) {
                    ticker.tick()?;
                    *x = match within {
                        None => true,
                        Some(boxes) => {
                            let co = tin.corners(0, t as u32);
                            let (x0, x1) = (
                                co[0][0].min(co[1][0]).min(co[2][0]),
                                co[0][0].max(co[1][0]).max(co[2][0]),
                            );
                            let (y0, y1) = (
                                co[0][1].min(co[1][1]).min(co[2][1]),
                                co[0][1].max(co[1][1]).max(co[2][1]),
                            );
                            boxes
                                .iter()
                                .any(|b| x0 <= b[2] && x1 >= b[0] && y0 <= b[3] && y1 >= b[1])
                        }
                    };
                }
            } else {
                let (plv, pn) = (&tin.levels[l - 1], &need[l - 1]);
                let needed = pn.iter().enumerate().take(plv.num_domain());
                for (t, _) in needed.filter(|p| *p.1) {
                    for c in plv.child_start[t]..plv.child_start[t + 1] {
                        nd[c as usize] = (c as usize) < n;
                    }
                }
            }
            need.push(nd);
        }
        let zscale = tin.bbox.max_z.abs().max(tin.bbox.min_z.abs()).max(1.0);
        for l in (0..level).rev() {
            let lv = &tin.levels[l];
            let mut b = vec![0.0f64; lv.num_triangles()];
            for (t, bt) in b.iter_mut().enumerate().take(lv.num_domain()) {
                if !need[l][t] {
                    *bt = f64::INFINITY;
                    continue;
                }
                ticker.tick()?;
                let co = tin.corners(l, t as u32);
                let (c0, c1) = (lv.child_start[t], lv.child_start[t + 1]);
                let mut m = 0.0f64;
                for c in c0..c1 {
                    let extra = if l + 1 < level {
                        up[l + 1][c as usize]
                    } else {
                        0.0
                    };
                    for v in tin.levels[l + 1].tris[c as usize] {
                        let p = tin.verts[v as usize];
                        m = m.max(p[2] + extra - interpolate(&co, p[0], p[1]));
                    }
                }
                // the rounding of the planes' interpolations
                *bt = m + 1e-9 * zscale;
            }
            up[l] = b;
        }
        Ok(Bounds { up })
    }
}

/// The stretch `[lo, hi]` of the ray from `o` along `dir` inside the
/// triangle of corners `co` (closed, counter-clockwise half-planes), and
/// the corners opposite the edges it enters and leaves by; empty when
/// `hi <= lo`.
#[inline]
fn span(co: &[[f64; 3]; 3], o: [f64; 2], dir: [f64; 2]) -> (f64, f64, usize, usize) {
    let (mut lo, mut hi, mut entry, mut exit) = (f64::NEG_INFINITY, f64::INFINITY, 0, 0);
    for j in 0..3 {
        // edge opposite corner j: from corner j+1 to corner j+2
        let (p, q) = (co[(j + 1) % 3], co[(j + 2) % 3]);
        let (ex, ey) = (q[0] - p[0], q[1] - p[1]);
        let s0 = ex * (o[1] - p[1]) - ey * (o[0] - p[0]);
        let s1 = ex * dir[1] - ey * dir[0];
        if s1 > 0.0 {
            let u = -s0 / s1;
            if u > lo {
                lo = u;
                entry = j;
            }
        } else if s1 < 0.0 {
            let u = -s0 / s1;
            if u < hi {
                hi = u;
                exit = j;
            }
        } else if s0 < 0.0 {
            return (0.0, -1.0, 0, 0);
        }
    }
    (lo, hi, entry, exit)
}

/// The plane of the triangle of corners `co` as seen from `o`: the height
/// at offset `(vx, vy)` from `o` is `p + gx vx + gy vy`, as `[p, gx, gy]`
/// (the triangle's own [`interpolate`] up to rounding).
#[inline]
pub(super) fn plane(co: &[[f64; 3]; 3], o: [f64; 2]) -> [f64; 3] {
    let [a, b, c] = co;
    let (bx, by, bz) = (b[0] - a[0], b[1] - a[1], b[2] - a[2]);
    let (cx, cy, cz) = (c[0] - a[0], c[1] - a[1], c[2] - a[2]);
    let inv = 1.0 / (bx * cy - cx * by);
    let gx = (bz * cy - cz * by) * inv;
    let gy = (bx * cz - cx * bz) * inv;
    [a[2] + gx * (o[0] - a[0]) + gy * (o[1] - a[1]), gx, gy]
}

/// The plane of the triangle of corners `co` along the ray from `o` along
/// `dir`: the height at distance `u` is `p + s u`, as `(p, s)`.
#[inline]
fn along(co: &[[f64; 3]; 3], o: [f64; 2], dir: [f64; 2]) -> (f64, f64) {
    let [p, gx, gy] = plane(co, o);
    (p, gx * dir[0] + gy * dir[1])
}

/// Whether the surface of `level` stays below `limit` (in `f`, drop `c`,
/// eye at `z0`) along the ray from `o` along `dir` from `far` to `dist`,
/// where the point at `dist` is in triangle `t`: walked back from `t`
/// across the edges the ray enters by, triangle by triangle of the level
/// itself. None where the walk loses the ray (rounding at a vertex, a
/// stretch over void or off the hull): the caller walks it from the eye.
#[allow(clippy::too_many_arguments)]
pub(super) fn clear_back(
    tin: &Tin,
    level: usize,
    mut t: u32,
    o: [f64; 2],
    dir: [f64; 2],
    far: f64,
    dist: f64,
    c: f64,
    z0: f64,
    limit: f64,
) -> Option<bool> {
    let lv = &tin.levels[level];
    let mut b = dist;
    let slack = 1e-9 * (1.0 + dist);
    for _ in 0..64 {
        if lv.is_void(t) {
            return None;
        }
        let co = tin.corners(level, t);
        let (lo, hi, entry, _) = span(&co, o, dir);
        if hi < b - slack || lo > b + slack {
            return None;
        }
        let a = lo.max(far);
        if a < b {
            let (p, s) = along(&co, o, dir);
            if fmax(a, b, p + s * a, p + s * b, c, z0) > limit {
                return Some(false);
            }
        }
        if lo <= far {
            return Some(true);
        }
        b = lo;
        t = lv.nbrs[t as usize][entry];
        if t == NONE {
            return None;
        }
    }
    None
}

/// The most of `f(u) = (z(u) - c u² - z₀) / u` over `[a, b]` (`0 < a <= b`)
/// for `z` linear from `za` at `a` to `zb` at `b`: at an end, or where
/// `f' = 0` inside.
#[inline]
pub(super) fn fmax(a: f64, b: f64, za: f64, zb: f64, c: f64, z0: f64) -> f64 {
    let f = |u: f64, z: f64| (z - c * u * u - z0) / u;
    let mut m = f(a, za).max(f(b, zb));
    if c > 0.0 && b > a {
        // z(u) = p + s u, f = s - c u + (p - z0) / u, f' = 0 at u² = (z0 - p) / c
        let s = (zb - za) / (b - a);
        let p = za - s * a;
        let q = (z0 - p) / c;
        if q > 0.0 {
            let u = q.sqrt();
            if u > a && u < b {
                m = m.max(f(u, p + s * u));
            }
        }
    }
    m
}

/// What a ray walk reports, in order of distance along the ray.
pub(super) trait RaySink {
    /// Whether a coarse stretch `[a, b]` (`a > 0`) whose surface is at most
    /// `za`..`zb` (linear) can be skipped; if so it is taken as skipped.
    fn skip(&mut self, a: f64, b: f64, za: f64, zb: f64) -> bool;
    /// A stretch `[a, b]` of the level's surface, linear from `za` to `zb`.
    fn piece(&mut self, a: f64, b: f64, za: f64, zb: f64);
    /// Whether the walk may stop here.
    fn done(&self) -> bool;
}

/// One ray from the eye, walked through the hierarchy.
pub(super) struct RayWalk<'a> {
    pub(super) tin: &'a Tin,
    pub(super) level: usize,
    pub(super) bounds: &'a Bounds,
    pub(super) o: [f64; 2],
    pub(super) dir: [f64; 2],
    pub(super) len: f64,
    /// Distances below this are the eye's own point (no elevation there).
    pub(super) near: f64,
    pub(super) pieces: u64,
    pub(super) pruned: u64,
    /// The children still to walk, of every triangle being descended.
    pub(super) kids: Vec<(f64, f64, u32)>,
}

impl RayWalk<'_> {
    /// The stretch `[lo, hi]` of the ray inside triangle `t` of level `l`
    /// (closed, counter-clockwise half-planes); empty when `hi <= lo`.
    #[inline]
    fn interval(&self, l: usize, t: u32) -> (f64, f64, usize) {
        let (lo, hi, _, exit) = span(&self.tin.corners(l, t), self.o, self.dir);
        (lo, hi, exit)
    }

    /// The surface of triangle `t` of level `l` along the ray: `z(u) = p +
    /// s u`, as `(p, s)`.
    #[inline]
    fn along(&self, l: usize, t: u32) -> (f64, f64) {
        along(&self.tin.corners(l, t), self.o, self.dir)
    }

    /// Walk the ray from the eye to `len` (or off the hull), reporting to
    /// `sink`.
    pub(super) fn run(&mut self, from: f64, sink: &mut dyn RaySink) {
        let Some(mut t) = locate::locate_hull(
            self.tin,
            0,
            self.o[0] + from * self.dir[0],
            self.o[1] + from * self.dir[1],
        ) else {
            return;
        };
        let mut u = from;
        let mut guard = 0usize;
        let max_steps = 4 * self.tin.levels[0].num_triangles() + 16;
        while u < self.len && !sink.done() && guard < max_steps {
            guard += 1;
            let (lo, hi, exit) = self.interval(0, t);
            let (a, b) = (lo.max(u), hi.min(self.len));
            if b > a {
                self.descend(0, t, a, b, sink);
                u = b;
            } else if hi < u - 1e-9 * (1.0 + u) || lo > u + 1e-9 * (1.0 + u) {
                // lost (rounding at a vertex): find the triangle ahead again
                let s = u + 1e-7 * (1.0 + u);
                match locate::locate_hull(
                    self.tin,
                    0,
                    self.o[0] + s * self.dir[0],
                    self.o[1] + s * self.dir[1],
                ) {
                    Some(n) if n != t => {
                        t = n;
                        continue;
                    }
                    _ => return,
                }
            }
            if u >= self.len {
                return;
            }
            let n = self.tin.levels[0].nbrs[t as usize][exit];
            if n == NONE {
                return;
            }
            t = n;
        }
    }

    fn descend(&mut self, l: usize, t: u32, a: f64, b: f64, sink: &mut dyn RaySink) {
        if sink.done() || self.tin.levels[l].is_void(t) {
            return;
        }
        if b <= self.near {
            return;
        }
        let a = a.max(self.near);
        let (p, sl) = self.along(l, t);
        let (za, zb) = (p + sl * a, p + sl * b);
        if l == self.level {
            self.pieces += 1;
            sink.piece(a, b, za, zb);
            return;
        }
        let up = self.bounds.up[l][t as usize];
        if sink.skip(a, b, za + up, zb + up) {
            self.pruned += 1;
            return;
        }
        // the children the stretch crosses, in order along the ray, on the
        // walk's one stack (deeper calls push above them and take theirs
        // off before returning)
        let lv = &self.tin.levels[l];
        let (c0, c1) = (lv.child_start[t as usize], lv.child_start[t as usize + 1]);
        let start = self.kids.len();
        for c in c0..c1 {
            let (lo, hi, _) = self.interval(l + 1, c);
            let (x, y) = (lo.max(a), hi.min(b));
            if y > x {
                // insertion by entry (a few children)
                self.kids.push((x, y, c));
                let mut k = self.kids.len() - 1;
                while k > start && self.kids[k - 1].0 > x {
                    self.kids.swap(k - 1, k);
                    k -= 1;
                }
            }
        }
        let end = self.kids.len();
        for k in start..end {
            let (x, y, c) = self.kids[k];
            self.descend(l + 1, c, x, y, sink);
        }
        self.kids.truncate(start);
    }
}

/// One stretch of a ray's running horizon: over `[a, b]` the surface is
/// linear from `za` to `zb` (NaN: a stretch that cannot raise the
/// horizon, skipped), the running maximum of `f` is `m0` at `a` and `m1`
/// at `b`.
#[derive(Clone, Copy, Debug)]
struct Piece {
    a: f64,
    b: f64,
    za: f64,
    zb: f64,
    m0: f64,
    m1: f64,
}

/// The running horizon of one ray as the stretches of its walk:
/// [`Horizon::at`] gives the most of `f` over `(0, x]` for any `x`, exact
/// on the level's surface (where the walk stopped short, off the hull or
/// over void, nothing more rises).
pub(super) struct Horizon {
    pieces: Vec<Piece>,
    c: f64,
    z0: f64,
    /// The piece the last query fell in (queries come in nearly
    /// ascending order).
    cur: usize,
}

impl Horizon {
    pub(super) fn new() -> Horizon {
        Horizon {
            pieces: Vec::new(),
            c: 0.0,
            z0: 0.0,
            cur: 0,
        }
    }

    /// Forget the last ray: ready for a walk with drop `c` and eye `z0`.
    pub(super) fn reset(&mut self, c: f64, z0: f64) {
        self.pieces.clear();
        self.c = c;
        self.z0 = z0;
        self.cur = 0;
    }

    fn m(&self) -> f64 {
        self.pieces.last().map_or(f64::NEG_INFINITY, |p| p.m1)
    }

    /// A stretch `[a, b]` at the running maximum (one for consecutive
    /// ones).
    fn flat(&mut self, a: f64, b: f64) {
        let m = self.m();
        match self.pieces.last_mut() {
            Some(p) if p.za.is_nan() => p.b = b,
            _ => self.pieces.push(Piece {
                a,
                b,
                za: f64::NAN,
                zb: f64::NAN,
                m0: m,
                m1: m,
            }),
        }
    }

    /// The most of `f` over `(0, x]`.
    #[inline]
    pub(super) fn at(&mut self, x: f64) -> f64 {
        let ps = &self.pieces;
        if ps.is_empty() || x < ps[0].a {
            return f64::NEG_INFINITY;
        }
        let mut k = self.cur.min(ps.len() - 1);
        while k + 1 < ps.len() && ps[k + 1].a <= x {
            k += 1;
        }
        while k > 0 && ps[k].a > x {
            k -= 1;
        }
        self.cur = k;
        let p = ps[k];
        if x >= p.b {
            p.m1
        } else if p.za.is_nan() {
            p.m0
        } else {
            let zx = p.za + (p.zb - p.za) * ((x - p.a) / (p.b - p.a));
            p.m0.max(fmax(p.a, x, p.za, zx, self.c, self.z0))
        }
    }
}

impl RaySink for Horizon {
    fn skip(&mut self, a: f64, b: f64, za: f64, zb: f64) -> bool {
        if fmax(a, b, za, zb, self.c, self.z0) <= self.m() {
            self.flat(a, b);
            true
        } else {
            false
        }
    }

    fn piece(&mut self, a: f64, b: f64, za: f64, zb: f64) {
        let m = self.m();
        let m1 = m.max(fmax(a, b, za, zb, self.c, self.z0));
        if m1 == m {
            // nothing rose
            self.flat(a, b);
            return;
        }
        self.pieces.push(Piece {
            a,
            b,
            za,
            zb,
            m0: m,
            m1,
        });
    }

    fn done(&self) -> bool {
        false
    }
}

/// The exact check of one cell: blocked once `f` goes above `limit`.
pub(super) struct Check {
    pub(super) c: f64,
    pub(super) z0: f64,
    pub(super) limit: f64,
    pub(super) blocked: bool,
}

impl RaySink for Check {
    fn skip(&mut self, a: f64, b: f64, za: f64, zb: f64) -> bool {
        fmax(a, b, za, zb, self.c, self.z0) <= self.limit
    }

    fn piece(&mut self, a: f64, b: f64, za: f64, zb: f64) {
        if fmax(a, b, za, zb, self.c, self.z0) > self.limit {
            self.blocked = true;
        }
    }

    fn done(&self) -> bool {
        self.blocked
    }
}
