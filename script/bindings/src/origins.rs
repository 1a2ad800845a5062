//! Call sites on meshes: every mesh a recipe makes remembers the call that made it (the function,
//! file, line and column), and each of its faces keeps that through later operations — the
//! origin chain of the kernel's face parts ([`blocksmith_kernel::mesh::Origin`]), which the
//! studio follows from a clicked face back to the recipe line (`cylinder` at 12 → `-` at 14 →
//! `+` at 20).
//!
//! One hook for every function, the script API's and the recipe's own: before a recipe runs,
//! [`mark_call_sites`] wraps each call in its compiled form in `__made_at(call, name, file,
//! line, column)`, which stamps the call's site on the mesh the call returns (or on each mesh of
//! an array it returns) and hands back everything else unchanged. No function needs its call
//! context for it, so the dropped-result lint, which reads the functions' declarations and runs
//! on the recipe as written, judges them as before.
//!
//! What is marked: function calls, operators that may combine meshes (`+ - * / % & | ^`), and
//! each method call of a chain (`cube(2).translate(v).rotate(r)` records `cube`, `translate`,
//! `rotate`; splitting a chain after a method call changes nothing, since what a method call
//! returns is a new value either way). Left as they are: assignment targets, property and index
//! chains (`a.b.c()` may write back into `a.b`) and Rhai's keyword functions (`Fn`, `eval`,
//! `print`, …). A compound assignment to a variable (`m -= hole`, and `m = m - hole`, which
//! Rhai compiles to it) is followed by `m.__made_here(…)`, which stamps the variable in place,
//! so `+=` on an array still appends in place.
//! A call that hands back a mesh held elsewhere (`fn keep(m) { m }`) made nothing new and adds
//! no step. The bodies of the script's functions are marked too: a mesh made inside `fn part()`
//! records its line there, then `part` where it is called.
//!
//! The same pass makes each `catch (e)` begin with `e.__caught()`, which turns an error Rhai
//! raised itself (caught as an object map) into the message a run prints, explained: an unknown
//! property is caught as "Mesh has no property `volum` …", as it would be printed. A call that
//! finds no function is raised explained in the first place, wherever it is, by
//! [`crate::lookup_failure`].

use std::sync::Arc;

use blocksmith_kernel::mesh::Span;
use rhai::{
    ASTFlags, Array, BinaryExpr, Dynamic, Engine, Expr, FnCallExpr, ImmutableString, NativeCallContext, Position, Stmt,
    StmtBlock, AST, INT,
};

use crate::api::mesh::SharedMesh;

/// The name of the function the marked calls go through.
pub const MADE_AT: &str = "__made_at";

/// The name of the method a marked compound assignment (`m -= hole`) calls on its variable.
pub const MADE_HERE: &str = "__made_here";

/// The name of the method a marked `catch (e)` calls on its variable first.
pub const CAUGHT: &str = "__caught";

/// Registers [`MADE_AT`], [`MADE_HERE`] and [`CAUGHT`] on `engine` (the catalogue and the
/// reference leave `__` names out).
pub fn register(engine: &mut Engine) {
    engine.register_fn(MADE_AT, made_at);
    engine.register_fn(MADE_HERE, made_here);
    engine.register_fn(CAUGHT, explain_caught);
}

/// `e.__caught()`: a Rhai error caught by `catch (e)` (an object map with `error`, `message`,
/// `line`...) becomes the message a run prints for it, a lookup failure explained
/// ([`crate::explain`]: "catmull_clark(Mesh, float) matches no signature of …"), so what a
/// recipe catches reads as what it would be told. The script API's own errors, and whatever a
/// recipe throws, are caught as they were thrown.
fn explain_caught(ctx: NativeCallContext, value: &mut Dynamic) {
    let Some(map) = value.read_lock::<rhai::Map>() else { return };
    let text = |key: &str| map.get(key).and_then(|v| v.read_lock::<ImmutableString>().map(|s| s.to_string()));
    let (Some(kind), Some(message)) = (text("error"), text("message")) else { return };
    if !kind.starts_with("Error") {
        return;
    }
    drop(map);
    *value = crate::explain::explain(ctx.engine(), &message).into();
}

/// `variable.__caught()`.
fn caught(variable: Expr, pos: Position) -> Stmt {
    let call = CAUGHT_TEMPLATE.with(Clone::clone);
    let dot = BinaryExpr { lhs: variable, rhs: Expr::MethodCall(call.into(), pos) };
    Stmt::Expr(Expr::Dot(dot.into(), ASTFlags::empty(), pos).into())
}

/// `x.__made_here(call, file, line, column)`: records the call's site on `x` in place.
fn made_here(value: &mut Dynamic, call: ImmutableString, file: ImmutableString, line: INT, column: INT) {
    *value = made_at(std::mem::take(value), call, file, line, column);
}

/// `__made_at(value, call, file, line, column)`: `value` with the call's site recorded on it.
fn made_at(value: Dynamic, call: ImmutableString, file: ImmutableString, line: INT, column: INT) -> Dynamic {
    let span = Span {
        file: (!file.is_empty()).then(|| Arc::from(file.as_str())),
        line: u32::try_from(line).unwrap_or(0),
        column: u32::try_from(column).unwrap_or(0),
    };
    stamp(value, &call, &span)
}

/// `value` with `call` at `span` recorded as the newest step of its mesh's origin chain, or of
/// each mesh of an array; other values unchanged.
pub fn stamp(value: Dynamic, call: &str, span: &Span) -> Dynamic {
    if value.is_shared() {
        // A captured variable: its mesh is held elsewhere too.
        return value;
    }
    if value.is::<SharedMesh>() {
        let mut mesh = value.cast::<SharedMesh>();
        if let Some(m) = Arc::get_mut(&mut mesh.0) {
            m.record_origin(call, span.clone());
        }
        return Dynamic::from(mesh);
    }
    if value.is_array() {
        let mut items = value.cast::<Array>();
        for item in &mut items {
            if item.is::<SharedMesh>() && !item.is_shared() {
                *item = stamp(std::mem::take(item), call, span);
            }
        }
        return Dynamic::from_array(items);
    }
    value
}

/// `ast` with every call that may make a mesh marked, and every `catch (e)` explaining `e`
/// (see the module's doc), at the top level and in the bodies of the script's own functions
/// and closures: a mesh made inside `fn part()` remembers its line there, and then the call of
/// `part` at its own line. The file is the script's name as errors give it (the AST's source).
///
/// A call that cannot make a mesh is left as it is, so that arithmetic in a loop costs what it
/// did: a function or method of `engine` whose every overload returns something that holds no
/// mesh (`sin`, `len`, `volume`, Vec3 arithmetic; see [`never_makes_a_mesh`]), and an operator
/// with a literal operand (no operator takes a mesh and a literal). The script's own functions
/// and closures may return anything, and are marked.
#[must_use]
pub fn mark_call_sites(engine: &Engine, ast: &AST) -> AST {
    let file: ImmutableString = ast.source().unwrap_or_default().into();
    let marker = Marker { file, never_mesh: never_makes_a_mesh(engine) };
    let statements: Vec<Stmt> = ast.statements().iter().cloned().map(|s| marker.stmt(s)).collect();
    let mut functions = rhai::Module::new();
    for (.., def) in ast.shared_lib().iter_script_fn_info() {
        let mut def = rhai::ScriptFuncDef::clone(def);
        #[allow(irrefutable_let_patterns)] // one variant without rhai's `grain` feature
        if let rhai::ScriptFuncPayload::Statements(body) = &mut def.body {
            marker.block(body);
        }
        functions.set_script_fn(def);
    }
    let mut marked = AST::new(statements, functions);
    if let Some(source) = ast.source() {
        marked.set_source(source);
    }
    marked
}

/// Rhai's keyword functions, whose calls are evaluated specially (in the caller's scope, or
/// as a print), and which make no mesh.
pub(crate) const KEYWORDS: &[&str] =
    &["Fn", "call", "curry", "eval", "print", "debug", "type_of", "is_def_var", "is_def_fn", "is_shared", "this"];

/// Operators that may take meshes and make one.
const MESH_OPERATORS: &[&str] = &["+", "-", "*", "/", "%", "&", "|", "^"];

struct Marker {
    file: ImmutableString,
    /// Names of functions, methods and operators that never return a mesh.
    never_mesh: std::collections::HashSet<ImmutableString>,
}

/// The names whose every overload registered on `engine` returns a type that holds no mesh
/// (what [`stamp`] stamps: a `Mesh`, or an array of them; `any` may be either). Script-defined
/// functions are not registered and never in the set.
#[must_use]
pub fn never_makes_a_mesh(engine: &Engine) -> std::collections::HashSet<ImmutableString> {
    let may = |returns: &str| returns.contains("Mesh") || returns.contains("array") || returns == "any";
    let mut by_name: std::collections::HashMap<&str, bool> = std::collections::HashMap::new();
    let catalogue = crate::catalogue::of(engine);
    for o in catalogue.iter() {
        *by_name.entry(o.name.as_str()).or_insert(false) |= may(&o.returns);
    }
    by_name.into_iter().filter(|(_, may)| !may).map(|(name, _)| name.into()).collect()
}

/// Whether `e` is a literal (no mesh operator takes one).
fn is_literal(e: &Expr) -> bool {
    matches!(
        e,
        Expr::IntegerConstant(..)
            | Expr::FloatConstant(..)
            | Expr::StringConstant(..)
            | Expr::BoolConstant(..)
            | Expr::CharConstant(..)
            | Expr::Unit(..)
    )
}

impl Marker {
    fn block(&self, block: &mut StmtBlock) {
        let statements = block.statements_mut();
        for s in statements.iter_mut() {
            let taken = std::mem::replace(s, Stmt::Noop(Position::NONE));
            *s = self.stmt(taken);
        }
    }

    fn stmt(&self, stmt: Stmt) -> Stmt {
        match stmt {
            Stmt::If(mut x, pos) => {
                self.flow(&mut x);
                Stmt::If(x, pos)
            }
            Stmt::While(mut x, pos) => {
                self.flow(&mut x);
                Stmt::While(x, pos)
            }
            Stmt::Do(mut x, flags, pos) => {
                self.flow(&mut x);
                Stmt::Do(x, flags, pos)
            }
            Stmt::For(mut x, pos) => {
                self.flow(&mut x.2);
                Stmt::For(x, pos)
            }
            Stmt::TryCatch(mut x, pos) => {
                self.flow(&mut x);
                // `catch (e)`: `e` is first turned into the message a run would print.
                if let Expr::Variable(..) = &x.expr {
                    let explain = caught(x.expr.clone(), x.expr.position());
                    x.branch.statements_mut().insert(0, explain);
                }
                Stmt::TryCatch(x, pos)
            }
            Stmt::Var(mut x, flags, pos) => {
                x.1 = self.expr(std::mem::replace(&mut x.1, Expr::Unit(Position::NONE)));
                Stmt::Var(x, flags, pos)
            }
            Stmt::Assignment(mut x) => {
                // The target stays as written; only the value is marked.
                x.1.rhs = self.expr(std::mem::replace(&mut x.1.rhs, Expr::Unit(Position::NONE)));
                let op = x.0.get_op_assignment_info().map(|info| info.5).filter(|op| MESH_OPERATORS.contains(op));
                // A value left unmarked (a literal, or a call that makes no mesh) adds no mesh.
                let adds_mesh = match &x.1.rhs {
                    Expr::FnCall(call, _) => call.name == MADE_AT || KEYWORDS.contains(&call.name.as_str()),
                    e => !is_literal(e),
                };
                match (op.filter(|_| adds_mesh), &x.1.lhs) {
                    (Some(op), target @ Expr::Variable(..)) => {
                        let pos = x.0.position();
                        let after = self.wrap_in_place(target.clone(), op.into(), pos);
                        Stmt::Block(StmtBlock::new([Stmt::Assignment(x), after], pos, pos).into())
                    }
                    _ => Stmt::Assignment(x),
                }
            }
            Stmt::FnCall(call, pos) => match self.expr(Expr::FnCall(call, pos)) {
                Expr::FnCall(call, pos) => Stmt::FnCall(call, pos),
                other => Stmt::Expr(other.into()),
            },
            Stmt::Block(mut b) => {
                self.block(&mut b);
                Stmt::Block(b)
            }
            Stmt::Expr(e) => Stmt::Expr(self.expr(*e).into()),
            Stmt::Return(Some(e), flags, pos) => Stmt::Return(Some(self.expr(*e).into()), flags, pos),
            Stmt::BreakLoop(Some(e), flags, pos) => Stmt::BreakLoop(Some(self.expr(*e).into()), flags, pos),
            Stmt::Switch(mut x, pos) => {
                x.0 = self.expr(std::mem::replace(&mut x.0, Expr::Unit(Position::NONE)));
                for case in &mut x.1.expressions {
                    case.rhs = self.expr(std::mem::replace(&mut case.rhs, Expr::Unit(Position::NONE)));
                }
                Stmt::Switch(x, pos)
            }
            other => other,
        }
    }

    fn flow(&self, flow: &mut rhai::FlowControl) {
        flow.expr = self.expr(std::mem::replace(&mut flow.expr, Expr::Unit(Position::NONE)));
        self.block(&mut flow.body);
        self.block(&mut flow.branch);
    }

    fn exprs(&self, list: impl Iterator<Item = Expr>) -> Vec<Expr> {
        list.map(|e| self.expr(e)).collect()
    }

    fn expr(&self, expr: Expr) -> Expr {
        match expr {
            Expr::FnCall(mut call, pos) => {
                let args = std::mem::take(&mut call.args);
                call.args = self.exprs(args.into_iter()).into_iter().collect();
                let marked = !KEYWORDS.contains(&call.name.as_str())
                    && (call.op_token.is_none()
                        || (MESH_OPERATORS.contains(&call.name.as_str()) && !call.args.iter().any(is_literal)));
                if marked {
                    let name = call.name.clone();
                    self.wrap(Expr::FnCall(call, pos), name, pos)
                } else {
                    Expr::FnCall(call, pos)
                }
            }
            Expr::Dot(x, flags, pos) => self.chain(*x, flags, pos, true),
            Expr::Array(items, pos) => Expr::Array(self.exprs(items.into_iter()).into_iter().collect(), pos),
            Expr::InterpolatedString(items, pos) => {
                Expr::InterpolatedString(self.exprs(items.into_iter()).into_iter().collect(), pos)
            }
            Expr::Map(mut x, pos) => {
                for (_, value) in &mut x.0 {
                    *value = self.expr(std::mem::replace(value, Expr::Unit(Position::NONE)));
                }
                Expr::Map(x, pos)
            }
            Expr::Stmt(mut block) => {
                self.block(&mut block);
                Expr::Stmt(block)
            }
            Expr::And(mut x, pos) => {
                for e in x.iter_mut() {
                    *e = self.expr(std::mem::replace(e, Expr::Unit(Position::NONE)));
                }
                Expr::And(x, pos)
            }
            Expr::Or(mut x, pos) => {
                for e in x.iter_mut() {
                    *e = self.expr(std::mem::replace(e, Expr::Unit(Position::NONE)));
                }
                Expr::Or(x, pos)
            }
            Expr::Coalesce(mut x, pos) => {
                for e in x.iter_mut() {
                    *e = self.expr(std::mem::replace(e, Expr::Unit(Position::NONE)));
                }
                Expr::Coalesce(x, pos)
            }
            other => other,
        }
    }

    /// A `.` chain `root.link.rest`: the root marked as any expression, then split after each
    /// leading method call, each part marked; a chain that reaches a property or an index is
    /// left whole from there on (its method calls' arguments still marked).
    /// `mark_root`: whether the root is still to be marked (not when it is the marked head of a
    /// chain already split).
    fn chain(&self, x: BinaryExpr, flags: ASTFlags, pos: Position, mark_root: bool) -> Expr {
        let BinaryExpr { lhs, rhs } = x;
        // Rhai holds a variable a chain starts from until the chain ends, so an argument that
        // reads it fails (a data race). Split, the chain would let go of it early and such a
        // recipe would run here and fail elsewhere: such a chain is marked whole.
        let held = match &lhs {
            Expr::Variable(v, ..) if mentions(&rhs, &v.1) => true,
            Expr::ThisPtr(..) if mentions_this(&rhs) => true,
            _ => false,
        };
        let root = match lhs {
            // A property or variable root is a place the chain may write back to.
            e @ (Expr::Variable(..) | Expr::ThisPtr(..) | Expr::Property(..)) => e,
            e if mark_root => self.expr(e),
            e => e,
        };
        if held {
            let last = last_method(&rhs);
            let whole = Expr::Dot(BinaryExpr { lhs: root, rhs }.into(), flags, pos);
            return match last {
                Some((name, call_pos)) => self.wrap(whole, name, call_pos),
                None => whole,
            };
        }
        match rhs {
            Expr::MethodCall(call, call_pos) => {
                let call = self.method_args(call);
                let name = call.name.clone();
                let whole =
                    Expr::Dot(BinaryExpr { lhs: root, rhs: Expr::MethodCall(call, call_pos) }.into(), flags, pos);
                self.wrap(whole, name, call_pos)
            }
            Expr::Dot(inner, inner_flags, inner_pos) if matches!(inner.lhs, Expr::MethodCall(..)) => {
                let BinaryExpr { lhs: Expr::MethodCall(call, call_pos), rhs: rest } = *inner else {
                    unreachable!("matched a method call")
                };
                let call = self.method_args(call);
                let name = call.name.clone();
                let head =
                    Expr::Dot(BinaryExpr { lhs: root, rhs: Expr::MethodCall(call, call_pos) }.into(), flags, pos);
                let head = self.wrap(head, name, call_pos);
                self.chain(BinaryExpr { lhs: head, rhs: rest }, inner_flags, inner_pos, false)
            }
            rest => Expr::Dot(BinaryExpr { lhs: root, rhs: rest }.into(), flags, pos),
        }
    }

    fn method_args(&self, mut call: Box<FnCallExpr>) -> Box<FnCallExpr> {
        let args = std::mem::take(&mut call.args);
        call.args = self.exprs(args.into_iter()).into_iter().collect();
        call
    }

    /// The arguments naming a call's site: `name, file, line, column`.
    fn site(&self, name: ImmutableString, pos: Position) -> [Expr; 4] {
        let (line, column) = (pos.line().unwrap_or(0), pos.position().unwrap_or(0));
        [
            Expr::StringConstant(name, pos),
            Expr::StringConstant(self.file.clone(), pos),
            Expr::IntegerConstant(line as INT, pos),
            Expr::IntegerConstant(column as INT, pos),
        ]
    }

    /// `__made_at(e, name, file, line, column)`.
    fn wrap(&self, e: Expr, name: ImmutableString, pos: Position) -> Expr {
        if self.never_mesh.contains(&name) {
            return e;
        }
        let mut call = TEMPLATE.with(Clone::clone);
        call.args = std::iter::once(e).chain(self.site(name, pos)).collect();
        Expr::FnCall(call.into(), pos)
    }
}

/// Whether `e` reads the variable `name` anywhere (closures' captures included).
fn mentions(e: &Expr, name: &str) -> bool {
    !e.walk(&mut Vec::new(), &mut |path: &[rhai::ASTNode]| {
        !matches!(path.last(), Some(rhai::ASTNode::Expr(Expr::Variable(v, ..))) if v.1 == name)
    })
}

/// Whether `e` reads `this` anywhere.
fn mentions_this(e: &Expr) -> bool {
    !e.walk(&mut Vec::new(), &mut |path: &[rhai::ASTNode]| {
        !matches!(path.last(), Some(rhai::ASTNode::Expr(Expr::ThisPtr(..))))
    })
}

/// The name and place of the method call a chain ends with, if it ends with one.
fn last_method(rhs: &Expr) -> Option<(ImmutableString, Position)> {
    match rhs {
        Expr::MethodCall(call, pos) => Some((call.name.clone(), *pos)),
        Expr::Dot(x, ..) => last_method(&x.rhs),
        _ => None,
    }
}

impl Marker {
    /// `variable.__made_here(name, file, line, column)`.
    fn wrap_in_place(&self, variable: Expr, name: ImmutableString, pos: Position) -> Stmt {
        let mut call = IN_PLACE.with(Clone::clone);
        call.args = self.site(name, pos).into_iter().collect();
        let dot = BinaryExpr { lhs: variable, rhs: Expr::MethodCall(call.into(), pos) };
        Stmt::Expr(Expr::Dot(dot.into(), ASTFlags::empty(), pos).into())
    }
}

/// The method call a script `let x = 0; x.METHOD(…)` compiles to, as the parser makes it (its
/// name and hashes).
fn method_call_template(script: &str) -> FnCallExpr {
    let ast = Engine::new_raw().compile(script).expect("the marker call compiles");
    let found = match ast.statements().get(1) {
        Some(Stmt::Expr(e)) => match &**e {
            Expr::Dot(x, ..) => match &x.rhs {
                Expr::MethodCall(call, _) => Some((**call).clone()),
                _ => None,
            },
            _ => None,
        },
        _ => None,
    };
    found.unwrap_or_else(|| unreachable!("the marker method call compiles to a method call: {ast:?}"))
}

thread_local! {
    /// A compiled method call of [`CAUGHT`] without arguments.
    static CAUGHT_TEMPLATE: FnCallExpr = method_call_template(&format!("let x = 0; x.{CAUGHT}()"));

    /// A compiled method call of [`MADE_HERE`] with four arguments.
    static IN_PLACE: FnCallExpr = method_call_template(&format!("let x = 0; x.{MADE_HERE}(\"\", \"\", 0, 0)"));

    /// A compiled call of [`MADE_AT`] with five arguments: its name and hashes, as the parser
    /// computes them.
    static TEMPLATE: FnCallExpr = {
        let ast = Engine::new_raw()
            .compile(format!("{MADE_AT}((), \"\", \"\", 0, 0)"))
            .expect("the marker call compiles");
        match ast.statements().first() {
            Some(Stmt::FnCall(call, _)) => (**call).clone(),
            Some(Stmt::Expr(e)) => match &**e {
                Expr::FnCall(call, _) => (**call).clone(),
                other => unreachable!("the marker call compiles to a call, not {other:?}"),
            },
            other => unreachable!("the marker call compiles to a call, not {other:?}"),
        }
    };
}

#[cfg(test)]
#[path = "tests_origins.rs"]
mod tests;
