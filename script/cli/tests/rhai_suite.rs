//! `cargo test` runs the `.rhai` test suite under `tests/` through the binary, as the README
//! tells users to: `blocksmith test tests --out target/test-output`.

use std::path::Path;
use std::process::Command;

#[test]
fn every_rhai_test_passes() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).ancestors().nth(2).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_blocksmith"))
        .current_dir(root)
        .args(["test", "tests", "--out", "target/test-output"])
        .output()
        .unwrap();
    let report = String::from_utf8_lossy(&out.stdout);
    println!("{report}{}", String::from_utf8_lossy(&out.stderr));
    let last = report.lines().last().unwrap_or_default();
    assert!(last.ends_with(" 0 failed") && !last.starts_with("0 passed"), "{report}");
    assert!(out.status.success(), "{report}");
}
