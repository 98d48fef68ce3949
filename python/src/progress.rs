//! What a long run calls back into Python from outside the GIL: a tqdm bar when asked
//! for and installed, the stop that Ctrl-C sets ([`crate::errors::interruptible`]), and,
//! for `smooth`, the user's per-iteration callback. One type for `smooth`, `remesh`,
//! `decimate` and `fill_holes`, so that every run stops on Ctrl-C the same way.

use std::ops::ControlFlow;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The bar, the stop that Ctrl-C sets and the first exception raised in a callback.
/// The first exception (the bar's or the user's callback's) stops the run and is raised
/// by [`finish`](Self::finish) instead of the run's own stop; a `KeyboardInterrupt` is
/// raised by [`crate::errors::interruptible`] instead of both.
pub(crate) struct Progress {
    bar: Option<Py<PyAny>>,
    shown: usize,
    failure: Option<PyErr>,
    /// Set by the calling thread when a signal handler raised.
    stop: Arc<AtomicBool>,
}

impl Progress {
    /// No bar yet, no stop.
    pub(crate) fn new() -> Self {
        Self {
            bar: None,
            shown: 0,
            failure: None,
            stop: Arc::default(),
        }
    }

    /// The stop [`crate::errors::interruptible`] sets on Ctrl-C (shared with this).
    pub(crate) fn stop(&self) -> Arc<AtomicBool> {
        Arc::clone(&self.stop)
    }

    /// Opens a bar of `total` steps named `desc` when `wanted` and tqdm is installed.
    pub(crate) fn open_bar(
        &mut self,
        py: Python<'_>,
        wanted: bool,
        total: usize,
        desc: &str,
    ) -> PyResult<()> {
        if wanted {
            self.bar = progress_bar(py, total, desc)?;
        }
        Ok(())
    }

    /// Moves the bar to `done` of `total` (called without the GIL); `Break` once an
    /// exception is waiting or Ctrl-C was pressed.
    pub(crate) fn show(&mut self, done: usize, total: usize) -> ControlFlow<()> {
        self.show_and_call(
            done,
            total,
            None::<fn(Python<'_>) -> PyResult<ControlFlow<()>>>,
        )
    }

    /// As [`show`](Self::show), then calls `callback` with the GIL when there is one.
    /// Its `Break` stops the run without an exception; its error stops it with one.
    pub(crate) fn show_and_call<F>(
        &mut self,
        done: usize,
        total: usize,
        callback: Option<F>,
    ) -> ControlFlow<()>
    where
        F: FnOnce(Python<'_>) -> PyResult<ControlFlow<()>>,
    {
        if self.failure.is_some() || self.stop.load(Ordering::Relaxed) {
            return ControlFlow::Break(());
        }
        let moves = self.bar.is_some() && done > self.shown;
        if !moves && callback.is_none() {
            return ControlFlow::Continue(());
        }
        Python::attach(|py| {
            let outcome = self.call(py, done, total).and_then(|()| match callback {
                Some(callback) => callback(py),
                None => Ok(ControlFlow::Continue(())),
            });
            outcome.unwrap_or_else(|e| {
                self.failure = Some(e);
                ControlFlow::Break(())
            })
        })
    }

    fn call(&mut self, py: Python<'_>, done: usize, total: usize) -> PyResult<()> {
        if let Some(bar) = &self.bar
            && done > self.shown
        {
            let step = done - self.shown;
            self.shown = done;
            bar.setattr(py, "total", total)?;
            bar.call_method1(py, "update", (step,))?;
        }
        Ok(())
    }

    /// Runs `work` without the GIL (and with panics turned into exceptions), under a
    /// bar of `total` steps named `desc` when `wanted`, stopping on Ctrl-C
    /// ([`crate::errors::interruptible`]); `work` gets this to call
    /// [`show`](Self::show) or [`show_and_call`](Self::show_and_call). The
    /// `KeyboardInterrupt`, else the first exception of a callback (the bar's, the
    /// user's), is raised instead of `work`'s result.
    pub(crate) fn run<T: Send>(
        py: Python<'_>,
        wanted: bool,
        total: usize,
        desc: &str,
        work: impl FnOnce(&mut Self) -> PyResult<T> + Send,
    ) -> PyResult<T> {
        let mut progress = Self::new();
        progress.open_bar(py, wanted, total, desc)?;
        let stop = progress.stop();
        let result = crate::errors::interruptible(py, &stop, || work(&mut progress));
        progress.finish_after(py, result)
    }

    /// Closes the bar and returns `result` of a run under [`crate::errors::interruptible`]:
    /// its `KeyboardInterrupt` when Ctrl-C stopped the run, else the first exception of
    /// a callback, else `result`.
    pub(crate) fn finish_after<T>(self, py: Python<'_>, result: PyResult<T>) -> PyResult<T> {
        let interrupted = self.stop.load(Ordering::Relaxed);
        let failure = self.finish(py);
        if !interrupted {
            failure?;
        }
        result
    }

    /// Closes the bar; the first exception, if any.
    pub(crate) fn finish(mut self, py: Python<'_>) -> PyResult<()> {
        if let Some(bar) = self.bar.take()
            && let Err(e) = bar.call_method0(py, "close")
        {
            self.failure.get_or_insert(e);
        }
        self.failure.map_or(Ok(()), Err)
    }
}

/// A tqdm progress bar over `total` steps named `desc`, or None when tqdm is not
/// installed.
fn progress_bar(py: Python<'_>, total: usize, desc: &str) -> PyResult<Option<Py<PyAny>>> {
    let Ok(tqdm) = py.import("tqdm.auto").or_else(|_| py.import("tqdm")) else {
        return Ok(None);
    };
    let kwargs = PyDict::new(py);
    kwargs.set_item("total", total)?;
    kwargs.set_item("unit", "it")?;
    kwargs.set_item("desc", desc)?;
    Ok(Some(
        tqdm.getattr("tqdm")?.call((), Some(&kwargs))?.unbind(),
    ))
}
