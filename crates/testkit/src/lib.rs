//! # beltrami-testkit
//!
//! Test support for people who build on beltrami: pin a pipeline with snapshot tests
//! that stay stable, check a plug-in weight scheme, and compare with OpenMesh.
//!
//! - **Stable summaries** for snapshots (`Display` for humans, `serde` for JSON):
//!   [`MeshSummary`] (counts, boundary loops, bounding box, area, volume),
//!   [`SmoothingSummary`] (what a smoothing run did, without times),
//!   [`MetricsTable`] (named measurements with units) and [`ComparisonTable`]
//!   (deviations from a reference in units of the bounding-box diagonal). Measured values are rounded to a documented number of significant
//!   digits — [`SUMMARY_DIGITS`] (6) for measures, [`DEVIATION_DIGITS`] (2) for
//!   deviations — with [`round_significant`], which rounds half to even on the exact
//!   decimal value and gives the same digits on every platform. A change in the last
//!   bits of a result does not change a snapshot; a real change does.
//! - **A conformance check** for a [`WeightScheme`](beltrami_weights::WeightScheme):
//!   [`check_scheme`] / [`assert_scheme_conforms`] verify finite weights on boundary and
//!   degenerate fixtures, agreement of the bulk and per-halfedge paths, symmetry where
//!   claimed, translation invariance and position independence where claimed.
//! - **Deterministic fixtures** ([`fixtures`]): irregular meshes with obtuse triangles,
//!   noise, genus and several boundary loops, and the paper's noisy F-lens, identical to
//!   the last bit on every platform ([`SplitMix64`], `beltrami-surfaces`' seeded noise).
//! - **OpenMesh references** ([`openmesh`]): readers for what `tools/openmesh-ref`
//!   writes, and the configuration that reproduces OpenMesh's `JacobiLaplaceSmootherT`.
//!
//! ## Quick start
//!
//! A snapshot test of your own pipeline (with `insta`, `assert_snapshot!(text)`):
//!
//! ```
//! use beltrami_halfedge::primitives;
//! use beltrami_smooth::{smooth, SmoothConfig};
//! use beltrami_testkit::{MeshSummary, SmoothingSummary};
//! use beltrami_weights::Cotangent;
//!
//! let sphere = primitives::icosphere(2);
//! let mesh = sphere.mesh()?;
//! let out = smooth(&mesh, &sphere.positions, &Cotangent, SmoothConfig::new(0.8, 10))?;
//!
//! let text = format!(
//!     "{}\n{}",
//!     MeshSummary::new(&mesh, &out.positions)?,
//!     SmoothingSummary::new(&mesh, &sphere.positions, &out)?,
//! );
//! // insta::assert_snapshot!(text);
//! assert!(text.contains("vertices: 162, edges: 480, faces: 320"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! And the conformance check, in the test suite of your own weight scheme:
//!
//! ```
//! use beltrami_testkit::{assert_scheme_conforms, SchemeClaims};
//! use beltrami_weights::Uniform; // your scheme here
//! assert_scheme_conforms(&Uniform, SchemeClaims::new().symmetric(true));
//! ```

mod comparison;
mod conformance;
pub mod fixtures;
mod metrics;
pub mod numbering;
pub mod openmesh;
mod rng;
mod round;
mod smoothing;
mod summary;

pub use comparison::{ComparisonRow, ComparisonTable, Deviation};
pub use conformance::{
    Check, ConformanceReport, SYMMETRY_TOLERANCE, SchemeClaims, TRANSLATION_TOLERANCE,
    assert_scheme_conforms, check_scheme,
};
pub use metrics::{MetricRow, MetricsTable};
pub use rng::{Lcg64, SplitMix64};
pub use round::{DEVIATION_DIGITS, SUMMARY_DIGITS, format_significant, round_significant};
pub use smoothing::SmoothingSummary;
pub use summary::MeshSummary;
