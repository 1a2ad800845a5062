//! The memory budget: size-driven operations estimate the memory of their result from their
//! arguments and refuse, before allocating, when it is over the budget — an allocation failure
//! would abort the process.
//!
//! The budget is process-wide. Unless the caller sets another with [`set_memory_limit`], it is
//! the smallest of what the process may actually use (read once, on Linux):
//! - [`DEFAULT_MEMORY_SHARE`] of the machine's physical memory (`MemTotal` of `/proc/meminfo`);
//! - the memory limit of the process's cgroup and of each cgroup above it (v2 `memory.max`, v1
//!   `memory.limit_in_bytes`, as in a container, a Slurm or a Kubernetes job), less what the
//!   cgroup already uses (its usage without the page cache it can drop, `inactive_file`);
//! - the soft `RLIMIT_AS` (`ulimit -v`) less the address space already mapped (`VmSize`), and
//!   the soft `RLIMIT_DATA` less the data already mapped (`VmData`), read from
//!   `/proc/self/limits` and `/proc/self/status`.
//!
//! (An allocation past a cgroup limit is killed, one past an rlimit fails — and aborts: either
//! way the process is gone, so the estimates must meet the tightest.)

use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::OnceLock;

use super::LimitError;

/// The share of physical memory the default budget allows: one half.
pub const DEFAULT_MEMORY_SHARE: f64 = 0.5;

/// 0: not set, the default applies.
static LIMIT: AtomicU64 = AtomicU64::new(0);

/// The memory budget in bytes: the one set by [`set_memory_limit`], else the smallest of
/// [`DEFAULT_MEMORY_SHARE`] of physical memory (4 GiB when it cannot be read), the cgroup
/// limits less their usage and the rlimits less what is mapped (see the module documentation;
/// at least 64 MiB).
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
    *DEFAULT.get_or_init(|| {
        let share = match physical_memory() {
            Some(total) => (total as f64 * DEFAULT_MEMORY_SHARE) as u64,
            None => 4 << 30,
        };
        let read = |p: &str| std::fs::read_to_string(p).ok();
        let cgroup = read("/proc/self/cgroup").and_then(|c| cgroup_available(&c, Path::new("/sys/fs/cgroup")));
        let rlimit = match (read("/proc/self/limits"), read("/proc/self/status")) {
            (Some(limits), Some(status)) => rlimit_available(&limits, &status),
            _ => None,
        };
        // At least 64 MiB: a limit already used up still lets small work run (and be refused
        // by name when large).
        [Some(share), cgroup, rlimit].into_iter().flatten().min().unwrap_or(share).max(64 << 20)
    })
}

/// `MemTotal` of `/proc/meminfo` (Linux); `None` elsewhere.
fn physical_memory() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    field_kib(&info, "MemTotal:")
}

/// The value in bytes of the line `key  N kB` of a `/proc` file's `text`.
fn field_kib(text: &str, key: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with(key))?;
    let kib: u64 = line[key.len()..].split_whitespace().next()?.parse().ok()?;
    kib.checked_mul(1024)
}

/// The memory the process may still take under its rlimits: the soft `RLIMIT_AS` less `VmSize`
/// and the soft `RLIMIT_DATA` less `VmData`, the smaller; `None` when both are unlimited.
/// `limits` is the text of `/proc/self/limits`, `status` that of `/proc/self/status`.
fn rlimit_available(limits: &str, status: &str) -> Option<u64> {
    let soft = |name: &str| -> Option<u64> {
        let line = limits.lines().find(|l| l.starts_with(name))?;
        line[name.len()..].split_whitespace().next()?.parse().ok()
    };
    let address = soft("Max address space").map(|l| l.saturating_sub(field_kib(status, "VmSize:").unwrap_or(0)));
    let data = soft("Max data size").map(|l| l.saturating_sub(field_kib(status, "VmData:").unwrap_or(0)));
    address.into_iter().chain(data).min()
}

/// Limits of 2⁶² bytes and over mean none (cgroup v1 writes 9223372036854771712 for none).
const NO_LIMIT: u64 = 1 << 62;

/// The memory the process may still take under its cgroups, the smallest over its cgroup and
/// every one above it of the limit less the usage (without the inactive page cache); `None`
/// when none has a limit. `proc_cgroup` is the text of `/proc/self/cgroup`, `root` where the
/// cgroup file systems are mounted (`/sys/fs/cgroup`: v2 there, v1 in `root/memory`). A
/// cgroup path not found under the mount (a container's own namespace) is read at the mount.
fn cgroup_available(proc_cgroup: &str, root: &Path) -> Option<u64> {
    let mut best: Option<u64> = None;
    for line in proc_cgroup.lines() {
        let mut fields = line.splitn(3, ':');
        let (Some(id), Some(controllers), Some(path)) = (fields.next(), fields.next(), fields.next()) else {
            continue;
        };
        let (mount, limit_file, usage_file, cache_key) = if id == "0" && controllers.is_empty() {
            (root.to_path_buf(), "memory.max", "memory.current", "inactive_file")
        } else if controllers.split(',').any(|c| c == "memory") {
            (root.join("memory"), "memory.limit_in_bytes", "memory.usage_in_bytes", "total_inactive_file")
        } else {
            continue;
        };
        let own = mount.join(path.trim_start_matches('/'));
        let mut dir = if own.is_dir() { own } else { mount.clone() };
        loop {
            let number = |f: &str| std::fs::read_to_string(dir.join(f)).ok()?.trim().parse::<u64>().ok();
            if let Some(limit) = number(limit_file).filter(|&l| l < NO_LIMIT) {
                let usage = number(usage_file).unwrap_or(0);
                let cache = std::fs::read_to_string(dir.join("memory.stat"))
                    .ok()
                    .and_then(|stat| stat_value(&stat, cache_key))
                    .unwrap_or(0);
                let available = limit.saturating_sub(usage.saturating_sub(cache));
                best = Some(best.map_or(available, |b| b.min(available)));
            }
            if dir == mount || !dir.pop() || !dir.starts_with(&mount) {
                break;
            }
        }
    }
    best
}

/// The value of the line `key N` of a cgroup `memory.stat`.
fn stat_value(stat: &str, key: &str) -> Option<u64> {
    stat.lines().find_map(|l| l.strip_prefix(key)?.strip_prefix(' ')?.trim().parse().ok())
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

    #[test]
    fn rlimits_less_what_is_mapped_bound_the_budget() {
        // `ulimit -v 6291456` (6 GiB) with 300 MiB mapped leaves 5.7 GiB; the data limit is
        // looser. Unlimited (or a missing line) bounds nothing.
        let limits = "Limit                     Soft Limit           Hard Limit           Units\n\
                      Max data size             8589934592           unlimited            bytes\n\
                      Max address space         6442450944           unlimited            bytes\n";
        let status = "Name:\tblocksmith\nVmSize:\t  307200 kB\nVmData:\t  102400 kB\n";
        assert_eq!(rlimit_available(limits, status), Some((6 << 30) - (300 << 20)));
        let unlimited = limits.replace("8589934592", "unlimited").replace("6442450944", "unlimited");
        assert_eq!(rlimit_available(&unlimited, status), None);
        let data_only = limits.replace("6442450944", "unlimited").replace("8589934592", "1073741824");
        assert_eq!(rlimit_available(&data_only, status), Some((1 << 30) - (100 << 20)));
    }

    #[test]
    fn cgroup_limits_less_usage_bound_the_budget() {
        // v2: the job's cgroup (2 GiB, 500 MiB used of which 100 MiB is droppable cache) under
        // a parent of 1.5 GiB with 1 GiB used: the parent is the tighter (512 MiB).
        let root = tempfile::tempdir().unwrap();
        let job = root.path().join("slurm/job_7");
        std::fs::create_dir_all(&job).unwrap();
        let write = |dir: &Path, f: &str, text: &str| std::fs::write(dir.join(f), text).unwrap();
        write(&job, "memory.max", "2147483648\n");
        write(&job, "memory.current", "524288000\n");
        write(&job, "memory.stat", "anon 1\ninactive_file 104857600\nactive_file 5\n");
        write(job.parent().unwrap(), "memory.max", "1610612736\n");
        write(job.parent().unwrap(), "memory.current", "1073741824\n");
        write(root.path(), "memory.max", "max\n");
        assert_eq!(cgroup_available("0::/slurm/job_7\n", root.path()), Some(512 << 20));
        // Without the parent's limit, the job's: 2 GiB − 400 MiB.
        write(job.parent().unwrap(), "memory.max", "max\n");
        assert_eq!(cgroup_available("0::/slurm/job_7\n", root.path()), Some((2048 - 400) << 20));
        // A namespaced path that is not under the mount reads the mount itself (unlimited).
        assert_eq!(cgroup_available("0::/elsewhere\n", root.path()), None);
        // v1: the memory controller's hierarchy; its "no limit" is a huge number.
        let v1 = root.path().join("memory/docker/abc");
        std::fs::create_dir_all(&v1).unwrap();
        write(&v1, "memory.limit_in_bytes", "1073741824\n");
        write(&v1, "memory.usage_in_bytes", "268435456\n");
        write(&v1, "memory.stat", "cache 5\ntotal_inactive_file 0\n");
        write(&root.path().join("memory"), "memory.limit_in_bytes", "9223372036854771712\n");
        let text = "12:pids:/docker/abc\n4:memory:/docker/abc\n0::/\n";
        assert_eq!(cgroup_available(text, root.path()), Some(768 << 20));
        assert_eq!(cgroup_available("4:cpu,memory:/docker/abc\n", root.path()), Some(768 << 20));
        assert_eq!(cgroup_available("garbage\n", root.path()), None);
    }
}
