//! Turning a diffusion time into a step and an iteration count.

use beltrami_halfedge::reorder::VertexPermutation;
use beltrami_halfedge::{DVec3, HalfedgeMesh, VertexId};
use beltrami_weights::{Laplacian, Normalization, WeightScheme};

use crate::config::{Boundary, SmoothConfig};
use crate::error::SmoothError;

/// A step for an area-normalised run whose caller gave none: `fraction` (a positive
/// number; it is not checked, [`Smoother::new`](crate::Smoother::new) checks the step)
/// of the largest stable explicit step on `positions`, `1 / max_i (W_i / A_i)` (weight
/// sum over vertex area) over the vertices that move (not isolated, not pinned, not on a
/// boundary that `config.boundary` fixes), the limit
/// [`Smoother::stable_step_limit`](crate::Smoother::stable_step_limit) gives for the
/// same configuration; in the unit of `A_i / W_i` (length² for cotangent and uniform
/// weights).
///
/// With weight-sum rows λ is a fraction (stable up to 1) and [`DEFAULT_LAMBDA`](
/// crate::DEFAULT_LAMBDA) = 0.8 works on any mesh; with area rows λ is a time in length²,
/// and 0.8 is unstable for an explicit step on a part whose edges are shorter than about
/// 1.8 units and, for an implicit step, draws a part a few units across together to a
/// point (mean-curvature flow shrinks a unit sphere to a point by t = 0.25). `fraction =
/// DEFAULT_LAMBDA` takes the same share of the stable range as 0.8 does with weight-sum
/// rows: on a regular triangle mesh with cotangent weights and edges of length `h`, where
/// `W_i / A_i = 4 / h²`, it is 0.2 h², the step of λ = 0.8 with weight-sum rows.
///
/// `Ok(None)` with weight-sum normalisation, or when no vertex moves with a positive
/// rate (every moving row stuck). Costs one assembly of the operator's row sums and
/// scales (no weights kept).
///
/// # Errors
/// [`SmoothError::Weights`] when the operator cannot be assembled (positions not one
/// per vertex, mixed-Voronoi areas of polygon faces, a weight that is not finite), as
/// [`Smoother::new`](crate::Smoother::new) reports it.
///
/// # Examples
/// ```
/// use beltrami_halfedge::geometry::VertexAreaKind;
/// use beltrami_halfedge::primitives;
/// use beltrami_smooth::{DEFAULT_LAMBDA, SmoothConfig, area_step};
/// use beltrami_weights::{Cotangent, LaplacianOptions, Normalization};
/// let sphere = primitives::icosphere(3);
/// let mesh = sphere.mesh().unwrap();
/// let area = LaplacianOptions::new().normalization(Normalization::Area(VertexAreaKind::MixedVoronoi));
/// let config = SmoothConfig::new(DEFAULT_LAMBDA, 10).laplacian(area);
/// let step = area_step(&mesh, &sphere.positions, &Cotangent, &config, DEFAULT_LAMBDA)?.unwrap();
/// // About 0.2 h² on the unit sphere of level 3 (mean edge about 0.15).
/// assert!(step > 0.002 && step < 0.006, "{step}");
/// # Ok::<(), beltrami_smooth::SmoothError>(())
/// ```
pub fn area_step(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    scheme: &dyn WeightScheme,
    config: &SmoothConfig,
    fraction: f64,
) -> Result<Option<f64>, SmoothError> {
    if config.laplacian.normalization == Normalization::WeightSum {
        return Ok(None);
    }
    let laplacian = Laplacian::new_without_weights(mesh, positions, scheme, config.laplacian)?;
    let fixed_boundary = config.boundary == Boundary::Fixed;
    let mut moves: Vec<bool> = mesh
        .vertices()
        .map(|v| !(mesh.is_isolated(v) || (fixed_boundary && mesh.is_boundary_vertex(v))))
        .collect();
    for v in &config.pinned {
        if let Some(m) = moves.get_mut(v.index()) {
            *m = false;
        }
    }
    let rate = area_rate(&laplacian, &moves);
    Ok((rate > 0.0 && rate.is_finite()).then(|| fraction / rate))
}

/// The largest rate `max_i W_i / A_i` of the moving rows of an area-normalised
/// Laplacian (weight sum over vertex area, in 1/length²), 0 when no row moves.
pub(crate) fn area_rate(laplacian: &Laplacian, moves: &[bool]) -> f64 {
    let mut rate: f64 = 0.0;
    for (i, &row) in moves.iter().enumerate() {
        let v = VertexId::new(i as u32);
        if row && let Some(scale) = laplacian.scale(v) {
            rate = rate.max(laplacian.weight_sum(v) * scale);
        }
    }
    rate
}

/// How a run diffuses for a given time.
pub(crate) struct Plan<'a> {
    /// The internal numbering, when the run reorders.
    pub(crate) perm: Option<&'a VertexPermutation>,
    /// The positions, internal numbering.
    pub(crate) positions: &'a [DVec3],
    /// The operator on them.
    pub(crate) laplacian: &'a Laplacian,
    /// Which vertices move with their Laplacian row (internal numbering).
    pub(crate) moves: &'a [bool],
    /// The largest step allowed (the configured λ).
    pub(crate) max_lambda: f64,
    /// Whether an area-normalised step must also stay below half the explicit
    /// stability limit (explicit runs; an implicit step is stable at any size).
    pub(crate) explicit: bool,
}

/// The step and iteration count that diffuse for the time `t` (length²); see
/// [`DiffusionTime`](crate::DiffusionTime).
pub(crate) fn resolve_duration(plan: &Plan<'_>, t: f64) -> Result<(f64, usize), SmoothError> {
    let Plan {
        perm,
        positions,
        laplacian,
        moves,
        max_lambda,
        explicit,
    } = *plan;
    if t == 0.0 {
        return Ok((max_lambda, 0));
    }
    let (time_per_unit, max_step) = match laplacian.options().normalization {
        Normalization::WeightSum => {
            // A normalised row acting on f = ½|x − x_i|² gives ½⟨ℓ²⟩_w, the
            // weighted mean squared edge length; Δf = 2 on a surface, so the row is
            // ≈ (⟨ℓ²⟩_w / 4) Δ: one step λ advances vertex i's time by λ⟨ℓ²⟩_w / 4.
            // The mean over the moving rows is the mesh's time per unit step.
            let mut sum = 0.0;
            let mut count = 0usize;
            // Summed in the caller's vertex order, so that reordering changes no bit.
            for old in 0..positions.len() {
                let v = VertexId::new(perm.map_or(old as u32, |p| p.old_to_new()[old]));
                if !moves[v.index()] {
                    continue;
                }
                let xi = positions[v.index()];
                let w = laplacian.weight_sum(v);
                let mut s = 0.0;
                for (j, wij) in laplacian.row(v) {
                    s += wij * positions[j.index()].distance_squared(xi);
                }
                let mean = s / w;
                if w > 0.0 && mean.is_finite() && mean > 0.0 {
                    sum += mean;
                    count += 1;
                }
            }
            let mean = if count == 0 { 0.0 } else { sum / count as f64 };
            if !(mean > 0.0 && mean.is_finite()) {
                return Err(SmoothError::InvalidDuration {
                    reason: "the mesh has no moving vertex with edges of positive length to measure time by".into(),
                });
            }
            // One step λ advances the time by λ ⟨ℓ²⟩ / 4.
            (mean / 4.0, max_lambda)
        }
        // Area normalisation: λ is a time per iteration.
        _ => {
            let rate = if explicit {
                area_rate(laplacian, moves)
            } else {
                0.0
            };
            let cap = if rate > 0.0 { 0.5 / rate } else { max_lambda };
            (1.0, max_lambda.min(cap))
        }
    };
    let units = t / time_per_unit;
    let iterations = (units / max_step).ceil();
    if !(iterations.is_finite() && iterations <= 1e9) {
        return Err(SmoothError::InvalidDuration {
            reason: format!("the time {t} would need {iterations} iterations"),
        });
    }
    let iterations = (iterations as usize).max(1);
    Ok((units / iterations as f64, iterations))
}
