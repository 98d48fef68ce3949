//! Isotropic remeshing: a new triangulation of the same surface whose edges all have
//! about the same length L, with the sharp features and the boundary kept.
//!
//! The algorithm of Botsch and Kobbelt (2004), as pmp-library's `uniform_remeshing`
//! runs it, on the editable [`EditMesh`]. Each of the `iterations`:
//!
//! 1. **split** every edge longer than 4/3 L at its midpoint (repeatedly);
//! 2. **collapse** every edge shorter than 4/5 L into one of its end points, unless the
//!    topology forbids it ([`EditMesh::is_collapse_ok`]), or it would make an edge
//!    longer than 4/3 L, turn a triangle over, move a corner or leave a feature curve;
//!    of two possible directions, the vertex of lower valence goes;
//! 3. **flip** every interior, non-feature edge whose flip brings the valences of its
//!    four vertices closer to 6 (4 on the boundary), when [`EditMesh::is_flip_ok`] and no
//!    triangle folds;
//! 4. **relax** tangentially: five Jacobi sweeps moving each vertex towards the
//!    area-weighted centroid of its triangles within its tangent plane (a vertex on a
//!    feature curve along the curve's tangent, towards the mean of its two feature
//!    edges' midpoints), then **project** every vertex back onto the *input* surface
//!    (a [`SurfaceIndex`] built once), a vertex on a feature curve onto the input's
//!    feature curves. The closest point of the input's triangles is then lifted onto
//!    the smooth surface through them (Phong tessellation with vertex normals, flat up to
//!    the feature curves and across sharp edges; see [`RemeshOptions::smooth_projection`]),
//!    so that on a curved surface the vertices lie on the surface the triangles
//!    approximate, not up to a triangle's sagitta below it.
//!
//! After the last iteration, every non-feature edge opposite an angle above 170° (a
//! *cap*) is flipped when that is valid and folds nothing, as pmp-library does.
//!
//! The thresholds 4/5 and 4/3 make the split and collapse steps converge: a split leaves
//! halves of at least 2/3 L, which no collapse touches, and a collapse never makes an edge
//! a split would cut again.
//!
//! ## Features and boundary
//!
//! With [`RemeshOptions::feature_angle`] = θ, an interior edge whose two triangles'
//! normals differ by more than θ is a *feature edge*; boundary edges are always feature
//! edges (a boundary is a curve to keep). The flag is an edge property of the
//! [`EditMesh`], so it follows the edits: both halves of a split feature edge are
//! features; flips never touch a feature edge; a collapse along a feature keeps the
//! flag of the surviving edge and is refused when it would merge a feature edge away.
//! A vertex with one or more than two feature edges, or whose two feature edges turn by
//! more than θ (without a feature angle: by more than [`DEFAULT_CORNER_ANGLE`]), is a
//! *corner*: it never moves and is never collapsed away. Other feature vertices move
//! only along their curve and are projected back onto the input's feature edges, so
//! every output vertex on a feature lies on an input feature edge, and every boundary
//! vertex on the input's boundary polyline. No collapse joins two feature vertices
//! across a non-feature edge, so the number of boundary loops, the genus and the
//! feature network stay.
//!
//! ## Adaptive sizing
//!
//! With [`EdgeLength::Adaptive`] the single L becomes a length per vertex (Dunyach et
//! al. 2013, pmp-library's `adaptive_remeshing`): from the largest principal curvature
//! κ estimated on the input, the length `sqrt(6 e r − 3 e²)` of a chord deviating by the
//! allowed error e from a circle of radius r = 1/κ, clamped to `[min_edge, max_edge]`.
//! An edge's target is the smaller of its end points'.
//!
//! # References
//! - M. Botsch, L. Kobbelt, "A remeshing approach to multiresolution modeling",
//!   Symposium on Geometry Processing 2004.
//! - M. Dunyach, D. Vanderhaeghe, L. Barthe, M. Botsch, "Adaptive remeshing for
//!   real-time mesh deformation", Eurographics 2013 short papers.
//! - M. Botsch, L. Kobbelt, M. Pauly, P. Alliez, B. Lévy, *Polygon Mesh Processing*,
//!   AK Peters 2010, §6.5 (incremental remeshing).
//! - pmp-library, `src/pmp/algorithms/remeshing.cpp` (the same steps and thresholds).

mod curves;
mod passes;
mod phong;
mod sizing;

use std::ops::ControlFlow;

use beltrami_halfedge::edit::VertexProperty;
use beltrami_halfedge::geometry::DEGENERACY_RATIO;
use beltrami_halfedge::{DVec3, EdgeId, EditMesh, FaceId, HalfedgeMesh, TopologyError, VertexId};
use beltrami_metrics::distance::SurfaceIndex;
use rayon::prelude::*;

use crate::error::{about_count, algorithm_error, check_finite, check_mesh, short};
use crate::scale::{Scale, at_unit_size};

pub use curves::FOLD_ANGLE;
use passes::Remesher;
use phong::PhongSurface;
pub use phong::SMOOTH_ANGLE;

/// Without a feature angle, a boundary vertex whose two boundary edges turn by more than
/// this (30°, in radians) is a corner and stays.
pub const DEFAULT_CORNER_ANGLE: f64 = std::f64::consts::PI / 6.0;

/// The most triangles a remesh may aim at (about `area / (√3/4 · L²)`, summed over the
/// input's faces with the smallest target length at their corners); a smaller target
/// length is refused with [`RemeshError::TooManyFaces`] before any work.
pub const MAX_REMESH_FACES: usize = 50_000_000;

/// How the target edge length L is given.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum EdgeLength {
    /// L in the positions' unit.
    Absolute(f64),
    /// L as a multiple of the input's mean edge length.
    Relative(f64),
    /// Curvature-adaptive sizing (Dunyach et al. 2013, pmp-library's
    /// `adaptive_remeshing`): at each vertex, the length of a chord that deviates by
    /// the approximation error from a circle of the largest principal curvature radius,
    /// clamped to the smallest and largest edge length. The curvature is estimated on
    /// the input (cotangent mean curvature and angle defect) at vertices off the
    /// features and the boundary, smoothed twice over the neighbours, and follows the
    /// vertices: a split averages its end points' lengths, a projection interpolates the
    /// input's field. Values left `None` are derived from the input
    /// ([`AdaptiveSizing`]); the report says which were used
    /// ([`RemeshReport::adaptive`]).
    Adaptive(AdaptiveSizing),
}

/// The settings of curvature-adaptive sizing ([`EdgeLength::Adaptive`]), in the
/// positions' unit. Each value left `None` is derived from the input's mean edge length
/// L̄, so that `AdaptiveSizing::default()` keeps about the input's density where the
/// surface has its typical curvature, refines where it is more curved and coarsens where
/// it is flatter:
/// - `min_edge`: L̄ / 4 (at most a given `max_edge`);
/// - `max_edge`: 4 L̄ (at least a given `min_edge`);
/// - `approx_error`: the deviation of a chord of length L̄ from a circle of the median
///   curvature (over the vertices whose curvature is above `10⁻⁶ / L̄`, after smoothing),
///   so that vertices of that curvature get exactly L̄; on a surface with no such vertex
///   (flat) every vertex gets `max_edge` whatever the error, and L̄ is used.
///
/// # Examples
/// ```
/// use beltrami_algorithms::{AdaptiveSizing, EdgeLength, RemeshOptions};
/// let defaults = RemeshOptions::default().adaptive_sizing(AdaptiveSizing::default());
/// let given = RemeshOptions::default().adaptive(0.01, 0.2, 0.001);
/// assert_eq!(
///     given.edge_length,
///     EdgeLength::Adaptive(AdaptiveSizing {
///         min_edge: Some(0.01),
///         max_edge: Some(0.2),
///         approx_error: Some(0.001),
///     })
/// );
/// assert_ne!(defaults, given);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AdaptiveSizing {
    /// The smallest target edge length (default L̄ / 4).
    pub min_edge: Option<f64>,
    /// The largest target edge length (default 4 L̄).
    pub max_edge: Option<f64>,
    /// The allowed distance between an edge and the curved surface (default: that of a
    /// chord of length L̄ at the median curvature).
    pub approx_error: Option<f64>,
}

/// The values an adaptive run used ([`RemeshReport::adaptive`]), in the positions' unit:
/// those given in [`AdaptiveSizing`] and those derived from the input.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct AdaptiveLengths {
    /// The smallest target edge length.
    pub min_edge: f64,
    /// The largest target edge length.
    pub max_edge: f64,
    /// The allowed distance between an edge and the curved surface.
    pub approx_error: f64,
}

/// The most iterations a remeshing run takes ([`RemeshOptions::iterations`]): the
/// counts of splits, collapses and flips settle within 10 to 20 iterations, and a larger
/// count is most likely a typing error that would run for hours on a large mesh.
pub const MAX_REMESH_ITERATIONS: usize = 1000;

/// The settings of [`remesh`].
///
/// # Examples
/// ```
/// use beltrami_algorithms::{EdgeLength, RemeshOptions};
/// let options = RemeshOptions::default()
///     .edge_length(0.1)
///     .iterations(5)
///     .feature_angle(45f64.to_radians());
/// assert_eq!(options.edge_length, EdgeLength::Absolute(0.1));
/// assert!(options.projection);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct RemeshOptions {
    /// The target edge length L. Default: the input's mean edge length
    /// (`Relative(1.0)`).
    pub edge_length: EdgeLength,
    /// The number of split–collapse–flip–relax iterations (default 10, as pmp-library;
    /// at most [`MAX_REMESH_ITERATIONS`]).
    pub iterations: usize,
    /// Edges whose two triangles' normals differ by more than this angle (radians, in
    /// `[0, π]`) are feature edges and are kept. `None` (the default): no interior edge
    /// is a feature; the boundary is kept in any case.
    pub feature_angle: Option<f64>,
    /// Project the vertices back onto the input surface after each iteration (default
    /// `true`). Without it the vertices only move within their tangent planes, and a
    /// curved surface shrinks a little. Feature vertices are projected onto the input's
    /// feature curves either way.
    pub projection: bool,
    /// Project onto a smooth surface over the input rather than onto its flat triangles
    /// (default `true`): the closest point of the input is lifted by Phong tessellation
    /// from the input's vertex normals (averaged up to the feature edges and the boundary);
    /// triangles whose corner normals differ by more than [`SMOOTH_ANGLE`] (across
    /// sharp edges that are not features) are not lifted. On a curved surface the vertices then lie on
    /// the underlying surface instead of up to a facet's sagitta below it, and the
    /// distance between input and output shrinks by about 40 %; flat regions between
    /// creases stay exactly flat. Off, every vertex lies on the input's triangles.
    /// Without [`projection`](Self::projection) it has no effect.
    pub smooth_projection: bool,
}

impl Default for RemeshOptions {
    fn default() -> Self {
        Self {
            edge_length: EdgeLength::Relative(1.0),
            iterations: 10,
            feature_angle: None,
            projection: true,
            smooth_projection: true,
        }
    }
}

impl RemeshOptions {
    /// Sets the target edge length L, in the positions' unit.
    #[must_use]
    pub fn edge_length(mut self, length: f64) -> Self {
        self.edge_length = EdgeLength::Absolute(length);
        self
    }

    /// Sets the target edge length to `factor` times the input's mean edge length.
    #[must_use]
    pub fn relative_edge_length(mut self, factor: f64) -> Self {
        self.edge_length = EdgeLength::Relative(factor);
        self
    }

    /// Sets curvature-adaptive sizing ([`EdgeLength::Adaptive`]) with all three values
    /// given, lengths in the positions' unit.
    #[must_use]
    pub fn adaptive(mut self, min_edge: f64, max_edge: f64, approx_error: f64) -> Self {
        self.edge_length = EdgeLength::Adaptive(AdaptiveSizing {
            min_edge: Some(min_edge),
            max_edge: Some(max_edge),
            approx_error: Some(approx_error),
        });
        self
    }

    /// Sets curvature-adaptive sizing ([`EdgeLength::Adaptive`]); the values left `None`
    /// are derived from the input ([`AdaptiveSizing`]).
    #[must_use]
    pub fn adaptive_sizing(mut self, sizing: AdaptiveSizing) -> Self {
        self.edge_length = EdgeLength::Adaptive(sizing);
        self
    }

    /// Sets the number of iterations.
    #[must_use]
    pub fn iterations(mut self, iterations: usize) -> Self {
        self.iterations = iterations;
        self
    }

    /// Sets the feature angle, in radians.
    #[must_use]
    pub fn feature_angle(mut self, radians: f64) -> Self {
        self.feature_angle = Some(radians);
        self
    }

    /// Turns the projection onto the input surface on or off.
    #[must_use]
    pub fn projection(mut self, on: bool) -> Self {
        self.projection = on;
        self
    }

    /// Projects onto the smooth (Phong) surface over the input, or onto its flat
    /// triangles ([`RemeshOptions::smooth_projection`]).
    #[must_use]
    pub fn smooth_projection(mut self, on: bool) -> Self {
        self.smooth_projection = on;
        self
    }
}

/// What one iteration of [`remesh`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct RemeshIteration {
    /// Edges split.
    pub splits: usize,
    /// Edges collapsed.
    pub collapses: usize,
    /// Edges flipped.
    pub flips: usize,
}

/// What [`remesh`] did. Lengths are in the positions' unit.
#[derive(Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct RemeshReport {
    /// The target edge length L used; for adaptive sizing, the mean of the sizing field
    /// over the input's vertices.
    pub target_edge_length: f64,
    /// With adaptive sizing, the smallest and largest edge length and the approximation
    /// error used (given or derived from the input); `None` otherwise.
    pub adaptive: Option<AdaptiveLengths>,
    /// The counts of each iteration, in order.
    pub iterations: Vec<RemeshIteration>,
    /// Edges split, in all iterations.
    pub splits: usize,
    /// Edges collapsed, in all iterations.
    pub collapses: usize,
    /// Edges flipped, in all iterations and in the final removal of caps.
    pub flips: usize,
    /// Of those, edges flipped at the end because they were opposite an angle above
    /// 170° (pmp-library's "remove caps" step).
    pub cap_flips: usize,
    /// Vertices of the input.
    pub vertices_before: usize,
    /// Faces of the input.
    pub faces_before: usize,
    /// Vertices of the output.
    pub vertices: usize,
    /// Faces of the output.
    pub faces: usize,
    /// The input's mean edge length.
    pub mean_edge_length_before: f64,
    /// The input's edge-length coefficient of variation (standard deviation / mean).
    pub edge_length_cv_before: f64,
    /// The output's mean edge length.
    pub mean_edge_length: f64,
    /// The output's edge-length coefficient of variation.
    pub edge_length_cv: f64,
    /// Interior edges of the input found sharper than the feature angle.
    pub feature_edges: usize,
    /// Interior edges of the input given as features by the caller
    /// ([`remesh_with_feature_edges`]), sharp or not.
    pub given_feature_edges: usize,
    /// Those of the feature edges whose two triangles fold back onto each other (a
    /// dihedral angle above [`FOLD_ANGLE`], 150°): on a scan these are folded slivers,
    /// which stay in the output as feature curves, folds and all.
    pub fold_edges: usize,
    /// Boundary edges of the input (kept as curves).
    pub boundary_edges: usize,
    /// Vertices of the input that are corners and stay where they are.
    pub corners: usize,
    /// The largest distance from an output vertex to the input's triangles: the
    /// one-sided Hausdorff distance at the vertices (a lower bound of the one between
    /// surfaces). With [`RemeshOptions::smooth_projection`] on a curved surface it is
    /// about the input triangles' depth below the surface they approximate (their
    /// sagitta), as the vertices are lifted onto that surface; with a faceted projection
    /// it is zero to rounding. Isolated vertices (in no face) are kept where they are and
    /// not counted.
    pub hausdorff: f64,
    /// The largest distance from an input vertex (in a face) to the output's triangles,
    /// in the positions' unit: the other side of the Hausdorff distance at the
    /// vertices. Where the remeshing rounds off what the output's edges cannot follow
    /// (the sharp edges and corners of a part without [`RemeshOptions::feature_angle`],
    /// detail smaller than the target length) this is the one that shows it: the
    /// corner of a cube (a tetrahedron with edges 1 and √2) remeshed without features
    /// keeps its vertices on its faces (`hausdorff` 1e-16) while its corners end 0.40
    /// from the result.
    pub hausdorff_from_input: f64,
    /// Degenerate triangles of the input: flat for their size (twice the area at most
    /// `DEGENERACY_RATIO` times the longest edge squared) or shrunk to a point (every
    /// edge below 10⁻⁹ of the bounding box diagonal).
    pub degenerate_faces_before: usize,
    /// Degenerate triangles of the output, by the same test. A run stops with
    /// [`RemeshError::Degenerate`] when those beyond the input's count are more than a
    /// tenth of the faces; a few can survive on noisy input with sharp features, and a
    /// caller who needs none checks this count.
    pub degenerate_faces: usize,
}

algorithm_error! {
    /// Why [`remesh`] could not run. Every variant names the offending element or value.
    #[derive(Debug, Clone, PartialEq, thiserror::Error)]
    #[non_exhaustive]
    pub enum RemeshError for "remeshing" {
        /// The mesh has no faces, or all its edges have length zero: there is no surface to
        /// remesh and no mean edge length.
        #[error("the mesh has no faces or no edge of non-zero length; there is nothing to remesh")]
        Empty,
        /// Every face of the mesh has zero area (its triangles are flat: their corners
        /// lie on a line or coincide): there is no surface to remesh.
        #[error("every face of the mesh has zero area (its corners lie on a line); there is no surface to remesh")]
        NoArea,
        /// The target length is so small for the surface's area that the result would be
        /// too large.
        #[error(
            "a target edge length of {} would make {}; at most {max} are allowed",
            short(*.edge_length),
            about_count(*.predicted)
        )]
        TooManyFaces {
            /// The (smallest) target edge length.
            edge_length: f64,
            /// The estimated number of triangles, `area / (√3/4 · L²)`.
            predicted: f64,
            /// [`MAX_REMESH_FACES`].
            max: usize,
        },
        /// An edit the checks allowed was refused: a defect of this crate, reported rather
        /// than panicking.
        #[error("an edit failed: {0}")]
        Edit(#[from] beltrami_halfedge::EditError),
        /// The input or the result did not convert between the frozen and the editable
        /// mesh.
        #[error("{0}")]
        Topology(#[from] TopologyError),
        /// A closest-point query failed (a defect: the positions are finite).
        #[error("projecting onto the input: {0}")]
        Metrics(#[from] beltrami_metrics::MetricsError),
        /// An iteration left more than a tenth of the faces with no area (flat for their
        /// size, or shrunk to a point) beyond those of the input: the target edge length
        /// is too long for the surface (a closed surface coarsened to a few vertices,
        /// whose tangential relaxation then draws them together). The run stops there;
        /// no mesh is returned.
        #[error(
            "{faces} of the result's {total} faces would be degenerate (the input has {input_faces}): {}",
            degenerate_advice(*.input_faces, *.edge_length, *.diagonal)
        )]
        Degenerate {
            /// Degenerate faces of the result.
            faces: usize,
            /// Degenerate faces of the input.
            input_faces: usize,
            /// Faces of the result at that iteration.
            total: usize,
            /// The (mean) target edge length.
            edge_length: f64,
            /// The diagonal of the input's bounding box.
            diagonal: f64,
        },
        /// An iteration drew the surface together to a small solid, its triangles' extent
        /// (bounding box diagonal) at most [`MIN_EXTENT_SHARE`] of the input's: the
        /// target edge length is too long for the surface (a closed surface coarsened to
        /// a few vertices, which the tangential relaxation then moves together while the
        /// projection keeps them on the surface). The run stops there; no mesh is
        /// returned.
        #[error(
            "the result would shrink to {extent:.6} across, against the input's bounding box diagonal of {diagonal:.6}: a target edge length of {} is too long for this surface; use a shorter one",
            short(*.edge_length)
        )]
        Shrunk {
            /// The bounding box diagonal of the result's triangles at that iteration.
            extent: f64,
            /// The diagonal of the input's bounding box.
            diagonal: f64,
            /// The (mean) target edge length.
            edge_length: f64,
        },
        /// A pair of [`remesh_with_feature_edges`] is not an edge of the input: a vertex
        /// index out of range, or two vertices no edge joins.
        #[error("feature edge {index} ({a}, {b}) is not an edge of the mesh: {why}")]
        FeatureEdge {
            /// The pair's position in the list (0-based).
            index: usize,
            /// Its first vertex.
            a: u64,
            /// Its second vertex.
            b: u64,
            /// `"vertex N is out of range (M vertices)"` or `"no edge joins them"`.
            why: String,
        },
        /// The progress closure of [`remesh_with_progress`] asked to stop.
        #[error("remeshing was stopped after {done} of {total} iterations")]
        Stopped {
            /// The iterations done.
            done: usize,
            /// The iterations asked for.
            total: usize,
        },
    }
}

/// Whether `x` is a number above zero.
fn is_positive(x: f64) -> bool {
    x > 0.0
}

/// The mean and coefficient of variation of the edge lengths of `mesh`.
fn edge_length_stats(mesh: &EditMesh) -> (f64, f64) {
    let lengths: Vec<f64> = mesh
        .edges()
        .map(|e| {
            let [a, b] = mesh.edge_vertices(e);
            mesh.position(a).distance(mesh.position(b))
        })
        .collect();
    if lengths.is_empty() {
        return (0.0, 0.0);
    }
    let n = lengths.len() as f64;
    let mean = lengths.iter().sum::<f64>() / n;
    let var = lengths.iter().map(|l| (l - mean) * (l - mean)).sum::<f64>() / n;
    let cv = if mean > 0.0 { var.sqrt() / mean } else { 0.0 };
    (mean, cv)
}

impl RemeshOptions {
    /// These options for a run at `scale`: the lengths in the positions' unit scaled.
    fn scaled(&self, scale: &Scale) -> Self {
        let edge_length = match self.edge_length {
            EdgeLength::Absolute(l) => EdgeLength::Absolute(scale.length(l)),
            EdgeLength::Relative(r) => EdgeLength::Relative(r),
            EdgeLength::Adaptive(AdaptiveSizing {
                min_edge,
                max_edge,
                approx_error,
            }) => EdgeLength::Adaptive(AdaptiveSizing {
                min_edge: min_edge.map(|x| scale.length(x)),
                max_edge: max_edge.map(|x| scale.length(x)),
                approx_error: approx_error.map(|x| scale.length(x)),
            }),
        };
        Self {
            edge_length,
            ..*self
        }
    }
}

impl RemeshReport {
    /// The report of a run at `scale` with `options` (as the caller gave them), in the
    /// caller's unit. The pattern names every field (`_` for those without a unit), so
    /// that a new one is not left unscaled; the lengths given come back as given (one the
    /// run's numbers could not hold was clamped, see `Scale::length`).
    fn scaled_back(mut self, scale: &Scale, options: &RemeshOptions) -> Self {
        let Self {
            target_edge_length,
            adaptive,
            iterations: _,
            splits: _,
            collapses: _,
            flips: _,
            cap_flips: _,
            vertices_before: _,
            faces_before: _,
            vertices: _,
            faces: _,
            mean_edge_length_before,
            edge_length_cv_before: _,
            mean_edge_length,
            edge_length_cv: _,
            feature_edges: _,
            given_feature_edges: _,
            fold_edges: _,
            boundary_edges: _,
            corners: _,
            hausdorff,
            hausdorff_from_input,
            degenerate_faces_before: _,
            degenerate_faces: _,
        } = &mut self;
        let used = adaptive
            .as_mut()
            .map(|a| [&mut a.min_edge, &mut a.max_edge, &mut a.approx_error]);
        let lengths = [
            target_edge_length,
            mean_edge_length_before,
            mean_edge_length,
            hausdorff,
            hausdorff_from_input,
        ];
        for length in lengths.into_iter().chain(used.into_iter().flatten()) {
            *length = scale.length_back(*length);
        }
        match options.edge_length {
            EdgeLength::Absolute(l) => self.target_edge_length = l,
            EdgeLength::Adaptive(given) => {
                if let Some(used) = &mut self.adaptive {
                    used.min_edge = given.min_edge.unwrap_or(used.min_edge);
                    used.max_edge = given.max_edge.unwrap_or(used.max_edge);
                    used.approx_error = given.approx_error.unwrap_or(used.approx_error);
                }
            }
            EdgeLength::Relative(_) => {}
        }
        self
    }
}

impl RemeshError {
    /// The error of a run at `scale` with `options` (as the caller gave them), its
    /// lengths in the caller's unit: a target length given is named as given (scaled, it
    /// may have been clamped, see `Scale::length`). (Invalid options are found in the
    /// caller's values, see [`remesh_at_scale`].)
    fn scaled_back(self, scale: &Scale, options: &RemeshOptions) -> Self {
        let given = match options.edge_length {
            EdgeLength::Absolute(l) => Some(l),
            _ => None,
        };
        let back = |x| given.unwrap_or_else(|| scale.length_back(x));
        match self {
            Self::TooManyFaces {
                edge_length,
                predicted,
                max,
            } => Self::TooManyFaces {
                // The smallest target: the given one, or adaptive sizing's smallest
                // given where the sizing field reached it.
                edge_length: match options.edge_length {
                    EdgeLength::Adaptive(AdaptiveSizing {
                        min_edge: Some(m), ..
                    }) if edge_length == scale.length(m) => m,
                    _ => back(edge_length),
                },
                predicted,
                max,
            },
            Self::Degenerate {
                faces,
                input_faces,
                total,
                edge_length,
                diagonal,
            } => Self::Degenerate {
                faces,
                input_faces,
                total,
                edge_length: back(edge_length),
                diagonal: scale.length_back(diagonal),
            },
            Self::Shrunk {
                extent,
                diagonal,
                edge_length,
            } => Self::Shrunk {
                extent: scale.length_back(extent),
                diagonal: scale.length_back(diagonal),
                edge_length: back(edge_length),
            },
            // The others carry no length.
            e => e,
        }
    }
}

/// Checks the options against the input and returns the target edge length (the
/// input's mean edge length for adaptive sizing, replaced by the sizing field's mean).
fn target_length(options: &RemeshOptions, mean_edge: f64) -> Result<f64, RemeshError> {
    let bad = |reason: String| Err(RemeshError::Options { reason });
    let target = match options.edge_length {
        EdgeLength::Absolute(l) if !(l.is_finite() && l > 0.0) => {
            return bad(format!(
                "the target edge length must be positive and finite, got {}",
                beltrami_halfedge::exact_number(l)
            ));
        }
        EdgeLength::Relative(r) if !(r.is_finite() && r > 0.0) => {
            return bad(format!(
                "the relative target edge length must be positive and finite, got {}",
                beltrami_halfedge::exact_number(r)
            ));
        }
        EdgeLength::Adaptive(sizing) => {
            for (name, x) in [
                ("the smallest edge length", sizing.min_edge),
                ("the largest edge length", sizing.max_edge),
                ("the approximation error", sizing.approx_error),
            ] {
                if let Some(x) = x
                    && !(x.is_finite() && x > 0.0)
                {
                    return bad(format!(
                        "{name} must be positive and finite, got {}",
                        beltrami_halfedge::exact_number(x)
                    ));
                }
            }
            if let (Some(min_edge), Some(max_edge)) = (sizing.min_edge, sizing.max_edge)
                && min_edge > max_edge
            {
                return bad(format!(
                    "the smallest edge length {} exceeds the largest {}",
                    beltrami_halfedge::exact_number(min_edge),
                    beltrami_halfedge::exact_number(max_edge)
                ));
            }
            mean_edge
        }
        EdgeLength::Absolute(l) => l,
        EdgeLength::Relative(r) => r * mean_edge,
    };
    if options.iterations > MAX_REMESH_ITERATIONS {
        return bad(format!(
            "remeshing takes at most {MAX_REMESH_ITERATIONS} iterations (it settles within 10 to 20), got {}",
            options.iterations
        ));
    }
    if let Some(a) = options.feature_angle
        && !(0.0..=std::f64::consts::PI).contains(&a)
    {
        return bad(format!(
            "the feature angle must be between 0 and pi radians, got {}",
            beltrami_halfedge::exact_number(a)
        ));
    }
    Ok(target)
}

/// Remeshes a triangle mesh isotropically: returns a new mesh of the same surface whose
/// edges have about the target length L, its positions, and a report.
///
/// Botsch and Kobbelt's incremental remeshing, as pmp-library's `uniform_remeshing`:
/// each iteration splits the edges longer than 4/3 L at their midpoints, collapses those
/// shorter than 4/5 L (unless the topology, a feature, a corner, a new edge longer than
/// 4/3 L or a folded triangle forbids it), flips edges towards valence 6 (4 on the
/// boundary), relaxes the vertices tangentially (area-weighted centroids in the tangent
/// plane; feature vertices along their curve) and projects them back onto the input
/// surface (feature vertices onto the input's feature curves; the others by default onto
/// the smooth surface through the input's triangles,
/// [`RemeshOptions::smooth_projection`]). Boundary edges, and with
/// [`RemeshOptions::feature_angle`] the sharp edges, are feature curves: never flipped,
/// never collapsed across; corners (where other than two feature edges meet, or the
/// curve turns by more than the feature angle or [`DEFAULT_CORNER_ANGLE`]) never move.
/// `docs/remeshing.md` in the repository has the details and measurements.
///
/// The result has the input's topology (Euler characteristic, number
/// of boundary loops), its boundary and feature curves, and passes
/// [`EditMesh::check_integrity`]; the same input and options give the same output, bit
/// for bit. Vertices and faces are numbered afresh.
///
/// # Errors
/// [`RemeshError::PositionCount`], [`RemeshError::NotTriangle`],
/// [`RemeshError::NonFinite`] for bad input; [`RemeshError::Empty`] for a mesh without
/// faces or of zero size; [`RemeshError::NoArea`] for one whose faces are all flat; [`RemeshError::Options`] for a non-positive or non-finite
/// length, factor or error, an adaptive smallest length above the largest, or a feature
/// angle outside `[0, π]`; [`RemeshError::TooManyFaces`] when the target length is too
/// small for the surface.
///
/// # Complexity
/// O(iterations · (F log F_in)) for a result of F faces on an input of F_in faces: each
/// step is linear in the mesh, and a projection is a search in the input's hierarchy.
///
/// # Examples
/// ```
/// use beltrami_algorithms::{remesh, RemeshOptions};
/// use beltrami_halfedge::primitives;
///
/// let sphere = primitives::icosphere(3);
/// let mesh = sphere.mesh()?;
/// let options = RemeshOptions::default().relative_edge_length(2.0);
/// let (coarse, positions, report) = remesh(&mesh, &sphere.positions, &options)?;
/// assert!(coarse.n_faces() < mesh.n_faces() / 2);
/// assert_eq!(positions.len(), coarse.n_vertices());
/// assert!((report.mean_edge_length / report.target_edge_length - 1.0).abs() < 0.15);
/// // The vertices lie on the unit sphere the input's triangles approximate, not on the
/// // triangles themselves (up to 4.5e-3 below it).
/// assert!(positions.iter().all(|p| (p.length() - 1.0).abs() < 1e-4));
/// assert!(report.hausdorff < 4.6e-3);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # References
/// M. Botsch, L. Kobbelt, "A remeshing approach to multiresolution modeling", SGP 2004.
pub fn remesh(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    options: &RemeshOptions,
) -> Result<(HalfedgeMesh, Vec<DVec3>, RemeshReport), RemeshError> {
    remesh_with_progress(mesh, positions, options, |_, _| ControlFlow::Continue(()))
}

/// [`remesh`], calling `progress(done, total)` after each of the `total` iterations
/// (`done` counts from 1), for a progress bar on large meshes: an iteration of a
/// million-vertex mesh takes about a second on two cores. The result is [`remesh`]'s.
/// `progress` returns [`ControlFlow::Break`] to stop (a user's interrupt, say).
///
/// # Errors
/// As for [`remesh`], and [`RemeshError::Stopped`] when `progress` stopped the run.
///
/// # Examples
/// ```
/// use beltrami_algorithms::{remesh_with_progress, RemeshOptions};
/// use beltrami_halfedge::primitives;
///
/// let sphere = primitives::icosphere(2);
/// let mesh = sphere.mesh()?;
/// let mut seen = Vec::new();
/// let options = RemeshOptions::default().iterations(3);
/// remesh_with_progress(&mesh, &sphere.positions, &options, |done, total| {
///     seen.push((done, total));
///     std::ops::ControlFlow::Continue(())
/// })?;
/// assert_eq!(seen, [(1, 3), (2, 3), (3, 3)]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn remesh_with_progress(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    options: &RemeshOptions,
    progress: impl FnMut(usize, usize) -> ControlFlow<()>,
) -> Result<(HalfedgeMesh, Vec<DVec3>, RemeshReport), RemeshError> {
    remesh_with_feature_edges(mesh, positions, &[], options, progress)
}

/// [`remesh_with_progress`] with feature edges given by the caller: each pair `[a, b]`
/// of `feature_edges` names the edge between input vertices `a` and `b` (in either
/// order), which is kept as a feature curve like an edge sharper than
/// [`RemeshOptions::feature_angle`] (never flipped or collapsed across; its vertices
/// move only along it and are projected onto the input's feature edges; corners where
/// other than two feature edges meet or the curve turns by more than the feature angle,
/// or [`DEFAULT_CORNER_ANGLE`] without one). This is the edge attribute a caller sets
/// for creases no angle finds: a gentle fillet's border, a measured part's datum line,
/// the seam between two materials. The given edges and the sharp ones are kept alike;
/// boundary edges are kept in any case. [`RemeshReport::given_feature_edges`] counts the
/// interior edges given. With no pairs this is [`remesh_with_progress`].
///
/// # Errors
/// As for [`remesh_with_progress`], and [`RemeshError::FeatureEdge`] for a pair that is
/// not an edge of `mesh` (checked before any work).
///
/// # Examples
/// ```
/// use beltrami_algorithms::{remesh_with_feature_edges, RemeshOptions};
/// use beltrami_halfedge::primitives;
///
/// // A flat 8 × 8 grid (unit cells) with its middle row of edges, y = 4, given as a
/// // feature line.
/// let grid = primitives::grid(8, 8);
/// let mesh = grid.mesh()?;
/// let on_line = |p: &beltrami_halfedge::DVec3| (p.y - 4.0).abs() < 1e-12;
/// let line: Vec<[u32; 2]> = mesh
///     .edges()
///     .map(|e| mesh.edge_vertices(e).map(|v| v.index() as u32))
///     .filter(|[a, b]| on_line(&grid.positions[*a as usize]) && on_line(&grid.positions[*b as usize]))
///     .collect();
/// let options = RemeshOptions::default().relative_edge_length(1.5);
/// let (out, x, report) =
///     remesh_with_feature_edges(&mesh, &grid.positions, &line, &options, |_, _| {
///         std::ops::ControlFlow::Continue(())
///     })?;
/// assert_eq!(report.given_feature_edges, line.len());
/// // The line is still a chain of edges of the result.
/// let kept = out
///     .edges()
///     .filter(|&e| out.edge_vertices(e).iter().all(|v| on_line(&x[v.index()])))
///     .count();
/// assert!(kept >= 4);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn remesh_with_feature_edges(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    feature_edges: &[[u32; 2]],
    options: &RemeshOptions,
    progress: impl FnMut(usize, usize) -> ControlFlow<()>,
) -> Result<(HalfedgeMesh, Vec<DVec3>, RemeshReport), RemeshError> {
    check_mesh(mesh, positions)?;
    check_finite(positions)?;
    // Far from unit size, at a power of two times it (`crate::scale`), the options'
    // lengths with it.
    at_unit_size(
        mesh,
        positions,
        |x, scale| match scale {
            None => remesh_at_scale(mesh, x, feature_edges, (options, options), progress),
            Some(scale) => {
                let run = options.scaled(scale);
                remesh_at_scale(mesh, x, feature_edges, (&run, options), progress)
                    .map_err(|e| e.scaled_back(scale, options))
            }
        },
        |report, scale| report.scaled_back(scale, options),
    )
}

/// [`remesh_with_feature_edges`] at the positions' own size, with `options` at that
/// size and `caller`, the caller's, checked where a run at the caller's size checks them
/// (a length scaled to the edge of the range of numbers may no longer show what was
/// wrong with it: two lengths beyond it become one).
fn remesh_at_scale(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    feature_edges: &[[u32; 2]],
    (options, caller): (&RemeshOptions, &RemeshOptions),
    progress: impl FnMut(usize, usize) -> ControlFlow<()>,
) -> Result<(HalfedgeMesh, Vec<DVec3>, RemeshReport), RemeshError> {
    let given = given_edges(mesh, feature_edges)?;
    let mut edit = EditMesh::from_mesh(mesh, positions)?;
    let (mean_before, cv_before) = edge_length_stats(&edit);
    let total_area: f64 = edit.faces().map(|f| face_area(&edit, f)).sum();
    if mesh.n_faces() == 0 || !is_positive(mean_before) {
        return Err(RemeshError::Empty);
    }
    if !is_positive(total_area) {
        return Err(RemeshError::NoArea);
    }
    target_length(caller, mean_before)?;
    let target = target_length(options, mean_before)?;
    let feature = edit.add_edge_property("remesh:feature", false)?;
    let corner = edit.add_vertex_property("remesh:corner", false)?;
    let corner_angle = options.feature_angle.unwrap_or(DEFAULT_CORNER_ANGLE);
    let found = curves::detect(
        &mut edit,
        feature,
        corner,
        options.feature_angle,
        corner_angle,
        &given,
    );
    // A given edge that is not sharp (a datum line on a smooth surface) is no crease:
    // the smooth surface runs across it as it does without it, and its vertices are
    // lifted onto that surface as the others are.
    let given_only = |e: EdgeId| {
        given.get(e.index()).copied().unwrap_or(false)
            && !mesh.is_boundary_edge(e)
            && !options
                .feature_angle
                .is_some_and(|a| curves::dihedral(&edit, e) > a)
    };
    let crease: Vec<bool> = {
        let flags = edit.values(feature);
        mesh.edges()
            .map(|e| flags[e.index()] && !given_only(e))
            .collect()
    };
    let curves = curves::CurveIndex::new(&edit, mesh, feature, |e| crease[e.index()]);
    let phong = (options.projection && options.smooth_projection)
        .then(|| PhongSurface::new(mesh, positions, |e| crease[e.index()]));
    let index = SurfaceIndex::new(mesh, positions)?;
    // Lengths far beyond the surface's extent act alike (every edge is short, no edge
    // long); capped, their squares (the relaxation's weights) stay finite.
    let cap = MAX_SIZING_SHARE * face_extent(&edit);
    let sizing = edit.add_vertex_property("remesh:sizing", target.min(cap))?;
    let mut reference = None;
    let mut target = target;
    let mut adaptive = None;
    if let EdgeLength::Adaptive(given) = options.edge_length {
        let curvature = sizing::curvature_field(&edit, feature);
        let lengths = sizing::resolve(given, &curvature, mean_before);
        let mut field = sizing::lengths(&curvature, lengths);
        target = mean(&field);
        for x in &mut field {
            *x = x.min(cap);
        }
        for v in mesh.vertices() {
            edit.set(sizing, v, field[v.index()]);
        }
        reference = Some(field);
        adaptive = Some(lengths);
    }
    check_result_size(&edit, sizing)?;
    let guard = DegeneracyGuard::new(&edit, target);

    let mut remesher = Remesher {
        mesh: edit,
        feature,
        corner,
        sizing,
        surface: options.projection.then_some(&index),
        reference: if options.projection { reference } else { None },
        curves,
        phong,
    };
    let mut report = RemeshReport {
        target_edge_length: target,
        adaptive,
        vertices_before: mesh.n_vertices(),
        faces_before: mesh.n_faces(),
        mean_edge_length_before: mean_before,
        edge_length_cv_before: cv_before,
        feature_edges: found.feature_edges,
        given_feature_edges: found.given_edges,
        fold_edges: found.fold_edges,
        boundary_edges: found.boundary_edges,
        corners: found.corners,
        degenerate_faces_before: guard.input_faces,
        degenerate_faces: guard.input_faces,
        ..RemeshReport::default()
    };
    run_passes(
        &mut remesher,
        options.iterations,
        &guard,
        &mut report,
        progress,
    )?;
    let mut edit = remesher.mesh;
    edit.remove_property(feature);
    edit.remove_property(corner);
    edit.remove_property(sizing);
    edit.garbage_collection();
    (report.mean_edge_length, report.edge_length_cv) = edge_length_stats(&edit);
    let (out, out_positions) = edit.into_mesh()?;
    measure_result(&out, &out_positions, (mesh, positions), &index, &mut report)?;
    Ok((out, out_positions, report))
}

/// The edges `feature_edges` name (pairs of vertices of `mesh`), flagged by edge id.
///
/// # Errors
/// [`RemeshError::FeatureEdge`] for the first pair that is not an edge.
fn given_edges(mesh: &HalfedgeMesh, feature_edges: &[[u32; 2]]) -> Result<Vec<bool>, RemeshError> {
    if feature_edges.is_empty() {
        return Ok(Vec::new());
    }
    let n = mesh.n_vertices();
    let mut given = vec![false; mesh.n_edges()];
    for (index, &[a, b]) in feature_edges.iter().enumerate() {
        let refuse = |why: String| RemeshError::FeatureEdge {
            index,
            a: u64::from(a),
            b: u64::from(b),
            why,
        };
        if let Some(&v) = [a, b].iter().find(|&&v| v as usize >= n) {
            return Err(refuse(format!("vertex {v} is out of range ({n} vertices)")));
        }
        let h = mesh
            .find_halfedge(VertexId::new(a), VertexId::new(b))
            .ok_or_else(|| refuse("no edge joins them".to_string()))?;
        given[h.edge().index()] = true;
    }
    Ok(given)
}

/// The multiple of the extent of the input's triangles (their bounding box diagonal) at
/// which the target length at a vertex is capped. A target beyond the surface's
/// extent makes every edge short and none long, so the runs do the same at any such
/// length; the cap keeps the relaxation's weights (areas over squared lengths) from
/// vanishing when a length's square overflows (about 1.3e154 and up), which let a
/// sphere collapse into a sliver tetrahedron instead of being refused.
const MAX_SIZING_SHARE: f64 = 1e3;

/// The mean of `values` (not empty), without overflow for values near `f64::MAX`.
fn mean(values: &[f64]) -> f64 {
    let n = values.len() as f64;
    let sum = values.iter().sum::<f64>();
    if sum.is_finite() {
        sum / n
    } else {
        values.iter().map(|x| x / n).sum()
    }
}

/// The share of the input's bounding box diagonal below which the result's triangles'
/// extent means the surface was drawn together ([`RemeshError::Shrunk`]). A tetrahedron
/// inscribed in a sphere keeps 0.58 of the sphere's; the 8-vertex cube remeshed at its
/// own mean edge length without feature edges drew together to 0.09 of its diagonal in
/// 10 iterations, and at 0.7 of it to 0.01.
pub const MIN_EXTENT_SHARE: f64 = 0.25;

/// What the remesher watches for after every iteration: many faces that are degenerate
/// ([`degenerate_faces`]) beyond the input's count, or a surface drawn together into a
/// small solid, mean the target is too long for the surface
/// ([`RemeshError::Degenerate`], [`RemeshError::Shrunk`]); stopping at once also stops
/// the runaway of splits that degenerate faces start.
struct DegeneracyGuard {
    /// The length below which a face whose every edge is shorter counts as a point:
    /// `10⁻⁹` times the input's bounding box diagonal.
    point: f64,
    /// Degenerate faces of the input.
    input_faces: usize,
    /// The (mean) target edge length, for the error.
    edge_length: f64,
    /// The input's bounding box diagonal, for the error.
    diagonal: f64,
}

impl DegeneracyGuard {
    /// The guard of a run on `input` (whose editable copy is `edit`) towards
    /// `edge_length`.
    fn new(edit: &EditMesh, edge_length: f64) -> Self {
        // The triangles' extent, as for the result: isolated vertices are no part of
        // the surface (and stay where they are).
        let diagonal = face_extent(edit);
        let point = 1e-9 * diagonal;
        Self {
            point,
            input_faces: degenerate_faces(edit, point),
            edge_length,
            diagonal,
        }
    }

    /// [`RemeshError::Degenerate`] when more than a tenth of `mesh`'s faces are
    /// degenerate ones beyond the input's count. A few such faces come and go on noisy
    /// input with sharp features (later passes remove them); a tenth and more is a
    /// surface drawn together, or a runaway of splits.
    ///
    /// [`RemeshError::Shrunk`] when the extent of `mesh`'s triangles is at most
    /// [`MIN_EXTENT_SHARE`] of the input's.
    ///
    /// Returns the number of degenerate faces of `mesh` otherwise.
    fn check(&self, mesh: &EditMesh) -> Result<usize, RemeshError> {
        let extent = face_extent(mesh);
        if extent <= MIN_EXTENT_SHARE * self.diagonal {
            return Err(RemeshError::Shrunk {
                extent,
                diagonal: self.diagonal,
                edge_length: self.edge_length,
            });
        }
        let faces = degenerate_faces(mesh, self.point);
        let new = faces.saturating_sub(self.input_faces);
        if new == 0 || new * 10 <= mesh.n_faces() {
            return Ok(faces);
        }
        Err(RemeshError::Degenerate {
            faces,
            input_faces: self.input_faces,
            total: mesh.n_faces(),
            edge_length: self.edge_length,
            diagonal: self.diagonal,
        })
    }
}

/// What the [`RemeshError::Degenerate`] message advises: a shorter target edge length,
/// or, when the input has degenerate faces of its own, those first (remeshing splits a
/// flat triangle into more flat ones at any length).
fn degenerate_advice(input_faces: usize, edge_length: f64, diagonal: f64) -> String {
    if input_faces > 0 {
        let also = if edge_length > 0.05 * diagonal {
            format!(
                " (a target edge length of {} for a bounding box diagonal of {diagonal:.6} may be too long as well)",
                short(edge_length)
            )
        } else {
            String::new()
        };
        format!(
            "the input's own degenerate faces (flat for their size, such as a stray collinear triangle) are split into more at any target length; remove them from the input first (`remove_flat_triangles`; on the command line `beltrami repair IN OUT --flat-faces`){also}"
        )
    } else {
        format!(
            "a target edge length of {} is too long for this surface, whose bounding box diagonal is {diagonal:.6}; use a shorter one",
            short(edge_length)
        )
    }
}

/// The bounding box diagonal of the corners of `mesh`'s triangles (isolated vertices
/// left out); 0 without triangles.
fn face_extent(mesh: &EditMesh) -> f64 {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for f in mesh.faces() {
        for v in mesh.vertices_around_face(f) {
            lo = lo.min(mesh.position(v));
            hi = hi.max(mesh.position(v));
        }
    }
    if lo.x <= hi.x { lo.distance(hi) } else { 0.0 }
}

/// The triangles of `mesh` that are flat for their size (twice the area at most
/// [`DEGENERACY_RATIO`] times the longest edge squared, the test of
/// `Geometry::is_degenerate_face`) or drawn into a point (every edge shorter than
/// `point`, which the relative test alone lets pass as a well-shaped tiny triangle).
/// Counted on rayon's threads.
fn degenerate_faces(mesh: &EditMesh, point: f64) -> usize {
    (0..mesh.face_capacity())
        .into_par_iter()
        .filter(|&i| {
            let f = FaceId::new(i as u32);
            if !mesh.is_live_face(f) {
                return false;
            }
            let h = mesh.face_halfedge(f);
            let [a, b, c] = [
                mesh.from_vertex(h),
                mesh.to_vertex(h),
                mesh.to_vertex(mesh.next(h)),
            ]
            .map(|v| mesh.position(v));
            let longest = (b - a)
                .length_squared()
                .max((c - b).length_squared())
                .max((a - c).length_squared());
            let twice_area = (b - a).cross(c - a).length();
            twice_area <= DEGENERACY_RATIO * longest || longest < point * point
        })
        .count()
}

/// Refuses a target so small for the surface's area that the result would have more
/// than [`MAX_REMESH_FACES`] faces, estimated before any work: each face's area over
/// that of an equilateral triangle of its smallest corner's target length.
fn check_result_size(edit: &EditMesh, sizing: VertexProperty<f64>) -> Result<(), RemeshError> {
    let predicted: f64 = edit
        .faces()
        .map(|f| {
            let size = edit
                .vertices_around_face(f)
                .map(|v| *edit.get(sizing, v))
                .fold(f64::INFINITY, f64::min);
            face_area(edit, f) / (3f64.sqrt() / 4.0 * size * size)
        })
        .sum();
    if predicted.is_nan() || predicted > MAX_REMESH_FACES as f64 {
        return Err(RemeshError::TooManyFaces {
            edge_length: edit
                .values(sizing)
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min),
            predicted,
            max: MAX_REMESH_FACES,
        });
    }
    Ok(())
}

/// The area of face `f` (a triangle).
fn face_area(edit: &EditMesh, f: FaceId) -> f64 {
    curves::triangle_normal(edit, edit.face_halfedge(f)).length() / 2.0
}

/// The share of the iterations, from the first, whose collapse step may collapse an edge
/// into its midpoint. Those collapses even out uneven triangles, nearly all in the first
/// two or three iterations (the scan-like sphere: 18 478, 1 827, 496, 176, then under a
/// hundred per iteration). On a mesh already near the target length they go on at a
/// steady rate instead (the golf ball: 36 to 70 in every iteration), each leaving a 5–7
/// pair that no flip removes: 108 vertices of valence other than 6 with midpoints in 4
/// of 10 iterations, 114 in 5, 132 in 7 to 10.
const MIDPOINT_SHARE: f64 = 0.4;

/// How many of `iterations`, from the first, collapse into midpoints: the
/// [`MIDPOINT_SHARE`], rounded up (at least one).
fn midpoint_iterations(iterations: usize) -> usize {
    ((iterations as f64 * MIDPOINT_SHARE).ceil() as usize).max(1)
}

/// `iterations` rounds of split, collapse, flip and relax, then the removal of caps,
/// counted into `report`; `guard` checks the mesh after each round and at the end.
fn run_passes(
    remesher: &mut Remesher<'_>,
    iterations: usize,
    guard: &DegeneracyGuard,
    report: &mut RemeshReport,
    mut progress: impl FnMut(usize, usize) -> ControlFlow<()>,
) -> Result<(), RemeshError> {
    let with_midpoints = midpoint_iterations(iterations);
    for done in 1..=iterations {
        let splits = remesher.split_long_edges()?;
        let collapses = remesher.collapse_short_edges(done <= with_midpoints)?;
        let flips = remesher.flip_edges()?;
        remesher.relax()?;
        report.degenerate_faces = guard.check(&remesher.mesh)?;
        report.iterations.push(RemeshIteration {
            splits,
            collapses,
            flips,
        });
        report.splits += splits;
        report.collapses += collapses;
        report.flips += flips;
        if progress(done, iterations).is_break() {
            return Err(RemeshError::Stopped {
                done,
                total: iterations,
            });
        }
    }
    if !report.iterations.is_empty() {
        let caps = remesher.remove_caps()?;
        report.flips += caps;
        report.cap_flips = caps;
        report.degenerate_faces = guard.check(&remesher.mesh)?;
    }
    Ok(())
}

/// The result's counts and the distances at the vertices (those in a face) between it
/// and the input (`input`, indexed as `index`), both ways, into `report`.
fn measure_result(
    out: &HalfedgeMesh,
    out_positions: &[DVec3],
    input: (&HalfedgeMesh, &[DVec3]),
    index: &SurfaceIndex,
    report: &mut RemeshReport,
) -> Result<(), RemeshError> {
    report.vertices = out.n_vertices();
    report.faces = out.n_faces();
    let on_surface = |mesh: &HalfedgeMesh, positions: &[DVec3]| -> Vec<DVec3> {
        mesh.vertices()
            .filter(|&v| !mesh.is_isolated(v))
            .map(|v| positions[v.index()])
            .collect()
    };
    let largest = |d: Vec<f64>| d.into_iter().fold(0.0, f64::max);
    report.hausdorff = largest(index.distances(&on_surface(out, out_positions))?);
    if out.n_faces() > 0 {
        let result = SurfaceIndex::new(out, out_positions)?;
        report.hausdorff_from_input = largest(result.distances(&on_surface(input.0, input.1))?);
    }
    Ok(())
}
