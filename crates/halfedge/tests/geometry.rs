//! Geometry over positions: closed-form values on the procedural primitives, invariants
//! (sums, Gauss–Bonnet, rigid motions, scaling) and degenerate input.
//!
//! Expected values are derived by hand in the comments beside each assertion.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_3, FRAC_PI_4, PI, TAU};

use beltrami_halfedge::geometry::{DEGENERACY_RATIO, Geometry, NormalWeighting, VertexAreaKind};
use beltrami_halfedge::primitives::{self, Primitive};
use beltrami_halfedge::{DVec3, EdgeId, FaceId, HalfedgeMesh, TopologyError, VertexId};
use glam::DQuat;
use proptest::prelude::*;

const WEIGHTINGS: [NormalWeighting; 3] = [
    NormalWeighting::Mean,
    NormalWeighting::Area,
    NormalWeighting::Angle,
];
const AREA_KINDS: [VertexAreaKind; 2] = [VertexAreaKind::Barycentric, VertexAreaKind::MixedVoronoi];

/// A mesh with its positions.
#[derive(Clone, Debug)]
struct Fixture {
    mesh: HalfedgeMesh,
    positions: Vec<DVec3>,
}

impl Fixture {
    fn new(p: Primitive) -> Self {
        let mesh = p.mesh().expect("primitive builds");
        mesh.check_integrity().expect("primitive is valid");
        Self {
            mesh,
            positions: p.positions,
        }
    }

    fn from_faces<F: AsRef<[u32]>>(positions: Vec<DVec3>, faces: &[F]) -> Self {
        let mesh = HalfedgeMesh::from_polygons(positions.len(), faces).expect("valid faces");
        mesh.check_integrity().expect("valid mesh");
        Self { mesh, positions }
    }

    fn geometry(&self) -> Geometry<'_> {
        Geometry::new(&self.mesh, &self.positions).expect("one position per vertex")
    }

    fn mapped(&self, f: impl Fn(DVec3) -> DVec3) -> Self {
        Self {
            mesh: self.mesh.clone(),
            positions: self.positions.iter().map(|&p| f(p)).collect(),
        }
    }
}

fn v(i: u32) -> VertexId {
    VertexId::new(i)
}

fn f(i: u32) -> FaceId {
    FaceId::new(i)
}

#[track_caller]
fn assert_near(actual: f64, expected: f64, tol: f64) {
    assert!(
        (actual - expected).abs() <= tol,
        "{actual} differs from {expected} by {:e} (tolerance {tol:e})",
        (actual - expected).abs()
    );
}

#[track_caller]
fn assert_rel(actual: f64, expected: f64, rel: f64) {
    assert!(
        (actual - expected).abs() <= rel * expected.abs(),
        "{actual} differs from {expected} by {:e} relative (tolerance {rel:e})",
        ((actual - expected) / expected).abs()
    );
}

#[track_caller]
fn assert_vec_near(actual: DVec3, expected: DVec3, tol: f64) {
    assert!(
        (actual - expected).length() <= tol,
        "{actual} differs from {expected} by {:e} (tolerance {tol:e})",
        (actual - expected).length()
    );
}

/// The sum of the corner angles at `v` (over the halfedges entering it).
fn angle_sum(g: &Geometry<'_>, v: VertexId) -> f64 {
    g.mesh()
        .halfedges_around_vertex(v)
        .map(|h| g.corner_angle(h.twin()))
        .sum()
}

/// Σ_v (2π − angle sum), the total angle defect; 2π χ on a closed mesh (Gauss–Bonnet).
fn total_angle_defect(g: &Geometry<'_>) -> f64 {
    g.mesh().vertices().map(|v| TAU - angle_sum(g, v)).sum()
}

/// OpenMesh's normalisation, written out: `n * (1 / sqrt(x² + y² + z²))`, ZERO for 0.
fn openmesh_normalize(n: [f64; 3]) -> DVec3 {
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if len != 0.0 {
        let r = 1.0 / len;
        DVec3::new(n[0] * r, n[1] * r, n[2] * r)
    } else {
        DVec3::ZERO
    }
}

/// OpenMesh's `calc_face_normal(p0, p1, p2)`, written out component by component.
fn openmesh_triangle_normal(p0: DVec3, p1: DVec3, p2: DVec3) -> DVec3 {
    let a = [p2.x - p1.x, p2.y - p1.y, p2.z - p1.z]; // p1p2
    let b = [p0.x - p1.x, p0.y - p1.y, p0.z - p1.z]; // p1p0
    openmesh_normalize([
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ])
}

/// OpenMesh's Newell loop for polygons, written out.
fn openmesh_newell_normal(ps: &[DVec3]) -> DVec3 {
    let mut n = [0.0; 3];
    for (i, &p) in ps.iter().enumerate() {
        let q = ps[(i + 1) % ps.len()];
        let a = [p.x - q.x, p.y - q.y, p.z - q.z];
        let b = [p.x + q.x, p.y + q.y, p.z + q.z];
        n[0] += a[1] * b[2];
        n[1] += a[2] * b[0];
        n[2] += a[0] * b[1];
    }
    openmesh_normalize(n)
}

fn bits(v: DVec3) -> [u64; 3] {
    [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()]
}

// ---------------------------------------------------------------------------------------
// The view

#[test]
fn positions_must_match_the_vertices() {
    let fx = Fixture::new(primitives::triangle());
    for n in [0, 2, 4] {
        let positions = vec![DVec3::ZERO; n];
        assert_eq!(
            Geometry::new(&fx.mesh, &positions).unwrap_err(),
            TopologyError::PositionCount {
                positions: n,
                vertices: 3
            }
        );
    }
    let g = fx.geometry();
    assert_eq!(g.positions(), &fx.positions[..]);
    assert_eq!(g.position(v(1)), DVec3::X);
    assert_eq!(g.mesh().n_faces(), 1);
}

// ---------------------------------------------------------------------------------------
// Closed forms on the primitives

#[test]
fn unit_triangle() {
    // (0,0,0), (1,0,0), (0,1,0): a right isosceles triangle with legs 1.
    let fx = Fixture::new(primitives::triangle());
    let g = fx.geometry();
    let m = &fx.mesh;

    assert_eq!(g.face_area(f(0)), 0.5);
    assert_eq!(g.surface_area(), 0.5);
    // (p2 − p1) × (p0 − p1) = (−1, 1, 0) × (−1, 0, 0) = (0, 0, 1): exactly +z.
    assert_eq!(g.face_normal(f(0)), DVec3::Z);
    assert_eq!(g.face_vector_area(f(0)), DVec3::new(0.0, 0.0, 0.5));
    assert_vec_near(
        g.face_centroid(f(0)),
        DVec3::new(1.0, 1.0, 0.0) / 3.0,
        1e-16,
    );
    assert!(!g.is_degenerate_face(f(0)));

    // Edges 0–1 and 0–2 have length 1, 1–2 has √2.
    let mut lengths: Vec<f64> = m.edges().map(|e| g.edge_length(e)).collect();
    lengths.sort_by(f64::total_cmp);
    assert_eq!(lengths, [1.0, 1.0, 2f64.sqrt()]);
    assert_near(
        g.mean_edge_length().unwrap(),
        (2.0 + 2f64.sqrt()) / 3.0,
        1e-15,
    );

    // Angles: π/2 at vertex 0, π/4 at 1 and 2. Cotangents: 0, 1, 1.
    for h in m.halfedges() {
        let opposite = m.opposite_vertex(h);
        match opposite.map(VertexId::raw) {
            None => {
                assert_eq!(g.opposite_angle(h), None);
                assert_eq!(g.opposite_cotangent(h), 0.0);
                assert_eq!(g.corner_angle(h), 0.0);
            }
            Some(0) => {
                assert_near(g.opposite_angle(h).unwrap(), FRAC_PI_2, 1e-15);
                assert_eq!(g.opposite_cotangent(h), 0.0);
            }
            Some(_) => {
                assert_near(g.opposite_angle(h).unwrap(), FRAC_PI_4, 1e-15);
                assert_eq!(g.opposite_cotangent(h), 1.0);
            }
        }
    }
    assert_near(angle_sum(&g, v(0)), FRAC_PI_2, 1e-15);
    assert_near(angle_sum(&g, v(1)), FRAC_PI_4, 1e-15);

    // Barycentric: A/3 each. Mixed (right triangle, Voronoi rule): at the right angle
    // ⅛(1·cot 45° + 1·cot 45°) = ¼; at a 45° corner ⅛(|leg|² cot 45° + |hyp|² cot 90°) = ⅛.
    for i in 0..3 {
        assert_near(
            g.vertex_area(v(i), VertexAreaKind::Barycentric),
            1.0 / 6.0,
            1e-16,
        );
    }
    let mixed = |i| g.vertex_area(v(i), VertexAreaKind::MixedVoronoi);
    assert_eq!((mixed(0), mixed(1), mixed(2)), (0.25, 0.125, 0.125));

    for w in WEIGHTINGS {
        for i in 0..3 {
            assert_eq!(g.vertex_normal(v(i), w), DVec3::Z, "{w:?}");
        }
    }
    assert_eq!(
        g.bounding_box(),
        Some((DVec3::ZERO, DVec3::new(1.0, 1.0, 0.0)))
    );
    assert_vec_near(
        g.surface_centroid().unwrap(),
        DVec3::new(1.0, 1.0, 0.0) / 3.0,
        1e-16,
    );
    assert_eq!(
        g.volume(),
        Err(TopologyError::NotClosed { boundary_loops: 1 })
    );
}

#[test]
fn hexagon_fan() {
    // Six equilateral triangles of side 1 around the centre vertex 0.
    let fx = Fixture::new(primitives::hexagon_fan());
    let g = fx.geometry();
    let m = &fx.mesh;
    let sqrt3 = 3f64.sqrt();

    for face in m.faces() {
        assert_near(g.face_area(face), sqrt3 / 4.0, 1e-15);
        assert_vec_near(g.face_normal(face), DVec3::Z, 1e-15);
        assert!(!g.is_degenerate_face(face));
    }
    assert_near(g.surface_area(), 3.0 * sqrt3 / 2.0, 1e-14);
    for e in m.edges() {
        assert_near(g.edge_length(e), 1.0, 1e-15);
    }
    assert_near(g.mean_edge_length().unwrap(), 1.0, 1e-15);

    for h in m.halfedges() {
        if m.is_boundary_halfedge(h) {
            assert_eq!(g.opposite_angle(h), None);
            assert_eq!(g.opposite_cotangent(h), 0.0);
            assert_eq!(g.corner_angle(h), 0.0);
        } else {
            assert_near(g.corner_angle(h), FRAC_PI_3, 1e-14);
            assert_near(g.opposite_angle(h).unwrap(), FRAC_PI_3, 1e-14);
            assert_near(g.opposite_cotangent(h), 1.0 / sqrt3, 1e-14);
        }
    }
    // Full turn at the centre; two corners of 60° at a rim vertex.
    assert_near(angle_sum(&g, v(0)), TAU, 1e-14);
    for i in 1..7 {
        assert_near(angle_sum(&g, v(i)), 2.0 * FRAC_PI_3, 1e-14);
    }

    // Equilateral triangles: the Voronoi share ⅛(1·cot 60° + 1·cot 60°) = 1/(4√3) equals
    // the barycentric A/3 = √3/12. Centre: six shares, √3/2; rim vertex: two, √3/6.
    for kind in AREA_KINDS {
        assert_near(g.vertex_area(v(0), kind), sqrt3 / 2.0, 1e-14);
        for i in 1..7 {
            assert_near(g.vertex_area(v(i), kind), sqrt3 / 6.0, 1e-14);
        }
    }
    for w in WEIGHTINGS {
        for vertex in m.vertices() {
            assert_vec_near(g.vertex_normal(vertex, w), DVec3::Z, 1e-15);
        }
    }
    assert_vec_near(g.surface_centroid().unwrap(), DVec3::ZERO, 1e-15);
    assert_eq!(
        g.volume(),
        Err(TopologyError::NotClosed { boundary_loops: 1 })
    );
}

#[test]
fn grid() {
    let (nx, ny) = (5u32, 4u32);
    let fx = Fixture::new(primitives::grid(nx, ny));
    let g = fx.geometry();
    let m = &fx.mesh;
    let id = |i: u32, j: u32| v(j * (nx + 1) + i);

    // Every triangle is half a unit square; integer coordinates make it exact.
    for face in m.faces() {
        assert_eq!(g.face_area(face), 0.5);
        assert_eq!(g.face_normal(face), DVec3::Z);
    }
    assert_eq!(g.surface_area(), f64::from(nx * ny));
    for w in WEIGHTINGS {
        for vertex in m.vertices() {
            assert_eq!(g.vertex_normal(vertex, w), DVec3::Z, "{w:?}");
        }
    }

    for kind in AREA_KINDS {
        let areas = g.vertex_areas(kind).unwrap();
        let total: f64 = areas.as_slice().iter().sum();
        assert_near(total, f64::from(nx * ny), 1e-13);
        // Interior vertices: six triangles, the Voronoi cell is the unit square around it.
        for j in 1..ny {
            for i in 1..nx {
                assert_near(areas[id(i, j)], 1.0, 1e-15);
            }
        }
    }
    // Mixed areas are exact here: right angle → ¼, 45° corner → ⅛.
    let mixed = g.vertex_areas(VertexAreaKind::MixedVoronoi).unwrap();
    assert_eq!(mixed[id(2, 2)], 1.0);
    // Corner (0, 0): two 45° corners → ¼ (Voronoi cell [0, ½]²); barycentric 2·(½)/3.
    assert_eq!(mixed[id(0, 0)], 0.25);
    assert_near(
        g.vertex_area(id(0, 0), VertexAreaKind::Barycentric),
        1.0 / 3.0,
        1e-16,
    );
    // Bottom edge midpoint (2, 0): one right angle and two 45° corners → ½.
    assert_eq!(mixed[id(2, 0)], 0.5);

    // Interior angle sums are 2π, the flat grid has no defect inside.
    for j in 1..ny {
        for i in 1..nx {
            assert_near(angle_sum(&g, id(i, j)), TAU, 1e-14);
        }
    }
    assert_eq!(
        g.bounding_box(),
        Some((DVec3::ZERO, DVec3::new(f64::from(nx), f64::from(ny), 0.0)))
    );
    assert_vec_near(
        g.surface_centroid().unwrap(),
        DVec3::new(2.5, 2.0, 0.0),
        1e-14,
    );
    assert_eq!(
        g.volume(),
        Err(TopologyError::NotClosed { boundary_loops: 1 })
    );
}

#[test]
fn cube() {
    let fx = Fixture::new(primitives::cube());
    let g = fx.geometry();
    let m = &fx.mesh;

    assert_eq!(g.surface_area(), 6.0);
    assert_eq!(g.volume(), Ok(1.0));
    // Two triangles per side, in the order of `primitives::cube`.
    let sides = [
        -DVec3::Z,
        DVec3::Z,
        -DVec3::Y,
        DVec3::Y,
        -DVec3::X,
        DVec3::X,
    ];
    for face in m.faces() {
        assert_eq!(g.face_normal(face), sides[face.index() / 2], "{face:?}");
        assert_eq!(g.face_area(face), 0.5);
    }
    // Each corner sees a right angle from each of its three sides (one 90° corner or two
    // 45° corners): 3π/2, so the total defect is 8·π/2 = 4π = 2π·χ with χ = 2.
    for vertex in m.vertices() {
        assert_near(angle_sum(&g, vertex), 1.5 * PI, 1e-14);
    }
    assert_near(total_angle_defect(&g), 2.0 * TAU, 1e-13);

    // Angle-weighted normals see a right angle from each side: the diagonal, whatever
    // the split of the sides.
    for vertex in m.vertices() {
        let p = g.position(vertex);
        let diagonal = (p - DVec3::splat(0.5)).normalize();
        assert_vec_near(
            g.vertex_normal(vertex, NormalWeighting::Angle),
            diagonal,
            1e-15,
        );
    }
    // Vertex 1 = (1,0,0) lies in [0,3,1] (−z), [0,1,5] (−y), [1,3,7] and [1,7,5] (+x):
    // the mean and the area-weighted normal are (2, −1, −1)/√6.
    for w in [NormalWeighting::Mean, NormalWeighting::Area] {
        assert_vec_near(
            g.vertex_normal(v(1), w),
            DVec3::new(2.0, -1.0, -1.0) / 6f64.sqrt(),
            1e-15,
        );
    }
    // Vertex 0 lies in two triangles of each of its three sides.
    assert_vec_near(
        g.vertex_normal(v(0), NormalWeighting::Mean),
        -DVec3::ONE / 3f64.sqrt(),
        1e-15,
    );

    for kind in AREA_KINDS {
        let total: f64 = g.vertex_areas(kind).unwrap().as_slice().iter().sum();
        assert_near(total, 6.0, 1e-14);
    }
    assert_eq!(g.bounding_box(), Some((DVec3::ZERO, DVec3::ONE)));
    assert_vec_near(g.surface_centroid().unwrap(), DVec3::splat(0.5), 1e-15);
    assert_near(
        g.mean_edge_length().unwrap(),
        (12.0 + 6.0 * 2f64.sqrt()) / 18.0,
        1e-15,
    );
}

#[test]
fn cube_volume_does_not_depend_on_the_origin() {
    let fx = Fixture::new(primitives::cube());
    for t in [
        DVec3::new(0.1, 0.2, 0.3),
        DVec3::new(-123.456, 78.9, 1e4 + 0.1),
        DVec3::new(1e6 + 0.3, -2e6 + 0.7, 3e6 + 0.11),
    ] {
        let moved = fx.mapped(|p| p + t);
        let g = moved.geometry();
        // Translating rounds the positions by up to ½ ulp of |t| (1e6 → 1.2e-10): the
        // cube's sides move by that much, and so does the volume.
        let tol = 8.0 * f64::EPSILON * t.abs().max_element().max(1.0);
        assert_near(g.volume().unwrap(), 1.0, tol);
        assert_near(g.surface_area(), 6.0, tol);
        assert_vec_near(g.surface_centroid().unwrap(), t + DVec3::splat(0.5), tol);
    }
}

#[test]
fn tetrahedron() {
    // Regular tetrahedron inscribed in the unit sphere: edge a = √(8/3), area √3·a² = 8/√3,
    // volume a³/(6√2) = 8/(9√3); every face angle π/3.
    let fx = Fixture::new(primitives::tetrahedron());
    let g = fx.geometry();
    let m = &fx.mesh;
    let sqrt3 = 3f64.sqrt();

    for e in m.edges() {
        assert_near(g.edge_length(e), (8.0f64 / 3.0).sqrt(), 1e-15);
    }
    assert_near(g.surface_area(), 8.0 / sqrt3, 1e-14);
    assert_near(g.volume().unwrap(), 8.0 / (9.0 * sqrt3), 1e-15);
    for h in m.halfedges() {
        assert_near(g.corner_angle(h), FRAC_PI_3, 1e-15);
        assert_near(g.opposite_cotangent(h), 1.0 / sqrt3, 1e-15);
    }
    // Each face normal points away from the opposite vertex, i.e. along −(that vertex).
    for face in m.faces() {
        let corners = m.triangle_vertices(face);
        let opposite = m.vertices().find(|v| !corners.contains(v)).unwrap();
        assert_vec_near(g.face_normal(face), -g.position(opposite), 1e-15);
    }
    // By symmetry every vertex normal is radial, under every weighting.
    for w in WEIGHTINGS {
        for vertex in m.vertices() {
            assert_vec_near(g.vertex_normal(vertex, w), g.position(vertex), 1e-15);
        }
    }
    // Angle defect 2π − 3·π/3 = π at each of the 4 vertices: 4π.
    assert_near(total_angle_defect(&g), 2.0 * TAU, 1e-14);
    // Pyramids from the centre: V = ⅓ Σ A_f (n_f · p_f).
    let pyramids: f64 = m
        .faces()
        .map(|face| {
            let p = g.position(m.triangle_vertices(face)[0]);
            g.face_area(face) * g.face_normal(face).dot(p) / 3.0
        })
        .sum();
    assert_near(g.volume().unwrap(), pyramids, 1e-15);
    assert_vec_near(g.surface_centroid().unwrap(), DVec3::ZERO, 1e-15);
}

/// Whether every vertex lies on or below the plane of every face.
fn is_convex(g: &Geometry<'_>) -> bool {
    let m = g.mesh();
    m.faces().all(|face| {
        let n = g.face_normal(face);
        let d = n.dot(g.position(m.triangle_vertices(face)[0]));
        g.positions().iter().all(|p| n.dot(*p) <= d + 1e-12)
    })
}

#[test]
fn icosphere_converges_to_the_sphere() {
    let sphere_area = 4.0 * PI;
    let ball_volume = 4.0 * PI / 3.0;
    let mut previous: Option<(f64, f64)> = None;
    for level in 0..=5 {
        let fx = Fixture::new(primitives::icosphere(level));
        let g = fx.geometry();
        let (area, volume) = (g.surface_area(), g.volume().unwrap());
        // Inscribed in the unit sphere: both fall short.
        assert!(area < sphere_area && volume < ball_volume, "level {level}");
        let (area_error, volume_error) = (sphere_area - area, ball_volume - volume);
        // Second order: each level halves the edges, the errors drop by about 4.
        if let Some((a, v)) = previous
            && level >= 3
        {
            assert!((3.8..4.2).contains(&(a / area_error)), "level {level}");
            assert!((3.8..4.2).contains(&(v / volume_error)), "level {level}");
        }
        previous = Some((area_error, volume_error));
        // A convex polyhedron has χ = 2: total defect 4π.
        assert_near(total_angle_defect(&g), 2.0 * TAU, 1e-11);
    }
}

#[test]
fn icosphere_level_4_lies_within_the_polyhedral_bounds() {
    let fx = Fixture::new(primitives::icosphere(4));
    let g = fx.geometry();
    let m = &fx.mesh;
    assert!(is_convex(&g));
    // A convex polyhedron inscribed in the unit sphere contains the ball of radius r_in,
    // the smallest distance from the centre to a face plane, and is contained in the unit
    // ball; area and volume are monotone under inclusion of convex bodies.
    let r_in = m
        .faces()
        .map(|face| {
            g.face_normal(face)
                .dot(g.position(m.triangle_vertices(face)[0]))
        })
        .fold(f64::INFINITY, f64::min);
    assert!(r_in > 0.99 && r_in < 1.0);
    let (area, volume) = (g.surface_area(), g.volume().unwrap());
    assert!(4.0 * PI * r_in * r_in <= area && area <= 4.0 * PI, "{area}");
    assert!(4.0 / 3.0 * PI * r_in.powi(3) <= volume && volume <= 4.0 / 3.0 * PI);
    // The volume is also the sum of the pyramids on the faces, ⅓ Σ A_f (n_f · p_f).
    let pyramids: f64 = m
        .faces()
        .map(|face| {
            let p = g.position(m.triangle_vertices(face)[0]);
            g.face_area(face) * g.face_normal(face).dot(p) / 3.0
        })
        .sum();
    assert_rel(volume, pyramids, 1e-13);
}

#[test]
fn icosphere_vertex_normals_are_radial() {
    let fx = Fixture::new(primitives::icosphere(4));
    let g = fx.geometry();
    let normals = WEIGHTINGS.map(|w| g.vertex_normals(w));
    for vertex in fx.mesh.vertices() {
        let radial = g.position(vertex).normalize();
        for (w, n) in WEIGHTINGS.iter().zip(&normals) {
            let n = n[vertex];
            assert_near(n.length(), 1.0, 1e-15);
            assert!(n.angle_between(radial) < 1e-2, "{w:?} at {vertex:?}");
        }
        for a in &normals {
            for b in &normals {
                assert!(a[vertex].angle_between(b[vertex]) < 1e-2);
            }
        }
    }
}

#[test]
fn icosphere_mean_curvature_from_cotangents_and_mixed_areas() {
    // Meyer et al. Eq. 8: K(x_i) = 1/(2 A_i) Σ_j (cot α_ij + cot β_ij)(x_i − x_j) is the
    // mean curvature normal 2 H n; on the unit sphere H = 1 and n is radial.
    let fx = Fixture::new(primitives::icosphere(4));
    let g = fx.geometry();
    let m = &fx.mesh;
    let areas = g.vertex_areas(VertexAreaKind::MixedVoronoi).unwrap();
    for vertex in m.vertices() {
        let mut k = DVec3::ZERO;
        for h in m.halfedges_around_vertex(vertex) {
            let w = g.opposite_cotangent(h) + g.opposite_cotangent(h.twin());
            k -= g.edge_vector(h) * w;
        }
        k /= 2.0 * areas[vertex];
        assert_vec_near(k, 2.0 * g.position(vertex), 2e-2);
    }
}

#[test]
fn torus_volume_is_the_polyhedral_closed_form() {
    // Each quad (i,j),(i+1,j),(i+1,j+1),(i,j+1) is a planar trapezoid, so the mesh bounds
    // the solid swept by the regular n_minor-gon (area ½ n r² sin(2π/n), centroid at
    // radius R) along straight chords between the n_major half-planes. Sweeping a section
    // through an angle step Δ along chords has volume sin(Δ)·R·A, so
    //     V = n_major sin(2π/n_major) · R · ½ n_minor r² sin(2π/n_minor),
    // which tends to 2π²Rr² with relative error about ((2π/n_major)² + (2π/n_minor)²)/6.
    let (major, minor) = (2.0, 0.5);
    let smooth = 2.0 * PI * PI * major * minor * minor;
    let mut previous_error: Option<f64> = None;
    for (n_major, n_minor) in [(16u32, 8u32), (32, 16), (64, 32), (128, 64)] {
        let fx = Fixture::new(primitives::torus(major, minor, n_major, n_minor));
        let g = fx.geometry();
        let (nm, nn) = (f64::from(n_major), f64::from(n_minor));
        let polyhedral =
            nm * (TAU / nm).sin() * major * 0.5 * nn * minor * minor * (TAU / nn).sin();
        let volume = g.volume().unwrap();
        assert_rel(volume, polyhedral, 1e-13);
        let error = (smooth - volume) / smooth;
        let predicted = ((TAU / nm).powi(2) + (TAU / nn).powi(2)) / 6.0;
        assert!(
            error > 0.0 && error < 1.1 * predicted,
            "{error} vs {predicted}"
        );
        if let Some(e) = previous_error {
            assert!((3.8..4.2).contains(&(e / error)));
        }
        previous_error = Some(error);
        // Genus 1: χ = 0, no total defect.
        assert_near(total_angle_defect(&g), 0.0, 1e-10);
        // Centred on the origin.
        assert_vec_near(g.surface_centroid().unwrap(), DVec3::ZERO, 1e-13);
    }
}

#[test]
fn volume_needs_a_closed_mesh() {
    // An open cylinder of four quads (two boundary loops).
    let mut positions = Vec::new();
    for z in [0.0, 1.0] {
        for k in 0..4 {
            let a = f64::from(k) * FRAC_PI_2;
            positions.push(DVec3::new(a.cos(), a.sin(), z));
        }
    }
    let faces: Vec<[u32; 4]> = (0..4)
        .map(|k| [k, (k + 1) % 4, 4 + (k + 1) % 4, 4 + k])
        .collect();
    let tube = Fixture::from_faces(positions, &faces);
    assert_eq!(
        tube.geometry().volume(),
        Err(TopologyError::NotClosed { boundary_loops: 2 })
    );
    // Removing one face of a closed mesh opens it.
    let cube = primitives::cube();
    let open = Fixture::from_faces(
        cube.positions,
        &cube.faces.iter().skip(1).collect::<Vec<_>>(),
    );
    assert_eq!(
        open.geometry().volume(),
        Err(TopologyError::NotClosed { boundary_loops: 1 })
    );
    // Reversing every face flips the sign.
    let cube = primitives::cube();
    let inward: Vec<Vec<u32>> = cube
        .faces
        .iter()
        .map(|face| face.iter().rev().copied().collect())
        .collect();
    let inside_out = Fixture::from_faces(cube.positions, &inward);
    assert_eq!(inside_out.geometry().volume(), Ok(-1.0));
}

#[test]
fn cube_quads_match_the_triangulated_cube() {
    let quads = Fixture::new(primitives::cube_quads());
    let tris = Fixture::new(primitives::cube());
    let (q, t) = (quads.geometry(), tris.geometry());

    assert_eq!(q.surface_area(), 6.0);
    assert_eq!(q.volume(), Ok(1.0));
    assert_eq!(q.surface_centroid(), t.surface_centroid());
    for face in quads.mesh.faces() {
        // Quad k is the side of triangles 2k and 2k + 1.
        assert_eq!(q.face_area(face), 1.0);
        assert_eq!(q.face_normal(face), t.face_normal(f(2 * face.raw())));
        assert_eq!(q.face_vector_area(face), q.face_normal(face));
        assert!(!q.is_degenerate_face(face));
        let c = q.face_centroid(face);
        assert_eq!(c.to_array().iter().filter(|&&x| x == 0.5).count(), 2);
    }
    for h in quads.mesh.halfedges() {
        assert_eq!(q.corner_angle(h), FRAC_PI_2);
        assert_eq!(q.opposite_angle(h), None);
        assert_eq!(q.opposite_cotangent(h), 0.0);
    }
    // Three quads at every corner: the diagonal for every weighting; a quarter of each.
    for vertex in quads.mesh.vertices() {
        let diagonal = (q.position(vertex) - DVec3::splat(0.5)).normalize();
        for w in WEIGHTINGS {
            assert_vec_near(q.vertex_normal(vertex, w), diagonal, 1e-15);
        }
        for kind in AREA_KINDS {
            assert_eq!(q.vertex_area(vertex, kind), 0.75);
        }
    }
    assert_eq!(
        q.vertex_areas(VertexAreaKind::MixedVoronoi),
        Err(TopologyError::NotTriangle { face: 0, len: 4 })
    );
    let bary = q.vertex_areas(VertexAreaKind::Barycentric).unwrap();
    assert_eq!(bary.as_slice(), &[0.75; 8]);
}

#[test]
fn polygon_normal_and_area_of_a_non_planar_quad() {
    // A skew quad: Newell's vector equals the sum of the fan's cross products,
    // (p1 − p0) × (p2 − p0) + (p2 − p0) × (p3 − p0).
    let positions = vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(2.0, 0.0, 0.5),
        DVec3::new(2.0, 1.0, 0.0),
        DVec3::new(0.0, 1.0, 0.5),
    ];
    let fx = Fixture::from_faces(positions.clone(), &[[0u32, 1, 2, 3]]);
    let g = fx.geometry();
    let [p0, p1, p2, p3] = [positions[0], positions[1], positions[2], positions[3]];
    let newell = (p1 - p0).cross(p2 - p0) + (p2 - p0).cross(p3 - p0);
    assert_vec_near(g.face_vector_area(f(0)), newell / 2.0, 1e-15);
    assert_near(g.face_area(f(0)), newell.length() / 2.0, 1e-15);
    assert_eq!(
        bits(g.face_normal(f(0))),
        bits(openmesh_newell_normal(&positions))
    );
    assert_vec_near(g.face_normal(f(0)), newell.normalize(), 1e-15);
    assert_vec_near(g.face_centroid(f(0)), DVec3::new(1.0, 0.5, 0.25), 1e-16);
}

// ---------------------------------------------------------------------------------------
// Agreement with OpenMesh's arithmetic

proptest! {
    #[test]
    fn triangle_normals_are_openmesh_bit_for_bit(
        c in proptest::array::uniform9(-1000.0f64..1000.0),
        scale in prop_oneof![Just(1.0), Just(1e-6), Just(1e6)],
    ) {
        let ps: Vec<DVec3> = c.chunks(3).map(|c| DVec3::new(c[0], c[1], c[2]) * scale).collect();
        let fx = Fixture::from_faces(ps.clone(), &[[0u32, 1, 2]]);
        let n = fx.geometry().face_normal(f(0));
        prop_assert_eq!(bits(n), bits(openmesh_triangle_normal(ps[0], ps[1], ps[2])));
    }

    #[test]
    fn polygon_normals_are_openmesh_bit_for_bit(
        c in proptest::array::uniform15(-1000.0f64..1000.0),
    ) {
        let ps: Vec<DVec3> = c.chunks(3).map(|c| DVec3::new(c[0], c[1], c[2])).collect();
        let fx = Fixture::from_faces(ps.clone(), &[[0u32, 1, 2, 3, 4]]);
        let n = fx.geometry().face_normal(f(0));
        prop_assert_eq!(bits(n), bits(openmesh_newell_normal(&ps)));
    }
}

#[test]
fn mean_vertex_normal_matches_openmesh_at_a_boundary_vertex() {
    // An open fan around vertex 0: f0 = [0,1,2], f1 = [0,2,3], f2 = [0,3,4]. OpenMesh's
    // vertex-face circulator runs clockwise from the outgoing boundary halfedge 0 → 4:
    // f2, f1, f0.
    let positions = vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(0.35, 0.93, 0.09),
        DVec3::new(-0.76, 0.73, 0.0),
        DVec3::new(-0.89, -0.53, 0.2),
        DVec3::new(0.03, -0.95, 0.02),
    ];
    let fx = Fixture::from_faces(positions, &[[0u32, 1, 2], [0, 2, 3], [0, 3, 4]]);
    let g = fx.geometry();
    let n = |i| g.face_normal(f(i));
    let clockwise = openmesh_normalize((n(2) + n(1) + n(0)).to_array());
    let counter_clockwise = openmesh_normalize((n(0) + n(1) + n(2)).to_array());
    // These positions are chosen so that the two orders round differently.
    assert_ne!(bits(clockwise), bits(counter_clockwise));
    // OpenMesh 9.0 (TriMesh with Vec3d points, these faces added in order,
    // update_normals) gives vertex 0 this normal.
    let openmesh = DVec3::new(0.09159282423302725, 0.03298322814883433, 0.9952501500677605);
    assert_eq!(bits(clockwise), bits(openmesh));
    assert_eq!(
        bits(g.vertex_normal(v(0), NormalWeighting::Mean)),
        bits(openmesh)
    );
}

#[test]
fn mean_vertex_normal_matches_openmesh_at_an_interior_vertex() {
    // A closed, non-planar fan of five triangles fk = [0, k+1, (k+1) % 5 + 1] around
    // vertex 0. OpenMesh's outgoing halfedge of an interior vertex lies in the face that
    // closed its fan, the last one added (f4), so its circulator visits f4, f3, f2, f1, f0.
    let positions = vec![
        DVec3::new(0.0, 0.0, 0.5),
        DVec3::new(0.24, 0.91, 0.14),
        DVec3::new(-0.83, 0.62, -0.07),
        DVec3::new(-0.82, -0.57, 0.03),
        DVec3::new(0.32, -0.86, 0.23),
        DVec3::new(0.95, 0.02, 0.24),
    ];
    let faces: Vec<[u32; 3]> = (1..=5).map(|k| [0, k, k % 5 + 1]).collect();
    let fx = Fixture::from_faces(positions, &faces);
    let g = fx.geometry();
    assert!(!fx.mesh.is_boundary_vertex(v(0)));
    let n = |i| g.face_normal(f(i));
    let from_last = openmesh_normalize((n(4) + n(3) + n(2) + n(1) + n(0)).to_array());
    let from_first = openmesh_normalize((n(0) + n(4) + n(3) + n(2) + n(1)).to_array());
    let counter_clockwise = openmesh_normalize((n(0) + n(1) + n(2) + n(3) + n(4)).to_array());
    assert_ne!(bits(from_last), bits(from_first));
    assert_ne!(bits(from_last), bits(counter_clockwise));
    // OpenMesh 9.0, as above.
    let openmesh = DVec3::new(-0.1234060185707186, 0.046606697966278, 0.9912612018460137);
    assert_eq!(bits(from_last), bits(openmesh));
    assert_eq!(
        bits(g.vertex_normal(v(0), NormalWeighting::Mean)),
        bits(openmesh)
    );
}

#[test]
fn plural_queries_equal_the_singular_ones_bit_for_bit() {
    for p in [
        primitives::icosphere(2),
        primitives::torus(1.0, 0.3, 10, 7),
        primitives::cube_quads(),
        primitives::hexagon_fan(),
    ] {
        let fx = Fixture::new(p);
        let g = fx.geometry();
        let m = &fx.mesh;
        let normals = g.face_normals();
        let areas = g.face_areas();
        for face in m.faces() {
            assert_eq!(bits(normals[face]), bits(g.face_normal(face)));
            assert_eq!(areas[face].to_bits(), g.face_area(face).to_bits());
        }
        for w in WEIGHTINGS {
            let all = g.vertex_normals(w);
            for vertex in m.vertices() {
                assert_eq!(bits(all[vertex]), bits(g.vertex_normal(vertex, w)));
            }
        }
        let bary = g.vertex_areas(VertexAreaKind::Barycentric).unwrap();
        for vertex in m.vertices() {
            assert_eq!(
                bary[vertex].to_bits(),
                g.vertex_area(vertex, VertexAreaKind::Barycentric).to_bits()
            );
        }
    }
}

// ---------------------------------------------------------------------------------------
// Invariants

#[test]
fn vertex_areas_sum_to_the_surface_area() {
    for p in [
        primitives::triangle(),
        primitives::hexagon_fan(),
        primitives::grid(7, 3),
        primitives::tetrahedron(),
        primitives::cube(),
        primitives::icosphere(3),
        primitives::torus(1.0, 0.4, 16, 9),
        // A torus so coarse that it has obtuse triangles.
        primitives::torus(1.0, 0.9, 3, 12),
    ] {
        let fx = Fixture::new(p);
        let g = fx.geometry();
        if fx.mesh.n_faces() == 72 {
            let obtuse = fx
                .mesh
                .halfedges()
                .filter(|&h| g.corner_angle(h) > FRAC_PI_2);
            assert!(obtuse.count() > 0);
        }
        let area = g.surface_area();
        for kind in AREA_KINDS {
            let areas = g.vertex_areas(kind).unwrap();
            assert!(areas.as_slice().iter().all(|&a| a > 0.0));
            let total: f64 = areas.as_slice().iter().sum();
            assert_rel(total, area, 1e-14);
        }
    }
}

#[test]
fn obtuse_triangle_mixed_areas() {
    // (0,0), (4,0), (2,1): area 2, the angle at (2,1) is obtuse
    // ((−2,−1)·(2,−1) = −3 < 0): A/2 there, A/4 at the others.
    let fx = Fixture::from_faces(
        vec![
            DVec3::ZERO,
            DVec3::new(4.0, 0.0, 0.0),
            DVec3::new(2.0, 1.0, 0.0),
        ],
        &[[0u32, 1, 2]],
    );
    let g = fx.geometry();
    let mixed = g.vertex_areas(VertexAreaKind::MixedVoronoi).unwrap();
    assert_eq!(mixed.as_slice(), &[0.5, 0.5, 1.0]);
    // cot of the obtuse angle: (u·v)/|u×v| = −3/4.
    let h = fx.mesh.find_halfedge(v(0), v(1)).unwrap();
    assert_eq!(g.opposite_cotangent(h), -0.75);
    // The acute angles: u = (4,0), v = (2,1) at vertex 0 → 8/4 = 2.
    let h = fx.mesh.find_halfedge(v(1), v(2)).unwrap();
    assert_eq!(g.opposite_cotangent(h), 2.0);
}

#[test]
fn cotangent_laplacian_of_a_linear_function_vanishes_on_a_plane() {
    // A grid with interior vertices jittered inside the plane z = 0 (deterministically),
    // rotated out of the coordinate planes: Σ_j (cot α + cot β)(x_j − x_i) = 0 inside.
    let base = Fixture::new(primitives::grid(6, 5));
    let rotation = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
    let mut fx = base.mapped(|p| p);
    for (i, p) in fx.positions.iter_mut().enumerate() {
        let vertex = v(i as u32);
        if !base.mesh.is_boundary_vertex(vertex) {
            let s = (i as f64 * 12.9898).sin() * 43758.5453;
            let t = (i as f64 * 78.233).sin() * 12345.678;
            *p += DVec3::new(s.fract() * 0.3, t.fract() * 0.3, 0.0);
        }
        *p = rotation * *p;
    }
    let g = fx.geometry();
    let m = &fx.mesh;
    for vertex in m.vertices().filter(|&x| !m.is_boundary_vertex(x)) {
        let mut lx = DVec3::ZERO;
        let mut total = 0.0;
        for h in m.halfedges_around_vertex(vertex) {
            let w = g.opposite_cotangent(h) + g.opposite_cotangent(h.twin());
            lx += g.edge_vector(h) * w;
            total += w.abs();
        }
        assert!(lx.length() < 1e-13 * total, "{vertex:?}: {lx}");
    }
}

#[test]
fn halfedge_quantities_are_consistent() {
    let fx = Fixture::new(primitives::torus(1.0, 0.35, 11, 7));
    let g = fx.geometry();
    let m = &fx.mesh;
    for h in m.halfedges() {
        assert_eq!(g.edge_vector(h), -g.edge_vector(h.twin()));
        assert_eq!(g.edge_length(h.edge()), g.edge_vector(h).length());
        // The opposite angle is the corner angle at the end of next(h).
        let angle = g.opposite_angle(h).unwrap();
        assert_eq!(angle, g.corner_angle(m.next(h)));
        assert_near(g.opposite_cotangent(h), 1.0 / angle.tan(), 1e-12);
    }
    // The three angles of each triangle sum to π.
    for face in m.faces() {
        let sum: f64 = m
            .halfedges_around_face(face)
            .map(|h| g.corner_angle(h))
            .sum();
        assert_near(sum, PI, 1e-14);
    }
    let mean = m.edges().map(|e| g.edge_length(e)).sum::<f64>() / m.n_edges() as f64;
    assert_near(g.mean_edge_length().unwrap(), mean, 1e-15);
}

// ---------------------------------------------------------------------------------------
// Degenerate input

/// Every query on every element is finite and unit normals are unit or zero.
fn assert_all_finite(g: &Geometry<'_>) {
    let m = g.mesh();
    for h in m.halfedges() {
        assert!(g.corner_angle(h).is_finite());
        assert!(g.opposite_cotangent(h).is_finite());
        assert!(g.opposite_angle(h).is_none_or(f64::is_finite));
        assert!(g.edge_length(h.edge()).is_finite());
    }
    for face in m.faces() {
        let n = g.face_normal(face);
        assert!(n == DVec3::ZERO || (n.length() - 1.0).abs() < 1e-15, "{n}");
        assert!(g.face_area(face).is_finite());
        assert!(g.face_vector_area(face).is_finite());
        assert!(g.face_centroid(face).is_finite());
    }
    for vertex in m.vertices() {
        for w in WEIGHTINGS {
            let n = g.vertex_normal(vertex, w);
            assert!(n == DVec3::ZERO || (n.length() - 1.0).abs() < 1e-15, "{n}");
        }
        for kind in AREA_KINDS {
            let a = g.vertex_area(vertex, kind);
            assert!(a.is_finite() && a >= 0.0);
        }
    }
    assert!(g.surface_area().is_finite());
    assert!(g.mean_edge_length().is_none_or(f64::is_finite));
    if let Ok(volume) = g.volume() {
        assert!(volume.is_finite());
    }
    assert!(g.surface_centroid().is_none_or(|c| c.is_finite()));
}

#[test]
fn collinear_triangle() {
    let fx = Fixture::from_faces(
        vec![DVec3::ZERO, DVec3::X, DVec3::new(2.0, 0.0, 0.0)],
        &[[0u32, 1, 2]],
    );
    let g = fx.geometry();
    assert_all_finite(&g);
    assert!(g.is_degenerate_face(f(0)));
    assert_eq!(g.face_area(f(0)), 0.0);
    assert_eq!(g.face_normal(f(0)), DVec3::ZERO);
    for h in fx.mesh.halfedges() {
        assert_eq!(g.opposite_cotangent(h), 0.0);
    }
    // Angles 0, π, 0: the middle vertex sees the other two in opposite directions.
    assert_eq!(angle_sum(&g, v(0)), 0.0);
    assert_near(angle_sum(&g, v(1)), PI, 1e-15);
    for kind in AREA_KINDS {
        assert_eq!(g.vertex_areas(kind).unwrap().as_slice(), &[0.0; 3]);
    }
    for w in WEIGHTINGS {
        assert_eq!(g.vertex_normal(v(1), w), DVec3::ZERO);
    }
    assert_eq!(g.surface_centroid(), None);
}

#[test]
fn coincident_vertices() {
    let fx = Fixture::from_faces(vec![DVec3::ONE; 3], &[[0u32, 1, 2]]);
    let g = fx.geometry();
    assert_all_finite(&g);
    assert!(g.is_degenerate_face(f(0)));
    for h in fx.mesh.halfedges() {
        assert_eq!(g.corner_angle(h), 0.0);
        assert_eq!(g.opposite_cotangent(h), 0.0);
        assert_eq!(g.edge_length(h.edge()), 0.0);
    }
    assert_eq!(g.face_centroid(f(0)), DVec3::ONE);
    assert_eq!(g.mean_edge_length(), Some(0.0));
}

#[test]
fn needles_on_both_sides_of_the_threshold() {
    let needle = |h: f64| {
        Fixture::from_faces(
            vec![DVec3::ZERO, DVec3::X, DVec3::new(0.5, h, 0.0)],
            &[[0u32, 1, 2]],
        )
    };
    // Height 1e-9: twice the area over the longest edge squared is 1e-9 > 1e-12.
    let thin = needle(1e-9);
    let g = thin.geometry();
    assert_all_finite(&g);
    assert!(!g.is_degenerate_face(f(0)));
    let apex = thin.mesh.find_halfedge(v(0), v(1)).unwrap();
    // At the apex u = (−0.5, −h), v = (0.5, −h): cot = (h² − ¼)/h ≈ −2.5e8.
    assert_rel(g.opposite_cotangent(apex), (1e-18 - 0.25) / 1e-9, 1e-9);
    assert_vec_near(g.face_normal(f(0)), DVec3::Z, 1e-15);

    // Height 1e-13: degenerate, every cotangent 0, no mixed area, normal still defined.
    let flat = needle(1e-13);
    let g = flat.geometry();
    assert_all_finite(&g);
    assert!(g.is_degenerate_face(f(0)));
    // Longest edge 1: the ratio is twice the area, 1e-13.
    assert!(2.0 * g.face_area(f(0)) <= DEGENERACY_RATIO);
    for h in flat.mesh.halfedges() {
        assert_eq!(g.opposite_cotangent(h), 0.0);
    }
    for vertex in flat.mesh.vertices() {
        assert_eq!(g.vertex_area(vertex, VertexAreaKind::MixedVoronoi), 0.0);
        assert_eq!(g.vertex_normal(vertex, NormalWeighting::Area), DVec3::ZERO);
        assert_eq!(g.vertex_normal(vertex, NormalWeighting::Angle), DVec3::ZERO);
        // The mean adds the face normal as OpenMesh does.
        assert_eq!(g.vertex_normal(vertex, NormalWeighting::Mean), DVec3::Z);
    }
}

#[test]
fn degenerate_triangles_inside_a_mesh() {
    // A flat grid with two kinds of degenerate triangles: vertex (2,2) moved onto (3,3)
    // (the two triangles of cell (2,2) get coincident vertices), and vertex (3,1) moved
    // 1e-14 past the diagonal of cell (2,1) (triangle (2,1),(3,1),(3,2) becomes a sliver
    // turned upside down, with a −z normal).
    let mut fx = Fixture::new(primitives::grid(5, 5));
    let id = |i: usize, j: usize| j * 6 + i;
    fx.positions[id(2, 2)] = fx.positions[id(3, 3)];
    fx.positions[id(3, 1)] = DVec3::new(2.5, 1.5 + 1e-14, 0.0);
    let g = fx.geometry();
    assert_all_finite(&g);
    let degenerate: Vec<FaceId> = fx
        .mesh
        .faces()
        .filter(|&x| g.is_degenerate_face(x))
        .collect();
    // Cell (i, j) holds faces 2(5j + i) and 2(5j + i) + 1.
    assert_eq!(degenerate, [f(14), f(24), f(25)]);
    assert_eq!(g.face_normal(f(14)), -DVec3::Z);
    assert_eq!(g.face_normal(f(24)), DVec3::ZERO);
    let area = g.surface_area();
    let bary: f64 = g
        .vertex_areas(VertexAreaKind::Barycentric)
        .unwrap()
        .as_slice()
        .iter()
        .sum();
    assert_rel(bary, area, 1e-14);
    // Mixed areas leave out the degenerate triangles only (areas at most ½·1e-12·ℓ²).
    let mixed: f64 = g
        .vertex_areas(VertexAreaKind::MixedVoronoi)
        .unwrap()
        .as_slice()
        .iter()
        .sum();
    let degenerate_area: f64 = fx
        .mesh
        .faces()
        .filter(|&x| g.is_degenerate_face(x))
        .map(|x| g.face_area(x))
        .sum();
    assert_near(mixed, area - degenerate_area, 1e-13);
    // The flat grid keeps +z normals wherever they are defined.
    for vertex in fx.mesh.vertices() {
        for w in WEIGHTINGS {
            let n = g.vertex_normal(vertex, w);
            assert!(
                n == DVec3::ZERO || (n - DVec3::Z).length() < 1e-12,
                "{w:?} {n}"
            );
        }
    }
}

#[test]
fn isolated_vertices_and_empty_meshes() {
    let fx = Fixture::from_faces(
        vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(5.0, -3.0, 2.0)],
        &[[0u32, 1, 2]],
    );
    let g = fx.geometry();
    assert_all_finite(&g);
    for w in WEIGHTINGS {
        assert_eq!(g.vertex_normal(v(3), w), DVec3::ZERO);
    }
    for kind in AREA_KINDS {
        assert_eq!(g.vertex_area(v(3), kind), 0.0);
    }
    assert_eq!(
        g.bounding_box(),
        Some((DVec3::new(0.0, -3.0, 0.0), DVec3::new(5.0, 1.0, 2.0)))
    );

    // A closed mesh with an isolated vertex is still closed.
    let mut tet = primitives::tetrahedron();
    tet.positions.push(DVec3::splat(100.0));
    let faces: Vec<&[u32]> = tet.faces.iter().collect();
    let fx = Fixture::from_faces(tet.positions, &faces);
    assert_near(
        fx.geometry().volume().unwrap(),
        8.0 / (9.0 * 3f64.sqrt()),
        1e-13,
    );

    let empty = Fixture::from_faces(Vec::new(), &[] as &[[u32; 3]]);
    let g = empty.geometry();
    assert_eq!(g.bounding_box(), None);
    assert_eq!(g.mean_edge_length(), None);
    assert_eq!(g.surface_area(), 0.0);
    assert_eq!(g.volume(), Ok(0.0));
    assert_eq!(g.surface_centroid(), None);
    assert!(g.face_normals().is_empty());
    assert!(
        g.vertex_areas(VertexAreaKind::MixedVoronoi)
            .unwrap()
            .is_empty()
    );
}

#[test]
fn extreme_scales_keep_scale_invariant_results() {
    let base = Fixture::new(primitives::tetrahedron());
    let reference = base.geometry();
    for s in [1e-200, 1e-100, 1e-30, 1e30, 1e100, 1e200, 1e300] {
        let fx = base.mapped(|p| p * s);
        let g = fx.geometry();
        for face in fx.mesh.faces() {
            assert_vec_near(g.face_normal(face), reference.face_normal(face), 1e-15);
            assert!(!g.is_degenerate_face(face));
        }
        for h in fx.mesh.halfedges() {
            assert_near(g.corner_angle(h), FRAC_PI_3, 1e-15);
            assert_near(g.opposite_cotangent(h), 1.0 / 3f64.sqrt(), 1e-15);
        }
        for vertex in fx.mesh.vertices() {
            for w in WEIGHTINGS {
                assert_vec_near(
                    g.vertex_normal(vertex, w),
                    base.positions[vertex.index()],
                    1e-15,
                );
            }
        }
        assert_rel(
            g.edge_length(EdgeId::new(0)),
            (8.0f64 / 3.0).sqrt() * s,
            1e-15,
        );
        // Areas and volumes are finite exactly when representable.
        let area = 8.0 / 3f64.sqrt() * s * s;
        if area.is_finite() && area > 1e-290 {
            assert_rel(g.surface_area(), area, 1e-14);
        } else if area.is_infinite() {
            assert_eq!(g.surface_area(), f64::INFINITY);
        }
        let volume = 8.0 / (9.0 * 3f64.sqrt()) * s * s * s;
        if volume.is_finite() && volume > 1e-290 {
            assert_rel(g.volume().unwrap(), volume, 1e-14);
        }
    }
}

#[test]
fn near_overflow_coordinates() {
    // Differences of these positions overflow; the normal is still +z.
    let fx = Fixture::from_faces(
        vec![
            DVec3::new(-1e308, -1e308, 0.0),
            DVec3::new(1e308, -1e308, 0.0),
            DVec3::new(0.0, 1e308, 0.0),
        ],
        &[[0u32, 1, 2]],
    );
    let g = fx.geometry();
    assert_eq!(g.face_normal(f(0)), DVec3::Z);
    for w in WEIGHTINGS {
        assert_eq!(g.vertex_normal(v(0), w), DVec3::Z);
    }
    for h in fx
        .mesh
        .halfedges()
        .filter(|&h| !fx.mesh.is_boundary_halfedge(h))
    {
        assert!(g.opposite_cotangent(h).is_finite());
        assert!(g.corner_angle(h) > 0.0 && g.corner_angle(h) < PI);
    }
    assert!(!g.is_degenerate_face(f(0)));
    // The area, 4e616, is not representable.
    assert_eq!(g.face_area(f(0)), f64::INFINITY);
    assert!(g.surface_centroid().unwrap().is_finite());
}

// ---------------------------------------------------------------------------------------
// Rigid motions and scaling

fn rotation() -> impl Strategy<Value = DQuat> {
    proptest::array::uniform4(-1.0f64..1.0)
        .prop_filter("a usable quaternion", |q| {
            q.iter().map(|x| x * x).sum::<f64>() > 0.01
        })
        .prop_map(|q| DQuat::from_xyzw(q[0], q[1], q[2], q[3]).normalize())
}

fn fixture(which: usize) -> Fixture {
    Fixture::new(match which {
        0 => primitives::icosphere(2),
        1 => primitives::torus(1.5, 0.5, 12, 8),
        2 => primitives::cube(),
        _ => primitives::cube_quads(),
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn rigid_motions_preserve_measures(
        q in rotation(),
        t in proptest::array::uniform3(-10.0f64..10.0),
        which in 0..4usize,
    ) {
        let fx = fixture(which);
        let t = DVec3::from_array(t);
        let moved = fx.mapped(|p| q * p + t);
        let (a, b) = (fx.geometry(), moved.geometry());
        let rel = |x: f64, y: f64| (x - y).abs() <= 1e-12 * x.abs().max(y.abs());

        prop_assert!(rel(a.surface_area(), b.surface_area()));
        prop_assert!(rel(a.volume().unwrap(), b.volume().unwrap()));
        prop_assert!(rel(a.mean_edge_length().unwrap(), b.mean_edge_length().unwrap()));
        for face in fx.mesh.faces() {
            prop_assert!(rel(a.face_area(face), b.face_area(face)));
            prop_assert!((q * a.face_normal(face) - b.face_normal(face)).length() < 1e-12);
        }
        for h in fx.mesh.halfedges() {
            prop_assert!((a.corner_angle(h) - b.corner_angle(h)).abs() < 1e-12);
            let (ca, cb) = (a.opposite_cotangent(h), b.opposite_cotangent(h));
            prop_assert!((ca - cb).abs() < 1e-12 * ca.abs().max(1.0));
        }
        for vertex in fx.mesh.vertices() {
            for w in WEIGHTINGS {
                let (na, nb) = (a.vertex_normal(vertex, w), b.vertex_normal(vertex, w));
                prop_assert!((q * na - nb).length() < 1e-12);
            }
            for kind in AREA_KINDS {
                prop_assert!(rel(a.vertex_area(vertex, kind), b.vertex_area(vertex, kind)));
            }
        }
        let (ca, cb) = (a.surface_centroid().unwrap(), b.surface_centroid().unwrap());
        prop_assert!((q * ca + t - cb).length() < 1e-12);
    }

    #[test]
    fn scaling_multiplies_areas_by_s2_and_volume_by_s3(
        s in 1e-3f64..1e3,
        which in 0..4usize,
    ) {
        let fx = fixture(which);
        let scaled = fx.mapped(|p| p * s);
        let (a, b) = (fx.geometry(), scaled.geometry());
        let rel = |x: f64, y: f64| (x - y).abs() <= 1e-12 * x.abs().max(y.abs());

        prop_assert!(rel(a.surface_area() * s * s, b.surface_area()));
        prop_assert!(rel(a.volume().unwrap() * s * s * s, b.volume().unwrap()));
        prop_assert!(rel(a.mean_edge_length().unwrap() * s, b.mean_edge_length().unwrap()));
        for face in fx.mesh.faces() {
            prop_assert!(rel(a.face_area(face) * s * s, b.face_area(face)));
            prop_assert!((a.face_normal(face) - b.face_normal(face)).length() < 1e-12);
        }
        for h in fx.mesh.halfedges() {
            prop_assert!((a.corner_angle(h) - b.corner_angle(h)).abs() < 1e-12);
            let (ca, cb) = (a.opposite_cotangent(h), b.opposite_cotangent(h));
            prop_assert!((ca - cb).abs() < 1e-12 * ca.abs().max(1.0));
        }
        for vertex in fx.mesh.vertices() {
            for kind in AREA_KINDS {
                prop_assert!(rel(a.vertex_area(vertex, kind) * s * s, b.vertex_area(vertex, kind)));
            }
        }
    }
}
