//! Reading stored bytes back into a tin, whole or a group at a time, and
//! the heap that takes.

use super::read::{
    BLOCK_LEN, FIXED_LEN, HEADER_LEN_V3, Header, LevelInfo, Rd, VERSION_1, header_len_of,
    is_compact, read_header, stored_header_hash, value_len,
};
use super::seal::{check_block, check_group, content_hash, plan};
use crate::interrupt::Interrupt;
use crate::par;
use crate::tin::check::validate_structure_checked;
use crate::tin::compact::{self, Plan, Stream};
use crate::tin::hierarchy::child_starts;
use crate::tin::{Grid, Level, NONE, Tin, TinError};

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
            return Err(TinError::corrupt(format!(
                "length mismatch: value has {} bytes, header says {}",
                b.len(),
                h.total_len
            )));
        }
        if content_hash(b) != h.hash {
            return Err(TinError::corrupt(
                "content hash mismatch (value is corrupted)",
            ));
        }
        interrupt()?;
        let (verts, levels) = decode_v4(b, &h, interrupt)?;
        return finish(&h, verts, levels, interrupt);
    }
    let expect = value_len(&h).ok_or_else(|| TinError::corrupt("counts overflow"))?;
    if h.total_len != b.len() as u64 || expect != b.len() as u64 {
        return Err(TinError::corrupt(format!(
            "length mismatch: value has {} bytes, header says {} and its counts need {}",
            b.len(),
            h.total_len,
            expect
        )));
    }
    if content_hash(b) != h.hash {
        return Err(TinError::corrupt(
            "content hash mismatch (value is corrupted)",
        ));
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
        outline: Default::default(),
        hull: Default::default(),
    }
}

/// Where each version-4 group is in the value `b` (payload and checksum),
/// from its directory; an error unless the groups fill the value exactly.
pub fn group_ranges(b: &[u8], plan: &Plan) -> Result<Vec<std::ops::Range<usize>>, TinError> {
    let ng = plan.num_groups() as usize;
    let hl = header_len_of(b);
    let data = ng
        .checked_mul(4)
        .and_then(|d| d.checked_add(hl))
        .filter(|&d| d <= b.len())
        .ok_or_else(|| {
            TinError::corrupt("the directory of groups runs past the end of the value")
        })?;
    let mut out = Vec::with_capacity(ng);
    let mut start = 0u64;
    for (k, e) in b[hl..data].chunks_exact(4).enumerate() {
        let end = u32::from_le_bytes([e[0], e[1], e[2], e[3]]) as u64;
        let (a, z) = group_place(k as u64, data as u64, start, end, b.len() as u64)?;
        out.push(a as usize..z as usize);
        start = end;
    }
    let start = start as usize;
    if data + start != b.len() {
        return Err(TinError::corrupt("bytes after the last group"));
    }
    Ok(out)
}

/// Format-4 group `k` of a value with header `h` and header hash `hh`,
/// read as `raw` (payload and checksum): checked, then decoded as the `n`
/// elements of `s` from element `first`.
pub(crate) fn open_group(
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
pub(crate) fn group_place(
    k: u64,
    data: u64,
    start: u64,
    end: u64,
    total: u64,
) -> Result<(u64, u64), TinError> {
    if end < start + 9 || data + end > total {
        return Err(TinError::corrupt(format!(
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
                _ => return Err(TinError::corrupt("a group decoded to the wrong kind")),
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
