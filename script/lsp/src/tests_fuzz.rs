//! Every feature on recipes as they are while being typed: each example and standard-library
//! module, edited at random (seeded, the same edits on every run) — tokens typed in, runs of
//! characters deleted, lines doubled, back to the file every 50 edits — and after each edit the
//! diagnostics, and completion, hover, signature help, definition, symbols and inlay hints at
//! the edited place. A panic fails the test; so does a call that runs for many seconds (a hang,
//! not a speed). The suite makes 20 edits of each file (about 20 s); the full fuzz is
//! `BLOCKSMITH_LSP_FUZZ_EDITS=1000 cargo test --release -p blocksmith-lsp --lib tests_fuzz --
//! --nocapture` (40,000 edits in 755 s on one core, 2026-12-06: no panic, the slowest edit 42 ms;
//! all seven features after every edit cost about 19 ms), which prints the slowest edit.

use std::path::Path;
use std::time::{Duration, Instant};

use blocksmith_kernel::math::SplitMix64;

use crate::Analyzer;

/// What editing types in: brackets and quotes left open, operators, keywords, calls, comments,
/// interpolation, a line break, a multi-byte character.
const TYPED: &[&str] = &[
    "(",
    ")",
    "{",
    "}",
    "[",
    "]",
    "#{",
    "\"",
    "`",
    "'",
    ".",
    ",",
    ";",
    ":",
    "::",
    "=",
    "+",
    "-",
    "|x|",
    "let ",
    "fn ",
    "import \"",
    "m.",
    "cube(",
    "#{ twist: ",
    "//",
    "/*",
    "*/",
    "${",
    "\n",
    "é",
    "0.5",
    "1e400",
    "this",
    "}\n",
];

/// The largest char boundary of `text` at or before `at`.
fn boundary(text: &str, mut at: usize) -> usize {
    at = at.min(text.len());
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    at
}

/// One random edit of `text`; the place it was made.
fn edit(text: &mut String, rng: &mut SplitMix64) -> usize {
    let at = boundary(text, rng.below(text.len() + 1));
    match rng.below(3) {
        0 => text.insert_str(at, TYPED[rng.below(TYPED.len())]),
        1 => {
            let end = boundary(text, at + 1 + rng.below(6));
            text.replace_range(at..end, "");
        }
        _ => {
            let start = text[..at].rfind('\n').map_or(0, |i| i + 1);
            let end = text[at..].find('\n').map_or(text.len(), |i| at + i + 1);
            let line = text[start..end].to_string();
            text.insert_str(start, &line);
        }
    }
    boundary(text, at)
}

#[test]
fn random_edits_of_every_recipe_never_panic_or_hang() {
    let a = Analyzer::new();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let hang = Duration::from_secs(20);
    let edits: usize = std::env::var("BLOCKSMITH_LSP_FUZZ_EDITS").ok().and_then(|n| n.parse().ok()).unwrap_or(20);
    let mut slowest = (Duration::ZERO, String::new());
    let mut recipes = 0;
    for dir in ["examples", "stdlib"] {
        let mut files: Vec<_> = std::fs::read_dir(root.join(dir)).unwrap().map(|e| e.unwrap().path()).collect();
        files.retain(|p| p.extension().is_some_and(|e| e == "rhai"));
        files.sort();
        for path in files {
            let original = std::fs::read_to_string(&path).unwrap();
            let uri = crate::navigate::uri_of(&path).unwrap();
            let dir = path.parent();
            let mut rng = SplitMix64::new(recipes as u64 + 1);
            let mut text = original.clone();
            for k in 0..edits {
                if k % 50 == 0 {
                    text.clone_from(&original);
                }
                let at = edit(&mut text, &mut rng);
                let start = Instant::now();
                let _ = crate::diagnose::diagnostics(&a, &text, Some(&path));
                let _ = crate::complete::complete(&a, &text, at, dir);
                let _ = crate::describe::hover(&a, &text, at, dir);
                let _ = crate::describe::signature_help(&a, &text, at, dir);
                let _ = crate::navigate::definition(&text, at, &uri, dir);
                let _ = crate::inlay::hints(&a, &text, None);
                let _ = crate::navigate::symbols(&a, &text);
                let took = start.elapsed();
                if took > slowest.0 {
                    slowest = (took, format!("{} edit {k}", path.display()));
                }
                assert!(took < hang, "{} after edit {k} at byte {at}: {took:?}\n{text}", path.display());
            }
            recipes += 1;
        }
    }
    assert!(recipes > 30, "{recipes}");
    eprintln!("slowest: {slowest:?}");
}

#[test]
fn every_feature_at_every_place_of_a_recipe_with_multi_byte_characters() {
    // An identifier after a dash of three bytes ('–') or an accented letter: the features cut
    // the text at character boundaries, never inside one.
    let a = Analyzer::new();
    let text = "// a – b\nlet m = cube(1);\nlet é = 2;\n–m.vol\nimport \"–\" as x;\nx::–f(é)\n";
    let uri = crate::navigate::uri_of(Path::new("/tmp/multi.rhai")).unwrap();
    for at in (0..=text.len()).filter(|&i| text.is_char_boundary(i)) {
        let _ = crate::complete::complete(&a, text, at, None);
        let _ = crate::describe::hover(&a, text, at, None);
        let _ = crate::describe::signature_help(&a, text, at, None);
        let _ = crate::navigate::definition(text, at, &uri, None);
    }
    assert_eq!(crate::text::ident_start("a – bc"), 6);
    assert_eq!(crate::text::ident_start("–"), 3);
    assert_eq!(crate::text::ident_start("é"), 0);
}
