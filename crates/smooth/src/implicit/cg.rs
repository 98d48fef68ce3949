//! Jacobi-preconditioned conjugate gradient on a [`Matrix`] for the three coordinates
//! at once: three independent iterations (each with its own step lengths and stopping
//! test) run in lockstep, so that every pass over the matrix serves all three.
//!
//! One iteration is three parallel passes over fixed chunks of [`CHUNK`] rows:
//!
//! 1. `q = A p` and the partial sums of `pᵀ q`;
//! 2. `r −= α q`, `z = r / diag(A)` (not stored) and the partial sums of `rᵀ r` and
//!    `rᵀ z`;
//! 3. `x += α p` (deferred from pass 2, so that `p` is read once per iteration outside
//!    the matrix pass) and `p = z + β p`.
//!
//! Partial sums are formed row by row inside a chunk and added in chunk order, so the
//! bits do not depend on the number of threads.

use beltrami_halfedge::DVec3;
use rayon::prelude::*;

use super::CHUNK;
use super::system::Matrix;

/// The outcome of one solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct CgOutcome {
    /// Iterations done, summed over the three coordinates.
    pub(super) iterations: usize,
    /// The most iterations any one coordinate did (the limit when one did not
    /// converge).
    pub(super) longest: usize,
    /// The relative residual reached, `‖b − A x‖₂ / ‖b‖₂` (0 for `b = 0`), worst
    /// coordinate.
    pub(super) residual: f64,
    /// Whether a search direction had non-positive curvature `pᵀ A p ≤ 0` (the matrix
    /// is not positive definite).
    pub(super) indefinite: bool,
}

/// Scratch vectors, one [`DVec3`] per vertex each.
#[derive(Clone, Debug, Default)]
pub(super) struct Cg {
    r: Vec<DVec3>,
    p: Vec<DVec3>,
    q: Vec<DVec3>,
}

/// Adds per-chunk partial sums in chunk order.
fn total<const K: usize>(partials: &[[DVec3; K]]) -> [DVec3; K] {
    let mut sum = [DVec3::ZERO; K];
    for part in partials {
        for (s, p) in sum.iter_mut().zip(part) {
            *s += *p;
        }
    }
    sum
}

/// Per component: `a` where `mask` is set, else `b`.
#[inline]
fn select(mask: [bool; 3], a: DVec3, b: DVec3) -> DVec3 {
    DVec3::new(
        if mask[0] { a.x } else { b.x },
        if mask[1] { a.y } else { b.y },
        if mask[2] { a.z } else { b.z },
    )
}

/// [`select`], or `a` when every component is set (`ALL`): the common case, a loop
/// without per-component choices.
#[inline(always)]
fn pick<const ALL: bool>(mask: [bool; 3], a: DVec3, b: DVec3) -> DVec3 {
    if ALL { a } else { select(mask, a, b) }
}

/// `‖v‖ / ‖b‖` per coordinate from the squared norms `vv` (`‖v‖` itself where `b` is 0).
fn relative(vv: DVec3, b_norm: [f64; 3]) -> [f64; 3] {
    let mut out = [0.0; 3];
    for c in 0..3 {
        let norm = vv[c].sqrt();
        out[c] = if b_norm[c] > 0.0 {
            norm / b_norm[c]
        } else {
            norm
        };
    }
    out
}

/// One chunk of pass 2: `r −= α q` for the `active` coordinates; returns the chunk's
/// `Σ r²` and `Σ r z` (`z = r / d`), summed row by row.
#[inline(always)]
fn residual_chunk<const ALL: bool>(
    active: [bool; 3],
    alpha: DVec3,
    r: &mut [DVec3],
    (q, d): (&[DVec3], &[f64]),
) -> [DVec3; 2] {
    let mut sums = [DVec3::ZERO; 2];
    for (r, (q, d)) in r.iter_mut().zip(q.iter().zip(d)) {
        *r = pick::<ALL>(active, *r - alpha * *q, *r);
        let z = *r / *d;
        sums[0] += *r * *r;
        sums[1] += *r * z;
    }
    sums
}

/// One chunk of pass 3: `x += α p` for the `active` coordinates, then `p = z + β p`
/// (`z = r / d`) for the `update` coordinates (`ALL`: every coordinate in both).
#[inline(always)]
fn advance_chunk<const ALL: bool>(
    (active, alpha): ([bool; 3], DVec3),
    (update, beta): ([bool; 3], DVec3),
    (x, p): (&mut [DVec3], &mut [DVec3]),
    (r, d): (&[DVec3], &[f64]),
) {
    for ((x, p), (r, d)) in x.iter_mut().zip(p.iter_mut()).zip(r.iter().zip(d)) {
        *x = pick::<ALL>(active, *x + alpha * *p, *x);
        let z = *r / *d;
        *p = pick::<ALL>(update, z + beta * *p, *p);
    }
}

/// One chunk of the last pass 3, when no direction is needed any more: `x += α p` for
/// the `active` coordinates.
#[inline(always)]
fn finish_chunk(active: [bool; 3], alpha: DVec3, x: &mut [DVec3], p: &[DVec3]) {
    for (x, p) in x.iter_mut().zip(p) {
        *x = select(active, *x + alpha * *p, *x);
    }
}

/// Where the lockstep iteration stands.
struct Lockstep {
    /// Per coordinate: still iterating (has not met the tolerance).
    active: [bool; 3],
    /// `rᵀ z` of the current residual.
    rz: DVec3,
    /// The last recursively updated relative residual per coordinate.
    residual: [f64; 3],
    /// Iterations summed over the coordinates, and of the longest one.
    iterations: usize,
    longest: usize,
    indefinite: bool,
}

impl Cg {
    /// Solves `A x = b` for the three coordinates, `b` the right-hand side of `initial`
    /// ([`Matrix::rhs`], formed here row by row where needed), starting from `initial`;
    /// `x` holds the solution on return. Each coordinate stops when `‖b − A x‖₂ ≤
    /// tolerance ‖b‖₂` (its iterate then stays fixed) or after `max_iterations`
    /// iterations; the whole solve stops at the first direction of non-positive
    /// curvature. The residual returned is recomputed from `A x`, not the recursively
    /// updated one.
    pub(super) fn solve_coordinates(
        &mut self,
        a: &Matrix<'_>,
        initial: &[DVec3],
        x: &mut [DVec3],
        tolerance: f64,
        max_iterations: usize,
    ) -> CgOutcome {
        self.reserve(x.len());
        let (b_norm, rr, rz) = self.start(a, initial, x);
        let residual = relative(rr, b_norm);
        let mut state = Lockstep {
            active: residual.map(|r| r.is_nan() || r > tolerance),
            rz,
            residual,
            iterations: 0,
            longest: 0,
            indefinite: false,
        };
        while state.active.iter().any(|&a| a) && state.longest < max_iterations {
            if !self.iterate(a, x, &mut state, b_norm, tolerance) {
                break;
            }
        }
        let residual = relative(true_residual(a, initial, x), b_norm);
        // The worst coordinate (a NaN, should one occur, wins).
        let worst = residual
            .into_iter()
            .fold(0.0, |w: f64, r| if r.is_nan() || r > w { r } else { w });
        CgOutcome {
            iterations: state.iterations,
            longest: state.longest,
            residual: worst,
            indefinite: state.indefinite,
        }
    }

    /// Sizes the scratch vectors for `n` unknowns.
    fn reserve(&mut self, n: usize) {
        for v in [&mut self.r, &mut self.p, &mut self.q] {
            v.resize(n, DVec3::ZERO);
        }
    }

    /// The first pass: `x ← initial`, `r = b − A x`, `p = z = r / d`; returns `‖b‖`
    /// per coordinate, `Σ r²` and `Σ r z`.
    fn start(
        &mut self,
        a: &Matrix<'_>,
        initial: &[DVec3],
        x: &mut [DVec3],
    ) -> ([f64; 3], DVec3, DVec3) {
        let d = a.diagonal();
        let partials: Vec<[DVec3; 3]> = x
            .par_chunks_mut(CHUNK)
            .zip(self.r.par_chunks_mut(CHUNK))
            .zip(self.p.par_chunks_mut(CHUNK))
            .enumerate()
            .map(|(c, ((x, r), p))| {
                let first = c * CHUNK;
                let mut sums = [DVec3::ZERO; 3];
                for k in 0..x.len() {
                    let i = first + k;
                    let b = a.rhs_row(initial, i);
                    x[k] = initial[i];
                    r[k] = b - a.row_product(initial, i);
                    p[k] = r[k] / d[i];
                    sums[0] += b * b;
                    sums[1] += r[k] * r[k];
                    sums[2] += r[k] * p[k];
                }
                sums
            })
            .collect();
        let [bb, rr, rz] = total(&partials);
        (bb.to_array().map(f64::sqrt), rr, rz)
    }

    /// One lockstep iteration (the three passes); `false` when it stopped at a
    /// direction of non-positive curvature.
    fn iterate(
        &mut self,
        a: &Matrix<'_>,
        x: &mut [DVec3],
        state: &mut Lockstep,
        b_norm: [f64; 3],
        tolerance: f64,
    ) -> bool {
        let curvature = self.product(a);
        let mut alpha = DVec3::ZERO;
        for c in 0..3 {
            if state.active[c] {
                if curvature[c].is_nan() || curvature[c] <= 0.0 {
                    state.indefinite = true;
                }
                alpha[c] = state.rz[c] / curvature[c];
            }
        }
        if state.indefinite {
            return false;
        }
        let active = state.active;
        let [rr, rz_next] = self.update_residual(a.diagonal(), active, alpha);
        state.iterations += active.iter().filter(|&&a| a).count();
        state.longest += 1;
        let now = relative(rr, b_norm);
        let mut beta = DVec3::ZERO;
        let mut update = [false; 3];
        for c in 0..3 {
            if active[c] {
                state.residual[c] = now[c];
                if state.residual[c] <= tolerance {
                    state.active[c] = false;
                } else {
                    beta[c] = rz_next[c] / state.rz[c];
                    state.rz[c] = rz_next[c];
                    update[c] = true;
                }
            }
        }
        self.advance(a.diagonal(), x, (active, alpha), (update, beta));
        true
    }

    /// Pass 1: `q = A p`; returns `Σ p q`.
    fn product(&mut self, a: &Matrix<'_>) -> DVec3 {
        let p = &self.p;
        let partials: Vec<[DVec3; 1]> = self
            .q
            .par_chunks_mut(CHUNK)
            .enumerate()
            .map(|(c, q)| [a.product_rows(p, q, c * CHUNK)])
            .collect();
        let [curvature] = total(&partials);
        curvature
    }

    /// Pass 2: `r −= α q` for the `active` coordinates; returns `Σ r²` and `Σ r z`.
    fn update_residual(&mut self, d: &[f64], active: [bool; 3], alpha: DVec3) -> [DVec3; 2] {
        let q = &self.q;
        let partials: Vec<[DVec3; 2]> = self
            .r
            .par_chunks_mut(CHUNK)
            .enumerate()
            .map(|(c, r)| {
                let rows = c * CHUNK..c * CHUNK + r.len();
                let read = (&q[rows.clone()], &d[rows]);
                if active == [true; 3] {
                    residual_chunk::<true>(active, alpha, r, read)
                } else {
                    residual_chunk::<false>(active, alpha, r, read)
                }
            })
            .collect();
        total(&partials)
    }

    /// Pass 3: `x += α p` for the coordinates `step.0` (those of pass 2), then `p = z +
    /// β p` for the coordinates `direction.0` that go on; without any, only `x`.
    fn advance(
        &mut self,
        d: &[f64],
        x: &mut [DVec3],
        step: ([bool; 3], DVec3),
        direction: ([bool; 3], DVec3),
    ) {
        let r = &self.r;
        let p = self.p.par_chunks_mut(CHUNK);
        let x = x.par_chunks_mut(CHUNK);
        if !direction.0.iter().any(|&u| u) {
            let (active, alpha) = step;
            x.zip(p)
                .for_each(|(x, p)| finish_chunk(active, alpha, x, p));
            return;
        }
        let all = step.0 == [true; 3] && direction.0 == [true; 3];
        x.zip(p).enumerate().for_each(|(c, (x, p))| {
            let rows = c * CHUNK..c * CHUNK + x.len();
            let read = (&r[rows.clone()], &d[rows]);
            if all {
                advance_chunk::<true>(step, direction, (x, p), read);
            } else {
                advance_chunk::<false>(step, direction, (x, p), read);
            }
        });
    }
}

/// `Σ (b − A x)²` per coordinate, `b` the right-hand side of `initial` (recomputed).
fn true_residual(a: &Matrix<'_>, initial: &[DVec3], x: &[DVec3]) -> DVec3 {
    let partials: Vec<[DVec3; 1]> = (0..a.n().div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| {
            let first = c * CHUNK;
            let mut sum = DVec3::ZERO;
            for i in first..(first + CHUNK).min(a.n()) {
                let e = a.rhs_row(initial, i) - a.row_product(x, i);
                sum += e * e;
            }
            [sum]
        })
        .collect();
    let [rr] = total(&partials);
    rr
}
