//! Atomic file replacement: write beside the target, then rename over it; and staged
//! writes, which keep the renamed-over step for later so that a command with several
//! outputs replaces all of them or none.
//!
//! The protocol, in order: create a temporary file `.beltrami-XXXXXX.tmp` in the
//! target's directory (same file system, so the rename is atomic), write, `fsync` the
//! file, rename it over the target, `fsync` the directory (Unix) so that the rename
//! itself survives a power loss. Until the rename, the target is untouched; after it,
//! the target is the whole new file. A reader therefore sees the old file or the new
//! one, never a mixture, even when the writing process is killed.
//! [`set_flush_to_disk`]`(false)` leaves out the two flushes: the replacement stays a
//! rename, which a killed process cannot tear, but a power loss may, and so may a
//! write error that only a flush reports (network file systems).
//!
//! On every error the temporary file is removed. Every temporary file alive is also
//! listed in a process-wide registry, so that a program's signal handler can remove
//! them with [`remove_staged_files`] before it exits (the `beltrami` CLI does this on
//! Ctrl-C and `SIGTERM`). Only a process killed outright (`SIGKILL`, power loss) can
//! leave one behind, under a fresh random name that no later write reuses.
//!
//! A target that is a symbolic link is written through: the link stays, and the file
//! it points to is replaced.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, MutexGuard};

use tempfile::{NamedTempFile, TempPath};

use crate::error::IoError;
use crate::format::{MeshFormat, VertexAttributes, WriteOptions};
use crate::write::{write_mesh_to, write_ply_to};
use beltrami_halfedge::MeshData;

/// The temporary files of staged writes that are neither committed nor dropped yet,
/// and whether [`remove_staged_files`] has run.
///
/// Every step that creates, renames or removes a temporary file holds this lock, so
/// that a signal handler running on another thread sees each file either not yet
/// created or listed, never created and not yet listed; and once the handler has
/// closed the registry, no new temporary file is created before the process exits.
static LIVE: Mutex<Registry> = Mutex::new(Registry {
    closed: false,
    paths: Vec::new(),
});

struct Registry {
    /// Set by [`remove_staged_files`]: later writes fail instead of creating files.
    closed: bool,
    paths: Vec<PathBuf>,
}

impl Registry {
    /// Takes `path` off the list of live temporary files.
    fn forget(&mut self, path: &Path) {
        self.paths.retain(|p| p != path);
    }

    /// The error of a write attempted after [`remove_staged_files`].
    fn check_open(&self) -> Result<(), IoError> {
        if self.closed {
            Err(IoError::Io {
                operation: "create a file in the output's directory",
                source: std::io::Error::new(
                    std::io::ErrorKind::Interrupted,
                    "the process is being interrupted",
                ),
            })
        } else {
            Ok(())
        }
    }
}

/// Whether staged and atomic writes flush to disk ([`set_flush_to_disk`]).
static FLUSH: AtomicBool = AtomicBool::new(true);

/// Sets whether this process's staged and atomic writes flush each file and its
/// directory to disk (`fsync`) before and after the rename: on by default. Off, the
/// target is still replaced by a rename (a killed process leaves it untouched), but a
/// power loss or operating-system crash soon after may leave the old file, an empty
/// one or a partly written one there; and a write error that a file system reports
/// only when the file is flushed (network file systems may, for a full disk or a
/// quota) goes unnoticed, so that a short file can replace the target. Each flush costs
/// about 0.3 ms on a local disk; for many small files into local scratch space.
pub fn set_flush_to_disk(flush: bool) {
    FLUSH.store(flush, Ordering::Relaxed);
}

thread_local! {
    /// This thread's choice, which overrides [`FLUSH`] while set ([`with_flush_to_disk`]).
    static FLUSH_HERE: std::cell::Cell<Option<bool>> = const { std::cell::Cell::new(None) };
}

/// Runs `f` with this thread's staged and atomic writes flushing to disk or not, as
/// `flush` says, whatever [`set_flush_to_disk`] set for the process (what `flush = false`
/// gives up is said there). The thread's previous choice comes back when `f` returns or
/// panics. For a choice per call, where the process-wide switch would reach other
/// threads' writes too (Python's `write(..., sync=False)`); writes that `f` hands to
/// other threads keep the process's setting.
pub fn with_flush_to_disk<T>(flush: bool, f: impl FnOnce() -> T) -> T {
    /// Puts the thread's previous choice back when dropped, also when `f` panics.
    struct Restore(Option<bool>);
    impl Drop for Restore {
        fn drop(&mut self) {
            FLUSH_HERE.with(|here| here.set(self.0));
        }
    }
    let _restore = Restore(FLUSH_HERE.with(|here| here.replace(Some(flush))));
    f()
}

/// Whether staged and atomic writes flush to disk: this thread's choice inside
/// [`with_flush_to_disk`], else the process's ([`set_flush_to_disk`]).
#[must_use]
pub fn flushes_to_disk() -> bool {
    FLUSH_HERE
        .with(std::cell::Cell::get)
        .unwrap_or_else(|| FLUSH.load(Ordering::Relaxed))
}

fn live() -> MutexGuard<'static, Registry> {
    // A panic while the list was held leaves it consistent (push/retain only).
    LIVE.lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Removes every temporary file of a staged or in-progress atomic write of this
/// process, and returns how many were removed. Meant for a signal handler that is
/// about to end the process (Ctrl-C, `SIGTERM`): the targets stay untouched, and no
/// `.beltrami-*.tmp` file is left behind.
///
/// Afterwards the process writes no more files through this module: staged files
/// whose temporary file is gone fail to commit, and new writes (and
/// [`check_writable`]) fail with [`IoError::Io`] of kind `Interrupted`. A write that
/// another thread is committing at the moment of the call finishes first (the
/// target is then the whole new file).
pub fn remove_staged_files() -> usize {
    let mut registry = live();
    registry.closed = true;
    let mut removed = 0;
    for path in registry.paths.drain(..) {
        let done = if path.is_dir() {
            fs::remove_dir_all(&path)
        } else {
            fs::remove_file(&path)
        };
        if done.is_ok() {
            removed += 1;
        }
    }
    removed
}

/// A file written to a temporary file beside its target and flushed to disk (unless
/// [`set_flush_to_disk`]`(false)`), waiting
/// for [`commit`](Self::commit) to rename it over the target. Dropping it removes
/// the temporary file and leaves the target untouched.
///
/// Stage every output of a command first, then commit them all: a failure while
/// producing any output then changes no file.
///
/// # Examples
/// ```
/// use beltrami_io::stage_bytes;
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let dir = tempfile::tempdir()?;
/// let (a, b) = (dir.path().join("a.json"), dir.path().join("b.json"));
/// let staged = [stage_bytes(&a, b"{}")?, stage_bytes(&b, b"[]")?];
/// assert!(!a.exists() && !b.exists());
/// for file in staged {
///     file.commit()?;
/// }
/// assert_eq!(std::fs::read(&b)?, b"[]");
/// # Ok(())
/// # }
/// ```
#[derive(Debug)]
#[must_use = "a staged file is removed unless it is committed"]
pub struct StagedFile {
    temp: Option<TempPath>,
    /// The file that the commit replaces (a symbolic link resolved).
    target: PathBuf,
    /// The directory of `target`, flushed after the rename.
    dir: PathBuf,
}

impl StagedFile {
    /// The file that [`commit`](Self::commit) replaces: the path given, or the file
    /// it links to when it is a symbolic link.
    #[must_use]
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Renames the temporary file over the target and flushes the directory (unless
    /// [`set_flush_to_disk`]`(false)`).
    ///
    /// # Errors
    /// [`IoError::Io`] when the rename fails (then the temporary file is removed and
    /// the target untouched) or the directory cannot be flushed.
    pub fn commit(self) -> Result<(), IoError> {
        let dir = self.rename()?;
        sync_directory(&dir)
    }

    /// Renames the temporary file over the target and returns the directory to flush.
    fn rename(mut self) -> Result<PathBuf, IoError> {
        let Some(temp) = self.temp.take() else {
            unreachable!("a staged file holds its temporary file until commit or drop")
        };
        let temp_path = temp.to_path_buf();
        let mut registry = live();
        // On failure the returned `PathPersistError` owns the temporary path, and
        // dropping it (in `map_err`, under the lock) removes the file.
        let result = temp.persist(&self.target).map_err(|e| IoError::Io {
            operation: "replace the target file",
            source: without_path(&e.error),
        });
        registry.forget(&temp_path);
        drop(registry);
        result?;
        Ok(std::mem::take(&mut self.dir))
    }
}

/// Commits `files` in order, as [`StagedFile::commit`] does one by one, but flushes
/// each directory once, after the last rename into it: a command writing its mesh and
/// its report into one directory flushes that directory once instead of twice. (One
/// by one, each file was durable before the next was renamed; here all are once the
/// call returns `Ok`, flushing on.)
///
/// # Errors
/// The index in `files` of the file that failed, with its error. When a rename fails,
/// the files before it are in place, and that file and the ones after it are removed
/// with their targets untouched; that error is returned even if a flush failed too.
/// Otherwise every file is in place, and when flushing a directory fails the error is
/// that of the first directory that failed (index: the last file renamed into it);
/// every directory is flushed either way.
pub fn commit_staged(files: Vec<StagedFile>) -> Result<(), (usize, IoError)> {
    // (directory, index of the last file renamed into it), in order of first use.
    let mut dirs: Vec<(PathBuf, usize)> = Vec::new();
    let mut failed = None;
    for (index, file) in files.into_iter().enumerate() {
        if failed.is_some() {
            // Dropped: its temporary file is removed.
            continue;
        }
        match file.rename() {
            Ok(dir) => match dirs.iter_mut().find(|(d, _)| *d == dir) {
                Some(entry) => entry.1 = index,
                None => dirs.push((dir, index)),
            },
            Err(e) => failed = Some((index, e)),
        }
    }
    let mut flush_failed = None;
    for (dir, index) in &dirs {
        if let Err(e) = sync_directory(dir) {
            flush_failed.get_or_insert((*index, e));
        }
    }
    match failed.or(flush_failed) {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

impl Drop for StagedFile {
    fn drop(&mut self) {
        if let Some(temp) = self.temp.take() {
            let mut registry = live();
            registry.forget(&temp);
            drop(temp);
        }
    }
}

/// An `std::io::Error` of the same kind and OS code, without the temporary file's
/// name that `tempfile` adds: messages name the path the user gave, not
/// `.beltrami-XXXXXX.tmp`.
fn without_path(e: &std::io::Error) -> std::io::Error {
    match e.raw_os_error() {
        Some(code) => std::io::Error::from_raw_os_error(code),
        // tempfile wraps the system's error as "<error> at path \"<temporary file>\"":
        // its message without the temporary name (the bare kind said only "entity not
        // found").
        None => {
            let text = e.to_string();
            match text.find(" at path \"") {
                Some(end) if end > 0 => std::io::Error::new(e.kind(), &text[..end]),
                _ => std::io::Error::from(e.kind()),
            }
        }
    }
}

/// The error of creating a temporary file in `dir`: the system's message, naming the
/// directory (not the temporary file).
fn temporary_file_error(dir: &Path, e: &std::io::Error) -> IoError {
    let bare = without_path(e);
    IoError::Io {
        operation: "create a file in the output's directory",
        source: std::io::Error::new(bare.kind(), format!("{}: {bare}", dir.display())),
    }
}

/// The file a write to `path` replaces: `path` itself, or for a symbolic link the
/// file it points to (followed through chains of links; a dangling link names the
/// file it would create).
///
/// # Errors
/// [`IoError::Io`] when a link cannot be read or the links form a loop.
pub fn resolve_target(path: impl AsRef<Path>) -> Result<PathBuf, IoError> {
    let path = path.as_ref();
    let mut current = path.to_path_buf();
    // Linux's own limit on links followed in one lookup.
    for _ in 0..40 {
        match fs::symlink_metadata(&current) {
            Ok(meta) if meta.file_type().is_symlink() => {
                let link = fs::read_link(&current)
                    .map_err(|e| IoError::io("read the symbolic link")(without_path(&e)))?;
                current = match current.parent() {
                    Some(parent) if link.is_relative() => parent.join(link),
                    _ => link,
                };
            }
            _ => return Ok(current),
        }
    }
    Err(IoError::Io {
        operation: "follow the symbolic link",
        source: std::io::Error::other("too many levels of symbolic links"),
    })
}

/// Refuses `out.ply/` (and `out.ply/.`, `..`): a path ending in a slash, `.` or `..`
/// names a directory, which no file can replace (the rename at the end of a write would
/// fail, after all the work).
fn refuse_directory_name(path: &Path) -> Result<(), IoError> {
    let text = path.as_os_str().to_string_lossy();
    let last = text
        .rsplit(['/', std::path::MAIN_SEPARATOR])
        .next()
        .unwrap_or("");
    if last.is_empty() || last == "." || last == ".." {
        return Err(IoError::Io {
            operation: "write the output",
            source: std::io::Error::other(
                "a path ending in a slash, `.` or `..` names a directory; give a file name",
            ),
        });
    }
    Ok(())
}

/// The directory a file at `path` lives in (`.` for a bare file name).
fn directory_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Checks, without writing anything that stays, that a file can be written at
/// `path`: its directory (of the link's target, for a symbolic link) exists, is a
/// directory, and a file can be created in it. Call it for every output before a
/// long computation, so that a typo in a directory name fails at once.
///
/// # Errors
/// [`IoError::Io`] naming what failed: the path ends in a slash (a directory's name),
/// the directory does not exist or is not a directory, or a file cannot be created in
/// it (permissions, read-only file system, full disk).
pub fn check_writable(path: impl AsRef<Path>) -> Result<(), IoError> {
    let path = path.as_ref();
    refuse_directory_name(path)?;
    let target = resolve_target(path)?;
    let dir = directory_of(&target);
    match fs::metadata(&dir) {
        Ok(meta) if meta.is_dir() => {}
        Ok(_) => {
            return Err(IoError::Io {
                operation: "use the output's directory",
                source: std::io::Error::other(format!("{} is not a directory", dir.display())),
            });
        }
        Err(e) => {
            return Err(IoError::Io {
                operation: "find the output's directory",
                source: std::io::Error::new(
                    e.kind(),
                    format!("{}: {}", dir.display(), without_path(&e)),
                ),
            });
        }
    }
    if fs::metadata(&target).is_ok_and(|m| m.is_dir()) {
        return Err(IoError::Io {
            operation: "write the output",
            source: std::io::Error::other("it is a directory"),
        });
    }
    // The probe file is removed when it is dropped, before the lock is released: a
    // signal handler cannot run between its creation and its removal.
    let registry = live();
    registry.check_open()?;
    temp_builder()
        .tempfile_in(&dir)
        .map(drop)
        .map_err(|e| temporary_file_error(&dir, &e))
}

fn temp_builder() -> tempfile::Builder<'static, 'static> {
    let mut builder = tempfile::Builder::new();
    builder.prefix(".beltrami-").suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(fs::Permissions::from_mode(0o666));
    }
    builder
}

/// Runs `write` on a temporary file in the directory of `path` (of its target, for a
/// symbolic link) and flushes it to disk (unless [`set_flush_to_disk`]`(false)`). The
/// result replaces the target on [`StagedFile::commit`]; on any error, or when the result is dropped, the
/// temporary file is removed and the target is untouched.
///
/// A new file gets the permissions a plain create would give it (`0o666` less the
/// umask on Unix); an existing file keeps its permissions.
///
/// # Errors
/// [`IoError::Io`] naming the operation that failed, and every error of `write`.
pub fn stage_with(
    path: impl AsRef<Path>,
    write: impl FnOnce(&mut dyn Write) -> Result<(), IoError>,
) -> Result<StagedFile, IoError> {
    let path = path.as_ref();
    refuse_directory_name(path)?;
    let target = resolve_target(path)?;
    let dir = directory_of(&target);
    let mut registry = live();
    registry.check_open()?;
    let mut file: NamedTempFile = temp_builder()
        .tempfile_in(&dir)
        .map_err(|e| temporary_file_error(&dir, &e))?;
    registry.paths.push(file.path().to_path_buf());
    drop(registry);
    let result = (|| {
        if let Ok(existing) = fs::metadata(&target)
            && existing.is_file()
        {
            file.as_file()
                .set_permissions(existing.permissions())
                .map_err(|e| IoError::io("copy the permissions of the existing file")(e))?;
        }
        write(&mut file)?;
        if !flushes_to_disk() {
            return Ok(());
        }
        file.as_file()
            .sync_all()
            .map_err(IoError::io("flush the file to disk"))
    })();
    let temp = file.into_temp_path();
    match result {
        Ok(()) => Ok(StagedFile {
            temp: Some(temp),
            target,
            dir,
        }),
        Err(e) => {
            let mut registry = live();
            registry.forget(&temp);
            drop(temp);
            Err(e)
        }
    }
}

/// A directory being filled beside its target, which [`commit`](Self::commit) puts in
/// the target's place (replacing an earlier directory there as a whole). Dropping it
/// removes it and everything in it, and leaves the target untouched.
///
/// # Examples
/// ```
/// use beltrami_io::stage_dir;
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let parent = tempfile::tempdir()?;
/// let target = parent.path().join("results");
/// let staged = stage_dir(&target)?;
/// std::fs::write(staged.path().join("table.csv"), "a,b\n")?;
/// assert!(!target.exists());
/// staged.commit()?;
/// assert!(target.join("table.csv").exists());
/// # Ok(())
/// # }
/// ```
#[derive(Debug)]
#[must_use = "a staged directory is removed unless it is committed"]
pub struct StagedDir {
    temp: Option<tempfile::TempDir>,
    target: PathBuf,
}

/// Creates an empty directory beside `path` (a hidden `.beltrami-XXXXXX.tmp` in the
/// same parent directory), to be filled and then put in place of `path` by
/// [`StagedDir::commit`]. Like staged files, it is listed for
/// [`remove_staged_files`].
///
/// # Errors
/// [`IoError::Io`] when the directory cannot be created (a missing parent,
/// permissions).
pub fn stage_dir(path: impl AsRef<Path>) -> Result<StagedDir, IoError> {
    let path = path.as_ref();
    let parent = directory_of(path);
    let mut registry = live();
    registry.check_open()?;
    let temp = tempfile::Builder::new()
        .prefix(".beltrami-")
        .suffix(".tmp")
        .tempdir_in(&parent)
        .map_err(|e| IoError::Io {
            operation: "create a directory beside the output directory",
            source: without_path(&e),
        })?;
    registry.paths.push(temp.path().to_path_buf());
    drop(registry);
    Ok(StagedDir {
        temp: Some(temp),
        target: path.to_path_buf(),
    })
}

impl StagedDir {
    /// The directory to fill.
    #[must_use]
    pub fn path(&self) -> &Path {
        self.temp
            .as_ref()
            .map_or(self.target.as_path(), tempfile::TempDir::path)
    }

    /// Puts the filled directory in place of the target: an existing target
    /// directory is first renamed aside, then removed once the new one is in place.
    ///
    /// # Errors
    /// [`IoError::Io`] when a rename fails; the target is then as it was.
    pub fn commit(mut self) -> Result<(), IoError> {
        let Some(temp) = self.temp.take() else {
            unreachable!("a staged directory holds its directory until commit or drop")
        };
        // The renames run under the registry's lock: a signal handler waits for them,
        // so that neither the new directory nor the old one is left under a temporary
        // name.
        let mut registry = live();
        let new = temp.keep();
        registry.forget(&new);
        let parent = directory_of(&self.target);
        let old = if self.target.exists() {
            let aside = tempfile::Builder::new()
                .prefix(".beltrami-")
                .suffix(".old")
                .tempdir_in(&parent)
                .map_err(|e| {
                    IoError::io("create a directory beside the output directory")(without_path(&e))
                })?
                .keep();
            // A rename over an empty directory replaces it.
            if let Err(e) = fs::rename(&self.target, &aside) {
                let _ = fs::remove_dir_all(&new);
                let _ = fs::remove_dir(&aside);
                return Err(IoError::io("move the earlier output directory aside")(
                    without_path(&e),
                ));
            }
            Some(aside)
        } else {
            None
        };
        if let Err(e) = fs::rename(&new, &self.target) {
            if let Some(aside) = &old {
                let _ = fs::rename(aside, &self.target);
            }
            let _ = fs::remove_dir_all(&new);
            return Err(IoError::io("put the output directory in place")(
                without_path(&e),
            ));
        }
        if let Some(aside) = old {
            fs::remove_dir_all(&aside).map_err(|e| {
                IoError::io("remove the earlier output directory")(without_path(&e))
            })?;
        }
        drop(registry);
        sync_directory(&parent)
    }
}

impl Drop for StagedDir {
    fn drop(&mut self) {
        if let Some(temp) = self.temp.take() {
            let mut registry = live();
            registry.forget(temp.path());
            drop(temp);
        }
    }
}

/// Runs `write` on a temporary file beside `path`, then renames it over `path`: the
/// atomic replacement of one file (see the module documentation).
pub(crate) fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> Result<(), IoError>,
) -> Result<(), IoError> {
    stage_with(path, write)?.commit()
}

/// Stages `bytes` for `path` (see [`stage_with`]).
///
/// # Errors
/// As [`stage_with`].
pub fn stage_bytes(path: impl AsRef<Path>, bytes: &[u8]) -> Result<StagedFile, IoError> {
    let path = path.as_ref();
    stage_with(path, |file| {
        file.write_all(bytes).map_err(IoError::io("write the file"))
    })
}

/// Stages a mesh file for `path`, in the format of its extension, as
/// [`write_mesh`](crate::write_mesh) writes it (see [`stage_with`]).
///
/// # Errors
/// The errors of [`write_mesh`](crate::write_mesh).
pub fn stage_mesh(
    path: impl AsRef<Path>,
    mesh: &MeshData,
    options: &WriteOptions,
) -> Result<StagedFile, IoError> {
    let path = path.as_ref();
    let format = MeshFormat::from_path(path)?;
    stage_with(path, |file| write_mesh_to(file, mesh, format, options))
}

/// Stages a PLY file with per-vertex attributes for `path`, as
/// [`write_ply`](crate::write_ply) writes it (see [`stage_with`]).
///
/// # Errors
/// The errors of [`write_ply`](crate::write_ply).
pub fn stage_ply(
    path: impl AsRef<Path>,
    mesh: &MeshData,
    attributes: &VertexAttributes,
    options: &WriteOptions,
) -> Result<StagedFile, IoError> {
    let path = path.as_ref();
    stage_with(path, |file| write_ply_to(file, mesh, attributes, options))
}

/// Flushes the directory entry of a renamed file to disk. File systems that cannot
/// sync a directory (the call fails with `EINVAL` there) make the rename durable
/// anyway, so that failure is not an error.
#[cfg(unix)]
fn sync_directory(dir: &Path) -> Result<(), IoError> {
    if !flushes_to_disk() {
        return Ok(());
    }
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
/// that the rename is durable (both flushes unless [`set_flush_to_disk`]`(false)`). On
/// any error an existing file is
/// left untouched and no temporary file remains. Use it for reports (JSON, CSV) that
/// must never be half-written.
///
/// # Errors
/// [`IoError::Io`] naming the operation that failed (creating the temporary file in
/// the target's directory, writing, flushing, renaming, flushing the directory).
pub fn write_bytes_atomic(path: impl AsRef<Path>, bytes: &[u8]) -> Result<(), IoError> {
    let path = path.as_ref();
    stage_bytes(path, bytes)?.commit()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temporaries(dir: &Path) -> Vec<String> {
        fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|name| name.starts_with(".beltrami-"))
            .collect()
    }

    #[test]
    fn a_dropped_stage_leaves_the_target_and_no_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.json");
        fs::write(&path, b"old").unwrap();
        let staged = stage_bytes(&path, b"new").unwrap();
        assert_eq!(temporaries(dir.path()).len(), 1);
        assert_eq!(fs::read(&path).unwrap(), b"old");
        drop(staged);
        assert_eq!(fs::read(&path).unwrap(), b"old");
        assert!(temporaries(dir.path()).is_empty());
    }

    #[test]
    fn committing_together_replaces_every_target_in_order() {
        let (one, two) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
        let paths = [
            one.path().join("a.ply"),
            two.path().join("b.json"),
            one.path().join("c.json"),
        ];
        fs::write(&paths[2], b"old").unwrap();
        let files = paths
            .iter()
            .zip([&b"a"[..], b"b", b"c"])
            .map(|(p, bytes)| stage_bytes(p, bytes).unwrap())
            .collect();
        commit_staged(files).unwrap();
        for (p, bytes) in paths.iter().zip([&b"a"[..], b"b", b"c"]) {
            assert_eq!(fs::read(p).unwrap(), bytes);
        }
        assert!(temporaries(one.path()).is_empty() && temporaries(two.path()).is_empty());
    }

    #[test]
    fn a_failed_rename_keeps_the_earlier_files_and_removes_the_later() {
        let dir = tempfile::tempdir().unwrap();
        let first = dir.path().join("first.ply");
        // A non-empty directory: renaming a file over it fails.
        let blocked = dir.path().join("blocked");
        fs::create_dir(&blocked).unwrap();
        fs::write(blocked.join("keep"), b"x").unwrap();
        let last = dir.path().join("last.json");
        fs::write(&last, b"old").unwrap();
        let files = vec![
            stage_bytes(&first, b"new").unwrap(),
            stage_bytes(&blocked, b"new").unwrap(),
            stage_bytes(&last, b"new").unwrap(),
        ];
        let (index, e) = commit_staged(files).unwrap_err();
        assert_eq!(index, 1, "{e}");
        assert!(e.to_string().contains("replace the target file"), "{e}");
        assert_eq!(fs::read(&first).unwrap(), b"new");
        assert!(blocked.join("keep").exists());
        assert_eq!(fs::read(&last).unwrap(), b"old");
        assert!(temporaries(dir.path()).is_empty());
    }

    // `remove_staged_files` closes the process-wide registry, so its test runs in a
    // process of its own: tests/interrupt.rs.

    #[cfg(unix)]
    #[test]
    fn a_symbolic_link_is_written_through() {
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real.json");
        fs::write(&real, b"old").unwrap();
        let link = dir.path().join("link.json");
        std::os::unix::fs::symlink("real.json", &link).unwrap();
        write_bytes_atomic(&link, b"new").unwrap();
        assert!(
            fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(fs::read(&real).unwrap(), b"new");
    }

    #[test]
    fn check_writable_names_a_missing_directory_not_a_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("nope").join("out.ply");
        let e = check_writable(&missing).unwrap_err().to_string();
        assert!(e.contains("nope"), "{e}");
        assert!(!e.contains(".beltrami-"), "{e}");
        check_writable(dir.path().join("out.ply")).unwrap();
        assert!(check_writable(dir.path()).is_err());
        assert!(temporaries(dir.path()).is_empty());
    }

    /// `out.ply/` names a directory: refused before any work, not at the final rename.
    #[test]
    fn check_writable_refuses_a_trailing_slash() {
        let dir = tempfile::tempdir().unwrap();
        for name in ["out.ply/", "out.ply/.", "out.ply/..", "."] {
            let slash = format!("{}/{name}", dir.path().display());
            let e = check_writable(&slash).unwrap_err().to_string();
            assert!(e.contains("names a directory"), "{name}: {e}");
        }
        check_writable(dir.path().join("out.ply")).unwrap();
        assert!(temporaries(dir.path()).is_empty());
    }

    /// The choice holds inside the call only, nests, comes back after a panic, and does
    /// not reach another thread. (The process-wide switch is left on: other tests of
    /// this binary write files.)
    #[test]
    fn a_thread_s_choice_holds_inside_the_call_only() {
        assert!(flushes_to_disk());
        with_flush_to_disk(false, || {
            assert!(!flushes_to_disk());
            with_flush_to_disk(true, || assert!(flushes_to_disk()));
            assert!(!flushes_to_disk());
            let other = std::thread::spawn(flushes_to_disk).join().unwrap();
            assert!(other, "another thread keeps the process's setting");
        });
        assert!(flushes_to_disk());
        let panicked = std::panic::catch_unwind(|| {
            with_flush_to_disk(false, || panic!("inside"));
        });
        assert!(panicked.is_err());
        assert!(flushes_to_disk());
    }
}
