//! Every trap of the page falls in as the page says, and every fix runs.

use super::*;
use crate::run::run_recipe;
use crate::EngineOptions;

/// Runs `code` as a recipe file; the formatted error, if any.
fn run(code: &str) -> Result<(), String> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("trap.rhai");
    std::fs::write(&path, code).unwrap();
    run_recipe(&path, EngineOptions::default()).map(|_| ()).map_err(|f| f.error.0)
}

#[test]
fn each_trap_gives_the_error_the_page_shows_and_each_fix_runs() {
    for t in TRAPS {
        match run(t.wrong) {
            // A silent trap runs (its own asserts state the surprising value).
            Ok(()) => assert!(t.error.is_empty(), "{}: ran without the error `{}`", t.title, t.error),
            Err(e) => {
                assert!(!t.error.is_empty(), "{}: the page says it runs, but:\n{e}", t.title);
                assert!(e.contains(t.error), "{}: the page says `{}`, blocksmith says:\n{e}", t.title, t.error);
                // Every error points at its line.
                assert!(e.contains("trap.rhai:") && e.contains(" | "), "{}: no line and caret:\n{e}", t.title);
            }
        }
        if let Err(e) = run(t.fix) {
            panic!("{}: the fix fails:\n{e}", t.title);
        }
    }
}

#[test]
fn the_page_names_each_trap_with_its_code_error_and_fix() {
    let md = markdown();
    assert!(md.starts_with(&format!("## {TITLE}\n")));
    for t in TRAPS {
        assert!(md.contains(&format!("### {}\n", t.title)));
        assert!(md.contains(t.wrong) && md.contains(t.fix));
        if !t.error.is_empty() {
            assert!(md.contains(&format!("blocksmith says: `{}`", t.error)), "{}", t.title);
        }
    }
    // The traps issue 37 names are all there.
    for must in ["by value", "do not see", "reserved", "Ranges are not arrays", "Integer division"] {
        assert!(TRAPS.iter().any(|t| t.title.contains(must)), "no trap about {must}");
    }
}
