//! `blocksmith lsp` driven by a real language-server client: pytest-lsp (PyPI, on pygls) runs
//! tests/lsp/test_lsp.py against this build's binary. `.ci/run` installs pytest-lsp into a
//! virtual environment and names its Python in `BLOCKSMITH_LSP_PYTHON`; elsewhere the test
//! looks for `.ci/lsp-py` and fails under CI when neither is there (skips, saying so, on a
//! developer's machine without it).

use std::path::PathBuf;
use std::process::Command;
use std::time::Duration;

#[path = "support/child.rs"]
mod child;

fn python() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("BLOCKSMITH_LSP_PYTHON") {
        return Some(PathBuf::from(p));
    }
    let local = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../.ci/lsp-py/bin/python");
    local.is_file().then_some(local)
}

#[test]
fn a_real_client_gets_diagnostics_completion_hover_definitions_and_the_run_lens() {
    let Some(python) = python() else {
        assert!(std::env::var_os("CI").is_none(), "CI must install pytest-lsp (.ci/run sets BLOCKSMITH_LSP_PYTHON)");
        eprintln!(
            "skipped: no pytest-lsp (python3 -m venv .ci/lsp-py && .ci/lsp-py/bin/pip install pytest-lsp==1.0.1)"
        );
        return;
    };
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/lsp");
    let logs = tempfile::tempdir().unwrap();
    let (out_path, err_path) = (logs.path().join("stdout"), logs.path().join("stderr"));
    let mut child = Command::new(python)
        .args(["-m", "pytest", "-q", "-p", "no:cacheprovider", "test_lsp.py"])
        .current_dir(&dir)
        .env("BLOCKSMITH_BIN", env!("CARGO_BIN_EXE_blocksmith"))
        .stdout(std::fs::File::create(&out_path).unwrap())
        .stderr(std::fs::File::create(&err_path).unwrap())
        .spawn()
        .expect("run pytest");
    // A server that stops answering (or never ends) fails the test instead of holding CI.
    let status = child::wait_within(&mut child, Duration::from_secs(300));
    if status.is_none() {
        let _ = child.kill();
        let _ = child.wait();
    }
    let text = format!(
        "{}{}",
        std::fs::read_to_string(&out_path).unwrap_or_default(),
        std::fs::read_to_string(&err_path).unwrap_or_default()
    );
    let status = status.unwrap_or_else(|| panic!("pytest-lsp still ran after 300 s:\n{text}"));
    assert!(status.success(), "{text}");
    assert!(text.contains("5 passed"), "{text}");
}
