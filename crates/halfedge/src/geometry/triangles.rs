//! Geometry over a flat triangle list instead of a [`HalfedgeMesh`]: the whole-mesh
//! measures and per-triangle quantities a smoother needs once the half-edge mesh is no
//! longer kept, with the bits of the [`Geometry`] queries on the mesh built from the
//! same list.

use glam::DVec3;

use super::kernel::{Frame, Sum, Triangle, VecSum, ldexp};
use super::{Geometry, VertexAreaKind};
use crate::ids::VertexId;
use crate::mesh::HalfedgeMesh;

/// A mesh without vertices or faces: the connectivity of a [`Geometry`] whose queries
/// read the positions alone.
static NO_MESH: HalfedgeMesh = HalfedgeMesh {
    v_out: Vec::new(),
    h_to: Vec::new(),
    h_next: Vec::new(),
    h_prev: Vec::new(),
    h_face: Vec::new(),
    f_he: Vec::new(),
};

/// A borrowed flat triangle list (vertex indices, three per triangle, each triangle in
/// face order from its first vertex) with its vertex positions: the whole-mesh measures of [`Geometry`] without a
/// [`HalfedgeMesh`].
///
/// For a triangle mesh built from the same list (`HalfedgeMesh::from_polygons(n,
/// triangles)`, or any triangle mesh whose
/// [`to_polygons`](HalfedgeMesh::to_polygons) is the list), every query gives the bits
/// of the query of the same name on [`Geometry`]: the faces are visited in list order,
/// each from its first vertex, and the centred frame is taken over the vertices that
/// some triangle uses (on a triangle mesh, those that are not isolated).
///
/// # Examples
/// ```
/// use beltrami_halfedge::geometry::{Geometry, TriangleGeometry};
/// use beltrami_halfedge::{primitives, HalfedgeMesh};
/// let sphere = primitives::icosphere(2);
/// let mesh = sphere.mesh()?;
/// let triangles = mesh.to_polygons().indices().to_vec();
/// let list = TriangleGeometry::new(&triangles, &sphere.positions)?;
/// let on_mesh = Geometry::new(&mesh, &sphere.positions)?;
/// assert_eq!(list.volume().to_bits(), on_mesh.volume()?.to_bits());
/// # Ok::<(), beltrami_halfedge::TopologyError>(())
/// ```
#[derive(Clone, Copy, Debug)]
pub struct TriangleGeometry<'a> {
    triangles: &'a [u32],
    positions: &'a [DVec3],
}

impl<'a> TriangleGeometry<'a> {
    /// A view of `triangles` with vertex `v` at `positions[v]`.
    ///
    /// # Errors
    /// [`TopologyError::NotTriangle`](crate::TopologyError::NotTriangle) when the length
    /// of `triangles` is not a multiple of 3 (the last, incomplete face is named);
    /// [`TopologyError::VertexOutOfRange`](crate::TopologyError::VertexOutOfRange) when a
    /// triangle names a vertex that has no position (the first such triangle).
    pub fn new(triangles: &'a [u32], positions: &'a [DVec3]) -> Result<Self, crate::TopologyError> {
        if !triangles.len().is_multiple_of(3) {
            return Err(crate::TopologyError::NotTriangle {
                face: u32::try_from(triangles.len() / 3).unwrap_or(u32::MAX),
                len: triangles.len() % 3,
            });
        }
        let n = positions.len();
        // The largest index first (a plain reduction), the first bad one only then.
        let largest = triangles.iter().copied().max().unwrap_or(0);
        if (largest as usize) < n || triangles.is_empty() {
            return Ok(Self {
                triangles,
                positions,
            });
        }
        if let Some(k) = triangles.iter().position(|&v| v as usize >= n) {
            return Err(crate::TopologyError::VertexOutOfRange {
                face: k / 3,
                vertex: triangles[k],
                n_vertices: n,
            });
        }
        Ok(Self {
            triangles,
            positions,
        })
    }

    /// The triangles, three indices each.
    #[must_use]
    pub fn triangles(&self) -> &'a [u32] {
        self.triangles
    }

    /// The positions, one per vertex.
    #[must_use]
    pub fn positions(&self) -> &'a [DVec3] {
        self.positions
    }

    /// The signed volume in unit³ enclosed by the triangles, `Σ p0 · (p1 × p2) / 6` in
    /// list order, relative to the centre of the bounding box of the vertices the
    /// triangles use, with compensated summation: the bits of [`Geometry::volume`] on a
    /// closed mesh built from the list. Meaningful for a closed surface only, which is
    /// not checked here (the mesh's query checks it). 0.0 without triangles.
    ///
    /// # Complexity
    /// O(V + F).
    #[must_use]
    pub fn volume(&self) -> f64 {
        let Some(frame) = self.centred_frame() else {
            return 0.0;
        };
        let mut sum = Sum::default();
        let x = self.positions;
        for t in self.triangles.chunks_exact(3) {
            let q0 = frame.span(x[t[0] as usize]);
            let q1 = frame.span(x[t[1] as usize]);
            let q2 = frame.span(x[t[2] as usize]);
            sum.add(q0.dot(q1.cross(q2)));
        }
        ldexp(sum.value() / 6.0, 3 * frame.exponent())
    }

    /// The centre of area of the surface: the bits of [`Geometry::surface_centroid`] on
    /// a mesh built from the list; `None` when the total area is zero.
    ///
    /// # Complexity
    /// O(V + F).
    #[must_use]
    pub fn surface_centroid(&self) -> Option<DVec3> {
        let frame = self.centred_frame()?;
        let mut weight = Sum::default();
        let mut moment = VecSum::default();
        let x = self.positions;
        for t in self.triangles.chunks_exact(3) {
            let q0 = frame.span(x[t[0] as usize]);
            let q1 = frame.span(x[t[1] as usize]);
            let q2 = frame.span(x[t[2] as usize]);
            let w = (q1 - q0).cross(q2 - q0).length();
            weight.add(w);
            moment.add((q0 + q1 + q2) * (w / 3.0));
        }
        let w = weight.value();
        if w.is_nan() || w <= 0.0 {
            return None;
        }
        let offset = moment.value() / w;
        let e = frame.exponent();
        Some(
            frame.origin() + DVec3::new(ldexp(offset.x, e), ldexp(offset.y, e), ldexp(offset.z, e)),
        )
    }

    /// The frame of [`Geometry`]'s whole-mesh measures: around the centre of the
    /// bounding box of the used vertices, folded in vertex order; `None` when no vertex
    /// is used.
    fn centred_frame(&self) -> Option<Frame> {
        let mut used = vec![0u64; self.positions.len().div_ceil(64)];
        for &v in self.triangles {
            used[v as usize / 64] |= 1 << (v % 64);
        }
        let mut corners = (0..self.positions.len())
            .filter(|&v| (used[v / 64] >> (v % 64)) & 1 != 0)
            .map(|v| self.positions[v]);
        let first = corners.next()?;
        let (lo, hi) = corners.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p)));
        let centre = lo * 0.5 + hi * 0.5;
        Some(Frame::new(centre, &[lo, hi]))
    }
}

/// The share of corner `corner` (0, 1 or 2) of the triangle with vertex positions
/// `triangle` (in face order, from the face's first vertex) in the area of that corner's
/// vertex under `kind`, in unit²: a third of the area (barycentric) or Meyer et al.'s
/// mixed Voronoi share. The term [`Geometry::vertex_area`] adds for that face, bit for
/// bit, so that a vertex's area can be summed without the mesh: add the shares of its
/// triangles in counter-clockwise order (the order of its outgoing halfedges) from 0.0.
///
/// # Panics
/// If `corner` is not 0, 1 or 2.
///
/// # Examples
/// ```
/// use beltrami_halfedge::geometry::{VertexAreaKind, vertex_area_share};
/// use beltrami_halfedge::DVec3;
/// let t = [DVec3::ZERO, DVec3::new(4.0, 0.0, 0.0), DVec3::new(2.0, 1.0, 0.0)];
/// assert_eq!(vertex_area_share(t, 2, VertexAreaKind::MixedVoronoi), 1.0);
/// assert_eq!(vertex_area_share(t, 0, VertexAreaKind::Barycentric), 2.0 / 3.0);
/// ```
#[inline]
#[must_use]
pub fn vertex_area_share(triangle: [DVec3; 3], corner: usize, kind: VertexAreaKind) -> f64 {
    assert!(corner < 3, "a triangle has three corners");
    let t = Triangle(triangle);
    match kind {
        VertexAreaKind::Barycentric => t.area() / 3.0,
        VertexAreaKind::MixedVoronoi => t.mixed_area(corner),
    }
}

/// The cotangents of `triangles` (vertex ids in face order) at `positions` into `out`,
/// three per triangle (opposite the edges ending at its first, second and third vertex):
/// the bits of [`Geometry::triangle_cotangents_into`], which reads only the positions,
/// for a caller that holds a triangle list but no mesh.
///
/// # Panics
/// If `out` is not three times as long as `triangles`, or a vertex has no position.
pub fn triangle_cotangents_into(positions: &[DVec3], triangles: &[[VertexId; 3]], out: &mut [f64]) {
    let geometry = Geometry {
        mesh: &NO_MESH,
        positions,
    };
    geometry.triangle_cotangents_into(triangles, out);
}

/// [`triangle_cotangents_into`] in blocks of [`BLOCK`](super::BLOCK) triangles: the bits of
/// [`Geometry::triangle_cotangents_blocked_into`] (the cotangent opposite the halfedge
/// ending at the `k`-th vertex of triangle `t` at
/// [`blocked_index`](super::blocked_index)`(t, k)`), for a
/// caller that holds a triangle list but no mesh.
///
/// # Panics
/// If `out.len() != 3 * BLOCK * triangles.len().div_ceil(BLOCK)`, or a vertex has no
/// position.
pub fn triangle_cotangents_blocked_into(
    positions: &[DVec3],
    triangles: &[[VertexId; 3]],
    out: &mut [f64],
) {
    let geometry = Geometry {
        mesh: &NO_MESH,
        positions,
    };
    geometry.triangle_cotangents_blocked_into(triangles, out);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives;

    /// Volume and centroid over the list have the bits of the mesh's, far from the
    /// origin and at a huge scale too (the frame's rescaling), with an isolated vertex far
    /// away (outside the frame); a bad list is a typed error.
    #[test]
    fn measures_over_the_list_have_the_bits_of_the_mesh() {
        let torus = primitives::torus(2.0, 0.6, 12, 7);
        for (shift, scale) in [
            (DVec3::ZERO, 1.0),
            (DVec3::new(1e6, -3e5, 7.0), 1.0),
            (DVec3::ONE, 1e250),
        ] {
            let mut x: Vec<DVec3> = torus
                .positions
                .iter()
                .enumerate()
                .map(|(i, &p)| (p + DVec3::splat(0.01 * (i as f64).sin())) * scale + shift)
                .collect();
            x.push(DVec3::splat(-1e9));
            let mesh = HalfedgeMesh::from_polygons(x.len(), torus.faces.iter()).unwrap();
            let flat = mesh.to_polygons().indices().to_vec();
            let list = TriangleGeometry::new(&flat, &x).unwrap();
            let on_mesh = Geometry::new(&mesh, &x).unwrap();
            assert_eq!(list.volume().to_bits(), on_mesh.volume().unwrap().to_bits());
            let (a, b) = (
                list.surface_centroid().unwrap(),
                on_mesh.surface_centroid().unwrap(),
            );
            assert_eq!(
                a.to_array().map(f64::to_bits),
                b.to_array().map(f64::to_bits)
            );
            assert_eq!(list.triangles().len(), flat.len());
        }
        let x = [DVec3::ZERO; 3];
        assert_eq!(
            TriangleGeometry::new(&[0, 1, 2, 0], &x).unwrap_err(),
            crate::TopologyError::NotTriangle { face: 1, len: 1 }
        );
        assert_eq!(
            TriangleGeometry::new(&[0, 1, 3], &x).unwrap_err(),
            crate::TopologyError::VertexOutOfRange {
                face: 0,
                vertex: 3,
                n_vertices: 3
            }
        );
        assert_eq!(TriangleGeometry::new(&[], &x).unwrap().volume(), 0.0);
        assert!(
            TriangleGeometry::new(&[], &x)
                .unwrap()
                .surface_centroid()
                .is_none()
        );
    }

    /// The shares of a vertex's triangles summed in its order give `vertex_area`; the
    /// cotangents without a mesh are the geometry's.
    #[test]
    fn shares_and_cotangents_have_the_bits_of_the_mesh() {
        let sphere = primitives::icosphere(2);
        let mesh = sphere.mesh().unwrap();
        let x: Vec<DVec3> = sphere
            .positions
            .iter()
            .enumerate()
            .map(|(i, &p)| p * (1.0 + 0.1 * (i as f64).sin()))
            .collect();
        let geometry = Geometry::new(&mesh, &x).unwrap();
        for kind in [VertexAreaKind::Barycentric, VertexAreaKind::MixedVoronoi] {
            for v in mesh.vertices() {
                let mut area = 0.0;
                for h in mesh.halfedges_around_vertex(v) {
                    let Some(f) = mesh.face(h) else { continue };
                    let corners: Vec<VertexId> = mesh.vertices_around_face(f).collect();
                    let corner = corners.iter().position(|&c| c == v).unwrap();
                    let t = [0, 1, 2].map(|k| x[corners[k].index()]);
                    area += vertex_area_share(t, corner, kind);
                }
                assert_eq!(area.to_bits(), geometry.vertex_area(v, kind).to_bits());
            }
        }
        let triangles: Vec<[VertexId; 3]> = mesh
            .faces()
            .map(|f| {
                let c: Vec<VertexId> = mesh.vertices_around_face(f).collect();
                [c[0], c[1], c[2]]
            })
            .collect();
        let mut a = vec![0.0; 3 * triangles.len()];
        let mut b = vec![1.0; 3 * triangles.len()];
        triangle_cotangents_into(&x, &triangles, &mut a);
        geometry.triangle_cotangents_into(&triangles, &mut b);
        assert_eq!(
            a.iter().map(|c| c.to_bits()).collect::<Vec<_>>(),
            b.iter().map(|c| c.to_bits()).collect::<Vec<_>>()
        );
    }

    /// A mesh's triangle list is its `to_polygons` indices, closed or open; a polygon
    /// mesh is handed back unchanged.
    #[test]
    fn a_mesh_becomes_its_triangle_list() {
        for shape in [
            primitives::icosphere(2),
            primitives::grid(6, 4),
            primitives::tetrahedron(),
        ] {
            let mesh = shape.mesh().unwrap();
            let polygons = mesh.to_polygons();
            assert_eq!(mesh.into_triangle_indices().unwrap(), polygons.indices());
        }
        let cube = primitives::cube_quads();
        let mesh = cube.mesh().unwrap();
        assert_eq!(*mesh.clone().into_triangle_indices().unwrap_err(), mesh);
    }
}
