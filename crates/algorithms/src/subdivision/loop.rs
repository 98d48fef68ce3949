//! Loop subdivision (Loop 1987) with the boundary curve rules, as OpenMesh's
//! `Subdivider::Uniform::LoopT` computes it.

use std::f64::consts::PI;

use beltrami_halfedge::{EdgeId, HalfedgeMesh, VertexId};
use glam::DVec3;
use rayon::prelude::*;

use super::{Scheme, boundary_neighbours, check_input, edge, ring_sum, vertex};
use crate::error::SubdivisionError;

/// Loop subdivision: `steps` times, every triangle is split into four at its edge
/// midpoints, and the points are placed by Loop's masks.
///
/// The rules (those of OpenMesh's `LoopT`, and of pmp-library's `loop_subdivision`
/// with its default boundary handling):
/// - an interior vertex of valence `n` moves to `(1 − α) p + (α / n) Σ q` over its
///   one-ring `q`, with Loop's original `α(n) = (40 − (3 + 2 cos(2π/n))²) / 64` (5/8 −
///   (3/8 + cos(2π/n)/4)², 3/8 for `n = 6`), not Warren's simplified weights;
/// - a boundary vertex follows the cubic B-spline of its boundary: `(6 p + p₋ + p₊) /
///   8` with its two boundary neighbours; the interior does not pull it;
/// - an interior edge `ab` with opposite vertices `c` and `d` gets the point
///   `(3 (a + b) + c + d) / 8`; a boundary edge its midpoint `(a + b) / 2`.
///
/// So the boundary of the limit surface is the uniform cubic B-spline of the boundary
/// polygon, and it depends on the boundary alone.
///
/// Numbering: the old vertices keep their ids and move; the point of edge `e` of the
/// step's input is vertex `n_vertices + e`. For the first step this is OpenMesh's
/// numbering, since beltrami and OpenMesh number the edges of a mesh built from the
/// same face list alike; after that the meshes are numbered differently (OpenMesh edits
/// in place). Face `f` with vertices `[a, b, c]` becomes faces `4f` to `4f + 3`: the
/// corner triangles at `a`, `b` and `c`, then the middle one, each starting at its old
/// vertex or at the point of the edge after its first vertex.
///
/// # Examples
/// ```
/// use beltrami_algorithms::loop_subdivide;
/// use beltrami_halfedge::primitives;
///
/// let tet = primitives::tetrahedron();
/// let (mesh, positions) = loop_subdivide(&tet.mesh()?, &tet.positions, 1)?;
/// assert_eq!((mesh.n_vertices(), mesh.n_edges(), mesh.n_faces()), (10, 24, 16));
/// // The edge points come after the 4 old vertices, in edge order.
/// assert_eq!(positions.len(), 10);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`SubdivisionError::PositionCount`] when `positions` does not have one entry per
/// vertex, [`NotTriangle`](SubdivisionError::NotTriangle) naming the first face that
/// is not a triangle, [`TooLarge`](SubdivisionError::TooLarge) when the result would
/// not fit in a mesh (checked before any work).
///
/// # Complexity
/// O(4^steps · F) time and memory. Each step computes the positions and takes the finer
/// connectivity from [`HalfedgeMesh::split_triangles`], which writes it in closed form,
/// O(V + E + F) without sorting or hashing; all passes but a prefix sum over the faces
/// run in parallel. The connectivity is exactly what [`HalfedgeMesh::from_polygons`]
/// builds from the face list above.
///
/// # References
/// Charles Loop, *Smooth Subdivision Surfaces Based on Triangles*, Master's thesis,
/// University of Utah, 1987. Boundary rules: Hoppe et al., *Piecewise Smooth Surface
/// Reconstruction*, SIGGRAPH 1994 (the B-spline masks, without their crease rules).
pub fn loop_subdivide(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    steps: usize,
) -> Result<(HalfedgeMesh, Vec<DVec3>), SubdivisionError> {
    check_input(Scheme::Loop, mesh, positions, steps)?;
    let mut current = (mesh.clone(), positions.to_vec());
    for _ in 0..steps {
        current = loop_step(&current.0, &current.1)?;
    }
    Ok(current)
}

/// One Loop step of a checked triangle mesh.
fn loop_step(
    mesh: &HalfedgeMesh,
    p: &[DVec3],
) -> Result<(HalfedgeMesh, Vec<DVec3>), SubdivisionError> {
    let (nv, ne) = (mesh.n_vertices(), mesh.n_edges());
    let mut out = Vec::with_capacity(nv + ne);
    out.par_extend(
        (0..nv)
            .into_par_iter()
            .map(|v| vertex_point(mesh, p, vertex(v))),
    );
    out.par_extend(
        (0..ne)
            .into_par_iter()
            .map(|e| edge_point(mesh, p, edge(e))),
    );

    Ok((mesh.split_triangles()?, out))
}

/// Loop's weights `(1 − α(n), α(n) / n)` for an interior vertex of valence `n`, with
/// OpenMesh's order of operations.
fn weights(valence: usize) -> (f64, f64) {
    let inv = 1.0 / valence as f64;
    let t = 3.0 + 2.0 * (2.0 * PI * inv).cos();
    let alpha = (40.0 - t * t) / 64.0;
    (1.0 - alpha, inv * alpha)
}

/// The new position of old vertex `v`.
fn vertex_point(mesh: &HalfedgeMesh, p: &[DVec3], v: VertexId) -> DVec3 {
    let pv = p[v.index()];
    if mesh.is_boundary_vertex(v) {
        match boundary_neighbours(mesh, v) {
            Some((next, prev)) => (pv * 6.0 + p[next.index()] + p[prev.index()]) * 0.125,
            None => pv,
        }
    } else {
        let (sum, valence) = ring_sum(mesh, p, v);
        let (own, each) = weights(valence);
        sum * each + pv * own
    }
}

/// The position of the new vertex on edge `e`.
fn edge_point(mesh: &HalfedgeMesh, p: &[DVec3], e: EdgeId) -> DVec3 {
    let [h0, h1] = e.halfedges();
    let ends = p[mesh.to_vertex(h0).index()] + p[mesh.to_vertex(h1).index()];
    if mesh.is_boundary_edge(e) {
        ends * 0.5
    } else {
        let c = p[mesh.to_vertex(mesh.next(h0)).index()];
        let d = p[mesh.to_vertex(mesh.next(h1)).index()];
        (ends * 3.0 + c + d) * 0.125
    }
}

#[cfg(test)]
mod tests {
    use super::weights;

    #[test]
    fn regular_interior_weight_is_three_eighths() {
        let (own, each) = weights(6);
        assert!((own - 5.0 / 8.0).abs() < 1e-15);
        assert!((each * 6.0 - 3.0 / 8.0).abs() < 1e-15);
    }

    #[test]
    fn weights_are_an_affine_combination() {
        for n in 3..100 {
            let (own, each) = weights(n);
            assert!((own + n as f64 * each - 1.0).abs() < 1e-14, "valence {n}");
            assert!(own > 0.0 && each > 0.0, "valence {n}");
        }
    }
}
