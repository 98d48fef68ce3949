//! Cross-section profiles: the intersection of a triangle mesh with a plane, as
//! polylines, and the numbers a metrologist compares two profiles by.
//!
//! [`cross_section`] cuts a mesh with a [`Plane`] and returns its [`Polyline`]s: closed
//! loops and open chains (which end on the mesh boundary), each point recording the edge
//! or vertex it came from. [`Polyline::length`], [`profile_length`] and
//! [`profile_deviation`] compare the profile of a smoothed surface with that of the
//! original (the paper's cross-sectional profile comparison).
//!
//! # Conventions
//!
//! - **Side of the plane.** With `n` the unit plane normal and `p₀` the plane point, a
//!   vertex `x` is on the positive side when `d(x) = (x − p₀) · n ≥ 0` and on the
//!   negative side when `d(x) < 0`: a vertex exactly on the plane counts as positive. An
//!   edge is cut when its ends are on different sides, and nowhere else.
//! - **Vertices on the plane.** A cut edge whose positive end lies exactly on the plane
//!   is cut at that vertex: the point is the vertex position itself, recorded as
//!   [`PointSource::Vertex`], and the consecutive cuts at the same vertex give one point,
//!   so no point is duplicated and no gap opens. Edges and faces lying in the plane are
//!   on the positive side: the section then runs along the border between them and the
//!   negative side, and where no part of the surface is strictly below the plane the
//!   section is empty even if faces lie in it (flip the normal to get the border on the
//!   other side). A vertex where the section touches itself (the surface crosses the
//!   plane twice through one vertex on it) appears once per passage. A vertex a rounding
//!   error off the plane is not on it: each cut edge at it gives its own point, those
//!   points a rounding error apart.
//! - **Orientation.** Every segment runs along `n × n_f`, with `n_f` the normal of the
//!   triangle it crosses (counter-clockwise vertex order). For a closed, outward-oriented
//!   surface the loops therefore run as the boundary of the cross-sectional area seen
//!   from the side the plane normal points to: counter-clockwise around the area
//!   (right-hand rule about `n`), clockwise around its holes (the inner loop of a torus
//!   cut through its hole). An open chain on a surface whose normals point to the viewer
//!   runs with the negative side on its right.
//! - **Closed polylines** do not repeat their first point at the end; their length
//!   includes the closing segment.
//! - **Units.** Points, lengths and deviations are in the unit of the positions.
//!
//! # Examples
//!
//! ```
//! use beltrami_halfedge::geometry::Geometry;
//! use beltrami_halfedge::{primitives, DVec3};
//! use beltrami_metrics::profile::{cross_section, Plane};
//!
//! let cube = primitives::cube();
//! let mesh = cube.mesh()?;
//! let plane = Plane::new(DVec3::new(0.0, 0.0, 0.5), DVec3::Z)?;
//! let section = cross_section(&Geometry::new(&mesh, &cube.positions)?, &plane)?;
//! assert_eq!(section.len(), 1);
//! assert!(section[0].closed);
//! assert!((section[0].length() - 4.0).abs() < 1e-15);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # References
//!
//! - The cross-sectional profile comparison of *Comparison of discrete
//!   Laplacian–Beltrami operators and their applications in surface metrology*
//!   (section 3).
//! - ISO 25178-2:2012, *Geometrical product specifications (GPS) — Surface texture:
//!   Areal — Part 2: Terms, definitions and surface texture parameters* (profiles as
//!   sections of the areal surface).
//! - X. Jiang, L. Cooper, P. J. Scott: *Freeform surface filtering using the diffusion
//!   equation*. Proc. R. Soc. A 467 (2011) 841, doi 10.1098/rspa.2010.0307.

mod compare;
mod section;

use beltrami_halfedge::{DVec3, EdgeId, VertexId};

use crate::MetricsError;

pub use compare::{ProfileDeviation, profile_deviation, profile_length};
pub use section::cross_section;

/// A plane through a point with a unit normal; the normal decides the positive side and
/// the orientation of a cross-section (see the [module documentation](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    point: DVec3,
    normal: DVec3,
}

impl Plane {
    /// The plane through `point` with normal direction `normal` (any non-zero length; it
    /// is normalised).
    ///
    /// # Errors
    /// [`MetricsError::InvalidParameter`] when `point` is not finite, or when `normal` is
    /// zero or not finite.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::DVec3;
    /// use beltrami_metrics::profile::Plane;
    /// let plane = Plane::new(DVec3::ZERO, DVec3::new(0.0, 0.0, 2.0))?;
    /// assert_eq!(plane.normal(), DVec3::Z);
    /// assert!(Plane::new(DVec3::ZERO, DVec3::ZERO).is_err());
    /// # Ok::<(), beltrami_metrics::MetricsError>(())
    /// ```
    pub fn new(point: DVec3, normal: DVec3) -> Result<Self, MetricsError> {
        if !point.is_finite() {
            return Err(MetricsError::InvalidParameter {
                name: "plane point",
                reason: "must be finite",
            });
        }
        // Divide by the largest component first, so that very long or very short normals
        // normalise without overflow or underflow.
        let largest = normal.abs().max_element();
        if !(normal.is_finite() && largest > 0.0) {
            return Err(MetricsError::InvalidParameter {
                name: "plane normal",
                reason: "must be finite and non-zero",
            });
        }
        let normal = (normal / largest).normalize();
        Ok(Self { point, normal })
    }

    /// The point the plane was given through.
    #[must_use]
    pub fn point(&self) -> DVec3 {
        self.point
    }

    /// The unit normal.
    #[must_use]
    pub fn normal(&self) -> DVec3 {
        self.normal
    }

    /// The signed distance `(x − p₀) · n` of `x` from the plane, positive on the side the
    /// normal points to.
    #[must_use]
    pub fn signed_distance(&self, x: DVec3) -> f64 {
        (x - self.point).dot(self.normal)
    }
}

/// Where a profile point comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PointSource {
    /// A mesh vertex lying exactly on the plane; the point is its position.
    Vertex(VertexId),
    /// An edge whose ends are strictly on either side of the plane; the point is the
    /// linear interpolation of the ends at the plane.
    Edge(EdgeId),
}

/// A point of a profile with its origin on the mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProfilePoint {
    /// The position, in the unit of the mesh positions.
    pub position: DVec3,
    /// The edge or vertex it was computed from.
    pub source: PointSource,
}

/// A polyline of a cross-section: points in order, closed (a loop) or open (a chain that
/// ends on the mesh boundary).
///
/// A closed polyline does not repeat its first point. A polyline may consist of a single
/// point where the plane only touches the surface at a vertex.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Polyline {
    /// The points in order along the section (see the [module documentation](self) for
    /// the orientation).
    pub points: Vec<ProfilePoint>,
    /// Whether the last point joins the first.
    pub closed: bool,
}

impl Polyline {
    /// The positions of the points, in order.
    pub fn positions(&self) -> impl ExactSizeIterator<Item = DVec3> + '_ {
        self.points.iter().map(|p| p.position)
    }

    /// The segments `(start, end)` in order, including the closing segment of a closed
    /// polyline with at least two points. A single point has no segment.
    pub fn segments(&self) -> impl Iterator<Item = (DVec3, DVec3)> + '_ {
        let n = self.points.len();
        let count = match n {
            0 | 1 => 0,
            _ if self.closed => n,
            _ => n - 1,
        };
        (0..count).map(move |i| (self.points[i].position, self.points[(i + 1) % n].position))
    }

    /// The length: the sum of the segment lengths `Σ |p_{i+1} − p_i|`, closing segment
    /// included for a closed polyline; 0 for a single point.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::{DVec3, VertexId};
    /// use beltrami_metrics::profile::{Polyline, ProfilePoint, PointSource};
    /// let point = |x: f64, y: f64| ProfilePoint {
    ///     position: DVec3::new(x, y, 0.0),
    ///     source: PointSource::Vertex(VertexId::new(0)),
    /// };
    /// let mut square = Polyline {
    ///     points: vec![point(0.0, 0.0), point(1.0, 0.0), point(1.0, 1.0), point(0.0, 1.0)],
    ///     closed: false,
    /// };
    /// assert_eq!(square.length(), 3.0);
    /// square.closed = true;
    /// assert_eq!(square.length(), 4.0);
    /// ```
    #[must_use]
    pub fn length(&self) -> f64 {
        self.segments()
            .map(|(a, b)| crate::distortion::robust_length(b - a))
            .sum()
    }
}
