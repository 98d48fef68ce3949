//! # beltrami-study
//!
//! Runs the Laplace–Beltrami comparison — surfaces × weight schemes × iteration counts —
//! and writes its results (CSV, JSON), the paper's figures as plots, renders of the
//! smoothed meshes, and a report that checks the paper's findings against the numbers.
//!
//! ```no_run
//! use beltrami_study::{StudyConfig, run_study, write_study};
//! use beltrami_weights::WeightRegistry;
//!
//! let config = StudyConfig::paper(&WeightRegistry::with_builtins());
//! let results = run_study(&config, &mut |_| {})?;
//! write_study(&results, std::path::Path::new("study"))?;
//! # Ok::<(), beltrami_study::StudyError>(())
//! ```

mod case;
mod closed_form;
mod config;
mod countermeasures;
mod error;
mod figures;
mod findings;
mod measure;
mod optimum;
mod out_dir;
mod preservation;
mod remeshing;
mod report;
mod results;
mod run;
mod scan;
mod timing;
mod units;

pub use case::SurfaceCase;
pub use closed_form::{predicted_radius, weighted_mean_edge_sq};
pub use config::{
    DEFAULT_SEEDS, MAX_RELATIVE_NOISE, MAX_STUDY_ITERATIONS, PAPER_SCHEMES, StudyConfig,
    paper_iterations,
};
pub use countermeasures::{Countermeasure, countermeasure_surface};
pub use error::{PreservationError, StudyError};
pub use figures::{Figure, OVERLAP_FRACTION, curves_overlap, differences, write_figures};
pub use findings::{
    Comparison, Finding, FindingsContext, MedianTimeRatios, REL_TOL, SAME_SPEED, Spread,
    TIMED_SURFACES, Verdict, compare, findings, findings_with, sig, sphere_closed_form,
};
pub use measure::{FEATURE_THRESHOLD_DEG, Measured};
pub use optimum::{Optimum, optima};
pub use out_dir::{
    OutDirError, SCAN_ENTRIES, STUDY_ENTRIES, check_out_dir, is_any_study_entry, is_scan_entry,
    is_study_entry,
};
pub use preservation::{
    EdgePreservation, EdgePreservationOptions, FlatRegion, Measures, SchemeOutcome,
    edge_preservation,
};
pub use remeshing::{
    CotangentRms, MeshFigures, REMESH_ITERATIONS, REMESH_LONG_ITERATIONS, RemeshComparison,
    RemeshRow, SHARE_TOL, TOO_COARSE_VERTICES, default_remesh, describe_target,
};
pub use report::{Written, write_study};
pub use results::{CSV_HEADER, Row, to_csv};
pub use run::{
    EARLY_ITERATIONS, Progress, RmsPoint, SchemeRun, Snapshot, StudyResults, SurfaceResult,
    UNITS_CUTOFF, run_study,
};
pub use scan::{
    DEFAULT_IMPLICIT_STEPS, OBSERVE_EVERY_UP_TO, OBSERVE_STRIDE, REPORT_ITERATIONS,
    SCAN_CSV_HEADER, ScanBest, ScanConfig, ScanMethod, ScanResults, ScanRow, ScanSurface,
    ScanTiming, ScanWritten, TAUBIN_LAMBDA, TAUBIN_MU, TIME_HEADING, run_scan, scan_csv,
    smooth_options, write_scan,
};
pub use timing::{
    MachineInfo, SchemeTiming, TIMING_ITERATIONS, TIMING_REPEATS, Timings, cpu_model, git_commit,
    machine_info, median,
};
pub use units::{UnitsComparison, UnitsRow, units_comparison};
