//! `blocksmith doc --format json`: the reference for editors. Every function by name with all
//! its overloads (signature, kind, receiver, parameters with their script types, return type,
//! doc text and examples), then the standard library's modules.

use serde_json::{json, Value};

use super::reference::{Reference, Section};
use crate::catalogue::Overload;

/// The JSON of `r`:
///
/// ```text
/// { "version": "0.1.0",
///   "functions": [ { "name": "cube", "overloads": [ { "signature": "cube(size: any) -> Mesh",
///       "kind": "function" | "method" | "property" | "operator", "property": null | "get" | "set",
///       "receiver": null | "Mesh", "params": [ { "name": "size", "type": "any" } ],
///       "returns": "Mesh", "doc": "...", "examples": ["..."],
///       "topic": null | "primitives", "section": "Primitives" } ] } ],
///   "modules": [ { "name": "check", "import": "import \"check\" as check;", "doc": "...",
///       "functions": [ { "name": "check::solid", "signature": "check::solid(m, genus)",
///         "params": [ { "name": "m", "type": "any" } ], "doc": "...", "examples": [] } ] } ],
///   "builtins": [ { "name": "sin", "signature": "sin(x: float) -> float", "params": [...],
///       "returns": "float", "doc": "..." } ] }
/// ```
#[must_use]
pub fn reference(r: &Reference) -> Value {
    let mut functions: Vec<Value> = Vec::new();
    let mut current: Option<(&str, Vec<Value>)> = None;
    for f in &r.functions {
        match &mut current {
            Some((name, overloads)) if *name == f.name => overloads.push(overload(f)),
            _ => {
                if let Some((name, overloads)) = current.take() {
                    functions.push(json!({ "name": name, "overloads": overloads }));
                }
                current = Some((&f.name, vec![overload(f)]));
            }
        }
    }
    if let Some((name, overloads)) = current {
        functions.push(json!({ "name": name, "overloads": overloads }));
    }
    let modules: Vec<Value> = r
        .modules
        .iter()
        .map(|m| {
            let fns: Vec<Value> = m
                .functions
                .iter()
                .map(|f| {
                    json!({
                        "name": f.path(),
                        "signature": f.signature(),
                        "params": f.params.iter().map(|p| json!({ "name": p, "type": "any" })).collect::<Vec<_>>(),
                        "doc": f.doc,
                        "examples": super::examples_in(&f.doc),
                    })
                })
                .collect();
            json!({
                "name": m.name,
                "import": format!("import \"{}\" as {};", m.name, m.name),
                "doc": m.doc,
                "functions": fns,
            })
        })
        .collect();
    let builtins: Vec<Value> = r
        .builtins
        .iter()
        .map(|f| {
            json!({
                "name": f.name,
                "signature": f.signature(),
                "params": f.params.iter().map(|(n, t)| json!({ "name": n, "type": t })).collect::<Vec<_>>(),
                "returns": f.returns,
                "doc": f.doc,
            })
        })
        .collect();
    json!({ "version": env!("CARGO_PKG_VERSION"), "functions": functions, "modules": modules, "builtins": builtins })
}

/// One overload's object.
fn overload(f: &Overload) -> Value {
    // `kind` keeps its first meaning (by the first parameter's type), whatever the topic.
    let operator = !f.name.starts_with(|c: char| c.is_alphabetic() || c == '_');
    let kind = match (operator, f.property, f.receiver()) {
        (true, _, _) => "operator",
        (_, Some(_), _) => "property",
        (_, None, Some(_)) => "method",
        (_, None, None) => "function",
    };
    json!({
        "signature": f.signature(),
        "kind": kind,
        "property": f.property,
        "receiver": f.receiver(),
        "params": f.params.iter().map(|(n, t)| json!({ "name": n, "type": t })).collect::<Vec<_>>(),
        "returns": f.returns,
        "doc": f.doc,
        "examples": super::examples_in(&f.doc),
        "topic": f.topic,
        "section": Section::of(f).title(),
    })
}
