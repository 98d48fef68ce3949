//! `beltrami.read` and `beltrami.write`.

use beltrami_halfedge::{RepairOptions, repair};
use beltrami_io::{
    Encoding, MeshFormat, ReadOptions, VertexAttributes, Weld, WriteOptions, read_mesh_with,
    write_mesh, write_ply,
};
use numpy::PyReadonlyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::errors::{io_error, no_panic, topology_error};
use crate::mesh::Mesh;

// The signature of `read` writes the default out (a literal shows in
// `inspect.signature`, a constant shows as `Ellipsis`): it must stay the library's.
const _: () = assert!(Weld::DEFAULT_RELATIVE == 1e-6);

/// The largest weld tolerance, as on the command line: a hundredth of the diagonal
/// already joins features of a coarse mesh.
const MAX_WELD_TOLERANCE: f64 = 0.01;

/// Reads a mesh file (.ply, .stl, .obj or .off) or a height map (.x3p or .sdf, in
/// metres, as a triangulated grid of its valid points) and builds its connectivity.
///
/// `weld_tolerance` welds an STL's triangle corners closer than this fraction of the
/// bounding-box diagonal (0 welds identical coordinates only; at most 0.01); indexed
/// formats are read as they are. `lenient` reads a PLY file holding more than its
/// header declares for what the header declares. `repair` repairs the faces (drops
/// degenerate and duplicate faces, cuts non-manifold edges, re-orients, splits
/// pinched vertices, removes unreferenced vertices) instead of failing; `info(mesh)`
/// then lists what changed; `triangulate` (with `repair`) also splits polygons into
/// triangles by ear clipping in their plane.
///
/// Raises `FileNotFoundError` (or another `OSError`) when the file cannot be read,
/// `FormatError` when it cannot be decoded and `MeshError` when its faces are not an
/// oriented 2-manifold. The file is read without holding the GIL.
#[pyfunction]
#[pyo3(signature = (path, *, weld_tolerance = 1e-6, lenient = false, repair = false, triangulate = false))]
pub(crate) fn read(
    py: Python<'_>,
    path: &Bound<'_, PyAny>,
    weld_tolerance: f64,
    lenient: bool,
    repair: bool,
    triangulate: bool,
) -> PyResult<Mesh> {
    let path = crate::errors::path_arg("path", path)?;
    crate::errors::triangulate_needs_repair(repair, triangulate)?;
    let weld = if weld_tolerance == 0.0 {
        Weld::Exact
    } else {
        Weld::Relative(weld_tolerance)
    };
    weld.check()
        .map_err(|e| PyValueError::new_err(format!("weld_tolerance: {e}")))?;
    if weld_tolerance > MAX_WELD_TOLERANCE {
        return Err(PyValueError::new_err(format!(
            "weld_tolerance {weld_tolerance} is a fraction of the bounding-box diagonal and at most {MAX_WELD_TOLERANCE}; larger values weld the part's own features together"
        )));
    }
    let options = ReadOptions::new().weld(weld).lenient(lenient);
    let fix = repair.then(|| RepairOptions::new().triangulate(triangulate));
    py.detach(|| no_panic(|| read_inner(&path, &options, fix.as_ref())))
}

fn read_inner(
    path: &std::path::Path,
    options: &ReadOptions,
    fix: Option<&RepairOptions>,
) -> PyResult<Mesh> {
    let format = MeshFormat::from_path(path).map_err(|e| io_error(path, &e))?;
    let (data, _report) = read_mesh_with(path, options).map_err(|e| io_error(path, &e))?;
    let (positions, faces, report) = if let Some(fix) = fix {
        let repaired = repair(&data.positions, &data.faces, fix)
            .map_err(|e| topology_error(Some(path), &e))?;
        crate::errors::refuse_empty_repair(Some(path), data.faces.len(), repaired.faces.len())?;
        (repaired.positions, repaired.faces, Some(repaired.report))
    } else {
        (data.positions, data.faces, None)
    };
    let mesh = beltrami_halfedge::HalfedgeMesh::from_polygon_list(positions.len(), &faces)
        .map_err(|e| {
            if fix.is_some() {
                topology_error(Some(path), &e)
            } else {
                crate::errors::repairable_error(Some(path), &e)
            }
        })?;
    Ok(Mesh {
        positions,
        faces: std::sync::Arc::new(faces),
        mesh: std::sync::Arc::new(mesh),
        source: Some((path.to_path_buf(), format)),
        repair: report,
    })
}

/// Writes a mesh file; the format follows the extension (.ply, .stl, .obj or .off, or
/// .x3p or .sdf for a mesh that is a height map's grid, such as one read from one).
///
/// PLY and STL are written binary unless `ascii`; PLY stores float64 coordinates, so
/// a PLY round trip is exact. `scalars` (a mapping from names to one value per
/// vertex) adds per-vertex `double` properties and needs a .ply path. The file is
/// replaced atomically, without holding the GIL.
///
/// A write-protected file is replaced only with `force=True`, as the commands replace
/// one only with `--force`.
///
/// The file is flushed to disk (fsync) before the rename and its directory after it, so
/// that the new file survives a power loss. `sync=False` leaves the flushes out, as
/// the commands' `--no-sync` does: the target is still replaced by a rename (an
/// interrupted call leaves it untouched), but a power loss or operating-system crash
/// soon after may leave the old file, an empty one or a partly written one there, and a
/// write error that a file system reports only at the flush (network file systems may,
/// for a full disk or a quota) goes unnoticed. For many small files into local scratch
/// space; a flush costs about 0.3 ms on a local disk.
///
/// Raises `FormatError` for an unsupported extension or bad scalars, or for an STL file
/// of a mesh whose repair on reading split vertices (STL would join them again),
/// `PermissionError` for a write-protected file without `force`, `OSError` when the
/// file cannot be written. Warns (`UserWarning`) when an STL file leaves out vertices
/// in no face: STL stores triangles only.
#[pyfunction]
#[pyo3(signature = (path, mesh, scalars = None, *, ascii = false, force = false, sync = true))]
pub(crate) fn write(
    py: Python<'_>,
    path: &Bound<'_, PyAny>,
    mesh: &Mesh,
    scalars: Option<&Bound<'_, PyAny>>,
    ascii: bool,
    force: bool,
    sync: bool,
) -> PyResult<()> {
    let path = crate::errors::path_arg("path", path)?;
    if !force && std::fs::metadata(&path).is_ok_and(|m| m.is_file() && m.permissions().readonly()) {
        return Err(pyo3::exceptions::PyPermissionError::new_err(format!(
            "{}: the file is write-protected (pass force=True to replace it)",
            path.display()
        )));
    }
    // STL keeps no vertex indices: the copies a repair on reading split off would be
    // joined to their originals again when the file is read.
    let split = mesh.repair.as_ref().map_or(0, |r| r.split_vertices.len());
    if let Some(message) = MeshFormat::from_path(&path)
        .ok()
        .and_then(|f| f.loses_split_vertices(split))
    {
        return Err(crate::errors::FormatError::new_err(format!(
            "{}: {message}",
            path.display()
        )));
    }
    // STL stores triangles only: say so when a vertex in no face is left out.
    let dropped = MeshFormat::from_path(&path)
        .ok()
        .and_then(|f| f.drops_vertices_in_no_face(mesh.mesh.n_isolated_vertices()));
    let options = WriteOptions::default().encoding(if ascii {
        Encoding::Ascii
    } else {
        Encoding::BinaryLittleEndian
    });
    let data = mesh.data();
    let attributes = match scalars {
        None => None,
        Some(scalars) => {
            let numpy = py.import("numpy")?;
            // Any mapping (a dict, a `MappingProxyType`, a pandas row's `to_dict()`):
            // its items.
            let items = scalars.call_method0("items").map_err(|_| {
                pyo3::exceptions::PyTypeError::new_err(
                    "scalars must be a mapping from names to one value per vertex",
                )
            })?;
            let mut fields = Vec::new();
            for item in items.try_iter()? {
                let (name, values): (Bound<'_, PyAny>, Bound<'_, PyAny>) = item?.extract()?;
                let name: String = name.extract()?;
                let values = numpy.call_method1("ascontiguousarray", (values, "float64"))?;
                let values = numpy.call_method1("ravel", (values,))?;
                let values: PyReadonlyArray1<'_, f64> = values.extract()?;
                fields.push((name, values.as_slice()?.to_vec()));
            }
            Some(VertexAttributes {
                scalars: fields,
                colors: None,
            })
        }
    };
    if attributes.is_some() && MeshFormat::from_path(&path).ok() != Some(MeshFormat::Ply) {
        return Err(crate::errors::FormatError::new_err(format!(
            "{}: scalars are written to .ply files only",
            path.display()
        )));
    }
    // The choice is this thread's (the pool worker `no_panic` runs the write on), for this
    // call only: other threads' writes keep flushing. The write path starts no parallel
    // work; if it did, a worker waiting inside it could run another queued call (a
    // study's staged directory, say) under this choice.
    py.detach(|| {
        no_panic(|| {
            beltrami_io::with_flush_to_disk(sync, || match &attributes {
                None => write_mesh(&path, &data, &options),
                Some(attributes) => write_ply(&path, &data, attributes, &options),
            })
            .map_err(|e| io_error(&path, &e))
        })
    })?;
    // Said once the file is written (a failed write has nothing to warn about).
    if let Some(note) = dropped {
        crate::errors::warn_user(py, &format!("{}: {note}", path.display()))?;
    }
    Ok(())
}
