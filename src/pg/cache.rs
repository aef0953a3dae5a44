//! Backend-local cache of decoded `tin` values, keyed by the content hash and
//! length stored in the header, bounded by `tinmerge.cache_size` (MB), least
//! recently used first out. Holds owned Rust data only (never Datums).

use std::cell::RefCell;
use std::sync::Arc;

use super::{raise_tin, CACHE_SIZE_MB};
use crate::tin::{Tin, TinError};

struct Entry {
    hash: u64,
    len: u64,
    tin: Arc<Tin>,
    bytes: usize,
    last: u64,
}

#[derive(Default)]
struct Cache {
    entries: Vec<Entry>,
    clock: u64,
    hits: u64,
    misses: u64,
}

thread_local! {
    static CACHE: RefCell<Cache> = RefCell::new(Cache::default());
}

/// Approximate heap size of a decoded value.
fn size_of(t: &Tin) -> usize {
    let mut n = t.verts.len() * 24;
    for l in &t.levels {
        n += l.tris.len() * 28 + l.child_start.len() * 4 + l.grid.cells.len() * 4;
    }
    n
}

/// The decoded value for (hash, len), decoding with `decode` on a miss.
pub fn get_or_decode(
    hash: u64,
    len: u64,
    decode: impl FnOnce() -> Result<Tin, TinError>,
) -> Arc<Tin> {
    let found = CACHE.with(|c| {
        let mut c = c.borrow_mut();
        c.clock += 1;
        let now = c.clock;
        let hit = c
            .entries
            .iter_mut()
            .find(|e| e.hash == hash && e.len == len)
            .map(|e| {
                e.last = now;
                e.tin.clone()
            });
        if hit.is_some() {
            c.hits += 1;
        } else {
            c.misses += 1;
        }
        hit
    });
    if let Some(t) = found {
        return t;
    }
    // decode outside the borrow: an ERROR here must not leave it borrowed
    let tin = Arc::new(decode().unwrap_or_else(|e| raise_tin(e)));
    let limit = CACHE_SIZE_MB.get().max(0) as usize * 1024 * 1024;
    let bytes = size_of(&tin);
    if bytes <= limit {
        CACHE.with(|c| {
            let mut c = c.borrow_mut();
            let mut used: usize = c.entries.iter().map(|e| e.bytes).sum();
            while used + bytes > limit && !c.entries.is_empty() {
                let oldest = (0..c.entries.len())
                    .min_by_key(|&i| c.entries[i].last)
                    .unwrap_or(0);
                used -= c.entries.swap_remove(oldest).bytes;
            }
            let last = c.clock;
            c.entries.push(Entry {
                hash,
                len,
                tin: tin.clone(),
                bytes,
                last,
            });
        });
    }
    tin
}

/// (hits, misses, entries, bytes) of this backend's cache.
pub fn stats() -> (u64, u64, usize, usize) {
    CACHE.with(|c| {
        let c = c.borrow();
        (
            c.hits,
            c.misses,
            c.entries.len(),
            c.entries.iter().map(|e| e.bytes).sum(),
        )
    })
}
