//! Completion: after `alias::` the functions of the module imported as `alias`; after `x.`
//! the methods and properties of `x`'s type when it can be inferred (else every method); in an
//! `import "…"` the modules next to the recipe and the standard library's; elsewhere
//! functions, constants, the recipe's own functions, variables and module aliases.

use std::path::Path;

use lsp_types::{CompletionItem, CompletionItemKind, Documentation};

use crate::infer::{members, type_of_text, variables_in_text};
use crate::navigate::{functions, imports};
use crate::Analyzer;

/// Rhai's statement keywords, offered among plain words.
const KEYWORDS: [&str; 20] = [
    "let", "const", "fn", "private", "if", "else", "for", "in", "while", "loop", "do", "until", "break", "continue",
    "return", "throw", "try", "catch", "import", "export",
];

/// Where the bracket opened at byte `open` of `code` closes.
#[must_use]
pub fn closing(code: &str, open: usize) -> Option<usize> {
    let mut depth = 0i64;
    for (i, c) in code[open..].char_indices() {
        match c {
            '(' | '[' | '{' => depth += 1,
            ')' | ']' | '}' => {
                depth -= 1;
                if depth == 0 {
                    return Some(open + i);
                }
            }
            _ => {}
        }
    }
    None
}

fn item(label: &str, kind: CompletionItemKind, detail: Option<String>, doc: Option<&str>) -> CompletionItem {
    CompletionItem {
        label: label.to_string(),
        kind: Some(kind),
        detail,
        documentation: doc.filter(|d| !d.is_empty()).map(|d| Documentation::String(d.to_string())),
        ..CompletionItem::default()
    }
}

/// The completions at byte `offset` of `text` (the recipe at `dir`, if saved).
#[must_use]
pub fn complete(a: &Analyzer, text: &str, offset: usize, dir: Option<&Path>) -> Vec<CompletionItem> {
    let before = &text[..offset.min(text.len())];
    let line = &before[before.rfind('\n').map_or(0, |i| i + 1)..];
    // Inside `import "…`.
    if let Some(q) = line.rfind('"') {
        if line[..q].trim_end().ends_with("import") && !line[q + 1..].contains('"') {
            return import_paths(&line[q + 1..], dir);
        }
    }
    let start = crate::text::ident_start(before);
    let head = &before[..start];
    if let Some(path) = head.strip_suffix("::") {
        let alias_start = crate::text::ident_start(path);
        return module_members(a, text, &path[alias_start..], dir);
    }
    if let Some(receiver) = head.strip_suffix('.') {
        let vars = variables_in_text(&a.catalogue, &before[..start]);
        let t = type_of_text(&|v| vars.get(v).cloned(), &a.catalogue, receiver);
        return methods(a, t.as_deref());
    }
    if let Some(keys) = crate::options::keys_at(a, text, offset) {
        return keys;
    }
    words(a, text, &before[..start])
}

/// The `.rhai` files and folders next to the recipe starting with `partial` (without the
/// extension, as `import` names them) and the standard library's modules.
fn import_paths(partial: &str, dir: Option<&Path>) -> Vec<CompletionItem> {
    let mut out: Vec<CompletionItem> = blocksmith_script::resolver::Resolver::stdlib_names()
        .into_iter()
        .map(|n| item(n, CompletionItemKind::MODULE, Some("standard library".into()), None))
        .collect();
    let (folder, _) = partial.rfind('/').map_or(("", partial), |i| (&partial[..=i], &partial[i + 1..]));
    if let Some(dir) = dir {
        if let Ok(entries) = std::fs::read_dir(dir.join(folder)) {
            for e in entries.filter_map(Result::ok) {
                let name = e.file_name().to_string_lossy().to_string();
                if name.starts_with('.') {
                    continue;
                }
                if e.path().is_dir() {
                    out.push(item(&format!("{folder}{name}/"), CompletionItemKind::FOLDER, None, None));
                } else if let Some(stem) = name.strip_suffix(".rhai") {
                    out.push(item(&format!("{folder}{stem}"), CompletionItemKind::FILE, Some(name.clone()), None));
                }
            }
        }
    }
    out.sort_by(|a, b| a.label.cmp(&b.label));
    out
}

/// The functions of the module imported as `alias`.
fn module_members(a: &Analyzer, text: &str, alias: &str, dir: Option<&Path>) -> Vec<CompletionItem> {
    let Some(imp) = imports(text).into_iter().find(|i| i.alias == alias) else { return Vec::new() };
    let Some(file) = crate::navigate::module_file(&imp.name, dir) else { return Vec::new() };
    let Ok(source) = std::fs::read_to_string(&file) else { return Vec::new() };
    let _ = a;
    functions(&source)
        .iter()
        .map(|f| item(&f.name, CompletionItemKind::FUNCTION, Some(f.signature(Some(alias))), Some(&f.doc)))
        .collect()
}

/// The methods and properties of type `t`, or every method of the API when it is not known.
fn methods(a: &Analyzer, t: Option<&str>) -> Vec<CompletionItem> {
    let chosen: Vec<&blocksmith_script::catalogue::Overload> = match t {
        Some(t) => members(&a.catalogue, t),
        None => a.catalogue.iter().filter(|o| o.ours && o.receiver().is_some() && o.property != Some("set")).collect(),
    };
    let mut out: Vec<CompletionItem> = Vec::new();
    // Only names a recipe can write after `.`: not the engine's indexers (`index$get$`) nor
    // operators.
    let writable = |name: &str| {
        name.starts_with(|c: char| c.is_alphabetic() || c == '_')
            && name.chars().all(|c| c.is_alphanumeric() || c == '_')
    };
    for o in chosen.into_iter().filter(|o| writable(&o.name)) {
        if out.last().is_some_and(|l: &CompletionItem| l.label == o.name) {
            continue;
        }
        let kind = if o.property.is_some() { CompletionItemKind::PROPERTY } else { CompletionItemKind::METHOD };
        out.push(item(&o.name, kind, Some(o.signature()), Some(&o.doc)));
    }
    out.sort_by(|a, b| a.label.cmp(&b.label));
    out.dedup_by(|a, b| a.label == b.label);
    out
}

/// Functions and constants, the recipe's functions and variables, module aliases, keywords.
fn words(a: &Analyzer, text: &str, before: &str) -> Vec<CompletionItem> {
    let mut out: Vec<CompletionItem> = Vec::new();
    for o in a.catalogue.iter().filter(|o| o.property.is_none() && o.name.starts_with(|c: char| c.is_alphabetic())) {
        if o.receiver().is_some() && o.ours {
            continue;
        }
        let kind = if o.params.is_empty() && o.name.chars().all(|c| c.is_uppercase() || c == '_') {
            CompletionItemKind::CONSTANT
        } else {
            CompletionItemKind::FUNCTION
        };
        out.push(item(&o.name, kind, Some(o.signature()), Some(&o.doc)));
    }
    for f in functions(text) {
        out.push(item(&f.name, CompletionItemKind::FUNCTION, Some(f.signature(None)), Some(&f.doc)));
    }
    let vars = variables_in_text(&a.catalogue, before);
    for (name, t) in &vars {
        out.push(item(name, CompletionItemKind::VARIABLE, Some(t.clone()), None));
    }
    for imp in imports(text) {
        out.push(item(&imp.alias, CompletionItemKind::MODULE, Some(format!("import \"{}\"", imp.name)), None));
    }
    out.extend(KEYWORDS.iter().map(|k| item(k, CompletionItemKind::KEYWORD, None, None)));
    out.sort_by(|a, b| a.label.cmp(&b.label));
    out.dedup_by(|a, b| a.label == b.label);
    out
}
