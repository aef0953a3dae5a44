//! The line merge through a stored tree: descend only where a node's
//! capsule is not strictly inside the triangle the walk is in.

use super::view::{PartView, View};
use super::{Node, bad};
use crate::geom::P2;
use crate::geom::co;
use crate::interrupt::Interrupt;
use crate::merge::line::widened::{Near, Visited, walk_near};
use crate::merge::line::{Polyline, Sink, Walker};
use crate::tin::{Tin, TinError};
use robust::{Coord, orient2d};

/// Whether the capsule of radius `r` around segment pq lies strictly
/// inside triangle `t` (conservative: a margin covers rounding).
fn capsule_inside(tin: &Tin, level: usize, t: u32, p: P2, q: P2, r: f64) -> bool {
    let c = tin.corners(level, t);
    let mag = p[0].abs().max(p[1].abs()).max(q[0].abs()).max(q[1].abs());
    (0..3).all(|j| {
        let (a, b) = (c[(j + 1) % 3], c[(j + 2) % 3]);
        let (ca, cb) = (Coord { x: a[0], y: a[1] }, Coord { x: b[0], y: b[1] });
        let len = (b[0] - a[0]).hypot(b[1] - a[1]);
        let need = r * len * (1.0 + 1e-9) + 1e-9 * len * len + 1e-12 * mag * len;
        let (op, oq) = (orient2d(ca, cb, co(p)), orient2d(ca, cb, co(q)));
        op > 0.0 && oq > 0.0 && op > need && oq > need
    })
}

/// What the descent does besides walking: the plain cut, or the widened
/// line.
trait Visit<S: Sink> {
    /// Added to every node's error for the containment test.
    fn radius(&self) -> f64 {
        0.0
    }
    /// The stretch from vertex `first` lies strictly inside triangle `t`.
    fn inside(&mut self, _t: u32, _first: usize) {}
    /// Whether the stretch p..q (error `e`), which starts in `t`, may be
    /// passed over without walking it.
    fn pass_over(&mut self, _t: u32, _p: P2, _q: P2, _e: f64) -> bool {
        false
    }
    /// Walk original segment `k`.
    fn leaf(&mut self, w: &mut Walker<'_, S>, part: &PartView, k: usize) -> Result<(), TinError>;
}

/// The plain cut: every sink.
struct Cut;

impl<S: Sink> Visit<S> for Cut {
    fn leaf(&mut self, w: &mut Walker<'_, S>, part: &PartView, k: usize) -> Result<(), TinError> {
        w.segment(part, k)
    }
}

/// The widened line: triangles within `r`, recorded in `near`; a segment's
/// key is `base` plus its index in the part.
struct Widen<'n, 't> {
    near: &'n mut Near<'t>,
    base: u64,
    r: f64,
}

impl Visit<Visited> for Widen<'_, '_> {
    fn radius(&self) -> f64 {
        self.r
    }
    fn inside(&mut self, t: u32, first: usize) {
        self.near.touch(t, self.base + first as u64);
    }
    fn pass_over(&mut self, t: u32, p: P2, q: P2, e: f64) -> bool {
        // every triangle the stretch could come near (within e + r of its
        // segment) is already found: it adds nothing
        self.near.all_found_near(t, p, q, e + self.r, 64)
    }
    fn leaf(
        &mut self,
        w: &mut Walker<'_, Visited>,
        part: &PartView,
        k: usize,
    ) -> Result<(), TinError> {
        walk_near(self.near, w, part, k, self.base + k as u64)
    }
}

fn descend<S: Sink, V: Visit<S>>(
    tin: &Tin,
    level: usize,
    part: &PartView,
    w: &mut Walker<'_, S>,
    (index, nd): (u32, Node),
    visit: &mut V,
    depth: usize,
) -> Result<(), TinError> {
    if depth > 64 {
        return Err(bad("the tree is too deep"));
    }
    let (f, l) = (nd.first as usize, nd.last as usize);
    if let Some(t) = w.current() {
        let (p, q) = (part.pt(f)?, part.pt(l)?);
        if capsule_inside(tin, level, t, p, q, nd.err + visit.radius()) {
            visit.inside(t, f);
            return w.run_inside(part, f, l);
        }
        if l > f + 1 && visit.pass_over(t, p, q, nd.err) {
            w.jump_to(q)?;
            return Ok(());
        }
    }
    if nd.child_count > 0 {
        let mut at = nd.first;
        for c in nd.child_first..nd.child_first + nd.child_count {
            let cn = part.v.node(c, part.n)?;
            if cn.first != at || cn.last <= cn.first || cn.last > nd.last {
                return Err(bad(format!("children of node {index} do not tile it")));
            }
            at = cn.last;
            descend(tin, level, part, w, (c, cn), visit, depth + 1)?;
        }
        if at != nd.last {
            return Err(bad(format!("children of node {index} do not tile it")));
        }
        return Ok(());
    }
    for k in f..l {
        visit.leaf(w, part, k)?;
    }
    Ok(())
}

impl PartView<'_, '_> {
    /// The root node, with its index.
    fn root(&self) -> Result<(u32, Node), TinError> {
        Ok((self.root, self.v.node(self.root, self.n)?))
    }
}

/// The line merge through a stored tree: the same reports to `sink` as
/// [`crate::merge::line::walk_parts`] on the same line.
pub fn walk_tree<S: Sink>(
    tin: &Tin,
    level: usize,
    tree: &View,
    sink: &mut S,
    on_part: &mut dyn FnMut(&mut S, usize),
    interrupt: &mut Interrupt<'_>,
) -> Result<(), TinError> {
    for pi in 0..tree.header.num_parts {
        on_part(sink, pi as usize);
        interrupt()?;
        let part = tree.part_line(pi)?;
        let mut w = Walker::new(tin, level, sink, interrupt);
        let p0 = part.pt(0)?;
        w.start_part(p0)?;
        let root = part.root()?;
        descend(tin, level, &part, &mut w, root, &mut Cut, 0)?;
        w.end_part(p0, moves(&part, root.1)?);
    }
    Ok(())
}

/// Whether a part has two distinct points (its root segment has length or
/// its error is positive).
fn moves(part: &PartView, root: Node) -> Result<bool, TinError> {
    Ok(part.pt(root.first as usize)? != part.pt(root.last as usize)? || root.err > 0.0)
}

/// Widened line through a stored tree: the same triangles, in the same
/// order, as [`crate::merge::line::widened::near_line`].
pub fn near_tree(
    tin: &Tin,
    level: usize,
    tree: &View,
    half_width: f64,
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<u32>, TinError> {
    let mut near = Near::new(tin, level, half_width);
    let mut base: u64 = 0;
    for pi in 0..tree.header.num_parts {
        let part = tree.part_line(pi)?;
        let mut vis = Visited::default();
        let mut w = Walker::new(tin, level, &mut vis, interrupt);
        w.interrupt_now()?;
        let p0 = part.pt(0)?;
        w.start_part(p0)?;
        let start = w.current();
        let root = part.root()?;
        let mut visit = Widen {
            near: &mut near,
            base,
            r: half_width,
        };
        descend(tin, level, &part, &mut w, root, &mut visit, 0)?;
        if !moves(&part, root.1)? {
            near.still_part(base, p0, start, &mut || w.interrupt_now())?;
        }
        base += part.len() as u64;
    }
    Ok(near.ordered())
}
