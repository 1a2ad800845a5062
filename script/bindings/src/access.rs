//! What a run may read and write: its project, the paths the user granted, and how much it may
//! write ([`Policy`], set by the host; [`Access`], a run's copy with what it has written).
//!
//! The rule (README "Limits and guarantees"): a confined run reads and writes only inside its
//! **project** — the nearest folder above the recipe holding `.git` or a `blocksmith.toml`,
//! else the recipe's own folder ([`project_of`]) — and the paths the policy grants (`-o`,
//! `--out`, `--manifest`, `--allow-read`, `--allow-write`, `blocksmith.toml`). Paths are judged
//! by their real location: symbolic links and `..` resolved, a path that does not exist yet by
//! its nearest existing ancestor ([`real_path`]). Whatever the confinement, no save replaces the
//! recipe or a module it imported, or a file without write permission, and a run writes at most
//! [`Policy::max_writes`] files and about [`Policy::max_write_bytes`] bytes.
//!
//! A policy whose saves are [`Saves::Report`] (`blocksmith params`, `render`, `watch`) writes
//! nothing: each save the recipe asks for is listed ([`Access::reported`]) instead.

use std::cell::RefCell;
use std::path::{Component, Path, PathBuf};
use std::rc::Rc;
use std::sync::RwLock;

/// What a run does with the saves a recipe asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Saves {
    /// Writes them (within the policy).
    Write,
    /// Writes nothing: lists each instead (`blocksmith params`, `render`, `watch`).
    Report,
}

/// What runs may read and write, set by the host (the `blocksmith` command from its flags and
/// `blocksmith.toml`) for the whole process ([`set_policy`]), as the memory budget is.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct Policy {
    /// Whether reads and writes are held to the project and the granted paths.
    /// Default value: `false` (a program embedding the library decides; the `blocksmith`
    /// command confines every run).
    pub confined: bool,
    /// Files and folders (with everything under them) a run may read besides its project.
    /// Default value: none.
    pub read: Vec<PathBuf>,
    /// Files and folders (with everything under them) a run may write, and read, besides its
    /// project. Default value: none.
    pub write: Vec<PathBuf>,
    /// Whether saves are done or only reported. Default value: [`Saves::Write`].
    pub saves: Saves,
    /// How many files one run may write. Default value: [`Policy::DEFAULT_MAX_WRITES`] (100).
    pub max_writes: u64,
    /// How many bytes one run may write: a save is refused once the run has written this
    /// many. Default value: [`Policy::DEFAULT_MAX_WRITE_BYTES`] (4 GiB).
    pub max_write_bytes: u64,
}

impl Policy {
    /// The files a run may write unless raised (`--max-writes`): a recipe saving in a loop
    /// stops here rather than filling a folder.
    pub const DEFAULT_MAX_WRITES: u64 = 100;
    /// The bytes a run may write unless raised (`--max-write-size`).
    pub const DEFAULT_MAX_WRITE_BYTES: u64 = 4 << 30;
    /// Not confined, saves written, the default limits.
    pub const DEFAULT: Policy = Policy {
        confined: false,
        read: Vec::new(),
        write: Vec::new(),
        saves: Saves::Write,
        max_writes: Policy::DEFAULT_MAX_WRITES,
        max_write_bytes: Policy::DEFAULT_MAX_WRITE_BYTES,
    };

    /// The policy held to the project and the granted paths.
    #[must_use]
    pub fn confined(self) -> Policy {
        Policy { confined: true, ..self }
    }

    /// The policy with `paths` readable too.
    #[must_use]
    pub fn with_read(mut self, paths: impl IntoIterator<Item = PathBuf>) -> Policy {
        self.read.extend(paths);
        self
    }

    /// The policy with `paths` writable (and readable) too.
    #[must_use]
    pub fn with_write(mut self, paths: impl IntoIterator<Item = PathBuf>) -> Policy {
        self.write.extend(paths);
        self
    }

    /// The policy with saves done or only reported.
    #[must_use]
    pub fn with_saves(self, saves: Saves) -> Policy {
        Policy { saves, ..self }
    }

    /// The policy with other write limits.
    #[must_use]
    pub fn with_write_limits(self, max_writes: u64, max_write_bytes: u64) -> Policy {
        Policy { max_writes, max_write_bytes, ..self }
    }
}

impl Default for Policy {
    fn default() -> Policy {
        Policy::DEFAULT
    }
}

static POLICY: RwLock<Policy> = RwLock::new(Policy::DEFAULT);

/// Sets the policy of every run started after it in this process ([`Access::default`]).
pub fn set_policy(policy: Policy) {
    *POLICY.write().unwrap_or_else(std::sync::PoisonError::into_inner) = policy;
}

/// The process's policy ([`set_policy`]; [`Policy::DEFAULT`] until set).
#[must_use]
pub fn policy() -> Policy {
    POLICY.read().unwrap_or_else(std::sync::PoisonError::into_inner).clone()
}

/// The project of a recipe in the folder `dir`: the nearest folder at or above it holding
/// `.git` or a `blocksmith.toml`, else `dir` itself; as a real path.
#[must_use]
pub fn project_of(dir: &Path) -> PathBuf {
    let dir = real_path(dir).unwrap_or_else(|_| dir.to_path_buf());
    dir.ancestors()
        .find(|d| d.join(".git").exists() || d.join("blocksmith.toml").is_file())
        .map_or_else(|| dir.clone(), Path::to_path_buf)
}

/// Where `path` really is: absolute, every symbolic link and `..` resolved. A path that does
/// not exist yet is its nearest existing ancestor's real path followed by the rest.
///
/// # Errors
/// A symbolic link whose target does not exist (writing through it would create a file
/// wherever it points), or no working directory.
pub fn real_path(path: &Path) -> Result<PathBuf, String> {
    let absolute = std::path::absolute(path).map_err(|e| format!("cannot resolve `{}`: {e}", path.display()))?;
    let mut real = PathBuf::new();
    for c in absolute.components() {
        match c {
            Component::Prefix(_) | Component::RootDir => real.push(c),
            Component::CurDir => {}
            // `real` is a real path (or a missing one below a real one): its parent is `..`.
            Component::ParentDir => {
                real.pop();
            }
            Component::Normal(name) => {
                let next = real.join(name);
                real = match next.symlink_metadata() {
                    Ok(meta) if meta.file_type().is_symlink() => next.canonicalize().map_err(|_| {
                        format!("`{}` is a symbolic link to a file that does not exist", path.display())
                    })?,
                    _ => next,
                };
            }
        }
    }
    Ok(real)
}

/// The run's own state: its policy made concrete (the project found, granted paths resolved)
/// and what it has written.
#[derive(Debug)]
struct State {
    policy: Policy,
    /// The project's real path, once known (see [`Access::enter`]).
    project: Option<PathBuf>,
    read: Vec<PathBuf>,
    write: Vec<PathBuf>,
    /// Paths the host writes through the script's `save` (`run -o`, the studio's own file).
    host: Vec<PathBuf>,
    files: u64,
    bytes: u64,
    reported: Vec<PathBuf>,
}

/// A run's access: the process's [`Policy`] for one run, with its project and what it has
/// written. Carried in the [`crate::RunContext`]; cloning shares it.
#[derive(Clone, Debug)]
pub struct Access(Rc<RefCell<State>>);

impl Default for Access {
    /// The process's policy ([`policy`]).
    fn default() -> Access {
        Access::new(policy())
    }
}

/// What a write check decided.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Write {
    /// Write the file at this path.
    Do(PathBuf),
    /// Write nothing: the policy only reports saves (listed in [`Access::reported`]).
    Report,
}

impl Access {
    /// A run's access under `policy`, its project not yet known.
    #[must_use]
    pub fn new(policy: Policy) -> Access {
        let resolve = |ps: &[PathBuf]| ps.iter().map(|p| real_path(p).unwrap_or_else(|_| p.clone())).collect();
        let (read, write) = (resolve(&policy.read), resolve(&policy.write));
        Access(Rc::new(RefCell::new(State {
            policy,
            project: None,
            read,
            write,
            host: Vec::new(),
            files: 0,
            bytes: 0,
            reported: Vec::new(),
        })))
    }

    /// The access with saves only reported, whatever the process's policy says (the studio's
    /// runs).
    #[must_use]
    pub fn reporting(self) -> Access {
        self.0.borrow_mut().policy.saves = Saves::Report;
        self
    }

    /// Starts the run of the recipe at `recipe`: its project is found from its folder.
    pub fn enter(&self, recipe: &Path) {
        let dir = recipe.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
        self.0.borrow_mut().project = Some(project_of(dir));
    }

    /// The project: the recipe's ([`Access::enter`]), else the working directory's.
    #[must_use]
    pub fn project(&self) -> PathBuf {
        if let Some(p) = &self.0.borrow().project {
            return p.clone();
        }
        let project = project_of(Path::new("."));
        self.0.borrow_mut().project = Some(project.clone());
        project
    }

    /// Lets the host write `path` through the script's `save` (the `-o` of `blocksmith run`,
    /// the studio's temporary file), whatever the confinement and even when saves are only
    /// reported; the recipe and read-only files stay refused.
    pub fn grant_host(&self, path: &Path) {
        if let Ok(p) = real_path(path) {
            self.0.borrow_mut().host.push(p);
        }
    }

    /// Whether the host named `path` for writing ([`Access::grant_host`]).
    #[must_use]
    pub fn is_host(&self, path: &Path) -> bool {
        real_path(path).is_ok_and(|p| self.0.borrow().host.contains(&p))
    }

    /// The saves not done because saves are only reported, in order.
    #[must_use]
    pub fn reported(&self) -> Vec<PathBuf> {
        self.0.borrow().reported.clone()
    }

    /// Whether `real` is inside the project or one of `granted`.
    fn inside(&self, real: &Path, granted: impl Fn(&State) -> Vec<PathBuf>) -> bool {
        let project = self.project();
        let s = self.0.borrow();
        real.starts_with(&project) || granted(&s).iter().any(|g| real.starts_with(g))
    }

    /// Checks that the run may read `path` (a `load`, an `import`);
    ///
    /// # Errors
    /// A path outside the project and the granted paths, naming the flag that allows it.
    pub fn check_read(&self, path: &Path) -> Result<(), String> {
        if !self.0.borrow().policy.confined {
            return Ok(());
        }
        let real = real_path(path)?;
        if self.inside(&real, |s| [s.read.clone(), s.write.clone(), s.host.clone()].concat()) {
            return Ok(());
        }
        Err(self.outside(path, &real, "read"))
    }

    fn outside(&self, path: &Path, real: &Path, what: &str) -> String {
        let shown = if real == path { String::new() } else { format!(" (really {})", real.display()) };
        let folder = if real.is_dir() { real } else { real.parent().unwrap_or(real) };
        format!(
            "`{}`{shown} is outside the project {} (the nearest folder above the recipe holding .git or \
             blocksmith.toml, else the recipe's own): a recipe may {what} only there; allow it with \
             --allow-{what} {} (or `allow_{what}` in blocksmith.toml)",
            path.display(),
            self.project().display(),
            folder.display(),
        )
    }

    /// Checks that the run may write `path` (a `save`), and counts the file: [`Write::Do`] with
    /// where to write, or [`Write::Report`] when saves are only reported. `protected` are the
    /// files no save may replace (the recipe and the modules it imported).
    ///
    /// # Errors
    /// A path outside the project and the granted paths (naming the flag that allows it), the
    /// recipe or an imported module, a file without write permission, or a run that has
    /// written its limit of files or bytes (naming how to raise it).
    pub fn check_write(&self, path: &Path, protected: &[PathBuf]) -> Result<Write, String> {
        let real = real_path(path)?;
        let host = self.0.borrow().host.contains(&real);
        if !host && self.0.borrow().policy.saves == Saves::Report {
            // Nothing is written, so nothing is refused: the listing shows every save asked for.
            self.0.borrow_mut().reported.push(path.to_path_buf());
            return Ok(Write::Report);
        }
        check_replaceable(path, &real, protected)?;
        if host {
            return Ok(Write::Do(path.to_path_buf()));
        }
        if self.0.borrow().policy.confined && !self.inside(&real, |s| s.write.clone()) {
            return Err(self.outside(path, &real, "write"));
        }
        let mut s = self.0.borrow_mut();
        if s.files >= s.policy.max_writes {
            return Err(format!(
                "not writing `{}`: this run has written {} files, its limit (raise it with --max-writes N \
                 or `max_writes` in blocksmith.toml)",
                path.display(),
                s.files
            ));
        }
        if s.bytes >= s.policy.max_write_bytes {
            return Err(format!(
                "not writing `{}`: this run has written {} bytes, its limit of {} (raise it with \
                 --max-write-size SIZE or `max_write_size` in blocksmith.toml)",
                path.display(),
                s.bytes,
                s.policy.max_write_bytes
            ));
        }
        s.files += 1;
        Ok(Write::Do(path.to_path_buf()))
    }

    /// Counts the bytes of the file just written at `path` (and of the buffers a `.gltf` names).
    pub fn wrote(&self, path: &Path) {
        let size = |p: &Path| std::fs::metadata(p).map_or(0, |m| m.len());
        let mut bytes = size(path);
        if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("gltf")) {
            bytes += crate::gltf_buffers::buffer_files(path).iter().map(|b| size(b)).sum::<u64>();
        }
        let mut s = self.0.borrow_mut();
        s.bytes = s.bytes.saturating_add(bytes);
    }
}

/// Checks that a file the host itself writes (`--manifest`, `render -o`) may be replaced: it
/// is none of `protected` (the recipe, its imports) and is not read-only.
///
/// # Errors
/// As above, naming the path.
pub fn check_host_write(path: &Path, protected: &[PathBuf]) -> Result<(), String> {
    let real = real_path(path)?;
    check_replaceable(path, &real, protected)
}

fn check_replaceable(path: &Path, real: &Path, protected: &[PathBuf]) -> Result<(), String> {
    // A .gltf's save also replaces the buffers it names now (the new buffer is named by its
    // content, so it replaces nothing).
    let targets = if real.extension().is_some_and(|e| e.eq_ignore_ascii_case("gltf")) {
        [vec![real.to_path_buf()], crate::gltf_buffers::buffer_files(real)].concat()
    } else {
        vec![real.to_path_buf()]
    };
    for target in &targets {
        if protected.iter().any(|p| real_path(p).is_ok_and(|p| &p == target)) {
            return Err(format!(
                "not writing `{}`: it is the recipe or a module it imports, which a run never replaces",
                target.display()
            ));
        }
        if std::fs::metadata(target).is_ok_and(|m| m.permissions().readonly()) {
            return Err(format!(
                "not writing `{}`: the file is read-only, and a run never replaces a file without write \
                 permission (make it writable first if you mean to replace it)",
                path.display()
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn real_paths_resolve_links_and_parents_even_below_missing_folders() {
        let d = tempfile::tempdir().unwrap();
        let root = d.path().canonicalize().unwrap();
        std::fs::create_dir(root.join("in")).unwrap();
        std::os::unix::fs::symlink("/", root.join("in/up")).unwrap();
        // A link is followed; `..` climbs from where the link really points.
        assert_eq!(real_path(&root.join("in/up/etc")).unwrap(), Path::new("/etc"));
        // Below a missing folder `..` is still applied, and links after it followed again.
        assert_eq!(real_path(&root.join("in/missing/../up/tmp/x")).unwrap(), Path::new("/tmp/x"));
        assert_eq!(real_path(&root.join("in/a/b/../../../x")).unwrap(), root.join("x"));
        std::os::unix::fs::symlink(root.join("nowhere"), root.join("in/dangling")).unwrap();
        assert!(real_path(&root.join("in/dangling")).unwrap_err().contains("does not exist"));
    }

    #[test]
    fn a_confined_run_reads_and_writes_only_in_its_project_and_granted_paths() {
        let d = tempfile::tempdir().unwrap();
        let root = d.path().canonicalize().unwrap();
        std::fs::create_dir_all(root.join("proj/sub")).unwrap();
        std::fs::create_dir(root.join("proj/.git")).unwrap();
        std::fs::create_dir(root.join("other")).unwrap();
        let access = Access::new(Policy::DEFAULT.confined().with_read([root.join("other")]));
        // The project is the folder holding .git above the recipe.
        access.enter(&root.join("proj/sub/r.rhai"));
        assert_eq!(access.project(), root.join("proj"));
        assert!(access.check_read(&root.join("proj/a.obj")).is_ok());
        assert!(access.check_read(&root.join("other/a.obj")).is_ok());
        let e = access.check_write(&root.join("other/a.obj"), &[]).unwrap_err();
        assert!(e.contains("--allow-write") && e.contains("other"), "{e}");
        let e = access.check_read(&root.join("proj/../x.obj")).unwrap_err();
        assert!(e.contains("--allow-read") && e.contains("outside the project"), "{e}");
        assert_eq!(
            access.check_write(&root.join("proj/sub/a.obj"), &[]).unwrap(),
            Write::Do(root.join("proj/sub/a.obj"))
        );
    }

    #[test]
    fn writes_stop_at_the_limit_and_reported_saves_are_not_counted() {
        let access = Access::new(Policy::DEFAULT.with_write_limits(2, u64::MAX));
        for _ in 0..2 {
            assert!(access.check_write(Path::new("a.obj"), &[]).is_ok());
        }
        let e = access.check_write(Path::new("a.obj"), &[]).unwrap_err();
        assert!(e.contains("written 2 files") && e.contains("--max-writes"), "{e}");
        let report = Access::new(Policy::DEFAULT.with_saves(Saves::Report));
        assert_eq!(report.check_write(Path::new("a.obj"), &[]).unwrap(), Write::Report);
        assert_eq!(report.reported(), [PathBuf::from("a.obj")]);
    }
}
