//! The heap in use, counted by [`CountingAllocator`] when a program installs it as its global
//! allocator, so that an interpreter can stop once its data is over the memory budget instead
//! of letting a failed allocation abort the process.
//!
//! Counting costs one relaxed atomic add per allocation and per free. Without the counting
//! allocator (a program embedding the kernel with an allocator of its own), [`check_heap`] reads
//! the process's resident memory instead, every [`RESIDENT_SAMPLE_EVERY`]th call (Linux's
//! `/proc/self/status`; elsewhere nothing is checked).

use std::alloc::{GlobalAlloc, Layout};
use std::sync::atomic::{AtomicU32, AtomicU64, AtomicUsize, Ordering};

use super::{memory_limit, LimitError};

/// Bytes allocated and not yet freed through [`CountingAllocator`]; 0 when it is not installed.
static LIVE: AtomicUsize = AtomicUsize::new(0);

/// A global allocator counting the bytes in use of the allocator it wraps.
///
/// ```ignore
/// #[global_allocator]
/// static ALLOCATOR: CountingAllocator<std::alloc::System> = CountingAllocator(std::alloc::System);
/// ```
#[derive(Debug, Default)]
pub struct CountingAllocator<A>(pub A);

// SAFETY: every call is forwarded unchanged to the wrapped allocator; only a counter is added.
unsafe impl<A: GlobalAlloc> GlobalAlloc for CountingAllocator<A> {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's contract is the wrapped allocator's.
        let p = unsafe { self.0.alloc(layout) };
        if !p.is_null() {
            LIVE.fetch_add(layout.size(), Ordering::Relaxed);
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: as for `alloc`.
        let p = unsafe { self.0.alloc_zeroed(layout) };
        if !p.is_null() {
            LIVE.fetch_add(layout.size(), Ordering::Relaxed);
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: as for `alloc`.
        unsafe { self.0.dealloc(ptr, layout) };
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: as for `alloc`.
        let p = unsafe { self.0.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            if new_size >= layout.size() {
                LIVE.fetch_add(new_size - layout.size(), Ordering::Relaxed);
            } else {
                LIVE.fetch_sub(layout.size() - new_size, Ordering::Relaxed);
            }
        }
        p
    }
}

/// The bytes of heap in use, when a [`CountingAllocator`] counts them.
#[must_use]
pub fn heap_in_use() -> Option<u64> {
    match LIVE.load(Ordering::Relaxed) {
        0 => None,
        n => Some(n as u64),
    }
}

/// How many calls of [`check_heap`] without a counting allocator read the resident memory once:
/// reading it is a system call of some microseconds, a script step some tens of nanoseconds.
pub const RESIDENT_SAMPLE_EVERY: u32 = 4096;

/// Refuses to go on when the heap in use is over the memory budget.
///
/// The heap is the count of [`CountingAllocator`] when it is installed, else the process's
/// resident memory, read every [`RESIDENT_SAMPLE_EVERY`]th call (the last reading stands in
/// between), so that data growing a little at every step is stopped near the budget either way.
///
/// # Errors
/// [`LimitError::HeapOverBudget`] with the bytes in use and the budget.
pub fn check_heap() -> Result<(), LimitError> {
    let bytes = match heap_in_use() {
        Some(bytes) => bytes,
        None => sampled_resident_memory(),
    };
    let limit = memory_limit();
    if bytes > limit {
        return Err(LimitError::HeapOverBudget { bytes, limit });
    }
    Ok(())
}

/// The resident memory last read, read again on every [`RESIDENT_SAMPLE_EVERY`]th call; 0 where
/// it cannot be read.
fn sampled_resident_memory() -> u64 {
    static CALLS: AtomicU32 = AtomicU32::new(0);
    static LAST: AtomicU64 = AtomicU64::new(0);
    if CALLS.fetch_add(1, Ordering::Relaxed).is_multiple_of(RESIDENT_SAMPLE_EVERY) {
        LAST.store(resident_memory().unwrap_or(0), Ordering::Relaxed);
    }
    LAST.load(Ordering::Relaxed)
}

/// The process's resident memory in bytes: `VmRSS` of `/proc/self/status` (Linux).
fn resident_memory() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// Refuses `extra` more bytes (an estimate, in `f64` so that it cannot overflow) for `what` when
/// they and the heap in use are over the memory budget.
///
/// # Errors
/// [`LimitError::OverBudget`] naming `what`, the estimate (in use plus `extra`) and the budget.
pub fn check_growth(what: impl FnOnce() -> String, extra: f64) -> Result<(), LimitError> {
    super::check_memory(what, heap_in_use().unwrap_or(0) as f64 + extra)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_counter_follows_allocations_and_frees_through_the_wrapper() {
        let a = CountingAllocator(std::alloc::System);
        let layout = Layout::from_size_align(1 << 20, 8).unwrap();
        let before = LIVE.load(Ordering::Relaxed);
        // SAFETY: a non-zero layout, freed with the same layout and the grown size.
        unsafe {
            let p = a.alloc(layout);
            assert!(!p.is_null());
            assert!(LIVE.load(Ordering::Relaxed) >= before + (1 << 20));
            let q = a.realloc(p, layout, 3 << 20);
            assert!(!q.is_null());
            assert!(heap_in_use().is_some_and(|n| n >= 3 << 20));
            a.dealloc(q, Layout::from_size_align(3 << 20, 8).unwrap());
        }
        assert_eq!(LIVE.load(Ordering::Relaxed), before);
        assert!(check_heap().is_ok());
        // Without the counting allocator (this test binary) the resident memory stands in.
        assert!(resident_memory().is_some_and(|n| n > 1 << 20));
        let e = check_growth(|| "a padded array".into(), 1e30).unwrap_err().to_string();
        assert!(e.starts_with("a padded array needs an estimated"), "{e}");
    }
}
