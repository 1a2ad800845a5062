//! The features on small recipes: each class of diagnostic with its range, completion after
//! `m.` and inside `#{}`, hover equal to `blocksmith doc`, definitions into imported modules;
//! and the repository's recipes diagnosed without a false error.

use lsp_types::{DiagnosticSeverity, NumberOrString, Position};

use crate::text::Lines;
use crate::Analyzer;

fn diagnose(a: &Analyzer, src: &str) -> Vec<(String, u32, u32, u32, String)> {
    crate::diagnose::diagnostics(a, src, None)
        .into_iter()
        .map(|d| {
            let code = match d.code {
                Some(NumberOrString::String(s)) => s,
                _ => String::new(),
            };
            (code, d.range.start.line, d.range.start.character, d.range.end.character, d.message)
        })
        .collect()
}

#[test]
fn each_class_of_diagnostic_has_its_range() {
    let a = Analyzer::new();
    // Syntax.
    let d = diagnose(&a, "let m = cube(2;\n");
    assert_eq!(d.len(), 1, "{d:?}");
    assert_eq!(d[0].0, "syntax");
    // Unknown function with did-you-mean, at the name.
    let d = diagnose(&a, "let m = cilinder(1, 2, 16);\nm\n");
    assert_eq!(d[0].0, "unknown-function", "{d:?}");
    assert_eq!((d[0].1, d[0].2, d[0].3), (0, 8, 16));
    assert!(d[0].4.contains("did you mean `cylinder`"), "{d:?}");
    // Unknown method on a known Mesh.
    let d = diagnose(&a, "let m = cube(1);\nlet v = m.volum();\nv\n");
    assert_eq!((d[0].0.as_str(), d[0].1, d[0].2, d[0].3), ("unknown-function", 1, 10, 15), "{d:?}");
    assert_eq!(d[0].4, "Mesh has no method `volum` (did you mean `volume`?)");
    // A property.
    let d = diagnose(&a, "let m = cube(1);\nm.vertex_cont\n");
    assert_eq!(d[0].0, "unknown-property", "{d:?}");
    assert!(d[0].4.contains("did you mean `.vertex_count`"), "{d:?}");
    // No signature: a float where a count is needed, as a run explains it.
    let d = diagnose(&a, "cylinder(1, 2, 16.5)\n");
    assert_eq!((d[0].0.as_str(), d[0].2, d[0].3), ("no-signature", 0, 8), "{d:?}");
    assert!(d[0].4.contains("argument 3 `segments` must be an integer, got a float"), "{d:?}");
    let d = diagnose(&a, "cube(1).translate(1, 2, 3, 4, 5)\n");
    assert_eq!(d[0].0, "no-signature", "{d:?}");
    // An array is a colour or a point as far as a reading can tell; a map is neither.
    let d = diagnose(&a, "let c = [1, 0, 0];\ncube(1).color(c) + extrude(rect([0, 0], [1, 1]).translate(c), 1)\n");
    assert!(d.iter().all(|x| x.0 != "no-signature"), "{d:?}");
    let d = diagnose(&a, "cube(1).color(#{ r: 1 })\n");
    assert_eq!(d[0].0, "no-signature", "{d:?}");
    assert!(d[0].4.contains("must be a colour"), "{d:?}");
    // Unknown option key, at the key.
    let d = diagnose(&a, "let p = rect([0, 0], [1, 1]);\nextrude(p, 2, #{ twsit: 30 })\n");
    assert_eq!((d[0].0.as_str(), d[0].1, d[0].2, d[0].3), ("unknown-option", 1, 17, 22), "{d:?}");
    assert!(d[0].4.contains("did you mean `twist`"), "{d:?}");
    // A param whose default breaks its own range.
    let d = diagnose(&a, "let n = param(\"n\", 20, #{ min: 1, max: 12 });\ncube(n)\n");
    assert_eq!((d[0].0.as_str(), d[0].1, d[0].2), ("param-default", 0, 19), "{d:?}");
    assert!(d[0].4.contains("`n`") && d[0].4.contains("20"), "{d:?}");
    // An import that resolves nowhere.
    let d = diagnose(&a, "import \"chek\" as c;\n1\n");
    assert_eq!((d[0].0.as_str(), d[0].2, d[0].3), ("unresolved-import", 7, 13), "{d:?}");
    assert!(d[0].4.contains("did you mean \"check\""), "{d:?}");
    // The lint, as a warning.
    let all = crate::diagnose::diagnostics(&a, "let c = cube(2);\nc.translate([5, 0, 0]);\nc\n", None);
    assert_eq!(all[0].severity, Some(DiagnosticSeverity::WARNING));
    assert_eq!((all[0].range.start.line, all[0].range.start.character), (1, 2));
}

#[test]
fn scripts_own_functions_closures_and_modules_are_not_unknown() {
    let a = Analyzer::new();
    let src = "fn leg(h) { cube(1).scale([0.1, 0.1, h]) }\nlet f = |x| x * 2;\nlet g = f(2);\n\
               import \"check\" as check;\nlet m = leg(2);\ncheck::solid(m, 0);\nfn lift(dz) { this.translate([0, 0, dz]) }\n\
               let b = block([0, 0, 0], [1, 1, 1]);\nb.lift(1);\nprint(type_of(m));\nm\n";
    let d = diagnose(&a, src);
    assert!(d.iter().all(|x| x.0 == "dropped-result"), "{d:?}");
}

#[test]
fn the_repository_s_recipes_have_no_false_error() {
    let a = Analyzer::new();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut checked = 0;
    // The script tests make errors on purpose (to check their messages): not these.
    for dir in ["examples", "stdlib"] {
        let mut files: Vec<_> = std::fs::read_dir(root.join(dir)).unwrap().map(|e| e.unwrap().path()).collect();
        files.retain(|p| p.extension().is_some_and(|e| e == "rhai"));
        for p in files {
            let src = std::fs::read_to_string(&p).unwrap();
            let d = crate::diagnose::diagnostics(&a, &src, Some(&p));
            let errors: Vec<_> = d.iter().filter(|d| d.severity == Some(DiagnosticSeverity::ERROR)).collect();
            assert!(errors.is_empty(), "{}: {errors:#?}", p.display());
            checked += 1;
        }
    }
    assert!(checked > 30, "{checked}");
}

fn labels(items: &[lsp_types::CompletionItem]) -> Vec<&str> {
    items.iter().map(|i| i.label.as_str()).collect()
}

#[test]
fn completion_follows_the_receiver_option_maps_imports_and_modules() {
    let a = Analyzer::new();
    let src = "let m = cube(2).translate([1, 0, 0]);\nm.";
    let items = crate::complete::complete(&a, src, src.len(), None);
    let l = labels(&items);
    assert!(l.contains(&"catmull_clark") && l.contains(&"vertex_count") && l.contains(&"volume"), "{l:?}");
    assert!(!l.contains(&"sharp_all"), "a Block method on a Mesh: {l:?}");
    assert!(l.iter().all(|x| x.chars().all(|c| c.is_alphanumeric() || c == '_')), "engine-internal names: {l:?}");
    let src = "let p = rect([0, 0], [1, 1]);\nextrude(p, 2, #{ tw";
    let l: Vec<String> =
        labels(&crate::complete::complete(&a, src, src.len(), None)).iter().map(|s| s.to_string()).collect();
    assert_eq!(l, ["center", "scale", "slices", "twist"]);
    let src = "import \"ch";
    assert!(labels(&crate::complete::complete(&a, src, src.len(), None)).contains(&"check"));
    let src = "import \"check\" as c;\nc::";
    let l: Vec<String> =
        labels(&crate::complete::complete(&a, src, src.len(), None)).iter().map(|s| s.to_string()).collect();
    assert!(l.contains(&"solid".to_string()), "{l:?}");
    let src = "let x = cyl";
    assert!(labels(&crate::complete::complete(&a, src, src.len(), None)).contains(&"cylinder"));
}

#[test]
fn hover_is_blocksmith_doc_and_signature_help_follows_the_argument() {
    let a = Analyzer::new();
    let src = "let m = cylinder(1, 2, 16);\nm.volume()\n";
    let h = crate::describe::hover(&a, src, 10, None).unwrap();
    let lsp_types::HoverContents::Markup(text) = h.contents else { panic!() };
    let doc =
        blocksmith_script::doc::render_as(&a.engine, Some("cylinder"), blocksmith_script::doc::Format::Text).unwrap();
    assert_eq!(text.value, doc);
    let src = "let m = cube(1);\nm.translate([1, ";
    let s = crate::describe::signature_help(&a, src, src.len(), None).unwrap();
    let active = &s.signatures[s.active_signature.unwrap() as usize];
    assert_eq!(active.label, "translate(offset: Vec3) -> Mesh");
    let src = "cylinder(1, 2, ";
    let s = crate::describe::signature_help(&a, src, src.len(), None).unwrap();
    assert_eq!(s.active_parameter, Some(2));
}

#[test]
fn definitions_lead_into_imported_modules_and_the_script_s_functions() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("parts.rhai"), "/// A leg.\nfn leg(h) {\n    cube(1)\n}\n").unwrap();
    let src = "import \"parts\" as p;\nfn top() { cube(2) }\nlet l = p::leg(2);\ntop()\n";
    let uri = crate::navigate::uri_of(&d.path().join("main.rhai")).unwrap();
    let at = |needle: &str| src.find(needle).unwrap() + 1;
    let loc = crate::navigate::definition(src, at("leg(2)"), &uri, Some(d.path())).unwrap();
    assert!(loc.uri.as_str().ends_with("/parts.rhai"), "{loc:?}");
    assert_eq!(loc.range.start, Position::new(1, 3));
    let loc = crate::navigate::definition(src, at("parts\""), &uri, Some(d.path())).unwrap();
    assert!(loc.uri.as_str().ends_with("/parts.rhai"));
    let loc = crate::navigate::definition(src, src.rfind("top").unwrap() + 1, &uri, Some(d.path())).unwrap();
    assert_eq!((loc.uri, loc.range.start), (uri, Position::new(1, 3)));
    // The standard library is written out where an editor can open it.
    let src = "import \"check\" as check;\ncheck::solid(cube(1), 0);\n";
    let loc = crate::navigate::definition(
        src,
        src.find("solid").unwrap(),
        &crate::navigate::uri_of(d.path()).unwrap(),
        Some(d.path()),
    )
    .unwrap();
    assert!(loc.uri.as_str().ends_with("/check.rhai") && loc.range.start.line > 0, "{loc:?}");
}

#[test]
fn symbols_and_inlay_hints_list_functions_and_parameters() {
    let a = Analyzer::new();
    let src = "let n = param(\"count\", 5, #{ min: 1, max: 12, step: 1 });\nfn f(x) { x }\ncube(n)\n";
    let s = crate::navigate::symbols(&a, src);
    let names: Vec<&str> = s.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["count", "f"]);
    let h = crate::inlay::hints(&a, src, None);
    assert_eq!(h.len(), 1);
    let lsp_types::InlayHintLabel::String(label) = &h[0].label else { panic!() };
    assert!(label.starts_with(": int, ") && label.contains("12"), "{label}");
    assert_eq!(h[0].position, Lines::new(src).position(src.find(");").unwrap() + 1));
}
