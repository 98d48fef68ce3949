//! The progress bars of long commands: on stderr, only when it is a terminal (a pipe,
//! a file or a test sees nothing), cleared when the work is done.

use std::io::IsTerminal;

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
