//! The cavity a recovered segment crosses, triangulated again on each
//! side ([`Greedy::recover`]): Delaunay in the pseudo-polygon, then put
//! in the cavity's slots and linked.

use super::super::measure::Source;
use super::super::mesh::{NONE, next};
use super::Greedy;

impl<S: Source + ?Sized> Greedy<'_, S> {
    /// Triangulate the polygon of `chain` (its base from the first vertex
    /// to the last, the others on the base's left) as Delaunay.
    pub(super) fn fill(&self, chain: &[u32], out: &mut Vec<[u32; 3]>) {
        if chain.len() < 3 {
            return;
        }
        let (a, b) = (chain[0], chain[chain.len() - 1]);
        let pt = |v: u32| {
            let p = &self.m.pts[v as usize];
            robust::Coord { x: p[0], y: p[1] }
        };
        let mut k = 1;
        for i in 2..chain.len() - 1 {
            if robust::incircle(pt(a), pt(b), pt(chain[k]), pt(chain[i])) > 0.0 {
                k = i;
            }
        }
        out.push([a, b, chain[k]]);
        self.fill(&chain[..=k], out);
        self.fill(&chain[k..], out);
    }

    /// Put triangles `tris` in the slots of `cavity` (as many), linked to
    /// each other and to the triangles around; the edge `locked` locked.
    pub(super) fn replace(&mut self, cavity: &[u32], tris: &[[u32; 3]], locked: (u32, u32)) {
        use std::collections::HashMap;
        let mut outer = HashMap::new();
        let parent = self.m.parent[cavity[0] as usize];
        for &t in cavity {
            for h in 3 * t..3 * t + 3 {
                let g = self.m.twin[h as usize];
                if g == NONE || !cavity.contains(&(g / 3)) {
                    let key = (self.m.v[h as usize], self.m.v[next(h) as usize]);
                    outer.insert(key, (g, self.m.locked[h as usize]));
                }
            }
        }
        let mut inner = HashMap::new();
        for (&t, tri) in cavity.iter().zip(tris) {
            for k in 0..3 {
                self.m.v[3 * t as usize + k] = tri[k];
                inner.insert((tri[k], tri[(k + 1) % 3]), 3 * t + k as u32);
            }
            self.m.parent[t as usize] = parent;
        }
        for &t in cavity {
            for h in 3 * t..3 * t + 3 {
                let key = (self.m.v[h as usize], self.m.v[next(h) as usize]);
                if let Some(&(g, lock)) = outer.get(&key) {
                    self.m.link(h, g, lock);
                } else if let Some(&g) = inner.get(&(key.1, key.0)) {
                    let lock = key == locked || key == (locked.1, locked.0);
                    self.m.link(h, g, lock);
                }
            }
            self.m.refresh_out(t);
            self.touched.push(t);
        }
    }
}
