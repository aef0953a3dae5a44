//! Writing a tin as stored bytes, in the current format and the older
//! ones (for tests and upgrades).

use super::read::{
    BLOCK_PAYLOAD, FIXED_LEN, HEADER_LEN, HEADER_LEN_V3, HEADER_LEN_V4, HEADER_LEN_V6,
    LEVEL_RECORD, LevelSums, MAGIC, SUMS_RECORD, VERSION, VERSION_1, VERSION_3, VERSION_5,
    VERSION_6, VERSION_7, header_hash, num_blocks,
};
use super::seal::{block_checksum, content_hash};
use crate::par;
use crate::tin::compact::{self, Plan, VertexCoding};
use crate::tin::lattice::Lattice;
use crate::tin::{MAX_LEVELS, Tin};

/// Serialise a tin (whose structure is valid) to its storage bytes, in the
/// current format version ([`VERSION`]), vertices raw.
pub fn encode(tin: &Tin) -> Vec<u8> {
    encode_on(tin, None)
}

/// [`encode`] for a tin built on a raster's pixel lattice: when every
/// vertex is a pixel centre of `lattice` (and every height a float32
/// value), vertices are stored as lattice indices and `f32` heights.
pub fn encode_on(tin: &Tin, lattice: Option<&Lattice>) -> Vec<u8> {
    encode_compact(tin, lattice, &[])
}

/// [`encode_on`] with each level's sums in the header (format 6, or 7 with
/// void triangles): `sums` has one entry per level, what
/// `merge::area::whole::level_sums` makes of `tin`.
pub fn encode_with_sums(tin: &Tin, lattice: Option<&Lattice>, sums: &[LevelSums]) -> Vec<u8> {
    assert_eq!(sums.len(), tin.levels.len(), "one sum per level");
    encode_compact(tin, lattice, sums)
}

/// The compact formats: 4 or 5 without sums, 6 or 7 with them.
fn encode_compact(tin: &Tin, lattice: Option<&Lattice>, sums: &[LevelSums]) -> Vec<u8> {
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
    let void = tin.levels.iter().any(|l| l.num_void > 0);
    let (version, hl) = match (void, sums.is_empty()) {
        (false, true) => (VERSION, HEADER_LEN_V4),
        (true, true) => (VERSION_5, HEADER_LEN_V4),
        (false, false) => (VERSION_6, HEADER_LEN_V6),
        (true, false) => (VERSION_7, HEADER_LEN_V6),
    };
    out[4..6].copy_from_slice(&version.to_le_bytes());
    out[8..12].copy_from_slice(&(hl as u32).to_le_bytes());
    let lat = lattice.filter(|_| coding != VertexCoding::Raw);
    for v in lat.map_or([0.0; 6], |l| {
        [l.ip_x, l.ip_y, l.scale_x, l.scale_y, l.skew_x, l.skew_y]
    }) {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out.extend_from_slice(&(coding as u32).to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes());
    if !sums.is_empty() {
        for i in 0..MAX_LEVELS {
            let a = sums.get(i).map_or([0.0; 7], LevelSums::to_array);
            for v in a {
                out.extend_from_slice(&v.to_le_bytes());
            }
            out.extend_from_slice(&[0u8; SUMS_RECORD - 56]);
        }
    }
    let data: usize = groups.iter().map(|g| g.len() + 8).sum();
    let total = hl + 4 * groups.len() + data;
    out[24..32].copy_from_slice(&(total as u64).to_le_bytes());
    out.extend_from_slice(&[0u8; 8]);
    debug_assert_eq!(out.len(), hl);
    let hh = header_hash(&out);
    out[hl - 8..].copy_from_slice(&hh.to_le_bytes());
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
