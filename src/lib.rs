//! tinmerge: adaptive hierarchical triangulations merged with PostGIS data.
//!
//! `tin`, `merge`, `render` and `io` are pure Rust (no pgrx); `pg` is the SQL layer.
pub mod io;
pub mod merge;
pub mod render;
pub mod tin;

pub mod pg;

/// Every Rust allocation is counted (`tin::memory`): the SQL layer bounds a
/// call's memory with it (`tinmerge.max_memory`), tests measure peaks.
#[global_allocator]
static ALLOCATOR: tin::memory::Counting = tin::memory::Counting;

/// Required at the crate root by `cargo pgrx test`.
#[cfg(test)]
pub mod pg_test {
    pub fn setup(_options: Vec<&str>) {}
    pub fn postgresql_conf_options() -> Vec<&'static str> {
        vec![]
    }
}
