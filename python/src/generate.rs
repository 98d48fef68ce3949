//! `beltrami.generate`: the paper's test surfaces, optionally with seeded noise.

use beltrami_io::MeshData;
use beltrami_surfaces::{NoiseLevel, Size, SurfaceKind, add_normal_noise, cut_holes};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::errors::no_panic;
use crate::mesh::Mesh;

/// The default hole radii in mean edge lengths, tried in turn: 3 (the command's
/// default), then smaller ones for a surface too small for it.
const DEFAULT_HOLE_RADII: [f64; 4] = [3.0, 2.0, 1.5, 1.0];

/// The largest sphere level: 10 485 762 vertices.
const MAX_SPHERE_LEVEL: u32 = 10;

/// One of the paper's test surfaces, as `beltrami generate` writes it.
///
/// `surface` is `"flens"` (open free-form lens, mm), `"sphere"` (unit icosphere),
/// `"block"` (genus-3 part with sharp edges, mm) or `"golfball"` (dimpled ball, mm).
/// `noise` adds Gaussian noise along the vertex normals with this standard
/// deviation, a multiple of the mean edge length (or in the surface's length unit
/// with `absolute_noise`), drawn from `seed` (the same numbers on every platform).
/// `level` is the sphere's subdivision level, 0 to 10 (default 6: 40 962 vertices).
/// `shuffle` renumbers the vertices in a random order drawn from this seed.
/// `size="small"` gives a coarse version of the same shape (for tests and quick
/// looks). `holes` cuts this many round holes into the surface, as a scan leaves
/// them where the sensor saw nothing: each removes the faces whose centroid lies
/// within `hole_radius` mean edge lengths (default 3, or 2, 1.5 or 1 on a surface too
/// small for it, such as `size="small"`'s F-lens, with a `UserWarning` naming the
/// radius) of a vertex drawn from `seed`
/// away from the boundary and from the other holes; the vertices are renumbered, so
/// `holes` and `shuffle` exclude each other. Generate the surface again without
/// `noise` and `holes` for the clean reference.
///
/// The same arguments give the same bits as the command line's file.
///
/// Raises `ValueError` for an unknown surface or size, a negative count or seed, a
/// level above 10 or for another surface than the sphere, `size="small"` with a level,
/// `hole_radius` without `holes` or not positive, `holes` with `shuffle`, more holes
/// than fit or holes that remove the whole surface, and noise so large that a position
/// overflows.
#[pyfunction]
#[pyo3(signature = (surface, *, noise = None, absolute_noise = false, seed = 1, level = None, shuffle = None, size = "paper", holes = None, hole_radius = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn generate(
    py: Python<'_>,
    surface: &str,
    noise: Option<f64>,
    absolute_noise: bool,
    seed: i128,
    level: Option<i128>,
    shuffle: Option<i128>,
    size: &str,
    holes: Option<i128>,
    hole_radius: Option<f64>,
) -> PyResult<Mesh> {
    let seed: u64 = crate::errors::nonnegative("seed", seed)?;
    let level: Option<u32> = crate::errors::nonnegative_opt("level", level)?;
    let shuffle: Option<u64> = crate::errors::nonnegative_opt("shuffle", shuffle)?;
    let holes: Option<usize> = crate::errors::nonnegative_opt("holes", holes)?;
    let hole_radius = match (holes, hole_radius) {
        (None, Some(_)) => {
            return Err(PyValueError::new_err("hole_radius needs holes"));
        }
        (_, Some(r)) if !(r > 0.0 && r.is_finite()) => {
            return Err(PyValueError::new_err(format!(
                "hole_radius must be positive and finite, got {r}"
            )));
        }
        (_, r) => r,
    };
    if holes.is_some() && shuffle.is_some() {
        return Err(PyValueError::new_err(
            "holes and shuffle cannot be combined (cutting holes renumbers the vertices)",
        ));
    }
    let size = match size {
        "paper" => Size::Paper,
        "small" => Size::Small,
        _ => {
            return Err(PyValueError::new_err(format!(
                "size must be 'paper' or 'small', got '{size}'"
            )));
        }
    };
    if level.is_some() && size == Size::Small {
        return Err(PyValueError::new_err(
            "size='small' and level exclude each other: level sets the sphere's size",
        ));
    }
    let kind = match surface {
        "flens" => SurfaceKind::FLens,
        "sphere" => SurfaceKind::Sphere,
        "block" => SurfaceKind::Block,
        "golfball" => SurfaceKind::GolfBall,
        _ => {
            return Err(PyValueError::new_err(format!(
                "surface must be one of 'flens', 'sphere', 'block', 'golfball', got '{surface}'"
            )));
        }
    };
    match (kind, level) {
        (SurfaceKind::Sphere, Some(l)) if l > MAX_SPHERE_LEVEL => {
            return Err(PyValueError::new_err(format!(
                "level must be 0 to {MAX_SPHERE_LEVEL}, got {l}"
            )));
        }
        (SurfaceKind::Sphere, _) | (_, None) => {}
        (_, Some(_)) => {
            return Err(PyValueError::new_err("level applies to the sphere only"));
        }
    }
    let (positions, faces, radius) = py.detach(|| {
        no_panic(|| {
            let surface = match level {
                Some(level) => beltrami_surfaces::sphere(level),
                None => kind.generate_sized(size),
            };
            let mesh = surface.mesh().map_err(|e| {
                PyValueError::new_err(format!("internal: generated surface is invalid: {e}"))
            })?;
            let positions = match noise {
                None => surface.positions.clone(),
                Some(level) => {
                    let level = if absolute_noise {
                        NoiseLevel::Absolute(level)
                    } else {
                        NoiseLevel::RelativeToMeanEdge(level)
                    };
                    add_normal_noise(&mesh, &surface.positions, level, seed)
                        .map_err(|e| PyValueError::new_err(e.to_string()))?
                        .0
                }
            };
            if let Some(count) = holes {
                // As `beltrami generate --holes`: the radius in mean edge lengths of the
                // clean surface, the holes cut into the noisy one.
                let mean = beltrami_halfedge::geometry::Geometry::new(&mesh, &surface.positions)
                    .ok()
                    .and_then(|g| g.mean_edge_length())
                    .ok_or_else(|| {
                        PyValueError::new_err("internal: generated surface has no edges")
                    })?;
                let noisy = MeshData::new(positions, surface.faces.clone());
                // The default radius shrinks on a surface too small for it (the small
                // F-lens takes 2); a radius given is kept, and its error raised.
                let radii = match hole_radius {
                    Some(r) => vec![r],
                    None => DEFAULT_HOLE_RADII.to_vec(),
                };
                let mut first = None;
                for r in radii {
                    match cut_holes(&noisy, count, r * mean, seed) {
                        Ok(cut) => {
                            return Ok((cut.data.positions, cut.data.faces, Some(r)));
                        }
                        Err(e) => {
                            first.get_or_insert(e);
                        }
                    }
                }
                // The error of the radius asked for (the default's when none was).
                return Err(PyValueError::new_err(first.map_or_else(String::new, |e| {
                    if hole_radius.is_none() {
                        format!(
                            "{e} (the default hole_radius of {} mean edge lengths was tried down to {})",
                            DEFAULT_HOLE_RADII[0],
                            DEFAULT_HOLE_RADII[DEFAULT_HOLE_RADII.len() - 1]
                        )
                    } else {
                        e.to_string()
                    }
                })));
            }
            Ok(match shuffle {
                None => (positions, surface.faces.clone(), None),
                Some(seed) => {
                    let order = beltrami_surfaces::shuffle_order(positions.len(), seed);
                    let noisy = order.iter().map(|&old| positions[old as usize]).collect();
                    (noisy, surface.shuffled(seed).faces.clone(), None)
                }
            })
        })
    })?;
    if hole_radius.is_none()
        && let Some(used) = radius.filter(|&r| r != DEFAULT_HOLE_RADII[0])
    {
        crate::errors::warn_user(
            py,
            &format!(
                "the default hole_radius of {} mean edge lengths does not fit this surface; the holes have radius {used}",
                DEFAULT_HOLE_RADII[0]
            ),
        )?;
    }
    Mesh::build(py, positions, faces, None)
}
