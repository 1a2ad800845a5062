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
///       "returns": "Mesh", "doc": "...", "examples": ["..."] } ] } ],
///   "modules": [ { "name": "check", "import": "import \"check\" as check;", "doc": "...",
///       "functions": [ { "name": "check::solid", "signature": "check::solid(m, genus)",
///         "params": [ { "name": "m", "type": "any" } ], "doc": "...", "examples": [] } ] } ] }
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
    json!({ "version": env!("CARGO_PKG_VERSION"), "functions": functions, "modules": modules })
}

/// One overload's object.
fn overload(f: &Overload) -> Value {
    let kind = match (Section::of(f), f.property) {
        (Section::Operators, _) => "operator",
        (_, Some(_)) => "property",
        (Section::Type(_), None) => "method",
        (Section::Functions, None) => "function",
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
    })
}
