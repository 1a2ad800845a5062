//! Saves that never destroy a file: the bytes go to a temporary file in the destination's own
//! folder, which is flushed, synced to disk and then renamed over the destination.
//!
//! A rename within one file system is atomic (POSIX `rename(2)`), so a reader sees either the
//! old file or the new one, never a partial file; when anything fails before the rename (the
//! writer's own error, a full disk, a file-size limit) the temporary file is removed and the
//! old file is left as it was.

use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use super::IoError;

/// Writes the file at `path` atomically: runs `write` on a buffered writer to a temporary file
/// in the same folder, then flushes, syncs and renames it into place.
///
/// A new file gets the permissions a plain create would give it (0666 less the umask); a
/// replaced file keeps its permissions. A symbolic link at `path` is replaced by the file.
///
/// # Errors
/// `write`'s own error as it is; [`IoError::Write`] naming `path` when the temporary file
/// cannot be created, written, synced or renamed. In every case the old file (if any) is
/// intact and no temporary file remains.
///
/// See also [`super::save`], which writes every mesh format through this function.
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<(), IoError>,
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
    let (file, temp_path) = builder.tempfile_in(dir).map_err(io_error)?.into_parts();
    let mut w = BufWriter::with_capacity(1 << 20, file);
    write(&mut w)?;
    let file = w.into_inner().map_err(|e| io_error(e.into_error()))?;
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
}
