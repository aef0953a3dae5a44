//! The raw levels assembled into a [`Tin`]: vertices in Morton order,
//! neighbours, children, point-location grids.

use super::common::*;
use crate::interrupt::Interrupt;
use crate::tin::hierarchy::{child_starts, compute_neighbours};

use crate::tin::{Bbox, Level, NONE, Tin, TinError, grid};

/// Morton code of a point normalised to the bbox (16 bits per axis).
pub(super) fn morton(b: &Bbox, x: f64, y: f64) -> u32 {
    let nx = ((x - b.min_x) / (b.max_x - b.min_x).max(f64::MIN_POSITIVE) * 65535.0) as u32;
    let ny = ((y - b.min_y) / (b.max_y - b.min_y).max(f64::MIN_POSITIVE) * 65535.0) as u32;
    fn spread(mut v: u32) -> u32 {
        v &= 0xffff;
        v = (v | (v << 8)) & 0x00ff00ff;
        v = (v | (v << 4)) & 0x0f0f0f0f;
        v = (v | (v << 2)) & 0x33333333;
        v = (v | (v << 1)) & 0x55555555;
        v
    }
    spread(nx) | (spread(ny) << 1)
}

/// Sort each level's block of new vertices (`num_vertices` of the previous
/// level up to its own) by Morton code, keeping the prefix property, and
/// renumber the triangles: vertices near in space are then near in memory,
/// which is what a walk between neighbouring triangles reads.
pub(super) fn reorder_vertices(verts: Vec<[f64; 3]>, raw: &mut [RawLevel]) -> Vec<[f64; 3]> {
    let bbox = Bbox::of(&verts);
    let mut order: Vec<u32> = (0..verts.len() as u32).collect();
    let mut start = 0usize;
    for r in raw.iter() {
        let end = (r.num_vertices as usize).min(verts.len());
        if end > start {
            // each key computed once, not at every comparison
            let mut keyed: Vec<(u32, u32)> = order[start..end]
                .iter()
                .map(|&v| {
                    let p = verts[v as usize];
                    (morton(&bbox, p[0], p[1]), v)
                })
                .collect();
            keyed.sort_unstable();
            for (o, k) in order[start..end].iter_mut().zip(keyed) {
                *o = k.1;
            }
            start = end;
        }
    }
    let mut new_id = vec![0u32; verts.len()];
    for (new, &old) in order.iter().enumerate() {
        new_id[old as usize] = new as u32;
    }
    for r in raw.iter_mut() {
        for t in r.tris.iter_mut() {
            for v in t.iter_mut() {
                *v = new_id[*v as usize];
            }
        }
    }
    order.iter().map(|&v| verts[v as usize]).collect()
}

/// A triangle's sort key at its level: first its parent's final position
/// (at level 0: 1 when void, else 0, so the void ones come last), then the
/// Morton code of its centroid; then the triangle and its index in the
/// level's raw `tris`.
type Keyed = (u32, u32, [u32; 3], u32);

/// Every triangle of level `l`'s keys ([`Keyed`]), found on threads chunk
/// by chunk, in triangle order: `parents` are indexes into the previous
/// level's raw `tris`, `position` their final positions.
fn sort_keys(
    tin: &Tin,
    l: usize,
    tris: &[[u32; 3]],
    parents: &[u32],
    void: &[bool],
    position: &[u32],
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<Keyed>, TinError> {
    let centroid = |t: &[u32; 3]| {
        let (a, b, c) = (
            tin.verts[t[0] as usize],
            tin.verts[t[1] as usize],
            tin.verts[t[2] as usize],
        );
        ((a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0)
    };
    // parents found on threads, chunk by chunk, kept in triangle order
    let key = |i: usize| -> Result<Keyed, TinError> {
        let t = &tris[i];
        let (x, y) = centroid(t);
        let parent = if l == 0 {
            NONE
        } else if let Some(&p) = parents.get(i) {
            match position.get(p as usize) {
                Some(&q) => q,
                None => {
                    return Err(TinError::Degenerate(format!(
                        "internal: parent {p} of a triangle of level {l} does not exist"
                    )));
                }
            }
        } else {
            return Err(TinError::Degenerate(format!(
                "internal: no parent at level {} for a triangle of level {l}",
                l - 1
            )));
        };
        // void triangles last: at level 0 by their mark, below by
        // their parent (the void ones are the previous level's last)
        let first = if l == 0 {
            u32::from(void.get(i).copied().unwrap_or(false))
        } else {
            parent
        };
        Ok((first, morton(&tin.bbox, x, y), *t, i as u32))
    };
    let chunks: Vec<std::ops::Range<usize>> = (0..tris.len())
        .step_by(4096)
        .map(|s| s..(s + 4096).min(tris.len()))
        .collect();
    let mut keyed: Vec<Keyed> = Vec::with_capacity(tris.len());
    crate::par::map_batched(
        &chunks,
        |c| c.clone().map(key).collect::<Result<Vec<_>, TinError>>(),
        interrupt,
        &mut |part| {
            keyed.extend(part?);
            Ok(())
        },
    )?;
    Ok(keyed)
}

/// [`assemble`] of a build's levels, verified
/// ([`crate::tin::check::verify_built`]): no build hands out a value that
/// fails its own checks (issue 73). Triangles a caller gives
/// (`from_triangles`) are assembled as they are.
pub(crate) fn assemble_verified(
    verts: Vec<[f64; 3]>,
    raw: Vec<RawLevel>,
    srid: i32,
    grids: bool,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    let tin = assemble(verts, raw, srid, grids, interrupt)?;
    crate::tin::check::verify_built(&tin, grids, interrupt)?;
    Ok(tin)
}

/// Order triangles, link neighbours, place parents and
/// build grid indexes (when `grids`; else left empty for the caller). Its
/// levels are reported as a phase's progress ([`crate::progress::step`]).
pub(super) fn assemble(
    verts: Vec<[f64; 3]>,
    mut raw: Vec<RawLevel>,
    srid: i32,
    grids: bool,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    let verts = reorder_vertices(verts, &mut raw);
    let bbox = Bbox::of(&verts);
    let mut tin = Tin {
        srid,
        bbox,
        verts,
        levels: Vec::with_capacity(raw.len()),
    };
    // the final position of each triangle of the previous level, by its
    // index in that level's `tris`
    let mut position: Vec<u32> = Vec::new();
    let n = raw.len() as u64;
    for (l, raw_level) in raw.into_iter().enumerate() {
        crate::progress::step("assembling the levels", "levels", l as u64, n);
        let RawLevel {
            tolerance,
            max_error,
            num_vertices,
            tris,
            parents,
            void,
        } = raw_level;
        // a triangle is void when its parent is; at level 0 when marked
        let prev_domain = match l {
            0 => 0,
            _ => tin.levels[l - 1].num_domain() as u32,
        };
        if !parents.is_empty() && parents.len() != tris.len() {
            return Err(TinError::Degenerate(format!(
                "internal: {} parents for {} triangles at level {l}",
                parents.len(),
                tris.len()
            )));
        }
        interrupt()?;
        let mut keyed = sort_keys(&tin, l, &tris, &parents, &void, &position, interrupt)?;
        // each copy gone as soon as the next is made: the last level's
        // arrays are the peak of a whole build
        drop(tris);
        drop(parents);
        interrupt()?;
        keyed.sort_unstable();
        interrupt()?;
        let tris: Vec<[u32; 3]> = keyed.iter().map(|k| k.2).collect();
        let num_void = if l == 0 {
            keyed.iter().filter(|k| k.0 == 1).count()
        } else {
            keyed.iter().filter(|k| k.0 >= prev_domain).count()
        } as u32;
        let parent: Vec<u32> = if l == 0 {
            vec![NONE; keyed.len()]
        } else {
            keyed.iter().map(|k| k.0).collect()
        };
        position = vec![0; keyed.len()];
        for (k, e) in keyed.iter().enumerate() {
            position[e.3 as usize] = k as u32;
        }
        drop(keyed);
        if l > 0 {
            let prev = &mut tin.levels[l - 1];
            prev.child_start = child_starts(&parent, prev.tris.len());
        }
        let nbrs = compute_neighbours(&tris)?;
        interrupt()?;
        let mut level = Level {
            tolerance,
            max_error,
            num_vertices,
            num_void,
            tris,
            nbrs,
            parent,
            child_start: Vec::new(),
            grid: crate::tin::Grid {
                cell: 1.0,
                nx: 0,
                ny: 0,
                cells: Vec::new(),
            },
            outline: Default::default(),
            hull: Default::default(),
        };
        if grids {
            level.grid = grid::build_grid(&tin.verts, &tin.bbox, &level);
        }
        tin.levels.push(level);
    }
    crate::progress::step("assembling the levels", "levels", n, n);
    Ok(tin)
}
