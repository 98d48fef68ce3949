//! `beltrami.fit_sphere`, `fit_circle` and `fit_cylinder`, as `beltrami fit --json`.

use beltrami_halfedge::DVec3;
use beltrami_metrics::fits::{self, FitOptions, FitPoints};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{metrics_error, no_panic};
use crate::mesh::{Mesh, vertices_from};

/// The shapes `fit` knows.
#[derive(Clone, Copy)]
enum Shape {
    Sphere,
    Circle,
    Cylinder,
}

impl Shape {
    fn name(self) -> &'static str {
        match self {
            Self::Sphere => "sphere",
            Self::Circle => "circle",
            Self::Cylinder => "cylinder",
        }
    }
}

/// What a fit found, as the fields of `fit --json`.
struct Fitted {
    center: DVec3,
    axis: Option<DVec3>,
    radius: f64,
    rms_residual: f64,
    max_residual: f64,
    plane_rms: Option<f64>,
    iterations: usize,
    converged: bool,
    points: usize,
}

/// Fits `shape` to a `Mesh`'s vertices (area-weighted with `weighted`) or to an (N, 3)
/// array of points: the dict of `fit --json`.
fn fit<'py>(
    py: Python<'py>,
    shape: Shape,
    points: &Bound<'py, PyAny>,
    weighted: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let mesh = points.downcast::<Mesh>().ok().map(Bound::get);
    let owned;
    let positions: &[DVec3] = match mesh {
        Some(m) => &m.positions,
        None => {
            owned = vertices_from(points)?;
            &owned
        }
    };
    if weighted && mesh.is_none() {
        return Err(PyValueError::new_err(
            "weighted needs a Mesh (the weights are vertex areas), not bare points",
        ));
    }
    let f = py.detach(|| {
        no_panic(|| {
            let input = match mesh.filter(|_| weighted) {
                Some(m) => {
                    FitPoints::area_weighted(&m.mesh, positions).map_err(|e| metrics_error(&e))?
                }
                None => FitPoints::new(positions),
            };
            let points = input
                .weights()
                .map_or(positions.len(), |w| w.iter().filter(|&&w| w > 0.0).count());
            fit_shape(shape, &input, points)
        })
    })?;
    let file = mesh
        .and_then(|m| m.source.as_ref())
        .map(|(p, _)| p.display().to_string());
    f.to_dict(py, file, shape, weighted)
}

/// Fits `shape` to `input` with the default options; `points` is the number of points
/// of positive weight.
fn fit_shape(shape: Shape, input: &FitPoints<'_>, points: usize) -> PyResult<Fitted> {
    let options = FitOptions::default();
    Ok(match shape {
        Shape::Sphere => {
            let f = fits::fit_sphere(input, &options).map_err(|e| metrics_error(&e))?;
            Fitted {
                center: f.center,
                axis: None,
                radius: f.radius,
                rms_residual: f.rms_residual,
                max_residual: f.max_residual,
                plane_rms: None,
                iterations: f.iterations,
                converged: f.converged,
                points,
            }
        }
        Shape::Circle => {
            let f = fits::fit_circle(input, &options).map_err(|e| metrics_error(&e))?;
            Fitted {
                center: f.center,
                axis: Some(f.axis),
                radius: f.radius,
                rms_residual: f.rms_residual,
                max_residual: f.max_residual,
                plane_rms: Some(f.plane_rms),
                iterations: f.iterations,
                converged: f.converged,
                points,
            }
        }
        Shape::Cylinder => {
            let f = fits::fit_cylinder(input, None, &options).map_err(|e| metrics_error(&e))?;
            Fitted {
                center: f.axis_point,
                axis: Some(f.axis),
                radius: f.radius,
                rms_residual: f.rms_residual,
                max_residual: f.max_residual,
                plane_rms: None,
                iterations: f.iterations,
                converged: f.converged,
                points,
            }
        }
    })
}

impl Fitted {
    /// The dict of `fit --json`: `file` (the mesh's source, if any), `shape`,
    /// `weighted` and the fit's fields.
    fn to_dict<'py>(
        &self,
        py: Python<'py>,
        file: Option<String>,
        shape: Shape,
        weighted: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let f = self;
        let d = PyDict::new(py);
        d.set_item("file", file)?;
        d.set_item("shape", shape.name())?;
        d.set_item("weighted", weighted)?;
        d.set_item("points", f.points)?;
        d.set_item("center", f.center.to_array())?;
        if let Some(axis) = f.axis {
            d.set_item("axis", axis.to_array())?;
        }
        d.set_item("radius", f.radius)?;
        d.set_item("rms_residual", f.rms_residual)?;
        d.set_item("max_residual", f.max_residual)?;
        if let Some(plane) = f.plane_rms {
            d.set_item("plane_rms", plane)?;
        }
        d.set_item("iterations", f.iterations)?;
        d.set_item("converged", f.converged)?;
        Ok(d)
    }
}

/// The least-squares sphere (orthogonal distances) through a mesh's vertices or an
/// (N, 3) array of points: a dict with the keys of `beltrami fit sphere --json`
/// (`file`, `shape`, `weighted`, `points`, `center`, `radius`, `rms_residual`,
/// `max_residual`, `iterations`, `converged`).
///
/// `weighted` weighs each vertex by its share of the surface area (a fit over the
/// surface rather than over the vertex set; needs a Mesh). Raises `MetricsError`
/// when the points do not determine a sphere (too few, all on a plane).
#[pyfunction]
#[pyo3(signature = (points, *, weighted = false))]
pub(crate) fn fit_sphere<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyAny>,
    weighted: bool,
) -> PyResult<Bound<'py, PyDict>> {
    fit(py, Shape::Sphere, points, weighted)
}

/// The least-squares circle: a plane through the points, then the circle in it; the
/// keys of `beltrami fit circle --json` (those of `fit_sphere`, with the plane normal
/// `axis` and `plane_rms`, the RMS distance of the points from the plane).
#[pyfunction]
#[pyo3(signature = (points, *, weighted = false))]
pub(crate) fn fit_circle<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyAny>,
    weighted: bool,
) -> PyResult<Bound<'py, PyDict>> {
    fit(py, Shape::Circle, points, weighted)
}

/// The least-squares cylinder; the keys of `beltrami fit cylinder --json` (those of
/// `fit_sphere`, with the unit `axis`; `center` is the axis point nearest the points'
/// centroid).
#[pyfunction]
#[pyo3(signature = (points, *, weighted = false))]
pub(crate) fn fit_cylinder<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyAny>,
    weighted: bool,
) -> PyResult<Bound<'py, PyDict>> {
    fit(py, Shape::Cylinder, points, weighted)
}
