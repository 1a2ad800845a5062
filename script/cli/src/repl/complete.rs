//! Tab completion in the REPL: after `x.` the methods and properties of `x`'s type (the
//! session knows its variables' values, and the catalogue the types functions return), after
//! `alias::` the functions and constants of the module imported as `alias`, after `:load ` the
//! script files and folders, after `:` the commands, else every name.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use blocksmith_script::catalogue::{self, Overload};

/// What completion knows about the session, taken after each entry.
#[derive(Debug, Clone, Default)]
pub struct Known {
    /// Function, type, keyword and variable names.
    pub names: Vec<String>,
    /// Each variable's script type (`Mesh`, `array`, `map`, `int`...).
    pub variables: BTreeMap<String, String>,
    /// The keys of the variables that hold object maps.
    pub keys: BTreeMap<String, Vec<String>>,
    /// The names each imported module offers (its functions and constants), by alias.
    pub modules: BTreeMap<String, Vec<String>>,
    /// Where relative `:load` paths start.
    pub dir: PathBuf,
}

/// The REPL's commands, for completion after `:`.
const COMMANDS: [&str; 6] = [":help", ":doc", ":load", ":save", ":show", ":quit"];

/// Where the word being completed starts in `line` and its candidates, for the cursor at `pos`.
#[must_use]
pub fn candidates(known: &Known, catalogue: &[Overload], line: &str, pos: usize) -> (usize, Vec<String>) {
    let before = &line[..pos];
    let trimmed = before.trim_start();
    if let Some(path) = trimmed.strip_prefix(":load ").or_else(|| trimmed.strip_prefix(":l ")) {
        let path = path.trim_start();
        return (pos - path.len(), script_paths(&known.dir, path));
    }
    if trimmed.starts_with(':') && !trimmed.contains(char::is_whitespace) {
        let found = COMMANDS.iter().filter(|c| c.starts_with(trimmed)).map(|c| (*c).to_string()).collect();
        return (pos - trimmed.len(), found);
    }
    let start = before.rfind(|c: char| !(c.is_alphanumeric() || c == '_')).map_or(0, |i| i + 1);
    let word = &before[start..];
    if let Some(path) = before[..start].strip_suffix("::") {
        let alias_start = path.rfind(|c: char| !(c.is_alphanumeric() || c == '_')).map_or(0, |i| i + 1);
        let pool = known.modules.get(&path[alias_start..]).map(Vec::as_slice).unwrap_or_default();
        return (start, pool.iter().filter(|n| n.starts_with(word)).cloned().collect());
    }
    let members = before[..start].strip_suffix('.').map(|receiver| {
        let t = type_of(known, catalogue, receiver);
        let keys = known.keys.get(receiver.trim()).cloned().unwrap_or_default();
        let mut m = t.map(|t| members(catalogue, &t)).unwrap_or_default();
        m.extend(keys);
        m.sort();
        m.dedup();
        m
    });
    let pool = members.as_ref().unwrap_or(&known.names);
    let found =
        pool.iter().filter(|n| n.starts_with(word) && (members.is_some() || !word.is_empty())).cloned().collect();
    (start, found)
}

/// The method and property names callable on a value of script type `t`, blocksmith's and
/// Rhai's own.
#[must_use]
pub fn members(catalogue: &[Overload], t: &str) -> Vec<String> {
    let mut out: Vec<String> = catalogue
        .iter()
        .filter(|o| o.params.first().is_some_and(|(_, pt)| pt == t))
        .filter(|o| o.name.starts_with(|c: char| c.is_alphabetic()) && o.property != Some("set"))
        .map(|o| o.name.clone())
        .collect();
    out.sort();
    out.dedup();
    out
}

/// The script type of the expression `expr` (the text before a `.`), when it can be told
/// without running it: a variable's, or what the function, method or property at its end
/// returns (when all of that name's overloads that fit return one type).
#[must_use]
pub fn type_of(known: &Known, catalogue: &[Overload], expr: &str) -> Option<String> {
    let expr = receiver_text(expr);
    if expr.is_empty() {
        return None;
    }
    if let Some(t) = known.variables.get(expr) {
        return Some(t.clone());
    }
    let (callee, called) = match expr.strip_suffix(')') {
        Some(inner) => (&expr[..matching_open(inner)?], true),
        None => (expr, false),
    };
    let name_start = callee.rfind(|c: char| !(c.is_alphanumeric() || c == '_')).map_or(0, |i| i + 1);
    let name = &callee[name_start..];
    let receiver = callee[..name_start].strip_suffix('.');
    if !called && receiver.is_none() {
        return None;
    }
    let receiver_type = match receiver {
        Some(r) => Some(type_of(known, catalogue, r)?),
        None => None,
    };
    let mut returns = catalogue.iter().filter(|o| {
        o.name == name
            && (o.property == Some("get")) != called
            && receiver_type.as_ref().is_none_or(|t| o.params.first().is_some_and(|(_, pt)| pt == t))
    });
    let first = returns.next()?.returns.clone();
    (returns.all(|o| o.returns == first) && first != "any" && first != "nothing").then_some(first)
}

/// The receiver expression at the end of `text`: identifiers, `.`, `::` and bracketed groups
/// back to the first character that cannot be part of one (`let x = cube(1).` → `cube(1)`).
fn receiver_text(text: &str) -> &str {
    let bytes = text.as_bytes();
    let mut i = text.len();
    while i > 0 {
        let c = bytes[i - 1];
        if c == b')' || c == b']' {
            match matching_open(&text[..i - 1]) {
                Some(open) => i = open,
                None => break,
            }
        } else if c.is_ascii_alphanumeric() || c == b'_' || c == b'.' || c == b':' || c >= 0x80 {
            i -= 1;
        } else {
            break;
        }
    }
    text[i..].trim_start_matches('.')
}

/// Where the bracket opens that closes just after `inner` (the text before a `)` or `]`).
fn matching_open(inner: &str) -> Option<usize> {
    let mut depth = 0i64;
    for (i, c) in inner.char_indices().rev() {
        match c {
            ')' | ']' | '}' => depth += 1,
            '(' | '[' | '{' if depth == 0 => return Some(i),
            '(' | '[' | '{' => depth -= 1,
            _ => {}
        }
    }
    None
}

/// The `.rhai` files and the folders whose path starts with `partial`, relative to `dir`
/// (folders end in `/`; hidden ones only when `partial`'s last part starts with `.`).
#[must_use]
pub fn script_paths(dir: &Path, partial: &str) -> Vec<String> {
    let (folder, prefix) = match partial.rfind('/') {
        Some(i) => (&partial[..=i], &partial[i + 1..]),
        None => ("", partial),
    };
    let base = if Path::new(folder).is_absolute() { PathBuf::from(folder) } else { dir.join(folder) };
    let Ok(entries) = std::fs::read_dir(&base) else { return Vec::new() };
    let mut out: Vec<String> = entries
        .filter_map(Result::ok)
        .filter_map(|e| {
            let name = e.file_name().to_str()?.to_string();
            if !name.starts_with(prefix) || (name.starts_with('.') && !prefix.starts_with('.')) {
                return None;
            }
            let is_dir = e.file_type().ok()?.is_dir() || e.path().is_dir();
            if is_dir {
                Some(format!("{folder}{name}/"))
            } else {
                name.ends_with(".rhai").then(|| format!("{folder}{name}"))
            }
        })
        .collect();
    out.sort();
    out
}

/// The script type name of a value's Rust type name, as the catalogue writes types.
#[must_use]
pub fn script_type_of(engine: &rhai::Engine, value: &rhai::Dynamic) -> String {
    catalogue::script_type(engine.map_type_name(value.type_name()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn known() -> Known {
        let mut k = Known::default();
        k.variables.insert("m".into(), "Mesh".into());
        k.variables.insert("b".into(), "Block".into());
        k.variables.insert("s".into(), "map".into());
        k.keys.insert("s".into(), vec!["blocks".into(), "triangles".into()]);
        k.names = vec!["cube".into(), "cylinder".into(), "m".into()];
        k
    }

    /// The functions of an engine as the REPL makes it.
    fn standard() -> std::rc::Rc<[Overload]> {
        catalogue::of(&blocksmith_script::new_engine(blocksmith_script::EngineOptions::default()))
    }

    #[test]
    fn members_follow_the_receivers_type() {
        let cat = &*standard();
        let k = known();
        let (start, mesh) = candidates(&k, cat, "let v = m.vol", 13);
        assert_eq!((start, mesh), (10, vec!["volume".to_string()]));
        let (_, mesh) = candidates(&k, cat, "m.", 2);
        assert!(mesh.contains(&"catmull_clark".into()) && mesh.contains(&"vertex_count".into()), "{mesh:?}");
        assert!(!mesh.contains(&"sharp_all".into()), "a Block method offered on a Mesh: {mesh:?}");
        let (_, block) = candidates(&k, cat, "b.", 2);
        assert!(block.contains(&"sharp_all".into()) && block.contains(&"subdivide".into()), "{block:?}");
        assert!(!block.contains(&"catmull_clark".into()), "{block:?}");
        // A map's keys come with its methods.
        let (_, map) = candidates(&k, cat, "s.tr", 4);
        assert_eq!(map, ["triangles"]);
        // Unknown receivers give nothing rather than every name.
        assert!(candidates(&k, cat, "nope.", 5).1.is_empty());
        // Plain words complete from every name.
        assert_eq!(candidates(&k, cat, "let c = cy", 10), (8, vec!["cylinder".to_string()]));
    }

    #[test]
    fn types_of_calls_and_chains_come_from_the_catalogue() {
        let cat = &*standard();
        let k = known();
        assert_eq!(type_of(&k, cat, "cube(1)").as_deref(), Some("Mesh"));
        assert_eq!(type_of(&k, cat, "let x = cube(2).translate([1, 0, 0])").as_deref(), Some("Mesh"));
        assert_eq!(type_of(&k, cat, "blocks()").as_deref(), Some("BlockModel"));
        assert_eq!(type_of(&k, cat, "m.vertex_count").as_deref(), Some("int"));
        assert_eq!(type_of(&k, cat, "m").as_deref(), Some("Mesh"));
        assert_eq!(type_of(&k, cat, "nothing_here"), None);
        let (_, after_call) = candidates(&k, cat, "cube(1).catmull_clark_l", 23);
        assert_eq!(after_call, ["catmull_clark_limit", "catmull_clark_limit_normals"]);
    }

    #[test]
    fn module_members_follow_their_alias() {
        let cat = &*standard();
        let mut k = known();
        k.modules.insert("check".into(), vec!["close_to".into(), "closed".into(), "manifold".into()]);
        assert_eq!(candidates(&k, cat, "check::clo", 10), (7, vec!["close_to".to_string(), "closed".to_string()]));
        assert_eq!(candidates(&k, cat, "let ok = check::", 16).1.len(), 3);
        // An alias the session has not imported offers nothing, not every name.
        assert!(candidates(&k, cat, "nope::c", 7).1.is_empty());
    }

    #[test]
    fn load_completes_script_files_and_folders() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("table.rhai"), "cube(1)").unwrap();
        std::fs::write(dir.path().join("tall.txt"), "").unwrap();
        std::fs::create_dir(dir.path().join("tables")).unwrap();
        std::fs::write(dir.path().join("tables").join("legs.rhai"), "").unwrap();
        let k = Known { dir: dir.path().to_path_buf(), ..Known::default() };
        let cat = &*standard();
        assert_eq!(candidates(&k, cat, ":load ta", 8), (6, vec!["table.rhai".to_string(), "tables/".to_string()]));
        assert_eq!(candidates(&k, cat, ":load tables/l", 14), (6, vec!["tables/legs.rhai".to_string()]));
        assert_eq!(candidates(&k, cat, ":lo", 3), (0, vec![":load".to_string()]));
    }
}
