//! Reading a stored value's header, and where its sections and blocks lie.

use crate::tin::compact::VertexCoding;
use crate::tin::lattice::Lattice;
use crate::tin::{Bbox, MAX_LEVELS, TinError};
use xxhash_rust::xxh3::Xxh3;

pub const MAGIC: &[u8; 4] = b"TINM";
/// The format version [`encode`](super::encode::encode) writes.
pub const VERSION: u16 = 4;
/// Format 4 with void triangles (a domain that is not the convex hull):
/// written when a level has any, so that a reader of format 4 refuses it.
pub const VERSION_5: u16 = 5;
/// Format 4 with each level's whole-surface sums in the header
/// ([`LevelSums`]): written since 0.26.0.
pub const VERSION_6: u16 = 6;
/// Format 5 (void triangles) with the sums of format 6.
pub const VERSION_7: u16 = 7;
/// Formats 4 to 7 (compact, in groups).
pub(crate) fn is_compact(version: u16) -> bool {
    (VERSION..=VERSION_7).contains(&version)
}
/// Formats that may have void triangles (5 and 7).
pub(crate) fn has_void(version: u16) -> bool {
    version == VERSION_5 || version == VERSION_7
}
/// Formats whose header holds each level's sums (6 and 7).
pub(crate) fn has_sums(version: u16) -> bool {
    version == VERSION_6 || version == VERSION_7
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
/// Bytes of one level's sums in a format-6 or -7 header.
pub const SUMS_RECORD: usize = 64;
/// Where the sums start in a format-6 or -7 header (after the fields of
/// format 4 but its hash).
pub const SUMS_AT: usize = HEADER_LEN_V4 - 8;
/// Length of a format-6 or -7 header: format 4's, with 16 level sums
/// before the header hash.
pub const HEADER_LEN_V6: usize = HEADER_LEN_V4 + MAX_LEVELS * SUMS_RECORD;
/// Bytes that hold the header of any version (within the first TOAST chunk
/// of a stored value). Every value written since format 6 is longer than
/// this; an older one may be shorter (its header is shorter too).
pub const HEADER_LEN: usize = HEADER_LEN_V6;
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

/// The sums over a whole level's surface (its triangles that are not void)
/// in the tin's own units, stored in format 6 and 7 headers, so a tile
/// wholly inside a polygon answers from its header alone. They are what
/// the area merge sums over the level, in its order
/// (`merge::area::whole`): planar and surface area, min and max height,
/// the integrals of height and of slope (degrees) over the planar area, the
/// steepest slope.
/// The area merge works with the same record
/// (`merge::area::surface::SurfaceStats`) for any clipped surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LevelSums {
    /// Planar area.
    pub area2d: f64,
    /// Surface area.
    pub area3d: f64,
    pub min_z: f64,
    pub max_z: f64,
    /// Integral of z over the planar area.
    pub z_integral: f64,
    /// Integral of the slope (degrees) over the planar area.
    pub slope_integral: f64,
    /// Steepest triangle with some area inside, degrees.
    pub max_slope: f64,
}

impl LevelSums {
    /// The seven numbers in their stored order.
    pub fn to_array(&self) -> [f64; 7] {
        [
            self.area2d,
            self.area3d,
            self.min_z,
            self.max_z,
            self.z_integral,
            self.slope_integral,
            self.max_slope,
        ]
    }

    fn from_array(a: [f64; 7]) -> LevelSums {
        LevelSums {
            area2d: a[0],
            area3d: a[1],
            min_z: a[2],
            max_z: a[3],
            z_integral: a[4],
            slope_integral: a[5],
            max_slope: a[6],
        }
    }

    /// Why stored sums cannot be a surface's (None when they can): every
    /// number finite, areas positive and the surface's at least the
    /// plane's (up to rounding), heights ordered and within the bbox,
    /// slopes in 0..90 degrees.
    fn fault(&self, bbox: &Bbox) -> Option<&'static str> {
        let a = self.to_array();
        if a.iter().any(|v| !v.is_finite()) {
            return Some("a sum is not finite");
        }
        if self.area2d <= 0.0 || self.area3d < self.area2d * (1.0 - 1e-12) {
            return Some("the areas are not a surface's");
        }
        if self.min_z > self.max_z || self.min_z < bbox.min_z || self.max_z > bbox.max_z {
            return Some("the heights are not within the bounding box");
        }
        let s = self.slope_integral / self.area2d;
        if !(0.0..=90.0).contains(&self.max_slope) || !(-1e-9..=90.0 + 1e-9).contains(&s) {
            return Some("the slopes are not in 0..90 degrees");
        }
        None
    }
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
    /// Versions 6 and 7: each level's sums (empty before).
    pub sums: Vec<LevelSums>,
}

impl Header {
    pub fn num_levels(&self) -> usize {
        self.levels.len()
    }

    /// Bytes of this header in the value (where a compact value's
    /// directory starts).
    pub fn header_len(&self) -> usize {
        header_len(self.version).unwrap_or(FIXED_LEN)
    }

    /// The stored sums of level `l` (formats 6 and 7).
    pub fn level_sums(&self, l: usize) -> Option<&LevelSums> {
        self.sums.get(l)
    }

    /// Per level: triangles and grid cells.
    pub(crate) fn level_counts(&self) -> Vec<(usize, usize)> {
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

pub(super) struct Rd<'a> {
    pub(super) b: &'a [u8],
    pub(super) pos: usize,
}

impl<'a> Rd<'a> {
    pub(super) fn take(&mut self, n: usize) -> Result<&'a [u8], TinError> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.b.len());
        match end {
            Some(e) => {
                let s = &self.b[self.pos..e];
                self.pos = e;
                Ok(s)
            }
            None => Err(TinError::corrupt(format!(
                "truncated: needs {} bytes at offset {}, value has {}",
                n,
                self.pos,
                self.b.len()
            ))),
        }
    }
    pub(super) fn u16(&mut self) -> Result<u16, TinError> {
        let s = self.take(2)?;
        Ok(u16::from_le_bytes([s[0], s[1]]))
    }
    pub(super) fn u32(&mut self) -> Result<u32, TinError> {
        let s = self.take(4)?;
        Ok(u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
    }
    pub(super) fn u64(&mut self) -> Result<u64, TinError> {
        let s = self.take(8)?;
        let mut a = [0u8; 8];
        a.copy_from_slice(s);
        Ok(u64::from_le_bytes(a))
    }
    pub(super) fn f64(&mut self) -> Result<f64, TinError> {
        Ok(f64::from_bits(self.u64()?))
    }
    pub(super) fn align8(&mut self) -> Result<(), TinError> {
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
        return Err(TinError::corrupt(format!(
            "truncated: {} bytes, the header alone is {FIXED_LEN}",
            b.len()
        )));
    }
    let mut r = Rd { b, pos: 0 };
    if r.take(4)? != MAGIC {
        return Err(TinError::corrupt("bad magic number (not a tin value)"));
    }
    let version = r.u16()?;
    let want_len = match header_len(version) {
        Some(l) => l,
        None => {
            return Err(TinError::corrupt(format!(
                "format version {version} is not supported (this build reads versions {VERSION_1}, {VERSION_3} and {VERSION} to {VERSION_7})"
            )));
        }
    };
    let _flags = r.u16()?;
    let hl = r.u32()?;
    if hl as usize != want_len {
        return Err(TinError::corrupt(format!(
            "header length {hl}, expected {want_len} for format version {version}"
        )));
    }
    if version != VERSION_1 {
        if b.len() < want_len {
            return Err(TinError::corrupt(format!(
                "truncated: {} bytes, the header alone is {want_len}",
                b.len()
            )));
        }
        if header_hash(b) != stored_header_hash(b) {
            return Err(TinError::corrupt(
                "header hash mismatch (the header is corrupted)",
            ));
        }
    }
    let srid = r.u32()? as i32;
    let nl = r.u32()?;
    if nl == 0 || nl as usize > MAX_LEVELS {
        return Err(TinError::corrupt(format!(
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
        if !has_void(version) && li.num_void != 0 {
            return Err(TinError::corrupt(format!(
                "level {l}: void triangles in a format-{version} value"
            )));
        }
        if li.num_void > li.num_triangles {
            return Err(TinError::corrupt(format!(
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
            .ok_or_else(|| TinError::corrupt(format!("unknown vertex coding {code}")))?;
        let lattice = l.is_valid().then_some(l);
        if coding != VertexCoding::Raw && lattice.is_none() {
            return Err(TinError::corrupt(
                "lattice-coded vertices without a valid lattice",
            ));
        }
        (lattice, coding)
    } else {
        (None, VertexCoding::Raw)
    };
    let mut sums = Vec::new();
    if has_sums(version) {
        r.pos = SUMS_AT;
        for l in 0..nl {
            let mut a = [0.0; 7];
            for v in &mut a {
                *v = r.f64()?;
            }
            r.take(SUMS_RECORD - 56)?;
            let s = LevelSums::from_array(a);
            if let Some(why) = s.fault(&bbox) {
                return Err(TinError::corrupt(format!("level {l}'s stored sums: {why}")));
            }
            sums.push(s);
        }
    }
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
        sums,
    })
}

/// Header length of a format version, None for an unknown one.
pub(crate) fn header_len(version: u16) -> Option<usize> {
    match version {
        VERSION_1 => Some(FIXED_LEN),
        VERSION_3 => Some(HEADER_LEN_V3),
        VERSION | VERSION_5 => Some(HEADER_LEN_V4),
        VERSION_6 | VERSION_7 => Some(HEADER_LEN_V6),
        _ => None,
    }
}

/// Header length of the value starting with `b` (by its version field).
pub(super) fn header_len_of(b: &[u8]) -> usize {
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
pub(crate) fn num_blocks(body: u64) -> u64 {
    body.div_ceil(BLOCK_PAYLOAD as u64)
}

/// Length of a whole value with these counts, or None on overflow.
pub(super) fn value_len(h: &Header) -> Option<u64> {
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
pub(crate) fn block_at(body: u64, k: u64) -> (u64, usize) {
    let start = HEADER_LEN_V3 as u64 + k * BLOCK_LEN as u64;
    let payload = (body - k * BLOCK_PAYLOAD as u64).min(BLOCK_PAYLOAD as u64) as usize;
    (start, payload)
}

/// The stored header hash of a version-3 or -4 header, computed: xxh3 of
/// the header up to the hash itself, with the content hash (32..40)
/// zeroed.
pub(super) fn header_hash(b: &[u8]) -> u64 {
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
