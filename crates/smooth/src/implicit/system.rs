//! The linear system of one backward-Euler step, `(M − t L) x' = M x`, in the row layout
//! of the [`Laplacian`]: one slot per halfedge `i → j`, rows in one-ring order.

use std::ops::Range;

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
    /// Row `i` is `offsets[i]..offsets[i + 1]` (see [`slots`](Self::slots)); `u32`
    /// like the halfedge handles, half the bytes the matrix passes stream.
    offsets: Vec<u32>,
    /// The neighbour `j` of each slot.
    pub(super) neighbours: Vec<u32>,
    /// The slot of the twin halfedge `j → i`.
    twins: Vec<u32>,
    /// Vertices that never move (fixed boundary, pinned, isolated).
    fixed: Vec<bool>,
    /// The time step `t`.
    time_step: f64,
    /// Symmetrised weights `½ (w_ij + w_ji)` per slot.
    weights: Vec<f64>,
    /// The lumped mass `M_ii` (vertex area or weight sum).
    mass: Vec<f64>,
    /// Whether row `i` is an unknown (not Dirichlet) in the current assembly.
    pub(super) free: Vec<bool>,
    /// The diagonal of `A` (1 for a Dirichlet row).
    pub(super) diagonal: Vec<f64>,
    /// The off-diagonal `A_ij` per slot (0 when `i` or `j` is Dirichlet); during
    /// [`assemble`](Self::assemble) first the operator's weights per slot.
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

/// Splits `data` (one entry per slot) into the slots of consecutive chunks of
/// [`CHUNK`] rows: `(first row, slots)` per chunk.
fn row_chunks<'a, T>(offsets: &[u32], mut data: &'a mut [T]) -> Vec<(usize, &'a mut [T])> {
    let n = offsets.len() - 1;
    let mut out = Vec::with_capacity(n.div_ceil(CHUNK));
    for first in (0..n).step_by(CHUNK) {
        let last = (first + CHUNK).min(n);
        let (head, rest) = std::mem::take(&mut data)
            .split_at_mut(offsets[last] as usize - offsets[first] as usize);
        out.push((first, head));
        data = rest;
    }
    out
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
        offsets.push(0u32);
        let mut total = 0usize;
        for i in 0..n {
            total += laplacian.row_halfedges(VertexId::new(i as u32)).len();
            // At most one slot per halfedge, and halfedge handles are `u32`.
            offsets.push(total as u32);
        }
        let mut neighbours = vec![0u32; total];
        let mut twins = vec![0u32; total];
        row_chunks(&offsets, &mut neighbours)
            .into_par_iter()
            .zip(row_chunks(&offsets, &mut twins))
            .for_each(|((first, nb), (_, tw))| {
                let base = offsets[first] as usize;
                let last = (first + CHUNK).min(n);
                for i in first..last {
                    let v = VertexId::new(i as u32);
                    let slots = offsets[i] as usize - base..offsets[i + 1] as usize - base;
                    for ((h, (j, _)), (nb, tw)) in laplacian
                        .row_halfedges(v)
                        .zip(laplacian.row(v))
                        .zip(nb[slots.clone()].iter_mut().zip(&mut tw[slots]))
                    {
                        *nb = j.raw();
                        // The twin `j → i` leaves `j`, so it lies in row `j`.
                        let k = laplacian
                            .row_halfedges(j)
                            .position(|g| g == h.twin())
                            .expect("every halfedge lies in the row of the vertex it leaves");
                        *tw = offsets[j.index()] + k as u32;
                    }
                }
            });
        debug_assert!(total <= mesh.n_halfedges());
        Self {
            offsets,
            neighbours,
            twins,
            fixed,
            time_step,
            weights: vec![0.0; total],
            mass: vec![0.0; n],
            free: vec![false; n],
            diagonal: vec![1.0; n],
            off_diagonal: vec![0.0; total],
            stuck: 0,
        }
    }

    /// The slots of row `i`.
    #[inline]
    pub(super) fn slots(&self, i: usize) -> Range<usize> {
        self.offsets[i] as usize..self.offsets[i + 1] as usize
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
    ///
    /// Three parallel passes over fixed chunks of rows (the weights of each row, then
    /// the symmetrised weights, mass and diagonal, then the off-diagonal entries); the
    /// first non-finite entry in row order is the error, whatever the thread count.
    pub(super) fn assemble(
        &mut self,
        laplacian: &Laplacian,
        areas: Option<&[f64]>,
    ) -> Result<(), NonFiniteEntry> {
        let n = self.n();
        let offsets = &self.offsets;
        // The operator's weights per slot, in `off_diagonal` until the last pass.
        row_chunks(offsets, &mut self.off_diagonal)
            .into_par_iter()
            .for_each(|(first, raw)| {
                let base = offsets[first] as usize;
                for i in first..(first + CHUNK).min(n) {
                    let slots = offsets[i] as usize - base..offsets[i + 1] as usize - base;
                    for (slot, (_, w)) in raw[slots]
                        .iter_mut()
                        .zip(laplacian.row(VertexId::new(i as u32)))
                    {
                        *slot = w;
                    }
                }
            });
        let t = self.time_step;
        let (raw, twins, fixed) = (&self.off_diagonal, &self.twins, &self.fixed);
        let rows = self
            .mass
            .par_chunks_mut(CHUNK)
            .zip(self.free.par_chunks_mut(CHUNK))
            .zip(self.diagonal.par_chunks_mut(CHUNK));
        let tallies: Vec<(usize, Option<u32>)> = row_chunks(offsets, &mut self.weights)
            .into_par_iter()
            .zip(rows)
            .map(|((first, weights), ((mass, free), diagonal))| {
                let base = offsets[first] as usize;
                let mut stuck = 0;
                let mut bad = None;
                for k in 0..mass.len() {
                    let i = first + k;
                    let slots = offsets[i] as usize..offsets[i + 1] as usize;
                    let row = &mut weights[slots.start - base..slots.end - base];
                    // ½ w + ½ w is w exactly, so symmetric schemes keep their bits.
                    for (w, s) in row.iter_mut().zip(slots) {
                        *w = 0.5 * raw[s] + 0.5 * raw[twins[s] as usize];
                    }
                    let sum: f64 = row.iter().sum();
                    let m = areas.map_or(sum, |a| a[i]);
                    mass[k] = m;
                    let movable = laplacian.scale(VertexId::new(i as u32)).is_some()
                        && sum.is_finite()
                        && sum > 0.0
                        && m.is_finite()
                        && m > 0.0;
                    free[k] = !fixed[i] && movable;
                    stuck += usize::from(!fixed[i] && !movable);
                    diagonal[k] = if free[k] { m + t * sum } else { 1.0 };
                    if !diagonal[k].is_finite() && bad.is_none() {
                        bad = Some(i as u32);
                    }
                }
                (stuck, bad)
            })
            .collect();
        self.stuck = tallies.iter().map(|&(s, _)| s).sum();
        let diagonal_bad = tallies.iter().find_map(|&(_, b)| b);
        let (neighbours, weights, free) = (&self.neighbours, &self.weights, &self.free);
        let off_bad: Vec<Option<u32>> = row_chunks(offsets, &mut self.off_diagonal)
            .into_par_iter()
            .map(|(first, off)| {
                let base = offsets[first] as usize;
                let mut bad = None;
                for i in first..(first + CHUNK).min(n) {
                    for s in offsets[i] as usize..offsets[i + 1] as usize {
                        let j = neighbours[s] as usize;
                        let a = if free[i] && free[j] {
                            -t * weights[s]
                        } else {
                            0.0
                        };
                        if !a.is_finite() && bad.is_none() {
                            bad = Some(i as u32);
                        }
                        off[s - base] = a;
                    }
                }
                bad
            })
            .collect();
        // The first bad row, as a sequential pass would find it: a diagonal is checked
        // before the off-diagonal entries of any row.
        match diagonal_bad.or_else(|| off_bad.into_iter().flatten().next()) {
            Some(vertex) => Err(NonFiniteEntry { vertex }),
            None => Ok(()),
        }
    }

    /// The right-hand side `b` of the current assembly for positions `x`: `M_ii x_i`
    /// plus `t w_ij x_j` for every Dirichlet neighbour `j` of a free row, and `x_i` for
    /// a Dirichlet row.
    pub(super) fn rhs(&self, x: &[DVec3], b: &mut [DVec3]) {
        b.par_chunks_mut(CHUNK).enumerate().for_each(|(c, out)| {
            let first = c * CHUNK;
            for (k, bi) in out.iter_mut().enumerate() {
                *bi = self.rhs_row(x, first + k);
            }
        });
    }

    /// Row `i` of [`rhs`](Self::rhs).
    #[inline]
    pub(super) fn rhs_row(&self, x: &[DVec3], i: usize) -> DVec3 {
        if self.free[i] {
            let t = self.time_step;
            let mut s = x[i] * self.mass[i];
            for slot in self.slots(i) {
                let j = self.neighbours[slot] as usize;
                if !self.free[j] {
                    s += x[j] * (t * self.weights[slot]);
                }
            }
            s
        } else {
            x[i]
        }
    }

    /// `(A x)_i` for row `i`.
    #[inline(always)]
    pub(super) fn row_product(&self, x: &[DVec3], i: usize) -> DVec3 {
        let slots = self.slots(i);
        let mut s = x[i] * self.diagonal[i];
        for (&a, &j) in self.off_diagonal[slots.clone()]
            .iter()
            .zip(&self.neighbours[slots])
        {
            s += x[j as usize] * a;
        }
        s
    }
}
