//! The flat little-endian storage layout of a `tin` value (the bytes after the
//! 4-byte varlena length word).
//!
//! ```text
//! offset size  field
//!      0    4  magic "TINM"
//!      4    2  format version (6 with the sums, 7 with the sums and void
//!              triangles: what the extension writes; 4 and 5 without
//!              the sums; 1 and 3 still read)
//!      6    2  flags (0)
//!      8    4  header length (version 1: 856, version 3: 864, versions 4
//!              and 5: 920, versions 6 and 7: 1944)
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
//!    912 1024  (version 6) 16 level sums of 64 bytes (unused ones zero):
//!              planar area, surface area, min z, max z, integral of z,
//!              integral of slope, steepest slope (f64), reserved 8
//!              ([`LevelSums`])
//!   1936    8  (version 6) header hash: xxh3-64 of bytes 0..1936 with the
//!              content hash zeroed
//! ```
//! Version 5 is version 4 with void triangles (see [`super::Level::num_void`]):
//! an older reader must refuse it, not show the void as terrain. Versions 6
//! and 7 are versions 4 and 5 with each level's sums over its whole surface
//! in the header (`merge::area::whole` makes them; written since 0.26.0),
//! so a polygon that holds the terrain is answered from the first TOAST
//! chunk alone; a reader checks them for sense ([`read_header`]: finite,
//! areas positive, heights within the bbox, slopes in 0..90), the header
//! hash for damage.
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
//!
//! The parts: `read` (the header and the value's sections and blocks),
//! `seal` (checksums, hashes, resealing), `encode`, `decode`, `hex` (the
//! text form).

mod decode;
mod encode;
mod hex;
mod read;
mod seal;

pub use decode::*;
pub use encode::*;
pub use hex::*;
pub use read::*;
pub use seal::*;
