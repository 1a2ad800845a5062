//! Where a script's files are: the file it names for reading ([`input_file`]: from the working
//! directory, else next to the script) or writing ([`output_file`]: under the run's output
//! directory), each checked against what the run may read and write ([`crate::access`]) and
//! recorded with the run. Every API function that touches a file goes through here.

use std::fs;
use std::path::PathBuf;

use rhai::NativeCallContext;

use crate::access::Write;
use crate::context::RunContext;
use crate::convert::{fail, ScriptResult};

/// The file a script names by `path` for writing, once the run's access allows it
/// ([`crate::access::Access::check_write`]): a relative path goes under the run's output
/// directory; missing parent directories are created; the run's list of writes, if it keeps
/// one ([`crate::context::Writes`]), gains it. `None` when the run only reports its saves
/// (`blocksmith params`, `render`, `watch`): the save is listed as a warning and not done.
/// Errors name `func`. After writing, call [`wrote`].
///
/// # Errors
/// A relative path leaving the output directory, a path the run may not write (outside its
/// project, the recipe, read-only, over the write limits), or a directory that cannot be
/// created.
pub fn output_file(ctx: &NativeCallContext, func: &str, path: &str) -> ScriptResult<Option<PathBuf>> {
    let run = RunContext::of(ctx);
    let p = match run.output_path(path) {
        Ok(p) => p,
        Err(e) => return fail(func, e),
    };
    let p = match run.access.check_write(&p, &run.protected()) {
        Ok(Write::Do(p)) => p,
        Ok(Write::Report) => {
            run.warnings.push(
                ctx,
                format!(
                    "{func}: `{}` not written: `blocksmith params`, `render` and `watch` never write files",
                    p.display()
                ),
            );
            return Ok(None);
        }
        Err(e) => return Err(crate::convert::error(func, e)),
    };
    if let Some(dir) = p.parent().filter(|d| !d.as_os_str().is_empty()) {
        if let Err(e) = fs::create_dir_all(dir) {
            return fail(func, format!("cannot create directory {}: {e}", dir.display()));
        }
    }
    if let Some(writes) = &run.writes {
        writes.push(&p);
    }
    Ok(Some(p))
}

/// The second file a save writes beside the one [`output_file`] allowed (an OBJ's material
/// library), checked as that one was: the run may write it (inside its project, not the recipe,
/// not read-only), or the host named the first file (`run -o`) and this one is its companion.
/// `Ok(false)` when the run only reports saves. Errors name `func` and say what the file is.
///
/// # Errors
/// A companion the run may not write.
pub fn companion_file(
    ctx: &NativeCallContext,
    func: &str,
    first: &std::path::Path,
    path: &std::path::Path,
    what: &str,
) -> ScriptResult<bool> {
    let run = RunContext::of(ctx);
    if run.access.is_host(first) {
        run.access.grant_host(path);
    }
    match run.access.check_write(path, &run.protected()) {
        Ok(Write::Do(p)) => {
            if let Some(writes) = &run.writes {
                writes.push(&p);
            }
            Ok(true)
        }
        Ok(Write::Report) => Ok(false),
        Err(e) => Err(crate::convert::error(func, format!("{what} {}: {e}", path.display()))),
    }
}

/// Counts the file just written at `path` against the run's write limits.
pub fn wrote(ctx: &NativeCallContext, path: &std::path::Path) {
    RunContext::of(ctx).access.wrote(path);
}

/// The file a script names by `path` for reading (from the working directory, else next to
/// the script): checked against what the run may read, and recorded as an input of the run
/// when it exists. Errors name `func`.
///
/// # Errors
/// A path outside what the run may read.
pub fn input_file(ctx: &NativeCallContext, func: &str, path: &str) -> ScriptResult<PathBuf> {
    let run = RunContext::of(ctx);
    let p = run.input_path(path);
    run.access.check_read(&p).map_err(|e| crate::convert::error(func, e))?;
    if p.exists() {
        run.record.input(&p);
    }
    Ok(p)
}
