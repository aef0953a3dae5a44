//! SQL layer (placeholder while the core compiles).
