//! The whole reference as one model (every function, method, property and operator, and the
//! standard library's modules) and its Markdown page, docs/reference.md.

use std::collections::BTreeMap;

use rhai::Engine;

use super::modules::{self, Module};
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
}

/// Where an overload is listed: free functions, operators, or the methods of one type.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub enum Section {
    /// Called by name: `cube(2)`, `union(a, b)`.
    Functions,
    /// `a + b`, `v * 2`, `a == b`.
    Operators,
    /// Methods and properties of a script type (`m.translate(v)`, `m.volume`).
    Type(String),
}

impl Section {
    /// The section of `f`.
    #[must_use]
    pub fn of(f: &Overload) -> Section {
        if !f.name.starts_with(|c: char| c.is_alphabetic() || c == '_') {
            return Section::Operators;
        }
        match f.receiver() {
            Some(t) => Section::Type(t.to_string()),
            None => Section::Functions,
        }
    }

    /// The section's heading.
    #[must_use]
    pub fn title(&self) -> String {
        match self {
            Section::Functions => "Functions".into(),
            Section::Operators => "Operators".into(),
            Section::Type(t) => t.clone(),
        }
    }

    /// One line under the heading.
    fn intro(&self) -> String {
        match self {
            Section::Functions => "Called by name: `cube(2)`, `blocks()`.".into(),
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
        Reference { functions: super::functions(engine), modules: modules::stdlib(engine) }
    }

    /// Only what `name` names: a function or operator (every overload), a type (its methods
    /// and properties), a module, or one module function (`check::solid`). `None` when
    /// nothing is of that name.
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
        (!functions.is_empty() || !modules.is_empty()).then_some(Reference { functions, modules })
    }

    /// The overloads by section (functions, operators, then types by name), each by name.
    #[must_use]
    pub fn sections(&self) -> BTreeMap<Section, BTreeMap<&str, Vec<&Overload>>> {
        let mut out: BTreeMap<Section, BTreeMap<&str, Vec<&Overload>>> = BTreeMap::new();
        for f in &self.functions {
            out.entry(Section::of(f)).or_default().entry(f.name.as_str()).or_default().push(f);
        }
        out
    }
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
             standard library, from the doc comments of the bindings. `blocksmith doc NAME` prints one entry in \
             the terminal. Generated, do not edit: refresh with\n\n",
        );
        out.push_str(&format!("    {REFRESH_MARKDOWN}\n\n"));
        out.push_str("## Contents\n\n");
        for (s, names) in &sections {
            out.push_str(&format!("- [{}](#{}) ({})\n", s.title(), slug(&s.title()), names.len()));
        }
        if !r.modules.is_empty() {
            out.push_str("- [Standard library](#standard-library): ");
            let links: Vec<String> =
                r.modules.iter().map(|m| format!("[{}](#module-{})", m.name, slug(&m.name))).collect();
            out.push_str(&links.join(", "));
            out.push('\n');
        }
        out.push('\n');
    }
    for (s, names) in &sections {
        out.push_str(&format!("## {}\n\n{}\n\n", s.title(), s.intro()));
        for (name, overloads) in names {
            out.push_str(&format!("### {}\n\n", heading(name)));
            // Overloads sharing a text are shown together; each different text follows its own.
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
    out.truncate(out.trim_end().len());
    out.push('\n');
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
        for heading in ["## Functions", "## Operators", "## Mesh", "## Block", "## BlockModel", "## Standard library"] {
            assert!(md.contains(&format!("\n{heading}\n")), "no {heading}");
        }
        assert!(md.contains("- [Mesh](#mesh)"), "contents link to sections");
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
