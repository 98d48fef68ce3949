//! Small dense linear algebra for the fits: symmetric eigen-decomposition by Jacobi
//! rotations and Cholesky solves of small normal equations.
//!
//! Written here rather than taken from nalgebra or faer: the fits need 3×3 to 5×5
//! symmetric systems only, in `f64`, with glam vectors on either side; a few dozen lines
//! keep the arithmetic visible and the dependency tree small.

// Index loops mirror the matrix formulas they implement.
#![allow(clippy::needless_range_loop)]

use glam::DVec3;

/// The eigenvalues of a symmetric `N × N` matrix in ascending order, with unit eigenvectors
/// (row `k` of the second result belongs to eigenvalue `k`), by cyclic Jacobi rotations.
///
/// Jacobi's method is accurate to rounding in the eigenvalues relative to the matrix norm,
/// and its eigenvectors are orthonormal to rounding. Entries must be finite.
///
/// # References
/// G. H. Golub, C. F. Van Loan: *Matrix Computations*, 4th ed., §8.5 (the cyclic Jacobi
/// method, with Rutishauser's stable rotation formulas).
pub(crate) fn symmetric_eigen<const N: usize>(m: [[f64; N]; N]) -> ([f64; N], [[f64; N]; N]) {
    let mut a = m;
    let mut v = [[0.0; N]; N];
    for (i, row) in v.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    for _sweep in 0..64 {
        let off: f64 = (0..N)
            .flat_map(|i| (0..N).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| a[i][j] * a[i][j])
            .sum();
        let diag: f64 = (0..N).map(|i| a[i][i] * a[i][i]).sum();
        if off <= 1e-30 * diag {
            break;
        }
        for p in 0..N {
            for q in p + 1..N {
                if a[p][q] == 0.0 {
                    continue;
                }
                let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                // A ← Jᵀ A J for the rotation J in the (p, q) plane.
                for k in 0..N {
                    let (akp, akq) = (a[k][p], a[k][q]);
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for k in 0..N {
                    let (apk, aqk) = (a[p][k], a[q][k]);
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for row in v.iter_mut() {
                    let (vp, vq) = (row[p], row[q]);
                    row[p] = c * vp - s * vq;
                    row[q] = s * vp + c * vq;
                }
            }
        }
    }
    // Columns of v are the eigenvectors; sort ascending by eigenvalue.
    let mut order: [usize; N] = std::array::from_fn(|i| i);
    order.sort_by(|&i, &j| a[i][i].total_cmp(&a[j][j]));
    let values = order.map(|i| a[i][i]);
    let vectors = order.map(|i| std::array::from_fn(|k| v[k][i]));
    (values, vectors)
}

/// The eigenvalues (ascending) and unit eigenvectors of a symmetric 3 × 3 matrix, as
/// [`symmetric_eigen`] with glam vectors.
pub(crate) fn symmetric_eigen3(m: [[f64; 3]; 3]) -> ([f64; 3], [DVec3; 3]) {
    let (values, vectors) = symmetric_eigen(m);
    (values, vectors.map(DVec3::from_array))
}

/// Solves `A x = b` for a symmetric positive definite `A` by Cholesky factorisation, or
/// `None` when a pivot is not positive beyond rounding (`A` singular or indefinite to
/// working precision).
pub(crate) fn cholesky_solve<const N: usize>(a: [[f64; N]; N], b: [f64; N]) -> Option<[f64; N]> {
    let scale = (0..N).map(|i| a[i][i].abs()).fold(0.0, f64::max);
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    let mut l = [[0.0; N]; N];
    for i in 0..N {
        for j in 0..=i {
            let mut sum = a[i][j];
            for k in 0..j {
                sum -= l[i][k] * l[j][k];
            }
            if i == j {
                if sum <= 1e-14 * scale {
                    return None;
                }
                l[i][i] = sum.sqrt();
            } else {
                l[i][j] = sum / l[j][j];
            }
        }
    }
    let mut y = [0.0; N];
    for i in 0..N {
        let mut sum = b[i];
        for k in 0..i {
            sum -= l[i][k] * y[k];
        }
        y[i] = sum / l[i][i];
    }
    let mut x = [0.0; N];
    for i in (0..N).rev() {
        let mut sum = y[i];
        for k in i + 1..N {
            sum -= l[k][i] * x[k];
        }
        x[i] = sum / l[i][i];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// Solves `A x = b` for a symmetric positive definite `n × n` matrix `A` (row-major in
/// `a`, only the lower triangle read) by Cholesky factorisation, or `None` when a pivot
/// is not positive beyond rounding; the dynamically sized twin of [`cholesky_solve`], for
/// the normal equations of a polynomial fit.
pub(crate) fn cholesky_solve_dyn(a: &[f64], b: &[f64]) -> Option<Vec<f64>> {
    let n = b.len();
    debug_assert_eq!(a.len(), n * n);
    let scale = (0..n).map(|i| a[i * n + i].abs()).fold(0.0, f64::max);
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    let mut l = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..=i {
            let mut sum = a[i * n + j];
            for k in 0..j {
                sum -= l[i * n + k] * l[j * n + k];
            }
            if i == j {
                if sum <= 1e-13 * scale {
                    return None;
                }
                l[i * n + i] = sum.sqrt();
            } else {
                l[i * n + j] = sum / l[j * n + j];
            }
        }
    }
    let mut y = vec![0.0; n];
    for i in 0..n {
        let mut sum = b[i];
        for k in 0..i {
            sum -= l[i * n + k] * y[k];
        }
        y[i] = sum / l[i * n + i];
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        let mut sum = y[i];
        for k in i + 1..n {
            sum -= l[k * n + i] * x[k];
        }
        x[i] = sum / l[i * n + i];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// A unit vector orthogonal to the unit vector `n`, chosen deterministically (from the
/// coordinate axis least aligned with `n`).
pub(crate) fn orthogonal(n: DVec3) -> DVec3 {
    let a = n.abs();
    let helper = if a.x <= a.y && a.x <= a.z {
        DVec3::X
    } else if a.y <= a.z {
        DVec3::Y
    } else {
        DVec3::Z
    };
    n.cross(helper).normalize()
}

/// `v` or `−v`, whichever has a positive component of largest magnitude (the first such
/// component on ties): the sign convention of fitted axes.
pub(crate) fn canonical_sign(v: DVec3) -> DVec3 {
    let a = v.abs();
    let k = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    if v[k] < 0.0 { -v } else { v }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigen_of_a_rotated_diagonal_matrix() {
        // R diag(1, 2, 5) Rᵀ for a rotation about (1, 1, 1).
        let axis = DVec3::ONE.normalize();
        let (s, c) = 0.7f64.sin_cos();
        let rot = |p: DVec3| p * c + axis.cross(p) * s + axis * axis.dot(p) * (1.0 - c);
        let cols = [rot(DVec3::X), rot(DVec3::Y), rot(DVec3::Z)];
        let d = [1.0, 2.0, 5.0];
        let m: [[f64; 3]; 3] = std::array::from_fn(|i| {
            std::array::from_fn(|j| (0..3).map(|k| d[k] * cols[k][i] * cols[k][j]).sum())
        });
        let (values, vectors) = symmetric_eigen3(m);
        for k in 0..3 {
            assert!((values[k] - d[k]).abs() < 1e-14);
            assert!((vectors[k].dot(cols[k]).abs() - 1.0).abs() < 1e-14);
        }
    }

    #[test]
    fn cholesky_solves_and_refuses_singular_systems() {
        let a = [[4.0, 2.0, 0.6], [2.0, 5.0, 1.0], [0.6, 1.0, 3.0]];
        let x = [1.0, -2.0, 0.5];
        let b: [f64; 3] = std::array::from_fn(|i| (0..3).map(|j| a[i][j] * x[j]).sum());
        let y = cholesky_solve(a, b).unwrap();
        assert!((0..3).all(|i| (y[i] - x[i]).abs() < 1e-15));
        assert!(cholesky_solve([[1.0, 1.0], [1.0, 1.0]], [1.0, 1.0]).is_none());
        assert!(cholesky_solve([[0.0; 2]; 2], [1.0, 1.0]).is_none());
        let flat: Vec<f64> = a.iter().flatten().copied().collect();
        let z = cholesky_solve_dyn(&flat, &b).unwrap();
        assert!((0..3).all(|i| (z[i] - x[i]).abs() < 1e-15));
        assert!(cholesky_solve_dyn(&[1.0, 1.0, 1.0, 1.0], &[1.0, 1.0]).is_none());
    }

    #[test]
    fn axes_get_a_canonical_sign() {
        assert_eq!(
            canonical_sign(DVec3::new(0.1, -0.9, 0.3)),
            DVec3::new(-0.1, 0.9, -0.3)
        );
        let n = DVec3::new(0.3, -0.4, 0.866).normalize();
        assert!(orthogonal(n).dot(n).abs() < 1e-16);
    }
}
