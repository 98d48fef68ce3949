//! The linear system of one backward-Euler step, `(M − t L) x' = M x`, on the row layout
//! of the [`Laplacian`]: one slot per halfedge `i → j`, rows in one-ring order. The
//! layout (row offsets, neighbours) and the operator's weights are the operator's own,
//! borrowed through a [`Matrix`]; the system stores only what it adds per slot (the
//! twin slot and the matrix entry) and per row.

use std::ops::Range;

use beltrami_halfedge::{DVec3, VertexId};
use beltrami_weights::Laplacian;
use rayon::prelude::*;

use super::CHUNK;

/// The matrix `A = M + t K` (`K = −L`, the symmetric stiffness) and what the right-hand
/// side needs, with Dirichlet rows (fixed, pinned, isolated and stuck vertices) replaced
/// by identity rows and their columns moved to the right-hand side, so that `A` stays
/// symmetric. Read it through [`matrix`](Self::matrix), with the operator it was
/// assembled from.
#[derive(Clone, Debug)]
pub(super) struct System {
    /// The slot of the twin halfedge `j → i` of each slot `i → j`.
    twins: Vec<u32>,
    /// Vertices that never move (fixed boundary, pinned, isolated).
    fixed: Vec<bool>,
    /// The time step `t`.
    time_step: f64,
    /// The lumped mass `M_ii` (vertex area or weight sum).
    mass: Vec<f64>,
    /// Whether row `i` is an unknown (not Dirichlet) in the current assembly.
    pub(super) free: Vec<bool>,
    /// Whether free row `i` has a Dirichlet neighbour (a column moved to the
    /// right-hand side) in the current assembly.
    coupled: Vec<bool>,
    /// The diagonal of `A` (1 for a Dirichlet row).
    diagonal: Vec<f64>,
    /// The off-diagonal `A_ij` per slot (0 when `i` or `j` is Dirichlet).
    off_diagonal: Vec<f64>,
    /// Vertices that should move but cannot (see [`assemble`](Self::assemble)).
    pub(super) stuck: usize,
}

/// A non-finite matrix entry: the time step times a weight overflowed.
#[derive(Clone, Copy, Debug)]
pub(super) struct NonFiniteEntry {
    /// The row.
    pub(super) vertex: u32,
}

/// The assembled [`System`] on the row layout of its operator, as plain slices: what
/// the solvers read.
#[derive(Clone, Copy, Debug)]
pub(super) struct Matrix<'a> {
    /// Row `i` is `offsets[i]..offsets[i + 1]` (the operator's offsets, `u32` like the
    /// halfedge handles).
    offsets: &'a [u32],
    /// The neighbour `j` of each slot.
    pub(super) neighbours: &'a [u32],
    /// The operator's weight `w_ij` of each slot (before symmetrisation).
    raw: &'a [f64],
    /// See [`System`].
    twins: &'a [u32],
    time_step: f64,
    mass: &'a [f64],
    free: &'a [bool],
    coupled: &'a [bool],
    diagonal: &'a [f64],
    off_diagonal: &'a [f64],
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

/// The symmetrised weight `½ w_ij + ½ w_ji` of slot `s` (`raw` the operator's weights
/// per slot). `½ w + ½ w` is `w` exactly, so symmetric schemes keep their bits.
#[inline(always)]
fn symmetrised(raw: &[f64], twins: &[u32], s: usize) -> f64 {
    0.5 * raw[s] + 0.5 * raw[twins[s] as usize]
}

/// The slot of the twin `j → i` of slot `s` (`i → j`, in row `i`): the slot of row `j`
/// whose neighbour is `i`, or, when `i` and `j` are joined by more than one edge, the
/// slot of the twin halfedge.
fn twin_slot(
    laplacian: &Laplacian,
    offsets: &[u32],
    neighbours: &[u32],
    i: usize,
    s: usize,
) -> u32 {
    let j = neighbours[s] as usize;
    let row = offsets[j] as usize..offsets[j + 1] as usize;
    let mut hits = row.clone().filter(|&k| neighbours[k] as usize == i);
    match (hits.next(), hits.next()) {
        (Some(k), None) => k as u32,
        _ => {
            // Several edges between `i` and `j`: find the twin halfedge itself.
            let v = VertexId::new(i as u32);
            let h = laplacian
                .row_halfedges(v)
                .nth(s - offsets[i] as usize)
                .expect("the slot lies in its row");
            let k = laplacian
                .row_halfedges(VertexId::new(j as u32))
                .position(|g| g == h.twin())
                .expect("every halfedge lies in the row of the vertex it leaves");
            (row.start + k) as u32
        }
    }
}

impl System {
    /// The system on the layout of `laplacian` with `fixed` vertices as permanent
    /// Dirichlet rows; [`assemble`](Self::assemble) fills it.
    pub(super) fn new(laplacian: &Laplacian, fixed: Vec<bool>, time_step: f64) -> Self {
        let n = laplacian.n_rows();
        let rows = laplacian.rows();
        let (offsets, neighbours) = (rows.offsets, rows.neighbours);
        let total = neighbours.len();
        let mut twins = vec![0u32; total];
        row_chunks(offsets, &mut twins)
            .into_par_iter()
            .for_each(|(first, tw)| {
                let base = offsets[first] as usize;
                for i in first..(first + CHUNK).min(n) {
                    for s in offsets[i] as usize..offsets[i + 1] as usize {
                        tw[s - base] = twin_slot(laplacian, offsets, neighbours, i, s);
                    }
                }
            });
        Self {
            twins,
            fixed,
            time_step,
            mass: vec![0.0; n],
            free: vec![false; n],
            coupled: vec![false; n],
            diagonal: vec![1.0; n],
            off_diagonal: vec![0.0; total],
            stuck: 0,
        }
    }

    /// The matrix as last assembled from `laplacian` (the operator the system was made
    /// and assembled with).
    pub(super) fn matrix<'a>(&'a self, laplacian: &'a Laplacian) -> Matrix<'a> {
        let rows = laplacian.rows();
        debug_assert_eq!(rows.neighbours.len(), self.twins.len());
        Matrix {
            offsets: rows.offsets,
            neighbours: rows.neighbours,
            raw: rows.weights,
            twins: &self.twins,
            time_step: self.time_step,
            mass: &self.mass,
            free: &self.free,
            coupled: &self.coupled,
            diagonal: &self.diagonal,
            off_diagonal: &self.off_diagonal,
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
    ///
    /// Two parallel passes over fixed chunks of rows (the mass and diagonal, then the
    /// off-diagonal entries, which need the neighbours' Dirichlet flags); the first
    /// non-finite entry in row order is the error, whatever the thread count.
    pub(super) fn assemble(
        &mut self,
        laplacian: &Laplacian,
        areas: Option<&[f64]>,
    ) -> Result<(), NonFiniteEntry> {
        let diagonal_bad = self.assemble_diagonal(laplacian, areas);
        let off_bad = self.assemble_off_diagonal(laplacian);
        // The first bad row, as a sequential pass would find it: a diagonal is checked
        // before the off-diagonal entries of any row.
        match diagonal_bad.or(off_bad) {
            Some(vertex) => Err(NonFiniteEntry { vertex }),
            None => Ok(()),
        }
    }

    /// The first pass of [`assemble`](Self::assemble): per row the symmetrised weight
    /// sum, the mass, whether the row is free, and the diagonal; counts the stuck rows
    /// and returns the first row whose diagonal is not finite.
    fn assemble_diagonal(&mut self, laplacian: &Laplacian, areas: Option<&[f64]>) -> Option<u32> {
        let rows = laplacian.rows();
        let (offsets, raw) = (rows.offsets, rows.weights);
        let t = self.time_step;
        let (twins, fixed) = (&self.twins, &self.fixed);
        let tallies: Vec<(usize, Option<u32>)> = self
            .mass
            .par_chunks_mut(CHUNK)
            .zip(self.free.par_chunks_mut(CHUNK))
            .zip(self.diagonal.par_chunks_mut(CHUNK))
            .enumerate()
            .map(|(c, ((mass, free), diagonal))| {
                let mut stuck = 0;
                let mut bad = None;
                for k in 0..mass.len() {
                    let i = c * CHUNK + k;
                    let sum: f64 = (offsets[i] as usize..offsets[i + 1] as usize)
                        .map(|s| symmetrised(raw, twins, s))
                        .sum();
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
        tallies.iter().find_map(|&(_, b)| b)
    }

    /// The second pass of [`assemble`](Self::assemble): `A_ij = −t (½ w_ij + ½ w_ji)`
    /// between free rows, 0 otherwise, and whether a free row has a Dirichlet
    /// neighbour; returns the first row with a non-finite entry.
    fn assemble_off_diagonal(&mut self, laplacian: &Laplacian) -> Option<u32> {
        let rows = laplacian.rows();
        let (offsets, neighbours, raw) = (rows.offsets, rows.neighbours, rows.weights);
        let n = self.n();
        let t = self.time_step;
        let (twins, free) = (&self.twins, &self.free);
        let bad: Vec<Option<u32>> = row_chunks(offsets, &mut self.off_diagonal)
            .into_par_iter()
            .zip(self.coupled.par_chunks_mut(CHUNK))
            .map(|((first, off), coupled)| {
                let base = offsets[first] as usize;
                let mut bad = None;
                for i in first..(first + CHUNK).min(n) {
                    coupled[i - first] = free[i]
                        && neighbours[offsets[i] as usize..offsets[i + 1] as usize]
                            .iter()
                            .any(|&j| !free[j as usize]);
                    for s in offsets[i] as usize..offsets[i + 1] as usize {
                        let j = neighbours[s] as usize;
                        let a = if free[i] && free[j] {
                            -t * symmetrised(raw, twins, s)
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
        bad.into_iter().flatten().next()
    }
}

impl Matrix<'_> {
    /// The number of unknowns (vertices).
    pub(super) fn n(&self) -> usize {
        self.diagonal.len()
    }

    /// The slots of row `i`.
    #[inline]
    pub(super) fn slots(&self, i: usize) -> Range<usize> {
        self.offsets[i] as usize..self.offsets[i + 1] as usize
    }

    /// The diagonal of `A` (1 for a Dirichlet row).
    pub(super) fn diagonal(&self) -> &[f64] {
        self.diagonal
    }

    /// The off-diagonal `A_ij` per slot (0 when `i` or `j` is Dirichlet).
    pub(super) fn off_diagonal(&self) -> &[f64] {
        self.off_diagonal
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
        if !self.free[i] {
            return x[i];
        }
        let mut s = x[i] * self.mass[i];
        if self.coupled[i] {
            let t = self.time_step;
            for slot in self.slots(i) {
                let j = self.neighbours[slot] as usize;
                if !self.free[j] {
                    s += x[j] * (t * symmetrised(self.raw, self.twins, slot));
                }
            }
        }
        s
    }

    /// `q = A p` for the rows `first..first + q.len()`; returns `Σ p_i q_i` over them,
    /// in row order. Each row sums its diagonal term, then its slots in order, as
    /// [`row_product`](Self::row_product).
    pub(super) fn product_rows(&self, p: &[DVec3], q: &mut [DVec3], first: usize) -> DVec3 {
        product_chunk(
            &self.offsets[first..=first + q.len()],
            self.neighbours,
            self.off_diagonal,
            &self.diagonal[first..first + q.len()],
            p,
            (q, first),
        )
    }

    /// `(A x)_i` for row `i`: the diagonal term, then the slots in order.
    #[inline(always)]
    pub(super) fn row_product(&self, x: &[DVec3], i: usize) -> DVec3 {
        let slots = self.slots(i);
        let mut s = x[i] * self.diagonal[i];
        for (&w, &j) in self.off_diagonal[slots.clone()]
            .iter()
            .zip(&self.neighbours[slots])
        {
            s += x[j as usize] * w;
        }
        s
    }
}

/// [`Matrix::product_rows`] on plain slices (`offsets` and `diagonal` those of the
/// chunk's rows), so that the compiler keeps them in registers across the row loop.
#[inline(never)]
fn product_chunk(
    offsets: &[u32],
    neighbours: &[u32],
    entries: &[f64],
    diagonal: &[f64],
    p: &[DVec3],
    (q, first): (&mut [DVec3], usize),
) -> DVec3 {
    let mut pq = DVec3::ZERO;
    for (k, (q, &d)) in q.iter_mut().zip(diagonal).enumerate() {
        let i = first + k;
        let slots = offsets[k] as usize..offsets[k + 1] as usize;
        let mut s = p[i] * d;
        for (&w, &j) in entries[slots.clone()].iter().zip(&neighbours[slots]) {
            s += p[j as usize] * w;
        }
        *q = s;
        pq += p[i] * s;
    }
    pq
}
