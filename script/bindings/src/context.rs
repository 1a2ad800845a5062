//! What a running script knows of its surroundings: `--set` parameters, where it lives and
//! where relative output paths go. Carried as the engine's default tag.

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::path::{Component, Path, PathBuf};
use std::rc::Rc;
use std::sync::{Arc, Mutex};

use rhai::{Dynamic, NativeCallContext, Position};

use crate::record::Recorder;

/// The surroundings of one script run.
#[derive(Clone, Debug, Default)]
pub struct RunContext {
    /// `--set name=value` pairs, values unparsed.
    pub params: BTreeMap<String, String>,
    /// The directory of the script being run (relative `load` paths are tried there too).
    pub script_dir: Option<PathBuf>,
    /// Where relative `save` paths are written (the working directory for `run` and the REPL,
    /// the output directory for `test`).
    pub output_dir: Option<PathBuf>,
    /// What the run declares and reads (parameters, input files), filled in as it goes.
    pub record: Recorder,
    /// Where `show(value)` puts its values: the studio (`blocksmith watch`, the REPL) shows
    /// them; `None` elsewhere, where `show` does nothing.
    pub shown: Option<Shown>,
    /// Where the files the run writes are listed as it writes them, for a watcher that must
    /// not take a run's own saves for edits (`blocksmith watch`); `None` elsewhere.
    pub writes: Option<Writes>,
    /// The warnings the run gives as it goes (blocks that touch without connecting), shown
    /// with the lint's: `run` and the REPL print them, `blocksmith test` fails on them.
    pub warnings: Warnings,
    /// The engine's functions, read once when an error is first explained
    /// ([`crate::catalogue::of`]).
    pub catalogue: crate::catalogue::Kept,
    /// What the run may read and write (its project, granted paths, write limits), and what
    /// it has written: the process's policy by default ([`crate::access`]).
    pub access: crate::access::Access,
    /// Where the script's `print` and `debug` go: standard output (Rhai's own, the default),
    /// or standard error when standard output carries something a parser reads alone
    /// (`run --stats json`).
    pub print_to: PrintTo,
    /// `--time t` (`run`, `render`): the time at which an `Animation` the recipe ends with is
    /// posed — `run` writes that still, `render` draws it
    /// ([`crate::api::anim::pose_of_value`]); `None`: `run` writes the animation, `render`
    /// draws its last frame.
    pub time: Option<f64>,
}

/// Where a script's `print` and `debug` lines go.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PrintTo {
    /// Standard output, as Rhai prints them.
    #[default]
    Stdout,
    /// Standard error, leaving standard output to the host (`run --stats json | jq`).
    Stderr,
}

/// A warning a running script gave: where (the module's source name, `None` for the script
/// itself, and the position of the call) and what.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Warning {
    /// The source of the module whose call gave it, or `None` for the script being run.
    pub source: Option<String>,
    /// The position of the call.
    pub position: Position,
    /// What is wrong and the fix.
    pub message: String,
}

/// The warnings of a run, in order. Cloning shares them.
#[derive(Clone, Debug, Default)]
pub struct Warnings(Rc<RefCell<Vec<Warning>>>);

impl Warnings {
    /// Adds the warning `message` for the call of `ctx`.
    pub fn push(&self, ctx: &NativeCallContext, message: String) {
        let source = ctx.call_source().map(str::to_string);
        self.0.borrow_mut().push(Warning { source, position: ctx.call_position(), message });
    }

    /// The warnings so far, leaving none.
    #[must_use]
    pub fn take(&self) -> Vec<Warning> {
        std::mem::take(&mut *self.0.borrow_mut())
    }
}

/// The files a run writes, listed before each is written, shared with other threads.
/// Cloning shares the list.
#[derive(Clone, Debug, Default)]
pub struct Writes(Arc<Mutex<Vec<PathBuf>>>);

impl Writes {
    /// Lists `path` (made absolute, its folder's symbolic links resolved, as a watcher names
    /// it), and for a `.gltf` the buffer files it names now, which the save replaces.
    pub fn push(&self, path: &Path) {
        let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
        let resolved = match (absolute.parent().and_then(|d| d.canonicalize().ok()), absolute.file_name()) {
            (Some(dir), Some(name)) => dir.join(name),
            _ => absolute,
        };
        let gltf = resolved.extension().is_some_and(|e| e.eq_ignore_ascii_case("gltf"));
        let mut list = self.0.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        if gltf {
            // The buffers the .gltf names now, which the save replaces (the new one is named
            // by its content, `STEM.HASH.bin`, known once written).
            list.extend(crate::gltf_buffers::buffer_files(&resolved));
        }
        list.push(resolved);
    }

    /// The files listed so far.
    #[must_use]
    pub fn list(&self) -> Vec<PathBuf> {
        self.0.lock().unwrap_or_else(std::sync::PoisonError::into_inner).clone()
    }

    /// Whether `path` is listed.
    #[must_use]
    pub fn contains(&self, path: &Path) -> bool {
        self.0.lock().unwrap_or_else(std::sync::PoisonError::into_inner).iter().any(|p| p == path)
    }

    /// Empties the list (a new run starts).
    pub fn clear(&self) {
        self.0.lock().unwrap_or_else(std::sync::PoisonError::into_inner).clear();
    }
}

/// The values a script passed to `show`, in order. Cloning shares them.
#[derive(Clone, Debug, Default)]
pub struct Shown(Rc<RefCell<Vec<Dynamic>>>);

impl Shown {
    /// Adds a value.
    pub fn push(&self, value: Dynamic) {
        self.0.borrow_mut().push(value);
    }

    /// The values so far, leaving none.
    #[must_use]
    pub fn take(&self) -> Vec<Dynamic> {
        std::mem::take(&mut *self.0.borrow_mut())
    }
}

impl RunContext {
    /// The context of the current call (an empty one when none was set).
    #[must_use]
    pub fn of(ctx: &NativeCallContext) -> Rc<RunContext> {
        ctx.tag().and_then(|t| t.clone().try_cast::<Rc<RunContext>>()).unwrap_or_default()
    }

    /// The context of `engine`'s runs (its default tag; an empty one when none was set).
    #[must_use]
    pub fn of_engine(engine: &rhai::Engine) -> Rc<RunContext> {
        engine.default_tag().clone().try_cast::<Rc<RunContext>>().unwrap_or_default()
    }

    /// The files no save of the run may replace: the recipe and the modules it imported.
    #[must_use]
    pub fn protected(&self) -> Vec<PathBuf> {
        let inputs = self.record.snapshot().inputs;
        inputs.into_iter().filter(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("rhai"))).collect()
    }

    /// Where to read `path`: as given when it exists (or is absolute), else next to the script.
    #[must_use]
    pub fn input_path(&self, path: &str) -> PathBuf {
        let p = Path::new(path);
        if p.is_absolute() || p.exists() {
            return p.to_path_buf();
        }
        match &self.script_dir {
            Some(dir) if dir.join(p).exists() => dir.join(p),
            _ => p.to_path_buf(),
        }
    }

    /// Where to write `path`: as given when absolute or when there is no output directory,
    /// else under the output directory, which a relative path may not leave.
    ///
    /// # Errors
    /// A relative path whose `..` segments climb out of the output directory.
    pub fn output_path(&self, path: &str) -> Result<PathBuf, String> {
        let p = Path::new(path);
        let Some(dir) = self.output_dir.as_ref().filter(|_| !p.is_absolute()) else {
            return Ok(p.to_path_buf());
        };
        let mut depth = 0usize;
        for c in p.components() {
            match c {
                Component::ParentDir if depth == 0 => {
                    return Err(format!(
                        "the path `{path}` leaves the output directory {}; relative paths are written inside it",
                        dir.display()
                    ))
                }
                Component::ParentDir => depth -= 1,
                Component::Normal(_) => depth += 1,
                Component::CurDir | Component::RootDir | Component::Prefix(_) => {}
            }
        }
        Ok(dir.join(p))
    }

    /// Packs the context as an engine tag.
    pub fn into_tag(self) -> Dynamic {
        Dynamic::from(Rc::new(self))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_output_paths_cannot_leave_the_output_directory() {
        let ctx = RunContext { output_dir: Some(PathBuf::from("out")), ..RunContext::default() };
        assert_eq!(ctx.output_path("a/../b.obj").unwrap(), Path::new("out/a/../b.obj"));
        assert_eq!(ctx.output_path("/tmp/x.obj").unwrap(), Path::new("/tmp/x.obj"));
        for escape in ["../../x.obj", "a/../../x.obj", "./../x.obj"] {
            let e = ctx.output_path(escape).unwrap_err();
            assert!(e.contains("leaves the output directory out"), "{escape}: {e}");
        }
        // Without an output directory (run, the REPL) paths are the working directory's.
        assert_eq!(RunContext::default().output_path("../x.obj").unwrap(), Path::new("../x.obj"));
    }
}
