//! Every ```rhai example in a binding's doc comment runs and passes.

use blocksmith_script::{doc, new_engine, EngineOptions, RunContext};

#[test]
fn every_doc_example_runs() {
    let out = tempfile::tempdir().unwrap();
    let options = || EngineOptions {
        context: RunContext { output_dir: Some(out.path().to_path_buf()), ..RunContext::default() },
        ..EngineOptions::default()
    };
    let examples = doc::examples(&new_engine(options()));
    assert!(examples.len() > 20, "only {} examples found", examples.len());
    let mut failures = Vec::new();
    for (name, code) in &examples {
        // `load` examples read what `save` examples wrote: run them from the output directory.
        let engine = new_engine(options());
        let _ = std::env::set_current_dir(out.path());
        if let Err(e) = engine.run(code) {
            failures.push(format!("{name}: {e}\n{code}"));
        }
    }
    assert!(failures.is_empty(), "{} doc examples failed:\n{}", failures.len(), failures.join("\n"));
}

/// The README's tour is a script too: it must keep running as the API grows.
#[test]
fn readme_tour_runs() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).ancestors().nth(2).unwrap();
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let start = readme.find("```rhai\n").expect("a ```rhai block in the README") + "```rhai\n".len();
    let code = &readme[start..start + readme[start..].find("```").unwrap()];
    let value = new_engine(EngineOptions::default()).eval::<rhai::Dynamic>(code);
    let value = value.unwrap_or_else(|e| panic!("README tour failed: {e}\n{code}"));
    assert!(value.is::<blocksmith_script::api::mesh::SharedMesh>(), "the tour ends with a Mesh");
}

/// Every function, property, operator and standard-library function shows how it is used:
/// a ```rhai example in its doc comment, which `every_doc_example_runs` keeps true.
#[test]
fn every_function_has_an_example() {
    let missing = doc::without_example(&new_engine(EngineOptions::default()));
    assert!(
        missing.is_empty(),
        "{} functions have no ```rhai example in their doc comment:\n{}",
        missing.len(),
        missing.join("\n")
    );
}

/// docs/reference.md and docs/reference.html are what `blocksmith doc --format markdown|html`
/// writes today.
#[test]
fn reference_pages_are_current() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).ancestors().nth(2).unwrap();
    let engine = new_engine(EngineOptions::default());
    let pages = [
        ("docs/reference.md", doc::Format::Markdown, doc::reference::REFRESH_MARKDOWN),
        ("docs/reference.html", doc::Format::Html, doc::reference::REFRESH_HTML),
    ];
    for (file, format, refresh) in pages {
        let fresh = doc::render_as(&engine, None, format).unwrap();
        let kept = std::fs::read_to_string(root.join(file)).unwrap_or_default();
        if kept != fresh {
            let line = kept.lines().zip(fresh.lines()).position(|(a, b)| a != b).map_or(0, |i| i + 1);
            panic!(
                "{file} is out of date (first difference at line {line}); refresh it from the repository's \
                 root with\n    {refresh}"
            );
        }
    }
}
