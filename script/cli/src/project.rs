//! A run's project and what it may read and write: the `--allow-read`, `--allow-write`,
//! `--max-writes` and `--max-write-size` flags merged with the project's `blocksmith.toml`, made
//! the process's [`Policy`] ([`blocksmith_script::access`]).
//!
//! `blocksmith.toml`, at the project's root (the folder that marks the project), in its
//! `[access]` table:
//!
//! ```toml
//! [access]
//! allow_read = ["../scans", "~/meshes"]   # files or folders, relative to this file; ~ is your home
//! allow_write = ["../renders"]
//! max_writes = 500                        # files one run may write (default 100)
//! max_write_size = "8G"                   # bytes one run may write (default 4G; units K M G T)
//! ```
//!
//! Read with a small parser of this subset of TOML (tables, strings, integers, arrays of
//! strings, comments): the command needs no more.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use blocksmith_script::access::{self, Policy, Saves};

/// The flags that widen what a run may read and write, and its write limits.
#[derive(clap::Args, Clone, Debug, Default)]
pub struct AccessArgs {
    /// A file or folder the recipe may also read, besides its project (the nearest folder above
    /// it holding .git or blocksmith.toml); repeatable.
    #[arg(long = "allow-read", value_name = "PATH")]
    pub allow_read: Vec<PathBuf>,
    /// A file or folder the recipe may also write (and read), besides its project; repeatable.
    #[arg(long = "allow-write", value_name = "PATH")]
    pub allow_write: Vec<PathBuf>,
    /// How many files one run may write (default 100).
    #[arg(long, value_name = "N")]
    pub max_writes: Option<u64>,
    /// How many bytes one run may write: 200M, 8G (default 4G).
    #[arg(long, value_name = "SIZE", value_parser = parse_size)]
    pub max_write_size: Option<u64>,
}

impl AccessArgs {
    /// Makes the process's policy for runs of recipes at `anchor` (a recipe, or the folder a
    /// REPL or test run starts in): confined to the project, widened by `blocksmith.toml`, these
    /// flags and the paths the user `named` (`-o`, `--out`, `--manifest`, which the recipe may
    /// write too), saves done or only reported.
    ///
    /// # Errors
    /// A `blocksmith.toml` that cannot be read or parsed, naming the file and the line.
    pub fn apply(&self, anchor: &Path, named: &[&Path], saves: Saves) -> Result<(), String> {
        let dir = if anchor.is_dir() { anchor } else { anchor.parent().unwrap_or(Path::new(".")) };
        let dir = if dir.as_os_str().is_empty() { Path::new(".") } else { dir };
        let project = access::project_of(dir);
        let toml = project.join("blocksmith.toml");
        let from_file = if toml.is_file() { Settings::read(&toml)? } else { Settings::default() };
        let policy = Policy::DEFAULT
            .confined()
            .with_saves(saves)
            .with_read(from_file.allow_read.into_iter().chain(self.allow_read.iter().cloned()))
            .with_write(
                from_file
                    .allow_write
                    .into_iter()
                    .chain(self.allow_write.iter().cloned())
                    .chain(named.iter().map(|p| p.to_path_buf())),
            )
            .with_write_limits(
                self.max_writes.or(from_file.max_writes).unwrap_or(Policy::DEFAULT_MAX_WRITES),
                self.max_write_size.or(from_file.max_write_size).unwrap_or(Policy::DEFAULT_MAX_WRITE_BYTES),
            );
        access::set_policy(policy);
        Ok(())
    }
}

/// The `[access]` table of a `blocksmith.toml`, its paths resolved against the file's folder.
#[derive(Debug, Default, PartialEq)]
pub struct Settings {
    pub allow_read: Vec<PathBuf>,
    pub allow_write: Vec<PathBuf>,
    pub max_writes: Option<u64>,
    pub max_write_size: Option<u64>,
}

/// A value of the TOML subset.
#[derive(Debug, Clone, PartialEq)]
enum Value {
    Str(String),
    Int(i64),
    Strs(Vec<String>),
}

impl Settings {
    /// Reads and parses the file at `path`.
    ///
    /// # Errors
    /// The read error, or what is wrong and where.
    pub fn read(path: &Path) -> Result<Settings, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("error: cannot read {}: {e}", path.display()))?;
        let base = path.parent().unwrap_or(Path::new("."));
        Settings::parse(&text, base).map_err(|e| format!("error: {}:{e}", path.display()))
    }

    /// Parses `text`, relative paths taken from `base`.
    ///
    /// # Errors
    /// `LINE: message` for the first thing wrong.
    pub fn parse(text: &str, base: &Path) -> Result<Settings, String> {
        let tables = parse_toml(text)?;
        let mut s = Settings::default();
        let Some(table) = tables.get("access") else { return Ok(s) };
        for (key, (line, value)) in table {
            let bad = |what: &str| format!("{line}: `{key}` must be {what}");
            match (key.as_str(), value) {
                ("allow_read", Value::Strs(v)) => s.allow_read = v.iter().map(|p| resolve(base, p)).collect(),
                ("allow_write", Value::Strs(v)) => s.allow_write = v.iter().map(|p| resolve(base, p)).collect(),
                ("allow_read" | "allow_write", _) => return Err(bad("an array of paths, such as [\"../meshes\"]")),
                ("max_writes", Value::Int(n)) if *n >= 0 => s.max_writes = Some(*n as u64),
                ("max_writes", _) => return Err(bad("a number of files, such as 500")),
                ("max_write_size", Value::Int(n)) if *n >= 0 => s.max_write_size = Some(*n as u64),
                ("max_write_size", Value::Str(t)) => s.max_write_size = Some(parse_size(t).map_err(|e| bad(&e))?),
                ("max_write_size", _) => return Err(bad("a size, such as \"8G\"")),
                _ => {
                    return Err(format!(
                        "{line}: unknown key `{key}` in [access] (it has allow_read, allow_write, max_writes, \
                         max_write_size)"
                    ))
                }
            }
        }
        Ok(s)
    }
}

/// `p` from the folder `base`; `~` or `~/…` from the home folder.
fn resolve(base: &Path, p: &str) -> PathBuf {
    let home = || std::env::var_os("HOME").map(PathBuf::from);
    if p == "~" {
        if let Some(h) = home() {
            return h;
        }
    }
    if let (Some(rest), Some(h)) = (p.strip_prefix("~/"), home()) {
        return h.join(rest);
    }
    base.join(p)
}

type Table = BTreeMap<String, (usize, Value)>;

/// The tables of `text` (keys before any table header go to the table ``""``).
fn parse_toml(text: &str) -> Result<BTreeMap<String, Table>, String> {
    let mut tables: BTreeMap<String, Table> = BTreeMap::new();
    let mut current = String::new();
    let mut lines = text.lines().enumerate();
    while let Some((i, raw)) = lines.next() {
        let line = strip_comment(raw).trim().to_string();
        let n = i + 1;
        if line.is_empty() {
            continue;
        }
        if let Some(name) = line.strip_prefix('[').and_then(|l| l.strip_suffix(']')) {
            current = name.trim().to_string();
            tables.entry(current.clone()).or_default();
            continue;
        }
        let Some((key, value)) = line.split_once('=') else {
            return Err(format!("{n}: expected `key = value` or `[table]`, got `{line}`"));
        };
        let mut value = value.trim().to_string();
        // An array may continue over several lines.
        while value.starts_with('[') && !value.ends_with(']') {
            let Some((_, more)) = lines.next() else { return Err(format!("{n}: the array is never closed")) };
            value.push(' ');
            value.push_str(strip_comment(more).trim());
        }
        let key = key.trim().trim_matches('"').to_string();
        let parsed = parse_value(&value).map_err(|e| format!("{n}: {key}: {e}"))?;
        if tables.entry(current.clone()).or_default().insert(key.clone(), (n, parsed)).is_some() {
            return Err(format!("{n}: `{key}` is given twice"));
        }
    }
    Ok(tables)
}

/// `line` without a `#` comment (a `#` inside a string stays).
fn strip_comment(line: &str) -> &str {
    let mut quote: Option<char> = None;
    let mut escaped = false;
    for (i, c) in line.char_indices() {
        match (c, quote) {
            ('\\', Some('"')) if !escaped => {
                escaped = true;
                continue;
            }
            ('"' | '\'', None) => quote = Some(c),
            (c, Some(q)) if c == q && !escaped => quote = None,
            ('#', None) => return &line[..i],
            _ => {}
        }
        escaped = false;
    }
    line
}

fn parse_value(v: &str) -> Result<Value, String> {
    if let Some(inner) = v.strip_prefix('[').and_then(|v| v.strip_suffix(']')) {
        let mut items = Vec::new();
        let mut rest = inner.trim();
        while !rest.is_empty() {
            let (s, after) = parse_string(rest)?;
            items.push(s);
            rest = after.trim_start();
            rest = rest.strip_prefix(',').unwrap_or(rest).trim_start();
        }
        return Ok(Value::Strs(items));
    }
    if v.starts_with('"') || v.starts_with('\'') {
        let (s, after) = parse_string(v)?;
        if !after.trim().is_empty() {
            return Err(format!("unexpected `{}` after the string", after.trim()));
        }
        return Ok(Value::Str(s));
    }
    v.replace('_', "")
        .parse::<i64>()
        .map(Value::Int)
        .map_err(|_| format!("expected a string, number or array, got `{v}`"))
}

/// A basic (`"…"`, with `\\`, `\"`, `\n`, `\t` escapes) or literal (`'…'`) string at the start
/// of `s`, and what follows it.
fn parse_string(s: &str) -> Result<(String, &str), String> {
    let quote =
        s.chars().next().filter(|c| *c == '"' || *c == '\'').ok_or_else(|| format!("expected a string, got `{s}`"))?;
    let mut out = String::new();
    let mut chars = s.char_indices().skip(1);
    while let Some((i, c)) = chars.next() {
        match c {
            c if c == quote => return Ok((out, &s[i + 1..])),
            '\\' if quote == '"' => match chars.next().map(|(_, c)| c) {
                Some('n') => out.push('\n'),
                Some('t') => out.push('\t'),
                Some(c @ ('"' | '\\')) => out.push(c),
                other => return Err(format!("unknown escape `\\{}`", other.unwrap_or(' '))),
            },
            c => out.push(c),
        }
    }
    Err(format!("the string {s} is never closed"))
}

/// A size in bytes: a number with an optional unit K, M, G or T (powers of 1024).
///
/// # Errors
/// Anything else.
pub fn parse_size(s: &str) -> Result<u64, String> {
    let bad = || format!("a size such as 200M or 8G, got `{s}`");
    let t = s.trim();
    let t = t.strip_suffix("iB").or_else(|| t.strip_suffix('B')).unwrap_or(t);
    let (number, scale) = match t.chars().last().map(|c| c.to_ascii_uppercase()) {
        Some('K') => (&t[..t.len() - 1], 1u64 << 10),
        Some('M') => (&t[..t.len() - 1], 1 << 20),
        Some('G') => (&t[..t.len() - 1], 1 << 30),
        Some('T') => (&t[..t.len() - 1], 1 << 40),
        _ => (t, 1),
    };
    let x = number.trim().parse::<f64>().map_err(|_| bad())? * scale as f64;
    if x.is_finite() && (0.0..1.8e19).contains(&x) {
        Ok(x as u64)
    } else {
        Err(bad())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_access_table_is_read_with_paths_from_the_file_folder() {
        let text = "# a project\nname = \"x\"\n[access]\nallow_read = [\"../scans\", # old scans\n  '/data/m#1']\n\
                    allow_write = [\"renders\"]\nmax_writes = 1_000\nmax_write_size = \"8G\"\n[other]\nk = 1\n";
        let s = Settings::parse(text, Path::new("/p")).unwrap();
        assert_eq!(s.allow_read, [PathBuf::from("/p/../scans"), PathBuf::from("/data/m#1")]);
        assert_eq!(s.allow_write, [PathBuf::from("/p/renders")]);
        assert_eq!((s.max_writes, s.max_write_size), (Some(1000), Some(8 << 30)));
    }

    #[test]
    fn mistakes_name_the_line_and_the_key() {
        let e = Settings::parse("[access]\nallow_red = [\"x\"]\n", Path::new("/p")).unwrap_err();
        assert!(e.starts_with("2: unknown key `allow_red`"), "{e}");
        let e = Settings::parse("[access]\nmax_writes = \"many\"\n", Path::new("/p")).unwrap_err();
        assert!(e.starts_with("2: `max_writes` must be a number"), "{e}");
        let e = Settings::parse("[access]\nallow_read = [\"x\"\n", Path::new("/p")).unwrap_err();
        assert!(e.contains("never closed"), "{e}");
    }
}
