//! Physical units: the same Gaussian cut-off wavelength on spheres of different density
//! gives the same result; the same λ × iterations does not.

use beltrami_halfedge::DVec3;
use beltrami_halfedge::geometry::VertexAreaKind;
use beltrami_smooth::{DiffusionTime, ImplicitSolver, Method, SmoothConfig, SmoothError, smooth};
use beltrami_weights::{Cotangent, LaplacianOptions, Normalization, WeightScheme};

/// One tessellation of the unit sphere, filtered two ways.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct UnitsRow {
    /// The icosphere's subdivision level.
    pub level: u32,
    /// Its vertex count.
    pub vertices: usize,
    /// Iterations the smoother chose for the cut-off.
    pub iterations_cutoff: usize,
    /// Mean radius after filtering with the cut-off.
    pub radius_cutoff: f64,
    /// Mean radius after the fixed λ × iterations of the finest level.
    pub radius_fixed: f64,
    /// Mean radius after one implicit (backward Euler) step of the whole time `t`,
    /// cotangent weights with barycentric-area normalisation (the Laplace–Beltrami
    /// operator in length units).
    pub radius_implicit: f64,
    /// Wall time of that implicit step (assembly, factorisation and solve), seconds.
    pub implicit_seconds: f64,
}

/// The cut-off comparison on unit icospheres.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct UnitsComparison {
    /// The weight scheme.
    pub scheme: String,
    /// The largest step λ (weight-sum normalisation).
    pub lambda: f64,
    /// The cut-off wavelength λc, in radii.
    pub cutoff: f64,
    /// The diffusion time `t = 0.017558 λc²`.
    pub time: f64,
    /// The radius of the continuous mean-curvature flow at `t`: `√(1 − 4t)`.
    pub expected_radius: f64,
    /// The fixed iteration count (the finest level's choice for the cut-off).
    pub iterations_fixed: usize,
    /// Coarsest to finest.
    pub rows: Vec<UnitsRow>,
}

fn mean_radius(x: &[DVec3]) -> f64 {
    x.iter().map(|p| p.length()).sum::<f64>() / x.len().max(1) as f64
}

/// Filters clean unit icospheres of each level in `levels` (ascending) with the
/// cut-off `cutoff` (in radii), again with the finest level's λ × iterations, and with
/// one implicit step of the cut-off's time (cotangent, area-normalised).
///
/// # Errors
/// A [`SmoothError`] of any run.
///
/// # Panics
/// Never: the icospheres it builds are valid meshes.
pub fn units_comparison(
    scheme: &dyn WeightScheme,
    lambda: f64,
    cutoff: f64,
    levels: &[u32],
) -> Result<UnitsComparison, SmoothError> {
    let duration = DiffusionTime::Cutoff(cutoff);
    let spheres: Vec<_> = levels
        .iter()
        .map(|&l| {
            let p = beltrami_halfedge::primitives::icosphere(l);
            let mesh = p.mesh().expect("an icosphere is a valid mesh");
            (l, mesh, p.positions)
        })
        .collect();
    let mut timed = Vec::with_capacity(spheres.len());
    for (_, mesh, x) in &spheres {
        let out = smooth(
            mesh,
            x,
            scheme,
            SmoothConfig::new(lambda, 1).duration(duration),
        )?;
        timed.push((out.report.iterations, mean_radius(&out.positions)));
    }
    let iterations_fixed = timed.last().map_or(0, |t| t.0);
    let mut rows = Vec::with_capacity(spheres.len());
    for ((level, mesh, x), (iterations_cutoff, radius_cutoff)) in spheres.iter().zip(timed) {
        let out = smooth(mesh, x, scheme, SmoothConfig::new(lambda, iterations_fixed))?;
        let area =
            LaplacianOptions::new().normalization(Normalization::Area(VertexAreaKind::Barycentric));
        let start = std::time::Instant::now();
        // One backward-Euler step of the whole time.
        let implicit = smooth(
            mesh,
            x,
            &Cotangent,
            SmoothConfig::new(duration.time(), 1)
                .laplacian(area)
                .method(Method::implicit(ImplicitSolver::Cholesky)),
        )?;
        let implicit_seconds = start.elapsed().as_secs_f64();
        rows.push(UnitsRow {
            radius_implicit: mean_radius(&implicit.positions),
            implicit_seconds,
            level: *level,
            vertices: mesh.n_vertices(),
            iterations_cutoff,
            radius_cutoff,
            radius_fixed: mean_radius(&out.positions),
        });
    }
    let time = duration.time();
    Ok(UnitsComparison {
        scheme: scheme.name().to_string(),
        lambda,
        cutoff,
        time,
        expected_radius: (1.0 - 4.0 * time).sqrt(),
        iterations_fixed,
        rows,
    })
}
