//! `blocksmith repl`: an interactive session. Definitions persist between entries; Ctrl-C stops
//! a running evaluation and keeps the session; Ctrl-D exits. Works with piped standard input too.

pub mod complete;
pub mod input;

use std::collections::BTreeMap;
use std::io::Write;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use rhai::{Dynamic, Engine, Position, Scope, AST};
use rustyline::completion::{Completer, Pair};
use rustyline::error::ReadlineError;
use rustyline::history::DefaultHistory;
use rustyline::validate::{ValidationContext, ValidationResult, Validator};
use rustyline::{CompletionType, Config, Context, Editor, Helper, Highlighter, Hinter};

use blocksmith_script::catalogue::{self, Overload};
use blocksmith_script::context::{RunContext, Shown};
use blocksmith_script::diagnostics::{format_error, format_parse_error, format_run_warnings};
use blocksmith_script::run::{compile_file, describe, save_value};
use blocksmith_script::{doc, new_engine, EngineOptions};
use blocksmith_studio::{self as studio, scene::Scene};

const HELP: &str = "\
Enter Rhai statements; the value of the last one is shown. Definitions persist.
Commands:
  :help          this text
  :doc NAME      the reference of a function (`:doc` alone lists everything)
  :load FILE     run a script in this session (its functions and variables stay)
  :save PATH [EXPR]
                 write EXPR's value (or the last value) to PATH by extension and say
                 which value it wrote; quote a PATH with spaces: :save \"my part.stl\" m
  :show [EXPR]   show EXPR (or the last value) in the studio page, started on first use;
                 show(value) in code does the same
  :quit          leave (Ctrl-D too)
Ctrl-C stops a running evaluation; Tab completes names, after `x.` the methods and
properties of x's type, after `alias::` what an imported module offers; an unfinished entry
(open brackets or string) continues at `..>`.";

/// The prompt of a new entry.
const PROMPT: &str = "bs> ";
/// The prompt of an entry's next line while it is unfinished ([`input::unfinished`]).
const CONTINUE: &str = "..> ";

/// Completion ([`complete`]). Piped input gathers an unfinished entry's lines in rustyline's
/// validator; a terminal gathers them in [`read_entry`], with the continuation prompt.
#[derive(Helper, Highlighter, Hinter)]
struct ReplHelper {
    known: complete::Known,
    /// The session engine's functions.
    catalogue: std::rc::Rc<[Overload]>,
    gather_lines: bool,
}

impl Completer for ReplHelper {
    type Candidate = Pair;
    fn complete(&self, line: &str, pos: usize, _ctx: &Context<'_>) -> rustyline::Result<(usize, Vec<Pair>)> {
        let (start, found) = complete::candidates(&self.known, &self.catalogue, line, pos);
        Ok((start, found.into_iter().map(|n| Pair { display: n.clone(), replacement: n }).collect()))
    }
}

impl Validator for ReplHelper {
    fn validate(&self, ctx: &mut ValidationContext) -> rustyline::Result<ValidationResult> {
        Ok(if self.gather_lines && input::open_brackets(ctx.input()) > 0 {
            ValidationResult::Incomplete
        } else {
            ValidationResult::Valid(None)
        })
    }
}

/// One entry from a terminal: a line, and while it is unfinished, more lines read with the
/// continuation prompt. Ctrl-C drops the unfinished entry; Ctrl-D ends it (and the session).
fn read_entry(editor: &mut Editor<ReplHelper, DefaultHistory>) -> Result<String, ReadlineError> {
    let mut entry = editor.readline(PROMPT)?;
    while input::unfinished(&entry) {
        match editor.readline(CONTINUE) {
            Ok(more) => {
                entry.push('\n');
                entry.push_str(&more);
            }
            Err(ReadlineError::Eof) => break,
            Err(e) => return Err(e),
        }
    }
    Ok(entry)
}

/// `(path, alias)` of each `import "path" as alias;` in an entry.
fn imports_of(entry: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut rest = entry;
    while let Some(i) = rest.find("import") {
        let after = &rest[i + "import".len()..];
        rest = after;
        let a = after.trim_start();
        let Some(q) = a.strip_prefix('"') else { continue };
        let Some(end) = q.find('"') else { continue };
        let path = &q[..end];
        let tail = q[end + 1..].trim_start();
        let Some(tail) = tail.strip_prefix("as") else { continue };
        let alias: String = tail.trim_start().chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
        if !alias.is_empty() {
            out.push((path.to_string(), alias));
        }
    }
    out
}

/// `:save`'s argument as `(path, expression)`: the path is the first word, or a quoted
/// string (`"my part.stl"`); the rest, trimmed, is the expression (empty for the last value).
fn split_path(arg: &str) -> (&str, &str) {
    let arg = arg.trim();
    if let Some(quoted) = arg.strip_prefix('"') {
        if let Some(end) = quoted.find('"') {
            return (&quoted[..end], quoted[end + 1..].trim());
        }
    }
    arg.split_once(char::is_whitespace).map_or((arg, ""), |(p, e)| (p, e.trim()))
}

/// One REPL session: the engine, the variables, the functions defined so far and the last value.
pub struct Session {
    engine: Engine,
    scope: Scope<'static>,
    functions: AST,
    last: Dynamic,
    interrupt: Arc<AtomicBool>,
    /// Values passed to `show` by the entry being evaluated.
    shown: Shown,
    /// The studio page, once something was shown: its session and address.
    studio: Option<(Arc<studio::session::Session>, String)>,
    /// Whether the first show opens the page in the browser (an interactive session).
    pub open_page: bool,
    /// Whether the page was opened in a browser.
    opened: bool,
    /// The dropped results of the entry being evaluated and the warnings it gave as it ran.
    warnings: Vec<String>,
    /// The limits each entry runs under (a fresh count and deadline per entry).
    limits: EngineOptions,
    /// The names each module imported so far offers, by alias, for completion after `alias::`.
    modules: BTreeMap<String, Vec<String>>,
}

impl Session {
    /// A new session; `interrupt` stops a running evaluation when set.
    #[cfg(test)]
    #[must_use]
    pub fn new(interrupt: Arc<AtomicBool>) -> Session {
        Session::with_limits(interrupt, None, None)
    }

    /// A new session whose entries each stop after `max_operations` operations or `timeout`.
    #[must_use]
    pub fn with_limits(interrupt: Arc<AtomicBool>, max_operations: Option<u64>, timeout: Option<Duration>) -> Session {
        let cwd = std::env::current_dir().ok();
        let shown = Shown::default();
        let context = RunContext { script_dir: cwd, shown: Some(shown.clone()), ..RunContext::default() };
        let limits = EngineOptions {
            context,
            max_operations,
            timeout,
            interrupt: Some(interrupt.clone()),
            progress: crate::progress_bars::on_terminal(),
        };
        let engine = new_engine(limits.clone());
        Session {
            engine,
            scope: Scope::new(),
            functions: AST::empty(),
            last: Dynamic::UNIT,
            interrupt,
            shown,
            studio: None,
            open_page: false,
            opened: false,
            warnings: Vec::new(),
            limits,
            modules: BTreeMap::new(),
        }
    }

    /// The functions of the session's engine, for completion.
    #[must_use]
    pub fn catalogue(&self) -> std::rc::Rc<[Overload]> {
        catalogue::of(&self.engine)
    }

    /// What completion knows now: names, the variables' types and maps' keys, the folder.
    #[must_use]
    pub fn known(&self) -> complete::Known {
        let mut known = complete::Known {
            names: self.names(),
            dir: std::env::current_dir().unwrap_or_default(),
            ..complete::Known::default()
        };
        for (name, _, value) in self.scope.iter() {
            known.variables.insert(name.to_string(), complete::script_type_of(&self.engine, &value));
            if let Some(map) = value.read_lock::<rhai::Map>() {
                known.keys.insert(name.to_string(), map.keys().map(ToString::to_string).collect());
            }
        }
        known.modules = self.modules.clone();
        known
    }

    /// Names for completion: functions, types and the session's variables.
    #[must_use]
    pub fn names(&self) -> Vec<String> {
        let mut n = doc::names(&self.engine);
        n.extend(self.scope.iter().map(|(name, _, _)| name.to_string()));
        n.extend(
            ["Vec3", "Mesh", "let", "const", "fn", "import", "for", "while", "loop", "if", "else", "return"]
                .map(String::from),
        );
        n.sort();
        n.dedup();
        n
    }

    /// Handles one entry (a command or code) and returns what to print; `None` to quit.
    pub fn handle(&mut self, entry: &str) -> Option<String> {
        let t = entry.trim();
        if t.is_empty() {
            return Some(String::new());
        }
        if let Some(cmd) = t.strip_prefix(':') {
            let (name, arg) = cmd.split_once(char::is_whitespace).map_or((cmd, ""), |(a, b)| (a, b.trim()));
            return match name {
                "quit" | "q" | "exit" => None,
                "help" | "h" => Some(HELP.to_string()),
                "doc" => Some(doc::render(&self.engine, (!arg.is_empty()).then_some(arg)).unwrap_or_else(|e| e)),
                "load" if !arg.is_empty() => Some(self.load(arg)),
                "save" if !arg.is_empty() => Some(self.save_command(arg)),
                "load" | "save" => Some(format!(":{name} needs a path")),
                "show" => Some(self.show_command(arg)),
                _ => Some(format!("unknown command :{name} (try :help)")),
            };
        }
        let out = self.eval(entry, "<repl>");
        Some(self.with_shown(out))
    }

    /// `out`, followed by what showing the values passed to `show` says, if there were any.
    fn with_shown(&mut self, out: String) -> String {
        let values = self.shown.take();
        if values.is_empty() {
            return out;
        }
        let said = self.show_values(values);
        if out.is_empty() {
            said
        } else {
            format!("{out}\n{said}")
        }
    }

    /// `:save PATH [EXPR]`: writes the value of `EXPR` (or the last value) to `PATH` and says
    /// which value it wrote, so a save of the wrong value does not pass unnoticed.
    fn save_command(&mut self, arg: &str) -> String {
        let (path, expr) = split_path(arg);
        if path.is_empty() {
            return ":save needs a path: `:save PATH [EXPR]`".into();
        }
        let (value, from) = if expr.is_empty() {
            if self.last.is_unit() {
                return format!(
                    "nothing to save to {path}: evaluate a value first, or name one (`:save {path} cube(1)`)"
                );
            }
            (self.last.clone(), "the last value".to_string())
        } else {
            match self.eval_value(expr, "<repl>") {
                Ok(v) if v.is_unit() => return format!("nothing to save to {path}: `{expr}` has no value"),
                Ok(v) => (v, format!("`{expr}`")),
                Err(e) => return e,
            }
        };
        let what = describe(&self.engine, &value);
        self.interrupt.store(false, Ordering::SeqCst);
        blocksmith_script::set_limits(&mut self.engine, &self.limits);
        match save_value(&self.engine, &self.functions, value, &PathBuf::from(path)) {
            Ok(()) => format!("wrote {path}: {from}, {what}"),
            Err(e) => e.0,
        }
    }

    /// `:show [EXPR]`: the value of `EXPR`, or the last value, on the studio page.
    fn show_command(&mut self, arg: &str) -> String {
        if arg.is_empty() {
            return self.show_values(vec![self.last.clone()]);
        }
        match self.eval_value(arg, "<repl>") {
            Ok(v) => {
                // Values passed to `show` inside the expression are shown with it.
                let mut values = self.shown.take();
                values.push(v);
                self.show_values(values)
            }
            Err(e) => {
                drop(self.shown.take());
                e
            }
        }
    }

    /// Shows `values` (one: as it is; several: as layers `[0]`, `[1]`, ...) on the studio
    /// page, starting it on first use.
    fn show_values(&mut self, mut values: Vec<Dynamic>) -> String {
        let value = if values.len() == 1 { values.pop().unwrap_or_default() } else { Dynamic::from_array(values) };
        if value.is_unit() {
            return "nothing to show: give an expression (`:show cube(1)`) or evaluate a value first".into();
        }
        let layers = match studio::scene::layers(&self.engine, &self.functions, value) {
            Ok(l) => l,
            Err(e) => return e.0,
        };
        let first = self.studio.is_none();
        let (session, url) = match self.studio() {
            Ok(s) => s,
            Err(e) => return e,
        };
        let count = layers.len();
        let triangles: usize = layers.iter().map(|l| l.mesh.triangle_count()).sum();
        session.show(Scene { layers, run_time: std::time::Duration::ZERO, params: Vec::new(), warnings: Vec::new() });
        let layers = if count == 1 { String::new() } else { format!("{count} layers, ") };
        let mut said = format!("shown at {url} ({layers}{triangles} triangles)");
        if first && !self.opened {
            // Once, quietly: the page is not open anywhere yet.
            said.push_str("\n(open the address in a browser; every value shown goes to that page)");
        }
        said
    }

    /// The studio's session and address, starting its server (127.0.0.1, any free port, a
    /// token of its own) on first use.
    fn studio(&mut self) -> Result<(Arc<studio::session::Session>, String), String> {
        if let Some(s) = &self.studio {
            return Ok(s.clone());
        }
        let session = studio::session::Session::for_values("repl");
        let server = studio::server::Studio::bind(0)?;
        let url = server.url();
        let served = Arc::clone(&session);
        std::thread::spawn(move || {
            if let Err(e) = server.serve(&served) {
                eprintln!("{e}");
            }
        });
        self.opened = self.open_page && studio::open_browser(&url).is_ok();
        self.studio = Some((Arc::clone(&session), url.clone()));
        Ok((session, url))
    }

    fn eval(&mut self, source: &str, name: &str) -> String {
        let out = match self.eval_value(source, name) {
            Ok(v) if v.is_unit() => String::new(),
            Ok(v) => format!("=> {}", describe(&self.engine, &v)),
            Err(e) => e,
        };
        self.with_warnings(out)
    }

    /// The entry's dropped results ([`blocksmith_script::lint`]) as warnings; the session's variables
    /// give their receivers' types. An entry ending in `;` only shows its last value, so that
    /// one counts as dropped too.
    fn dropped_results(&self, ast: &AST, source: &str, name: &str) -> Vec<String> {
        let known: Vec<(String, String)> =
            self.scope.iter().map(|(n, _, v)| (n.to_string(), v.type_name().to_string())).collect();
        blocksmith_script::lint::dropped_results_knowing(
            ast,
            source,
            known.iter().map(|(n, t)| (n.as_str(), t.as_str())),
            !source.trim_end().ends_with(';'),
        )
        .iter()
        .map(|d| blocksmith_script::diagnostics::format_warning(name, source, d.position, &d.message))
        .chain(blocksmith_script::lint::imported_warnings(&self.engine, ast, None))
        .collect()
    }

    /// The last entry's warnings, then `out`.
    fn with_warnings(&mut self, out: String) -> String {
        let mut lines = std::mem::take(&mut self.warnings);
        if !out.is_empty() {
            lines.push(out);
        }
        lines.join("\n")
    }

    /// Evaluates `source` in the session; a value that is not nothing becomes the last value.
    fn eval_value(&mut self, source: &str, name: &str) -> Result<Dynamic, String> {
        let ast =
            self.engine.compile_with_scope(&self.scope, source).map_err(|e| format_parse_error(name, source, &e))?;
        self.run_ast(ast, source, name)
    }

    fn run_ast(&mut self, ast: AST, source: &str, name: &str) -> Result<Dynamic, String> {
        self.warnings = self.dropped_results(&ast, source, name);
        let merged = self.functions.merge(&blocksmith_script::origins::mark_call_sites(&self.engine, &ast));
        self.interrupt.store(false, Ordering::SeqCst);
        blocksmith_script::set_limits(&mut self.engine, &self.limits);
        let result = self.engine.eval_ast_with_scope::<Dynamic>(&mut self.scope, &merged);
        // What the entry warned of as it ran (blocks that touch without connecting), after the lint's.
        self.warnings.extend(format_run_warnings(&self.limits.context.warnings.take(), name, source));
        self.functions = merged;
        self.functions.clear_statements();
        match result {
            Ok(v) => {
                self.keep_imports(source);
                if !v.is_unit() {
                    self.last = v.clone();
                }
                Ok(v)
            }
            Err(e) => Err(format_error(&self.engine, name, source, &e)),
        }
    }

    /// Imports are evaluated into the engine as static modules so later entries can use them.
    fn keep_imports(&mut self, source: &str) {
        for (path, alias) in imports_of(source) {
            let resolved = self.engine.module_resolver().resolve(&self.engine, None, &path, Position::NONE);
            if let Ok(module) = resolved {
                self.modules.insert(alias.clone(), module_names(&module));
                self.engine.register_static_module(alias, module);
            }
        }
    }

    fn load(&mut self, path: &str) -> String {
        let out = match compile_file(&self.engine, &PathBuf::from(path)) {
            Ok((source, ast)) => match self.run_ast(ast, &source, path) {
                Ok(v) if v.is_unit() => String::new(),
                Ok(v) => format!("=> {}", describe(&self.engine, &v)),
                Err(e) => e,
            },
            Err(e) => e.0,
        };
        let out = self.with_warnings(out);
        self.with_shown(out)
    }
}

/// The functions and constants a module offers, sorted, each once.
fn module_names(module: &rhai::Module) -> Vec<String> {
    let functions = module.gen_fn_signatures_with_mapper(|t| t.into()).filter_map(|sig| {
        let name = sig.split('(').next()?.trim();
        let name = name.rsplit(' ').next()?;
        (!name.is_empty()).then(|| name.to_string())
    });
    let mut names: Vec<String> = functions.chain(module.iter_var().map(|(n, _)| n.to_string())).collect();
    names.sort();
    names.dedup();
    names
}

fn history_path() -> Option<PathBuf> {
    std::env::var_os("BLOCKSMITH_HISTORY")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".blocksmith_history")))
}

/// Runs the REPL on the terminal (or piped standard input) until `:quit` or end of input.
///
/// # Errors
/// When the terminal cannot be set up.
pub fn run(max_operations: Option<u64>, timeout: Option<Duration>) -> Result<(), String> {
    let interrupt = Arc::new(AtomicBool::new(false));
    let flag = interrupt.clone();
    // Ctrl-C while a script runs: stop it, keep the session. (While reading a line the
    // terminal is in raw mode and Ctrl-C reaches rustyline as a key instead.)
    let _ = ctrlc::set_handler(move || flag.store(true, Ordering::SeqCst));
    let mut session = Session::with_limits(interrupt, max_operations, timeout);
    session.open_page = std::io::IsTerminal::is_terminal(&std::io::stdin());
    let interactive = std::io::IsTerminal::is_terminal(&std::io::stdin());
    let config = Config::builder().completion_type(CompletionType::List).build();
    let mut editor: Editor<ReplHelper, DefaultHistory> =
        Editor::with_config(config).map_err(|e| format!("repl: {e}"))?;
    editor.set_helper(Some(ReplHelper {
        known: session.known(),
        catalogue: session.catalogue(),
        gather_lines: !interactive,
    }));
    let history = history_path();
    if let Some(h) = &history {
        let _ = editor.load_history(h);
    }
    println!("blocksmith {} — :help for help, Ctrl-D to exit", env!("CARGO_PKG_VERSION"));
    // Piped input: errors name their line of the input, and any failed entry fails the run.
    let (mut first_line, mut failed) = (1usize, 0usize);
    loop {
        let entry = if interactive { read_entry(&mut editor) } else { editor.readline(PROMPT) };
        match entry {
            Ok(line) => {
                let _ = editor.add_history_entry(line.as_str());
                let out = session.handle(&line);
                let lines_in = line.split('\n').count();
                match out {
                    None => break,
                    Some(out) if out.is_empty() => {}
                    Some(out) if interactive => println!("{out}"),
                    Some(out) => {
                        let out = renumbered(&out, first_line);
                        failed += usize::from(out.contains(": error: "));
                        println!("{out}");
                    }
                }
                first_line += lines_in;
                let _ = std::io::stdout().flush();
                if let Some(h) = editor.helper_mut() {
                    h.known = session.known();
                }
            }
            Err(ReadlineError::Interrupted) => println!("^C"),
            Err(ReadlineError::Eof) => break,
            Err(e) => return Err(format!("repl: {e}")),
        }
    }
    if let Some(h) = &history {
        let _ = editor.save_history(h);
    }
    if failed > 0 {
        return Err(format!("{failed} of the entries failed"));
    }
    Ok(())
}

/// `out` with each `<repl>:L:C:` of an entry starting at input line `first` written as
/// `<stdin>:LINE:C:`, the line counted in the whole input.
fn renumbered(out: &str, first: usize) -> String {
    out.lines()
        .map(|l| {
            let Some(rest) = l.strip_prefix("<repl>:") else { return l.to_string() };
            let Some((n, tail)) = rest.split_once(':') else { return l.to_string() };
            match n.parse::<usize>() {
                Ok(n) => format!("<stdin>:{}:{tail}", first + n - 1),
                Err(_) => l.to_string(),
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn session_keeps_variables_functions_and_imports() {
        let mut s = Session::new(Arc::new(AtomicBool::new(false)));
        assert_eq!(s.handle("fn double(x) { x * 2 }").unwrap(), "");
        assert_eq!(s.handle("let a = double(21);").unwrap(), "");
        assert_eq!(s.handle("a").unwrap(), "=> 42");
        assert!(s.handle("cube(2)").unwrap().contains("Mesh(8 vertices"));
        // A dropped result is a warning, and the entry still runs.
        s.handle("let c = cube(2);").unwrap();
        let w = s.handle("c.translate([1, 0, 0]);").unwrap();
        assert!(w.starts_with("<repl>:1:3: warning: the result of `translate` is dropped"), "{w}");
        assert_eq!(s.handle("c = c.translate([1, 0, 0]);").unwrap(), "");
        let err = s.handle("a.nope()").unwrap();
        assert!(err.starts_with("<repl>:1:"), "{err}");
        assert_eq!(s.handle("a + 1").unwrap(), "=> 43");
        assert!(s.handle(":quit").is_none());
    }

    #[test]
    fn imported_modules_complete_after_their_alias() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join("shapes.rhai"),
            "export const SIDE = 2;\nfn box_of(s) { cube(s) }\nfn bowl() { 1 }",
        )
        .unwrap();
        let mut s = Session::new(Arc::new(AtomicBool::new(false)));
        let path = dir.path().join("shapes").to_string_lossy().replace('\\', "/");
        assert_eq!(s.handle(&format!("import \"{path}\" as sh;")).unwrap(), "");
        let known = s.known();
        let cat = &*s.catalogue();
        assert_eq!(complete::candidates(&known, cat, "sh::bo", 6).1, ["bowl", "box_of"]);
        assert_eq!(complete::candidates(&known, cat, "sh::S", 5).1, ["SIDE"]);
        assert!(s.handle("sh::box_of(2)").unwrap().contains("Mesh(8 vertices"));
    }

    #[test]
    fn save_writes_the_expression_or_the_last_value_and_says_which() {
        let dir = tempfile::tempdir().unwrap();
        let at = |name: &str| dir.path().join(name).to_string_lossy().replace('\\', "/");
        let mut s = Session::new(Arc::new(AtomicBool::new(false)));
        let none = s.handle(&format!(":save {}", at("none.stl"))).unwrap();
        assert!(none.starts_with("nothing to save to "), "{none}");
        s.handle("let small = cube(1);").unwrap();
        s.handle("let big = cube(4);").unwrap();
        s.handle("big").unwrap();
        // An expression names the value; the answer says which value went where.
        let said = s.handle(&format!(":save {} small", at("small.stl"))).unwrap();
        assert!(said.starts_with(&format!("wrote {}: `small`, Mesh(8 vertices", at("small.stl"))), "{said}");
        let back = blocksmith_kernel::io::load(std::path::Path::new(&at("small.stl"))).unwrap();
        assert!((back.volume() - 1.0).abs() < 1e-6, "the small cube was written: {}", back.volume());
        // Without one, the last value, said so.
        let said = s.handle(&format!(":save {}", at("last.stl"))).unwrap();
        assert!(said.contains(": the last value, Mesh(8 vertices"), "{said}");
        // A quoted path with a space, then an expression.
        let said = s.handle(&format!(":save \"{}\" big.translate([1, 0, 0])", at("a b.stl"))).unwrap();
        assert!(said.contains("`big.translate([1, 0, 0])`"), "{said}");
        assert!(std::path::Path::new(&at("a b.stl")).exists());
        // A failing expression is reported at its place, nothing written.
        let err = s.handle(&format!(":save {} nope", at("nope.stl"))).unwrap();
        assert!(err.contains("nope") && !std::path::Path::new(&at("nope.stl")).exists(), "{err}");
        assert_eq!(split_path("out.glb  m.translate([1, 0, 0])"), ("out.glb", "m.translate([1, 0, 0])"));
        assert_eq!(split_path("\"a b.glb\""), ("a b.glb", ""));
    }

    #[test]
    fn save_of_a_value_that_cannot_be_saved_lists_each_savable_type_once() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = Session::new(Arc::new(AtomicBool::new(false)));
        let path = dir.path().join("x.glb").to_string_lossy().replace('\\', "/");
        let said = s.handle(&format!(":save {path} 42")).unwrap();
        assert!(said.contains("cannot be saved"), "{said}");
        let list = &said[said.find("one of ").expect("a list of types") + "one of ".len()..];
        let types: Vec<&str> = list.trim_end_matches(')').split(", ").collect();
        let mut unique = types.clone();
        unique.dedup();
        assert_eq!(types, unique, "{said}");
        assert!(types.contains(&"Mesh"), "{said}");
    }
}
