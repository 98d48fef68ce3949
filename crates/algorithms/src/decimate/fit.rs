//! The final fit of a decimated mesh to its input: each vertex moves, mostly along the
//! surface normal, to bring the simplified surface closer to the input's triangles.
//!
//! The energy is Hoppe et al.'s distance energy with point-to-plane distances: samples
//! of the input (its face centroids, weighted by area) are matched to their closest
//! points on the output, and the output's vertices are moved to minimise the squared
//! distance of those points to the samples' planes,
//! `Σ_i a_i (n_i · (Σ_k b_ik x_k − c_i))²`, where `c_i`, `n_i` and `a_i` are the input
//! face's centroid, unit normal and area and `b_ik` the barycentric coordinates of the
//! closest point in its output triangle. Gauss–Seidel sweeps solve it vertex by vertex
//! with the other vertices fixed (a 3 × 3 system per vertex), with a small pull towards
//! the current position, so that the tangential directions, which the planes do not
//! fix, stay where they are and the triangles keep their shape. A move that would turn
//! a triangle over, go farther than half the vertex's shortest edge, or leave the worst
//! triangle around the vertex below shape quality 0.3 (or the decimation's aspect-ratio
//! bound) and worse than it was, is not made.
//! Boundary vertices stay. The samples are matched again in each round.
//!
//! # References
//! - H. Hoppe, T. DeRose, T. Duchamp, J. McDonald, W. Stuetzle, "Mesh optimization",
//!   SIGGRAPH 1993 (the distance energy and its alternation of projection and fit).
//! - P. Cignoni, C. Rocchini, R. Scopigno, "Metro: measuring error on simplified
//!   surfaces", Computer Graphics Forum 17(2), 1998 (the error it lowers).

use beltrami_halfedge::{DVec3, HalfedgeMesh, VertexId};
use beltrami_metrics::MetricsError;
use beltrami_metrics::distance::SurfaceIndex;
use glam::DMat3;
use rayon::prelude::*;

use beltrami_halfedge::geometry::{self, CompensatedSum as Sum};

/// The weight of the pull towards the current position, relative to the trace of the
/// vertex's plane matrix.
const PULL: f64 = 1e-3;

/// Gauss–Seidel sweeps per round.
const SWEEPS: usize = 4;

/// One sample of the input: the centroid, unit normal and area of a face.
struct Sample {
    centroid: DVec3,
    normal: DVec3,
    area: f64,
}

/// What [`fit_to_input`] did.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Fit {
    /// Rounds done (0 when the input has no area).
    pub(super) rounds: usize,
    /// The area-weighted RMS plane distance of the samples before the fit.
    pub(super) rms_before: f64,
    /// The same after the last round's sweeps, with that round's matches.
    pub(super) rms_after: f64,
}

/// Moves the vertices of `out` (positions `x`) towards the input surface (`input`,
/// positions `y`) in `rounds` rounds of matching and fitting. Sequential sweeps over the
/// vertices in order, after parallel closest-point queries whose answers do not depend
/// on the thread count: the result is the same on any number of threads.
///
/// # Errors
/// The closest-point index's errors (none in practice: positions are finite).
pub(super) fn fit_to_input(
    out: &HalfedgeMesh,
    x: &mut [DVec3],
    input: &HalfedgeMesh,
    y: &[DVec3],
    rounds: usize,
    max_aspect_ratio: Option<f64>,
) -> Result<Fit, MetricsError> {
    // A triangle of aspect ratio a has shape quality 1/a: the bound raises the floor.
    let floor = max_aspect_ratio.map_or(SHAPE, |a| SHAPE.max(1.0 / a));
    let samples = face_samples(input, y);
    let total_area: f64 = samples.iter().map(|s| s.area).sum();
    if samples.is_empty() || total_area.is_nan() || total_area <= 0.0 {
        return Ok(Fit::default());
    }
    let centroids: Vec<DVec3> = samples.iter().map(|s| s.centroid).collect();
    let fixed: Vec<bool> = out.vertices().map(|v| out.is_boundary_vertex(v)).collect();
    let mut fit = Fit {
        rounds,
        ..Fit::default()
    };
    for round in 0..rounds {
        let mut matches = Matches::new(out, x, &samples, &centroids)?;
        if round == 0 {
            fit.rms_before = matches.energy(&samples, total_area);
        }
        for _ in 0..SWEEPS {
            for v in out.vertices() {
                if fixed[v.index()] {
                    continue;
                }
                if let Some(step) = matches.step(v, &samples)
                    && allowed(out, x, v, step, floor)
                {
                    x[v.index()] += step;
                    matches.moved(v, step, &samples);
                }
            }
        }
        fit.rms_after = matches.energy(&samples, total_area);
    }
    Ok(fit)
}

/// One sample per input face of non-zero area: its centroid, unit normal and area.
fn face_samples(input: &HalfedgeMesh, y: &[DVec3]) -> Vec<Sample> {
    input
        .faces()
        .filter_map(|f| {
            let [a, b, c] = input.triangle_vertices(f).map(|v| y[v.index()]);
            let cross = (b - a).cross(c - a);
            let area = 0.5 * cross.length();
            (area > 0.0 && area.is_finite()).then(|| Sample {
                centroid: (a + b + c) / 3.0,
                normal: cross / (2.0 * area),
                area,
            })
        })
        .collect()
}

/// The samples matched to the output in one round: each vertex's samples with their
/// barycentric weights, and each sample's signed plane distance (residual), kept up to
/// date as vertices move.
struct Matches {
    /// `entries[offsets[v]..offsets[v + 1]]` are vertex `v`'s samples.
    offsets: Vec<usize>,
    /// (sample, the vertex's barycentric weight at the sample's closest point).
    entries: Vec<(u32, f64)>,
    /// `n_i · (q_i − c_i)` for each sample, `q_i` its closest output point.
    residual: Vec<f64>,
    /// Each vertex's inverse system matrix `(Σ a_i b_i² n_i n_iᵀ + pull · trace · I)⁻¹`,
    /// fixed within a round; `None` where it has no samples or is singular.
    inverse: Vec<Option<DMat3>>,
}

impl Matches {
    /// Matches every sample centroid to its closest point on the output `(out, x)`.
    fn new(
        out: &HalfedgeMesh,
        x: &[DVec3],
        samples: &[Sample],
        centroids: &[DVec3],
    ) -> Result<Self, MetricsError> {
        let index = SurfaceIndex::new(out, x)?;
        let closest = index.closest_points(centroids)?;
        let matched: Vec<([VertexId; 3], [f64; 3])> = closest
            .par_iter()
            .map(|cp| {
                let t = out.triangle_vertices(cp.face);
                (t, barycentric(cp.point, t.map(|v| x[v.index()])))
            })
            .collect();
        let mut offsets = vec![0usize; x.len() + 1];
        for (t, _) in &matched {
            for v in t {
                offsets[v.index() + 1] += 1;
            }
        }
        for i in 0..x.len() {
            offsets[i + 1] += offsets[i];
        }
        let mut fill = offsets.clone();
        let mut entries = vec![(0u32, 0.0f64); offsets[x.len()]];
        for (i, (t, b)) in matched.iter().enumerate() {
            for (v, &w) in t.iter().zip(b) {
                entries[fill[v.index()]] = (i as u32, w);
                fill[v.index()] += 1;
            }
        }
        let residual = matched
            .par_iter()
            .zip(samples)
            .map(|((t, b), s)| {
                let q = x[t[0].index()] * b[0] + x[t[1].index()] * b[1] + x[t[2].index()] * b[2];
                s.normal.dot(q - s.centroid)
            })
            .collect();
        let inverse = (0..x.len())
            .into_par_iter()
            .map(|v| {
                let mut h = DMat3::ZERO;
                for &(i, b) in &entries[offsets[v]..offsets[v + 1]] {
                    let s = &samples[i as usize];
                    h += outer(s.normal * (s.area * b * b), s.normal);
                }
                let trace = h.x_axis.x + h.y_axis.y + h.z_axis.z;
                if trace.is_nan() || trace <= 0.0 {
                    return None;
                }
                h += DMat3::from_diagonal(DVec3::splat(PULL * trace));
                let det = h.determinant();
                (det.is_finite() && det != 0.0).then(|| h.inverse())
            })
            .collect();
        Ok(Self {
            offsets,
            entries,
            residual,
            inverse,
        })
    }

    /// Vertex `v`'s samples.
    fn own(&self, v: VertexId) -> &[(u32, f64)] {
        &self.entries[self.offsets[v.index()]..self.offsets[v.index() + 1]]
    }

    /// The move of `v` that minimises its samples' energy with the other vertices
    /// fixed, with the pull towards its position; `None` where it has no samples or the
    /// system is singular.
    fn step(&self, v: VertexId, samples: &[Sample]) -> Option<DVec3> {
        let inverse = self.inverse[v.index()]?;
        let mut g = DVec3::ZERO;
        for &(i, b) in self.own(v) {
            let s = &samples[i as usize];
            g += s.normal * (s.area * b * self.residual[i as usize]);
        }
        let step = -(inverse * g);
        step.is_finite().then_some(step)
    }

    /// Updates the residuals of `v`'s samples after `v` moved by `step`.
    fn moved(&mut self, v: VertexId, step: DVec3, samples: &[Sample]) {
        let (start, end) = (self.offsets[v.index()], self.offsets[v.index() + 1]);
        for &(i, b) in &self.entries[start..end] {
            self.residual[i as usize] += b * samples[i as usize].normal.dot(step);
        }
    }

    /// The area-weighted RMS of the residuals, `sqrt(Σ a_i r_i² / total_area)`.
    fn energy(&self, samples: &[Sample], total_area: f64) -> f64 {
        let mut sum = Sum::default();
        for (r, s) in self.residual.iter().zip(samples) {
            sum.add(s.area * r * r);
        }
        (sum.value() / total_area).sqrt()
    }
}

/// `a bᵀ`.
fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

/// The barycentric coordinates of `p` (a point of the triangle, up to rounding) in
/// triangle `t`, clamped to the triangle; the centroid's for a degenerate triangle.
fn barycentric(p: DVec3, [a, b, c]: [DVec3; 3]) -> [f64; 3] {
    let [_, v, w] = geometry::barycentric(p, a, b, c);
    let (v, w) = (v.clamp(0.0, 1.0), w.clamp(0.0, 1.0));
    let s = v + w;
    let (v, w) = if s > 1.0 { (v / s, w / s) } else { (v, w) };
    [1.0 - v - w, v, w]
}

/// Whether moving vertex `v` by `step` keeps every triangle around it facing the same
/// way, moves it by at most half its shortest edge, and leaves the worst triangle around
/// it no worse than before or than shape quality `floor`, whichever is lower.
fn allowed(mesh: &HalfedgeMesh, x: &[DVec3], v: VertexId, step: DVec3, floor: f64) -> bool {
    let p = x[v.index()];
    let shortest = mesh
        .vertices_around_vertex(v)
        .map(|w| p.distance_squared(x[w.index()]))
        .fold(f64::INFINITY, f64::min);
    if step.length_squared() > 0.25 * shortest {
        return false;
    }
    let moved = p + step;
    let mut worst_before = f64::INFINITY;
    let mut worst_after = f64::INFINITY;
    for h in mesh.halfedges_around_vertex(v) {
        if mesh.is_boundary_halfedge(h) {
            continue;
        }
        let a = x[mesh.to_vertex(h).index()];
        let b = x[mesh.to_vertex(mesh.next(h)).index()];
        let before = (a - p).cross(b - p);
        let after = (a - moved).cross(b - moved);
        if before.dot(after) <= 0.0 {
            return false;
        }
        worst_before = worst_before.min(quality(p, a, b));
        worst_after = worst_after.min(quality(moved, a, b));
    }
    worst_after >= worst_before.min(floor)
}

/// The smallest shape quality ([`quality`]) a move may leave around a vertex, unless
/// the triangles there were already worse (then they may not get worse); a
/// `max_aspect_ratio` of the decimation raises it to the inverse of that ratio.
const SHAPE: f64 = 0.3;

/// The shape quality of triangle `(p, a, b)`: `4·area / (√3·longest edge²)`, 1 for an
/// equilateral triangle, 0 for a flat one. (Not the collapse loop's squared quality:
/// the fit compares unsquared values, and its output bytes depend on that.)
fn quality(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let longest = (a - p)
        .length_squared()
        .max((b - a).length_squared())
        .max((p - b).length_squared());
    let twice_area = (a - p).cross(b - p).length();
    if longest > 0.0 {
        2.0 * twice_area / (3f64.sqrt() * longest)
    } else {
        0.0
    }
}
