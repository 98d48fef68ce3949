//! The mesh algorithms: `beltrami.quality`, `subdivide`, `delaunay`, `remesh`,
//! `decimate` and `fill_holes`, with the words, defaults and JSON keys of the commands
//! `info --quality`, `subdivide`, `delaunay`, `remesh`, `decimate` and `fill-holes`.

use beltrami_algorithms::quality::ASPECT_RATIO_BINS;
use beltrami_algorithms::{
    AdaptiveSizing, BlockedBy, DecimateError, DecimateOptions, DecimateStop, DelaunayError,
    DelaunayOptions, FillError, FillOptions, FlatError, FlatOptions, MeshQuality, Placement,
    QualityError, RemeshError, RemeshOptions, Scheme, SkipReason, SubdivisionError, delaunay_flip,
    flipped_faces, mesh_quality,
};
use beltrami_halfedge::{DVec3, HalfedgeMesh};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{
    MeshError, at_least_opt, no_panic, nonnegative, nonnegative_opt, topology_error,
};
use crate::mesh::Mesh;
use crate::progress::Progress;

fn quality_error(e: &QualityError) -> PyErr {
    match e {
        QualityError::NotTriangle { face, len } => MeshError::new_err(format!(
            "face {face} has {len} vertices; quality needs a triangle mesh (bt.Mesh(vertices, faces, repair=True, triangulate=True) splits the polygons into triangles)"
        )),
        e => MeshError::new_err(e.to_string()),
    }
}

/// A new `Mesh` from a result of the algorithms (valid by construction).
fn result_mesh(mesh: HalfedgeMesh, positions: Vec<DVec3>) -> Mesh {
    let faces = mesh.to_polygons();
    Mesh {
        positions,
        faces: std::sync::Arc::new(faces),
        mesh: std::sync::Arc::new(mesh),
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

/// `quality_before` and `quality_after` of an edit's report (as `--json` has them):
/// the triangle quality of the input and of the result, measured without the GIL.
fn set_quality_change(
    py: Python<'_>,
    d: &Bound<'_, PyDict>,
    before: (&HalfedgeMesh, &[DVec3]),
    after: (&HalfedgeMesh, &[DVec3]),
) -> PyResult<()> {
    let (b, a) = py.detach(|| {
        no_panic(|| {
            let b = mesh_quality(before.0, before.1).map_err(|e| quality_error(&e))?;
            let a = mesh_quality(after.0, after.1).map_err(|e| quality_error(&e))?;
            Ok((b, a))
        })
    })?;
    d.set_item("quality_before", quality_dict(py, &b, None)?)?;
    d.set_item("quality_after", quality_dict(py, &a, None)?)?;
    Ok(())
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
/// vertices keep their indices; new ones are appended. Returns a new `Mesh`; with
/// `steps=0` an unchanged copy (the identity, as in a loop over the steps; the CLI
/// refuses `--steps 0`, where writing the input unchanged is most likely a mistake).
///
/// Raises `ValueError` for an unknown scheme or a negative `steps`, `MeshError` for a
/// mesh without faces, a polygon mesh or a result too large for a mesh, and `MemoryError`, before anything is
/// allocated, for a result that would need more memory than the machine has available
/// (`Scheme::BYTES_PER_FACE`, 256 bytes per face of the result, against `MemAvailable`
/// plus free swap on Linux), naming the most steps that fit.
#[pyfunction]
#[pyo3(signature = (mesh, scheme = "loop", steps = 1))]
pub(crate) fn subdivide(py: Python<'_>, mesh: &Mesh, scheme: &str, steps: i128) -> PyResult<Mesh> {
    let steps: usize = nonnegative("steps", steps)?;
    let Some(scheme) = Scheme::from_name(scheme) else {
        return Err(PyValueError::new_err(format!(
            "unknown scheme {scheme:?}; the schemes are {}",
            Scheme::ALL.map(Scheme::name).join(", ")
        )));
    };
    // As the command refuses them, before the memory is looked at: a mesh without faces
    // (nothing to subdivide, however many steps) and one that is not of triangles.
    require_faces(mesh, "subdivide")?;
    if let Some(f) = mesh.mesh.faces().find(|&f| mesh.mesh.face_valence(f) != 3) {
        return Err(MeshError::new_err(format!(
            "face {} has {} vertices; subdivide needs a triangle mesh (bt.Mesh(vertices, faces, repair=True, triangulate=True) splits the polygons into triangles)",
            f.index(),
            mesh.mesh.face_valence(f)
        )));
    }
    let available = beltrami_io::available_memory();
    if !scheme.fits(&mesh.mesh, steps, available, 0) && scheme.fits(&mesh.mesh, steps, None, 0) {
        let faces = scheme.counts(&mesh.mesh, steps).faces;
        let most = scheme.most_steps_that_fit(&mesh.mesh, steps, available, 0);
        return Err(pyo3::exceptions::PyMemoryError::new_err(format!(
            "steps={steps} of {} subdivision would make {faces} faces, needing about {:.1} GB, more than the {:.1} GB this machine has available; at most steps={most} fits this mesh",
            scheme.name(),
            Scheme::bytes_needed(faces, 0) as f64 / 1e9,
            available.unwrap_or(0) as f64 / 1e9,
        )));
    }
    let (m, p) = py.detach(|| {
        no_panic(|| {
            scheme
                .subdivide(&mesh.mesh, &mesh.positions, steps)
                .map_err(|e| match e {
                    SubdivisionError::NotTriangle { face, len } => MeshError::new_err(format!(
                        "face {face} has {len} vertices; subdivide needs a triangle mesh (bt.Mesh(vertices, faces, repair=True, triangulate=True) splits the polygons into triangles)"
                    )),
                    e => MeshError::new_err(e.to_string()),
                })
        })
    })?;
    Ok(result_mesh(m, p))
}

/// `MeshError` for a mesh without faces, as the commands refuse one (`what` names the
/// operation in the message).
fn require_faces(mesh: &Mesh, what: &str) -> PyResult<()> {
    if mesh.mesh.n_faces() == 0 {
        return Err(MeshError::new_err(format!(
            "the mesh has {} vertices but no faces; {what} needs a surface of triangles",
            mesh.mesh.n_vertices()
        )));
    }
    Ok(())
}

/// Flips edges until no cotangent weight is negative (a Delaunay mesh on the same
/// vertices), as `beltrami delaunay`. `max_dihedral` (degrees, 0 to 180) leaves edges
/// whose two triangles meet at a larger angle alone (features, curved regions);
/// `max_flips` caps the flips (default ten per edge). Returns `(Mesh, report)` with the
/// report's keys as `delaunay --json`: `vertices`, `faces`, `flips`, `negative_before`,
/// `negative_after`, `kept_by_dihedral`, `kept_by_topology`, `kept_by_flip_limit`,
/// `hit_flip_limit`, `max_deviation` (how far the surface moved, in the mesh's unit) and
/// `max_dihedral_degrees` (the bound given, or None).
///
/// Raises `ValueError` for a dihedral bound outside [0, 180], `MeshError` for a polygon
/// mesh or one without faces.
#[pyfunction]
#[pyo3(signature = (mesh, max_dihedral = None, max_flips = None))]
pub(crate) fn delaunay<'py>(
    py: Python<'py>,
    mesh: &Mesh,
    max_dihedral: Option<f64>,
    max_flips: Option<i128>,
) -> PyResult<(Mesh, Bound<'py, PyDict>)> {
    require_faces(mesh, "delaunay")?;
    let mut options = DelaunayOptions::default();
    if let Some(d) = max_dihedral {
        if !(0.0..=180.0).contains(&d) {
            return Err(PyValueError::new_err(format!(
                "max_dihedral must be between 0 and 180 degrees, got {d}"
            )));
        }
        options = options.max_dihedral(d.to_radians());
    }
    if let Some(n) = nonnegative_opt("max_flips", max_flips)? {
        options = options.max_flips(n);
    }
    let (m, p, report) = py.detach(|| {
        no_panic(|| {
            delaunay_flip(&mesh.mesh, &mesh.positions, options).map_err(|e| match e {
                DelaunayError::NotTriangle { face, len } => MeshError::new_err(format!(
                    "face {face} has {len} vertices; delaunay needs a triangle mesh (bt.Mesh(vertices, faces, repair=True, triangulate=True) splits the polygons into triangles)"
                )),
                DelaunayError::Topology(e) => topology_error(None, &e),
                e => MeshError::new_err(e.to_string()),
            })
        })
    })?;
    let d = PyDict::new(py);
    d.set_item("vertices", m.n_vertices())?;
    d.set_item("faces", m.n_faces())?;
    d.set_item("flips", report.flips)?;
    d.set_item("negative_before", report.negative_before)?;
    d.set_item("negative_after", report.negative_after)?;
    d.set_item("kept_by_dihedral", report.kept_by_dihedral)?;
    d.set_item("kept_by_topology", report.kept_by_topology)?;
    d.set_item("kept_by_flip_limit", report.kept_by_flip_limit)?;
    d.set_item("hit_flip_limit", report.hit_flip_limit)?;
    d.set_item("max_deviation", report.max_deviation)?;
    d.set_item("max_dihedral_degrees", max_dihedral)?;
    Ok((result_mesh(m, p), d))
}

/// Removes flat triangles (zero-area slivers: a corner on the opposite edge, two corners
/// at one point), as `beltrami repair --flat-faces`: a cap's longest edge is flipped (on
/// the boundary the cap is deleted), a needle's zero-length edge collapsed, a flat
/// triangle alone deleted; none of these moves the surface. `max_height_ratio`: a
/// triangle is flat when its height is at most this share of its longest edge (default
/// 1e-12, the triangles cotangent weights treat as absent; at most 0.1; larger values
/// take near-slivers, whose flip or deletion moves the surface by up to their height).
/// `max_move` (in the mesh's unit, default 0): the longest distance a collapse may move
/// a vertex where no flip or deletion removes a sliver. The tests do not depend on the
/// mesh's unit. Returns `(Mesh, report)` with the report's keys as `repair --flat-faces
/// --json`'s `flat_triangles`: `before`, `after` (flat triangles left), `flips`,
/// `deleted` (caps on the boundary), `alone` (flat triangles alone), `collapses`,
/// `max_move` (how far a collapse moved a vertex), `max_height` (how far flips and
/// deletions moved the surface at most), and `vertex_origin` (for each output vertex,
/// the input vertex it is).
///
/// Raises `ValueError` for a ratio outside [0, 0.1] or a negative or NaN `max_move`,
/// `MeshError` for a polygon mesh, one without faces, or when no face would be left
/// (every triangle flat).
#[pyfunction]
#[pyo3(signature = (mesh, max_height_ratio = 1e-12, max_move = 0.0))]
pub(crate) fn remove_flat_triangles<'py>(
    py: Python<'py>,
    mesh: &Mesh,
    max_height_ratio: f64,
    max_move: f64,
) -> PyResult<(Mesh, Bound<'py, PyDict>)> {
    require_faces(mesh, "remove_flat_triangles")?;
    let options = FlatOptions::default()
        .max_height_ratio(max_height_ratio)
        .max_move(max_move);
    let (m, p, report) = py.detach(|| {
        no_panic(|| {
            beltrami_algorithms::remove_flat_triangles(&mesh.mesh, &mesh.positions, options)
                .map_err(|e| match e {
                    FlatError::NotTriangle { face, len } => MeshError::new_err(format!(
                        "face {face} has {len} vertices; remove_flat_triangles needs a triangle mesh (bt.Mesh(vertices, faces, repair=True, triangulate=True) splits the polygons into triangles)"
                    )),
                    FlatError::Options { reason } => PyValueError::new_err(reason),
                    FlatError::Topology(e) => topology_error(None, &e),
                    e => MeshError::new_err(e.to_string()),
                })
        })
    })?;
    if m.n_faces() == 0 && mesh.mesh.n_faces() > 0 {
        return Err(MeshError::new_err(format!(
            "removing the flat triangles left no face: every one of the {} {} was flat",
            mesh.mesh.n_faces(),
            if mesh.mesh.n_faces() == 1 {
                "triangle"
            } else {
                "triangles"
            }
        )));
    }
    let d = PyDict::new(py);
    d.set_item("before", report.flat_before)?;
    d.set_item("after", report.flat_after)?;
    d.set_item("flips", report.flips)?;
    d.set_item("deleted", report.deleted)?;
    d.set_item("alone", report.alone)?;
    d.set_item("collapses", report.collapses)?;
    d.set_item("max_move", report.max_move)?;
    d.set_item("max_height", report.max_height)?;
    d.set_item(
        "vertex_origin",
        numpy::PyArray1::from_vec(py, report.vertex_origin.iter().map(|&i| i as i64).collect()),
    )?;
    Ok((result_mesh(m, p), d))
}

/// The vertex index pairs of a (K, 2) integer array (`remesh`'s `feature_edges`).
fn edge_pairs(x: &Bound<'_, PyAny>) -> PyResult<Vec<[u32; 2]>> {
    let numpy = x.py().import("numpy")?;
    let array = numpy.call_method1("asarray", (x,))?;
    let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    // No pairs: `[]` (which numpy makes a float array) or any empty array.
    if shape.iter().product::<usize>() == 0 && matches!(shape.as_slice(), [0] | [0, 2]) {
        return Ok(Vec::new());
    }
    let bad = || {
        let shape: Vec<String> = shape.iter().map(ToString::to_string).collect();
        PyValueError::new_err(format!(
            "feature_edges must be a (K, 2) array of vertex indices (integers), got shape ({}) of dtype kind {kind:?}",
            shape.join(", ")
        ))
    };
    if !(matches!(kind.as_str(), "i" | "u") && matches!(shape.as_slice(), [_, 2])) {
        return Err(bad());
    }
    let values: Vec<i128> = array
        .call_method0("ravel")?
        .call_method0("tolist")?
        .extract()?;
    values
        .chunks_exact(2)
        .enumerate()
        .map(|(row, pair)| {
            let index = |v: i128| {
                u32::try_from(v).map_err(|_| {
                    PyValueError::new_err(format!(
                        "feature_edges row {row}: vertex index {v} is not a vertex of the mesh"
                    ))
                })
            };
            Ok([index(pair[0])?, index(pair[1])?])
        })
        .collect()
}

fn algorithm_error(what: &str, e: impl std::fmt::Display) -> PyErr {
    MeshError::new_err(format!("{what}: {e}"))
}

/// `remesh`'s `adaptive` argument: `True` (every value derived from the input) or a
/// tuple `(min_edge, max_edge, error)` whose `None` entries are derived.
pub(crate) enum Adaptive {
    /// `True` or `False`.
    Flag(bool),
    /// The three values, each optional.
    Values((Option<f64>, Option<f64>, Option<f64>)),
}

impl<'py> FromPyObject<'py> for Adaptive {
    /// `True`/`False`, or a sequence of three numbers or `None`s; anything else is a
    /// `TypeError` that says what `adaptive` accepts (not PyO3's enum-extraction text).
    fn extract_bound(value: &Bound<'py, PyAny>) -> PyResult<Self> {
        if let Ok(flag) = value.extract::<bool>() {
            return Ok(Self::Flag(flag));
        }
        value
            .extract::<(Option<f64>, Option<f64>, Option<f64>)>()
            .map(Self::Values)
            .map_err(|_| {
                let shown = value
                    .repr()
                    .map_or_else(|_| "?".to_string(), |r| r.to_string());
                pyo3::exceptions::PyTypeError::new_err(format!(
                    "adaptive must be True, False, None or a tuple (min_edge, max_edge, error) of three numbers or None entries, got {shown}"
                ))
            })
    }
}

/// Isotropic remeshing (Botsch & Kobbelt 2004), as `beltrami remesh`: splits, collapses,
/// valence flips and tangential relaxation towards one edge length, every vertex
/// projected back onto the smooth (Phong) surface through the input's triangles, or with
/// `smooth_projection=False` onto the triangles themselves. `edge_length` (in the mesh's unit) or
/// `edge_length_relative` (a multiple of the input's mean edge length; default 1), or
/// `adaptive=(min_edge, max_edge, error)` for curvature-adaptive sizing (a `None`
/// entry, or `adaptive=True` for all three, is derived from the input as
/// `remesh --adaptive` does: a quarter and four times the mean edge length, and the error
/// that keeps the mean edge length at the median curvature; the report's `min_edge`,
/// `max_edge` and `approx_error` give the values used);
/// `features` (degrees) keeps edges sharper than that as curves; `feature_edges`, a (K,
/// 2) array of vertex index pairs (the edge between each pair), keeps those edges as
/// curves too, for creases no angle finds (`remesh --feature-edges`); the boundary is
/// always kept; `progress=True` shows a tqdm bar of the iterations when tqdm is
/// installed.
/// Returns `(Mesh, report)`, the report with the keys of `remesh --json` (without the
/// file names and `seconds`).
///
/// Raises `ValueError` for bad options or a pair of `feature_edges` that is not an edge
/// (naming its row), `MeshError` for a polygon mesh, a target too small for the surface
/// (too many triangles) or as long as the surface itself (the result would have faces
/// of no area).
#[pyfunction]
#[pyo3(signature = (mesh, edge_length = None, *, edge_length_relative = None, adaptive = None, iterations = 10, features = None, feature_edges = None, projection = true, smooth_projection = true, progress = false))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn remesh<'py>(
    py: Python<'py>,
    mesh: &Mesh,
    edge_length: Option<f64>,
    edge_length_relative: Option<f64>,
    adaptive: Option<Adaptive>,
    iterations: i128,
    features: Option<f64>,
    feature_edges: Option<&Bound<'py, PyAny>>,
    projection: bool,
    smooth_projection: bool,
    progress: bool,
) -> PyResult<(Mesh, Bound<'py, PyDict>)> {
    let given_edges = feature_edges.map(edge_pairs).transpose()?;
    let adaptive = match adaptive {
        None | Some(Adaptive::Flag(false)) => None,
        Some(Adaptive::Flag(true)) => Some(AdaptiveSizing::default()),
        Some(Adaptive::Values((min_edge, max_edge, approx_error))) => Some(AdaptiveSizing {
            min_edge,
            max_edge,
            approx_error,
        }),
    };
    let given = [
        edge_length.is_some(),
        edge_length_relative.is_some(),
        adaptive.is_some(),
    ];
    if given.iter().filter(|&&g| g).count() > 1 {
        return Err(PyValueError::new_err(
            "give one of edge_length, edge_length_relative and adaptive",
        ));
    }
    let iterations: usize = nonnegative("iterations", iterations)?;
    let mut options = RemeshOptions::default()
        .iterations(iterations)
        .projection(projection)
        .smooth_projection(smooth_projection);
    if let Some(l) = edge_length {
        options = options.edge_length(l);
    }
    if let Some(r) = edge_length_relative {
        options = options.relative_edge_length(r);
    }
    if let Some(sizing) = adaptive {
        options = options.adaptive_sizing(sizing);
    }
    if let Some(deg) = features {
        if !(0.0..=180.0).contains(&deg) {
            return Err(PyValueError::new_err(format!(
                "features must be between 0 and 180 degrees, got {deg}"
            )));
        }
        options = options.feature_angle(deg.to_radians());
    }
    let (m, p, r) = Progress::run(py, progress, iterations, "remesh", |bar| {
        beltrami_algorithms::remesh_with_feature_edges(
            &mesh.mesh,
            &mesh.positions,
            given_edges.as_deref().unwrap_or_default(),
            &options,
            |done, total| bar.show(done, total),
        )
        .map_err(|e| match e {
            RemeshError::Options { .. } | RemeshError::FeatureEdge { .. } => {
                PyValueError::new_err(e.to_string())
            }
            e => algorithm_error("remesh", e),
        })
    })?;
    let d = PyDict::new(py);
    d.set_item("target_edge_length", r.target_edge_length)?;
    d.set_item("adaptive", adaptive.is_some())?;
    d.set_item("min_edge", r.adaptive.map(|a| a.min_edge))?;
    d.set_item("max_edge", r.adaptive.map(|a| a.max_edge))?;
    d.set_item("approx_error", r.adaptive.map(|a| a.approx_error))?;
    d.set_item("iterations", r.iterations.len())?;
    d.set_item("splits", r.splits)?;
    d.set_item("collapses", r.collapses)?;
    d.set_item("flips", r.flips)?;
    d.set_item("vertices_before", r.vertices_before)?;
    d.set_item("faces_before", r.faces_before)?;
    d.set_item("vertices", r.vertices)?;
    d.set_item("faces", r.faces)?;
    d.set_item("mean_edge_length_before", r.mean_edge_length_before)?;
    d.set_item("edge_length_cv_before", r.edge_length_cv_before)?;
    d.set_item("mean_edge_length", r.mean_edge_length)?;
    d.set_item("edge_length_cv", r.edge_length_cv)?;
    d.set_item("feature_edges", r.feature_edges)?;
    d.set_item("given_feature_edges", r.given_feature_edges)?;
    d.set_item("fold_edges", r.fold_edges)?;
    d.set_item("boundary_edges", r.boundary_edges)?;
    d.set_item("corners", r.corners)?;
    d.set_item("hausdorff", r.hausdorff)?;
    d.set_item("hausdorff_from_input", r.hausdorff_from_input)?;
    d.set_item("degenerate_faces_before", r.degenerate_faces_before)?;
    d.set_item("degenerate_faces", r.degenerate_faces)?;
    d.set_item("feature_angle_degrees", features)?;
    d.set_item("projection", projection)?;
    d.set_item("smooth_projection", projection && smooth_projection)?;
    set_quality_change(py, &d, (&mesh.mesh, &mesh.positions), (&m, &p))?;
    Ok((result_mesh(m, p), d))
}

/// Quadric-error decimation (Garland & Heckbert 1997), as `beltrami decimate`: to
/// `vertices` vertices or `ratio` of them (exactly one), by halfedge collapses that keep
/// the topology. `max_error` and `max_distance` (in the mesh's unit),
/// `max_normal_deviation` (degrees) and `max_aspect_ratio` stop collapses that would
/// exceed them; `keep_boundary` keeps every boundary vertex; `placement` is
/// `"optimal"` (the kept vertex moves to the quadric's minimum, the default) or
/// `"endpoint"` (it stays: output vertices are input vertices); `quality_threshold`
/// (default 0.4, in [0, 1]; 0 turns it off) makes collapses that create poorly shaped
/// triangles cost more; `openmesh=True` is OpenMesh's plain quadric decimation
/// (endpoint placement, no shape penalty); `plane_weights` is `"area"` (the default) or
/// `"uniform"` and `stabilizer` (default 0) the weight of a pull towards the input
/// positions, as `decimate --plane-weights/--stabilizer`; `flip_tolerance` (default 0.2,
/// 0 turns it off) lets edges be flipped towards valence 6 after the collapses where the
/// surface moves by at most that fraction of the largest collapse error, as
/// `decimate --flip-tolerance`; `fit_rounds` (default 2, 0 turns it off, at most 100)
/// rounds of the final fit that moves the vertices to bring the surface closer to the
/// input (none when nothing was collapsed), as `decimate --fit-rounds`; `distance=False`
/// skips measuring the Hausdorff distance (the three `hausdorff` keys are then None), as
/// `decimate --no-distance`;
/// `progress=True` shows a tqdm bar of the collapses when tqdm is installed. `None`
/// means the default. Returns
/// `(Mesh, report)`, the report with the keys of `decimate --json` (without the file
/// names and `seconds`).
///
/// Options that could not take effect are refused, as the command line refuses them:
/// with `openmesh=True`, any of `placement`, `quality_threshold`, `plane_weights`,
/// `stabilizer`, `flip_tolerance` and `fit_rounds` given (OpenMesh's plain quadrics fix
/// them); `fit_rounds` above 0 with `placement="endpoint"`, `max_distance` or
/// `max_normal_deviation` (no fit is made with them); `flip_tolerance` above 0 with
/// `max_distance` or `max_normal_deviation` (no flips are made with them).
///
/// Raises `ValueError` for bad options, `MeshError` for a polygon mesh.
#[pyfunction]
#[pyo3(signature = (mesh, vertices = None, *, ratio = None, max_error = None, max_normal_deviation = None, keep_boundary = false, placement = None, quality_threshold = None, openmesh = false, max_aspect_ratio = None, max_distance = None, plane_weights = None, stabilizer = None, flip_tolerance = None, fit_rounds = None, distance = true, progress = false))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn decimate<'py>(
    py: Python<'py>,
    mesh: &Mesh,
    vertices: Option<i128>,
    ratio: Option<f64>,
    max_error: Option<f64>,
    max_normal_deviation: Option<f64>,
    keep_boundary: bool,
    placement: Option<&str>,
    quality_threshold: Option<f64>,
    openmesh: bool,
    max_aspect_ratio: Option<f64>,
    max_distance: Option<f64>,
    plane_weights: Option<&str>,
    stabilizer: Option<f64>,
    flip_tolerance: Option<f64>,
    fit_rounds: Option<i128>,
    distance: bool,
    progress: bool,
) -> PyResult<(Mesh, Bound<'py, PyDict>)> {
    let vertices: Option<usize> = at_least_opt("vertices", vertices, 1)?;
    if let Some(deg) = max_normal_deviation
        && !(0.0..=180.0).contains(&deg)
    {
        return Err(PyValueError::new_err(format!(
            "max_normal_deviation must be between 0 and 180 degrees, got {deg}"
        )));
    }
    let given_fit_rounds: Option<usize> = nonnegative_opt("fit_rounds", fit_rounds)?;
    refuse_ignored_decimate_options(
        openmesh,
        [
            ("placement", placement.is_some()),
            ("quality_threshold", quality_threshold.is_some()),
            ("plane_weights", plane_weights.is_some()),
            ("stabilizer", stabilizer.is_some()),
            ("flip_tolerance", flip_tolerance.is_some()),
            ("fit_rounds", given_fit_rounds.is_some()),
        ],
    )?;
    let defaults = DecimateOptions::default();
    let fit_rounds = given_fit_rounds.unwrap_or(defaults.fit_rounds);
    let quality_threshold = quality_threshold.unwrap_or(defaults.quality_threshold);
    let stabilizer = stabilizer.unwrap_or(defaults.stabilizer);
    let (fits, flips) = (
        given_fit_rounds.is_some_and(|n| n > 0),
        flip_tolerance.is_some_and(|f| f > 0.0),
    );
    let flip_tolerance = flip_tolerance.unwrap_or(defaults.flip_tolerance);
    let placement = placement.unwrap_or("optimal");
    let plane_weights = plane_weights.unwrap_or("area");
    let mut options = match (vertices, ratio) {
        (Some(n), None) => DecimateOptions::default().vertices(n),
        (None, Some(r)) => DecimateOptions::default().ratio(r),
        _ => {
            return Err(PyValueError::new_err(
                "give exactly one of vertices and ratio",
            ));
        }
    };
    let placement = match placement {
        "optimal" => Placement::Optimal,
        "endpoint" => Placement::Endpoint,
        _ => {
            return Err(PyValueError::new_err(format!(
                "placement must be 'optimal' or 'endpoint', got '{placement}'"
            )));
        }
    };
    if !(0.0..=1.0).contains(&quality_threshold) {
        return Err(PyValueError::new_err(format!(
            "quality_threshold must be in [0, 1], got {quality_threshold}"
        )));
    }
    let area_weighted = match plane_weights {
        "area" => true,
        "uniform" => false,
        _ => {
            return Err(PyValueError::new_err(format!(
                "plane_weights must be 'area' or 'uniform', got '{plane_weights}'"
            )));
        }
    };
    options = if openmesh {
        // OpenMesh's decimater makes no flips; the default tolerance does not apply.
        options
            .placement(Placement::Endpoint)
            .quality_threshold(0.0)
            .flip_tolerance(0.0)
            .fit_rounds(0)
    } else {
        options
            .placement(placement)
            .quality_threshold(quality_threshold)
            .area_weighted(area_weighted)
            .stabilizer(stabilizer)
            .flip_tolerance(flip_tolerance)
            .fit_rounds(fit_rounds)
    };
    options = options
        .keep_boundary(keep_boundary)
        .measure_distance(distance);
    if let Some(e) = max_error {
        options = options.max_error(e);
    }
    if let Some(deg) = max_normal_deviation {
        options = options.max_normal_deviation(deg.to_radians());
    }
    if let Some(a) = max_aspect_ratio {
        options = options.max_aspect_ratio(a);
    }
    if let Some(d) = max_distance {
        options = options.max_distance(d);
    }
    refuse_blocked_decimate_steps(&options, fits, flips)?;
    // The bar's total is the planned collapses, which the first call gives.
    let (m, p, r) = Progress::run(py, progress, 0, "decimate", |bar| {
        beltrami_algorithms::decimate_with_progress(
            &mesh.mesh,
            &mesh.positions,
            &options,
            |done, planned| bar.show(done, planned),
        )
        .map_err(|e| match e {
            DecimateError::Options { .. } => PyValueError::new_err(e.to_string()),
            e => algorithm_error("decimate", e),
        })
    })?;
    let d = PyDict::new(py);
    d.set_item("vertices_before", r.vertices_before)?;
    d.set_item("vertices_after", r.vertices_after)?;
    d.set_item("faces_before", r.faces_before)?;
    d.set_item("faces_after", r.faces_after)?;
    d.set_item("target_vertices", r.target_vertices)?;
    d.set_item("target_reached", r.target_reached)?;
    d.set_item(
        "stop",
        match r.stop {
            DecimateStop::TargetReached => "target reached",
            _ => "no collapse left",
        },
    )?;
    d.set_item("collapses", r.collapses)?;
    let refused = PyDict::new(py);
    refused.set_item("topology", r.refused.topology)?;
    refused.set_item("boundary", r.refused.boundary)?;
    refused.set_item("max_error", r.refused.error)?;
    refused.set_item("normal_flip", r.refused.normal_flip)?;
    refused.set_item("max_normal_deviation", r.refused.normal_deviation)?;
    refused.set_item("max_aspect_ratio", r.refused.aspect_ratio)?;
    refused.set_item("max_distance", r.refused.distance)?;
    d.set_item("refused", refused)?;
    d.set_item(
        "placement",
        match options.placement {
            Placement::Optimal => "optimal",
            _ => "endpoint",
        },
    )?;
    d.set_item("quality_threshold", options.quality_threshold)?;
    let weights = if options.area_weighted {
        "area"
    } else {
        "uniform"
    };
    d.set_item("plane_weights", weights)?;
    d.set_item("stabilizer", options.stabilizer)?;
    d.set_item("flip_tolerance", options.flip_tolerance)?;
    d.set_item("flips", r.flips)?;
    d.set_item("fit_rounds", r.fit_rounds)?;
    // None without a fit, as `--json`'s null: not a 0.0 that reads as a perfect fit.
    let fitted = |x: f64| (r.fit_rounds > 0).then_some(x);
    d.set_item("fit_rms_before", fitted(r.fit_rms_before))?;
    d.set_item("fit_rms_after", fitted(r.fit_rms_after))?;
    d.set_item("max_quadric_error", r.max_quadric_error)?;
    // None when not measured (`distance=False`), as `--no-distance`'s null.
    let measured = |x: f64| r.distance_measured.then_some(x);
    d.set_item("hausdorff", measured(r.hausdorff))?;
    d.set_item("hausdorff_to_input", measured(r.hausdorff_to_input))?;
    d.set_item("hausdorff_from_input", measured(r.hausdorff_from_input))?;
    set_quality_change(py, &d, (&mesh.mesh, &mesh.positions), (&m, &p))?;
    Ok((result_mesh(m, p), d))
}

/// Refuses, as `beltrami decimate` does (exit 2 there), options given explicitly that
/// the run could not honour with `openmesh=True`: any of `openmesh_conflicts`
/// (OpenMesh's plain quadrics fix them).
fn refuse_ignored_decimate_options(
    openmesh: bool,
    openmesh_conflicts: [(&str, bool); 6],
) -> PyResult<()> {
    if openmesh && let Some((name, _)) = openmesh_conflicts.iter().find(|(_, given)| *given) {
        return Err(PyValueError::new_err(format!(
            "{name} cannot be given with openmesh=True, which is OpenMesh's plain quadrics (endpoint placement, no shape penalty, area-weighted planes, no stabilizer, no flips and no fit)"
        )));
    }
    Ok(())
}

/// Refuses, as `beltrami decimate` does, `fit_rounds` or `flip_tolerance` given above 0
/// when a setting of `options` keeps that step off
/// (`DecimateOptions::fit_blocked_by`, `flips_blocked_by`).
fn refuse_blocked_decimate_steps(
    options: &DecimateOptions,
    fits: bool,
    flips: bool,
) -> PyResult<()> {
    let name = |blocker| match blocker {
        BlockedBy::EndpointPlacement => "placement='endpoint'",
        BlockedBy::MaxDistance => "max_distance",
        BlockedBy::MaxNormalDeviation => "max_normal_deviation",
        _ => "the other options",
    };
    if fits && let Some(blocker) = options.fit_blocked_by() {
        return Err(PyValueError::new_err(format!(
            "fit_rounds cannot be given with {}, with which no fit is made (leave fit_rounds out or give 0)",
            name(blocker)
        )));
    }
    if flips && let Some(blocker) = options.flips_blocked_by() {
        return Err(PyValueError::new_err(format!(
            "flip_tolerance cannot be given with {}, with which no flips are made (leave flip_tolerance out or give 0)",
            name(blocker)
        )));
    }
    Ok(())
}

/// Hole filling (Liepa 2003), as `beltrami fill-holes`: each boundary loop of at most
/// `max_loop_edges` edges (default 500) triangulated by minimum weight, refined to the
/// surrounding density (`refine`) and faired with the rim fixed (`fair`). In each
/// connected component the loop with the longest perimeter is that component's outer
/// boundary and stays open unless `fill_all`.
/// Returns `(Mesh, report)`: `loops`, `filled` and `skipped` (a dict per loop:
/// `boundary_edges`, `perimeter`, and `faces_added`, `vertices_added`, `area`,
/// `faired_order` or the `reason`), `faces_added`, `vertices_added`,
/// `boundary_loops_left`, `max_loop_edges`, `quality_before` and `quality_after`, as
/// `fill-holes --json`. The input's vertices and faces keep
/// their indices; new ones are appended.
///
/// `progress=True` shows a tqdm bar of the boundary loops when tqdm is installed; Ctrl-C
/// stops the run between two loops with `KeyboardInterrupt`.
///
/// Raises `ValueError` for bad options, `MeshError` for a polygon mesh or one without
/// faces.
#[pyfunction]
#[pyo3(signature = (mesh, *, max_loop_edges = None, fill_all = false, refine = true, fair = true, progress = false))]
pub(crate) fn fill_holes<'py>(
    py: Python<'py>,
    mesh: &Mesh,
    max_loop_edges: Option<i128>,
    fill_all: bool,
    refine: bool,
    fair: bool,
    progress: bool,
) -> PyResult<(Mesh, Bound<'py, PyDict>)> {
    require_faces(mesh, "fill_holes")?;
    let mut options = FillOptions::default()
        .fill_all(fill_all)
        .refine(refine)
        .fair(fair);
    if let Some(n) = at_least_opt("max_loop_edges", max_loop_edges, 3)? {
        options = options.max_loop_edges(n);
    }
    let loops = mesh.mesh.boundary_loops().count();
    let (m, p, r) = Progress::run(py, progress, loops, "fill_holes", |bar| {
        beltrami_algorithms::fill_holes_with_progress(
            &mesh.mesh,
            &mesh.positions,
            &options,
            |done, total| bar.show(done, total),
        )
        .map_err(|e| match e {
            FillError::Options { .. } => PyValueError::new_err(e.to_string()),
            e => algorithm_error("fill_holes", e),
        })
    })?;
    let d = PyDict::new(py);
    d.set_item("vertices", m.n_vertices())?;
    d.set_item("faces", m.n_faces())?;
    d.set_item("loops", r.loops)?;
    let filled = r
        .filled
        .iter()
        .map(|h| {
            let e = PyDict::new(py);
            e.set_item("boundary_edges", h.boundary_edges)?;
            e.set_item("perimeter", h.perimeter)?;
            e.set_item("faces_added", h.faces_added)?;
            e.set_item("vertices_added", h.vertices_added)?;
            e.set_item("area", h.area)?;
            e.set_item("faired_order", h.faired_order)?;
            Ok(e)
        })
        .collect::<PyResult<Vec<_>>>()?;
    let skipped = r
        .skipped
        .iter()
        .map(|h| {
            let e = PyDict::new(py);
            e.set_item("boundary_edges", h.boundary_edges)?;
            e.set_item("perimeter", h.perimeter)?;
            e.set_item(
                "reason",
                match h.reason {
                    SkipReason::OuterBoundary => "outer_boundary",
                    SkipReason::TooLarge => "too_large",
                    SkipReason::NonManifoldVertex => "non_manifold_vertex",
                    _ => "no_manifold_triangulation",
                },
            )?;
            Ok(e)
        })
        .collect::<PyResult<Vec<_>>>()?;
    d.set_item("filled", filled)?;
    d.set_item("skipped", skipped)?;
    d.set_item("faces_added", r.faces_added)?;
    d.set_item("vertices_added", r.vertices_added)?;
    d.set_item("boundary_loops_left", m.boundary_loops().count())?;
    d.set_item("max_loop_edges", options.max_loop_edges)?;
    set_quality_change(py, &d, (&mesh.mesh, &mesh.positions), (&m, &p))?;
    Ok((result_mesh(m, p), d))
}
