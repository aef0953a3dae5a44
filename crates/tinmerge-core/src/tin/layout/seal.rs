//! Block checksums, header and content hashes, and resealing a value.

use super::read::{BLOCK_LEN, BLOCK_PAYLOAD, FIXED_LEN, HEADER_LEN_V3, Header, VERSION_1};
use crate::tin::TinError;
use crate::tin::compact::Plan;
use xxhash_rust::xxh3::Xxh3;

/// The payload of version-3 block `k` of the value with header hash
/// `hh`, from `b` = payload and checksum as stored; an error when the
/// checksum does not match.
pub(crate) fn check_block(hh: u64, k: u64, b: &[u8]) -> Result<&[u8], TinError> {
    checked(hh, k, b, "block")
}

/// The payload of block or group `k` (`what`), checked against its
/// checksum (the last 8 bytes of `b`).
fn checked<'a>(hh: u64, k: u64, b: &'a [u8], what: &str) -> Result<&'a [u8], TinError> {
    if b.len() < 8 {
        return Err(TinError::corrupt(format!("{what} {k} truncated")));
    }
    let (payload, sum) = b.split_at(b.len() - 8);
    let stored = u64::from_le_bytes(sum.try_into().unwrap_or([0; 8]));
    if block_checksum(hh, k, payload) != stored {
        return Err(TinError::corrupt(format!(
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

pub(super) fn block_checksum(hh: u64, k: u64, payload: &[u8]) -> u64 {
    xxhash_rust::xxh3::xxh3_64_with_seed(payload, hh.wrapping_add(k))
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
    use super::read::{
        HEADER_LEN_V4, VERSION_3, header_hash, header_len_of, is_compact, read_header,
    };
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
    let hl = header_len_of(b);
    if b.len() >= hl.max(HEADER_LEN_V4) && is_compact(u16::from_le_bytes([b[4], b[5]])) {
        let hh = header_hash(b);
        b[hl - 8..hl].copy_from_slice(&hh.to_le_bytes());
        // the groups the directory names, as far as it and the value go
        if let Ok(h) = read_header(b) {
            let ng = plan(&h).num_groups() as usize;
            let data = hl + 4 * ng;
            let mut start = 0usize;
            for k in 0..ng {
                let Some(e) = b.get(hl + 4 * k..hl + 4 * k + 4) else {
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
