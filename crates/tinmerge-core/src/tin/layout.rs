//! The flat little-endian storage layout of a `tin` value (the bytes after the
//! 4-byte varlena length word).
//!
//! ```text
//! offset size  field
//!      0    4  magic "TINM"
//!      4    2  format version (4 written, 5 when a level has void
//!              triangles; 1 and 3 still read)
//!      6    2  flags (0)
//!      8    4  header length (version 1: 856, version 3: 864, version 4: 920)
//!     12    4  SRID (i32)
//!     16    4  number of levels L (1..16)
//!     20    4  number of vertices V (all levels)
//!     24    8  total length of the value in bytes (u64)
//!     32    8  content hash: xxh3-64 of the value with these 8 bytes zeroed
//!     40   48  bbox: min x, min y, max x, max y, min z, max z (f64)
//!     88  768  16 level records of 48 bytes (unused ones zero):
//!              tolerance f64, max error f64, triangles u32, vertices u32,
//!              grid nx u32, grid ny u32, grid cell size f64,
//!              (version 5) void triangles u32 (the last ones of the
//!              level: outside the domain), reserved 4
//!    856    8  (version 3) header hash: xxh3-64 of bytes 0..856 with the
//!              content hash zeroed
//!    856   48  (version 4) the raster lattice of the vertices: ip x, ip y,
//!              scale x, scale y, skew x, skew y (f64; all 0: none)
//!    904    4  (version 4) vertex coding (0 raw, 1 lattice + f32 z,
//!              2 lattice + f64 z; [`super::compact::VertexCoding`])
//!    908    4  (version 4) reserved (0)
//!    912    8  (version 4) header hash: xxh3-64 of bytes 0..912 with the
//!              content hash zeroed
//! ```
//! Version 5 is version 4 with void triangles (see [`super::Level::num_void`]):
//! an older reader must refuse it, not show the void as terrain.
//! Version 4 is compact ([`super::compact`]): after the header, a directory
//! of one u32 per group (where the group ends, counted from the end of the
//! directory), then the groups, each a codec byte, its coded or
//! zstd-compressed elements and an 8-byte checksum (xxh3-64 seeded with the
//! header hash plus the group number). The groups are the vertices (256
//! each), then per level the triangles, neighbours, parents (512 each) and
//! grid cells (2,048 each).
//!
//! Versions 1 and 3 have this body (each section's offset follows from the
//! header's counts):
//! ```text
//!   vertices: V x (x, y, z) f64
//!   per level: triangles T x 3 u32, neighbours T x 3 u32, parents T x u32,
//!              padding to 8, grid cells nx*ny u32, padding to 8
//! ```
//! Version 1 stores the body as it is, after the 856-byte header. Version 3
//! cuts it into blocks of [`BLOCK_PAYLOAD`] bytes, each followed by its
//! 8-byte checksum (xxh3-64 of the payload, seeded with the header hash plus
//! the block number, so a block from another value or another place fails).
//! A reader that holds the header can fetch and verify just the blocks a
//! merge touches ([`super::sliced`]), which the whole-value hash cannot
//! allow (an element at a block boundary takes two).
//!
//! A reader checks `total length == length implied by the counts` before it
//! allocates anything; a full decode checks every hash, then
//! [`super::check::validate_structure`] before the value is used.

use super::check::validate_structure_checked;
use super::compact::{self, Plan, Stream, VertexCoding};
use super::hierarchy::child_starts;
use super::lattice::Lattice;
use super::par;
use super::{Bbox, Grid, Level, MAX_LEVELS, NONE, Tin, TinError};
use crate::interrupt::Interrupt;
use xxhash_rust::xxh3::Xxh3;

pub const MAGIC: &[u8; 4] = b"TINM";
/// The format version [`encode`] writes.
pub const VERSION: u16 = 4;
/// Format 4 with void triangles (a domain that is not the convex hull):
/// written when a level has any, so that a reader of format 4 refuses it.
pub const VERSION_5: u16 = 5;
/// Formats 4 and 5 (compact, in groups).
pub fn is_compact(version: u16) -> bool {
    version == VERSION || version == VERSION_5
}
/// Format 3: the body of format 1 in checksummed blocks.
pub const VERSION_3: u16 = 3;
/// The first format: the body unblocked, one hash for the whole value.
pub const VERSION_1: u16 = 1;
pub const LEVEL_RECORD: usize = 48;
/// Length of the version-1 header (the fields common to every version).
pub const FIXED_LEN: usize = 88 + MAX_LEVELS * LEVEL_RECORD;
/// Length of a version-3 header (the fixed fields and the header hash).
pub const HEADER_LEN_V3: usize = FIXED_LEN + 8;
/// Length of a version-4 header (the fixed fields, the lattice, the
/// vertex coding and the header hash).
pub const HEADER_LEN_V4: usize = FIXED_LEN + 48 + 8 + 8;
/// Bytes that hold the header of any version. Every value is longer than
/// this.
pub const HEADER_LEN: usize = HEADER_LEN_V4;
/// Body bytes per version-3 block (two PostgreSQL TOAST chunks, about).
pub const BLOCK_PAYLOAD: usize = 4080;
/// A version-3 block as stored: payload and checksum.
pub const BLOCK_LEN: usize = BLOCK_PAYLOAD + 8;

/// Per-level summary stored in the header.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LevelInfo {
    pub tolerance: f64,
    pub max_error: f64,
    pub num_triangles: u32,
    pub num_vertices: u32,
    pub grid_nx: u32,
    pub grid_ny: u32,
    pub grid_cell: f64,
    /// Version 5: the level's last `num_void` triangles are void.
    pub num_void: u32,
}

/// The fixed header, readable from the first [`HEADER_LEN`] bytes alone.
#[derive(Clone, Debug, PartialEq)]
pub struct Header {
    /// Format version (1, 3 or 4).
    pub version: u16,
    pub srid: i32,
    pub num_vertices: u32,
    pub total_len: u64,
    pub hash: u64,
    pub bbox: Bbox,
    pub levels: Vec<LevelInfo>,
    /// Version 4: the raster lattice the vertices are coded on.
    pub lattice: Option<Lattice>,
    /// Version 4: how the vertices are coded (versions 1 and 3: raw).
    pub vertex_coding: VertexCoding,
}

impl Header {
    pub fn num_levels(&self) -> usize {
        self.levels.len()
    }

    /// Per level: triangles and grid cells.
    pub fn level_counts(&self) -> Vec<(usize, usize)> {
        self.levels
            .iter()
            .map(|l| {
                (
                    l.num_triangles as usize,
                    l.grid_nx as usize * l.grid_ny as usize,
                )
            })
            .collect()
    }
}

fn corrupt(s: impl Into<String>) -> TinError {
    TinError::Corrupt(s.into())
}

struct Rd<'a> {
    b: &'a [u8],
    pos: usize,
}

impl<'a> Rd<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], TinError> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.b.len());
        match end {
            Some(e) => {
                let s = &self.b[self.pos..e];
                self.pos = e;
                Ok(s)
            }
            None => Err(corrupt(format!(
                "truncated: needs {} bytes at offset {}, value has {}",
                n,
                self.pos,
                self.b.len()
            ))),
        }
    }
    fn u16(&mut self) -> Result<u16, TinError> {
        let s = self.take(2)?;
        Ok(u16::from_le_bytes([s[0], s[1]]))
    }
    fn u32(&mut self) -> Result<u32, TinError> {
        let s = self.take(4)?;
        Ok(u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
    }
    fn u64(&mut self) -> Result<u64, TinError> {
        let s = self.take(8)?;
        let mut a = [0u8; 8];
        a.copy_from_slice(s);
        Ok(u64::from_le_bytes(a))
    }
    fn f64(&mut self) -> Result<f64, TinError> {
        Ok(f64::from_bits(self.u64()?))
    }
    fn align8(&mut self) -> Result<(), TinError> {
        let pad = (8 - self.pos % 8) % 8;
        self.take(pad).map(|_| ())
    }
}

/// Parse and check the header (needs at least its own length:
/// [`FIXED_LEN`] for version 1, [`HEADER_LEN_V3`], [`HEADER_LEN_V4`]). A
/// version-3 or -4 header is checked against its own hash, so a damaged
/// header is an error even when nothing else of the value is read.
pub fn read_header(b: &[u8]) -> Result<Header, TinError> {
    if b.len() < FIXED_LEN {
        return Err(corrupt(format!(
            "truncated: {} bytes, the header alone is {FIXED_LEN}",
            b.len()
        )));
    }
    let mut r = Rd { b, pos: 0 };
    if r.take(4)? != MAGIC {
        return Err(corrupt("bad magic number (not a tin value)"));
    }
    let version = r.u16()?;
    let want_len = match header_len(version) {
        Some(l) => l,
        None => {
            return Err(corrupt(format!(
                "format version {version} is not supported (this build reads versions {VERSION_1}, {VERSION_3}, {VERSION} and {VERSION_5})"
            )));
        }
    };
    let _flags = r.u16()?;
    let hl = r.u32()?;
    if hl as usize != want_len {
        return Err(corrupt(format!(
            "header length {hl}, expected {want_len} for format version {version}"
        )));
    }
    if version != VERSION_1 {
        if b.len() < want_len {
            return Err(corrupt(format!(
                "truncated: {} bytes, the header alone is {want_len}",
                b.len()
            )));
        }
        if header_hash(b) != stored_header_hash(b) {
            return Err(corrupt("header hash mismatch (the header is corrupted)"));
        }
    }
    let srid = r.u32()? as i32;
    let nl = r.u32()?;
    if nl == 0 || nl as usize > MAX_LEVELS {
        return Err(corrupt(format!(
            "number of levels {nl} is not in 1..{MAX_LEVELS}"
        )));
    }
    let num_vertices = r.u32()?;
    let total_len = r.u64()?;
    let hash = r.u64()?;
    let bbox = Bbox {
        min_x: r.f64()?,
        min_y: r.f64()?,
        max_x: r.f64()?,
        max_y: r.f64()?,
        min_z: r.f64()?,
        max_z: r.f64()?,
    };
    let mut levels = Vec::with_capacity(nl as usize);
    for l in 0..nl {
        let li = LevelInfo {
            tolerance: r.f64()?,
            max_error: r.f64()?,
            num_triangles: r.u32()?,
            num_vertices: r.u32()?,
            grid_nx: r.u32()?,
            grid_ny: r.u32()?,
            grid_cell: r.f64()?,
            num_void: r.u32()?,
        };
        r.take(4)?;
        if version != VERSION_5 && li.num_void != 0 {
            return Err(corrupt(format!(
                "level {l}: void triangles in a format-{version} value"
            )));
        }
        if li.num_void > li.num_triangles {
            return Err(corrupt(format!(
                "level {l}: {} void triangles of {}",
                li.num_void, li.num_triangles
            )));
        }
        levels.push(li);
    }
    r.pos = FIXED_LEN;
    let (lattice, vertex_coding) = if is_compact(version) {
        let l = Lattice {
            ip_x: r.f64()?,
            ip_y: r.f64()?,
            scale_x: r.f64()?,
            scale_y: r.f64()?,
            skew_x: r.f64()?,
            skew_y: r.f64()?,
        };
        let code = r.u32()?;
        let coding = VertexCoding::from_u32(code)
            .ok_or_else(|| corrupt(format!("unknown vertex coding {code}")))?;
        let lattice = l.is_valid().then_some(l);
        if coding != VertexCoding::Raw && lattice.is_none() {
            return Err(corrupt("lattice-coded vertices without a valid lattice"));
        }
        (lattice, coding)
    } else {
        (None, VertexCoding::Raw)
    };
    Ok(Header {
        version,
        srid,
        num_vertices,
        total_len,
        hash,
        bbox,
        levels,
        lattice,
        vertex_coding,
    })
}

/// Header length of a format version, None for an unknown one.
pub fn header_len(version: u16) -> Option<usize> {
    match version {
        VERSION_1 => Some(FIXED_LEN),
        VERSION_3 => Some(HEADER_LEN_V3),
        VERSION | VERSION_5 => Some(HEADER_LEN_V4),
        _ => None,
    }
}

/// Header length of the value starting with `b` (by its version field).
fn header_len_of(b: &[u8]) -> usize {
    let v = b.get(4..6).map_or(0, |s| u16::from_le_bytes([s[0], s[1]]));
    header_len(v).unwrap_or(FIXED_LEN)
}

/// Logical offsets (within the body) of one level's sections.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LevelSections {
    pub tris: u64,
    pub nbrs: u64,
    pub parents: u64,
    pub cells: u64,
}

/// Length of the body with these counts and where each level's sections
/// start (vertices start at 0), or None on overflow.
pub fn sections(h: &Header) -> Option<(u64, Vec<LevelSections>)> {
    let pad8 = |x: u64| x.checked_add(7).map(|v| v / 8 * 8);
    let mut len = (h.num_vertices as u64).checked_mul(24)?;
    let mut out = Vec::with_capacity(h.levels.len());
    for lv in &h.levels {
        let t = lv.num_triangles as u64;
        let tris = len;
        let nbrs = tris.checked_add(t.checked_mul(12)?)?;
        let parents = nbrs.checked_add(t.checked_mul(12)?)?;
        let cells = pad8(parents.checked_add(t.checked_mul(4)?)?)?;
        len = pad8(
            cells.checked_add(
                (lv.grid_nx as u64)
                    .checked_mul(lv.grid_ny as u64)?
                    .checked_mul(4)?,
            )?,
        )?;
        out.push(LevelSections {
            tris,
            nbrs,
            parents,
            cells,
        });
    }
    Some((len, out))
}

/// Number of version-3 blocks of a body of `body` bytes.
pub fn num_blocks(body: u64) -> u64 {
    body.div_ceil(BLOCK_PAYLOAD as u64)
}

/// Length of a whole value with these counts, or None on overflow.
fn value_len(h: &Header) -> Option<u64> {
    let (body, _) = sections(h)?;
    if h.version == VERSION_1 {
        body.checked_add(FIXED_LEN as u64)
    } else {
        body.checked_add(HEADER_LEN_V3 as u64)?
            .checked_add(num_blocks(body).checked_mul(8)?)
    }
}

/// Where version-3 block `k` of a body of `body` bytes starts in the value,
/// and its payload length.
pub fn block_at(body: u64, k: u64) -> (u64, usize) {
    let start = HEADER_LEN_V3 as u64 + k * BLOCK_LEN as u64;
    let payload = (body - k * BLOCK_PAYLOAD as u64).min(BLOCK_PAYLOAD as u64) as usize;
    (start, payload)
}

/// The payload of version-3 block `k` of the value with header hash
/// `hh`, from `b` = payload and checksum as stored; an error when the
/// checksum does not match.
pub fn check_block(hh: u64, k: u64, b: &[u8]) -> Result<&[u8], TinError> {
    checked(hh, k, b, "block")
}

/// The payload of block or group `k` (`what`), checked against its
/// checksum (the last 8 bytes of `b`).
fn checked<'a>(hh: u64, k: u64, b: &'a [u8], what: &str) -> Result<&'a [u8], TinError> {
    if b.len() < 8 {
        return Err(corrupt(format!("{what} {k} truncated")));
    }
    let (payload, sum) = b.split_at(b.len() - 8);
    let stored = u64::from_le_bytes(sum.try_into().unwrap_or([0; 8]));
    if block_checksum(hh, k, payload) != stored {
        return Err(corrupt(format!(
            "checksum mismatch in {what} {k} (the value is corrupted)"
        )));
    }
    Ok(payload)
}

/// The packed payload of version-4 group `k`, from `b` = payload and
/// checksum as stored; an error when the checksum does not match.
pub fn check_group(hh: u64, k: u64, b: &[u8]) -> Result<&[u8], TinError> {
    checked(hh, k, b, "group")
}

fn block_checksum(hh: u64, k: u64, payload: &[u8]) -> u64 {
    xxhash_rust::xxh3::xxh3_64_with_seed(payload, hh.wrapping_add(k))
}

/// The stored header hash of a version-3 or -4 header, computed: xxh3 of
/// the header up to the hash itself, with the content hash (32..40)
/// zeroed.
fn header_hash(b: &[u8]) -> u64 {
    let end = (header_len_of(b) - 8).min(b.len());
    let mut h = Xxh3::new();
    h.update(&b[..32.min(end)]);
    h.update(&[0u8; 8]);
    h.update(b.get(40..end).unwrap_or(&[]));
    h.digest()
}

/// The header hash of a version-3 or -4 header (checked by
/// [`read_header`]).
pub fn stored_header_hash(b: &[u8]) -> u64 {
    let hl = header_len_of(b);
    b.get(hl - 8..hl)
        .and_then(|s| s.try_into().ok())
        .map(u64::from_le_bytes)
        .unwrap_or(0)
}

/// Content hash of a value (hash field taken as zero).
pub fn content_hash(b: &[u8]) -> u64 {
    let mut h = Xxh3::new();
    h.update(&b[..32.min(b.len())]);
    if b.len() >= 40 {
        h.update(&[0u8; 8]);
        h.update(&b[40..]);
    }
    h.digest()
}

/// Recompute every hash of a value after its bytes were changed (tests that
/// craft values: structural validation, not the hashes, must reject them).
#[cfg(feature = "bench")]
pub fn reseal(b: &mut [u8]) {
    if b.len() >= HEADER_LEN_V3 && b[4..6] == VERSION_3.to_le_bytes() {
        let hh = header_hash(b);
        b[FIXED_LEN..HEADER_LEN_V3].copy_from_slice(&hh.to_le_bytes());
        // the blocks as decode reads them; a last piece of 8 bytes or less
        // (a truncated value) has no payload to seal
        for (k, blk) in b[HEADER_LEN_V3..].chunks_mut(BLOCK_LEN).enumerate() {
            if blk.len() > 8 {
                let (payload, sum) = blk.split_at_mut(blk.len() - 8);
                sum.copy_from_slice(&block_checksum(hh, k as u64, payload).to_le_bytes());
            }
        }
    }
    if b.len() >= HEADER_LEN_V4
        && (b[4..6] == VERSION.to_le_bytes() || b[4..6] == VERSION_5.to_le_bytes())
    {
        let hh = header_hash(b);
        b[HEADER_LEN_V4 - 8..HEADER_LEN_V4].copy_from_slice(&hh.to_le_bytes());
        // the groups the directory names, as far as it and the value go
        if let Ok(h) = read_header(b) {
            let ng = plan(&h).num_groups() as usize;
            let data = HEADER_LEN_V4 + 4 * ng;
            let mut start = 0usize;
            for k in 0..ng {
                let Some(e) = b.get(HEADER_LEN_V4 + 4 * k..HEADER_LEN_V4 + 4 * k + 4) else {
                    break;
                };
                let end = u32::from_le_bytes([e[0], e[1], e[2], e[3]]) as usize;
                if end < start + 8 || data + end > b.len() {
                    break;
                }
                let (payload, sum) = b[data + start..data + end].split_at_mut(end - start - 8);
                sum.copy_from_slice(&block_checksum(hh, k as u64, payload).to_le_bytes());
                start = end;
            }
        }
    }
    if b.len() >= 40 {
        let h = content_hash(b);
        b[32..40].copy_from_slice(&h.to_le_bytes());
    }
}

/// Offset in a value of byte `logical` of its body.
pub fn body_offset(h: &Header, logical: usize) -> usize {
    if h.version == VERSION_1 {
        FIXED_LEN + logical
    } else {
        HEADER_LEN_V3 + logical / BLOCK_PAYLOAD * BLOCK_LEN + logical % BLOCK_PAYLOAD
    }
}

/// The groups of a version-4 value with this header.
pub fn plan(h: &Header) -> Plan {
    Plan::new(h.num_vertices as usize, &h.level_counts())
}

/// Serialise a tin (whose structure is valid) to its storage bytes, in the
/// current format version ([`VERSION`]), vertices raw.
pub fn encode(tin: &Tin) -> Vec<u8> {
    encode_on(tin, None)
}

/// [`encode`] for a tin built on a raster's pixel lattice: when every
/// vertex is a pixel centre of `lattice` (and every height a float32
/// value), vertices are stored as lattice indices and `f32` heights.
pub fn encode_on(tin: &Tin, lattice: Option<&Lattice>) -> Vec<u8> {
    let coding = compact::vertex_coding(lattice, &tin.verts);
    let idx = match (coding, lattice) {
        (VertexCoding::Raw, _) | (_, None) => None,
        (_, Some(l)) => compact::lattice_indices(l, &tin.verts),
    };
    let coding = if idx.is_some() {
        coding
    } else {
        VertexCoding::Raw
    };
    let levels: Vec<(usize, usize)> = tin
        .levels
        .iter()
        .map(|l| (l.tris.len(), l.grid.cells.len()))
        .collect();
    let jobs = Plan::new(tin.verts.len(), &levels).groups();
    let groups: Vec<Vec<u8>> = par::map(&jobs, |&(s, first, n, _)| {
        compact::pack(&compact::encode_group(
            tin,
            s,
            first,
            n,
            coding,
            idx.as_deref(),
        ))
    });
    let mut out = fixed_header(tin, VERSION_1);
    let version = if tin.levels.iter().any(|l| l.num_void > 0) {
        VERSION_5
    } else {
        VERSION
    };
    out[4..6].copy_from_slice(&version.to_le_bytes());
    out[8..12].copy_from_slice(&(HEADER_LEN_V4 as u32).to_le_bytes());
    let lat = lattice.filter(|_| coding != VertexCoding::Raw);
    for v in lat.map_or([0.0; 6], |l| {
        [l.ip_x, l.ip_y, l.scale_x, l.scale_y, l.skew_x, l.skew_y]
    }) {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out.extend_from_slice(&(coding as u32).to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes());
    let data: usize = groups.iter().map(|g| g.len() + 8).sum();
    let total = HEADER_LEN_V4 + 4 * groups.len() + data;
    out[24..32].copy_from_slice(&(total as u64).to_le_bytes());
    out.extend_from_slice(&[0u8; 8]);
    let hh = header_hash(&out);
    out[HEADER_LEN_V4 - 8..].copy_from_slice(&hh.to_le_bytes());
    out.reserve(total - out.len());
    let mut end = 0usize;
    for g in &groups {
        end += g.len() + 8;
        out.extend_from_slice(&(end as u32).to_le_bytes());
    }
    for (k, g) in groups.iter().enumerate() {
        out.extend_from_slice(g);
        out.extend_from_slice(&block_checksum(hh, k as u64, g).to_le_bytes());
    }
    debug_assert_eq!(out.len(), total);
    seal(out)
}

/// Serialise in format version 3 (0.5.0 wrote it; kept to check that
/// reading version 3 is exact).
pub fn encode_v3(tin: &Tin) -> Vec<u8> {
    let (mut out, body) = header_and_body(tin, VERSION_3);
    let hh = header_hash(&out);
    out.extend_from_slice(&hh.to_le_bytes());
    out.reserve(body.len() + body.len() / BLOCK_PAYLOAD * 8 + 8);
    for (k, payload) in body.chunks(BLOCK_PAYLOAD).enumerate() {
        out.extend_from_slice(payload);
        out.extend_from_slice(&block_checksum(hh, k as u64, payload).to_le_bytes());
    }
    seal(out)
}

/// Serialise in format version 1 (the test fixtures were written so; kept
/// to check that reading version 1 is exact).
pub fn encode_v1(tin: &Tin) -> Vec<u8> {
    let (mut out, body) = header_and_body(tin, VERSION_1);
    out.extend_from_slice(&body);
    seal(out)
}

/// Patch the total length and the content hash.
fn seal(mut out: Vec<u8>) -> Vec<u8> {
    let total = out.len() as u64;
    out[24..32].copy_from_slice(&total.to_le_bytes());
    let h = content_hash(&out);
    out[32..40].copy_from_slice(&h.to_le_bytes());
    out
}

/// The fixed header (total length and content hash still zero; the total
/// length is filled in for version 3, whose header hash covers it) and the
/// body.
fn header_and_body(tin: &Tin, version: u16) -> (Vec<u8>, Vec<u8>) {
    let mut out = fixed_header(tin, version);
    let body = raw_body(tin);
    if version != VERSION_1 {
        let total = (HEADER_LEN_V3 + body.len()) as u64 + num_blocks(body.len() as u64) * 8;
        out[24..32].copy_from_slice(&total.to_le_bytes());
    }
    (out, body)
}

/// The fields common to every version ([`FIXED_LEN`] bytes; total length
/// and content hash zero).
fn fixed_header(tin: &Tin, version: u16) -> Vec<u8> {
    let mut out: Vec<u8> = Vec::with_capacity(HEADER_LEN);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&version.to_le_bytes());
    out.extend_from_slice(&0u16.to_le_bytes());
    let hl = if version == VERSION_1 {
        FIXED_LEN
    } else {
        HEADER_LEN_V3
    };
    out.extend_from_slice(&(hl as u32).to_le_bytes());
    out.extend_from_slice(&tin.srid.to_le_bytes());
    out.extend_from_slice(&(tin.levels.len() as u32).to_le_bytes());
    out.extend_from_slice(&(tin.verts.len() as u32).to_le_bytes());
    out.extend_from_slice(&0u64.to_le_bytes()); // total length, patched below
    out.extend_from_slice(&0u64.to_le_bytes()); // hash, patched at the end
    let b = &tin.bbox;
    for v in [b.min_x, b.min_y, b.max_x, b.max_y, b.min_z, b.max_z] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    for i in 0..MAX_LEVELS {
        match tin.levels.get(i) {
            Some(lv) => {
                out.extend_from_slice(&lv.tolerance.to_le_bytes());
                out.extend_from_slice(&lv.max_error.to_le_bytes());
                out.extend_from_slice(&(lv.tris.len() as u32).to_le_bytes());
                out.extend_from_slice(&lv.num_vertices.to_le_bytes());
                out.extend_from_slice(&lv.grid.nx.to_le_bytes());
                out.extend_from_slice(&lv.grid.ny.to_le_bytes());
                out.extend_from_slice(&lv.grid.cell.to_le_bytes());
                out.extend_from_slice(&lv.num_void.to_le_bytes());
                out.extend_from_slice(&[0u8; 4]);
            }
            None => out.extend_from_slice(&[0u8; LEVEL_RECORD]),
        }
    }
    debug_assert_eq!(out.len(), FIXED_LEN);
    out
}

/// The body of versions 1 and 3 (before version 3 cuts it into blocks).
fn raw_body(tin: &Tin) -> Vec<u8> {
    let mut body: Vec<u8> = Vec::new();
    for v in &tin.verts {
        for c in v {
            body.extend_from_slice(&c.to_le_bytes());
        }
    }
    let pad = |out: &mut Vec<u8>| {
        while !out.len().is_multiple_of(8) {
            out.push(0);
        }
    };
    for lv in &tin.levels {
        for t in &lv.tris {
            for v in t {
                body.extend_from_slice(&v.to_le_bytes());
            }
        }
        for t in &lv.nbrs {
            for v in t {
                body.extend_from_slice(&v.to_le_bytes());
            }
        }
        for p in &lv.parent {
            body.extend_from_slice(&p.to_le_bytes());
        }
        pad(&mut body);
        for c in &lv.grid.cells {
            body.extend_from_slice(&c.to_le_bytes());
        }
        pad(&mut body);
    }
    body
}

/// Parse and fully validate storage bytes. The length implied by the header's
/// counts is checked against the actual length before anything is allocated.
pub fn decode(b: &[u8]) -> Result<Tin, TinError> {
    decode_checked(b, &mut || Ok(()))
}

/// [`decode`] calling `interrupt` between its phases and regularly inside
/// the validation (a cancel does not wait for a whole 15 MB value).
pub fn decode_checked(b: &[u8], interrupt: &mut Interrupt<'_>) -> Result<Tin, TinError> {
    let h = read_header(b)?;
    if is_compact(h.version) {
        if h.total_len != b.len() as u64 {
            return Err(corrupt(format!(
                "length mismatch: value has {} bytes, header says {}",
                b.len(),
                h.total_len
            )));
        }
        if content_hash(b) != h.hash {
            return Err(corrupt("content hash mismatch (value is corrupted)"));
        }
        interrupt()?;
        let (verts, levels) = decode_v4(b, &h, interrupt)?;
        return finish(&h, verts, levels, interrupt);
    }
    let expect = value_len(&h).ok_or_else(|| corrupt("counts overflow"))?;
    if h.total_len != b.len() as u64 || expect != b.len() as u64 {
        return Err(corrupt(format!(
            "length mismatch: value has {} bytes, header says {} and its counts need {}",
            b.len(),
            h.total_len,
            expect
        )));
    }
    if content_hash(b) != h.hash {
        return Err(corrupt("content hash mismatch (value is corrupted)"));
    }
    interrupt()?;
    let unblocked;
    let body: &[u8] = if h.version == VERSION_1 {
        &b[FIXED_LEN..]
    } else {
        let hh = stored_header_hash(b);
        let mut v = Vec::with_capacity(b.len());
        for (k, blk) in b[HEADER_LEN_V3..].chunks(BLOCK_LEN).enumerate() {
            v.extend_from_slice(check_block(hh, k as u64, blk)?);
        }
        unblocked = v;
        &unblocked
    };
    let mut r = Rd { b: body, pos: 0 };
    let mut verts = Vec::with_capacity(h.num_vertices as usize);
    for _ in 0..h.num_vertices {
        verts.push([r.f64()?, r.f64()?, r.f64()?]);
    }
    let mut levels: Vec<Level> = Vec::with_capacity(h.levels.len());
    for li in &h.levels {
        interrupt()?;
        let nt = li.num_triangles as usize;
        let mut tris = Vec::with_capacity(nt);
        for _ in 0..nt {
            tris.push([r.u32()?, r.u32()?, r.u32()?]);
        }
        let mut nbrs = Vec::with_capacity(nt);
        for _ in 0..nt {
            nbrs.push([r.u32()?, r.u32()?, r.u32()?]);
        }
        let mut parent = Vec::with_capacity(nt);
        for _ in 0..nt {
            parent.push(r.u32()?);
        }
        r.align8()?;
        let nc = li.grid_nx as usize * li.grid_ny as usize;
        let mut cells = Vec::with_capacity(nc);
        for _ in 0..nc {
            cells.push(r.u32()?);
        }
        r.align8()?;
        levels.push(level_of(li, tris, nbrs, parent, cells));
    }
    finish(&h, verts, levels, interrupt)
}

/// The level records of a header with these arrays (child ranges still
/// empty).
fn level_of(
    li: &LevelInfo,
    tris: Vec<[u32; 3]>,
    nbrs: Vec<[u32; 3]>,
    parent: Vec<u32>,
    cells: Vec<u32>,
) -> Level {
    Level {
        tolerance: li.tolerance,
        max_error: li.max_error,
        num_vertices: li.num_vertices,
        num_void: li.num_void,
        tris,
        nbrs,
        parent,
        child_start: Vec::new(),
        grid: Grid {
            cell: li.grid_cell,
            nx: li.grid_nx,
            ny: li.grid_ny,
            cells,
        },
    }
}

/// Where each version-4 group is in the value `b` (payload and checksum),
/// from its directory; an error unless the groups fill the value exactly.
pub fn group_ranges(b: &[u8], plan: &Plan) -> Result<Vec<std::ops::Range<usize>>, TinError> {
    let ng = plan.num_groups() as usize;
    let data = ng
        .checked_mul(4)
        .and_then(|d| d.checked_add(HEADER_LEN_V4))
        .filter(|&d| d <= b.len())
        .ok_or_else(|| corrupt("the directory of groups runs past the end of the value"))?;
    let mut out = Vec::with_capacity(ng);
    let mut start = 0u64;
    for (k, e) in b[HEADER_LEN_V4..data].chunks_exact(4).enumerate() {
        let end = u32::from_le_bytes([e[0], e[1], e[2], e[3]]) as u64;
        let (a, z) = group_place(k as u64, data as u64, start, end, b.len() as u64)?;
        out.push(a as usize..z as usize);
        start = end;
    }
    let start = start as usize;
    if data + start != b.len() {
        return Err(corrupt("bytes after the last group"));
    }
    Ok(out)
}

/// Format-4 group `k` of a value with header `h` and header hash `hh`,
/// read as `raw` (payload and checksum): checked, then decoded as the `n`
/// elements of `s` from element `first`.
pub fn open_group(
    h: &Header,
    hh: u64,
    k: u64,
    raw: &[u8],
    s: Stream,
    first: usize,
    n: usize,
) -> Result<compact::Group, TinError> {
    let packed = check_group(hh, k, raw)?;
    compact::decode_group(packed, s, first, n, h.vertex_coding, h.lattice.as_ref())
}

/// Groups decoded as one piece of work by a whole decode (about 0.3 ms).
const DECODE_RUN: usize = 32;

/// Value offsets of format-4 group `k` (payload and checksum) from its
/// directory entry `end` and the one before (`start`; 0 for the first
/// group), both relative to `data`, the end of the directory: an error
/// unless the group holds a codec byte and its checksum and ends within
/// the value's `total` bytes.
pub fn group_place(
    k: u64,
    data: u64,
    start: u64,
    end: u64,
    total: u64,
) -> Result<(u64, u64), TinError> {
    if end < start + 9 || data + end > total {
        return Err(corrupt(format!(
            "group {k} has a bad place in the directory"
        )));
    }
    Ok((data + start, data + end))
}

/// The arrays of a version-4 value (header and length already checked).
fn decode_v4(
    b: &[u8],
    h: &Header,
    interrupt: &mut Interrupt<'_>,
) -> Result<(Vec<[f64; 3]>, Vec<Level>), TinError> {
    let plan = plan(h);
    let ranges = group_ranges(b, &plan)?;
    let hh = stored_header_hash(b);
    let jobs = plan.groups();
    let nl = h.levels.len();
    // (capacities bounded by the value's length: counts are what the
    // groups then hold, group by group)
    let cap = |n: usize| n.min(b.len());
    let mut verts: Vec<[f64; 3]> = Vec::with_capacity(cap(h.num_vertices as usize));
    // per level: triangles, neighbours, parents, grid cells
    type Arrays = (Vec<[u32; 3]>, Vec<[u32; 3]>, Vec<u32>, Vec<u32>);
    let mut arrays: Vec<Arrays> = h
        .levels
        .iter()
        .map(|l| {
            let t = cap(l.num_triangles as usize);
            (
                Vec::with_capacity(t),
                Vec::with_capacity(t),
                Vec::with_capacity(t),
                Vec::with_capacity(cap(l.grid_nx as usize * l.grid_ny as usize)),
            )
        })
        .collect();
    let decode_one = |&(s, first, n, k): &(Stream, usize, usize, u64)| {
        let raw = b
            .get(ranges.get(k as usize).cloned().unwrap_or(0..0))
            .unwrap_or(&[]);
        open_group(h, hh, k, raw, s, first, n).map(|g| (s, g))
    };
    // runs of groups (a group takes microseconds: handing them to threads
    // one by one would cost more than decoding them)
    let runs: Vec<&[(Stream, usize, usize, u64)]> = jobs.chunks(DECODE_RUN).collect();
    let decode_run = |run: &&[(Stream, usize, usize, u64)]| {
        run.iter().map(decode_one).collect::<Result<Vec<_>, _>>()
    };
    par::map_batched(&runs, decode_run, interrupt, &mut |r| {
        for (s, g) in r? {
            match (s, g) {
                (Stream::Verts, compact::Group::Verts(v)) => verts.extend(v),
                (Stream::Tris(l), compact::Group::Triples(v)) if l < nl => arrays[l].0.extend(v),
                (Stream::Nbrs(l), compact::Group::Triples(v)) if l < nl => arrays[l].1.extend(v),
                (Stream::Parents(l), compact::Group::Ids(v)) if l < nl => arrays[l].2.extend(v),
                (Stream::Cells(l), compact::Group::Ids(v)) if l < nl => arrays[l].3.extend(v),
                _ => return Err(corrupt("a group decoded to the wrong kind")),
            }
        }
        Ok(())
    })?;
    let levels = h
        .levels
        .iter()
        .zip(arrays)
        .map(|(li, (t, n, p, c))| level_of(li, t, n, p, c))
        .collect();
    Ok((verts, levels))
}

/// Child ranges, then the whole structure checked.
fn finish(
    h: &Header,
    verts: Vec<[f64; 3]>,
    mut levels: Vec<Level>,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    for l in 1..levels.len() {
        let np = levels[l - 1].tris.len();
        let parents_ok = levels[l]
            .parent
            .iter()
            .all(|&p| p != NONE && (p as usize) < np);
        if parents_ok {
            levels[l - 1].child_start = child_starts(&levels[l].parent, np);
        }
    }
    let tin = Tin {
        srid: h.srid,
        bbox: h.bbox,
        verts,
        levels,
    };
    interrupt()?;
    validate_structure_checked(&tin, interrupt)?;
    Ok(tin)
}

/// Upper-case hex of the storage bytes (text output, as PostGIS prints geometry).
pub fn to_hex(b: &[u8]) -> String {
    const D: &[u8; 16] = b"0123456789ABCDEF";
    let mut s = String::with_capacity(b.len() * 2);
    for &x in b {
        s.push(D[(x >> 4) as usize] as char);
        s.push(D[(x & 15) as usize] as char);
    }
    s
}

/// Parse hex text (either case) into bytes.
pub fn from_hex(s: &str) -> Result<Vec<u8>, TinError> {
    let s = s.trim();
    if !s.len().is_multiple_of(2) {
        return Err(corrupt("hex text has an odd number of digits"));
    }
    let val = |c: u8| -> Result<u8, TinError> {
        match c {
            b'0'..=b'9' => Ok(c - b'0'),
            b'a'..=b'f' => Ok(c - b'a' + 10),
            b'A'..=b'F' => Ok(c - b'A' + 10),
            _ => Err(corrupt(format!("'{}' is not a hex digit", c as char))),
        }
    };
    s.as_bytes()
        .chunks_exact(2)
        .map(|p| Ok(val(p[0])? << 4 | val(p[1])?))
        .collect()
}

/// Upper bound of the heap used to decode a stored value with this header
/// (formats 1 and 3: the decoded arrays and the grid index are about the
/// stored size, and a format-3 body is first copied out of its blocks;
/// format 4: the arrays its counts imply, the child ranges, the group list
/// and one group's scratch).
pub fn decode_bytes(h: &Header) -> usize {
    if !is_compact(h.version) {
        return (h.total_len as usize)
            .saturating_mul(5)
            .saturating_div(2)
            .saturating_add(1 << 16);
    }
    let mut n = (h.num_vertices as usize).saturating_mul(24);
    for l in &h.levels {
        let cells = (l.grid_nx as usize).saturating_mul(l.grid_ny as usize);
        n = n
            .saturating_add((l.num_triangles as usize).saturating_mul(32))
            .saturating_add(cells.saturating_mul(4));
    }
    n.saturating_add((plan(h).num_groups() as usize).saturating_mul(48))
        .saturating_add(1 << 17)
}

/// [`decode_bytes`] of stored bytes (from their length when the header
/// does not read: decoding then fails at once).
pub fn decode_bytes_of(b: &[u8]) -> usize {
    match read_header(b) {
        Ok(h) => decode_bytes(&h),
        Err(_) => b
            .len()
            .saturating_mul(5)
            .saturating_div(2)
            .saturating_add(1 << 16),
    }
}
