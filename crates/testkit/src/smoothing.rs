//! [`SmoothingSummary`]: what a smoothing run did, without the parts that change between
//! runs (times).

use std::fmt;

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::{DVec3, HalfedgeMesh, TopologyError};
use beltrami_smooth::{Boundary, Smoothed, StopReason, WeightUpdate};
use beltrami_weights::{NegativeWeights, Normalization};
use serde::Serialize;

use crate::round::{SUMMARY_DIGITS, format_significant, round_significant};

/// The settings and the effect of a smoothing run, rounded for snapshots.
///
/// Lengths are in units of the input's bounding-box diagonal, so the summary reads the
/// same for a mesh in millimetres and in metres; ratios compare the output with the
/// input. Every `f64` field holds its value rounded to [`SUMMARY_DIGITS`] significant
/// digits. Wall times are left out on purpose: they differ on every run.
///
/// # Examples
/// ```
/// use beltrami_halfedge::primitives;
/// use beltrami_smooth::{smooth, SmoothConfig};
/// use beltrami_testkit::SmoothingSummary;
/// use beltrami_weights::Uniform;
///
/// let sphere = primitives::icosphere(2);
/// let mesh = sphere.mesh()?;
/// let out = smooth(&mesh, &sphere.positions, &Uniform, SmoothConfig::new(0.8, 10))?;
/// let summary = SmoothingSummary::new(&mesh, &sphere.positions, &out)?;
/// assert_eq!(summary.scheme, "uniform");
/// assert!(summary.volume_ratio.unwrap() < 1.0); // diffusion shrinks
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SmoothingSummary {
    /// The weight scheme's name.
    pub scheme: String,
    /// The step λ.
    pub lambda: f64,
    /// Iterations requested.
    pub iterations_requested: usize,
    /// Iterations done.
    pub iterations_done: usize,
    /// `fixed`, `free` or `curve`.
    pub boundary: String,
    /// `every` or `once`.
    pub update: String,
    /// `weight-sum` or `area (<kind>)`.
    pub normalization: String,
    /// `keep`, `clamp` or `abs`.
    pub negative_weights: String,
    /// Number of pinned vertices.
    pub pinned: usize,
    /// `completed` or `observer`.
    pub stop: String,
    /// The largest number of stuck vertices in any iteration.
    pub max_stuck_vertices: usize,
    /// Vertices whose position changed.
    pub moved_vertices: usize,
    /// The largest distance a vertex moved, over the input's bounding-box diagonal.
    pub max_displacement: f64,
    /// The root-mean-square distance the vertices moved, over the input's bounding-box
    /// diagonal.
    pub rms_displacement: f64,
    /// Surface area after / before.
    pub area_ratio: f64,
    /// Enclosed volume after / before, for a closed mesh with non-zero volume.
    pub volume_ratio: Option<f64>,
}

fn round(x: f64) -> f64 {
    round_significant(x, SUMMARY_DIGITS)
}

fn boundary_name(b: Boundary) -> String {
    match b {
        Boundary::Fixed => "fixed".into(),
        Boundary::Free => "free".into(),
        Boundary::Curve => "curve".into(),
        other => format!("{other:?}").to_lowercase(),
    }
}

fn update_name(u: WeightUpdate) -> String {
    match u {
        WeightUpdate::Every => "every".into(),
        WeightUpdate::Once => "once".into(),
        other => format!("{other:?}").to_lowercase(),
    }
}

fn normalization_name(n: Normalization) -> String {
    match n {
        Normalization::WeightSum => "weight-sum".into(),
        Normalization::Area(kind) => format!("area ({kind:?})").to_lowercase(),
        other => format!("{other:?}").to_lowercase(),
    }
}

fn negative_name(n: NegativeWeights) -> String {
    match n {
        NegativeWeights::Keep => "keep".into(),
        NegativeWeights::Clamp => "clamp".into(),
        NegativeWeights::Abs => "abs".into(),
        other => format!("{other:?}").to_lowercase(),
    }
}

fn stop_name(s: StopReason) -> String {
    match s {
        StopReason::Completed => "completed".into(),
        StopReason::Observer => "observer".into(),
        other => format!("{other:?}").to_lowercase(),
    }
}

impl SmoothingSummary {
    /// Summarises the run `smoothed` of `mesh` that started from `before`.
    ///
    /// # Errors
    /// [`TopologyError::PositionCount`] when `before` or the smoothed positions do not
    /// have one entry per vertex.
    pub fn new(
        mesh: &HalfedgeMesh,
        before: &[DVec3],
        smoothed: &Smoothed,
    ) -> Result<Self, TopologyError> {
        let g0 = Geometry::new(mesh, before)?;
        let g1 = Geometry::new(mesh, &smoothed.positions)?;
        let diagonal = g0.bounding_box().map_or(0.0, |(lo, hi)| (hi - lo).length());
        let per_diagonal = |d: f64| if diagonal > 0.0 { d / diagonal } else { d };
        let mut max: f64 = 0.0;
        let mut squares = 0.0;
        let mut moved = 0;
        for (a, b) in before.iter().zip(&smoothed.positions) {
            let d = (*b - *a).length();
            max = max.max(d);
            squares += d * d;
            moved += usize::from(a != b);
        }
        let rms = if before.is_empty() {
            0.0
        } else {
            (squares / before.len() as f64).sqrt()
        };
        let ratio = |after: f64, before: f64| (before != 0.0).then(|| round(after / before));
        let volume_ratio = match (g0.volume(), g1.volume()) {
            (Ok(v0), Ok(v1)) => ratio(v1, v0),
            _ => None,
        };
        let report = &smoothed.report;
        let config = &report.config;
        Ok(Self {
            scheme: report.scheme.clone(),
            lambda: round(config.lambda),
            iterations_requested: config.iterations,
            iterations_done: report.iterations,
            boundary: boundary_name(config.boundary),
            update: update_name(config.update),
            normalization: normalization_name(config.laplacian.normalization),
            negative_weights: negative_name(config.laplacian.negative),
            pinned: config.pinned.len(),
            stop: stop_name(report.stop),
            max_stuck_vertices: report.max_stuck_vertices,
            moved_vertices: moved,
            max_displacement: round(per_diagonal(max)),
            rms_displacement: round(per_diagonal(rms)),
            area_ratio: ratio(g1.surface_area(), g0.surface_area()).unwrap_or(1.0),
            volume_ratio,
        })
    }
}

impl fmt::Display for SmoothingSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let n = |x: f64| format_significant(x, SUMMARY_DIGITS);
        writeln!(
            f,
            "scheme: {}, lambda: {}, iterations: {} of {} ({})",
            self.scheme,
            n(self.lambda),
            self.iterations_done,
            self.iterations_requested,
            self.stop
        )?;
        writeln!(
            f,
            "boundary: {}, weights: {}, normalisation: {}, negative weights: {}, pinned: {}",
            self.boundary, self.update, self.normalization, self.negative_weights, self.pinned
        )?;
        writeln!(
            f,
            "moved vertices: {}, max stuck vertices: {}",
            self.moved_vertices, self.max_stuck_vertices
        )?;
        writeln!(
            f,
            "displacement / bbox diagonal: max {}, rms {}",
            n(self.max_displacement),
            n(self.rms_displacement)
        )?;
        match self.volume_ratio {
            Some(v) => writeln!(
                f,
                "area ratio: {}, volume ratio: {}",
                n(self.area_ratio),
                n(v)
            ),
            None => writeln!(f, "area ratio: {}, volume ratio: -", n(self.area_ratio)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use beltrami_halfedge::primitives;
    use beltrami_smooth::{SmoothConfig, smooth};
    use beltrami_weights::{Cotangent, Uniform};

    #[test]
    fn a_flat_grid_with_a_fixed_boundary_does_not_move_under_cotangent_weights() {
        let grid = primitives::grid(5, 4);
        let mesh = grid.mesh().unwrap();
        let out = smooth(
            &mesh,
            &grid.positions,
            &Cotangent,
            SmoothConfig::new(0.5, 5),
        )
        .unwrap();
        let s = SmoothingSummary::new(&mesh, &grid.positions, &out).unwrap();
        assert_eq!(s.max_displacement, 0.0);
        assert_eq!(s.area_ratio, 1.0);
        assert_eq!(s.volume_ratio, None);
        assert_eq!(s.boundary, "fixed");
        assert_eq!(s.stop, "completed");
    }

    #[test]
    fn a_sphere_shrinks_and_the_summary_says_so() {
        let sphere = primitives::icosphere(2);
        let mesh = sphere.mesh().unwrap();
        let config = SmoothConfig::new(0.8, 10).boundary(Boundary::Free);
        let out = smooth(&mesh, &sphere.positions, &Uniform, config).unwrap();
        let s = SmoothingSummary::new(&mesh, &sphere.positions, &out).unwrap();
        assert_eq!(s.moved_vertices, 162);
        assert!(s.volume_ratio.unwrap() < 0.99);
        assert!(s.area_ratio < 1.0);
        assert!(s.max_displacement > 0.0 && s.max_displacement < 0.1);
        let text = s.to_string();
        assert!(text.contains("scheme: uniform, lambda: 0.8, iterations: 10 of 10"));
        assert!(!text.contains("time"));
    }
}
