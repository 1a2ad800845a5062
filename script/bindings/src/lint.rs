//! The dropped-result lint: before a script runs, find the calls whose result is thrown away
//! while their receiver is left as it was — `c.translate([5, 0, 0]);` as a statement moves
//! nothing, since a mesh's transforms return a new mesh — and the chains whose later edits reach
//! only a dropped new value (`c.translate(v).crease_all();` creases a moved copy nobody keeps).
//! A Block's edits return the block itself, so a chain of them on a variable
//! (`b.subdivide("+z", 2, 2).sharp_all();`) edits the variable and is not reported.
//!
//! Which functions keep their receiver comes from their declarations ([`crate::api::registry`]).
//! Receivers' types are followed through `let` and assignments from the functions' declared
//! return types; a method whose overloads disagree (a Block's `translate` edits the block) is
//! judged only when the receiver's type is known. Script-defined functions and Rhai's own are
//! never judged.

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

use rhai::{ASTNode, Engine, Expr, FnCallExpr, Position, Stmt, AST};

use crate::api::registry::{candidates, Declared};

/// One dropped result: where the dropped call is and what to write instead.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Dropped {
    /// The position of the call whose result is dropped.
    pub position: Position,
    /// The message: what is lost and the fix.
    pub message: String,
}

/// The dropped results of the script compiled as `ast` from `source`, in source order.
/// Function bodies and closures are checked too (their last statement is their value, not a
/// dropped one).
#[must_use]
pub fn dropped_results(ast: &AST, source: &str) -> Vec<Dropped> {
    dropped_results_knowing(ast, source, std::iter::empty(), true)
}

/// As [`dropped_results`], knowing the values of some variables already (a REPL session's):
/// `(name, type name)` pairs, the type name as Rhai reports it (`blocksmith::api::mesh::SharedMesh`).
/// `last_used`: whether the last statement's value is kept (a script's is its model; a REPL
/// entry ending in `;` only shows it).
#[must_use]
pub fn dropped_results_knowing<'a>(
    ast: &AST,
    source: &str,
    known: impl IntoIterator<Item = (&'a str, &'a str)>,
    last_used: bool,
) -> Vec<Dropped> {
    let mut lint = Lint::default();
    for (name, type_name) in known {
        let short = type_name.rsplit("::").next().unwrap_or(type_name);
        let declared = crate::api::registry::REGISTRY.iter().find_map(|d| match d.receiver {
            Some(r) if r == short => Some(r),
            _ => None,
        });
        if let Some(t) = declared {
            lint.types.insert(name.to_string(), t);
        }
    }
    lint.block(ast.statements(), last_used);
    let engine = Engine::new_raw();
    for f in ast.iter_fn_def() {
        let (start, end) = (f.body.start_position(), f.body.end_position());
        let Some(body) = only_between(source, start, end) else { continue };
        // The body compiled alone, everything else blanked, keeps its positions.
        let Ok(body_ast) = engine.compile(&body) else { continue };
        let mut inner = Lint { types: HashMap::new(), found: Vec::new() };
        inner.block(body_ast.statements(), true);
        lint.found.append(&mut inner.found);
    }
    lint.found.sort_by_key(|d| (d.position.line(), d.position.position()));
    lint.found.dedup();
    lint.found
}

/// The dropped results in the modules `ast` imports by name from files next to `dir` (the
/// importing script's folder), and in the modules those import, as warnings naming each
/// module's file. A module's last statement is not its value, so it counts as dropped too.
/// Standard-library modules are checked with the repository, and a module that is missing or
/// does not compile is left to the run to report.
#[must_use]
pub fn imported_warnings(engine: &Engine, ast: &AST, dir: Option<&Path>) -> Vec<String> {
    let mut seen = HashSet::new();
    let mut out = Vec::new();
    lint_imports(engine, ast, dir, &mut seen, &mut out);
    out
}

fn lint_imports(engine: &Engine, ast: &AST, dir: Option<&Path>, seen: &mut HashSet<PathBuf>, out: &mut Vec<String>) {
    for name in import_names(ast) {
        let file = if name.ends_with(".rhai") { name } else { format!("{name}.rhai") };
        let path = dir.map_or_else(|| PathBuf::from(&file), |d| d.join(&file));
        let key = path.canonicalize().unwrap_or_else(|_| path.clone());
        if !path.is_file() || !seen.insert(key.clone()) {
            continue;
        }
        let Ok(source) = std::fs::read_to_string(&path) else { continue };
        let Ok(module) = engine.compile(&source) else { continue };
        let shown = path.display().to_string();
        let found = dropped_results_knowing(&module, &source, std::iter::empty(), false);
        out.extend(found.iter().map(|d| crate::diagnostics::format_warning(&shown, &source, d.position, &d.message)));
        lint_imports(engine, &module, path.parent(), seen, out);
    }
}

/// The names of the modules `ast` imports with a literal name (`import "parts" as p;`).
fn import_names(ast: &AST) -> Vec<String> {
    let mut names = Vec::new();
    ast.walk(&mut |path: &[ASTNode]| {
        if let Some(ASTNode::Stmt(Stmt::Import(x, _))) = path.last() {
            if let Expr::StringConstant(s, _) = &x.0 {
                names.push(s.to_string());
            }
        }
        true
    });
    names
}

/// `source` with every character outside `start..=end` replaced by a space (lines kept).
fn only_between(source: &str, start: Position, end: Position) -> Option<String> {
    let (sl, sc) = (start.line()?, start.position().unwrap_or(1));
    let (el, ec) = (end.line()?, end.position().unwrap_or(usize::MAX));
    let mut out = String::with_capacity(source.len());
    for (i, line) in source.split('\n').enumerate() {
        if i > 0 {
            out.push('\n');
        }
        let l = i + 1;
        for (j, ch) in line.chars().enumerate() {
            let c = j + 1;
            let inside = (l > sl || (l == sl && c >= sc)) && (l < el || (l == el && c <= ec));
            out.push(if inside || ch == '\r' { ch } else { ' ' });
        }
    }
    Some(out)
}

#[derive(Default)]
struct Lint {
    /// The Rust type of each variable whose value's type is known (`SharedMesh`, `Block`, ...).
    types: HashMap<String, &'static str>,
    found: Vec<Dropped>,
}

/// One call of a method chain, in order: `name(args)` on the previous link's value.
struct Link<'a> {
    call: &'a FnCallExpr,
    pos: Position,
}

impl Lint {
    fn block(&mut self, stmts: &[Stmt], value_used: bool) {
        for (i, s) in stmts.iter().enumerate() {
            self.stmt(s, value_used && i + 1 == stmts.len());
        }
    }

    fn stmt(&mut self, s: &Stmt, used: bool) {
        match s {
            Stmt::Var(x, ..) => {
                let (ident, expr, _) = &**x;
                self.expr(expr);
                self.set_type(ident.name.as_str(), expr);
            }
            Stmt::Assignment(x) => {
                let (op, bin) = &**x;
                self.expr(&bin.rhs);
                if let Expr::Variable(v, ..) = &bin.lhs {
                    if op.is_op_assignment() {
                        self.types.remove(v.1.as_str());
                    } else {
                        self.set_type(v.1.as_str(), &bin.rhs);
                    }
                }
            }
            Stmt::FnCall(call, pos) => {
                self.args(call);
                if !used {
                    self.dropped_call(call, *pos);
                }
            }
            Stmt::Expr(e) => {
                self.expr(e);
                if !used {
                    self.dropped_expr(e);
                }
            }
            Stmt::If(fc, _) | Stmt::TryCatch(fc, _) => {
                self.expr(&fc.expr);
                self.block(fc.body.statements(), used);
                self.block(fc.branch.statements(), used);
            }
            Stmt::While(fc, _) | Stmt::Do(fc, ..) => {
                self.expr(&fc.expr);
                self.block(fc.body.statements(), false);
            }
            Stmt::For(x, _) => {
                let (var, counter, fc) = &**x;
                self.expr(&fc.expr);
                self.types.remove(var.name.as_str());
                if let Some(c) = counter {
                    self.types.remove(c.name.as_str());
                }
                self.block(fc.body.statements(), false);
            }
            Stmt::Block(b) => self.block(b.statements(), used),
            Stmt::Switch(x, _) => {
                let (e, cases) = &**x;
                self.expr(e);
                for case in &cases.expressions {
                    self.expr(&case.lhs);
                    match &case.rhs {
                        Expr::Stmt(b) => self.block(b.statements(), used),
                        other => {
                            self.expr(other);
                            if !used {
                                self.dropped_expr(other);
                            }
                        }
                    }
                }
            }
            Stmt::Return(Some(e), ..) | Stmt::BreakLoop(Some(e), ..) => self.expr(e),
            _ => {}
        }
    }

    /// Visits the statement blocks nested in an expression (whose values are used).
    fn expr(&mut self, e: &Expr) {
        match e {
            Expr::Stmt(b) => self.block(b.statements(), true),
            Expr::FnCall(call, _) | Expr::MethodCall(call, _) => self.args(call),
            Expr::Dot(bin, ..) | Expr::Index(bin, ..) => {
                self.expr(&bin.lhs);
                self.expr(&bin.rhs);
            }
            Expr::Array(items, _) | Expr::InterpolatedString(items, _) => items.iter().for_each(|x| self.expr(x)),
            Expr::And(items, _) | Expr::Or(items, _) | Expr::Coalesce(items, _) => {
                items.iter().for_each(|x| self.expr(x));
            }
            Expr::Map(m, _) => m.0.iter().for_each(|(_, x)| self.expr(x)),
            _ => {}
        }
    }

    fn args(&mut self, call: &FnCallExpr) {
        call.args.iter().for_each(|a| self.expr(a));
    }

    fn set_type(&mut self, name: &str, value: &Expr) {
        match self.type_of(value) {
            Some(t) => self.types.insert(name.to_string(), t),
            None => self.types.remove(name),
        };
    }

    /// The Rust type of `e`'s value when the declarations settle it.
    fn type_of(&self, e: &Expr) -> Option<&'static str> {
        match e {
            Expr::Variable(v, ..) => self.types.get(v.1.as_str()).copied(),
            Expr::FnCall(call, _) if call.namespace.is_empty() => {
                let receiver = call.args.first().and_then(|a| self.type_of(a));
                unique_return(call.name.as_str(), call.args.len(), receiver)
            }
            Expr::Dot(..) => {
                let (root, links) = chain(e)?;
                let mut t = self.type_of(root);
                for l in &links {
                    t = unique_return(l.call.name.as_str(), l.call.args.len() + 1, t);
                }
                t
            }
            _ => None,
        }
    }

    /// `f(x, ...)` as a statement: a function whose value is all it gives (`cube(2);`), a
    /// method called function-style (`translate(c, v);`), or an edit of a temporary value
    /// (`crease(cube(1), e);`).
    fn dropped_call(&mut self, call: &FnCallExpr, pos: Position) {
        let name = call.name.as_str();
        // `print` and `debug` return the text they write, which Rhai sends to the output.
        if !call.namespace.is_empty() || matches!(name, "print" | "debug") {
            return;
        }
        let receiver = call.args.first().and_then(|a| self.type_of(a));
        let decls: Vec<&Declared> = candidates(name, call.args.len(), receiver).collect();
        if decls.is_empty() {
            return;
        }
        if decls.iter().all(|d| d.returns_new_value()) {
            let message = match call.args.first() {
                Some(Expr::Variable(v, ..)) if decls.iter().all(|d| d.receiver.is_some()) => {
                    let x = v.1.as_str();
                    format!(
                        "the result of `{name}` is dropped and `{x}` is unchanged (`{name}` returns a new value); \
                         write `{x} = {name}({x}, …);`"
                    )
                }
                _ => format!(
                    "the result of `{name}` is dropped (`{name}` returns a new value and changes nothing); \
                     keep it with `let x = {}`",
                    shown(call)
                ),
            };
            self.found.push(Dropped { position: pos, message });
        } else if decls.iter().all(|d| d.edits_receiver()) && call.args.first().is_some_and(|a| !self.held(a)) {
            let made = call.args.first().map_or_else(String::new, describe);
            let message = format!(
                "`{name}` changes the value `{made}` returned, and that value is then dropped; keep it first: \
                 `let x = {made}; {name}(x, …);`"
            );
            self.found.push(Dropped { position: pos, message });
        }
    }

    /// `x.f(...).g(...);` as a statement.
    fn dropped_expr(&mut self, e: &Expr) {
        let Some((root, links)) = chain(e) else { return };
        let Some(last) = links.last() else { return };
        let mut t = self.type_of(root);
        for l in &links[..links.len() - 1] {
            t = unique_return(l.call.name.as_str(), l.call.args.len() + 1, t);
        }
        let name = last.call.name.as_str();
        let decls: Vec<&Declared> = candidates(name, last.call.args.len() + 1, t).collect();
        if decls.is_empty() {
            return;
        }
        let var = match root {
            Expr::Variable(v, ..) => Some(v.1.as_str()),
            _ => None,
        };
        let calls = links.iter().map(|l| shown(l.call)).collect::<Vec<_>>().join(".");
        if decls.iter().all(|d| d.returns_new_value()) {
            let message = match var {
                Some(x) if links.len() == 1 => format!(
                    "the result of `{name}` is dropped and `{x}` is unchanged (`{name}` returns a new value); \
                     write `{x} = {x}.{calls};`"
                ),
                Some(x) => format!(
                    "the result of `{name}` is dropped, so it changes nothing (`{name}` returns a new value); \
                     to keep it, write `{x} = {x}.{calls};`"
                ),
                None => format!(
                    "the result of `{name}` is dropped (`{name}` returns a new value and changes nothing); \
                     keep it with `let x = …;`"
                ),
            };
            self.found.push(Dropped { position: last.pos, message });
        } else if decls.iter().all(|d| d.edits_receiver()) {
            // The value the last call edits: made by the last earlier call that does not return
            // its receiver itself, or the root when every earlier one does (a Block's edits).
            // A script's own function or overloads that disagree leave it unknown: not judged.
            let mut t = self.type_of(root);
            let mut made_by = None;
            let mut unknown = false;
            for (i, l) in links[..links.len() - 1].iter().enumerate() {
                let arity = l.call.args.len() + 1;
                let ds: Vec<&Declared> = candidates(l.call.name.as_str(), arity, t).collect();
                let selves = ds.iter().filter(|d| d.returns_receiver()).count();
                if ds.is_empty() || selves != 0 && selves != ds.len() {
                    unknown = true;
                } else if selves == 0 {
                    (made_by, unknown) = (Some(i), false);
                }
                t = unique_return(l.call.name.as_str(), arity, t);
            }
            if unknown || made_by.is_none() && self.held(root) {
                return;
            }
            // An edit of a value the chain made (a new mesh, a copy, a constructor's value):
            // dropped with it.
            let Some(prev) = made_by.map(|i| links[i].call.name.as_str()) else {
                let made = describe(root);
                let message = format!(
                    "`{name}` changes the value `{made}` returned, and that value is then dropped; keep it first: \
                     `let x = {made}; x.{calls};`"
                );
                self.found.push(Dropped { position: last.pos, message });
                return;
            };
            let target = var.map_or_else(|| "the value".to_string(), |x| format!("`{x}`"));
            let split = var.map_or_else(String::new, |x| {
                // Each earlier link as a statement of its own: kept by assignment when it
                // returns a new value, else an edit of `x` itself.
                let root_type = self.type_of(root);
                let mut t = root_type;
                let mut stmts: Vec<String> = Vec::new();
                for (i, l) in links.iter().enumerate() {
                    let arity = l.call.args.len() + 1;
                    let fresh = {
                        let mut ds = candidates(l.call.name.as_str(), arity, t).peekable();
                        ds.peek().is_some() && ds.all(Declared::returns_new_value)
                    };
                    let returns = unique_return(l.call.name.as_str(), arity, t);
                    if fresh && (returns.is_none() || returns != root_type) {
                        // A value of another kind (a model's block): keep it in a variable of its own.
                        let shown_calls =
                            |ls: &[Link<'_>]| ls.iter().map(|l| shown(l.call)).collect::<Vec<_>>().join(".");
                        let (made, rest) = links.split_at(i + 1);
                        return format!(
                            "; keep it first: `let y = {x}.{}; y.{};`",
                            shown_calls(made),
                            shown_calls(rest)
                        );
                    }
                    stmts.push(if fresh {
                        format!("{x} = {x}.{};", shown(l.call))
                    } else {
                        format!("{x}.{};", shown(l.call))
                    });
                    t = unique_return(l.call.name.as_str(), arity, t);
                }
                format!("; write one change per statement: `{}`", stmts.join(" "))
            });
            let j = made_by.unwrap_or_default();
            let prev_fresh = {
                let mut t = self.type_of(root);
                for l in &links[..j] {
                    t = unique_return(l.call.name.as_str(), l.call.args.len() + 1, t);
                }
                let arity = links[j].call.args.len() + 1;
                let mut ds = candidates(prev, arity, t).peekable();
                ds.peek().is_some() && ds.all(Declared::returns_new_value)
            };
            let what = if prev_fresh { "new value" } else { "copy" };
            let message = format!(
                "`{name}` changes the {what} that `{prev}` returned, and that {what} is dropped: {target} does \
                 not get it{split}"
            );
            self.found.push(Dropped { position: last.pos, message });
        }
    }
}

impl Lint {
    /// Whether `e`'s value is one a variable holds: a variable, an element or property of one,
    /// or an edit of such a value that may return it itself (`b.subdivide(…)` on a Block `b`,
    /// function-style too).
    fn held(&self, e: &Expr) -> bool {
        match e {
            Expr::FnCall(call, _) if call.namespace.is_empty() => {
                let Some(first) = call.args.first() else { return false };
                let receiver = self.type_of(first);
                // Overloads that disagree (a parameter's `translate`) are not judged: held.
                candidates(call.name.as_str(), call.args.len(), receiver).any(Declared::returns_receiver)
                    && self.held(first)
            }
            Expr::Dot(..) => match chain(e) {
                Some((root, links)) => {
                    let mut t = self.type_of(root);
                    for l in &links {
                        let arity = l.call.args.len() + 1;
                        if !candidates(l.call.name.as_str(), arity, t).any(Declared::returns_receiver) {
                            return false;
                        }
                        t = unique_return(l.call.name.as_str(), arity, t);
                    }
                    self.held(root)
                }
                // A property or an index on the way: part of a held value.
                None => true,
            },
            other => !is_temporary(other),
        }
    }
}

/// Whether `e` makes a value no variable holds (a call's result, a literal): an edit of it is
/// lost unless the value is kept.
fn is_temporary(e: &Expr) -> bool {
    !matches!(e, Expr::Variable(..) | Expr::Index(..) | Expr::Dot(..) | Expr::Property(..) | Expr::ThisPtr(..))
}

/// A temporary as a message shows it: `cube(…)`, or `…` for another expression.
fn describe(e: &Expr) -> String {
    match e {
        Expr::FnCall(call, _) => shown(call),
        _ => "…".to_string(),
    }
}

/// A call as a fix shows it: `name(…)`, or `name()` without arguments.
fn shown(call: &FnCallExpr) -> String {
    let args = if call.args.is_empty() { "" } else { "…" };
    format!("{}({args})", call.name)
}

/// The single return type of the declarations of `name`, if they agree.
fn unique_return(name: &str, arity: usize, receiver: Option<&'static str>) -> Option<&'static str> {
    let mut types = candidates(name, arity, receiver).map(|d| d.returns);
    let first = types.next()?;
    (types.all(|t| t == first) && first != "()" && first != "Dynamic").then_some(first)
}

/// A method chain `root.f(..).g(..)`: its root and its calls in order; `None` when a link is a
/// property or an index (not judged).
fn chain(e: &Expr) -> Option<(&Expr, Vec<Link<'_>>)> {
    let Expr::Dot(bin, ..) = e else { return None };
    let mut links = Vec::new();
    flatten(&bin.rhs, &mut links)?;
    Some((&bin.lhs, links))
}

fn flatten<'a>(e: &'a Expr, out: &mut Vec<Link<'a>>) -> Option<()> {
    match e {
        Expr::MethodCall(call, pos) => {
            out.push(Link { call, pos: *pos });
            Some(())
        }
        Expr::Dot(bin, ..) => {
            flatten(&bin.lhs, out)?;
            flatten(&bin.rhs, out)
        }
        _ => None,
    }
}

/// The lint's findings as warnings (`file:line:col: warning: ...`, source line, caret), one
/// after another.
#[must_use]
pub fn format_warnings(name: &str, source: &str, found: &[Dropped]) -> String {
    found
        .iter()
        .map(|d| crate::diagnostics::format_warning(name, source, d.position, &d.message))
        .collect::<Vec<_>>()
        .join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lint(src: &str) -> Vec<String> {
        let engine = crate::new_engine(crate::EngineOptions::default());
        let ast = engine.compile(src).unwrap();
        dropped_results(&ast, src)
            .into_iter()
            .map(|d| format!("{}:{} {}", d.position.line().unwrap(), d.position.position().unwrap(), d.message))
            .collect()
    }

    #[test]
    fn a_dropped_mesh_transform_is_found_with_its_fix() {
        let found = lint("let c = cube(2);\nc.translate([5, 0, 0]);\nc\n");
        assert_eq!(found.len(), 1, "{found:?}");
        assert!(found[0].starts_with("2:3 the result of `translate` is dropped and `c` is unchanged"), "{found:?}");
        assert!(found[0].ends_with("write `c = c.translate(…);`"), "{found:?}");
    }

    #[test]
    fn a_kept_result_an_edit_and_the_script_value_pass() {
        // Assigned, used as an argument, edited in place (crease_all), the script's last value,
        // a function's last value: nothing is dropped.
        let src = "let c = cube(2);\nc = c.translate([5, 0, 0]);\nc.crease_all();\nlet v = c.volume();\n\
                   fn moved(m) { m.translate([1, 0, 0]) }\nlet b = block([0, 0, 0], [1, 1, 1]);\n\
                   b.translate([1, 0, 0]);\nb.sharp_all();\nc.rotate([0, 0, 1], 30)\n";
        assert_eq!(lint(src), Vec::<String>::new());
    }

    #[test]
    fn dropped_results_inside_blocks_loops_and_functions_are_found() {
        let src = "let c = cube(1);\nfor i in 0..2 {\n    c.scale(2);\n}\nif true { c.mirror([1, 0, 0]); }\n\
                   fn f(m) {\n    m.triangulate();\n    m\n}\nlet g = |m| { m.catmull_clark(1); m };\nc\n";
        let found = lint(src);
        let lines: Vec<&str> = found.iter().map(|f| f.split(' ').next().unwrap()).collect();
        assert_eq!(lines, ["3:7", "5:13", "7:7", "10:17"], "{found:?}");
    }

    #[test]
    fn an_unknown_receiver_is_judged_only_when_every_overload_agrees() {
        // `m` is a parameter: translate could be a Block's (an edit), so nothing is said; a
        // name only Mesh has (catmull_clark) returns a new value whatever the receiver.
        let found = lint("fn f(m) {\n    m.translate([1, 0, 0]);\n    m.loop_subdivide(1);\n    m\n}\n1\n");
        assert_eq!(found.len(), 1, "{found:?}");
        assert!(found[0].starts_with("3:7 the result of `loop_subdivide`"), "{found:?}");
    }

    #[test]
    fn a_chain_of_block_edits_edits_the_block_and_an_edit_of_a_copy_is_found() {
        // A Block's edits return the block itself: the chain edits `b`, function-style too.
        let src = "let b = block([0, 0, 0], [1, 1, 1]);\nb.subdivide(\"+z\", 2, 2).sharp_all();\n\
                   b.translate([1, 0, 0]).rotate([0, 0, 1], 90).smooth([\"+x+y\"]);\n\
                   sharp_all(subdivide(b, \"+x\", 2, 1));\nlet m = blocks();\nm.add(b);\nm\n";
        assert_eq!(lint(src), Vec::<String>::new());
        // A script's own method may return `this`: not judged.
        let src = "fn lift(dz) { this.translate([0, 0, dz]) }\nlet b = block([0, 0, 0], [1, 1, 1]);\n\
                   b.lift(1).sharp_all();\nb\n";
        assert_eq!(lint(src), Vec::<String>::new());
        // A model's `block(id)` is a copy: editing it changes nothing the model holds.
        let found = lint("let m = blocks();\nm.add(block([0, 0, 0], [1, 1, 1]));\nm.block(0).sharp_all();\nm\n");
        assert_eq!(found.len(), 1, "{found:?}");
        assert!(
            found[0].starts_with("3:12 `sharp_all` changes the new value that `block` returned")
                && found[0].ends_with("keep it first: `let y = m.block(…); y.sharp_all();`"),
            "{found:?}"
        );
        // A chain of edits on a fresh block that is then dropped.
        let found = lint("block([0, 0, 0], [1, 1, 1]).subdivide(\"+z\", 2, 2).sharp_all();\n1\n");
        assert_eq!(found.len(), 1, "{found:?}");
        assert!(
            found[0].contains("`sharp_all` changes the value `block(…)` returned")
                && found[0].ends_with("`let x = block(…); x.subdivide(…).sharp_all();`"),
            "{found:?}"
        );
        // A chain ending in a save is its effect, not a dropped result.
        assert_eq!(lint("let c = cube(1);\nc.translate([1, 0, 0]).save(\"x.obj\");\n1\n"), Vec::<String>::new());
    }

    #[test]
    fn function_style_calls_and_chains_from_constructors() {
        let found = lint("let c = cube(1);\ntranslate(c, [1, 0, 0]);\ncube(2).scale(3);\nc\n");
        assert_eq!(found.len(), 2, "{found:?}");
        assert!(found[0].contains("write `c = translate(c, …);`"), "{found:?}");
        assert!(found[1].starts_with("3:9 the result of `scale` is dropped"), "{found:?}");
    }

    #[test]
    fn a_constructor_s_dropped_value_and_an_edit_of_a_temporary_are_found() {
        // `cube(2);` makes a mesh nobody keeps; `crease(cube(1), e)` and `cube(1).crease_all()`
        // edit a mesh that is dropped right after.
        let src = "cube(2);\nblocks();\ncrease(cube(1), [[0, 1]]);\ncube(1).crease_all();\nlet c = cube(1);\n\
                   c.translate([1, 0, 0]).crease_all();\nc\n";
        let found = lint(src);
        assert_eq!(found.len(), 5, "{found:?}");
        assert!(
            found[0].starts_with("1:1 the result of `cube` is dropped") && found[0].ends_with("`let x = cube(…)`"),
            "{found:?}"
        );
        assert!(found[1].starts_with("2:1 the result of `blocks` is dropped"), "{found:?}");
        assert!(
            found[2].starts_with("3:1 `crease` changes the value `cube(…)` returned")
                && found[2].ends_with("`let x = cube(…); crease(x, …);`"),
            "{found:?}"
        );
        assert!(found[3].starts_with("4:9 `crease_all` changes the value `cube(…)` returned"), "{found:?}");
        assert!(
            found[4].starts_with("6:24 `crease_all` changes the new value that `translate` returned")
                && found[4].ends_with("`c = c.translate(…); c.crease_all();`"),
            "{found:?}"
        );
    }

    #[test]
    fn effects_and_edits_of_variables_are_silent() {
        // An edit of a variable (function-style too), a save, a parameter, an assertion, a
        // shown value: each does something though its value is dropped.
        let src = "let c = cube(1);\ncrease(c, [[0, 1]]);\ncrease_all(c);\ncube(1).save(\"x.obj\");\n\
                   param(\"size\", 2);\nassert(true, \"yes\");\nshow(c);\nlet parts = [cube(1)];\n\
                   parts[0].crease_all();\nc\n";
        assert_eq!(lint(src), Vec::<String>::new());
    }

    #[test]
    fn imported_modules_are_linted_with_their_own_file_names() {
        let d = tempfile::tempdir().unwrap();
        std::fs::write(
            d.path().join("parts.rhai"),
            "fn leg() {\n    let l = cube(1);\n    l.scale(2);\n    l\n}\nimport \"deeper\" as deeper;\n",
        )
        .unwrap();
        std::fs::write(d.path().join("deeper.rhai"), "let x = cube(1);\nx.mirror([1, 0, 0]);\n").unwrap();
        let engine = crate::new_engine(crate::EngineOptions::default());
        let ast =
            engine.compile("import \"parts\" as p;\nimport \"parts\" as q;\nimport \"plants\" as std;\n1\n").unwrap();
        let found = imported_warnings(&engine, &ast, Some(d.path()));
        assert_eq!(found.len(), 2, "{found:?}");
        assert!(found[0].contains("parts.rhai:3:7: warning: the result of `scale` is dropped"), "{found:?}");
        assert!(found[1].contains("deeper.rhai:2:3: warning: the result of `mirror` is dropped"), "{found:?}");
    }

    #[test]
    fn the_repository_s_scripts_drop_no_result() {
        // Examples, the standard library and the script tests are what users copy from.
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let engine = crate::new_engine(crate::EngineOptions::default());
        let mut checked = 0;
        for dir in ["examples", "stdlib", "tests"] {
            let mut files: Vec<_> = std::fs::read_dir(root.join(dir)).unwrap().map(|e| e.unwrap().path()).collect();
            files.retain(|p| p.extension().is_some_and(|e| e == "rhai"));
            for p in files {
                let src = std::fs::read_to_string(&p).unwrap();
                let ast = engine.compile(&src).unwrap();
                let found = dropped_results(&ast, &src);
                assert!(found.is_empty(), "{}: {}", p.display(), format_warnings("", &src, &found));
                checked += 1;
            }
        }
        assert!(checked > 40, "{checked}");
    }
}
