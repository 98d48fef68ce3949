//! Weight schemes written in Python: `beltrami.register_weight`.
//!
//! The Python function is called once per weight refresh with per-halfedge numpy
//! arrays for the whole mesh, and returns one weight per halfedge, so a scheme runs at
//! numpy speed.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock, PoisonError};

use beltrami_halfedge::HalfedgeId;
use beltrami_weights::{WeightContext, WeightScheme};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::weights::{register, replace};

/// A weight scheme whose weights a Python function computes.
struct PythonScheme {
    name: String,
    description: String,
    function: Py<PyAny>,
    depends_on_positions: bool,
    /// The first exception the function raised, re-raised after the run.
    failure: Slot,
}

/// Where a Python scheme leaves the exception its function raised.
pub(crate) type Slot = Arc<Mutex<Option<PyErr>>>;

/// The exception slots of the Python schemes, by name.
fn slots() -> &'static Mutex<HashMap<String, Slot>> {
    static SLOTS: OnceLock<Mutex<HashMap<String, Slot>>> = OnceLock::new();
    SLOTS.get_or_init(Mutex::default)
}

impl PythonScheme {
    /// Calls the function on the context's arrays; the weights, or the exception.
    fn call(&self, ctx: &WeightContext<'_>) -> PyResult<Vec<f64>> {
        let mesh = ctx.mesh();
        let n = mesh.n_halfedges();
        let mut from = Vec::with_capacity(n);
        let mut to = Vec::with_capacity(n);
        let mut face = Vec::with_capacity(n);
        let mut vector = Vec::with_capacity(3 * n);
        let mut length = Vec::with_capacity(n);
        let mut cot = Vec::with_capacity(n);
        let mut normal = Vec::with_capacity(3 * n);
        let mut area = Vec::with_capacity(n);
        for h in mesh.halfedges() {
            from.push(i64::from(mesh.from_vertex(h).index() as u32));
            to.push(i64::from(mesh.to_vertex(h).index() as u32));
            let f = mesh.face(h);
            face.push(f.map_or(-1, |f| f.index() as i64));
            vector.extend(ctx.edge_vector(h).to_array());
            length.push(ctx.edge_length(h));
            cot.push(ctx.opposite_cotangent(h));
            normal.extend(f.map_or([0.0; 3], |f| ctx.face_normal(f).to_array()));
            area.push(f.map_or(0.0, |f| ctx.face_area(f)));
        }
        let positions: Vec<f64> = ctx.positions().iter().flat_map(|p| p.to_array()).collect();
        let n_vertices = ctx.positions().len();
        Python::attach(|py| {
            let d = PyDict::new(py);
            let twin: Vec<i64> = (0..n as i64).map(|h| h ^ 1).collect();
            d.set_item("from_vertex", PyArray1::from_vec(py, from))?;
            d.set_item("to_vertex", PyArray1::from_vec(py, to))?;
            d.set_item("twin", PyArray1::from_vec(py, twin))?;
            d.set_item("face", PyArray1::from_vec(py, face))?;
            d.set_item(
                "edge_vector",
                PyArray1::from_vec(py, vector).reshape([n, 3])?,
            )?;
            d.set_item("edge_length", PyArray1::from_vec(py, length))?;
            d.set_item("opposite_cotangent", PyArray1::from_vec(py, cot))?;
            d.set_item(
                "face_normal",
                PyArray1::from_vec(py, normal).reshape([n, 3])?,
            )?;
            d.set_item("face_area", PyArray1::from_vec(py, area))?;
            d.set_item(
                "positions",
                PyArray1::from_vec(py, positions).reshape([n_vertices, 3])?,
            )?;
            let weights = self.function.call1(py, (d,))?;
            let numpy = py.import("numpy")?;
            let weights = numpy.call_method1("ascontiguousarray", (weights, "float64"))?;
            let weights = numpy.call_method1("ravel", (weights,))?;
            let weights: PyReadonlyArray1<'_, f64> = weights.extract()?;
            let weights = weights.as_slice()?;
            if weights.len() != n {
                return Err(PyValueError::new_err(format!(
                    "weight scheme {:?} returned {} weights for {n} halfedges",
                    self.name,
                    weights.len()
                )));
            }
            Ok(weights.to_vec())
        })
    }
}

impl WeightScheme for PythonScheme {
    fn name(&self) -> &str {
        &self.name
    }

    fn description(&self) -> &str {
        &self.description
    }

    fn weight(&self, ctx: &WeightContext<'_>, h: HalfedgeId) -> f64 {
        let mut out = vec![0.0; ctx.mesh().n_halfedges()];
        self.fill_weights(ctx, &mut out);
        out[h.index()]
    }

    fn fill_weights(&self, ctx: &WeightContext<'_>, out: &mut [f64]) {
        match self.call(ctx) {
            Ok(weights) => out.copy_from_slice(&weights),
            Err(e) => {
                // Non-finite weights stop the run; the exception is raised after it.
                self.failure
                    .lock()
                    .unwrap_or_else(PoisonError::into_inner)
                    .get_or_insert(e);
                out.fill(f64::NAN);
            }
        }
    }

    fn depends_on_positions(&self) -> bool {
        self.depends_on_positions
    }
}

/// Where the Python scheme `name` leaves its exception (`None` for a built-in scheme).
/// A run takes it with the scheme, before it starts, and reads it with [`take`] after
/// it: a scheme replaced meanwhile (`register_weight(..., replace=True)` from another
/// thread) gets a new slot, and the run must read the one its scheme writes.
pub(crate) fn failure_slot(name: &str) -> Option<Slot> {
    slots()
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .get(name)
        .cloned()
}

/// The first exception left in `slot` since it was last read, if any.
pub(crate) fn take(slot: Option<&Slot>) -> Option<PyErr> {
    slot?.lock().unwrap_or_else(PoisonError::into_inner).take()
}

/// Registers a weight scheme computed by a Python function, under `name`.
///
/// `function(h)` is called once per weight refresh with a dict of per-halfedge numpy
/// arrays for the whole mesh (H halfedges; halfedge `h` goes from vertex `i` to
/// vertex `j`, its twin is `h ^ 1`; boundary halfedges included):
///
/// - `from_vertex`, `to_vertex`, `twin`, `face` (int64; `face` is -1 on the boundary);
/// - `edge_vector` (H, 3) `x_j - x_i`, `edge_length` (H);
/// - `opposite_cotangent` (H): the cotangent of the angle opposite `h` in its
///   triangle, 0 on the boundary and for degenerate triangles;
/// - `face_normal` (H, 3) and `face_area` (H) of the face of `h` (0 on the boundary);
/// - `positions` (N, 3): the current vertex positions.
///
/// It returns one weight per halfedge, `w_ij` for `h = (i -> j)`, the coefficient of
/// `j` in the row of `i` (array-like of H floats). The name then works wherever a
/// built-in's does (`smooth(mesh, weights=name)`). `depends_on_positions=False`
/// tells the smoother that the weights never change, so they are computed once.
///
/// The function runs with the GIL held; an exception raised in it stops the run and
/// propagates. Raises `TypeError` when `function` is not callable, `ValueError` when the
/// name is not lowercase letters, digits, `-` and `_`, or is taken. `replace=True` puts
/// the new function in the place of a scheme registered from Python under the same
/// name (a notebook cell run again); a built-in scheme is never replaced.
///
/// Example, the cotangent weights: `lambda h: 0.5 * (h["opposite_cotangent"] +
/// h["opposite_cotangent"][h["twin"]])`.
#[pyfunction]
#[pyo3(signature = (name, function, *, description = "", depends_on_positions = true, replace = false))]
pub(crate) fn register_weight(
    py: Python<'_>,
    name: &Bound<'_, PyAny>,
    function: Py<PyAny>,
    description: &str,
    depends_on_positions: bool,
    replace: bool,
) -> PyResult<()> {
    let name: String = name.extract().map_err(|_| {
        pyo3::exceptions::PyTypeError::new_err(format!(
            "the scheme's name must be a str, got {}",
            name.get_type()
                .name()
                .map_or_else(|_| "an object".to_string(), |n| n.to_string())
        ))
    })?;
    if !function.bind(py).is_callable() {
        return Err(pyo3::exceptions::PyTypeError::new_err(format!(
            "the weight function must be callable (it is called with a dict of per-halfedge arrays), got {}",
            function.bind(py).get_type().name()?
        )));
    }
    let failure = Slot::default();
    let scheme = PythonScheme {
        name: name.clone(),
        description: description.to_string(),
        function,
        depends_on_positions,
        failure: Arc::clone(&failure),
    };
    let own = slots()
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .contains_key(&name);
    if replace && own {
        self::replace(scheme)?;
    } else if replace && crate::weights::is_registered(&name)? {
        return Err(PyValueError::new_err(format!(
            "{name:?} is a built-in weight scheme; replace=True replaces only schemes registered from Python"
        )));
    } else {
        register(scheme)?;
    }
    slots()
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .insert(name, failure);
    Ok(())
}
