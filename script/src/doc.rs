//! `blocksmith doc`: the API reference, generated from the engine's own function metadata and
//! the doc comments of the bindings (never a hand-written list).

use std::collections::BTreeMap;

use rhai::Engine;
use serde_json::Value;

/// One documented function overload.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FnDoc {
    /// The script name (`x` for the getter `get$x`).
    pub name: String,
    /// The signature as scripts see it.
    pub signature: String,
    /// The doc comment, without the `///` markers.
    pub doc: String,
}

/// Every function registered by blocksmith (not Rhai's built-ins), sorted by name then signature.
#[must_use]
pub fn functions(engine: &Engine) -> Vec<FnDoc> {
    let json = engine.gen_fn_metadata_to_json(false).unwrap_or_default();
    let root: Value = serde_json::from_str(&json).unwrap_or(Value::Null);
    let mut out = Vec::new();
    for f in root.get("functions").and_then(Value::as_array).into_iter().flatten() {
        let raw_name = f.get("name").and_then(Value::as_str).unwrap_or_default();
        let comments: Vec<&str> =
            f.get("docComments").and_then(Value::as_array).into_iter().flatten().filter_map(Value::as_str).collect();
        if comments.is_empty() {
            continue;
        }
        let name = raw_name.trim_start_matches("get$").trim_start_matches("set$").to_string();
        let signature = f.get("signature").and_then(Value::as_str).unwrap_or(raw_name).to_string();
        let signature = script_signature(&signature.replace("get$", "get ").replace("set$", "set "));
        out.push(FnDoc { name, signature, doc: clean_comments(&comments) });
    }
    out.sort_by(|a, b| (&a.name, &a.signature).cmp(&(&b.name, &b.signature)));
    out
}

/// A Rust signature as scripts see it: `ScriptResult<SharedMesh>` → `Mesh`, `f64` → `float`,
/// `blocksmith_kernel::Vec3` → `Vec3`, a parameter `segments_` → `segments`; a function without
/// parameters keeps its `()` and one that returns nothing shows no arrow.
fn script_signature(rust: &str) -> String {
    let mut s = rust.replace("ctx: NativeCallContext, ", "").replace("ctx: NativeCallContext", "").replace("&mut ", "");
    if let Some(i) = s.find("ScriptResult<") {
        if s.ends_with('>') {
            s = format!("{}{}", &s[..i], &s[i + "ScriptResult<".len()..s.len() - 1]);
        }
    }
    if let Some(stripped) = s.strip_suffix(" -> ()") {
        s = stripped.to_string();
    }
    for (from, to) in [
        ("SharedMesh", "Mesh"),
        ("ImmutableString", "string"),
        ("&str", "string"),
        ("String", "string"),
        ("i64", "int"),
        ("INT", "int"),
        ("f64", "float"),
        ("Dynamic", "any"),
        ("Array", "array"),
        ("Map", "map"),
        ("FnPtr", "closure"),
        (": ()", ": nothing"),
    ] {
        s = s.replace(from, to);
    }
    without_paths(&without_trailing_underscores(&s))
}

/// `a::b::Vec3` → `Vec3`: scripts never see Rust module paths.
fn without_paths(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut word = String::new();
    let mut chars = s.chars().peekable();
    while let Some(c) = chars.next() {
        if c.is_alphanumeric() || c == '_' {
            word.push(c);
        } else if c == ':' && chars.peek() == Some(&':') {
            chars.next();
            word.clear();
        } else {
            out.push_str(&word);
            word.clear();
            out.push(c);
        }
    }
    out.push_str(&word);
    out
}

/// Parameter names written `segments_` in Rust (to avoid a clash) read `segments` in scripts.
fn without_trailing_underscores(s: &str) -> String {
    s.replace("_:", ":")
}

/// The type of a signature's first parameter (the receiver of a method call), if any.
fn receiver_type(signature: &str) -> Option<&str> {
    let open = signature.find('(')?;
    let params = &signature[open + 1..];
    let first = params.split([',', ')']).next()?.trim();
    let (_, ty) = first.split_once(": ")?;
    Some(ty.trim())
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
    let chosen: Vec<&FnDoc> = all.iter().filter(|f| name.is_none_or(|n| f.name == n)).collect();
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
    let mut by_name: BTreeMap<&str, Vec<&FnDoc>> = BTreeMap::new();
    for f in chosen {
        by_name.entry(f.name.as_str()).or_default().push(f);
    }
    let mut out = String::new();
    for (_, overloads) in by_name {
        // Overloads sharing a text are shown together; each different text follows its own.
        let mut groups: Vec<(&str, Vec<&str>)> = Vec::new();
        for f in &overloads {
            match groups.iter_mut().find(|(d, _)| *d == f.doc) {
                Some((_, sigs)) => sigs.push(&f.signature),
                None => groups.push((&f.doc, vec![&f.signature])),
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
fn render_type(all: &[FnDoc], name: &str) -> Option<String> {
    let methods: Vec<&FnDoc> = all.iter().filter(|f| receiver_type(&f.signature) == Some(name)).collect();
    if methods.is_empty() {
        return None;
    }
    let mut out =
        format!("{name}: {} methods and properties (`blocksmith doc NAME` for one in full)\n\n", methods.len());
    let width = methods.iter().map(|f| f.signature.chars().count()).max().unwrap_or(0).min(60);
    let mut seen = std::collections::BTreeSet::new();
    for f in methods {
        if !seen.insert((&f.name, &f.signature)) {
            continue;
        }
        let first = f.doc.lines().next().unwrap_or_default();
        out.push_str(&format!("{:<width$}  {first}\n", f.signature));
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
