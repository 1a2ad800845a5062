//! A hint to the processor that a value will be read soon (blocksmith patch, PATCHES.md, 11).
//!
//! The loops it serves walk a mesh or a point set by index in no spatial order (a hull's
//! outside points, the coplanar flood of faces sorted by area), so each step waits on a cache
//! miss; fetching a few steps ahead overlaps those waits. A hint changes no result.

/// Fetches the cache lines of `value`: both ends, since a 24-byte position straddles two lines
/// one time in three. A no-op off x86-64.
#[inline(always)]
pub(crate) fn prefetch<T>(value: &T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch is only a hint; it reads nothing and cannot fault. The last byte is
    // inside `value`.
    unsafe {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let first = (value as *const T).cast::<i8>();
        _mm_prefetch::<_MM_HINT_T0>(first);
        _mm_prefetch::<_MM_HINT_T0>(first.add(std::mem::size_of::<T>().saturating_sub(1)));
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}
