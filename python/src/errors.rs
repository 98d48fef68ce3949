//! The Python exceptions and the mapping of the library's errors onto them.
//!
//! Messages are the library error's one line, prefixed with the file's path where a
//! file is involved, as the command line prints them.

use std::io::ErrorKind;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::Duration;

use beltrami_halfedge::TopologyError;
use beltrami_io::IoError;

use pyo3::exceptions::{
    PyFileExistsError, PyFileNotFoundError, PyIsADirectoryError, PyOSError, PyPermissionError,
    PyRuntimeError, PyTypeError, PyValueError,
};
use pyo3::prelude::*;

/// The Python integer `value` given as the argument `name` in the unsigned type `T` (a
/// count, a level or a seed), or a `ValueError` naming the argument: integers arrive as
/// `i128`, so that a negative one is a value error like any other instead of the
/// conversion's `OverflowError`.
pub(crate) fn nonnegative<T: TryFrom<i128>>(name: &str, value: i128) -> PyResult<T> {
    T::try_from(value).map_err(|_| {
        PyValueError::new_err(if value < 0 {
            format!("{name} must be 0 or more, got {value}")
        } else {
            format!("{name} is too large: {value}")
        })
    })
}

/// An optional integer argument of at least `min`, as a `T`: a `ValueError` that states
/// the real limit ("vertices must be at least 1, got -1") below it, and says it is too
/// large when it does not fit.
pub(crate) fn at_least_opt<T: TryFrom<i128>>(
    name: &str,
    value: Option<i128>,
    min: i128,
) -> PyResult<Option<T>> {
    value
        .map(|v| {
            if v < min {
                return Err(PyValueError::new_err(format!(
                    "{name} must be at least {min}, got {v}"
                )));
            }
            T::try_from(v).map_err(|_| PyValueError::new_err(format!("{name} is too large: {v}")))
        })
        .transpose()
}

/// [`nonnegative`] for an optional argument.
pub(crate) fn nonnegative_opt<T: TryFrom<i128>>(
    name: &str,
    value: Option<i128>,
) -> PyResult<Option<T>> {
    value.map(|v| nonnegative(name, v)).transpose()
}

pyo3::create_exception!(
    beltrami,
    MeshError,
    PyValueError,
    "A mesh that is not a valid oriented 2-manifold, or arrays that do not describe one."
);
pyo3::create_exception!(
    beltrami,
    FormatError,
    PyValueError,
    "A mesh file that cannot be decoded (bad header, truncated data, unsupported extension)."
);
pyo3::create_exception!(
    beltrami,
    SmoothError,
    PyValueError,
    "Smoothing could not run (a bad option for this mesh) or had to stop (a non-finite position)."
);
pyo3::create_exception!(
    beltrami,
    MetricsError,
    PyValueError,
    "A measurement (fit, distance, residual) could not be computed."
);

/// An error of reading or writing `path`: `OSError` (or its subclass for the error's
/// kind) when the operating system refused, `FormatError` otherwise.
pub(crate) fn io_error(path: &Path, e: &IoError) -> PyErr {
    let message = format!("{}: {e}", path.display());
    match e {
        IoError::Io { source, .. } => os_error(source.kind(), message),
        _ => FormatError::new_err(message),
    }
}

/// The `OSError` subclass Python raises for an error of this kind.
fn os_error(kind: ErrorKind, message: String) -> PyErr {
    match kind {
        ErrorKind::NotFound => PyFileNotFoundError::new_err(message),
        ErrorKind::PermissionDenied => PyPermissionError::new_err(message),
        ErrorKind::AlreadyExists => PyFileExistsError::new_err(message),
        ErrorKind::IsADirectory => PyIsADirectoryError::new_err(message),
        _ => PyOSError::new_err(message),
    }
}

/// A topology error, with the file's path in front when the mesh came from a file.
pub(crate) fn topology_error(path: Option<&Path>, e: &TopologyError) -> PyErr {
    MeshError::new_err(match path {
        Some(path) => format!("{}: {e}", path.display()),
        None => e.to_string(),
    })
}

/// [`topology_error`] for faces given by the user (`Mesh(...)`, `read`), saying to pass
/// `repair=True` when the repair fixes the problem.
pub(crate) fn repairable_error(path: Option<&Path>, e: &TopologyError) -> PyErr {
    let hint = if e.is_repairable() {
        " (pass repair=True to repair it)"
    } else {
        ""
    };
    MeshError::new_err(match path {
        Some(path) => format!("{}: {e}{hint}", path.display()),
        None => format!("{e}{hint}"),
    })
}

/// `MeshError` when a repair left none of `before` faces (every one degenerate or a
/// duplicate), as the command line's `repair` refuses to write such a mesh.
pub(crate) fn refuse_empty_repair(
    path: Option<&Path>,
    before: usize,
    after: usize,
) -> PyResult<()> {
    if before == 0 || after > 0 {
        return Ok(());
    }
    let message = format!(
        "the repair left none of the {before} {}: every one was degenerate or a duplicate",
        if before == 1 { "face" } else { "faces" }
    );
    Err(MeshError::new_err(match path {
        Some(path) => format!("{}: {message}", path.display()),
        None => message,
    }))
}

/// A smoothing error: `SmoothError`, whose message is the library's.
pub(crate) fn smooth_error(e: &beltrami_smooth::SmoothError) -> PyErr {
    SmoothError::new_err(e.to_string())
}

/// A metrics error: `MetricsError`, whose message is the library's.
pub(crate) fn metrics_error(e: &beltrami_metrics::MetricsError) -> PyErr {
    MetricsError::new_err(e.to_string())
}

/// Runs `f` on a worker of the package's thread pool ([`pool`]), turning a panic (a
/// bug of the library, never bad input) into a `RuntimeError` instead of letting it
/// unwind into Python.
pub(crate) fn no_panic<T: Send>(f: impl FnOnce() -> PyResult<T> + Send) -> PyResult<T> {
    match pool() {
        Some(pool) => pool.install(|| caught(f)),
        None => caught(f),
    }
}

/// `f()`, with a panic turned into a `RuntimeError`.
fn caught<T>(f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).unwrap_or_else(|payload| {
        let what = payload
            .downcast_ref::<&str>()
            .map(|s| (*s).to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown cause".to_string());
        Err(PyRuntimeError::new_err(format!(
            "internal error in beltrami (please report it): {what}"
        )))
    })
}

/// Runs `f` on a worker of the package's thread pool without the GIL, with panics
/// turned into `RuntimeError` (as [`no_panic`]), while the calling thread looks for
/// Ctrl-C every [`SIGNAL_INTERVAL`]: Python runs its signal handlers on the main
/// thread only, so a look from the worker that runs `f` would see nothing. On a
/// signal whose handler raises (`KeyboardInterrupt`, or a handler of the user's),
/// `stop` is set for `f` to see between two of its steps (or before it starts, when
/// the pool was busy), `f`'s end is waited for, and the handler's exception is
/// returned instead of `f`'s result.
///
/// Called from another thread than Python's main one (where no handler runs), or from
/// a worker of the pool (a run started inside another's callback: waiting there for a
/// job queued behind it would never end), it runs `f` as [`no_panic`] does.
pub(crate) fn interruptible<T: Send>(
    py: Python<'_>,
    stop: &AtomicBool,
    f: impl FnOnce() -> PyResult<T> + Send,
) -> PyResult<T> {
    if rayon::current_thread_index().is_some() || !on_main_thread(py)? {
        return py.detach(|| no_panic(f));
    }
    let mut interrupt = None;
    let result = py.detach(|| {
        let (done, ended) = mpsc::channel::<()>();
        let mut out = None;
        let work = |out: &mut Option<PyResult<T>>| {
            *out = Some(if stop.load(Ordering::Relaxed) {
                // Interrupted while the job waited for a worker: not started.
                Err(PyRuntimeError::new_err("stopped before it started"))
            } else {
                caught(f)
            });
            drop(done);
        };
        let wait = |interrupt: &mut Option<PyErr>| {
            while let Err(RecvTimeoutError::Timeout) = ended.recv_timeout(SIGNAL_INTERVAL) {
                if interrupt.is_none()
                    && let Err(e) = Python::attach(|py| py.check_signals())
                {
                    *interrupt = Some(e);
                    stop.store(true, Ordering::Relaxed);
                }
            }
        };
        match pool() {
            Some(pool) => pool.in_place_scope(|scope| {
                scope.spawn(|_| work(&mut out));
                wait(&mut interrupt);
            }),
            None => std::thread::scope(|scope| {
                scope.spawn(|| work(&mut out));
                wait(&mut interrupt);
            }),
        }
        out.unwrap_or_else(|| {
            Err(PyRuntimeError::new_err(
                "internal error in beltrami (please report it): the run ended without a result",
            ))
        })
    });
    interrupt.map_or(result, Err)
}

/// Whether this is Python's main thread, the one signal handlers run on.
fn on_main_thread(py: Python<'_>) -> PyResult<bool> {
    let threading = py.import("threading")?;
    let current = threading.call_method0("current_thread")?;
    Ok(current.is(&threading.call_method0("main_thread")?))
}

/// How often a run's calling thread looks for Ctrl-C ([`interruptible`]).
pub(crate) const SIGNAL_INTERVAL: Duration = Duration::from_millis(100);

/// The thread pool every call of the package runs on, built on first use with rayon's
/// default size (`RAYON_NUM_THREADS`, else the number of logical cores); `None` if it
/// cannot be built (then calls run on rayon's global pool as before).
///
/// A call runs on a worker of this pool rather than on the Python thread, so that a
/// parallel pass of one chunk (a small mesh) runs where it is instead of being handed
/// to a pool thread and waited for, which on meshes of a few thousand vertices is a
/// large part of each smoothing iteration. Results do not depend on the pool's size.
///
/// The pool belongs to the process that built it. A child made by `fork` (the default
/// start method of `multiprocessing` and `ProcessPoolExecutor` on Linux) inherits the
/// pool's memory but none of its threads, and a call there would wait for them forever;
/// so a call from another process id builds that process its own pool, and the copy is
/// forgotten (dropping it would signal threads that do not exist in the child).
fn pool() -> Option<std::sync::Arc<rayon::ThreadPool>> {
    use std::sync::{Arc, Mutex, PoisonError};
    static POOL: Mutex<Option<(u32, Arc<rayon::ThreadPool>)>> = Mutex::new(None);
    let pid = std::process::id();
    let current = |slot: &Option<(u32, Arc<rayon::ThreadPool>)>| {
        slot.as_ref()
            .filter(|(owner, _)| *owner == pid)
            .map(|(_, pool)| Arc::clone(pool))
    };
    if let Some(pool) = current(&POOL.lock().unwrap_or_else(PoisonError::into_inner)) {
        return Some(pool);
    }
    // Built without the lock held: a fork while the lock is held would leave the child
    // a locked mutex, and building starts threads.
    let built = Arc::new(rayon::ThreadPoolBuilder::new().build().ok()?);
    let mut slot = POOL.lock().unwrap_or_else(PoisonError::into_inner);
    if let Some(pool) = current(&slot) {
        // Another thread of this process built one meanwhile; this one goes unused.
        return Some(pool);
    }
    if let Some(inherited) = slot.replace((pid, Arc::clone(&built))) {
        std::mem::forget(inherited);
    }
    Some(built)
}

/// A path argument as Python's own file functions take one: `str`, `bytes` or an
/// `os.PathLike` giving either (`os.fsdecode`, so undecodable bytes survive as on the
/// file system). Anything else is a `TypeError` naming the argument.
pub(crate) fn path_arg(name: &str, value: &Bound<'_, PyAny>) -> PyResult<std::path::PathBuf> {
    let os = value.py().import("os")?;
    os.call_method1("fsdecode", (value,))
        .and_then(|text| text.extract::<std::path::PathBuf>())
        .map_err(|_| {
            PyTypeError::new_err(format!(
                "{name}: expected str, bytes or os.PathLike, got {}",
                type_name(value)
            ))
        })
}

/// Vertex indices given as a sequence of integers (a list, a tuple, a numpy array):
/// `TypeError` naming the argument for a string or anything not a sequence of
/// integers, `ValueError` for an integer that is no vertex index (negative, or beyond
/// the 32-bit indices of a mesh).
pub(crate) fn vertex_indices(name: &str, value: &Bound<'_, PyAny>) -> PyResult<Vec<u32>> {
    let not_indices = || {
        PyTypeError::new_err(format!(
            "{name}: expected a sequence of vertex indices (integers), got {}",
            type_name(value)
        ))
    };
    if value.is_instance_of::<pyo3::types::PyString>()
        || value.is_instance_of::<pyo3::types::PyBytes>()
        || value.is_instance_of::<pyo3::types::PyByteArray>()
    {
        return Err(not_indices());
    }
    // A numpy array or scalar of booleans (dtype kind 'b').
    let numpy_bool = |obj: &Bound<'_, PyAny>| {
        obj.getattr("dtype")
            .and_then(|d| d.getattr("kind"))
            .and_then(|k| k.extract::<String>())
            .is_ok_and(|k| k == "b")
    };
    // A boolean mask (numpy's `z < 0`) is no list of indices: True would pin vertex 1.
    if numpy_bool(value) {
        return Err(PyTypeError::new_err(format!(
            "{name}: expected vertex indices, got a boolean mask (pass numpy.flatnonzero(mask))"
        )));
    }
    let mut indices = Vec::new();
    for item in value.try_iter().map_err(|_| not_indices())? {
        let item = item?;
        if item.is_instance_of::<pyo3::types::PyBool>() || numpy_bool(&item) {
            return Err(PyTypeError::new_err(format!(
                "{name}: expected integers, got a boolean"
            )));
        }
        let v: i128 = match item.extract() {
            Ok(v) => v,
            // An integer beyond 128 bits is an integer all the same: no vertex index.
            Err(_) if item.is_instance_of::<pyo3::types::PyInt>() => {
                return Err(PyValueError::new_err(format!(
                    "{name}: {item} is not a vertex index"
                )));
            }
            Err(_) => {
                return Err(PyTypeError::new_err(format!(
                    "{name}: expected integers, got {}",
                    type_name(&item)
                )));
            }
        };
        indices
            .push(u32::try_from(v).map_err(|_| {
                PyValueError::new_err(format!("{name}: {v} is not a vertex index"))
            })?);
    }
    Ok(indices)
}

/// Issues a `UserWarning` with `message` at the caller's line (a message holding a NUL
/// byte, which no message of this package does, loses it).
pub(crate) fn warn_user(py: Python<'_>, message: &str) -> PyResult<()> {
    let text = std::ffi::CString::new(message.replace('\0', ""))
        .unwrap_or_else(|_| c"beltrami".to_owned());
    PyErr::warn(
        py,
        &py.get_type::<pyo3::exceptions::PyUserWarning>(),
        &text,
        1,
    )
}

/// The name of `value`'s type, for messages.
fn type_name(value: &Bound<'_, PyAny>) -> String {
    value
        .get_type()
        .name()
        .map_or_else(|_| "an object".to_string(), |n| n.to_string())
}

/// `ValueError` for `triangulate=True` without `repair=True`, as the commands refuse
/// `--triangulate` without `--repair`.
pub(crate) fn triangulate_needs_repair(repair: bool, triangulate: bool) -> PyResult<()> {
    if triangulate && !repair {
        return Err(PyValueError::new_err(
            "triangulate=True applies with repair=True",
        ));
    }
    Ok(())
}
