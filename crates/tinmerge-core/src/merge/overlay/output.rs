//! The overlay's output: its triangles, their provenance, heights, and the
//! cut and fill between the two surfaces over it.

use crate::tin::NONE;

/// The overlay of two TINs.
#[derive(Clone, Debug, Default)]
pub struct Overlay {
    /// Output vertices (x, y).
    pub pts: Vec<[f64; 2]>,
    /// Height of each output vertex on surface A and on surface B.
    pub za: Vec<f64>,
    pub zb: Vec<f64>,
    /// Output triangles, counter-clockwise.
    pub tris: Vec<[u32; 3]>,
    /// Triangle of A (at its level) and of B containing each output triangle.
    pub tri_a: Vec<u32>,
    pub tri_b: Vec<u32>,
    /// Proper crossings of an edge of A with an edge of B.
    pub crossings: usize,
    /// Pieces that had to be inserted with splitting (rounding of crossing
    /// points made them cross another piece; constrained-triangulation path
    /// only).
    pub resplit: usize,
    /// Why the face-by-face path ([`crate::merge::overlay::faces`]) was not used and
    /// the constrained triangulation built instead (None: faces path).
    pub fallback: Option<String>,
    /// Output triangles off the common domain: in a void triangle of A or
    /// of B ([`crate::tin::Level::num_void`]); empty when there are none.
    /// They keep the triangulation convex; no answer is made of them.
    pub void: Vec<bool>,
    /// Output triangles over which A and B are one plane (their triangles'
    /// planes agree to [`SAME_PLANE`] of the heights): unchanged for
    /// [`difference`]. Filled by [`crate::merge::overlay::mark_same`]; empty
    /// when not asked.
    pub same: Vec<bool>,
}

/// Two triangles are one plane when each one's corners lie on the other's
/// plane to within this fraction of their heights (at least 1): half a
/// micrometre at 500 m, far below the precision of any terrain survey, and
/// far above the rounding of evaluating a plane a triangle's size away.
pub const SAME_PLANE: f64 = 1e-9;

impl Overlay {
    /// Whether output triangle `t` is off the common domain.
    #[inline]
    pub fn is_void(&self, t: usize) -> bool {
        self.void.get(t).copied().unwrap_or(false)
    }

    /// The output triangles in the common domain.
    pub fn domain(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.tris.len()).filter(|&t| !self.is_void(t))
    }

    /// Planar area of output triangle `t`.
    pub fn area(&self, t: usize) -> f64 {
        let [a, b, c] = self.tris[t].map(|v| self.pts[v as usize]);
        0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]))
    }

    /// Corners of output triangle `t` with heights from A (`from_b` false)
    /// or from B.
    pub fn corners(&self, t: usize, from_b: bool) -> [[f64; 3]; 3] {
        self.tris[t].map(|v| {
            let p = self.pts[v as usize];
            let z = if from_b {
                self.zb[v as usize]
            } else {
                self.za[v as usize]
            };
            [p[0], p[1], z]
        })
    }
}

/// Cut and fill between surfaces A and B over the overlay: (volume where A
/// is above B, volume where A is below B, planar area where they differ).
/// Exact for the piecewise linear surfaces: within an output triangle both
/// are linear, and the triangle is split at the zero line of A - B.
///
/// A triangle is unchanged where [`Overlay::same`] says A and B are one
/// plane over it, or (not known) where they agree exactly at its corners.
/// The heights where edges cross are interpolated, from an edge or a
/// triangle of each tin, and where the two surfaces are one plane they can
/// differ in their last bits: exact equality at the corners counted 17,600
/// to 44,000 m² of the tutorial's pair as changed, where the surfaces are
/// one plane over 68,590 m², depending on how the crossings' heights were
/// interpolated.
pub fn difference(o: &Overlay) -> (f64, f64, f64) {
    let (mut cut, mut fill, mut changed) = (0.0, 0.0, 0.0);
    for t in o.domain() {
        let area = o.area(t);
        let d = o.tris[t].map(|v| o.za[v as usize] - o.zb[v as usize]);
        if o.same.get(t).copied().unwrap_or(false) || d.iter().all(|&x| x == 0.0) {
            continue;
        }
        changed += area;
        let pos = positive_part(area, d);
        let neg = positive_part(area, d.map(|x| -x));
        cut += pos;
        fill += neg;
    }
    (cut, fill, changed)
}

/// Integral over a triangle of area `area` of max(f, 0) for the linear f
/// with corner values `d`.
pub(super) fn positive_part(area: f64, d: [f64; 3]) -> f64 {
    let total = area * (d[0] + d[1] + d[2]) / 3.0;
    let pos: Vec<f64> = d.iter().copied().filter(|&x| x > 0.0).collect();
    let non: Vec<f64> = d.iter().copied().filter(|&x| x <= 0.0).collect();
    match (pos.as_slice(), non.as_slice()) {
        ([], _) => 0.0,
        (_, []) => total,
        // one corner above: a corner triangle, scaled by t1 * t2, mean d0 / 3
        ([p], [n1, n2]) => area * p * p * p / (3.0 * (p - n1) * (p - n2)),
        // two corners above: everything minus the negative corner triangle
        ([p1, p2], [n]) => total + area * (-n) * (-n) * (-n) / (3.0 * (p1 - n) * (p2 - n)),
        _ => 0.0,
    }
}

/// The vertices no triangle uses dropped, the triangles renumbered: a
/// point met only where two closed triangles touch (faces path: a point of
/// the common domain's boundary with no face around it), or only by flat
/// slivers outside the common domain (constrained path).
pub(super) fn drop_unused(o: &mut Overlay) {
    let mut used = vec![false; o.pts.len()];
    for t in &o.tris {
        for &v in t {
            used[v as usize] = true;
        }
    }
    if used.iter().all(|&u| u) {
        return;
    }
    let mut map = vec![NONE; used.len()];
    let mut k = 0usize;
    for i in 0..used.len() {
        if used[i] {
            map[i] = k as u32;
            o.pts[k] = o.pts[i];
            o.za[k] = o.za[i];
            o.zb[k] = o.zb[i];
            k += 1;
        }
    }
    o.pts.truncate(k);
    o.za.truncate(k);
    o.zb.truncate(k);
    for t in &mut o.tris {
        *t = t.map(|v| map[v as usize]);
    }
}
