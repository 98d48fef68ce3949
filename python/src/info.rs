//! `beltrami.info`: counts, topology and geometry of a mesh, as `beltrami info --json`.

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::{DVec3, HalfedgeMesh, RepairReport};
use beltrami_io::MeshFormat;
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
    let m = &mesh.mesh;
    let geometry = Geometry::new(m, &mesh.positions).map_err(|e| topology_error(None, &e))?;
    let mut loop_lengths: Vec<usize> = m.boundary_loops().map(|l| l.len()).collect();
    loop_lengths.sort_unstable_by(|a, b| b.cmp(a));
    let bbox = geometry.bounding_box();
    let components = m.connected_components();
    let component_genus: Vec<Option<u32>> =
        components.summaries.iter().map(|c| c.genus()).collect();
    let degenerate_faces = m
        .faces()
        .filter(|&f| geometry.is_degenerate_face(f))
        .count();
    let d = PyDict::new(py);
    d.set_item(
        "file",
        mesh.source.as_ref().map(|(p, _)| p.display().to_string()),
    )?;
    d.set_item("format", mesh.source.as_ref().map(|(_, f)| format_name(*f)))?;
    d.set_item("vertices", m.n_vertices())?;
    d.set_item("faces", m.n_faces())?;
    d.set_item("edges", m.n_edges())?;
    d.set_item("triangle_mesh", m.is_triangle_mesh())?;
    d.set_item("boundary_loops", loop_lengths.len())?;
    d.set_item("boundary_loop_lengths", loop_lengths)?;
    d.set_item("components", components.count())?;
    d.set_item("euler_characteristic", m.euler_characteristic())?;
    d.set_item("closed", m.n_faces() > 0 && m.is_closed())?;
    d.set_item(
        "genus",
        match component_genus.as_slice() {
            [only] => *only,
            _ => None,
        },
    )?;
    d.set_item("component_genus", component_genus)?;
    d.set_item(
        "isolated_vertices",
        m.vertices().filter(|&v| m.is_isolated(v)).count(),
    )?;
    d.set_item("degenerate_faces", degenerate_faces)?;
    d.set_item("bbox_min", bbox.map(|(lo, _)| lo.to_array()))?;
    d.set_item("bbox_max", bbox.map(|(_, hi)| hi.to_array()))?;
    d.set_item("mean_edge_length", geometry.mean_edge_length())?;
    d.set_item("area", surface_area(&geometry, m, &mesh.positions))?;
    d.set_item("volume", geometry.volume().ok())?;
    d.set_item(
        "repairs",
        repairs(py, &mesh.repair.clone().unwrap_or_default())?,
    )?;
    Ok(d)
}

/// The format's name as `info` prints it.
fn format_name(format: MeshFormat) -> &'static str {
    match format {
        MeshFormat::Ply => "PLY",
        MeshFormat::Stl => "STL",
        MeshFormat::Obj => "OBJ",
        MeshFormat::Off => "OFF",
        MeshFormat::X3p => "X3P",
        MeshFormat::Sdf => "SDF",
        _ => "mesh",
    }
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
    d.set_item("cut_edges", pairs(&r.cut_edges))?;
    d.set_item("opened_edges", pairs(&r.opened_edges))?;
    d.set_item("flipped_faces", r.flipped_faces.clone())?;
    d.set_item("split_vertices", pairs(&r.split_vertices))?;
    d.set_item("removed_vertices", r.removed_vertices.clone())?;
    Ok(d)
}

/// The surface area, computed again at a power-of-two scale when the face areas
/// overflow, so that `inf` means the true area is beyond float64 (as `info` does).
fn surface_area(geometry: &Geometry<'_>, mesh: &HalfedgeMesh, positions: &[DVec3]) -> f64 {
    let area = geometry.surface_area();
    if area.is_finite() {
        return area;
    }
    let largest = positions
        .iter()
        .map(|p| p.abs().max_element())
        .fold(0.0f64, f64::max);
    if !largest.is_finite() || largest == 0.0 {
        return area;
    }
    let k = largest.log2().ceil();
    let scale = (-k).exp2();
    let scaled: Vec<DVec3> = positions.iter().map(|p| *p * scale).collect();
    match Geometry::new(mesh, &scaled) {
        Ok(g) => g.surface_area() * (2.0 * k).exp2(),
        Err(_) => area,
    }
}
