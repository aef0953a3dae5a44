//! A stored value (format 3) read block by block: point location fetches
//! the header once, then only the blocks holding the grid cells, triangles,
//! neighbours and vertices its walk touches, each verified against its own
//! checksum the first time it is read. The first point query on a large
//! terrain then costs a few blocks, not the whole value.
//!
//! The fetch is a callback (`offset, length -> bytes`): PostgreSQL's
//! `pg_detoast_datum_slice` in the extension, a slice of a `Vec` in tests.
//! Blocks stay in the [`SlicedTin`] (the extension keeps one per stored
//! value and bounds their number); [`SlicedTin::reader`] pairs it with the
//! fetch of the current call as a [`Mesh`], so the one exact walk of
//! [`super::locate`] runs on it.
//!
//! Only values written whole and validated reach a table (`tin_in`,
//! `tin_recv` and the builders check everything), so what a block can hold
//! is either what was written or damage, which its checksum catches. Every
//! id read is still range-checked, so nothing read can index out of bounds.
//!
//! ```
//! use tinmerge_core::tin::build::build;
//! use tinmerge_core::tin::{layout, locate, sliced::SlicedTin, TinError};
//! let mut pts = Vec::new();
//! for i in 0..60 { for j in 0..60 {
//!     pts.push([i as f64, j as f64, ((i * 7 + j * 13) % 11) as f64]);
//! } }
//! let tin = build(pts, &[2.0, 0.0], 0, &mut || Ok(())).unwrap();
//! let stored = layout::encode(&tin);
//! let s = SlicedTin::new(&stored[..layout::HEADER_LEN]).unwrap().unwrap();
//! let mut fetch = |at: u64, len: usize| -> Result<Vec<u8>, TinError> {
//!     Ok(stored[at as usize..at as usize + len].to_vec())
//! };
//! let r = s.reader(&mut fetch);
//! let t = locate::locate_in(&r, 1, 20.3, 31.7).unwrap();
//! assert_eq!(t, locate::locate(&tin, 1, 20.3, 31.7));
//! assert!(s.cached_bytes() < stored.len() / 4);
//! ```

use super::layout::{self, Header, LevelSections, BLOCK_PAYLOAD};
use super::mesh::{Indexed, Mesh};
use super::{Bbox, TinError, NONE};
use std::cell::{Cell, RefCell};
use std::collections::HashMap;

fn corrupt(s: impl Into<String>) -> TinError {
    TinError::Corrupt(s.into())
}

/// The fetch of the current call: `(offset in the value, length) -> bytes`.
pub type Fetch<'a> = dyn FnMut(u64, usize) -> Result<Vec<u8>, TinError> + 'a;

/// A format-3 value known by its header, with the blocks read so far.
pub struct SlicedTin {
    header: Header,
    header_hash: u64,
    body: u64,
    sections: Vec<LevelSections>,
    blocks: RefCell<HashMap<u64, Box<[u8]>>>,
    cached: Cell<usize>,
}

impl SlicedTin {
    /// From the first [`layout::HEADER_LEN`] bytes of a value; `None` for a
    /// format-1 value, which has one hash for the whole value and is read
    /// whole.
    pub fn new(head: &[u8]) -> Result<Option<SlicedTin>, TinError> {
        let header = layout::read_header(head)?;
        if header.version != layout::VERSION {
            return Ok(None);
        }
        let (body, sections) =
            layout::sections(&header).ok_or_else(|| corrupt("counts overflow"))?;
        let want = layout::HEADER_LEN as u64 + body + layout::num_blocks(body) * 8;
        if header.total_len != want {
            return Err(corrupt(format!(
                "length mismatch: header says {} bytes, its counts need {want}",
                header.total_len
            )));
        }
        Ok(Some(SlicedTin {
            header_hash: layout::stored_header_hash(head),
            header,
            body,
            sections,
            blocks: RefCell::new(HashMap::new()),
            cached: Cell::new(0),
        }))
    }

    pub fn header(&self) -> &Header {
        &self.header
    }

    /// Bytes of the blocks held.
    pub fn cached_bytes(&self) -> usize {
        self.cached.get()
    }

    /// Number of blocks held and in the value.
    pub fn blocks(&self) -> (usize, u64) {
        (self.blocks.borrow().len(), layout::num_blocks(self.body))
    }

    /// This value as a [`Mesh`], fetching missing blocks with `fetch`.
    pub fn reader<'a>(&'a self, fetch: &'a mut Fetch<'a>) -> Reader<'a> {
        Reader {
            s: self,
            fetch: RefCell::new(fetch),
        }
    }
}

/// A [`SlicedTin`] with the fetch of one call.
pub struct Reader<'a> {
    s: &'a SlicedTin,
    fetch: RefCell<&'a mut Fetch<'a>>,
}

impl Reader<'_> {
    /// `N` bytes at body offset `at` (an element may straddle two blocks:
    /// sections of the second and later levels start on 8-byte boundaries).
    fn read<const N: usize>(&self, at: u64) -> Result<[u8; N], TinError> {
        if at + N as u64 > self.s.body {
            return Err(corrupt("read past the end of the value"));
        }
        let mut out = [0u8; N];
        let mut done = 0usize;
        while done < N {
            let pos = at + done as u64;
            let k = pos / BLOCK_PAYLOAD as u64;
            let off = (pos % BLOCK_PAYLOAD as u64) as usize;
            let n = (N - done).min(BLOCK_PAYLOAD - off);
            self.with_block(k, |b| {
                let src = b
                    .get(off..off + n)
                    .ok_or_else(|| corrupt(format!("block {k} is shorter than its place")))?;
                out[done..done + n].copy_from_slice(src);
                Ok(())
            })?;
            done += n;
        }
        Ok(out)
    }

    /// Run `f` on the verified payload of block `k`, fetching it first if
    /// it is not held.
    fn with_block(
        &self,
        k: u64,
        f: impl FnOnce(&[u8]) -> Result<(), TinError>,
    ) -> Result<(), TinError> {
        let s = self.s;
        if let Some(b) = s.blocks.borrow().get(&k) {
            return f(b);
        }
        let (start, payload) = layout::block_at(s.body, k);
        let raw = (self.fetch.borrow_mut())(start, payload + 8)?;
        if raw.len() != payload + 8 {
            return Err(corrupt(format!(
                "block {k}: read {} bytes, expected {}",
                raw.len(),
                payload + 8
            )));
        }
        let data: Box<[u8]> = layout::check_block(s.header_hash, k, &raw)?.into();
        let r = f(&data);
        s.cached.set(s.cached.get() + data.len());
        s.blocks.borrow_mut().insert(k, data);
        r
    }

    fn u32s<const N: usize, const B: usize>(&self, at: u64) -> Result<[u32; N], TinError> {
        let b: [u8; B] = self.read(at)?;
        let mut out = [0u32; N];
        for (i, o) in out.iter_mut().enumerate() {
            *o = u32::from_le_bytes([b[4 * i], b[4 * i + 1], b[4 * i + 2], b[4 * i + 3]]);
        }
        Ok(out)
    }

    fn level(&self, level: usize) -> Result<&LevelSections, TinError> {
        self.s
            .sections
            .get(level)
            .ok_or_else(|| corrupt(format!("level {level} out of range")))
    }

    fn check_tri(&self, level: usize, t: u32) -> Result<(), TinError> {
        if (t as usize) < self.num_triangles(level) {
            Ok(())
        } else {
            Err(corrupt(format!(
                "triangle {t} out of range at level {level}"
            )))
        }
    }
}

impl Mesh for Reader<'_> {
    type Err = TinError;

    fn num_levels(&self) -> usize {
        self.s.header.levels.len()
    }

    fn num_triangles(&self, level: usize) -> usize {
        self.s
            .header
            .levels
            .get(level)
            .map_or(0, |l| l.num_triangles as usize)
    }

    fn tri(&self, level: usize, t: u32) -> Result<[u32; 3], TinError> {
        self.check_tri(level, t)?;
        let v = self.u32s::<3, 12>(self.level(level)?.tris + 12 * t as u64)?;
        if v.iter().any(|&i| i >= self.s.header.num_vertices) {
            return Err(corrupt(format!("vertex id out of range in triangle {t}")));
        }
        Ok(v)
    }

    fn nbrs(&self, level: usize, t: u32) -> Result<[u32; 3], TinError> {
        self.check_tri(level, t)?;
        let n = self.u32s::<3, 12>(self.level(level)?.nbrs + 12 * t as u64)?;
        let nt = self.num_triangles(level) as u32;
        if n.iter().any(|&i| i != NONE && i >= nt) {
            return Err(corrupt(format!(
                "neighbour id out of range in triangle {t}"
            )));
        }
        Ok(n)
    }

    fn num_vertices(&self) -> usize {
        self.s.header.num_vertices as usize
    }

    fn parent(&self, level: usize, t: u32) -> Result<u32, TinError> {
        self.check_tri(level, t)?;
        let [p] = self.u32s::<1, 4>(self.level(level)?.parents + 4 * t as u64)?;
        let ok = match level.checked_sub(1) {
            None => p == NONE,
            Some(up) => (p as usize) < self.num_triangles(up),
        };
        if !ok {
            return Err(corrupt(format!("parent of triangle {t} out of range")));
        }
        Ok(p)
    }

    /// By binary search in the next level's parents (sorted): O(log n)
    /// reads, a few blocks.
    fn children(&self, level: usize, t: u32) -> Result<std::ops::Range<u32>, TinError> {
        self.check_tri(level, t)?;
        let next = level + 1;
        if next >= self.s.sections.len() {
            return Ok(0..0);
        }
        let n = self.num_triangles(next) as u32;
        let at = self.level(next)?.parents;
        // first child whose parent is >= p
        let lower = |p: u32| -> Result<u32, TinError> {
            let (mut lo, mut hi) = (0u32, n);
            while lo < hi {
                let mid = lo + (hi - lo) / 2;
                let [q] = self.u32s::<1, 4>(at + 4 * mid as u64)?;
                if q < p {
                    lo = mid + 1;
                } else {
                    hi = mid;
                }
            }
            Ok(lo)
        };
        Ok(lower(t)?..lower(t + 1)?)
    }

    fn vert(&self, v: u32) -> Result<[f64; 3], TinError> {
        if v >= self.s.header.num_vertices {
            return Err(corrupt(format!("vertex {v} out of range")));
        }
        let b: [u8; 24] = self.read(24 * v as u64)?;
        let f = |i: usize| {
            let mut a = [0u8; 8];
            a.copy_from_slice(&b[8 * i..8 * i + 8]);
            f64::from_le_bytes(a)
        };
        Ok([f(0), f(1), f(2)])
    }
}

impl Indexed for Reader<'_> {
    fn bbox(&self) -> &Bbox {
        &self.s.header.bbox
    }

    fn grid(&self, level: usize) -> (f64, u32, u32) {
        match self.s.header.levels.get(level) {
            Some(l) if l.grid_nx > 0 && l.grid_ny > 0 => (l.grid_cell, l.grid_nx, l.grid_ny),
            _ => (0.0, 0, 0),
        }
    }

    fn cell(&self, level: usize, i: u32) -> Result<u32, TinError> {
        let (_, nx, ny) = self.grid(level);
        if i as u64 >= nx as u64 * ny as u64 {
            return Err(corrupt(format!("grid cell {i} out of range")));
        }
        let [t] = self.u32s::<1, 4>(self.level(level)?.cells + 4 * i as u64)?;
        self.check_tri(level, t)?;
        Ok(t)
    }
}
