//! `cargo test` runs the `.rhai` test suite under `tests/` as `blocksmith test` would.

use std::path::Path;

use blocksmith::test_runner;

#[test]
fn every_rhai_test_passes() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let files = test_runner::collect(&[root.join("tests")]).unwrap();
    assert!(!files.is_empty(), "no .rhai tests found");
    let outcomes = test_runner::run_all(&files, &root.join("target/test-output"));
    let report = test_runner::report(&outcomes);
    println!("{report}");
    assert!(outcomes.iter().all(|o| o.error.is_none()), "{report}");
}
