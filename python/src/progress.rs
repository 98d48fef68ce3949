//! What a long run calls back into Python from outside the GIL: a tqdm bar when asked
//! for and installed, a look for Ctrl-C at most every [`SIGNAL_INTERVAL`], and, for
//! `smooth`, the user's per-iteration callback. One type for `smooth`, `remesh` and
//! `decimate`, so that every run stops on Ctrl-C the same way.

use std::ops::ControlFlow;
use std::time::{Duration, Instant};

use pyo3::prelude::*;
use pyo3::types::PyDict;

/// How often a run looks for Ctrl-C when nothing else takes the GIL.
pub(crate) const SIGNAL_INTERVAL: Duration = Duration::from_millis(100);

/// The bar, the signal clock and the first exception raised in a callback. The first
/// exception (the bar's, the user's callback's, or `KeyboardInterrupt`) stops the run
/// and is raised by [`finish`](Self::finish) instead of the run's own stop.
pub(crate) struct Progress {
    bar: Option<Py<PyAny>>,
    shown: usize,
    failure: Option<PyErr>,
    last_signal_check: Instant,
}

impl Progress {
    /// No bar yet; Ctrl-C is looked for from the first call on.
    pub(crate) fn new() -> Self {
        Self {
            bar: None,
            shown: 0,
            failure: None,
            last_signal_check: Instant::now(),
        }
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

    /// Moves the bar to `done` of `total` and looks for Ctrl-C when due (called
    /// without the GIL); `Break` once an exception is waiting.
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
        if self.failure.is_some() {
            return ControlFlow::Break(());
        }
        let due = self.last_signal_check.elapsed() >= SIGNAL_INTERVAL;
        let moves = self.bar.is_some() && done > self.shown;
        if !due && !moves && callback.is_none() {
            return ControlFlow::Continue(());
        }
        Python::attach(|py| {
            let outcome = self
                .call(py, done, total, due)
                .and_then(|()| match callback {
                    Some(callback) => callback(py),
                    None => Ok(ControlFlow::Continue(())),
                });
            outcome.unwrap_or_else(|e| {
                self.failure = Some(e);
                ControlFlow::Break(())
            })
        })
    }

    fn call(&mut self, py: Python<'_>, done: usize, total: usize, due: bool) -> PyResult<()> {
        if due {
            self.last_signal_check = Instant::now();
            py.check_signals()?;
        }
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
    /// bar of `total` steps named `desc` when `wanted`; `work` gets this to call
    /// [`show`](Self::show) or [`show_and_call`](Self::show_and_call). The first
    /// exception of a callback (the bar's, the user's, `KeyboardInterrupt`) is raised
    /// instead of `work`'s result.
    pub(crate) fn run<T: Send>(
        py: Python<'_>,
        wanted: bool,
        total: usize,
        desc: &str,
        work: impl FnOnce(&mut Self) -> PyResult<T> + Send,
    ) -> PyResult<T> {
        let mut progress = Self::new();
        progress.open_bar(py, wanted, total, desc)?;
        let result = py.detach(|| crate::errors::no_panic(|| work(&mut progress)));
        progress.finish(py)?;
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
