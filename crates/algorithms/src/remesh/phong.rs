//! The smooth surface the remesher projects onto: Phong tessellation of the input.
//!
//! A vertex projected onto the closest point of a faceted input sits as deep below the
//! underlying curved surface as that facet's sagitta, and the output's own facets add
//! theirs: on a sphere the distance between input and output is about the sum of the two.
//! Phong tessellation (Boubekeur and Alexa 2008) lifts the closest point `q` of triangle
//! `(p₀, p₁, p₂)` with barycentric weights `wᵢ` and vertex normals `nᵢ` by
//!
//! ```text
//! q' = q − α · Σ wᵢ ((q − pᵢ)·nᵢ) nᵢ,
//! ```
//!
//! the weighted mean of `q`'s projections onto the three tangent planes, blended with `q`.
//! With α = ½ the lift reproduces a sphere to the fourth order in the edge length (on the
//! level-6 icosphere a facet's midpoint lies 5.7e-5 below the unit sphere, its Phong
//! point 5e-9), where the paper's α = ¾ overshoots by half the sagitta. The surface
//! passes through the input's vertices and along its edges, is continuous across edges
//! whose end points have one normal each, and is flat wherever the normals are the
//! face's.
//!
//! The normals are per face corner: Max's weighted mean of the face normals around the
//! vertex (exact for vertices on a sphere, folds and open fans included), within the fan of faces reached without crossing a feature edge or the
//! boundary, so the faces of a part with features stay flat up to the feature curves
//! (their corners' normals are the face normal). A triangle whose corner normals differ
//! by more than [`SMOOTH_ANGLE`] spans a sharp edge that was not asked for as a feature,
//! and is not lifted: a cube's faces stay flat without features. A flat triangle at a
//! vertex of a sharp edge that is not a feature, whose averaged normal leans less than
//! that from the face's (the rim of a hole through a block), is lifted by the lean:
//! machined parts are remeshed with features (docs/remeshing.md).
//! The triangle's own normal plays no part, so a scan's folded slivers are lifted with
//! their neighbours.
//!
//! # References
//! - T. Boubekeur, M. Alexa, "Phong tessellation", ACM Transactions on Graphics 27(5),
//!   SIGGRAPH Asia 2008.
//! - N. Max, "Weights for computing vertex normals from facet normals", Journal of
//!   Graphics Tools 4(2), 1999.

use beltrami_halfedge::{DVec3, EdgeId, FaceId, HalfedgeId, HalfedgeMesh, VertexId};

/// The shape factor α of the lift: ½ reproduces spheres (see the module's text).
pub(super) const SHAPE_FACTOR: f64 = 0.5;

/// A triangle is lifted only where its three corner normals are within this angle
/// (radians, 30°) of each other; elsewhere (along sharp edges that are not features)
/// the projection stays on the flat triangle.
pub const SMOOTH_ANGLE: f64 = std::f64::consts::PI / 6.0;

/// The input's vertex normals, for the Phong lift of closest points.
pub(super) struct PhongSurface {
    /// Per vertex, the unit normal of its whole fan; zero where a crease (feature or
    /// boundary edge) cuts the fan, whose corners then have normals of their own.
    vertex_normals: Vec<DVec3>,
    /// Per face: [`SMOOTH`] (its corners take their vertices' normals), [`FLAT`] (not
    /// lifted: corner normals more than [`SMOOTH_ANGLE`] apart, or one undefined in a
    /// fan of degenerate triangles), or an index into `corner_normals`.
    faces: Vec<u32>,
    /// The corner normals of the lifted faces that touch a creased vertex, in the order
    /// of [`HalfedgeMesh::triangle_vertices`].
    corner_normals: Vec<[DVec3; 3]>,
}

/// A face whose corners take their vertices' normals.
const SMOOTH: u32 = u32::MAX;
/// A face that is not lifted.
const FLAT: u32 = u32::MAX - 1;

impl PhongSurface {
    /// The corner normals of the triangle mesh `mesh` with `positions`; `feature(e)` says
    /// whether edge `e` is a feature (boundary edges are creases in any case).
    pub(super) fn new(
        mesh: &HalfedgeMesh,
        positions: &[DVec3],
        feature: impl Fn(EdgeId) -> bool,
    ) -> Self {
        let crease: Vec<bool> = mesh
            .edges()
            .map(|e| feature(e) || mesh.is_boundary_edge(e))
            .collect();
        // The edges a, b at the corner of outgoing halfedge `h`'s triangle, a × b its
        // normal (twice the area).
        let corner = |h: HalfedgeId| {
            let p = positions[mesh.from_vertex(h).index()];
            let a = positions[mesh.to_vertex(h).index()] - p;
            let b = positions[mesh.from_vertex(mesh.prev(h)).index()] - p;
            (a, b)
        };
        // The corners of the fan of the face of `h` (outgoing from its vertex), up to the
        // creases, into `fan`.
        let collect_fan = |h: HalfedgeId, fan: &mut Vec<HalfedgeId>| {
            fan.clear();
            fan.push(h);
            // Counter-clockwise: cross the edge of prev(g) into the next face.
            let mut ccw_end = h;
            loop {
                if crease[mesh.prev(ccw_end).edge().index()] {
                    break;
                }
                let g = mesh.ccw_rotated(ccw_end);
                if g == h {
                    return;
                }
                if mesh.face(g).is_none() {
                    break;
                }
                fan.push(g);
                ccw_end = g;
            }
            // Clockwise: cross the edge of g into the previous face.
            let mut cw_end = h;
            loop {
                if crease[cw_end.edge().index()] {
                    break;
                }
                let g = mesh.cw_rotated(cw_end);
                if g == h || mesh.face(g).is_none() {
                    break;
                }
                fan.push(g);
                cw_end = g;
            }
        };
        // The fan's normal with Max's (1999) weights: Σ uᵢ × uᵢ₊₁ over its corners, with
        // uᵢ = eᵢ / |eᵢ|² for the edges eᵢ from the vertex in fan order. For vertices on a
        // sphere the uᵢ lie in one plane normal to the sphere's, so the sum over the
        // closed polygon of the uᵢ is exact however uneven the triangles (angle or area
        // weights are off by up to a degree on a scan's triangles, and the lift by
        // several sagittas). An open fan (at the boundary or a feature) is summed as it
        // is: closing its polygon with a term from the last edge to the first would make
        // it exact on a sphere, but that term joins two nearly opposite edges and, on the
        // F-lens, doubles the lift's error at the rim. A fold of the triangles can wind
        // the polygon the other way round, so the sum is turned to the side of the fan's
        // area-weighted normal.
        let mut fan = Vec::new();
        let mut fan_normal = |h: HalfedgeId| {
            collect_fan(h, &mut fan);
            let u = |e: DVec3| e / e.length_squared();
            let (mut sum, mut area) = (DVec3::ZERO, DVec3::ZERO);
            for &g in &fan {
                let (a, b) = corner(g);
                area += a.cross(b);
                sum += u(a).cross(u(b));
            }
            if sum.dot(area) < 0.0 {
                sum = -sum;
            }
            if sum.is_finite() {
                sum.normalize_or_zero()
            } else {
                DVec3::ZERO
            }
        };
        // A vertex with no crease at it has one fan for all its corners: one normal,
        // computed once (24 B per vertex, where a normal per corner took 72 B per face).
        let vertex_normals: Vec<DVec3> = mesh
            .vertices()
            .map(|v| {
                let Some(h) = mesh.outgoing_halfedge(v) else {
                    return DVec3::ZERO;
                };
                let creased = mesh
                    .halfedges_around_vertex(v)
                    .any(|g| crease[g.edge().index()]);
                if creased { DVec3::ZERO } else { fan_normal(h) }
            })
            .collect();
        let creased = |v: VertexId| vertex_normals[v.index()] == DVec3::ZERO;
        let mut corner_normals = Vec::new();
        let faces = mesh
            .faces()
            .map(|f| {
                // triangle_vertices(f) are the targets of h₀, h₁, h₂: the corner at
                // to_vertex(hᵢ) is the start of next(hᵢ).
                let h0 = mesh.face_halfedge(f);
                let h1 = mesh.next(h0);
                let h2 = mesh.next(h1);
                let corners = [h1, h2, h0];
                let own = corners.iter().any(|&h| creased(mesh.from_vertex(h)));
                let normals = corners.map(|h| {
                    let normal = vertex_normals[mesh.from_vertex(h).index()];
                    if normal == DVec3::ZERO {
                        fan_normal(h)
                    } else {
                        normal
                    }
                });
                let [n0, n1, n2] = normals;
                let smooth = [(n0, n1), (n1, n2), (n2, n0)].iter().all(|(m, n)| {
                    let angle = m.angle_between(*n);
                    angle.is_finite() && angle <= SMOOTH_ANGLE
                });
                if !smooth {
                    FLAT
                } else if own {
                    corner_normals.push(normals);
                    u32::try_from(corner_normals.len() - 1).unwrap_or(FLAT)
                } else {
                    SMOOTH
                }
            })
            .collect();
        Self {
            vertex_normals,
            faces,
            corner_normals,
        }
    }

    /// The corner normals of face `f`, whose vertices are `vertices`, or `None` when `f`
    /// is not lifted.
    fn normals(&self, f: FaceId, vertices: [VertexId; 3]) -> Option<[DVec3; 3]> {
        match self.faces[f.index()] {
            SMOOTH => Some(vertices.map(|v| self.vertex_normals[v.index()])),
            FLAT => None,
            k => Some(self.corner_normals[k as usize]),
        }
    }

    /// The Phong lift of `q`, a point of face `f` whose vertices are `vertices` at
    /// `corners` (in [`HalfedgeMesh::triangle_vertices`] order) with barycentric weights
    /// `weights`. `q` itself where the face is not lifted.
    pub(super) fn lift(
        &self,
        f: FaceId,
        vertices: [VertexId; 3],
        corners: [DVec3; 3],
        weights: [f64; 3],
        q: DVec3,
    ) -> DVec3 {
        let Some(normals) = self.normals(f, vertices) else {
            return q;
        };
        let mut offset = DVec3::ZERO;
        for ((p, n), w) in corners.iter().zip(normals).zip(weights) {
            offset += w * (q - *p).dot(n) * n;
        }
        let lifted = q - SHAPE_FACTOR * offset;
        if lifted.is_finite() { lifted } else { q }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use beltrami_halfedge::primitives;

    /// On an icosphere the lift of a facet's points lands on the unit sphere to under
    /// 0.5 % of the facet's sagitta (level 4: 1.9e-6 against 1.1e-3), where the flat
    /// points are up to the sagitta deep; the error is of fourth order in the edge length,
    /// so the ratio shrinks about fourfold per level.
    #[test]
    fn the_lift_puts_facet_points_on_the_sphere() {
        let sphere = primitives::icosphere(4);
        let mesh = sphere.mesh().unwrap();
        let surface = PhongSurface::new(&mesh, &sphere.positions, |_| false);
        let (mut flat, mut lifted) = (0f64, 0f64);
        for f in mesh.faces() {
            let vertices = mesh.triangle_vertices(f);
            let corners = vertices.map(|v| sphere.positions[v.index()]);
            for weights in [
                [1.0 / 3.0; 3],
                [0.5, 0.5, 0.0],
                [0.2, 0.3, 0.5],
                [1.0, 0.0, 0.0],
            ] {
                let q = corners[0] * weights[0] + corners[1] * weights[1] + corners[2] * weights[2];
                flat = flat.max((q.length() - 1.0).abs());
                let r = surface.lift(f, vertices, corners, weights, q);
                lifted = lifted.max((r.length() - 1.0).abs());
            }
        }
        assert!(flat > 1e-3, "sagitta {flat}");
        assert!(lifted < 5e-3 * flat, "lifted {lifted} against flat {flat}");
    }

    /// Max's normals with the orientation rule are exact for vertices on a sphere: on an
    /// icosphere whose vertices were pushed along the sphere by up to 0.45 of an edge
    /// (folding some triangles), with a cap cut off, every corner normal of a closed fan
    /// is radial; those of the open fans at the hole's rim are within two edges' turn.
    #[test]
    fn corner_normals_are_radial_on_an_uneven_sphere_with_folds_and_a_hole() {
        let sphere = primitives::icosphere(3);
        let mesh = sphere.mesh().unwrap();
        let edge = sphere.positions[0].distance(
            sphere.positions[mesh
                .to_vertex(mesh.outgoing_halfedge(VertexId::new(0)).unwrap())
                .index()],
        );
        // A fixed pseudo-random tangential push of each vertex, back onto the sphere.
        let positions: Vec<DVec3> = sphere
            .positions
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let t = i as f64;
                let push = DVec3::new((t * 12.9898).sin(), (t * 78.233).sin(), (t * 37.719).sin());
                let tangential = push - push.dot(*p) * *p;
                (*p + 0.45 * edge * tangential).normalize()
            })
            .collect();
        let faces: Vec<[u32; 3]> = mesh
            .faces()
            .map(|f| mesh.triangle_vertices(f).map(|v| v.index() as u32))
            .filter(|t| t.iter().any(|&v| positions[v as usize].z < 0.8))
            .collect();
        let used: Vec<bool> = (0..positions.len())
            .map(|v| faces.iter().any(|t| t.contains(&(v as u32))))
            .collect();
        assert!(used.iter().any(|u| !u), "the cap is cut off");
        let cut = HalfedgeMesh::from_polygons(positions.len(), &faces).unwrap();
        assert!(
            cut.vertices()
                .any(|v| cut.is_boundary_vertex(v) && !cut.is_isolated(v))
        );
        let folds = cut
            .faces()
            .filter(|&f| {
                let [a, b, c] = cut.triangle_vertices(f).map(|v| positions[v.index()]);
                (b - a).cross(c - a).dot(a + b + c) < 0.0
            })
            .count();
        assert!(folds > 0, "some triangles fold");
        let surface = PhongSurface::new(&cut, &positions, |_| false);
        let (mut worst, mut rim) = (0f64, 0f64);
        for f in cut.faces() {
            let vertices = cut.triangle_vertices(f);
            let Some(normals) = surface.normals(f, vertices) else {
                continue;
            };
            for (v, n) in vertices.iter().zip(normals) {
                let off = n.angle_between(positions[v.index()]);
                if cut.is_boundary_vertex(*v) {
                    rim = rim.max(off);
                } else {
                    worst = worst.max(off);
                }
            }
        }
        // Exact up to rounding (2e-8 here, at a fold whose polygon of the uᵢ is small);
        // angle-weighted normals are off by degrees on such a mesh.
        assert!(worst < 1e-7, "{worst} rad off the radial direction");
        // The open fans' normals are off by about the angle one edge turns on the sphere
        // (0.18 rad here, with edges of 0.15 rad, pushed and folded).
        assert!(rim > worst && rim < 2.0 * edge, "{rim} rad off at the rim");
    }

    /// A cube's faces stay flat without features: the corner normals of every triangle
    /// differ by 70° or more, so no triangle is lifted.
    #[test]
    fn flat_faces_between_creases_stay_flat() {
        let cube = primitives::cube();
        let mesh = cube.mesh().unwrap();
        let surface = PhongSurface::new(&mesh, &cube.positions, |_| false);
        for f in mesh.faces() {
            let vertices = mesh.triangle_vertices(f);
            let corners = vertices.map(|v| cube.positions[v.index()]);
            let weights = [0.2, 0.3, 0.5];
            let q = corners[0] * 0.2 + corners[1] * 0.3 + corners[2] * 0.5;
            assert!(surface.normals(f, vertices).is_none());
            let r = surface.lift(f, vertices, corners, weights, q);
            assert!(
                r.distance(q) < 1e-15,
                "face {f:?} moved by {}",
                r.distance(q)
            );
        }
    }
}
