//! The overlay's output: its triangles, their provenance, heights, and the
//! cut and fill between the two surfaces over it.

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
}

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
pub fn difference(o: &Overlay) -> (f64, f64, f64) {
    let (mut cut, mut fill, mut changed) = (0.0, 0.0, 0.0);
    for t in o.domain() {
        let area = o.area(t);
        let d = o.tris[t].map(|v| o.za[v as usize] - o.zb[v as usize]);
        if d.iter().all(|&x| x == 0.0) {
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
