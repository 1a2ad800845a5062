//! `blocksmith run`: evaluate a recipe and write its last value to a model file.

use std::path::{Path, PathBuf};

use rhai::{Dynamic, Engine, Scope, AST};

use crate::context::RunContext;
use crate::diagnostics::{format_error, format_parse_error};
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
pub fn eval_file(path: &Path, mut options: EngineOptions) -> Result<(Dynamic, AST), RunError> {
    options.context.script_dir = path.parent().map(Path::to_path_buf);
    let engine = new_engine(options);
    let (source, ast) = compile_file(&engine, path)?;
    let value = engine
        .eval_ast_with_scope::<Dynamic>(&mut Scope::new(), &ast)
        .map_err(|e| RunError(format_error(&path.display().to_string(), &source, &e)))?;
    Ok((value, ast))
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
    let mut scope = Scope::new();
    scope.push("__value", value);
    scope.push("__path", out.display().to_string());
    let call = engine.compile("save(__value, __path)").map_err(|e| RunError(format!("error: {e}")))?;
    let call = functions.clone_functions_only().merge(&call);
    engine.run_ast_with_scope(&mut scope, &call).map_err(|e| {
        let msg = crate::diagnostics::message(&e);
        if msg.contains("Function not found: save") {
            RunError(format!(
                "error: cannot write a {type_name} to {}: values of that type cannot be saved",
                out.display()
            ))
        } else {
            RunError(format!("error: {msg}"))
        }
    })
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

/// Options of `blocksmith run`.
#[derive(Debug, Clone, Default)]
pub struct RunCommand {
    pub file: PathBuf,
    pub output: Option<PathBuf>,
    pub params: Vec<(String, String)>,
    pub max_operations: Option<u64>,
}

/// Runs `blocksmith run`: evaluates the recipe and writes its last value to the output file.
/// Returns a one-line summary.
///
/// # Errors
/// Any error of the run or the write, formatted.
pub fn execute(cmd: &RunCommand) -> Result<String, RunError> {
    let context = RunContext { params: cmd.params.iter().cloned().collect(), ..RunContext::default() };
    let options = EngineOptions { context, max_operations: cmd.max_operations, interrupt: None };
    let (value, ast) = eval_file(&cmd.file, options.clone())?;
    let engine = new_engine(options);
    let summary = describe(&engine, &value);
    match &cmd.output {
        Some(out) => {
            save_value(&engine, &ast, value, out)?;
            Ok(format!("wrote {} ({summary})", out.display()))
        }
        None => Ok(summary),
    }
}
