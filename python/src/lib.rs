//! # beltrami-python
//!
//! The Python extension module `beltrami._beltrami`, re-exported by the pure-Python
//! package `beltrami`: meshes from and to numpy arrays, reading and writing mesh
//! files, `info`, `smooth` with the options, defaults and report of
//! `beltrami smooth`, comparisons and fits, and the mesh algorithms (`quality`,
//! `subdivide`, `delaunay`, `remesh`, `decimate`, `fill_holes`). Heavy calls run without the GIL; errors become Python
//! exceptions with the library's one-line messages.

mod algorithms;
mod compare;
mod errors;
mod fit;
mod generate;
mod info;
mod io;
mod mesh;
mod operator;
mod progress;
mod residual;
mod scheme;
mod smooth;
mod study;
mod weights;

use pyo3::prelude::*;

/// The extension module.
#[pymodule]
fn _beltrami(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<mesh::Mesh>()?;
    m.add("MeshError", py.get_type::<errors::MeshError>())?;
    m.add("FormatError", py.get_type::<errors::FormatError>())?;
    m.add("SmoothError", py.get_type::<errors::SmoothError>())?;
    m.add("MetricsError", py.get_type::<errors::MetricsError>())?;
    m.add_function(wrap_pyfunction!(io::read, m)?)?;
    m.add_function(wrap_pyfunction!(io::write, m)?)?;
    m.add_function(wrap_pyfunction!(info::info, m)?)?;
    m.add_function(wrap_pyfunction!(smooth::smooth, m)?)?;
    m.add_function(wrap_pyfunction!(weights::weight_schemes, m)?)?;
    m.add_function(wrap_pyfunction!(generate::generate, m)?)?;
    m.add_function(wrap_pyfunction!(operator::laplacian, m)?)?;
    m.add_function(wrap_pyfunction!(operator::mass_matrix, m)?)?;
    m.add_function(wrap_pyfunction!(scheme::register_weight, m)?)?;
    m.add_function(wrap_pyfunction!(compare::compare, m)?)?;
    m.add_function(wrap_pyfunction!(compare::distances, m)?)?;
    m.add_function(wrap_pyfunction!(fit::fit_sphere, m)?)?;
    m.add_function(wrap_pyfunction!(fit::fit_circle, m)?)?;
    m.add_function(wrap_pyfunction!(fit::fit_cylinder, m)?)?;
    m.add_function(wrap_pyfunction!(residual::residual, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms::quality, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms::subdivide, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms::delaunay, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms::remove_flat_triangles, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms::remesh, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms::decimate, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms::fill_holes, m)?)?;
    m.add_function(wrap_pyfunction!(study::study, m)?)?;
    Ok(())
}
