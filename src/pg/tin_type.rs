//! The `tin` SQL type: a flat varlena (see `tinmerge_core::tin::layout`) passed to
//! Rust as the raw Datum, so header-only functions read just a slice and
//! full reads go through the backend cache.

use pgrx::callconv::{BoxRet, FcInfo};
use pgrx::datum::Datum as RetDatum;
use pgrx::pg_sys;
use pgrx::prelude::*;
use pgrx::IntoDatum;
use std::ffi::{CStr, CString};
use std::rc::Rc;
use std::sync::{Arc, Weak};

use super::cache;
use super::errors::{raise, OrRaise};
use super::interrupt::interrupt;
use super::memory;
use super::varlena::{hex_input, recv_bytes, varlena_datum};
use tinmerge_core::merge::area::whole;
use tinmerge_core::tin::lattice::Lattice;
use tinmerge_core::tin::layout::{self, Header, HEADER_LEN};
use tinmerge_core::tin::sliced::SlicedTin;
use tinmerge_core::tin::{Tin, TinError};

/// Bytes of data in one TOAST chunk (PostgreSQL's `TOAST_MAX_CHUNK_SIZE`,
/// a macro bindgen does not export; 1,996 for 8 KB blocks): a slice read
/// costs the chunks it touches, so sliced reads ask for whole chunks.
const TOAST_CHUNK: u64 = {
    const fn maxalign(n: u64) -> u64 {
        (n + 7) & !7
    }
    // EXTERN_TUPLE_MAX_SIZE (4 tuples per page, after the page header and
    // their item pointers), less the tuple header, chunk id, chunk number
    // and varlena header of a chunk row
    let tuple_max = ((pg_sys::BLCKSZ as u64 - maxalign(24 + 4 * 4)) / 4) & !7;
    tuple_max - maxalign(23) - 4 - 4 - 4
};
const _: () = assert!(pg_sys::BLCKSZ != 8192 || TOAST_CHUNK == 1996);
/// Chunks read past a missing one (the next groups of an array are
/// usually the next ones a merge needs; docs/performance.md).
const READ_AHEAD: u64 = 1;
/// Chunks read with the header when a value is first read in slices, with
/// as much of its group directory as they hold (8 KB: the whole directory
/// of a value of up to about 2,000 groups); the rest of a larger directory
/// is read a page at a time as groups are needed.
const PREFIX_CHUNKS: u64 = 4;

/// The backend's local transaction id: unique per transaction in this
/// backend (read-only ones included), unlike the start timestamp, which two
/// quick transactions can share.
pub(super) fn transaction_epoch() -> i64 {
    // SAFETY: MyProc is either NULL (checked) or this backend's PGPROC, valid
    // for the backend's life; the timestamp call has no preconditions.
    unsafe {
        let proc_ = pg_sys::MyProc;
        if proc_.is_null() {
            pg_sys::GetCurrentTransactionStartTimestamp()
        } else {
            i64::from((*proc_).lxid)
        }
    }
}

/// What the point and line functions read: the decoded value, or the
/// stored value read block by block (see [`TinArg::mesh_source`]).
pub enum MeshSource {
    Decoded(Arc<Tin>),
    Sliced(Rc<SlicedTin>),
}

raw_datum_arg!(
    /// A `tin` argument: the Datum as passed, not detoasted.
    TinArg,
    "tin"
);

impl TinArg {
    fn ptr(&self) -> *mut pg_sys::varlena {
        self.0.cast_mut_ptr()
    }

    /// The TOAST pointer's identity when the Datum is an on-disk TOAST
    /// pointer (the usual case for a tin read from a table).
    fn toast_key(&self) -> Option<cache::ToastKey> {
        let p = self.ptr();
        // SAFETY: p is this call's non-NULL tin Datum; its first byte tells the
        // varlena kind, and only an external (1b_e) header of the on-disk tag is
        // read as a varatt_external, unaligned as it is stored.
        unsafe {
            if pgrx::varatt_is_1b_e(p)
                && pgrx::vartag_external(p) as u32 == pg_sys::vartag_external::VARTAG_ONDISK
            {
                let e = std::ptr::read_unaligned(
                    pgrx::vardata_1b_e(p) as *const pg_sys::varatt_external
                );
                Some(cache::ToastKey {
                    relid: e.va_toastrelid.to_u32(),
                    valueid: e.va_valueid.to_u32(),
                    rawsize: e.va_rawsize,
                    extinfo: e.va_extinfo,
                })
            } else {
                None
            }
        }
    }

    /// For an on-disk value: its TOAST key, the transaction it is looked up
    /// in, and what this transaction remembers of it.
    fn remembered(&self) -> Option<(cache::ToastKey, i64, Option<cache::Alias>)> {
        let key = self.toast_key()?;
        let epoch = transaction_epoch();
        Some((key, epoch, cache::alias_for(&key, epoch)))
    }

    /// The decoded value when this transaction met the same on-disk value
    /// before and it is still cached: the per-row path of a join with a
    /// terrain or a table of tiles (no clone of what is remembered).
    fn decoded_as_before(&self) -> Option<Arc<Tin>> {
        let key = self.toast_key()?;
        cache::decoded_alias(&key, transaction_epoch())
    }

    /// What this transaction knows of the value without decoding it: its
    /// header (remembered from an earlier row for the same on-disk value,
    /// or read through a prefix slice and remembered), and the TOAST key
    /// and transaction a decode is to be remembered under (None for a value
    /// not on disk). The decoded value still at hand is
    /// [`TinArg::decoded_as_before`]'s.
    fn known(&self) -> Known {
        let Some((key, epoch, alias)) = self.remembered() else {
            return Known {
                header: Arc::new(self.read_header()),
                key: None,
            };
        };
        let header = match alias {
            Some(a) => a.header,
            None => {
                let header = Arc::new(self.read_header());
                cache::remember(
                    key,
                    epoch,
                    cache::Alias {
                        header: header.clone(),
                        tin: Weak::new(),
                    },
                );
                header
            }
        };
        Known {
            header,
            key: Some((key, epoch)),
        }
    }

    /// The fixed header, read through a prefix slice (no full detoast), or
    /// remembered from an earlier row of this transaction for the same
    /// on-disk value.
    pub fn header(&self) -> Arc<Header> {
        self.known().header
    }

    fn read_header(&self) -> Header {
        layout::read_header(self.slice(0, HEADER_LEN)).or_raise()
    }

    /// The whole value's bytes (detoasted into the current memory context).
    pub fn bytes(&self) -> &[u8] {
        // SAFETY: self's Datum is a non-NULL tin of this call; the detoasted copy
        // is palloc'd in the current memory context, which outlives the borrow.
        unsafe {
            let v = pg_sys::pg_detoast_datum(self.ptr());
            pgrx::varlena::varlena_to_byte_slice(v)
        }
    }

    /// For the point and line functions: the decoded value when this backend
    /// holds it (or the value is not stored out of line, or is in format
    /// 1), otherwise the stored value read in slices, so a query that
    /// touches a few points or lines of a large terrain reads a few blocks,
    /// not the whole value. After [`cache::SLICED_CALLS`] calls on one value,
    /// or once it holds an eighth of the blocks, it is decoded whole.
    pub fn mesh_source(&self) -> MeshSource {
        if let Some(t) = self.decoded_as_before() {
            cache::count_alias_hit();
            return MeshSource::Decoded(t);
        }
        let k = self.known();
        if k.key.is_none() || k.header.version == layout::VERSION_1 {
            return MeshSource::Decoded(self.decode(k));
        }
        if let Some(t) = cache::peek(k.header.hash, k.header.total_len) {
            // decoded by an earlier transaction: remembered for the rest of
            // this one, so its next rows take the first path above
            k.remember(&t);
            return MeshSource::Decoded(t);
        }
        match cache::sliced(k.header.hash, k.header.total_len, || {
            // the header and the group directory in one read, in whole
            // chunks, up to PREFIX_CHUNKS of them
            let want = SlicedTin::prefix_len(&k.header)
                .div_ceil(TOAST_CHUNK)
                .clamp(1, PREFIX_CHUNKS)
                * TOAST_CHUNK;
            let prefix = self.slice(0, want.min(k.header.total_len) as usize);
            SlicedTin::new(prefix)
                .map(|s| s.map(|s| s.with_units(TOAST_CHUNK, READ_AHEAD).with_prefix(prefix)))
        }) {
            Some(s) => MeshSource::Sliced(s),
            None => MeshSource::Decoded(self.decode(k)),
        }
    }

    /// Bytes `at..at + len` of the stored value (offsets past its varlena
    /// header), fetching only the TOAST
    /// chunks that cover them (fewer when the value is shorter).
    fn slice(&self, at: u64, len: usize) -> &[u8] {
        // SAFETY: as in bytes(); past the value's end PostgreSQL returns a
        // shorter or empty slice.
        unsafe {
            let s = pg_sys::pg_detoast_datum_slice(self.ptr(), at as i32, len as i32);
            pgrx::varlena::varlena_to_byte_slice(s)
        }
    }

    /// The fetch a [`SlicedTin`] reads its blocks with.
    pub fn fetch(&self) -> impl FnMut(u64, usize) -> Result<Vec<u8>, TinError> + '_ {
        move |at, len| {
            if at.saturating_add(len as u64) > i32::MAX as u64 {
                return Err(TinError::Corrupt(format!(
                    "block at {at} lies beyond the largest value"
                )));
            }
            Ok(self.slice(at, len).to_vec())
        }
    }

    /// The decoded, validated value, from the backend cache when the same
    /// content was decoded before. For a stored value met again in this
    /// transaction this is one look-up, with no read of the value at all.
    pub fn tin(&self) -> Arc<Tin> {
        if let Some(t) = self.decoded_as_before() {
            cache::count_alias_hit();
            return t;
        }
        self.decode(self.known())
    }

    /// The decoded value for what is known of it (from the backend cache
    /// when the same content was decoded before), remembered for the rest
    /// of the transaction.
    fn decode(&self, k: Known) -> Arc<Tin> {
        let need = layout::decode_bytes(&k.header);
        let tin = cache::get_or_decode(k.header.hash, k.header.total_len, need, || {
            layout::decode_checked(self.bytes(), &mut interrupt)
        });
        k.remember(&tin);
        tin
    }
}

/// See [`TinArg::known`].
struct Known {
    header: Arc<Header>,
    key: Option<(cache::ToastKey, i64)>,
}

impl Known {
    /// Remember `tin` as the decoded value for the rest of the transaction
    /// (a value on disk only).
    fn remember(self, tin: &Arc<Tin>) {
        if let Some((key, epoch)) = self.key {
            let alias = cache::Alias {
                header: self.header,
                tin: Arc::downgrade(tin),
            };
            cache::remember(key, epoch, alias);
        }
    }
}

/// A `tin` result: storage bytes, copied into a palloc'd varlena on return.
pub struct TinOut(pub Vec<u8>);

impl IntoDatum for TinOut {
    fn into_datum(self) -> Option<pg_sys::Datum> {
        Some(varlena_datum(&self.0, "tin"))
    }
    fn type_oid() -> pg_sys::Oid {
        pg_sys::InvalidOid
    }
}

// SAFETY: box_into returns the Datum of into_datum (a palloc'd tin
// varlena), or NULL.
unsafe impl BoxRet for TinOut {
    unsafe fn box_into<'fcx>(self, fcinfo: &mut FcInfo<'fcx>) -> RetDatum<'fcx> {
        match self.into_datum() {
            // SAFETY: d is a complete palloc'd tin varlena.
            Some(d) => unsafe { fcinfo.return_raw_datum(d) },
            None => fcinfo.return_null(),
        }
    }
}

pgrx::pgrx_sql_entity_graph::impl_sql_translatable!(TinOut, "tin");

impl TinOut {
    /// A tin in the current storage format, each level's whole sums in its
    /// header (format 6 or 7: `merge::area::whole`).
    pub fn from_tin(t: &Tin) -> TinOut {
        Self::encode(t, None)
    }

    /// A tin built on a raster's pixel lattice: vertices stored as lattice
    /// indices and float32 heights when they are exactly that.
    pub fn from_tin_on(t: &Tin, lattice: &Lattice) -> TinOut {
        Self::encode(t, Some(lattice))
    }

    /// Pure (no PostgreSQL call): tiles are encoded on worker threads. The
    /// sums cost a walk of each level, a few percent of a build. Should
    /// they fail (a sweep around the terrain crossing a triangle: a bug,
    /// never seen) the value is written without them (format 4 or 5),
    /// whose answers come from its triangles, the same.
    fn encode(t: &Tin, lattice: Option<&Lattice>) -> TinOut {
        match whole::level_sums(t, &mut || Ok(())) {
            Ok(sums) => TinOut(layout::encode_with_sums(t, lattice, &sums)),
            Err(_) => TinOut(layout::encode_on(t, lattice)),
        }
    }
}

extension_sql!(
    "CREATE TYPE tin;\nCREATE TYPE linetree;",
    name = "tin_shell",
    bootstrap
);

/// Input bytes as a result value, once they decode and validate in full;
/// otherwise an ERROR with `code`.
fn validated(bytes: Vec<u8>, code: PgSqlErrorCode) -> TinOut {
    memory::reserve(layout::decode_bytes_of(&bytes), || {
        format!("reading a tin value of {} bytes", bytes.len())
    });
    if let Err(e) = layout::decode(&bytes) {
        raise(code, e.to_string());
    }
    TinOut(bytes)
}

/// Text input: hex of the storage bytes, fully validated.
#[pg_extern(immutable, strict, parallel_safe, requires = ["tin_shell"])]
fn tin_in(input: &CStr) -> TinOut {
    let bytes = hex_input(input, "tin");
    validated(bytes, PgSqlErrorCode::ERRCODE_INVALID_TEXT_REPRESENTATION)
}

extension_sql!(
    r#"
COMMENT ON FUNCTION tin_in(cstring) IS 'Text input of tin: hex of the binary form, fully validated.';
"#,
    name = "tin_in_sql",
    requires = [tin_in]
);

/// Text output: upper-case hex of the storage bytes.
#[pg_extern(immutable, strict, parallel_safe, requires = ["tin_shell"])]
fn tin_out(t: TinArg) -> CString {
    CString::new(layout::to_hex(t.bytes())).unwrap_or_default()
}

extension_sql!(
    r#"
COMMENT ON FUNCTION tin_out(tin) IS 'Text output of tin: hex of the binary form.';
"#,
    name = "tin_out_sql",
    requires = [tin_out]
);

/// Binary input: the storage bytes, fully validated.
#[pg_extern(immutable, strict, parallel_safe, requires = ["tin_shell"])]
fn tin_recv(mut buf: pgrx::datum::Internal) -> TinOut {
    let bytes = recv_bytes(&mut buf, "tin");
    validated(bytes, PgSqlErrorCode::ERRCODE_INVALID_BINARY_REPRESENTATION)
}

extension_sql!(
    r#"
COMMENT ON FUNCTION tin_recv(internal) IS 'Binary input of tin, fully validated.';
"#,
    name = "tin_recv_sql",
    requires = [tin_recv]
);

/// Binary output: the storage bytes.
#[pg_extern(immutable, strict, parallel_safe, requires = ["tin_shell"])]
fn tin_send(t: TinArg) -> Vec<u8> {
    t.bytes().to_vec()
}

extension_sql!(
    r#"
COMMENT ON FUNCTION tin_send(tin) IS 'Binary output of tin.';
"#,
    name = "tin_send_sql",
    requires = [tin_send]
);

extension_sql!(
    r#"
CREATE TYPE tin (
    INPUT = tin_in,
    OUTPUT = tin_out,
    RECEIVE = tin_recv,
    SEND = tin_send,
    INTERNALLENGTH = VARIABLE,
    ALIGNMENT = double,
    STORAGE = external
);
COMMENT ON TYPE tin IS 'A terrain surface as an adaptive hierarchical triangulation: levels 0 (coarsest) to n-1 (finest), each nested in the previous one. Text form: hex of the binary form.';
"#,
    name = "tin_type",
    requires = [tin_in, tin_out, tin_recv, tin_send]
);

/// `tin_rewrite`: the same terrain in the current storage format (one
/// whose header holds the sums, format 6 or 7, is returned as it is; a value
/// stored by an older version keeps reading as it is; rewriting it lets the
/// per-row point functions read it in slices).
#[pg_extern(support = _tin_plan_support, immutable, strict, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn tin_rewrite(t: TinArg) -> TinOut {
    if !t.header().sums.is_empty() {
        return TinOut(t.bytes().to_vec());
    }
    TinOut::from_tin(&t.tin())
}

extension_sql!(
    r#"
COMMENT ON FUNCTION tin_rewrite(tin) IS 'The same tin in the current storage format (format 6, or 7 with void triangles: compressed groups with their own checksums, about a fifth of format 3, read in slices by the point, line and area functions, and each level''s whole statistics in the header, so a tile wholly inside a polygon is answered from its header); a value already in it is returned as it is. Answers do not change. UPDATE terrain SET t = tin_rewrite(t) converts stored values (docs/upgrading.md).';
"#,
    name = "tin_rewrite_sql",
    requires = [tin_rewrite]
);

/// `=` on tin: the same stored bytes. Two pointers to the same on-disk
/// TOAST value are equal without reading it (`GROUP BY t` over the rows of
/// a merge meets the same terrain on every row); otherwise the headers'
/// content hashes and lengths are compared first (header-only reads), the
/// bytes only when they agree.
#[pg_extern(immutable, strict, parallel_safe, requires = ["tin_type"])]
fn tin_eq(a: TinArg, b: TinArg) -> bool {
    if let (Some(ka), Some(kb)) = (a.toast_key(), b.toast_key()) {
        if ka == kb {
            return true;
        }
    }
    let (ha, hb) = (a.header(), b.header());
    ha.hash == hb.hash && ha.total_len == hb.total_len && a.bytes() == b.bytes()
}

extension_sql!(
    r#"
COMMENT ON FUNCTION tin_eq(tin, tin) IS 'True when two tins are the same value (the same bytes; header hashes and lengths compared first). The function behind the = operator.';
"#,
    name = "tin_eq_sql",
    requires = [tin_eq]
);

/// `<>` on tin.
#[pg_extern(immutable, strict, parallel_safe, requires = ["tin_type"])]
fn tin_ne(a: TinArg, b: TinArg) -> bool {
    !tin_eq(a, b)
}

extension_sql!(
    r#"
COMMENT ON FUNCTION tin_ne(tin, tin) IS 'True when two tins are different values. The function behind the <> operator.';
"#,
    name = "tin_ne_sql",
    requires = [tin_ne]
);

/// Hash support for `=` (GROUP BY, DISTINCT, hash joins): the header's
/// content hash folded to 32 bits; equal values have equal headers.
#[pg_extern(immutable, strict, parallel_safe, requires = ["tin_type"])]
fn tin_hash(t: TinArg) -> i32 {
    let h = t.header().hash;
    (h ^ (h >> 32)) as u32 as i32
}

extension_sql!(
    r#"
COMMENT ON FUNCTION tin_hash(tin) IS '32-bit hash of a tin (its stored content hash): hash operator class support for =.';
"#,
    name = "tin_hash_sql",
    requires = [tin_hash]
);

/// The decoded tin of an argument and a level resolved against it (one
/// cache look-up per row).
pub(crate) fn tin_level(t: &TinArg, level: Option<i32>) -> (Arc<Tin>, usize) {
    let tin = t.tin();
    let l = tin.level_index(level).or_raise();
    (tin, l)
}
