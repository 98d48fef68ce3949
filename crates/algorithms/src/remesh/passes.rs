//! The four steps of one remeshing iteration on the [`EditMesh`]: split, collapse, flip,
//! relax (with the projections).

use crate::valence::{Valences, collapse_keeps_valences};
use beltrami_halfedge::edit::{EdgeProperty, VertexProperty};
use beltrami_halfedge::geometry::barycentric;
use beltrami_halfedge::{DVec3, EdgeId, EditMesh, HalfedgeId, VertexId};
use beltrami_metrics::distance::SurfaceIndex;
use rayon::prelude::*;

use super::RemeshError;
use super::curves::{CurveIndex, feature_count, triangle_normal};
use super::phong::PhongSurface;

/// Passes of one step over all edges, at most (pmp-library's limit): a pass that changes
/// nothing ends the step earlier.
const MAX_PASSES: usize = 10;

/// The smallest angle a flip made as one of a pair ([`Remesher::flip_pairs`]) may leave
/// in its two new triangles, in degrees. Lower, the pairs raise the share of valence-6
/// vertices further but cost the smallest angle of the block's feature strips (15°:
/// 21.8° against 25.5° without pairs); higher, they are rarer (30°: 87.6 % regular on
/// the scan-like sphere against 89.8 % at 20°).
const PAIR_MIN_ANGLE_DEGREES: f64 = 20.0;

/// Relaxation sweeps per iteration (pmp-library's value).
const RELAX_SWEEPS: usize = 5;

/// The feature flags of the edges and the corner flags of the vertices, copied for a
/// flip step: flips change neither (a flipped edge is never a feature and keeps its
/// id), and a slice is cheaper than a typed property look-up per edge.
struct Pinned {
    feature: Vec<bool>,
    corner: Vec<bool>,
}

/// The mesh being remeshed with its flags and the input surface.
pub(super) struct Remesher<'a> {
    pub(super) mesh: EditMesh,
    pub(super) feature: EdgeProperty<bool>,
    pub(super) corner: VertexProperty<bool>,
    /// The target edge length at each vertex: L everywhere for uniform remeshing, the
    /// curvature-adaptive field otherwise. An edge's target is the smaller of its end
    /// points'.
    pub(super) sizing: VertexProperty<f64>,
    /// The input surface, when vertices are projected onto it.
    pub(super) surface: Option<&'a SurfaceIndex>,
    /// For adaptive sizing: the sizing field at the input's vertices, interpolated at
    /// the projected points.
    pub(super) reference: Option<Vec<f64>>,
    /// The input's feature curves (and boundary).
    pub(super) curves: CurveIndex,
    /// The smooth surface over the input that projected points are lifted onto, when
    /// [`RemeshOptions::smooth_projection`](super::RemeshOptions::smooth_projection) is
    /// on.
    pub(super) phong: Option<PhongSurface>,
}

impl Remesher<'_> {
    fn length(&self, a: VertexId, b: VertexId) -> f64 {
        self.mesh.position(a).distance(self.mesh.position(b))
    }

    /// The target length of an edge between `a` and `b`.
    fn size(&self, a: VertexId, b: VertexId) -> f64 {
        self.mesh
            .get(self.sizing, a)
            .min(*self.mesh.get(self.sizing, b))
    }

    fn is_feature(&self, e: EdgeId) -> bool {
        *self.mesh.get(self.feature, e)
    }

    fn is_corner(&self, v: VertexId) -> bool {
        *self.mesh.get(self.corner, v)
    }

    fn features_at(&self, v: VertexId) -> usize {
        feature_count(&self.mesh, self.feature, v)
    }

    /// Projects `v` onto the input: onto the feature curves when it lies on a feature,
    /// else onto the surface (when projection is on). Corners and isolated vertices
    /// stay.
    fn project(&mut self, v: VertexId) -> Result<(), RemeshError> {
        let projected = self.projection(v)?;
        self.apply_projection(v, projected);
        Ok(())
    }

    /// Where [`project`](Self::project) puts `v`, and its new target length when the
    /// sizing follows the input's: `None` when `v` stays.
    fn projection(&self, v: VertexId) -> Result<Option<(DVec3, Option<f64>)>, RemeshError> {
        if self.is_corner(v) || self.mesh.is_isolated(v) {
            return Ok(None);
        }
        let p = self.mesh.position(v);
        if self.features_at(v) > 0 {
            let (q, smooth) = self.curves.closest(p);
            // On a given curve that is no crease, lifted onto the smooth surface as the
            // vertices off it are.
            let lifted = match (&self.phong, self.surface, smooth) {
                (Some(phong), Some(surface), Some((s, weights))) => {
                    let corners = s.vertices.map(|w| surface.positions()[w.index()]);
                    phong.lift(s.face, s.vertices, corners, weights, q)
                }
                _ => q,
            };
            return Ok(Some((lifted, None)));
        }
        self.surface_projection(p)
    }

    /// Where a point `p` off the feature curves goes: its closest point on the input's
    /// triangles, lifted onto the smooth surface when that is on, with the sizing
    /// interpolated there for adaptive sizing; `None` without projection.
    fn surface_projection(&self, p: DVec3) -> Result<Option<(DVec3, Option<f64>)>, RemeshError> {
        let Some(surface) = self.surface else {
            return Ok(None);
        };
        let closest = surface.closest_point(p)?;
        if self.phong.is_none() && self.reference.is_none() {
            return Ok(Some((closest.point, None)));
        }
        // The corners from the index's own face table: one look-up, where the input's
        // halfedges take three dependent ones.
        let Some(vertices) = surface.triangle_vertices(closest.face) else {
            return Ok(Some((closest.point, None)));
        };
        let [a, b, c] = vertices.map(|v| surface.positions()[v.index()]);
        let weights = barycentric(closest.point, a, b, c);
        let size = self.reference.as_ref().and_then(|sizing| {
            let size: f64 = vertices
                .iter()
                .zip(weights)
                .map(|(w, t)| t * sizing[w.index()])
                .sum();
            (size.is_finite() && size > 0.0).then_some(size)
        });
        let point = match &self.phong {
            Some(phong) => phong.lift(closest.face, vertices, [a, b, c], weights, closest.point),
            None => closest.point,
        };
        Ok(Some((point, size)))
    }

    /// Moves `v` where [`projection`](Self::projection) said.
    fn apply_projection(&mut self, v: VertexId, projected: Option<(DVec3, Option<f64>)>) {
        if let Some((q, size)) = projected {
            self.mesh.set_position(v, q);
            if let Some(size) = size {
                self.mesh.set(self.sizing, v, size);
            }
        }
    }

    /// Splits every edge longer than 4/3 L at its midpoint, repeatedly; the halves of a
    /// feature edge stay features (the edge property's split rule). Returns the count.
    pub(super) fn split_long_edges(&mut self) -> Result<usize, RemeshError> {
        let mut splits = 0;
        for _ in 0..MAX_PASSES {
            let mut changed = false;
            for i in 0..self.mesh.edge_capacity() {
                let e = EdgeId::new(i as u32);
                if !self.mesh.is_live_edge(e) {
                    continue;
                }
                let [a, b] = self.mesh.edge_vertices(e);
                if self.length(a, b) <= 4.0 / 3.0 * self.size(a, b) {
                    continue;
                }
                let mid = (self.mesh.position(a) + self.mesh.position(b)) * 0.5;
                let v = self.mesh.split_edge(e, mid)?;
                self.project(v)?;
                splits += 1;
                changed = true;
            }
            if !changed {
                break;
            }
        }
        Ok(splits)
    }

    /// Whether removing `v0` by collapsing `h = v0 → v1` keeps every edge at most
    /// `4/3 L` and turns no surviving triangle over (its normal keeps a positive dot
    /// product with the old one and a non-zero length).
    fn collapse_is_fine(&self, h: HalfedgeId) -> bool {
        let (v0, v1) = (self.mesh.from_vertex(h), self.mesh.to_vertex(h));
        self.ring_stays_fine(v0, v1, v1, self.mesh.position(v1))
    }

    /// Whether collapsing `h = v0 → v1` with the merged vertex at `q` keeps every edge
    /// at that vertex at most `4/3 L` and turns no surviving triangle of either end
    /// point's ring over (nor makes it vanish).
    fn collapse_to_point_is_fine(&self, h: HalfedgeId, q: DVec3) -> bool {
        let (v0, v1) = (self.mesh.from_vertex(h), self.mesh.to_vertex(h));
        self.ring_stays_fine(v0, v1, v1, q) && self.ring_stays_fine(v1, v0, v1, q)
    }

    /// Whether moving `x` to `q` as it merges with its neighbour `y` into the vertex
    /// `kept` keeps every edge from `q` to `x`'s other neighbours at most `4/3 L` (the
    /// target between `kept` and the neighbour) and turns none of `x`'s triangles that
    /// survive the merge over (nor makes one vanish). The triangles at the edge `x y` are
    /// removed by the collapse.
    fn ring_stays_fine(&self, x: VertexId, y: VertexId, kept: VertexId, q: DVec3) -> bool {
        let px = self.mesh.position(x);
        self.mesh.halfedges_around_vertex(x).all(|g| {
            let w = self.mesh.to_vertex(g);
            if w != y && self.mesh.position(w).distance(q) > 4.0 / 3.0 * self.size(kept, w) {
                return false;
            }
            let Some(o) = self.mesh.opposite_vertex(g) else {
                return true;
            };
            if w == y || o == y {
                return true; // removed by the collapse
            }
            let (pa, pb) = (self.mesh.position(w), self.mesh.position(o));
            let before = (pa - px).cross(pb - px);
            let after = (pa - q).cross(pb - q);
            !(before.dot(after) <= 0.0 || after.length_squared() == 0.0)
        })
    }

    /// Collapses `h`'s edge into its midpoint, projected onto the input, when
    /// [`collapse_to_point_is_fine`](Self::collapse_to_point_is_fine) there and the
    /// valences get no further from 6 ([`collapse_keeps_valences`]). For an interior edge
    /// off the curves whose collapse into either end point was refused. Returns whether
    /// it collapsed.
    fn collapse_into_midpoint(&mut self, h: HalfedgeId) -> Result<bool, RemeshError> {
        if !collapse_keeps_valences(&self.mesh, h) {
            return Ok(false);
        }
        let (v0, v1) = (self.mesh.from_vertex(h), self.mesh.to_vertex(h));
        let mid = (self.mesh.position(v0) + self.mesh.position(v1)) * 0.5;
        let projected = self.surface_projection(mid)?;
        let q = projected.map_or(mid, |(q, _)| q);
        if !self.collapse_to_point_is_fine(h, q) {
            return Ok(false);
        }
        let kept = self.mesh.collapse_edge(h)?;
        self.mesh.set_position(kept, mid);
        self.apply_projection(kept, projected);
        Ok(true)
    }

    /// Whether a collapse removing `from(h)` would drop a feature edge: the edges merged
    /// away in the triangles at the edge (`prev(h)` and `next(twin h)`) must not be
    /// features, since the merged edge at the kept vertex keeps its own flag.
    fn collapse_drops_feature(&self, h: HalfedgeId) -> bool {
        let t = h.twin();
        (self.mesh.face(h).is_some() && self.is_feature(self.mesh.prev(h).edge()))
            || (self.mesh.face(t).is_some() && self.is_feature(self.mesh.next(t).edge()))
    }

    /// Collapses every edge shorter than 4/5 L into one of its end points, repeatedly,
    /// unless that breaks the topology, a feature or boundary curve, a corner, or makes
    /// an edge longer than 4/3 L or a folded triangle; with `midpoints`, an edge off the
    /// curves whose end points both fail the length or fold test goes into its projected
    /// midpoint when that passes them and keeps the valences as near 6. Returns the
    /// count.
    pub(super) fn collapse_short_edges(&mut self, midpoints: bool) -> Result<usize, RemeshError> {
        let mut collapses = 0;
        for _ in 0..MAX_PASSES {
            let mut changed = false;
            for i in 0..self.mesh.edge_capacity() {
                let e = EdgeId::new(i as u32);
                if !self.mesh.is_live_edge(e) {
                    continue;
                }
                let [h01, h10] = e.halfedges();
                let (v0, v1) = (self.mesh.from_vertex(h01), self.mesh.to_vertex(h01));
                if self.length(v0, v1) >= 4.0 / 5.0 * self.size(v0, v1) {
                    continue;
                }
                // ok01: remove v0 (collapse h01); ok10: remove v1 (collapse h10).
                let (mut ok01, mut ok10) = (true, true);
                let (c0, c1) = (self.is_corner(v0), self.is_corner(v1));
                ok01 &= !c0;
                ok10 &= !c1;
                let (f0, f1) = (self.features_at(v0) > 0, self.features_at(v1) > 0);
                if f0 && f1 {
                    if !self.is_feature(e) {
                        continue; // a shortcut between two curves, or across one
                    }
                    ok01 &= !self.collapse_drops_feature(h01);
                    ok10 &= !self.collapse_drops_feature(h10);
                } else if f0 {
                    ok01 = false;
                } else if f1 {
                    ok10 = false;
                }
                // A closed component stays a solid: a tetrahedron is the coarsest.
                let flat = self.mesh.collapse_flattens_tetrahedron(h01);
                ok01 = ok01 && !flat && self.mesh.is_collapse_ok(h01);
                ok10 = ok10 && !flat && self.mesh.is_collapse_ok(h10);
                // Both possible: remove the vertex of lower valence first.
                let order = if self.mesh.valence(v0) < self.mesh.valence(v1) {
                    [(ok01, h01), (ok10, h10)]
                } else {
                    [(ok10, h10), (ok01, h01)]
                };
                let mut collapsed = false;
                for (ok, h) in order {
                    if ok && self.collapse_is_fine(h) {
                        self.mesh.collapse_edge(h)?;
                        collapsed = true;
                        break;
                    }
                }
                // Neither end point may go (mostly: the kept one would get an edge
                // longer than 4/3 L): an edge off the curves may still collapse into
                // its midpoint.
                if midpoints && !collapsed && ok01 && ok10 && !f0 && !f1 {
                    collapsed = self.collapse_into_midpoint(order[0].1)?;
                }
                if collapsed {
                    collapses += 1;
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        Ok(collapses)
    }

    /// Whether flipping interior edge `e` keeps both new triangles facing the way the two
    /// old ones face (no fold-over, no degenerate triangle).
    fn flip_is_fine(&self, e: EdgeId) -> bool {
        let [h, t] = e.halfedges();
        let old = triangle_normal(&self.mesh, h) + triangle_normal(&self.mesh, t);
        let (Some(a), Some(b)) = (self.mesh.opposite_vertex(h), self.mesh.opposite_vertex(t))
        else {
            return false;
        };
        let (v0, v1) = (self.mesh.from_vertex(h), self.mesh.to_vertex(h));
        let p = |v: VertexId| self.mesh.position(v);
        // After the flip: (a, b, v1) and (b, a, v0).
        let n1 = (p(b) - p(a)).cross(p(v1) - p(a));
        let n2 = (p(a) - p(b)).cross(p(v0) - p(b));
        n1.dot(old) > 0.0 && n2.dot(old) > 0.0 && n1.dot(n2) > 0.0
    }

    /// Flips every interior, non-feature edge away from corners whose flip brings the
    /// valences of its four vertices closer to 6 (4 on the boundary), repeatedly, when
    /// the flip is valid and folds nothing; then the [pairs](Self::flip_pairs) of flips
    /// that do so together. Returns the count.
    pub(super) fn flip_edges(&mut self) -> Result<usize, RemeshError> {
        let mut valence = Valences::new(&self.mesh);
        let pinned = Pinned {
            feature: self.mesh.values(self.feature).to_vec(),
            corner: self.mesh.values(self.corner).to_vec(),
        };
        let mut flips = 0;
        for _ in 0..MAX_PASSES {
            let mut changed = false;
            for i in 0..self.mesh.edge_capacity() {
                let e = EdgeId::new(i as u32);
                let Some(quad) = self.flip_quad(&pinned, e) else {
                    continue;
                };
                if valence.flip_improves(quad) && self.mesh.is_flip_ok(e) && self.flip_is_fine(e) {
                    self.mesh.flip_edge(e)?;
                    valence.flipped(quad);
                    flips += 1;
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        flips += self.flip_pairs(&mut valence, &pinned)?;
        Ok(flips)
    }

    /// The quad `[v0, v1, a, b]` of edge `e` when the flip step may flip it: a live,
    /// interior, non-feature edge with no corner among its four vertices.
    fn flip_quad(&self, pinned: &Pinned, e: EdgeId) -> Option<[VertexId; 4]> {
        if !self.mesh.is_live_edge(e) || pinned.feature[e.index()] || self.mesh.is_boundary_edge(e)
        {
            return None;
        }
        let [h, t] = e.halfedges();
        let a = self.mesh.opposite_vertex(h)?;
        let b = self.mesh.opposite_vertex(t)?;
        let quad = [self.mesh.from_vertex(h), self.mesh.to_vertex(h), a, b];
        (!quad.iter().any(|&v| pinned.corner[v.index()])).then_some(quad)
    }

    /// Whether `e` (quad `[v0, v1, a, b]`) may flip as one of a pair: the flip is valid,
    /// folds nothing, and leaves both new triangles `(a, b, v1)` and `(b, a, v0)` with
    /// no angle below [`PAIR_MIN_ANGLE_DEGREES`].
    fn pair_flip_is_fine(&self, e: EdgeId, quad: [VertexId; 4]) -> bool {
        let [v0, v1, a, b] = quad.map(|v| self.mesh.position(v));
        let smallest = |p: DVec3, q: DVec3, r: DVec3| {
            let at_p = (q - p).angle_between(r - p);
            let at_q = (p - q).angle_between(r - q);
            at_p.min(at_q).min(std::f64::consts::PI - at_p - at_q)
        };
        let least = smallest(a, b, v1).min(smallest(b, a, v0));
        self.mesh.is_flip_ok(e)
            && self.flip_is_fine(e)
            && least >= PAIR_MIN_ANGLE_DEGREES.to_radians()
    }

    /// Pairs of flips that lower the valence deviation together where no single flip
    /// does: a flip that leaves `Σ (valence − optimal)²` over its quad unchanged (it
    /// moves a 5–7 pair of vertices by one edge, a *glide*) followed by one that lowers
    /// it among the edges at the first flip's four vertices (the two 5–7 pairs meet and
    /// cancel). Both flips must pass [`pair_flip_is_fine`](Self::pair_flip_is_fine); a
    /// first flip with no second is undone. Run after the single flips of
    /// [`flip_edges`](Self::flip_edges), which cannot remove such pairs, as a 5–7 pair
    /// only moves at no gain. Returns the count of flips made (twice the pairs).
    fn flip_pairs(
        &mut self,
        valence: &mut Valences,
        pinned: &Pinned,
    ) -> Result<usize, RemeshError> {
        let mut flips = 0;
        let mut near: Vec<EdgeId> = Vec::new();
        for i in 0..self.mesh.edge_capacity() {
            let e = EdgeId::new(i as u32);
            let Some(quad) = self.flip_quad(pinned, e) else {
                continue;
            };
            if !valence.flip_keeps(quad) || !self.pair_flip_is_fine(e, quad) {
                continue;
            }
            self.mesh.flip_edge(e)?;
            valence.flipped(quad);
            near.clear();
            for &v in &quad {
                for h in self.mesh.halfedges_around_vertex(v) {
                    let e2 = h.edge();
                    if e2 != e && !near.contains(&e2) {
                        near.push(e2);
                    }
                }
            }
            let second = near.iter().find_map(|&e2| {
                let q2 = self.flip_quad(pinned, e2)?;
                (valence.flip_improves(q2) && self.pair_flip_is_fine(e2, q2)).then_some((e2, q2))
            });
            match second {
                Some((e2, q2)) => {
                    self.mesh.flip_edge(e2)?;
                    valence.flipped(q2);
                    flips += 2;
                }
                None => {
                    // Back: flipping the edge again restores the quad's diagonal.
                    self.mesh.flip_edge(e)?;
                    valence.unflipped(quad);
                }
            }
        }
        Ok(flips)
    }

    /// Flips every interior non-feature edge opposite an angle above 170° (a *cap*, a
    /// triangle flattened onto one edge), when the flip is valid and folds nothing: the
    /// final step of pmp-library's remeshing. Returns the count.
    pub(super) fn remove_caps(&mut self) -> Result<usize, RemeshError> {
        let cap = 170f64.to_radians();
        let mut flips = 0;
        for i in 0..self.mesh.edge_capacity() {
            let e = EdgeId::new(i as u32);
            if !self.mesh.is_live_edge(e) || self.is_feature(e) || self.mesh.is_boundary_edge(e) {
                continue;
            }
            let [h, t] = e.halfedges();
            let (Some(b), Some(d)) = (self.mesh.opposite_vertex(h), self.mesh.opposite_vertex(t))
            else {
                continue;
            };
            let (a, c) = (self.mesh.from_vertex(h), self.mesh.to_vertex(h));
            let p = |v: VertexId| self.mesh.position(v);
            let angle = |o: VertexId| (p(a) - p(o)).angle_between(p(c) - p(o));
            let largest = angle(b).max(angle(d));
            if largest > cap && self.mesh.is_flip_ok(e) && self.flip_is_fine(e) {
                self.mesh.flip_edge(e)?;
                flips += 1;
            }
        }
        Ok(flips)
    }

    /// The move of `v` in one relaxation sweep: a vertex on a feature curve moves along
    /// the curve's tangent towards the length-weighted mean of its two feature edges'
    /// midpoints; any other vertex to the area-weighted centroid of its triangles,
    /// projected onto its tangent plane. Zero for corners and degenerate neighbourhoods.
    fn relaxation_move(&self, v: VertexId) -> DVec3 {
        if self.is_corner(v) {
            return DVec3::ZERO;
        }
        let p = self.mesh.position(v);
        // The columns once, not a typed look-up per neighbour.
        let (sizing, feature) = (
            self.mesh.values(self.sizing),
            self.mesh.values(self.feature),
        );
        let s = |w: VertexId| sizing[w.index()];
        // The first two feature edges' far ends, and how many there are.
        let mut ends = [(DVec3::ZERO, 0.0); 2];
        let mut n_ends = 0;
        for h in self.mesh.halfedges_around_vertex(v) {
            if feature[h.edge().index()] {
                if let Some(end) = ends.get_mut(n_ends) {
                    let w = self.mesh.to_vertex(h);
                    *end = (self.mesh.position(w), s(w));
                }
                n_ends += 1;
            }
        }
        let u = match n_ends {
            0 => {
                let mut centroid = DVec3::ZERO;
                let mut weight = 0.0;
                // The vertex normal in the same walk: the sum of the triangles'
                // unnormalised normals (`curves::triangle_normal`), in circulation
                // order, a zero added for the boundary gap (so a zero keeps its sign as
                // a plain sum of all of them would leave it).
                let mut normal = DVec3::ZERO;
                for h in self.mesh.halfedges_around_vertex(v) {
                    let Some(o) = self.mesh.opposite_vertex(h) else {
                        normal += DVec3::ZERO;
                        continue;
                    };
                    let w = self.mesh.to_vertex(h);
                    let (b, c) = (self.mesh.position(w), self.mesh.position(o));
                    let cross = (b - p).cross(c - p);
                    normal += cross;
                    let size = (s(v) + s(w) + s(o)) / 3.0;
                    let area = cross.length() / (size * size);
                    centroid += area * (p + b + c) / 3.0;
                    weight += area;
                }
                if weight <= 0.0 {
                    return DVec3::ZERO;
                }
                let n = normal.normalize_or_zero();
                let u = centroid / weight - p;
                u - n * u.dot(n)
            }
            2 => {
                let [(a, sa), (b, sb)] = &ends;
                let wa = a.distance(p) / (0.5 * (s(v) + sa));
                let wb = b.distance(p) / (0.5 * (s(v) + sb));
                if wa + wb <= 0.0 {
                    return DVec3::ZERO;
                }
                let mean = (wa * (p + *a) * 0.5 + wb * (p + *b) * 0.5) / (wa + wb);
                let tangent = ((*a - p).normalize_or_zero() - (*b - p).normalize_or_zero())
                    .normalize_or_zero();
                tangent * (mean - p).dot(tangent)
            }
            _ => DVec3::ZERO,
        };
        if u.is_finite() { u } else { DVec3::ZERO }
    }

    /// Tangential relaxation: [`RELAX_SWEEPS`] Jacobi sweeps (all moves computed, then
    /// applied), each followed by the projection of feature vertices onto the input's
    /// curves; then every other vertex is projected onto the input surface.
    ///
    /// The moves and the final projections are computed on rayon's threads (each
    /// depends only on the mesh before the pass) and applied in vertex order, so the
    /// result does not depend on the thread count.
    pub(super) fn relax(&mut self) -> Result<(), RemeshError> {
        let vertices: Vec<VertexId> = self.mesh.vertices().collect();
        // Relaxation moves no edge: whether a vertex is on a feature is fixed here.
        let on_feature: Vec<bool> = {
            let this = &*self;
            vertices
                .par_iter()
                .map(|&v| this.features_at(v) > 0)
                .collect()
        };
        for _ in 0..RELAX_SWEEPS {
            let moves: Vec<DVec3> = {
                let this = &*self;
                vertices
                    .par_iter()
                    .map(|&v| this.relaxation_move(v))
                    .collect()
            };
            for ((&v, u), &feature) in vertices.iter().zip(moves).zip(&on_feature) {
                if u != DVec3::ZERO {
                    let p = self.mesh.position(v);
                    self.mesh.set_position(v, p + u);
                    if feature {
                        self.project(v)?;
                    }
                }
            }
        }
        if self.surface.is_some() {
            let projected: Vec<_> = {
                let this = &*self;
                vertices
                    .par_iter()
                    .zip(&on_feature)
                    .map(|(&v, &feature)| {
                        if feature {
                            Ok(None)
                        } else {
                            this.projection(v)
                        }
                    })
                    .collect()
            };
            // The first error in vertex order, as a sequential pass would report it.
            for (&v, projected) in vertices.iter().zip(projected) {
                self.apply_projection(v, projected?);
            }
        }
        Ok(())
    }
}
