//! Pieces of the constrained overlay that the rounding of crossings made
//! cross again, added with splitting at crossings computed from exact
//! orientations ([`add_splitting`]).

use super::outside::Cdt;
use crate::geom::{crossing, strictly_between, within_roundings};
use crate::interrupt::Ticker;
use crate::tin::TinError;
use spade::handles::FixedVertexHandle;
use spade::{Intersection, LineIntersectionIterator, Point2, Triangulation};

/// Adds the piece `from`-`to` to `cdt`, splitting it and every piece it
/// crosses at their crossing, computed as [`crossing`] does (from exact
/// orientations, so the point lies on both pieces up to rounding), or at
/// an end of either that lies on the other up to a rounding or within
/// `eps` of that point.
///
/// spade's own splitting insertion computes the crossing of the two lines
/// in floating point and, where that lands off both (nearly parallel
/// pieces), routes the piece through the nearest vertex instead: on a tin
/// overlaid with itself at two levels, where a child edge runs along its
/// coarse edge within a few roundings, it bent an edge of the input 7 cm
/// off its line (harness seed 197197).
pub(super) fn add_splitting(
    cdt: &mut Cdt,
    from: FixedVertexHandle,
    to: FixedVertexHandle,
    eps: f64,
    tk: &mut Ticker<'_, '_>,
) -> Result<(), TinError> {
    let pos = |cdt: &Cdt, h: FixedVertexHandle| {
        let p = cdt.vertex(h).position();
        [p.x, p.y]
    };
    let mut todo = vec![(from, to)];
    // each split adds a vertex and at most four pieces; rounding that kept
    // making new crossings would not end
    let mut budget = 10_000usize;
    while let Some((u, v)) = todo.pop() {
        tk.tick()?;
        budget = budget.checked_sub(1).ok_or_else(|| {
            TinError::Degenerate(
                "overlay: pieces of the inputs' edges keep crossing after every split \
                 (edges too near each other for double precision)"
                    .into(),
            )
        })?;
        if u == v {
            continue;
        }
        if cdt.can_add_constraint(u, v) {
            cdt.add_constraint(u, v);
            continue;
        }
        // the first piece in the way
        let mut hit = None;
        for x in LineIntersectionIterator::new_from_handles(cdt, u, v).skip(1) {
            match x {
                Intersection::VertexIntersection(h) => {
                    if h.fix() != v {
                        hit = Some(Err(h.fix()));
                    }
                    break;
                }
                Intersection::EdgeIntersection(e) if e.is_constraint_edge() => {
                    hit = Some(Ok((e.from().fix(), e.to().fix(), e.fix().as_undirected())));
                    break;
                }
                _ => {}
            }
        }
        match hit {
            // through a vertex: two pieces
            Some(Err(h)) => {
                todo.push((h, v));
                todo.push((u, h));
            }
            Some(Ok((w1, w2, e))) => {
                let (pu, pv, p1, p2) = (pos(cdt, u), pos(cdt, v), pos(cdt, w1), pos(cdt, w2));
                // an end of either piece on the other up to a rounding is
                // where they cross: two long pieces meeting at a tiny angle
                // cross a rounding from where they meet, and points computed
                // there only move the crossing along them (harness seed
                // 226663: 1.8 km edges 1/1800 apart, split without end)
                let p3 = |p: [f64; 2]| [p[0], p[1], 0.0];
                let (u3, v3, a3, b3) = (p3(pu), p3(pv), p3(p1), p3(p2));
                let on = |c: &[f64; 3], a: &[f64; 3], b: &[f64; 3]| {
                    within_roundings(a, b, c, 1.0) && strictly_between(a, b, c)
                };
                // Ok: the vertex where they cross; Err: a new point there
                let at = if on(&u3, &a3, &b3) {
                    Ok(u)
                } else if on(&v3, &a3, &b3) {
                    Ok(v)
                } else if on(&a3, &u3, &v3) {
                    Ok(w1)
                } else if on(&b3, &u3, &v3) {
                    Ok(w2)
                } else {
                    // canonical order: the same point whichever piece comes first
                    let (s, t) = if u.index() < v.index() {
                        (pu, pv)
                    } else {
                        (pv, pu)
                    };
                    let (s2, t2) = if w1.index() < w2.index() {
                        (p1, p2)
                    } else {
                        (p2, p1)
                    };
                    let x = crossing(s, t, s2, t2);
                    [u, v, w1, w2]
                        .into_iter()
                        .find(|&h| {
                            let p = pos(cdt, h);
                            (p[0] - x[0]).abs() <= eps && (p[1] - x[1]).abs() <= eps
                        })
                        .ok_or(x)
                };
                cdt.remove_constraint_edge(e);
                let h = match at {
                    Ok(h) => h,
                    Err(x) => cdt.insert(Point2::new(x[0], x[1])).map_err(|e| {
                        TinError::Degenerate(format!("overlay: a crossing point: {e:?}"))
                    })?,
                };
                todo.push((w1, h));
                todo.push((h, w2));
                todo.push((h, v));
                todo.push((u, h));
            }
            // spade says the piece cannot be added but its walk meets
            // nothing in the way: not a triangulation it made
            None => {
                return Err(TinError::Degenerate(
                    "overlay: a piece of an input edge cannot be added and crosses nothing".into(),
                ));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interrupt::Ticker;

    /// Whether the constraint edges lead from `u` to `v` by forward steps
    /// along the line `uv`, each vertex within `tol` of it.
    fn chain(cdt: &Cdt, u: FixedVertexHandle, v: FixedVertexHandle, tol: f64) -> bool {
        let p = |h: FixedVertexHandle| cdt.vertex(h).position();
        let (a, b) = (p(u), p(v));
        let d = [b.x - a.x, b.y - a.y];
        let len2 = d[0] * d[0] + d[1] * d[1];
        let along = |q: Point2<f64>| ((q.x - a.x) * d[0] + (q.y - a.y) * d[1]) / len2;
        let off = |q: Point2<f64>| ((q.x - a.x) * d[1] - (q.y - a.y) * d[0]).abs() / len2.sqrt();
        let mut todo = vec![u];
        while let Some(cur) = todo.pop() {
            if cur == v {
                return true;
            }
            todo.extend(
                cdt.vertex(cur)
                    .out_edges()
                    .filter(|e| e.is_constraint_edge())
                    .map(|e| e.to())
                    .filter(|w| along(w.position()) > along(p(cur)) && off(w.position()) <= tol)
                    .map(|w| w.fix()),
            );
        }
        false
    }

    /// A child edge along its coarse edge within a rounding (harness seed
    /// 197197: a tin overlaid with itself at levels 2 and 0, UTM
    /// coordinates), its end 1e-10 m to the left of the coarse edge, two
    /// more edges from that end crossing the coarse edge to the right a
    /// few nanometres on (vertices 3037, 693, 3060 and 3061 of that tin). The rounded crossings put the coarse edge's
    /// pieces across the child edge; after the splits both edges, and the
    /// two crossing ones, are chains of constraint edges along their lines.
    #[test]
    fn nearly_parallel_pieces_split_on_both_lines() {
        let (w1, w2) = (
            [371683.0227199141, 3280689.601243232],
            [371700.48835296585, 3280692.835619723],
        );
        let (u, v) = (
            [371684.96334580873, 3280689.9606183977],
            [371694.01959998376, 3280691.637702504],
        );
        let (r1, r2) = (
            [u[0] + 5.175002385687549, u[1] + 0.589375271461904],
            [u[0] + 5.175002385687549, u[1] + 0.934375430457294],
        );
        // ids as in the overlay: vertices first, then the crossings
        let (x1, x2) = (crossing(u, r1, w1, w2), crossing(u, r2, w1, w2));
        let pts: Vec<Point2<f64>> = [w1, w2, u, v, r1, r2, x1, x2]
            .iter()
            .map(|p| Point2::new(p[0], p[1]))
            .collect();
        let along =
            |p: [f64; 2]| (p[0] - w1[0]) * (w2[0] - w1[0]) + (p[1] - w1[1]) * (w2[1] - w1[1]);
        let (first, second) = if along(x1) < along(x2) {
            (6, 7)
        } else {
            (7, 6)
        };
        let pieces = vec![
            [2, 3],
            [2, 6],
            [6, 4],
            [2, 7],
            [7, 5],
            [0, first],
            [first, second],
            [second, 1],
        ];
        let mut conflicts = Vec::new();
        let mut cdt = Cdt::try_bulk_load_cdt(pts, pieces, |e| conflicts.push(e)).unwrap();
        assert!(!conflicts.is_empty(), "rounding made pieces cross again");
        let mut never = || Ok(());
        let mut tk = Ticker::new(&mut never);
        let eps = super::super::constrained::snap_eps(w2[1]);
        for [a, b] in conflicts {
            let h = FixedVertexHandle::from_index;
            add_splitting(&mut cdt, h(a), h(b), eps, &mut tk).unwrap();
        }
        let h = FixedVertexHandle::from_index;
        assert!(
            chain(&cdt, h(2), h(3), 1e-9),
            "the child edge is a chain along its line"
        );
        assert!(
            chain(&cdt, h(0), h(1), 1e-9),
            "the coarse edge is a chain along its line"
        );
        assert!(chain(&cdt, h(2), h(4), 1e-9) && chain(&cdt, h(2), h(5), 1e-9));
    }
}
