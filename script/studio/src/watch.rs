//! Re-running on save: the folders of every file the last run read (the recipe, the modules
//! it imported, the files it loaded — the run's record, see [`blocksmith_script::record::RunRecord`]) are
//! watched (`notify`), and the set follows the runs: a new import's folder is added, a folder
//! no run reads any more is dropped. A change to the contents or name of one of those files,
//! or of a `.rhai` file beside the recipe (a module the recipe is about to import), is told
//! to the session once the files have been quiet for [`DEBOUNCE`] and their sizes are what
//! they were at their last event, so an editor's burst of writes — truncate, write, rename —
//! makes one run, and never one on a half-written file. Reads (the runs' own) and other files
//! in those folders do not count, and the session tells a run's own saves from edits (see
//! [`Session::files_changed`]), so a run never starts another.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::sync::Arc;
use std::time::Duration;

use notify::event::{EventKind, ModifyKind};
use notify::{RecursiveMode, Watcher};

use super::session::Session;

/// The quiet time after the last change before a run: editors write a file in one burst
/// (well under this), and it is part of every save-to-screen latency.
pub const DEBOUNCE: Duration = Duration::from_millis(20);

/// What the watching thread hears.
enum Heard {
    /// A file changed.
    Changed(PathBuf),
    /// A run read these files, each as it was when the run ended.
    Inputs(Vec<(PathBuf, Option<FileStamp>)>),
}

/// What tells one version of a file from another: its length, modification time and inode
/// (an editor's save by rename makes a new inode).
#[derive(Clone, Debug, PartialEq, Eq)]
struct FileStamp(u64, Option<std::time::SystemTime>, u64);

impl FileStamp {
    fn of(path: &Path) -> Option<FileStamp> {
        let m = std::fs::metadata(path).ok()?;
        #[cfg(unix)]
        let inode = std::os::unix::fs::MetadataExt::ino(&m);
        #[cfg(not(unix))]
        let inode = 0;
        Some(FileStamp(m.len(), m.modified().ok(), inode))
    }
}

/// Whether a change to `changed` should run the recipe at `recipe` again, `inputs` being the
/// files the last run read. All paths absolute, symbolic links resolved.
#[must_use]
pub fn triggers(recipe: &Path, inputs: &BTreeSet<PathBuf>, changed: &Path) -> bool {
    let beside =
        changed.parent() == recipe.parent() && changed.extension().is_some_and(|e| e.eq_ignore_ascii_case("rhai"));
    changed == recipe || inputs.contains(changed) || beside
}

/// The size of the file at `path` (`None`: no file).
fn size(path: &Path) -> Option<u64> {
    std::fs::metadata(path).ok().map(|m| m.len())
}

/// Whether an event of `kind` changes what a file holds (not a read, not its metadata).
#[must_use]
pub fn is_change(kind: &EventKind) -> bool {
    match kind {
        EventKind::Create(_) | EventKind::Remove(_) => true,
        EventKind::Modify(m) => !matches!(m, ModifyKind::Metadata(_)),
        _ => false,
    }
}

/// The folders to watch for `recipe` and `inputs`: each one's parent, once.
#[must_use]
pub fn folders(recipe: &Path, inputs: &BTreeSet<PathBuf>) -> BTreeSet<PathBuf> {
    std::iter::once(recipe)
        .chain(inputs.iter().map(PathBuf::as_path))
        .filter_map(Path::parent)
        .map(Path::to_path_buf)
        .collect()
}

/// Watches the files of the session's runs for as long as the process lives.
///
/// # Errors
/// The recipe's folder cannot be watched.
pub fn watch(session: &Arc<Session>) -> Result<(), String> {
    let recipe = std::fs::canonicalize(session.source.path())
        .map_err(|e| format!("error: cannot watch {}: {e}", session.source.path().display()))?;
    let (heard, hearing) = mpsc::channel::<Heard>();
    let events = heard.clone();
    let mut watcher = notify::recommended_watcher(move |event: notify::Result<notify::Event>| {
        if let Ok(event) = event {
            if is_change(&event.kind) {
                for p in event.paths {
                    let _ = events.send(Heard::Changed(p));
                }
            }
        }
    })
    .map_err(|e| format!("error: cannot watch {}: {e}", recipe.display()))?;
    let mut watched = BTreeSet::new();
    for dir in folders(&recipe, &BTreeSet::new()) {
        watcher
            .watch(&dir, RecursiveMode::NonRecursive)
            .map_err(|e| format!("error: cannot watch {}: {e}", dir.display()))?;
        watched.insert(dir);
    }
    session.on_inputs(move |inputs| {
        let stamped = inputs.iter().map(|p| (p.clone(), FileStamp::of(p))).collect();
        let _ = heard.send(Heard::Inputs(stamped));
    });
    let target = Arc::clone(session);
    let mut watched: BTreeMap<PathBuf, Option<Identity>> =
        watched.into_iter().map(|d| (d.clone(), identity(&d))).collect();
    std::thread::spawn(move || {
        let mut inputs = BTreeSet::new();
        // Watches the folders of the recipe and `inputs` and no others. A folder newly watched
        // was not watched while the run read its files: those that changed since (their stamp
        // when the run ended differs from now) are returned, as their events were not heard.
        let follow = |watcher: &mut notify::RecommendedWatcher,
                      watched: &mut BTreeMap<PathBuf, Option<Identity>>,
                      stamped: &[(PathBuf, Option<FileStamp>)]|
         -> Vec<PathBuf> {
            let inputs: BTreeSet<PathBuf> = stamped.iter().map(|(p, _)| p.clone()).collect();
            let wanted = folders(&recipe, &inputs);
            watched.retain(|dir, _| {
                let keep = wanted.contains(dir);
                if !keep {
                    let _ = watcher.unwatch(dir);
                }
                keep
            });
            let mut missed = Vec::new();
            for new in wanted {
                if let std::collections::btree_map::Entry::Vacant(slot) = watched.entry(new) {
                    if let Err(e) = watcher.watch(slot.key(), RecursiveMode::NonRecursive) {
                        eprintln!("warning: cannot watch {}: {e}", slot.key().display());
                    }
                    let id = identity(slot.key());
                    let dir = slot.key().clone();
                    slot.insert(id);
                    missed.extend(
                        stamped
                            .iter()
                            .filter(|(p, then)| p.parent() == Some(dir.as_path()) && FileStamp::of(p) != *then)
                            .map(|(p, _)| p.clone()),
                    );
                }
            }
            missed
        };
        // One run per burst: wait for a change that counts, then for the quiet after it, with
        // every changed file the size it had at its last event.
        loop {
            let first = match hearing.recv_timeout(CHECK) {
                Ok(Heard::Inputs(now)) => {
                    inputs = now.iter().map(|(p, _)| p.clone()).collect();
                    let missed = follow(&mut watcher, &mut watched, &now);
                    if !missed.is_empty() {
                        target.files_changed(&missed);
                    }
                    continue;
                }
                Ok(Heard::Changed(p)) if triggers(&recipe, &inputs, &p) => p,
                Ok(Heard::Changed(_)) => continue,
                Err(mpsc::RecvTimeoutError::Timeout) => {
                    if replaced(&mut watcher, &mut watched) {
                        target.files_changed(std::slice::from_ref(&recipe));
                    }
                    continue;
                }
                Err(mpsc::RecvTimeoutError::Disconnected) => return,
            };
            let mut changed: BTreeMap<PathBuf, Option<u64>> = BTreeMap::new();
            changed.insert(first.clone(), size(&first));
            loop {
                match hearing.recv_timeout(DEBOUNCE) {
                    Ok(Heard::Changed(p)) => {
                        if triggers(&recipe, &inputs, &p) {
                            changed.insert(p.clone(), size(&p));
                        }
                    }
                    Ok(Heard::Inputs(now)) => {
                        inputs = now.iter().map(|(p, _)| p.clone()).collect();
                        for p in follow(&mut watcher, &mut watched, &now) {
                            changed.insert(p.clone(), size(&p));
                        }
                    }
                    Err(mpsc::RecvTimeoutError::Timeout) => {
                        let growing: Vec<PathBuf> =
                            changed.iter().filter(|(p, &n)| size(p) != n).map(|(p, _)| p.clone()).collect();
                        if growing.is_empty() {
                            break;
                        }
                        for p in growing {
                            changed.insert(p.clone(), size(&p));
                        }
                    }
                    Err(mpsc::RecvTimeoutError::Disconnected) => return,
                }
            }
            target.files_changed(&changed.into_keys().collect::<Vec<_>>());
        }
    });
    Ok(())
}

/// How often the watched folders are checked for having been replaced.
pub const CHECK: Duration = Duration::from_millis(250);

/// Watches again each watched folder that was deleted and made again (a `git checkout` of
/// another branch does this): to the operating system it is a new folder, which the old watch
/// does not see. Whether any was, so its files count as changed.
fn replaced(watcher: &mut impl Watcher, watched: &mut BTreeMap<PathBuf, Option<Identity>>) -> bool {
    let mut any = false;
    for (dir, id) in watched.iter_mut() {
        let now = identity(dir);
        if now == *id {
            continue;
        }
        let _ = watcher.unwatch(dir);
        if now.is_some() {
            if watcher.watch(dir, RecursiveMode::NonRecursive).is_err() {
                continue; // not yet: at the next check
            }
            any = true;
        }
        *id = now;
    }
    any
}

/// What tells a folder from another made at the same path (device and inode on Unix).
type Identity = (u64, u64);

/// The identity of the folder at `path`, `None` when there is none.
fn identity(path: &Path) -> Option<Identity> {
    let m = std::fs::metadata(path).ok()?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        Some((m.dev(), m.ino()))
    }
    #[cfg(not(unix))]
    {
        let made = m.created().ok().and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok());
        Some((0, made.map_or(0, |d| d.as_nanos() as u64)))
    }
}

#[cfg(test)]
mod tests {
    use notify::event::{AccessKind, CreateKind, DataChange, MetadataKind};

    use super::*;

    #[test]
    fn the_recipe_its_inputs_and_scripts_beside_it_trigger_and_other_files_do_not() {
        let r = Path::new("/a/gear.rhai");
        let inputs: BTreeSet<PathBuf> =
            [r, Path::new("/lib/teeth.rhai"), Path::new("/a/data/profile.stl")].map(PathBuf::from).into();
        assert!(triggers(r, &inputs, r));
        assert!(triggers(r, &inputs, Path::new("/a/_parts.RHAI")));
        assert!(triggers(r, &inputs, Path::new("/lib/teeth.rhai")));
        assert!(triggers(r, &inputs, Path::new("/a/data/profile.stl")));
        assert!(!triggers(r, &inputs, Path::new("/lib/other.rhai")), "only the imported module of another folder");
        assert!(!triggers(r, &inputs, Path::new("/a/data/other.stl")));
        assert!(!triggers(r, &inputs, Path::new("/a/gear.glb")));
        assert!(!triggers(r, &inputs, Path::new("/a/notes.txt")));
        let dirs: Vec<PathBuf> = folders(r, &inputs).into_iter().collect();
        assert_eq!(dirs, ["/a", "/a/data", "/lib"].map(PathBuf::from));
    }

    #[test]
    fn writes_count_and_reads_do_not() {
        assert!(is_change(&EventKind::Modify(ModifyKind::Data(DataChange::Any))));
        assert!(is_change(&EventKind::Create(CreateKind::File)));
        assert!(!is_change(&EventKind::Access(AccessKind::Any)));
        assert!(!is_change(&EventKind::Modify(ModifyKind::Metadata(MetadataKind::Any))));
    }
}
