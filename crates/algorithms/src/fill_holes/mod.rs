//! Hole filling after Liepa: each chosen boundary loop is closed by a minimum-weight
//! triangulation, refined to the density of its rim and faired so that it continues the
//! surrounding surface smoothly.
//!
//! For each loop, in three steps (as pmp-library's `fill_hole`):
//!
//! 1. **Triangulation.** Dynamic programming over the sub-polygons `[i, k]` of the loop
//!    (O(n³) time, O(n²) memory for n loop edges) finds the triangulation that minimises
//!    the weight `(largest dihedral angle, area)`, compared lexicographically: first the
//!    largest fold between neighbouring triangles (the patch's own and those across the
//!    rim), measured as `1 − cos θ`, then the total area. A triangle that would add an
//!    edge already in the mesh (two loop vertices joined elsewhere) is refused, since
//!    that edge would get a third face.
//! 2. **Refinement** (optional, on by default). With `ℓ` the mean rim edge length, patch
//!    edges longer than `4/3 ℓ` are split at their midpoints, new edges shorter than
//!    `4/5 ℓ` collapsed, non-Delaunay patch edges flipped and new vertices relaxed
//!    towards the centroid of their neighbours in their tangent plane, in up to ten
//!    rounds — a simplified version of pmp-library's isotropic remeshing of the patch
//!    (which also uses valence-driven flips). Only the patch's own edges and new vertices
//!    change; the rim and the rest of the mesh keep their ids and bits.
//! 3. **Fairing** (optional, on by default). The new vertices solve `Δᵏ x = 0` (k = 2:
//!    thin plate, the default as pmp-library's `minimize_curvature`; k = 1: membrane)
//!    with every other vertex fixed, so the patch meets the surrounding surface with a
//!    continuous tangent plane (k = 2) or position (k = 1). `Δ` uses cotangent weights
//!    and barycentric vertex areas (or uniform weights and unit masses); the sparse
//!    symmetric positive definite system is solved by a sparse Cholesky factorisation.
//!    If it fails (degenerate triangles), the uniform membrane (k = 1), whose system is
//!    always positive definite, is used instead and the report says so.
//!
//! **Which loops.** A scan of an open part has one outer boundary that must not be
//! closed. By default every loop is filled *except the one with the largest perimeter
//! in each connected component* (the outer boundary of an open surface; on a closed
//! surface with holes, the largest hole), so that a mesh of several open patches keeps
//! every patch's outer boundary; [`FillOptions::fill_all`] fills those too, for a closed
//! part. Loops of more
//! than [`FillOptions::max_loop_edges`] edges are skipped, as are loops through a vertex
//! with two boundary gaps and loops every triangulation of which would duplicate an
//! edge or a face (the rim of a lone triangle); the report lists each skipped loop and
//! why.
//!
//! **Numbering.** The input's vertices keep their ids, order and positions bit for bit;
//! the new vertices follow them, hole by hole. The input's faces keep their ids and
//! order; the new faces follow.
//!
//! # References
//! - P. Liepa, "Filling holes in meshes", Eurographics Symposium on Geometry Processing,
//!   2003.
//! - M. Botsch, L. Kobbelt, M. Pauly, P. Alliez, B. Lévy, *Polygon Mesh Processing*,
//!   AK Peters 2010, §6.5 (isotropic remeshing) and §4.3 (fairing).
//! - pmp-library, `src/pmp/algorithms/hole_filling.cpp` and `fairing.cpp`.

mod fair;
mod refine;
mod triangulate;

use std::ops::ControlFlow;

use beltrami_halfedge::{DVec3, EditError, EditMesh, HalfedgeId, HalfedgeMesh, TopologyError};

use crate::error::{algorithm_error, check_finite, check_mesh};
use crate::scale::{Scale, at_unit_size};

use fair::FairFailure;
use refine::Patch;
use triangulate::TriangulateError;

/// The Laplacian used by the fairing step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum FairWeights {
    /// Weight 1 per edge, mass 1 per vertex: the umbrella operator, which also evens out
    /// the vertex spacing.
    Uniform,
    /// Cotangent weights `(cot α + cot β)/2` and a third of the incident triangles' area
    /// as mass: the discrete Laplace–Beltrami operator, independent of the
    /// triangulation's spacing (the default, as pmp-library).
    #[default]
    Cotangent,
}

/// The settings of [`fill_holes`] and [`fill_hole`].
///
/// # Examples
/// ```
/// use beltrami_algorithms::FillOptions;
/// let options = FillOptions::default().fill_all(true).fair_order(1);
/// assert!(options.fill_all && options.refine && options.fair);
/// assert_eq!((options.max_loop_edges, options.fair_order), (500, 1));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct FillOptions {
    /// Loops with more edges are skipped (at least 3; default 500). The triangulation
    /// costs O(n³) time and O(n²) memory: 500 edges take about 2·10⁷ triangle weights
    /// and 4 MB, well under a second.
    pub max_loop_edges: usize,
    /// Fill every loop, the one with the largest perimeter in each connected component
    /// included (a closed part). Default `false`: that loop is taken for the outer
    /// boundary of an open surface and left open, one per component.
    pub fill_all: bool,
    /// Refine the patch to the rim's edge length (default `true`). Without refinement no
    /// vertex is added, so there is nothing to fair either.
    pub refine: bool,
    /// Fair the new vertices (default `true`); `false` leaves the refined patch near the
    /// initial triangulation, flat between the rim vertices.
    pub fair: bool,
    /// The order k of the fairing, `Δᵏ x = 0`: 1 (membrane, continuous position) or 2
    /// (thin plate, continuous tangent plane; default).
    pub fair_order: u8,
    /// The Laplacian of the fairing (default cotangent).
    pub fair_weights: FairWeights,
}

impl Default for FillOptions {
    fn default() -> Self {
        Self {
            max_loop_edges: 500,
            fill_all: false,
            refine: true,
            fair: true,
            fair_order: 2,
            fair_weights: FairWeights::Cotangent,
        }
    }
}

impl FillOptions {
    /// Sets the largest number of edges of a loop that is filled.
    #[must_use]
    pub fn max_loop_edges(mut self, edges: usize) -> Self {
        self.max_loop_edges = edges;
        self
    }

    /// Fills each component's loop of the largest perimeter too (a closed part).
    #[must_use]
    pub fn fill_all(mut self, yes: bool) -> Self {
        self.fill_all = yes;
        self
    }

    /// Turns the refinement on or off.
    #[must_use]
    pub fn refine(mut self, yes: bool) -> Self {
        self.refine = yes;
        self
    }

    /// Turns the fairing on or off.
    #[must_use]
    pub fn fair(mut self, yes: bool) -> Self {
        self.fair = yes;
        self
    }

    /// Sets the fairing order (1 or 2).
    #[must_use]
    pub fn fair_order(mut self, k: u8) -> Self {
        self.fair_order = k;
        self
    }

    /// Sets the fairing Laplacian.
    #[must_use]
    pub fn fair_weights(mut self, weights: FairWeights) -> Self {
        self.fair_weights = weights;
        self
    }

    fn validate(&self) -> Result<(), FillError> {
        if self.max_loop_edges < 3 {
            return Err(FillError::Options {
                reason: format!(
                    "the largest loop to fill must have at least 3 edges, got {}",
                    self.max_loop_edges
                ),
            });
        }
        if !(1..=2).contains(&self.fair_order) {
            return Err(FillError::Options {
                reason: format!("the fairing order must be 1 or 2, got {}", self.fair_order),
            });
        }
        Ok(())
    }
}

/// One filled hole.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct FilledHole {
    /// The boundary halfedge the loop was traced from: for [`fill_holes`] the loop's
    /// lowest halfedge id in the input mesh, for [`fill_hole`] the one given.
    pub halfedge: HalfedgeId,
    /// The number of edges (and vertices) of the loop.
    pub boundary_edges: usize,
    /// The loop's length, in the positions' unit.
    pub perimeter: f64,
    /// Faces added: `boundary_edges − 2` by the triangulation, two more per new vertex.
    pub faces_added: usize,
    /// Vertices added by the refinement.
    pub vertices_added: usize,
    /// The area of the patch after fairing, in the unit squared.
    pub area: f64,
    /// The fairing order used: the one asked for, 1 when the asked system could not be
    /// solved and the uniform membrane was used instead, `None` when nothing was faired
    /// (fairing off, or no new vertex).
    pub faired_order: Option<u8>,
    /// Whether the fairing fell back to the uniform membrane.
    pub fair_fallback: bool,
}

/// Why a loop was left open.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum SkipReason {
    /// The loop of the largest perimeter in its connected component, taken for the
    /// outer boundary of an open surface (see [`FillOptions::fill_all`]).
    OuterBoundary,
    /// More edges than [`FillOptions::max_loop_edges`].
    TooLarge,
    /// A vertex of the loop appears twice in it or has a second boundary gap (another
    /// loop through it): filling would leave a non-manifold vertex.
    NonManifoldVertex,
    /// Every triangulation of the loop would duplicate an edge already in the mesh, or
    /// (a loop of three edges around one face, such as a lone triangle's) a face.
    NoManifoldTriangulation,
}

impl SkipReason {
    /// The reason in a few words, for reports.
    #[must_use]
    pub fn describe(self) -> &'static str {
        match self {
            Self::OuterBoundary => "the outer boundary (its component's largest perimeter)",
            Self::TooLarge => "more edges than the limit",
            Self::NonManifoldVertex => "a vertex on two boundary loops",
            Self::NoManifoldTriangulation => "no triangulation without a duplicate edge or face",
        }
    }
}

/// One loop left open.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct SkippedHole {
    /// The loop's first boundary halfedge (its lowest id in the input mesh).
    pub halfedge: HalfedgeId,
    /// The number of edges of the loop.
    pub boundary_edges: usize,
    /// The loop's length, in the positions' unit.
    pub perimeter: f64,
    /// Why it was left open.
    pub reason: SkipReason,
}

/// What [`fill_holes`] did: every boundary loop of the input is in `filled` or
/// `skipped`, in the order of their lowest halfedge id.
#[derive(Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct FillReport {
    /// The number of boundary loops of the input.
    pub loops: usize,
    /// The holes filled.
    pub filled: Vec<FilledHole>,
    /// The loops left open, with the reason.
    pub skipped: Vec<SkippedHole>,
    /// Faces added in all.
    pub faces_added: usize,
    /// Vertices added in all.
    pub vertices_added: usize,
}

algorithm_error! {
    /// Why hole filling could not run. Every variant names the offending element or value.
    #[derive(Debug, Clone, PartialEq, thiserror::Error)]
    #[non_exhaustive]
    pub enum FillError for "hole filling" {
        /// [`fill_hole`] was given a halfedge that is not a live boundary halfedge.
        #[error("{halfedge} is not a boundary halfedge")]
        NotBoundary {
            /// The halfedge.
            halfedge: HalfedgeId,
        },
        /// [`fill_hole`] was given a loop it leaves open; the mesh is unchanged.
        #[error("the loop of {boundary_edges} edges at {halfedge} was not filled: {}", .reason.describe())]
        Skipped {
            /// The halfedge given.
            halfedge: HalfedgeId,
            /// The number of edges of its loop.
            boundary_edges: usize,
            /// Why.
            reason: SkipReason,
        },
        /// An edit the checks allowed was refused: a defect of this crate, reported rather
        /// than panicking.
        #[error("editing the patch failed: {0}")]
        Edit(#[from] EditError),
        /// The input or the result did not convert between the frozen and the editable
        /// mesh.
        #[error("{0}")]
        Topology(#[from] TopologyError),
        /// The progress closure of [`fill_holes_with_progress`] asked to stop.
        #[error("hole filling was stopped after {done} of {total} boundary loops")]
        Stopped {
            /// The loops done (filled or skipped).
            done: usize,
            /// The boundary loops of the input.
            total: usize,
        },
    }
}

impl FillReport {
    /// The report of a run at `scale`, in the caller's unit (perimeters and areas). The
    /// patterns name every field (`_` for those without a unit), so that a new one is
    /// not left unscaled.
    fn scaled_back(mut self, scale: &Scale) -> Self {
        let Self {
            loops: _,
            filled,
            skipped,
            faces_added: _,
            vertices_added: _,
        } = &mut self;
        for hole in filled {
            let FilledHole {
                halfedge: _,
                boundary_edges: _,
                perimeter,
                faces_added: _,
                vertices_added: _,
                area,
                faired_order: _,
                fair_fallback: _,
            } = hole;
            *perimeter = scale.length_back(*perimeter);
            *area = scale.area_back(*area);
        }
        for hole in skipped {
            let SkippedHole {
                halfedge: _,
                boundary_edges: _,
                perimeter,
                reason: _,
            } = hole;
            *perimeter = scale.length_back(*perimeter);
        }
        self
    }
}

/// The length of a boundary loop.
fn perimeter(mesh: &EditMesh, hole: &[HalfedgeId]) -> f64 {
    hole.iter()
        .map(|&h| {
            mesh.position(mesh.from_vertex(h))
                .distance(mesh.position(mesh.to_vertex(h)))
        })
        .sum()
}

/// Fills the hole bounded by the boundary halfedge `boundary` in place: minimum-weight
/// triangulation, then (as `options` say) refinement and fairing; see [`fill_holes`]
/// for the steps. New vertices, edges and faces are
/// appended; no existing element is moved or renumbered (call
/// [`EditMesh::garbage_collection`] afterwards: refinement may leave deleted slots of
/// its own new elements). [`FillOptions::fill_all`] is not used here.
///
/// Works on any mesh whose faces next to the loop are triangles; the cotangent fairing
/// ignores non-triangular faces.
///
/// # Errors
/// [`FillError::Options`] for bad options; [`FillError::NotBoundary`] when `boundary`
/// is not a live boundary halfedge; [`FillError::Skipped`] (mesh unchanged) when the
/// loop has more than [`FillOptions::max_loop_edges`] edges, passes a vertex twice or
/// through one with two boundary gaps, or cannot be triangulated without duplicating an
/// edge; [`FillError::Edit`] on a defect.
///
/// # Complexity
/// O(n³) for a loop of n edges, plus O(m) per refinement pass and a sparse Cholesky
/// factorisation for a patch of m new vertices.
///
/// # Examples
/// ```
/// use beltrami_algorithms::{fill_hole, FillOptions};
/// use beltrami_halfedge::{EditMesh, VertexId, primitives};
///
/// let ico = primitives::icosphere(2);
/// let mut mesh = EditMesh::from_mesh(&ico.mesh()?, &ico.positions)?;
/// // Cut the five faces around vertex 0 (which goes with them).
/// let fan: Vec<_> = mesh.faces_around_vertex(VertexId::new(0)).collect();
/// for f in fan {
///     mesh.delete_face(f)?;
/// }
/// let h = mesh.halfedges().find(|&h| mesh.is_boundary_halfedge(h)).unwrap();
/// let hole = fill_hole(&mut mesh, h, &FillOptions::default())?;
/// assert_eq!(hole.boundary_edges, 5);
/// assert!(mesh.is_closed());
/// mesh.garbage_collection();
/// mesh.check_integrity()?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn fill_hole(
    mesh: &mut EditMesh,
    boundary: HalfedgeId,
    options: &FillOptions,
) -> Result<FilledHole, FillError> {
    options.validate()?;
    if !mesh.is_live_halfedge(boundary) || !mesh.is_boundary_halfedge(boundary) {
        return Err(FillError::NotBoundary { halfedge: boundary });
    }
    let hole = triangulate::trace_loop(mesh, boundary);
    let skipped = |reason| FillError::Skipped {
        halfedge: boundary,
        boundary_edges: hole.len(),
        reason,
    };
    if hole.len() > options.max_loop_edges {
        return Err(skipped(SkipReason::TooLarge));
    }
    fill_loop(mesh, &hole, options).map_err(|e| match e {
        LoopError::Skip(reason) => skipped(reason),
        LoopError::Edit(e) => FillError::Edit(e),
    })
}

/// Why one loop was not filled.
enum LoopError {
    Skip(SkipReason),
    Edit(EditError),
}

impl From<EditError> for LoopError {
    fn from(e: EditError) -> Self {
        Self::Edit(e)
    }
}

/// Fills the loop `hole` (boundary halfedges in `next` order).
fn fill_loop(
    mesh: &mut EditMesh,
    hole: &[HalfedgeId],
    options: &FillOptions,
) -> Result<FilledHole, LoopError> {
    let triangles = triangulate::plan(mesh, hole).map_err(|e| {
        LoopError::Skip(match e {
            TriangulateError::NonManifold(_) => SkipReason::NonManifoldVertex,
            TriangulateError::NoTriangulation => SkipReason::NoManifoldTriangulation,
        })
    })?;
    let perimeter = perimeter(mesh, hole);
    let patch = Patch {
        first_vertex: mesh.vertex_capacity(),
        first_edge: mesh.edge_capacity(),
        first_face: mesh.face_capacity(),
    };
    for t in &triangles {
        mesh.add_face(t)?;
    }
    if options.refine {
        let target = perimeter / hole.len() as f64;
        refine::refine(mesh, patch, target)?;
    }
    let free = patch.vertices(mesh);
    let mut faired_order = None;
    let mut fair_fallback = false;
    if options.fair && !free.is_empty() {
        match fair::fair(mesh, &free, options.fair_order, options.fair_weights) {
            Ok(()) => faired_order = Some(options.fair_order),
            Err(FairFailure::Mass | FairFailure::Solver) => {
                fair_fallback = true;
                if fair::fair(mesh, &free, 1, FairWeights::Uniform).is_ok() {
                    faired_order = Some(1);
                }
            }
        }
    }
    let mut faces_added = 0;
    let mut area = 0.0;
    for f in
        (patch.first_face..mesh.face_capacity()).map(|i| beltrami_halfedge::FaceId::new(i as u32))
    {
        if !mesh.is_live_face(f) {
            continue;
        }
        faces_added += 1;
        let h = mesh.face_halfedge(f);
        let a = mesh.position(mesh.from_vertex(h));
        let b = mesh.position(mesh.to_vertex(h));
        let c = mesh.position(mesh.to_vertex(mesh.next(h)));
        area += 0.5 * (b - a).cross(c - a).length();
    }
    Ok(FilledHole {
        halfedge: hole[0],
        boundary_edges: hole.len(),
        perimeter,
        faces_added,
        vertices_added: free.len(),
        area,
        faired_order,
        fair_fallback,
    })
}

/// Which of `loops` (with `perimeters`) are outer boundaries: in each connected
/// component of `mesh`, the loop of the largest perimeter (the first of the longest, on a
/// tie).
fn outer_loops(mesh: &HalfedgeMesh, loops: &[Vec<HalfedgeId>], perimeters: &[f64]) -> Vec<bool> {
    let components = mesh.connected_components();
    // Per component, the longest loop so far.
    let mut longest: Vec<Option<(usize, f64)>> = vec![None; components.count()];
    for (i, (hole, &p)) in loops.iter().zip(perimeters).enumerate() {
        let c = components.vertex_component[mesh.to_vertex(hole[0])] as usize;
        match longest[c] {
            Some((_, q)) if q >= p => {}
            _ => longest[c] = Some((i, p)),
        }
    }
    let mut outer = vec![false; loops.len()];
    for (i, _) in longest.into_iter().flatten() {
        outer[i] = true;
    }
    outer
}

/// Fills the holes of a triangle mesh: every boundary loop except the one of the
/// largest perimeter in each connected component (all of them with
/// [`FillOptions::fill_all`]) and except those
/// longer than [`FillOptions::max_loop_edges`] is closed by a minimum-weight
/// triangulation, refined to the rim's edge length and faired. Returns the new mesh, its positions and a report of
/// every loop, filled or skipped with the reason.
///
/// # Algorithm
/// After P. Liepa, "Filling holes in meshes" (SGP 2003), as pmp-library's
/// `hole_filling.cpp`:
///
/// 1. *Triangulation*: dynamic programming over the sub-polygons of the loop finds the
///    triangulation of least weight `(largest dihedral angle, area)`, compared
///    lexicographically; the angle is measured as `1 − cos θ` between neighbouring
///    normals, those across the rim included. Triangles that would duplicate an
///    existing edge are refused.
/// 2. *Refinement* ([`FillOptions::refine`]): with `ℓ` the mean rim edge length, patch
///    edges longer than `4/3 ℓ` are split at their midpoints, new edges shorter than
///    `4/5 ℓ` collapsed, non-Delaunay patch edges flipped and new vertices relaxed in
///    their tangent planes, for up to ten rounds (a simplified isotropic remeshing of
///    the patch only).
/// 3. *Fairing* ([`FillOptions::fair`]): the new vertices solve `Δᵏ x = 0`
///    ([`FillOptions::fair_order`], cotangent or uniform [`FairWeights`]) with every
///    other vertex fixed, by a sparse Cholesky factorisation; should that fail
///    (degenerate triangles), the uniform membrane is used and
///    [`FilledHole::fair_fallback`] says so.
///
/// The loop of the largest perimeter in each connected component is left open by
/// default because a scan of an open part has exactly one outer boundary, which must
/// not be closed, and a mesh of several patches has one per patch; on a closed part set
/// [`FillOptions::fill_all`].
///
/// The input's vertices keep their ids and positions bit for bit; new vertices are
/// appended, hole by hole in the order of the loops' lowest halfedge ids. The input's
/// faces keep their ids; new faces are appended. Deterministic: the same input gives
/// the same output bit for bit.
///
/// # Errors
/// [`FillError::PositionCount`] when `positions` does not match the mesh;
/// [`FillError::NotTriangle`] when a face is not a triangle;
/// [`FillError::NonFinite`] for a non-finite position;
/// [`FillError::Options`] for `max_loop_edges < 3` or a fairing order other than 1, 2;
/// [`FillError::Edit`] / [`FillError::Topology`] on a defect.
///
/// # Complexity
/// O(V + F) for the copy, plus per filled loop of n edges O(n³) for the triangulation
/// and the refinement and fairing of its patch.
///
/// # Examples
/// ```
/// use beltrami_algorithms::{fill_holes, FillOptions, SkipReason};
/// use beltrami_halfedge::{HalfedgeMesh, primitives};
///
/// // An icosphere without its first face: one hole of 3 edges.
/// let ico = primitives::icosphere(3);
/// let faces: Vec<&[u32]> = ico.faces.iter().skip(1).collect();
/// let open = HalfedgeMesh::from_polygons(ico.positions.len(), faces)?;
/// // The only loop is also the longest: a closed part needs `fill_all`.
/// let (_, _, report) = fill_holes(&open, &ico.positions, &FillOptions::default())?;
/// assert_eq!(report.skipped[0].reason, SkipReason::OuterBoundary);
/// let options = FillOptions::default().fill_all(true);
/// let (closed, positions, report) = fill_holes(&open, &ico.positions, &options)?;
/// assert!(closed.is_closed());
/// assert_eq!((report.filled.len(), report.faces_added), (1, 1));
/// assert_eq!(positions, ico.positions);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn fill_holes(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    options: &FillOptions,
) -> Result<(HalfedgeMesh, Vec<DVec3>, FillReport), FillError> {
    fill_holes_with_progress(mesh, positions, options, |_, _| ControlFlow::Continue(()))
}

/// [`fill_holes`], calling `progress(done, total)` after each boundary loop (`total`
/// loops, the outer boundary and the loops skipped included), where a caller shows a bar
/// or looks for an interruption; returning [`ControlFlow::Break`] stops the run before
/// the next loop.
///
/// # Errors
/// As for [`fill_holes`], and [`FillError::Stopped`] when `progress` stopped the run.
///
/// # Examples
/// ```
/// use std::ops::ControlFlow;
/// use beltrami_algorithms::{fill_holes_with_progress, FillOptions};
/// use beltrami_halfedge::{HalfedgeMesh, primitives};
///
/// // An icosphere without two faces far apart: two holes.
/// let ico = primitives::icosphere(3);
/// let faces: Vec<&[u32]> = ico.faces.iter().enumerate()
///     .filter(|&(f, _)| f != 0 && f != 600).map(|(_, face)| face).collect();
/// let open = HalfedgeMesh::from_polygons(ico.positions.len(), faces)?;
/// let mut seen = Vec::new();
/// let options = FillOptions::default().fill_all(true);
/// let (closed, _, _) = fill_holes_with_progress(&open, &ico.positions, &options, |done, total| {
///     seen.push((done, total));
///     ControlFlow::Continue(())
/// })?;
/// assert!(closed.is_closed());
/// assert_eq!(seen, [(1, 2), (2, 2)]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn fill_holes_with_progress(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    options: &FillOptions,
    progress: impl FnMut(usize, usize) -> ControlFlow<()>,
) -> Result<(HalfedgeMesh, Vec<DVec3>, FillReport), FillError> {
    check_mesh(mesh, positions)?;
    check_finite(positions)?;
    options.validate()?;
    // Far from unit size, at a power of two times it (`crate::scale`); the options hold
    // no length.
    let (out, mut x, report) = at_unit_size(
        mesh,
        positions,
        |x, _| fill_holes_at_scale(mesh, x, options, progress),
        FillReport::scaled_back,
    )?;
    // The input's vertices keep their ids and positions, with their bits (a run far from
    // unit size scales them there and back, which rounds a coordinate that becomes
    // subnormal on the way).
    x[..positions.len()].copy_from_slice(positions);
    Ok((out, x, report))
}

/// [`fill_holes_with_progress`] at the positions' own size (checked).
fn fill_holes_at_scale(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    options: &FillOptions,
    mut progress: impl FnMut(usize, usize) -> ControlFlow<()>,
) -> Result<(HalfedgeMesh, Vec<DVec3>, FillReport), FillError> {
    let loops: Vec<Vec<HalfedgeId>> = mesh.boundary_loops().collect();
    let mut edit = EditMesh::from_mesh(mesh, positions)?;
    let perimeters: Vec<f64> = loops.iter().map(|l| perimeter(&edit, l)).collect();
    let outer = if options.fill_all {
        vec![false; loops.len()]
    } else {
        outer_loops(mesh, &loops, &perimeters)
    };
    let mut report = FillReport {
        loops: loops.len(),
        ..FillReport::default()
    };
    let total = loops.len();
    for (i, hole) in loops.iter().enumerate() {
        if i > 0 && progress(i, total).is_break() {
            return Err(FillError::Stopped { done: i, total });
        }
        let skip = |reason| SkippedHole {
            halfedge: hole[0],
            boundary_edges: hole.len(),
            perimeter: perimeters[i],
            reason,
        };
        if outer[i] {
            report.skipped.push(skip(SkipReason::OuterBoundary));
            continue;
        }
        if hole.len() > options.max_loop_edges {
            report.skipped.push(skip(SkipReason::TooLarge));
            continue;
        }
        match fill_loop(&mut edit, hole, options) {
            Ok(filled) => {
                report.faces_added += filled.faces_added;
                report.vertices_added += filled.vertices_added;
                report.filled.push(filled);
            }
            Err(LoopError::Skip(reason)) => report.skipped.push(skip(reason)),
            Err(LoopError::Edit(e)) => return Err(FillError::Edit(e)),
        }
    }
    if total > 0 && progress(total, total).is_break() {
        return Err(FillError::Stopped { done: total, total });
    }
    edit.garbage_collection();
    let (out, out_positions) = edit.into_mesh()?;
    Ok((out, out_positions, report))
}
