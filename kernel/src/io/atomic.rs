//! Saves that never destroy a file: the bytes go to a temporary file in the destination's own
//! folder, which is flushed, synced to disk and then renamed over the destination.
//!
//! A rename within one file system is atomic (POSIX `rename(2)`), so a reader sees either the
//! old file or the new one, never a partial file; when anything fails before the rename (the
//! writer's own error, a full disk, a file-size limit) the temporary file is removed and the
//! old file is left as it was.
//!
//! Writing a large file stops with the current cancellation token: every buffer handed to the
//! file (a megabyte) first polls it ([`crate::limits::poll`]), so a save stopped by a deadline
//! or Ctrl-C ends as quickly, with the old file intact and its temporary file removed.
//!
//! Every temporary file is also listed, while it lives, in a process-wide registry: a signal
//! handler that must end the process at once (SIGTERM, a second Ctrl-C) calls
//! [`remove_temporaries`] first, so that no `.NAME.*.tmp` is left behind on any way out that
//! can be caught (SIGKILL cannot).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The temporary files of the saves under way.
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Removes every temporary file of the saves under way in this process (see the module
/// documentation), returning how many it removed. The saves themselves then fail at their
/// rename, leaving their old files as they were. Meant for a signal handler (ctrlc's runs on
/// its own thread, where taking a lock is allowed) just before it exits.
pub fn remove_temporaries() -> usize {
    remove_temporaries_where(|_| true)
}

/// [`remove_temporaries`] for the temporary files `keep_out` accepts only (tests, which run
/// beside other tests' saves).
fn remove_temporaries_where(keep_out: impl Fn(&Path) -> bool) -> usize {
    let mut live = LIVE.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    let n = live.iter().filter(|p| keep_out(p) && std::fs::remove_file(p).is_ok()).count();
    live.retain(|p| !keep_out(p));
    n
}

/// A temporary file's entry in the registry, taken out when dropped.
struct Registered(PathBuf);

impl Registered {
    fn new(path: &Path) -> Registered {
        LIVE.lock().unwrap_or_else(std::sync::PoisonError::into_inner).push(path.to_path_buf());
        Registered(path.to_path_buf())
    }
}

impl Drop for Registered {
    fn drop(&mut self) {
        let mut live = LIVE.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some(i) = live.iter().position(|p| *p == self.0) {
            live.swap_remove(i);
        }
    }
}

use super::IoError;
use crate::mesh::MeshError;

/// The temporary file a save writes, polling the current cancellation token before each write
/// (see the module documentation).
#[derive(Debug)]
pub struct StoppableFile(File);

impl Write for StoppableFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        crate::limits::poll().map_err(std::io::Error::other)?;
        self.0.write(buf)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.0.flush()
    }
}

/// Writes the file at `path` atomically: runs `write` on a buffered writer to a temporary file
/// in the same folder, then flushes, syncs and renames it into place.
///
/// A new file gets the permissions a plain create would give it (0666 less the umask); a
/// replaced file keeps its permissions. A symbolic link at `path` is replaced by the file.
///
/// # Errors
/// `write`'s own error as it is; [`IoError::Mesh`] with [`MeshError::Limit`] when the
/// current cancellation token stopped the writing; [`IoError::Write`] naming `path` when the
/// temporary file cannot be created, written, synced or renamed. In every case the old file (if any) is
/// intact and no temporary file remains.
///
/// See also [`super::save`], which writes every mesh format through this function.
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<StoppableFile>) -> Result<(), IoError>,
) -> Result<(), IoError> {
    let io_error = |source: std::io::Error| IoError::Write { path: path.into(), source };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let prefix = format!(".{name}.");
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        // The mode is passed to open(2), which applies the umask; an existing file's mode is
        // kept exactly.
        let mode = std::fs::metadata(path).map(|m| m.permissions().mode() & 0o7777).unwrap_or(0o666);
        builder.permissions(std::fs::Permissions::from_mode(mode));
    }
    // Dropping `temp_path` on any early return removes the temporary file.
    // Declared before `temp_path`, so dropped after it: the file goes before its entry does,
    // and a handler never misses a live temporary.
    let _registered: Registered;
    let (file, temp_path) = builder.tempfile_in(dir).map_err(io_error)?.into_parts();
    _registered = Registered::new(&temp_path);
    let mut w = BufWriter::with_capacity(1 << 20, StoppableFile(file));
    let written = write(&mut w).and_then(|()| w.flush().map_err(io_error));
    if let Err(e) = written {
        // A stop shows as the writer's error on the way out; name it as the stop it is.
        return Err(match crate::limits::poll() {
            Err(stop) => IoError::Mesh { path: path.into(), source: MeshError::Limit(stop) },
            Ok(()) => e,
        });
    }
    let file = w.into_inner().map_err(|e| io_error(e.into_error()))?.0;
    file.sync_all().map_err(io_error)?;
    drop(file);
    temp_path.persist(path).map_err(|e| io_error(e.error))?;
    // The rename itself is durable once the folder is synced; a failure here loses nothing.
    if let Ok(d) = File::open(dir) {
        let _ = d.sync_all();
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn entries(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> =
            std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        names.sort();
        names
    }

    #[test]
    fn a_writer_failing_half_way_leaves_the_old_file_and_no_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("old.obj");
        std::fs::write(&path, b"the old contents").unwrap();
        // 3 MB written (past the 1 MB buffer, so bytes reached the temporary file) then an error.
        let e = write_atomic(&path, |w| {
            w.write_all(&vec![b'x'; 3 << 20]).unwrap();
            Err(IoError::Internal { path: path.clone(), reason: "failed half-way".into() })
        })
        .unwrap_err();
        assert!(e.to_string().contains("failed half-way"), "{e}");
        assert_eq!(std::fs::read(&path).unwrap(), b"the old contents");
        assert_eq!(entries(dir.path()), ["old.obj"]);
    }

    #[test]
    fn a_save_stopped_while_writing_names_the_stop_and_leaves_the_old_file() {
        use crate::limits::{install, CancelToken};
        use std::sync::atomic::{AtomicBool, Ordering};
        use std::sync::Arc;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("old.glb");
        std::fs::write(&path, b"the old contents").unwrap();
        let flag = Arc::new(AtomicBool::new(false));
        let _g = install(CancelToken::with(Some(flag.clone()), None, None));
        // The stop comes after the first megabyte: the next buffer handed to the file sees it.
        let e = write_atomic(&path, |w| {
            for i in 0..8 {
                if i == 1 {
                    flag.store(true, Ordering::Relaxed);
                }
                w.write_all(&vec![b'x'; 1 << 20]).map_err(|e| IoError::Write { path: path.clone(), source: e })?;
            }
            Ok(())
        })
        .unwrap_err();
        assert_eq!(e.to_string(), format!("{}: interrupted", path.display()));
        assert_eq!(std::fs::read(&path).unwrap(), b"the old contents");
        assert_eq!(entries(dir.path()), ["old.glb"]);
    }

    #[test]
    fn a_successful_write_replaces_the_file_and_keeps_its_mode() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("m.stl");
        std::fs::write(&path, b"old").unwrap();
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o640)).unwrap();
        }
        write_atomic(&path, |w| w.write_all(b"new").map_err(|e| IoError::Write { path: path.clone(), source: e }))
            .unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"new");
        assert_eq!(entries(dir.path()), ["m.stl"]);
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            assert_eq!(std::fs::metadata(&path).unwrap().permissions().mode() & 0o777, 0o640);
        }
    }

    #[test]
    fn a_missing_folder_is_a_write_error_naming_the_path() {
        let e = write_atomic(Path::new("/nonexistent/dir/x.obj"), |_| Ok(())).unwrap_err();
        assert!(matches!(e, IoError::Write { .. }) && e.to_string().starts_with("/nonexistent/dir/x.obj"), "{e}");
    }

    #[test]
    fn a_signal_handler_removes_the_temporaries_of_saves_under_way() {
        // A save blocked half-way (its writer waiting) while another thread — a signal
        // handler — removes the live temporaries: the file is gone at once, and the save then
        // fails at its rename with the old file intact and nothing left behind.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("big.stl");
        std::fs::write(&path, b"the old contents").unwrap();
        let (started, wait) = std::sync::mpsc::channel::<()>();
        let (go, resume) = std::sync::mpsc::channel::<()>();
        let handler = {
            let dir = dir.path().to_path_buf();
            std::thread::spawn(move || {
                wait.recv().unwrap();
                assert!(entries(&dir).iter().any(|n| n.starts_with(".big.stl.") && n.ends_with(".tmp")));
                assert_eq!(remove_temporaries_where(|p| p.starts_with(&dir)), 1);
                let left = entries(&dir);
                go.send(()).unwrap();
                left
            })
        };
        let r = write_atomic(&path, |w| {
            w.write_all(&vec![b'x'; 3 << 20]).map_err(|e| IoError::Write { path: path.clone(), source: e })?;
            started.send(()).unwrap();
            resume.recv().unwrap();
            Ok(())
        });
        assert_eq!(handler.join().unwrap(), ["big.stl"], "the handler left no temporary file");
        assert!(r.is_err());
        assert_eq!(std::fs::read(&path).unwrap(), b"the old contents");
        assert_eq!(entries(dir.path()), ["big.stl"]);
    }
}
