//! `beltrami.info`: counts, topology and geometry of a mesh, as `beltrami info --json`.

use beltrami_halfedge::RepairReport;
use beltrami_halfedge::geometry::Geometry;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::topology_error;
use crate::mesh::Mesh;

/// Counts, topology and geometry of `mesh`: a dict with the keys of
/// `beltrami info --json` (`file`, `format`, `vertices`, `faces`, `edges`,
/// `triangle_mesh`, `boundary_loops`, `boundary_loop_lengths`, `components`,
/// `euler_characteristic`, `closed`, `genus`, `component_genus`,
/// `isolated_vertices`, `degenerate_faces`, `bbox_min`, `bbox_max`,
/// `mean_edge_length`, `area`, `volume`, `repairs`).
///
/// `file` and `format` are None for a mesh built from arrays; `volume` is None for
/// an open mesh; `genus` is None for several components (see `component_genus`).
#[pyfunction]
pub(crate) fn info<'py>(py: Python<'py>, mesh: &Mesh) -> PyResult<Bound<'py, PyDict>> {
    let s = Geometry::new(&mesh.mesh, &mesh.positions)
        .map_err(|e| topology_error(None, &e))?
        .summary();
    let d = PyDict::new(py);
    d.set_item(
        "file",
        mesh.source.as_ref().map(|(p, _)| p.display().to_string()),
    )?;
    d.set_item("format", mesh.source.as_ref().map(|(_, f)| f.name()))?;
    d.set_item("vertices", s.vertices)?;
    d.set_item("faces", s.faces)?;
    d.set_item("edges", s.edges)?;
    d.set_item("triangle_mesh", s.triangle_mesh)?;
    d.set_item("boundary_loops", s.boundary_loop_lengths.len())?;
    d.set_item("boundary_loop_lengths", s.boundary_loop_lengths)?;
    d.set_item("components", s.components)?;
    d.set_item("euler_characteristic", s.euler_characteristic)?;
    d.set_item("closed", s.closed)?;
    d.set_item("genus", s.genus)?;
    d.set_item("component_genus", s.component_genus)?;
    d.set_item("isolated_vertices", s.isolated_vertices)?;
    d.set_item("degenerate_faces", s.degenerate_faces)?;
    d.set_item("bbox_min", s.bounding_box.map(|(lo, _)| lo.to_array()))?;
    d.set_item("bbox_max", s.bounding_box.map(|(_, hi)| hi.to_array()))?;
    d.set_item("mean_edge_length", s.mean_edge_length)?;
    d.set_item("area", s.area)?;
    d.set_item("volume", s.volume)?;
    d.set_item(
        "repairs",
        repairs(py, &mesh.repair.clone().unwrap_or_default())?,
    )?;
    Ok(d)
}

/// What a repair changed, with the keys of `info --json`'s `repairs`.
fn repairs<'py>(py: Python<'py>, r: &RepairReport) -> PyResult<Bound<'py, PyDict>> {
    let pairs = |v: &[(u32, u32)]| v.iter().map(|&(a, b)| [a, b]).collect::<Vec<_>>();
    let d = PyDict::new(py);
    d.set_item("merged_vertices", pairs(&r.merged_vertices))?;
    d.set_item(
        "dropped_degenerate_faces",
        r.dropped_degenerate_faces.clone(),
    )?;
    d.set_item(
        "dropped_duplicate_faces",
        r.dropped_duplicate_faces
            .iter()
            .map(|&(a, b)| [a, b])
            .collect::<Vec<_>>(),
    )?;
    d.set_item("shortened_faces", r.shortened_faces.clone())?;
    d.set_item("triangulated_faces", r.triangulated_faces.clone())?;
    d.set_item("cut_edges", pairs(&r.cut_edges))?;
    d.set_item("opened_edges", pairs(&r.opened_edges))?;
    d.set_item("flipped_faces", r.flipped_faces.clone())?;
    d.set_item("split_vertices", pairs(&r.split_vertices))?;
    d.set_item("removed_vertices", r.removed_vertices.clone())?;
    Ok(d)
}
