//! The valence flips after the collapses: edges flipped towards valence 6 (4 on the
//! boundary) where the surface hardly moves.

use beltrami_halfedge::{DVec3, EdgeId, EditError, EditMesh, VertexId};

use super::geometry::{aspect_ratio, cross, shape_quality_squared};
use crate::valence::Valences;

/// Passes over the edges at most (each pass flips what improves; most meshes settle in
/// two or three).
const MAX_PASSES: usize = 10;

/// Flips interior edges of `mesh` towards valence 6 (4 on the boundary), in edge order,
/// pass after pass until none is flipped. A flip of the edge `v0 v1` between the
/// triangles `(v0, v1, a)` and `(v1, v0, b)` is made when
/// - it lowers `Σ (valence − optimal)²` over the four vertices (the rule of the flip step
///   of Botsch and Kobbelt's remeshing, and pmp-library's `Remeshing::flip_edges`);
/// - the mesh allows it ([`EditMesh::is_flip_ok`]: no edge `a b` already);
/// - it moves the surface by at most `tolerance`: the two diagonals' midpoints lie
///   within `tolerance` of each other along the quad's normal;
/// - neither new triangle turns against the quad's normal;
/// - the worse new triangle's shape quality (`4A / (√3 ℓ²_max)`) is at least that of the
///   worse old one or `threshold`, whichever is smaller, and its aspect ratio is at most
///   `max_aspect_ratio` when one is given.
///
/// Returns the number of flips.
///
/// # Errors
/// [`EditError`] when a flip the checks allowed is refused (a defect, reported rather
/// than panicking).
pub(super) fn flip_towards_valence_six(
    mesh: &mut EditMesh,
    tolerance: f64,
    threshold: f64,
    max_aspect_ratio: Option<f64>,
) -> Result<usize, EditError> {
    let mut valence = Valences::new(mesh);
    let threshold_squared = threshold * threshold;
    let mut flips = 0;
    for _ in 0..MAX_PASSES {
        let mut changed = false;
        for i in 0..mesh.edge_capacity() {
            let e = EdgeId::new(i as u32);
            if !mesh.is_live_edge(e) || mesh.is_boundary_edge(e) {
                continue;
            }
            let [h, t] = e.halfedges();
            let (Some(a), Some(b)) = (mesh.opposite_vertex(h), mesh.opposite_vertex(t)) else {
                continue;
            };
            let quad = [mesh.from_vertex(h), mesh.to_vertex(h), a, b];
            if !valence.flip_improves(quad)
                || !flip_is_close(mesh, quad, tolerance, threshold_squared, max_aspect_ratio)
                || !mesh.is_flip_ok(e)
            {
                continue;
            }
            mesh.flip_edge(e)?;
            valence.flipped(quad);
            flips += 1;
            changed = true;
        }
        if !changed {
            break;
        }
    }
    Ok(flips)
}

/// The geometric checks of [`flip_towards_valence_six`] for the quad `[v0, v1, a, b]`.
fn flip_is_close(
    mesh: &EditMesh,
    quad: [VertexId; 4],
    tolerance: f64,
    threshold_squared: f64,
    max_aspect_ratio: Option<f64>,
) -> bool {
    let [p0, p1, pa, pb] = quad.map(|v| mesh.position(v));
    let old = [[p0, p1, pa], [p1, p0, pb]];
    let new = [[pa, pb, p1], [pb, pa, p0]];
    let normal = (cross(old[0]) + cross(old[1])).normalize_or_zero();
    if normal == DVec3::ZERO {
        return false;
    }
    let height = (0.5 * (p0 + p1) - 0.5 * (pa + pb)).dot(normal).abs();
    if height > tolerance || new.iter().any(|&t| cross(t).dot(normal) <= 0.0) {
        return false;
    }
    let worst =
        |ts: [[DVec3; 3]; 2]| shape_quality_squared(ts[0]).min(shape_quality_squared(ts[1]));
    if worst(new) < worst(old).min(threshold_squared) {
        return false;
    }
    max_aspect_ratio.is_none_or(|r| new.iter().all(|&t| aspect_ratio(t) <= r))
}
