//! The outline of a level's domain: its boundary edges (a domain
//! triangle's edge on the hull or to a void triangle, the domain on the
//! left) chained into closed rings, with each ring's bounding box.
//!
//! A decoded value computes it once per level, on first use
//! ([`Tin::outline`]), and keeps it: `tin_drape` of a polygon, which asks
//! whether the polygon holds part of the outline and cuts it to the rings
//! near it, then reads only the rings whose box meets the polygon's, not
//! the whole level, on every call.

use rustc_hash::FxHashMap;

use super::{Level, Outline, Tin};
use crate::geom::{bbox2, xy};

impl Outline {
    /// The outline of `level`, whose vertices are `verts`.
    pub fn of(verts: &[[f64; 3]], level: &Level) -> Outline {
        let edges: Vec<[u32; 2]> = level.boundary_edges().collect();
        let rings = rings_of(&edges);
        let boxes = rings
            .iter()
            .map(|r| bbox2(r.iter().map(|&v| xy(&verts[v as usize]))))
            .collect();
        Outline {
            edges,
            rings,
            boxes,
        }
    }

    /// The rings whose box meets `b` = `[min x, min y, max x, max y]`
    /// (closed), as indices into [`Outline::rings`].
    pub fn rings_meeting(&self, b: &[f64; 4]) -> impl Iterator<Item = usize> + '_ {
        let b = *b;
        (0..self.rings.len()).filter(move |&i| {
            let r = &self.boxes[i];
            r[0] <= b[2] && b[0] <= r[2] && r[1] <= b[3] && b[1] <= r[3]
        })
    }
}

/// Boundary edges chained into closed rings of vertex ids. An open chain
/// (not a valid tin's boundary) and a ring of fewer than three vertices
/// are dropped.
fn rings_of(edges: &[[u32; 2]]) -> Vec<Vec<u32>> {
    let mut from: FxHashMap<u32, Vec<usize>> = FxHashMap::default();
    for (i, e) in edges.iter().enumerate() {
        from.entry(e[0]).or_default().push(i);
    }
    let mut used = vec![false; edges.len()];
    let mut rings = Vec::new();
    for s in 0..edges.len() {
        if used[s] {
            continue;
        }
        let mut ring = vec![edges[s][0]];
        let mut i = s;
        loop {
            used[i] = true;
            let v = edges[i][1];
            if v == edges[s][0] {
                break;
            }
            ring.push(v);
            let Some(n) = from
                .get(&v)
                .and_then(|es| es.iter().copied().find(|&k| !used[k]))
            else {
                ring.clear();
                break;
            };
            i = n;
        }
        if ring.len() >= 3 {
            rings.push(ring);
        }
    }
    rings
}

impl Tin {
    /// The outline of `level`'s domain, computed on the first call and
    /// kept with the value.
    ///
    /// ```
    /// use tinmerge_core::tin::build::build;
    /// // a 4 x 4 grid: one level, its domain the whole square
    /// let mut pts = Vec::new();
    /// for i in 0..4 {
    ///     for j in 0..4 {
    ///         pts.push([i as f64, j as f64, 0.0]);
    ///     }
    /// }
    /// let tin = build(pts, &[0.0], 0, &mut || Ok(())).unwrap();
    /// let o = tin.outline(0);
    /// assert_eq!(o.rings.len(), 1);
    /// assert_eq!(o.boxes[0], [0.0, 0.0, 3.0, 3.0]);
    /// assert_eq!(o.edges.len(), o.rings[0].len());
    /// ```
    pub fn outline(&self, level: usize) -> &Outline {
        let lv = &self.levels[level];
        lv.outline.get_or_init(|| Outline::of(&self.verts, lv))
    }
}
