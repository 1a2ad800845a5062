//! Why the kernel refused or stopped a piece of work.

use thiserror::Error;

/// A request over the memory budget, or work stopped by its cancellation token.
#[derive(Clone, Debug, Error, PartialEq)]
#[non_exhaustive]
pub enum LimitError {
    /// The estimated memory of the result is over the budget (refused before allocating).
    #[error("{what} needs an estimated {}, over the memory budget of {} (raise it with --memory-limit)", human_bytes(*bytes), human_bytes(*limit))]
    OverBudget { what: String, bytes: u64, limit: u64 },
    /// The heap in use is over the budget (an interpreter's data grew past it).
    #[error("the memory in use ({}) is over the memory budget of {} (raise it with --memory-limit)", human_bytes(*bytes), human_bytes(*limit))]
    HeapOverBudget { bytes: u64, limit: u64 },
    /// The work was stopped by its token.
    #[error("{0}")]
    Stopped(StopReason),
}

/// What stopped a piece of work.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StopReason {
    /// The caller's interrupt flag was set (Ctrl-C, a studio's stop button).
    Interrupted,
    /// The deadline passed.
    Timeout { seconds: f64 },
    /// The operation count passed its maximum.
    Operations { max: u64 },
}

impl std::fmt::Display for StopReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StopReason::Interrupted => write!(f, "interrupted"),
            StopReason::Timeout { seconds } => write!(f, "time limit reached (--timeout {seconds})"),
            StopReason::Operations { max } => write!(f, "operation limit reached (--max-operations {max})"),
        }
    }
}

/// `bytes` in binary units with three significant digits: `512 bytes`, `1.50 KiB`, `5.37 GiB`.
#[must_use]
pub fn human_bytes(bytes: u64) -> String {
    const UNITS: [&str; 6] = ["KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    if bytes < 1024 {
        return format!("{bytes} bytes");
    }
    let mut x = bytes as f64 / 1024.0;
    let mut unit = 0;
    while x >= 1024.0 && unit + 1 < UNITS.len() {
        x /= 1024.0;
        unit += 1;
    }
    let digits = if x >= 100.0 {
        0
    } else if x >= 10.0 {
        1
    } else {
        2
    };
    format!("{x:.digits$} {}", UNITS[unit])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_read_in_binary_units_with_three_digits() {
        assert_eq!(human_bytes(512), "512 bytes");
        assert_eq!(human_bytes(1536), "1.50 KiB");
        assert_eq!(human_bytes(5_400_000_000), "5.03 GiB");
        assert_eq!(human_bytes(u64::MAX), "16.0 EiB");
    }
}
