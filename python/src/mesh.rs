//! `beltrami.Mesh`: positions and faces with their half-edge connectivity.

use std::path::PathBuf;
use std::sync::Arc;

use beltrami_halfedge::{DVec3, HalfedgeMesh, PolygonList, RepairOptions, RepairReport};
use beltrami_io::{MeshData, MeshFormat};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyList;

use crate::errors::{MeshError, no_panic, repairable_error, topology_error};

/// A triangle (or polygon) mesh: vertex positions, faces and their half-edge
/// connectivity, validated when built.
///
/// `Mesh(vertices, faces)` takes an (N, 3) array of coordinates (any real dtype,
/// stored as float64) and an (M, k) array of vertex indices (any integer dtype,
/// k ≥ 3; k = 3 for triangles), or a list of faces of different sizes (as `faces`
/// returns a mesh of triangles and quads); an empty list is no faces. Raises
/// `MeshError` naming the offending vertex or face when a coordinate is not finite, an
/// index is out of range, or the faces do not form an oriented 2-manifold.
/// `Mesh(vertices, faces, repair=True)` repairs the faces instead, as `read(path,
/// repair=True)` does (drops degenerate and duplicate faces, those of one or two
/// vertices too, cuts non-manifold edges, re-orients, splits pinched vertices, removes
/// vertices no face uses; `info(mesh)` then lists what changed, in the input's indices),
/// and raises `MeshError` only when the repair leaves no face. A mesh pickles (process pools,
/// Dask) and copies as itself (it cannot change).
///
/// What is copied: a C-contiguous float64 (N, 3) array is read in place and copied
/// once, into the mesh's own positions (the half-edge structure owns its arrays, so
/// the mesh never aliases numpy memory; a later change to the array does not change
/// the mesh). Any other layout or dtype (Fortran order, a strided view, float32,
/// integers) is first converted by `numpy.ascontiguousarray`, a second copy. The faces
/// are read as int64 the same way (int32 faces, e.g. Open3D's, are converted first)
/// and copied into the mesh's face list. `vertices` and `faces` return fresh copies.
#[pyclass(module = "beltrami", name = "Mesh", frozen)]
pub(crate) struct Mesh {
    pub(crate) positions: Vec<DVec3>,
    /// Shared with the meshes made from this one with new positions (`smooth`'s
    /// result), which therefore copy neither the faces nor the connectivity.
    pub(crate) faces: Arc<PolygonList>,
    pub(crate) mesh: Arc<HalfedgeMesh>,
    /// The file the mesh was read from, and its format.
    pub(crate) source: Option<(PathBuf, MeshFormat)>,
    /// What a repair on reading changed.
    pub(crate) repair: Option<RepairReport>,
}

impl Mesh {
    /// Builds the connectivity of `positions` and `faces` (without the GIL).
    pub(crate) fn build(
        py: Python<'_>,
        positions: Vec<DVec3>,
        faces: PolygonList,
        source: Option<(PathBuf, MeshFormat)>,
    ) -> PyResult<Self> {
        let path = source.as_ref().map(|(p, _)| p.clone());
        let mesh = py.detach(|| {
            no_panic(|| {
                HalfedgeMesh::from_polygon_list(positions.len(), &faces)
                    .map_err(|e| topology_error(path.as_deref(), &e))
            })
        })?;
        Ok(Self {
            positions,
            faces: Arc::new(faces),
            mesh: Arc::new(mesh),
            source,
            repair: None,
        })
    }

    /// The positions and faces as the io crate holds them (copied).
    pub(crate) fn data(&self) -> MeshData {
        MeshData::new(self.positions.clone(), PolygonList::clone(&self.faces))
    }

    /// The same connectivity with new positions (the faces and the connectivity are
    /// shared, not copied).
    pub(crate) fn with_positions(&self, positions: Vec<DVec3>) -> Self {
        Self {
            positions,
            faces: Arc::clone(&self.faces),
            mesh: Arc::clone(&self.mesh),
            source: None,
            repair: None,
        }
    }
}

/// What `Mesh.__reduce__` returns: the class and its arguments, `(vertices, faces)`.
type Reduced<'py> = (Bound<'py, PyAny>, (Bound<'py, PyAny>, Bound<'py, PyAny>));

/// `numpy.ascontiguousarray(x, dtype)`.
fn contiguous<'py>(x: &Bound<'py, PyAny>, dtype: &str) -> PyResult<Bound<'py, PyAny>> {
    let numpy = x.py().import("numpy")?;
    numpy.call_method1("ascontiguousarray", (x, dtype))
}

/// The vertices of an (N, 3) array of any real dtype.
pub(crate) fn vertices_from(x: &Bound<'_, PyAny>) -> PyResult<Vec<DVec3>> {
    let kind: String = contiguous_kind(x)?;
    if !matches!(kind.as_str(), "f" | "i" | "u") {
        return Err(MeshError::new_err(format!(
            "vertices must be real numbers, got dtype kind {kind:?}"
        )));
    }
    let array = contiguous(x, "float64")?;
    let array: PyReadonlyArray2<'_, f64> = array.extract().map_err(|_| {
        MeshError::new_err(format!(
            "vertices must be an (N, 3) array, got shape {}",
            shape_of(x)
        ))
    })?;
    if array.shape()[1] != 3 {
        return Err(MeshError::new_err(format!(
            "vertices must be an (N, 3) array, got shape {}",
            shape_of(x)
        )));
    }
    let slice = array.as_slice()?;
    let positions: Vec<DVec3> = slice
        .chunks_exact(3)
        .map(|c| DVec3::new(c[0], c[1], c[2]))
        .collect();
    if let Some((i, p)) = positions.iter().enumerate().find(|(_, p)| !p.is_finite()) {
        let value = p
            .to_array()
            .into_iter()
            .find(|c| !c.is_finite())
            .unwrap_or(f64::NAN);
        return Err(MeshError::new_err(format!(
            "vertex {i} has a non-finite coordinate ({value})"
        )));
    }
    Ok(positions)
}

/// The dtype kind of `x` as numpy sees it (`f`, `i`, `u`, `b`, `O`, …).
fn contiguous_kind(x: &Bound<'_, PyAny>) -> PyResult<String> {
    let numpy = x.py().import("numpy")?;
    numpy
        .call_method1("asarray", (x,))?
        .getattr("dtype")?
        .getattr("kind")?
        .extract()
}

/// The shape of `x` as numpy sees it, for messages.
fn shape_of(x: &Bound<'_, PyAny>) -> String {
    x.py()
        .import("numpy")
        .and_then(|np| np.call_method1("shape", (x,)))
        .and_then(|s| s.str().map(|s| s.to_string()))
        .unwrap_or_else(|_| "?".to_string())
}

/// The faces of an (M, k) integer array, k ≥ 3, or of a sequence of faces of any sizes
/// (as [`Mesh::faces`] returns a polygon mesh's), indices in `0..n_vertices`. An empty
/// sequence is no faces.
fn faces_from(x: &Bound<'_, PyAny>, n_vertices: usize, short_ok: bool) -> PyResult<PolygonList> {
    let numpy = x.py().import("numpy")?;
    let is_array = x.is_instance(&numpy.getattr("ndarray")?)?;
    if !is_array && x.len().is_ok_and(|n| n == 0) {
        return Ok(PolygonList::new());
    }
    // A list of faces of different sizes: numpy cannot make an array of it (numpy
    // 1.24 and later raise; earlier ones make an array of objects).
    let ragged = !is_array
        && numpy
            .call_method1("asarray", (x,))
            .and_then(|a| a.getattr("dtype")?.getattr("kind")?.extract::<String>())
            .map_or(true, |kind| kind == "O");
    if ragged {
        let mut faces = PolygonList::new();
        for (f, face) in x.try_iter()?.enumerate() {
            let face = face?;
            let row = face_row(&face, f, n_vertices)?;
            // With a repair, a face of one or two vertices is dropped, as the repair of a
            // file drops it.
            if row.len() < 3 && !short_ok {
                return Err(MeshError::new_err(format!(
                    "face {f} has {} vertices; a face needs at least 3",
                    row.len()
                )));
            }
            faces.push(&row);
        }
        return Ok(faces);
    }
    let kind = contiguous_kind(x)?;
    // No faces: an (0, k) array, or an empty 1-D one (`np.array([])`, of any dtype).
    let shape: Vec<usize> = numpy.call_method1("shape", (x,))?.extract()?;
    if matches!(shape.as_slice(), [0] | [0, _]) {
        return Ok(PolygonList::new());
    }
    if !matches!(kind.as_str(), "i" | "u") {
        return Err(MeshError::new_err(format!(
            "faces must be an integer array, got dtype kind {kind:?}"
        )));
    }
    let bad_shape = || {
        MeshError::new_err(format!(
            "faces must be an (M, 3) array (or (M, k), k >= 3, for polygons), got shape {}",
            shape_of(x)
        ))
    };
    // Unsigned faces are read as unsigned, so that a value beyond i64 is named as it is.
    let (m, k, values): (usize, usize, Vec<i128>) = if kind == "u" {
        let array = contiguous(x, "uint64")?;
        let array: PyReadonlyArray2<'_, u64> = array.extract().map_err(|_| bad_shape())?;
        let (m, k) = (array.shape()[0], array.shape()[1]);
        (
            m,
            k,
            array.as_slice()?.iter().map(|&v| i128::from(v)).collect(),
        )
    } else {
        let array = contiguous(x, "int64")?;
        let array: PyReadonlyArray2<'_, i64> = array.extract().map_err(|_| bad_shape())?;
        let (m, k) = (array.shape()[0], array.shape()[1]);
        (
            m,
            k,
            array.as_slice()?.iter().map(|&v| i128::from(v)).collect(),
        )
    };
    if (k < 3 && m > 0 && !short_ok) || k == 0 {
        return Err(bad_shape());
    }
    let mut faces = PolygonList::with_capacity(m, m * k);
    let mut face = Vec::with_capacity(k);
    for (f, row) in values.chunks_exact(k.max(1)).enumerate().take(m) {
        face.clear();
        for &v in row {
            face.push(vertex_index(v, f, n_vertices)?);
        }
        faces.push(&face);
    }
    Ok(faces)
}

/// The vertex indices of face `f` given as a sequence of integers.
fn face_row(face: &Bound<'_, PyAny>, f: usize, n_vertices: usize) -> PyResult<Vec<u32>> {
    let numpy = face.py().import("numpy")?;
    if face.len().is_ok_and(|n| n == 0) {
        return Err(MeshError::new_err(format!(
            "face {f} has 0 vertices; a face needs at least 3"
        )));
    }
    let row = numpy.call_method1("asarray", (face,))?;
    let kind: String = row.getattr("dtype")?.getattr("kind")?.extract()?;
    let ndim: usize = row.getattr("ndim")?.extract()?;
    if ndim != 1 || !matches!(kind.as_str(), "i" | "u") {
        return Err(MeshError::new_err(format!(
            "face {f} must be a sequence of vertex indices (integers), got {}",
            face.repr().map(|r| r.to_string()).unwrap_or_default()
        )));
    }
    row.call_method0("tolist")?
        .extract::<Vec<i128>>()?
        .into_iter()
        .map(|v| vertex_index(v, f, n_vertices))
        .collect()
}

/// Index `v` of face `f`, checked against `n_vertices`.
fn vertex_index(v: i128, f: usize, n_vertices: usize) -> PyResult<u32> {
    match u32::try_from(v) {
        Ok(i) if (i as usize) < n_vertices => Ok(i),
        _ => Err(MeshError::new_err(format!(
            "face {f} refers to vertex {v}, but there are only {n_vertices} vertices"
        ))),
    }
}

/// An (N, 3) float64 array of `positions`, read-only.
pub(crate) fn positions_array<'py>(
    py: Python<'py>,
    positions: &[DVec3],
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let flat: Vec<f64> = positions.iter().flat_map(|p| p.to_array()).collect();
    let array = PyArray1::from_vec(py, flat).reshape([positions.len(), 3])?;
    read_only(&array)?;
    Ok(array)
}

/// Marks a fresh array read-only: it is a copy, and writing into it would not change
/// the mesh.
fn read_only(array: &Bound<'_, PyAny>) -> PyResult<()> {
    array.call_method(
        "setflags",
        (),
        Some(&[("write", false)].into_py_dict(array.py())?),
    )?;
    Ok(())
}

use pyo3::types::IntoPyDict;

#[pymethods]
impl Mesh {
    #[new]
    #[pyo3(signature = (vertices, faces, *, repair = false, triangulate = false))]
    fn new(
        py: Python<'_>,
        vertices: &Bound<'_, PyAny>,
        faces: &Bound<'_, PyAny>,
        repair: bool,
        triangulate: bool,
    ) -> PyResult<Self> {
        crate::errors::triangulate_needs_repair(repair, triangulate)?;
        let positions = vertices_from(vertices)?;
        let faces = faces_from(faces, positions.len(), repair)?;
        if !repair {
            let mesh = py.detach(|| {
                no_panic(|| {
                    HalfedgeMesh::from_polygon_list(positions.len(), &faces)
                        .map_err(|e| repairable_error(None, &e))
                })
            })?;
            return Ok(Self {
                positions,
                faces: Arc::new(faces),
                mesh: Arc::new(mesh),
                source: None,
                repair: None,
            });
        }
        let repaired = py.detach(|| {
            no_panic(|| {
                beltrami_halfedge::repair(
                    &positions,
                    &faces,
                    &RepairOptions::new().triangulate(triangulate),
                )
                .map_err(|e| topology_error(None, &e))
            })
        })?;
        crate::errors::refuse_empty_repair(None, faces.len(), repaired.faces.len())?;
        let mut mesh = Self::build(py, repaired.positions, repaired.faces, None)?;
        mesh.repair = Some(repaired.report);
        Ok(mesh)
    }

    /// The vertex coordinates, an (N, 3) float64 array (a read-only copy).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        positions_array(py, &self.positions)
    }

    /// The faces: an (M, 3) int64 array for a triangle mesh, (M, k) when every face
    /// has k vertices, otherwise a list of 1-D int64 arrays (a read-only copy).
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let mut sizes = self.faces.iter().map(<[u32]>::len);
        let k = sizes.next().unwrap_or(3);
        if sizes.all(|s| s == k) {
            let flat: Vec<i64> = self.faces.indices().iter().map(|&i| i64::from(i)).collect();
            let array = PyArray1::from_vec(py, flat).reshape([self.faces.len(), k])?;
            read_only(&array)?;
            Ok(array.into_any())
        } else {
            let list = PyList::empty(py);
            for face in self.faces.iter() {
                let face: Vec<i64> = face.iter().map(|&i| i64::from(i)).collect();
                let face = PyArray1::from_vec(py, face);
                read_only(&face)?;
                list.append(face)?;
            }
            Ok(list.into_any())
        }
    }

    /// The number of vertices.
    #[getter]
    fn n_vertices(&self) -> usize {
        self.mesh.n_vertices()
    }

    /// The number of faces.
    #[getter]
    fn n_faces(&self) -> usize {
        self.mesh.n_faces()
    }

    /// The number of edges.
    #[getter]
    fn n_edges(&self) -> usize {
        self.mesh.n_edges()
    }

    /// Whether every face is a triangle.
    #[getter]
    fn is_triangle_mesh(&self) -> bool {
        self.mesh.is_triangle_mesh()
    }

    /// Whether the mesh has no boundary (and at least one face).
    #[getter]
    fn is_closed(&self) -> bool {
        self.mesh.n_faces() > 0 && self.mesh.is_closed()
    }

    /// The file the mesh was read from, or None.
    #[getter]
    fn path(&self) -> Option<PathBuf> {
        self.source.as_ref().map(|(p, _)| p.clone())
    }

    fn __len__(&self) -> usize {
        self.mesh.n_vertices()
    }

    /// Pickles as `Mesh(vertices, faces)` (a process pool, Dask, `multiprocessing`);
    /// the file it was read from and its repair report are not kept.
    fn __reduce__<'py>(slf: &Bound<'py, Self>, py: Python<'py>) -> PyResult<Reduced<'py>> {
        let mesh = slf.get();
        Ok((
            slf.get_type().into_any(),
            (mesh.vertices(py)?.into_any(), mesh.faces(py)?),
        ))
    }

    /// The mesh itself: it cannot change, so a copy would be the same.
    fn __copy__(slf: Py<Self>) -> Py<Self> {
        slf
    }

    /// The mesh itself, as [`__copy__`](Self::__copy__).
    fn __deepcopy__(slf: Py<Self>, _memo: &Bound<'_, PyAny>) -> Py<Self> {
        slf
    }

    fn __repr__(&self) -> String {
        format!(
            "Mesh({} vertices, {} faces{})",
            self.mesh.n_vertices(),
            self.mesh.n_faces(),
            self.source
                .as_ref()
                .map(|(p, _)| format!(", from {}", p.display()))
                .unwrap_or_default()
        )
    }
}
