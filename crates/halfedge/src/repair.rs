//! Repairing a polygon soup into a face list that builds: [`repair`].
//!
//! Where [`HalfedgeMesh::build`] repairs while building (and keeps the input's vertex
//! numbering), [`repair`] works on the soup itself and returns a cleaned soup,
//! positions included, that a user can write to a file and that
//! [`HalfedgeMesh::from_polygons`] accepts. Every change is recorded per element, in
//! input indices, in a [`RepairReport`].

use std::collections::{HashMap, VecDeque};
use std::fmt;

use glam::DVec3;
use petgraph::unionfind::UnionFind;
use rayon::prelude::*;

use crate::build::{Corners, check_count, repeated_vertex};
use crate::error::TopologyError;
use crate::mesh::{HalfedgeMesh, INVALID};
use crate::polygons::PolygonList;

/// Options of [`repair`].
///
/// The default applies every topological repair (see [`repair`] for the list) and
/// merges no vertices. The topological repairs cannot be switched off one by one: each
/// is needed for the result to build. To see the problems of a face list as errors
/// instead, build it with [`HalfedgeMesh::from_polygons`].
///
/// # Examples
/// ```
/// use beltrami_halfedge::RepairOptions;
/// let options = RepairOptions::new()
///     .merge_distance(Some(1e-6))
///     .drop_unreferenced(false);
/// assert_eq!(options.merges_within(), Some(1e-6));
/// assert!(!options.drops_unreferenced());
/// assert!(options.cuts_non_orientable());
/// assert_eq!(RepairOptions::default().merges_within(), None);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct RepairOptions {
    merge_distance: Option<f64>,
    drop_unreferenced: bool,
    cut_non_orientable: bool,
    orient_outward: bool,
    triangulate: bool,
}

impl Default for RepairOptions {
    /// Every topological repair, no merging, unreferenced vertices removed, a
    /// non-orientable component cut open.
    fn default() -> Self {
        Self {
            merge_distance: None,
            drop_unreferenced: true,
            cut_non_orientable: true,
            orient_outward: true,
            triangulate: false,
        }
    }
}

impl RepairOptions {
    /// The default options (the same as [`RepairOptions::default`]).
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Merge vertices closer than `distance` (absolute, in mesh units; `None`, the
    /// default, merges nothing).
    ///
    /// The rule is greedy in vertex order, so that nothing chains: vertex `v` merges
    /// into the lowest-numbered vertex before it that was not itself merged and lies
    /// within `distance` of it (Euclidean, `|p_v − p_t| ≤ distance`). Every merged
    /// vertex is therefore within `distance` of the vertex it merged into, whose
    /// position is kept unchanged (no averaging), and the vertices that remain are more
    /// than `distance` apart. `Some(0.0)` merges exactly coincident vertices. A negative
    /// or NaN distance merges nothing (no pair satisfies the rule); an infinite one
    /// merges every vertex into the first. Vertices with a non-finite coordinate are
    /// never merged.
    #[must_use]
    pub fn merge_distance(mut self, distance: Option<f64>) -> Self {
        self.merge_distance = distance;
        self
    }

    /// Remove vertices that no remaining face uses (default `true`), renumbering the
    /// others compactly in their input order. When `false` they are kept as isolated
    /// vertices.
    #[must_use]
    pub fn drop_unreferenced(mut self, yes: bool) -> Self {
        self.drop_unreferenced = yes;
        self
    }

    /// Cut a component that cannot be oriented consistently (a Möbius strip) open along
    /// the edges where orienting it fails (default `true`); when `false` such a
    /// component is an error, [`TopologyError::NonOrientable`].
    #[must_use]
    pub fn cut_non_orientable(mut self, yes: bool) -> Self {
        self.cut_non_orientable = yes;
        self
    }

    /// Turn every closed component whose faces enclose a negative volume inside out,
    /// so that its faces are counter-clockwise seen from outside (default `true`).
    /// Consistent orientation alone leaves a closed part inside out when most of its
    /// faces were written clockwise; volumes, signed distances and volume-preserving
    /// smoothing need them outward. Open components are left as oriented.
    #[must_use]
    pub fn orient_outward(mut self, yes: bool) -> Self {
        self.orient_outward = yes;
        self
    }

    /// Split every face of more than three corners into triangles (default `false`),
    /// by ear clipping in its own plane ([`triangulate_polygon`](crate::triangulate_polygon):
    /// a quadrilateral along its shorter diagonal inside it), after the degenerate and
    /// duplicate faces are dropped: the editing algorithms, which need triangles, then accept the
    /// mesh. The vertices stay as they are.
    #[must_use]
    pub fn triangulate(mut self, yes: bool) -> Self {
        self.triangulate = yes;
        self
    }

    /// Whether closed components are turned to face outward.
    #[must_use]
    pub fn orients_outward(&self) -> bool {
        self.orient_outward
    }

    /// The merge distance, if vertices are merged.
    #[must_use]
    pub fn merges_within(&self) -> Option<f64> {
        self.merge_distance
    }

    /// Whether unreferenced vertices are removed.
    #[must_use]
    pub fn drops_unreferenced(&self) -> bool {
        self.drop_unreferenced
    }

    /// Whether a non-orientable component is cut open (rather than an error).
    #[must_use]
    pub fn cuts_non_orientable(&self) -> bool {
        self.cut_non_orientable
    }
}

/// The result of [`repair`]: a face list that builds, its positions, and what changed.
///
/// # Examples
/// ```
/// use beltrami_halfedge::{repair, DVec3, PolygonList, RepairOptions};
/// // Two triangles that touch at vertex 0 only (a bow tie).
/// let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, -DVec3::X, -DVec3::Y];
/// let faces = PolygonList::from_triangles(&[[0, 1, 2], [0, 3, 4]]);
/// let repaired = repair(&positions, &faces, &RepairOptions::default())?;
/// assert_eq!(repaired.positions.len(), 6);
/// assert_eq!(repaired.faces.get(1), Some(&[5, 3, 4][..]));
/// assert_eq!(repaired.report.split_vertices, [(0, 5)]);
/// assert_eq!(repaired.mesh()?.connected_components().count(), 2);
/// # Ok::<(), beltrami_halfedge::TopologyError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct Repaired {
    /// Output vertex positions, in mesh units: kept input vertices in input order, then
    /// the copies made by splitting vertices. Each is bit-identical to the position of
    /// its input vertex (for a merged vertex, of the vertex it merged into).
    pub positions: Vec<DVec3>,
    /// Output faces, indexing [`positions`](Self::positions), in input order, each
    /// counter-clockwise and starting at the same vertex as its input face.
    pub faces: PolygonList,
    /// What changed.
    pub report: RepairReport,
}

impl Repaired {
    /// Builds the half-edge connectivity of the repaired faces.
    ///
    /// # Errors
    /// Never for the output of [`repair`]; the `Result` is that of
    /// [`HalfedgeMesh::from_polygons`].
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::{repair, primitives, RepairOptions};
    /// let cube = primitives::cube();
    /// let repaired = repair(&cube.positions, &cube.faces, &RepairOptions::default())?;
    /// assert!(repaired.mesh()?.is_closed());
    /// # Ok::<(), beltrami_halfedge::TopologyError>(())
    /// ```
    pub fn mesh(&self) -> Result<HalfedgeMesh, TopologyError> {
        HalfedgeMesh::from_polygon_list(self.positions.len(), &self.faces)
    }
}

/// What [`repair`] changed, element by element, in input indices (faces and vertices
/// 0-based, as given to [`repair`]) unless a field says otherwise. Every list is in
/// ascending order of its first member, except
/// [`split_vertices`](Self::split_vertices), in ascending order of the copies.
///
/// Every input face is either kept ([`face_origin`](Self::face_origin)), dropped as
/// degenerate or dropped as a duplicate: output faces + degenerate + duplicate = input
/// faces, where a face split into triangles ([`triangulated_faces`](Self::triangulated_faces))
/// counts once (its triangles share its input face in `face_origin`).
///
/// # Examples
/// ```
/// use beltrami_halfedge::{repair, DVec3, PolygonList, RepairOptions};
/// // Face 1 is wound the other way round; vertex 3 is used by no face.
/// let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ONE, DVec3::NEG_Y];
/// let faces = PolygonList::from_triangles(&[[0, 1, 2], [0, 1, 4]]);
/// let report = repair(&positions, &faces, &RepairOptions::default())?.report;
/// assert_eq!(report.flipped_faces, [1]);
/// assert_eq!(report.removed_vertices, [3]);
/// assert_eq!(report.vertex_map, [Some(0), Some(1), Some(2), None, Some(3)]);
/// assert_eq!(report.to_string(), "1 face flipped, 1 unreferenced vertex removed");
/// # Ok::<(), beltrami_halfedge::TopologyError>(())
/// ```
#[derive(Clone, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct RepairReport {
    /// `(vertex, target)`: vertex merged into the lower-numbered vertex `target` (see
    /// [`RepairOptions::merge_distance`]).
    pub merged_vertices: Vec<(u32, u32)>,
    /// Faces dropped as degenerate: fewer than three distinct vertices (after merging),
    /// or a vertex that comes back after others (a polygon touching itself). A face of
    /// three distinct collinear vertices is not degenerate here: geometry is not looked
    /// at.
    pub dropped_degenerate_faces: Vec<usize>,
    /// Faces kept with fewer corners: a corner repeating the vertex of the corner
    /// before it (a zero-length edge, often made by merging; e.g. `[a, b, c, c]`) was
    /// removed.
    pub shortened_faces: Vec<usize>,
    /// Faces of more than three corners split into triangles (with
    /// [`RepairOptions::triangulate`]), by input face.
    pub triangulated_faces: Vec<usize>,
    /// `(face, earlier)`: face dropped because it lists the same cycle of vertices as
    /// the earlier kept face, in either orientation (after merging and shortening). Two
    /// copies of a triangle wound opposite ways are a zero-volume sliver pair: the first
    /// is kept, the second dropped, like any other duplicate.
    pub dropped_duplicate_faces: Vec<(usize, usize)>,
    /// `(a, b)` with `a < b`: edges shared by more than two faces, cut into manifold
    /// sheets (see [`repair`] for the pairing rule). The vertices are input vertices.
    pub cut_edges: Vec<(u32, u32)>,
    /// `(a, b)` with `a < b`: edges between two faces that were opened into two boundary
    /// edges, either to make a non-orientable component orientable or because the
    /// sheets of a cut edge stayed joined around both its ends. The vertices are input
    /// vertices.
    pub opened_edges: Vec<(u32, u32)>,
    /// Faces whose orientation was reversed (the face keeps its first vertex and
    /// reverses the rest).
    pub flipped_faces: Vec<usize>,
    /// `(vertex, copy)`: input vertex split, with `copy` the **output** vertex that
    /// carries one of its extra fans of faces (pinched vertices, and the ends of cut or
    /// opened edges). The input vertex's first fan keeps
    /// [`vertex_map`](Self::vertex_map)`[vertex]`.
    pub split_vertices: Vec<(u32, u32)>,
    /// Input vertices without an output vertex: used by no remaining face (only when
    /// [`RepairOptions::drop_unreferenced`] is on), or merged into such a vertex.
    pub removed_vertices: Vec<u32>,
    /// The output vertex of each input vertex (for a merged vertex, that of its
    /// target; for a split one, that of its first fan); `None` for removed vertices.
    pub vertex_map: Vec<Option<u32>>,
    /// The input face of each output face.
    pub face_origin: Vec<usize>,
}

impl RepairReport {
    /// Whether nothing was changed: then the output faces and positions are the input
    /// ones, [`vertex_map`](Self::vertex_map) and [`face_origin`](Self::face_origin)
    /// are identities.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.merged_vertices.is_empty()
            && self.dropped_degenerate_faces.is_empty()
            && self.shortened_faces.is_empty()
            && self.triangulated_faces.is_empty()
            && self.dropped_duplicate_faces.is_empty()
            && self.cut_edges.is_empty()
            && self.opened_edges.is_empty()
            && self.flipped_faces.is_empty()
            && self.split_vertices.is_empty()
            && self.removed_vertices.is_empty()
    }
}

impl fmt::Display for RepairReport {
    /// One line of counts, e.g. `2 vertices merged, 1 duplicate face dropped`; `no
    /// repair needed` when [empty](Self::is_empty).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let items = [
            (self.merged_vertices.len(), "vertex", "vertices", "merged"),
            (
                self.dropped_degenerate_faces.len(),
                "degenerate face",
                "degenerate faces",
                "dropped",
            ),
            (
                self.dropped_duplicate_faces.len(),
                "duplicate face",
                "duplicate faces",
                "dropped",
            ),
            (self.shortened_faces.len(), "face", "faces", "shortened"),
            (
                self.triangulated_faces.len(),
                "face",
                "faces",
                "triangulated",
            ),
            (
                self.cut_edges.len(),
                "non-manifold edge",
                "non-manifold edges",
                "cut",
            ),
            (self.opened_edges.len(), "edge", "edges", "opened"),
            (self.flipped_faces.len(), "face", "faces", "flipped"),
            (self.split_vertices.len(), "vertex", "vertices", "split off"),
            (
                self.removed_vertices.len(),
                "unreferenced vertex",
                "unreferenced vertices",
                "removed",
            ),
        ];
        let mut first = true;
        for (count, one, many, done) in items {
            if count == 0 {
                continue;
            }
            if !first {
                f.write_str(", ")?;
            }
            first = false;
            let noun = if count == 1 { one } else { many };
            write!(f, "{count} {noun} {done}")?;
        }
        if first {
            f.write_str("no repair needed")?;
        }
        Ok(())
    }
}

/// Repairs a polygon soup into faces that [`HalfedgeMesh::from_polygons`] accepts: an
/// oriented 2-manifold with boundary, each connected component consistently oriented.
///
/// `positions` are the vertex positions (mesh units); `faces` index them (0-based,
/// counter-clockwise; triangles and larger polygons). The steps, in order:
///
/// 1. **merge** vertices closer than [`RepairOptions::merge_distance`] (off by
///    default);
/// 2. **shorten** faces with a corner repeating the previous corner's vertex, and
///    **drop degenerate** faces (fewer than three distinct vertices, or a vertex that
///    comes back);
/// 3. **drop duplicate** faces: the same cycle of vertices as an earlier face, either
///    way round; the earliest copy is kept; then, with [`RepairOptions::triangulate`],
///    **split** every face of more than three corners into triangles;
/// 4. **cut non-manifold edges**: the faces on an edge shared by more than two faces
///    are paired into sheets, in input order: the earliest face not yet paired takes
///    the earliest later one that traverses the edge the other way; failing that, the
///    earliest later one (orienting then flips one side); a face left over is a sheet
///    of its own. Each sheet gets its own copy of the edge (the first sheet keeps the
///    input vertices);
/// 5. **reorient** each component consistently by a breadth-first walk from its
///    lowest face, then keep whichever of the two orientations flips fewer faces (on
///    a tie, the lowest face keeps its orientation). An edge where no consistent
///    orientation exists is opened (a Möbius strip becomes a strip), or with
///    [`RepairOptions::cut_non_orientable`] off the component is an error;
/// 6. **split pinched vertices**: every fan of faces around a vertex after its first
///    gets a copy of the vertex, numbered after all kept vertices. Should the sheets
///    of a cut edge still meet around both its ends (tangled input), the faces of the
///    later sheet are also detached from their neighbours around the end with the
///    lower vertex number, and this step runs again;
/// 7. **drop unreferenced** vertices ([`RepairOptions::drop_unreferenced`]), numbering
///    the others compactly in input order.
///
/// Only step 1 and the triangulation look at positions; the result does not depend on the number of
/// threads. An input that needs no repair is returned unchanged, with an empty report.
///
/// # Errors
/// [`TopologyError::VertexOutOfRange`] naming the first face with an index outside
/// `positions`; [`TopologyError::NonOrientable`] naming the lowest face of a
/// non-orientable component when [`RepairOptions::cut_non_orientable`] is off;
/// [`TopologyError::TooManyElements`] when there are more elements than `u32` handles
/// can address.
///
/// # Complexity
/// O(C log C) time and O(C + V) memory for C face corners and V vertices (merging
/// hashes positions on a grid of twice the merge distance). Step 6 repeats only for
/// tangled input, at most once per opened edge.
///
/// # Examples
/// ```
/// use beltrami_halfedge::{repair, DVec3, HalfedgeMesh, PolygonList, RepairOptions};
/// // A tetrahedron whose face [1, 2, 3] is listed twice, the second time reversed.
/// let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
/// let faces =
///     PolygonList::from_triangles(&[[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2], [3, 2, 1]]);
/// assert!(HalfedgeMesh::from_polygons(4, faces.iter()).is_err());
///
/// let repaired = repair(&positions, &faces, &RepairOptions::default())?;
/// assert_eq!(repaired.report.dropped_duplicate_faces, [(4, 2)]);
/// assert_eq!(repaired.report.to_string(), "1 duplicate face dropped");
/// let mesh = repaired.mesh()?;
/// assert!(mesh.is_closed());
/// assert_eq!(mesh.n_vertices(), 4);
/// # Ok::<(), beltrami_halfedge::TopologyError>(())
/// ```
pub fn repair(
    positions: &[DVec3],
    faces: &PolygonList,
    options: &RepairOptions,
) -> Result<Repaired, TopologyError> {
    check_input(positions, faces)?;
    let n = positions.len();
    let mut report = RepairReport::default();

    // 1. Merge.
    let target = merge_step(positions, options.merge_distance, &mut report);

    // 2. Shorten and drop degenerate faces.
    let (list, origin) = clean_faces(faces, &target, &mut report);

    // 3. Drop duplicates.
    let (list, origin) = drop_duplicates(&list, &origin, &mut report);
    // 3b. Split polygons into triangles when asked: after the duplicates are dropped
    // (two copies of a polygon are one polygon however their lists start).
    let (list, origin) = if options.triangulate {
        triangulate_faces(positions, list, origin, &mut report)
    } else {
        (list, origin)
    };

    // 4. Pair the faces of each edge.
    let corners = Corners::new(&list);
    let mut mate = pair_corners(&corners, &mut report);

    // 5. Orient.
    let mut flip = orient(
        &corners,
        &list.offsets(),
        &mut mate,
        &origin,
        options.cut_non_orientable,
        &mut report,
    )?;

    // 6. Split, detaching tangled sheets until each vertex pair has one edge.
    let classes = split_vertices(&corners, &mut mate, n, &mut report)?;

    // 7. Number the output vertices and write the faces.
    let numbering = Numbering::new(
        positions,
        &target,
        &classes,
        options.drop_unreferenced,
        &mut report,
    );
    let mut out_faces = numbering.write_faces(&list, &classes.out, &flip);

    // 8. Turn every closed component that encloses a negative volume inside out, so
    // that its faces are counter-clockwise seen from outside.
    if options.orient_outward && flip_inward_components(&numbering.positions, &out_faces, &mut flip)
    {
        out_faces = numbering.write_faces(&list, &classes.out, &flip);
    }
    finish_report(&mut report, &flip, origin, &target, &numbering.final_id);
    Ok(Repaired {
        positions: numbering.positions,
        faces: out_faces,
        report,
    })
}

/// Checks that the counts fit `u32` handles and that every face's vertices exist.
fn check_input(positions: &[DVec3], faces: &PolygonList) -> Result<(), TopologyError> {
    let n = positions.len();
    check_count("vertices", n)?;
    check_count("faces", faces.len())?;
    check_count("halfedges", 2 * faces.n_corners())?;
    for (f, face) in faces.iter().enumerate() {
        if let Some(&vertex) = face.iter().find(|&&v| v as usize >= n) {
            return Err(TopologyError::VertexOutOfRange {
                face: f,
                vertex,
                n_vertices: n,
            });
        }
    }
    Ok(())
}

/// Step 1: the vertex each input vertex merges into (itself when none), recorded in
/// the report.
fn merge_step(positions: &[DVec3], distance: Option<f64>, report: &mut RepairReport) -> Vec<u32> {
    let target = match distance {
        Some(distance) => merge_targets(positions, distance),
        None => (0..positions.len() as u32).collect(),
    };
    report.merged_vertices = target
        .iter()
        .enumerate()
        .filter(|&(v, &t)| t as usize != v)
        .map(|(v, &t)| (v as u32, t))
        .collect();
    target
}

/// Step 4: pairs the faces of each edge. `mate[k]` is the corner glued to corner `k`
/// along their common edge (`INVALID` on the boundary); an edge of more than two faces
/// is cut into sheets and recorded in the report.
fn pair_corners(corners: &Corners<'_>, report: &mut RepairReport) -> Vec<u32> {
    let (sorted, starts) = corners.edge_groups();
    let mut mate = vec![INVALID; corners.indices.len()];
    for g in starts.windows(2) {
        let group = &sorted[g[0]..g[1]];
        match *group {
            [_] => {}
            [k1, k2] => {
                mate[k1 as usize] = k2;
                mate[k2 as usize] = k1;
            }
            _ => {
                pair_sheets(corners, group, &mut mate);
                report.cut_edges.push(edge_of(corners, group[0]));
            }
        }
    }
    mate
}

/// Step 6: the fans of the vertices, after detaching tangled sheets until each vertex
/// pair has one edge.
fn split_vertices(
    corners: &Corners<'_>,
    mate: &mut [u32],
    n: usize,
    report: &mut RepairReport,
) -> Result<VertexClasses, TopologyError> {
    let prev = previous_corners(corners);
    loop {
        let classes = vertex_classes(corners, mate, n)?;
        if !detach_tangled_sheets(corners, &prev, &classes.out, mate, report) {
            return Ok(classes);
        }
    }
}

/// Step 7: the output numbering of the vertices: the kept input vertices in input
/// order, then the copies of split vertices.
struct Numbering {
    /// Per input vertex, its output id (`INVALID` when merged away or dropped).
    final_id: Vec<u32>,
    /// How many input vertices are kept; the copies follow them.
    n_kept: u32,
    /// The output positions.
    positions: Vec<DVec3>,
}

impl Numbering {
    /// Numbers the vertices that stay (merge targets that a face references, or all of
    /// them when unreferenced ones are kept) and the copies, recording the copies in
    /// the report.
    fn new(
        positions: &[DVec3],
        target: &[u32],
        classes: &VertexClasses,
        drop_unreferenced: bool,
        report: &mut RepairReport,
    ) -> Self {
        let n = positions.len();
        let mut referenced = vec![false; n];
        for &o in &classes.out {
            if let Some(r) = referenced.get_mut(o as usize) {
                *r = true;
            }
        }
        let mut final_id = vec![INVALID; n];
        let mut out_positions = Vec::with_capacity(n + classes.copies.len());
        for v in 0..n {
            if target[v] as usize == v && (referenced[v] || !drop_unreferenced) {
                final_id[v] = out_positions.len() as u32;
                out_positions.push(positions[v]);
            }
        }
        let n_kept = out_positions.len() as u32;
        for (i, &original) in classes.copies.iter().enumerate() {
            out_positions.push(positions[original as usize]);
            report.split_vertices.push((original, n_kept + i as u32));
        }
        Numbering {
            final_id,
            n_kept,
            positions: out_positions,
        }
    }

    /// The output id of vertex `o` of the corner classes (an input vertex, or `n + i`
    /// for the `i`-th copy).
    #[inline]
    fn renumber(&self, o: u32) -> u32 {
        let n = self.final_id.len();
        if (o as usize) < n {
            self.final_id[o as usize]
        } else {
            self.n_kept + (o - n as u32)
        }
    }

    /// The output faces: face `f` of `list` with its corners' output vertices from
    /// `out`, reversed after its first corner when `flip[f]`.
    fn write_faces(&self, list: &PolygonList, out: &[u32], flip: &[bool]) -> PolygonList {
        let offsets = list.offsets();
        let mut out_faces = PolygonList::with_capacity(list.len(), list.n_corners());
        let mut buf = Vec::new();
        for f in 0..list.len() {
            buf.clear();
            buf.extend(
                out[offsets[f]..offsets[f + 1]]
                    .iter()
                    .map(|&o| self.renumber(o)),
            );
            if flip[f] {
                buf[1..].reverse();
            }
            out_faces.push(&buf);
        }
        out_faces
    }
}

/// Step 8: toggles `flip` on every face of a closed component that encloses a negative
/// volume, when the faces build. Returns whether any face changed.
fn flip_inward_components(positions: &[DVec3], faces: &PolygonList, flip: &mut [bool]) -> bool {
    let Ok(mesh) = HalfedgeMesh::from_polygons(positions.len(), faces.iter()) else {
        return false;
    };
    let inward = inward_components(&mesh, positions);
    if !inward.iter().any(|&i| i) {
        return false;
    }
    let components = mesh.connected_components();
    for (f, flip) in flip.iter_mut().enumerate() {
        let c = components.face_component[crate::FaceId::new(f as u32)] as usize;
        if inward[c] {
            *flip = !*flip;
        }
    }
    true
}

/// Fills the report's lists that follow from the final faces and numbering: flipped
/// faces and face origins (input face ids), the vertex map and the removed vertices;
/// sorts the opened edges.
fn finish_report(
    report: &mut RepairReport,
    flip: &[bool],
    origin: Vec<usize>,
    target: &[u32],
    final_id: &[u32],
) {
    report.flipped_faces = flip
        .iter()
        .enumerate()
        .filter(|&(_, &flipped)| flipped)
        .map(|(f, _)| origin[f])
        .collect();
    report.flipped_faces.sort_unstable();
    // A polygon split into triangles is flipped as a whole: one entry per input face.
    report.flipped_faces.dedup();
    report.vertex_map = target
        .iter()
        .map(|&t| Some(final_id[t as usize]).filter(|&id| id != INVALID))
        .collect();
    report.removed_vertices = (0..target.len() as u32)
        .filter(|&v| report.vertex_map[v as usize].is_none())
        .collect();
    report.opened_edges.sort_unstable();
    report.opened_edges.dedup();
    report.face_origin = origin;
}

/// For each connected component of `mesh`, whether it is closed and encloses a negative
/// signed volume (its faces turn clockwise seen from outside). The volume is summed over
/// the fan triangles of each face, relative to the component's first vertex, so that a
/// component far from the origin keeps its accuracy.
fn inward_components(mesh: &HalfedgeMesh, positions: &[DVec3]) -> Vec<bool> {
    let components = mesh.connected_components();
    let mut origin = vec![None; components.count()];
    let mut volume = vec![0.0f64; components.count()];
    for f in mesh.faces() {
        let c = components.face_component[f] as usize;
        let mut corners = mesh.vertices_around_face(f).map(|v| positions[v.index()]);
        let Some(first) = corners.next() else {
            continue;
        };
        let o = *origin[c].get_or_insert(first);
        let a = first - o;
        let mut previous: Option<DVec3> = None;
        for p in corners {
            let b = p - o;
            if let Some(prev) = previous {
                volume[c] += a.dot(prev.cross(b)) / 6.0;
            }
            previous = Some(b);
        }
    }
    components
        .summaries
        .iter()
        .zip(volume)
        .map(|(summary, v)| summary.is_closed() && v < 0.0)
        .collect()
}

/// The vertex each vertex merges into (itself when kept), by the greedy rule of
/// [`RepairOptions::merge_distance`].
///
/// Kept vertices are hashed on a grid of cells `2 * distance` wide (1 for a zero
/// distance): two points within `distance` lie in the same or adjacent cells even with
/// the rounding of the division, so the 27 cells around a vertex hold every candidate.
/// Kept vertices are more than `distance` apart, so a cell holds a bounded number.
fn merge_targets(positions: &[DVec3], distance: f64) -> Vec<u32> {
    let mut target: Vec<u32> = (0..positions.len() as u32).collect();
    if distance.is_nan() || distance < 0.0 {
        return target;
    }
    let cell = if distance > 0.0 { 2.0 * distance } else { 1.0 };
    let cell_of = |p: DVec3| {
        // Finite / positive (or / infinity, giving 0): a saturating cast, never NaN.
        let c = (p / cell).floor();
        [c.x as i64, c.y as i64, c.z as i64]
    };
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    for (v, &p) in positions.iter().enumerate() {
        if !p.is_finite() {
            continue;
        }
        let key = cell_of(p);
        let mut best: Option<u32> = None;
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let near = [
                        key[0].saturating_add(dx),
                        key[1].saturating_add(dy),
                        key[2].saturating_add(dz),
                    ];
                    // Each cell's list is ascending: its first match is its lowest.
                    let found = grid.get(&near).and_then(|kept| {
                        kept.iter()
                            .copied()
                            .find(|&t| distance_between(positions[t as usize], p) <= distance)
                    });
                    if let Some(t) = found {
                        best = Some(best.map_or(t, |b| b.min(t)));
                    }
                }
            }
        }
        match best {
            Some(t) => target[v] = t,
            None => grid.entry(key).or_default().push(v as u32),
        }
    }
    target
}

/// `|p − q|` without overflow in the squares (scaled by the largest component).
fn distance_between(p: DVec3, q: DVec3) -> f64 {
    let d = p - q;
    let scale = d.abs().max_element();
    if scale == 0.0 || !scale.is_finite() {
        return scale;
    }
    scale * (d / scale).length()
}

/// Step 2: maps the faces through `target`, removes corners that repeat the previous
/// corner's vertex, and drops faces left degenerate. Returns the kept faces and the
/// input index of each.
fn clean_faces(
    faces: &PolygonList,
    target: &[u32],
    report: &mut RepairReport,
) -> (PolygonList, Vec<usize>) {
    let mut list = PolygonList::with_capacity(faces.len(), faces.n_corners());
    let mut origin = Vec::with_capacity(faces.len());
    let mut buf: Vec<u32> = Vec::new();
    let mut scratch = Vec::new();
    for (f, face) in faces.iter().enumerate() {
        buf.clear();
        for &v in face {
            let t = target[v as usize];
            if buf.last() != Some(&t) {
                buf.push(t);
            }
        }
        while buf.len() > 1 && buf.first() == buf.last() {
            buf.pop();
        }
        if buf.len() < 3 || repeated_vertex(&buf, &mut scratch).is_some() {
            report.dropped_degenerate_faces.push(f);
            continue;
        }
        if buf.len() != face.len() {
            report.shortened_faces.push(f);
        }
        list.push(&buf);
        origin.push(f);
    }
    (list, origin)
}

/// Step 3b: every face of more than three corners split into triangles (see
/// [`triangulate_polygon`](crate::triangulate_polygon)), each triangle with its
/// polygon's input face as origin.
fn triangulate_faces(
    positions: &[DVec3],
    list: PolygonList,
    origin: Vec<usize>,
    report: &mut RepairReport,
) -> (PolygonList, Vec<usize>) {
    if list.is_triangles() {
        return (list, origin);
    }
    let mut out = PolygonList::with_capacity(list.len(), list.n_corners());
    let mut out_origin = Vec::with_capacity(list.len());
    let mut triangles = Vec::new();
    for (face, &f) in list.iter().zip(&origin) {
        if face.len() == 3 {
            out.push(face);
            out_origin.push(f);
            continue;
        }
        triangles.clear();
        crate::triangulate_polygon(positions, face, &mut triangles);
        for t in &triangles {
            out.push(t);
            out_origin.push(f);
        }
        report.triangulated_faces.push(f);
    }
    (out, out_origin)
}

/// Step 3: drops every face that lists the same cycle of vertices as an earlier one,
/// either way round. Faces are compared by a canonical form: the cycle started at its
/// lowest vertex and run towards the lower of that vertex's two neighbours.
fn drop_duplicates(
    list: &PolygonList,
    origin: &[usize],
    report: &mut RepairReport,
) -> (PolygonList, Vec<usize>) {
    let mut canonical = Vec::with_capacity(list.n_corners());
    for face in list.iter() {
        let len = face.len();
        let start = (0..len).min_by_key(|&i| face[i]).unwrap_or(0);
        if face[(start + 1) % len] <= face[(start + len - 1) % len] {
            canonical.extend((0..len).map(|i| face[(start + i) % len]));
        } else {
            canonical.extend((0..len).map(|i| face[(start + len - i) % len]));
        }
    }
    let offsets = list.offsets();
    let key = |f: u32| &canonical[offsets[f as usize]..offsets[f as usize + 1]];
    let mut order: Vec<u32> = (0..list.len() as u32).collect();
    // A total order (ties broken by face), so the parallel sort is deterministic.
    order.par_sort_unstable_by(|&f, &g| key(f).cmp(key(g)).then(f.cmp(&g)));
    let mut duplicate_of = vec![INVALID; list.len()];
    let mut first = 0;
    for (i, &f) in order.iter().enumerate() {
        if i > 0 && key(f) == key(order[i - 1]) {
            duplicate_of[f as usize] = first;
        } else {
            first = f;
        }
    }
    if duplicate_of.iter().all(|&d| d == INVALID) {
        return (list.clone(), origin.to_vec());
    }
    let mut kept = PolygonList::with_capacity(list.len(), list.n_corners());
    let mut kept_origin = Vec::with_capacity(list.len());
    for (f, face) in list.iter().enumerate() {
        match duplicate_of[f] {
            INVALID => {
                kept.push(face);
                kept_origin.push(origin[f]);
            }
            d => report
                .dropped_duplicate_faces
                .push((origin[f], origin[d as usize])),
        }
    }
    (kept, kept_origin)
}

/// The undirected edge of corner `k` as `(lower, higher)` vertex.
fn edge_of(corners: &Corners<'_>, k: u32) -> (u32, u32) {
    let (a, b) = (corners.from(k), corners.to(k));
    (a.min(b), a.max(b))
}

/// Step 4 for one edge of more than two faces (`group`: its corners in face order):
/// the earliest unpaired corner is glued to the earliest later unpaired one running the
/// other way, failing that to the earliest later unpaired one; a corner left over stays
/// unglued. O(len) with one cursor per direction.
fn pair_sheets(corners: &Corners<'_>, group: &[u32], mate: &mut [u32]) {
    let way = |k: u32| usize::from(corners.from(k) != corners.from(group[0]));
    let mut by_way: [Vec<usize>; 2] = [Vec::new(), Vec::new()];
    for (i, &k) in group.iter().enumerate() {
        by_way[way(k)].push(i);
    }
    let mut cursor = [0usize; 2];
    let mut paired = vec![false; group.len()];
    for i in 0..group.len() {
        if paired[i] {
            continue;
        }
        paired[i] = true;
        let w = way(group[i]);
        let mut partner = None;
        for side in [1 - w, w] {
            let list = &by_way[side];
            // Skipped entries are at or before `i` or paired: never eligible again.
            while cursor[side] < list.len()
                && (list[cursor[side]] <= i || paired[list[cursor[side]]])
            {
                cursor[side] += 1;
            }
            if let Some(&j) = list.get(cursor[side]) {
                partner = Some(j);
                break;
            }
        }
        if let Some(j) = partner {
            paired[j] = true;
            mate[group[i] as usize] = group[j];
            mate[group[j] as usize] = group[i];
        }
    }
}

/// Step 5: which faces to flip so that every glued pair of corners runs opposite ways.
/// A glued pair that contradicts the walk is opened (or, without `cut`, the component
/// is an error).
fn orient(
    corners: &Corners<'_>,
    offsets: &[usize],
    mate: &mut [u32],
    origin: &[usize],
    cut: bool,
    report: &mut RepairReport,
) -> Result<Vec<bool>, TopologyError> {
    let n_faces = offsets.len() - 1;
    let mut parity: Vec<Option<bool>> = vec![None; n_faces];
    let mut flip = vec![false; n_faces];
    let mut members = Vec::new();
    let mut queue = VecDeque::new();
    for start in 0..n_faces {
        if parity[start].is_some() {
            continue;
        }
        parity[start] = Some(false);
        members.clear();
        queue.push_back(start);
        while let Some(f) = queue.pop_front() {
            members.push(f);
            let flipped = parity[f] == Some(true);
            for k in offsets[f]..offsets[f + 1] {
                let m = mate[k];
                if m == INVALID {
                    continue;
                }
                let g = corners.face(m);
                let same_way = corners.from(k as u32) == corners.from(m);
                let want = flipped ^ same_way;
                match parity[g] {
                    None => {
                        parity[g] = Some(want);
                        queue.push_back(g);
                    }
                    Some(have) if have != want => {
                        if !cut {
                            return Err(TopologyError::NonOrientable {
                                face: origin[start],
                            });
                        }
                        mate[k] = INVALID;
                        mate[m as usize] = INVALID;
                        report.opened_edges.push(edge_of(corners, m));
                    }
                    Some(_) => {}
                }
            }
        }
        let n_flipped = members.iter().filter(|&&f| parity[f] == Some(true)).count();
        let invert = 2 * n_flipped > members.len();
        for &f in &members {
            flip[f] = (parity[f] == Some(true)) != invert;
        }
    }
    Ok(flip)
}

/// The corner before each corner in its face.
fn previous_corners(corners: &Corners<'_>) -> Vec<u32> {
    let n_corners = corners.indices.len() as u32;
    let mut prev = vec![0; n_corners as usize];
    for k in 0..n_corners {
        prev[corners.next(k) as usize] = k;
    }
    prev
}

/// The corner of `k`'s face at vertex `x`, one of the two ends of `k`'s edge.
fn corner_at(corners: &Corners<'_>, k: u32, x: u32) -> u32 {
    if corners.from(k) == x {
        k
    } else {
        corners.next(k)
    }
}

/// The fans of faces around the vertices: which output vertex each corner gets.
struct VertexClasses {
    /// Per corner, its output vertex before compaction: the input vertex for its first
    /// fan, `n + i` for the `i`-th copy.
    out: Vec<u32>,
    /// The input vertex of each copy.
    copies: Vec<u32>,
}

/// Step 6: corners at a vertex are joined when their faces are glued along an edge at
/// that vertex; each class is a fan (a chain or cycle of faces). The class of a
/// vertex's first corner keeps the vertex; every other class gets a copy, numbered in
/// order of its first corner.
fn vertex_classes(
    corners: &Corners<'_>,
    mate: &[u32],
    n: usize,
) -> Result<VertexClasses, TopologyError> {
    let n_corners = corners.indices.len();
    let mut fans = UnionFind::<u32>::new(n_corners);
    for (k, &m) in mate.iter().enumerate() {
        let k = k as u32;
        if m == INVALID || m < k {
            continue;
        }
        let (a, b) = (corners.from(k), corners.to(k));
        fans.union(corner_at(corners, k, a), corner_at(corners, m, a));
        fans.union(corner_at(corners, k, b), corner_at(corners, m, b));
    }
    let mut first_fan = vec![INVALID; n];
    let mut copy_of_fan = vec![INVALID; n_corners];
    let mut out = Vec::with_capacity(n_corners);
    let mut copies = Vec::new();
    for (k, &v) in corners.indices.iter().enumerate() {
        let fan = fans.find(k as u32);
        let first = &mut first_fan[v as usize];
        if *first == INVALID {
            *first = fan;
        }
        if *first == fan {
            out.push(v);
            continue;
        }
        let copy = &mut copy_of_fan[fan as usize];
        if *copy == INVALID {
            check_count("vertices", n + copies.len() + 1)?;
            *copy = (n + copies.len()) as u32;
            copies.push(v);
        }
        out.push(*copy);
    }
    Ok(VertexClasses { out, copies })
}

/// Step 6, continued: finds vertex pairs of the output (`out`, per corner) joined by
/// more than one edge (the sheets of a cut edge that still meet around both its ends)
/// and detaches every sheet after the first around the end with the lower input vertex,
/// by opening the faces' other edges at that end. Returns whether anything was opened.
///
/// Each such pair opens at least one edge: the later sheet's corners at that end share
/// the first sheet's fan, which they can only reach through one of those other edges.
fn detach_tangled_sheets(
    corners: &Corners<'_>,
    prev: &[u32],
    out: &[u32],
    mate: &mut [u32],
    report: &mut RepairReport,
) -> bool {
    let out_corners = corners.with_indices(out);
    let (sorted, starts) = out_corners.edge_groups();
    let mut opened = false;
    for g in starts.windows(2) {
        let group = &sorted[g[0]..g[1]];
        let first = group[0];
        let keep = mate[first as usize];
        if group.len() == 1 || (group.len() == 2 && keep == group[1]) {
            continue;
        }
        for &c in &group[1..] {
            if c == keep {
                continue;
            }
            let (lower, _) = edge_of(corners, c);
            let at = corner_at(corners, c, lower);
            // The face's other edge at `lower`: the one ending there or the one leaving.
            let other = if at == c { prev[at as usize] } else { at };
            let m = mate[other as usize];
            if m != INVALID {
                mate[other as usize] = INVALID;
                mate[m as usize] = INVALID;
                report.opened_edges.push(edge_of(corners, other));
                opened = true;
            }
        }
    }
    opened
}
