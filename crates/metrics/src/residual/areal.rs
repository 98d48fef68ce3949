//! ISO 25178-2 areal field parameters of a per-vertex scalar field on a triangle mesh.

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::{FaceId, HalfedgeMesh, TopologyError};

use super::integrals::{Sum, gradient, mean_abs, mean_powers, pow2_inverse};
use crate::MetricsError;
use crate::distortion::check_finite_positions;

/// The datum heights are measured from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Datum {
    /// The field as given: heights from the reference surface (the smoothed form). This is
    /// ISO 25178-2's definition, whose heights are taken from the reference surface of the
    /// scale-limited surface.
    #[default]
    ReferenceSurface,
    /// The field minus its area-weighted mean `μ = (1/A) ∫ r dA`: heights from the mean
    /// level, as for a levelled planar surface. Changes Sa, Sq, Sp, Sv, Sz, Ssk and Sku;
    /// Sdq and Sdr do not depend on a constant.
    Mean,
}

/// How integrals of a height over the surface are evaluated (the mean of `|z|`, `z²`,
/// `z³`, `z⁴` and the material ratio curve).
///
/// Both rules see the heights only at the vertices. They differ in what they assume
/// between them:
///
/// - [`Lumped`](Self::Lumped) weights each vertex value by its barycentric area `A_i` (a
///   third of the area of each triangle around it): `∫ g(z) dA ≈ Σ_i A_i g(z_i)`. On a
///   regular grid this is the trapezoid rule, and like it, it converges quickly to the
///   integral of the smooth surface the vertices sample: its error is second order in
///   the edge length with a small constant, and for a texture that is periodic over the
///   grid it is spectrally accurate. Instrument software averages the heights of its grid
///   points with equal weights; the trapezoid rule differs from that only in halving the
///   weights of the boundary points.
/// - [`ExactInterpolant`](Self::ExactInterpolant) integrates `g` of the piecewise-linear
///   interpolant of the vertex values exactly. That interpolant cuts across every crest
///   and trough, so for `g(z) = z²` it lies below the smooth surface's value (a sine
///   sampled at phase steps `h` keeps only the factor `sqrt((2 + cos h) / 3)` of its Sq);
///   it converges at second order from below, with a constant several hundred times
///   larger on the texture of docs/metrics.md. Use it to characterise the triangulated
///   surface itself.
///
/// The mean height `(1/A) ∫ z dA` is the same under both rules (the lumped rule is exact
/// for functions linear on each triangle); Sp and Sv are vertex extremes and Sdq, Sdr
/// per-triangle gradients under both. For the material ratio curve see
/// [`MaterialRatioCurve`](super::MaterialRatioCurve).
///
/// # References
/// - ISO 25178-2:2012, clause 4 (the field parameters as integrals over the definition
///   area, which a discrete surface approximates).
/// - R. Leach (ed.): *Characterisation of Areal Surface Texture*. Springer, 2013, the
///   chapter *The areal field parameters* (F. Blateyron: the parameters as means over the
///   grid points).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Quadrature {
    /// Area-weighted vertex values, `Σ_i A_i g(z_i) / Σ_i A_i` (the default).
    #[default]
    Lumped,
    /// Exact integrals of the piecewise-linear interpolant of the vertex values.
    ExactInterpolant,
}

/// The choices behind the areal parameters of a field on a mesh: the datum heights are
/// measured from and the quadrature of the height integrals.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub struct ArealOptions {
    /// The datum (default: the reference surface, as ISO 25178-2 defines).
    pub datum: Datum,
    /// The quadrature of the height parameters (default: lumped).
    pub quadrature: Quadrature,
}

impl ArealOptions {
    /// Sets [`datum`](Self::datum): the datum heights are measured from.
    #[must_use]
    pub fn datum(mut self, datum: Datum) -> Self {
        self.datum = datum;
        self
    }

    /// Sets [`quadrature`](Self::quadrature): the quadrature of the height integrals.
    #[must_use]
    pub fn quadrature(mut self, quadrature: Quadrature) -> Self {
        self.quadrature = quadrature;
        self
    }
}

/// The ISO 25178-2 areal field parameters of a residual surface. See
/// [`areal_parameters`] for the definitions; [module documentation](super) for the
/// formulas.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArealParameters {
    /// Arithmetic mean height `Sa = (1/A) ∫ |r| dA`, in length units.
    pub sa: f64,
    /// Root mean square height `Sq = sqrt((1/A) ∫ r² dA)`, in length units.
    pub sq: f64,
    /// Maximum peak height `Sp = max r`, in length units.
    pub sp: f64,
    /// Maximum pit height `Sv = |min r|`, in length units, a positive number.
    pub sv: f64,
    /// Maximum height `Sz = Sp + Sv`, in length units.
    pub sz: f64,
    /// Skewness `Ssk = (1/Sq³) (1/A) ∫ r³ dA`, dimensionless; `None` when `Sq = 0`.
    pub ssk: Option<f64>,
    /// Kurtosis `Sku = (1/Sq⁴) (1/A) ∫ r⁴ dA`, dimensionless; `None` when `Sq = 0`.
    pub sku: Option<f64>,
    /// Root mean square gradient `Sdq = sqrt((1/A) Σ_T A_T |∇r|²)`, dimensionless.
    pub sdq: f64,
    /// Developed interfacial area ratio `Sdr = (1/A) Σ_T A_T (sqrt(1 + |∇r|²) − 1)`,
    /// dimensionless (multiply by 100 for the percentage usually quoted).
    pub sdr: f64,
    /// The area `A = Σ_T A_T` of the surface, in length units squared.
    pub area: f64,
    /// The area-weighted mean `μ = (1/A) ∫ r dA` of the field as given (before any
    /// datum shift), in length units.
    pub mean: f64,
    /// The datum the heights were measured from.
    pub datum: Datum,
    /// The quadrature of Sa, Sq, Ssk and Sku.
    pub quadrature: Quadrature,
}

/// The ISO 25178-2 areal field parameters of a per-vertex scalar field `r` (a residual
/// surface, in length units) on a triangle mesh whose positions give the geometry.
///
/// Heights are `z = r` as given ([`Datum::ReferenceSurface`], the standard's definition
/// for a residual from the reference form) or `z = r − μ` ([`Datum::Mean`]). With `A_T`
/// the area of triangle `T`, `A = Σ A_T`, and `A_i` the barycentric area of vertex `i`:
///
/// - `Sa = (1/A) ∫ |z|`, `Sq = sqrt((1/A) ∫ z²)`, `Ssk = (1/Sq³)(1/A) ∫ z³`,
///   `Sku = (1/Sq⁴)(1/A) ∫ z⁴`, each integral by the [`Quadrature`] of `options`: by
///   default the lumped rule `∫ g(z) ≈ Σ_i A_i g(z_i)` (the trapezoid rule on a grid,
///   which converges to the sampled smooth surface's values), or the exact integrals of
///   the piecewise-linear interpolant of the [module documentation](super) (`|z|` split
///   at the zero line);
/// - `μ = (1/A) Σ_T A_T (r_a + r_b + r_c)/3`, the same under both rules;
/// - `Sp = max z`, `Sv = |min z|`, `Sz = Sp + Sv` over the vertices of the faces (a
///   linear interpolant takes its extremes at vertices). As in the standard `Sv` is a
///   positive depth; with [`Datum::ReferenceSurface`] and a field that does not change
///   sign, `Sz` is then not the range `max − min` (use [`Datum::Mean`] for a range);
/// - `Sdq` and `Sdr` treat `z` as a height field over the reference form: on each
///   triangle, `∇z` is the gradient of the linear interpolant in the triangle's own plane,
///   `Sdq = sqrt(Σ A_T |∇z|² / A)` and `Sdr = Σ A_T (sqrt(1 + |∇z|²) − 1) / A`
///   (evaluated as `|∇z|² / (sqrt(1 + |∇z|²) + 1)`, without cancellation): exact for the
///   triangulated surface, which is the developed area of Stout et al. that instrument
///   software also uses. Degenerate triangles (see [`Geometry::is_degenerate_face`]) have
///   no gradient and add nothing to these two sums (their area is negligible).
///
/// Units: `Sa, Sq, Sp, Sv, Sz` in the unit of `r` (the positions' unit for a residual);
/// `Ssk, Sku, Sdq, Sdr` dimensionless. Sums are compensated and the field is scaled by a
/// power of two (exactly) before taking powers, so the moments neither overflow nor
/// underflow.
///
/// # Errors
/// - [`MetricsError::Empty`] when the mesh has no face (`what = "mesh"`) or its faces
///   have zero total area (`what = "mesh area"`);
/// - [`MetricsError::Topology`] with [`TopologyError::NotTriangle`] for a face that is not
///   a triangle;
/// - [`MetricsError::FieldLength`] when `field` does not have one value per vertex;
/// - [`MetricsError::NonFinite`] for a NaN or infinite value (`what = "residual value"`)
///   or position (`what = "position"`), or a face area beyond the range of `f64`
///   (`what = "face area"`).
///
/// # Complexity
/// O(V + F).
///
/// # Examples
/// ```
/// use beltrami_halfedge::geometry::Geometry;
/// use beltrami_halfedge::primitives;
/// use beltrami_metrics::residual::{areal_parameters, ArealOptions, Datum, Quadrature};
///
/// // A plane rising at 45° over a flat grid: Sdq = 1, Sdr = √2 − 1.
/// let grid = primitives::grid(8, 8);
/// let mesh = grid.mesh()?;
/// let geometry = Geometry::new(&mesh, &grid.positions)?;
/// let r: Vec<f64> = grid.positions.iter().map(|p| p.x).collect();
/// let options = ArealOptions::default().datum(Datum::Mean);
/// let s = areal_parameters(&geometry, &r, &options)?;
/// assert!((s.sdq - 1.0).abs() < 1e-12);
/// assert!((s.sdr - (2f64.sqrt() - 1.0)).abs() < 1e-12);
/// // |x − 4| on the grid's columns by the trapezoid rule: (2·(1+2+3) + 4/2·2) / 8.
/// assert!((s.sa - 2.0).abs() < 1e-12 && (s.sz - 8.0).abs() < 1e-12);
/// // The interpolant's Sq² is the exact mean of (x − 4)² over [0, 8]: 16/3.
/// let exact = options.quadrature(Quadrature::ExactInterpolant);
/// let s = areal_parameters(&geometry, &r, &exact)?;
/// assert!((s.sq * s.sq - 16.0 / 3.0).abs() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # References
/// - ISO 25178-2:2012, *Geometrical product specifications (GPS) — Surface texture:
///   Areal — Part 2: Terms, definitions and surface texture parameters*, clauses 4.1
///   (height parameters Sq, Ssk, Sku, Sp, Sv, Sz, Sa: 4.1.1 to 4.1.7) and 4.3 (hybrid
///   parameters Sdq 4.3.1, Sdr 4.3.2).
/// - R. Leach (ed.): *Characterisation of Areal Surface Texture*. Springer, 2013, the
///   chapter *The areal field parameters* (F. Blateyron; discrete formulas on grids).
/// - K. J. Stout et al.: *The development of methods for the characterisation of roughness
///   in three dimensions*. EUR 15178 EN, 1993 (the triangulated surface area behind Sdr).
/// - L. Pagani, Q. Qi, X. Jiang, P. J. Scott: *Towards a new definition of areal surface
///   texture parameters on freeform surface*. Measurement 109 (2017), doi
///   10.1016/j.measurement.2017.05.028.
pub fn areal_parameters(
    geometry: &Geometry<'_>,
    field: &[f64],
    options: &ArealOptions,
) -> Result<ArealParameters, MetricsError> {
    let surface = Surface::new(geometry, field)?;
    let shift = surface.shift(options.datum);
    let (absolute, moments) = height_integrals(&surface, shift, options.quadrature);
    let slopes = face_slopes(geometry, &surface);
    let (sdq, sdr) = slope_parameters(&slopes, surface.weight_total);
    let mean_of = |s: &Sum| s.value() / surface.weight_total;
    let m2 = mean_of(&moments[1]).max(0.0);
    let m3 = mean_of(&moments[2]);
    let m4 = mean_of(&moments[3]).max(0.0);
    let (low, high) = surface.extremes();
    let sp = (high - shift) / surface.scale;
    let sv = (low - shift).abs() / surface.scale;
    Ok(ArealParameters {
        sa: mean_of(&absolute) / surface.scale,
        sq: m2.sqrt() / surface.scale,
        sp,
        sv,
        sz: sp + sv,
        ssk: (m2 > 0.0).then(|| m3 / (m2 * m2.sqrt())),
        sku: (m2 > 0.0).then(|| m4 / (m2 * m2)),
        sdq,
        sdr,
        area: surface.area,
        mean: surface.mean_scaled / surface.scale,
        datum: options.datum,
        quadrature: options.quadrature,
    })
}

/// The weighted integrals of `|z|` and of `z, z², z³, z⁴` over the surface, with
/// `z = scaled field − shift`, by `quadrature` (unnormalised: divide by the weight total
/// for means).
fn height_integrals(surface: &Surface<'_>, shift: f64, quadrature: Quadrature) -> (Sum, [Sum; 4]) {
    let mut moments = [Sum::default(); 4];
    let mut absolute = Sum::default();
    match quadrature {
        Quadrature::Lumped => {
            for (&z, &w) in surface.scaled.iter().zip(&surface.vertex_weights) {
                if w > 0.0 {
                    let z = z - shift;
                    let (z2, wz) = (z * z, w * z);
                    absolute.add(w * z.abs());
                    moments[0].add(wz);
                    moments[1].add(wz * z);
                    moments[2].add(wz * z2);
                    moments[3].add(w * z2 * z2);
                }
            }
        }
        Quadrature::ExactInterpolant => {
            for (f, &w) in surface.mesh.faces().zip(&surface.face_weights) {
                let r = surface.face_values(f).map(|r| r - shift);
                for (m, p) in moments.iter_mut().zip(mean_powers(r)) {
                    m.add(w * p);
                }
                absolute.add(w * mean_abs(r));
            }
        }
    }
    (absolute, moments)
}

/// `(weight, |∇r|)` of every non-degenerate face with a gradient, in face order, for Sdq
/// and Sdr.
fn face_slopes(geometry: &Geometry<'_>, surface: &Surface<'_>) -> Vec<(f64, f64)> {
    let mesh = geometry.mesh();
    let mut slopes = Vec::with_capacity(mesh.n_faces());
    for (f, &w) in mesh.faces().zip(&surface.face_weights) {
        if geometry.is_degenerate_face(f) {
            continue;
        }
        let corners = mesh.triangle_vertices(f).map(|v| geometry.position(v));
        if let Some((g, edge_scale)) = gradient(corners, surface.face_values(f)) {
            // ∇r = g · edge_scale / scale: the field was scaled by `scale`.
            slopes.push((w, g.length() * (edge_scale / surface.scale)));
        }
    }
    slopes
}

/// A validated field on a triangle mesh, prepared for integration: face and vertex
/// weights (areas scaled by a power of two so that their sums cannot overflow) and the
/// field scaled by a power of two into `[-2, 2)` over the vertices of the faces.
pub(super) struct Surface<'a> {
    pub(super) mesh: &'a HalfedgeMesh,
    /// `A_T · area_scale` per face.
    pub(super) face_weights: Vec<f64>,
    /// `A_i · area_scale` per vertex: a third of the weights of its faces (0 for a vertex
    /// of no face).
    pub(super) vertex_weights: Vec<f64>,
    /// Whether each vertex belongs to a face.
    on_surface: Vec<bool>,
    /// `Σ face_weights` (= `Σ vertex_weights` up to rounding).
    pub(super) weight_total: f64,
    /// The surface area `A`.
    pub(super) area: f64,
    /// The field times `scale`.
    pub(super) scaled: Vec<f64>,
    /// The power of two the field was multiplied by.
    pub(super) scale: f64,
    /// The area-weighted mean of `scaled`.
    pub(super) mean_scaled: f64,
}

impl<'a> Surface<'a> {
    /// Validates the mesh, positions and field (see [`areal_parameters`] for the errors)
    /// and prepares the weights.
    pub(super) fn new(geometry: &Geometry<'a>, field: &[f64]) -> Result<Self, MetricsError> {
        let mesh = geometry.mesh();
        validate(mesh, field)?;
        check_finite_positions(geometry.positions())?;

        let mut areas = Vec::with_capacity(mesh.n_faces());
        let mut total = Sum::default();
        for f in mesh.faces() {
            let a = geometry.face_area(f);
            if !a.is_finite() {
                return Err(MetricsError::NonFinite {
                    what: "face area",
                    index: f.index(),
                });
            }
            areas.push(a);
            total.add(a);
        }
        let area = total.value();
        let largest_area = areas.iter().fold(0.0f64, |m, &a| m.max(a));
        if largest_area == 0.0 {
            return Err(MetricsError::Empty { what: "mesh area" });
        }
        let area_scale = pow2_inverse(largest_area);
        let face_weights: Vec<f64> = areas.iter().map(|&a| a * area_scale).collect();
        let weight_total = {
            let mut s = Sum::default();
            face_weights.iter().for_each(|&w| s.add(w));
            s.value()
        };
        let mut vertex_weights = vec![0.0; mesh.n_vertices()];
        let mut on_surface = vec![false; mesh.n_vertices()];
        for (f, &w) in mesh.faces().zip(&face_weights) {
            for v in mesh.vertices_around_face(f) {
                vertex_weights[v.index()] += w / 3.0;
                on_surface[v.index()] = true;
            }
        }

        // The field on the surface's vertices, scaled by a power of two into [-2, 2).
        let largest = field
            .iter()
            .zip(&on_surface)
            .filter(|(_, on)| **on)
            .fold(0.0f64, |m, (r, _)| m.max(r.abs()));
        let scale = if largest > 0.0 {
            pow2_inverse(largest)
        } else {
            1.0
        };
        let scaled: Vec<f64> = field.iter().map(|&r| r * scale).collect();
        let mut surface = Self {
            mesh,
            face_weights,
            vertex_weights,
            on_surface,
            weight_total,
            area,
            scaled,
            scale,
            mean_scaled: 0.0,
        };
        let mut first = Sum::default();
        for (f, &w) in mesh.faces().zip(&surface.face_weights) {
            first.add(w * mean_powers(surface.face_values(f))[0]);
        }
        surface.mean_scaled = first.value() / weight_total;
        Ok(surface)
    }

    /// The scaled values at the corners of triangle `f`.
    pub(super) fn face_values(&self, f: FaceId) -> [f64; 3] {
        self.mesh
            .triangle_vertices(f)
            .map(|v| self.scaled[v.index()])
    }

    /// The scaled shift of the datum: 0 or the mean.
    pub(super) fn shift(&self, datum: Datum) -> f64 {
        match datum {
            Datum::ReferenceSurface => 0.0,
            Datum::Mean => self.mean_scaled,
        }
    }

    /// Whether vertex `i` belongs to a face.
    pub(super) fn on_surface(&self, i: usize) -> bool {
        self.on_surface[i]
    }

    /// The least and largest scaled values over the vertices of the faces.
    pub(super) fn extremes(&self) -> (f64, f64) {
        let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
        for (i, &r) in self.scaled.iter().enumerate() {
            if self.on_surface(i) {
                low = low.min(r);
                high = high.max(r);
            }
        }
        (low, high)
    }
}

/// `Sdq = sqrt(Σ w s² / W)` and `Sdr = Σ w (sqrt(1 + s²) − 1) / W` from the face weights
/// `w` and slopes `s = |∇r|`. The squares are taken relative to the largest slope, so
/// that Sdq is finite whenever the slopes are; a developed-area term is evaluated as
/// `s² / (sqrt(1 + s²) + 1)` (no cancellation for small slopes), and as `s − 1` beyond
/// 10¹⁵⁰ where `sqrt(1 + s²)` equals `s` in `f64`.
fn slope_parameters(slopes: &[(f64, f64)], weight_total: f64) -> (f64, f64) {
    let steepest = slopes.iter().fold(0.0f64, |m, &(_, s)| m.max(s));
    if steepest == 0.0 {
        return (0.0, 0.0);
    }
    if !steepest.is_finite() {
        return (f64::INFINITY, f64::INFINITY);
    }
    let mut relative_sq = Sum::default();
    let mut developed = Sum::default();
    for &(w, s) in slopes {
        let q = s / steepest;
        relative_sq.add(w * q * q);
        developed.add(
            w * if s <= 1e150 {
                s * s / ((1.0 + s * s).sqrt() + 1.0)
            } else {
                s - 1.0
            },
        );
    }
    (
        steepest * (relative_sq.value() / weight_total).sqrt(),
        developed.value() / weight_total,
    )
}

/// Checks the mesh (non-empty, triangles) and the field (length, finite values).
fn validate(mesh: &HalfedgeMesh, field: &[f64]) -> Result<(), MetricsError> {
    if mesh.n_faces() == 0 {
        return Err(MetricsError::Empty { what: "mesh" });
    }
    if !mesh.is_triangle_mesh()
        && let Some(f) = mesh.faces().find(|&f| mesh.face_valence(f) != 3)
    {
        return Err(MetricsError::Topology(TopologyError::NotTriangle {
            face: f.raw(),
            len: mesh.face_valence(f),
        }));
    }
    if field.len() != mesh.n_vertices() {
        return Err(MetricsError::FieldLength {
            what: "residual",
            got: field.len(),
            expected: mesh.n_vertices(),
        });
    }
    if let Some(index) = field.iter().position(|r| !r.is_finite()) {
        return Err(MetricsError::NonFinite {
            what: "residual value",
            index,
        });
    }
    Ok(())
}
