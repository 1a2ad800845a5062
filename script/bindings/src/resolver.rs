//! `import "name" as x;` — finds `name.rhai` next to the importing script, then in the standard
//! library embedded in the binary (`stdlib/*.rhai`).

use std::cell::RefCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

use rhai::module_resolvers::FileModuleResolver;
use rhai::{Engine, EvalAltResult, Module, ModuleResolver, Position, Scope, Shared};

use crate::access::Access;
use crate::record::Recorder;

type SharedModule = Shared<Module>;

include!(concat!(env!("OUT_DIR"), "/stdlib.rs"));

/// The module resolver of every blocksmith engine.
pub struct Resolver {
    base: Option<PathBuf>,
    files: FileModuleResolver,
    stdlib_cache: RefCell<HashMap<String, SharedModule>>,
    record: Recorder,
    access: Option<Access>,
}

impl Resolver {
    /// A resolver looking next to scripts (and in `base` for scripts without a source path,
    /// such as REPL entries), then in the standard library.
    #[must_use]
    pub fn new(base: Option<PathBuf>) -> Resolver {
        let files = match &base {
            Some(b) => FileModuleResolver::new_with_path(b),
            None => FileModuleResolver::new(),
        };
        Resolver { base, files, stdlib_cache: RefCell::new(HashMap::new()), record: Recorder::default(), access: None }
    }

    /// The resolver, recording each module it resolves (the file, or the standard-library
    /// module's name) in `record`.
    #[must_use]
    pub fn recording(self, record: Recorder) -> Resolver {
        Resolver { record, ..self }
    }

    /// The resolver, importing only the files `access` lets the run read (imports obey the
    /// same rule as `load`).
    #[must_use]
    pub fn confined_by(self, access: Access) -> Resolver {
        Resolver { access: Some(access), ..self }
    }

    /// The source of standard-library module `name`, if there is one.
    #[must_use]
    pub fn stdlib_source(name: &str) -> Option<&'static str> {
        STDLIB.iter().find(|(n, _)| *n == name).map(|(_, s)| *s)
    }

    /// The names of the standard-library modules.
    #[must_use]
    pub fn stdlib_names() -> Vec<&'static str> {
        STDLIB.iter().map(|(n, _)| *n).collect()
    }

    fn local_path(&self, source: Option<&str>, path: &str) -> PathBuf {
        let file = if path.ends_with(".rhai") { path.to_string() } else { format!("{path}.rhai") };
        let p = Path::new(&file);
        if p.is_absolute() {
            return p.to_path_buf();
        }
        let dir = source
            .and_then(|s| Path::new(s).parent().map(Path::to_path_buf))
            .or_else(|| self.base.clone())
            .unwrap_or_default();
        dir.join(p)
    }
}

impl ModuleResolver for Resolver {
    fn resolve(
        &self,
        engine: &Engine,
        source: Option<&str>,
        path: &str,
        pos: Position,
    ) -> Result<SharedModule, Box<EvalAltResult>> {
        let local = self.local_path(source, path);
        if local.exists() {
            if let Some(access) = &self.access {
                access
                    .check_read(&local)
                    .map_err(|e| Box::new(EvalAltResult::ErrorRuntime(format!("import: {e}").into(), pos)))?;
            }
            // Absolute, so the file resolver does not join it to its own base a second time.
            let local = local.canonicalize().unwrap_or(local);
            self.record.input(&local);
            return self.files.resolve(engine, None, &local.to_string_lossy(), pos);
        }
        let name = path.trim_end_matches(".rhai");
        if Resolver::stdlib_source(name).is_some() {
            self.record.stdlib(name);
        }
        if let Some(m) = self.stdlib_cache.borrow().get(name) {
            return Ok(m.clone());
        }
        if let Some(src) = Resolver::stdlib_source(name) {
            let mut ast = engine
                .compile(src)
                .map_err(|e| Box::new(EvalAltResult::ErrorInModule(format!("stdlib/{name}.rhai"), e.into(), pos)))?;
            ast.set_source(format!("stdlib/{name}.rhai"));
            let module: SharedModule =
                Module::eval_ast_as_new(Scope::new(), &crate::origins::mark_call_sites(engine, &ast), engine)
                    .map_err(|e| Box::new(EvalAltResult::ErrorInModule(format!("stdlib/{name}.rhai"), e, pos)))?
                    .into();
            self.stdlib_cache.borrow_mut().insert(name.to_string(), module.clone());
            return Ok(module);
        }
        let message = format!(
            "import: module \"{path}\" not found: no file {} and no standard-library module of that name \
             (the standard library has: {})",
            local.display(),
            Resolver::stdlib_names().join(", ")
        );
        Err(Box::new(EvalAltResult::ErrorRuntime(message.into(), pos)))
    }
}
