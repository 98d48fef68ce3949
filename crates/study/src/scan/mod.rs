//! The study on a surface the user gives (a scan), optionally against a clean
//! reference: every weight scheme with plain, Taubin, HC and implicit smoothing,
//! observed iteration by iteration, with the best iteration count per scheme and
//! method when a reference is given.
//!
//! ```
//! use beltrami_halfedge::primitives;
//! use beltrami_study::{ScanConfig, ScanMethod, ScanSurface, run_scan};
//! use beltrami_surfaces::{NoiseLevel, add_normal_noise};
//!
//! let clean = primitives::icosphere(2);
//! let mut noisy = clean.clone();
//! let mesh = clean.mesh().unwrap();
//! let level = NoiseLevel::RelativeToMeanEdge(0.2);
//! noisy.positions = add_normal_noise(&mesh, &clean.positions, level, 1).unwrap().0;
//! let input = ScanSurface::new("noisy", noisy)?;
//! let reference = ScanSurface::new("clean", clean)?;
//! let config = ScanConfig::default().methods(vec![ScanMethod::Plain]).max_iterations(10);
//! let results = run_scan(input, Some(reference), &config, &mut |_| {})?;
//! // Smoothing brings the noisy sphere closer to the clean one.
//! assert!(results.best[0].rms < results.baseline().rms.unwrap());
//! # Ok::<(), beltrami_study::StudyError>(())
//! ```

mod config;
mod report;
mod run;

pub use config::{
    DEFAULT_IMPLICIT_STEPS, OBSERVE_EVERY_UP_TO, OBSERVE_STRIDE, ScanConfig, ScanMethod,
    TAUBIN_LAMBDA, TAUBIN_MU,
};
pub use report::{
    REPORT_ITERATIONS, SCAN_CSV_HEADER, ScanWritten, TIME_HEADING, scan_csv, smooth_options,
    write_scan,
};
pub use run::{ScanBest, ScanResults, ScanRow, ScanSurface, ScanTiming, run_scan};
