//! Re-running on save: the recipe's folder is watched (`notify`); a change to the contents or
//! name of the recipe or of a `.rhai` file beside it (its imports) asks the session for a run
//! once the folder has been quiet for [`DEBOUNCE`], so an editor's burst of writes — truncate,
//! write, rename — makes one run, and never one on a half-written file. Reads (the runs' own)
//! and model files the recipe writes there do not count, so a run never starts another.

use std::path::Path;
use std::sync::mpsc;
use std::sync::Arc;
use std::time::Duration;

use notify::event::{EventKind, ModifyKind};
use notify::{RecommendedWatcher, RecursiveMode, Watcher};

use super::session::Session;

/// The quiet time after the last change before a run.
pub const DEBOUNCE: Duration = Duration::from_millis(50);

/// Whether a change to `changed` should run the recipe at `recipe` again.
#[must_use]
pub fn triggers(recipe: &Path, changed: &Path) -> bool {
    changed == recipe || changed.extension().is_some_and(|e| e.eq_ignore_ascii_case("rhai"))
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

/// Watches the folder of the session's file until the returned watcher is dropped.
///
/// # Errors
/// The folder cannot be watched.
pub fn watch(session: &Arc<Session>) -> Result<RecommendedWatcher, String> {
    let file = std::fs::canonicalize(session.source.path())
        .map_err(|e| format!("error: cannot watch {}: {e}", session.source.path().display()))?;
    let dir = file.parent().map_or_else(|| Path::new(".").to_path_buf(), Path::to_path_buf);
    let (changed, changes) = mpsc::channel::<()>();
    let mut watcher = notify::recommended_watcher(move |event: notify::Result<notify::Event>| {
        if let Ok(event) = event {
            if is_change(&event.kind) && event.paths.iter().any(|p| triggers(&file, p)) {
                let _ = changed.send(());
            }
        }
    })
    .map_err(|e| format!("error: cannot watch {}: {e}", dir.display()))?;
    watcher
        .watch(&dir, RecursiveMode::NonRecursive)
        .map_err(|e| format!("error: cannot watch {}: {e}", dir.display()))?;
    let target = Arc::clone(session);
    std::thread::spawn(move || {
        // One run per burst: wait for a change, then for the quiet after it.
        while changes.recv().is_ok() {
            loop {
                match changes.recv_timeout(DEBOUNCE) {
                    Ok(()) => {}
                    Err(mpsc::RecvTimeoutError::Timeout) => break,
                    Err(mpsc::RecvTimeoutError::Disconnected) => return,
                }
            }
            target.request_run();
        }
    });
    Ok(watcher)
}

#[cfg(test)]
mod tests {
    use notify::event::{AccessKind, CreateKind, DataChange, MetadataKind};

    use super::*;

    #[test]
    fn the_recipe_and_scripts_beside_it_trigger_and_written_models_do_not() {
        let r = Path::new("/a/gear.rhai");
        assert!(triggers(r, r));
        assert!(triggers(r, Path::new("/a/_parts.RHAI")));
        assert!(!triggers(r, Path::new("/a/gear.glb")));
        assert!(!triggers(r, Path::new("/a/notes.txt")));
    }

    #[test]
    fn writes_count_and_reads_do_not() {
        assert!(is_change(&EventKind::Modify(ModifyKind::Data(DataChange::Any))));
        assert!(is_change(&EventKind::Create(CreateKind::File)));
        assert!(!is_change(&EventKind::Access(AccessKind::Any)));
        assert!(!is_change(&EventKind::Modify(ModifyKind::Metadata(MetadataKind::Any))));
    }
}
