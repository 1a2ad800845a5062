//! `blocksmith doc`: the API reference, generated from the engine's own function metadata and
//! the doc comments of the bindings (never a hand-written list).

use std::collections::BTreeMap;

use rhai::Engine;

use crate::catalogue::{self, Overload};

/// Every documented function registered by blocksmith (not Rhai's built-ins), sorted by name
/// then signature, as the catalogue shows them to scripts.
#[must_use]
pub fn functions(engine: &Engine) -> Vec<Overload> {
    catalogue::overloads(engine, false).into_iter().filter(|o| o.ours).collect()
}

/// A doc comment's lines without their `///` or `//!` markers, trimmed.
pub(crate) fn clean_comments(comments: &[&str]) -> String {
    let mut lines = Vec::new();
    for c in comments {
        for line in c.lines() {
            let l = line.trim_start();
            let l = l.strip_prefix("///").or_else(|| l.strip_prefix("//!")).unwrap_or(l);
            lines.push(l.strip_prefix(' ').unwrap_or(l).to_string());
        }
    }
    lines.join("\n").trim().to_string()
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
    if chosen.is_empty() {
        let n = name.unwrap_or_default();
        if let Some(text) = render_type(&all, n) {
            return Ok(text);
        }
        let mut near: Vec<&str> = all
            .iter()
            .map(|f| f.name.as_str())
            .filter(|m| m.contains(n) || n.contains(*m) || crate::param::edit_distance(m, n) <= 2)
            .collect();
        near.dedup();
        let hint = if near.is_empty() { String::new() } else { format!(" (did you mean: {}?)", near.join(", ")) };
        return Err(format!("doc: no function or type named `{n}`{hint}"));
    }
    let mut by_name: BTreeMap<&str, Vec<&Overload>> = BTreeMap::new();
    for f in chosen {
        by_name.entry(f.name.as_str()).or_default().push(f);
    }
    // The whole reference opens with how each kind of value changes.
    let mut out = if name.is_none() { crate::editing::overview() } else { String::new() };
    for (_, overloads) in by_name {
        // Overloads sharing a text are shown together; each different text follows its own.
        let mut groups: Vec<(&str, Vec<String>)> = Vec::new();
        for f in &overloads {
            match groups.iter_mut().find(|(d, _)| *d == f.doc) {
                Some((_, sigs)) => sigs.push(f.signature()),
                None => groups.push((&f.doc, vec![f.signature()])),
            }
        }
        for (doc, sigs) in groups {
            for sig in sigs {
                out.push_str(&format!("{sig}\n"));
            }
            for line in doc.lines() {
                out.push_str(&format!("    {line}\n"));
            }
            out.push('\n');
        }
    }
    Ok(out)
}

/// `doc Mesh`: the methods and properties whose receiver is the type `name`, one line each.
fn render_type(all: &[Overload], name: &str) -> Option<String> {
    let methods: Vec<&Overload> = all.iter().filter(|f| f.receiver() == Some(name)).collect();
    if methods.is_empty() {
        return None;
    }
    let mut out =
        format!("{name}: {} methods and properties (`blocksmith doc NAME` for one in full)\n\n", methods.len());
    if let Some(k) = crate::editing::kind(name) {
        out.push_str(&format!("{}\n\n", k.text));
    }
    let width = methods.iter().map(|f| f.signature().chars().count()).max().unwrap_or(0).min(60);
    for f in methods {
        let first = f.doc.lines().next().unwrap_or_default();
        out.push_str(&format!("{:<width$}  {first}\n", f.signature()));
    }
    Some(out)
}

/// The ```` ```rhai ```` examples of every doc comment, as `(function name, code)`.
#[must_use]
pub fn examples(engine: &Engine) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for f in functions(engine) {
        let mut code: Option<String> = None;
        for line in f.doc.lines() {
            let t = line.trim();
            match &mut code {
                None if t == "```rhai" => code = Some(String::new()),
                Some(c) if t == "```" => {
                    out.push((f.name.clone(), std::mem::take(c)));
                    code = None;
                }
                Some(c) => {
                    c.push_str(line);
                    c.push('\n');
                }
                None => {}
            }
        }
    }
    out.sort();
    out.dedup();
    out
}

/// Every function and type name scripts can use (for completion).
#[must_use]
pub fn names(engine: &Engine) -> Vec<String> {
    let mut v: Vec<String> = functions(engine).into_iter().map(|f| f.name).collect();
    v.sort();
    v.dedup();
    v
}
