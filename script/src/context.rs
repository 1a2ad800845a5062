//! What a running script knows of its surroundings: `--set` parameters, where it lives and
//! where relative output paths go. Carried as the engine's default tag.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::rc::Rc;

use rhai::{Dynamic, NativeCallContext};

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
}

impl RunContext {
    /// The context of the current call (an empty one when none was set).
    #[must_use]
    pub fn of(ctx: &NativeCallContext) -> Rc<RunContext> {
        ctx.tag().and_then(|t| t.clone().try_cast::<Rc<RunContext>>()).unwrap_or_default()
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

    /// Where to write `path`: as given when absolute, else under the output directory.
    #[must_use]
    pub fn output_path(&self, path: &str) -> PathBuf {
        let p = Path::new(path);
        match &self.output_dir {
            Some(dir) if !p.is_absolute() => dir.join(p),
            _ => p.to_path_buf(),
        }
    }

    /// Packs the context as an engine tag.
    pub fn into_tag(self) -> Dynamic {
        Dynamic::from(Rc::new(self))
    }
}

/// Parses a `--set` value of a parameter whose default has no simple type (see
/// [`crate::param`]): integer, float, bool, else string.
pub fn parse_param(text: &str) -> Dynamic {
    if let Ok(i) = text.parse::<rhai::INT>() {
        Dynamic::from(i)
    } else if let Ok(f) = text.parse::<f64>() {
        Dynamic::from(f)
    } else if let Ok(b) = text.parse::<bool>() {
        Dynamic::from(b)
    } else {
        Dynamic::from(text.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn params_parse_as_int_float_bool_then_string() {
        assert_eq!(parse_param("12").as_int().unwrap(), 12);
        assert_eq!(parse_param("1.5").as_float().unwrap(), 1.5);
        assert!(parse_param("true").as_bool().unwrap());
        assert_eq!(parse_param("oak").into_string().unwrap(), "oak");
    }
}
