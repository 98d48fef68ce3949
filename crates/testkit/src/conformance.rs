//! A conformance check for plug-in [`WeightScheme`]s: the properties every scheme must
//! have to run safely through the Laplacian, smoothing, the CLI and the study.

use std::fmt;

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::primitives::{self, Primitive};
use beltrami_halfedge::{DVec3, HalfedgeId, HalfedgeMesh};
use beltrami_smooth::{Boundary, SmoothConfig, smooth};
use beltrami_weights::{Laplacian, LaplacianOptions, WeightContext, WeightScheme};
use serde::Serialize;

use crate::fixtures;

/// What a scheme claims about itself, so the check can hold it to it.
///
/// # Examples
/// ```
/// use beltrami_testkit::SchemeClaims;
/// let claims = SchemeClaims::new().symmetric(true);
/// assert!(claims.symmetric);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct SchemeClaims {
    /// `w_ij = w_ji` for every edge (uniform, inverse distance and cotangent weights are
    /// symmetric; mean-value weights are not).
    pub symmetric: bool,
}

impl SchemeClaims {
    /// No claims beyond what every scheme must satisfy.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Claims (or not) that the weights are symmetric.
    #[must_use]
    pub fn symmetric(mut self, yes: bool) -> Self {
        self.symmetric = yes;
        self
    }
}

/// Relative tolerance of the symmetry and bulk-versus-single checks: a few roundings.
pub const SYMMETRY_TOLERANCE: f64 = 1e-12;

/// Tolerance of the translation-invariance check, relative to the largest weight
/// magnitude of the mesh. Translating by a few units changes every edge vector by
/// rounding (about 1e-16 of the translation), which an ill-conditioned weight (a
/// cotangent near a sliver) may amplify; 1e-8 is far above that and far below any real
/// dependence on absolute position.
pub const TRANSLATION_TOLERANCE: f64 = 1e-8;

/// The outcome of one check on one fixture.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Check {
    /// The property checked.
    pub property: &'static str,
    /// The fixture it was checked on.
    pub fixture: &'static str,
    /// Whether it holds.
    pub passed: bool,
    /// What went wrong (empty when it passed).
    pub detail: String,
}

/// Everything [`check_scheme`] found, printable as a checklist.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ConformanceReport {
    /// The scheme's name.
    pub scheme: String,
    /// The claims it was checked against.
    pub symmetric_claimed: bool,
    /// One entry per property and fixture.
    pub checks: Vec<Check>,
}

impl ConformanceReport {
    /// Whether every check passed.
    #[must_use]
    pub fn passed(&self) -> bool {
        self.checks.iter().all(|c| c.passed)
    }

    /// The checks that failed.
    #[must_use]
    pub fn failures(&self) -> Vec<&Check> {
        self.checks.iter().filter(|c| !c.passed).collect()
    }
}

impl fmt::Display for ConformanceReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "weight scheme '{}' (symmetric claimed: {})",
            self.scheme,
            if self.symmetric_claimed { "yes" } else { "no" }
        )?;
        for c in &self.checks {
            let mark = if c.passed { "ok  " } else { "FAIL" };
            write!(f, "{mark} {:<24} {}", c.property, c.fixture)?;
            if !c.detail.is_empty() {
                write!(f, ": {}", c.detail)?;
            }
            writeln!(f)?;
        }
        Ok(())
    }
}

/// The fixtures the check runs on: an open irregular grid with obtuse triangles (a
/// boundary and negative cotangents), a patch with a collinear triangle and a
/// zero-length edge, and a closed icosphere.
fn conformance_fixtures() -> Vec<(&'static str, Primitive)> {
    vec![
        ("obtuse grid (boundary)", fixtures::obtuse_grid()),
        ("degenerate patch", fixtures::degenerate_patch()),
        ("icosphere level 2", primitives::icosphere(2)),
    ]
}

fn weights_of(scheme: &dyn WeightScheme, ctx: &WeightContext<'_>) -> Vec<f64> {
    let mut out = vec![f64::NAN; ctx.mesh().n_halfedges()];
    scheme.fill_weights(ctx, &mut out);
    out
}

fn close(a: f64, b: f64, tolerance: f64) -> bool {
    a == b || (a - b).abs() <= tolerance * a.abs().max(b.abs())
}

/// Runs every conformance check on `scheme` and reports each result.
///
/// The properties, each checked on every fixture (see the crate docs for why each
/// matters):
///
/// - **finite** — `fill_weights` and `weight` give finite numbers for every halfedge,
///   boundary halfedges and degenerate triangles included;
/// - **bulk equals single** — `fill_weights` agrees with `weight` halfedge by halfedge
///   (within [`SYMMETRY_TOLERANCE`], relative);
/// - **symmetric** (only when claimed) — `w(h) = w(twin(h))` within
///   [`SYMMETRY_TOLERANCE`], relative;
/// - **translation invariant** — translating every position by the same vector changes
///   no weight by more than [`TRANSLATION_TOLERANCE`] times the largest weight;
/// - **position independence** (only when `depends_on_positions()` is `false`) — the
///   weights do not change when the positions do;
/// - **assembles and smooths** — the [`Laplacian`] assembles and three free-boundary
///   smoothing steps with λ = 0.5 give finite positions.
///
/// # Examples
/// ```
/// use beltrami_testkit::{check_scheme, SchemeClaims};
/// use beltrami_weights::Cotangent;
/// let report = check_scheme(&Cotangent, SchemeClaims::new().symmetric(true));
/// assert!(report.passed(), "{report}");
/// ```
///
/// # Panics
/// Never: the fixtures it builds are valid meshes (tested).
#[must_use]
pub fn check_scheme(scheme: &dyn WeightScheme, claims: SchemeClaims) -> ConformanceReport {
    let mut checks = Vec::new();
    for (fixture, p) in conformance_fixtures() {
        let mesh = p.mesh().expect("conformance fixtures are valid meshes");
        let geometry = Geometry::new(&mesh, &p.positions).expect("matching positions");
        let ctx = WeightContext::new(geometry);
        let weights = FixtureWeights {
            scheme,
            mesh: &mesh,
            positions: &p.positions,
            bulk: weights_of(scheme, &ctx),
            single: mesh.halfedges().map(|h| scheme.weight(&ctx, h)).collect(),
        };
        let mut record = |property: &'static str, detail: Option<String>| {
            checks.push(Check {
                property,
                fixture,
                passed: detail.is_none(),
                detail: detail.unwrap_or_default(),
            });
        };
        record("finite", weights.not_finite());
        record("bulk equals single", weights.bulk_differs());
        if claims.symmetric {
            record("symmetric", weights.asymmetric());
        }
        record("translation invariant", weights.translation_changes());
        if !scheme.depends_on_positions() {
            record("position independent", weights.positions_change());
        }
        record("assembles and smooths", weights.smoothing_fails());
    }
    ConformanceReport {
        scheme: scheme.name().to_string(),
        symmetric_claimed: claims.symmetric,
        checks,
    }
}

/// A scheme's weights on one fixture; each check returns the first failure's detail,
/// or `None` when it passes.
struct FixtureWeights<'a> {
    scheme: &'a dyn WeightScheme,
    mesh: &'a HalfedgeMesh,
    positions: &'a [DVec3],
    /// Per halfedge, from `fill_weights`.
    bulk: Vec<f64>,
    /// Per halfedge, from `weight`.
    single: Vec<f64>,
}

impl FixtureWeights<'_> {
    /// The first halfedge whose bulk or single weight is not finite.
    fn not_finite(&self) -> Option<String> {
        let (mesh, bulk, single) = (self.mesh, &self.bulk, &self.single);
        let bad = mesh
            .halfedges()
            .find(|h| !bulk[h.index()].is_finite() || !single[h.index()].is_finite());
        bad.map(|h| {
            format!(
                "halfedge {} ({} -> {}): fill_weights {}, weight {}",
                h.raw(),
                mesh.from_vertex(h).raw(),
                mesh.to_vertex(h).raw(),
                bulk[h.index()],
                single[h.index()]
            )
        })
    }

    /// The first halfedge whose bulk and single weights differ beyond
    /// [`SYMMETRY_TOLERANCE`].
    fn bulk_differs(&self) -> Option<String> {
        let (bulk, single) = (&self.bulk, &self.single);
        let mismatch = self
            .mesh
            .halfedges()
            .find(|h| !close(bulk[h.index()], single[h.index()], SYMMETRY_TOLERANCE));
        mismatch.map(|h| {
            format!(
                "halfedge {}: fill_weights {} but weight {}",
                h.raw(),
                bulk[h.index()],
                single[h.index()]
            )
        })
    }

    /// The first halfedge whose weight differs from its twin's beyond
    /// [`SYMMETRY_TOLERANCE`].
    fn asymmetric(&self) -> Option<String> {
        let (mesh, bulk) = (self.mesh, &self.bulk);
        let asymmetric = mesh
            .halfedges()
            .find(|h| !close(bulk[h.index()], bulk[h.twin().index()], SYMMETRY_TOLERANCE));
        asymmetric.map(|h: HalfedgeId| {
            format!(
                "w({} -> {}) = {} but w({} -> {}) = {}",
                mesh.from_vertex(h).raw(),
                mesh.to_vertex(h).raw(),
                bulk[h.index()],
                mesh.to_vertex(h).raw(),
                mesh.from_vertex(h).raw(),
                bulk[h.twin().index()]
            )
        })
    }

    /// The first halfedge whose weight changes, beyond [`TRANSLATION_TOLERANCE`] times
    /// the largest weight, when every position moves by (3, -5, 7).
    fn translation_changes(&self) -> Option<String> {
        let bulk = &self.bulk;
        let offset = DVec3::new(3.0, -5.0, 7.0);
        let moved: Vec<DVec3> = self.positions.iter().map(|&q| q + offset).collect();
        let moved_geometry = Geometry::new(self.mesh, &moved).expect("matching positions");
        let translated = weights_of(self.scheme, &WeightContext::new(moved_geometry));
        let scale = bulk
            .iter()
            .filter(|w| w.is_finite())
            .fold(0.0f64, |m, w| m.max(w.abs()));
        let tolerance = TRANSLATION_TOLERANCE * scale.max(f64::MIN_POSITIVE);
        let changed = self.mesh.halfedges().find(|h| {
            let d = (translated[h.index()] - bulk[h.index()]).abs();
            d.is_nan() || d > tolerance
        });
        changed.map(|h| {
            format!(
                "halfedge {}: {} before, {} after translating by (3, -5, 7)",
                h.raw(),
                bulk[h.index()],
                translated[h.index()]
            )
        })
    }

    /// The first halfedge whose weight changes at all when the positions are scaled
    /// unevenly (for a scheme that claims not to depend on positions).
    fn positions_change(&self) -> Option<String> {
        let bulk = &self.bulk;
        let squeezed: Vec<DVec3> = self
            .positions
            .iter()
            .map(|&q| q * DVec3::new(2.0, 0.5, 3.0))
            .collect();
        let squeezed_geometry = Geometry::new(self.mesh, &squeezed).expect("matching positions");
        let other = weights_of(self.scheme, &WeightContext::new(squeezed_geometry));
        let differs = self
            .mesh
            .halfedges()
            .find(|h| other[h.index()].to_bits() != bulk[h.index()].to_bits());
        differs.map(|h| {
            format!(
                "depends_on_positions() is false, but halfedge {} changed from {} to {}",
                h.raw(),
                bulk[h.index()],
                other[h.index()]
            )
        })
    }

    /// Why the Laplacian does not assemble or three free-boundary smoothing steps with
    /// λ = 0.5 give a non-finite position.
    fn smoothing_fails(&self) -> Option<String> {
        let (mesh, positions, scheme) = (self.mesh, self.positions, self.scheme);
        Laplacian::new(mesh, positions, scheme, LaplacianOptions::default())
            .map_err(|e| format!("the Laplacian does not assemble: {e}"))
            .and_then(|_| {
                let config = SmoothConfig::new(0.5, 3).boundary(Boundary::Free);
                smooth(mesh, positions, scheme, config)
                    .map_err(|e| format!("smoothing failed: {e}"))
            })
            .and_then(
                |out| match out.positions.iter().position(|q| !q.is_finite()) {
                    Some(v) => Err(format!("vertex {v} is not finite after smoothing")),
                    None => Ok(()),
                },
            )
            .err()
    }
}

/// Runs [`check_scheme`] and panics with the whole report when a check fails — the one
/// line to put in a scheme's own test suite.
///
/// # Panics
/// When any conformance check fails; the message is the report.
///
/// # Examples
/// ```
/// use beltrami_testkit::{assert_scheme_conforms, SchemeClaims};
/// use beltrami_weights::InverseDistance;
/// assert_scheme_conforms(&InverseDistance, SchemeClaims::new().symmetric(true));
/// ```
pub fn assert_scheme_conforms(scheme: &dyn WeightScheme, claims: SchemeClaims) {
    let report = check_scheme(scheme, claims);
    assert!(
        report.passed(),
        "weight scheme '{}' does not conform:\n{report}",
        report.scheme
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use beltrami_weights::{Cotangent, InverseDistance, Uniform};

    #[test]
    fn the_built_in_schemes_conform() {
        for scheme in [&Uniform as &dyn WeightScheme, &InverseDistance, &Cotangent] {
            let report = check_scheme(scheme, SchemeClaims::new().symmetric(true));
            assert!(report.passed(), "{report}");
            // 3 fixtures x (finite, bulk, symmetric, translation, assembles) + uniform's
            // position-independence check.
            let expected = if scheme.depends_on_positions() {
                15
            } else {
                18
            };
            assert_eq!(report.checks.len(), expected, "{report}");
        }
    }

    /// Infinite on zero-length edges: 1/|e| without a guard.
    struct Unguarded;
    impl WeightScheme for Unguarded {
        fn name(&self) -> &str {
            "unguarded"
        }
        fn weight(&self, ctx: &WeightContext<'_>, h: HalfedgeId) -> f64 {
            1.0 / ctx.edge_vector(h).length()
        }
    }

    /// Depends on where the mesh is: |x_j|.
    struct Absolute;
    impl WeightScheme for Absolute {
        fn name(&self) -> &str {
            "absolute"
        }
        fn weight(&self, ctx: &WeightContext<'_>, h: HalfedgeId) -> f64 {
            1.0 + ctx.position(ctx.mesh().to_vertex(h)).length()
        }
    }

    /// Claims to ignore positions but does not; and its bulk path differs from `weight`.
    struct Liar;
    impl WeightScheme for Liar {
        fn name(&self) -> &str {
            "liar"
        }
        fn weight(&self, ctx: &WeightContext<'_>, h: HalfedgeId) -> f64 {
            1.0 + ctx.edge_vector(h).length()
        }
        fn fill_weights(&self, _ctx: &WeightContext<'_>, out: &mut [f64]) {
            out.fill(1.0);
        }
        fn depends_on_positions(&self) -> bool {
            false
        }
    }

    fn failed(report: &ConformanceReport) -> Vec<&'static str> {
        let mut names: Vec<&'static str> = report.failures().iter().map(|c| c.property).collect();
        names.dedup();
        names
    }

    #[test]
    fn an_unguarded_division_is_caught_on_the_degenerate_patch() {
        let report = check_scheme(&Unguarded, SchemeClaims::new().symmetric(true));
        assert!(!report.passed());
        let failures = report.failures();
        assert!(
            failures.iter().all(|c| c.fixture == "degenerate patch"),
            "{report}"
        );
        assert!(failures.iter().any(|c| c.property == "finite"), "{report}");
        assert!(report.to_string().contains("FAIL finite"));
    }

    #[test]
    fn a_position_dependent_weight_is_caught() {
        let report = check_scheme(&Absolute, SchemeClaims::new());
        assert_eq!(failed(&report), ["translation invariant"], "{report}");
        assert_eq!(
            report.failures().len(),
            3,
            "one failure per fixture: {report}"
        );
    }

    #[test]
    fn an_asymmetric_weight_is_caught_only_when_symmetry_is_claimed() {
        assert!(
            check_scheme(&Absolute, SchemeClaims::new())
                .checks
                .iter()
                .all(|c| c.property != "symmetric")
        );
        let report = check_scheme(&Absolute, SchemeClaims::new().symmetric(true));
        assert!(
            report.failures().iter().any(|c| c.property == "symmetric"),
            "{report}"
        );
    }

    #[test]
    fn false_claims_about_positions_and_bulk_paths_are_caught() {
        let report = check_scheme(&Liar, SchemeClaims::new().symmetric(true));
        let names = failed(&report);
        assert!(names.contains(&"bulk equals single"), "{report}");
        // The bulk path ignores positions, so the position check cannot see the lie;
        // the bulk-versus-single check does.
        assert!(!names.contains(&"finite"));
    }

    #[test]
    #[should_panic(expected = "does not conform")]
    fn assert_scheme_conforms_panics_with_the_report() {
        assert_scheme_conforms(&Unguarded, SchemeClaims::new());
    }
}
