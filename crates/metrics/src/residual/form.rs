//! F-operators: the residual of a measured mesh from a least-squares form fitted to it.

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::{DVec3, VertexMap};

use crate::MetricsError;
use crate::distortion::check_finite_positions;
use crate::fits::{
    CylinderFit, FitOptions, FitPoints, PlaneFit, PolynomialFit, SphereFit, fit_cylinder,
    fit_plane, fit_polynomial, fit_sphere,
};

/// A nominal form to remove from a measured surface (an F-operator).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Form {
    /// The least-squares plane ([`fit_plane`]).
    Plane,
    /// A bivariate polynomial of total degree 1 to 6 in the best-fit plane's coordinates
    /// ([`fit_polynomial`]); degree 1 is the plane.
    Polynomial {
        /// The total degree.
        degree: u32,
    },
    /// The least-squares sphere ([`fit_sphere`]).
    Sphere,
    /// The least-squares cylinder ([`fit_cylinder`]).
    Cylinder,
}

/// The fitted form, with its parameters.
#[derive(Clone, Debug, PartialEq)]
pub enum FittedForm {
    /// A plane.
    Plane(PlaneFit),
    /// A polynomial over a plane.
    Polynomial(PolynomialFit),
    /// A sphere.
    Sphere(SphereFit),
    /// A cylinder.
    Cylinder(CylinderFit),
}

impl FittedForm {
    /// The form's name as the command line prints it: `plane`, `polynomial`, `sphere`
    /// or `cylinder`.
    #[must_use]
    pub fn kind(&self) -> &'static str {
        match self {
            Self::Plane(_) => "plane",
            Self::Polynomial(_) => "polynomial",
            Self::Sphere(_) => "sphere",
            Self::Cylinder(_) => "cylinder",
        }
    }

    /// The polynomial's total degree; `None` for the other forms.
    #[must_use]
    pub fn degree(&self) -> Option<u32> {
        match self {
            Self::Polynomial(f) => Some(f.degree),
            _ => None,
        }
    }

    /// The form's reference point: the plane's centroid, the polynomial frame's origin,
    /// the sphere's centre, the cylinder's axis point nearest the centroid.
    #[must_use]
    pub fn point(&self) -> DVec3 {
        match self {
            Self::Plane(f) => f.point,
            Self::Polynomial(f) => f.origin,
            Self::Sphere(f) => f.center,
            Self::Cylinder(f) => f.axis_point,
        }
    }

    /// The plane's unit normal (the polynomial's plane's), the cylinder's unit axis;
    /// `None` for the sphere.
    #[must_use]
    pub fn direction(&self) -> Option<DVec3> {
        match self {
            Self::Plane(f) => Some(f.normal),
            Self::Polynomial(f) => Some(f.normal),
            Self::Sphere(_) => None,
            Self::Cylinder(f) => Some(f.axis),
        }
    }

    /// The radius of the sphere or cylinder; `None` for the others.
    #[must_use]
    pub fn radius(&self) -> Option<f64> {
        match self {
            Self::Sphere(f) => Some(f.radius),
            Self::Cylinder(f) => Some(f.radius),
            _ => None,
        }
    }

    /// The area-weighted RMS of the orthogonal residuals, in length units.
    #[must_use]
    pub fn rms_residual(&self) -> f64 {
        match self {
            Self::Plane(f) => f.rms_residual,
            Self::Polynomial(f) => f.rms_residual,
            Self::Sphere(f) => f.rms_residual,
            Self::Cylinder(f) => f.rms_residual,
        }
    }
}

/// The residual of a measured mesh from a fitted form. See [`form_residual`].
#[derive(Clone, Debug, PartialEq)]
pub struct FormResidual {
    /// The signed orthogonal distance of each vertex from the form, in length units.
    pub residual: VertexMap<f64>,
    /// The closest point of the form to each vertex (`vertex − residual · n` with `n`
    /// the form's unit normal there, on the residual's positive side): the measured mesh
    /// laid onto the form, its reference surface.
    pub foot_points: Vec<DVec3>,
    /// The form.
    pub form: FittedForm,
    /// Whether the residual is the negated distance of the fit's own sign convention
    /// (the mesh's faces point towards the inside of the sphere or cylinder, or against
    /// the plane's normal).
    pub flipped: bool,
}

/// The residual of a measured mesh from the least-squares `form` fitted to its vertices,
/// area-weighted (each vertex weighted by its barycentric area, so that the fit is over
/// the surface, not over the vertices): the F-operator of ISO 25178-2 by a fitted form
/// instead of a smoothed mesh.
///
/// The residual at a vertex is its **orthogonal distance** to the form, signed: positive
/// on the side the measured mesh's faces point to on balance, that is outward or up for
/// a surface oriented outward or upward (the convention of [`normal_residual`](super::normal_residual)):
///
/// - plane: `(p − c) · n`, `n` the plane normal turned towards the faces' side;
/// - polynomial: the distance to the closest point of `w = P(u, v)`, positive on the side
///   of the faces (see [`PolynomialFit::residual`]);
/// - sphere: `|p − c| − R`, negated when the faces point towards the centre (a concave
///   cap seen from inside, a spherical cup);
/// - cylinder: the distance from the axis minus `R`, negated when the faces point
///   towards the axis (a bore).
///
/// Which side the faces point to is decided by the sum over the faces of their vector
/// areas against the form's outward (or up) direction at their centroids. The
/// [`foot_points`](FormResidual::foot_points) lay the mesh onto the form; the areal
/// parameters of the residual are integrals over that reference surface.
///
/// # Errors
/// - [`MetricsError::NonFinite`] for a non-finite position (`"position"`), or a residual
///   that is not finite (`"residual value"`);
/// - [`MetricsError::Empty`] for a mesh without faces (`"mesh"`);
/// - the errors of the fit: [`MetricsError::TooFewPoints`], [`MetricsError::Degenerate`]
///   (coplanar points for a sphere, collinear ones for a plane or cylinder),
///   [`MetricsError::NoConvergence`], and [`MetricsError::InvalidParameter`] for a
///   polynomial degree outside 1 to 6.
///
/// # Examples
/// ```
/// use beltrami_halfedge::geometry::Geometry;
/// use beltrami_halfedge::{primitives, DVec3};
/// use beltrami_metrics::residual::{form_residual, Form};
///
/// // A unit icosphere measured 1 % too large at its north pole only.
/// let sphere = primitives::icosphere(3);
/// let mesh = sphere.mesh()?;
/// let measured: Vec<DVec3> = sphere.positions.iter()
///     .map(|&p| if p.z > 0.999 { 1.01 * p } else { p })
///     .collect();
/// let fit = form_residual(&Geometry::new(&mesh, &measured)?, Form::Sphere)?;
/// let top = measured.iter().position(|p| p.z > 1.0).unwrap();
/// assert!(fit.residual.as_slice()[top] > 0.009); // a peak: outside the sphere
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # References
/// - ISO 25178-2:2012, clause 3.1 (the F-operation and the reference surface; heights
///   are measured from it, along its normal).
/// - ISO 25178-3:2012 (specification operators: form removal by least-squares
///   association before filtering).
/// - C. M. Shakarji: *Least-squares fitting algorithms of the NIST algorithm testing
///   system*. Journal of Research of NIST 103(6), 1998.
pub fn form_residual(measured: &Geometry<'_>, form: Form) -> Result<FormResidual, MetricsError> {
    let mesh = measured.mesh();
    let positions = measured.positions();
    check_finite_positions(positions)?;
    if mesh.n_faces() == 0 {
        return Err(MetricsError::Empty { what: "mesh" });
    }
    let points = FitPoints::area_weighted(mesh, positions)?;
    let options = FitOptions::default();
    // The outward (or up) direction of the fit at a point.
    let fitted = match form {
        Form::Plane => FittedForm::Plane(fit_plane(&points)?),
        Form::Polynomial { degree } => FittedForm::Polynomial(fit_polynomial(&points, degree)?),
        Form::Sphere => FittedForm::Sphere(fit_sphere(&points, &options)?),
        Form::Cylinder => FittedForm::Cylinder(fit_cylinder(&points, None, &options)?),
    };
    let outward = |p: DVec3| -> DVec3 {
        match &fitted {
            FittedForm::Plane(f) => f.normal,
            FittedForm::Polynomial(f) => f.normal,
            FittedForm::Sphere(f) => (p - f.center).normalize_or_zero(),
            FittedForm::Cylinder(f) => {
                let d = p - f.axis_point;
                (d - f.axis * d.dot(f.axis)).normalize_or_zero()
            }
        }
    };
    let mut balance = 0.0;
    for f in mesh.faces() {
        balance += measured
            .face_vector_area(f)
            .dot(outward(measured.face_centroid(f)));
    }
    let flipped = balance < 0.0;
    let sign = if flipped { -1.0 } else { 1.0 };
    let mut residual = Vec::with_capacity(positions.len());
    let mut foot_points = Vec::with_capacity(positions.len());
    for (index, &p) in positions.iter().enumerate() {
        let (r, foot) = match &fitted {
            FittedForm::Plane(f) => {
                let r = f.residual(p);
                (r, p - f.normal * r)
            }
            FittedForm::Polynomial(f) => {
                let foot = f.foot_point(p);
                (f.residual(p), foot)
            }
            FittedForm::Sphere(f) => {
                let u = outward(p);
                (
                    f.residual(p),
                    if u == DVec3::ZERO {
                        p
                    } else {
                        f.center + u * f.radius
                    },
                )
            }
            FittedForm::Cylinder(f) => {
                let u = outward(p);
                let d = p - f.axis_point;
                let on_axis = f.axis_point + f.axis * d.dot(f.axis);
                (
                    f.residual(p),
                    if u == DVec3::ZERO {
                        p
                    } else {
                        on_axis + u * f.radius
                    },
                )
            }
        };
        if !(r.is_finite() && foot.is_finite()) {
            return Err(MetricsError::NonFinite {
                what: "residual value",
                index,
            });
        }
        residual.push(sign * r);
        foot_points.push(foot);
    }
    Ok(FormResidual {
        residual: VertexMap::from_vec(residual),
        foot_points,
        form: fitted,
        flipped,
    })
}
