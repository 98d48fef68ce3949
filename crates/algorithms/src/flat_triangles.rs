//! Removal of flat triangles: triangles whose height is a vanishing part of their longest
//! edge (three collinear corners, a corner on the opposite edge, two or three corners at
//! one point), by edits that leave the surface where it is.
//!
//! Scans and CAD exports carry such slivers: a T-junction closed by a zero-area
//! triangle, a vertex welded twice. Their angles are 0° and 180°, so their cotangent
//! weights are unbounded (the Laplacian treats them as absent and their vertices may
//! not move), their normals are undefined, and remeshing splits one into more. Each is
//! removed by the edit its shape calls for, as CGAL's `remove_degenerate_faces` does:
//!
//! - a **cap** (one corner on the opposite, longest edge): that edge is flipped, which
//!   replaces the cap and its neighbour by two triangles covering the same area (the cap
//!   has none), so the surface does not move; on the boundary, where there is no
//!   neighbour, the cap is deleted when its middle corner can become a boundary vertex
//!   (the boundary then runs through that corner, along the same line); a flat
//!   triangle alone, a component of no area, is deleted with its corners;
//! - a **needle** (two corners at one point): its shortest edge, of length 0, is
//!   collapsed into the endpoint on the boundary (either otherwise). With
//!   [`FlatOptions::max_move`] a longer edge may be collapsed too (a cap whose flip would
//!   make another flat triangle or fold), moving one vertex by up to that distance, when
//!   no triangle around it folds over or turns against its neighbours.
//!
//! Every test is made on each triangle's edge vectors divided by their largest
//! component, so that what counts as flat, and which edit is allowed, does not depend on
//! the unit: a mesh in metres of 10⁻¹⁷⁰ or 10³⁰⁰ gives the same edits as in millimetres.

use std::collections::VecDeque;

use beltrami_halfedge::geometry::{DEGENERACY_RATIO, distance};
use beltrami_halfedge::{
    DVec3, EditMesh, FaceId, HalfedgeId, HalfedgeMesh, TopologyError, VertexId,
};

use crate::error::{algorithm_error, check_finite, check_mesh, short};

/// The settings of [`remove_flat_triangles`].
///
/// # Examples
/// ```
/// use beltrami_algorithms::FlatOptions;
/// let options = FlatOptions::default().max_height_ratio(1e-9);
/// assert_eq!(options.max_height_ratio, 1e-9);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct FlatOptions {
    /// A triangle is flat when its height over its longest edge is at most this share
    /// of that edge (twice its area at most `max_height_ratio × longest²`). Default
    /// [`DEGENERACY_RATIO`] (10⁻¹²), the triangles cotangent weights treat as absent;
    /// larger values also take near-slivers, whose cotangents are large but finite, and
    /// whose flip or deletion then moves the surface by up to their height
    /// ([`FlatReport::max_height`]). In `[0, MAX_HEIGHT_RATIO]`.
    pub max_height_ratio: f64,
    /// The longest distance a collapse may move a vertex, in the positions' unit
    /// (default 0: only edges of zero length are collapsed, and the surface does not
    /// move). A flat triangle that neither a flip nor a deletion removes (its longest edge
    /// already has a diagonal, or its neighbour is flat too) then stays, unless a
    /// collapse of one of its two shorter edges within this distance does (the shortest
    /// first); such a collapse moves the vertex's other triangles with it.
    pub max_move: f64,
}

impl Default for FlatOptions {
    fn default() -> Self {
        Self {
            max_height_ratio: DEGENERACY_RATIO,
            max_move: 0.0,
        }
    }
}

/// The largest [`FlatOptions::max_height_ratio`]: a tenth, a cap whose largest angle is
/// about 157°. Beyond it sound triangles would count as flat (an equilateral one has a
/// ratio of 0.87).
pub const MAX_HEIGHT_RATIO: f64 = 0.1;

impl FlatOptions {
    /// Checks the options: [`FlatError::Options`] for a height ratio outside
    /// `[0, MAX_HEIGHT_RATIO]` or a negative or NaN longest move.
    ///
    /// # Errors
    /// [`FlatError::Options`], naming the option.
    pub fn check(&self) -> Result<(), FlatError> {
        let ratio = self.max_height_ratio;
        if !(0.0..=MAX_HEIGHT_RATIO).contains(&ratio) {
            return Err(FlatError::Options {
                reason: format!(
                    "the largest height ratio of a flat triangle must be between 0 and {MAX_HEIGHT_RATIO}, got {}",
                    short(ratio)
                ),
            });
        }
        if self.max_move.is_nan() || self.max_move < 0.0 {
            return Err(FlatError::Options {
                reason: format!(
                    "the longest move of a collapse must be >= 0, got {}",
                    short(self.max_move)
                ),
            });
        }
        Ok(())
    }

    /// Sets the largest height ratio of a flat triangle.
    #[must_use]
    pub fn max_height_ratio(mut self, ratio: f64) -> Self {
        self.max_height_ratio = ratio;
        self
    }

    /// Sets the longest distance a collapse may move a vertex.
    #[must_use]
    pub fn max_move(mut self, distance: f64) -> Self {
        self.max_move = distance;
        self
    }
}

/// What [`remove_flat_triangles`] did.
#[derive(Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct FlatReport {
    /// Flat triangles of the input.
    pub flat_before: usize,
    /// Flat triangles left: no flip, deletion or collapse within
    /// [`FlatOptions::max_move`] could remove them without folding a triangle over or
    /// changing the topology.
    pub flat_after: usize,
    /// Edges flipped (caps).
    pub flips: usize,
    /// Caps on the boundary deleted.
    pub deleted: usize,
    /// Flat triangles alone (components of their own) deleted.
    pub alone: usize,
    /// Edges collapsed (needles).
    pub collapses: usize,
    /// The longest distance a collapse moved a vertex, in the positions' unit (0 without
    /// collapses, and for collapses of zero-length edges).
    pub max_move: f64,
    /// The largest height of a triangle flipped away or deleted, in the positions' unit:
    /// those edits moved the surface by at most this (within rounding of 0 at the
    /// default height ratio).
    pub max_height: f64,
    /// For each output vertex, the input vertex it is (vertices are renumbered in order
    /// when collapses, or deletions of flat triangles alone, remove some).
    pub vertex_origin: Vec<usize>,
}

algorithm_error! {
    /// Why [`remove_flat_triangles`] could not run. Every variant names the offending
    /// element or value.
    #[derive(Debug, Clone, PartialEq, thiserror::Error)]
    #[non_exhaustive]
    pub enum FlatError for "removing flat triangles" {
        /// An edit the checks allowed was refused: a defect of this crate, reported
        /// rather than panicking.
        #[error("the edited mesh is not valid: {0}")]
        Edit(#[from] beltrami_halfedge::EditError),
        /// The input or the result did not convert between the frozen and the editable
        /// mesh.
        #[error("{0}")]
        Topology(#[from] TopologyError),
    }
}

/// Removes the flat triangles of a triangle mesh (zero-area slivers, which scans and CAD
/// exports carry; their cotangent weights are unbounded and remeshing splits each into
/// more): caps, whose middle corner lies on the longest edge, by flipping that edge (or,
/// on the boundary, by deleting them; a flat triangle alone is deleted too), needles,
/// two corners at one point, by collapsing their shortest edge. Flips, deletions and collapses of zero-length
/// edges leave every point of the surface where it was; with [`FlatOptions::max_move`]
/// a collapse may move one vertex by up to that distance ([`FlatReport::max_move`] says
/// how far they did), and only when the edits that move nothing are stuck. An edit is
/// made only when no triangle it creates or moves is flat or turned over against its
/// neighbours, and the topology is kept (closed stays closed, the genus and the boundary
/// loops stay; only a flat triangle alone, a component of no area, is deleted), so a few
/// triangles may stay flat ([`FlatReport::flat_after`]). Isolated vertices are kept.
///
/// Returns the mesh, its positions (the input's, less collapsed vertices, renumbered in
/// order; [`FlatReport::vertex_origin`] maps them back) and the report. A mesh without
/// flat triangles comes back unchanged.
///
/// # References
/// - M. Botsch, L. Kobbelt, M. Pauly, P. Alliez, B. Lévy, *Polygon Mesh Processing*,
///   A K Peters 2010, section 4.3 (caps and needles, removed by a flip and a collapse).
/// - CGAL, Polygon Mesh Processing, `remove_degenerate_faces` (the same edits, with the
///   boundary cases).
///
/// # Errors
/// [`FlatError::PositionCount`] when `positions` does not match the mesh;
/// [`FlatError::NotTriangle`] when a face is not a triangle;
/// [`FlatError::NonFinite`] for a non-finite position;
/// [`FlatError::Options`] for options [`FlatOptions::check`] refuses.
///
/// # Examples
/// ```
/// use beltrami_algorithms::{remove_flat_triangles, FlatOptions};
/// use beltrami_halfedge::{DVec3, HalfedgeMesh};
///
/// // A square whose diagonal carries a vertex at its midpoint, closed by a cap.
/// let positions = vec![
///     DVec3::new(0.0, 0.0, 0.0),
///     DVec3::new(1.0, 0.0, 0.0),
///     DVec3::new(1.0, 1.0, 0.0),
///     DVec3::new(0.0, 1.0, 0.0),
///     DVec3::new(0.5, 0.5, 0.0),
/// ];
/// let faces = [[0u32, 1, 4], [1, 2, 4], [0, 2, 3], [0, 4, 2]];
/// let mesh = HalfedgeMesh::from_polygons(positions.len(), faces)?;
/// let (out, out_positions, report) =
///     remove_flat_triangles(&mesh, &positions, FlatOptions::default())?;
/// assert_eq!((report.flat_before, report.flat_after, report.flips), (1, 0, 1));
/// assert_eq!(out_positions, positions); // a flip moves nothing
/// assert_eq!(out.n_faces(), 4);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn remove_flat_triangles(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    options: FlatOptions,
) -> Result<(HalfedgeMesh, Vec<DVec3>, FlatReport), FlatError> {
    check_mesh(mesh, positions)?;
    check_finite(positions)?;
    options.check()?;
    let ratio = options.max_height_ratio;
    let mut edit = EditMesh::from_mesh(mesh, positions)?;
    let flat_faces =
        |m: &EditMesh| -> Vec<FaceId> { m.faces().filter(|&f| is_flat(m, f, ratio)).collect() };
    let mut queue: VecDeque<FaceId> = flat_faces(&edit).into();
    let mut report = FlatReport {
        flat_before: queue.len(),
        ..FlatReport::default()
    };
    if queue.is_empty() {
        report.vertex_origin = (0..mesh.n_vertices()).collect();
        return Ok((mesh.clone(), positions.to_vec(), report));
    }
    // Every edit removes a flat triangle or replaces it by sound ones; the bound only
    // guards against a cycle of flips on a pathological input.
    let mut budget = 10 * edit.n_faces() + 100;
    // First the edits that move nothing (flips, deletions, collapses of zero-length
    // edges), as long as any applies: a cap beside a needle can be flipped once the
    // needle is gone. The faces they cannot fix wait in `stuck`; only when nothing else
    // is left may a collapse move a vertex (one at a time), after which the faces it
    // touched go through the edits that move nothing first again. Each edit queues the
    // faces around it, so a face waits only until something next to it changes.
    let mut stuck: VecDeque<FaceId> = VecDeque::new();
    'edits: while budget > 0 {
        while let Some(f) = queue.pop_front() {
            if budget == 0 {
                break 'edits;
            }
            if !edit.is_live_face(f) || !is_flat(&edit, f, ratio) {
                continue;
            }
            match fix(&mut edit, f, ratio, 0.0, &mut report)? {
                Some(touched) => {
                    budget -= 1;
                    queue.extend(touched);
                }
                None => stuck.push_back(f),
            }
        }
        if options.max_move == 0.0 {
            break;
        }
        loop {
            let Some(f) = stuck.pop_front() else {
                break 'edits;
            };
            if !edit.is_live_face(f) || !is_flat(&edit, f, ratio) {
                continue;
            }
            if let Some(touched) = fix(&mut edit, f, ratio, options.max_move, &mut report)? {
                budget -= 1;
                queue.extend(touched);
                continue 'edits;
            }
        }
    }
    report.flat_after = flat_faces(&edit).len();
    report.vertex_origin = (0..edit.vertex_capacity())
        .filter(|&i| edit.is_live_vertex(VertexId::new(i as u32)))
        .collect();
    let (out, out_positions) = edit.into_mesh()?;
    Ok((out, out_positions, report))
}

/// Whether live triangle `f` is flat: twice its area at most `ratio × longest²`.
fn is_flat(mesh: &EditMesh, f: FaceId, ratio: f64) -> bool {
    let [a, b, c] = corners(mesh, mesh.face_halfedge(f));
    flat(a, b, c, ratio)
}

/// The largest absolute coordinate of `vectors` (0 for zero vectors; not finite when a
/// difference overflowed).
fn magnitude(vectors: &[DVec3]) -> f64 {
    vectors
        .iter()
        .map(|v| v.abs().max_element())
        .fold(0.0, f64::max)
}

/// The edge vectors `b − a` and `c − a` of a triangle divided by the largest coordinate
/// of its three edges, and that coordinate: the scale-free shape the tests below use.
/// `None` when the corners coincide or a difference overflowed.
fn shape(a: DVec3, b: DVec3, c: DVec3) -> Option<(DVec3, DVec3, f64)> {
    let (u, v) = (b - a, c - a);
    let m = magnitude(&[u, v, c - b]);
    (m > 0.0 && m.is_finite()).then(|| (u / m, v / m, m))
}

/// Whether the triangle `(a, b, c)` is flat: twice its area at most `ratio` times its
/// longest edge squared, at any scale. Three corners at one point are flat; a triangle
/// whose edge overflows is not (nothing can be decided about it).
fn flat(a: DVec3, b: DVec3, c: DVec3, ratio: f64) -> bool {
    let Some((u, v, _)) = shape(a, b, c) else {
        return a == b && b == c;
    };
    let longest = u
        .length_squared()
        .max(v.length_squared())
        .max((v - u).length_squared());
    u.cross(v).length() <= ratio * longest
}

/// The height of the triangle `(a, b, c)` over its longest edge (0 for coincident
/// corners), at any scale.
fn height(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let Some((u, v, m)) = shape(a, b, c) else {
        return 0.0;
    };
    let longest = u.length().max(v.length()).max((v - u).length());
    m * u.cross(v).length() / longest
}

/// A normal of the triangle `(a, b, c)` (its direction; the length is of no meaning),
/// zero when the corners coincide, at any scale.
fn normal(a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    shape(a, b, c).map_or(DVec3::ZERO, |(u, v, _)| u.cross(v))
}

/// The positions of the corners of the triangle of `h`: from, to, and the third.
fn corners(mesh: &EditMesh, h: HalfedgeId) -> [DVec3; 3] {
    [
        mesh.position(mesh.from_vertex(h)),
        mesh.position(mesh.to_vertex(h)),
        mesh.position(mesh.to_vertex(mesh.next(h))),
    ]
}

/// Removes flat triangle `f` by one edit, if one is allowed (a collapse only when it
/// moves a vertex by at most `max_move`). Returns the faces to look at again, or `None` when
/// no edit was made.
fn fix(
    mesh: &mut EditMesh,
    f: FaceId,
    ratio: f64,
    max_move: f64,
    report: &mut FlatReport,
) -> Result<Option<Vec<FaceId>>, FlatError> {
    let h0 = mesh.face_halfedge(f);
    let hs = [h0, mesh.next(h0), mesh.prev(h0)];
    let edge_length = |h: HalfedgeId| {
        distance(
            mesh.position(mesh.from_vertex(h)),
            mesh.position(mesh.to_vertex(h)),
        )
    };
    let mut by_length = hs;
    by_length.sort_by(|&x, &y| edge_length(x).total_cmp(&edge_length(y)));
    let [shortest, _, longest] = by_length;
    let [a, b, c] = corners(mesh, h0);
    let h = height(a, b, c);

    // A flat triangle alone (a component of no area): deleted, with its corners.
    if hs.iter().all(|&g| mesh.is_boundary_halfedge(g.twin())) {
        mesh.delete_face(f)?;
        report.alone += 1;
        report.max_height = report.max_height.max(h);
        return Ok(Some(Vec::new()));
    }
    // A cap: flip the longest edge, or delete the cap on the boundary.
    let twin = longest.twin();
    if mesh.is_boundary_halfedge(twin) {
        let middle = mesh.to_vertex(mesh.next(longest));
        if !mesh.is_boundary_vertex(middle) {
            let neighbours = faces_around(mesh, middle);
            mesh.delete_face(f)?;
            report.deleted += 1;
            report.max_height = report.max_height.max(h);
            return Ok(Some(neighbours));
        }
    } else if flip_is_sound(mesh, longest, ratio) {
        mesh.flip_edge(longest.edge())?;
        report.flips += 1;
        report.max_height = report.max_height.max(h);
        let mut touched = vec![f];
        touched.extend(mesh.face(twin));
        for h in [longest, twin] {
            for k in [mesh.next(h), mesh.prev(h)] {
                touched.extend(mesh.face(k.twin()));
            }
        }
        return Ok(Some(touched));
    }

    // A needle (or a cap that could not be flipped): collapse the shortest edge that
    // folds nothing, into its endpoint on the boundary.
    for h in [shortest, by_length[1]] {
        for g in [h, h.twin()] {
            let (from, to) = (mesh.from_vertex(g), mesh.to_vertex(g));
            if mesh.is_boundary_vertex(from) && !mesh.is_boundary_vertex(to) {
                continue;
            }
            // A tetrahedron collapsed would be a closed pair of triangles back to back.
            if !mesh.is_collapse_ok(g)
                || mesh.collapse_flattens_tetrahedron(g)
                || !collapse_is_sound(mesh, g, ratio)
            {
                continue;
            }
            let moved = distance(mesh.position(from), mesh.position(to));
            if moved > max_move {
                continue;
            }
            let kept = mesh.collapse_edge(g)?;
            report.collapses += 1;
            report.max_move = report.max_move.max(moved);
            return Ok(Some(faces_around(mesh, kept)));
        }
    }
    Ok(None)
}

/// The live faces around `v`.
fn faces_around(mesh: &EditMesh, v: beltrami_halfedge::VertexId) -> Vec<FaceId> {
    mesh.halfedges_around_vertex(v)
        .filter_map(|h| mesh.face(h))
        .collect()
}

/// Whether flipping the edge of `h` (interior) is allowed and makes two triangles that
/// are not flat and face the way the neighbour across the edge does.
fn flip_is_sound(mesh: &EditMesh, h: HalfedgeId, ratio: f64) -> bool {
    if !mesh.is_flip_ok(h.edge()) {
        return false;
    }
    let twin = h.twin();
    let [v0, v1, a] = corners(mesh, h);
    let b = mesh.position(mesh.to_vertex(mesh.next(twin)));
    // The neighbour (v1, v0, b) gives the side the surface faces.
    let reference = normal(v1, v0, b);
    // The flip makes (a, b, v1) and (b, a, v0).
    [[a, b, v1], [b, a, v0]]
        .iter()
        .all(|&[p, q, r]| !flat(p, q, r, ratio) && normal(p, q, r).dot(reference) > 0.0)
}

/// Whether collapsing `h` (moving its start onto its end) leaves every triangle around
/// the start that survives either flat (if it was) or sound and facing the way its
/// neighbours do: a triangle sound before stays sound and keeps its side, and every sound
/// one afterwards faces the side of the sound triangles around the start before (a flat
/// one moved must not open folded over). A collapse that moves nothing changes no
/// triangle's shape.
fn collapse_is_sound(mesh: &EditMesh, h: HalfedgeId, ratio: f64) -> bool {
    let (from, to) = (mesh.from_vertex(h), mesh.to_vertex(h));
    let (start, target) = (mesh.position(from), mesh.position(to));
    if start == target {
        return true;
    }
    // The triangles around the start that survive: (start, b, c).
    let survivors: Vec<(DVec3, DVec3)> = mesh
        .halfedges_around_vertex(from)
        .filter(|&g| mesh.face(g).is_some())
        .map(|g| (mesh.to_vertex(g), mesh.to_vertex(mesh.next(g))))
        // The triangles at the edge itself disappear.
        .filter(|&(b, c)| b != to && c != to)
        .map(|(b, c)| (mesh.position(b), mesh.position(c)))
        .collect();
    let unit = |n: DVec3| n.try_normalize().unwrap_or(DVec3::ZERO);
    let side: DVec3 = survivors
        .iter()
        .filter(|&&(q, r)| !flat(start, q, r, ratio))
        .map(|&(q, r)| unit(normal(start, q, r)))
        .sum();
    survivors.iter().all(|&(q, r)| {
        let was_flat = flat(start, q, r, ratio);
        // A flat triangle may stay flat (it is removed later); a sound one may not
        // become flat.
        if flat(target, q, r, ratio) {
            return was_flat;
        }
        let after = normal(target, q, r);
        let kept_side = was_flat || after.dot(normal(start, q, r)) > 0.0;
        kept_side && after.dot(side) > 0.0
    })
}
