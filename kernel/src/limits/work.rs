//! How far long work has come, told to whoever listens on the calling thread (a host's
//! progress bar), the way the cancellation token is current on it: a kernel loop that knows
//! its length starts a [`Work`] of that many units and sets how many are done, without being
//! handed a callback, and the caller [`listen`]s around the call.
//!
//! Only the outermost work on a thread reports: an operation built of others (a plant's solid
//! made by booleans, a remesh that triangulates) shows one bar, its own.

use std::cell::{Cell, RefCell};

/// What a listener is told: `(done, total)` units of the outermost work under way.
type Listener = Box<dyn FnMut(u64, u64)>;

thread_local! {
    static LISTENER: RefCell<Option<Listener>> = const { RefCell::new(None) };
    static DEPTH: Cell<u32> = const { Cell::new(0) };
}

/// Makes `listener(done, total)` hear the progress of the work the calling thread does until
/// the guard is dropped (then the previous listener is restored).
#[must_use = "the listener hears only while the guard lives"]
pub fn listen(listener: impl FnMut(u64, u64) + 'static) -> ListenGuard {
    let previous = LISTENER.with(|l| l.replace(Some(Box::new(listener))));
    ListenGuard { previous }
}

/// Restores the previous listener when dropped.
pub struct ListenGuard {
    previous: Option<Listener>,
}

impl Drop for ListenGuard {
    fn drop(&mut self) {
        let previous = self.previous.take();
        LISTENER.with(|l| *l.borrow_mut() = previous);
    }
}

/// A piece of work of a known number of units, under way on the calling thread until dropped.
/// Reports `0` when started; costs a thread-local read per [`Work::set`] when nobody listens.
pub struct Work {
    total: u64,
    outermost: bool,
    /// The last count reported (none yet: `u64::MAX`), so a count is told once.
    last: Cell<u64>,
}

impl Work {
    /// Starts work of `total` units (reported as `(0, total)` when it is the outermost).
    #[must_use = "the work is under way only while the value lives"]
    pub fn start(total: u64) -> Work {
        let depth = DEPTH.with(|d| d.replace(d.get() + 1));
        let work = Work { total, outermost: depth == 0, last: Cell::new(u64::MAX) };
        work.set(0);
        work
    }

    /// `done` units of the total are done (held at the total; a count already told is not
    /// told again).
    pub fn set(&self, done: u64) {
        let done = done.min(self.total);
        if self.outermost && self.last.replace(done) != done {
            LISTENER.with(|l| {
                if let Some(listener) = l.borrow_mut().as_mut() {
                    listener(done, self.total);
                }
            });
        }
    }

    /// Reports the whole done: for the end of work that may stop short of its total (a
    /// decimation reaching its error bound first).
    pub fn finish(&self) {
        self.set(self.total);
    }
}

impl Drop for Work {
    fn drop(&mut self) {
        DEPTH.with(|d| d.set(d.get().saturating_sub(1)));
    }
}

/// What `work` reports, in order, with its result: for tests of the operations that report.
#[cfg(test)]
pub(crate) fn heard<R>(work: impl FnOnce() -> R) -> (R, Vec<(u64, u64)>) {
    let heard = std::rc::Rc::new(RefCell::new(Vec::new()));
    let h = std::rc::Rc::clone(&heard);
    let result = {
        let _guard = listen(move |done, total| h.borrow_mut().push((done, total)));
        work()
    };
    let reports = heard.borrow().clone();
    (result, reports)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_outermost_work_reports_to_the_listener_while_it_listens() {
        let ((), first) = heard(|| {
            let outer = Work::start(3);
            outer.set(1);
            {
                // Work inside work: not heard.
                let inner = Work::start(100);
                inner.set(50);
            }
            outer.set(7);
            outer.finish();
        });
        assert_eq!(first, vec![(0, 3), (1, 3), (3, 3)]);
        // Nobody listens now: nothing is heard and nothing fails.
        Work::start(5).set(2);
        // The depth is back to 0: the next outermost work is heard again.
        let ((), again) = heard(|| Work::start(4).set(4));
        assert_eq!(again, vec![(0, 4), (4, 4)]);
    }
}
