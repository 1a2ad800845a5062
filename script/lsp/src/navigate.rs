//! Where things are: the modules a recipe imports (its own files, or the standard library's,
//! written out once so an editor can open them), the functions it and they define, its
//! `param` declarations; go-to-definition and the document's symbols.

use std::path::{Path, PathBuf};

use lsp_types::{DocumentSymbol, Location, Range, SymbolKind, Uri};

use crate::text::{blank_strings_and_comments, is_ident, word_len, Lines};
use crate::Analyzer;

/// A module a recipe imports: `import "name" as alias;`.
#[derive(Debug, Clone)]
pub struct Import {
    /// The name in quotes.
    pub name: String,
    /// The alias its functions are called through.
    pub alias: String,
    /// The byte range of the name inside the quotes.
    pub span: std::ops::Range<usize>,
}

/// The imports of `text` with a literal name, found in the text (it need not parse).
#[must_use]
pub fn imports(text: &str) -> Vec<Import> {
    let code = blank_strings_and_comments(text);
    let mut out = Vec::new();
    for (i, _) in code.match_indices("import") {
        if i > 0 && code[..i].chars().next_back().is_some_and(is_ident) {
            continue;
        }
        let rest = &code[i + 6..];
        let Some(q) = rest.find('"') else { continue };
        if !rest[..q].trim().is_empty() {
            continue;
        }
        let start = i + 6 + q + 1;
        let Some(len) = code[start..].find('"') else { continue };
        let after = code[start + len + 1..].trim_start();
        let Some(alias_text) = after.strip_prefix("as") else { continue };
        let alias_text = alias_text.trim_start();
        let alias = &alias_text[..word_len(alias_text)];
        if alias.is_empty() {
            continue;
        }
        out.push(Import {
            name: text[start..start + len].to_string(),
            alias: alias.to_string(),
            span: start..start + len,
        });
    }
    out
}

/// The file `import "name"` opens from a recipe in `dir`: the file next to it, or the
/// standard-library module written out to a cache folder (the same text the binary embeds).
#[must_use]
pub fn module_file(name: &str, dir: Option<&Path>) -> Option<PathBuf> {
    match crate::diagnose::resolve_import(name, dir)? {
        Ok(path) => Some(path),
        Err(stdlib) => {
            let source = blocksmith_script::resolver::Resolver::stdlib_source(&stdlib)?;
            let folder = std::env::temp_dir().join(format!("blocksmith-stdlib-{}", env!("CARGO_PKG_VERSION")));
            std::fs::create_dir_all(&folder).ok()?;
            let file = folder.join(format!("{stdlib}.rhai"));
            if std::fs::read_to_string(&file).ok().as_deref() != Some(source) {
                std::fs::write(&file, source).ok()?;
            }
            Some(file)
        }
    }
}

/// A function defined in a script: name, parameters, doc comment and the byte range of its name.
#[derive(Debug, Clone)]
pub struct ScriptFn {
    pub name: String,
    pub params: Vec<String>,
    pub doc: String,
    pub span: std::ops::Range<usize>,
}

impl ScriptFn {
    /// `name(a, b)`, prefixed by `alias::` for a module's.
    #[must_use]
    pub fn signature(&self, alias: Option<&str>) -> String {
        let prefix = alias.map_or_else(String::new, |a| format!("{a}::"));
        format!("{prefix}{}({})", self.name, self.params.join(", "))
    }
}

/// The functions `text` defines (`fn name(a, b)` and `private fn`), with their `///` comments.
#[must_use]
pub fn functions(text: &str) -> Vec<ScriptFn> {
    let code = blank_strings_and_comments(text);
    let mut out = Vec::new();
    for (i, _) in code.match_indices("fn ") {
        if i > 0 && code[..i].chars().next_back().is_some_and(is_ident) {
            continue;
        }
        let rest = code[i + 3..].trim_start();
        let start = code.len() - rest.len();
        let len = word_len(rest);
        if len == 0 || !rest[len..].trim_start().starts_with('(') {
            continue;
        }
        let open = start + len + rest[len..].find('(').unwrap_or(0);
        let close = code[open..].find(')').map_or(code.len(), |c| open + c);
        let params =
            code[open + 1..close].split(',').map(str::trim).filter(|p| !p.is_empty()).map(String::from).collect();
        // The `///` lines right above.
        let line_start = text[..i].rfind('\n').map_or(0, |n| n + 1);
        let mut doc: Vec<&str> = Vec::new();
        for line in text[..line_start].lines().rev() {
            match line.trim_start().strip_prefix("///") {
                Some(d) => doc.push(d.strip_prefix(' ').unwrap_or(d)),
                None => break,
            }
        }
        doc.reverse();
        out.push(ScriptFn { name: rest[..len].to_string(), params, doc: doc.join("\n"), span: start..start + len });
    }
    out
}

/// The `param("name", …)` calls of `text`: the name and the byte range of the whole call.
#[must_use]
pub fn params(text: &str) -> Vec<(String, std::ops::Range<usize>)> {
    let code = blank_strings_and_comments(text);
    let mut out = Vec::new();
    for (i, _) in code.match_indices("param") {
        if (i > 0 && code[..i].chars().next_back().is_some_and(|c| is_ident(c) || c == '.'))
            || code[i + 5..].chars().next().is_some_and(is_ident)
        {
            continue;
        }
        let rest = &code[i + 5..];
        let Some(after) = rest.trim_start().strip_prefix('(') else { continue };
        let open = i + 5 + (rest.len() - after.len()) - 1;
        let Some(q) = after.trim_start().strip_prefix('"') else { continue };
        let name_start = code.len() - q.len();
        let Some(name_len) = code[name_start..].find('"') else { continue };
        let Some(close) = crate::complete::closing(&code, open) else { continue };
        out.push((text[name_start..name_start + name_len].to_string(), i..close + 1));
    }
    out
}

/// A path as a `file://` address.
#[must_use]
pub fn uri_of(path: &Path) -> Option<Uri> {
    let abs = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
    let mut s = String::from("file://");
    for c in abs.to_string_lossy().chars() {
        match c {
            'A'..='Z' | 'a'..='z' | '0'..='9' | '/' | '-' | '_' | '.' | '~' => s.push(c),
            _ => {
                let mut buf = [0u8; 4];
                for b in c.encode_utf8(&mut buf).bytes() {
                    s.push_str(&format!("%{b:02X}"));
                }
            }
        }
    }
    s.parse().ok()
}

/// The path of a `file://` address.
#[must_use]
pub fn path_of(uri: &Uri) -> Option<PathBuf> {
    let s = uri.as_str().strip_prefix("file://")?;
    let mut bytes = Vec::new();
    let raw = s.as_bytes();
    let mut i = 0;
    while i < raw.len() {
        if raw[i] == b'%' && i + 2 < raw.len() + 1 {
            if let Ok(b) = u8::from_str_radix(std::str::from_utf8(raw.get(i + 1..i + 3)?).ok()?, 16) {
                bytes.push(b);
                i += 3;
                continue;
            }
        }
        bytes.push(raw[i]);
        i += 1;
    }
    Some(PathBuf::from(String::from_utf8(bytes).ok()?))
}

/// Where the name at byte `offset` of `text` is defined: a script function of the document,
/// an imported module (on its alias or its name), or a module's function (`alias::name`).
#[must_use]
pub fn definition(text: &str, offset: usize, uri: &Uri, dir: Option<&Path>) -> Option<Location> {
    let lines = Lines::new(text);
    let imports = imports(text);
    if let Some(imp) = imports.iter().find(|i| i.span.start <= offset && offset <= i.span.end) {
        let file = module_file(&imp.name, dir)?;
        return Some(Location::new(uri_of(&file)?, Range::default()));
    }
    let (_, word) = crate::text::word_at(text, offset)?;
    if let Some((alias, name)) = word.split_once("::") {
        let imp = imports.iter().find(|i| i.alias == alias)?;
        let file = module_file(&imp.name, dir)?;
        let source = std::fs::read_to_string(&file).ok()?;
        let target = uri_of(&file)?;
        let module_lines = Lines::new(&source);
        return Some(match functions(&source).into_iter().find(|f| f.name == name) {
            Some(f) => Location::new(
                target,
                Range::new(module_lines.position(f.span.start), module_lines.position(f.span.end)),
            ),
            None => Location::new(target, Range::default()),
        });
    }
    if let Some(imp) = imports.iter().find(|i| i.alias == word) {
        let file = module_file(&imp.name, dir)?;
        return Some(Location::new(uri_of(&file)?, Range::default()));
    }
    let f = functions(text).into_iter().find(|f| f.name == word)?;
    Some(Location::new(uri.clone(), Range::new(lines.position(f.span.start), lines.position(f.span.end))))
}

/// The document's symbols: its functions and its parameters.
#[must_use]
#[allow(deprecated)] // `DocumentSymbol::deprecated` must be written, though deprecated.
pub fn symbols(_a: &Analyzer, text: &str) -> Vec<DocumentSymbol> {
    let lines = Lines::new(text);
    let range = |r: &std::ops::Range<usize>| Range::new(lines.position(r.start), lines.position(r.end));
    let mut out: Vec<DocumentSymbol> = Vec::new();
    for f in functions(text) {
        out.push(DocumentSymbol {
            name: f.name.clone(),
            detail: Some(f.signature(None)),
            kind: SymbolKind::FUNCTION,
            tags: None,
            deprecated: None,
            range: range(&f.span),
            selection_range: range(&f.span),
            children: None,
        });
    }
    for (name, span) in params(text) {
        out.push(DocumentSymbol {
            name,
            detail: Some("param".into()),
            kind: SymbolKind::VARIABLE,
            tags: None,
            deprecated: None,
            range: range(&span),
            selection_range: range(&span),
            children: None,
        });
    }
    out.sort_by_key(|s| (s.range.start.line, s.range.start.character));
    out
}
