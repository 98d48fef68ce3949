//! Errors of `beltrami-viz`.

/// Why a plot or render could not be produced.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum VizError {
    /// Drawing failed.
    #[error("cannot draw {name}: {reason}")]
    Draw {
        /// What was drawn (a plot title or file stem).
        name: String,
        /// Why.
        reason: String,
    },
    /// Invalid input (no data, mismatched lengths, zero image size …).
    #[error("invalid {what}: {reason}")]
    Invalid {
        /// What is invalid.
        what: &'static str,
        /// Why.
        reason: String,
    },
    /// Writing the file failed.
    #[error(transparent)]
    Write(#[from] beltrami_io::IoError),
}
