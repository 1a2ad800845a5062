//! The runner: the one way a recipe is run ([`run_recipe`]: `blocksmith run`, `params`,
//! `test`, `render`, the studio), and its value saved ([`save_value`]) or described
//! ([`describe`]).

use std::path::Path;
use std::time::{Duration, Instant};

use rhai::{Dynamic, Engine, Scope, AST};

use crate::diagnostics::{format_error, format_parse_error, format_run_warnings};
use crate::record::{Recorder, RunRecord};
use crate::spelling::did_you_mean;
use crate::{new_engine, EngineOptions};

/// A failed run, formatted for people (`file:line:col`, source line, caret, message).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RunError(pub String);

impl std::fmt::Display for RunError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// Reads and compiles `path` with `engine`; the AST's source is the path, so errors and imports
/// know where they are.
///
/// # Errors
/// The read or parse error, formatted.
pub fn compile_file(engine: &Engine, path: &Path) -> Result<(String, AST), RunError> {
    let name = path.display().to_string();
    let source =
        std::fs::read_to_string(path).map_err(|e| RunError(format!("{name}: error: cannot read the script: {e}")))?;
    let mut ast = engine.compile(&source).map_err(|e| RunError(format_parse_error(&name, &source, &e)))?;
    ast.set_source(name);
    Ok((source, ast))
}

/// Evaluates the script at `path` in a new engine made from `options` (its script directory
/// set to the script's) and returns its last value.
///
/// # Errors
/// A read, parse or runtime error, formatted.
pub fn run_file(path: &Path, options: EngineOptions) -> Result<Dynamic, RunError> {
    eval_file(path, options).map(|(value, _)| value)
}

/// As [`run_file`], also returning the script's compiled AST, whose functions (closures
/// included) the value may still need — see [`save_value`].
///
/// # Errors
/// A read, parse or runtime error, formatted.
pub fn eval_file(path: &Path, options: EngineOptions) -> Result<(Dynamic, AST), RunError> {
    let run = run_recipe(path, options)?;
    Ok((run.value, run.ast))
}

/// A finished run of a recipe: see [`run_recipe`].
pub struct RecipeRun {
    /// The engine the recipe ran in: use it to save or describe the value ([`save_value`],
    /// [`describe`]), since the value's types and closures belong to it.
    pub engine: Engine,
    /// The recipe's last value (the model).
    pub value: Dynamic,
    /// The compiled recipe: its functions, which closures held by the value may call.
    pub ast: AST,
    /// The parameters the recipe declared and the files it read.
    pub record: RunRecord,
    /// The wall-clock time of compiling and evaluating the recipe.
    pub elapsed: Duration,
    /// Calls whose result the recipe (or a module it imports) drops while their receiver
    /// stays as it was, found before it ran ([`crate::lint`]), then the warnings the run gave
    /// as it went ([`crate::context::Warnings`]: blocks that touch without connecting), formatted.
    pub warnings: Vec<String>,
}

/// A failed run of a recipe: the formatted error and what the run had declared and read up
/// to the failure (a watcher still knows which files to watch).
#[derive(Debug, Clone)]
pub struct RecipeFailure {
    /// The error, formatted for people (`file:line:col`, source line, caret, message).
    pub error: RunError,
    /// The parameters declared and files read before the failure. The script itself is
    /// always among the inputs, even when it could not be read.
    pub record: RunRecord,
}

impl From<RecipeFailure> for RunError {
    fn from(f: RecipeFailure) -> RunError {
        f.error
    }
}

/// Runs the recipe at `path` — the one way every command runs a recipe (`blocksmith run`,
/// `blocksmith params`, manifests, the studio): a fresh engine made from `options` (its script
/// directory set to the script's directory, a new record), the script compiled and evaluated.
///
/// The `--set` values in `options.context.params` are applied by each `param` call (parsed
/// by the default's type and checked there); after the run, a `--set` name that no `param`
/// call read is an error listing the recipe's parameters, with a did-you-mean.
///
/// ```no_run
/// use blocksmith_script::{run::run_recipe, EngineOptions};
/// let mut options = EngineOptions::default();
/// options.context.params.insert("teeth".into(), "16".into());
/// match run_recipe(std::path::Path::new("examples/gear.rhai"), options) {
///     Ok(run) => {
///         for p in &run.record.params {
///             println!("{} = {} ({})", p.name, p.value, p.kind.name());
///         }
///         println!("re-run when any of {:?} changes", run.record.inputs);
///     }
///     Err(failure) => eprintln!("{}\nwatching {:?}", failure.error, failure.record.inputs),
/// }
/// ```
///
/// # Errors
/// A read, parse or runtime error (a bad `--set` value included), or an unknown `--set` name,
/// formatted, with the record so far.
pub fn run_recipe(path: &Path, mut options: EngineOptions) -> Result<RecipeRun, RecipeFailure> {
    let start = Instant::now();
    options.context.script_dir = path.parent().map(Path::to_path_buf);
    options.context.access.enter(path);
    let record = Recorder::default();
    options.context.record = record.clone();
    record.input(path);
    let set_names: Vec<String> = options.context.params.keys().cloned().collect();
    let given = options.context.warnings.clone();
    let engine = new_engine(options);
    let fail = |error: RunError| RecipeFailure { error, record: record.snapshot() };
    let (source, ast) = compile_file(&engine, path).map_err(fail)?;
    let name = path.display().to_string();
    let mut warnings: Vec<String> = crate::lint::dropped_results(&ast, &source)
        .iter()
        .map(|d| crate::diagnostics::format_warning(&name, &source, d.position, &d.message))
        .collect();
    warnings.extend(crate::lint::imported_warnings(&engine, &ast, path.parent()));
    // Marked after the lint, which judges the recipe as written.
    let ast = crate::origins::mark_call_sites(&engine, &ast);
    let value = engine.eval_ast_with_scope::<Dynamic>(&mut Scope::new(), &ast).map_err(|e| {
        // A dropped result or an unconnected block is often why a later line fails: show it first.
        let mut text: Vec<String> = warnings.clone();
        text.extend(format_run_warnings(&given.take(), &name, &source));
        text.push(format_error(&engine, &name, &source, &e));
        fail(RunError(text.join("\n")))
    })?;
    warnings.extend(format_run_warnings(&given.take(), &name, &source));
    let elapsed = start.elapsed();
    let record = record.snapshot();
    if let Some(error) = unknown_set_names(path, &set_names, &record) {
        return Err(RecipeFailure { error, record });
    }
    Ok(RecipeRun { engine, value, ast, record, elapsed, warnings })
}

/// The error for `--set` names no `param` call read, listing the recipe's parameters.
fn unknown_set_names(path: &Path, set_names: &[String], record: &RunRecord) -> Option<RunError> {
    let unknown: Vec<&String> = set_names.iter().filter(|n| record.param(n).is_none()).collect();
    if unknown.is_empty() {
        return None;
    }
    let names = || record.params.iter().map(|p| p.name.as_str());
    let mut msg = String::new();
    for n in &unknown {
        let hint = did_you_mean(n, names()).map(|m| format!(" (did you mean `{m}`?)")).unwrap_or_default();
        msg.push_str(&format!("{}: error: --set {n}: the recipe has no parameter `{n}`{hint}\n", path.display()));
    }
    if record.params.is_empty() {
        msg.push_str("the recipe declares no parameters");
    } else {
        msg.push_str("its parameters are:\n");
        msg.push_str(crate::params::listing::to_text(&record.params).trim_end());
    }
    Some(RunError(msg))
}

/// Writes `value` to `out` with the script function `save` of the value's type (every savable
/// type registers one), so the same dispatch serves `run -o`, the REPL's `:save` and scripts.
/// `functions` are the script's functions, which closures held by the value (an animation's
/// script modifiers) call when it is written.
///
/// # Errors
/// When the value is nothing, has no `save`, or saving fails.
pub fn save_value(engine: &Engine, functions: &AST, value: Dynamic, out: &Path) -> Result<(), RunError> {
    if value.is_unit() {
        return Err(RunError(format!(
            "error: nothing to write to {}: the script's last value is empty (end the script with the model)",
            out.display()
        )));
    }
    let type_name = engine.map_type_name(value.type_name()).to_string();
    // The host names `out` (`run -o`, the studio's own file): the recipe's confinement and a
    // policy that only reports saves do not apply to it; the recipe's source still does.
    crate::RunContext::of_engine(engine).access.grant_host(out);
    let arg_types = [value.type_id(), std::any::TypeId::of::<rhai::ImmutableString>()];
    let mut scope = Scope::new();
    scope.push("__value", value);
    scope.push("__path", out.display().to_string());
    let call = engine.compile("save(__value, __path)").map_err(|e| RunError(format!("error: {e}")))?;
    let call = functions.clone_functions_only().merge(&call);
    engine.run_ast_with_scope(&mut scope, &call).map_err(|e| {
        if crate::lookup_failure::finds_native(engine, "save", &arg_types) {
            RunError(format!("error: {}", crate::diagnostics::explained_message(engine, &e)))
        } else {
            RunError(format!(
                "error: cannot write {} to {}: values of that type cannot be saved{}",
                crate::catalogue::a(&type_name),
                out.display(),
                savable_from(engine, &type_name)
            ))
        }
    })
}

/// How to get a value that can be saved from a `type_name`: its methods without arguments
/// that return a type with a `save` (`model.mesh()`, `vx.to_mesh()`), as advice.
fn savable_from(engine: &Engine, type_name: &str) -> String {
    let all = crate::catalogue::of(engine);
    // Each type once, however many `save` overloads it has (with and without options).
    let mut savable: Vec<&str> =
        all.iter().filter(|o| o.name == "save" && o.ours).filter_map(|o| o.receiver()).collect();
    savable.sort_unstable();
    savable.dedup();
    let mut ways: Vec<String> = all
        .iter()
        .filter(|o| o.ours && o.property.is_none() && o.receiver() == Some(type_name) && o.params.len() == 1)
        .filter(|o| savable.contains(&o.returns.as_str()))
        .map(|o| format!("`.{}()`", o.name))
        .collect();
    ways.sort_by_key(String::len);
    ways.dedup();
    if ways.is_empty() {
        format!(" (a script's last value is saved: end it with one of {})", savable.join(", "))
    } else {
        format!("; end the script with {}", ways.iter().map(|w| format!("its {w}")).collect::<Vec<_>>().join(" or "))
    }
}

/// A one-line description of `value` through its type's `to_string`.
#[must_use]
pub fn describe(engine: &Engine, value: &Dynamic) -> String {
    let mut scope = Scope::new();
    scope.push("__value", value.clone());
    engine
        .eval_with_scope::<String>(&mut scope, "to_string(__value)")
        .unwrap_or_else(|_| engine.map_type_name(value.type_name()).to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    fn with_set(pairs: &[(&str, &str)]) -> EngineOptions {
        let mut options = EngineOptions::default();
        options.context.params = pairs.iter().map(|(k, v)| ((*k).to_string(), (*v).to_string())).collect();
        options
    }

    #[test]
    fn the_record_lists_parameters_in_order_and_every_file_read() {
        let d = tempfile::tempdir().unwrap();
        let dir = d.path().canonicalize().unwrap();
        write(&dir, "inner.rhai", "fn two() { 2 }\n");
        write(&dir, "outer.rhai", "import \"inner\" as inner;\nfn width() { inner::two() * 2 }\n");
        crate::new_engine(EngineOptions::default())
            .run(&format!("cube(1).save(\"{}\")", dir.join("c.obj").display()))
            .unwrap();
        let recipe = write(
            &dir,
            "r.rhai",
            "import \"outer\" as outer;\nimport \"check\" as check;\n\
             let n = param(\"n\", 3, #{ min: 1, doc: \"count\" });\nlet m = load(\"c.obj\");\n\
             let s = param(\"s\", 0.5);\nparam(\"n\", 3);\nm.scale(s * outer::width() * n)\n",
        );
        let run = run_recipe(&recipe, with_set(&[("n", "4")])).unwrap();
        let names: Vec<&str> = run.record.params.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, ["n", "s"]);
        let n = &run.record.params[0];
        assert_eq!(
            (n.value.clone(), n.set, n.min, n.doc.as_deref()),
            (serde_json::json!(4), true, Some(1.0), Some("count"))
        );
        // The script first, then each file in the order first read; the stdlib by name.
        let inputs: Vec<PathBuf> =
            ["r.rhai", "outer.rhai", "inner.rhai", "c.obj"].iter().map(|f| dir.join(f)).collect();
        assert_eq!(run.record.inputs, inputs);
        assert_eq!(run.record.stdlib, ["check"]);
    }

    #[test]
    fn a_failed_run_still_records_the_files_read() {
        // A watcher re-runs when the broken module is fixed, so it must know the module.
        let d = tempfile::tempdir().unwrap();
        let dir = d.path().canonicalize().unwrap();
        write(&dir, "broken.rhai", "fn f( { 1 }\n");
        let recipe = write(&dir, "r.rhai", "let a = param(\"a\", 1);\nimport \"broken\" as b;\n1\n");
        let failure = run_recipe(&recipe, EngineOptions::default()).err().unwrap();
        assert_eq!(failure.record.inputs, [dir.join("r.rhai"), dir.join("broken.rhai")]);
        assert_eq!(failure.record.params.len(), 1);
        let missing = dir.join("missing.rhai");
        let failure = run_recipe(&missing, EngineOptions::default()).err().unwrap();
        assert!(failure.error.0.contains("cannot read the script"), "{}", failure.error);
        assert_eq!(failure.record.inputs, [missing]);
    }

    #[test]
    fn an_unknown_set_name_is_an_error_listing_the_parameters() {
        let d = tempfile::tempdir().unwrap();
        let recipe =
            write(d.path(), "t.rhai", "let h = param(\"legs_height\", 2.0);\nlet w = param(\"width\", 1);\nh * w\n");
        let e = run_recipe(&recipe, with_set(&[("leg_height", "2")])).err().unwrap().error.0;
        assert!(
            e.contains("--set leg_height: the recipe has no parameter `leg_height` (did you mean `legs_height`?)"),
            "{e}"
        );
        assert!(
            e.contains("its parameters are:") && e.contains("legs_height  float  2.0") && e.contains("width"),
            "{e}"
        );
        let e = run_recipe(&recipe, with_set(&[("colour", "red")])).err().unwrap().error.0;
        assert!(e.contains("no parameter `colour`\n"), "no hint for a far name: {e}");
    }

    #[test]
    fn a_bad_value_stops_the_recipe_at_its_param_call() {
        let d = tempfile::tempdir().unwrap();
        let out = d.path().join("never.obj");
        let recipe = write(
            d.path(),
            "t.rhai",
            &format!("let a = 1;\nlet steps = param(\"steps\", 8);\ncube(1).save(\"{}\");\n", out.display()),
        );
        let e = run_recipe(&recipe, with_set(&[("steps", "2.5")])).err().unwrap().error.0;
        assert!(
            e.contains("t.rhai:2:") && e.contains("param: `steps` must be an integer (default 8), got `2.5`"),
            "{e}"
        );
        assert!(!out.exists(), "the recipe ran on after the bad value");
    }
}
