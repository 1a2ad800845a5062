//! `blocksmith doc`: the API reference, generated from the engine's own function metadata and
//! the doc comments of the bindings (never a hand-written list).

pub mod guides;
pub mod html;
pub mod json;
pub mod modules;
pub mod reference;
pub mod topics;
pub mod traps;

use std::collections::BTreeMap;

use rhai::Engine;

use crate::catalogue::{self, Overload};

/// How `blocksmith doc` writes the reference.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Plain text for the terminal.
    Text,
    /// A Markdown page (docs/reference.md is this, for everything).
    Markdown,
    /// A standalone HTML page (docs/reference.html).
    Html,
    /// JSON for editors: every function with all its signatures ([`json`]).
    Json,
}

impl std::str::FromStr for Format {
    type Err = String;
    fn from_str(s: &str) -> Result<Format, String> {
        match s {
            "text" => Ok(Format::Text),
            "markdown" | "md" => Ok(Format::Markdown),
            "html" => Ok(Format::Html),
            "json" => Ok(Format::Json),
            _ => Err(format!("unknown format `{s}`; the formats are text, markdown, html and json")),
        }
    }
}

/// The reference of `name` (a function, a type, an operator, a standard-library module or
/// one of its functions), or of everything when `name` is `None`, written as `format`.
///
/// # Errors
/// Nothing of that name; the message lists near names.
pub fn render_as(engine: &Engine, name: Option<&str>, format: Format) -> Result<String, String> {
    if format == Format::Text {
        return render(engine, name);
    }
    let mut r = reference::Reference::of(engine);
    if let Some(n) = name {
        r = r.select(n).ok_or_else(|| not_found(engine, n))?;
    }
    Ok(match format {
        Format::Json => format!("{:#}\n", json::reference(&r)),
        Format::Html => html::page(&reference::markdown(&r, name.is_none())),
        _ => reference::markdown(&r, name.is_none()),
    })
}

/// Every documented function registered by blocksmith (not Rhai's built-ins), sorted by name
/// then signature, as the catalogue shows them to scripts.
#[must_use]
pub fn functions(engine: &Engine) -> Vec<Overload> {
    catalogue::overloads(engine, false).into_iter().filter(|o| o.ours).collect()
}

/// The reference for `name` (every overload, each group of overloads with its own text), for
/// a type (`doc Mesh`: every method and property taking it as receiver, with the first line of
/// its text), or for everything when `name` is `None`.
///
/// # Errors
/// No function or type of that name; the message lists near names.
pub fn render(engine: &Engine, name: Option<&str>) -> Result<String, String> {
    let all = functions(engine);
    let chosen: Vec<&Overload> = all.iter().filter(|f| name.is_none_or(|n| f.name == n)).collect();
    let module = name.and_then(|n| render_module(engine, n));
    if chosen.is_empty() {
        let n = name.unwrap_or_default();
        if let Some(text) = render_type(&all, n) {
            return Ok(text);
        }
        if let Some(text) = module {
            return Ok(text);
        }
        return render_builtin(engine, n).or_else(|| render_guide(n)).ok_or_else(|| not_found(engine, n));
    }
    let mut by_name: BTreeMap<&str, Vec<&Overload>> = BTreeMap::new();
    for f in chosen {
        by_name.entry(f.name.as_str()).or_default().push(f);
    }
    // The whole reference opens with how each kind of value changes.
    let mut out = if name.is_none() { crate::editing_rules::overview() } else { String::new() };
    if name.is_none() {
        out.push_str(&format!(
            "blocksmith {} script reference: `blocksmith doc NAME` for a function, a type (Mesh) or a \
             standard-library module ({}); --format markdown|html|json for other formats.\n\n",
            env!("CARGO_PKG_VERSION"),
            modules::stdlib(engine).iter().map(|m| m.name.as_str()).collect::<Vec<_>>().join(", ")
        ));
    }
    if name.is_none() {
        // The whole reference in the page's order: topics, operators, types (see `topics`).
        let r = reference::Reference::of(engine);
        let sections = r.sections();
        let mut builtins_done = false;
        for (section, names) in &sections {
            if !builtins_done && *section > reference::Section::Builtins {
                out.push_str(&builtins_text(&r));
                builtins_done = true;
            }
            let title = section.title();
            out.push_str(&format!("== {title} {}\n\n", "=".repeat(60usize.saturating_sub(title.len()))));
            for overloads in names.values() {
                push_overloads(&mut out, overloads);
            }
        }
        if !builtins_done {
            out.push_str(&builtins_text(&r));
        }
        for m in modules::stdlib(engine) {
            out.push_str(&module_text(&m));
        }
        out.push_str(&format!(
            "Guides: `blocksmith doc traps` ({}), {}.\n",
            traps::TITLE,
            guides::TITLES.iter().map(|t| format!("`blocksmith doc \"{t}\"`")).collect::<Vec<_>>().join(", ")
        ));
    } else {
        for overloads in by_name.values() {
            push_overloads(&mut out, overloads);
        }
    }
    // A module may share its name with a function (`check`): both are shown.
    out.push_str(&module.unwrap_or_default());
    Ok(out)
}

/// Overloads sharing a text shown together; each different text follows its own.
fn push_overloads(out: &mut String, overloads: &[&Overload]) {
    let mut groups: Vec<(&str, Vec<String>)> = Vec::new();
    for f in overloads {
        match groups.iter_mut().find(|(d, _)| *d == f.doc) {
            Some((_, sigs)) => sigs.push(f.signature()),
            None => groups.push((&f.doc, vec![f.signature()])),
        }
    }
    for (doc, sigs) in groups {
        for sig in sigs {
            out.push_str(&format!("{sig}\n"));
        }
        push_indented(out, doc);
    }
}

/// Rhai's everyday built-ins in the terminal: each group's note, then one line a function.
fn builtins_text(r: &reference::Reference) -> String {
    let title = reference::Section::Builtins.title();
    let mut out = format!("== {title} {}\n\n", "=".repeat(60usize.saturating_sub(title.len())));
    for g in topics::BUILTINS {
        out.push_str(&format!("{}\n", g.title));
        push_indented(&mut out, g.note);
        for (name, note) in g.names {
            let sigs: Vec<String> = r.builtins.iter().filter(|f| f.name == *name).map(Overload::signature).collect();
            if let Some(first) = sigs.first() {
                let more = if sigs.len() > 1 { format!(" (+{} more)", sigs.len() - 1) } else { String::new() };
                out.push_str(&format!(
                    "  {first}{more}{}\n",
                    if note.is_empty() { String::new() } else { format!("  — {note}") }
                ));
            }
        }
        out.push('\n');
    }
    out
}

/// `doc sin`: one of Rhai's everyday built-ins ([`topics::BUILTINS`]): its signatures, the
/// engine's text for it and blocksmith's note (units, traps).
fn render_builtin(engine: &Engine, name: &str) -> Option<String> {
    let all = reference::builtins(engine);
    let found: Vec<&Overload> = all.iter().filter(|f| f.name == name).collect();
    if found.is_empty() {
        return None;
    }
    let mut out = String::new();
    for f in &found {
        out.push_str(&format!("{}\n", f.signature()));
    }
    let text = found.iter().find(|f| !f.doc.is_empty()).map_or("", |f| f.doc.as_str());
    let note = topics::BUILTINS.iter().flat_map(|g| g.names).find(|(n, _)| *n == name).map_or("", |(_, note)| note);
    let first = text.split("\n\n").next().unwrap_or_default().trim();
    push_indented(
        &mut out,
        &format!("{first}\n\n{note}\n\n(Rhai's own function; `blocksmith doc` lists the everyday ones.)"),
    );
    Some(out)
}

/// `doc "block faces"`, `doc traps`: a guide of the reference, by a prefix of its heading.
fn render_guide(name: &str) -> Option<String> {
    let t = name.to_lowercase();
    if t == "traps" || (t.len() >= 4 && traps::TITLE.to_lowercase().starts_with(&t)) {
        return Some(traps::markdown());
    }
    guides::text(name)
}

/// `text` indented by four spaces, then a blank line.
fn push_indented(out: &mut String, text: &str) {
    for line in text.lines() {
        if line.is_empty() {
            out.push('\n');
        } else {
            out.push_str(&format!("    {line}\n"));
        }
    }
    out.push('\n');
}

/// `doc check` (a standard-library module: its header and every function in full) or `doc
/// check::solid` (one of its functions).
fn render_module(engine: &Engine, name: &str) -> Option<String> {
    let all = modules::stdlib(engine);
    if let Some(m) = all.iter().find(|m| m.name == name) {
        return Some(module_text(m));
    }
    let f = all.iter().flat_map(|m| &m.functions).filter(|f| f.path() == name).collect::<Vec<_>>();
    if f.is_empty() {
        return None;
    }
    let mut out = String::new();
    for f in f {
        out.push_str(&format!("{}\n", f.signature()));
        push_indented(&mut out, &f.doc);
    }
    Some(out)
}

/// A module's header (indented) and its functions in full.
fn module_text(m: &modules::Module) -> String {
    let mut out = format!("module {} (import \"{}\" as {};)\n", m.name, m.name, m.name);
    push_indented(&mut out, &m.doc);
    for f in &m.functions {
        out.push_str(&format!("{}\n", f.signature()));
        push_indented(&mut out, &f.doc);
    }
    out
}

/// Every name `blocksmith doc` knows: functions, types, modules and their functions.
fn known_names(engine: &Engine) -> Vec<String> {
    let all = functions(engine);
    let mut names: Vec<String> = all.iter().map(|f| f.name.clone()).collect();
    names.extend(all.iter().filter_map(Overload::receiver).map(str::to_string));
    for m in modules::stdlib(engine) {
        names.extend(m.functions.iter().map(modules::ModuleFn::path));
        names.push(m.name);
    }
    names.sort();
    names.dedup();
    names
}

/// The error for a name `doc` does not know, with the near names (by edit distance, or
/// containing one another).
fn not_found(engine: &Engine, n: &str) -> String {
    let lower = n.to_lowercase();
    let near: Vec<String> = known_names(engine)
        .into_iter()
        .filter(|m| {
            let m = m.to_lowercase();
            (m.len() > 2 && lower.len() > 2 && (m.contains(&lower) || lower.contains(&m)))
                || crate::spelling::edit_distance(&m, &lower) <= 2.max(lower.len() / 4)
        })
        .collect();
    let hint = if near.is_empty() { String::new() } else { format!(" (did you mean: {}?)", near.join(", ")) };
    format!("doc: no function, type or module named `{n}`{hint}")
}

/// `doc Mesh`: the methods and properties whose receiver is the type `name`, one line each.
fn render_type(all: &[Overload], name: &str) -> Option<String> {
    let methods: Vec<&Overload> = all.iter().filter(|f| f.receiver() == Some(name)).collect();
    if methods.is_empty() {
        return None;
    }
    let mut out =
        format!("{name}: {} methods and properties (`blocksmith doc NAME` for one in full)\n\n", methods.len());
    if let Some(k) = crate::editing_rules::kind(name) {
        out.push_str(&format!("{}\n\n", k.text));
    }
    let width = methods.iter().map(|f| f.signature().chars().count()).max().unwrap_or(0).min(60);
    for f in methods {
        let first = f.doc.lines().next().unwrap_or_default();
        out.push_str(&format!("{:<width$}  {first}\n", f.signature()));
    }
    Some(out)
}

/// The ```` ```rhai ```` examples of every doc comment, functions' and standard-library
/// modules' (named `module::function`), as `(function name, code)`.
#[must_use]
pub fn examples(engine: &Engine) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for f in functions(engine) {
        out.extend(examples_in(&f.doc).into_iter().map(|code| (f.name.clone(), code)));
    }
    for f in modules::stdlib(engine).iter().flat_map(|m| &m.functions) {
        out.extend(examples_in(&f.doc).into_iter().map(|code| (f.path(), code)));
    }
    out.sort();
    out.dedup();
    out
}

/// The code of each ```` ```rhai ```` block in a doc text.
#[must_use]
pub fn examples_in(doc: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut code: Option<String> = None;
    for line in doc.lines() {
        let t = line.trim();
        match &mut code {
            None if t == "```rhai" => code = Some(String::new()),
            Some(c) if t == "```" => {
                out.push(std::mem::take(c));
                code = None;
            }
            Some(c) => {
                c.push_str(line);
                c.push('\n');
            }
            None => {}
        }
    }
    out
}

/// The names (functions, properties, operators, `module::function`s) none of whose
/// overloads' doc comments has a ```` ```rhai ```` example.
#[must_use]
pub fn without_example(engine: &Engine) -> Vec<String> {
    let mut with: BTreeMap<String, bool> = BTreeMap::new();
    for f in functions(engine) {
        *with.entry(f.name.clone()).or_default() |= !examples_in(&f.doc).is_empty();
    }
    for f in modules::stdlib(engine).iter().flat_map(|m| &m.functions) {
        *with.entry(f.path()).or_default() |= !examples_in(&f.doc).is_empty();
    }
    with.into_iter().filter(|(_, has)| !has).map(|(n, _)| n).collect()
}

/// Every function and type name scripts can use (for completion).
#[must_use]
pub fn names(engine: &Engine) -> Vec<String> {
    let mut v: Vec<String> = functions(engine).into_iter().map(|f| f.name).collect();
    v.sort();
    v.dedup();
    v
}
