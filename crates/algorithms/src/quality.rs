//! Triangle quality: the figures a remeshing, decimation or hole-filling run is judged
//! by, and what decides whether cotangent weights behave.
//!
//! For a triangle mesh and its positions, [`mesh_quality`] measures the corner angles,
//! the aspect ratio of every triangle, the edge lengths, the valence distribution and
//! the interior edges whose cotangent weight is negative (`cot α + cot β < 0`, the
//! edges that are not locally Delaunay, Bobenko & Springborn 2007). [`flipped_faces`]
//! counts the triangles whose orientation turned against a reference placement of the
//! same mesh, the fold-overs smoothing can cause.
//!
//! # Conventions
//! - Angles are in degrees, measured as `atan2(|u × v|, u · v)`, exact to rounding for
//!   every shape.
//! - The aspect ratio of a triangle is its longest edge over its shortest altitude,
//!   scaled so that an equilateral triangle has 1: `√3 · ℓ_max² / (4 A)`. A right
//!   isosceles triangle has √3 ≈ 1.73, one whose shortest altitude is a tenth of its
//!   longest edge about 8.7.
//! - A triangle of zero area (or one whose area overflows `f64`) is *degenerate*: it
//!   has no angles or aspect ratio, is counted apart, and its corners give a
//!   cotangent of 0 (as in [`delaunay_flip`](crate::delaunay_flip)).
//! - A vertex is *regular* with valence 6 inside and 4 on the boundary, the valences
//!   of a regular triangulation of the plane and its straight border.
//!
//! # References
//! - J. R. Shewchuk, "What is a good linear finite element?", 2002 (angles and aspect
//!   ratios as quality measures).
//! - A. I. Bobenko, B. A. Springborn, "A discrete Laplace–Beltrami operator for
//!   simplicial surfaces", Discrete & Computational Geometry 38, 2007.

use beltrami_halfedge::{DVec3, HalfedgeId, HalfedgeMesh, VertexId};

use crate::error::{InputProblem, check_finite, check_mesh};
use crate::scale::Scale;

/// The upper ends of the aspect-ratio histogram's bins: `[1, 1.5)`, `[1.5, 2)`,
/// `[2, 3)`, `[3, 5)`, `[5, 10)` and `[10, ∞)`.
pub const ASPECT_RATIO_BINS: [f64; 5] = [1.5, 2.0, 3.0, 5.0, 10.0];

/// A cotangent sum below this counts as negative: a relative tolerance (the sum is
/// dimensionless) that keeps cocircular quadrilaterals, such as the two triangles of a
/// square, at zero.
pub(crate) const NEGATIVE_COT_TOLERANCE: f64 = -1e-12;

/// What [`mesh_quality`] measured.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct MeshQuality {
    /// Triangles measured (every face).
    pub faces: usize,
    /// Triangles of zero area, left out of the angle and aspect-ratio figures.
    pub degenerate_faces: usize,
    /// Angles and aspect ratios of the non-degenerate triangles; `None` when there is
    /// none.
    pub shape: Option<ShapeStats>,
    /// Edge lengths; `None` for a mesh without edges.
    pub edge_length: Option<EdgeLengthStats>,
    /// `valence_histogram[k]`: interior vertices with k edges.
    pub valence_histogram: Vec<usize>,
    /// `boundary_valence_histogram[k]`: boundary vertices with k edges.
    pub boundary_valence_histogram: Vec<usize>,
    /// Share of the connected vertices that are regular (valence 6 inside, 4 on the
    /// boundary), 0 to 1; 0 without connected vertices.
    pub regular_share: f64,
    /// Interior edges (two triangles).
    pub interior_edges: usize,
    /// Interior edges with a negative cotangent weight, `cot α + cot β < 0`.
    pub negative_cotangent_edges: usize,
}

impl MeshQuality {
    /// Share of the interior edges with a negative cotangent weight, 0 to 1; 0 without
    /// interior edges.
    #[must_use]
    pub fn negative_cotangent_share(&self) -> f64 {
        if self.interior_edges == 0 {
            0.0
        } else {
            self.negative_cotangent_edges as f64 / self.interior_edges as f64
        }
    }
}

/// Angles and aspect ratios of the non-degenerate triangles of a mesh.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct ShapeStats {
    /// The smallest corner angle, degrees.
    pub min_angle: f64,
    /// The largest corner angle, degrees.
    pub max_angle: f64,
    /// The mean over the triangles of each one's smallest angle, degrees (60 for an
    /// equilateral mesh; the mean of all angles is always 60 and says nothing).
    pub mean_min_angle: f64,
    /// The mean aspect ratio (1 for equilateral triangles).
    pub mean_aspect_ratio: f64,
    /// The largest aspect ratio.
    pub max_aspect_ratio: f64,
    /// Triangles per aspect-ratio bin; the bins end at [`ASPECT_RATIO_BINS`], the last
    /// one is open.
    pub aspect_ratio_histogram: Vec<usize>,
}

/// Edge lengths of a mesh, in the positions' unit.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct EdgeLengthStats {
    /// The shortest edge.
    pub min: f64,
    /// The mean edge length.
    pub mean: f64,
    /// The longest edge.
    pub max: f64,
    /// Coefficient of variation: the standard deviation (over the edges) divided by the
    /// mean; 0 for a mesh of equal edges. 0 when the mean is 0.
    pub cv: f64,
}

/// Why [`mesh_quality`] or [`flipped_faces`] could not measure.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum QualityError {
    /// The positions do not match the mesh.
    #[error("{positions} positions for a mesh of {vertices} vertices")]
    PositionCount {
        /// Positions given.
        positions: usize,
        /// Vertices of the mesh.
        vertices: usize,
    },
    /// A face is not a triangle.
    #[error("face {face} has {len} vertices; the quality figures are for triangle meshes")]
    NotTriangle {
        /// The face's index.
        face: usize,
        /// Its number of vertices.
        len: usize,
    },
    /// A position is NaN or infinite.
    #[error("vertex {vertex} has a non-finite position")]
    NonFinite {
        /// The vertex's index.
        vertex: usize,
    },
}

impl From<InputProblem> for QualityError {
    fn from(problem: InputProblem) -> Self {
        match problem {
            InputProblem::PositionCount {
                positions,
                vertices,
            } => Self::PositionCount {
                positions,
                vertices,
            },
            InputProblem::NotTriangle { face, len } => Self::NotTriangle { face, len },
            InputProblem::NonFinite { vertex } => Self::NonFinite { vertex },
        }
    }
}

fn check(mesh: &HalfedgeMesh, positions: &[DVec3]) -> Result<(), QualityError> {
    check_mesh(mesh, positions)?;
    check_finite(positions)?;
    Ok(())
}

/// The cotangent of the angle at `o` between the edges to `a` and `b`,
/// `(u · v) / |u × v|`; 0 for a degenerate corner.
pub(crate) fn corner_cot(o: DVec3, a: DVec3, b: DVec3) -> f64 {
    let (u, v) = (a - o, b - o);
    let sin = u.cross(v).length();
    let c = u.dot(v) / sin;
    if sin > 0.0 && c.is_finite() { c } else { 0.0 }
}

/// The corner angles (degrees) and aspect ratio of a triangle, `None` when it is
/// degenerate.
fn triangle_shape(p: [DVec3; 3]) -> Option<([f64; 3], f64)> {
    let twice_area = (p[1] - p[0]).cross(p[2] - p[0]).length();
    if twice_area <= 0.0 || !twice_area.is_finite() {
        return None;
    }
    let angle = |i: usize| {
        let (o, a, b) = (p[i], p[(i + 1) % 3], p[(i + 2) % 3]);
        let (u, v) = (a - o, b - o);
        u.cross(v).length().atan2(u.dot(v)).to_degrees()
    };
    let longest_sq = (0..3)
        .map(|i| p[i].distance_squared(p[(i + 1) % 3]))
        .fold(0.0f64, f64::max);
    let aspect = 3f64.sqrt() * longest_sq / (2.0 * twice_area);
    Some(([angle(0), angle(1), angle(2)], aspect))
}

fn positions_of(mesh: &HalfedgeMesh, positions: &[DVec3], h: HalfedgeId) -> [DVec3; 3] {
    let a = mesh.from_vertex(h);
    let b = mesh.to_vertex(h);
    let c = mesh.to_vertex(mesh.next(h));
    [
        positions[a.index()],
        positions[b.index()],
        positions[c.index()],
    ]
}

/// Measures the quality of a triangle mesh: angles, aspect ratios, edge lengths,
/// valences and negative cotangent weights (see the [module](self) for the
/// conventions).
///
/// # Errors
/// [`QualityError::PositionCount`] when `positions` does not match the mesh,
/// [`QualityError::NotTriangle`] for a face that is not a triangle,
/// [`QualityError::NonFinite`] for a NaN or infinite position.
///
/// # Complexity
/// O(V + E + F), one thread.
///
/// # Examples
/// ```
/// use beltrami_algorithms::mesh_quality;
/// use beltrami_halfedge::primitives;
///
/// let grid = primitives::grid(4, 4); // squares cut into right isosceles triangles
/// let q = mesh_quality(&grid.mesh()?, &grid.positions)?;
/// let shape = q.shape.unwrap();
/// assert!((shape.min_angle - 45.0).abs() < 1e-12);
/// assert!((shape.max_angle - 90.0).abs() < 1e-12);
/// assert_eq!(q.negative_cotangent_edges, 0); // right angles: cocircular, weight 0
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn mesh_quality(mesh: &HalfedgeMesh, positions: &[DVec3]) -> Result<MeshQuality, QualityError> {
    check(mesh, positions)?;
    // Far from unit size, measured at a power of two times the size, where squared
    // lengths and cross products neither underflow nor overflow (`crate::scale`); only
    // the edge lengths carry the unit.
    if let Some(scale) = Scale::of_mesh(mesh, positions) {
        let mut quality = measure(mesh, &scale.mesh_positions(mesh, positions));
        if let Some(lengths) = &mut quality.edge_length {
            lengths.min = scale.length_back(lengths.min);
            lengths.mean = scale.length_back(lengths.mean);
            lengths.max = scale.length_back(lengths.max);
        }
        return Ok(quality);
    }
    Ok(measure(mesh, positions))
}

/// [`mesh_quality`] at the positions' own size (checked).
fn measure(mesh: &HalfedgeMesh, positions: &[DVec3]) -> MeshQuality {
    let (degenerate_faces, shape) = shape_stats(mesh, positions);
    let edge_length = edge_length_stats(mesh, positions);
    let (valence_histogram, boundary_valence_histogram, regular_share) = valence_stats(mesh);
    let (interior_edges, negative_cotangent_edges) = cotangent_signs(mesh, positions);
    MeshQuality {
        faces: mesh.n_faces(),
        degenerate_faces,
        shape,
        edge_length,
        valence_histogram,
        boundary_valence_histogram,
        regular_share,
        interior_edges,
        negative_cotangent_edges,
    }
}

/// The number of degenerate triangles, and the angle and aspect-ratio statistics of
/// the others (`None` when there are none).
fn shape_stats(mesh: &HalfedgeMesh, positions: &[DVec3]) -> (usize, Option<ShapeStats>) {
    let mut degenerate_faces = 0;
    let mut shape: Option<ShapeStats> = None;
    let (mut sum_min_angle, mut sum_aspect, mut measured) = (0.0, 0.0, 0usize);
    for f in mesh.faces() {
        let Some((angles, aspect)) =
            triangle_shape(positions_of(mesh, positions, mesh.face_halfedge(f)))
        else {
            degenerate_faces += 1;
            continue;
        };
        let lo = angles.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = angles.iter().copied().fold(0.0f64, f64::max);
        let bin = ASPECT_RATIO_BINS.partition_point(|&end| end <= aspect);
        let s = shape.get_or_insert_with(|| ShapeStats {
            min_angle: f64::INFINITY,
            max_angle: 0.0,
            mean_min_angle: 0.0,
            mean_aspect_ratio: 0.0,
            max_aspect_ratio: 0.0,
            aspect_ratio_histogram: vec![0; ASPECT_RATIO_BINS.len() + 1],
        });
        s.min_angle = s.min_angle.min(lo);
        s.max_angle = s.max_angle.max(hi);
        s.max_aspect_ratio = s.max_aspect_ratio.max(aspect);
        s.aspect_ratio_histogram[bin] += 1;
        sum_min_angle += lo;
        sum_aspect += aspect;
        measured += 1;
    }
    if let Some(s) = shape.as_mut() {
        s.mean_min_angle = sum_min_angle / measured as f64;
        s.mean_aspect_ratio = sum_aspect / measured as f64;
    }
    (degenerate_faces, shape)
}

/// The edge-length statistics (`None` without edges).
fn edge_length_stats(mesh: &HalfedgeMesh, positions: &[DVec3]) -> Option<EdgeLengthStats> {
    // The geometry's lengths stay finite where the plain expression overflows (a mesh
    // at 1e300); a mesh that does not form a geometry has no edge to measure.
    let geometry = beltrami_halfedge::geometry::Geometry::new(mesh, positions).ok()?;
    let lengths: Vec<f64> = mesh.edges().map(|e| geometry.edge_length(e)).collect();
    (!lengths.is_empty()).then(|| {
        let min = lengths.iter().copied().fold(f64::INFINITY, f64::min);
        let max = lengths.iter().copied().fold(0.0f64, f64::max);
        let (mean, cv) = match mean_and_cv(&lengths, 1.0) {
            // Sums of lengths near the largest number overflow: the same sums of the
            // lengths over the longest, scaled back (the spread needs no scaling back).
            (mean, cv) if !(mean.is_finite() && cv.is_finite()) && max > 0.0 => {
                let (mean, cv) = mean_and_cv(&lengths, max);
                (mean * max, cv)
            }
            plain => plain,
        };
        EdgeLengthStats { min, mean, max, cv }
    })
}

/// The mean of `lengths / unit` and the coefficient of variation (0 for a zero mean).
fn mean_and_cv(lengths: &[f64], unit: f64) -> (f64, f64) {
    let n = lengths.len() as f64;
    let mean = lengths.iter().map(|l| l / unit).sum::<f64>() / n;
    let var = lengths
        .iter()
        .map(|l| (l / unit - mean).powi(2))
        .sum::<f64>()
        / n;
    (mean, if mean > 0.0 { var.sqrt() / mean } else { 0.0 })
}

/// The valence histograms of the interior and the boundary vertices (isolated ones
/// left out), and the share of regular vertices (valence 6 inside, 4 on the boundary).
fn valence_stats(mesh: &HalfedgeMesh) -> (Vec<usize>, Vec<usize>, f64) {
    let mut valence_histogram = Vec::new();
    let mut boundary_valence_histogram = Vec::new();
    let (mut regular, mut connected) = (0usize, 0usize);
    for v in mesh.vertices() {
        if mesh.is_isolated(v) {
            continue;
        }
        let k = mesh.valence(v);
        let boundary = mesh.is_boundary_vertex(v);
        let histogram = if boundary {
            &mut boundary_valence_histogram
        } else {
            &mut valence_histogram
        };
        if histogram.len() <= k {
            histogram.resize(k + 1, 0);
        }
        histogram[k] += 1;
        connected += 1;
        regular += usize::from(k == if boundary { 4 } else { 6 });
    }
    let regular_share = if connected == 0 {
        0.0
    } else {
        regular as f64 / connected as f64
    };
    (valence_histogram, boundary_valence_histogram, regular_share)
}

/// The number of interior edges, and of those whose cotangent weight is negative.
fn cotangent_signs(mesh: &HalfedgeMesh, positions: &[DVec3]) -> (usize, usize) {
    let (mut interior_edges, mut negative_cotangent_edges) = (0, 0);
    for e in mesh.edges() {
        if mesh.is_boundary_edge(e) {
            continue;
        }
        interior_edges += 1;
        let sum: f64 = e
            .halfedges()
            .into_iter()
            .map(|h| {
                let [a, b, o] = positions_of(mesh, positions, h);
                corner_cot(o, a, b)
            })
            .sum();
        negative_cotangent_edges += usize::from(sum < NEGATIVE_COT_TOLERANCE);
    }
    (interior_edges, negative_cotangent_edges)
}

/// Counts the triangles whose orientation turned against a reference placement of the
/// same mesh: those whose normal at `positions` points away (negative dot product) from
/// their normal at `reference` — the fold-overs a smoothing run can cause. A triangle
/// degenerate in either placement is not counted. The comparison is in one fixed frame,
/// made for displacements that are small against the surface's curvature (smoothing,
/// remeshing's relaxation): a rigid rotation by less than 90° flips nothing, a larger
/// one counts the faces it turns by more than 90°.
///
/// # Errors
/// [`QualityError::PositionCount`] when either position list does not match the mesh,
/// [`QualityError::NotTriangle`], [`QualityError::NonFinite`].
///
/// # Examples
/// ```
/// use beltrami_algorithms::flipped_faces;
/// use beltrami_halfedge::primitives;
///
/// let grid = primitives::grid(3, 3);
/// let mesh = grid.mesh()?;
/// let mut moved = grid.positions.clone();
/// assert_eq!(flipped_faces(&mesh, &moved, &grid.positions)?, 0);
/// moved[5].x += 3.0; // drag an interior vertex across its neighbours
/// assert!(flipped_faces(&mesh, &moved, &grid.positions)? > 0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn flipped_faces<'a>(
    mesh: &HalfedgeMesh,
    positions: &'a [DVec3],
    reference: &'a [DVec3],
) -> Result<usize, QualityError> {
    check(mesh, positions)?;
    check(mesh, reference)?;
    // Far from unit size, both at a power of two times their size, where the normals'
    // products neither underflow nor overflow (`crate::scale`).
    let scaled;
    let in_faces = |x: &'a [DVec3]| {
        x.iter()
            .enumerate()
            .filter(|&(i, _)| !mesh.is_isolated(VertexId::new(i as u32)))
            .map(|(_, p)| p)
    };
    let (positions, reference) = match Scale::of(in_faces(positions).chain(in_faces(reference))) {
        Some(scale) => {
            scaled = (scale.positions(positions), scale.positions(reference));
            (&scaled.0[..], &scaled.1[..])
        }
        None => (positions, reference),
    };
    let normal = |p: [DVec3; 3]| (p[1] - p[0]).cross(p[2] - p[0]);
    Ok(mesh
        .faces()
        .filter(|&f| {
            let h = mesh.face_halfedge(f);
            let now = normal(positions_of(mesh, positions, h));
            let before = normal(positions_of(mesh, reference, h));
            now.dot(before) < 0.0
        })
        .count())
}
