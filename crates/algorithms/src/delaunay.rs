//! Intrinsic-free Delaunay flipping: Lawson's edge flips on the mesh itself, until every
//! flippable interior edge has a non-negative cotangent weight.
//!
//! An interior edge with opposite angles α and β is *locally Delaunay* when
//! α + β ≤ π, i.e. `cot α + cot β ≥ 0` — exactly when its cotangent weight is not
//! negative. Flipping a non-Delaunay edge of a planar mesh (Lawson 1977) raises the
//! smallest angle and ends, after finitely many flips, at the Delaunay triangulation of
//! the same vertices, where every cotangent weight is non-negative: the negative-weight
//! problem of the cotangent Laplacian solved at the mesh instead of by clamping the
//! weight. On a curved surface a flip replaces the two triangles of a skew quadrilateral
//! by the other two, which moves the surface by up to the quadrilateral's fold; the
//! dihedral bound keeps that below a chosen angle, and the report measures it.
//!
//! # References
//! - C. L. Lawson, "Software for C¹ surface interpolation", Mathematical Software III,
//!   1977.
//! - A. I. Bobenko, B. A. Springborn, "A discrete Laplace–Beltrami operator for simplicial
//!   surfaces", Discrete & Computational Geometry 38, 2007 (why a Delaunay mesh gives
//!   non-negative cotangent weights).

use std::collections::VecDeque;

use beltrami_halfedge::{DVec3, EdgeId, EditMesh, HalfedgeId, HalfedgeMesh};
use beltrami_metrics::distance::SurfaceIndex;

use crate::error::{DelaunayError, check_finite, check_mesh};
use crate::quality::{NEGATIVE_COT_TOLERANCE, corner_cot};
use crate::scale::at_unit_size;

/// The settings of [`delaunay_flip`].
///
/// # Examples
/// ```
/// use beltrami_algorithms::DelaunayOptions;
/// let options = DelaunayOptions::default().max_dihedral(1f64.to_radians());
/// assert_eq!(options.max_dihedral, Some(1f64.to_radians()));
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct DelaunayOptions {
    /// Leave an edge alone when the angle between the normals of its two triangles
    /// (radians, 0 for a flat pair) exceeds this: a feature edge, or a flip that would
    /// change a curved surface by more than the caller accepts. `None`: every
    /// flippable non-Delaunay edge is flipped.
    pub max_dihedral: Option<f64>,
    /// The largest number of flips; `None` for ten per edge, which a planar mesh never
    /// needs (Lawson's algorithm terminates there) and which stops a cycle on a curved
    /// surface.
    pub max_flips: Option<usize>,
}

impl DelaunayOptions {
    /// Sets the largest dihedral angle of a flipped edge, in radians.
    #[must_use]
    pub fn max_dihedral(mut self, radians: f64) -> Self {
        self.max_dihedral = Some(radians);
        self
    }

    /// Sets the largest number of flips.
    #[must_use]
    pub fn max_flips(mut self, flips: usize) -> Self {
        self.max_flips = Some(flips);
        self
    }
}

/// What [`delaunay_flip`] did.
#[derive(Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct DelaunayReport {
    /// Flips done.
    pub flips: usize,
    /// Interior edges with a negative cotangent weight before.
    pub negative_before: usize,
    /// Interior edges with a negative cotangent weight after.
    pub negative_after: usize,
    /// Of those left negative, how many the dihedral bound kept.
    pub kept_by_dihedral: usize,
    /// Of those left negative, how many could not be flipped: the flipped edge would
    /// already exist, or a triangle is degenerate.
    pub kept_by_topology: usize,
    /// Of those left negative, how many could have been flipped but were left when the
    /// flip limit stopped the run.
    pub kept_by_flip_limit: usize,
    /// Whether the flip limit stopped the run.
    pub hit_flip_limit: bool,
    /// The distance between the input and output surfaces (in the positions' unit),
    /// measured at the midpoints of the removed and the added edges, each against the
    /// other surface: the Hausdorff distance where the flipped edges are apart (the
    /// farthest point of one triangulation of a skew quadrilateral from the other is
    /// the midpoint of its diagonal), a lower bound of it otherwise. 0 without flips.
    pub max_deviation: f64,
}

/// The cotangent of the angle opposite `h` in its triangle; 0 on the boundary or for a
/// degenerate corner.
fn opposite_cot(mesh: &EditMesh, h: HalfedgeId) -> f64 {
    mesh.opposite_vertex(h).map_or(0.0, |o| {
        corner_cot(
            mesh.position(o),
            mesh.position(mesh.from_vertex(h)),
            mesh.position(mesh.to_vertex(h)),
        )
    })
}

/// `cot α + cot β` of an interior edge (twice its cotangent weight).
fn cot_sum(mesh: &EditMesh, e: EdgeId) -> f64 {
    let [h, t] = e.halfedges();
    opposite_cot(mesh, h) + opposite_cot(mesh, t)
}

/// Whether `e` is interior and not locally Delaunay, by the rule of
/// [`mesh_quality`](crate::mesh_quality). The tolerance keeps cocircular
/// quadrilaterals (a regular grid) from flipping back and forth.
fn is_negative(mesh: &EditMesh, e: EdgeId) -> bool {
    !mesh.is_boundary_edge(e) && cot_sum(mesh, e) < NEGATIVE_COT_TOLERANCE
}

/// The angle between the normals of the two triangles of interior edge `e`, radians.
fn dihedral(mesh: &EditMesh, e: EdgeId) -> f64 {
    let normal = |h: HalfedgeId| {
        let a = mesh.position(mesh.from_vertex(h));
        let b = mesh.position(mesh.to_vertex(h));
        let c = mesh.opposite_vertex(h).map_or(a, |o| mesh.position(o));
        (b - a).cross(c - a)
    };
    let [h, t] = e.halfedges();
    let (n, m) = (normal(h), normal(t));
    let angle = n.angle_between(m);
    if angle.is_finite() { angle } else { 0.0 }
}

/// Flips edges of the mesh, keeping its vertices, until every interior edge is locally
/// Delaunay (`cot α + cot β ≥ 0`, its cotangent weight not negative) or is left alone
/// by the options; returns the new mesh, its positions (the input's, unchanged) and a
/// report.
///
/// Lawson's algorithm: every interior edge is checked once, and the four edges around
/// each flip are checked again; when none is left to check, the edges still to flip
/// (refused before while their flipped edge existed) are checked again, until none is
/// left or [`DelaunayOptions::max_flips`] stops the run. Boundary edges are never
/// flipped, and neither is an edge whose flipped edge already exists. With [`DelaunayOptions::max_dihedral`],
/// edges whose two triangles meet at a larger angle stay (features, curved regions).
/// The vertex numbering is the input's; faces are renumbered (garbage collection after
/// the flips keeps their order).
///
/// # Errors
/// [`DelaunayError::PositionCount`] when `positions` does not match the mesh;
/// [`DelaunayError::NotTriangle`] when a face is not a triangle;
/// [`DelaunayError::NonFinite`] for a non-finite position;
/// [`DelaunayError::Options`] for a negative or NaN dihedral bound.
///
/// # Examples
/// ```
/// use beltrami_algorithms::{delaunay_flip, DelaunayOptions};
/// use beltrami_halfedge::{DVec3, primitives};
///
/// // A grid with its vertices pushed about: some edges are not Delaunay.
/// let mut grid = primitives::grid(8, 8);
/// for (i, p) in grid.positions.iter_mut().enumerate() {
///     *p += DVec3::new(0.4 * ((i * 7 % 5) as f64 / 5.0 - 0.4), 0.3 * ((i * 3 % 7) as f64 / 7.0 - 0.4), 0.0);
/// }
/// let mesh = grid.mesh()?;
/// let (flipped, positions, report) =
///     delaunay_flip(&mesh, &grid.positions, DelaunayOptions::default())?;
/// assert!(report.negative_before > 0 && report.negative_after == 0);
/// assert!(report.max_deviation < 1e-12); // a plane stays a plane
/// assert_eq!(flipped.n_faces(), mesh.n_faces());
/// assert_eq!(positions, grid.positions);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn delaunay_flip(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    options: DelaunayOptions,
) -> Result<(HalfedgeMesh, Vec<DVec3>, DelaunayReport), DelaunayError> {
    check_mesh(mesh, positions)?;
    check_finite(positions)?;
    if let Some(d) = options.max_dihedral
        && (d.is_nan() || d < 0.0)
    {
        return Err(DelaunayError::Options {
            reason: format!(
                "the largest dihedral angle must be >= 0, got {}",
                beltrami_halfedge::exact_number(d)
            ),
        });
    }
    // Far from unit size, at a power of two times it (`crate::scale`): the cotangents'
    // products would leave the range of numbers and hide the negative weights.
    let (out, _, report) = at_unit_size(
        mesh,
        positions,
        |x, _| flip_at_scale(mesh, x, options),
        |mut report, scale| {
            report.max_deviation = scale.length_back(report.max_deviation);
            report
        },
    )?;
    // A flip moves no vertex: the input's positions, with their bits (a run far from
    // unit size scales them there and back, which rounds a coordinate that becomes
    // subnormal on the way).
    Ok((out, positions.to_vec(), report))
}

/// [`delaunay_flip`] at the positions' own size (checked).
fn flip_at_scale(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    options: DelaunayOptions,
) -> Result<(HalfedgeMesh, Vec<DVec3>, DelaunayReport), DelaunayError> {
    let mut edit = EditMesh::from_mesh(mesh, positions)?;
    let negative_before = edit.edges().filter(|&e| is_negative(&edit, e)).count();
    let limit = options.max_flips.unwrap_or(10 * edit.n_edges());
    let allowed =
        |m: &EditMesh, e: EdgeId| options.max_dihedral.is_none_or(|d| dihedral(m, e) <= d);

    let mut queue: VecDeque<EdgeId> = edit.edges().collect();
    let mut flipped = vec![false; edit.edge_capacity()];
    let mut report = DelaunayReport {
        negative_before,
        ..DelaunayReport::default()
    };
    // An edge refused because its flipped diagonal existed may become flippable when
    // that diagonal is flipped away elsewhere, without a flip next to it: once the queue
    // is empty, the edges still to flip are queued again, until none is left.
    loop {
        while let Some(e) = queue.pop_front() {
            if !is_negative(&edit, e) || !allowed(&edit, e) || !edit.is_flip_ok(e) {
                continue;
            }
            if report.flips == limit {
                report.hit_flip_limit = true;
                break;
            }
            edit.flip_edge(e)?;
            report.flips += 1;
            flipped[e.index()] = true;
            for h in e.halfedges() {
                queue.push_back(edit.next(h).edge());
                queue.push_back(edit.prev(h).edge());
            }
        }
        if report.hit_flip_limit {
            break;
        }
        queue.extend(
            edit.edges()
                .filter(|&e| is_negative(&edit, e) && allowed(&edit, e) && edit.is_flip_ok(e)),
        );
        if queue.is_empty() {
            break;
        }
    }
    for e in edit.edges() {
        if is_negative(&edit, e) {
            report.negative_after += 1;
            if !allowed(&edit, e) {
                report.kept_by_dihedral += 1;
            } else if !edit.is_flip_ok(e) {
                report.kept_by_topology += 1;
            } else {
                // Flippable and allowed: only the limit leaves such an edge.
                debug_assert!(report.hit_flip_limit);
                report.kept_by_flip_limit += 1;
            }
        }
    }
    edit.garbage_collection();
    let (out, out_positions) = edit.into_mesh()?;
    report.max_deviation = deviation(mesh, positions, &out, &flipped)?;
    Ok((out, out_positions, report))
}

/// The largest distance of a flipped region between the two surfaces: the midpoints of
/// the edges the input has and the output lacks, against the output, and the other way
/// round.
fn deviation(
    input: &HalfedgeMesh,
    positions: &[DVec3],
    output: &HalfedgeMesh,
    flipped: &[bool],
) -> Result<f64, DelaunayError> {
    if !flipped.contains(&true) {
        return Ok(0.0);
    }
    let midpoints = |mesh: &HalfedgeMesh, other: &HalfedgeMesh| -> Vec<DVec3> {
        mesh.edges()
            .filter_map(|e| {
                let h = e.halfedge(0);
                let (a, b) = (mesh.from_vertex(h), mesh.to_vertex(h));
                other
                    .find_halfedge(a, b)
                    .is_none()
                    .then(|| (positions[a.index()] + positions[b.index()]) * 0.5)
            })
            .collect()
    };
    let removed = midpoints(input, output);
    let added = midpoints(output, input);
    let mut max: f64 = 0.0;
    for (points, surface) in [(&removed, output), (&added, input)] {
        if points.is_empty() {
            continue;
        }
        let index = SurfaceIndex::new(surface, positions)?;
        for d in index.distances(points)? {
            max = max.max(d);
        }
    }
    Ok(max)
}
