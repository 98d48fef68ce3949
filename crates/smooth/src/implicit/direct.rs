//! The direct solver: faer's sparse Cholesky factorisation `A = L Lᵀ` (approximate
//! minimum degree ordering, simplicial or supernodal as faer decides), symbolic
//! analysis once per mesh, numeric factorisation whenever the matrix changes.

use beltrami_halfedge::DVec3;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, Mat, Par, Side};

use super::system::Matrix;

/// Why a factorisation failed.
#[derive(Clone, Debug)]
pub(super) enum FactorError {
    /// A pivot was not positive: the matrix is not positive definite.
    NotPositiveDefinite,
    /// Anything else (out of memory, index overflow), in faer's words.
    Other(String),
}

/// Everything is sequential ([`Par::Seq`]): faer's parallel supernodal kernels split
/// dense updates by the thread count, which this crate does not let change the bits of
/// a result.
const PAR: Par = Par::Seq;

/// The upper triangle of `A` in compressed sparse columns, its symbolic Cholesky
/// analysis and the current numeric factor.
pub(super) struct Direct {
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    values: Vec<f64>,
    /// The value index of each slot `i → j` with `j < i` (an entry of column `i`);
    /// `usize::MAX` for the other slots.
    slot_entry: Vec<usize>,
    /// The value index of each diagonal entry (the last of its column).
    diagonal_entry: Vec<usize>,
    symbolic: SymbolicCholesky<usize>,
    factor: Vec<f64>,
    factored: bool,
    memory: MemBuffer,
    rhs: Mat<f64>,
}

impl std::fmt::Debug for Direct {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Direct")
            .field("n", &self.diagonal_entry.len())
            .field("nnz", &self.row_idx.len())
            .field("factor_nnz", &self.factor.len())
            .finish_non_exhaustive()
    }
}

impl Direct {
    /// The sparsity pattern of `system` (every neighbour pair, whatever the current
    /// Dirichlet rows, so that the analysis stays valid when they change) and its
    /// symbolic analysis.
    pub(super) fn analyse(system: &Matrix<'_>) -> Result<Self, FactorError> {
        let n = system.n();
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(system.neighbours.len() / 2 + n);
        let mut slot_entry = vec![usize::MAX; system.neighbours.len()];
        let mut diagonal_entry = Vec::with_capacity(n);
        let mut column: Vec<(usize, usize)> = Vec::new();
        col_ptr.push(0);
        for i in 0..n {
            column.clear();
            for slot in system.slots(i) {
                let j = system.neighbours[slot] as usize;
                if j < i {
                    column.push((j, slot));
                }
            }
            column.sort_unstable();
            // Two edges between the same pair of vertices share one entry.
            for (k, &(j, slot)) in column.iter().enumerate() {
                if k == 0 || column[k - 1].0 != j {
                    row_idx.push(j);
                }
                slot_entry[slot] = row_idx.len() - 1;
            }
            diagonal_entry.push(row_idx.len());
            row_idx.push(i);
            col_ptr.push(row_idx.len());
        }
        let pattern = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let symbolic = factorize_symbolic_cholesky(
            pattern,
            Side::Upper,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )
        .map_err(|e| FactorError::Other(format!("{e:?}")))?;
        let req = StackReq::any_of(&[
            symbolic.factorize_numeric_llt_scratch::<f64>(PAR, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(3, PAR),
        ]);
        let memory = MemBuffer::try_new(req).map_err(|e| FactorError::Other(format!("{e:?}")))?;
        let mut factor = Vec::new();
        factor
            .try_reserve_exact(symbolic.len_val())
            .map_err(|e| FactorError::Other(e.to_string()))?;
        factor.resize(symbolic.len_val(), 0.0);
        Ok(Self {
            values: vec![0.0; row_idx.len()],
            col_ptr,
            row_idx,
            slot_entry,
            diagonal_entry,
            symbolic,
            factor,
            factored: false,
            memory,
            rhs: Mat::zeros(n, 3),
        })
    }

    /// The number of non-zeros of the Cholesky factor.
    pub(super) fn factor_nnz(&self) -> usize {
        self.factor.len()
    }

    /// Factorises the current matrix of `system` numerically, reusing the analysis.
    pub(super) fn factorize(&mut self, system: &Matrix<'_>) -> Result<(), FactorError> {
        self.factored = false;
        self.values.fill(0.0);
        for (i, &d) in system.diagonal().iter().enumerate() {
            self.values[self.diagonal_entry[i]] = d;
        }
        for (&entry, &a) in self.slot_entry.iter().zip(system.off_diagonal()) {
            if entry != usize::MAX {
                self.values[entry] += a;
            }
        }
        let n = system.n();
        let pattern =
            SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx);
        let matrix = SparseColMatRef::new(pattern, &self.values);
        let stack = MemStack::new(&mut self.memory);
        match self.symbolic.factorize_numeric_llt::<f64>(
            &mut self.factor,
            matrix,
            Side::Upper,
            LltRegularization::default(),
            PAR,
            stack,
            Default::default(),
        ) {
            Ok(_) => {
                self.factored = true;
                Ok(())
            }
            // The only error is a non-positive pivot.
            Err(_) => Err(FactorError::NotPositiveDefinite),
        }
    }

    /// Marks the factor stale (the matrix changed).
    pub(super) fn invalidate(&mut self) {
        self.factored = false;
    }

    /// Whether a numeric factor is ready.
    pub(super) fn is_factored(&self) -> bool {
        self.factored
    }

    /// Solves `A x = b` for the three coordinates with the current factor, in place.
    pub(super) fn solve(&mut self, b: &mut [DVec3]) {
        debug_assert!(self.factored);
        for c in 0..3 {
            let col = self.rhs.col_as_slice_mut(c);
            for (x, p) in col.iter_mut().zip(b.iter()) {
                *x = p[c];
            }
        }
        let stack = MemStack::new(&mut self.memory);
        LltRef::new(&self.symbolic, &self.factor).solve_in_place_with_conj(
            Conj::No,
            self.rhs.as_mut(),
            PAR,
            stack,
        );
        for c in 0..3 {
            let col = self.rhs.col_as_slice(c);
            for (x, p) in col.iter().zip(b.iter_mut()) {
                p[c] = *x;
            }
        }
    }
}
