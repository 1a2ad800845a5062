//! The whole reference as one model (every function, method, property and operator, and the
//! standard library's modules) and its Markdown page, docs/reference.md.

use std::collections::BTreeMap;

use rhai::Engine;

use super::modules::{self, Module};
use super::topics;
use crate::catalogue::Overload;

/// The command that writes docs/reference.md from a checkout's root (the test that keeps the
/// page current names it).
pub const REFRESH_MARKDOWN: &str = "cargo run --bin blocksmith -- doc --format markdown > docs/reference.md";
/// The command that writes docs/reference.html.
pub const REFRESH_HTML: &str = "cargo run --bin blocksmith -- doc --format html > docs/reference.html";

/// Everything `blocksmith doc` documents.
#[derive(Debug, Clone)]
pub struct Reference {
    /// blocksmith's functions (documented, not Rhai's built-ins), sorted by name.
    pub functions: Vec<Overload>,
    /// The standard library's modules.
    pub modules: Vec<Module>,
    /// Rhai's own functions that recipes use every day ([`topics::BUILTINS`]), from the
    /// engine's metadata.
    pub builtins: Vec<Overload>,
}

/// Where an overload is listed, in the reference's order: free functions by topic, Rhai's
/// built-ins, operators, then the methods of each type (see [`topics`] for the rule).
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub enum Section {
    /// Constructors and free functions of one topic: its order in [`topics::TOPICS`], its key.
    Topic(usize, String),
    /// Rhai's built-in functions (`sin`, `floor`, `push`...).
    Builtins,
    /// `a + b`, `v * 2`, `a == b`.
    Operators,
    /// Methods and properties of a script type (`m.translate(v)`, `m.volume`).
    Type(String),
}

impl Section {
    /// The section of one of blocksmith's functions `f`.
    #[must_use]
    pub fn of(f: &Overload) -> Section {
        match topics::place(f) {
            topics::Place::Topic(key) => Section::Topic(topics::order(&key), key),
            topics::Place::Operators => Section::Operators,
            topics::Place::Type(t) => Section::Type(t),
        }
    }

    /// The section's heading.
    #[must_use]
    pub fn title(&self) -> String {
        match self {
            Section::Topic(_, key) => topics::title(key),
            Section::Builtins => "Rhai's built-in functions".into(),
            Section::Operators => "Operators".into(),
            Section::Type(t) => t.clone(),
        }
    }

    /// One line under the heading.
    fn intro(&self) -> String {
        match self {
            Section::Topic(_, key) => {
                let intro = topics::intro(key);
                if intro.is_empty() {
                    "Called by name.".into()
                } else {
                    intro.into()
                }
            }
            Section::Builtins => "The language's own functions that recipes use every day, from its metadata (the \
                                  whole list: rhai.rs/book). Angles here are in **radians**; blocksmith's are in \
                                  degrees."
                .into(),
            Section::Operators => "Written between values: `a + b` (a mesh union), `v * 2`.".into(),
            Section::Type(t) => format!(
                "The methods and properties of a `{t}` value `x`: `x.name(...)` or `name(x, ...)`; a \
                 property reads as `x.name` (and, with a setter, is written as `x.name = value`)."
            ),
        }
    }
}

impl Reference {
    /// The reference of `engine`'s functions and the standard library.
    #[must_use]
    pub fn of(engine: &Engine) -> Reference {
        Reference { functions: super::functions(engine), modules: modules::stdlib(engine), builtins: builtins(engine) }
    }

    /// Only what `name` names: a function or operator (every overload), a type (its methods
    /// and properties), a module, one module function (`check::solid`) or a listed built-in
    /// (`sin`). `None` when nothing is of that name.
    #[must_use]
    pub fn select(self, name: &str) -> Option<Reference> {
        let functions: Vec<Overload> =
            self.functions.iter().filter(|f| f.name == name || f.receiver() == Some(name)).cloned().collect();
        let modules: Vec<Module> = self
            .modules
            .into_iter()
            .filter_map(|mut m| {
                if m.name != name {
                    m.functions.retain(|f| f.path() == name);
                    if m.functions.is_empty() {
                        return None;
                    }
                }
                Some(m)
            })
            .collect();
        // A built-in only when blocksmith has nothing of that name (`to_string` is both).
        let builtins: Vec<Overload> = if functions.is_empty() {
            self.builtins.into_iter().filter(|f| f.name == name).collect()
        } else {
            Vec::new()
        };
        (!functions.is_empty() || !modules.is_empty() || !builtins.is_empty()).then_some(Reference {
            functions,
            modules,
            builtins,
        })
    }

    /// The overloads by section (topics, operators, then types by name), each by name.
    #[must_use]
    pub fn sections(&self) -> BTreeMap<Section, BTreeMap<&str, Vec<&Overload>>> {
        let mut out: BTreeMap<Section, BTreeMap<&str, Vec<&Overload>>> = BTreeMap::new();
        for f in &self.functions {
            out.entry(Section::of(f)).or_default().entry(f.name.as_str()).or_default().push(f);
        }
        out
    }

    /// The free functions filed under a topic whose first parameter is of type `t` (`dot` for
    /// `Vec3`): a type's section points to them.
    #[must_use]
    pub fn taking(&self, t: &str) -> Vec<&str> {
        let mut out: Vec<&str> = self
            .functions
            .iter()
            .filter(|f| f.receiver() == Some(t) && matches!(Section::of(f), Section::Topic(..)))
            .map(|f| f.name.as_str())
            .collect();
        out.dedup();
        out
    }
}

/// Rhai's built-ins of [`topics::BUILTINS`] that `engine` has, every overload (signatures as
/// scripts see them, repeated ones once), with the group's note on the function appended.
#[must_use]
pub fn builtins(engine: &Engine) -> Vec<Overload> {
    let all = crate::catalogue::of(engine);
    let mut out: Vec<Overload> = Vec::new();
    for group in topics::BUILTINS {
        for (name, _) in group.names {
            for f in all.iter().filter(|f| !f.ours && f.name == *name) {
                if !out.iter().any(|o| o.signature() == f.signature()) {
                    out.push(f.clone());
                }
            }
        }
    }
    out
}

/// The Markdown page of `r`; `whole` adds the title, the note on how the page is made and the
/// contents (docs/reference.md is the whole reference).
#[must_use]
pub fn markdown(r: &Reference, whole: bool) -> String {
    let sections = r.sections();
    let mut out = String::new();
    if whole {
        out.push_str("# blocksmith script reference\n\n");
        out.push_str(
            "Every function, method, property and operator a blocksmith script can use, and the modules of the \
             standard library, from the doc comments of the bindings: first the functions you call by name, by \
             topic, then Rhai's own everyday functions, the operators, and each type's methods and properties. \
             `blocksmith doc NAME` prints one entry in the terminal. Angles are in degrees everywhere in \
             blocksmith; Rhai's `sin`, `cos`, `tan` and `atan` use radians. Coming from OpenSCAD, Python or \
             JavaScript? Read [Rhai for OpenSCAD, Python and JavaScript users](#rhai-for-openscad-python-and-javascript-users) \
             first. Generated, do not edit: refresh with\n\n",
        );
        out.push_str(&format!("    {REFRESH_MARKDOWN}\n\n"));
        out.push_str("## Contents\n\n");
        let entry = |s: &Section, n: usize| format!("[{}](#{}) ({n})", s.title(), slug(&s.title()));
        let topics: Vec<String> = sections
            .iter()
            .filter(|(s, _)| matches!(s, Section::Topic(..)))
            .map(|(s, names)| entry(s, names.len()))
            .collect();
        out.push_str(&format!("- Functions by topic: {}\n", topics.join(", ")));
        if !r.builtins.is_empty() {
            out.push_str(&format!("- {}\n", entry(&Section::Builtins, builtin_names(r).len())));
        }
        if let Some(ops) = sections.get(&Section::Operators) {
            out.push_str(&format!("- {}\n", entry(&Section::Operators, ops.len())));
        }
        let types: Vec<String> = sections
            .iter()
            .filter(|(s, _)| matches!(s, Section::Type(_)))
            .map(|(s, names)| entry(s, names.len()))
            .collect();
        out.push_str(&format!("- Types, their methods and properties: {}\n", types.join(", ")));
        if !r.modules.is_empty() {
            out.push_str("- [Standard library](#standard-library): ");
            let links: Vec<String> =
                r.modules.iter().map(|m| format!("[{}](#module-{})", m.name, slug(&m.name))).collect();
            out.push_str(&links.join(", "));
            out.push('\n');
        }
        out.push_str(&format!(
            "- Guides: [{}](#{}), {}\n",
            super::traps::TITLE,
            slug(super::traps::TITLE),
            super::guides::TITLES.iter().map(|t| format!("[{t}](#{})", slug(t))).collect::<Vec<_>>().join(", ")
        ));
        out.push('\n');
    }
    let mut builtins_done = r.builtins.is_empty();
    for (s, names) in &sections {
        if !builtins_done && *s > Section::Builtins {
            out.push_str(&builtins_markdown(r));
            builtins_done = true;
        }
        out.push_str(&format!("## {}\n\n{}\n\n", s.title(), s.intro()));
        if let Section::Type(t) = s {
            let taking = r.taking(t);
            if !taking.is_empty() {
                let links: Vec<String> = taking.iter().map(|n| format!("[{n}](#{})", slug(n))).collect();
                out.push_str(&format!(
                    "Free functions taking a `{t}` first are listed by topic: {}.\n\n",
                    links.join(", ")
                ));
            }
        }
        for (name, overloads) in names {
            out.push_str(&format!("### {}\n\n", heading(name)));
            push_groups(&mut out, overloads);
        }
    }
    if !builtins_done {
        out.push_str(&builtins_markdown(r));
    }
    if !r.modules.is_empty() {
        out.push_str(
            "## Standard library\n\nModules written in Rhai, built into blocksmith: `import \"NAME\" as NAME;`.\n\n",
        );
        for m in &r.modules {
            out.push_str(&format!("### Module {}\n\n```rhai\nimport \"{}\" as {};\n```\n\n", m.name, m.name, m.name));
            out.push_str(&format!("```text\n{}\n```\n\n", m.doc));
            for f in &m.functions {
                out.push_str(&format!("#### {}\n\n```text\n{}\n```\n\n{}\n\n", f.path(), f.signature(), f.doc.trim()));
            }
        }
    }
    if whole {
        out.push_str(&super::traps::markdown());
        out.push_str(&super::guides::markdown());
    }
    out.truncate(out.trim_end().len());
    out.push('\n');
    out
}

/// Overloads sharing a text shown together; each different text follows its own.
fn push_groups(out: &mut String, overloads: &[&Overload]) {
    let mut groups: Vec<(&str, Vec<String>)> = Vec::new();
    for f in overloads {
        match groups.iter_mut().find(|(d, _)| *d == f.doc) {
            Some((_, sigs)) => sigs.push(f.signature()),
            None => groups.push((&f.doc, vec![f.signature()])),
        }
    }
    for (doc, sigs) in groups {
        out.push_str(&format!("```text\n{}\n```\n\n{}\n\n", sigs.join("\n"), doc.trim()));
    }
}

/// The names of the built-ins `r` lists, in [`topics::BUILTINS`]' order.
fn builtin_names(r: &Reference) -> Vec<&'static str> {
    topics::BUILTINS
        .iter()
        .flat_map(|g| g.names.iter().map(|(n, _)| *n))
        .filter(|n| r.builtins.iter().any(|f| f.name == *n))
        .collect()
}

/// The section of Rhai's built-ins: each group's note, then each function's signatures, the
/// first paragraph of its metadata text and blocksmith's note on it.
fn builtins_markdown(r: &Reference) -> String {
    let mut out = format!("## {}\n\n{}\n\n", Section::Builtins.title(), Section::Builtins.intro());
    for g in topics::BUILTINS {
        let present: Vec<&(&str, &str)> =
            g.names.iter().filter(|(n, _)| r.builtins.iter().any(|f| f.name == *n)).collect();
        if present.is_empty() {
            continue;
        }
        out.push_str(&format!("### {}\n\n{}\n\n", g.title, g.note));
        for (name, note) in present {
            let sigs: Vec<String> = r.builtins.iter().filter(|f| f.name == *name).map(Overload::signature).collect();
            let text = r.builtins.iter().find(|f| f.name == *name && !f.doc.is_empty()).map_or("", |f| f.doc.as_str());
            let first = text.split("\n\n").next().unwrap_or_default().trim();
            out.push_str(&format!("#### {name}\n\n```text\n{}\n```\n\n", sigs.join("\n")));
            if !first.is_empty() {
                out.push_str(&format!("{first}\n\n"));
            }
            if !note.is_empty() {
                out.push_str(&format!("{note}\n\n"));
            }
        }
    }
    out
}

/// A function name as a heading: operators in code spans, so Markdown does not read them.
fn heading(name: &str) -> String {
    if name.starts_with(|c: char| c.is_alphabetic() || c == '_') {
        name.to_string()
    } else {
        format!("`{name}`")
    }
}

/// The anchor of a heading, as GitHub and the HTML page make it: lower case, spaces as `-`,
/// other punctuation dropped.
#[must_use]
pub fn slug(heading: &str) -> String {
    heading
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn page_has_every_section_and_module() {
        let engine = crate::new_engine(crate::EngineOptions::default());
        let r = Reference::of(&engine);
        let md = markdown(&r, true);
        assert!(md.starts_with("# blocksmith script reference\n"), "{}", &md[..200]);
        for heading in [
            "## Primitives",
            "## Math and vectors",
            "## Rhai's built-in functions",
            "## Operators",
            "## Mesh",
            "## Block",
            "## BlockModel",
            "## Standard library",
            "## Rhai for OpenSCAD, Python and JavaScript users",
            "## Block faces and sub-face grids",
        ] {
            assert!(md.contains(&format!("\n{heading}\n")), "no {heading}");
        }
        assert!(
            md.contains("[Mesh](#mesh) (") && md.contains("[Primitives](#primitives) ("),
            "contents link to sections"
        );
        assert!(md.contains("### Module check") && md.contains("#### check::solid"));
        assert!(md.contains("```text\ncube("), "signatures in code blocks");
        // The mesh CSG operators are documented with the operators.
        let ops = &md[md.find("\n## Operators\n").unwrap()..];
        let ops = &ops[..ops[1..].find("\n## ").unwrap()];
        assert!(ops.contains("+(a: Mesh, b: Mesh) -> Mesh"), "{ops}");
        assert!(ops.contains("-(a: BlockModel, b: Mesh) -> Mesh"), "{ops}");
    }

    #[test]
    fn selecting_keeps_only_what_the_name_names() {
        let engine = crate::new_engine(crate::EngineOptions::default());
        let r = Reference::of(&engine);
        let cube = r.clone().select("cube").unwrap();
        assert!(cube.functions.iter().all(|f| f.name == "cube") && cube.modules.is_empty());
        let mesh = r.clone().select("Mesh").unwrap();
        assert!(mesh.functions.len() > 20 && mesh.functions.iter().all(|f| f.receiver() == Some("Mesh")));
        let check = r.clone().select("check::solid").unwrap();
        assert!(check.functions.is_empty() && check.modules[0].functions.len() == 1);
        assert!(r.select("no_such_thing").is_none());
        assert_eq!(slug("Standard library"), "standard-library");
        assert_eq!(slug("Module check"), "module-check");
    }
}
