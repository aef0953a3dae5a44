//! Per-level grid index (Scarlatos §6.3): a regular grid over the bounding box with
//! about four cells per level vertex (so a cell holds at most about one
//! vertex and a walk from the cell's triangle takes one or two steps). Each
//! cell keeps the triangle containing its centre (or, for a centre outside
//! the domain, the hull triangle a walk towards it ended on), so point
//! location starts next to the answer.

use super::locate::{Walk, walk_raw};
use super::{Bbox, Grid, Level};

/// Cells per level vertex aimed at.
pub const CELLS_PER_VERTEX: f64 = 4.0;
/// Largest number of cells per level vertex (bounds the index's size).
pub const MAX_CELLS_PER_VERTEX: u64 = 8;

/// Cell size and dimensions for `nv` vertices over `b`.
pub(crate) fn grid_shape(b: &Bbox, nv: u32) -> (f64, u32, u32) {
    let w = (b.max_x - b.min_x).max(0.0);
    let h = (b.max_y - b.min_y).max(0.0);
    let nv = nv.max(1) as f64;
    let mut cell = (w * h / (CELLS_PER_VERTEX * nv)).sqrt();
    if !(cell.is_finite() && cell > 0.0) {
        cell = w.max(h).max(1e-9);
    }
    loop {
        let nx = ((w / cell).floor() + 1.0).max(1.0);
        let ny = ((h / cell).floor() + 1.0).max(1.0);
        if nx * ny <= MAX_CELLS_PER_VERTEX as f64 * nv + 16.0 {
            return (cell, nx as u32, ny as u32);
        }
        cell *= 1.25;
    }
}

/// Build the grid of `level` (whose triangles and neighbours are final).
pub(crate) fn build_grid(verts: &[[f64; 3]], b: &Bbox, level: &Level) -> Grid {
    let (cell, nx, ny) = grid_shape(b, level.num_vertices);
    let mut cells = Vec::with_capacity((nx * ny) as usize);
    let mut row_start = 0u32;
    for r in 0..ny {
        let y = b.min_y + (r as f64 + 0.5) * cell;
        let mut hint = row_start;
        for c in 0..nx {
            let x = b.min_x + (c as f64 + 0.5) * cell;
            let t = match walk_raw(verts, level, hint, x, y) {
                Walk::Inside(t) | Walk::Outside(t) => t,
            };
            if c == 0 {
                row_start = t;
            }
            hint = t;
            cells.push(t);
        }
    }
    Grid {
        cell,
        nx,
        ny,
        cells,
    }
}
