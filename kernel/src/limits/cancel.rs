//! The cancellation token: an interrupt flag, a deadline and an operation count, checked by
//! long loops of the kernel so that any of them stops the work within a fraction of a second.
//!
//! The token of the running work is the calling thread's *current* token ([`install`]); kernel
//! loops call [`check`] (one unit of work) or [`charge`] (`n` units: elements processed), which
//! cost an atomic add and, every 1024 units, a clock read. Parallel loops take [`current`] on
//! the calling thread and check that token on the workers. Without a token nothing is ever
//! stopped.

use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Instant;

use super::{LimitError, StopReason};

/// What stops a piece of work: any of an interrupt flag, a deadline, an operation count with
/// its maximum. Clones share their state.
#[derive(Clone, Debug, Default)]
pub struct CancelToken {
    inner: Arc<Inner>,
}

#[derive(Debug, Default)]
struct Inner {
    interrupt: Option<Arc<AtomicBool>>,
    deadline: Option<(Instant, f64)>,
    operations: Option<(Arc<AtomicU64>, u64)>,
    /// Units charged, to read the clock every 1024 of them.
    work: AtomicU64,
}

impl CancelToken {
    /// A token with no condition: it never stops anything.
    #[must_use]
    pub fn new() -> CancelToken {
        CancelToken::default()
    }

    /// A token stopping when `interrupt` is set (it is only read, never cleared), when
    /// `deadline` (an instant and the limit in seconds, for the message) passes, or when the
    /// shared `operations` counter passes its maximum; kernel work adds its units to that
    /// counter.
    #[must_use]
    pub fn with(
        interrupt: Option<Arc<AtomicBool>>,
        deadline: Option<(Instant, f64)>,
        operations: Option<(Arc<AtomicU64>, u64)>,
    ) -> CancelToken {
        CancelToken { inner: Arc::new(Inner { interrupt, deadline, operations, work: AtomicU64::new(0) }) }
    }

    /// Whether the token can ever stop anything.
    #[must_use]
    pub fn is_active(&self) -> bool {
        self.inner.interrupt.is_some() || self.inner.deadline.is_some() || self.inner.operations.is_some()
    }

    /// Why the work must stop now, if it must (reads the clock).
    #[must_use]
    pub fn stopped(&self) -> Option<StopReason> {
        let i = &self.inner;
        if i.interrupt.as_ref().is_some_and(|f| f.load(Ordering::Relaxed)) {
            return Some(StopReason::Interrupted);
        }
        if let Some((counter, max)) = &i.operations {
            if counter.load(Ordering::Relaxed) > *max {
                return Some(StopReason::Operations { max: *max });
            }
        }
        match i.deadline {
            Some((at, seconds)) if Instant::now() >= at => Some(StopReason::Timeout { seconds }),
            _ => None,
        }
    }

    /// Adds `units` of work, then checks the flag and the count (and the clock every 1024
    /// units).
    ///
    /// # Errors
    /// [`LimitError::Stopped`] with the reason.
    pub fn charge(&self, units: u64) -> Result<(), LimitError> {
        let i = &self.inner;
        if !self.is_active() {
            return Ok(());
        }
        if i.interrupt.as_ref().is_some_and(|f| f.load(Ordering::Relaxed)) {
            return Err(LimitError::Stopped(StopReason::Interrupted));
        }
        if let Some((counter, max)) = &i.operations {
            if counter.fetch_add(units, Ordering::Relaxed).saturating_add(units) > *max {
                return Err(LimitError::Stopped(StopReason::Operations { max: *max }));
            }
        }
        let before = i.work.fetch_add(units, Ordering::Relaxed);
        if let Some((at, seconds)) = i.deadline {
            if (before >> 10 != before.wrapping_add(units) >> 10 || units >= 1024) && Instant::now() >= at {
                return Err(LimitError::Stopped(StopReason::Timeout { seconds }));
            }
        }
        Ok(())
    }

    /// Whether `other` is this very token (a clone of it).
    #[must_use]
    pub fn same(&self, other: &CancelToken) -> bool {
        Arc::ptr_eq(&self.inner, &other.inner)
    }
}

thread_local! {
    static CURRENT: RefCell<Option<CancelToken>> = const { RefCell::new(None) };
}

/// Makes `token` the calling thread's current token until the guard is dropped (then the
/// previous one is restored). Cheap when `token` is already current.
#[must_use = "the token is current only while the guard lives"]
pub fn install(token: CancelToken) -> InstallGuard {
    let previous = CURRENT.with(|c| c.replace(Some(token)));
    InstallGuard { previous }
}

/// Restores the previous current token when dropped.
#[derive(Debug)]
pub struct InstallGuard {
    previous: Option<CancelToken>,
}

impl InstallGuard {
    /// Keeps the token current after the guard is gone (until another is installed).
    pub fn keep(mut self) {
        self.previous = None;
        std::mem::forget(self);
    }
}

impl Drop for InstallGuard {
    fn drop(&mut self) {
        let previous = self.previous.take();
        CURRENT.with(|c| *c.borrow_mut() = previous);
    }
}

/// Makes `token` the calling thread's current token for good (until another is installed),
/// unless it already is: an interpreter calls this on every step, so that kernel work it starts
/// — on whichever thread it runs — checks its token and never one left by earlier work.
pub fn make_current(token: &CancelToken) {
    let already = CURRENT.with(|c| c.borrow().as_ref().is_some_and(|t| t.same(token)));
    if !already {
        install(token.clone()).keep();
    }
}

/// The calling thread's current token (a never-stopping one when none is installed), to hand
/// to the workers of a parallel loop.
#[must_use]
pub fn current() -> CancelToken {
    CURRENT.with(|c| c.borrow().clone()).unwrap_or_default()
}

/// Whether the calling thread's current token has stopped (interrupt, deadline or operation
/// count), without charging any work: for the inner loops of work already charged as a whole,
/// called every [`POLL_EVERY`] items so that a stop lands within milliseconds.
///
/// # Errors
/// [`LimitError::Stopped`] with the reason.
pub fn poll() -> Result<(), LimitError> {
    CURRENT.with(|c| match c.borrow().as_ref().and_then(CancelToken::stopped) {
        Some(reason) => Err(LimitError::Stopped(reason)),
        None => Ok(()),
    })
}

/// How many items of an inner loop go between two [`poll`]s: 65,536 (a millisecond or less of
/// work per item of microseconds down to nanoseconds).
pub const POLL_EVERY: usize = 1 << 16;

/// [`poll`] when item `i` of a loop starts a new run of [`POLL_EVERY`] items.
///
/// # Errors
/// As [`poll`].
#[inline]
pub fn poll_at(i: usize) -> Result<(), LimitError> {
    if i.is_multiple_of(POLL_EVERY) && i > 0 {
        poll()
    } else {
        Ok(())
    }
}

/// Checks the calling thread's current token for one unit of work.
///
/// # Errors
/// [`LimitError::Stopped`] with the reason.
pub fn check() -> Result<(), LimitError> {
    charge(1)
}

/// Charges `units` of work to the calling thread's current token.
///
/// # Errors
/// [`LimitError::Stopped`] with the reason.
pub fn charge(units: u64) -> Result<(), LimitError> {
    CURRENT.with(|c| match &*c.borrow() {
        Some(t) => t.charge(units),
        None => Ok(()),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn polls_see_a_stop_without_charging_and_only_every_poll_every_items() {
        use std::sync::atomic::AtomicU64;
        let counter = Arc::new(AtomicU64::new(0));
        let flag = Arc::new(AtomicBool::new(false));
        let _g = install(CancelToken::with(Some(flag.clone()), None, Some((counter.clone(), 10))));
        poll().unwrap();
        flag.store(true, Ordering::Relaxed);
        assert_eq!(poll(), Err(LimitError::Stopped(StopReason::Interrupted)));
        poll_at(1).unwrap();
        poll_at(0).unwrap();
        assert_eq!(poll_at(POLL_EVERY), Err(LimitError::Stopped(StopReason::Interrupted)));
        assert_eq!(counter.load(Ordering::Relaxed), 0, "a poll charges nothing");
    }

    #[test]
    fn no_token_never_stops() {
        for _ in 0..5000 {
            check().unwrap();
        }
        assert!(current().stopped().is_none());
    }

    #[test]
    fn the_interrupt_flag_stops_the_installed_token_and_the_guard_restores_the_previous() {
        let flag = Arc::new(AtomicBool::new(false));
        {
            let _g = install(CancelToken::with(Some(flag.clone()), None, None));
            check().unwrap();
            flag.store(true, Ordering::Relaxed);
            assert_eq!(check(), Err(LimitError::Stopped(StopReason::Interrupted)));
            // The flag is the caller's: reading it does not clear it.
            assert!(flag.load(Ordering::Relaxed));
        }
        check().unwrap();
    }

    #[test]
    fn the_operation_count_is_shared_with_the_caller() {
        let counter = Arc::new(AtomicU64::new(90));
        let t = CancelToken::with(None, None, Some((counter.clone(), 100)));
        t.charge(10).unwrap();
        assert_eq!(counter.load(Ordering::Relaxed), 100);
        assert_eq!(t.charge(1), Err(LimitError::Stopped(StopReason::Operations { max: 100 })));
    }

    #[test]
    fn a_passed_deadline_stops_within_1024_units() {
        let t = CancelToken::with(None, Some((Instant::now() + Duration::from_millis(1), 0.001)), None);
        std::thread::sleep(Duration::from_millis(5));
        let stopped_after = (1..=2048).find(|_| t.charge(1).is_err());
        assert!(stopped_after.is_some_and(|n| n <= 1024), "{stopped_after:?}");
        assert!(matches!(t.stopped(), Some(StopReason::Timeout { .. })));
    }
}
