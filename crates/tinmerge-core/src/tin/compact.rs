//! The compact body of storage format 4: every array of a tin (vertices;
//! per level triangles, neighbours, parents and grid cells) cut into groups
//! of a fixed number of elements, each group coded on its own, compressed
//! with zstd and sealed with its own checksum, so a reader decodes exactly
//! the groups a merge touches.
//!
//! Codings inside a group (before zstd):
//! - **vertices** of a raster build: column and row on the pixel lattice
//!   (zig-zag deltas from the previous vertex, LEB128 varints), then the
//!   heights as `f32` when every height is a float32 value (any float32 or
//!   integer band), else `f64`. World coordinates come back through
//!   [`Lattice::centre`], the one formula the build used, so they are
//!   bit-identical. Other vertices (point builds, overlays): raw `f64`.
//! - **triangles**: each vertex id as its place in a move-to-front cache of
//!   the last 16 ids (one byte), or, on a miss, the zig-zag delta from the
//!   previous missed id (one byte when small, else an escape and a varint).
//!   Triangles are sorted by parent and then in Morton order, so most
//!   corners are corners of the triangles just before.
//! - **neighbours**: `0` for none, else zig-zag(`n - t`) + 1, as varints.
//! - **parents**: zig-zag delta of `parent + 1` (0 for none) from the
//!   previous one (parents are sorted: mostly 0 or 1).
//! - **grid cells**: zig-zag delta from the previous cell.
//!
//! A group starts with one byte: 0 = the coding stored as it is, 1 = zstd.
//!
//! ```
//! use tinmerge_core::tin::compact::{varint, read_varint, zigzag, unzigzag};
//! let mut b = Vec::new();
//! varint(&mut b, zigzag(-300));
//! let mut at = 0;
//! assert_eq!(unzigzag(read_varint(&b, &mut at).unwrap()), -300);
//! assert_eq!(at, b.len());
//! ```

use super::lattice::Lattice;
use super::{NONE, TinError};
use std::cell::RefCell;

/// Triangles (and their neighbours and parents) per group.
pub const GROUP: usize = 512;
/// Vertices per group (the corners of one triangle are often in groups of
/// different levels: small groups keep what a point query holds small).
pub const VERT_GROUP: usize = 256;
/// Grid cells per group.
pub const CELL_GROUP: usize = 2048;
/// zstd level of the groups (decoding speed does not depend on it).
const ZSTD_LEVEL: i32 = 3;
/// Move-to-front cache of the triangle coding.
const CACHE: usize = 16;

/// How the vertices of a format-4 value are coded (stored in its header).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VertexCoding {
    /// x, y, z as `f64`.
    Raw = 0,
    /// Lattice column and row, z as `f32`.
    LatticeF32 = 1,
    /// Lattice column and row, z as `f64`.
    LatticeF64 = 2,
}

impl VertexCoding {
    pub(crate) fn from_u32(v: u32) -> Option<VertexCoding> {
        match v {
            0 => Some(VertexCoding::Raw),
            1 => Some(VertexCoding::LatticeF32),
            2 => Some(VertexCoding::LatticeF64),
            _ => None,
        }
    }
}

/// One array of a tin, as format 4 stores it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Stream {
    Verts,
    Tris(usize),
    Nbrs(usize),
    Parents(usize),
    Cells(usize),
}

/// The groups of a value: how many each array has and where its first one
/// is in the value's list of groups (vertices first, then per level
/// triangles, neighbours, parents and cells).
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// (stream, elements, first group)
    streams: Vec<(Stream, usize, u64)>,
    total: u64,
    per: usize,
    per_vert: usize,
    per_cell: usize,
}

impl Plan {
    /// From the counts: vertices, and per level triangles and grid cells
    /// (groups of [`GROUP`], [`VERT_GROUP`] and [`CELL_GROUP`]).
    pub fn new(num_vertices: usize, levels: &[(usize, usize)]) -> Plan {
        Plan::sized(num_vertices, levels, GROUP, VERT_GROUP, CELL_GROUP)
    }

    /// [`Plan::new`] with other group sizes (`per` triangles, `per_vert`
    /// vertices, `per_cell` cells; each at least 1).
    pub fn sized(
        num_vertices: usize,
        levels: &[(usize, usize)],
        per: usize,
        per_vert: usize,
        per_cell: usize,
    ) -> Plan {
        let (per, per_vert, per_cell) = (per.max(1), per_vert.max(1), per_cell.max(1));
        let mut streams = Vec::with_capacity(1 + 4 * levels.len());
        let mut total = 0u64;
        let mut push = |s: Stream, n: usize| {
            streams.push((s, n, total));
            let p = match s {
                Stream::Cells(_) => per_cell,
                Stream::Verts => per_vert,
                _ => per,
            };
            total += n.div_ceil(p) as u64;
        };
        push(Stream::Verts, num_vertices);
        for (l, &(t, c)) in levels.iter().enumerate() {
            push(Stream::Tris(l), t);
            push(Stream::Nbrs(l), t);
            push(Stream::Parents(l), t);
            push(Stream::Cells(l), c);
        }
        Plan {
            streams,
            total,
            per,
            per_vert,
            per_cell,
        }
    }

    /// Elements per group of `s`.
    pub(crate) fn per_group(&self, s: Stream) -> usize {
        match s {
            Stream::Cells(_) => self.per_cell,
            Stream::Verts => self.per_vert,
            _ => self.per,
        }
    }

    /// Every group: (stream, first element, elements, group number), in
    /// storage order.
    pub fn groups(&self) -> Vec<(Stream, usize, usize, u64)> {
        let mut out = Vec::with_capacity(self.total as usize);
        for &(s, n, g0) in &self.streams {
            let per = self.per_group(s);
            for (k, first) in (0..n).step_by(per).enumerate() {
                out.push((s, first, per.min(n - first), g0 + k as u64));
            }
        }
        out
    }

    /// Number of groups of the value.
    pub(crate) fn num_groups(&self) -> u64 {
        self.total
    }

    fn find(&self, s: Stream) -> Option<&(Stream, usize, u64)> {
        // `sized` pushes the vertices, then per level triangles,
        // neighbours, parents and cells: the place follows from the stream
        let at = match s {
            Stream::Verts => Some(0),
            Stream::Tris(l) => l.checked_mul(4).map(|x| x + 1),
            Stream::Nbrs(l) => l.checked_mul(4).map(|x| x + 2),
            Stream::Parents(l) => l.checked_mul(4).map(|x| x + 3),
            Stream::Cells(l) => l.checked_mul(4).map(|x| x + 4),
        }?;
        self.streams.get(at).filter(|e| e.0 == s)
    }

    /// The group holding element `i` of `s`: (group number in the value,
    /// first element of the group, elements in the group), or None when
    /// `i` is out of range.
    pub(crate) fn group_of(&self, s: Stream, i: usize) -> Option<(u64, usize, usize)> {
        let &(_, n, first) = self.find(s)?;
        if i >= n {
            return None;
        }
        let per = self.per_group(s);
        let k = i / per;
        let start = k * per;
        Some((first + k as u64, start, per.min(n - start)))
    }
}

/// Append `v` as an LEB128 varint.
pub fn varint(out: &mut Vec<u8>, mut v: u64) {
    loop {
        let b = (v & 0x7f) as u8;
        v >>= 7;
        if v == 0 {
            out.push(b);
            return;
        }
        out.push(b | 0x80);
    }
}

/// Read an LEB128 varint at `*at`, advancing it.
pub fn read_varint(b: &[u8], at: &mut usize) -> Result<u64, TinError> {
    let mut v = 0u64;
    for shift in (0..64).step_by(7) {
        let byte = *b
            .get(*at)
            .ok_or_else(|| TinError::corrupt("group ends inside a number"))?;
        *at += 1;
        v |= ((byte & 0x7f) as u64) << shift;
        if byte & 0x80 == 0 {
            return Ok(v);
        }
    }
    Err(TinError::corrupt("number longer than 64 bits in a group"))
}

pub fn zigzag(v: i64) -> u64 {
    ((v << 1) ^ (v >> 63)) as u64
}

pub fn unzigzag(v: u64) -> i64 {
    ((v >> 1) as i64) ^ -((v & 1) as i64)
}

/// The lattice column and row of every vertex, when every vertex is
/// exactly the centre [`Lattice::centre`] gives for whole numbers (what a
/// raster build makes); None otherwise.
pub(crate) fn lattice_indices(lat: &Lattice, verts: &[[f64; 3]]) -> Option<Vec<[i32; 2]>> {
    if !lat.is_valid() {
        return None;
    }
    let det = lat.det();
    verts
        .iter()
        .map(|v| {
            let (dx, dy) = (v[0] - lat.ip_x, v[1] - lat.ip_y);
            let c = (lat.scale_y * dx - lat.skew_x * dy) / det - 0.5;
            let r = (lat.scale_x * dy - lat.skew_y * dx) / det - 0.5;
            if !(c.abs() < 2e9 && r.abs() < 2e9) {
                return None;
            }
            let (c, r) = (c.round(), r.round());
            (lat.centre(c, r) == (v[0], v[1])).then_some([c as i32, r as i32])
        })
        .collect()
}

/// How to code these vertices given the build's lattice (if any).
pub fn vertex_coding(lat: Option<&Lattice>, verts: &[[f64; 3]]) -> VertexCoding {
    match lat.and_then(|l| lattice_indices(l, verts)) {
        None => VertexCoding::Raw,
        Some(_) if verts.iter().all(|v| (v[2] as f32) as f64 == v[2]) => VertexCoding::LatticeF32,
        Some(_) => VertexCoding::LatticeF64,
    }
}

/// Code one group of vertices (`idx`: their lattice indices, for the
/// lattice codings).
pub fn encode_verts(verts: &[[f64; 3]], idx: Option<&[[i32; 2]]>, coding: VertexCoding) -> Vec<u8> {
    let mut out = Vec::with_capacity(verts.len() * 8);
    match (coding, idx) {
        (VertexCoding::Raw, _) | (_, None) => {
            for v in verts {
                for c in v {
                    out.extend_from_slice(&c.to_le_bytes());
                }
            }
        }
        (_, Some(idx)) => {
            let (mut pc, mut pr) = (0i64, 0i64);
            for &[c, r] in idx {
                varint(&mut out, zigzag(c as i64 - pc));
                varint(&mut out, zigzag(r as i64 - pr));
                (pc, pr) = (c as i64, r as i64);
            }
            for v in verts {
                if coding == VertexCoding::LatticeF32 {
                    out.extend_from_slice(&(v[2] as f32).to_le_bytes());
                } else {
                    out.extend_from_slice(&v[2].to_le_bytes());
                }
            }
        }
    }
    out
}

/// Decode `n` vertices coded by [`encode_verts`].
pub(crate) fn decode_verts(
    b: &[u8],
    n: usize,
    coding: VertexCoding,
    lat: Option<&Lattice>,
) -> Result<Vec<[f64; 3]>, TinError> {
    let mut out = Vec::with_capacity(n);
    let f64_at = |at: usize| -> Result<f64, TinError> {
        b.get(at..at + 8)
            .and_then(|s| s.try_into().ok())
            .map(f64::from_le_bytes)
            .ok_or_else(|| TinError::corrupt("vertex group is truncated"))
    };
    let used = match (coding, lat) {
        (VertexCoding::Raw, _) => {
            for i in 0..n {
                out.push([f64_at(24 * i)?, f64_at(24 * i + 8)?, f64_at(24 * i + 16)?]);
            }
            24 * n
        }
        (_, None) => {
            return Err(TinError::corrupt(
                "lattice-coded vertices without a lattice",
            ));
        }
        (_, Some(lat)) => {
            let mut at = 0usize;
            let (mut c, mut r) = (0i64, 0i64);
            let mut cr = Vec::with_capacity(n);
            for _ in 0..n {
                c = c.wrapping_add(unzigzag(read_varint(b, &mut at)?));
                r = r.wrapping_add(unzigzag(read_varint(b, &mut at)?));
                if c.abs() > i32::MAX as i64 || r.abs() > i32::MAX as i64 {
                    return Err(TinError::corrupt("lattice index out of range"));
                }
                cr.push((c as f64, r as f64));
            }
            for (i, (c, r)) in cr.into_iter().enumerate() {
                let (x, y) = lat.centre(c, r);
                let z = if coding == VertexCoding::LatticeF32 {
                    let s = b
                        .get(at + 4 * i..at + 4 * i + 4)
                        .and_then(|s| s.try_into().ok())
                        .map(f32::from_le_bytes)
                        .ok_or_else(|| TinError::corrupt("vertex group is truncated"))?;
                    s as f64
                } else {
                    f64_at(at + 8 * i)?
                };
                out.push([x, y, z]);
            }
            at + n * if coding == VertexCoding::LatticeF32 {
                4
            } else {
                8
            }
        }
    };
    if used != b.len() {
        return Err(TinError::corrupt("vertex group has bytes left over"));
    }
    Ok(out)
}

/// Code one group of triangles.
pub fn encode_tris(tris: &[[u32; 3]]) -> Vec<u8> {
    let mut out = Vec::with_capacity(tris.len() * 4);
    let mut cache: Vec<u32> = Vec::with_capacity(CACHE + 1);
    let mut last = 0i64;
    for t in tris {
        for &v in t {
            if let Some(i) = cache.iter().position(|&c| c == v) {
                out.push(i as u8);
                cache.remove(i);
            } else {
                let d = zigzag(v as i64 - last);
                last = v as i64;
                if d < (127 - CACHE) as u64 {
                    out.push(CACHE as u8 + d as u8);
                } else {
                    out.push(127);
                    varint(&mut out, d);
                }
            }
            cache.insert(0, v);
            cache.truncate(CACHE);
        }
    }
    out
}

/// Decode `n` triangles coded by [`encode_tris`].
pub(crate) fn decode_tris(b: &[u8], n: usize) -> Result<Vec<[u32; 3]>, TinError> {
    let mut out = Vec::with_capacity(n);
    // the move-to-front cache of the encoder, in a fixed array
    let mut cache = [0u32; CACHE];
    let mut held = 0usize;
    let mut last = 0i64;
    let mut at = 0usize;
    for _ in 0..n {
        let mut t = [0u32; 3];
        for v in t.iter_mut() {
            let code = *b
                .get(at)
                .ok_or_else(|| TinError::corrupt("triangle group is truncated"))?;
            at += 1;
            let id = if (code as usize) < CACHE {
                let i = code as usize;
                if i >= held {
                    return Err(TinError::corrupt(
                        "triangle group refers to an empty cache slot",
                    ));
                }
                let id = cache[i];
                cache.copy_within(0..i, 1);
                id
            } else {
                let d = if code == 127 {
                    read_varint(b, &mut at)?
                } else if code < 127 {
                    (code as usize - CACHE) as u64
                } else {
                    return Err(TinError::corrupt(format!(
                        "bad code {code} in a triangle group"
                    )));
                };
                last = last.wrapping_add(unzigzag(d));
                if !(0..NONE as i64).contains(&last) {
                    return Err(TinError::corrupt(
                        "vertex id out of range in a triangle group",
                    ));
                }
                cache.copy_within(0..CACHE - 1, 1);
                held = (held + 1).min(CACHE);
                last as u32
            };
            cache[0] = id;
            *v = id;
        }
        out.push(t);
    }
    if at != b.len() {
        return Err(TinError::corrupt("triangle group has bytes left over"));
    }
    Ok(out)
}

/// Code one group of neighbour links; `first` is the id of its first
/// triangle.
pub fn encode_nbrs(nbrs: &[[u32; 3]], first: usize) -> Vec<u8> {
    let mut out = Vec::with_capacity(nbrs.len() * 4);
    for (k, n) in nbrs.iter().enumerate() {
        let t = (first + k) as i64;
        for &v in n {
            varint(
                &mut out,
                if v == NONE {
                    0
                } else {
                    zigzag(v as i64 - t) + 1
                },
            );
        }
    }
    out
}

/// Decode `n` neighbour triples coded by [`encode_nbrs`].
pub(crate) fn decode_nbrs(b: &[u8], n: usize, first: usize) -> Result<Vec<[u32; 3]>, TinError> {
    let mut out = Vec::with_capacity(n);
    let mut at = 0usize;
    for k in 0..n {
        let t = (first + k) as i64;
        let mut x = [NONE; 3];
        for v in x.iter_mut() {
            let c = read_varint(b, &mut at)?;
            if c != 0 {
                let id = t.wrapping_add(unzigzag(c - 1));
                if !(0..NONE as i64).contains(&id) {
                    return Err(TinError::corrupt("neighbour id out of range in a group"));
                }
                *v = id as u32;
            }
        }
        out.push(x);
    }
    if at != b.len() {
        return Err(TinError::corrupt("neighbour group has bytes left over"));
    }
    Ok(out)
}

/// Code one group of parents, or of grid cells (`plus_one`: parents, where
/// [`NONE`] is coded as 0).
pub fn encode_ids(ids: &[u32], plus_one: bool) -> Vec<u8> {
    let mut out = Vec::with_capacity(ids.len() * 2);
    let mut prev = 0i64;
    for &v in ids {
        let x = if plus_one {
            if v == NONE { 0 } else { v as i64 + 1 }
        } else {
            v as i64
        };
        varint(&mut out, zigzag(x - prev));
        prev = x;
    }
    out
}

/// Decode `n` ids coded by [`encode_ids`].
pub(crate) fn decode_ids(b: &[u8], n: usize, plus_one: bool) -> Result<Vec<u32>, TinError> {
    let mut out = Vec::with_capacity(n);
    let mut at = 0usize;
    let mut prev = 0i64;
    for _ in 0..n {
        prev = prev.wrapping_add(unzigzag(read_varint(b, &mut at)?));
        let v = match (plus_one, prev) {
            (true, 0) => NONE,
            (true, x) if (1..=NONE as i64).contains(&x) => (x - 1) as u32,
            (false, x) if (0..NONE as i64).contains(&x) => x as u32,
            _ => return Err(TinError::corrupt("id out of range in a group")),
        };
        out.push(v);
    }
    if at != b.len() {
        return Err(TinError::corrupt("id group has bytes left over"));
    }
    Ok(out)
}

/// Compress a coded group: a codec byte, then zstd (or the coding as it
/// is when zstd does not make it smaller).
pub fn pack(coded: &[u8]) -> Vec<u8> {
    // one compression context per thread: making one costs more than
    // compressing a group
    thread_local! {
        static Z: RefCell<Option<zstd::bulk::Compressor<'static>>> =
            RefCell::new(zstd::bulk::Compressor::new(ZSTD_LEVEL).ok());
    }
    let z = Z.with(|z| z.borrow_mut().as_mut().map(|c| c.compress(coded)));
    if let Some(Ok(z)) = z
        && z.len() < coded.len()
    {
        let mut out = Vec::with_capacity(z.len() + 1);
        out.push(1);
        out.extend_from_slice(&z);
        return out;
    }
    let mut out = Vec::with_capacity(coded.len() + 1);
    out.push(0);
    out.extend_from_slice(coded);
    out
}

/// Undo [`pack`]; the coding of a group is at most `max` bytes.
pub fn unpack(b: &[u8], max: usize) -> Result<Vec<u8>, TinError> {
    match b.split_first() {
        Some((0, rest)) if rest.len() <= max => Ok(rest.to_vec()),
        Some((1, rest)) => {
            // one decompression context per thread (making one costs more
            // than decompressing a group)
            thread_local! {
                static Z: RefCell<Option<zstd::bulk::Decompressor<'static>>> =
                    RefCell::new(zstd::bulk::Decompressor::new().ok());
            }
            Z.with(|z| match z.borrow_mut().as_mut() {
                Some(d) => d.decompress(rest, max),
                None => zstd::bulk::decompress(rest, max),
            })
            .map_err(|e| TinError::corrupt(format!("a group does not decompress: {e}")))
        }
        Some((c, _)) if *c > 1 => Err(TinError::corrupt(format!("unknown group codec {c}"))),
        _ => Err(TinError::corrupt("empty or oversized group")),
    }
}

/// Largest coding of a group of `n` elements of `s`.
pub fn max_coded(s: Stream, n: usize) -> usize {
    n * match s {
        Stream::Verts => 24,
        Stream::Tris(_) => 3 * 6,
        Stream::Nbrs(_) => 3 * 10,
        Stream::Parents(_) | Stream::Cells(_) => 10,
    }
}

/// A decoded group.
#[derive(Clone, Debug, PartialEq)]
pub enum Group {
    Verts(Vec<[f64; 3]>),
    /// Triangles or neighbour triples.
    Triples(Vec<[u32; 3]>),
    /// Parents or grid cells.
    Ids(Vec<u32>),
}

impl Group {
    /// Heap bytes held.
    pub fn bytes(&self) -> usize {
        match self {
            Group::Verts(v) => v.len() * 24,
            Group::Triples(v) => v.len() * 12,
            Group::Ids(v) => v.len() * 4,
        }
    }
}

/// Code elements `first..first + n` of stream `s` of a tin (before
/// [`pack`]).
pub(crate) fn encode_group(
    tin: &super::Tin,
    s: Stream,
    first: usize,
    n: usize,
    coding: VertexCoding,
    idx: Option<&[[i32; 2]]>,
) -> Vec<u8> {
    let r = first..first + n;
    match s {
        Stream::Verts => encode_verts(&tin.verts[r.clone()], idx.map(|i| &i[r]), coding),
        Stream::Tris(l) => encode_tris(&tin.levels[l].tris[r]),
        Stream::Nbrs(l) => encode_nbrs(&tin.levels[l].nbrs[r], first),
        Stream::Parents(l) => encode_ids(&tin.levels[l].parent[r], true),
        Stream::Cells(l) => encode_ids(&tin.levels[l].grid.cells[r], false),
    }
}

/// Decode a packed group of `n` elements of `s` starting at element
/// `first`.
pub fn decode_group(
    packed: &[u8],
    s: Stream,
    first: usize,
    n: usize,
    coding: VertexCoding,
    lat: Option<&Lattice>,
) -> Result<Group, TinError> {
    let b = unpack(packed, max_coded(s, n))?;
    Ok(match s {
        Stream::Verts => Group::Verts(decode_verts(&b, n, coding, lat)?),
        Stream::Tris(_) => Group::Triples(decode_tris(&b, n)?),
        Stream::Nbrs(_) => Group::Triples(decode_nbrs(&b, n, first)?),
        Stream::Parents(_) => Group::Ids(decode_ids(&b, n, true)?),
        Stream::Cells(_) => Group::Ids(decode_ids(&b, n, false)?),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codings_round_trip() {
        let tris = vec![[0, 1, 2], [2, 1, 3], [5_000_000, 3, 2], [7, 8, 9]];
        assert_eq!(decode_tris(&encode_tris(&tris), 4).unwrap(), tris);
        let nbrs = vec![[1, NONE, NONE], [NONE, 0, 7_000_000]];
        assert_eq!(
            decode_nbrs(&encode_nbrs(&nbrs, 1000), 2, 1000).unwrap(),
            nbrs
        );
        let p = vec![NONE, 0, 0, 1, 5, 5, 4_000_000_000];
        assert_eq!(decode_ids(&encode_ids(&p, true), p.len(), true).unwrap(), p);
        let c = vec![9, 3, 0, u32::MAX - 1];
        assert_eq!(
            decode_ids(&encode_ids(&c, false), c.len(), false).unwrap(),
            c
        );
        let coded = encode_tris(&tris);
        assert_eq!(unpack(&pack(&coded), 100).unwrap(), coded);
        assert!(unpack(&pack(&coded), 2).is_err() || coded.len() <= 2);
    }

    #[test]
    fn lattice_vertices_are_exact() {
        let lat = Lattice {
            ip_x: -84.40041666666667,
            ip_y: 36.46125,
            scale_x: 1.0 / 1200.0,
            scale_y: -1.0 / 1200.0,
            skew_x: 0.0,
            skew_y: 0.0,
        };
        let verts: Vec<[f64; 3]> = (0..50)
            .map(|i| {
                let (x, y) = lat.centre((i * 7 % 13) as f64, (i * 3 % 11) as f64);
                [x, y, 300.25 + i as f64]
            })
            .collect();
        assert_eq!(vertex_coding(Some(&lat), &verts), VertexCoding::LatticeF32);
        let idx = lattice_indices(&lat, &verts).unwrap();
        let b = encode_verts(&verts, Some(&idx), VertexCoding::LatticeF32);
        let back = decode_verts(&b, verts.len(), VertexCoding::LatticeF32, Some(&lat)).unwrap();
        assert_eq!(back, verts);
        let mut off = verts.clone();
        off[3][0] += 1e-9;
        assert_eq!(vertex_coding(Some(&lat), &off), VertexCoding::Raw);
        off[3][0] = verts[3][0];
        off[3][2] = 0.1;
        assert_eq!(vertex_coding(Some(&lat), &off), VertexCoding::LatticeF64);
    }
}
