//! A stored value (format 4, or 3) read group by group: point location
//! fetches the header once, then only the groups holding the grid cells,
//! triangles, neighbours and vertices its walk touches (format 4: the
//! directory entries and compressed groups; format 3: the 4 KB blocks
//! under a group of 128 elements), each verified against its own checksum
//! and decoded the first time it is read. The first point query on a large
//! terrain then costs a few groups, not the whole value.
//!
//! The fetch is a callback (`offset, length -> bytes`): PostgreSQL's
//! `pg_detoast_datum_slice` in the extension, a slice of a `Vec` in tests.
//! Decoded groups stay in the [`SlicedTin`] (the extension keeps one per
//! stored value and bounds their number); [`SlicedTin::reader`] pairs it with the
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
//! let (held, total) = s.blocks();
//! assert!((held as u64) < total); // only the groups the walk touched
//! ```

use super::compact::{Group, Plan, Stream};
use super::layout::{self, BLOCK_PAYLOAD, Header, LevelSections};
use super::mesh::{Indexed, Mesh};
use super::{Bbox, NONE, TinError};
use rustc_hash::FxHashMap as HashMap;
use std::cell::{Cell, RefCell};
use std::rc::Rc;

/// The fetch of the current call: `(offset in the value, length) -> bytes`.
pub type Fetch<'a> = dyn FnMut(u64, usize) -> Result<Vec<u8>, TinError> + 'a;

/// Elements per group read from a format-3 value (cells: 4x).
const V3_GROUP: usize = 128;
/// Directory entries per directory page read at once (format 4).
const DIR_PAGE: u64 = 1024;

/// Where the groups are.
enum Kind {
    /// Format 3: elements at fixed places in the blocked body.
    V3 {
        body: u64,
        sections: Vec<LevelSections>,
    },
    /// Format 4: a directory, then the groups.
    V4 {
        /// Pages of the directory read so far.
        pages: RefCell<HashMap<u64, Rc<[u32]>>>,
    },
}

/// A format-3 or -4 value known by its header, with the groups read so
/// far.
pub struct SlicedTin {
    header: Header,
    header_hash: u64,
    plan: Plan,
    kind: Kind,
    groups: RefCell<HashMap<u64, Rc<Group>>>,
    cached: Cell<usize>,
    /// Reads in whole units of the storage under the fetch (0: exact
    /// reads), with `ahead` more units after a missing one.
    unit: u64,
    ahead: u64,
    /// Units read so far (by unit number).
    units: RefCell<HashMap<u64, Rc<[u8]>>>,
}

impl SlicedTin {
    /// From the first [`layout::HEADER_LEN`] bytes of a value; `None` for a
    /// format-1 value, which has one hash for the whole value and is read
    /// whole.
    pub fn new(head: &[u8]) -> Result<Option<SlicedTin>, TinError> {
        let header = layout::read_header(head)?;
        let counts = header.level_counts();
        let (plan, kind) = match header.version {
            v if layout::is_compact(v) => {
                let plan = layout::plan(&header);
                // the directory and a checksummed byte per group at least
                let least = (header.header_len() as u64)
                    .saturating_add(plan.num_groups().saturating_mul(13));
                if header.total_len < least {
                    return Err(TinError::corrupt(format!(
                        "length mismatch: header says {} bytes, its groups need at least {least}",
                        header.total_len
                    )));
                }
                (
                    plan,
                    Kind::V4 {
                        pages: RefCell::new(HashMap::default()),
                    },
                )
            }
            layout::VERSION_3 => {
                let (body, sections) = layout::sections(&header)
                    .ok_or_else(|| TinError::corrupt("counts overflow"))?;
                let want = layout::HEADER_LEN_V3 as u64 + body + layout::num_blocks(body) * 8;
                if header.total_len != want {
                    return Err(TinError::corrupt(format!(
                        "length mismatch: header says {} bytes, its counts need {want}",
                        header.total_len
                    )));
                }
                (
                    Plan::sized(
                        header.num_vertices as usize,
                        &counts,
                        V3_GROUP,
                        V3_GROUP,
                        4 * V3_GROUP,
                    ),
                    Kind::V3 { body, sections },
                )
            }
            _ => return Ok(None),
        };
        Ok(Some(SlicedTin {
            header_hash: layout::stored_header_hash(head),
            header,
            plan,
            kind,
            groups: RefCell::new(HashMap::default()),
            cached: Cell::new(0),
            unit: 0,
            ahead: 0,
            units: RefCell::new(HashMap::default()),
        }))
    }

    /// Read whole units of `unit` bytes of the value (the TOAST chunk size
    /// in the extension: a slice costs the chunks it touches, so the rest
    /// of a touched chunk is free), keeping them for the groups that
    /// follow, and `ahead` more units after a missing one (groups of one
    /// array are stored in spatial order, so a query's next group is
    /// often the next one). `unit` 0 reads exactly the bytes asked for.
    ///
    /// ```
    /// # use tinmerge_core::tin::build::build;
    /// # use tinmerge_core::tin::{layout, locate, sliced::SlicedTin, TinError};
    /// # let mut pts = Vec::new();
    /// # for i in 0..60 { for j in 0..60 {
    /// #     pts.push([i as f64, j as f64, ((i * 7 + j * 13) % 11) as f64]);
    /// # } }
    /// # let tin = build(pts, &[2.0, 0.0], 0, &mut || Ok(())).unwrap();
    /// let stored = layout::encode(&tin);
    /// let s = SlicedTin::new(&stored[..layout::HEADER_LEN])
    ///     .unwrap()
    ///     .unwrap()
    ///     .with_units(1996, 1);
    /// let mut calls = 0;
    /// let mut fetch = |at: u64, len: usize| -> Result<Vec<u8>, TinError> {
    ///     assert_eq!(at % 1996, 0);
    ///     calls += 1;
    ///     Ok(stored[at as usize..at as usize + len].to_vec())
    /// };
    /// let r = s.reader(&mut fetch);
    /// assert_eq!(locate::locate_in(&r, 1, 20.3, 31.7).unwrap(), locate::locate(&tin, 1, 20.3, 31.7));
    /// ```
    pub fn with_units(mut self, unit: u64, ahead: u64) -> SlicedTin {
        self.unit = unit;
        self.ahead = ahead;
        self
    }

    /// How many bytes at the start of the value hold its header and, in
    /// format 4, its group directory: a reader that fetches them first
    /// (see [`SlicedTin::with_prefix`]) finds every group without reading
    /// the directory page by page.
    pub fn prefix_len(header: &Header) -> u64 {
        let end = match header.version {
            v if layout::is_compact(v) => (header.header_len() as u64)
                .saturating_add(layout::plan(header).num_groups().saturating_mul(4)),
            _ => layout::HEADER_LEN as u64,
        };
        end.min(header.total_len)
    }

    /// Keep `bytes`, the first bytes of the value (read with the header),
    /// as units already read (only with [`SlicedTin::with_units`]; a
    /// partial last unit is kept only when it ends the value).
    pub fn with_prefix(self, bytes: &[u8]) -> SlicedTin {
        self.keep_units(0, bytes);
        self
    }

    /// Keep `bytes`, read from the start of unit `first`, as the units
    /// they hold (not already held): whole units, and a partial last one
    /// only when it ends the value. Nothing without units.
    fn keep_units(&self, first: u64, bytes: &[u8]) {
        let unit = self.unit;
        if unit == 0 {
            return;
        }
        let mut units = self.units.borrow_mut();
        for (i, piece) in bytes.chunks(unit as usize).enumerate() {
            let c = first + i as u64;
            let ends_value = c * unit + piece.len() as u64 == self.header.total_len;
            if (piece.len() as u64 == unit || ends_value)
                && let std::collections::hash_map::Entry::Vacant(e) = units.entry(c)
            {
                self.cached.set(self.cached.get() + piece.len());
                e.insert(Rc::from(piece));
            }
        }
    }

    pub fn header(&self) -> &Header {
        &self.header
    }

    /// Bytes of the decoded groups (and directory pages) held.
    pub fn cached_bytes(&self) -> usize {
        self.cached.get()
    }

    /// Number of groups held and in the value.
    pub fn blocks(&self) -> (usize, u64) {
        (self.groups.borrow().len(), self.plan.num_groups())
    }

    /// This value as a [`Mesh`], fetching missing groups with `fetch`.
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
    /// Bytes `at..at + len` of the value, through the units held (see
    /// [`SlicedTin::with_units`]).
    fn fetch(&self, at: u64, len: usize) -> Result<Vec<u8>, TinError> {
        let (unit, total) = (self.s.unit, self.s.header.total_len);
        if unit == 0 || len == 0 {
            return self.fetch_exact(at, len);
        }
        let end = at
            .checked_add(len as u64)
            .filter(|&e| e <= total)
            .ok_or_else(|| {
                TinError::corrupt(format!("read of {len} bytes at {at} past the value's end"))
            })?;
        let (c0, c1) = (at / unit, (end - 1) / unit);
        let missing: Vec<u64> = {
            let units = self.s.units.borrow();
            (c0..=c1).filter(|c| !units.contains_key(c)).collect()
        };
        if let (Some(&m0), Some(&m1)) = (missing.first(), missing.last()) {
            // the missing units, and up to `ahead` more not held yet
            let last_unit = (total - 1) / unit;
            let mut m_end = m1;
            {
                let units = self.s.units.borrow();
                while m_end < last_unit
                    && m_end < m1 + self.s.ahead
                    && !units.contains_key(&(m_end + 1))
                {
                    m_end += 1;
                }
            }
            let from = m0 * unit;
            let to = ((m_end + 1) * unit).min(total);
            let raw = self.fetch_exact(from, (to - from) as usize)?;
            self.s.keep_units(m0, &raw);
        }
        let units = self.s.units.borrow();
        let mut out = Vec::with_capacity(len);
        for c in c0..=c1 {
            let u = units
                .get(&c)
                .ok_or_else(|| TinError::corrupt(format!("unit {c} of the value was not read")))?;
            let lo = at.max(c * unit) - c * unit;
            let hi = end.min((c + 1) * unit) - c * unit;
            out.extend_from_slice(
                u.get(lo as usize..hi as usize)
                    .ok_or_else(|| TinError::corrupt(format!("unit {c} of the value is short")))?,
            );
        }
        Ok(out)
    }

    fn fetch_exact(&self, at: u64, len: usize) -> Result<Vec<u8>, TinError> {
        let raw = (self.fetch.borrow_mut())(at, len)?;
        if raw.len() != len {
            return Err(TinError::corrupt(format!(
                "read {} bytes at {at}, expected {len}",
                raw.len()
            )));
        }
        Ok(raw)
    }

    /// Element `i` of stream `s`, through `f` on its decoded group and
    /// its place there.
    fn with<T>(
        &self,
        s: Stream,
        i: usize,
        f: impl Fn(&Group, usize) -> Option<T>,
    ) -> Result<T, TinError> {
        let (k, first, n) = self
            .s
            .plan
            .group_of(s, i)
            .ok_or_else(|| TinError::corrupt(format!("element {i} of {s:?} out of range")))?;
        let found = {
            let groups = self.s.groups.borrow();
            groups.get(&k).map(|g| f(g, i - first))
        };
        let v = match found {
            Some(v) => v,
            None => {
                let g = Rc::new(self.load(s, k, first, n)?);
                self.s.cached.set(self.s.cached.get() + g.bytes());
                self.s.groups.borrow_mut().insert(k, g.clone());
                f(&g, i - first)
            }
        };
        v.ok_or_else(|| TinError::corrupt(format!("group {k} does not hold {s:?} {i}")))
    }

    /// Read, check and decode group `k` (elements `first..first + n` of
    /// `s`).
    fn load(&self, s: Stream, k: u64, first: usize, n: usize) -> Result<Group, TinError> {
        let h = &self.s.header;
        match &self.s.kind {
            Kind::V4 { pages } => {
                let (start, end) = self.group_place(pages, k)?;
                let raw = self.fetch(start, (end - start) as usize)?;
                layout::open_group(h, self.s.header_hash, k, &raw, s, first, n)
            }
            Kind::V3 { body, sections } => {
                let (at, size) = match s {
                    Stream::Verts => (0, 24),
                    Stream::Tris(l) => (sec(sections, l)?.tris, 12),
                    Stream::Nbrs(l) => (sec(sections, l)?.nbrs, 12),
                    Stream::Parents(l) => (sec(sections, l)?.parents, 4),
                    Stream::Cells(l) => (sec(sections, l)?.cells, 4),
                };
                let b = self.v3_bytes(*body, at + (first * size) as u64, n * size)?;
                let u32_at = |o: usize| u32::from_le_bytes([b[o], b[o + 1], b[o + 2], b[o + 3]]);
                Ok(match s {
                    Stream::Verts => Group::Verts(
                        b.chunks_exact(24)
                            .map(|v| {
                                let f = |j: usize| {
                                    let mut a = [0u8; 8];
                                    a.copy_from_slice(&v[8 * j..8 * j + 8]);
                                    f64::from_le_bytes(a)
                                };
                                [f(0), f(1), f(2)]
                            })
                            .collect(),
                    ),
                    Stream::Tris(_) | Stream::Nbrs(_) => Group::Triples(
                        (0..n)
                            .map(|e| [u32_at(12 * e), u32_at(12 * e + 4), u32_at(12 * e + 8)])
                            .collect(),
                    ),
                    Stream::Parents(_) | Stream::Cells(_) => {
                        Group::Ids((0..n).map(|e| u32_at(4 * e)).collect())
                    }
                })
            }
        }
    }

    /// Value offsets of format-4 group `k` (payload and checksum), from
    /// its directory entry and the one before.
    fn group_place(
        &self,
        pages: &RefCell<HashMap<u64, Rc<[u32]>>>,
        k: u64,
    ) -> Result<(u64, u64), TinError> {
        let ng = self.s.plan.num_groups();
        let hl = self.s.header.header_len() as u64;
        let data = hl + 4 * ng;
        let entry = |e: u64| -> Result<u64, TinError> {
            let p = e / DIR_PAGE;
            let held = pages.borrow().get(&p).cloned();
            let page = match held {
                Some(pg) => pg,
                None => {
                    let n = DIR_PAGE.min(ng - p * DIR_PAGE) as usize;
                    let raw = self.fetch(hl + 4 * p * DIR_PAGE, 4 * n)?;
                    let pg: Rc<[u32]> = raw
                        .chunks_exact(4)
                        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                        .collect();
                    self.s.cached.set(self.s.cached.get() + 4 * n);
                    pages.borrow_mut().insert(p, pg.clone());
                    pg
                }
            };
            Ok(page.get((e % DIR_PAGE) as usize).copied().unwrap_or(0) as u64)
        };
        let end = entry(k)?;
        let start = if k == 0 { 0 } else { entry(k - 1)? };
        layout::group_place(k, data, start, end, self.s.header.total_len)
    }

    /// `len` bytes of a format-3 body at `at`, from the blocks under them
    /// (each checked).
    fn v3_bytes(&self, body: u64, at: u64, len: usize) -> Result<Vec<u8>, TinError> {
        if at + len as u64 > body {
            return Err(TinError::corrupt("read past the end of the value"));
        }
        let mut out = Vec::with_capacity(len);
        let (first, last) = (
            at / BLOCK_PAYLOAD as u64,
            (at + len as u64 - 1) / BLOCK_PAYLOAD as u64,
        );
        for k in first..=last {
            let (start, payload) = layout::block_at(body, k);
            let raw = self.fetch(start, payload + 8)?;
            let data = layout::check_block(self.s.header_hash, k, &raw)?;
            let b0 = k * BLOCK_PAYLOAD as u64;
            let lo = at.max(b0) - b0;
            let hi = (at + len as u64).min(b0 + payload as u64) - b0;
            let piece = data
                .get(lo as usize..hi as usize)
                .ok_or_else(|| TinError::corrupt(format!("block {k} is shorter than its place")))?;
            out.extend_from_slice(piece);
        }
        Ok(out)
    }

    fn check_tri(&self, level: usize, t: u32) -> Result<(), TinError> {
        if (t as usize) < self.num_triangles(level) {
            Ok(())
        } else {
            Err(TinError::corrupt(format!(
                "triangle {t} out of range at level {level}"
            )))
        }
    }

    fn triple(&self, s: Stream, t: u32) -> Result<[u32; 3], TinError> {
        self.with(s, t as usize, |g, j| match g {
            Group::Triples(v) => v.get(j).copied(),
            _ => None,
        })
    }

    fn id(&self, s: Stream, i: u32) -> Result<u32, TinError> {
        self.with(s, i as usize, |g, j| match g {
            Group::Ids(v) => v.get(j).copied(),
            _ => None,
        })
    }
}

fn sec(sections: &[LevelSections], l: usize) -> Result<&LevelSections, TinError> {
    sections
        .get(l)
        .ok_or_else(|| TinError::corrupt(format!("level {l} out of range")))
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
    fn num_domain(&self, level: usize) -> usize {
        self.s.header.levels.get(level).map_or(0, |l| {
            (l.num_triangles as usize).saturating_sub(l.num_void as usize)
        })
    }

    fn tri(&self, level: usize, t: u32) -> Result<[u32; 3], TinError> {
        self.check_tri(level, t)?;
        let v = self.triple(Stream::Tris(level), t)?;
        if v.iter().any(|&i| i >= self.s.header.num_vertices) {
            return Err(TinError::corrupt(format!(
                "vertex id out of range in triangle {t}"
            )));
        }
        Ok(v)
    }

    fn nbrs(&self, level: usize, t: u32) -> Result<[u32; 3], TinError> {
        self.check_tri(level, t)?;
        let n = self.triple(Stream::Nbrs(level), t)?;
        let nt = self.num_triangles(level) as u32;
        if n.iter().any(|&i| i != NONE && i >= nt) {
            return Err(TinError::corrupt(format!(
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
        let p = self.id(Stream::Parents(level), t)?;
        let ok = match level.checked_sub(1) {
            None => p == NONE,
            Some(up) => (p as usize) < self.num_triangles(up),
        };
        if !ok {
            return Err(TinError::corrupt(format!(
                "parent of triangle {t} out of range"
            )));
        }
        Ok(p)
    }

    /// By search in the next level's parents (sorted), starting where
    /// `t`'s children would be if every triangle had as many (children are
    /// in parent order): galloping from there brackets them in a few
    /// reads, in the groups that hold them, where a binary search over the
    /// whole level would read a group at each of its first steps.
    fn children(&self, level: usize, t: u32) -> Result<std::ops::Range<u32>, TinError> {
        self.check_tri(level, t)?;
        let next = level + 1;
        if next >= self.num_levels() {
            return Ok(0..0);
        }
        let n = self.num_triangles(next) as u64;
        let np = self.num_triangles(level).max(1) as u64;
        let parent = |i: u64| self.id(Stream::Parents(next), i as u32);
        // first child whose parent is >= p: gallop from the estimate to a
        // bracket [lo, hi) with parent(lo - 1) < p <= parent(hi), then bisect
        let lower = |p: u32| -> Result<u32, TinError> {
            let guess = (p as u64 * n / np).min(n);
            let (mut lo, mut hi);
            if guess < n && parent(guess)? < p {
                // forward: parent(lo - 1) < p
                lo = guess + 1;
                let mut step = 1u64;
                loop {
                    let probe = lo + step - 1;
                    if probe >= n {
                        hi = n;
                        break;
                    }
                    if parent(probe)? >= p {
                        hi = probe;
                        break;
                    }
                    lo = probe + 1;
                    step *= 2;
                }
            } else {
                // backward: parent(hi) >= p (or hi = n)
                hi = guess;
                let mut step = 1u64;
                loop {
                    if hi < step {
                        lo = 0;
                        break;
                    }
                    let probe = hi - step;
                    if parent(probe)? < p {
                        lo = probe + 1;
                        break;
                    }
                    hi = probe;
                    step *= 2;
                }
            }
            while lo < hi {
                let mid = lo + (hi - lo) / 2;
                if parent(mid)? < p {
                    lo = mid + 1;
                } else {
                    hi = mid;
                }
            }
            Ok(lo as u32)
        };
        Ok(lower(t)?..lower(t + 1)?)
    }

    fn vert(&self, v: u32) -> Result<[f64; 3], TinError> {
        if v >= self.s.header.num_vertices {
            return Err(TinError::corrupt(format!("vertex {v} out of range")));
        }
        self.with(Stream::Verts, v as usize, |g, j| match g {
            Group::Verts(x) => x.get(j).copied(),
            _ => None,
        })
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
            return Err(TinError::corrupt(format!("grid cell {i} out of range")));
        }
        let t = self.id(Stream::Cells(level), i)?;
        self.check_tri(level, t)?;
        Ok(t)
    }
}
