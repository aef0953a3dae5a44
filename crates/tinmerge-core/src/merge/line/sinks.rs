//! What a walk of the line leaves: [`Piece`]s (the line cut per triangle,
//! with heights, by [`PieceSink`]) or the triangles crossed
//! ([`TriangleSink`]), and the runs of pieces along each part.

use super::walk::{Part, Sink, walk_parts};
use crate::geom::{P2, dist};
use crate::interrupt::Interrupt;
use crate::tin::mesh::{Indexed, Mesh};
use crate::tin::{Tin, TinError, interpolate};

/// One piece of a cut line: the stretch inside one triangle, with heights
/// from the surface.
#[derive(Clone, Debug, PartialEq)]
pub struct Piece {
    /// Index of the part (LINESTRING) the piece comes from.
    pub part: usize,
    pub triangle: u32,
    /// x, y, z; z from the triangle's plane.
    pub points: Vec<[f64; 3]>,
    /// Distance along the part of each point.
    pub along: Vec<f64>,
}

impl Piece {
    pub fn length2d(&self) -> f64 {
        self.points
            .windows(2)
            .map(|w| dist([w[0][0], w[0][1]], [w[1][0], w[1][1]]))
            .sum()
    }
    pub fn length3d(&self) -> f64 {
        self.points
            .windows(2)
            .map(|w| {
                let (dx, dy, dz) = (w[1][0] - w[0][0], w[1][1] - w[0][1], w[1][2] - w[0][2]);
                (dx * dx + dy * dy + dz * dz).sqrt()
            })
            .sum()
    }
    pub fn rise(&self) -> f64 {
        match (self.points.first(), self.points.last()) {
            (Some(a), Some(b)) => b[2] - a[2],
            _ => 0.0,
        }
    }
}

/// Collects [`Piece`]s (repeated points dropped), heights from the mesh.
pub struct PieceSink<'a, M: Mesh = Tin> {
    tin: &'a M,
    level: usize,
    pub part: usize,
    pub pieces: Vec<Piece>,
    open: bool,
    /// The first read error of the mesh (a damaged block of a value read in
    /// slices); the pieces are not to be used when it is set.
    pub err: Option<TinError>,
}

impl<'a, M: Mesh> PieceSink<'a, M>
where
    TinError: From<M::Err>,
{
    pub fn new(tin: &'a M, level: usize) -> Self {
        PieceSink {
            tin,
            level,
            part: 0,
            pieces: Vec::new(),
            open: false,
            err: None,
        }
    }

    /// The pieces, or the first read error.
    pub fn finish(self) -> Result<Vec<Piece>, TinError> {
        match self.err {
            Some(e) => Err(e),
            None => Ok(self.pieces),
        }
    }
}

impl<M: Mesh> Sink for PieceSink<'_, M>
where
    TinError: From<M::Err>,
{
    fn point(&mut self, tri: u32, p: P2, along: f64) {
        let z = match self.tin.corners(self.level, tri) {
            Ok(c) => interpolate(&c, p[0], p[1]),
            Err(e) => {
                self.err.get_or_insert(e.into());
                f64::NAN
            }
        };
        if self.open
            && let Some(last) = self.pieces.last_mut()
            && last.triangle == tri
        {
            if let Some(lp) = last.points.last()
                && lp[0] == p[0]
                && lp[1] == p[1]
            {
                return;
            }
            last.points.push([p[0], p[1], z]);
            last.along.push(along);
            return;
        }
        self.pieces.push(Piece {
            part: self.part,
            triangle: tri,
            points: vec![[p[0], p[1], z]],
            along: vec![along],
        });
        self.open = true;
    }
    fn brk(&mut self) {
        self.open = false;
    }
}

/// Collects the triangles in travel order (a triangle entered again after
/// another, or after leaving the domain, appears again).
#[derive(Default)]
pub struct TriangleSink {
    pub tris: Vec<u32>,
    open: bool,
}

impl Sink for TriangleSink {
    fn wants_points(&self) -> bool {
        false
    }
    fn point(&mut self, tri: u32, _p: P2, _along: f64) {
        if !(self.open && self.tris.last() == Some(&tri)) {
            self.tris.push(tri);
        }
        self.open = true;
    }
    fn brk(&mut self) {
        self.open = false;
    }
}

/// The line cut into pieces, one per triangle crossed (plain walk).
pub fn pieces(tin: &Tin, level: usize, parts: &[Part]) -> Result<Vec<Piece>, TinError> {
    pieces_in(tin, level, parts, &mut || Ok(()))
}

/// [`pieces`] on any mesh (a stored value read in slices).
pub fn pieces_in<M: Indexed>(
    m: &M,
    level: usize,
    parts: &[Part],
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<Piece>, TinError>
where
    TinError: From<M::Err>,
{
    let mut sink = PieceSink::new(m, level);
    walk_parts(
        m,
        level,
        parts,
        &mut sink,
        &mut |s, i| s.part = i,
        interrupt,
    )?;
    sink.finish()
}

/// Triangles the line passes through, in travel order (plain walk).
pub fn triangles(tin: &Tin, level: usize, parts: &[Part]) -> Result<Vec<u32>, TinError> {
    let mut sink = TriangleSink::default();
    walk_parts(tin, level, parts, &mut sink, &mut |_, _| {}, &mut || Ok(()))?;
    Ok(sink.tris)
}

/// The pieces joined into continuous runs (a run ends where the line leaves
/// the domain or a part ends): the draped line, with a vertex at every
/// triangle-edge crossing. Returns (part, points, distance along the part
/// of each point).
pub fn runs(pieces: &[Piece]) -> Vec<(usize, Vec<[f64; 3]>, Vec<f64>)> {
    let mut out: Vec<(usize, Vec<[f64; 3]>, Vec<f64>)> = Vec::new();
    let mut prev_end: Option<(usize, [f64; 2])> = None;
    for p in pieces {
        let Some(first) = p.points.first() else {
            continue;
        };
        let joins = prev_end == Some((p.part, [first[0], first[1]]));
        match out.last_mut() {
            Some(run) if joins => {
                // the crossing point is already there (end of the last piece)
                run.1.extend_from_slice(&p.points[1..]);
                run.2.extend_from_slice(&p.along[1..]);
            }
            _ => out.push((p.part, p.points.clone(), p.along.clone())),
        }
        if let Some(l) = p.points.last() {
            prev_end = Some((p.part, [l[0], l[1]]));
        }
    }
    out
}
