//! The binary under hostile input: saves that fail leave the old file, test output stays in
//! its directory, long work stops on request, and no request aborts the process.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn blocksmith() -> Command {
    Command::new(env!("CARGO_BIN_EXE_blocksmith"))
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A failure: non-zero exit, no panic or abort, and the message expected.
fn assert_fails_with(o: &Output, needle: &str) {
    let err = stderr(o);
    assert!(!o.status.success(), "expected failure, got success; stderr:\n{err}");
    assert!(o.status.code().is_some(), "killed by a signal: {:?}\n{err}", o.status);
    assert!(!err.contains("panicked"), "a panic reached the user:\n{err}");
    assert!(err.contains(needle), "expected {needle:?} in:\n{err}");
}

fn entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    names
}

#[cfg(unix)]
#[test]
fn a_save_cut_short_by_the_file_size_limit_leaves_the_old_file_and_no_partial_file() {
    // `ulimit -f 64` allows 32 KiB per file (512-byte blocks); the icosphere's GLB is about
    // 0.5 MB. SIGXFSZ is ignored so that the write fails with EFBIG instead of killing us.
    let d = tempfile::tempdir().unwrap();
    let recipe = write(d.path(), "big.rhai", "icosphere(1, 5)\n");
    let old = write(d.path(), "old.glb", "the old file");
    let o = Command::new("sh")
        .arg("-c")
        .arg("trap '' XFSZ; ulimit -f 64; exec \"$0\" run \"$1\" -o \"$2\"")
        .arg(env!("CARGO_BIN_EXE_blocksmith"))
        .arg(&recipe)
        .arg(&old)
        .output()
        .unwrap();
    assert_fails_with(&o, "old.glb: cannot write the file");
    assert_eq!(std::fs::read_to_string(&old).unwrap(), "the old file");
    assert_eq!(entries(d.path()), ["big.rhai", "old.glb"]);
}

#[test]
fn test_output_cannot_escape_the_out_directory() {
    let d = tempfile::tempdir().unwrap();
    let tests = d.path().join("a/b");
    std::fs::create_dir_all(&tests).unwrap();
    write(&tests, "escape.rhai", "cube(1).save(\"../../x.obj\");\n");
    write(&tests, "inside.rhai", "cube(1).save(\"sub/../y.obj\");\n");
    let out = tests.join("out");
    let o = blocksmith().arg("test").arg(&tests).arg("--out").arg(&out).output().unwrap();
    let report = String::from_utf8_lossy(&o.stdout);
    assert!(report.contains("leaves the output directory"), "{report}");
    assert!(report.lines().last() == Some("1 passed, 1 failed"), "{report}");
    assert!(out.join("y.obj").exists());
    assert!(!d.path().join("a/x.obj").exists() && !tests.join("x.obj").exists());
}
