//! The intersection of a triangle mesh with a plane.

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::{FaceId, HalfedgeId, HalfedgeMesh, TopologyError};

use super::{Plane, PointSource, Polyline, ProfilePoint};
use crate::MetricsError;
use crate::distortion::check_finite_positions;

/// The cross-section of a triangle mesh by a plane: its polylines, open chains first
/// (those that end on the mesh boundary), then closed loops.
///
/// Each triangle with vertices on both sides of the plane contributes one segment between
/// the points where the plane cuts its two cut edges; segments of adjacent triangles
/// share the point on their common edge, so they join into chains and loops. A point on an
/// edge with ends `u` (negative side) and `w` (positive side) is the linear interpolation
/// `u + t (w − u)` with `t = d(u) / (d(u) − d(w))`, evaluated from the nearer end; when
/// `d(w) = 0` it is `w` itself, recorded as a vertex point (see the [module
/// documentation](super) for the side rule, vertices on the plane and the orientation).
///
/// The order is deterministic: chains in the order of the face where they start, then
/// loops in the order of their lowest-numbered face. A loop starts at the point where the
/// section enters that face.
///
/// # Errors
/// - [`MetricsError::Topology`] with [`TopologyError::NotTriangle`] for a face with more
///   than three vertices (triangulate first);
/// - [`MetricsError::NonFinite`] with `what = "position"` for a non-finite position.
///
/// # Complexity
/// O(V + H).
///
/// # Examples
/// ```
/// use beltrami_halfedge::geometry::Geometry;
/// use beltrami_halfedge::{primitives, DVec3};
/// use beltrami_metrics::profile::{cross_section, Plane, PointSource};
///
/// // A 4 × 2 grid cut along the column of vertices x = 1: one open chain through the
/// // three vertices of that column, with no duplicated point.
/// let grid = primitives::grid(4, 2);
/// let mesh = grid.mesh()?;
/// let plane = Plane::new(DVec3::new(1.0, 0.0, 0.0), DVec3::X)?;
/// let section = cross_section(&Geometry::new(&mesh, &grid.positions)?, &plane)?;
/// assert_eq!(section.len(), 1);
/// assert!(!section[0].closed);
/// let sources: Vec<PointSource> = section[0].points.iter().map(|p| p.source).collect();
/// assert!(sources.iter().all(|s| matches!(s, PointSource::Vertex(_))));
/// assert_eq!(section[0].points.len(), 3);
/// assert_eq!(section[0].length(), 2.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn cross_section(
    geometry: &Geometry<'_>,
    plane: &Plane,
) -> Result<Vec<Polyline>, MetricsError> {
    let mesh = geometry.mesh();
    check_triangles(mesh)?;
    check_finite_positions(geometry.positions())?;

    let distance: Vec<f64> = geometry
        .positions()
        .iter()
        .map(|&x| plane.signed_distance(x))
        .collect();
    let cut = Cut {
        geometry,
        distance: &distance,
    };

    // Per face: the halfedge where the section enters it (from the positive to the
    // negative side) and the one where it leaves (from negative to positive).
    let crossing: Vec<Option<(HalfedgeId, HalfedgeId)>> =
        mesh.faces().map(|f| cut.crossing(f)).collect();
    let mut visited = vec![false; mesh.n_faces()];
    let mut polylines = Vec::new();

    // Open chains start in a face entered across a boundary edge.
    for f in mesh.faces() {
        if let Some((enter, _)) = crossing[f.index()]
            && mesh.is_boundary_halfedge(enter.twin())
            && !visited[f.index()]
        {
            polylines.push(cut.walk(f, &crossing, &mut visited, false));
        }
    }
    // Every other crossed face lies on a loop.
    for f in mesh.faces() {
        if crossing[f.index()].is_some() && !visited[f.index()] {
            polylines.push(cut.walk(f, &crossing, &mut visited, true));
        }
    }
    Ok(polylines)
}

/// Fails on the first face that is not a triangle.
fn check_triangles(mesh: &HalfedgeMesh) -> Result<(), MetricsError> {
    if mesh.is_triangle_mesh() {
        return Ok(());
    }
    match mesh.faces().find(|&f| mesh.face_valence(f) != 3) {
        Some(f) => Err(MetricsError::Topology(TopologyError::NotTriangle {
            face: f.raw(),
            len: mesh.face_valence(f),
        })),
        None => Ok(()),
    }
}

/// A mesh with the signed distances of its vertices from the cutting plane.
struct Cut<'a, 'g> {
    geometry: &'a Geometry<'g>,
    distance: &'a [f64],
}

impl Cut<'_, '_> {
    fn positive(&self, h: HalfedgeId) -> bool {
        self.distance[self.geometry.mesh().to_vertex(h).index()] >= 0.0
    }

    /// The (enter, leave) halfedges of face `f`: enter goes from the positive to the
    /// negative side, leave from negative to positive. `None` when the face is not cut.
    fn crossing(&self, f: FaceId) -> Option<(HalfedgeId, HalfedgeId)> {
        let mesh = self.geometry.mesh();
        let mut enter = None;
        let mut leave = None;
        for h in mesh.halfedges_around_face(f) {
            match (self.positive(h.twin()), self.positive(h)) {
                (true, false) => enter = Some(h),
                (false, true) => leave = Some(h),
                _ => {}
            }
        }
        enter.zip(leave)
    }

    /// The point where the plane cuts the edge of `h` (whose ends are on different sides).
    fn point(&self, h: HalfedgeId) -> ProfilePoint {
        let mesh = self.geometry.mesh();
        let (mut u, mut w) = (mesh.from_vertex(h), mesh.to_vertex(h));
        if self.distance[u.index()] >= 0.0 {
            std::mem::swap(&mut u, &mut w);
        }
        let (du, dw) = (self.distance[u.index()], self.distance[w.index()]);
        let (xu, xw) = (self.geometry.position(u), self.geometry.position(w));
        if dw == 0.0 {
            return ProfilePoint {
                position: xw,
                source: PointSource::Vertex(w),
            };
        }
        // du < 0 < dw: both fractions lie in (0, 1); interpolate from the nearer end so
        // that the point does not depend on which halfedge of the edge is asked.
        let t = du / (du - dw);
        let position = if t <= 0.5 {
            xu + t * (xw - xu)
        } else {
            xw + (dw / (dw - du)) * (xu - xw)
        };
        ProfilePoint {
            position,
            source: PointSource::Edge(h.edge()),
        }
    }

    /// Follows the section from face `start` until it leaves the mesh (open chain) or
    /// returns to `start` (loop), marking the faces it crosses.
    fn walk(
        &self,
        start: FaceId,
        crossing: &[Option<(HalfedgeId, HalfedgeId)>],
        visited: &mut [bool],
        closed: bool,
    ) -> Polyline {
        let mesh = self.geometry.mesh();
        let mut points = Vec::new();
        let mut face = start;
        if let Some((enter, _)) = crossing[face.index()] {
            push(&mut points, self.point(enter));
        }
        while let Some((_, leave)) = crossing[face.index()] {
            visited[face.index()] = true;
            // The halfedge leaving this face enters the face across it.
            match mesh.face(leave.twin()) {
                Some(next) if next == start => break,
                Some(next) if !visited[next.index()] => {
                    push(&mut points, self.point(leave));
                    face = next;
                }
                // The boundary (end of a chain), or a face already on a polyline, which a
                // valid manifold mesh never reaches.
                _ => {
                    push(&mut points, self.point(leave));
                    break;
                }
            }
        }
        if closed {
            // The last point may be the same vertex as the first.
            while points.len() > 1 && points.last().map(|p| p.source) == Some(points[0].source) {
                points.pop();
            }
        }
        Polyline { points, closed }
    }
}

/// Appends `p` unless it is the same vertex point as the last one.
fn push(points: &mut Vec<ProfilePoint>, p: ProfilePoint) {
    let same_vertex = matches!(
        (points.last().map(|q| q.source), p.source),
        (Some(PointSource::Vertex(a)), PointSource::Vertex(b)) if a == b
    );
    if !same_vertex {
        points.push(p);
    }
}
