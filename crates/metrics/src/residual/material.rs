//! The areal material ratio curve and what ISO 25178-2 derives from it: Smr(c), Smc(mr),
//! Sxp, the stratified-surface (Sk) family of ISO 13565-2, and the volume parameters.

use beltrami_halfedge::geometry::Geometry;

use super::areal::{ArealOptions, Quadrature, Surface};
use super::integrals::Sum;
use crate::MetricsError;

/// Heights at which [`MaterialRatioCurve::from_mesh`] evaluates the exact interpolant's
/// curve: `LEVELS + 1` equally spaced levels from the highest to the lowest vertex.
const LEVELS: usize = 4096;

/// The width of the window of the equivalent straight line, 40 % (ISO 13565-2).
const CORE_WINDOW: f64 = 0.4;

/// The areal material ratio curve (Abbott–Firestone curve) of a height field: for each
/// height `c`, the fraction `Smr(c)` of the area where the surface is at or above `c`;
/// and its inverse `Smc(mr)`, the height at which the material ratio is `mr`.
///
/// The curve is stored as a monotone polyline of points `(mr, c)`, `mr` rising from 0
/// to 1 and `c` falling from the highest to the lowest height, and is linear between
/// them. Material ratios are given and returned in **percent** (0 to 100) by the
/// public methods; heights are in the field's unit (the positions' unit for a
/// residual), on the datum of the [`ArealOptions`] it was built with.
///
/// # Which curve
/// - **Lumped** (the default, [`Quadrature::Lumped`]): the heights of the vertices, each
///   with its barycentric area as weight (on a regular grid, the trapezoid weights; for
///   grid data with equal weights, the empirical distribution of the samples). Sorted
///   from the highest, vertex `k` stands for the material ratios between `C_{k−1}` and
///   `C_k`, the cumulative weights before and after it; the curve passes through
///   `((C_{k−1} + C_k) / 2, z_k)` (the mid-point, or Hazen, plotting position; vertices
///   of equal height make one point, at the middle of their joint share) and is flat
///   from `mr = 0` to the first point and from the last point to `mr = 1`.
/// - **Exact interpolant** ([`Quadrature::ExactInterpolant`]): the material ratio of
///   the piecewise-linear interpolant, computed exactly at 4097 equally spaced heights
///   from the highest to the lowest vertex value (a triangle with corner values
///   `a ≤ b ≤ c` has the fraction `1 − (t − a)² / ((b − a)(c − a))` of its area above
///   `t ∈ [a, b]` and `(c − t)² / ((c − a)(c − b))` above `t ∈ [b, c]`), linear between.
///
/// The lumped curve is the distribution of the vertex heights: it resolves material
/// ratios to the weight of one distinct height. On areal data, where every vertex has
/// its own height, it converges faster than the exact interpolant's curve (see
/// docs/metrics.md); a profile repeated on every row of a grid has only as many heights
/// as the profile has samples, and there the exact curve is the better one.
///
/// # References
/// - ISO 25178-2:2012, clause 4.4 (functions and related parameters: the areal
///   material ratio function, Smr(c), Smc(mr), Sxp and the volume parameters).
/// - ISO 13565-2:1996, *Surfaces having stratified functional properties — Height
///   characterization using the linear material ratio curve*.
/// - R. Leach (ed.): *Characterisation of Areal Surface Texture*. Springer, 2013, the
///   chapter *The areal field parameters* (F. Blateyron: functions and related
///   parameters).
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialRatioCurve {
    /// `(mr, c)`, `mr` in `[0, 1]` non-decreasing, `c` non-increasing; the first point
    /// has `mr = 0`, the last `mr = 1`.
    points: Vec<(f64, f64)>,
}

/// The stratified-surface parameters of ISO 13565-2 applied to the areal material ratio
/// curve, as ISO 25178-2 prescribes. See [`MaterialRatioCurve::stratified`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StratifiedParameters {
    /// Core height `Sk = c₁ − c₂`, the height difference of the equivalent straight line
    /// between `mr = 0 %` and `mr = 100 %`, in length units.
    pub sk: f64,
    /// Reduced peak height `Spk`, the height of the triangle with base `Smr1` and the
    /// area `Sak1` of the peaks above the core, in length units.
    pub spk: f64,
    /// Reduced dale height `Svk`, the height of the triangle with base `100 % − Smr2` and
    /// the area `Sak2` of the dales below the core, in length units.
    pub svk: f64,
    /// Peak material component `Smr1 = Smr(c₁)`, in percent: the material ratio at the
    /// top of the core.
    pub smr1: f64,
    /// Valley material component `Smr2 = Smr(c₂)`, in percent: the material ratio at
    /// the bottom of the core.
    pub smr2: f64,
    /// Peak area `Sak1 = ∫₀^{Smr1} (Smc(q) − c₁) dq`, with `q` in percent: in
    /// percent × length units, as ISO 13565-2 gives `A1` (divide by 100 for the peak
    /// material volume above the core per unit area).
    pub sak1: f64,
    /// Dale area `Sak2 = ∫_{Smr2}^{100 %} (c₂ − Smc(q)) dq`, in percent × length units,
    /// as ISO 13565-2 gives `A2`.
    pub sak2: f64,
    /// The top of the core `c₁`, the equivalent line's height at `mr = 0 %`.
    pub core_top: f64,
    /// The bottom of the core `c₂`, the equivalent line's height at `mr = 100 %`.
    pub core_bottom: f64,
    /// Where the 40 % window of the equivalent line starts, in percent.
    pub window_start: f64,
}

/// The volume parameters of ISO 25178-2 at the material ratios `p` and `q`. See
/// [`MaterialRatioCurve::volume`].
///
/// Volumes are per unit area, so they have the unit of length: with heights in µm, one
/// µm of volume per area is 1 µm³/µm² = 1 mL/m², the unit ISO 25178-2 quotes them in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VolumeParameters {
    /// Peak material volume `Vmp = Vm(p)`.
    pub vmp: f64,
    /// Core material volume `Vmc = Vm(q) − Vm(p)`.
    pub vmc: f64,
    /// Core void volume `Vvc = Vv(p) − Vv(q)`.
    pub vvc: f64,
    /// Dale void volume `Vvv = Vv(q)`.
    pub vvv: f64,
    /// The material ratio `p`, in percent (10 % by default).
    pub p: f64,
    /// The material ratio `q`, in percent (80 % by default).
    pub q: f64,
}

impl MaterialRatioCurve {
    /// The material ratio curve of a per-vertex field on a triangle mesh, with heights on
    /// `options.datum` and the [`Quadrature`] of `options.quadrature` (see the
    /// [type documentation](Self)).
    ///
    /// # Errors
    /// As [`areal_parameters`](super::areal_parameters): an empty mesh or one of zero
    /// area, a face that is not a triangle, a field of the wrong length, a non-finite
    /// value or position.
    ///
    /// # Complexity
    /// Lumped: O(V log V). Exact: O(F + Σ_T (range of T) / Δ) with `Δ` the level spacing,
    /// 1/4096 of the height range.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::geometry::Geometry;
    /// use beltrami_halfedge::primitives;
    /// use beltrami_metrics::residual::{ArealOptions, MaterialRatioCurve, Quadrature};
    ///
    /// // A tilted plane z = x over [0, 10]: heights uniformly distributed, so the
    /// // curve is the straight line from (0 %, 10) to (100 %, 0).
    /// let grid = primitives::grid(10, 1);
    /// let mesh = grid.mesh()?;
    /// let z: Vec<f64> = grid.positions.iter().map(|p| p.x).collect();
    /// let exact = ArealOptions::default().quadrature(Quadrature::ExactInterpolant);
    /// let curve = MaterialRatioCurve::from_mesh(&Geometry::new(&mesh, &grid.positions)?, &z, &exact)?;
    /// assert!((curve.smr(7.5) - 25.0).abs() < 1e-9);
    /// assert!((curve.smc(40.0)? - 6.0).abs() < 1e-9);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn from_mesh(
        geometry: &Geometry<'_>,
        field: &[f64],
        options: &ArealOptions,
    ) -> Result<Self, MetricsError> {
        let surface = Surface::new(geometry, field)?;
        let shift = surface.shift(options.datum);
        let unscale = |z: f64| (z - shift) / surface.scale;
        match options.quadrature {
            Quadrature::Lumped => {
                let mut samples: Vec<(f64, f64)> = (0..surface.scaled.len())
                    .filter(|&i| surface.vertex_weights[i] > 0.0)
                    .map(|i| (unscale(surface.scaled[i]), surface.vertex_weights[i]))
                    .collect();
                if samples.is_empty() {
                    return Err(MetricsError::Empty { what: "mesh area" });
                }
                Ok(Self::from_sorted(&mut samples))
            }
            Quadrature::ExactInterpolant => {
                let (low, high) = surface.extremes();
                if high <= low {
                    return Ok(Self::flat(unscale(high)));
                }
                let step = (high - low) / LEVELS as f64;
                let level = |j: usize| {
                    if j == LEVELS {
                        low
                    } else {
                        high - step * j as f64
                    }
                };
                // The first level at or below x (levels fall with j; level(LEVELS) = low <= x).
                let first_level_at_or_below = |x: f64| {
                    let mut j = (((high - x) / step).ceil().max(0.0) as usize).min(LEVELS);
                    while j > 0 && level(j - 1) <= x {
                        j -= 1;
                    }
                    while j < LEVELS && level(j) > x {
                        j += 1;
                    }
                    j
                };
                // whole[j]: the weight of the triangles entirely at or above level j, first
                // counted at j; partial[j]: the parts of the others at or above level j.
                let mut whole = vec![0.0; LEVELS + 2];
                let mut partial = vec![Sum::default(); LEVELS + 1];
                for (f, &w) in surface.mesh.faces().zip(&surface.face_weights) {
                    let mut v = surface.face_values(f);
                    v.sort_by(f64::total_cmp);
                    let [a, b, c] = v;
                    // Levels j >= first_full (level(j) <= a) see the whole triangle.
                    let first_full = first_level_at_or_below(a);
                    whole[first_full] += w;
                    if c > a {
                        // Levels strictly inside (a, c) see a part of it.
                        let top = (((high - c) / step).floor().max(0.0) as usize).saturating_sub(1);
                        for (j, slot) in partial.iter_mut().enumerate().take(first_full).skip(top) {
                            let t = level(j);
                            if t >= c {
                                continue;
                            }
                            let fraction = if t <= b {
                                1.0 - (t - a) * (t - a) / ((b - a) * (c - a))
                            } else {
                                (c - t) * (c - t) / ((c - a) * (c - b))
                            };
                            slot.add(w * fraction);
                        }
                    }
                }
                let mut points = Vec::with_capacity(LEVELS + 1);
                let mut cumulative = Sum::default();
                for (j, p) in partial.iter().enumerate() {
                    cumulative.add(whole[j]);
                    let mr =
                        ((cumulative.value() + p.value()) / surface.weight_total).clamp(0.0, 1.0);
                    points.push((mr, unscale(level(j))));
                }
                // Rounding: force the ends and monotonicity.
                points[0].0 = 0.0;
                if let Some(last) = points.last_mut() {
                    last.0 = 1.0;
                }
                for k in 1..points.len() {
                    points[k].0 = points[k].0.max(points[k - 1].0);
                }
                Ok(Self { points })
            }
        }
    }

    /// The material ratio curve of heights with weights (the lumped rule): for grid data,
    /// the heights of the valid points with equal weights, or trapezoid weights. Heights
    /// are taken as they are (subtract a mean first for heights from the mean plane).
    ///
    /// # Errors
    /// - [`MetricsError::FieldLength`] when the lengths differ;
    /// - [`MetricsError::NonFinite`] for a non-finite height (`"height"`) or weight
    ///   (`"weight"`);
    /// - [`MetricsError::InvalidParameter`] for a negative weight;
    /// - [`MetricsError::Empty`] when no weight is positive (`"weights"`).
    ///
    /// # Examples
    /// ```
    /// use beltrami_metrics::residual::MaterialRatioCurve;
    ///
    /// // Four equally weighted heights: each stands for 25 % of the area.
    /// let curve = MaterialRatioCurve::from_weighted_heights(&[3.0, 1.0, 2.0, 0.0], &[1.0; 4])?;
    /// assert_eq!(curve.smc(12.5)?, 3.0); // the mid-point of the highest quarter
    /// assert_eq!(curve.smr(1.5), 50.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn from_weighted_heights(heights: &[f64], weights: &[f64]) -> Result<Self, MetricsError> {
        if heights.len() != weights.len() {
            return Err(MetricsError::FieldLength {
                what: "weights",
                got: weights.len(),
                expected: heights.len(),
            });
        }
        let mut samples = Vec::with_capacity(heights.len());
        for (index, (&z, &w)) in heights.iter().zip(weights).enumerate() {
            if !z.is_finite() {
                return Err(MetricsError::NonFinite {
                    what: "height",
                    index,
                });
            }
            if !w.is_finite() {
                return Err(MetricsError::NonFinite {
                    what: "weight",
                    index,
                });
            }
            if w < 0.0 {
                return Err(MetricsError::InvalidParameter {
                    name: "weights",
                    reason: "must not be negative",
                });
            }
            if w > 0.0 {
                samples.push((z, w));
            }
        }
        if samples.is_empty() {
            return Err(MetricsError::Empty { what: "weights" });
        }
        Ok(Self::from_sorted(&mut samples))
    }

    /// A curve of a constant height.
    fn flat(c: f64) -> Self {
        Self {
            points: vec![(0.0, c), (1.0, c)],
        }
    }

    /// The lumped curve of `(height, weight)` samples (positive weights): sorted from the
    /// highest, each at the mid-point of its share of the material ratio.
    fn from_sorted(samples: &mut [(f64, f64)]) -> Self {
        // Highest first; equal heights in input order (stable sort).
        samples.sort_by(|a, b| b.0.total_cmp(&a.0));
        let total = {
            let mut s = Sum::default();
            samples.iter().for_each(|&(_, w)| s.add(w));
            s.value()
        };
        let mut points = Vec::with_capacity(samples.len() + 2);
        points.push((0.0, samples[0].0));
        let mut before = Sum::default();
        // Samples of equal height form one point, at the middle of their joint share.
        for group in samples.chunk_by(|a, b| a.0 == b.0) {
            let start = before.value();
            group.iter().for_each(|&(_, w)| before.add(w));
            let mid = 0.5 * (start + before.value()) / total;
            points.push((mid.clamp(0.0, 1.0), group[0].0));
        }
        points.push((1.0, samples[samples.len() - 1].0));
        for k in 1..points.len() {
            points[k].0 = points[k].0.max(points[k - 1].0);
        }
        Self { points }
    }

    /// The points `(mr, c)` of the polyline, `mr` as a fraction from 0 to 1 (multiply by
    /// 100 for percent) and `c` the height.
    #[must_use]
    pub fn points(&self) -> &[(f64, f64)] {
        &self.points
    }

    /// The highest height, `Smc(0 %)`.
    #[must_use]
    pub fn highest(&self) -> f64 {
        self.points[0].1
    }

    /// The lowest height, `Smc(100 %)`.
    #[must_use]
    pub fn lowest(&self) -> f64 {
        self.points[self.points.len() - 1].1
    }

    /// The areal material ratio `Smr(c)` in percent: the share of the area at or above
    /// height `c` (0 above the highest point, 100 at or below the lowest). Linear between
    /// the curve's points; where the curve stays at the height `c` over a range of ratios
    /// (a flat stretch), the largest of them.
    ///
    /// # References
    /// ISO 25178-2:2012, clause 4.4 (areal material ratio Smr(c)).
    #[must_use]
    pub fn smr(&self, c: f64) -> f64 {
        100.0 * self.ratio_at(c)
    }

    /// `Smr(c)` as a fraction.
    fn ratio_at(&self, c: f64) -> f64 {
        if c.is_nan() {
            return 0.0;
        }
        // Points at or above c (heights fall along the polyline).
        let n = self.points.partition_point(|&(_, z)| z >= c);
        if n == 0 {
            return 0.0;
        }
        if n == self.points.len() {
            return 1.0;
        }
        let (m0, z0) = self.points[n - 1];
        let (m1, z1) = self.points[n];
        // z0 >= c > z1.
        m0 + (m1 - m0) * (z0 - c) / (z0 - z1)
    }

    /// The inverse areal material ratio `Smc(mr)`: the height at which the material ratio
    /// is `mr`, given in percent (0 to 100), in length units. Linear between the curve's
    /// points; where the curve jumps over a range of heights at one ratio, the highest.
    ///
    /// # Errors
    /// [`MetricsError::InvalidParameter`] for `mr` outside `[0, 100]` or NaN.
    ///
    /// # References
    /// ISO 25178-2:2012, clause 4.4 (inverse areal material ratio Smc(mr)).
    pub fn smc(&self, mr: f64) -> Result<f64, MetricsError> {
        Ok(self.height_at(percent("material ratio", mr)?))
    }

    /// `Smc` at the fraction `q ∈ [0, 1]`.
    fn height_at(&self, q: f64) -> f64 {
        // First point whose ratio reaches q.
        let n = self.points.partition_point(|&(m, _)| m < q);
        if n == 0 {
            return self.points[0].1;
        }
        if n == self.points.len() {
            return self.lowest();
        }
        let (m0, z0) = self.points[n - 1];
        let (m1, z1) = self.points[n];
        if m1 <= m0 {
            return z0;
        }
        z0 + (z1 - z0) * (q - m0) / (m1 - m0)
    }

    /// `∫_a^b g(q, Smc(q)) dq` for `0 ≤ a ≤ b ≤ 1` and a `g` that is at most quadratic
    /// along each linear piece, by Simpson's rule on each piece (exact there).
    fn integrate(&self, a: f64, b: f64, g: impl Fn(f64, f64) -> f64) -> f64 {
        let mut sum = Sum::default();
        if b <= a {
            return 0.0;
        }
        let first = self
            .points
            .partition_point(|&(m, _)| m <= a)
            .saturating_sub(1);
        for k in first..self.points.len() - 1 {
            let (m0, _) = self.points[k];
            let (m1, _) = self.points[k + 1];
            if m0 >= b {
                break;
            }
            let (lo, hi) = (m0.max(a), m1.min(b));
            if hi <= lo {
                continue;
            }
            let at = |q: f64| {
                let z = if m1 > m0 {
                    let (z0, z1) = (self.points[k].1, self.points[k + 1].1);
                    z0 + (z1 - z0) * (q - m0) / (m1 - m0)
                } else {
                    self.points[k].1
                };
                g(q, z)
            };
            let mid = 0.5 * (lo + hi);
            sum.add((hi - lo) / 6.0 * (at(lo) + 4.0 * at(mid) + at(hi)));
        }
        sum.value()
    }

    /// The peak extreme height `Sxp = Smc(p) − Smc(q)`, `p` and `q` in percent (ISO
    /// 25178-3 defaults: `p = 2.5 %`, `q = 50 %`), in length units: the height of the
    /// highest peaks above the median surface, ignoring the top `p` of the area.
    ///
    /// # Errors
    /// [`MetricsError::InvalidParameter`] unless `0 ≤ p ≤ q ≤ 100`.
    ///
    /// # References
    /// ISO 25178-2:2012, clause 4.4 (peak extreme height Sxp); ISO 25178-3:2012 (the
    /// default ratios).
    pub fn sxp(&self, p: f64, q: f64) -> Result<f64, MetricsError> {
        let (p, q) = ordered(p, q)?;
        Ok(self.height_at(p) - self.height_at(q))
    }

    /// The material volume `Vm(mr) = ∫₀^{mr} (Smc(q) − Smc(mr)) dq` at the material ratio
    /// `mr` in percent: the volume of material above the height `Smc(mr)` per unit area,
    /// in length units (mL/m² for µm).
    ///
    /// # Errors
    /// [`MetricsError::InvalidParameter`] for `mr` outside `[0, 100]` or NaN.
    ///
    /// # References
    /// ISO 25178-2:2012, clause 4.4 (material volume Vm(p)).
    pub fn vm(&self, mr: f64) -> Result<f64, MetricsError> {
        let m = percent("material ratio", mr)?;
        let c = self.height_at(m);
        Ok(self.integrate(0.0, m, |_, z| z - c).max(0.0))
    }

    /// The void volume `Vv(mr) = ∫_{mr}^{1} (Smc(mr) − Smc(q)) dq` at the material ratio
    /// `mr` in percent: the volume of space below the height `Smc(mr)` per unit area, in
    /// length units (mL/m² for µm).
    ///
    /// # Errors
    /// [`MetricsError::InvalidParameter`] for `mr` outside `[0, 100]` or NaN.
    ///
    /// # References
    /// ISO 25178-2:2012, clause 4.4 (void volume Vv(p)).
    pub fn vv(&self, mr: f64) -> Result<f64, MetricsError> {
        let m = percent("material ratio", mr)?;
        let c = self.height_at(m);
        Ok(self.integrate(m, 1.0, |_, z| c - z).max(0.0))
    }

    /// The volume parameters at the material ratios `p` and `q` in percent (ISO 25178-3
    /// defaults `p = 10 %`, `q = 80 %`): `Vmp = Vm(p)`, `Vmc = Vm(q) − Vm(p)`,
    /// `Vvc = Vv(p) − Vv(q)`, `Vvv = Vv(q)`, in length units (mL/m² for µm).
    ///
    /// # Errors
    /// [`MetricsError::InvalidParameter`] unless `0 ≤ p ≤ q ≤ 100`.
    ///
    /// # Examples
    /// ```
    /// use beltrami_metrics::residual::MaterialRatioCurve;
    ///
    /// // Heights uniform on [0, 1] (the curve Smc(q) = 1 − q): Vm(p) = p²/2, Vv(p) = (1 − p)²/2.
    /// let z: Vec<f64> = (0..=1000).map(|i| f64::from(i) / 1000.0).collect();
    /// let mut w = vec![1.0; z.len()];
    /// w[0] = 0.5;
    /// w[1000] = 0.5;
    /// let v = MaterialRatioCurve::from_weighted_heights(&z, &w)?.volume(10.0, 80.0)?;
    /// assert!((v.vmp - 0.005).abs() < 1e-5 && (v.vvv - 0.02).abs() < 1e-5);
    /// assert!((v.vmc - (0.32 - 0.005)).abs() < 1e-5 && (v.vvc - (0.405 - 0.02)).abs() < 1e-5);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # References
    /// ISO 25178-2:2012, clause 4.4 (volume parameters Vmp, Vmc, Vvc, Vvv); ISO
    /// 25178-3:2012 (the default ratios).
    pub fn volume(&self, p: f64, q: f64) -> Result<VolumeParameters, MetricsError> {
        ordered(p, q)?;
        let (vm_p, vm_q) = (self.vm(p)?, self.vm(q)?);
        let (vv_p, vv_q) = (self.vv(p)?, self.vv(q)?);
        Ok(VolumeParameters {
            vmp: vm_p,
            vmc: (vm_q - vm_p).max(0.0),
            vvc: (vv_p - vv_q).max(0.0),
            vvv: vv_q,
            p,
            q,
        })
    }

    /// The stratified-surface parameters Sk, Spk, Svk, Smr1, Smr2, Sak1 and Sak2 by the
    /// construction of ISO 13565-2 on the areal material ratio curve:
    ///
    /// 1. The **central region** is the 40 % window `[m, m + 40 %]` of material ratio
    ///    over which the secant of the curve, `(Smc(m + 40 %) − Smc(m)) / 40 %`, has the
    ///    least gradient (the first such window if several tie). The secant's height
    ///    difference is linear in `m` between the curve's points, so its extreme lies at a
    ///    window whose start or end is a point of the curve: those are the candidates.
    /// 2. The **equivalent straight line** is the least-squares line through the curve
    ///    over the central region, deviations in height, the curve weighted uniformly in
    ///    material ratio (integrals of the polyline, not a sum over its points). Its
    ///    heights at 0 % and 100 % are the core limits `c₁` and `c₂`; `Sk = c₁ − c₂`.
    /// 3. `Smr1 = Smr(c₁)` and `Smr2 = Smr(c₂)`.
    /// 4. The peak area `Sak1 = ∫₀^{Smr1} (Smc(q) − c₁) dq` and the dale area
    ///    `Sak2 = ∫_{Smr2}^{100 %} (c₂ − Smc(q)) dq` (in % × length); `Spk` and `Svk` are
    ///    the heights of the triangles of the same areas on the bases `Smr1` and
    ///    `100 % − Smr2`: `Spk = 2 Sak1 / Smr1`, `Svk = 2 Sak2 / (100 % − Smr2)` (0 when
    ///    the base is empty: no peak above the core, no dale below it).
    ///
    /// ISO 13565-2 uses the least-squares line over the region the secant finds, not the
    /// secant itself; for a curve that is straight over the region the two coincide.
    ///
    /// # Examples
    /// ```
    /// use beltrami_metrics::residual::MaterialRatioCurve;
    ///
    /// // Heights uniform on [0, 1]: the curve is a straight line, the core is everything.
    /// let z: Vec<f64> = (0..=1000).map(|i| f64::from(i) / 1000.0).collect();
    /// let s = MaterialRatioCurve::from_weighted_heights(&z, &vec![1.0; z.len()])?.stratified();
    /// assert!((s.sk - 1.0).abs() < 1e-3 && s.spk < 1e-3 && s.svk < 1e-3);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # References
    /// - ISO 13565-2:1996, clause 4 (the equivalent straight line and the parameters
    ///   Rk, Rpk, Rvk, Mr1, Mr2, and the areas A1, A2).
    /// - ISO 25178-2:2012, clause 5 (determination of the areal parameters for
    ///   stratified functional surfaces: ISO 13565-2 applied to the areal material ratio
    ///   curve; 5.1 Sk, Smr1, Smr2).
    #[must_use]
    pub fn stratified(&self) -> StratifiedParameters {
        let height_difference = |m: f64| self.height_at(m + CORE_WINDOW) - self.height_at(m);
        // Candidate window starts: 0, the end 60 %, and every point's ratio (minus 40 %).
        let last_start = 1.0 - CORE_WINDOW;
        let mut starts: Vec<f64> = vec![0.0, last_start];
        for &(m, _) in &self.points {
            for s in [m, m - CORE_WINDOW] {
                if (0.0..=last_start).contains(&s) {
                    starts.push(s);
                }
            }
        }
        starts.sort_by(f64::total_cmp);
        starts.dedup();
        // Least gradient: the height difference (never positive) closest to 0; the first.
        let mut best = (starts[0], height_difference(starts[0]));
        for &m in &starts[1..] {
            let d = height_difference(m);
            if d > best.1 {
                best = (m, d);
            }
        }
        let (a, b) = (best.0, best.0 + CORE_WINDOW);
        // Least-squares line c(q) = α + β (q − centre) over [a, b], uniform in q.
        let centre = 0.5 * (a + b);
        let mean = self.integrate(a, b, |_, z| z) / CORE_WINDOW;
        let moment = self.integrate(a, b, |q, z| (q - centre) * z);
        let beta = (moment / (CORE_WINDOW.powi(3) / 12.0)).min(0.0);
        let core_top = mean - beta * centre;
        let core_bottom = mean + beta * (1.0 - centre);
        let mr1 = self.ratio_at(core_top);
        let mr2 = self.ratio_at(core_bottom);
        let peaks = self.integrate(0.0, mr1, |_, z| z - core_top).max(0.0);
        let dales = self.integrate(mr2, 1.0, |_, z| core_bottom - z).max(0.0);
        StratifiedParameters {
            sk: core_top - core_bottom,
            spk: if mr1 > 0.0 { 2.0 * peaks / mr1 } else { 0.0 },
            svk: if mr2 < 1.0 {
                2.0 * dales / (1.0 - mr2)
            } else {
                0.0
            },
            smr1: 100.0 * mr1,
            smr2: 100.0 * mr2,
            sak1: 100.0 * peaks,
            sak2: 100.0 * dales,
            core_top,
            core_bottom,
            window_start: 100.0 * a,
        }
    }
}

/// A material ratio in percent as a fraction, or an error outside `[0, 100]`.
fn percent(name: &'static str, mr: f64) -> Result<f64, MetricsError> {
    if (0.0..=100.0).contains(&mr) {
        Ok(mr / 100.0)
    } else {
        Err(MetricsError::InvalidParameter {
            name,
            reason: "must be a percentage from 0 to 100",
        })
    }
}

/// `(p, q)` as fractions, checked `0 ≤ p ≤ q ≤ 100`.
fn ordered(p: f64, q: f64) -> Result<(f64, f64), MetricsError> {
    let (p, q) = (
        percent("material ratio p", p)?,
        percent("material ratio q", q)?,
    );
    if p > q {
        return Err(MetricsError::InvalidParameter {
            name: "material ratios",
            reason: "p must not exceed q",
        });
    }
    Ok((p, q))
}
