//! The mesh algorithms: `beltrami.quality`, `beltrami.subdivide`, `beltrami.delaunay`,
//! with the words, defaults and JSON keys of the commands `info --quality`,
//! `subdivide` and `delaunay`.

use beltrami_algorithms::quality::ASPECT_RATIO_BINS;
use beltrami_algorithms::{
    DelaunayError, DelaunayOptions, MeshQuality, QualityError, Scheme, SubdivisionError,
    delaunay_flip, flipped_faces, mesh_quality,
};
use beltrami_halfedge::{DVec3, HalfedgeMesh};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{MeshError, no_panic, topology_error};
use crate::mesh::Mesh;

fn quality_error(e: &QualityError) -> PyErr {
    match e {
        QualityError::NotTriangle { face, len } => MeshError::new_err(format!(
            "face {face} has {len} vertices; quality needs a triangle mesh (triangulate it first)"
        )),
        e => MeshError::new_err(e.to_string()),
    }
}

/// A new `Mesh` from a result of the algorithms (valid by construction).
fn result_mesh(mesh: HalfedgeMesh, positions: Vec<DVec3>) -> Mesh {
    let faces = mesh.to_polygons();
    Mesh {
        positions,
        faces,
        mesh,
        source: None,
        repair: None,
    }
}

/// Triangle quality of `mesh`, as the `quality` object of
/// `beltrami info --quality --json`: `degenerate_faces`, `min_angle_degrees`,
/// `max_angle_degrees`, `mean_min_angle_degrees`, `mean_aspect_ratio`,
/// `max_aspect_ratio` (None without a non-degenerate triangle), `aspect_ratio_bins`
/// (the bins' upper ends; the last bin is open), `aspect_ratio_histogram`,
/// `edge_length_min`, `edge_length_mean`, `edge_length_max`, `edge_length_cv` (the
/// coefficient of variation), `valence_histogram` and `boundary_valence_histogram`
/// (index k: vertices with k edges), `regular_share` (valence 6 inside, 4 on the
/// boundary; 0 to 1), `interior_edges`, `negative_cotangent_edges`,
/// `negative_cotangent_share`, and `flipped_faces`: with `reference` (the same mesh
/// at other positions, e.g. before smoothing) the triangles whose orientation turned
/// against it, else None.
///
/// Raises `MeshError` for a polygon mesh or a reference with other faces.
#[pyfunction]
#[pyo3(signature = (mesh, reference = None))]
pub(crate) fn quality<'py>(
    py: Python<'py>,
    mesh: &Mesh,
    reference: Option<&Mesh>,
) -> PyResult<Bound<'py, PyDict>> {
    if let Some(r) = reference
        && r.faces != mesh.faces
    {
        return Err(MeshError::new_err(format!(
            "the reference must have the same faces ({} faces against {}); the flipped-face count compares two placements of one mesh",
            r.faces.len(),
            mesh.faces.len()
        )));
    }
    let (q, flipped) = py.detach(|| {
        no_panic(|| {
            let q = mesh_quality(&mesh.mesh, &mesh.positions).map_err(|e| quality_error(&e))?;
            let flipped = reference
                .map(|r| flipped_faces(&mesh.mesh, &mesh.positions, &r.positions))
                .transpose()
                .map_err(|e| quality_error(&e))?;
            Ok((q, flipped))
        })
    })?;
    quality_dict(py, &q, flipped)
}

fn quality_dict<'py>(
    py: Python<'py>,
    q: &MeshQuality,
    flipped: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let shape = q.shape.as_ref();
    let edges = q.edge_length.as_ref();
    d.set_item("degenerate_faces", q.degenerate_faces)?;
    d.set_item("min_angle_degrees", shape.map(|s| s.min_angle))?;
    d.set_item("max_angle_degrees", shape.map(|s| s.max_angle))?;
    d.set_item("mean_min_angle_degrees", shape.map(|s| s.mean_min_angle))?;
    d.set_item("mean_aspect_ratio", shape.map(|s| s.mean_aspect_ratio))?;
    d.set_item("max_aspect_ratio", shape.map(|s| s.max_aspect_ratio))?;
    d.set_item("aspect_ratio_bins", ASPECT_RATIO_BINS.to_vec())?;
    d.set_item(
        "aspect_ratio_histogram",
        shape.map_or_else(
            || vec![0; ASPECT_RATIO_BINS.len() + 1],
            |s| s.aspect_ratio_histogram.clone(),
        ),
    )?;
    d.set_item("edge_length_min", edges.map(|e| e.min))?;
    d.set_item("edge_length_mean", edges.map(|e| e.mean))?;
    d.set_item("edge_length_max", edges.map(|e| e.max))?;
    d.set_item("edge_length_cv", edges.map(|e| e.cv))?;
    d.set_item("valence_histogram", q.valence_histogram.clone())?;
    d.set_item(
        "boundary_valence_histogram",
        q.boundary_valence_histogram.clone(),
    )?;
    d.set_item("regular_share", q.regular_share)?;
    d.set_item("interior_edges", q.interior_edges)?;
    d.set_item("negative_cotangent_edges", q.negative_cotangent_edges)?;
    d.set_item("negative_cotangent_share", q.negative_cotangent_share())?;
    d.set_item("flipped_faces", flipped)?;
    Ok(d)
}

/// Subdivides `mesh` `steps` times with `scheme` (`"loop"`: every triangle into four,
/// Loop 1987; `"sqrt3"`: √3 subdivision, Kobbelt 2000), as `beltrami subdivide`. The old
/// vertices keep their indices; new ones are appended. Returns a new `Mesh`.
///
/// Raises `ValueError` for an unknown scheme, `MeshError` for a polygon mesh or a
/// result too large for a mesh.
#[pyfunction]
#[pyo3(signature = (mesh, scheme = "loop", steps = 1))]
pub(crate) fn subdivide(py: Python<'_>, mesh: &Mesh, scheme: &str, steps: usize) -> PyResult<Mesh> {
    let Some(scheme) = Scheme::from_name(scheme) else {
        return Err(PyValueError::new_err(format!(
            "unknown scheme {scheme:?}; the schemes are {}",
            Scheme::ALL.map(Scheme::name).join(", ")
        )));
    };
    let (m, p) = py.detach(|| {
        no_panic(|| {
            scheme
                .subdivide(&mesh.mesh, &mesh.positions, steps)
                .map_err(|e| match e {
                    SubdivisionError::NotTriangle { face, len } => MeshError::new_err(format!(
                        "face {face} has {len} vertices; subdivide needs a triangle mesh (triangulate it first)"
                    )),
                    e => MeshError::new_err(e.to_string()),
                })
        })
    })?;
    Ok(result_mesh(m, p))
}

/// Flips edges until no cotangent weight is negative (a Delaunay mesh on the same
/// vertices), as `beltrami delaunay`. `max_dihedral` (degrees, 0 to 180) leaves edges
/// whose two triangles meet at a larger angle alone (features, curved regions);
/// `max_flips` caps the flips (default ten per edge). Returns `(Mesh, report)` with the
/// report's keys as `delaunay --json`: `flips`, `negative_before`, `negative_after`,
/// `kept_by_dihedral`, `kept_by_topology`, `hit_flip_limit`, `max_deviation` (how far
/// the surface moved, in the mesh's unit).
///
/// Raises `ValueError` for a dihedral bound outside [0, 180], `MeshError` for a polygon
/// mesh.
#[pyfunction]
#[pyo3(signature = (mesh, max_dihedral = None, max_flips = None))]
pub(crate) fn delaunay<'py>(
    py: Python<'py>,
    mesh: &Mesh,
    max_dihedral: Option<f64>,
    max_flips: Option<usize>,
) -> PyResult<(Mesh, Bound<'py, PyDict>)> {
    let mut options = DelaunayOptions::default();
    if let Some(d) = max_dihedral {
        if !(0.0..=180.0).contains(&d) {
            return Err(PyValueError::new_err(format!(
                "max_dihedral must be between 0 and 180 degrees, got {d}"
            )));
        }
        options = options.max_dihedral(d.to_radians());
    }
    if let Some(n) = max_flips {
        options = options.max_flips(n);
    }
    let (m, p, report) = py.detach(|| {
        no_panic(|| {
            delaunay_flip(&mesh.mesh, &mesh.positions, options).map_err(|e| match e {
                DelaunayError::NotTriangle { face, len } => MeshError::new_err(format!(
                    "face {face} has {len} vertices; delaunay needs a triangle mesh (triangulate it first)"
                )),
                DelaunayError::Topology(e) => topology_error(None, &e),
                e => MeshError::new_err(e.to_string()),
            })
        })
    })?;
    let d = PyDict::new(py);
    d.set_item("flips", report.flips)?;
    d.set_item("negative_before", report.negative_before)?;
    d.set_item("negative_after", report.negative_after)?;
    d.set_item("kept_by_dihedral", report.kept_by_dihedral)?;
    d.set_item("kept_by_topology", report.kept_by_topology)?;
    d.set_item("hit_flip_limit", report.hit_flip_limit)?;
    d.set_item("max_deviation", report.max_deviation)?;
    Ok((result_mesh(m, p), d))
}
