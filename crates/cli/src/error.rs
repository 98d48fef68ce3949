//! The CLI's error type: everything that ends a command with a message.

use std::fmt;
use std::path::PathBuf;

use beltrami_halfedge::TopologyError;
use beltrami_io::IoError;
use beltrami_metrics::MetricsError;
use beltrami_smooth::SmoothError;
use beltrami_weights::WeightError;

use crate::memory::{Limit, MemoryEstimate, Size};

/// A failed command. Displayed as one line, without the leading `error: `.
#[derive(Debug)]
pub(crate) enum CliError {
    /// A file could not be read or written.
    Io { path: PathBuf, source: IoError },
    /// A mesh file was read but is not a valid oriented 2-manifold.
    Topology {
        path: PathBuf,
        source: TopologyError,
        repairable: bool,
        /// Vertices within the distance of another (count, distance) when merging them
        /// would help: a file whose coincident vertices were written apart.
        near_duplicates: Option<(usize, f64)>,
    },
    /// Bad usage found after parsing (an unknown scheme name, a bad vertex list).
    Usage(String),
    /// Smoothing could not run or had to stop.
    Smooth { path: PathBuf, source: SmoothError },
    /// A metric could not be computed; `subject` names the file or the pair of files.
    Metrics {
        subject: String,
        source: MetricsError,
    },
    /// A mesh without faces where a command needs a surface.
    NoFaces {
        path: PathBuf,
        needed_by: &'static str,
        vertices: usize,
    },
    /// An input that the command cannot work on, for a reason given in `message`.
    Input { path: PathBuf, message: String },
    /// The study failed.
    Study(beltrami_study::StudyError),
    /// Writing to stdout failed.
    Stdout(std::io::Error),
    /// An output path names an input file and `--force` was not given.
    OverwritesInput { output: PathBuf, input: PathBuf },
    /// An output is an existing file without write permission and `--force` was not
    /// given.
    WriteProtected { path: PathBuf },
    /// The run would need more memory than `--max-memory` allows or, without it, than
    /// the machine has available.
    MemoryLimit {
        path: PathBuf,
        estimate: MemoryEstimate,
        limit: Limit,
    },
}

/// The one line for a face that is not a triangle, given to a command (or option) that
/// needs a triangle mesh.
pub(crate) fn not_triangles(command: &str, face: impl fmt::Display, len: usize) -> String {
    // Inside `repair` (its --flat-faces) the flag alone; elsewhere with --repair.
    let flags = if command == "--flat-faces" {
        "--triangulate"
    } else {
        "--repair --triangulate"
    };
    format!(
        "face {face} has {len} vertices; {command} needs a triangle mesh ({flags} splits the polygons into triangles)"
    )
}

impl CliError {
    /// 2 for bad usage (also an output that would overwrite an input), 1 for
    /// everything else.
    pub(crate) fn exit_code(&self) -> u8 {
        match self {
            Self::Usage(_) | Self::OverwritesInput { .. } => 2,
            Self::Stdout(_) if self.is_closed_pipe() => CLOSED_PIPE_EXIT,
            Self::Smooth { source, .. } if is_usage(source) => 2,
            _ => 1,
        }
    }
}

/// The exit code when the reader of stdout went away (`beltrami info x.ply | head -1`):
/// 128 + SIGPIPE, what a shell reports for a program the signal ended, as for the
/// standard tools. No message is printed for it.
pub(crate) const CLOSED_PIPE_EXIT: u8 = 141;

impl CliError {
    /// Whether this is a write to a stdout whose reader has gone (a broken pipe): the
    /// reader's choice, not an error worth a line on stderr.
    pub(crate) fn is_closed_pipe(&self) -> bool {
        matches!(self, Self::Stdout(e) if e.kind() == std::io::ErrorKind::BrokenPipe)
    }
}

/// Whether a smoothing error is decided by the options alone (a bad value or a bad
/// combination), not by the mesh: a usage error, exit code 2, reported without the
/// input's path. An unstable step depends on the mesh, but the fix is an option.
fn is_usage(e: &SmoothError) -> bool {
    matches!(
        e,
        SmoothError::InvalidLambda { .. }
            | SmoothError::CurveNeedsWeightSum
            | SmoothError::InvalidTaubin { .. }
            | SmoothError::InvalidHc { .. }
            | SmoothError::VolumeWithPinned
            | SmoothError::InvalidDuration { .. }
            | SmoothError::InvalidUntilChange { .. }
            | SmoothError::VolumeNotImplicit
            | SmoothError::InvalidSolverSettings { .. }
            | SmoothError::CurveNotImplicit
            | SmoothError::UnstableStep { .. }
    )
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io { path, source } => {
                write!(f, "{}: {source}", path.display())?;
                let more_than_declared = match source {
                    IoError::TrailingData { .. } => true,
                    IoError::PlyData { reason, .. } => reason.starts_with("the line holds"),
                    _ => false,
                };
                if more_than_declared {
                    write!(
                        f,
                        " (pass --lenient to read what the header declares and ignore the rest)"
                    )?;
                }
                Ok(())
            }
            Self::Topology {
                path,
                source,
                repairable,
                near_duplicates,
            } => {
                write!(f, "{}: {source}", path.display())?;
                let near = near_duplicates.map(|(n, d)| {
                    (
                        format!(
                            "{n} {} within {} of another: ",
                            crate::text::plural(n, "vertex lies", "vertices lie"),
                            crate::text::number(d)
                        ),
                        format!(" --merge-distance {}", crate::text::number(d)),
                    )
                });
                let (why, merge) = near.unwrap_or_default();
                match (repairable, merge.is_empty()) {
                    (true, _) => write!(
                        f,
                        " ({why}pass --repair{merge}, or keep a repaired copy with 'beltrami repair {} REPAIRED{merge}')",
                        path.display()
                    )?,
                    (false, false) => write!(f, " ({why}add{merge})")?,
                    (false, true) => {}
                }
                Ok(())
            }
            Self::Usage(message) => write!(f, "{message} (see 'beltrami --help')"),
            Self::Smooth { source, .. } if is_usage(source) => {
                write!(f, "{source} (see 'beltrami smooth --help')")
            }
            Self::Smooth { path, source } => write!(f, "{}: {source}", path.display()),
            Self::Metrics { subject, source } => write!(f, "{subject}: {source}"),
            Self::NoFaces {
                path,
                needed_by,
                vertices: 0,
            } => write!(
                f,
                "{}: the mesh is empty: no vertices, no faces ({needed_by} needs a surface)",
                path.display()
            ),
            Self::NoFaces {
                path,
                needed_by,
                vertices,
            } => write!(
                f,
                "{}: the mesh has {vertices} {} but no faces (points or lines only; {needed_by} needs a surface of triangles)",
                path.display(),
                crate::text::plural(*vertices, "vertex", "vertices")
            ),
            Self::Input { path, message } => write!(f, "{}: {message}", path.display()),
            Self::Study(e) => write!(f, "study: {e}"),
            Self::Stdout(e) => write!(f, "cannot write to stdout: {e}"),
            Self::OverwritesInput { output, input } => write!(
                f,
                "{}: refusing to overwrite the input file {} (pass --force to replace it)",
                output.display(),
                input.display()
            ),
            Self::WriteProtected { path } => write!(
                f,
                "{}: the file is write-protected (pass --force to replace it)",
                path.display()
            ),
            Self::MemoryLimit {
                path,
                estimate,
                limit,
            } => match limit {
                Limit::Given(limit) => write!(
                    f,
                    "{}: the run needs {estimate}, more than --max-memory {}",
                    path.display(),
                    Size(*limit)
                ),
                Limit::Available(available) => write!(
                    f,
                    "{}: the run needs {estimate}, more than the {} of memory available to it (pass --max-memory SIZE to run it anyway)",
                    path.display(),
                    Size(*available)
                ),
            },
        }
    }
}

impl From<std::io::Error> for CliError {
    fn from(e: std::io::Error) -> Self {
        Self::Stdout(e)
    }
}

impl From<WeightError> for CliError {
    fn from(e: WeightError) -> Self {
        Self::Usage(e.to_string())
    }
}
