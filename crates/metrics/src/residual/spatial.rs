//! The spatial parameters Sal and Str (from the autocorrelation function) and the
//! texture direction Std (from the angular power spectrum) of a height grid.

use std::f64::consts::PI;

use super::fft::{Complex, fft2};
use super::grid::HeightGrid;
use super::integrals::Sum;
use crate::MetricsError;

/// Directions of the autocorrelation's decay searched over half a turn (0.25° apart).
const DIRECTIONS: usize = 720;

/// The angular bins of the power spectrum over half a turn (0.5° wide).
const ANGLE_BINS: usize = 360;

/// Choices of [`spatial_parameters`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct SpatialOptions {
    /// The value `s` the autocorrelation decays to for Sal and Str, `0 < s < 1`
    /// (default 0.2, the ISO 25178-3 default).
    pub threshold: f64,
}

impl SpatialOptions {
    /// Sets [`threshold`](Self::threshold): the value the autocorrelation decays to, `0 < s < 1`.
    #[must_use]
    pub fn threshold(mut self, threshold: f64) -> Self {
        self.threshold = threshold;
        self
    }
}

impl Default for SpatialOptions {
    fn default() -> Self {
        Self { threshold: 0.2 }
    }
}

/// The spatial parameters of a height grid. See [`spatial_parameters`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpatialParameters {
    /// The autocorrelation length `Sal`: the shortest lag at which the autocorrelation
    /// falls to `s`, in length units. `None` when it falls to `s` in no direction within
    /// the lags the grid supports, or the heights are constant.
    pub sal: Option<f64>,
    /// The texture aspect ratio `Str = Sal / L`, with `L` the longest lag at which the
    /// autocorrelation falls to `s` (over the directions), dimensionless in `(0, 1]`:
    /// near 0 for a strongly directional texture, near 1 for an isotropic one. Where the
    /// autocorrelation does not fall to `s` in some direction within the supported lags,
    /// `L` is at least the longest supported lag, and `Str` is an upper bound.
    pub str: Option<f64>,
    /// Whether the autocorrelation fell to `s` in every direction (otherwise `str` is an
    /// upper bound).
    pub decays_in_every_direction: bool,
    /// The texture direction `Std`: the direction of the dominant lay, in degrees
    /// counter-clockwise from the grid's x axis, in `[0, 180)`. `None` for constant
    /// heights.
    pub std: Option<f64>,
}

/// The spatial parameters Sal, Str and Std of a height grid (ISO 25178-2), over its valid
/// points. The heights are first taken from their mean over the valid points.
///
/// **Autocorrelation.** With `z` the heights and `m` the indicator of valid points,
/// `f_ACF(t) = [Σ_x z(x) z(x + t) / Σ_x m(x) m(x + t)] / [Σ_x z(x)² / Σ_x m(x)]`: the
/// mean product of the pairs of valid points at the lag `t`, relative to the mean
/// square (the unbiased estimator, normalised by the overlap, which does not shrink at
/// long lags the way the estimator over the whole area does). Lags are supported where
/// at least a quarter of the valid points have a valid partner. The sums are computed
/// through one zero-padded FFT of `z + i m`.
///
/// **Sal and Str.** Along 720 directions over half a turn (the function is even), the
/// first lag at which `f_ACF` falls to `s` is found by stepping a quarter of the grid
/// spacing, with bicubic (Catmull–Rom) interpolation between lags, and refined by
/// bisection. `Sal` is the shortest of those lags (the fastest decay); `Str` is `Sal`
/// over the longest (the slowest decay). For a sine of wavelength `λ`, `f_ACF = cos(2π
/// t_x / λ)`, so `Sal = arccos(s) λ / 2π` (0.2180 λ at `s = 0.2`) and `Str → 0`.
///
/// **Std.** The angular power spectrum is the power `|F|²` of the heights' Fourier
/// transform (Hann-windowed, zero-padded) summed over wedges of 0.5° of the frequency
/// plane; at its maximum the frequency vector points across the lay, and Std is the
/// direction of the lay itself, 90° from it, refined by the power-weighted mean
/// direction within ±1.5° of the maximum. So a sine `z = sin(2π x / λ)`, whose crests
/// run along y, has `Std = 90°`, and grooves along x have `Std = 0°`.
///
/// # Errors
/// - [`MetricsError::InvalidParameter`] for a threshold outside `(0, 1)`;
/// - [`MetricsError::Empty`] (`"height grid"`) for a grid with fewer than 2 points along
///   x or y, or fewer than 4 valid points.
///
/// # Complexity
/// O(P log P) for the `P ≈ 4 nx ny` points of the padded transforms, plus
/// O(720 · lag range / spacing) for the decay search.
///
/// # Examples
/// ```
/// use beltrami_metrics::residual::{spatial_parameters, HeightGrid, SpatialOptions};
///
/// // Ridges along y: z = sin(2π x / 16) on a 129 × 129 grid of unit spacing.
/// let n = 129;
/// let heights = (0..n * n)
///     .map(|k| Some((std::f64::consts::TAU * (k % n) as f64 / 16.0).sin()))
///     .collect();
/// let grid = HeightGrid::new(n, n, 1.0, 1.0, heights)?;
/// let s = spatial_parameters(&grid, &SpatialOptions::default())?;
/// let sal = 0.2f64.acos() * 16.0 / std::f64::consts::TAU;
/// assert!((s.sal.unwrap() - sal).abs() < 0.02 * sal); // a finite grid: 8 periods
/// assert!(s.str.unwrap() < 0.1);
/// assert!((s.std.unwrap() - 90.0).abs() < 0.1);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # References
/// - ISO 25178-2:2012, clauses 3.1 (the autocorrelation function and the angular
///   spectrum), 4.2 (spatial parameters: 4.2.1 Sal, 4.2.2 Str) and 4.5 (miscellaneous
///   parameters: the texture direction Std); ISO 25178-3:2012 (the default `s = 0.2`).
/// - R. Leach (ed.): *Characterisation of Areal Surface Texture*. Springer, 2013, the
///   chapter *The areal field parameters* (F. Blateyron: spatial parameters).
pub fn spatial_parameters(
    grid: &HeightGrid,
    options: &SpatialOptions,
) -> Result<SpatialParameters, MetricsError> {
    let s = options.threshold;
    if !(s > 0.0 && s < 1.0) {
        return Err(MetricsError::InvalidParameter {
            name: "autocorrelation threshold",
            reason: "must lie strictly between 0 and 1",
        });
    }
    let (nx, ny) = (grid.nx(), grid.ny());
    let valid = grid.valid_count();
    if nx < 2 || ny < 2 || valid < 4 {
        return Err(MetricsError::Empty {
            what: "height grid",
        });
    }
    let mean = {
        let mut sum = Sum::default();
        grid.heights().iter().flatten().for_each(|&h| sum.add(h));
        sum.value() / valid as f64
    };
    let z: Vec<f64> = grid
        .heights()
        .iter()
        .map(|h| h.map_or(0.0, |h| h - mean))
        .collect();
    let largest = z.iter().fold(0.0f64, |m, &v| m.max(v.abs()));
    if largest == 0.0 {
        return Ok(SpatialParameters {
            sal: None,
            str: None,
            decays_in_every_direction: false,
            std: None,
        });
    }
    // Scale to unit size (the parameters do not depend on the heights' scale).
    let z: Vec<f64> = z.iter().map(|&v| v / largest).collect();
    let acf = Autocorrelation::new(grid, &z);
    let (sal, str, decays_in_every_direction) = acf.decay(s);
    Ok(SpatialParameters {
        sal,
        str,
        decays_in_every_direction,
        std: texture_direction(grid, &z),
    })
}

/// The autocorrelation on the lag grid `(a, b)`, `|a| < nx`, `|b| < ny`.
struct Autocorrelation {
    /// Padded sizes (powers of two, at least `2n − 1`).
    columns: usize,
    rows: usize,
    nx: usize,
    ny: usize,
    dx: f64,
    dy: f64,
    /// `f_ACF` at each padded index, `None` where unsupported.
    values: Vec<Option<f64>>,
}

impl Autocorrelation {
    fn new(grid: &HeightGrid, z: &[f64]) -> Self {
        let (nx, ny) = (grid.nx(), grid.ny());
        let columns = (2 * nx - 1).next_power_of_two();
        let rows = (2 * ny - 1).next_power_of_two();
        // Both correlations from one complex transform of f = z + i m: with F its
        // transform, Z(k) = (F(k) + F̄(−k)) / 2 and M(k) = (F(k) − F̄(−k)) / 2i, and the
        // inverse transform of |Z|² + i |M|² is Σ z z' + i Σ m m'.
        let heights = grid.heights();
        let mut data: Vec<Complex> = vec![(0.0, 0.0); rows * columns];
        for j in 0..ny {
            for i in 0..nx {
                let k = j * nx + i;
                let m = if heights[k].is_some() { 1.0 } else { 0.0 };
                data[j * columns + i] = (z[k], m);
            }
        }
        fft2(&mut data, rows, columns, false);
        let mut power = vec![(0.0, 0.0); rows * columns];
        for r in 0..rows {
            for c in 0..columns {
                let (fr, fi) = data[r * columns + c];
                let (gr, gi) = data[((rows - r) % rows) * columns + (columns - c) % columns];
                // F̄(−k) = (gr, −gi).
                let (zr, zi) = (0.5 * (fr + gr), 0.5 * (fi - gi));
                let (mr, mi) = (0.5 * (fi + gi), -0.5 * (fr - gr));
                power[r * columns + c] = (zr * zr + zi * zi, mr * mr + mi * mi);
            }
        }
        fft2(&mut power, rows, columns, true);
        let n = (rows * columns) as f64;
        let products: Vec<f64> = power.iter().map(|c| c.0 / n).collect();
        let pairs: Vec<f64> = power.iter().map(|c| c.1 / n).collect();
        let valid = pairs[0].round();
        let mean_square = products[0] / valid;
        let values = products
            .iter()
            .zip(&pairs)
            .map(|(&p, &c)| {
                let c = c.round();
                (c >= 0.25 * valid && c > 0.0).then(|| p / c / mean_square)
            })
            .collect();
        Self {
            columns,
            rows,
            nx,
            ny,
            dx: grid.dx(),
            dy: grid.dy(),
            values,
        }
    }

    /// `f_ACF` at the integer lag `(a, b)`, `None` outside the supported lags.
    fn at(&self, a: i64, b: i64) -> Option<f64> {
        if a.unsigned_abs() as usize >= self.nx || b.unsigned_abs() as usize >= self.ny {
            return None;
        }
        let i = a.rem_euclid(self.columns as i64) as usize;
        let j = b.rem_euclid(self.rows as i64) as usize;
        self.values[j * self.columns + i]
    }

    /// `f_ACF` at the lag `(tx, ty)` in length units, bicubic (Catmull–Rom) between
    /// lags; `None` unless the 4 × 4 lags around it are supported.
    fn interpolate(&self, tx: f64, ty: f64) -> Option<f64> {
        let (x, y) = (tx / self.dx, ty / self.dy);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (a, b) = (x0 as i64, y0 as i64);
        let mut rows = [0.0; 4];
        for (row, db) in rows.iter_mut().zip(-1..=2) {
            let mut v = [0.0; 4];
            for (slot, da) in v.iter_mut().zip(-1..=2) {
                *slot = self.at(a + da, b + db)?;
            }
            *row = catmull_rom(v, fx);
        }
        Some(catmull_rom(rows, fy))
    }

    /// `(Sal, Str, decayed in every direction)` for the threshold `s`.
    fn decay(&self, s: f64) -> (Option<f64>, Option<f64>, bool) {
        let step = 0.25 * self.dx.min(self.dy);
        let mut fastest: Option<f64> = None;
        let mut slowest = 0.0f64;
        let mut every = true;
        for k in 0..DIRECTIONS {
            let theta = PI * k as f64 / DIRECTIONS as f64;
            let (dir_x, dir_y) = (theta.cos(), theta.sin());
            let mut r = 0.0;
            let length = loop {
                let next = r + step;
                match self.interpolate(next * dir_x, next * dir_y) {
                    Some(value) if value <= s => {
                        // Bisection of the crossing between r (above s) and next.
                        let (mut above, mut below) = (r, next);
                        for _ in 0..40 {
                            let mid = 0.5 * (above + below);
                            match self.interpolate(mid * dir_x, mid * dir_y) {
                                Some(v) if v > s => above = mid,
                                _ => below = mid,
                            }
                        }
                        break Some(0.5 * (above + below));
                    }
                    Some(_) => r = next,
                    None => break None,
                }
            };
            match length {
                Some(l) => {
                    fastest = Some(fastest.map_or(l, |f| f.min(l)));
                    slowest = slowest.max(l);
                }
                None => {
                    every = false;
                    slowest = slowest.max(r);
                }
            }
        }
        let str = fastest.map(|f| {
            if slowest > 0.0 {
                (f / slowest).min(1.0)
            } else {
                1.0
            }
        });
        (fastest, str, every)
    }
}

/// The Catmull–Rom cubic through `v[1]` (at 0) and `v[2]` (at 1), with slopes from the
/// neighbours, at `t ∈ [0, 1]`.
fn catmull_rom(v: [f64; 4], t: f64) -> f64 {
    let [p0, p1, p2, p3] = v;
    let t2 = t * t;
    0.5 * (2.0 * p1
        + (p2 - p0) * t
        + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t2
        + (3.0 * p1 - p0 - 3.0 * p2 + p3) * t2 * t)
}

/// Std in degrees from the angular power spectrum of the (mean-free, scaled) heights `z`;
/// `None` when the spectrum holds no power off the zero frequency.
fn texture_direction(grid: &HeightGrid, z: &[f64]) -> Option<f64> {
    let (nx, ny) = (grid.nx(), grid.ny());
    let columns = (2 * nx).next_power_of_two();
    let rows = (2 * ny).next_power_of_two();
    let hann = |i: usize, n: usize| 0.5 - 0.5 * (2.0 * PI * i as f64 / (n - 1) as f64).cos();
    let mut data: Vec<Complex> = vec![(0.0, 0.0); rows * columns];
    for j in 0..ny {
        for i in 0..nx {
            data[j * columns + i] = (z[j * nx + i] * hann(i, nx) * hann(j, ny), 0.0);
        }
    }
    fft2(&mut data, rows, columns, false);
    // Frequencies (cycles per length) of index k of a transform of size n and spacing d.
    let frequency = |k: usize, n: usize, d: f64| {
        let signed = if k > n / 2 {
            k as f64 - n as f64
        } else {
            k as f64
        };
        signed / (n as f64 * d)
    };
    let bin_width = 180.0 / ANGLE_BINS as f64;
    let mut spectrum = vec![Sum::default(); ANGLE_BINS];
    let mut samples = Vec::with_capacity(rows * columns);
    for (index, &(re, im)) in data.iter().enumerate() {
        let (ky, kx) = (index / columns, index % columns);
        if kx == 0 && ky == 0 {
            continue;
        }
        let power = re * re + im * im;
        let (fx, fy) = (
            frequency(kx, columns, grid.dx()),
            frequency(ky, rows, grid.dy()),
        );
        let angle = fy.atan2(fx).to_degrees().rem_euclid(180.0);
        let bin = ((angle / bin_width).round() as usize) % ANGLE_BINS;
        spectrum[bin].add(power);
        samples.push((angle, power));
    }
    let (peak, _) = spectrum
        .iter()
        .enumerate()
        .map(|(k, s)| (k, s.value()))
        .fold(
            (0, 0.0),
            |best, (k, v)| if v > best.1 { (k, v) } else { best },
        );
    let centre = peak as f64 * bin_width;
    // Power-weighted mean direction (on doubled angles, so 0° and 180° meet) near the peak.
    let (mut c, mut s) = (Sum::default(), Sum::default());
    for &(angle, power) in &samples {
        let offset = (angle - centre + 90.0).rem_euclid(180.0) - 90.0;
        if offset.abs() <= 1.5 + 0.5 * bin_width {
            let doubled = (2.0 * angle).to_radians();
            c.add(power * doubled.cos());
            s.add(power * doubled.sin());
        }
    }
    if c.value() == 0.0 && s.value() == 0.0 {
        return None;
    }
    let across = 0.5 * s.value().atan2(c.value()).to_degrees();
    let lay = (across + 90.0).rem_euclid(180.0);
    // 180° itself (by rounding) is 0°.
    Some(if lay >= 180.0 { 0.0 } else { lay })
}
