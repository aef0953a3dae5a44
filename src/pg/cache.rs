//! Backend-local cache of decoded `tin` values, keyed by the content hash and
//! length stored in the header, bounded by `tinmerge.cache_size` (MB), least
//! recently used first out. Holds owned Rust data only (never Datums).
//!
//! A second, smaller map remembers the header of each on-disk TOAST value
//! seen in the current transaction, keyed by the TOAST pointer (relation,
//! value id, sizes), as PostGIS's `lwgeom_cache.c` does: a query calling a
//! function once per row on the same stored tin then reads neither the value
//! nor its header again; the per-row cost is two hash look-ups. The map is
//! emptied when the transaction changes, so a value id reused after VACUUM
//! can never be mistaken for the value it replaced.

use rustc_hash::FxHashMap;
use std::cell::RefCell;
use std::rc::Rc;
use std::sync::{Arc, Weak};

use pgrx::prelude::*;
use pgrx::{GucContext, GucFlags, GucRegistry, GucSetting};

use super::errors::raise_tin;
use super::memory;
use tinmerge_core::merge::area::surface::SubtreeSums;
use tinmerge_core::tin::layout::Header;
use tinmerge_core::tin::sliced::SlicedTin;
use tinmerge_core::tin::{Tin, TinError};

/// Identity of an on-disk TOAST value: `varatt_external`'s fields.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ToastKey {
    pub relid: u32,
    pub valueid: u32,
    pub rawsize: i32,
    pub extinfo: u32,
}

/// Most TOAST keys remembered per transaction before the map is emptied.
const MAX_ALIASES: usize = 4096;

/// What is remembered about one on-disk value: its header and, once
/// decoded, a weak link to the cached value (weak, so that the LRU bound
/// still decides what stays in memory).
#[derive(Clone)]
pub struct Alias {
    pub header: Arc<Header>,
    pub tin: Weak<Tin>,
}

#[derive(Default)]
struct Aliases {
    epoch: i64,
    /// The key looked up last: a per-row call on one stored tin hits here.
    last: Option<(ToastKey, Alias)>,
    map: FxHashMap<ToastKey, Alias>,
}

/// `tinmerge.cache_size`: MB of decoded tin values kept per backend.
pub static CACHE_SIZE_MB: GucSetting<i32> = GucSetting::<i32>::new(256);
pub fn define_guc() {
    GucRegistry::define_int_guc(
        c"tinmerge.cache_size",
        c"Megabytes of decoded tin values cached per backend.",
        c"A query calling tinmerge functions once per row on the same tin decodes it once per backend; this bounds the memory those decoded values use (0 disables the cache).",
        &CACHE_SIZE_MB,
        0,
        64 * 1024,
        GucContext::Userset,
        GucFlags::UNIT_MB,
    );
}

thread_local! {
    static ALIASES
: RefCell<Aliases> = RefCell::new(Aliases::default());
}

/// What is remembered for `key` in transaction `epoch`, if anything.
pub fn alias_for(key: &ToastKey, epoch: i64) -> Option<Alias> {
    ALIASES.with(|a| {
        let mut a = a.borrow_mut();
        if a.epoch != epoch {
            a.epoch = epoch;
            a.last = None;
            a.map.clear();
            return None;
        }
        if let Some((k, v)) = &a.last {
            if k == key {
                return Some(v.clone());
            }
        }
        let found = a.map.get(key).cloned();
        if let Some(v) = &found {
            a.last = Some((*key, v.clone()));
        }
        found
    })
}

/// The decoded value remembered for `key` in transaction `epoch`, when it
/// is still cached: what a per-row call meets on one stored tin (the key
/// looked up last) or on a few (a join with a table of tiles), without
/// cloning what is remembered.
pub fn decoded_alias(key: &ToastKey, epoch: i64) -> Option<Arc<Tin>> {
    ALIASES.with(|a| {
        let a = a.borrow();
        if a.epoch != epoch {
            return None;
        }
        match &a.last {
            Some((k, v)) if k == key => v.tin.upgrade(),
            _ => a.map.get(key).and_then(|v| v.tin.upgrade()),
        }
    })
}

/// Remember `alias` for `key` in transaction `epoch`.
pub fn remember(key: ToastKey, epoch: i64, alias: Alias) {
    ALIASES.with(|a| {
        let mut a = a.borrow_mut();
        if a.epoch != epoch || a.map.len() >= MAX_ALIASES {
            a.epoch = epoch;
            a.map.clear();
        }
        a.last = Some((key, alias.clone()));
        a.map.insert(key, alias);
    })
}

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

impl Cache {
    /// Drop least recently used values until `extra` more bytes fit in
    /// `limit`.
    fn trim(&mut self, limit: usize, extra: usize) {
        let mut used: usize = self.entries.iter().map(|e| e.bytes).sum();
        while used + extra > limit && !self.entries.is_empty() {
            let oldest = (0..self.entries.len())
                .min_by_key(|&i| self.entries[i].last)
                .unwrap_or(0);
            used -= self.entries.swap_remove(oldest).bytes;
        }
        memory::set_cached(used);
    }

    fn report(&self) {
        memory::set_cached(self.entries.iter().map(|e| e.bytes).sum());
    }
}

thread_local! {
    static CACHE: RefCell<Cache> = RefCell::new(Cache::default());
}

/// The decoded value for (hash, len), decoding with `decode` on a miss.
pub fn get_or_decode(
    hash: u64,
    len: u64,
    need: usize,
    decode: impl FnOnce() -> Result<Tin, TinError>,
) -> Arc<Tin> {
    let limit = cache_limit();
    if let Some(t) = lookup(hash, len, true) {
        return t;
    }
    memory::reserve(need, || format!("decoding a stored tin of {} bytes", len));
    // decode outside the borrow: an ERROR here must not leave it borrowed
    let tin = Arc::new(decode().unwrap_or_else(|e| raise_tin(e)));
    let bytes = tin.heap_bytes();
    if bytes <= limit {
        CACHE.with(|c| {
            let mut c = c.borrow_mut();
            c.trim(limit, bytes);
            let last = c.clock;
            c.entries.push(Entry {
                hash,
                len,
                tin: tin.clone(),
                bytes,
                last,
            });
            c.report();
        });
    }
    tin
}

/// The decoded value for (hash, len) when the cache holds it (no decode).
pub fn peek(hash: u64, len: u64) -> Option<Arc<Tin>> {
    lookup(hash, len, false)
}

/// `tinmerge.cache_size` in bytes.
fn cache_limit() -> usize {
    CACHE_SIZE_MB.get().max(0) as usize * 1024 * 1024
}

/// The cached value for (hash, len), marked as just used; a hit is counted,
/// and a miss when `count_miss` (the caller decodes next).
fn lookup(hash: u64, len: u64, count_miss: bool) -> Option<Arc<Tin>> {
    let limit = cache_limit();
    CACHE.with(|c| {
        let mut c = c.borrow_mut();
        // the setting may have been lowered since values were kept
        c.trim(limit, 0);
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
        } else if count_miss {
            c.misses += 1;
        }
        hit
    })
}

/// Per-row point calls on one stored value read in slices before the value
/// is decoded whole: a join of many rows with one terrain then pays one
/// decode, as before, while a query touching a few points never does.
pub const SLICED_CALLS: u64 = 2000;
/// Most stored values read in slices at once per backend: enough for the
/// tiles a county's boundary meets (a query that cycles through more
/// values than are kept reads every one again on every pass: with 64, the
/// 72 boundary tiles of a 5 km circle over 3 m tiles were all read again
/// each time). Their blocks stay within `tinmerge.cache_size` whatever
/// their number.
const MAX_SLICED: usize = 4096;

struct SlicedEntry {
    tin: Rc<SlicedTin>,
    calls: u64,
    last: u64,
}

#[derive(Default)]
struct Sliced {
    /// by (content hash, length)
    entries: FxHashMap<(u64, u64), SlicedEntry>,
    clock: u64,
}

impl Sliced {
    /// The least recently used entry's key.
    fn oldest(&self) -> Option<(u64, u64)> {
        self.entries
            .iter()
            .min_by_key(|(_, e)| e.last)
            .map(|(k, _)| *k)
    }
}

thread_local! {
    static SLICED: RefCell<Sliced> = RefCell::new(Sliced::default());
}

/// The stored value (hash, len) read in slices, made from its header bytes
/// with `make` on first use; `None` once it has served [`SLICED_CALLS`]
/// calls or holds an eighth of its blocks (the caller then decodes it
/// whole), or when `make` gives none (format 1). The blocks held by every
/// such value together stay within `tinmerge.cache_size`, least recently
/// used first out.
pub fn sliced(
    hash: u64,
    len: u64,
    make: impl FnOnce() -> Result<Option<SlicedTin>, TinError>,
) -> Option<Rc<SlicedTin>> {
    let limit = cache_limit();
    if limit == 0 {
        return None;
    }
    let found = SLICED.with(|c| {
        let mut c = c.borrow_mut();
        c.clock += 1;
        let now = c.clock;
        let e = c.entries.get_mut(&(hash, len))?;
        e.calls += 1;
        e.last = now;
        let (held, total) = e.tin.blocks();
        if e.calls > SLICED_CALLS || held as u64 * 8 > total {
            c.entries.remove(&(hash, len));
            return Some(None);
        }
        Some(Some(e.tin.clone()))
    });
    let tin = match found {
        Some(found) => found?,
        None => {
            // made outside the borrow: an ERROR must not leave it borrowed
            let t = Rc::new(make().unwrap_or_else(|e| raise_tin(e))?);
            SLICED.with(|c| {
                let mut c = c.borrow_mut();
                if c.entries.len() >= MAX_SLICED {
                    if let Some(k) = c.oldest() {
                        c.entries.remove(&k);
                    }
                }
                let last = c.clock;
                c.entries.insert(
                    (hash, len),
                    SlicedEntry {
                        tin: t.clone(),
                        calls: 1,
                        last,
                    },
                );
            });
            t
        }
    };
    SLICED.with(|c| {
        let mut c = c.borrow_mut();
        let mut used: usize = c.entries.values().map(|e| e.tin.cached_bytes()).sum();
        while used > limit && c.entries.len() > 1 {
            let Some(k) = c.oldest() else {
                break;
            };
            if let Some(e) = c.entries.remove(&k) {
                used -= e.tin.cached_bytes();
            }
        }
    });
    Some(tin)
}

/// (values, blocks, bytes) read in slices and held by this backend.
pub fn sliced_stats() -> (usize, usize, usize) {
    SLICED.with(|c| {
        let c = c.borrow();
        (
            c.entries.len(),
            c.entries.values().map(|e| e.tin.blocks().0).sum(),
            c.entries.values().map(|e| e.tin.cached_bytes()).sum(),
        )
    })
}

/// Count a hit served through a TOAST-key alias (bypassing the LRU scan).
pub fn count_alias_hit() {
    CACHE.with(|c| c.borrow_mut().hits += 1);
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

/// Subtree sums of stored values (`merge::area::surface::SubtreeSums`),
/// by (hash, length, target level), with the work done on each before its
/// sums were made: the statistics of an area sum the target level's
/// triangles inside one by one until that work would reach a quarter of
/// the level's triangle count ([`sums_due`]); then the sums are made (one
/// pass over the level, once) and that polygon and every later one adds a
/// coarse triangle inside in O(1). So a backend spends at most a quarter
/// of a pass before they pay, and a query of a few small polygons never
/// makes them. Bounded by a quarter of `tinmerge.cache_size`, least
/// recently used out first.
struct SumsEntry {
    work: u64,
    sums: Option<Arc<SubtreeSums>>,
    last: u64,
}

/// Most (value, level) work counters kept: enough for the tiles a county's
/// boundary meets, level by level (with 256, a cycle through 411 boundary
/// tiles dropped every tile's counter and sums before its next turn, and
/// made its sums again on every pass). An entry is a few dozen bytes; the
/// sums themselves stay within a quarter of `tinmerge.cache_size`.
const MAX_SUMS_ENTRIES: usize = 1 << 16;

#[derive(Default)]
struct SumsCache {
    /// by (content hash, length, level)
    entries: FxHashMap<(u64, u64, usize), SumsEntry>,
    clock: u64,
    /// bytes of the sums held (kept as they come and go: summing them over
    /// 65,536 entries on every call cost a 100 m circle's join 1.5 %)
    used: usize,
}

impl SumsCache {
    /// The entry of (hash, length, level), a fresh counter when there is
    /// none.
    fn entry(&mut self, key: (u64, u64, usize), now: u64) -> &mut SumsEntry {
        self.entries.entry(key).or_insert(SumsEntry {
            work: 0,
            sums: None,
            last: now,
        })
    }

    /// Drop the least recently used sums until `extra` more bytes fit in
    /// `limit`; past [`MAX_SUMS_ENTRIES`] counters, the older half of them.
    fn trim(&mut self, limit: usize, extra: usize) {
        while self.used + extra > limit {
            let Some(k) = self
                .entries
                .iter()
                .filter(|(_, e)| e.sums.is_some())
                .min_by_key(|(_, e)| e.last)
                .map(|(k, _)| *k)
            else {
                break;
            };
            if let Some(e) = self.entries.get_mut(&k) {
                self.used -= e.sums.take().map_or(0, |s| s.bytes());
            }
        }
        if self.entries.len() > MAX_SUMS_ENTRIES {
            let mut lasts: Vec<u64> = self.entries.values().map(|e| e.last).collect();
            let mid = lasts.len() / 2;
            let (_, cut, _) = lasts.select_nth_unstable(mid);
            let cut = *cut;
            let mut dropped = 0;
            self.entries.retain(|_, e| {
                let keep = e.last >= cut;
                if !keep {
                    dropped += e.sums.as_ref().map_or(0, |s| s.bytes());
                }
                keep
            });
            self.used -= dropped;
        }
        memory::set_cached_sums(self.used);
    }
}

thread_local! {
    static SUMS: RefCell<SumsCache> = RefCell::new(SumsCache::default());
}

/// The subtree sums of the value (hash, len) at `level`, when made.
pub fn subtree_sums(hash: u64, len: u64, level: usize) -> Option<Arc<SubtreeSums>> {
    SUMS.with(|c| {
        let mut c = c.borrow_mut();
        c.clock += 1;
        let now = c.clock;
        let e = c.entries.get_mut(&(hash, len, level))?;
        e.last = now;
        e.sums.clone()
    })
}

/// `work` triangles of `level` (of `triangles`) about to be summed one by
/// one on the value (hash, len), added to what was summed before: true
/// when the sums are due (no sums yet, and the work reaches a quarter of
/// the level: then making them, about one pass over the level, costs less
/// than what a few more such polygons would).
pub fn sums_due(hash: u64, len: u64, level: usize, work: u64, triangles: u64) -> bool {
    SUMS.with(|c| {
        let mut c = c.borrow_mut();
        c.clock += 1;
        let now = c.clock;
        let e = c.entry((hash, len, level), now);
        e.last = now;
        e.work = e.work.saturating_add(work);
        e.sums.is_none() && e.work.saturating_mul(4) >= triangles
    })
}

/// The sums of the value (hash, len) at `level` made with `make`
/// (estimated at `bytes`) and kept; None when they would not fit in a
/// quarter of `tinmerge.cache_size`.
pub fn make_sums(
    hash: u64,
    len: u64,
    level: usize,
    bytes: usize,
    make: impl FnOnce() -> Result<SubtreeSums, TinError>,
) -> Option<Arc<SubtreeSums>> {
    let limit = cache_limit() / 4;
    if bytes > limit {
        return None;
    }
    memory::reserve(bytes, || {
        format!("the subtree sums of a stored tin's level {level}")
    });
    // made outside the borrow: an ERROR here must not leave it borrowed
    let sums = Arc::new(make().unwrap_or_else(|e| raise_tin(e)));
    SUMS.with(|c| {
        let mut c = c.borrow_mut();
        c.trim(limit, sums.bytes());
        let now = c.clock;
        let e = c.entry((hash, len, level), now);
        let before = e.sums.replace(sums.clone()).map_or(0, |s| s.bytes());
        e.last = now;
        c.used = c.used - before + sums.bytes();
        memory::set_cached_sums(c.used);
    });
    Some(sums)
}

/// `tin_cache_stats()`: this backend's cache (hits, misses, entries, bytes).
#[pg_extern(volatile, parallel_safe)]
fn tin_cache_stats() -> TableIterator<
    'static,
    (
        name!(hits, i64),
        name!(misses, i64),
        name!(entries, i32),
        name!(bytes, i64),
        name!(sliced_values, i32),
        name!(sliced_blocks, i64),
        name!(sliced_bytes, i64),
    ),
> {
    let (h, m, e, b) = stats();
    let (sv, sb, sn) = sliced_stats();
    TableIterator::once((
        h as i64, m as i64, e as i32, b as i64, sv as i32, sb as i64, sn as i64,
    ))
}

extension_sql!(
    r#"
ALTER FUNCTION tin_cache_stats() ROWS 1;
COMMENT ON FUNCTION tin_cache_stats() IS 'This backend''s decoded-tin cache: hits, misses, entries and bytes; and the stored values it reads in slices (per-row point functions on a value it has not decoded): values, blocks held, bytes held (see tinmerge.cache_size).';
"#,
    name = "tin_cache_stats_sql",
    requires = [tin_cache_stats]
);
