//! `blocksmith test`: runs `.rhai` test scripts, each in a fresh engine, one line per script,
//! then `N passed, N failed`.
//!
//! A test passes when it runs to the end without an error and drops no result (a call whose
//! result is thrown away while its receiver stays as it was, [`blocksmith_script::lint`]: the test may
//! pass for the wrong reason). Files whose name starts with `_` are helpers for `import`, not
//! tests.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use std::process::ExitCode;

use blocksmith_script::progress::Progress;
use blocksmith_script::run::run_recipe;
use blocksmith_script::{EngineOptions, RunContext};

use crate::args::LimitArgs;
use crate::output::{fail, print_out};

/// Runs the test scripts under `paths` (default `tests/` of the working directory), relative
/// `save` paths going under `out`, each under `limits`; prints the report.
pub fn execute(paths: Vec<PathBuf>, out: &Path, limits: &LimitArgs) -> ExitCode {
    let limits = limits.apply();
    if paths.is_empty() && !Path::new("tests").is_dir() {
        let here = std::env::current_dir().map(|d| d.display().to_string()).unwrap_or_default();
        return fail(format!(
            "error: no tests directory in {here}: without paths, `blocksmith test` runs the .rhai files \
             under ./tests (relative to where it is run); give test files or directories"
        ));
    }
    let paths = if paths.is_empty() { vec![PathBuf::from("tests")] } else { paths };
    let files = match collect(&paths) {
        Ok(f) => f,
        Err(e) => return fail(e),
    };
    let outcomes = run_all(&files, out, limits.max_operations, limits.timeout, &limits.progress);
    print_out(&report(&outcomes));
    if outcomes.iter().any(|o| o.error.is_some()) {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}

/// The outcome of one test script.
#[derive(Debug, Clone)]
pub struct TestOutcome {
    pub path: PathBuf,
    pub elapsed: Duration,
    /// `None` when the script passed; the formatted error otherwise.
    pub error: Option<String>,
}

/// Every `*.rhai` file under `paths` (files as given, directories searched recursively), sorted,
/// each real file once: a symbolic link to a folder already searched (a link to `.`) or to a
/// file already found is not followed again, so links cannot repeat a test or loop.
///
/// # Errors
/// A path that does not exist.
pub fn collect(paths: &[PathBuf]) -> Result<Vec<PathBuf>, String> {
    let mut files = Vec::new();
    let mut seen = Seen::default();
    for p in paths {
        if p.is_file() {
            if seen.first(p) {
                files.push(p.clone());
            }
        } else if p.is_dir() {
            walk(p, &mut files, &mut seen);
        } else {
            return Err(format!("error: no such test file or directory: {}", p.display()));
        }
    }
    files.sort();
    files.dedup();
    Ok(files)
}

/// The real paths (links resolved) of the folders and files visited.
#[derive(Default)]
struct Seen(std::collections::HashSet<PathBuf>);

impl Seen {
    /// Whether `p` is seen for the first time (a path that cannot be resolved counts as new).
    fn first(&mut self, p: &Path) -> bool {
        self.0.insert(p.canonicalize().unwrap_or_else(|_| p.to_path_buf()))
    }
}

fn walk(dir: &Path, out: &mut Vec<PathBuf>, seen: &mut Seen) {
    if !seen.first(dir) {
        return;
    }
    let Ok(rd) = std::fs::read_dir(dir) else { return };
    let mut entries: Vec<PathBuf> = rd.filter_map(Result::ok).map(|e| e.path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            walk(&p, out, seen);
        } else if p.extension().is_some_and(|e| e == "rhai")
            && !p.file_name().and_then(|n| n.to_str()).is_some_and(|n| n.starts_with('_'))
            && seen.first(&p)
        {
            out.push(p);
        }
    }
}

/// Runs each test script in a fresh engine, on as many threads as there are cores; relative
/// `save` paths go under `output_dir`; each script stops after `max_operations` operations or
/// `timeout` (its own count and deadline). Outcomes come back in the order of `files`.
#[must_use]
pub fn run_all(
    files: &[PathBuf],
    output_dir: &Path,
    max_operations: Option<u64>,
    timeout: Option<Duration>,
    progress: &Progress,
) -> Vec<TestOutcome> {
    let next = AtomicUsize::new(0);
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get()).min(files.len().max(1));
    let mut outcomes: Vec<Option<TestOutcome>> = vec![None; files.len()];
    let results = std::sync::Mutex::new(&mut outcomes);
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::SeqCst);
                let Some(path) = files.get(i) else { break };
                let outcome = run_one(path, output_dir, max_operations, timeout, progress);
                if let Ok(mut r) = results.lock() {
                    r[i] = Some(outcome);
                }
            });
        }
    });
    outcomes.into_iter().flatten().collect()
}

/// How a test that expects a warning says so, after the warnings that failed it.
const TAKE_WARNINGS: &str = "(in a test every warning is an error; a test that expects a warning from a run, such as \
     mesh's unconnected blocks, takes them with `take_warnings()` and checks them)";

fn run_one(
    path: &Path,
    output_dir: &Path,
    max_operations: Option<u64>,
    timeout: Option<Duration>,
    progress: &Progress,
) -> TestOutcome {
    let start = Instant::now();
    let context = RunContext { output_dir: Some(output_dir.to_path_buf()), ..RunContext::default() };
    let options = EngineOptions {
        context,
        max_operations,
        timeout,
        progress: progress.clone(),
        interrupt: Some(crate::interrupt::flag()),
    };
    let error = match run_recipe(path, options) {
        Err(e) => Some(e.error.0),
        // In a test a warning is an error (a dropped result, blocks that touch without
        // connecting): the test may pass for the wrong reason. A test that means to make such a
        // model takes the run's warnings with `take_warnings()` and checks them.
        Ok(run) if !run.warnings.is_empty() => {
            let mut lines: Vec<String> =
                run.warnings.iter().map(|w| w.replacen(": warning: ", ": error: ", 1)).collect();
            lines.push(TAKE_WARNINGS.to_string());
            Some(lines.join("\n"))
        }
        Ok(_) => None,
    };
    TestOutcome { path: path.to_path_buf(), elapsed: start.elapsed(), error }
}

/// The report: one line per script (failures followed by their error, indented), then
/// `N passed, N failed`.
#[must_use]
pub fn report(outcomes: &[TestOutcome]) -> String {
    let mut out = String::new();
    for o in outcomes {
        let ms = o.elapsed.as_millis();
        match &o.error {
            None => out.push_str(&format!("ok   {} ({ms} ms)\n", o.path.display())),
            Some(e) => {
                out.push_str(&format!("FAIL {} ({ms} ms)\n", o.path.display()));
                for line in e.lines() {
                    out.push_str(&format!("     {line}\n"));
                }
            }
        }
    }
    let failed = outcomes.iter().filter(|o| o.error.is_some()).count();
    out.push_str(&format!("{} passed, {failed} failed\n", outcomes.len() - failed));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn links_to_folders_already_searched_visit_each_test_once() {
        // With one link to `.` every test was found again under the link, and with two the
        // search took 2^depth paths (it hung); each real file is one test.
        let d = tempfile::tempdir().unwrap();
        let dir = d.path();
        std::fs::write(dir.join("a.rhai"), "1").unwrap();
        std::fs::create_dir(dir.join("sub")).unwrap();
        std::fs::write(dir.join("sub/b.rhai"), "1").unwrap();
        std::os::unix::fs::symlink(".", dir.join("self1")).unwrap();
        std::os::unix::fs::symlink(".", dir.join("self2")).unwrap();
        std::os::unix::fs::symlink("..", dir.join("sub/up")).unwrap();
        std::os::unix::fs::symlink("a.rhai", dir.join("alias.rhai")).unwrap();
        let files = collect(&[dir.to_path_buf(), dir.join("a.rhai")]).unwrap();
        let real: Vec<PathBuf> = files.iter().map(|f| f.canonicalize().unwrap()).collect();
        let base = dir.canonicalize().unwrap();
        assert_eq!(files.len(), 2, "{files:?}");
        assert!(real.contains(&base.join("a.rhai")) && real.contains(&base.join("sub/b.rhai")), "{files:?}");
    }
}
