//! A small radix-2 complex FFT, in one and two dimensions.
//!
//! Written here rather than taken from a crate: the spatial parameters need the power
//! spectrum and the autocorrelation of one height grid, zero-padded to powers of two, a
//! few dozen lines of the textbook iterative Cooley–Tukey algorithm; the workspace has no
//! FFT dependency, and this keeps it so.

use std::f64::consts::TAU;

/// A complex number `(re, im)`.
pub(super) type Complex = (f64, f64);

/// The discrete Fourier transform of `data` in place, `X_k = Σ_n x_n e^{∓2πi kn/N}`
/// (`−` forward, `+` inverse; the inverse is not divided by `N`), for the tests: [`fft2`]
/// runs the same stages on rows and columns.
///
/// # Panics
/// When the length is not a power of two (a caller's bug).
#[cfg(test)]
fn fft(data: &mut [Complex], inverse: bool) {
    let n = data.len();
    assert!(n.is_power_of_two(), "FFT length {n} is not a power of two");
    transform(data, &twiddles(n, inverse));
}

/// `e^{∓2πi k/n}` for `k < n/2`, from the exact angles (not by repeated multiplication),
/// for accuracy.
fn twiddles(n: usize, inverse: bool) -> Vec<Complex> {
    let sign = if inverse { 1.0 } else { -1.0 };
    (0..n / 2)
        .map(|k| {
            let (s, c) = (sign * TAU * k as f64 / n as f64).sin_cos();
            (c, s)
        })
        .collect()
}

/// The iterative radix-2 transform of `data` (a power-of-two length `n`) with the
/// twiddles of length `n`: stage of length `len` uses every `n/len`-th of them.
fn transform(data: &mut [Complex], twiddles: &[Complex]) {
    let n = data.len();
    if n < 2 {
        return;
    }
    // Bit-reversal permutation.
    let bits = n.trailing_zeros();
    for i in 0..n {
        let j = i.reverse_bits() >> (usize::BITS - bits);
        if i < j {
            data.swap(i, j);
        }
    }
    let mut len = 2;
    while len <= n {
        let half = len / 2;
        let stride = n / len;
        for start in (0..n).step_by(len) {
            for k in 0..half {
                let (wr, wi) = twiddles[k * stride];
                let (ar, ai) = data[start + k];
                let (br, bi) = data[start + k + half];
                let (tr, ti) = (br * wr - bi * wi, br * wi + bi * wr);
                data[start + k] = (ar + tr, ai + ti);
                data[start + k + half] = (ar - tr, ai - ti);
            }
        }
        len *= 2;
    }
}

/// The two-dimensional discrete Fourier transform of a row-major `rows × columns` array
/// in place, `X_{kl} = Σ x_{rc} e^{∓2πi (kr/rows + lc/columns)}` (`−` forward, `+`
/// inverse, not divided by the size): every row, then every column (copied out in blocks
/// of 16, so that each row is read a cache line at a time), by the iterative radix-2
/// Cooley–Tukey algorithm.
///
/// # Panics
/// When a size is not a power of two (a caller's bug).
///
/// # References
/// J. W. Cooley, J. W. Tukey: *An algorithm for the machine calculation of complex
/// Fourier series*. Mathematics of Computation 19(90), 1965.
pub(super) fn fft2(data: &mut [Complex], rows: usize, columns: usize, inverse: bool) {
    debug_assert_eq!(data.len(), rows * columns);
    assert!(rows.is_power_of_two() && columns.is_power_of_two());
    let row_twiddles = twiddles(columns, inverse);
    for row in data.chunks_exact_mut(columns) {
        transform(row, &row_twiddles);
    }
    // Columns in blocks of 16, copied out row by row (whole cache lines) and back.
    const BLOCK: usize = 16;
    let column_twiddles = twiddles(rows, inverse);
    let mut block = vec![(0.0, 0.0); rows * BLOCK];
    for first in (0..columns).step_by(BLOCK) {
        let width = BLOCK.min(columns - first);
        for r in 0..rows {
            for k in 0..width {
                block[k * rows + r] = data[r * columns + first + k];
            }
        }
        for column in block.chunks_exact_mut(rows).take(width) {
            transform(column, &column_twiddles);
        }
        for r in 0..rows {
            for k in 0..width {
                data[r * columns + first + k] = block[k * rows + r];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The direct O(N²) transform.
    fn dft(x: &[Complex]) -> Vec<Complex> {
        let n = x.len();
        (0..n)
            .map(|k| {
                x.iter()
                    .enumerate()
                    .fold((0.0, 0.0), |(sr, si), (j, &(xr, xi))| {
                        let (s, c) = (-TAU * (k * j) as f64 / n as f64).sin_cos();
                        (sr + xr * c - xi * s, si + xr * s + xi * c)
                    })
            })
            .collect()
    }

    #[test]
    fn matches_the_direct_transform_and_inverts() {
        let x: Vec<Complex> = (0..16)
            .map(|i| ((i as f64 * 0.7).sin(), (i as f64 * 1.3).cos() - 0.2))
            .collect();
        let mut y = x.clone();
        fft(&mut y, false);
        for (a, b) in y.iter().zip(dft(&x)) {
            assert!((a.0 - b.0).abs() < 1e-12 && (a.1 - b.1).abs() < 1e-12);
        }
        fft(&mut y, true);
        for (a, b) in y.iter().zip(&x) {
            assert!((a.0 / 16.0 - b.0).abs() < 1e-14 && (a.1 / 16.0 - b.1).abs() < 1e-14);
        }
    }

    #[test]
    fn two_dimensional_transform_of_a_plane_wave() {
        // e^{2πi (2r/4 + 3c/8)} has all its energy at (2, 3).
        let (rows, columns) = (4, 8);
        let mut data: Vec<Complex> = (0..rows * columns)
            .map(|k| {
                let (r, c) = ((k / columns) as f64, (k % columns) as f64);
                let phase = TAU * (2.0 * r / 4.0 + 3.0 * c / 8.0);
                (phase.cos(), phase.sin())
            })
            .collect();
        fft2(&mut data, rows, columns, false);
        for (k, &(re, im)) in data.iter().enumerate() {
            let want = if k == 2 * columns + 3 { 32.0 } else { 0.0 };
            assert!(
                (re - want).abs() < 1e-12 && im.abs() < 1e-12,
                "{k}: {re} {im}"
            );
        }
    }
}
