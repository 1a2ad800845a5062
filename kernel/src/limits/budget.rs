//! The memory budget: size-driven operations estimate the memory of their result from their
//! arguments and refuse, before allocating, when it is over the budget — an allocation failure
//! would abort the process.
//!
//! The budget is process-wide: [`DEFAULT_MEMORY_SHARE`] of the machine's physical memory unless
//! the caller sets another with [`set_memory_limit`].

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::OnceLock;

use super::LimitError;

/// The share of physical memory the default budget allows: one half.
pub const DEFAULT_MEMORY_SHARE: f64 = 0.5;

/// 0: not set, the default applies.
static LIMIT: AtomicU64 = AtomicU64::new(0);

/// The memory budget in bytes: the one set by [`set_memory_limit`], else
/// [`DEFAULT_MEMORY_SHARE`] of physical memory (4 GiB when it cannot be read).
#[must_use]
pub fn memory_limit() -> u64 {
    match LIMIT.load(Ordering::Relaxed) {
        0 => default_limit(),
        n => n,
    }
}

/// Sets the process-wide memory budget in bytes; 0 restores the default.
pub fn set_memory_limit(bytes: u64) {
    LIMIT.store(bytes, Ordering::Relaxed);
}

fn default_limit() -> u64 {
    static DEFAULT: OnceLock<u64> = OnceLock::new();
    *DEFAULT.get_or_init(|| match physical_memory() {
        Some(total) => (total as f64 * DEFAULT_MEMORY_SHARE) as u64,
        None => 4 << 30,
    })
}

/// `MemTotal` of `/proc/meminfo` (Linux); `None` elsewhere.
fn physical_memory() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// Refuses `bytes` (an estimate, computed in `f64` so that it cannot overflow) of memory for
/// `what` when over the budget.
///
/// # Errors
/// [`LimitError::OverBudget`] naming `what`, the estimate and the budget.
pub fn check_memory(what: impl FnOnce() -> String, bytes: f64) -> Result<(), LimitError> {
    let limit = memory_limit();
    if bytes.is_nan() || bytes > limit as f64 {
        let bytes = if bytes.is_nan() || bytes >= u64::MAX as f64 { u64::MAX } else { bytes as u64 };
        return Err(LimitError::OverBudget { what: what(), bytes, limit });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_budget_is_a_share_of_physical_memory() {
        let limit = default_limit();
        assert!(limit >= 64 << 20, "{limit}");
        if let Some(total) = physical_memory() {
            assert!(limit < total, "{limit} of {total}");
        }
    }

    #[test]
    fn an_estimate_over_the_budget_is_refused_naming_both() {
        assert!(check_memory(|| "x".into(), 1e3).is_ok());
        let e = check_memory(|| "a 100000 × 100000 sphere".into(), 1e18).unwrap_err();
        let msg = e.to_string();
        assert!(msg.starts_with("a 100000 × 100000 sphere needs an estimated 888 PiB"), "{msg}");
        assert!(msg.contains("over the memory budget of") && msg.contains("--memory-limit"), "{msg}");
        assert!(check_memory(|| "y".into(), f64::INFINITY).is_err());
    }
}
