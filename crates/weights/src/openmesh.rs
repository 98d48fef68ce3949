//! OpenMesh's cotangent weights, reproduced operation by operation.

use beltrami_halfedge::{DVec3, HalfedgeId};

use crate::scheme::{WeightContext, WeightScheme};

/// The cotangent weights of OpenMesh's `LaplaceSmootherT` (the weights
/// `JacobiLaplaceSmootherT` uses for its `Normal` component), with OpenMesh's arithmetic:
/// for an edge with halfedges `h0 = 2e` and `h1 = 2e + 1`,
///
/// ```text
/// w = c(h0) + c(h1),   c(h) = 1 / tan(acos(clamp(d0 · d1, −1, 1)))
/// d0 = (p0 − p2) / |p0 − p2|,   d1 = (p1 − p2) / |p1 − p2|
/// ```
///
/// with `p0 = to_vertex(h0)`, `p1 = to_vertex(h1)` and `p2` the vertex opposite the edge
/// in the face of `h` (`to_vertex(next(h))`). Each step is the one OpenMesh 9.0 performs
/// (`normalize()` divides each component by the norm; the dot product sums x, y, z in
/// that order), and `acos` and `tan` come from the platform's C library as OpenMesh's
/// do, so that with the same library the weights agree bit for bit.
///
/// Use it with λ = 0.5, weights computed once and a fixed boundary to reproduce
/// `JacobiLaplaceSmootherT` with `Component::Normal` and `C0` (see `docs/testing.md`;
/// `beltrami_testkit::openmesh::smoother_config` builds that configuration).
///
/// Where this differs from OpenMesh, on purpose, so that weights stay finite:
///
/// - **No ½.** OpenMesh sums the two cotangents without halving them, so these weights
///   are twice [`Cotangent`](crate::Cotangent)'s. The factor cancels under weight-sum
///   normalisation (bit for bit: halving is exact), but not under area normalisation.
/// - **Boundary halfedges contribute 0.** OpenMesh takes the "opposite" vertex of a
///   boundary halfedge from the next boundary halfedge, which gives a meaningless term —
///   an infinity on a straight boundary. It only enters the rows of boundary vertices,
///   which OpenMesh's smoother never moves, so leaving it out changes no result of a
///   fixed-boundary run.
/// - **Non-finite terms are 0.** Where OpenMesh divides by zero (a zero-length edge, an
///   angle of exactly 0, a NaN clamped to 1) its term is infinite or NaN; here it is 0.
///
/// No degeneracy threshold is applied otherwise (unlike
/// [`WeightContext::opposite_cotangent`]): a sliver gives the huge cotangent OpenMesh
/// gives. Symmetric; negative when the two opposite angles sum to more than π.
///
/// # Examples
/// ```
/// use beltrami_halfedge::{geometry::Geometry, primitives};
/// use beltrami_weights::{Cotangent, OpenMeshCotangent, WeightContext, WeightScheme};
///
/// let grid = primitives::grid(3, 3);
/// let mesh = grid.mesh().unwrap();
/// let ctx = WeightContext::new(Geometry::new(&mesh, &grid.positions).unwrap());
/// for h in mesh.halfedges().filter(|&h| !mesh.is_boundary_edge(h.edge())) {
///     let (openmesh, ours) = (OpenMeshCotangent.weight(&ctx, h), Cotangent.weight(&ctx, h));
///     assert!((openmesh - 2.0 * ours).abs() < 1e-15);
/// }
/// ```
///
/// # References
/// OpenMesh 9.0, `Tools/Smoother/LaplaceSmootherT_impl.hh`, `compute_weights`.
#[derive(Clone, Copy, Debug, Default)]
pub struct OpenMeshCotangent;

/// `a / |a|` as OpenMesh's `normalize()` computes it: each component divided by
/// `sqrt(x² + y² + z²)`.
#[inline]
fn normalized(a: DVec3) -> DVec3 {
    let norm = (a.x * a.x + a.y * a.y + a.z * a.z).sqrt();
    DVec3::new(a.x / norm, a.y / norm, a.z / norm)
}

/// OpenMesh's term for the corner opposite edge (p0, p1) at p2, or 0 where OpenMesh's
/// would not be finite.
#[inline]
fn openmesh_cot(p0: DVec3, p1: DVec3, p2: DVec3) -> f64 {
    let d0 = normalized(p0 - p2);
    let d1 = normalized(p1 - p2);
    let dot = d0.x * d1.x + d0.y * d1.y + d0.z * d1.z;
    // std::max(-1, std::min(1, dot)): a NaN dot becomes 1, as in OpenMesh.
    let clamped = if dot < 1.0 { dot } else { 1.0 };
    let clamped = if -1.0 < clamped { clamped } else { -1.0 };
    let c = 1.0 / clamped.acos().tan();
    if c.is_finite() { c } else { 0.0 }
}

/// The term of halfedge `h`'s face for the edge whose halfedge 0 ends at `p0` and whose
/// halfedge 1 ends at `p1`.
#[inline]
fn face_term(ctx: &WeightContext<'_>, h: HalfedgeId, p0: DVec3, p1: DVec3) -> f64 {
    let mesh = ctx.mesh();
    if mesh.is_boundary_halfedge(h) {
        return 0.0;
    }
    let p2 = ctx.position(mesh.to_vertex(mesh.next(h)));
    openmesh_cot(p0, p1, p2)
}

impl WeightScheme for OpenMeshCotangent {
    fn name(&self) -> &str {
        "openmesh-cotangent"
    }

    fn description(&self) -> &str {
        "w_ij = cot a_ij + cot b_ij as OpenMesh's LaplaceSmootherT computes it"
    }

    fn weight(&self, ctx: &WeightContext<'_>, h: HalfedgeId) -> f64 {
        let mesh = ctx.mesh();
        let [h0, h1] = h.edge().halfedges();
        let p0 = ctx.position(mesh.to_vertex(h0));
        let p1 = ctx.position(mesh.to_vertex(h1));
        // OpenMesh: weight = 0; weight += term(h0); weight += term(h1).
        0.0 + face_term(ctx, h0, p0, p1) + face_term(ctx, h1, p0, p1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Cotangent;
    use beltrami_halfedge::geometry::Geometry;
    use beltrami_halfedge::{HalfedgeMesh, VertexId, primitives};

    fn ctx_weights(
        mesh: &HalfedgeMesh,
        positions: &[DVec3],
        scheme: &dyn WeightScheme,
    ) -> Vec<f64> {
        let ctx = WeightContext::new(Geometry::new(mesh, positions).unwrap());
        mesh.halfedges().map(|h| scheme.weight(&ctx, h)).collect()
    }

    #[test]
    fn twice_the_cotangent_weights_on_interior_edges() {
        let sphere = primitives::icosphere(2);
        let mesh = sphere.mesh().unwrap();
        let ours = ctx_weights(&mesh, &sphere.positions, &Cotangent);
        let openmesh = ctx_weights(&mesh, &sphere.positions, &OpenMeshCotangent);
        for (a, b) in ours.iter().zip(&openmesh) {
            assert!((2.0 * a - b).abs() <= 1e-13 * b.abs(), "{a} {b}");
        }
    }

    #[test]
    fn symmetric_and_one_sided_on_the_boundary() {
        let hex = primitives::hexagon_fan();
        let mesh = hex.mesh().unwrap();
        let w = ctx_weights(&mesh, &hex.positions, &OpenMeshCotangent);
        let cot60 = 1.0 / 3f64.sqrt();
        for e in mesh.edges() {
            let [h0, h1] = e.halfedges();
            assert_eq!(w[h0.index()].to_bits(), w[h1.index()].to_bits());
            let expected = if mesh.is_boundary_edge(e) {
                cot60
            } else {
                2.0 * cot60
            };
            // acos and tan of a nearly exact 60° lose a few digits.
            assert!((w[h0.index()] - expected).abs() < 1e-14, "{e:?}");
        }
    }

    #[test]
    fn negative_across_two_obtuse_angles() {
        // A rhombus split along its long diagonal: both angles opposite it are 120°.
        let s = 3f64.sqrt();
        let positions = [
            DVec3::new(-s, 0.0, 0.0),
            DVec3::new(0.0, -1.0, 0.0),
            DVec3::new(s, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        let mesh = HalfedgeMesh::from_polygons(4, [[0u32, 1, 2], [0, 2, 3]]).unwrap();
        let h = mesh
            .find_halfedge(VertexId::new(0), VertexId::new(2))
            .unwrap();
        let w = ctx_weights(&mesh, &positions, &OpenMeshCotangent)[h.index()];
        assert!((w + 2.0 / s).abs() < 1e-14, "{w}"); // 2 cot 120° = −2/√3
    }

    #[test]
    fn finite_where_openmesh_divides_by_zero() {
        // A zero-length edge (vertices 1 and 3 coincide) and a collinear triangle.
        let positions = [
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(0.5, 1.0, 0.0),
            DVec3::X,
            DVec3::new(2.0, 0.0, 0.0),
        ];
        let mesh = HalfedgeMesh::from_polygons(
            5,
            [[0u32, 1, 2], [1, 3, 2], [3, 4, 2], [0, 4, 3], [0, 3, 1]],
        )
        .unwrap();
        let w = ctx_weights(&mesh, &positions, &OpenMeshCotangent);
        assert!(w.iter().all(|x| x.is_finite()), "{w:?}");
    }
}
