//! The rays of a viewshed: each walked once through the hierarchy, coarse
//! triangles that cannot rise into view skipped whole ([`Bounds`]), the
//! running horizon kept along the ray ([`Profile`]) or one cell's own ray
//! checked against its target ([`Check`]).

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
}

impl RayWalk<'_> {
    /// The stretch `[lo, hi]` of the ray inside triangle `t` of level `l`
    /// (closed, counter-clockwise half-planes); empty when `hi <= lo`.
    #[inline]
    fn interval(&self, l: usize, t: u32) -> (f64, f64, usize) {
        let co = self.tin.corners(l, t);
        let (mut lo, mut hi, mut exit) = (f64::NEG_INFINITY, f64::INFINITY, 0);
        for j in 0..3 {
            // edge opposite corner j: from corner j+1 to corner j+2
            let (p, q) = (co[(j + 1) % 3], co[(j + 2) % 3]);
            let (ex, ey) = (q[0] - p[0], q[1] - p[1]);
            let s0 = ex * (self.o[1] - p[1]) - ey * (self.o[0] - p[0]);
            let s1 = ex * self.dir[1] - ey * self.dir[0];
            if s1 > 0.0 {
                lo = lo.max(-s0 / s1);
            } else if s1 < 0.0 {
                let u = -s0 / s1;
                if u < hi {
                    hi = u;
                    exit = j;
                }
            } else if s0 < 0.0 {
                return (0.0, -1.0, 0);
            }
        }
        (lo, hi, exit)
    }

    #[inline]
    fn z_at(&self, l: usize, t: u32, u: f64) -> f64 {
        let co = self.tin.corners(l, t);
        interpolate(
            &co,
            self.o[0] + u * self.dir[0],
            self.o[1] + u * self.dir[1],
        )
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
        let (za, zb) = (self.z_at(l, t, a), self.z_at(l, t, b));
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
        let lv = &self.tin.levels[l];
        let (c0, c1) = (lv.child_start[t as usize], lv.child_start[t as usize + 1]);
        let mut kids: smallvec_like::Stack = smallvec_like::Stack::default();
        for c in c0..c1 {
            let (lo, hi, _) = self.interval(l + 1, c);
            let (x, y) = (lo.max(a), hi.min(b));
            if y > x {
                kids.push((x, y, c));
            }
        }
        kids.sort();
        for &(x, y, c) in kids.as_slice() {
            self.descend(l + 1, c, x, y, sink);
        }
    }
}

/// A few children's stretches without a heap allocation for the usual
/// count.
mod smallvec_like {
    #[derive(Default)]
    pub struct Stack {
        n: usize,
        inline: [(f64, f64, u32); 16],
        more: Vec<(f64, f64, u32)>,
    }

    impl Stack {
        pub fn push(&mut self, v: (f64, f64, u32)) {
            if self.n < 16 {
                self.inline[self.n] = v;
            } else {
                if self.n == 16 {
                    self.more.extend_from_slice(&self.inline);
                }
                self.more.push(v);
            }
            self.n += 1;
        }

        pub fn as_slice(&self) -> &[(f64, f64, u32)] {
            if self.n <= 16 {
                &self.inline[..self.n]
            } else {
                &self.more
            }
        }

        pub fn sort(&mut self) {
            let by = |p: &(f64, f64, u32), q: &(f64, f64, u32)| p.0.total_cmp(&q.0);
            if self.n <= 16 {
                self.inline[..self.n].sort_unstable_by(by);
            } else {
                self.more.sort_unstable_by(by);
            }
        }
    }
}

/// The running horizon of one ray, kept every `step` along it:
/// `at[j]` = the most of `f` over `(0, j step]`.
pub(super) struct Profile<'a> {
    pub(super) at: &'a mut [f64],
    pub(super) step: f64,
    pub(super) c: f64,
    pub(super) z0: f64,
    /// The running maximum so far, and up to where.
    pub(super) m: f64,
    /// The next sample to write.
    pub(super) next: usize,
}

impl Profile<'_> {
    /// Write the samples up to distance `b` with the running maximum over
    /// `[a, b]` of a linear stretch (`None`: nothing there can raise it).
    fn advance(&mut self, a: f64, b: f64, lin: Option<(f64, f64)>) {
        let mut from = a;
        while self.next < self.at.len() {
            let s = self.next as f64 * self.step;
            if s > b {
                break;
            }
            if let Some((za, zb)) = lin
                && s > from
            {
                let zs = za + (zb - za) * ((s - a) / (b - a));
                let zf = za + (zb - za) * ((from - a) / (b - a));
                self.m = self.m.max(fmax(from, s, zf, zs, self.c, self.z0));
                from = s;
            }
            self.at[self.next] = self.m;
            self.next += 1;
        }
        if let Some((za, zb)) = lin
            && b > from
        {
            let zf = za + (zb - za) * ((from - a) / (b - a));
            self.m = self.m.max(fmax(from, b, zf, zb, self.c, self.z0));
        }
    }

    /// The samples left after the walk: nothing more rises.
    pub(super) fn finish(&mut self) {
        for v in &mut self.at[self.next..] {
            *v = self.m;
        }
        self.next = self.at.len();
    }
}

impl RaySink for Profile<'_> {
    fn skip(&mut self, a: f64, b: f64, za: f64, zb: f64) -> bool {
        if fmax(a, b, za, zb, self.c, self.z0) <= self.m {
            self.advance(a, b, None);
            true
        } else {
            false
        }
    }

    fn piece(&mut self, a: f64, b: f64, za: f64, zb: f64) {
        self.advance(a, b, Some((za, zb)));
    }

    fn done(&self) -> bool {
        self.next >= self.at.len()
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
