//! How the binary's allocator (mimalloc) gives memory back to the system.
//!
//! mimalloc returns freed memory to the system ("purges" it) a second after it is freed, and a
//! large boolean frees and allocates its arrays stage after stage for longer than that: its
//! later stages faulted their pages in afresh, and the system zeroed them. In the stress case of
//! `kernel/benches/csg.rs` (a million triangles) that was 0.8–1.1 s of system time in 4.1 s;
//! with a delay of 5 s it is 0.3 s, and the boolean 3.7 s, with the same peak (issue 38). Memory
//! freed stays with the process for those 5 s, used again meanwhile, then goes back.

/// mimalloc's `mi_option_purge_delay`: the sixteenth option of `mi_option_e` in the mimalloc.h
/// of mimalloc 3, the version libmimalloc-sys builds (the crate names no constant for it).
const PURGE_DELAY: libmimalloc_sys::mi_option_t = 15;

/// How long freed memory stays with the process, in milliseconds (mimalloc 3's default is 1000).
pub const PURGE_DELAY_MS: i64 = 5000;

/// Sets the purge delay to [`PURGE_DELAY_MS`]. mimalloc reads its options when it uses them,
/// so this holds from the first purge on; call it first thing.
pub fn keep_freed_memory() {
    // SAFETY: `mi_option_set` only stores an option's value (mimalloc's options are atomics,
    // safe to set from any thread at any time); PURGE_DELAY is one of its options (tested).
    unsafe { libmimalloc_sys::mi_option_set(PURGE_DELAY, PURGE_DELAY_MS as _) }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The option at that index is the purge delay: its default is mimalloc 3's 1000 ms, which
    /// no neighbouring option has, and it takes the value set.
    #[test]
    fn the_option_set_is_the_purge_delay() {
        // SAFETY: reads and stores of mimalloc's option values.
        unsafe {
            if std::env::var_os("MIMALLOC_PURGE_DELAY").is_none() {
                assert_eq!(libmimalloc_sys::mi_option_get(PURGE_DELAY), 1000);
            }
            keep_freed_memory();
            // `c_long` is `i64` here, `i32` elsewhere.
            #[allow(clippy::useless_conversion)]
            let set = i64::from(libmimalloc_sys::mi_option_get(PURGE_DELAY));
            assert_eq!(set, PURGE_DELAY_MS);
        }
    }
}
