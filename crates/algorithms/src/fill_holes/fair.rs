//! Fairing of a patch: the new vertices solve `Δᵏ x = 0` (k = 1 membrane, k = 2 thin
//! plate) with every other vertex fixed, as pmp-library's `fair(mesh, k)` with the
//! patch selected. The sparse symmetric positive definite system is solved by faer's
//! sparse Cholesky factorisation.

use std::collections::HashMap;
use std::collections::hash_map::Entry;

use beltrami_halfedge::{DVec3, EditMesh, HalfedgeId, VertexId};
use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};

use super::FairWeights;
use super::refine::opposite_cot;

/// Why a fairing system could not be solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum FairFailure {
    /// A vertex mass (its area share) is zero or not finite: degenerate triangles.
    Mass,
    /// The factorisation failed or the solution is not finite.
    Solver,
}

/// The weight of the edge of `h` in the Laplacian: 1 (uniform) or half the sum of the
/// cotangents of its opposite angles in the triangles beside it.
fn edge_weight(mesh: &EditMesh, h: HalfedgeId, weights: FairWeights) -> f64 {
    match weights {
        FairWeights::Uniform => 1.0,
        FairWeights::Cotangent => {
            let cot = |g: HalfedgeId| match mesh.face(g) {
                Some(f) if mesh.face_valence(f) == 3 => opposite_cot(mesh, g),
                _ => 0.0,
            };
            0.5 * (cot(h) + cot(h.twin()))
        }
    }
}

/// The row of `−L` (positive semi-definite) at `u`: `(u, Σ w)` and `(w, −w_uw)` for each
/// neighbour.
fn row(mesh: &EditMesh, u: VertexId, weights: FairWeights) -> Vec<(VertexId, f64)> {
    let mut entries = Vec::with_capacity(8);
    let mut diagonal = 0.0;
    for h in mesh.halfedges_around_vertex(u) {
        let w = edge_weight(mesh, h, weights);
        diagonal += w;
        entries.push((mesh.to_vertex(h), -w));
    }
    entries.push((u, diagonal));
    entries
}

/// The mass of `u`: 1 (uniform) or a third of the area of its triangles.
fn mass(mesh: &EditMesh, u: VertexId, weights: FairWeights) -> Result<f64, FairFailure> {
    match weights {
        FairWeights::Uniform => Ok(1.0),
        FairWeights::Cotangent => {
            let mut area = 0.0;
            for h in mesh.halfedges_around_vertex(u) {
                if let Some(f) = mesh.face(h)
                    && mesh.face_valence(f) == 3
                {
                    let p = mesh.position(u);
                    let a = mesh.position(mesh.to_vertex(h)) - p;
                    let b = mesh.position(mesh.to_vertex(mesh.next(h))) - p;
                    area += a.cross(b).length() / 6.0;
                }
            }
            if area > 0.0 && area.is_finite() {
                Ok(area)
            } else {
                Err(FairFailure::Mass)
            }
        }
    }
}

/// Moves the `free` vertices so that `Δᵏ x = 0` holds at each of them, every other
/// vertex fixed. `order` is 1 or 2.
pub(super) fn fair(
    mesh: &mut EditMesh,
    free: &[VertexId],
    order: u8,
    weights: FairWeights,
) -> Result<(), FairFailure> {
    let n = free.len();
    if n == 0 {
        return Ok(());
    }
    let index: HashMap<VertexId, usize> = free.iter().enumerate().map(|(i, &v)| (v, i)).collect();
    let mut rows: HashMap<VertexId, (Vec<(VertexId, f64)>, f64)> = HashMap::new();
    let mut entries: Vec<(usize, usize, f64)> = Vec::new();
    let mut rhs = vec![DVec3::ZERO; n];
    let mut add = |i: usize, j: VertexId, c: f64, entries: &mut Vec<(usize, usize, f64)>| {
        if let Some(&jj) = index.get(&j) {
            entries.push((i, jj, c));
        } else {
            rhs[i] -= mesh.position(j) * c;
        }
    };
    for (i, &u) in free.iter().enumerate() {
        let first = row(mesh, u, weights);
        if order == 1 {
            for (j, c) in first {
                add(i, j, c, &mut entries);
            }
            continue;
        }
        for (k, c1) in first {
            if let Entry::Vacant(slot) = rows.entry(k) {
                slot.insert((row(mesh, k, weights), mass(mesh, k, weights)?));
            }
            let (second, m) = &rows[&k];
            for &(j, c2) in second {
                add(i, j, c1 * c2 / m, &mut entries);
            }
        }
    }
    // One entry per (row, column), summed in a fixed order.
    entries.sort_by_key(|&(i, j, _)| (j, i));
    let mut triplets: Vec<Triplet<usize, usize, f64>> = Vec::with_capacity(entries.len());
    for (i, j, c) in entries {
        match triplets.last_mut() {
            Some(t) if t.row == i && t.col == j => t.val += c,
            _ => triplets.push(Triplet::new(i, j, c)),
        }
    }
    let matrix = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &triplets)
        .map_err(|_| FairFailure::Solver)?;
    let llt = matrix
        .sp_cholesky(Side::Lower)
        .map_err(|_| FairFailure::Solver)?;
    let mut b = Mat::<f64>::from_fn(n, 3, |i, c| rhs[i][c]);
    llt.solve_in_place(b.as_mut());
    let solution: Vec<DVec3> = (0..n)
        .map(|i| DVec3::new(b[(i, 0)], b[(i, 1)], b[(i, 2)]))
        .collect();
    if solution.iter().any(|p| !p.is_finite()) {
        return Err(FairFailure::Solver);
    }
    for (&v, &p) in free.iter().zip(&solution) {
        mesh.set_position(v, p);
    }
    Ok(())
}
