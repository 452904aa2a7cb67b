//! What another thread may do to a running derivation: cancel it, and watch how far it got.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// Shared with a running derivation through [`super::DeriveOptions::control`]: the engine
/// checks it where it checks the time budget (every 1,024 rule applications of a lot), so a
/// cancelled derivation stops within about a millisecond, and counts the rule applications it
/// has made there.
#[derive(Debug, Default)]
pub struct DeriveControl {
    cancelled: AtomicBool,
    applications: AtomicU64,
}

/// How many rule applications pass between two checks of the control.
pub(crate) const CHECK_EVERY: u64 = 1024;

impl DeriveControl {
    /// A control that has not been cancelled and has counted nothing.
    pub fn new() -> Self {
        Self::default()
    }

    /// Asks the derivations using this control to stop with an error at their next check.
    pub fn cancel(&self) {
        self.cancelled.store(true, Ordering::Relaxed);
    }

    /// Whether [`DeriveControl::cancel`] was called since the last [`DeriveControl::reset`].
    pub fn is_cancelled(&self) -> bool {
        self.cancelled.load(Ordering::Relaxed)
    }

    /// Rule applications counted so far, in steps of 1,024 per lot (a derivation of fewer
    /// applications counts none).
    pub fn applications(&self) -> u64 {
        self.applications.load(Ordering::Relaxed)
    }

    /// Clears the cancellation and the count, for the next derivation.
    pub fn reset(&self) {
        self.cancelled.store(false, Ordering::Relaxed);
        self.applications.store(0, Ordering::Relaxed);
    }

    /// Counts a check's worth of applications; whether the derivation must stop.
    pub(crate) fn tick(&self) -> bool {
        self.applications.fetch_add(CHECK_EVERY, Ordering::Relaxed);
        self.is_cancelled()
    }
}
