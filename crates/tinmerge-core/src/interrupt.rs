//! Cancelling long work: every long-running core function takes an
//! [`Interrupt`] callback, which the SQL layer points at PostgreSQL's
//! `CHECK_FOR_INTERRUPTS` plus its memory limit and tests at a counter. An
//! `Err` from it stops the work and is returned as is (usually
//! [`TinError::Interrupted`] or [`TinError::MemoryLimit`]).
//!
//! Loops that do little per step call it through a [`Ticker`], every
//! [`Ticker::EVERY`] steps, so the check costs nothing measurable.
//!
//! ```
//! use tinmerge_core::interrupt::{Interrupt, Ticker};
//! use tinmerge_core::error::TinError;
//!
//! fn count(n: u32, interrupt: &mut Interrupt<'_>) -> Result<u32, TinError> {
//!     let mut ticker = Ticker::new(interrupt);
//!     for _ in 0..n {
//!         ticker.tick()?;
//!     }
//!     Ok(n)
//! }
//! let mut calls = 0;
//! assert_eq!(count(10_000, &mut || { calls += 1; Ok(()) }).unwrap(), 10_000);
//! assert_eq!(calls, 2); // at ticks 4096 and 8192
//! assert!(count(5_000, &mut || Err(TinError::Interrupted)).is_err());
//! ```

use crate::error::TinError;

/// The interrupt callback every long-running function takes as
/// `&mut Interrupt<'_>`.
pub type Interrupt<'a> = dyn FnMut() -> Result<(), TinError> + 'a;

/// Calls an [`Interrupt`] every [`Ticker::EVERY`] ticks of a long loop.
pub struct Ticker<'a, 'b> {
    n: u32,
    f: &'a mut Interrupt<'b>,
}

impl<'a, 'b> Ticker<'a, 'b> {
    /// Ticks between two calls of the callback.
    pub const EVERY: u32 = 4096;

    pub fn new(f: &'a mut Interrupt<'b>) -> Self {
        Ticker { n: 0, f }
    }

    /// One step of work; calls the callback every [`Ticker::EVERY`] steps.
    #[inline]
    pub fn tick(&mut self) -> Result<(), TinError> {
        self.n = self.n.wrapping_add(1);
        if self.n.is_multiple_of(Self::EVERY) {
            (self.f)()?;
        }
        Ok(())
    }

    /// The callback itself, to hand to work that checks on its own terms
    /// (`tin::par::map_batched` between batches).
    pub fn callback(&mut self) -> &mut Interrupt<'b> {
        self.f
    }

    /// Call the callback now (between coarse pieces of work).
    pub fn check(&mut self) -> Result<(), TinError> {
        (self.f)()
    }
}
