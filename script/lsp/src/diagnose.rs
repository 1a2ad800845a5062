//! Diagnostics of a recipe as it is typed, without running it: the syntax error, the
//! dropped-result lint ([`blocksmith_script::lint`]), unknown functions, methods and properties
//! with a did-you-mean and calls that match no signature where the arguments' types are known
//! (both phrased by [`blocksmith_script::explain`], exactly as a run would report them),
//! `param` declarations whose default breaks their own range or choices (checked by
//! [`blocksmith_script::params::Declared`], as the run checks them), and imports that resolve to
//! no file and no standard-library module.

use std::collections::HashSet;
use std::path::Path;

use blocksmith_script::catalogue::Overload;
use blocksmith_script::explain::{explain, fits};
use lsp_types::{Diagnostic, DiagnosticSeverity, NumberOrString, Range};
use rhai::{ASTNode, Expr, FnCallExpr, Stmt, AST};

use crate::infer::{Link, Scope};
use crate::text::Lines;
use crate::Analyzer;

/// Rhai's own functions that are keywords rather than registered functions (the metadata does
/// not list them).
pub const KEYWORD_FUNCTIONS: [&str; 12] =
    ["print", "debug", "type_of", "Fn", "call", "curry", "is_def_var", "is_def_fn", "is_shared", "eval", "this", "fn"];

/// Where the diagnostics came from, shown by editors beside each message.
pub const SOURCE: &str = "blocksmith";

/// The diagnostics of `source` (the text of the file at `path`, if it has one).
#[must_use]
pub fn diagnostics(a: &Analyzer, source: &str, path: Option<&Path>) -> Vec<Diagnostic> {
    let lines = Lines::new(source);
    let ast = match a.engine.compile(source) {
        Ok(ast) => ast,
        Err(e) => {
            let range = lines.word_range(e.1);
            let message = e.0.to_string();
            return vec![diagnostic(range, DiagnosticSeverity::ERROR, "syntax", message)];
        }
    };
    let mut out = Vec::new();
    for d in blocksmith_script::lint::dropped_results(&ast, source) {
        out.push(diagnostic(lines.word_range(d.position), DiagnosticSeverity::WARNING, "dropped-result", d.message));
    }
    out.extend(imports(&ast, &lines, path));
    out.extend(calls(a, &ast, &lines));
    out.sort_by_key(|d| (d.range.start.line, d.range.start.character));
    out
}

fn diagnostic(range: Range, severity: DiagnosticSeverity, code: &str, message: String) -> Diagnostic {
    Diagnostic {
        range,
        severity: Some(severity),
        code: Some(NumberOrString::String(code.to_string())),
        source: Some(SOURCE.to_string()),
        message,
        ..Diagnostic::default()
    }
}

/// The modules a script imports by a literal name: (name, alias, position of the name).
#[must_use]
pub fn import_list(ast: &AST) -> Vec<(String, String, rhai::Position)> {
    let mut out = Vec::new();
    ast.walk(&mut |path: &[ASTNode]| {
        if let Some(ASTNode::Stmt(Stmt::Import(x, _))) = path.last() {
            if let Expr::StringConstant(s, pos) = &x.0 {
                out.push((s.to_string(), x.1.name.to_string(), *pos));
            }
        }
        true
    });
    out
}

/// Where `import "name"` leads from a script in `dir`: the file next to it, else the standard
/// library's module of that name (`Err` with the module's name), as the run's resolver looks.
pub fn resolve_import(name: &str, dir: Option<&Path>) -> Option<Result<std::path::PathBuf, String>> {
    let file = if name.ends_with(".rhai") { name.to_string() } else { format!("{name}.rhai") };
    let local = match dir {
        Some(d) => d.join(&file),
        None => Path::new(&file).to_path_buf(),
    };
    if local.is_file() {
        return Some(Ok(local));
    }
    let stem = name.trim_end_matches(".rhai");
    blocksmith_script::resolver::Resolver::stdlib_source(stem).map(|_| Err(stem.to_string()))
}

fn imports(ast: &AST, lines: &Lines<'_>, path: Option<&Path>) -> Vec<Diagnostic> {
    let dir = path.and_then(Path::parent);
    let mut out = Vec::new();
    for (name, _, pos) in import_list(ast) {
        if resolve_import(&name, dir).is_none() {
            let mut stdlib = blocksmith_script::resolver::Resolver::stdlib_names();
            stdlib.sort_unstable();
            let near = blocksmith_script::spelling::did_you_mean(&name, stdlib.iter().copied())
                .map_or_else(String::new, |n| format!(" (did you mean \"{n}\"?)"));
            let message = format!(
                "import: module \"{name}\" not found: no file {name}.rhai next to this recipe and no standard-library \
                 module of that name{near} (the standard library has: {})",
                stdlib.join(", ")
            );
            let mut range = lines.word_range(pos);
            range.end.character = range.start.character + name.encode_utf16().count() as u32 + 2;
            out.push(diagnostic(range, DiagnosticSeverity::ERROR, "unresolved-import", message));
        }
    }
    out
}

/// Unknown names, calls matching no signature and `param` declarations breaking their own
/// range, in the statements and then in each function's body (whose parameters' types are
/// unknown).
fn calls(a: &Analyzer, ast: &AST, lines: &Lines<'_>) -> Vec<Diagnostic> {
    let cat = &*a.catalogue;
    let mut defined: HashSet<String> = ast.iter_functions().map(|f| f.name.to_string()).collect();
    // A variable or parameter holding a closure is called by its name.
    ast.walk(&mut |path: &[ASTNode]| {
        match path.last() {
            Some(ASTNode::Stmt(Stmt::Var(x, ..))) => {
                defined.insert(x.0.name.to_string());
            }
            Some(ASTNode::Stmt(Stmt::For(x, _))) => {
                defined.insert(x.0.name.to_string());
            }
            _ => {}
        }
        true
    });
    for f in ast.iter_functions() {
        defined.extend(f.params.iter().map(|p| (*p).to_string()));
    }
    let known: HashSet<&str> = cat.iter().map(|o| o.name.as_str()).collect();
    let top: HashSet<*const Stmt> = ast.statements().iter().map(std::ptr::from_ref).collect();
    let mut scope = Scope::default();
    let mut in_functions = false;
    let mut out = Vec::new();
    let mut check = Check { cat, known: &known, defined: &defined, lines, out: &mut out, a };
    ast.walk(&mut |path: &[ASTNode]| {
        let Some(node) = path.last() else { return true };
        if path.len() == 1 {
            if let ASTNode::Stmt(s) = node {
                if !in_functions && !top.contains(&std::ptr::from_ref(*s)) {
                    in_functions = true;
                    scope = Scope::default();
                }
            }
        }
        match node {
            ASTNode::Stmt(s @ (Stmt::Var(..) | Stmt::Assignment(..))) => scope.assign(cat, s),
            ASTNode::Stmt(Stmt::For(x, _)) => {
                scope.vars.remove(x.0.name.as_str());
            }
            ASTNode::Stmt(Stmt::FnCall(call, pos)) | ASTNode::Expr(Expr::FnCall(call, pos)) => {
                check.function(&scope, call, *pos);
            }
            ASTNode::Expr(Expr::Dot(bin, ..)) => match path.len().checked_sub(2).map(|i| &path[i]) {
                Some(ASTNode::Expr(Expr::Dot(..))) => {}
                // `a[i].f()`: the chain starts at the element, whose type is not known.
                Some(ASTNode::Expr(Expr::Index(..))) => {
                    check.chain(&Scope::default(), &Expr::Unit(rhai::Position::NONE), &bin.rhs)
                }
                _ => check.chain(&scope, &bin.lhs, &bin.rhs),
            },
            _ => {}
        }
        true
    });
    out
}

struct Check<'x> {
    cat: &'x [Overload],
    known: &'x HashSet<&'x str>,
    defined: &'x HashSet<String>,
    lines: &'x Lines<'x>,
    out: &'x mut Vec<Diagnostic>,
    a: &'x Analyzer,
}

impl Check<'_> {
    fn exists(&self, name: &str) -> bool {
        self.known.contains(name) || self.defined.contains(name) || KEYWORD_FUNCTIONS.contains(&name)
    }

    /// Explains a call of `name` with arguments of the `given` types (`?` unknown) as a run
    /// would, through the catalogue's explanations.
    fn explained(&self, name: &str, given: &[String]) -> String {
        let text = format!("Function not found: {name} ({})", given.join(", "));
        explain(&self.a.engine, &text)
    }

    fn report(&mut self, pos: rhai::Position, code: &str, message: String) {
        let range = self.lines.word_range(pos);
        self.out.push(diagnostic(range, DiagnosticSeverity::ERROR, code, message));
    }

    fn function(&mut self, scope: &Scope, call: &FnCallExpr, pos: rhai::Position) {
        let name = call.name.as_str();
        if !call.namespace.is_empty()
            || call.is_operator_call()
            || !name.starts_with(|c: char| c.is_alphabetic() || c == '_')
        {
            return;
        }
        let given: Vec<Option<String>> = call.args.iter().map(|e| scope.type_of(self.cat, e)).collect();
        if name == "param" {
            self.param(call);
        }
        self.options(name, call.args.last());
        self.judge(name, &given, pos);
    }

    /// An unknown name, or a call whose argument count or known types fit no overload.
    fn judge(&mut self, name: &str, given: &[Option<String>], pos: rhai::Position) {
        if self.defined.contains(name) || KEYWORD_FUNCTIONS.contains(&name) {
            return;
        }
        let shown: Vec<String> = given.iter().map(|t| t.clone().unwrap_or_else(|| "?".into())).collect();
        if !self.exists(name) {
            let message = self.explained(name, &shown);
            self.report(pos, "unknown-function", message);
            return;
        }
        let overloads: Vec<&Overload> = self.cat.iter().filter(|o| o.name == name && o.property.is_none()).collect();
        // Rhai's own functions with a variable number of arguments are not judged.
        if overloads.is_empty() || !overloads.iter().any(|o| o.ours) {
            return;
        }
        let fit = overloads.iter().any(|o| {
            o.params.len() == given.len()
                && o.params.iter().zip(given).all(|((_, p), g)| g.as_ref().is_none_or(|g| fits(p, g)))
        });
        let arity_fits = overloads.iter().any(|o| o.params.len() == given.len());
        if !fit && (!arity_fits || given.iter().all(Option::is_some)) {
            let message = self.explained(name, &shown);
            self.report(pos, "no-signature", message);
        }
    }

    fn chain(&mut self, scope: &Scope, root: &Expr, rhs: &Expr) {
        let mut t = scope.type_of(self.cat, root);
        let mut links = Vec::new();
        links_with_positions(rhs, &mut links);
        for (link, call, pos) in links {
            match link {
                Link::Method(name, _) => {
                    let call = call.expect("a method link has its call");
                    let mut given = vec![t.clone()];
                    given.extend(call.args.iter().map(|e| scope.type_of(self.cat, e)));
                    if t.is_some() || !self.exists(name) {
                        self.judge(name, &given, pos);
                    }
                    self.options(name, call.args.last());
                    t = t.and_then(|r| crate::infer::returns(self.cat, name, Some(given.len()), Some(&r), false));
                }
                Link::Property("") => t = None,
                Link::Property(name) => {
                    let Some(r) = t.clone() else { continue };
                    if blocksmith_script::catalogue::is_api_type(&r)
                        && !self
                            .cat
                            .iter()
                            .any(|o| o.name == name && o.property.is_some() && o.receiver() == Some(r.as_str()))
                    {
                        let text = format!("Unknown property '{name}' for type '{r}'");
                        let message = explain(&self.a.engine, &text);
                        self.report(pos, "unknown-property", message);
                    }
                    t = crate::infer::returns(self.cat, name, None, Some(&r), true);
                }
            }
        }
    }

    /// The keys of a `#{…}` given to `name` that it does not know, as the run would refuse them.
    fn options(&mut self, name: &str, last: Option<&Expr>) {
        let Some(Expr::Map(map, _)) = last else { return };
        let Some(valid) = self.a.option_keys().get(name) else { return };
        for (key, _) in &map.0 {
            if valid.iter().any(|v| v == key.name.as_str()) {
                continue;
            }
            let near = blocksmith_script::spelling::did_you_mean(&key.name, valid.iter().map(String::as_str))
                .map_or_else(String::new, |n| format!(" (did you mean `{n}`?)"));
            let message =
                format!("{name}: unknown option `{}`{near}; valid options are: {}", key.name, valid.join(", "));
            self.report(key.pos, "unknown-option", message);
        }
    }

    /// `param(name, default, #{…})` with literal arguments, checked as the run checks it.
    fn param(&mut self, call: &FnCallExpr) {
        let (Some(Expr::StringConstant(name, _)), Some(default)) = (call.args.first(), call.args.get(1)) else {
            return;
        };
        let Some(value) = default.get_literal_value(None) else { return };
        let options = match call.args.get(2) {
            None => rhai::Map::new(),
            Some(e) => match e.get_literal_value(None).and_then(|m| m.try_cast::<rhai::Map>()) {
                Some(m) => m,
                None => return,
            },
        };
        if let Err(e) = blocksmith_script::params::Declared::new(name, value, options) {
            let message = blocksmith_script::diagnostics::message(&e);
            let pos = default.start_position();
            self.report(pos, "param-default", message);
        }
    }
}

/// The links of a `.` chain with the call and position of each.
fn links_with_positions<'a>(e: &'a Expr, out: &mut Vec<(Link<'a>, Option<&'a FnCallExpr>, rhai::Position)>) {
    match e {
        Expr::MethodCall(call, pos) => {
            out.push((Link::Method(call.name.as_str(), call.args.len() + 1), Some(call), *pos))
        }
        Expr::Property(p, pos) => out.push((Link::Property(p.2.as_str()), None, *pos)),
        Expr::Dot(bin, ..) => {
            links_with_positions(&bin.lhs, out);
            links_with_positions(&bin.rhs, out);
        }
        Expr::Index(bin, ..) => {
            // What an index gives is not known: the chain's type stops here.
            links_with_positions(&bin.lhs, out);
            out.push((Link::Property(""), None, rhai::Position::NONE));
        }
        _ => {}
    }
}
