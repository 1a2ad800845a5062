//! Every function scripts can call, as scripts see it: name, parameters with their script
//! types, return type and doc comment, from the engine's own metadata. The reference
//! (`blocksmith doc`), error explanations and completion read it.

use std::cell::OnceCell;
use std::rc::Rc;

use rhai::Engine;
use serde_json::Value;

/// One overload of a function.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Overload {
    /// The script name (a property `x` for the getter `get$x`).
    pub name: String,
    /// `Some("get")` / `Some("set")` for a property's getter or setter.
    pub property: Option<&'static str>,
    /// Parameters: name and script type (`int`, `float`, `Mesh`, `any`...).
    pub params: Vec<(String, String)>,
    /// The script type returned (`nothing` for none).
    pub returns: String,
    /// The doc comment, without the `///` markers.
    pub doc: String,
    /// Registered by blocksmith (not one of Rhai's built-ins).
    pub ours: bool,
    /// The reference topic its doc comment names on a line `Topic: KEY` (a line kept out of
    /// [`Overload::doc`]); see [`crate::doc::topics`].
    pub topic: Option<String>,
}

impl Overload {
    /// `name(a: int, b: float) -> Mesh`; a method shows its receiver as the first parameter.
    #[must_use]
    pub fn signature(&self) -> String {
        let params: Vec<String> = self.params.iter().map(|(n, t)| format!("{n}: {t}")).collect();
        let ret = if self.returns == "nothing" { String::new() } else { format!(" -> {}", self.returns) };
        match self.property {
            Some(kind) => format!("{kind} {}({}){ret}", self.name, params.join(", ")),
            None => format!("{}({}){ret}", self.name, params.join(", ")),
        }
    }

    /// The type of the receiver when the overload can be called as a method on a value of a
    /// script API type (`Mesh`, `Block`...).
    #[must_use]
    pub fn receiver(&self) -> Option<&str> {
        let t = self.params.first()?.1.as_str();
        is_api_type(t).then_some(t)
    }
}

/// Whether `t` is one of the script API's own types (capitalised: `Mesh`, `Vec3`...).
#[must_use]
pub fn is_api_type(t: &str) -> bool {
    t.chars().next().is_some_and(char::is_uppercase)
}

/// A Rust type as the metadata writes it, as scripts see it: `&mut SharedMesh` → `Mesh`,
/// `INT` → `int`, `Dynamic` → `any`...
#[must_use]
pub fn script_type(rust: &str) -> String {
    let t = rust.trim().trim_start_matches("&mut ").trim_start_matches('&').trim();
    let t = t.strip_prefix("ScriptResult<").and_then(|s| s.strip_suffix('>')).unwrap_or(t);
    let t = t.strip_prefix("RhaiResultOf<").and_then(|s| s.strip_suffix('>')).unwrap_or(t);
    // `core::result::Result<T, Box<EvalAltResult>>` (a closure registered by type): its `T`.
    let t = match t.find("Result<") {
        Some(i) if !t[..i].contains('<') => t[i + "Result<".len()..].split(',').next().unwrap_or(t).trim(),
        _ => t,
    };
    let t = t.rsplit("::").next().unwrap_or(t);
    match t {
        "SharedMesh" => "Mesh",
        "ImmutableString" | "str" | "String" | "string" | "&str | ImmutableString | String" => "string",
        "i64" | "INT" | "i32" | "u64" | "usize" => "int",
        "f64" | "FLOAT" | "f32" => "float",
        // The binding's argument kinds (`convert::Number`...), each a `Dynamic` it reads itself.
        "Number" => "number",
        "Integer" => "int",
        "Vector" => "Vec3",
        "Point2" => "[x, y]",
        "NumberOrPoint2" => "number|[x, y]",
        "NumberOrVector" => "number|Vec3",
        "Solid" => "Mesh|BlockModel",
        "Color" => "[r, g, b, a]|string",
        "ColorOrUnit" => "[r, g, b, a]|()",
        "Dynamic" | "?" | "" => "any",
        "Array" | "array" | "Vec<Dynamic>" => "array",
        "Map" | "map" => "map",
        "FnPtr" | "Fn" => "closure",
        "()" => "nothing",
        "char" => "char",
        "bool" => "bool",
        other => other,
    }
    .to_string()
}

/// A script type with its article, for sentences: `an integer`, `a float`, `an array`, `a Mesh`.
#[must_use]
pub fn a(script_type: &str) -> String {
    match script_type {
        "int" => "an integer".into(),
        "float" => "a float".into(),
        "string" => "a string".into(),
        "array" => "an array".into(),
        "map" => "an object map".into(),
        "closure" => "a closure".into(),
        "nothing" => "nothing".into(),
        "number" => "a number".into(),
        "number|Vec3" => "a number or a Vec3".into(),
        "Mesh|BlockModel" => "a Mesh or a BlockModel".into(),
        "[r, g, b, a]|string" => "a colour [r, g, b(, a)] (0 to 1) or \"#rrggbb\"".into(),
        "[r, g, b, a]|()" => "a colour [r, g, b, a] or ()".into(),
        "[x, y]" => "a point [x, y]".into(),
        "number|[x, y]" => "a number or a point [x, y]".into(),
        "any" => "any value".into(),
        "bool" => "a bool".into(),
        "char" => "a character".into(),
        t if t.starts_with(['A', 'E', 'I', 'O', 'U', 'a', 'e', 'i', 'o', 'u']) => format!("an {t}"),
        t => format!("a {t}"),
    }
}

/// The ways to get a `to` from a `from`: its methods returning one, fewest arguments (then
/// shortest names) first,
/// as a script writes them (`.to_mesh()`, `.pose(…)`).
#[must_use]
pub fn conversions(all: &[Overload], from: &str, to: &str) -> Vec<String> {
    let mut found: Vec<&Overload> =
        all.iter().filter(|o| o.property.is_none() && o.receiver() == Some(from) && o.returns == to).collect();
    found.sort_by_key(|o| (o.params.len(), o.name.len()));
    let mut out: Vec<String> = Vec::new();
    for o in found {
        let shown = format!("`.{}({})`", o.name, if o.params.len() > 1 { "…" } else { "" });
        if !out.iter().any(|s| s.starts_with(&format!("`.{}(", o.name))) {
            out.push(shown);
        }
    }
    out
}

fn overloads_of(engine: &Engine, include_builtins: bool) -> Vec<Overload> {
    let json = engine.gen_fn_metadata_to_json(include_builtins).unwrap_or_default();
    let root: Value = serde_json::from_str(&json).unwrap_or(Value::Null);
    let mut out = Vec::new();
    for f in root.get("functions").and_then(Value::as_array).into_iter().flatten() {
        let raw = f.get("name").and_then(Value::as_str).unwrap_or_default();
        let (name, property) = match (raw.strip_prefix("get$"), raw.strip_prefix("set$")) {
            (Some(n), _) => (n, Some("get")),
            (_, Some(n)) => (n, Some("set")),
            _ => (raw, None),
        };
        if f.get("isAnonymous").and_then(Value::as_bool) == Some(true) {
            continue;
        }
        let params: Vec<(String, String)> = f
            .get("params")
            .and_then(Value::as_array)
            .into_iter()
            .flatten()
            .filter(|p| p.get("type").and_then(Value::as_str) != Some("NativeCallContext"))
            .enumerate()
            .map(|(i, p)| {
                let n = p.get("name").and_then(Value::as_str).map_or_else(|| format!("arg{}", i + 1), str::to_string);
                // A name that clashes with a Rust keyword or a helper keeps a trailing `_`.
                (n.trim_end_matches('_').to_string(), script_type(p.get("type").and_then(Value::as_str).unwrap_or("")))
            })
            .collect();
        let returns = script_type(f.get("returnType").and_then(Value::as_str).unwrap_or("()"));
        let comments: Vec<&str> =
            f.get("docComments").and_then(Value::as_array).into_iter().flatten().filter_map(Value::as_str).collect();
        let (doc, topic) = crate::doc::topics::split_tag(&clean_comments(&comments));
        out.push(Overload { name: name.to_string(), property, params, returns, doc, ours: false, topic });
    }
    out
}

/// The functions of `engine`: blocksmith's (documented, `ours`) and, when `include_builtins`,
/// Rhai's own too; sorted by name, then signature.
#[must_use]
pub fn overloads(engine: &Engine, include_builtins: bool) -> Vec<Overload> {
    let mut ours = overloads_of(engine, false);
    for o in &mut ours {
        o.ours = !o.doc.is_empty();
    }
    if include_builtins {
        let known: std::collections::HashSet<String> = ours.iter().map(Overload::signature).collect();
        ours.extend(overloads_of(engine, true).into_iter().filter(|o| !known.contains(&o.signature())));
    }
    ours.sort_by_key(|o| (o.name.clone(), o.signature()));
    ours.dedup();
    ours
}

/// The catalogue of `engine`: every registered function and Rhai's built-ins. An engine made
/// by [`crate::new_engine`] reads its metadata once and keeps the catalogue in its
/// [`crate::RunContext`] ([`Kept`]); any other engine is read at each call. No engine is ever
/// built to answer: the catalogue is the asking engine's own.
#[must_use]
pub fn of(engine: &Engine) -> Rc<[Overload]> {
    match engine.default_tag().clone().try_cast::<Rc<crate::RunContext>>() {
        Some(context) => context.catalogue.get(engine),
        None => overloads(engine, true).into(),
    }
}

/// A catalogue read once and kept (see [`of`]). Cloning shares it.
#[derive(Clone, Default)]
pub struct Kept(Rc<OnceCell<Rc<[Overload]>>>);

impl Kept {
    /// The kept catalogue, read from `engine` the first time.
    #[must_use]
    pub fn get(&self, engine: &Engine) -> Rc<[Overload]> {
        Rc::clone(self.0.get_or_init(|| overloads(engine, true).into()))
    }
}

impl std::fmt::Debug for Kept {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(if self.0.get().is_some() { "Kept(read)" } else { "Kept(unread)" })
    }
}

/// A doc comment's lines without their `///` or `//!` markers, trimmed.
#[must_use]
pub fn clean_comments(comments: &[&str]) -> String {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signatures_read_as_scripts_see_them() {
        let all = &*of(&crate::new_engine(crate::EngineOptions::default()));
        let sig = |name: &str| -> Vec<String> {
            all.iter().filter(|o| o.name == name && o.ours).map(Overload::signature).collect()
        };
        // No leaked Rust names: a context parameter, `segments_`, `SharedMesh`, `()`.
        assert_eq!(sig("cylinder")[0], "cylinder(radius: number, height: number, segments: int) -> Mesh");
        // Arguments the binding reads itself say what they take, not `any`.
        assert!(
            sig("scale").contains(&"scale(m: Mesh, factor: number|Vec3) -> Mesh".to_string()),
            "{:?}",
            sig("scale")
        );
        assert!(
            sig("translate").contains(&"translate(m: Mesh, offset: Vec3) -> Mesh".to_string()),
            "{:?}",
            sig("translate")
        );
        assert_eq!(sig("union")[0], "union(a: Mesh|BlockModel, b: Mesh|BlockModel) -> Mesh");
        for want in [
            "color(m: Mesh, c: [r, g, b, a]|string) -> Mesh",
            "color(b: Block, c: [r, g, b, a]|string) -> Block",
            "color(pm: PolarMesh, c: [r, g, b, a]|string, faces: array) -> PolarMesh",
        ] {
            assert!(sig("color").contains(&want.to_string()), "{want}: {:?}", sig("color"));
        }
        assert_eq!(sig("face_color")[0], "face_color(m: Mesh, f: int) -> [r, g, b, a]|()");
        assert_eq!(sig("limit_eval")[0], "limit_eval(m: Mesh, face: int, u: number, v: number) -> map");
        // Operators registered from closures show the value they return, not `Result<..>`'s tail.
        assert!(all.iter().any(|o| o.name == "+" && o.signature() == "+(a: Mesh, b: Mesh) -> Mesh"));
        // `any` only where any value is taken or given.
        let any: Vec<String> = all
            .iter()
            .filter(|o| o.ours && (o.signature().contains(": any") || o.signature().ends_with("-> any")))
            .map(Overload::signature)
            .collect();
        assert!(
            any.iter().all(|s| [
                "assert_eq(",
                "show(",
                "param(",
                "parent(",
                "pad(",
                "push(",
                "+=(array",
                "hull(items",
                "load(path",
                "choice(r: Rng"
            ]
            .iter()
            .any(|n| s.starts_with(n))),
            "{any:?}"
        );
        // Rhai's built-ins are there too (for suggestions), not marked as ours.
        assert!(all.iter().any(|o| o.name == "len" && !o.ours));
        assert_eq!(conversions(all, "PolarMesh", "Mesh")[0], "`.to_mesh()`");
        assert_eq!(conversions(all, "Voxels", "Mesh"), ["`.to_mesh()`"]);
        assert_eq!(conversions(all, "Animation", "Mesh"), ["`.pose(…)`"]);
        assert_eq!(a("int"), "an integer");
        assert_eq!(a("array"), "an array");
        assert_eq!(a("Animation"), "an Animation");
        assert_eq!(script_type("ScriptResult<SharedMesh>"), "Mesh");
    }
}
