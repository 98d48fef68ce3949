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
//!    deterministic function of the input. The initial costs are computed on rayon's
//!    threads and taken in id order: the result does not depend on the thread count.
//!    When more than two entries per collapse go back into the heap over 4 096
//!    collapses (once a generation of collapses has used up the edges whose collapse
//!    leaves well-shaped triangles, on the level-8 sphere 2.5 per collapse), the bound
//!    of every queued entry is replaced by its full key at once, on rayon's threads in
//!    halfedge order, and the heap is built again (at most once per 32 768 collapses;
//!    [`DecimateReport::keyings`] counts them).
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

use std::ops::ControlFlow;

use std::f64::consts::PI;

use beltrami_halfedge::{DVec3, EditError, EditMesh, HalfedgeMesh, TopologyError};
use beltrami_metrics::MetricsError;
use beltrami_metrics::distance::{HausdorffSampling, SurfaceIndex, hausdorff};

use crate::error::{algorithm_error, check_finite, check_mesh};
use crate::scale::{Scale, at_unit_size};

/// The weight of a boundary constraint plane per unit of squared edge length (the face
/// planes are weighted by area, the same unit).
const BOUNDARY_WEIGHT: f64 = 1.0;

/// `Decimator::keyed_at` of a halfedge whose heap key is a lower bound.
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
    /// vertices are a subset of the input's, bit for bit (on a mesh far from unit size,
    /// whose run is scaled there and back, but for coordinates more than 2^1000 times
    /// smaller than the largest, which come back rounded).
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
    /// Whether each input triangle's plane enters the vertex quadrics weighted by the
    /// triangle's area (`true`, the default: Garland and Heckbert's and OpenMesh's
    /// choice) or with weight 1 (`false`: MeshLib's choice, which counts a region by its
    /// triangles rather than by its area). Boundary constraint planes follow: weighted
    /// by the squared edge length, or 1.
    pub area_weighted: bool,
    /// The weight of a pull towards each input vertex's own position, `w |x − p_v|²`
    /// added to its quadric, relative to one face plane (≥ 0, finite; default 0). With
    /// [`DecimateOptions::area_weighted`] `w` is this times the mean triangle area, else
    /// this. A small value (MeshLib uses 0.001) makes the optimal placement well
    /// defined in flat and cylindrical regions — there it moves the kept vertex towards
    /// the middle of the vertices it replaces instead of falling back to an end
    /// point — and changes it elsewhere by about the weight's share. It is not counted
    /// in the weight of [`DecimateOptions::max_error`]'s mean.
    pub stabilizer: f64,
    /// After the collapses, edges are flipped towards valence 6 (4 on the boundary)
    /// where a flip moves the surface by at most this fraction of the largest quadric
    /// error of a collapse done ([`DecimateReport::max_quadric_error`]), turns no
    /// triangle over and leaves no triangle worse shaped than the worse of the two it
    /// replaces or than shape quality 0.4 (the default
    /// [`DecimateOptions::quality_threshold`]), whichever is worse (≥ 0, finite; default 0.2; 0:
    /// no flips). On the level-6 and level-8 spheres, the golf ball and a scan-like
    /// surface the default raises the share of valence-6 vertices by 4–6 points with the
    /// same Hausdorff distance and smallest angle and a slightly smaller area RMS; on a
    /// flat region (the block's sides) it flips only edges whose quad is flat. No flip
    /// is made when [`DecimateOptions::max_distance`] or
    /// [`DecimateOptions::max_normal_deviation`] is set, whose bookkeeping follows
    /// collapses only; [`DecimateOptions::max_aspect_ratio`] holds for the flipped
    /// triangles too.
    pub flip_tolerance: f64,
    /// Rounds of the final fit to the input (default 2; 0: no fit). After the collapses
    /// and flips, the vertices move — mostly along the surface normal — so that the
    /// output surface comes closer to the input's triangles: each round matches the
    /// input's face centroids to their closest output points and moves every interior
    /// vertex to lower the area-weighted squared distance of those points to the input
    /// faces' planes (Hoppe et al. 1993's distance energy, point to plane;
    /// `decimate/fit.rs`). A move is not made when it would turn a triangle over, go
    /// farther than half the vertex's shortest edge, or leave a triangle around the
    /// vertex below shape quality 0.3 (or below the inverse of
    /// [`DecimateOptions::max_aspect_ratio`], when that is higher) unless one there was
    /// already worse (then none may get worse). Boundary vertices stay. On the level-6 sphere, the scan-like sphere
    /// and the golf ball the sampled RMS distance between output and input falls by
    /// 37–44 % and the edge-length variation by 10–25 %; the vertices then lie off the
    /// input's triangles (inside the faces' error band), so distances measured at the
    /// vertices alone rise. Only with [`Placement::Optimal`] and without
    /// [`DecimateOptions::max_distance`] and [`DecimateOptions::max_normal_deviation`],
    /// whose bounds follow collapses only; otherwise no fit is made. Nor when nothing was
    /// collapsed: every vertex is then an input vertex. At most [`MAX_FIT_ROUNDS`].
    pub fit_rounds: usize,
}

/// The default of [`DecimateOptions::fit_rounds`].
pub const DEFAULT_FIT_ROUNDS: usize = 2;

/// The most rounds of the final fit a run takes ([`DecimateOptions::fit_rounds`]): each
/// round re-matches the input's samples, so the distance stops falling after a few
/// (golf ball: 2.93e-3, 2.82e-3, 2.79e-3 after 1, 2, 3 rounds; on a noisy sphere it rises
/// again slightly after 3), and a count far above this is a typing error that would run
/// for hours.
pub const MAX_FIT_ROUNDS: usize = 100;

/// The default of [`DecimateOptions::quality_threshold`].
const DEFAULT_QUALITY_THRESHOLD: f64 = 0.4;

/// A setting of [`DecimateOptions`] that keeps a step after the collapses off (see
/// [`DecimateOptions::fit_blocked_by`] and [`DecimateOptions::flips_blocked_by`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum BlockedBy {
    /// [`Placement::Endpoint`].
    EndpointPlacement,
    /// [`DecimateOptions::max_distance`].
    MaxDistance,
    /// [`DecimateOptions::max_normal_deviation`].
    MaxNormalDeviation,
}

/// The default of [`DecimateOptions::flip_tolerance`].
const DEFAULT_FLIP_TOLERANCE: f64 = 0.2;

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
            area_weighted: true,
            stabilizer: 0.0,
            flip_tolerance: DEFAULT_FLIP_TOLERANCE,
            fit_rounds: DEFAULT_FIT_ROUNDS,
        }
    }
}

impl DecimateOptions {
    /// OpenMesh's `DecimaterT` with `ModQuadricT` alone: [`Placement::Endpoint`], no
    /// shape penalty (`quality_threshold` 0), area-weighted planes, no stabilizer, no
    /// flips and no fit; the other settings are the defaults.
    #[must_use]
    pub fn openmesh() -> Self {
        Self {
            placement: Placement::Endpoint,
            quality_threshold: 0.0,
            area_weighted: true,
            stabilizer: 0.0,
            flip_tolerance: 0.0,
            fit_rounds: 0,
            ..Self::default()
        }
    }

    /// Sets the rounds of the final fit to the input (0: no fit; see
    /// [`DecimateOptions::fit_rounds`]).
    #[must_use]
    pub fn fit_rounds(mut self, rounds: usize) -> Self {
        self.fit_rounds = rounds;
        self
    }

    /// Whether the final fit runs: rounds asked for and nothing keeps it off
    /// ([`fit_blocked_by`](Self::fit_blocked_by)).
    fn fits(&self) -> bool {
        self.fit_rounds > 0 && self.fit_blocked_by().is_none()
    }

    /// Whether the valence flips run: a tolerance above 0 and nothing keeps them off
    /// ([`flips_blocked_by`](Self::flips_blocked_by)).
    fn flips(&self) -> bool {
        self.flip_tolerance > 0.0 && self.flips_blocked_by().is_none()
    }

    /// The setting that keeps the final fit to the input off, whatever
    /// [`fit_rounds`](Self::fit_rounds) says: the first of endpoint placement (the fit
    /// moves vertices off the input's, which endpoint placement keeps), a distance bound
    /// and a normal-deviation bound (both hold only for the collapses' own placements);
    /// `None` when the fit runs with rounds asked for. A front end that takes the rounds
    /// from its user can refuse them rather than drop them.
    ///
    /// # Examples
    /// ```
    /// use beltrami_algorithms::{BlockedBy, DecimateOptions, Placement};
    /// let options = DecimateOptions::default().ratio(0.5);
    /// assert_eq!(options.fit_blocked_by(), None);
    /// let endpoint = options.placement(Placement::Endpoint);
    /// assert_eq!(endpoint.fit_blocked_by(), Some(BlockedBy::EndpointPlacement));
    /// assert_eq!(endpoint.flips_blocked_by(), None);
    /// let bounded = options.max_distance(0.01);
    /// assert_eq!(bounded.flips_blocked_by(), Some(BlockedBy::MaxDistance));
    /// ```
    #[must_use]
    pub fn fit_blocked_by(&self) -> Option<BlockedBy> {
        if self.placement == Placement::Endpoint {
            Some(BlockedBy::EndpointPlacement)
        } else {
            self.flips_blocked_by()
        }
    }

    /// The setting that keeps the valence flips after the collapses off, whatever
    /// [`flip_tolerance`](Self::flip_tolerance) says: a distance bound or a
    /// normal-deviation bound (a flip could break either); `None` when the flips run
    /// with a tolerance above 0.
    #[must_use]
    pub fn flips_blocked_by(&self) -> Option<BlockedBy> {
        if self.max_distance.is_some() {
            Some(BlockedBy::MaxDistance)
        } else if self.max_normal_deviation.is_some() {
            Some(BlockedBy::MaxNormalDeviation)
        } else {
            None
        }
    }

    /// Sets how far, as a fraction of the largest collapse error, the valence flips
    /// after the collapses may move the surface (0: no flips; see
    /// [`DecimateOptions::flip_tolerance`]).
    #[must_use]
    pub fn flip_tolerance(mut self, fraction: f64) -> Self {
        self.flip_tolerance = fraction;
        self
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

    /// Weighs each face plane by its triangle's area (`true`, the default) or with 1
    /// (see [`DecimateOptions::area_weighted`]).
    #[must_use]
    pub fn area_weighted(mut self, area_weighted: bool) -> Self {
        self.area_weighted = area_weighted;
        self
    }

    /// Sets the weight of the pull towards each input vertex (see
    /// [`DecimateOptions::stabilizer`]).
    #[must_use]
    pub fn stabilizer(mut self, weight: f64) -> Self {
        self.stabilizer = weight;
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
                return bad(format!(
                    "the target ratio must be in (0, 1], got {}",
                    beltrami_halfedge::exact_number(r)
                ));
            }
            _ => {}
        }
        if let Some(e) = self.max_error
            && !(e >= 0.0 && e.is_finite())
        {
            return bad(format!(
                "the largest quadric error must be finite and >= 0, got {}",
                beltrami_halfedge::exact_number(e)
            ));
        }
        if let Some(a) = self.max_normal_deviation
            && !(0.0..=PI).contains(&a)
        {
            return bad(format!(
                "the largest normal deviation must be in [0, pi] radians, got {}",
                beltrami_halfedge::exact_number(a)
            ));
        }
        if let Some(a) = self.max_aspect_ratio
            && !(a >= 1.0 && a.is_finite())
        {
            return bad(format!(
                "the largest aspect ratio must be finite and >= 1, got {}",
                beltrami_halfedge::exact_number(a)
            ));
        }
        if let Some(d) = self.max_distance
            && !(d >= 0.0 && d.is_finite())
        {
            return bad(format!(
                "the largest distance must be finite and >= 0, got {}",
                beltrami_halfedge::exact_number(d)
            ));
        }
        let w = self.stabilizer;
        if !(w >= 0.0 && w.is_finite()) {
            return bad(format!(
                "the stabilizer must be finite and >= 0, got {}",
                beltrami_halfedge::exact_number(w)
            ));
        }
        let t = self.quality_threshold;
        if !(0.0..=1.0).contains(&t) {
            return bad(format!(
                "the quality threshold must be in [0, 1], got {}",
                beltrami_halfedge::exact_number(t)
            ));
        }
        let f = self.flip_tolerance;
        if !(f >= 0.0 && f.is_finite()) {
            return bad(format!(
                "the flip tolerance must be finite and >= 0, got {}",
                beltrami_halfedge::exact_number(f)
            ));
        }
        if self.fit_rounds > MAX_FIT_ROUNDS {
            return bad(format!(
                "the fit takes at most {MAX_FIT_ROUNDS} rounds, got {}",
                self.fit_rounds
            ));
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
    /// How many times the collapse loop replaced the bounds in its queue by full keys
    /// at once, because many entries were going back into the queue one by one (more
    /// than two per collapse over 4 096 collapses; `docs/decimation.md`, step 5). 0 on
    /// most surfaces; a count of the work done, not of the result's quality.
    pub keyings: usize,
    /// Edges flipped towards valence 6 after the collapses
    /// ([`DecimateOptions::flip_tolerance`]).
    pub flips: usize,
    /// Why the run stopped.
    pub stop: DecimateStop,
    /// Whether the output has at most the target vertex count (exactly the target when
    /// the input had more).
    pub target_reached: bool,
    /// The largest quadric error of a collapse done, as a distance in the positions'
    /// unit (see [`DecimateOptions::max_error`]); 0 without collapses.
    pub max_quadric_error: f64,
    /// Rounds of the final fit to the input done ([`DecimateOptions::fit_rounds`]; 0
    /// when it did not run).
    pub fit_rounds: usize,
    /// The area-weighted RMS distance of the input's face centroids, along their faces'
    /// normals, to their closest points on the output, before the fit (in the
    /// positions' unit; 0 without a fit): the energy the fit lowers.
    pub fit_rms_before: f64,
    /// The same after the fit, from the last round's matches.
    pub fit_rms_after: f64,
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

impl DecimateOptions {
    /// These options for a run at `scale`: the lengths in the positions' unit scaled.
    fn scaled(&self, scale: &Scale) -> Self {
        Self {
            max_error: self.max_error.map(|x| scale.length(x)),
            max_distance: self.max_distance.map(|x| scale.length(x)),
            ..*self
        }
    }
}

impl DecimateReport {
    /// The report of a run at `scale`, in the caller's unit. The pattern names every
    /// field (`_` for those without a unit), so that a new one is not left unscaled.
    fn scaled_back(mut self, scale: &Scale) -> Self {
        let Self {
            vertices_before: _,
            faces_before: _,
            vertices_after: _,
            faces_after: _,
            target_vertices: _,
            collapses: _,
            refused: _,
            keyings: _,
            flips: _,
            stop: _,
            target_reached: _,
            max_quadric_error,
            fit_rounds: _,
            fit_rms_before,
            fit_rms_after,
            distance_measured: _,
            hausdorff,
            hausdorff_to_input,
            hausdorff_from_input,
        } = &mut self;
        for length in [
            max_quadric_error,
            fit_rms_before,
            fit_rms_after,
            hausdorff,
            hausdorff_to_input,
            hausdorff_from_input,
        ] {
            *length = scale.length_back(*length);
        }
        self
    }

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
        // Far from unit size both are measured at the input's scale (`crate::scale`);
        // positions that do not match their mesh are refused as at any size.
        let matching = |(mesh, x): (&HalfedgeMesh, &[DVec3])| mesh.n_vertices() == x.len();
        if let Some(scale) = (matching(input) && matching(output))
            .then(|| Scale::for_run(input.0, input.1))
            .flatten()
        {
            let x = scale.mesh_positions(input.0, input.1);
            let y = scale.mesh_positions(output.0, output.1);
            self.measure_distance_at_scale((input.0, &x), (output.0, &y))?;
            self.hausdorff = scale.length_back(self.hausdorff);
            self.hausdorff_to_input = scale.length_back(self.hausdorff_to_input);
            self.hausdorff_from_input = scale.length_back(self.hausdorff_from_input);
            return Ok(());
        }
        self.measure_distance_at_scale(input, output)
    }

    /// [`measure_distance`](Self::measure_distance) at the positions' own size.
    fn measure_distance_at_scale(
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
        /// The progress closure of [`decimate_with_progress`] asked to stop.
        #[error("decimation was stopped after {done} of {planned} collapses")]
        Stopped {
            /// The collapses done.
            done: usize,
            /// The collapses planned.
            planned: usize,
        },
    }
}

mod collapse_loop;
mod evaluate;
mod fit;
mod flips;
mod geometry;
mod heap;

use evaluate::Decimator;

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
    decimate_with_progress(mesh, positions, options, |_, _| ControlFlow::Continue(()))
}

/// [`decimate`], calling `progress(done, planned)` every few thousand collapses and
/// once at the end: the collapses done so far and those needed to reach the target
/// (`done` stops short of `planned` when no allowed collapse is left). For a progress
/// bar on large meshes; the result is [`decimate`]'s. `progress` returns
/// [`ControlFlow::Break`] to stop (a user's interrupt, say).
///
/// # Errors
/// As for [`decimate`], and [`DecimateError::Stopped`] when `progress` stopped the run.
///
/// # Examples
/// ```
/// use beltrami_algorithms::{decimate_with_progress, DecimateOptions};
/// use beltrami_halfedge::primitives;
///
/// let sphere = primitives::icosphere(5); // 10 242 vertices
/// let mesh = sphere.mesh()?;
/// let mut last = (0, 0);
/// let options = DecimateOptions::default().vertices(1000);
/// decimate_with_progress(&mesh, &sphere.positions, &options, |done, planned| {
///     assert!(done >= last.0);
///     last = (done, planned);
///     std::ops::ControlFlow::Continue(())
/// })?;
/// assert_eq!(last, (9242, 9242));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn decimate_with_progress(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    options: &DecimateOptions,
    progress: impl FnMut(usize, usize) -> ControlFlow<()>,
) -> Result<(HalfedgeMesh, Vec<DVec3>, DecimateReport), DecimateError> {
    check_mesh(mesh, positions)?;
    if mesh.n_faces() == 0 {
        return Err(DecimateError::NoFaces);
    }
    check_finite(positions)?;
    options.validate()?;
    // Far from unit size, at a power of two times it (`crate::scale`), the options'
    // lengths with it.
    at_unit_size(
        mesh,
        positions,
        |x, scale| {
            let run = scale.map_or(*options, |scale| options.scaled(scale));
            decimate_at_scale(mesh, x, &run, progress)
        },
        DecimateReport::scaled_back,
    )
}

/// [`decimate_with_progress`] at the positions' own size (checked).
fn decimate_at_scale(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    options: &DecimateOptions,
    progress: impl FnMut(usize, usize) -> ControlFlow<()>,
) -> Result<(HalfedgeMesh, Vec<DVec3>, DecimateReport), DecimateError> {
    let target = options.target_count(mesh.n_vertices());
    let edit = EditMesh::from_mesh(mesh, positions)?;
    let mut decimator = Decimator::new(edit, options, positions);
    let max_rms = decimator.run(mesh, target, progress)?;
    let refused = decimator.refused;
    let keyings = decimator.keyings as usize;
    let mut edit = decimator.mesh;
    let flips = if options.flips() {
        flips::flip_towards_valence_six(
            &mut edit,
            options.flip_tolerance * max_rms,
            DEFAULT_QUALITY_THRESHOLD,
            options.max_aspect_ratio,
        )?
    } else {
        0
    };
    let stop = if edit.n_vertices() <= target {
        DecimateStop::TargetReached
    } else {
        DecimateStop::NoCollapseLeft
    };
    // The conversion compacts the live elements as a garbage collection would.
    let (out, mut out_positions) = edit.into_mesh()?;
    // Without a collapse every vertex is an input vertex on the input's surface: a fit
    // could only move it by rounding (a target at or above the vertex count returns the
    // input's positions bit for bit).
    let collapsed = out.n_vertices() < mesh.n_vertices();
    let fit = if options.fits() && out.n_faces() > 0 && collapsed {
        Some(fit::fit_to_input(
            &out,
            &mut out_positions,
            mesh,
            positions,
            options.fit_rounds,
            options.max_aspect_ratio,
        )?)
    } else {
        None
    };
    let mut report = DecimateReport {
        vertices_before: mesh.n_vertices(),
        faces_before: mesh.n_faces(),
        vertices_after: out.n_vertices(),
        faces_after: out.n_faces(),
        target_vertices: target,
        collapses: mesh.n_vertices() - out.n_vertices(),
        refused,
        keyings,
        flips,
        stop,
        target_reached: stop == DecimateStop::TargetReached,
        max_quadric_error: max_rms,
        fit_rounds: fit.map_or(0, |f| f.rounds),
        fit_rms_before: fit.map_or(0.0, |f| f.rms_before),
        fit_rms_after: fit.map_or(0.0, |f| f.rms_after),
        ..DecimateReport::default()
    };
    if options.measure_distance {
        report.measure_distance((mesh, positions), (&out, &out_positions))?;
    }
    Ok((out, out_positions, report))
}

#[cfg(test)]
mod test_rng {
    /// A small deterministic generator for the tests (64-bit LCG, top bits).
    pub(super) struct Lcg(pub(super) u64);

    impl Lcg {
        pub(super) fn next(&mut self) -> u64 {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            self.0 >> 33
        }

        pub(super) fn unit(&mut self) -> f64 {
            self.next() as f64 / (1u64 << 31) as f64
        }
    }
}
