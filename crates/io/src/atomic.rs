//! Atomic file replacement: write beside the target, then rename over it.
//!
//! The protocol, in order: create a temporary file `.beltrami-XXXXXX.tmp` in the
//! target's directory (same file system, so the rename is atomic), write, `fsync` the
//! file, rename it over the target, `fsync` the directory (Unix) so that the rename
//! itself survives a power loss. Until the rename, the target is untouched; after it,
//! the target is the whole new file. A reader therefore sees the old file or the new
//! one, never a mixture, even when the writing process is killed. On every error the
//! temporary file is removed; only a process killed outright (`SIGKILL`, power loss)
//! can leave one behind, under a fresh random name that no later write reuses.

use std::fs;
use std::path::Path;

use tempfile::NamedTempFile;

use crate::error::IoError;

/// Runs `write` on a temporary file in the directory of `path`, flushes it to disk,
/// renames it over `path` and flushes the directory. On any error before the rename
/// the temporary file is removed and an existing `path` is left untouched.
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
    // On failure the returned `PersistError` owns the temporary file, and dropping it
    // removes the file.
    file.persist(path).map_err(|e| IoError::Io {
        operation: "replace the target file",
        source: e.error,
    })?;
    sync_directory(dir)
}

/// Flushes the directory entry of a renamed file to disk. File systems that cannot
/// sync a directory (the call fails with `EINVAL` there) make the rename durable
/// anyway, so that failure is not an error.
#[cfg(unix)]
fn sync_directory(dir: &Path) -> Result<(), IoError> {
    let directory = fs::File::open(dir).map_err(IoError::io("open the target's directory"))?;
    match directory.sync_all() {
        Err(e) if e.kind() != std::io::ErrorKind::InvalidInput => Err(IoError::Io {
            operation: "flush the target's directory to disk",
            source: e,
        }),
        _ => Ok(()),
    }
}

/// Directories cannot be opened as files here; the rename is as durable as the
/// platform makes it.
#[cfg(not(unix))]
#[allow(clippy::unnecessary_wraps, reason = "the same signature as on Unix")]
fn sync_directory(_dir: &Path) -> Result<(), IoError> {
    Ok(())
}

/// Writes `bytes` to `path` atomically: the bytes go to a temporary file beside `path`,
/// which is flushed to disk and renamed over `path`, and the directory is flushed so
/// that the rename is durable. On any error an existing file is
/// left untouched and no temporary file remains. Use it for reports (JSON, CSV) that
/// must never be half-written.
///
/// # Errors
/// [`IoError::Io`] naming the operation that failed (creating the temporary file in
/// the target's directory, writing, flushing, renaming, flushing the directory).
pub fn write_bytes_atomic(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    use std::io::Write;
    write_atomic(path, |file| {
        file.write_all(bytes).map_err(IoError::io("write the file"))
    })
}
