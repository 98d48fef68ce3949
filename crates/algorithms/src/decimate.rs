//! Decimation by quadric error metrics: halfedge collapses, cheapest first, until a target
//! vertex count is reached or no collapse is left that the constraints allow.
//!
//! # Algorithm
//!
//! Garland and Heckbert's quadric error metric with halfedge collapses, as OpenMesh's
//! `DecimaterT` + `ModQuadricT` and pmp-library's `Decimation` run it:
//!
//! 1. Every vertex gets the quadric `Q_v(x) = Σ A_f (n_f·x + d_f)²` of the planes of its
//!    triangles, each weighted by the triangle's area `A_f` (OpenMesh's choice; a
//!    degenerate triangle adds nothing). Unless boundary vertices are kept, every
//!    boundary edge adds the plane through it perpendicular to its triangle, weighted by
//!    the squared edge length, to both its vertices, so that the boundary curve is
//!    preserved as the surface is.
//! 2. The collapse of halfedge `v0 → v1` removes `v0` and costs `(Q_v0 + Q_v1)(p)`, with
//!    `p` the position `v1` gets: the minimiser of the summed quadric (the default,
//!    [`Placement::Optimal`]) or its own (endpoint placement, as OpenMesh does). By
//!    default the cost is divided by a shape penalty when the worst triangle the
//!    collapse makes is badly shaped ([`DecimateOptions::quality_threshold`], MeshLab's
//!    quality-weighted priority).
//! 3. An indexed binary heap holds every halfedge by its quadric cost (the two halfedges
//!    of an interior edge share one entry when their optimal placement is the same), a
//!    lower bound of its penalised cost; the shape penalty and legality are evaluated
//!    only when an entry reaches the top (an entry whose penalised cost is larger goes
//!    back with it), and a refused halfedge is parked until a collapse changes its
//!    neighbourhood. Ties go to the smaller halfedge id, so the result is a
//!    deterministic function of the input.
//! 4. After a collapse `v1` gets `Q_v0 + Q_v1`, the edges at `v1` are queued with their
//!    new cost and the parked halfedges around `v1`'s neighbours are queued again (with
//!    endpoint placement: the outgoing halfedges of `v0`'s former neighbours, OpenMesh's
//!    update).
//!
//! A collapse is legal when the topology allows it (OpenMesh's `is_collapse_ok` rules,
//! see [`EditMesh::collapse_edge`], plus `BaseDecimaterT::is_collapse_legal`'s: a
//! boundary vertex only moves along the boundary, `v0` keeps at least two faces, and two
//! valence-3 opposite vertices that are joined stay), no changed triangle flips or
//! degenerates, and every constraint of [`DecimateOptions`] holds.
//!
//! # References
//! - M. Garland, P. S. Heckbert, "Surface simplification using quadric error metrics",
//!   SIGGRAPH 1997.
//! - L. Kobbelt, S. Campagna, H.-P. Seidel, "A general framework for mesh decimation",
//!   Graphics Interface 1998 (the halfedge collapse and the decimation framework
//!   OpenMesh implements).
//! - M. Botsch, L. Kobbelt, M. Pauly, P. Alliez, B. Lévy, *Polygon Mesh Processing*,
//!   AK Peters 2010, chapter 7 (normal cones, the Hausdorff constraint).

use std::cmp::Ordering;
use std::f64::consts::PI;

use beltrami_halfedge::{
    DVec3, EditError, EditMesh, FaceId, HalfedgeId, HalfedgeMesh, TopologyError, VertexId,
};
use beltrami_metrics::MetricsError;
use beltrami_metrics::distance::{
    HausdorffSampling, SurfaceIndex, closest_point_on_triangle, hausdorff,
};
use glam::DMat3;

use crate::error::{algorithm_error, check_finite, check_mesh};

/// The weight of a boundary constraint plane per unit of squared edge length (the face
/// planes are weighted by area, the same unit).
const BOUNDARY_WEIGHT: f64 = 1.0;

/// [`Decimator::keyed_at`] of a halfedge whose heap key is a lower bound.
const NOT_KEYED: u32 = u32::MAX;

/// The seed of the surface samples of the reported Hausdorff distance.
const HAUSDORFF_SEED: u64 = 0x0dec_1a7e;

/// How many vertices [`decimate`] keeps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DecimateTarget {
    /// This many vertices (at least 1).
    Vertices(usize),
    /// This fraction of the input's vertices, in (0, 1]; the count is
    /// `round(ratio × vertices)`, at least 1.
    Ratio(f64),
}

impl Default for DecimateTarget {
    fn default() -> Self {
        Self::Ratio(0.5)
    }
}

/// Where the kept vertex of a collapse goes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Placement {
    /// The kept vertex stays where it is (OpenMesh's `ModQuadricT`): the output's
    /// vertices are a subset of the input's, bit for bit.
    Endpoint,
    /// The default. The kept vertex moves to the minimiser of the summed quadric (Garland and
    /// Heckbert's optimal placement, solving the 3 × 3 system). When that system is
    /// singular (a flat or cylindrical neighbourhood) or its solution lies farther than
    /// twice the edge length from the edge's midpoint, the better of the two end points
    /// is used. A kept vertex on the boundary never moves.
    #[default]
    Optimal,
}

/// The settings of [`decimate`]. Every bound is optional; without any, collapses stop
/// only at the target or when topology forbids every remaining one.
///
/// The default places the kept vertex optimally and penalises badly shaped triangles
/// ([`DecimateOptions::quality_threshold`] 0.4), which gives both a smaller distance to
/// the input and far fewer slivers than OpenMesh's plain quadric decimation;
/// [`DecimateOptions::openmesh`] gives that one (endpoint placement, no penalty).
///
/// # Examples
/// ```
/// use beltrami_algorithms::{DecimateOptions, DecimateTarget, Placement};
/// let options = DecimateOptions::default()
///     .ratio(0.25)
///     .max_normal_deviation(10f64.to_radians())
///     .keep_boundary(true)
///     .placement(Placement::Optimal);
/// assert_eq!(options.target, DecimateTarget::Ratio(0.25));
/// assert!(options.keep_boundary);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct DecimateOptions {
    /// How many vertices to keep (default: half of them).
    pub target: DecimateTarget,
    /// The largest quadric error of a collapse, as a distance in the positions' unit
    /// (not squared): the area-weighted root-mean-square distance of the kept vertex's
    /// new position to the planes of all input triangles (and boundary constraint
    /// planes) accumulated into the two vertices, `sqrt(Q(p) / ΣA)`. `None`: no bound.
    pub max_error: Option<f64>,
    /// The largest angle, radians in [0, π], between the normal of an output triangle
    /// and the normal of any input triangle merged into it (tracked with normal cones,
    /// as pmp-library does). `None`: only flips (a triangle's normal turning by 90° or
    /// more in one collapse, or from its normal at the start) and degenerate triangles
    /// are refused, which they always are; a triangle can then still end up folded
    /// against the surface it came from, which a loose bound (60°) prevents.
    pub max_normal_deviation: Option<f64>,
    /// Never remove a boundary vertex: every boundary vertex keeps its position bit for
    /// bit and the boundary polygon stays as it is.
    pub keep_boundary: bool,
    /// Where the kept vertex goes.
    pub placement: Placement,
    /// The largest aspect ratio of a triangle a collapse makes: `ℓ²_max √3 / (4A)`, 1 for
    /// an equilateral triangle, growing without bound as it degenerates. A collapse is
    /// refused when its worst new triangle exceeds the bound *and* is worse than the
    /// worst triangle it replaces (so a collapse that improves a bad region stays
    /// possible). At least 1; `None`: no bound.
    pub max_aspect_ratio: Option<f64>,
    /// The largest distance, in the positions' unit, from any input vertex to the output
    /// surface. Every input vertex is assigned to the triangle closest to it; a collapse
    /// is refused when a vertex assigned to one of the changed triangles would be
    /// farther than this from all triangles around the kept vertex afterwards (OpenMesh's
    /// `ModHausdorffT`). This bounds the one-sided distance input vertices → output, not
    /// the distance of points inside input triangles. `None`: no bound.
    pub max_distance: Option<f64>,
    /// The shape quality below which a collapse costs more, in [0, 1] (default 0.4;
    /// 0: no penalty). A triangle's quality is
    /// `4A / (√3 ℓ²_max)`, the inverse of its aspect ratio: 1 for an equilateral
    /// triangle, 0 for a degenerate one (0.3 is about a 15° needle). When the worst
    /// triangle a collapse makes has quality `q` below the threshold `t`, the
    /// collapse's quadric error (at least `10⁻¹²` times the fourth power of the mean
    /// input edge length, so that flat regions are ordered too) is divided by `q / t`
    /// (MeshLab's quadric edge collapse penalises the same way). This orders the
    /// collapses and never refuses one, so it does not keep the target from being
    /// reached.
    pub quality_threshold: f64,
    /// Whether [`decimate`] measures the Hausdorff distance between output and input for
    /// its report (default `true`). The measurement is no part of the decimation and can
    /// take a third of the time; without it the report's distances are 0 and
    /// [`DecimateReport::distance_measured`] is `false`, and
    /// [`DecimateReport::measure_distance`] measures them later.
    pub measure_distance: bool,
}

/// The default of [`DecimateOptions::quality_threshold`].
const DEFAULT_QUALITY_THRESHOLD: f64 = 0.4;

impl Default for DecimateOptions {
    fn default() -> Self {
        Self {
            target: DecimateTarget::default(),
            max_error: None,
            max_normal_deviation: None,
            keep_boundary: false,
            placement: Placement::Optimal,
            max_aspect_ratio: None,
            max_distance: None,
            quality_threshold: DEFAULT_QUALITY_THRESHOLD,
            measure_distance: true,
        }
    }
}

impl DecimateOptions {
    /// OpenMesh's `DecimaterT` with `ModQuadricT` alone: [`Placement::Endpoint`] and no
    /// shape penalty (`quality_threshold` 0); the other settings are the defaults.
    #[must_use]
    pub fn openmesh() -> Self {
        Self {
            placement: Placement::Endpoint,
            quality_threshold: 0.0,
            ..Self::default()
        }
    }

    /// Keeps `count` vertices.
    #[must_use]
    pub fn vertices(mut self, count: usize) -> Self {
        self.target = DecimateTarget::Vertices(count);
        self
    }

    /// Keeps the fraction `ratio` of the vertices, in (0, 1].
    #[must_use]
    pub fn ratio(mut self, ratio: f64) -> Self {
        self.target = DecimateTarget::Ratio(ratio);
        self
    }

    /// Sets the largest quadric error of a collapse, as a distance (see
    /// [`DecimateOptions::max_error`]).
    #[must_use]
    pub fn max_error(mut self, distance: f64) -> Self {
        self.max_error = Some(distance);
        self
    }

    /// Sets the largest normal deviation, in radians.
    #[must_use]
    pub fn max_normal_deviation(mut self, radians: f64) -> Self {
        self.max_normal_deviation = Some(radians);
        self
    }

    /// Keeps (`true`) or allows removing (`false`, the default) boundary vertices.
    #[must_use]
    pub fn keep_boundary(mut self, keep: bool) -> Self {
        self.keep_boundary = keep;
        self
    }

    /// Sets where the kept vertex goes.
    #[must_use]
    pub fn placement(mut self, placement: Placement) -> Self {
        self.placement = placement;
        self
    }

    /// Sets the largest aspect ratio of a new triangle (at least 1).
    #[must_use]
    pub fn max_aspect_ratio(mut self, ratio: f64) -> Self {
        self.max_aspect_ratio = Some(ratio);
        self
    }

    /// Sets the largest distance of an input vertex from the output surface.
    #[must_use]
    pub fn max_distance(mut self, distance: f64) -> Self {
        self.max_distance = Some(distance);
        self
    }

    /// Sets the shape quality below which collapses are penalised, in [0, 1] (0: no
    /// penalty; see [`DecimateOptions::quality_threshold`]).
    #[must_use]
    pub fn quality_threshold(mut self, threshold: f64) -> Self {
        self.quality_threshold = threshold;
        self
    }

    /// Measures (`true`, the default) or skips the report's Hausdorff distance (see
    /// [`DecimateOptions::measure_distance`]).
    #[must_use]
    pub fn measure_distance(mut self, measure: bool) -> Self {
        self.measure_distance = measure;
        self
    }

    /// Checks every value's range.
    fn validate(&self) -> Result<(), DecimateError> {
        let bad = |reason: String| Err(DecimateError::Options { reason });
        match self.target {
            DecimateTarget::Vertices(0) => {
                return bad("the target vertex count must be at least 1".into());
            }
            DecimateTarget::Ratio(r) if !(r > 0.0 && r <= 1.0) => {
                return bad(format!("the target ratio must be in (0, 1], got {r}"));
            }
            _ => {}
        }
        if let Some(e) = self.max_error
            && !(e >= 0.0 && e.is_finite())
        {
            return bad(format!(
                "the largest quadric error must be finite and >= 0, got {e}"
            ));
        }
        if let Some(a) = self.max_normal_deviation
            && !(0.0..=PI).contains(&a)
        {
            return bad(format!(
                "the largest normal deviation must be in [0, pi] radians, got {a}"
            ));
        }
        if let Some(a) = self.max_aspect_ratio
            && !(a >= 1.0 && a.is_finite())
        {
            return bad(format!(
                "the largest aspect ratio must be finite and >= 1, got {a}"
            ));
        }
        if let Some(d) = self.max_distance
            && !(d >= 0.0 && d.is_finite())
        {
            return bad(format!(
                "the largest distance must be finite and >= 0, got {d}"
            ));
        }
        let t = self.quality_threshold;
        if !(0.0..=1.0).contains(&t) {
            return bad(format!("the quality threshold must be in [0, 1], got {t}"));
        }
        Ok(())
    }

    /// The target vertex count for a mesh of `n` vertices.
    fn target_count(&self, n: usize) -> usize {
        match self.target {
            DecimateTarget::Vertices(count) => count,
            // `ratio` is in (0, 1], so the product is in [0, n] and the cast exact.
            DecimateTarget::Ratio(r) => ((r * n as f64).round() as usize).max(1),
        }
    }
}

/// Why [`decimate`] stopped.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum DecimateStop {
    /// The mesh has the target vertex count (or had no more to begin with).
    #[default]
    TargetReached,
    /// No collapse was left that the topology and the constraints allow; the refusal
    /// counts of [`DecimateReport::refused`] say which constraints stopped it.
    NoCollapseLeft,
}

/// How many candidate collapses each check refused. A vertex's outgoing halfedges are
/// evaluated again whenever its neighbourhood changes, so one halfedge can be counted
/// several times: these count evaluations, not distinct edges, and show which checks
/// limit the decimation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub struct RefusalCounts {
    /// The topology forbids the collapse (link condition, boundary rules, valence).
    pub topology: usize,
    /// [`DecimateOptions::keep_boundary`] keeps the vertex.
    pub boundary: usize,
    /// The quadric error exceeds [`DecimateOptions::max_error`].
    pub error: usize,
    /// A triangle would flip or degenerate.
    pub normal_flip: usize,
    /// A normal would deviate by more than [`DecimateOptions::max_normal_deviation`].
    pub normal_deviation: usize,
    /// A triangle would exceed [`DecimateOptions::max_aspect_ratio`].
    pub aspect_ratio: usize,
    /// An input vertex would be farther than [`DecimateOptions::max_distance`].
    pub distance: usize,
}

/// What [`decimate`] did.
#[derive(Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct DecimateReport {
    /// Vertices of the input.
    pub vertices_before: usize,
    /// Faces of the input.
    pub faces_before: usize,
    /// Vertices of the output.
    pub vertices_after: usize,
    /// Faces of the output.
    pub faces_after: usize,
    /// The target vertex count the options asked for.
    pub target_vertices: usize,
    /// Collapses done (`vertices_before − vertices_after`).
    pub collapses: usize,
    /// Candidate collapses refused, by check.
    pub refused: RefusalCounts,
    /// Why the run stopped.
    pub stop: DecimateStop,
    /// Whether the output has at most the target vertex count (exactly the target when
    /// the input had more).
    pub target_reached: bool,
    /// The largest quadric error of a collapse done, as a distance in the positions'
    /// unit (see [`DecimateOptions::max_error`]); 0 without collapses.
    pub max_quadric_error: f64,
    /// Whether the three distances below were measured
    /// ([`DecimateOptions::measure_distance`]); when not, they are 0.
    pub distance_measured: bool,
    /// The symmetric Hausdorff distance between output and input, in the positions'
    /// unit: the larger of the two one-sided distances below.
    pub hausdorff: f64,
    /// The largest distance from the output's vertices and surface samples to the input
    /// surface.
    pub hausdorff_to_input: f64,
    /// The largest distance from the input's vertices and surface samples to the output
    /// surface.
    pub hausdorff_from_input: f64,
}

impl DecimateReport {
    /// Measures the Hausdorff distance between the decimation's `output` and its
    /// `input` (each a mesh and its positions) into the report, as [`decimate`] does
    /// unless [`DecimateOptions::measure_distance`] is off: over the vertices plus one
    /// surface sample per input face on each side, with a fixed seed, so that the
    /// result is the same whichever measures it.
    ///
    /// # Errors
    /// [`DecimateError::Metrics`] when a mesh cannot be indexed (a position count that
    /// does not match, a non-finite position).
    pub fn measure_distance(
        &mut self,
        input: (&HalfedgeMesh, &[DVec3]),
        output: (&HalfedgeMesh, &[DVec3]),
    ) -> Result<(), DecimateError> {
        let samples = HausdorffSampling::VerticesAndSurface {
            samples: input.0.n_faces(),
            seed: HAUSDORFF_SEED,
        };
        let distance = hausdorff(
            &SurfaceIndex::new(output.0, output.1)?,
            &SurfaceIndex::new(input.0, input.1)?,
            samples,
        )?;
        self.distance_measured = true;
        self.hausdorff = distance.symmetric;
        self.hausdorff_to_input = distance.forward;
        self.hausdorff_from_input = distance.backward;
        Ok(())
    }
}

algorithm_error! {
    /// Why [`decimate`] could not run. Every variant names the offending element or value.
    #[derive(Debug, Clone, PartialEq, thiserror::Error)]
    #[non_exhaustive]
    pub enum DecimateError for "decimation" {
        /// The mesh has no face: there is no surface to decimate.
        #[error("the mesh has no faces; decimation needs a surface")]
        NoFaces,
        /// A collapse the checks allowed was refused: a defect of this crate, reported
        /// rather than panicking.
        #[error("the decimated mesh is not valid: {0}")]
        Edit(#[from] EditError),
        /// The input or the result did not convert between the frozen and the editable
        /// mesh.
        #[error("{0}")]
        Topology(#[from] TopologyError),
        /// Measuring the Hausdorff distance failed (a defect: the positions are finite).
        #[error("measuring the Hausdorff distance: {0}")]
        Metrics(#[from] MetricsError),
    }
}

/// A symmetric 4 × 4 quadric `Q(x) = xᵀAx + 2bᵀx + c` with the total weight of its
/// planes.
#[derive(Clone, Copy, Debug, Default)]
struct Quadric {
    /// `A` as `xx, xy, xz, yy, yz, zz`.
    a: [f64; 6],
    b: DVec3,
    c: f64,
    weight: f64,
}

impl Quadric {
    /// `w (n·x + d)²`.
    fn plane(n: DVec3, d: f64, w: f64) -> Self {
        Self {
            a: [
                w * n.x * n.x,
                w * n.x * n.y,
                w * n.x * n.z,
                w * n.y * n.y,
                w * n.y * n.z,
                w * n.z * n.z,
            ],
            b: n * (w * d),
            c: w * d * d,
            weight: w,
        }
    }

    fn add(&mut self, o: &Self) {
        for (a, b) in self.a.iter_mut().zip(o.a) {
            *a += b;
        }
        self.b += o.b;
        self.c += o.c;
        self.weight += o.weight;
    }

    fn sum(&self, o: &Self) -> Self {
        let mut s = *self;
        s.add(o);
        s
    }

    fn matrix(&self) -> DMat3 {
        let [xx, xy, xz, yy, yz, zz] = self.a;
        DMat3::from_cols(
            DVec3::new(xx, xy, xz),
            DVec3::new(xy, yy, yz),
            DVec3::new(xz, yz, zz),
        )
    }

    /// `Q(p)`, clamped at 0 against rounding.
    fn eval(&self, p: DVec3) -> f64 {
        let q = p.dot(self.matrix() * p) + 2.0 * self.b.dot(p) + self.c;
        q.max(0.0)
    }

    /// `sqrt(Q(p) / weight)`: the weighted RMS distance to the planes.
    fn rms(&self, p: DVec3) -> f64 {
        if self.weight > 0.0 {
            (self.eval(p) / self.weight).sqrt()
        } else {
            0.0
        }
    }

    /// The minimiser of `Q`, `−A⁻¹b`, when `A` is well conditioned: the symmetric
    /// adjugate once, its first column giving the determinant.
    fn minimiser(&self) -> Option<DVec3> {
        let [xx, xy, xz, yy, yz, zz] = self.a;
        let scale = self.a.iter().fold(0.0f64, |s, x| s.max(x.abs()));
        if scale <= 0.0 {
            return None;
        }
        // The cofactors of the symmetric matrix (the adjugate is symmetric too).
        let c_xx = yy * zz - yz * yz;
        let c_xy = xz * yz - xy * zz;
        let c_xz = xy * yz - xz * yy;
        let det = xx * c_xx + xy * c_xy + xz * c_xz;
        if det.abs() <= 1e-10 * scale * scale * scale {
            return None;
        }
        let c_yy = xx * zz - xz * xz;
        let c_yz = xy * xz - xx * yz;
        let c_zz = xx * yy - xy * xy;
        let b = -self.b;
        let x = DVec3::new(
            c_xx * b.x + c_xy * b.y + c_xz * b.z,
            c_xy * b.x + c_yy * b.y + c_yz * b.z,
            c_xz * b.x + c_yz * b.y + c_zz * b.z,
        ) / det;
        x.is_finite().then_some(x)
    }
}

/// A cone of unit normals: its axis and half opening angle (radians).
#[derive(Clone, Copy, Debug)]
struct NormalCone {
    center: DVec3,
    angle: f64,
}

impl NormalCone {
    fn new(n: DVec3) -> Self {
        Self {
            center: n,
            angle: 0.0,
        }
    }

    /// The smallest cone around both (pmp-library's `NormalCone::merge`).
    fn merge(self, other: Self) -> Self {
        let dp = self.center.dot(other.center).clamp(-1.0, 1.0);
        if dp > 0.99999 {
            Self {
                center: self.center,
                angle: self.angle.max(other.angle),
            }
        } else if dp < -0.99999 {
            Self {
                center: self.center,
                angle: PI,
            }
        } else {
            let center_angle = dp.acos();
            let min_angle = (-self.angle).min(center_angle - other.angle);
            let max_angle = self.angle.max(center_angle + other.angle);
            let angle = 0.5 * (max_angle - min_angle);
            let axis_angle = 0.5 * (min_angle + max_angle);
            let center = (self.center * (center_angle - axis_angle).sin()
                + other.center * axis_angle.sin())
                / center_angle.sin();
            Self {
                center: center.try_normalize().unwrap_or(self.center),
                angle,
            }
        }
    }
}

/// Why a candidate collapse was refused.
#[derive(Clone, Copy, Debug)]
enum Refusal {
    Topology,
    Boundary,
    Error,
    Flip,
    NormalDeviation,
    AspectRatio,
    Distance,
}

impl RefusalCounts {
    fn count(&mut self, r: Refusal) {
        let c = match r {
            Refusal::Topology => &mut self.topology,
            Refusal::Boundary => &mut self.boundary,
            Refusal::Error => &mut self.error,
            Refusal::Flip => &mut self.normal_flip,
            Refusal::NormalDeviation => &mut self.normal_deviation,
            Refusal::AspectRatio => &mut self.aspect_ratio,
            Refusal::Distance => &mut self.distance,
        };
        *c += 1;
    }
}

/// A legal collapse and what it changes.
struct Candidate {
    /// The same as a distance, `sqrt(Q(p) / ΣA)`.
    rms: f64,
    /// The kept vertex's new position.
    position: DVec3,
    /// The new normal cones of the changed faces (with a normal bound).
    cones: Vec<(FaceId, NormalCone)>,
    /// Faces whose input vertices are reassigned, and the new assignment (with a
    /// distance bound).
    cleared: Vec<FaceId>,
    assigned: Vec<(FaceId, Vec<u32>)>,
}

/// A binary min-heap of halfedges keyed by their collapse priority, with each halfedge's
/// place in the heap, so that a key is changed or removed in place (pmp-library's
/// `HeapInterface`): the heap never holds more than one entry per halfedge. Ties go to
/// the smaller halfedge id, so the order is a deterministic function of the keys.
struct Heap {
    /// `(key, halfedge)`, a min-heap in `(key, halfedge)` order.
    entries: Vec<(f64, u32)>,
    /// Per halfedge: its index in `entries`, or `u32::MAX` when it is not queued.
    place: Vec<u32>,
}

impl Heap {
    const ABSENT: u32 = u32::MAX;

    /// A heap of the given `(key, halfedge)` entries, for halfedge ids below `capacity`.
    fn new(entries: Vec<(f64, u32)>, capacity: usize) -> Self {
        let mut place = vec![Self::ABSENT; capacity];
        for (i, &(_, h)) in entries.iter().enumerate() {
            // `entries` holds at most one entry per halfedge id, each below `u32::MAX`.
            place[h as usize] = i as u32;
        }
        let mut heap = Self { entries, place };
        // Floyd's heap construction, O(n); the order of the entries taken out is the
        // strict `(key, halfedge)` order whatever the layout.
        for i in (0..heap.entries.len() / 2).rev() {
            heap.down(i);
        }
        heap
    }

    fn order(a: (f64, u32), b: (f64, u32)) -> Ordering {
        a.0.total_cmp(&b.0).then(a.1.cmp(&b.1))
    }

    fn less(&self, i: usize, j: usize) -> bool {
        Self::order(self.entries[i], self.entries[j]) == Ordering::Less
    }

    fn swap(&mut self, i: usize, j: usize) {
        self.entries.swap(i, j);
        self.place[self.entries[i].1 as usize] = i as u32;
        self.place[self.entries[j].1 as usize] = j as u32;
    }

    /// Moves the entry at `i` towards the root to its place; each entry it passes moves
    /// down one level (one write of each place, not a swap per level).
    fn up(&mut self, mut i: usize) {
        let moving = self.entries[i];
        while i > 0 {
            let parent = (i - 1) / 2;
            let above = self.entries[parent];
            if Self::order(moving, above) != Ordering::Less {
                break;
            }
            self.entries[i] = above;
            self.place[above.1 as usize] = i as u32;
            i = parent;
        }
        self.entries[i] = moving;
        self.place[moving.1 as usize] = i as u32;
    }

    /// Moves the entry at `i` towards the leaves to its place (as [`Heap::up`]).
    fn down(&mut self, mut i: usize) {
        let n = self.entries.len();
        let moving = self.entries[i];
        loop {
            let l = 2 * i + 1;
            if l >= n {
                break;
            }
            let r = l + 1;
            let c = if r < n && self.less(r, l) { r } else { l };
            let child = self.entries[c];
            if Self::order(child, moving) != Ordering::Less {
                break;
            }
            self.entries[i] = child;
            self.place[child.1 as usize] = i as u32;
            i = c;
        }
        self.entries[i] = moving;
        self.place[moving.1 as usize] = i as u32;
    }

    /// Queues `h` with `key`, or changes its key.
    fn set(&mut self, h: u32, key: f64) {
        let at = self.place[h as usize];
        if at == Self::ABSENT {
            self.entries.push((key, h));
            let i = self.entries.len() - 1;
            self.place[h as usize] = i as u32;
            self.up(i);
        } else {
            let i = at as usize;
            self.entries[i].0 = key;
            self.up(i);
            self.down(self.place[h as usize] as usize);
        }
    }

    /// Removes `h` if it is queued.
    fn remove(&mut self, h: u32) {
        let at = self.place[h as usize];
        if at == Self::ABSENT {
            return;
        }
        let i = at as usize;
        let last = self.entries.len() - 1;
        self.swap(i, last);
        self.entries.pop();
        self.place[h as usize] = Self::ABSENT;
        if i < last {
            self.up(i);
            self.down(i);
        }
    }

    /// Whether `h` is queued.
    fn contains(&self, h: u32) -> bool {
        self.place[h as usize] != Self::ABSENT
    }

    /// The smallest entry, without removing it.
    fn peek(&self) -> Option<(f64, u32)> {
        self.entries.first().copied()
    }
}

/// The raw normal `(b − a) × (c − a)` (twice the area).
fn cross(t: [DVec3; 3]) -> DVec3 {
    (t[1] - t[0]).cross(t[2] - t[0])
}

/// `ℓ²_max √3 / (4A)`: 1 for an equilateral triangle, infinite for a degenerate one.
fn aspect_ratio(t: [DVec3; 3]) -> f64 {
    let l2 = (t[1] - t[0])
        .length_squared()
        .max((t[2] - t[1]).length_squared())
        .max((t[0] - t[2]).length_squared());
    let twice_area = cross(t).length();
    if twice_area > 0.0 {
        l2 * 3f64.sqrt() / (2.0 * twice_area)
    } else {
        f64::INFINITY
    }
}

/// The square of `4A / (√3 ℓ²_max)`, the inverse of [`aspect_ratio`]: 1 for an
/// equilateral triangle, 0 for a degenerate one. (Squared to save a square root per
/// triangle; the caller takes one of the worst.)
fn shape_quality_squared(t: [DVec3; 3]) -> f64 {
    let l2 = (t[1] - t[0])
        .length_squared()
        .max((t[2] - t[1]).length_squared())
        .max((t[0] - t[2]).length_squared());
    if l2 > 0.0 {
        4.0 * cross(t).length_squared() / (3.0 * l2 * l2)
    } else {
        0.0
    }
}

struct Decimator<'a> {
    mesh: EditMesh,
    options: &'a DecimateOptions,
    input: &'a [DVec3],
    quadrics: Vec<Quadric>,
    /// The unit normal of every face when the decimation started (zero if degenerate).
    input_normals: Vec<DVec3>,
    cones: Vec<NormalCone>,
    points: Vec<Vec<u32>>,
    /// Per halfedge: refused when last looked at, to be queued again when its
    /// neighbourhood changes.
    parked: Vec<bool>,
    heap: Heap,
    /// Per halfedge: the collapse count when its full key was computed, or
    /// [`NOT_KEYED`] when its heap key is the lower bound.
    keyed_at: Vec<u32>,
    /// Per vertex: the collapse count when its one-ring last changed.
    changed_at: Vec<u32>,
    /// Collapses done so far.
    collapses: u32,
    /// Scratch: the outgoing halfedges of the kept vertex of a collapse.
    spokes: Vec<HalfedgeId>,
    /// Scratch: the neighbours of the removed vertex of a collapse.
    support: Vec<VertexId>,
    refused: RefusalCounts,
    /// The smallest quadric error the shape penalty divides (see
    /// [`DecimateOptions::quality_threshold`]): `10⁻¹² ℓ̄⁴` for the mean input edge
    /// length `ℓ̄`, so that flat regions are still ordered by shape.
    error_floor: f64,
}

impl<'a> Decimator<'a> {
    fn new(mesh: EditMesh, options: &'a DecimateOptions, input: &'a [DVec3]) -> Self {
        let nv = mesh.vertex_capacity();
        let nf = mesh.face_capacity();
        let nh = 2 * mesh.edge_capacity();
        let mut d = Self {
            mesh,
            options,
            input,
            quadrics: vec![Quadric::default(); nv],
            input_normals: vec![DVec3::ZERO; nf],
            cones: Vec::new(),
            points: Vec::new(),
            parked: vec![false; nh],
            heap: Heap::new(Vec::new(), nh),
            keyed_at: vec![NOT_KEYED; nh],
            changed_at: vec![0; nv],
            collapses: 0,
            spokes: Vec::new(),
            support: Vec::new(),
            refused: RefusalCounts::default(),
            error_floor: 0.0,
        };
        let faces: Vec<FaceId> = d.mesh.faces().collect();
        for &f in &faces {
            let vs = d.face_vertices(f);
            let n = cross(vs.map(|v| d.mesh.position(v)));
            let twice = n.length();
            d.input_normals[f.index()] = n.try_normalize().unwrap_or(DVec3::ZERO);
            // OpenMesh: a triangle of (almost) no area adds (almost) nothing.
            if twice > f64::from(f32::MIN_POSITIVE) {
                let n = n / twice;
                let q = Quadric::plane(n, -n.dot(d.mesh.position(vs[0])), 0.5 * twice);
                for v in vs {
                    d.quadrics[v.index()].add(&q);
                }
            }
        }
        let (mut sum, mut count) = (0.0, 0usize);
        for e in d.mesh.edges() {
            let [a, b] = d.mesh.edge_vertices(e);
            sum += (d.mesh.position(b) - d.mesh.position(a)).length();
            count += 1;
        }
        if count > 0 {
            let mean = sum / count as f64;
            d.error_floor = 1e-12 * mean.powi(4);
        }
        if !options.keep_boundary {
            let boundary: Vec<HalfedgeId> = d
                .mesh
                .halfedges()
                .filter(|&h| d.mesh.is_boundary_halfedge(h))
                .collect();
            for h in boundary {
                let (a, b) = (d.mesh.from_vertex(h), d.mesh.to_vertex(h));
                let Some(f) = d.mesh.face(h.twin()) else {
                    continue;
                };
                let normal = cross(d.face_vertices(f).map(|v| d.mesh.position(v)));
                let e = d.mesh.position(b) - d.mesh.position(a);
                if let Some(m) = e.cross(normal).try_normalize() {
                    let q = Quadric::plane(
                        m,
                        -m.dot(d.mesh.position(a)),
                        BOUNDARY_WEIGHT * e.length_squared(),
                    );
                    d.quadrics[a.index()].add(&q);
                    d.quadrics[b.index()].add(&q);
                }
            }
        }
        if options.max_normal_deviation.is_some() {
            d.cones = vec![NormalCone::new(DVec3::Z); nf];
            for &f in &faces {
                let n = cross(d.face_vertices(f).map(|v| d.mesh.position(v)));
                d.cones[f.index()] = NormalCone::new(n.try_normalize().unwrap_or(DVec3::Z));
            }
        }
        if options.max_distance.is_some() {
            d.points = vec![Vec::new(); nf];
            let vertices: Vec<VertexId> = d.mesh.vertices().collect();
            for v in vertices {
                if let Some(f) = d.mesh.faces_around_vertex(v).min() {
                    d.points[f.index()].push(v.raw());
                }
            }
        }
        d
    }

    fn face_vertices(&self, f: FaceId) -> [VertexId; 3] {
        let h = self.mesh.face_halfedge(f);
        let a = self.mesh.to_vertex(h);
        let h = self.mesh.next(h);
        let b = self.mesh.to_vertex(h);
        let c = self.mesh.to_vertex(self.mesh.next(h));
        [a, b, c]
    }

    /// The topological checks of OpenMesh's `is_collapse_legal`, and `keep_boundary`;
    /// `EditMesh`'s collapse rules (the link condition) are checked by the collapse
    /// itself.
    fn check_topology(&self, h: HalfedgeId) -> Result<(), Refusal> {
        let m = &self.mesh;
        if !m.is_live_halfedge(h) {
            return Err(Refusal::Topology);
        }
        let (v0, v1) = (m.from_vertex(h), m.to_vertex(h));
        let b0 = m.is_boundary_vertex(v0);
        if b0 && self.options.keep_boundary {
            return Err(Refusal::Boundary);
        }
        let (vl, vr) = (m.opposite_vertex(h), m.opposite_vertex(h.twin()));
        if b0 && (!m.is_boundary_vertex(v1) || (vl.is_some() && vr.is_some())) {
            return Err(Refusal::Topology);
        }
        if m.cw_rotated(m.cw_rotated(h)) == h {
            return Err(Refusal::Topology);
        }
        if let (Some(l), Some(r)) = (vl, vr)
            && m.valence(l) == 3
            && m.valence(r) == 3
            && m.find_halfedge(l, r).is_some()
        {
            return Err(Refusal::Topology);
        }
        Ok(())
    }

    /// The kept vertex's position for the collapse of `h` and the summed quadric.
    fn placement(&self, h: HalfedgeId) -> (DVec3, Quadric) {
        let m = &self.mesh;
        let (v0, v1) = (m.from_vertex(h), m.to_vertex(h));
        let (p0, p1) = (m.position(v0), m.position(v1));
        let q = self.quadrics[v0.index()].sum(&self.quadrics[v1.index()]);
        let position = match self.options.placement {
            Placement::Optimal if !m.is_boundary_vertex(v1) => q
                .minimiser()
                .filter(|x| (*x - 0.5 * (p0 + p1)).length() <= 2.0 * (p1 - p0).length())
                .unwrap_or_else(|| if q.eval(p0) < q.eval(p1) { p0 } else { p1 }),
            _ => p1,
        };
        (position, q)
    }

    /// The triangles the collapse of `h` changes, as `(face, new corners, old corners)`
    /// in the face's order: those around
    /// `v0` and, when the kept vertex moves, those around `v1`, without the (one or two)
    /// triangles at the edge, which are removed.
    fn changed_triangles(
        &self,
        h: HalfedgeId,
        position: DVec3,
        mut visit: impl FnMut(FaceId, [DVec3; 3], [DVec3; 3]) -> bool,
    ) -> bool {
        let m = &self.mesh;
        let (v0, v1) = (m.from_vertex(h), m.to_vertex(h));
        let removed = [m.face(h), m.face(h.twin())];
        let moved = position != m.position(v1);
        let centres: &[VertexId] = if moved { &[v0, v1] } else { &[v0] };
        for &c in centres {
            for g in m.halfedges_around_vertex(c) {
                let Some(f) = m.face(g) else {
                    continue;
                };
                if removed.contains(&Some(f)) {
                    continue;
                }
                let n = m.next(g);
                let (a, b) = (m.to_vertex(g), m.to_vertex(n));
                let at = |v: VertexId| {
                    if v == v0 || v == v1 {
                        position
                    } else {
                        m.position(v)
                    }
                };
                let before = [m.position(c), m.position(a), m.position(b)];
                if !visit(f, [position, at(a), at(b)], before) {
                    return false;
                }
            }
        }
        true
    }

    /// A lower bound of the heap key of collapsing `h` ([`Decimator::full_key`]): its
    /// quadric error (at least the error floor when the shape penalty is on), whether
    /// the twin's is bit for bit the same (both move the kept vertex to the same
    /// minimiser, neither end point is on the boundary, and they change the same
    /// triangles), and the kept vertex's position. Refuses what depends only on the two
    /// vertices' quadrics and positions (`keep_boundary`, `max_error`).
    ///
    /// The bound needs the two quadrics alone, so it is what a changed neighbourhood
    /// queues; the shape penalty, which needs every triangle the collapse makes, is
    /// evaluated when the entry reaches the top of the heap.
    fn bound(&self, h: HalfedgeId) -> Result<(f64, bool, DVec3), Refusal> {
        let m = &self.mesh;
        let (v0, v1) = (m.from_vertex(h), m.to_vertex(h));
        let b0 = m.is_boundary_vertex(v0);
        if self.options.keep_boundary && b0 {
            return Err(Refusal::Boundary);
        }
        let (position, q) = self.placement(h);
        if self.options.max_error.is_some_and(|e| q.rms(position) > e) {
            return Err(Refusal::Error);
        }
        let symmetric = self.options.placement == Placement::Optimal
            && position != m.position(v0)
            && position != m.position(v1)
            && !b0
            && !m.is_boundary_vertex(v1);
        let error = q.eval(position);
        let key = if self.options.quality_threshold > 0.0 {
            error.max(self.error_floor)
        } else {
            error
        };
        Ok((key, symmetric, position))
    }

    /// The heap key of collapsing `h` to `position`, given its [`Decimator::bound`]: the
    /// bound divided by the shape penalty when the worst new triangle's quality is
    /// below the threshold (never smaller than the bound). Refuses a collapse that
    /// makes a degenerate triangle.
    fn full_key(&self, h: HalfedgeId, bound: f64, position: DVec3) -> Result<f64, Refusal> {
        let threshold = self.options.quality_threshold;
        if threshold <= 0.0 {
            return Ok(bound);
        }
        let mut worst = f64::INFINITY;
        self.changed_triangles(h, position, |_, t, _| {
            worst = worst.min(shape_quality_squared(t));
            worst > 0.0
        });
        if worst <= 0.0 {
            return Err(Refusal::Flip);
        }
        Ok(bound / (worst.sqrt() / threshold).min(1.0))
    }

    /// Whether the full key of `h` computed last is still its key: no collapse has
    /// changed the one-ring of either end since.
    fn fresh(&self, h: HalfedgeId) -> bool {
        let at = self.keyed_at[h.index()];
        at != NOT_KEYED
            && self.changed_at[self.mesh.from_vertex(h).index()] <= at
            && self.changed_at[self.mesh.to_vertex(h).index()] <= at
    }

    /// Everything [`decimate`] checks for the collapse of `h`, and what it would change.
    ///
    /// `placed` is the kept vertex's position when the caller has just computed it
    /// ([`Decimator::bound`]).
    fn evaluate(&self, h: HalfedgeId, placed: Option<DVec3>) -> Result<Candidate, Refusal> {
        self.check_topology(h)?;
        let m = &self.mesh;
        let (v0, v1) = (m.from_vertex(h), m.to_vertex(h));
        let (position, q) = match placed {
            Some(p) => (p, self.quadrics[v0.index()].sum(&self.quadrics[v1.index()])),
            None => self.placement(h),
        };
        let rms = q.rms(position);
        if self.options.max_error.is_some_and(|e| rms > e) {
            return Err(Refusal::Error);
        }
        let removed = [m.face(h), m.face(h.twin())];
        let is_removed = |f: FaceId| removed.contains(&Some(f));
        // The changed faces and their new normals, for the bounds that need them.
        let keep_changed =
            self.options.max_normal_deviation.is_some() || self.options.max_aspect_ratio.is_some();
        let mut changed: Vec<(FaceId, DVec3)> = Vec::new();
        let mut flipped = false;
        self.changed_triangles(h, position, |f, t, before| {
            let old = cross(before);
            let Some(new) = cross(t).try_normalize() else {
                flipped = true;
                return false;
            };
            let input = self.input_normals[f.index()];
            if (old.dot(new) <= 0.0 && old != DVec3::ZERO)
                || (input.dot(new) <= 0.0 && input != DVec3::ZERO)
            {
                flipped = true;
                return false;
            }
            if keep_changed {
                changed.push((f, new));
            }
            true
        });
        if flipped {
            return Err(Refusal::Flip);
        }
        let new_triangle = |f: FaceId| {
            self.face_vertices(f).map(|v| {
                if v == v0 || v == v1 {
                    position
                } else {
                    m.position(v)
                }
            })
        };
        let mut cones = Vec::new();
        if let Some(max) = self.options.max_normal_deviation {
            // The face across `vl–v0` takes the place of the removed face `fl`, the
            // face across `v0–vr` that of `fr` (pmp-library): they inherit its cone.
            let heirs = [
                removed[0].and(m.face(m.prev(h).twin())),
                removed[1].and(m.face(m.next(h.twin()).twin())),
            ];
            for &(f, n) in &changed {
                let mut cone = self.cones[f.index()].merge(NormalCone::new(n));
                for (heir, r) in heirs.into_iter().zip(removed) {
                    if let (Some(heir), Some(r)) = (heir, r)
                        && heir == f
                    {
                        cone = cone.merge(self.cones[r.index()]);
                    }
                }
                if cone.angle > 0.5 * max {
                    return Err(Refusal::NormalDeviation);
                }
                cones.push((f, cone));
            }
        }
        if let Some(max) = self.options.max_aspect_ratio {
            let old_triangle = |f: FaceId| self.face_vertices(f).map(|v| m.position(v));
            let worst_new = changed
                .iter()
                .map(|&(f, _)| aspect_ratio(new_triangle(f)))
                .fold(0.0f64, f64::max);
            let worst_old = changed
                .iter()
                .map(|&(f, _)| f)
                .chain(removed.into_iter().flatten())
                .map(|f| aspect_ratio(old_triangle(f)))
                .fold(0.0f64, f64::max);
            if worst_new > max && worst_new > worst_old {
                return Err(Refusal::AspectRatio);
            }
        }
        let (mut cleared, mut assigned) = (Vec::new(), Vec::new());
        if let Some(max) = self.options.max_distance {
            cleared = m
                .faces_around_vertex(v0)
                .chain(m.faces_around_vertex(v1))
                .collect();
            cleared.sort_unstable();
            cleared.dedup();
            let targets: Vec<(FaceId, [DVec3; 3])> = cleared
                .iter()
                .filter(|&&f| !is_removed(f))
                .map(|&f| (f, new_triangle(f)))
                .collect();
            let mut lists: Vec<Vec<u32>> = vec![Vec::new(); targets.len()];
            for &f in &cleared {
                for &v in &self.points[f.index()] {
                    let p = self.input[v as usize];
                    let mut best: Option<(f64, usize)> = None;
                    for (i, (_, t)) in targets.iter().enumerate() {
                        let d = closest_point_on_triangle(p, *t).distance_squared;
                        if best.is_none_or(|(bd, _)| d < bd) {
                            best = Some((d, i));
                        }
                    }
                    match best {
                        Some((d, i)) if d <= max * max => lists[i].push(v),
                        _ => return Err(Refusal::Distance),
                    }
                }
            }
            assigned = targets.iter().map(|(f, _)| *f).zip(lists).collect();
        }
        Ok(Candidate {
            rms,
            position,
            cones,
            cleared,
            assigned,
        })
    }

    /// Queues the collapse of `h` with its current priority, or parks it (removed from
    /// the heap) and counts the refusal.
    fn queue(&mut self, h: HalfedgeId) {
        if !self.mesh.is_live_halfedge(h) {
            self.parked[h.index()] = false;
            self.heap.remove(h.raw());
            return;
        }
        let bound = self.bound(h).map(|(key, _, _)| key);
        self.queue_with(h, bound);
    }

    /// Queues the live halfedge `h` with its [`Decimator::bound`] `bound`, or parks it.
    fn queue_with(&mut self, h: HalfedgeId, bound: Result<f64, Refusal>) {
        let i = h.index();
        self.parked[i] = false;
        self.keyed_at[i] = NOT_KEYED;
        match bound {
            Ok(key) => self.heap.set(h.raw(), key),
            Err(r) => {
                self.heap.remove(h.raw());
                self.refuse(h, r);
            }
        }
    }

    /// Queues both halfedges of `h`'s edge ([`Decimator::queue`]), as one entry when
    /// their priorities are the same.
    fn queue_edge(&mut self, h: HalfedgeId) {
        if !self.mesh.is_live_halfedge(h) {
            self.queue(h);
            self.queue(h.twin());
            return;
        }
        match self.bound(h) {
            Ok((key, true, _)) => {
                // One entry for the edge, under its even halfedge; both directions are
                // tried when it comes to the top.
                let (even, odd) = if h.index() % 2 == 0 {
                    (h, h.twin())
                } else {
                    (h.twin(), h)
                };
                self.parked[even.index()] = false;
                self.parked[odd.index()] = false;
                self.keyed_at[even.index()] = NOT_KEYED;
                self.keyed_at[odd.index()] = NOT_KEYED;
                self.heap.set(even.raw(), key);
                self.heap.remove(odd.raw());
            }
            bound => {
                self.queue_with(h, bound.map(|(key, _, _)| key));
                self.queue(h.twin());
            }
        }
    }

    /// Counts the refusal of `h` and parks it until its neighbourhood changes. The
    /// boundary and error refusals change only with the two vertices' quadrics and
    /// positions, and a change of those queues the halfedge again anyway.
    fn refuse(&mut self, h: HalfedgeId, r: Refusal) {
        self.refused.count(r);
        self.parked[h.index()] = !matches!(r, Refusal::Boundary | Refusal::Error);
    }

    /// Collapses until `target` vertices are left or the heap is empty; returns the
    /// largest RMS error of a collapse done.
    ///
    /// The heap holds halfedges keyed by a lower bound of their priority
    /// ([`Decimator::bound`]); the full key with the shape penalty
    /// ([`Decimator::full_key`]) and legality are evaluated when one comes to the top
    /// (lazily, as most queued collapses are never done). A full key larger than the
    /// entry's goes back into the heap; since every other entry's key is at most its
    /// own full key, the entry collapsed is the one of the smallest full key among those
    /// whose key is up to date. A full key stays valid until a collapse changes the
    /// one-ring of either end. A refused halfedge is parked until a collapse changes
    /// its neighbourhood.
    fn run(&mut self, target: usize) -> Result<f64, DecimateError> {
        let halfedges: Vec<HalfedgeId> = self.mesh.halfedges().collect();
        let mut entries = Vec::with_capacity(halfedges.len());
        let mut skip_twin = false;
        for h in halfedges {
            // The halfedges come in pairs, `2e` then `2e + 1`: a symmetric pair is one
            // entry, under the even one.
            if std::mem::take(&mut skip_twin) {
                continue;
            }
            match self.bound(h) {
                Ok((key, symmetric, _)) => {
                    entries.push((key, h.raw()));
                    skip_twin = symmetric && h.index() % 2 == 0;
                }
                Err(r) => self.refuse(h, r),
            }
        }
        self.heap = Heap::new(entries, self.parked.len());
        let optimal = self.options.placement == Placement::Optimal;
        let recheck = self.options.quality_threshold > 0.0;
        let mut max_rms: f64 = 0.0;
        while self.mesh.n_vertices() > target {
            let Some((key, raw)) = self.heap.peek() else {
                break;
            };
            let h = HalfedgeId::new(raw);
            if !self.mesh.is_live_halfedge(h) {
                self.heap.remove(raw);
                continue;
            }
            let mut directions = [Some(h), None];
            let mut placed = None;
            if optimal || recheck {
                let current = self.bound(h).and_then(|(bound, symmetric, position)| {
                    if recheck && !self.fresh(h) {
                        let full = self.full_key(h, bound, position)?;
                        Ok((Some(full), symmetric, position))
                    } else {
                        Ok((None, symmetric, position))
                    }
                });
                if let Ok((Some(_), _, _)) = current {
                    self.keyed_at[h.index()] = self.collapses;
                }
                match current {
                    Ok((Some(full), _, _)) if full > key => {
                        // The entry's key was a lower bound, or the neighbourhood has
                        // changed since: it goes back with its full key.
                        self.heap.set(raw, full);
                        continue;
                    }
                    Ok((_, symmetric, position)) => {
                        placed = Some(position);
                        if symmetric && h.index() % 2 == 0 {
                            directions[1] = Some(h.twin());
                        } else if h.index() % 2 == 0 && !self.heap.contains(h.twin().raw()) {
                            // The edge's entry stood for both directions; no longer.
                            self.queue(h.twin());
                        }
                    }
                    Err(r) => {
                        self.heap.remove(raw);
                        self.refuse(h, r);
                        continue;
                    }
                }
            }
            self.heap.remove(raw);
            // The first direction the checks allow is collapsed; `EditMesh`'s own
            // topological checks (the link condition) run once, in the collapse, which
            // leaves the mesh unchanged when it refuses.
            let mut chosen = None;
            for g in directions.into_iter().flatten() {
                let candidate = match self.evaluate(g, placed) {
                    Ok(c) => c,
                    Err(r) => {
                        self.refuse(g, r);
                        continue;
                    }
                };
                let v0 = self.mesh.from_vertex(g);
                if !optimal {
                    self.support.clear();
                    self.support.extend(self.mesh.vertices_around_vertex(v0));
                }
                // The edge and one other edge of each triangle at it are removed; their
                // entries leave the heap now (a removal deep in the heap is cheap, one
                // that surfaces at the top later costs a full sift).
                let doomed = [
                    g,
                    self.mesh.next(g),
                    self.mesh.prev(g),
                    self.mesh.next(g.twin()),
                    self.mesh.prev(g.twin()),
                ];
                match self.mesh.collapse_edge(g) {
                    Ok(v1) => {
                        chosen = Some((v0, v1, candidate, doomed));
                        break;
                    }
                    Err(_) => self.refuse(g, Refusal::Topology),
                }
            }
            let Some((v0, v1, candidate, doomed)) = chosen else {
                continue;
            };
            for g in doomed {
                if !self.mesh.is_live_halfedge(g) {
                    self.heap.remove(g.raw());
                    self.heap.remove(g.twin().raw());
                }
            }
            self.mesh.set_position(v1, candidate.position);
            self.collapses += 1;
            // The one-rings of `v1` and its neighbours changed: their full keys are out
            // of date.
            self.spokes.clear();
            self.spokes.extend(self.mesh.halfedges_around_vertex(v1));
            self.changed_at[v1.index()] = self.collapses;
            for k in 0..self.spokes.len() {
                let u = self.mesh.to_vertex(self.spokes[k]);
                self.changed_at[u.index()] = self.collapses;
            }
            let q0 = self.quadrics[v0.index()];
            self.quadrics[v1.index()].add(&q0);
            for (f, cone) in candidate.cones {
                self.cones[f.index()] = cone;
            }
            for f in candidate.cleared {
                self.points[f.index()].clear();
            }
            for (f, list) in candidate.assigned {
                self.points[f.index()] = list;
            }
            max_rms = max_rms.max(candidate.rms);
            if !optimal {
                // `DecimaterT`'s update: the outgoing collapses of `v0`'s former
                // neighbours (`v1` among them) are evaluated again; those of `v1`'s other
                // neighbours keep their keys until their own neighbourhood changes.
                for k in 0..self.support.len() {
                    let u = self.support[k];
                    self.spokes.clear();
                    self.spokes.extend(self.mesh.halfedges_around_vertex(u));
                    for j in 0..self.spokes.len() {
                        self.queue(self.spokes[j]);
                    }
                }
                continue;
            }
            for k in 0..self.spokes.len() {
                let g = self.spokes[k];
                self.queue_edge(g);
            }
            for k in 0..self.spokes.len() {
                let u = self.mesh.to_vertex(self.spokes[k]);
                let start = self.mesh.outgoing_halfedge(u);
                let mut g = start;
                while let Some(e) = g {
                    if self.parked[e.index()] || self.parked[e.twin().index()] {
                        self.queue_edge(e);
                    }
                    let next = self.mesh.cw_rotated(e);
                    g = (Some(next) != start).then_some(next);
                }
            }
        }
        Ok(max_rms)
    }
}

/// Decimates a triangle mesh by quadric error metrics: halfedge collapses, cheapest
/// first, until `options.target` vertices are left or no collapse is left that the
/// topology and the constraints allow. Returns the new mesh, its positions and a report.
///
/// The output's vertices keep the input's relative order (garbage collection is a
/// stable compaction); with [`Placement::Endpoint`] each is an input vertex, bit for
/// bit. Topology is preserved: the Euler characteristic, the number of boundary loops
/// and closedness do not change, and the output is a valid [`HalfedgeMesh`]. Unless
/// [`DecimateOptions::measure_distance`] is off, the report's Hausdorff distance is
/// measured between the output and the input over their vertices plus one surface
/// sample per input face on each side, with a fixed seed
/// ([`DecimateReport::measure_distance`]).
///
/// # Errors
/// [`DecimateError::PositionCount`] when `positions` does not match the mesh;
/// [`DecimateError::NotTriangle`] when a face is not a triangle;
/// [`DecimateError::NoFaces`] for a mesh without faces;
/// [`DecimateError::NonFinite`] for a non-finite position;
/// [`DecimateError::Options`] for an option out of its range (see
/// [`DecimateOptions`]).
///
/// # Complexity
/// O(n log n) collapses and heap operations for `n` vertices; a queued cost is O(1), the
/// shape penalty at the top of the heap O(valence), a legality check O(valence²);
/// [`DecimateOptions::max_distance`] adds the input vertices of the changed triangles
/// times their number per evaluation.
///
/// # Examples
/// ```
/// use beltrami_algorithms::{decimate, DecimateOptions};
/// use beltrami_halfedge::primitives;
///
/// let sphere = primitives::icosphere(3); // 642 vertices
/// let mesh = sphere.mesh()?;
/// let (coarse, positions, report) =
///     decimate(&mesh, &sphere.positions, &DecimateOptions::default().vertices(200))?;
/// assert_eq!(coarse.n_vertices(), 200);
/// assert_eq!(positions.len(), 200);
/// assert!(report.target_reached);
/// assert_eq!(coarse.euler_characteristic(), 2);
/// assert!(report.hausdorff < 0.05); // a unit sphere
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn decimate(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    options: &DecimateOptions,
) -> Result<(HalfedgeMesh, Vec<DVec3>, DecimateReport), DecimateError> {
    check_mesh(mesh, positions)?;
    if mesh.n_faces() == 0 {
        return Err(DecimateError::NoFaces);
    }
    check_finite(positions)?;
    options.validate()?;
    let target = options.target_count(mesh.n_vertices());
    let edit = EditMesh::from_mesh(mesh, positions)?;
    let mut decimator = Decimator::new(edit, options, positions);
    let max_rms = decimator.run(target)?;
    let refused = decimator.refused;
    let mut edit = decimator.mesh;
    let stop = if edit.n_vertices() <= target {
        DecimateStop::TargetReached
    } else {
        DecimateStop::NoCollapseLeft
    };
    edit.garbage_collection();
    let (out, out_positions) = edit.into_mesh()?;
    let mut report = DecimateReport {
        vertices_before: mesh.n_vertices(),
        faces_before: mesh.n_faces(),
        vertices_after: out.n_vertices(),
        faces_after: out.n_faces(),
        target_vertices: target,
        collapses: mesh.n_vertices() - out.n_vertices(),
        refused,
        stop,
        target_reached: stop == DecimateStop::TargetReached,
        max_quadric_error: max_rms,
        ..DecimateReport::default()
    };
    if options.measure_distance {
        report.measure_distance((mesh, positions), (&out, &out_positions))?;
    }
    Ok((out, out_positions, report))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator for the tests (64-bit LCG, top bits).
    struct Lcg(u64);

    impl Lcg {
        fn next(&mut self) -> u64 {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            self.0 >> 33
        }

        fn unit(&mut self) -> f64 {
            self.next() as f64 / (1u64 << 31) as f64
        }
    }

    #[test]
    fn the_heap_gives_the_entries_in_key_then_id_order() {
        let mut rng = Lcg(7);
        let n = 500u32;
        // Few distinct keys, so that ties (broken by the id) are common.
        let mut initial: Vec<(f64, u32)> = Vec::new();
        for h in 0..n {
            if rng.next() % 3 != 0 {
                initial.push(((rng.next() % 20) as f64, h));
            }
        }
        let mut want: std::collections::BTreeMap<u32, f64> =
            initial.iter().map(|&(k, h)| (h, k)).collect();
        let mut heap = Heap::new(initial, n as usize);
        for _ in 0..2000 {
            let h = (rng.next() % u64::from(n)) as u32;
            if rng.next() % 4 == 0 {
                heap.remove(h);
                want.remove(&h);
            } else {
                let key = (rng.next() % 20) as f64 + 0.5 * rng.unit();
                heap.set(h, key);
                want.insert(h, key);
            }
            assert_eq!(heap.contains(h), want.contains_key(&h));
        }
        let mut expected: Vec<(f64, u32)> = want.into_iter().map(|(h, k)| (k, h)).collect();
        expected.sort_by(|a, b| Heap::order(*a, *b));
        let mut got = Vec::new();
        while let Some((key, h)) = heap.peek() {
            heap.remove(h);
            got.push((key, h));
        }
        assert_eq!(got, expected);
    }

    #[test]
    fn the_minimiser_solves_the_quadric_system() {
        let mut rng = Lcg(11);
        for _ in 0..200 {
            // A sum of a few planes through random points, as a vertex's quadric is.
            let mut q = Quadric::default();
            for _ in 0..4 {
                let n =
                    DVec3::new(rng.unit() - 0.5, rng.unit() - 0.5, rng.unit() - 0.5).normalize();
                let p = DVec3::new(rng.unit(), rng.unit(), rng.unit());
                q.add(&Quadric::plane(n, -n.dot(p), 0.1 + rng.unit()));
            }
            let Some(x) = q.minimiser() else {
                continue;
            };
            // The gradient 2(Ax + b) vanishes at the minimiser ...
            let residual = q.matrix() * x + q.b;
            assert!(
                residual.length() <= 1e-9 * (1.0 + q.b.length()),
                "{residual}"
            );
            // ... and the minimum is no larger than nearby values.
            for d in [DVec3::X, DVec3::Y, DVec3::Z] {
                assert!(q.eval(x) <= q.eval(x + 1e-3 * d) + 1e-12);
                assert!(q.eval(x) <= q.eval(x - 1e-3 * d) + 1e-12);
            }
        }
        // A single plane leaves the system singular: no minimiser.
        assert!(Quadric::plane(DVec3::Z, 0.0, 1.0).minimiser().is_none());
    }
}
