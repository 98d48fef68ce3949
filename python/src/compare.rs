//! `beltrami.compare` and `beltrami.distances`: a mesh against a reference surface,
//! as `beltrami compare --json`.

use std::time::Instant;

use beltrami_halfedge::geometry::{Geometry, VertexAreaKind};
use beltrami_metrics::MetricsError;
use beltrami_metrics::distance::{
    DistanceStats, HausdorffDistance, SampledDistance, SignedDistanceStats, SurfaceIndex,
    check_same_topology, displacement_stats, surface_distance,
};
use beltrami_metrics::measures::{closed_volume, surface_area};
use beltrami_metrics::normals::normal_deviation;
use numpy::PyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{MeshError, metrics_error, no_panic};
use crate::mesh::{Mesh, vertices_from};

/// The seed of the surface samples: fixed, so that a run is repeatable (as the
/// command line's).
const SAMPLE_SEED: u64 = 1;

/// The largest number of surface samples, as on the command line.
const MAX_SAMPLES: usize = 10_000_000;

/// The numbers of one comparison.
struct Comparison {
    stats: DistanceStats,
    signed: SignedDistanceStats,
    hausdorff: HausdorffDistance,
    /// With samples: the sampled distances mesh → reference and back.
    sampled: Option<(SampledDistance, SampledDistance)>,
    displacement: Option<DistanceStats>,
    normals: Option<beltrami_metrics::normals::NormalDeviation>,
    /// The mesh's and the reference's enclosed volumes and their ratio (None when the
    /// reference encloses none).
    volumes: Option<(f64, f64, Option<f64>)>,
    areas: (f64, f64),
    index_build: f64,
    queries: f64,
}

/// The file name, or None for a mesh built from arrays.
fn file(mesh: &Mesh) -> Option<String> {
    mesh.source.as_ref().map(|(p, _)| p.display().to_string())
}

fn needs_faces(mesh: &Mesh, what: &str) -> PyResult<()> {
    if mesh.mesh.n_faces() == 0 {
        return Err(MeshError::new_err(format!(
            "the {what} has {} vertices but no faces (points or lines only; compare needs a surface of triangles)",
            mesh.mesh.n_vertices()
        )));
    }
    Ok(())
}

fn measure(mesh: &Mesh, reference: &Mesh, samples: usize) -> Result<Comparison, MetricsError> {
    let clock = Instant::now();
    let reference_index = SurfaceIndex::new(&reference.mesh, &reference.positions)?;
    reference_index.prepare_signed();
    let mesh_index = SurfaceIndex::new(&mesh.mesh, &mesh.positions)?;
    let index_build = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    let signed = reference_index.signed_distances(&mesh.positions)?;
    let both = surface_distance(&mesh_index, &signed, &reference_index, samples, SAMPLE_SEED)?;
    let (hausdorff, sampled) = (both.hausdorff, both.sampled);
    let queries = clock.elapsed().as_secs_f64();

    let unsigned: Vec<f64> = signed.iter().map(|s| s.abs()).collect();
    let areas = Geometry::new(&mesh.mesh, &mesh.positions)
        .and_then(|g| g.vertex_areas(VertexAreaKind::Barycentric))
        .map_err(MetricsError::from)?;
    let stats = DistanceStats::new(&unsigned, areas.as_slice())?;
    let signed_stats = SignedDistanceStats::new(&signed)?;
    let (displacement, normals) = match check_same_topology(&mesh.mesh, &reference.mesh) {
        Ok(()) => {
            let d = displacement_stats(
                &mesh.mesh,
                &mesh.positions,
                &reference.mesh,
                &reference.positions,
            )?;
            let n = match normal_deviation(
                &mesh.mesh,
                &mesh.positions,
                &reference.mesh,
                &reference.positions,
            ) {
                Ok(n) => Some(n),
                Err(MetricsError::Empty { .. }) => None,
                Err(e) => return Err(e),
            };
            (Some(d), n)
        }
        Err(MetricsError::TopologyMismatch { .. }) => (None, None),
        Err(e) => return Err(e),
    };
    let mesh_geometry = Geometry::new(&mesh.mesh, &mesh.positions)?;
    let reference_geometry = Geometry::new(&reference.mesh, &reference.positions)?;
    let extent = beltrami_metrics::measures::surface_extent(&reference_geometry);
    let volumes = closed_volume(&mesh_geometry)?
        .zip(closed_volume(&reference_geometry)?)
        .map(|(m, r)| (m, r, beltrami_metrics::measures::volume_ratio(m, r, extent)));
    let areas = (
        surface_area(&mesh_geometry)?,
        surface_area(&reference_geometry)?,
    );
    Ok(Comparison {
        stats,
        signed: signed_stats,
        hausdorff,
        sampled,
        displacement,
        normals,
        volumes,
        areas,
        index_build,
        queries,
    })
}

fn summary<'py>(py: Python<'py>, mesh: &Mesh) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("file", file(mesh))?;
    d.set_item("vertices", mesh.mesh.n_vertices())?;
    d.set_item("faces", mesh.mesh.n_faces())?;
    d.set_item("closed", mesh.mesh.is_closed())?;
    Ok(d)
}

/// Distances, normals, areas and volumes of `mesh` against the `reference` surface: a
/// dict with the keys of `beltrami compare --json` (`mesh`, `reference`, `rms`,
/// `mean`, `max`, `area_rms`, `signed`, `hausdorff`, `hausdorff_mesh_to_reference`,
/// `hausdorff_reference_to_mesh`, `hausdorff_samples`, `surface_rms`, `same_topology`,
/// `displacement`, `normal_deviation_deg`, `normal_area_weighted_error`, `volume`,
/// `area`, `scalars`, `png`, `seconds`).
///
/// Distances are from the mesh's vertices to the closest point of the reference's
/// triangles; signed distances are positive on the side the reference's normals point
/// to. `samples` also measures the Hausdorff distance from that many points per
/// surface, spread uniformly by area (fixed seed), and the RMS distance of those points
/// to the other surface each way (`surface_rms`, None without samples). `displacement` and the normal
/// deviation need both meshes to share vertices and faces (None otherwise); `volume`
/// needs both closed (its `ratio` is None when the reference encloses no volume). `scalars` and `png` are always None (use `distances` and
/// `write(..., scalars=...)`). Runs without the GIL.
#[pyfunction]
#[pyo3(signature = (mesh, reference, *, samples = None))]
pub(crate) fn compare<'py>(
    py: Python<'py>,
    mesh: &Mesh,
    reference: &Mesh,
    samples: Option<i128>,
) -> PyResult<Bound<'py, PyDict>> {
    // As `compare --samples`: 1 to MAX_SAMPLES points; None takes no samples.
    if let Some(n) = samples
        && !(1..=MAX_SAMPLES as i128).contains(&n)
    {
        return Err(PyValueError::new_err(format!(
            "samples must be between 1 and {MAX_SAMPLES} (or None for no samples), got {n}"
        )));
    }
    let samples = samples.map_or(0, |n| n as usize);
    needs_faces(mesh, "mesh")?;
    needs_faces(reference, "reference")?;
    let start = Instant::now();
    let c = py
        .detach(|| no_panic(|| measure(mesh, reference, samples).map_err(|e| metrics_error(&e))))?;
    let d = PyDict::new(py);
    d.set_item("mesh", summary(py, mesh)?)?;
    d.set_item("reference", summary(py, reference)?)?;
    d.set_item("rms", c.stats.rms)?;
    d.set_item("mean", c.stats.mean)?;
    d.set_item("max", c.stats.max)?;
    d.set_item("area_rms", c.stats.area_weighted_rms)?;
    let signed = PyDict::new(py);
    signed.set_item("mean", c.signed.mean)?;
    signed.set_item("min", c.signed.min)?;
    signed.set_item("max", c.signed.max)?;
    signed.set_item("std_dev", c.signed.std_dev)?;
    d.set_item("signed", signed)?;
    d.set_item("hausdorff", c.hausdorff.symmetric)?;
    d.set_item("hausdorff_mesh_to_reference", c.hausdorff.forward)?;
    d.set_item("hausdorff_reference_to_mesh", c.hausdorff.backward)?;
    d.set_item("hausdorff_samples", samples)?;
    match &c.sampled {
        Some((there, back)) => {
            let rms = PyDict::new(py);
            rms.set_item("symmetric", there.rms.max(back.rms))?;
            rms.set_item("mesh_to_reference", there.rms)?;
            rms.set_item("reference_to_mesh", back.rms)?;
            d.set_item("surface_rms", rms)?;
        }
        None => d.set_item("surface_rms", py.None())?,
    }
    d.set_item("same_topology", c.displacement.is_some())?;
    match &c.displacement {
        Some(x) => {
            let disp = PyDict::new(py);
            disp.set_item("rms", x.rms)?;
            disp.set_item("mean", x.mean)?;
            disp.set_item("max", x.max)?;
            disp.set_item("area_rms", x.area_weighted_rms)?;
            d.set_item("displacement", disp)?;
        }
        None => d.set_item("displacement", py.None())?,
    }
    match &c.normals {
        Some(n) => {
            let normals = PyDict::new(py);
            normals.set_item("mean", n.mean_deg)?;
            normals.set_item("rms", n.rms_deg)?;
            normals.set_item("max", n.max_deg)?;
            normals.set_item("faces", n.compared)?;
            d.set_item("normal_deviation_deg", normals)?;
            d.set_item("normal_area_weighted_error", n.area_weighted_error)?;
        }
        None => {
            d.set_item("normal_deviation_deg", py.None())?;
            d.set_item("normal_area_weighted_error", py.None())?;
        }
    }
    match c.volumes {
        Some((m, r, ratio)) => {
            let v = PyDict::new(py);
            v.set_item("mesh", m)?;
            v.set_item("reference", r)?;
            v.set_item("ratio", ratio)?;
            d.set_item("volume", v)?;
        }
        None => d.set_item("volume", py.None())?,
    }
    let area = PyDict::new(py);
    area.set_item("mesh", c.areas.0)?;
    area.set_item("reference", c.areas.1)?;
    d.set_item("area", area)?;
    d.set_item("scalars", py.None())?;
    d.set_item("png", py.None())?;
    let total = start.elapsed().as_secs_f64();
    let seconds = PyDict::new(py);
    seconds.set_item("read", 0.0)?;
    seconds.set_item("index_build", c.index_build)?;
    seconds.set_item("queries", c.queries)?;
    seconds.set_item("other", (total - c.index_build - c.queries).max(0.0))?;
    seconds.set_item("total", total)?;
    d.set_item("seconds", seconds)?;
    Ok(d)
}

/// The distance of each point (a Mesh's vertices or an (N, 3) array) to the closest
/// point of the `reference` surface's triangles, as a float64 array; `signed=True`
/// gives it the sign of the side (positive where the reference's normals point:
/// outside). The numbers `compare` summarises, per point.
#[pyfunction]
#[pyo3(signature = (points, reference, *, signed = false))]
pub(crate) fn distances<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyAny>,
    reference: &Mesh,
    signed: bool,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    needs_faces(reference, "reference")?;
    let positions = match points.downcast::<Mesh>() {
        Ok(m) => m.get().positions.clone(),
        Err(_) => vertices_from(points)?,
    };
    let values = py.detach(|| {
        no_panic(|| {
            let index = SurfaceIndex::new(&reference.mesh, &reference.positions)
                .map_err(|e| metrics_error(&e))?;
            if signed {
                index.signed_distances(&positions)
            } else {
                index.distances(&positions)
            }
            .map_err(|e| metrics_error(&e))
        })
    })?;
    Ok(PyArray1::from_vec(py, values))
}
