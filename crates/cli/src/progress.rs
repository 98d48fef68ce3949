//! The progress bars of long commands: on stderr, only when it is a terminal (a pipe,
//! a file or a test sees nothing), cleared when the work is done.

use std::io::IsTerminal;
use std::ops::ControlFlow;

use indicatif::{ProgressBar, ProgressStyle};

/// A bar of `len` steps named `unit` ("iterations"), when `long` (the caller's
/// judgement that the run takes seconds) and stderr is a terminal.
pub(crate) fn bar(len: usize, unit: &str, long: bool) -> Option<ProgressBar> {
    (long && std::io::stderr().is_terminal()).then(|| {
        let bar = ProgressBar::new(len as u64);
        bar.set_style(
            ProgressStyle::with_template(&format!("{{bar:40}} {{pos}}/{{len}} {unit} {{elapsed}}"))
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        bar
    })
}

/// Runs `work` with a progress callback `(done, total)` that moves a [`bar`] of `len`
/// steps named `unit` (shown when `long` and stderr is a terminal) to `done` of `total`,
/// then clears the bar. The callback never asks to stop: Ctrl-C ends the process from
/// the signal handler.
pub(crate) fn with_bar<T>(
    len: usize,
    unit: &str,
    long: bool,
    work: impl FnOnce(&mut dyn FnMut(usize, usize) -> ControlFlow<()>) -> T,
) -> T {
    let progress = bar(len, unit, long);
    let mut show = |done: usize, total: usize| {
        if let Some(bar) = &progress {
            bar.set_length(total as u64);
            bar.set_position(done as u64);
        }
        ControlFlow::Continue(())
    };
    let result = work(&mut show);
    if let Some(bar) = progress {
        bar.finish_and_clear();
    }
    result
}
