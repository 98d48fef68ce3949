//! Refinement of a patch to the density of its rim: edge splits at midpoints, collapses
//! of short new edges, Delaunay flips and tangential relaxation, only on the patch's
//! own edges and vertices (after pmp-library's `HoleFilling::refine`).

use beltrami_halfedge::{DVec3, EdgeId, EditError, EditMesh, HalfedgeId, VertexId};

/// Which elements belong to the patch being refined: the vertices and edges created
/// since the patch was started (ids at or above these; the mesh only appends).
#[derive(Clone, Copy, Debug)]
pub(super) struct Patch {
    pub(super) first_vertex: usize,
    pub(super) first_edge: usize,
    pub(super) first_face: usize,
}

impl Patch {
    pub(super) fn is_new_vertex(self, v: VertexId) -> bool {
        v.index() >= self.first_vertex
    }

    pub(super) fn edges(self, mesh: &EditMesh) -> Vec<EdgeId> {
        (self.first_edge..mesh.edge_capacity())
            .map(|i| EdgeId::new(i as u32))
            .filter(|&e| mesh.is_live_edge(e))
            .collect()
    }

    pub(super) fn vertices(self, mesh: &EditMesh) -> Vec<VertexId> {
        (self.first_vertex..mesh.vertex_capacity())
            .map(|i| VertexId::new(i as u32))
            .filter(|&v| mesh.is_live_vertex(v))
            .collect()
    }
}

/// Rounds of split, collapse, flip and relax (pmp-library uses 10).
const ROUNDS: usize = 10;
/// Passes of each step within a round, at most.
const PASSES: usize = 10;

fn length(mesh: &EditMesh, e: EdgeId) -> f64 {
    let [a, b] = mesh.edge_vertices(e);
    mesh.position(a).distance(mesh.position(b))
}

/// The cotangent of the angle opposite `h` in its triangle, 0 on the boundary or for a
/// degenerate corner.
pub(super) fn opposite_cot(mesh: &EditMesh, h: HalfedgeId) -> f64 {
    let Some(o) = mesh.opposite_vertex(h) else {
        return 0.0;
    };
    let u = mesh.position(mesh.from_vertex(h)) - mesh.position(o);
    let v = mesh.position(mesh.to_vertex(h)) - mesh.position(o);
    let sin = u.cross(v).length();
    let c = u.dot(v) / sin;
    if sin > 0.0 && c.is_finite() { c } else { 0.0 }
}

/// Refines the patch towards edges of length `target`: edges longer than 4/3 · target
/// are split at their midpoints, new edges shorter than 4/5 · target collapsed into
/// their other end (when no edge longer than 4/3 · target results), non-Delaunay patch
/// edges flipped, and new vertices moved towards the centroid of their neighbours
/// within their tangent plane. Rim and outside vertices and edges are never touched.
pub(super) fn refine(mesh: &mut EditMesh, patch: Patch, target: f64) -> Result<(), EditError> {
    let high = 4.0 / 3.0 * target;
    let low = 4.0 / 5.0 * target;
    for _ in 0..ROUNDS {
        let mut changed = split_long(mesh, patch, high)?;
        changed |= collapse_short(mesh, patch, low, high)?;
        changed |= flip_delaunay(mesh, patch)?;
        relax(mesh, patch);
        if !changed {
            break;
        }
    }
    flip_delaunay(mesh, patch)?;
    Ok(())
}

fn split_long(mesh: &mut EditMesh, patch: Patch, high: f64) -> Result<bool, EditError> {
    let mut any = false;
    for _ in 0..PASSES {
        let long: Vec<EdgeId> = patch
            .edges(mesh)
            .into_iter()
            .filter(|&e| length(mesh, e) > high)
            .collect();
        if long.is_empty() {
            break;
        }
        for e in long {
            let [a, b] = mesh.edge_vertices(e);
            let mid = (mesh.position(a) + mesh.position(b)) * 0.5;
            mesh.split_edge(e, mid)?;
        }
        any = true;
    }
    Ok(any)
}

fn collapse_short(
    mesh: &mut EditMesh,
    patch: Patch,
    low: f64,
    high: f64,
) -> Result<bool, EditError> {
    let mut any = false;
    for _ in 0..PASSES {
        let mut done = false;
        for e in patch.edges(mesh) {
            if !mesh.is_live_edge(e) || length(mesh, e) >= low {
                continue;
            }
            // Collapse a new vertex into the other end, which keeps its position.
            let Some(h) = e.halfedges().into_iter().find(|&h| {
                let from = mesh.from_vertex(h);
                patch.is_new_vertex(from) && !mesh.is_boundary_vertex(from)
            }) else {
                continue;
            };
            let (from, to) = (mesh.from_vertex(h), mesh.to_vertex(h));
            let target = mesh.position(to);
            let too_long = mesh
                .vertices_around_vertex(from)
                .any(|w| w != to && mesh.position(w).distance(target) > high);
            if too_long
                || folds(mesh, from, to)
                || !mesh.is_collapse_ok(h)
                || mesh.collapse_flattens_tetrahedron(h)
            {
                continue;
            }
            mesh.collapse_edge(h)?;
            done = true;
        }
        if !done {
            break;
        }
        any = true;
    }
    Ok(any)
}

/// Whether moving `from` onto `to` would turn a triangle of `from` that survives the
/// collapse (one without `to`) upside down or make it degenerate.
fn folds(mesh: &EditMesh, from: VertexId, to: VertexId) -> bool {
    let (p, q) = (mesh.position(from), mesh.position(to));
    mesh.halfedges_around_vertex(from).any(|g| {
        if mesh.face(g).is_none() {
            return false;
        }
        let (w, u) = (mesh.to_vertex(g), mesh.to_vertex(mesh.next(g)));
        if w == to || u == to {
            return false;
        }
        let (a, b) = (mesh.position(w), mesh.position(u));
        (a - p).cross(b - p).dot((a - q).cross(b - q)) <= 0.0
    })
}

fn flip_delaunay(mesh: &mut EditMesh, patch: Patch) -> Result<bool, EditError> {
    let mut any = false;
    for _ in 0..PASSES {
        let mut done = false;
        for e in patch.edges(mesh) {
            if mesh.is_boundary_edge(e) {
                continue;
            }
            let [h, t] = e.halfedges();
            if opposite_cot(mesh, h) + opposite_cot(mesh, t) < -1e-12 && mesh.is_flip_ok(e) {
                mesh.flip_edge(e)?;
                done = true;
            }
        }
        if !done {
            break;
        }
        any = true;
    }
    Ok(any)
}

/// Moves each new vertex to the centroid of its neighbours, projected onto its tangent
/// plane (the area-weighted normal), in id order (Gauss–Seidel).
fn relax(mesh: &mut EditMesh, patch: Patch) {
    for v in patch.vertices(mesh) {
        let p = mesh.position(v);
        let mut sum = DVec3::ZERO;
        let mut count = 0.0;
        let mut normal = DVec3::ZERO;
        for h in mesh.halfedges_around_vertex(v) {
            let w = mesh.to_vertex(h);
            sum += mesh.position(w);
            count += 1.0;
            // The face of h is (v, w, to(next(h))).
            if mesh.face(h).is_some() {
                let a = mesh.position(w) - p;
                let b = mesh.position(mesh.to_vertex(mesh.next(h))) - p;
                normal += a.cross(b);
            }
        }
        if count == 0.0 {
            continue;
        }
        let n = normal.normalize_or_zero();
        let d = sum / count - p;
        let q = p + d - n * n.dot(d);
        if q.is_finite() {
            mesh.set_position(v, q);
        }
    }
}
