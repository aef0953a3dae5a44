//! The core's interrupt callback (`tinmerge_core::tin::Interrupt`):
//! PostgreSQL's `CHECK_FOR_INTERRUPTS`, then the running
//! `tinmerge.max_memory` check.

use pgrx::prelude::*;

use super::memory;
use tinmerge_core::tin::TinError;

/// Cancel requests and the memory limit, between pieces of work.
pub(crate) fn interrupt() -> Result<(), TinError> {
    pg_sys::check_for_interrupts!();
    memory::check()
}
