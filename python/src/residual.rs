//! `beltrami.residual`: the ISO 25178-2 areal parameters of a measured surface's residual
//! from its form, as `beltrami residual --json`.

use beltrami_halfedge::geometry::Geometry;
use beltrami_metrics::MetricsError;
use beltrami_metrics::distance::check_same_topology;
use beltrami_metrics::residual::{
    ArealOptions, Datum, Form, Quadrature, SurfaceTexture, TextureOptions, form_residual,
    normal_residual, surface_texture,
};
use numpy::PyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{metrics_error, no_panic};
use crate::mesh::Mesh;

/// What the computation gives back to be put into a dict.
struct Computed {
    texture: SurfaceTexture,
    form: Option<(beltrami_metrics::residual::FittedForm, bool)>,
    vertices: usize,
    faces: usize,
}

/// The residual of `measured` from its form and every areal parameter of it, with the
/// keys of `beltrami residual --json`, plus `heights`: the residual per vertex (from
/// the datum), a float64 array (what the command line writes with `--scalars`).
///
/// The form is either `smoothed` (the same mesh smoothed, e.g. by `smooth`: the residual
/// is the signed normal deviation from it) or `form`, a least-squares form fitted to
/// `measured`: `"plane"`, `"poly:N"` (N = 1 to 6), `"sphere"` or `"cylinder"`.
/// `quadrature` is `"lumped"` (area-weighted vertex values, the default) or `"exact"`
/// (the piecewise-linear interpolant); `remove_mean` measures heights from their mean;
/// `smr` lists heights at which to read the material ratio, `smc` material ratios (%) at
/// which to read the height. Lengths are in the mesh's unit.
///
/// Raises `ValueError` when neither or both of `smoothed` and `form` are given, for an
/// unknown form or quadrature, or an `smc` outside 0 to 100; `MetricsError` when the
/// meshes differ in topology or the parameters cannot be computed.
#[pyfunction]
#[pyo3(
    signature = (measured, smoothed = None, *, form = None, quadrature = "lumped", remove_mean = false, smr = Vec::new(), smc = Vec::new()),
    text_signature = "(measured, smoothed=None, *, form=None, quadrature='lumped', remove_mean=False, smr=(), smc=())"
)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn residual<'py>(
    py: Python<'py>,
    measured: &Mesh,
    smoothed: Option<&Mesh>,
    form: Option<&str>,
    quadrature: &str,
    remove_mean: bool,
    smr: Vec<f64>,
    smc: Vec<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let form: Option<Form> = match (smoothed, form) {
        (Some(_), Some(_)) => {
            return Err(PyValueError::new_err("give smoothed or form, not both"));
        }
        (None, None) => {
            return Err(PyValueError::new_err("residual needs smoothed or form"));
        }
        (_, Some(f)) => Some(
            f.parse()
                .map_err(|e: String| PyValueError::new_err(format!("form {f:?}: {e}")))?,
        ),
        (Some(_), None) => None,
    };
    let quadrature_kind = match quadrature {
        "lumped" => Quadrature::Lumped,
        "exact" => Quadrature::ExactInterpolant,
        q => {
            return Err(PyValueError::new_err(format!(
                "quadrature must be \"lumped\" or \"exact\", got {q:?}"
            )));
        }
    };
    if let Some(mr) = smc.iter().find(|mr| !(0.0..=100.0).contains(*mr)) {
        return Err(PyValueError::new_err(format!(
            "smc takes a material ratio in percent from 0 to 100, got {mr}"
        )));
    }
    if let Some(c) = smr.iter().find(|c| !c.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "smr takes finite heights, got {c}"
        )));
    }
    let datum = if remove_mean {
        Datum::Mean
    } else {
        Datum::ReferenceSurface
    };
    let options = TextureOptions::default()
        .areal(
            ArealOptions::default()
                .datum(datum)
                .quadrature(quadrature_kind),
        )
        .smr_heights(smr)
        .smc_ratios(smc);
    let computed = py.detach(|| {
        no_panic(|| compute(measured, smoothed, form, &options).map_err(|e| metrics_error(&e)))
    })?;
    to_dict(py, measured, smoothed, &computed, remove_mean, quadrature)
}

fn compute(
    measured: &Mesh,
    smoothed: Option<&Mesh>,
    form: Option<Form>,
    options: &TextureOptions,
) -> Result<Computed, MetricsError> {
    let measured_geometry = Geometry::new(&measured.mesh, &measured.positions)?;
    let (residual, reference_positions, reference_mesh, fitted) = match (smoothed, form) {
        (Some(s), _) => {
            check_same_topology(&measured.mesh, &s.mesh)?;
            let smoothed_geometry = Geometry::new(&s.mesh, &s.positions)?;
            let r = normal_residual(&measured_geometry, &smoothed_geometry)?;
            (r.into_vec(), s.positions.clone(), &s.mesh, None)
        }
        (None, Some(f)) => {
            let fit = form_residual(&measured_geometry, f)?;
            (
                fit.residual.into_vec(),
                fit.foot_points,
                &measured.mesh,
                Some((fit.form, fit.flipped)),
            )
        }
        (None, None) => unreachable!("checked by the caller"),
    };
    let geometry = Geometry::new(reference_mesh, &reference_positions)?;
    let texture = surface_texture(&geometry, &residual, options)?;
    Ok(Computed {
        texture,
        form: fitted,
        vertices: reference_mesh.n_vertices(),
        faces: reference_mesh.n_faces(),
    })
}

fn to_dict<'py>(
    py: Python<'py>,
    measured: &Mesh,
    smoothed: Option<&Mesh>,
    c: &Computed,
    remove_mean: bool,
    quadrature: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let file = |m: &Mesh| m.source.as_ref().map(|(p, _)| p.display().to_string());
    let d = PyDict::new(py);
    d.set_item("measured", file(measured))?;
    d.set_item("smoothed", smoothed.and_then(file))?;
    match &c.form {
        Some((form, flipped)) => {
            let f = PyDict::new(py);
            f.set_item("kind", form.kind())?;
            f.set_item("degree", form.degree())?;
            f.set_item("point", form.point().to_array())?;
            f.set_item("direction", form.direction().map(|v| v.to_array()))?;
            f.set_item("radius", form.radius())?;
            f.set_item("rms_residual", form.rms_residual())?;
            f.set_item("flipped", *flipped)?;
            d.set_item("form", f)?;
        }
        None => d.set_item("form", py.None())?,
    }
    d.set_item("vertices", c.vertices)?;
    d.set_item("faces", c.faces)?;
    d.set_item("datum", if remove_mean { "mean" } else { "reference" })?;
    d.set_item("quadrature", quadrature)?;
    let (s, k, v, sp) = (
        &c.texture.areal,
        &c.texture.stratified,
        &c.texture.volume,
        &c.texture.spatial,
    );
    for (key, value) in [
        ("sa", s.sa),
        ("sq", s.sq),
        ("sp", s.sp),
        ("sv", s.sv),
        ("sz", s.sz),
    ] {
        d.set_item(key, value)?;
    }
    d.set_item("ssk", s.ssk)?;
    d.set_item("sku", s.sku)?;
    d.set_item("sdq", s.sdq)?;
    d.set_item("sdr", s.sdr)?;
    d.set_item("sxp", c.texture.sxp)?;
    d.set_item("sk", k.sk)?;
    d.set_item("spk", k.spk)?;
    d.set_item("svk", k.svk)?;
    d.set_item("smr1", k.smr1)?;
    d.set_item("smr2", k.smr2)?;
    d.set_item("sak1", k.sak1)?;
    d.set_item("sak2", k.sak2)?;
    d.set_item("vmp", v.vmp)?;
    d.set_item("vmc", v.vmc)?;
    d.set_item("vvc", v.vvc)?;
    d.set_item("vvv", v.vvv)?;
    d.set_item("sal", sp.sal)?;
    d.set_item("str", sp.str)?;
    d.set_item("std", sp.std)?;
    let pairs = |values: &[(f64, f64)]| -> PyResult<Vec<Bound<'py, PyDict>>> {
        values
            .iter()
            .map(|&(height, ratio)| {
                let e = PyDict::new(py);
                e.set_item("height", height)?;
                e.set_item("ratio", ratio)?;
                Ok(e)
            })
            .collect()
    };
    d.set_item("smr", pairs(&c.texture.smr)?)?;
    d.set_item("smc", pairs(&c.texture.smc)?)?;
    let spatial = PyDict::new(py);
    spatial.set_item("step", sp.step)?;
    spatial.set_item("nx", sp.nx)?;
    spatial.set_item("ny", sp.ny)?;
    spatial.set_item("valid_points", sp.valid_points)?;
    spatial.set_item("threshold", sp.threshold)?;
    spatial.set_item("decays_in_every_direction", sp.decays_in_every_direction)?;
    spatial.set_item("unavailable", sp.unavailable.clone())?;
    d.set_item("spatial", spatial)?;
    d.set_item("mean", s.mean)?;
    d.set_item("area", s.area)?;
    d.set_item("scalars", py.None())?;
    d.set_item("heights", PyArray1::from_vec(py, c.texture.heights.clone()))?;
    Ok(d)
}
