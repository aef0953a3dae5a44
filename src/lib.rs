//! tinmerge: adaptive hierarchical triangulations merged with PostGIS data.
//!
//! This crate is the SQL layer only (`pg`): it converts arguments, calls the
//! pure core ([`tinmerge_core`]: the hierarchy, the merges, readers/writers,
//! pictures; no pgrx, a separate crate of the workspace so the compiler keeps
//! it that way) and maps its errors to SQLSTATEs.
#![deny(clippy::undocumented_unsafe_blocks)]

pub mod pg;

/// Every Rust allocation is counted (`tinmerge_core::tin::memory`): the SQL
/// layer bounds a call's memory with it (`tinmerge.max_memory`).
#[global_allocator]
static ALLOCATOR: tinmerge_core::tin::memory::Counting = tinmerge_core::tin::memory::Counting;

/// Required at the crate root by `cargo pgrx test`.
#[cfg(test)]
pub mod pg_test {
    pub fn setup(_options: Vec<&str>) {}
    pub fn postgresql_conf_options() -> Vec<&'static str> {
        vec![]
    }
}
