//! Limits on the kernel's work, so that no request aborts the process or runs unstoppably:
//! a memory budget that size-driven operations check *before* allocating ([`check_memory`]),
//! and a cancellation token that long loops check ([`check`]); long loops that know their
//! length also tell how far they are ([`Work`]) to whoever [`listen`]s.
//!
//! Both are set by the caller (the command line's `--memory-limit`, `--timeout`,
//! `--max-operations` and Ctrl-C) and reported as a [`LimitError`], which every module's error
//! type carries.

mod budget;
mod cancel;
mod error;
mod heap;
mod work;

pub use budget::{check_memory, memory_limit, set_memory_limit, DEFAULT_MEMORY_SHARE};
pub use cancel::{charge, check, current, install, make_current, poll, poll_at, CancelToken, InstallGuard, POLL_EVERY};
pub use error::{human_bytes, LimitError, StopReason};
pub use heap::{check_growth, check_heap, heap_in_use, CountingAllocator};
#[cfg(test)]
pub(crate) use work::heard;
pub use work::{listen, ListenGuard, Work};
