//! Jacobi-preconditioned conjugate gradient on [`System`] for the three coordinates at
//! once: three independent iterations (each with its own step lengths and stopping
//! test) run in lockstep, so that every pass over the matrix serves all three.
//!
//! One iteration is three parallel passes over fixed chunks of [`CHUNK`] rows:
//!
//! 1. `q = A p` and the partial sums of `pᵀ q`;
//! 2. `x += α p`, `r −= α q`, `z = r / diag(A)` (not stored) and the partial sums of
//!    `rᵀ r` and `rᵀ z`;
//! 3. `p = z + β p`.
//!
//! Partial sums are formed row by row inside a chunk and added in chunk order, so the
//! bits do not depend on the number of threads.

use beltrami_halfedge::DVec3;
use rayon::prelude::*;

use super::CHUNK;
use super::system::System;

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
    b: Vec<DVec3>,
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

/// One chunk of pass 2: `x += α p`, `r −= α q` for the `active` coordinates; returns
/// the chunk's `Σ r²` and `Σ r z` (`z = r / d`), summed row by row.
#[inline(always)]
fn update_chunk<const ALL: bool>(
    active: [bool; 3],
    alpha: DVec3,
    (x, r): (&mut [DVec3], &mut [DVec3]),
    (p, q, d): (&[DVec3], &[DVec3], &[f64]),
) -> [DVec3; 2] {
    let mut sums = [DVec3::ZERO; 2];
    for ((x, r), ((p, q), d)) in x.iter_mut().zip(r).zip(p.iter().zip(q).zip(d)) {
        *x = pick::<ALL>(active, *x + alpha * *p, *x);
        *r = pick::<ALL>(active, *r - alpha * *q, *r);
        let z = *r / *d;
        sums[0] += *r * *r;
        sums[1] += *r * z;
    }
    sums
}

/// One chunk of pass 3: `p = z + β p` (`z = r / d`) for the `update` coordinates.
#[inline(always)]
fn direction_chunk<const ALL: bool>(
    update: [bool; 3],
    beta: DVec3,
    p: &mut [DVec3],
    (r, d): (&[DVec3], &[f64]),
) {
    for (p, (r, d)) in p.iter_mut().zip(r.iter().zip(d)) {
        let z = *r / *d;
        *p = pick::<ALL>(update, z + beta * *p, *p);
    }
}

impl Cg {
    /// Solves `A x = b` for the three coordinates, `b` the right-hand side of `initial`
    /// ([`System::rhs`], formed here in the first pass), starting from `initial`; `x`
    /// holds the solution on return. Each coordinate stops when `‖b − A x‖₂ ≤
    /// tolerance ‖b‖₂` (its iterate then stays fixed) or after `max_iterations`
    /// iterations; the whole solve stops at the first direction of non-positive
    /// curvature. The residual returned is recomputed from `A x`, not the recursively
    /// updated one.
    pub(super) fn solve_coordinates(
        &mut self,
        system: &System,
        initial: &[DVec3],
        x: &mut [DVec3],
        tolerance: f64,
        max_iterations: usize,
    ) -> CgOutcome {
        let n = x.len();
        for v in [&mut self.b, &mut self.r, &mut self.p, &mut self.q] {
            v.resize(n, DVec3::ZERO);
        }
        let Self { b, r, p, q } = self;
        let d = &system.diagonal;

        // b = rhs(initial), x ← initial, r = b − A x, p = z = r / d; Σ b², Σ r², Σ r z.
        let partials: Vec<[DVec3; 3]> = x
            .par_chunks_mut(CHUNK)
            .zip(b.par_chunks_mut(CHUNK))
            .zip(r.par_chunks_mut(CHUNK))
            .zip(p.par_chunks_mut(CHUNK))
            .enumerate()
            .map(|(c, (((x, b), r), p))| {
                let first = c * CHUNK;
                let mut sums = [DVec3::ZERO; 3];
                for k in 0..x.len() {
                    let i = first + k;
                    b[k] = system.rhs_row(initial, i);
                    x[k] = initial[i];
                    r[k] = b[k] - system.row_product(initial, i);
                    p[k] = r[k] / d[i];
                    sums[0] += b[k] * b[k];
                    sums[1] += r[k] * r[k];
                    sums[2] += r[k] * p[k];
                }
                sums
            })
            .collect();
        let [bb, rr, mut rz] = total(&partials);
        let b_norm = bb.to_array().map(f64::sqrt);
        let relative = |rr: DVec3| -> [f64; 3] {
            let mut out = [0.0; 3];
            for c in 0..3 {
                let norm = rr[c].sqrt();
                out[c] = if b_norm[c] > 0.0 {
                    norm / b_norm[c]
                } else {
                    norm
                };
            }
            out
        };
        let mut residual = relative(rr);
        // A coordinate is active while it has not met the tolerance.
        let mut active = residual.map(|r| r.is_nan() || r > tolerance);
        let mut iterations = 0;
        let mut longest = 0;
        let mut indefinite = false;
        while active.iter().any(|&a| a) && longest < max_iterations {
            // q = A p; Σ p q.
            let partials: Vec<[DVec3; 1]> = q
                .par_chunks_mut(CHUNK)
                .enumerate()
                .map(|(c, q)| {
                    let first = c * CHUNK;
                    let mut pq = DVec3::ZERO;
                    for (k, qk) in q.iter_mut().enumerate() {
                        let i = first + k;
                        *qk = system.row_product(p, i);
                        pq += p[i] * *qk;
                    }
                    [pq]
                })
                .collect();
            let [curvature] = total(&partials);
            let mut alpha = DVec3::ZERO;
            for c in 0..3 {
                if active[c] {
                    if curvature[c].is_nan() || curvature[c] <= 0.0 {
                        indefinite = true;
                    }
                    alpha[c] = rz[c] / curvature[c];
                }
            }
            if indefinite {
                break;
            }
            // x += α p, r −= α q, z = r / d; Σ r², Σ r z.
            let partials: Vec<[DVec3; 2]> = x
                .par_chunks_mut(CHUNK)
                .zip(r.par_chunks_mut(CHUNK))
                .enumerate()
                .map(|(c, (x, r))| {
                    let rows = c * CHUNK..c * CHUNK + x.len();
                    let read = (&p[rows.clone()], &q[rows.clone()], &d[rows]);
                    if active == [true; 3] {
                        update_chunk::<true>(active, alpha, (x, r), read)
                    } else {
                        update_chunk::<false>(active, alpha, (x, r), read)
                    }
                })
                .collect();
            let [rr, rz_next] = total(&partials);
            iterations += active.iter().filter(|&&a| a).count();
            longest += 1;
            let now = relative(rr);
            let mut beta = DVec3::ZERO;
            let mut update = [false; 3];
            for c in 0..3 {
                if active[c] {
                    residual[c] = now[c];
                    if residual[c] <= tolerance {
                        active[c] = false;
                    } else {
                        beta[c] = rz_next[c] / rz[c];
                        rz[c] = rz_next[c];
                        update[c] = true;
                    }
                }
            }
            if update.iter().any(|&u| u) {
                // p = z + β p.
                p.par_chunks_mut(CHUNK)
                    .zip(r.par_chunks(CHUNK))
                    .enumerate()
                    .for_each(|(c, (p, r))| {
                        let d = &d[c * CHUNK..c * CHUNK + p.len()];
                        if update == [true; 3] {
                            direction_chunk::<true>(update, beta, p, (r, d));
                        } else {
                            direction_chunk::<false>(update, beta, p, (r, d));
                        }
                    });
            }
        }
        // The true residual, not the recursively updated one: Σ (b − A x)².
        let x = &*x;
        let partials: Vec<[DVec3; 1]> = b
            .par_chunks(CHUNK)
            .enumerate()
            .map(|(c, b)| {
                let first = c * CHUNK;
                let mut sum = DVec3::ZERO;
                for (k, bk) in b.iter().enumerate() {
                    let e = *bk - system.row_product(x, first + k);
                    sum += e * e;
                }
                [sum]
            })
            .collect();
        let [rr] = total(&partials);
        let residual = relative(rr);
        // The worst coordinate (a NaN, should one occur, wins).
        let worst = residual
            .into_iter()
            .fold(0.0, |w: f64, r| if r.is_nan() || r > w { r } else { w });
        CgOutcome {
            iterations,
            longest,
            residual: worst,
            indefinite,
        }
    }
}
