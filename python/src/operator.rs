//! `beltrami.laplacian` and `beltrami.mass_matrix`: the operators as `scipy.sparse`
//! CSR matrices, for people's own solvers.

use beltrami_halfedge::VertexId;
use beltrami_halfedge::geometry::{Geometry, VertexAreaKind};
use beltrami_weights::{Laplacian, LaplacianOptions, Normalization};
use numpy::PyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::errors::{MeshError, no_panic};
use crate::mesh::Mesh;
use crate::weights::scheme;

/// CSR arrays: data, column indices, row offsets.
type Csr = (Vec<f64>, Vec<i64>, Vec<i64>);

/// `scipy.sparse.csr_matrix((data, indices, indptr), shape=(n, n))`.
fn csr_matrix(
    py: Python<'_>,
    (data, indices, indptr): Csr,
    n: usize,
) -> PyResult<Bound<'_, PyAny>> {
    let sparse = py.import("scipy.sparse")?;
    sparse.getattr("csr_matrix")?.call1((
        (
            PyArray1::from_vec(py, data),
            PyArray1::from_vec(py, indices),
            PyArray1::from_vec(py, indptr),
        ),
        (n, n),
    ))
}

fn area_kind(vertex_area: &str) -> PyResult<VertexAreaKind> {
    match vertex_area {
        "mixed" => Ok(VertexAreaKind::MixedVoronoi),
        "barycentric" => Ok(VertexAreaKind::Barycentric),
        _ => Err(PyValueError::new_err(format!(
            "vertex_area must be one of 'mixed', 'barycentric', got '{vertex_area}'"
        ))),
    }
}

/// The Laplacian `L` the smoother applies, as an (N, N) `scipy.sparse` CSR matrix,
/// so that `L @ mesh.vertices` is the `L x` of docs/laplacian.md.
///
/// Sign and normalisation as there: `L x_i` points from `x_i` towards its weighted
/// neighbours, so `x + lam * L x` is one explicit step. Weight sum (`normalize="sum"`,
/// the default): `L_ij = w_ij / W_i`, `L_ii = -1`. Area (`"area"`): `L_ij = w_ij /
/// A_i`, `L_ii = -W_i / A_i`, with `A_i` the vertex area of `vertex_area`. Rows of
/// vertices that cannot move (weights summing to <= 0, zero area, isolated) are zero.
/// `weights` and `cotangent_negative` as for `smooth`. Needs scipy.
#[pyfunction]
#[pyo3(signature = (mesh, weights = "cotangent", normalize = "sum", *, vertex_area = "mixed", cotangent_negative = "keep"))]
pub(crate) fn laplacian<'py>(
    py: Python<'py>,
    mesh: &Mesh,
    weights: &str,
    normalize: Option<&str>,
    vertex_area: &str,
    cotangent_negative: &str,
) -> PyResult<Bound<'py, PyAny>> {
    // None is the default, as `smooth` takes it.
    let normalize = normalize.unwrap_or("sum");
    let normalization = match normalize {
        "sum" => Normalization::WeightSum,
        "area" => Normalization::Area(area_kind(vertex_area)?),
        _ => {
            return Err(PyValueError::new_err(format!(
                "normalize must be one of 'sum', 'area', got '{normalize}'"
            )));
        }
    };
    let negative = crate::study::negative_weights(cotangent_negative)?;
    let scheme = scheme(weights)?;
    let failure = crate::scheme::failure_slot(weights);
    let n = mesh.mesh.n_vertices();
    let csr = py.detach(|| {
        no_panic(|| {
            let options = LaplacianOptions::new()
                .normalization(normalization)
                .negative(negative);
            let lap = Laplacian::new(&mesh.mesh, &mesh.positions, scheme.as_ref(), options)
                .map_err(|e| MeshError::new_err(e.to_string()))?;
            let mut data = Vec::new();
            let mut indices = Vec::new();
            let mut indptr = Vec::with_capacity(n + 1);
            indptr.push(0);
            let stuck = lap.stuck_rows();
            for i in 0..n {
                let v = VertexId::new(i as u32);
                if let Some(scale) = lap.scale(v) {
                    let mut row: Vec<(i64, f64)> = lap
                        .row(v)
                        .map(|(j, w)| (j.index() as i64, w * scale))
                        .collect();
                    row.push((i as i64, -lap.weight_sum(v) * scale));
                    row.sort_by_key(|&(j, _)| j);
                    for (j, w) in row {
                        indices.push(j);
                        data.push(w);
                    }
                }
                indptr.push(indices.len() as i64);
            }
            Ok((data, indices, indptr, stuck))
        })
    });
    // The scheme's own exception first (and taken in any case, so that it is not
    // raised by a later call): a failed Python scheme leaves NaN weights, which the
    // operator then reports in less helpful terms.
    if let Some(e) = crate::scheme::take(failure.as_ref()) {
        return Err(e);
    }
    let (data, indices, indptr, stuck) = csr?;
    // Zero rows are what `smooth` warns of as vertices that cannot move.
    if stuck > 0 {
        let why = if mesh.mesh.is_triangle_mesh() || matches!(weights, "uniform" | "distance") {
            "their weights sum to <= 0 or their area is 0".to_string()
        } else {
            format!(
                "the mesh has polygon faces, on which {weights} weights are 0; use weights=\"uniform\" or \"distance\", or read it with repair=True, triangulate=True"
            )
        };
        crate::errors::warn_user(py, &format!("{stuck} of the {n} rows are zero ({why})"))?;
    }
    csr_matrix(py, (data, indices, indptr), n)
}

/// The lumped mass matrix: the diagonal (N, N) `scipy.sparse` CSR matrix of vertex
/// areas (`"mixed"`: mixed Voronoi, Meyer et al. 2003; `"barycentric"`: a third of
/// the incident triangles' areas), the `M` of the implicit step `(M - lam L) x' = M x`.
/// Needs scipy.
#[pyfunction]
#[pyo3(signature = (mesh, *, vertex_area = "mixed"))]
pub(crate) fn mass_matrix<'py>(
    py: Python<'py>,
    mesh: &Mesh,
    vertex_area: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let kind = area_kind(vertex_area)?;
    let n = mesh.mesh.n_vertices();
    let areas = py.detach(|| {
        no_panic(|| {
            Geometry::new(&mesh.mesh, &mesh.positions)
                .and_then(|g| g.vertex_areas(kind))
                .map_err(|e| MeshError::new_err(e.to_string()))
        })
    })?;
    let data: Vec<f64> = areas.as_slice().to_vec();
    let indices: Vec<i64> = (0..n as i64).collect();
    let indptr: Vec<i64> = (0..=n as i64).collect();
    csr_matrix(py, (data, indices, indptr), n)
}
