//! Bisection along the lattice from the driver: a triangle and its
//! neighbours ([`super::aligned::bisect`]), and a kept side's vertex made
//! by bisecting the triangles at it ([`Greedy::bisect_to`]).

use super::super::aligned;
use super::super::measure::Source;
use super::super::mesh::NONE;
use super::Greedy;
use crate::tin::TinError;

impl<S: Source + ?Sized> Greedy<'_, S> {
    /// Bisect triangle `t` along the lattice ([`aligned::bisect`]), its
    /// neighbours with it as it takes: the vertex at its hypotenuse's
    /// middle, or `None` (nothing changed, or no lattice).
    pub(super) fn bisect(&mut self, t: u32, hull: aligned::Hull) -> Result<Option<u32>, TinError> {
        let Some(g) = self.g.lattice() else {
            return Ok(None);
        };
        let w = g.width;
        let first = self.m.pts.len() as u32;
        let mut scratch = std::mem::take(&mut self.stack);
        let p = aligned::bisect(
            &mut self.m,
            t,
            &mut |c, r| g.at(c, r),
            &mut self.touched,
            &mut scratch,
            hull,
            0,
        );
        self.stack = scratch;
        if let Some(p) = p? {
            // the middles of the neighbours split first too
            for v in first..=p {
                let q = self.m.pts[v as usize];
                self.vid[q[1] as usize * w + q[0] as usize] = v;
            }
            return Ok(Some(p));
        }
        Ok(None)
    }

    /// Make sample `id`, on a hull side, a vertex by bisection along the
    /// lattice: the triangle on the side there is bisected at its
    /// hypotenuse, after its coarser ones inside, until `id` is the middle
    /// of one on the side ([`super::super::kept`]'s sides halved, a tile's whole
    /// side of 2^k pixels). False, having made nothing at `id`, when it
    /// cannot be (the triangle there is not along the lattice, or `id` is
    /// not where a bisection reaches); what was bisected on the way stays,
    /// along the lattice.
    pub(super) fn bisect_to(&mut self, id: u32) -> Result<bool, TinError> {
        let p = self.g.point(id);
        let at = [p[0] as i64, p[1] as i64];
        let mut start = 0;
        // each round halves the triangle on the side at `id`
        for _ in 0..64 {
            let (t, on) = self.locate(start, &p)?;
            start = t;
            let Some(h) = on else {
                return Ok(false);
            };
            if self.m.twin[h as usize] != NONE {
                return Ok(false);
            }
            let Some(v) = self.bisect(t, aligned::Hull::At(at))? else {
                return Ok(false);
            };
            if self.m.pts[v as usize][..2] == p[..2] {
                return Ok(true);
            }
        }
        Ok(false)
    }
}
