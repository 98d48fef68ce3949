//! The residual surface of a measured mesh against its reference form (a smoothed
//! version of it, or a fitted plane, polynomial, sphere or cylinder), and the ISO 25178-2
//! areal parameters of a residual.
//!
//! A metrologist removes the form of a measured surface (an F-operator: smoothing, or a
//! least-squares form) and characterises what is left, the residual, as surface texture:
//!
//! - [`normal_residual`] gives the residual per vertex against a smoothed mesh,
//!   [`form_residual`] against a fitted [`Form`];
//! - [`areal_parameters`]: the height parameters Sa, Sq, Sp, Sv, Sz, Ssk, Sku and the
//!   hybrid parameters Sdq, Sdr;
//! - [`MaterialRatioCurve`]: the material ratio curve Smr(c), its inverse Smc(mr), Sxp,
//!   the stratified-surface parameters Sk, Spk, Svk, Smr1, Smr2, Sak1, Sak2
//!   ([`MaterialRatioCurve::stratified`]) and the volume parameters Vmp, Vmc, Vvc, Vvv
//!   ([`MaterialRatioCurve::volume`]);
//! - [`spatial_parameters`] on a [`HeightGrid`], which [`resample_to_grid`] makes from a
//!   residual on a mesh: the autocorrelation length Sal, the texture aspect ratio Str,
//!   the texture direction Std.
//!
//! The height integrals (Sa, Sq, Ssk, Sku and the material ratio curve) use the lumped
//! rule by default, each vertex weighted by its barycentric area (the trapezoid rule on a
//! grid), which converges to the smooth surface's values; the exact integrals of the
//! piecewise-linear interpolant are the alternative ([`Quadrature`]).
//!
//! # The residual
//!
//! For a measured mesh `x` and its smoothed version `y` with the same topology, the
//! residual at vertex `i` is the **signed normal deviation**
//! `r_i = (x_i − y_i) · n_i`, with `n_i` the unit angle-weighted vertex normal of the
//! smoothed mesh: positive where the measured surface lies on the side the normals point
//! to (outside a closed, outward-oriented surface: a peak), negative below it (a pit).
//! It measures the displacement along the reference normal and ignores its tangential
//! part. For meshes of different topology (a measured mesh against a separately
//! triangulated nominal surface) use the closest-point signed distance of
//! [`crate::distance`] instead.
//!
//! # Exact integrals of a linear field ([`Quadrature::ExactInterpolant`])
//!
//! `r` is interpolated linearly on each triangle `T` (area `A_T`, vertex values `a, b,
//! c`). With barycentric coordinates `λ`, `∫_T λ₁^p λ₂^q λ₃^s dA = 2 A_T p! q! s! / (p + q
//! + s + 2)!`; expanding `(a λ₁ + b λ₂ + c λ₃)^k`, the multinomial coefficients cancel and
//! `∫_T r^k dA = 2 A_T k! / (k + 2)! · h_k(a, b, c)`, with `h_k` the sum of all monomials
//! of degree `k` in `a, b, c`:
//!
//! - `∫_T r dA = A_T (a + b + c) / 3`;
//! - `∫_T r² dA = A_T (a² + b² + c² + ab + bc + ca) / 6`;
//! - `∫_T r³ dA = A_T (a³ + b³ + c³ + a²b + a²c + b²a + b²c + c²a + c²b + abc) / 10`;
//! - `∫_T r⁴ dA = A_T h₄(a, b, c) / 15`, `h₄` the fifteen monomials of degree 4
//!   (`a⁴ + a³b + a²b² + … + abc² + …`).
//!
//! `|r|` is not linear where `r` changes sign inside `T`: the zero line cuts off the
//! corner of the one vertex `l` whose sign differs from the other two, `o₁` and `o₂`.
//! The corner is a triangle with the fractions `t₁ = l / (l − o₁)`, `t₂ = l / (l − o₂)`
//! of the edges at `l`, area `t₁ t₂ A_T`, over which `|r|` falls linearly from `|l|` to
//! 0; so `∫_corner |r| dA = |l| t₁ t₂ A_T / 3`, and with `σ` the sign of `l`,
//! `∫_T |r| dA = 2 |l| t₁ t₂ A_T / 3 − σ A_T (a + b + c) / 3`, exactly. Without a sign
//! change, `∫_T |r| dA = A_T |a + b + c| / 3`.
//!
//! The gradient of the interpolant in the plane of `T` (vertices `p_a, p_b, p_c`,
//! `e₁ = p_b − p_a`, `e₂ = p_c − p_a`, `N = e₁ × e₂`) is
//! `∇r = [(c − a) N × e₁ − (b − a) N × e₂] / |N|²`.
//!
//! # Units and datum
//!
//! `r` is in length units, so are Sa, Sq, Sp, Sv, Sz; Ssk, Sku, Sdq and Sdr are
//! dimensionless. ISO 25178-2 measures heights from the reference surface, so by default
//! ([`Datum::ReferenceSurface`]) the residual is taken as is; [`Datum::Mean`] first
//! removes its area-weighted mean.
//!
//! # Examples
//!
//! ```
//! use beltrami_halfedge::geometry::Geometry;
//! use beltrami_halfedge::{primitives, DVec3};
//! use beltrami_metrics::residual::{areal_parameters, normal_residual, ArealOptions};
//!
//! // A flat reference form and a "measured" surface 0.1 above it on the left half and
//! // 0.1 below on the right.
//! let grid = primitives::grid(8, 8);
//! let mesh = grid.mesh()?;
//! let measured: Vec<DVec3> = grid.positions.iter()
//!     .map(|&p| p + DVec3::new(0.0, 0.0, if p.x < 4.0 { 0.1 } else { -0.1 }))
//!     .collect();
//! let r = normal_residual(&Geometry::new(&mesh, &measured)?, &Geometry::new(&mesh, &grid.positions)?)?;
//! assert!((r.as_slice()[0] - 0.1).abs() < 1e-15 && (r.as_slice()[8] + 0.1).abs() < 1e-15);
//! let s = areal_parameters(&Geometry::new(&mesh, &grid.positions)?, r.as_slice(), &ArealOptions::default())?;
//! assert!((s.sp - 0.1).abs() < 1e-15 && (s.sv - 0.1).abs() < 1e-15);
//! assert!(s.sdq > 0.0); // the step between x = 3 and x = 4 slopes at 0.2
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # References
//!
//! - ISO 25178-2:2012, *Geometrical product specifications (GPS) — Surface texture:
//!   Areal — Part 2: Terms, definitions and surface texture parameters*.
//! - X. Jiang, L. Cooper, P. J. Scott: *Freeform surface filtering using the diffusion
//!   equation*. Proc. R. Soc. A 467 (2011) 841, doi 10.1098/rspa.2010.0307 (residuals on
//!   a freeform reference form).
//! - L. Pagani, Q. Qi, X. Jiang, P. J. Scott: *Towards a new definition of areal surface
//!   texture parameters on freeform surface*. Measurement 109 (2017), doi
//!   10.1016/j.measurement.2017.05.028.

mod areal;
mod fft;
mod form;
mod grid;
mod integrals;
mod material;
mod spatial;
mod texture;

use beltrami_halfedge::VertexMap;
use beltrami_halfedge::geometry::{Geometry, NormalWeighting};

use crate::MetricsError;
use crate::distortion::{check_finite_positions, check_same_topology};

pub use areal::{ArealOptions, ArealParameters, Datum, Quadrature, areal_parameters};
pub use form::{FittedForm, Form, FormResidual, form_residual};
pub use grid::{HeightGrid, PlaneFrame, ResampleOptions, ResampledGrid, resample_to_grid};
pub use material::{MaterialRatioCurve, StratifiedParameters, VolumeParameters};
pub use spatial::{SpatialOptions, SpatialParameters, spatial_parameters};
pub use texture::{
    SXP_RATIOS, SpatialSummary, SurfaceTexture, TextureOptions, VOLUME_RATIOS, surface_texture,
};

/// The residual of a measured mesh against its smoothed version of the same topology:
/// the signed normal deviation `r_i = (x_i − y_i) · n_i` per vertex, in length units,
/// with `x` the measured and `y` the smoothed positions and `n_i` the unit angle-weighted
/// vertex normal of the smoothed mesh ([`NormalWeighting::Angle`]).
///
/// Positive where the measured surface lies on the side the smoothed normals point to.
/// Where the smoothed normal is undefined (an isolated vertex, or all its faces
/// degenerate) the residual is 0. See the [module documentation](self) for the
/// alternative for meshes of different topology.
///
/// # Errors
/// - [`MetricsError::TopologyMismatch`] when the meshes do not share their topology;
/// - [`MetricsError::NonFinite`] for a non-finite position (`what = "position"`), or a
///   residual that overflows (`what = "residual value"`).
///
/// # Complexity
/// O(V + H).
///
/// # Examples
/// ```
/// use beltrami_halfedge::geometry::Geometry;
/// use beltrami_halfedge::{primitives, DVec3, VertexId};
/// use beltrami_metrics::residual::normal_residual;
///
/// let sphere = primitives::icosphere(2);
/// let mesh = sphere.mesh()?;
/// // The measured sphere is 1 % larger than its smoothed form: a positive residual.
/// let measured: Vec<DVec3> = sphere.positions.iter().map(|&p| 1.01 * p).collect();
/// let r = normal_residual(&Geometry::new(&mesh, &measured)?, &Geometry::new(&mesh, &sphere.positions)?)?;
/// assert!(r.as_slice().iter().all(|&r| r > 0.0099 && r <= 0.01 + 1e-15));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # References
/// G. Thürmer, C. A. Wüthrich: *Computing vertex normals from polygonal facets*. Journal
/// of Graphics Tools 3(1), 1998.
pub fn normal_residual(
    measured: &Geometry<'_>,
    smoothed: &Geometry<'_>,
) -> Result<VertexMap<f64>, MetricsError> {
    check_same_topology(smoothed.mesh(), measured.mesh())?;
    check_finite_positions(measured.positions())?;
    check_finite_positions(smoothed.positions())?;
    let normals = smoothed.vertex_normals(NormalWeighting::Angle);
    let mut residual = Vec::with_capacity(normals.len());
    for (v, &n) in normals.iter() {
        let r = (measured.position(v) - smoothed.position(v)).dot(n);
        if !r.is_finite() {
            return Err(MetricsError::NonFinite {
                what: "residual value",
                index: v.index(),
            });
        }
        residual.push(r);
    }
    Ok(VertexMap::from_vec(residual))
}
