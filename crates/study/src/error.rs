//! Errors of `beltrami-study`.

use std::path::PathBuf;

/// Why a study (or one of its outputs) failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StudyError {
    /// Writing an output file failed.
    #[error("{}: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        source: beltrami_io::IoError,
    },
    /// Creating an output directory failed.
    #[error("{}: cannot create the directory: {source}", path.display())]
    CreateDir {
        /// The directory.
        path: PathBuf,
        /// What went wrong.
        source: std::io::Error,
    },
    /// Drawing a plot failed.
    #[error("plot {name}: {reason}")]
    Plot {
        /// The plot's file stem.
        name: String,
        /// What went wrong.
        reason: String,
    },
    /// Encoding an image failed.
    #[error("image {name}: {reason}")]
    Image {
        /// The image's file stem.
        name: String,
        /// What went wrong.
        reason: String,
    },
    /// The edge-preservation comparison on the block failed.
    #[error("block / edge preservation: {0}")]
    EdgePreservation(#[from] PreservationError),
    /// An invalid study configuration.
    #[error("{0}")]
    Config(String),
    /// A given surface (`study --input` or its reference) that cannot be studied.
    #[error("{0}")]
    Input(String),
    /// Smoothing failed.
    #[error("{surface} / {scheme}: {source}")]
    Smooth {
        /// The surface.
        surface: String,
        /// The scheme.
        scheme: String,
        /// What went wrong.
        source: beltrami_smooth::SmoothError,
    },
    /// A metric could not be computed.
    #[error("{surface} / {scheme}: {source}")]
    Metrics {
        /// The surface.
        surface: String,
        /// The scheme.
        scheme: String,
        /// What went wrong.
        source: beltrami_metrics::MetricsError,
    },
}

/// Why an edge-preservation measurement ([`edge_preservation`](crate::edge_preservation))
/// could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PreservationError {
    /// An option outside its valid range.
    #[error("invalid {name}: {reason}")]
    InvalidParameter {
        /// The option, e.g. `"target"`.
        name: &'static str,
        /// Why it is invalid, with the value given.
        reason: String,
    },
    /// The mesh has no vertex the flat-region measure can use (no vertex whose faces,
    /// and its neighbours' faces, are coplanar on the clean surface).
    #[error("the clean surface has no flat-region vertex to measure smoothness on")]
    NoFlatRegion,
    /// The mesh and a positions slice do not fit together.
    #[error(transparent)]
    Topology(#[from] beltrami_halfedge::TopologyError),
    /// Smoothing with the named scheme failed.
    #[error("smoothing with {scheme:?} failed: {source}")]
    Smooth {
        /// The scheme's name.
        scheme: String,
        /// What went wrong.
        source: beltrami_smooth::SmoothError,
    },
    /// A metric could not be computed.
    #[error(transparent)]
    Metrics(#[from] beltrami_metrics::MetricsError),
}
