//! The option-map keys of each function that takes one, asked of the function itself: each
//! overload whose last parameter is a map is called once, on small sample arguments of its
//! parameters' types, with a key no function knows; the binding's own check refuses it and
//! names the valid keys (`unknown option `…`; valid options are: …`). So the keys come from
//! the same list the run checks against, never a second one. Functions that read or write
//! files are not asked.

use std::collections::HashMap;

use blocksmith_script::catalogue::Overload;
use lsp_types::{CompletionItem, CompletionItemKind};

use crate::text::{blank_strings_and_comments, enclosing_call, is_ident};
use crate::Analyzer;

/// The key no function knows.
const PROBE: &str = "blocksmith_lsp_probe";

/// A small value of each script type, as script text.
fn sample(t: &str) -> Option<&'static str> {
    Some(match t {
        "int" => "1",
        "float" => "1.0",
        "number" | "number|Vec3" | "number|[x, y]" | "any" => "1",
        "Vec3" => "[0.0, 0.0, 1.0]",
        "[x, y]" => "[0.0, 0.0]",
        "array" => "[]",
        "string" => "\"x\"",
        "bool" => "true",
        "map" => "#{}",
        "closure" => "|x| x",
        "Mesh" | "Mesh|BlockModel" => "cube(1)",
        "Profile" => "rect([0, 0], [1, 1])",
        "PolarMesh" => "polar_octahedron()",
        "Voxels" => "voxels(8)",
        "Block" => "block([0, 0, 0], [1, 1, 1])",
        "BlockModel" => "blocks()",
        "LSystem" => "lsystem(#{ axiom: \"F\", rules: #{} })",
        "Animation" => "animation(polar_octahedron())",
        "Rng" => "rng(1)",
        _ => return None,
    })
}

/// The valid keys of each function name (all its overloads that take a map agree to be asked;
/// a name any of whose overloads could not be asked is left out), sorted.
#[must_use]
pub fn probe(catalogue: &[Overload]) -> HashMap<String, Vec<String>> {
    // An engine of its own whose prints go nowhere (a server's standard output is the protocol).
    let mut engine = blocksmith_script::new_engine(blocksmith_script::EngineOptions::default());
    engine.on_print(|_| {});
    engine.on_debug(|_, _, _| {});
    let mut found: HashMap<String, Option<Vec<String>>> = HashMap::new();
    for o in catalogue.iter().filter(|o| o.ours && o.property.is_none()) {
        if o.params.last().is_none_or(|(_, t)| t != "map")
            || !o.name.starts_with(|c: char| c.is_alphabetic())
            || ["save", "load", "param", "show"].contains(&o.name.as_str())
        {
            continue;
        }
        let args: Option<Vec<&str>> = o.params[..o.params.len() - 1].iter().map(|(_, t)| sample(t)).collect();
        let keys = args.and_then(|args| {
            let mut call = format!("{}(", o.name);
            for a in args {
                call.push_str(a);
                call.push_str(", ");
            }
            call.push_str(&format!("#{{ {PROBE}: 0 }})"));
            let err = engine.eval::<rhai::Dynamic>(&call).err()?;
            let text = err.to_string();
            let i = text.find(&format!("`{PROBE}`"))?;
            let list = &text[i..];
            let list = &list[list.find(" are: ")? + 6..];
            let end = list.find([' ', '(', '\n']).map_or(list.len(), |e| e);
            let list = list[..end.max(list.find(" (").unwrap_or(0))].trim_end_matches(['.', ')']);
            Some(list.split(", ").map(|k| k.trim().to_string()).filter(|k| !k.is_empty()).collect::<Vec<_>>())
        });
        let entry = found.entry(o.name.clone()).or_insert_with(|| Some(Vec::new()));
        match (entry.as_mut(), keys) {
            (Some(all), Some(keys)) => all.extend(keys),
            _ => *entry = None,
        }
    }
    found
        .into_iter()
        .filter_map(|(name, keys)| {
            let mut keys = keys?;
            keys.sort();
            keys.dedup();
            Some((name, keys))
        })
        .collect()
}

/// The keys to offer when the cursor at byte `offset` of `text` is where a key goes in a
/// `#{ … }` passed to a function whose keys are known; `None` elsewhere.
#[must_use]
pub fn keys_at(a: &Analyzer, text: &str, offset: usize) -> Option<Vec<CompletionItem>> {
    let code = blank_strings_and_comments(&text[..offset.min(text.len())]);
    // The map the cursor is in: the nearest unclosed `#{`.
    let mut depth = 0i64;
    let mut open = None;
    for (i, c) in code.char_indices().rev() {
        match c {
            '}' | ')' | ']' => depth += 1,
            '(' | '[' if depth > 0 => depth -= 1,
            '{' if depth > 0 => depth -= 1,
            '{' if code[..i].ends_with('#') => {
                open = Some(i - 1);
                break;
            }
            '(' | '[' | '{' | ';' => return None,
            ':' if depth == 0 => return None,
            _ => {}
        }
    }
    let open = open?;
    // A key goes after `#{` or a `,`: the text since is one partial word.
    let since = code[open + 2..].rsplit(',').next().unwrap_or_default().trim_start();
    if !since.chars().all(is_ident) {
        return None;
    }
    let (name, _, _) = enclosing_call(text, open)?;
    let keys = a.option_keys().get(&name)?;
    Some(
        keys.iter()
            .map(|k| CompletionItem {
                label: k.clone(),
                kind: Some(CompletionItemKind::FIELD),
                detail: Some(format!("option of `{name}`")),
                insert_text: Some(format!("{k}: ")),
                ..CompletionItem::default()
            })
            .collect(),
    )
}
