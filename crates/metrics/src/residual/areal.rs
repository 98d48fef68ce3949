//! ISO 25178-2 areal field parameters of a per-vertex scalar field on a triangle mesh.

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::{HalfedgeMesh, TopologyError};

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
}

/// The ISO 25178-2 areal field parameters of a per-vertex scalar field `r` (a residual
/// surface, in length units) on a triangle mesh whose positions give the geometry, with
/// exact area-weighted integrals of the piecewise-linear interpolant of `r`.
///
/// Heights are `r` as given ([`Datum::ReferenceSurface`], the standard's definition for a
/// residual from the reference form) or `r − μ` ([`Datum::Mean`]). With `A_T` the area
/// of triangle `T` and `A = Σ A_T`:
///
/// - `Sa = (1/A) Σ ∫_T |r|`, `Sq = sqrt((1/A) Σ ∫_T r²)`,
///   `Ssk = (1/Sq³)(1/A) Σ ∫_T r³`, `Sku = (1/Sq⁴)(1/A) Σ ∫_T r⁴`, with the exact
///   triangle integrals of the [module documentation](super) (`|r|` split at the zero
///   line);
/// - `Sp = max r`, `Sv = |min r|`, `Sz = Sp + Sv` over the vertices of the faces (a
///   linear interpolant takes its extremes at vertices). As in the standard `Sv` is a
///   positive depth; with [`Datum::ReferenceSurface`] and a field that does not change
///   sign, `Sz` is then not the range `max − min` (use [`Datum::Mean`] for a range);
/// - `Sdq` and `Sdr` treat `r` as a height field over the reference form: on each
///   triangle, `∇r` is the gradient of the linear interpolant in the triangle's own plane,
///   `Sdq = sqrt(Σ A_T |∇r|² / A)` and `Sdr = Σ A_T (sqrt(1 + |∇r|²) − 1) / A`
///   (evaluated as `|∇r|² / (sqrt(1 + |∇r|²) + 1)`, without cancellation). Degenerate
///   triangles (see [`Geometry::is_degenerate_face`]) have no gradient and add nothing to
///   these two sums (their area is negligible).
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
/// use beltrami_metrics::residual::{areal_parameters, Datum};
///
/// // A plane rising at 45° over a flat grid: Sdq = 1, Sdr = √2 − 1.
/// let grid = primitives::grid(8, 8);
/// let mesh = grid.mesh()?;
/// let r: Vec<f64> = grid.positions.iter().map(|p| p.x).collect();
/// let s = areal_parameters(&Geometry::new(&mesh, &grid.positions)?, &r, Datum::Mean)?;
/// assert!((s.sdq - 1.0).abs() < 1e-12);
/// assert!((s.sdr - (2f64.sqrt() - 1.0)).abs() < 1e-12);
/// assert!((s.sa - 2.0).abs() < 1e-12 && (s.sz - 8.0).abs() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # References
/// - ISO 25178-2:2012, *Geometrical product specifications (GPS) — Surface texture:
///   Areal — Part 2: Terms, definitions and surface texture parameters*, clauses 4.1
///   (height parameters), 4.3 (hybrid parameters Sdq, Sdr).
/// - K. J. Stout et al.: *The development of methods for the characterisation of roughness
///   in three dimensions*. EUR 15178 EN, 1993 (the triangulated surface area behind Sdr).
/// - L. Pagani, Q. Qi, X. Jiang, P. J. Scott: *Towards a new definition of areal surface
///   texture parameters on freeform surface*. Measurement 109 (2017), doi
///   10.1016/j.measurement.2017.05.028.
pub fn areal_parameters(
    geometry: &Geometry<'_>,
    field: &[f64],
    datum: Datum,
) -> Result<ArealParameters, MetricsError> {
    let mesh = geometry.mesh();
    validate(mesh, field)?;
    check_finite_positions(geometry.positions())?;

    // Face areas, scaled by a power of two so that their sums cannot overflow.
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
    let weights: Vec<f64> = areas.iter().map(|&a| a * area_scale).collect();
    let weight_total = {
        let mut s = Sum::default();
        weights.iter().for_each(|&w| s.add(w));
        s.value()
    };

    // The field on the surface's vertices, scaled by a power of two into [-2, 2).
    let mut on_surface = vec![false; mesh.n_vertices()];
    for f in mesh.faces() {
        for v in mesh.vertices_around_face(f) {
            on_surface[v.index()] = true;
        }
    }
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
    let values = |f| mesh.triangle_vertices(f).map(|v| scaled[v.index()]);

    // Mean of the field as given, then the heights from the datum.
    let mut first = Sum::default();
    for (f, &w) in mesh.faces().zip(&weights) {
        first.add(w * mean_powers(values(f))[0]);
    }
    let mean_scaled = first.value() / weight_total;
    let shift = match datum {
        Datum::ReferenceSurface => 0.0,
        Datum::Mean => mean_scaled,
    };

    let mut moments = [Sum::default(); 4];
    let mut absolute = Sum::default();
    // (weight, |∇r|) of every non-degenerate face, for Sdq and Sdr.
    let mut slopes = Vec::with_capacity(mesh.n_faces());
    for (f, &w) in mesh.faces().zip(&weights) {
        let r = values(f).map(|r| r - shift);
        for (m, p) in moments.iter_mut().zip(mean_powers(r)) {
            m.add(w * p);
        }
        absolute.add(w * mean_abs(r));
        if geometry.is_degenerate_face(f) {
            continue;
        }
        let corners = mesh.triangle_vertices(f).map(|v| geometry.position(v));
        if let Some((g, edge_scale)) = gradient(corners, r) {
            // ∇r = g · edge_scale / scale: the field was scaled by `scale`.
            slopes.push((w, g.length() * (edge_scale / scale)));
        }
    }
    let (sdq, sdr) = slope_parameters(&slopes, weight_total);
    let mean_of = |s: &Sum| s.value() / weight_total;
    let m2 = mean_of(&moments[1]).max(0.0);
    let m3 = mean_of(&moments[2]);
    let m4 = mean_of(&moments[3]).max(0.0);

    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    for (r, _) in scaled.iter().zip(&on_surface).filter(|(_, on)| **on) {
        low = low.min(r - shift);
        high = high.max(r - shift);
    }
    let sp = high / scale;
    let sv = low.abs() / scale;
    Ok(ArealParameters {
        sa: mean_of(&absolute) / scale,
        sq: m2.sqrt() / scale,
        sp,
        sv,
        sz: sp + sv,
        ssk: (m2 > 0.0).then(|| m3 / (m2 * m2.sqrt())),
        sku: (m2 > 0.0).then(|| m4 / (m2 * m2)),
        sdq,
        sdr,
        area,
        mean: mean_scaled / scale,
        datum,
    })
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
    if !mesh.is_triangle_mesh() {
        if let Some(f) = mesh.faces().find(|&f| mesh.face_valence(f) != 3) {
            return Err(MetricsError::Topology(TopologyError::NotTriangle {
                face: f.raw(),
                len: mesh.face_valence(f),
            }));
        }
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
