//! tinmerge: adaptive hierarchical triangulations merged with PostGIS data.
//!
//! `tin`, `merge` and `io` are pure Rust (no pgrx); `pg` is the SQL layer.
pub mod io;
pub mod merge;
pub mod tin;

pub mod pg;

/// Required at the crate root by `cargo pgrx test`.
#[cfg(test)]
pub mod pg_test {
    pub fn setup(_options: Vec<&str>) {}
    pub fn postgresql_conf_options() -> Vec<&'static str> {
        vec![]
    }
}
