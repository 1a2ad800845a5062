//! The binary's allocator: mimalloc for small blocks, the C library's malloc for large ones, and
//! freed memory given back to the system once the program is idle.
//!
//! A boolean of a million triangles allocates and frees arrays of megabytes, stage after stage,
//! from several threads (issue 38). With mimalloc alone, a freed large block stayed with the
//! thread region of the arena it came from until purged, and the next stage's arrays were
//! placed in fresh pages beside it: the peak resident memory of a boolean was 1.3–2.4 times the
//! bytes in use at its peak (the die of `kernel/benches/csg.rs`: 9.8 MiB resident for 4.1 MiB
//! used at 9.5k triangles; 312 for 241 MiB at 486k; the stress case 660–700 for 498 MiB).
//! Purging at once kept the peak down but faulted every stage's pages in afresh (the die at
//! 486k triangles a third slower). glibc's malloc with one arena and no memory returned on
//! `free` reuses any freed block, whichever thread freed it, best fit among coalesced free
//! chunks, already faulted in: 264 MiB resident at 486k triangles, 523–559 MiB in the stress
//! case, and no slower (measured with `kernel/benches/csg_side_by_side.py`, 2026-12-07).
//! Small blocks stay with mimalloc, whose thread-local free lists are what small allocations
//! need.
//!
//! Memory freed that way stays with the process, so a thread ([`release_when_idle`]) hands it
//! back to the system (`malloc_trim`) once the large blocks in use have not changed for
//! [`IDLE`], after a drop of at least [`RELEASE_AT_LEAST`]: after a recipe in the studio, the
//! REPL or the language server, not in the middle of a boolean.
//!
//! On other systems than Linux with glibc, every block goes to mimalloc.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use mimalloc::MiMalloc;

/// Blocks of at least this many bytes are large: the C library's malloc serves them (with an
/// alignment of at most [`MALLOC_ALIGN`]). Measured against 16 and 64 KiB: the same times, the
/// least resident memory (the stress case 523–559 MiB, 524–535 at 16 KiB, 582–619 at 64 KiB).
pub const LARGE_BLOCK: usize = 4096;

/// The alignment glibc's malloc guarantees on 64-bit systems; blocks asking for more go to
/// mimalloc whatever their size.
const MALLOC_ALIGN: usize = 16;

/// How long the large blocks in use must stay unchanged before freed memory is handed back.
pub const IDLE: Duration = Duration::from_secs(2);

/// The least drop of large blocks in use, since the last release, worth a `malloc_trim`.
pub const RELEASE_AT_LEAST: usize = 32 << 20;

/// mimalloc's `mi_option_purge_delay`: the sixteenth option of `mi_option_e` in the mimalloc.h
/// of mimalloc 3, the version libmimalloc-sys builds (the crate names no constant for it).
const PURGE_DELAY: libmimalloc_sys::mi_option_t = 15;

/// How long mimalloc keeps freed small pages, in milliseconds (mimalloc 3's default is 1000):
/// a boolean frees and allocates its small blocks stage after stage for longer than a second.
pub const PURGE_DELAY_MS: i64 = 5000;

/// Bytes of large blocks in use, and their most since the last release.
static LARGE_IN_USE: AtomicUsize = AtomicUsize::new(0);
static LARGE_PEAK: AtomicUsize = AtomicUsize::new(0);

/// The global allocator: small blocks to mimalloc, large ones to the C library's malloc (see the
/// module's documentation).
#[derive(Debug, Default, Clone, Copy)]
pub struct SplitAllocator;

impl SplitAllocator {
    /// Whether a block of this layout goes to the C library's malloc.
    #[inline]
    fn is_large(size: usize, align: usize) -> bool {
        cfg!(all(target_os = "linux", target_env = "gnu")) && size >= LARGE_BLOCK && align <= MALLOC_ALIGN
    }

    /// `block` (a large block of `size` bytes just allocated, or null) counted as in use.
    #[inline]
    fn counted(block: *mut u8, size: usize) -> *mut u8 {
        if !block.is_null() {
            let now = LARGE_IN_USE.fetch_add(size, Ordering::Relaxed) + size;
            LARGE_PEAK.fetch_max(now, Ordering::Relaxed);
        }
        block
    }
}

// SAFETY: each block is allocated, resized and freed by one of two allocators, the one its
// layout names (`is_large` of its size and alignment); `dealloc` and `realloc` receive the
// layout the block was allocated with, so they pick the allocator that owns it. A resize that
// crosses `LARGE_BLOCK` allocates with the other allocator, copies and frees the old block.
unsafe impl GlobalAlloc for SplitAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY (both): the caller's contract (a layout of non-zero size) holds for either.
        if Self::is_large(layout.size(), layout.align()) {
            Self::counted(unsafe { System.alloc(layout) }, layout.size())
        } else {
            unsafe { MiMalloc.alloc(layout) }
        }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY (both): as for `alloc`.
        if Self::is_large(layout.size(), layout.align()) {
            Self::counted(unsafe { System.alloc_zeroed(layout) }, layout.size())
        } else {
            unsafe { MiMalloc.alloc_zeroed(layout) }
        }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        if Self::is_large(layout.size(), layout.align()) {
            LARGE_IN_USE.fetch_sub(layout.size(), Ordering::Relaxed);
            // SAFETY: a large layout's block came from `System` (see the impl's comment).
            unsafe { System.dealloc(ptr, layout) }
        } else {
            // SAFETY: as above, from mimalloc.
            unsafe { MiMalloc.dealloc(ptr, layout) }
        }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let (was_large, is_large) =
            (Self::is_large(layout.size(), layout.align()), Self::is_large(new_size, layout.align()));
        match (was_large, is_large) {
            (true, true) => {
                // SAFETY: the block came from `System`; the caller's contract is its.
                let p = unsafe { System.realloc(ptr, layout, new_size) };
                // The old size leaves the count before the new one enters it, so the peak is
                // not both at once; a failed resize keeps the old block, and its count.
                if !p.is_null() {
                    LARGE_IN_USE.fetch_sub(layout.size(), Ordering::Relaxed);
                }
                Self::counted(p, new_size)
            }
            // SAFETY: the block came from mimalloc; as above.
            (false, false) => unsafe { MiMalloc.realloc(ptr, layout, new_size) },
            _ => {
                // SAFETY: `new_size` with the block's alignment is a valid layout (the caller's
                // contract for `realloc`).
                let new_layout = unsafe { Layout::from_size_align_unchecked(new_size, layout.align()) };
                // SAFETY: a non-zero size, as the caller guarantees.
                let p = unsafe { self.alloc(new_layout) };
                if !p.is_null() {
                    // SAFETY: both blocks hold at least the smaller size and do not overlap; the
                    // old block is freed with its own layout, once.
                    unsafe {
                        std::ptr::copy_nonoverlapping(ptr, p, layout.size().min(new_size));
                        self.dealloc(ptr, layout);
                    }
                }
                p
            }
        }
    }
}

/// Sets both allocators' policies; call it first thing, before other threads start.
/// glibc's malloc: one arena for every thread (a block freed by one thread is reused by any),
/// no block of less than 1 GiB taken from the system with its own mapping (each would be
/// mapped, faulted in and unmapped again per allocation), and nothing handed back on `free`
/// ([`release_when_idle`] does that). mimalloc: freed small pages kept [`PURGE_DELAY_MS`].
/// Returns whether the C library took every setting (always true elsewhere).
pub fn configure() -> bool {
    // SAFETY: `mi_option_set` only stores an option's value (mimalloc's options are atomics,
    // safe to set from any thread at any time); PURGE_DELAY is one of its options (tested).
    unsafe { libmimalloc_sys::mi_option_set(PURGE_DELAY, PURGE_DELAY_MS as _) };
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        const NEVER_MAPPED_BELOW: libc::c_int = 1 << 30;
        const NEVER_TRIMMED_BELOW: libc::c_int = libc::c_int::MAX;
        // SAFETY: `mallopt` sets one of glibc's malloc parameters; each is a documented
        // parameter with a value in its range. It returns 1 on success.
        unsafe {
            libc::mallopt(libc::M_ARENA_MAX, 1) == 1
                && libc::mallopt(libc::M_MMAP_THRESHOLD, NEVER_MAPPED_BELOW) == 1
                && libc::mallopt(libc::M_TRIM_THRESHOLD, NEVER_TRIMMED_BELOW) == 1
        }
    }
    #[cfg(not(all(target_os = "linux", target_env = "gnu")))]
    true
}

/// Whether freed memory should go back now: the large blocks in use have not changed since the
/// last look (`last`), and have dropped by at least [`RELEASE_AT_LEAST`] from their peak.
fn should_release(in_use: usize, last: usize, peak: usize) -> bool {
    in_use == last && peak.saturating_sub(in_use) >= RELEASE_AT_LEAST
}

/// Hands the memory the C library's malloc holds free back to the system, now.
fn release_free_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: `malloc_trim` only returns free pages of malloc's own heap to the system.
    unsafe {
        libc::malloc_trim(0);
    }
    LARGE_PEAK.store(LARGE_IN_USE.load(Ordering::Relaxed), Ordering::Relaxed);
}

/// Starts the thread that hands freed memory back to the system once the program is idle (see
/// the module's documentation). It looks every [`IDLE`] and sleeps otherwise.
pub fn release_when_idle() {
    if !cfg!(all(target_os = "linux", target_env = "gnu")) {
        return;
    }
    let spawned = std::thread::Builder::new().name("memory release".into()).spawn(|| {
        let mut last = usize::MAX;
        loop {
            std::thread::sleep(IDLE);
            let in_use = LARGE_IN_USE.load(Ordering::Relaxed);
            if should_release(in_use, last, LARGE_PEAK.load(Ordering::Relaxed)) {
                release_free_memory();
            }
            last = in_use;
        }
    });
    // Without the thread the memory is only kept longer.
    drop(spawned);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The option at that index is the purge delay: its default is mimalloc 3's 1000 ms, which
    /// no neighbouring option has, and it takes the value set.
    #[test]
    fn the_option_set_is_the_purge_delay() {
        // SAFETY: reads of mimalloc's option values.
        unsafe {
            if std::env::var_os("MIMALLOC_PURGE_DELAY").is_none() {
                assert!(matches!(libmimalloc_sys::mi_option_get(PURGE_DELAY), 1000 | 5000));
            }
        }
        assert!(configure(), "the C library refused a setting");
        // SAFETY: as above.
        // `c_long` is `i64` here, `i32` elsewhere.
        #[allow(clippy::useless_conversion)]
        let set = i64::from(unsafe { libmimalloc_sys::mi_option_get(PURGE_DELAY) });
        assert_eq!(set, PURGE_DELAY_MS);
    }

    /// Blocks of every size class and alignment, grown and shrunk across the threshold, keep
    /// their bytes; zeroed ones are zero; the large ones are counted while in use.
    #[test]
    fn blocks_keep_their_bytes_across_both_allocators() {
        let a = SplitAllocator;
        for align in [1, 8, 16, 64, 4096] {
            for size in [1, 100, LARGE_BLOCK - 1, LARGE_BLOCK, 3 * LARGE_BLOCK, 1 << 20] {
                let layout = Layout::from_size_align(size, align).unwrap();
                // SAFETY: a valid layout of non-zero size; each block is written within its
                // size, resized with its current layout and freed once.
                unsafe {
                    let z = a.alloc_zeroed(layout);
                    assert!(!z.is_null());
                    assert!(std::slice::from_raw_parts(z, size).iter().all(|&b| b == 0), "{size} {align}");
                    a.dealloc(z, layout);
                    let p = a.alloc(layout);
                    assert_eq!(p as usize % align, 0, "{size} {align}");
                    let fill = |p: *mut u8, n: usize| (0..n).for_each(|i| *p.add(i) = (i % 251) as u8);
                    let check = |p: *const u8, n: usize| (0..n).all(|i| *p.add(i) == (i % 251) as u8);
                    fill(p, size);
                    let mut current = layout;
                    let mut p = p;
                    for new_size in [size * 2 + LARGE_BLOCK, size / 2 + 1, size] {
                        let q = a.realloc(p, current, new_size);
                        assert!(!q.is_null());
                        assert_eq!(q as usize % align, 0, "{size} -> {new_size} at {align}");
                        let kept = current.size().min(new_size);
                        assert!(check(q, kept), "{size} -> {new_size} at {align}");
                        fill(q, new_size);
                        current = Layout::from_size_align(new_size, align).unwrap();
                        p = q;
                    }
                    a.dealloc(p, current);
                }
            }
        }
        let layout = Layout::from_size_align(1 << 22, 8).unwrap();
        // SAFETY: as above.
        unsafe {
            let p = a.alloc(layout);
            // Other tests of this binary allocate meanwhile; the block's own bytes are there.
            if SplitAllocator::is_large(1 << 22, 8) {
                assert!(LARGE_IN_USE.load(Ordering::Relaxed) >= 1 << 22);
            }
            a.dealloc(p, layout);
        }
    }

    #[test]
    fn memory_goes_back_only_when_the_large_blocks_in_use_stay_the_same_after_a_drop() {
        let mib = 1 << 20;
        // Busy: the blocks in use changed since the last look.
        assert!(!should_release(10 * mib, 200 * mib, 200 * mib));
        // Idle, after a large drop.
        assert!(should_release(10 * mib, 10 * mib, 200 * mib));
        // Idle, but little to give back.
        assert!(!should_release(10 * mib, 10 * mib, 10 * mib + RELEASE_AT_LEAST - 1));
        assert!(should_release(10 * mib, 10 * mib, 10 * mib + RELEASE_AT_LEAST));
    }
}
