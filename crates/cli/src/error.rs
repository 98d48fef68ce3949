//! The CLI's error type: everything that ends a command with a message.

use std::fmt;
use std::path::PathBuf;

use beltrami_halfedge::TopologyError;
use beltrami_io::IoError;

/// A failed command. Displayed as one line, without the leading `error: `.
#[derive(Debug)]
pub(crate) enum CliError {
    /// A mesh file could not be read or written.
    Io { path: PathBuf, source: IoError },
    /// A mesh file was read but is not a valid oriented 2-manifold.
    Topology {
        path: PathBuf,
        source: TopologyError,
        repairable: bool,
    },
    /// Writing to stdout failed.
    Stdout(std::io::Error),
}

impl CliError {
    /// 1 for bad input or a failed write; usage errors (2) never reach this type.
    pub(crate) fn exit_code(&self) -> u8 {
        1
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io { path, source } => write!(f, "{}: {source}", path.display()),
            Self::Topology {
                path,
                source,
                repairable,
            } => {
                write!(f, "{}: {source}", path.display())?;
                if *repairable {
                    write!(f, " (--repair can fix this)")?;
                }
                Ok(())
            }
            Self::Stdout(e) => write!(f, "cannot write to stdout: {e}"),
        }
    }
}

impl From<std::io::Error> for CliError {
    fn from(e: std::io::Error) -> Self {
        Self::Stdout(e)
    }
}
