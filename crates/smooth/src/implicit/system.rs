//! The linear system of one backward-Euler step, `(M − t L) x' = M x`, in the row layout
//! of the [`Laplacian`]: one slot per halfedge `i → j`, rows in one-ring order.

use beltrami_halfedge::{DVec3, HalfedgeMesh, VertexId};
use beltrami_weights::Laplacian;
use rayon::prelude::*;

use super::CHUNK;

/// The matrix `A = M + t K` (`K = −L`, the symmetric stiffness) and what the right-hand
/// side needs, with Dirichlet rows (fixed, pinned, isolated and stuck vertices) replaced
/// by identity rows and their columns moved to the right-hand side, so that `A` stays
/// symmetric.
#[derive(Clone, Debug)]
pub(super) struct System {
    /// Row `i` is `offsets[i]..offsets[i + 1]`.
    pub(super) offsets: Vec<usize>,
    /// The neighbour `j` of each slot.
    pub(super) neighbours: Vec<u32>,
    /// The slot of the twin halfedge `j → i`.
    twins: Vec<u32>,
    /// Vertices that never move (fixed boundary, pinned, isolated).
    fixed: Vec<bool>,
    /// The time step `t`.
    time_step: f64,
    /// The operator's weights per slot (scratch of [`assemble`](Self::assemble)).
    raw: Vec<f64>,
    /// Symmetrised weights `½ (w_ij + w_ji)` per slot.
    weights: Vec<f64>,
    /// The lumped mass `M_ii` (vertex area or weight sum).
    mass: Vec<f64>,
    /// Whether row `i` is an unknown (not Dirichlet) in the current assembly.
    pub(super) free: Vec<bool>,
    /// The diagonal of `A` (1 for a Dirichlet row).
    pub(super) diagonal: Vec<f64>,
    /// The off-diagonal `A_ij` per slot (0 when `i` or `j` is Dirichlet).
    pub(super) off_diagonal: Vec<f64>,
    /// Vertices that should move but cannot (see [`assemble`](Self::assemble)).
    pub(super) stuck: usize,
}

/// A non-finite matrix entry: the time step times a weight overflowed.
#[derive(Clone, Copy, Debug)]
pub(super) struct NonFiniteEntry {
    /// The row.
    pub(super) vertex: u32,
}

impl System {
    /// The layout of `laplacian` (assembled on `mesh`) with `fixed` vertices as
    /// permanent Dirichlet rows.
    pub(super) fn new(
        mesh: &HalfedgeMesh,
        laplacian: &Laplacian,
        fixed: Vec<bool>,
        time_step: f64,
    ) -> Self {
        let n = laplacian.n_rows();
        let mut offsets = Vec::with_capacity(n + 1);
        let mut neighbours = Vec::with_capacity(mesh.n_halfedges());
        let mut slot_of_halfedge = vec![u32::MAX; mesh.n_halfedges()];
        offsets.push(0);
        for i in 0..n {
            let v = VertexId::new(i as u32);
            for (&h, (j, _)) in laplacian.row_halfedges(v).iter().zip(laplacian.row(v)) {
                slot_of_halfedge[h as usize] = neighbours.len() as u32;
                neighbours.push(j.raw());
            }
            offsets.push(neighbours.len());
        }
        // Every halfedge lies in the row of the vertex it leaves, so every twin has a
        // slot.
        let twins = (0..n)
            .flat_map(|i| laplacian.row_halfedges(VertexId::new(i as u32)))
            .map(|&h| slot_of_halfedge[(h ^ 1) as usize])
            .collect();
        let slots = neighbours.len();
        Self {
            offsets,
            neighbours,
            twins,
            fixed,
            time_step,
            raw: vec![0.0; slots],
            weights: vec![0.0; slots],
            mass: vec![0.0; n],
            free: vec![false; n],
            diagonal: vec![1.0; n],
            off_diagonal: vec![0.0; slots],
            stuck: 0,
        }
    }

    /// The number of unknowns (vertices).
    pub(super) fn n(&self) -> usize {
        self.diagonal.len()
    }

    /// Fills the matrix from the operator's current weights and `areas` (area
    /// normalisation; `None` for weight-sum normalisation, where the mass is the
    /// weight sum).
    ///
    /// A vertex that is not fixed becomes a Dirichlet row for this assembly (it is
    /// *stuck*, counted in [`stuck`](Self::stuck)) when the explicit operator could not
    /// move it either ([`Laplacian::scale`] is `None`), or when its symmetrised weights
    /// do not sum to a positive finite value, or its mass is not positive and finite.
    pub(super) fn assemble(
        &mut self,
        laplacian: &Laplacian,
        areas: Option<&[f64]>,
    ) -> Result<(), NonFiniteEntry> {
        let n = self.n();
        let raw = &mut self.raw;
        for i in 0..n {
            let v = VertexId::new(i as u32);
            for (slot, (_, w)) in raw[self.offsets[i]..self.offsets[i + 1]]
                .iter_mut()
                .zip(laplacian.row(v))
            {
                *slot = w;
            }
        }
        // ½ w + ½ w is w exactly, so symmetric schemes keep their bits.
        let raw = &self.raw;
        for ((w, &twin), &r) in self.weights.iter_mut().zip(&self.twins).zip(raw) {
            *w = 0.5 * r + 0.5 * raw[twin as usize];
        }
        let t = self.time_step;
        self.stuck = 0;
        for i in 0..n {
            let row = &self.weights[self.offsets[i]..self.offsets[i + 1]];
            let sum: f64 = row.iter().sum();
            let mass = areas.map_or(sum, |a| a[i]);
            self.mass[i] = mass;
            let movable = laplacian.scale(VertexId::new(i as u32)).is_some()
                && sum.is_finite()
                && sum > 0.0
                && mass.is_finite()
                && mass > 0.0;
            self.free[i] = !self.fixed[i] && movable;
            self.stuck += usize::from(!self.fixed[i] && !movable);
            self.diagonal[i] = if self.free[i] { mass + t * sum } else { 1.0 };
            if !self.diagonal[i].is_finite() {
                return Err(NonFiniteEntry { vertex: i as u32 });
            }
        }
        for i in 0..n {
            for k in self.offsets[i]..self.offsets[i + 1] {
                let j = self.neighbours[k] as usize;
                let a = if self.free[i] && self.free[j] {
                    -t * self.weights[k]
                } else {
                    0.0
                };
                if !a.is_finite() {
                    return Err(NonFiniteEntry { vertex: i as u32 });
                }
                self.off_diagonal[k] = a;
            }
        }
        Ok(())
    }

    /// The right-hand side `b` of the current assembly for positions `x`: `M_ii x_i`
    /// plus `t w_ij x_j` for every Dirichlet neighbour `j` of a free row, and `x_i` for
    /// a Dirichlet row.
    pub(super) fn rhs(&self, x: &[DVec3], b: &mut [DVec3]) {
        let t = self.time_step;
        b.par_chunks_mut(CHUNK).enumerate().for_each(|(c, out)| {
            let first = c * CHUNK;
            for (k, bi) in out.iter_mut().enumerate() {
                let i = first + k;
                *bi = if self.free[i] {
                    let mut s = x[i] * self.mass[i];
                    for slot in self.offsets[i]..self.offsets[i + 1] {
                        let j = self.neighbours[slot] as usize;
                        if !self.free[j] {
                            s += x[j] * (t * self.weights[slot]);
                        }
                    }
                    s
                } else {
                    x[i]
                };
            }
        });
    }

    /// `y = A x` for one coordinate, row by row (so the bits do not depend on the
    /// thread count).
    pub(super) fn multiply(&self, x: &[f64], y: &mut [f64]) {
        y.par_chunks_mut(CHUNK).enumerate().for_each(|(c, out)| {
            let first = c * CHUNK;
            for (k, yi) in out.iter_mut().enumerate() {
                let i = first + k;
                let mut s = self.diagonal[i] * x[i];
                for slot in self.offsets[i]..self.offsets[i + 1] {
                    s += self.off_diagonal[slot] * x[self.neighbours[slot] as usize];
                }
                *yi = s;
            }
        });
    }
}
