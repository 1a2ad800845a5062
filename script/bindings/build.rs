//! Embeds every `stdlib/*.rhai` file into the binary, so an installed `blocksmith` finds its
//! standard library without the source tree, and tabulates the script API's functions as their
//! declarations state them (what the dropped-result lint needs and Rhai's metadata lacks: which
//! functions leave their receiver unchanged).

use std::fmt::Write as _;
use std::path::Path;

/// This crate's folder, as cargo gives it to this run (not as it was when the script was
/// compiled: a build folder shared by two checkouts runs one compiled script for both).
fn manifest_dir() -> std::path::PathBuf {
    std::path::PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"))
}

/// The entries of `dir`; a folder that cannot be read fails the build rather than leaving the
/// table empty.
fn read_dir(dir: &Path) -> Vec<std::path::PathBuf> {
    let entries = std::fs::read_dir(dir).unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()));
    entries.filter_map(Result::ok).map(|e| e.path()).collect()
}

fn main() {
    stdlib();
    registry();
}

fn stdlib() {
    let dir = manifest_dir().join("../../stdlib");
    println!("cargo:rerun-if-changed={}", dir.display());
    let mut entries: Vec<_> = read_dir(&dir);
    entries.retain(|p| p.extension().is_some_and(|e| e == "rhai"));
    entries.sort();
    let mut out = String::from("/// The standard library: (module name, source), from `stdlib/*.rhai`.\npub const STDLIB: &[(&str, &str)] = &[\n");
    for p in entries {
        println!("cargo:rerun-if-changed={}", p.display());
        let name = p.file_stem().and_then(|s| s.to_str()).unwrap_or_default().to_string();
        let abs = p.canonicalize().expect("stdlib file path");
        writeln!(out, "    ({name:?}, include_str!({:?})),", abs.display().to_string()).unwrap();
    }
    out.push_str("];\n");
    let dest = Path::new(&std::env::var("OUT_DIR").expect("OUT_DIR")).join("stdlib.rs");
    std::fs::write(dest, out).expect("write stdlib.rs");
}

/// One registered script function as its `#[export_module]` declares it.
struct Declared {
    names: Vec<String>,
    receiver: Option<String>,
    arity: usize,
    pure: bool,
    context: bool,
    returns: String,
    params: Vec<String>,
    /// The api file that registers it (`mesh` for `src/api/mesh.rs`): the reference's topic of a
    /// free function without a `Topic:` line (`doc::topics`).
    module: String,
}

/// Reads every `#[export_module]` module of `src/api/*.rs` and writes the table of registered
/// functions the dropped-result lint works from (`api::registry`): names, the receiver's Rust
/// type when the first parameter is `&mut`, arity, whether it is declared `pure` (leaves its
/// receiver unchanged), whether it takes the call context (and so may act beyond its
/// arguments: write a file, declare a parameter) and the Rust type it returns. Getters and setters are left out.
fn registry() {
    let dir = manifest_dir().join("src/api");
    println!("cargo:rerun-if-changed={}", dir.display());
    let mut files: Vec<_> = read_dir(&dir);
    files.retain(|p| p.extension().is_some_and(|e| e == "rs"));
    files.sort();
    let mut all = Vec::new();
    for p in files {
        println!("cargo:rerun-if-changed={}", p.display());
        let text = std::fs::read_to_string(&p).expect("read api file");
        let module = p.file_stem().and_then(|s| s.to_str()).unwrap_or_default().to_string();
        all.extend(declared(&text).into_iter().map(|d| Declared { module: module.clone(), ..d }));
    }
    let mut out = String::from(
        "/// Every function of the script API's `#[export_module]`s (generated from their declarations).\n\
         pub const REGISTRY: &[Declared] = &[\n",
    );
    for d in all {
        for n in &d.names {
            writeln!(
                out,
                "    Declared {{ name: {n:?}, receiver: {:?}, arity: {}, pure: {}, context: {}, returns: {:?}, params: &{:?}, module: {:?} }},",
                d.receiver, d.arity, d.pure, d.context, d.returns, d.params, d.module
            )
            .unwrap();
        }
    }
    out.push_str("];\n");
    let dest = Path::new(&std::env::var("OUT_DIR").expect("OUT_DIR")).join("registry.rs");
    std::fs::write(dest, out).expect("write registry.rs");
}

fn declared(text: &str) -> Vec<Declared> {
    let mut out = Vec::new();
    let mut inside = false;
    let mut attrs = String::new();
    let mut lines = text.lines();
    while let Some(line) = lines.next() {
        if !inside {
            inside = line.starts_with("pub mod ") && line.trim_end().ends_with("_api {");
            continue;
        }
        if line == "}" {
            inside = false;
            continue;
        }
        let t = line.trim();
        if t.starts_with("#[rhai_fn(") {
            attrs.push_str(t);
            continue;
        }
        if line.starts_with("    pub fn ") {
            let mut sig = t.to_string();
            while !sig.trim_end().ends_with('{') {
                match lines.next() {
                    Some(l) => sig.push_str(l.trim()),
                    None => break,
                }
            }
            if let Some(d) = parse(&sig, &attrs) {
                out.push(d);
            }
        }
        if !t.starts_with("///") && !t.starts_with("#[") {
            attrs.clear();
        }
        if line.starts_with("    pub fn ") {
            attrs.clear();
        }
    }
    out
}

fn parse(sig: &str, attrs: &str) -> Option<Declared> {
    if attrs.contains("get = ") || attrs.contains("set = ") || attrs.contains("skip") {
        return None;
    }
    let rest = sig.strip_prefix("pub fn ")?;
    let open = rest.find('(')?;
    let ident = rest[..open].trim().to_string();
    // The parameter list: up to the matching parenthesis.
    let mut depth = 0;
    let mut close = open;
    for (i, c) in rest.char_indices().skip(open) {
        match c {
            '(' | '<' => depth += 1,
            ')' | '>' if depth > 0 => {
                depth -= 1;
                if depth == 0 && c == ')' {
                    close = i;
                    break;
                }
            }
            _ => {}
        }
    }
    let params_text = &rest[open + 1..close];
    let mut params = Vec::new();
    let (mut depth, mut start) = (0, 0);
    for (i, c) in params_text.char_indices() {
        match c {
            '<' | '(' | '[' => depth += 1,
            '>' | ')' | ']' => depth -= 1,
            ',' if depth == 0 => {
                params.push(params_text[start..i].trim());
                start = i + 1;
            }
            _ => {}
        }
    }
    params.push(params_text[start..].trim());
    let context = params.iter().any(|p| p.contains("NativeCallContext"));
    params.retain(|p| !p.is_empty() && !p.contains("NativeCallContext"));
    let ty = |p: &str| p.split_once(':').map(|(_, t)| t.trim().to_string()).unwrap_or_default();
    let receiver = params.first().map(|p| ty(p)).and_then(|t| t.strip_prefix("&mut ").map(str::to_string));
    let after = rest[close + 1..].trim().trim_end_matches('{').trim();
    let ret = after.strip_prefix("->").map(str::trim).unwrap_or("()");
    let ret = ret.strip_prefix("ScriptResult<").and_then(|r| r.strip_suffix('>')).unwrap_or(ret);
    let mut names: Vec<String> =
        attrs.split("name = \"").skip(1).filter_map(|s| s.split('"').next()).map(str::to_string).collect();
    if names.is_empty() {
        names.push(ident);
    }
    let pure = attrs.split(|c: char| !c.is_alphanumeric() && c != '_').any(|w| w == "pure");
    let types = params.iter().map(|p| ty(p).trim_start_matches("&mut ").trim_start_matches('&').to_string()).collect();
    Some(Declared {
        names,
        receiver,
        arity: params.len(),
        pure,
        context,
        returns: ret.to_string(),
        params: types,
        module: String::new(),
    })
}
