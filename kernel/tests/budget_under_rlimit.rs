//! The default memory budget meets the process's rlimit: under `ulimit -v 6G` (RLIMIT_AS), a
//! request the budget of half the physical memory would let through — and the allocator then
//! fail, aborting the process — is refused by name. The test runs itself again in a shell
//! that sets the limit (Linux; skipped where `sh` is missing).

use blocksmith_kernel::limits::memory_limit;
use blocksmith_kernel::mesh::Mesh;

const CHILD: &str = "BLOCKSMITH_RLIMIT_CHILD";

#[test]
fn under_ulimit_v_the_budget_refuses_what_would_abort() {
    if std::env::var_os(CHILD).is_some() {
        // In the child, limited to 6 GiB of address space: the budget is below it, and the
        // cube subdivided 11 times (25 million quads, an estimated 6+ GiB) is refused.
        let limit = memory_limit();
        assert!(limit < 6 << 30, "budget {limit}");
        let e = Mesh::cube(2.0).catmull_clark(11).map(|_| ()).unwrap_err().to_string();
        assert!(e.contains("over the memory budget"), "{e}");
        return;
    }
    if !cfg!(target_os = "linux") {
        return;
    }
    let exe = std::env::current_exe().unwrap();
    let out = match std::process::Command::new("sh")
        .arg("-c")
        .arg("ulimit -v 6291456 && exec \"$0\" --exact under_ulimit_v_the_budget_refuses_what_would_abort --nocapture")
        .arg(&exe)
        .env(CHILD, "1")
        .output()
    {
        Ok(out) => out,
        Err(_) => return,
    };
    let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "the child failed: {text}");
    assert!(text.contains("1 passed"), "{text}");
}
