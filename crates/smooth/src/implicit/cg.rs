//! Jacobi-preconditioned conjugate gradient on [`System`], one coordinate at a time.

use beltrami_halfedge::DVec3;
use rayon::prelude::*;

use super::CHUNK;
use super::system::System;

/// The outcome of one solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct CgOutcome {
    /// Iterations done.
    pub(super) iterations: usize,
    /// The relative residual reached, `‖b − A x‖₂ / ‖b‖₂` (0 for `b = 0`).
    pub(super) residual: f64,
    /// Whether a search direction had non-positive curvature `pᵀ A p ≤ 0` (the matrix
    /// is not positive definite).
    pub(super) indefinite: bool,
}

/// Scratch vectors, one coordinate long each.
#[derive(Clone, Debug, Default)]
pub(super) struct Cg {
    b: Vec<f64>,
    x: Vec<f64>,
    r: Vec<f64>,
    z: Vec<f64>,
    p: Vec<f64>,
    q: Vec<f64>,
}

/// `Σ a_i b_i` in fixed chunks, partial sums added in chunk order: the same bits on
/// any number of threads.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let partials: Vec<f64> = a
        .par_chunks(CHUNK)
        .zip(b.par_chunks(CHUNK))
        .map(|(a, b)| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>())
        .collect();
    partials.iter().sum()
}

impl Cg {
    /// Solves `A x = b` for the three coordinates, starting from `initial`; `rhs` holds
    /// `b` on entry and `x` on return. Iterations are summed over the coordinates, the
    /// residual is the worst one; stops at the first coordinate that meets
    /// non-positive curvature or misses the tolerance.
    pub(super) fn solve_coordinates(
        &mut self,
        system: &System,
        initial: &[DVec3],
        rhs: &mut [DVec3],
        tolerance: f64,
        max_iterations: usize,
    ) -> CgOutcome {
        let n = rhs.len();
        let mut b = std::mem::take(&mut self.b);
        let mut x = std::mem::take(&mut self.x);
        b.resize(n, 0.0);
        x.resize(n, 0.0);
        let mut total = CgOutcome {
            iterations: 0,
            residual: 0.0,
            indefinite: false,
        };
        for c in 0..3 {
            for ((bi, xi), (r, p)) in b.iter_mut().zip(x.iter_mut()).zip(rhs.iter().zip(initial)) {
                *bi = r[c];
                *xi = p[c];
            }
            let outcome = self.solve(system, &b, &mut x, tolerance, max_iterations);
            total.iterations += outcome.iterations;
            // The worst coordinate (a NaN, should one occur, wins).
            if outcome.residual.is_nan() || outcome.residual > total.residual {
                total.residual = outcome.residual;
            }
            total.indefinite = outcome.indefinite;
            for (xi, out) in x.iter().zip(rhs.iter_mut()) {
                out[c] = *xi;
            }
            if outcome.indefinite || outcome.residual.is_nan() || outcome.residual > tolerance {
                break;
            }
        }
        self.b = b;
        self.x = x;
        total
    }

    /// Solves `A x = b` from the initial guess in `x`, until `‖r‖ ≤ tolerance ‖b‖` or
    /// `max_iterations` iterations.
    pub(super) fn solve(
        &mut self,
        system: &System,
        b: &[f64],
        x: &mut [f64],
        tolerance: f64,
        max_iterations: usize,
    ) -> CgOutcome {
        let n = b.len();
        for v in [&mut self.r, &mut self.z, &mut self.p, &mut self.q] {
            v.resize(n, 0.0);
        }
        let Self { r, z, p, q, .. } = self;
        let d = &system.diagonal;
        system.multiply(x, q);
        r.par_iter_mut()
            .zip(b.par_iter().zip(q.par_iter()))
            .for_each(|(r, (b, q))| *r = b - q);
        let b_norm = dot(b, b).sqrt();
        let relative = |r: &[f64]| {
            let norm = dot(r, r).sqrt();
            if b_norm > 0.0 { norm / b_norm } else { norm }
        };
        let mut residual = relative(r);
        let mut outcome = CgOutcome {
            iterations: 0,
            residual,
            indefinite: false,
        };
        if residual <= tolerance {
            return outcome;
        }
        z.par_iter_mut()
            .zip(r.par_iter().zip(d.par_iter()))
            .for_each(|(z, (r, d))| *z = r / d);
        p.copy_from_slice(z);
        let mut rz = dot(r, z);
        while outcome.iterations < max_iterations {
            system.multiply(p, q);
            let curvature = dot(p, q);
            if curvature.is_nan() || curvature <= 0.0 {
                outcome.indefinite = true;
                return outcome;
            }
            let alpha = rz / curvature;
            x.par_iter_mut()
                .zip(p.par_iter())
                .for_each(|(x, p)| *x += alpha * p);
            r.par_iter_mut()
                .zip(q.par_iter())
                .for_each(|(r, q)| *r -= alpha * q);
            outcome.iterations += 1;
            residual = relative(r);
            outcome.residual = residual;
            if residual <= tolerance {
                break;
            }
            z.par_iter_mut()
                .zip(r.par_iter().zip(d.par_iter()))
                .for_each(|(z, (r, d))| *z = r / d);
            let rz_next = dot(r, z);
            let beta = rz_next / rz;
            rz = rz_next;
            p.par_iter_mut()
                .zip(z.par_iter())
                .for_each(|(p, z)| *p = z + beta * *p);
        }
        // The true residual, not the recursively updated one.
        system.multiply(x, q);
        r.par_iter_mut()
            .zip(b.par_iter().zip(q.par_iter()))
            .for_each(|(r, (b, q))| *r = b - q);
        outcome.residual = relative(r);
        outcome
    }
}
