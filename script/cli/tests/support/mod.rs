//! What several integration tests share: finding the browser the page and file tests run in.

use std::process::Command;

/// chromium, or None where it is missing (an error under CI, which installs it).
pub fn chromium() -> Option<&'static str> {
    let found = Command::new("chromium").arg("--version").output().is_ok_and(|o| o.status.success());
    if !found {
        assert!(std::env::var("CI").as_deref() != Ok("true"), "CI must install chromium for the browser tests");
        eprintln!("chromium not found: browser test skipped");
        return None;
    }
    Some("chromium")
}
