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

use beltrami_halfedge::geometry::CompensatedSum as Sum;

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
    let samples: Vec<Sample> = input
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
        .collect();
    let centroids: Vec<DVec3> = samples.iter().map(|s| s.centroid).collect();
    let triangles: Vec<[VertexId; 3]> = out.faces().map(|f| out.triangle_vertices(f)).collect();
    let fixed: Vec<bool> = out.vertices().map(|v| out.is_boundary_vertex(v)).collect();
    let total_area: f64 = samples.iter().map(|s| s.area).sum();
    let mut fit = Fit {
        rounds,
        ..Fit::default()
    };
    if samples.is_empty() || total_area.is_nan() || total_area <= 0.0 {
        fit.rounds = 0;
        return Ok(fit);
    }
    for round in 0..rounds {
        let index = SurfaceIndex::new(out, x)?;
        let closest = index.closest_points(&centroids)?;
        // Per sample: the output triangle and the barycentric coordinates of the match.
        let matched: Vec<([VertexId; 3], [f64; 3])> = closest
            .iter()
            .map(|cp| {
                let t = triangles[cp.face.index()];
                (t, barycentric(cp.point, t.map(|v| x[v.index()])))
            })
            .collect();
        // Each vertex's samples, as (sample, barycentric weight), in sample order.
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
        let mut residual: Vec<f64> = matched
            .iter()
            .zip(&samples)
            .map(|((t, b), s)| {
                let q = x[t[0].index()] * b[0] + x[t[1].index()] * b[1] + x[t[2].index()] * b[2];
                s.normal.dot(q - s.centroid)
            })
            .collect();
        let energy = |residual: &[f64]| {
            let mut sum = Sum::default();
            for (r, s) in residual.iter().zip(&samples) {
                sum.add(s.area * r * r);
            }
            (sum.value() / total_area).sqrt()
        };
        if round == 0 {
            fit.rms_before = energy(&residual);
        }
        for _ in 0..SWEEPS {
            for v in out.vertices() {
                if fixed[v.index()] {
                    continue;
                }
                let own = &entries[offsets[v.index()]..offsets[v.index() + 1]];
                let mut h = DMat3::ZERO;
                let mut g = DVec3::ZERO;
                for &(i, b) in own {
                    let s = &samples[i as usize];
                    let w = s.area * b;
                    h += outer(s.normal * (w * b), s.normal);
                    g += s.normal * (w * residual[i as usize]);
                }
                let trace = h.x_axis.x + h.y_axis.y + h.z_axis.z;
                if trace.is_nan() || trace <= 0.0 {
                    continue;
                }
                h += DMat3::from_diagonal(DVec3::splat(PULL * trace));
                let det = h.determinant();
                if det.is_nan() || det == 0.0 {
                    continue;
                }
                let step = -(h.inverse() * g);
                if !step.is_finite() || !allowed(out, x, v, step, floor) {
                    continue;
                }
                x[v.index()] += step;
                for &(i, b) in own {
                    residual[i as usize] += b * samples[i as usize].normal.dot(step);
                }
            }
        }
        fit.rms_after = energy(&residual);
    }
    Ok(fit)
}

/// `a bᵀ`.
fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

/// The barycentric coordinates of `p` (a point of the triangle, up to rounding) in
/// triangle `t`, clamped to the triangle; the centroid's for a degenerate triangle.
fn barycentric(p: DVec3, [a, b, c]: [DVec3; 3]) -> [f64; 3] {
    let (e1, e2, d) = (b - a, c - a, p - a);
    let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let (d1, d2) = (d.dot(e1), d.dot(e2));
    let den = d11 * d22 - d12 * d12;
    if den.is_nan() || den <= 0.0 {
        return [1.0 / 3.0; 3];
    }
    let v = ((d22 * d1 - d12 * d2) / den).clamp(0.0, 1.0);
    let w = ((d11 * d2 - d12 * d1) / den).clamp(0.0, 1.0);
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
/// equilateral triangle, 0 for a flat one.
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
