//! Atomic file replacement: write beside the target, then rename over it.

use std::fs;
use std::path::Path;

use tempfile::NamedTempFile;

use crate::error::IoError;

/// Runs `write` on a temporary file in the directory of `path`, flushes it to disk
/// and renames it over `path`. On any error the temporary file is removed and an
/// existing `path` is left untouched.
///
/// A new file gets the permissions a plain create would give it (`0o666` less the
/// umask on Unix); an existing file keeps its permissions.
pub(crate) fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut NamedTempFile) -> Result<(), IoError>,
) -> Result<(), IoError> {
    let dir = match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".beltrami-").suffix(".tmp");
    #[cfg(unix)]
    let permissions = {
        use std::os::unix::fs::PermissionsExt;
        fs::Permissions::from_mode(0o666)
    };
    #[cfg(unix)]
    builder.permissions(permissions);
    let mut file = builder
        .tempfile_in(dir)
        .map_err(IoError::io("create a temporary file beside the target"))?;
    if let Ok(existing) = fs::metadata(path) {
        if existing.is_file() {
            file.as_file()
                .set_permissions(existing.permissions())
                .map_err(IoError::io("copy the permissions of the existing file"))?;
        }
    }
    write(&mut file)?;
    file.as_file()
        .sync_all()
        .map_err(IoError::io("flush the file to disk"))?;
    file.persist(path).map_err(|e| IoError::Io {
        operation: "replace the target file",
        source: e.error,
    })?;
    Ok(())
}

/// Writes `bytes` to `path` atomically: the bytes go to a temporary file beside `path`,
/// which is flushed to disk and renamed over `path`. On any error an existing file is
/// left untouched and no temporary file remains. Use it for reports (JSON, CSV) that
/// must never be half-written.
///
/// # Errors
/// [`IoError::Io`] naming the operation that failed (creating the temporary file in
/// the target's directory, writing, flushing, renaming).
pub fn write_bytes_atomic(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    use std::io::Write;
    write_atomic(path, |file| {
        file.write_all(bytes).map_err(IoError::io("write the file"))
    })
}
