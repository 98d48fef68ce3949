//! √3 subdivision (Kobbelt 2000) with its boundary rule, as OpenMesh's
//! `Subdivider::Uniform::Sqrt3T` computes it.

use std::f64::consts::PI;

use beltrami_halfedge::{FaceId, HalfedgeId, HalfedgeMesh, VertexId};
use glam::DVec3;
use rayon::prelude::*;

use super::{Scheme, boundary_neighbours, build, check_input, edge, face, ring_sum, vertex};
use crate::error::SubdivisionError;

const ONE_THIRD: f64 = 1.0 / 3.0;
const ONE_27TH: f64 = 1.0 / 27.0;

/// √3 subdivision: `steps` times, a vertex is inserted at the centre of every
/// triangle and every old edge is flipped, so each triangle becomes three and two steps
/// give a triadic refinement (every edge split in three).
///
/// The rules (those of OpenMesh's `Sqrt3T`, which counts steps within one call, so the
/// first step is even):
/// - a new face vertex is the centroid of its triangle;
/// - an interior vertex of valence `n` moves to `(1 − α) p + (α / n) Σ q` over its
///   one-ring, with Kobbelt's `α(n) = (4 − 2 cos(2π/n)) / 9`;
/// - even steps (the first, third, …) leave boundary vertices where they are, give
///   every triangle its centre (boundary ones too) and do not flip boundary edges;
/// - odd steps trisect every boundary edge instead: a triangle with boundary edge
///   `P2 P3` (boundary neighbours `P1` before `P2` and `P4` after `P3`) gets no centre
///   but the two points `(P1 + 16 P2 + 10 P3) / 27` and `(10 P2 + 16 P3 + P4) / 27`,
///   and a boundary vertex moves to `(4 p₋ + 19 p + 4 p₊) / 27`. After an even step
///   each triangle has at most one boundary edge, so this is well defined.
///
/// Numbering: the old vertices keep their ids and move. An even step appends the
/// centre of face `f` as vertex `n_vertices + f`. An odd step appends first two
/// vertices per boundary edge, in edge order, the one nearer the source of the edge's
/// inner halfedge first, then the centres of the faces without a boundary edge, in face
/// order. For the first step this is OpenMesh's numbering (both number the edges and
/// faces of a mesh built from the same face list alike); after that the meshes are
/// numbered differently (OpenMesh edits in place). Faces are listed by edge of the
/// step's input: the two triangles across each flipped interior edge, the triangle of
/// each boundary edge, and (odd steps) the middle triangle of each trisected boundary
/// edge after all of them.
///
/// # Examples
/// ```
/// use beltrami_algorithms::sqrt3_subdivide;
/// use beltrami_halfedge::primitives;
///
/// let tet = primitives::tetrahedron();
/// let (mesh, positions) = sqrt3_subdivide(&tet.mesh()?, &tet.positions, 1)?;
/// // The tetrahedron becomes a triakis tetrahedron: 4 + 4 vertices, 12 triangles.
/// assert_eq!((mesh.n_vertices(), mesh.n_faces()), (8, 12));
/// assert_eq!(positions.len(), 8);
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
/// O(3^steps · F) time and memory; each step is dominated by building the finer mesh.
/// The position pass runs in parallel.
///
/// # References
/// Leif Kobbelt, *√3-Subdivision*, SIGGRAPH 2000, pp. 103–112 (interior rule, Section
/// 3; boundary rule, Section 5).
pub fn sqrt3_subdivide(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    steps: usize,
) -> Result<(HalfedgeMesh, Vec<DVec3>), SubdivisionError> {
    check_input(Scheme::Sqrt3, mesh, positions, steps)?;
    let mut current = (mesh.clone(), positions.to_vec());
    for step in 0..steps {
        current = if step % 2 == 0 {
            even_step(&current.0, &current.1)?
        } else {
            odd_step(&current.0, &current.1)?
        };
    }
    Ok(current)
}

/// Kobbelt's weights `(1 − α(n), α(n) / n)` for an interior vertex of valence `n`, with
/// OpenMesh's order of operations.
fn weights(valence: usize) -> (f64, f64) {
    let n = valence as f64;
    let alpha = (4.0 - 2.0 * (2.0 * PI / n).cos()) / 9.0;
    (1.0 - alpha, alpha / n)
}

/// The relaxed position of an interior vertex.
fn interior_point(mesh: &HalfedgeMesh, p: &[DVec3], v: VertexId) -> DVec3 {
    let (sum, valence) = ring_sum(mesh, p, v);
    let (own, each) = weights(valence);
    sum * each + p[v.index()] * own
}

/// The centroid of triangle `f`, summed from its first vertex.
fn centre(mesh: &HalfedgeMesh, p: &[DVec3], f: FaceId) -> DVec3 {
    let [a, b, c] = mesh.triangle_vertices(f);
    (p[a.index()] + p[b.index()] + p[c.index()]) * ONE_THIRD
}

/// An even step: every face gets its centre, boundary vertices stay.
fn even_step(
    mesh: &HalfedgeMesh,
    p: &[DVec3],
) -> Result<(HalfedgeMesh, Vec<DVec3>), SubdivisionError> {
    let (nv, ne, nf) = (mesh.n_vertices(), mesh.n_edges(), mesh.n_faces());
    let mut out = Vec::with_capacity(nv + nf);
    out.par_extend((0..nv).into_par_iter().map(|v| {
        let v = vertex(v);
        if mesh.is_boundary_vertex(v) {
            p[v.index()]
        } else {
            interior_point(mesh, p, v)
        }
    }));
    out.par_extend((0..nf).into_par_iter().map(|f| centre(mesh, p, face(f))));

    let x = |h: HalfedgeId| {
        let f = mesh.face(h).expect("x is asked of inner halfedges only");
        (nv + f.index()) as u32
    };
    let triangles = flipped_triangles(mesh, ne, 3 * nf, x, |_| None);
    Ok((build(nv + nf, &triangles)?, out))
}

/// An odd step: boundary edges are trisected, the other faces get their centres.
fn odd_step(
    mesh: &HalfedgeMesh,
    p: &[DVec3],
) -> Result<(HalfedgeMesh, Vec<DVec3>), SubdivisionError> {
    let (nv, ne, nf) = (mesh.n_vertices(), mesh.n_edges(), mesh.n_faces());
    // The inner halfedge of every boundary edge, in edge order; its points are
    // vertices nv + 2k and nv + 2k + 1.
    let mut first_point = vec![u32::MAX; ne];
    let mut inner = Vec::new();
    for (e, first) in first_point.iter_mut().enumerate() {
        let [h0, h1] = edge(e).halfedges();
        let h = match (mesh.is_boundary_halfedge(h0), mesh.is_boundary_halfedge(h1)) {
            (false, true) => h0,
            (true, false) => h1,
            _ => continue,
        };
        *first = (nv + 2 * inner.len()) as u32;
        inner.push(h);
    }
    // Per face, its boundary halfedge (if any), else the id of its centre.
    let mut boundary_of = vec![None; nf];
    for &h in &inner {
        let f = mesh.face(h).expect("an inner halfedge has a face");
        debug_assert!(
            boundary_of[f.index()].is_none(),
            "two boundary edges in face {f}"
        );
        boundary_of[f.index()] = Some(h);
    }
    let centred: Vec<usize> = (0..nf).filter(|&f| boundary_of[f].is_none()).collect();
    let first_centre = nv + 2 * inner.len();
    let mut centre_id = vec![u32::MAX; nf];
    for (i, &f) in centred.iter().enumerate() {
        centre_id[f] = (first_centre + i) as u32;
    }

    let mut out = Vec::with_capacity(first_centre + centred.len());
    out.par_extend((0..nv).into_par_iter().map(|v| {
        let v = vertex(v);
        let pv = p[v.index()];
        if !mesh.is_boundary_vertex(v) {
            interior_point(mesh, p, v)
        } else if let Some((next, prev)) = boundary_neighbours(mesh, v) {
            ((p[next.index()] + p[prev.index()]) * 4.0 + pv * 19.0) * ONE_27TH
        } else {
            pv
        }
    }));
    out.par_extend(inner.par_iter().flat_map_iter(|&h| {
        let t = h.twin();
        let p1 = p[mesh.to_vertex(mesh.next(t)).index()];
        let p2 = p[mesh.from_vertex(h).index()];
        let p3 = p[mesh.to_vertex(h).index()];
        let p4 = p[mesh.from_vertex(mesh.prev(t)).index()];
        [
            (p1 + p2 * 16.0 + p3 * 10.0) * ONE_27TH,
            (p2 * 10.0 + p3 * 16.0 + p4) * ONE_27TH,
        ]
    }));
    out.par_extend(centred.par_iter().map(|&f| centre(mesh, p, face(f))));

    // The vertex opposite halfedge h after its face is split: the face's centre, or,
    // in a face split along its boundary edge b, the point of b next to h.
    let x = |h: HalfedgeId| {
        let f = mesh
            .face(h)
            .expect("x is asked of inner halfedges only")
            .index();
        match boundary_of[f] {
            None => centre_id[f],
            Some(b) if mesh.next(b) == h => first_point[b.edge().index()] + 1,
            Some(b) => {
                debug_assert_eq!(mesh.prev(b), h, "x of a trisected edge");
                first_point[b.edge().index()]
            }
        }
    };
    let middle = |h: HalfedgeId| {
        let k = first_point[h.edge().index()];
        Some([k, k + 1, mesh.to_vertex(mesh.next(h)).raw()])
    };
    let triangles = flipped_triangles(mesh, ne, 3 * nf, x, middle);
    Ok((build(first_centre + centred.len(), &triangles)?, out))
}

/// The triangles after splitting and flipping: for every interior edge `a → b` (its
/// halfedge `2e`), with `x(h)` the vertex opposite halfedge `h` after the split, the
/// two triangles `[a, x(b→a), x(a→b)]` and `[x(b→a), b, x(a→b)]`; for a boundary edge
/// whose inner halfedge is `h`, either the triangle `middle(h)` of a trisected edge
/// (listed after all others), or `[from(h), to(h), x(h)]`.
fn flipped_triangles(
    mesh: &HalfedgeMesh,
    n_edges: usize,
    n_triangles: usize,
    x: impl Fn(HalfedgeId) -> u32,
    middle: impl Fn(HalfedgeId) -> Option<[u32; 3]>,
) -> Vec<[u32; 3]> {
    let mut triangles = Vec::with_capacity(n_triangles);
    let mut middles = Vec::new();
    for e in 0..n_edges {
        let [h0, h1] = edge(e).halfedges();
        let inner = match (mesh.is_boundary_halfedge(h0), mesh.is_boundary_halfedge(h1)) {
            (false, false) => {
                let (a, b) = (mesh.from_vertex(h0).raw(), mesh.to_vertex(h0).raw());
                let (xf, xg) = (x(h0), x(h1));
                triangles.push([a, xg, xf]);
                triangles.push([xg, b, xf]);
                continue;
            }
            (false, true) => h0,
            _ => h1,
        };
        match middle(inner) {
            Some(tri) => middles.push(tri),
            None => triangles.push([
                mesh.from_vertex(inner).raw(),
                mesh.to_vertex(inner).raw(),
                x(inner),
            ]),
        }
    }
    triangles.extend(middles);
    debug_assert_eq!(triangles.len(), n_triangles);
    triangles
}

#[cfg(test)]
mod tests {
    use super::weights;

    #[test]
    fn regular_interior_weight_is_one_third() {
        // alpha(6) = (4 - 2 cos(pi/3)) / 9 = 1/3.
        let (own, each) = weights(6);
        assert!((own - 2.0 / 3.0).abs() < 1e-15);
        assert!((each * 6.0 - 1.0 / 3.0).abs() < 1e-15);
    }

    #[test]
    fn weights_are_an_affine_combination() {
        for n in 3..100 {
            let (own, each) = weights(n);
            assert!((own + n as f64 * each - 1.0).abs() < 1e-14, "valence {n}");
        }
    }
}
