//! Child processes for the tests that include it (`#[path = "support/child.rs"] mod child;`):
//! waited for with a deadline, so a process that never ends fails its test instead of holding CI.

use std::process::{Child, ExitStatus};
use std::time::{Duration, Instant};

/// `child`'s exit status once it ends within `limit`; `None` when it still runs then (it is
/// left running: the caller kills it or asserts).
pub fn wait_within(child: &mut Child, limit: Duration) -> Option<ExitStatus> {
    let until = Instant::now() + limit;
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return Some(status);
        }
        if Instant::now() > until {
            return None;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}
