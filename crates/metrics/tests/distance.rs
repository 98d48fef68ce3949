//! Distances to a reference surface: exact point–triangle cases, analytic surfaces, signs,
//! a brute-force cross-check, Hausdorff, volumes, errors and determinism.

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::primitives::{self, Primitive};
use beltrami_halfedge::{DVec3, EdgeId, FaceId, HalfedgeMesh, TopologyError, VertexId};
use beltrami_metrics::MetricsError;
use beltrami_metrics::distance::{
    Feature, HausdorffSampling, SurfaceIndex, TriangleFeature, check_same_topology,
    closest_point_on_triangle, displacement_stats, displacements, distance_stats, hausdorff,
    one_sided_hausdorff, one_sided_hausdorff_from_vertex_distances, signed_distance_stats,
};
use beltrami_metrics::measures::{surface_area, volume};
use beltrami_testkit::SplitMix64;
use proptest::prelude::*;

/// Draws built on testkit's generator (not on the crate under test's own sampling).
trait Draws {
    /// A uniform point of the cube `[-half, half)³`, x then y then z.
    fn point(&mut self, half: f64) -> DVec3;
    /// A uniform unit direction (rejection sampling in the unit ball).
    fn direction(&mut self) -> DVec3;
}

impl Draws for SplitMix64 {
    fn point(&mut self, half: f64) -> DVec3 {
        DVec3::new(
            self.next_range(-half, half),
            self.next_range(-half, half),
            self.next_range(-half, half),
        )
    }
    fn direction(&mut self) -> DVec3 {
        loop {
            let p = self.point(1.0);
            let l = p.length();
            if l > 0.1 && l < 1.0 {
                return p / l;
            }
        }
    }
}

/// The exact distance from `p` to triangle `abc` by a method independent of the crate's:
/// the minimum of the three segment distances and, when the projection onto the plane falls
/// inside (same-side tests), the plane distance.
fn brute_triangle_distance2(p: DVec3, [a, b, c]: [DVec3; 3]) -> f64 {
    fn segment(p: DVec3, a: DVec3, b: DVec3) -> f64 {
        let ab = b - a;
        let l2 = ab.length_squared();
        let t = if l2 > 0.0 {
            ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (p - (a + ab * t)).length_squared()
    }
    let mut best = segment(p, a, b).min(segment(p, b, c)).min(segment(p, c, a));
    let n = (b - a).cross(c - a);
    let longest2 = (b - a)
        .length_squared()
        .max((c - a).length_squared())
        .max((c - b).length_squared());
    if n.length() > 1e-9 * longest2 {
        let q = p - n * ((p - a).dot(n) / n.length_squared());
        let inside = (b - a).cross(q - a).dot(n) >= 0.0
            && (c - b).cross(q - b).dot(n) >= 0.0
            && (a - c).cross(q - c).dot(n) >= 0.0;
        if inside {
            best = best.min((p - q).length_squared());
        }
    }
    best
}

fn build(primitive: &Primitive) -> (HalfedgeMesh, SurfaceIndex) {
    let mesh = primitive.mesh().unwrap();
    let index = SurfaceIndex::new(&mesh, &primitive.positions).unwrap();
    (mesh, index)
}

fn reversed(primitive: &Primitive) -> Primitive {
    let faces: Vec<[u32; 3]> = primitive.faces.iter().map(|f| [f[0], f[2], f[1]]).collect();
    Primitive {
        positions: primitive.positions.clone(),
        faces: beltrami_halfedge::PolygonList::from_triangles(&faces),
    }
}

// ---------------------------------------------------------------------------------------
// The point–triangle distance in all seven Voronoi regions.

#[test]
fn point_triangle_distance_in_each_voronoi_region() {
    let t = [
        DVec3::ZERO,
        DVec3::new(4.0, 0.0, 0.0),
        DVec3::new(0.0, 4.0, 0.0),
    ];
    let cases = [
        // (query, closest point, squared distance, feature)
        (
            DVec3::new(1.0, 1.0, 3.0),
            DVec3::new(1.0, 1.0, 0.0),
            9.0,
            TriangleFeature::Interior,
        ),
        (
            DVec3::new(2.0, -1.0, 1.0),
            DVec3::new(2.0, 0.0, 0.0),
            2.0,
            TriangleFeature::Edge(0),
        ),
        (
            DVec3::new(3.0, 3.0, 0.0),
            DVec3::new(2.0, 2.0, 0.0),
            2.0,
            TriangleFeature::Edge(1),
        ),
        (
            DVec3::new(-2.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            4.0,
            TriangleFeature::Edge(2),
        ),
        (
            DVec3::new(-1.0, -1.0, 2.0),
            t[0],
            6.0,
            TriangleFeature::Vertex(0),
        ),
        (
            DVec3::new(6.0, -1.0, 0.0),
            t[1],
            5.0,
            TriangleFeature::Vertex(1),
        ),
        (
            DVec3::new(-1.0, 6.0, 1.0),
            t[2],
            6.0,
            TriangleFeature::Vertex(2),
        ),
    ];
    for (p, q, d2, feature) in cases {
        let r = closest_point_on_triangle(p, t);
        assert_eq!(r.point, q, "closest point of {p}");
        assert_eq!(r.distance_squared, d2, "distance of {p}");
        assert_eq!(r.feature, feature, "feature of {p}");
    }
}

#[test]
fn point_triangle_distance_in_the_corner_wedges_of_an_obtuse_triangle() {
    // Obtuse at corner 0: the wedge behind it (Eberly's region 4) reaches edge interiors.
    let t = [
        DVec3::ZERO,
        DVec3::new(4.0, 0.0, 0.0),
        DVec3::new(-2.0, 2.0, 0.0),
    ];
    let r = closest_point_on_triangle(DVec3::new(0.5, -1.0, 0.0), t);
    assert_eq!(
        (r.point, r.distance_squared),
        (DVec3::new(0.5, 0.0, 0.0), 1.0)
    );
    assert_eq!(r.feature, TriangleFeature::Edge(0));
    // Behind corner 0 on the other side: edge 2 (from (-2, 2) to the origin), whose outward
    // normal in the plane is (-1, -1)/√2.
    let p = DVec3::new(-1.0, 1.0, 0.0) + DVec3::new(-1.0, -1.0, 0.0);
    let r = closest_point_on_triangle(p, t);
    assert!((r.point - DVec3::new(-1.0, 1.0, 0.0)).length() < 1e-15);
    assert!((r.distance_squared - 2.0).abs() < 1e-14);
    assert_eq!(r.feature, TriangleFeature::Edge(2));
    // Beyond corner 1 and corner 2, the nearest corner.
    let r = closest_point_on_triangle(DVec3::new(5.0, -1.0, 2.0), t);
    assert_eq!((r.point, r.feature), (t[1], TriangleFeature::Vertex(1)));
    let r = closest_point_on_triangle(DVec3::new(-3.0, 4.0, 0.0), t);
    assert_eq!((r.point, r.feature), (t[2], TriangleFeature::Vertex(2)));
}

#[test]
fn degenerate_triangles_fall_back_to_their_edges() {
    let p = DVec3::new(1.0, 1.0, 0.0);
    // Collinear corners: the closest point of the segment from (0,0,0) to (3,0,0).
    let line = [
        DVec3::ZERO,
        DVec3::new(3.0, 0.0, 0.0),
        DVec3::new(2.0, 0.0, 0.0),
    ];
    let r = closest_point_on_triangle(p, line);
    assert_eq!(
        (r.point, r.distance_squared),
        (DVec3::new(1.0, 0.0, 0.0), 1.0)
    );
    assert!(matches!(r.feature, TriangleFeature::Edge(_)));
    // All corners coincide: a point.
    let point = [DVec3::new(2.0, 1.0, 0.0); 3];
    let r = closest_point_on_triangle(p, point);
    assert_eq!((r.point, r.distance_squared), (point[0], 1.0));
    assert!(matches!(r.feature, TriangleFeature::Vertex(_)));
    // Two coincident corners.
    let needle = [DVec3::ZERO, DVec3::ZERO, DVec3::new(0.0, 2.0, 0.0)];
    let r = closest_point_on_triangle(p, needle);
    assert_eq!(
        (r.point, r.distance_squared),
        (DVec3::new(0.0, 1.0, 0.0), 1.0)
    );
    // A query on the triangle itself.
    let t = [DVec3::ZERO, DVec3::X, DVec3::Y];
    let on = closest_point_on_triangle(DVec3::new(0.25, 0.25, 0.0), t);
    assert_eq!(on.distance_squared, 0.0);
}

// ---------------------------------------------------------------------------------------
// Analytic surfaces.

#[test]
fn distances_to_a_plane_patch_are_analytic() {
    let grid = primitives::grid(10, 10); // [0, 10]² at z = 0
    let (_, index) = build(&grid);
    let mut rng = SplitMix64::new(7);
    for _ in 0..500 {
        // Above the patch: the distance is |z|.
        let p = DVec3::new(
            rng.next_range(0.0, 10.0),
            rng.next_range(0.0, 10.0),
            rng.next_range(-3.0, 3.0),
        );
        let c = index.closest_point(p).unwrap();
        assert!((c.distance() - p.z.abs()).abs() <= 1e-14, "{p}");
        assert!((c.point - DVec3::new(p.x, p.y, 0.0)).length() <= 1e-14);
        // Off the boundary: the distance to the clamped point of the square.
        let p = DVec3::new(
            rng.next_range(-5.0, 15.0),
            rng.next_range(-5.0, 15.0),
            rng.next_range(-3.0, 3.0),
        );
        let q = DVec3::new(p.x.clamp(0.0, 10.0), p.y.clamp(0.0, 10.0), 0.0);
        let c = index.closest_point(p).unwrap();
        assert!((c.distance() - p.distance(q)).abs() <= 1e-14, "{p}");
    }
    // Exact boundary features.
    let c = index.closest_point(DVec3::new(-3.0, 5.5, 4.0)).unwrap();
    assert_eq!((c.point, c.distance()), (DVec3::new(0.0, 5.5, 0.0), 5.0));
    assert!(matches!(c.feature, Feature::Edge(_)));
    let c = index.closest_point(DVec3::new(13.0, 14.0, 0.0)).unwrap();
    assert_eq!((c.point, c.distance()), (DVec3::new(10.0, 10.0, 0.0), 5.0));
    assert_eq!(c.feature, Feature::Vertex(VertexId::new(120)));
    // Signed: the grid's normals point to +z.
    assert_eq!(
        index.signed_distance(DVec3::new(2.5, 2.5, -0.5)).unwrap(),
        -0.5
    );
    assert_eq!(
        index.signed_distance(DVec3::new(2.5, 2.5, 0.5)).unwrap(),
        0.5
    );
}

/// The largest sag of an inscribed triangle mesh of the unit sphere: `1 − min_f sqrt(1 −
/// ρ_f²)`, with `ρ_f` the circumradius of face `f`. The polyhedron lies between the radii
/// `1 − sag` and 1, so distances to it differ from distances to the sphere by at most `sag`.
fn sphere_sag(sphere: &Primitive) -> f64 {
    let mut sag = 0.0f64;
    for f in sphere.faces.iter() {
        let [a, b, c] = [f[0], f[1], f[2]].map(|v| sphere.positions[v as usize]);
        let (la, lb, lc) = (b.distance(c), c.distance(a), a.distance(b));
        let area = 0.5 * (b - a).cross(c - a).length();
        let rho = la * lb * lc / (4.0 * area);
        sag = sag.max(1.0 - (1.0 - rho * rho).sqrt());
    }
    sag
}

#[test]
fn distances_to_a_sphere_mesh_are_within_the_sag_bound() {
    let sphere = primitives::icosphere(4); // 5120 faces
    let (_, index) = build(&sphere);
    let sag = sphere_sag(&sphere);
    // The sag of an equilateral face of edge ℓ is about ℓ²/6; level 4 has ℓ ≈ 0.076.
    assert!(sag > 5e-4 && sag < 1.2e-3, "sag {sag}");
    let mut rng = SplitMix64::new(11);
    for _ in 0..2000 {
        let r = rng.next_range(0.2, 3.0);
        let p = rng.direction() * r;
        let exact = (r - 1.0).abs();
        let d = index.closest_point(p).unwrap().distance();
        assert!((d - exact).abs() <= sag + 1e-15, "r {r}: {d} vs {exact}");
        // Outside points are farther from the inscribed polyhedron than from the sphere.
        if r > 1.0 {
            assert!(d >= exact - 1e-15);
        }
        let s = index.signed_distance(p).unwrap();
        assert_eq!(s.abs(), d);
        if (r - 1.0).abs() > sag {
            assert_eq!(s > 0.0, r > 1.0, "sign at r = {r}");
        }
    }
}

// ---------------------------------------------------------------------------------------
// Signs.

#[test]
fn signs_flip_when_the_reference_is_reversed() {
    let sphere = primitives::icosphere(3);
    let (_, index) = build(&sphere);
    let (_, flipped) = build(&reversed(&sphere));
    let mut rng = SplitMix64::new(3);
    let points: Vec<DVec3> = (0..1000)
        .map(|_| rng.direction() * rng.next_range(0.5, 1.5))
        .collect();
    let s = index.signed_distances(&points).unwrap();
    let t = flipped.signed_distances(&points).unwrap();
    for ((a, b), p) in s.iter().zip(&t).zip(&points) {
        assert!((a + b).abs() <= 1e-15 * (1.0 + a.abs()), "{p}: {a} vs {b}");
        assert!(a.abs() < 1e-12 || a.signum() == -b.signum());
    }
}

#[test]
fn cube_signs_near_edges_and_vertices() {
    let cube = primitives::cube(); // [0, 1]³, outward normals
    let (_, index) = build(&cube);
    let cases = [
        // Just outside an edge, in the edge's Voronoi region: the closest point is on the edge.
        (DVec3::new(1.01, 1.3, 0.5), 0.01f64.hypot(0.3)),
        // Exactly above the edge's end of one face: (p − q) is orthogonal to the other face's
        // normal, so the normal of the face with the smaller id may not decide.
        (DVec3::new(1.0, 1.3, 0.5), 0.3),
        (DVec3::new(1.3, 1.0, 0.5), 0.3),
        // Just outside a vertex, in its Voronoi region.
        (DVec3::new(1.001, 1.002, 1.003), 14e-6f64.sqrt()),
        (DVec3::new(-0.1, -0.2, -0.3), 0.14f64.sqrt()),
        // Just inside near an edge and a vertex: the nearest side decides.
        (DVec3::new(0.999, 0.998, 0.5), -0.001),
        (DVec3::new(0.999, 0.998, 0.997), -0.001),
        (DVec3::new(0.001, 0.002, 0.003), -0.001),
    ];
    for (p, expected) in cases {
        let s = index.signed_distance(p).unwrap();
        assert!((s - expected).abs() < 1e-12, "{p}: {s} vs {expected}");
    }
    let c = index.closest_point(DVec3::new(1.01, 1.3, 0.5)).unwrap();
    assert!(matches!(c.feature, Feature::Edge(_)));
    let c = index
        .closest_point(DVec3::new(1.001, 1.002, 1.003))
        .unwrap();
    assert_eq!(c.feature, Feature::Vertex(VertexId::new(7)));
}

#[test]
fn pseudo_normals_are_right_where_the_face_normal_rule_fails() {
    // A regular tetrahedron: its edges are sharp (the face normals meet at about 109.5°), so
    // for a point outside an edge, near one face's plane, the other face's normal points
    // away from it.
    let tetrahedron = primitives::tetrahedron();
    let (mesh, index) = build(&tetrahedron);
    let pos = &tetrahedron.positions;
    let normal = |f: FaceId| {
        let [a, b, c] = mesh.triangle_vertices(f).map(|v| pos[v.index()]);
        (b - a).cross(c - a).normalize()
    };
    let mut failures_of_face_rule = 0;
    for e in mesh.edges() {
        let [h, t] = e.halfedges();
        let (f1, f2) = (mesh.face(h).unwrap(), mesh.face(t).unwrap());
        let (n1, n2) = (normal(f1), normal(f2));
        let [u, v] = mesh.edge_vertices(e).map(|v| pos[v.index()]);
        let mid = (u + v) * 0.5;
        // Outside, in the edge's normal cone, close to face 1's normal direction.
        for (along1, along2) in [(1.0, 0.05), (0.05, 1.0), (1.0, 1.0)] {
            let p = mid + (n1 * along1 + n2 * along2) * 1e-3;
            let c = index.closest_point(p).unwrap();
            assert_eq!(c.feature, Feature::Edge(e), "edge {e:?}");
            let s = index.signed_distance(p).unwrap();
            assert!(s > 0.0 && (s - c.distance()).abs() == 0.0);
            let offset = p - c.point;
            if offset.dot(n1) < 0.0 || offset.dot(n2) < 0.0 {
                failures_of_face_rule += 1;
            }
        }
        // The same points are inside the reversed tetrahedron.
        let (_, flipped) = build(&reversed(&tetrahedron));
        let p = mid + (n1 + n2 * 0.05) * 1e-3;
        assert!(flipped.signed_distance(p).unwrap() < 0.0);
    }
    // The face-normal rule (CloudCompare's) gets one of the two faces wrong for the skewed
    // points of every edge.
    assert_eq!(failures_of_face_rule, 2 * 6);
    // At a vertex: outside along the sharp corner's axis, and skewed towards one face.
    let apex = pos[0];
    let p = apex + apex.normalize() * 1e-3;
    let c = index.closest_point(p).unwrap();
    assert_eq!(c.feature, Feature::Vertex(VertexId::new(0)));
    assert!(index.signed_distance(p).unwrap() > 0.0);
    assert!(index.signed_distance(apex * 0.999).unwrap() < 0.0);
}

// ---------------------------------------------------------------------------------------
// The brute-force cross-check.

/// A triangle soup (each triangle its own vertices; some degenerate) in [-1, 1]³.
fn soup(seed: u64, n: usize) -> Primitive {
    let mut rng = SplitMix64::new(seed);
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    for i in 0..n {
        let a = rng.point(1.0);
        let (b, c) = match i % 17 {
            // Exactly collinear and coincident corners now and then.
            5 => (a * 0.5, DVec3::ZERO),
            11 => (a, a),
            _ => (a + rng.point(0.3), a + rng.point(0.3)),
        };
        let base = positions.len() as u32;
        positions.extend([a, b, c]);
        faces.push([base, base + 1, base + 2]);
    }
    Primitive {
        positions,
        faces: beltrami_halfedge::PolygonList::from_triangles(&faces),
    }
}

/// A heightfield over an `n × n` grid with random heights (a connected open surface).
fn bumpy_grid(seed: u64, n: u32) -> Primitive {
    let mut grid = primitives::grid(n, n);
    let mut rng = SplitMix64::new(seed);
    for p in &mut grid.positions {
        *p = DVec3::new(
            p.x / f64::from(n),
            p.y / f64::from(n),
            rng.next_range(-0.2, 0.2),
        );
    }
    grid
}

fn cross_check(primitive: &Primitive, seed: u64, queries: usize) {
    let (_, index) = build(primitive);
    let triangles: Vec<[DVec3; 3]> = primitive
        .faces
        .iter()
        .map(|f| [f[0], f[1], f[2]].map(|v| primitive.positions[v as usize]))
        .collect();
    let mut rng = SplitMix64::new(seed);
    let points: Vec<DVec3> = (0..queries).map(|_| rng.point(1.5)).collect();
    let batch = index.closest_points(&points).unwrap();
    for (p, c) in points.iter().zip(&batch) {
        let brute = triangles
            .iter()
            .map(|&t| brute_triangle_distance2(*p, t))
            .fold(f64::INFINITY, f64::min)
            .sqrt();
        let d = c.distance();
        assert!(
            (d - brute).abs() <= 1e-12 * brute.max(1.0),
            "{p}: {d} vs {brute}"
        );
        // The reported point is on the reported face, at the reported distance.
        let own = brute_triangle_distance2(*p, triangles[c.face.index()]).sqrt();
        assert!((own - d).abs() <= 1e-12 * d.max(1.0));
        assert!((p.distance(c.point) - d).abs() <= 1e-12 * d.max(1.0));
        // A single query gives the same answer as the batch.
        let single = index.closest_point(*p).unwrap();
        assert_eq!(single.distance_squared, c.distance_squared);
        assert_eq!(single.face, c.face);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn bvh_matches_brute_force_on_triangle_soups(seed in any::<u64>(), n in 1usize..400) {
        cross_check(&soup(seed, n), seed ^ 0xABCD, 300);
    }

    #[test]
    fn bvh_matches_brute_force_on_heightfields(seed in any::<u64>(), n in 1u32..24) {
        cross_check(&bumpy_grid(seed, n), seed ^ 0x1234, 300);
    }
}

#[test]
fn a_reference_split_into_parallel_build_tasks_matches_brute_force() {
    // 81 920 triangles: the hierarchy's top is split into several subtrees built in
    // parallel; the answers must not depend on that, nor on the thread count.
    let sphere = primitives::icosphere(6);
    let (_, index) = build(&sphere);
    let triangles: Vec<[DVec3; 3]> = sphere
        .faces
        .iter()
        .map(|f| [f[0], f[1], f[2]].map(|v| sphere.positions[v as usize]))
        .collect();
    let mut rng = SplitMix64::new(77);
    // Near the surface (the case of a noisy scan) and anywhere in a box around it.
    let points: Vec<DVec3> = (0..400)
        .map(|i| {
            if i % 2 == 0 {
                rng.point(1.0).normalize_or(DVec3::X) * rng.next_range(0.98, 1.02)
            } else {
                rng.point(1.5)
            }
        })
        .collect();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| index.closest_points(&points).unwrap())
    };
    let batch = run(1);
    assert_eq!(batch, run(2));
    for (p, c) in points.iter().zip(&batch) {
        let brute = triangles
            .iter()
            .map(|&t| brute_triangle_distance2(*p, t))
            .fold(f64::INFINITY, f64::min)
            .sqrt();
        assert!(
            (c.distance() - brute).abs() <= 1e-12 * brute.max(1.0),
            "{p}: {} vs {brute}",
            c.distance()
        );
    }
}

#[test]
fn batch_results_do_not_depend_on_the_thread_count() {
    let sphere = primitives::icosphere(4);
    let (_, index) = build(&sphere);
    let mut rng = SplitMix64::new(5);
    let points: Vec<DVec3> = (0..20_000).map(|_| rng.point(1.3)).collect();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            (
                index.closest_points(&points).unwrap(),
                index.signed_distances(&points).unwrap(),
            )
        })
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert_eq!(one, run(3));
}

// ---------------------------------------------------------------------------------------
// Statistics.

#[test]
fn distance_statistics_of_a_scaled_sphere() {
    let sphere = primitives::icosphere(3);
    let (mesh, index) = build(&sphere);
    // Scaling by 1.1 puts every vertex 0.1 outside its own reference vertex, which is the
    // closest point of the (convex, inscribed) reference.
    let scaled: Vec<DVec3> = sphere.positions.iter().map(|p| *p * 1.1).collect();
    let stats = distance_stats(&mesh, &scaled, &index).unwrap();
    assert_eq!(stats.count, sphere.positions.len());
    for value in [stats.rms, stats.mean, stats.max, stats.area_weighted_rms] {
        assert!((value - 0.1).abs() < 1e-14, "{stats:?}");
    }
    let signed = signed_distance_stats(&mesh, &scaled, &index).unwrap();
    assert!((signed.mean - 0.1).abs() < 1e-14 && signed.min > 0.0 && signed.std_dev < 1e-14);
}

#[test]
fn area_weighted_rms_weighs_vertices_by_their_area() {
    // A 2 × 1 strip: vertex areas are 1/6 or 1/3 (corners touched by one or two triangles).
    let grid = primitives::grid(2, 1);
    let (mesh, index) = build(&grid);
    // Lift only vertex 1 (the middle of the bottom row, in three triangles: area 1/2).
    let mut lifted = grid.positions.clone();
    lifted[1].z = 0.6;
    let stats = distance_stats(&mesh, &lifted, &index).unwrap();
    let n = grid.positions.len() as f64; // 6 vertices
    assert!((stats.rms - (0.36 / n).sqrt()).abs() < 1e-15);
    assert!((stats.mean - 0.6 / n).abs() < 1e-15);
    assert_eq!(stats.max, 0.6);
    // Σ A_i = 2 (the lifted mesh's area is larger: use the measured mesh's areas).
    let geometry = beltrami_halfedge::geometry::Geometry::new(&mesh, &lifted).unwrap();
    let areas = geometry
        .vertex_areas(beltrami_halfedge::geometry::VertexAreaKind::Barycentric)
        .unwrap();
    let total: f64 = areas.as_slice().iter().sum();
    let expected = (areas.as_slice()[1] * 0.36 / total).sqrt();
    assert!((stats.area_weighted_rms - expected).abs() < 1e-15);
}

#[test]
fn displacement_needs_the_same_topology() {
    let sphere = primitives::icosphere(2);
    let mesh = sphere.mesh().unwrap();
    let moved: Vec<DVec3> = sphere
        .positions
        .iter()
        .map(|p| *p + DVec3::new(0.3, 0.4, 0.0))
        .collect();
    let d = displacements(&mesh, &moved, &mesh, &sphere.positions).unwrap();
    assert!(d.iter().all(|&x| (x - 0.5).abs() < 1e-15));
    let stats = displacement_stats(&mesh, &moved, &mesh, &sphere.positions).unwrap();
    assert!((stats.rms - 0.5).abs() < 1e-15 && (stats.area_weighted_rms - 0.5).abs() < 1e-15);

    let other = primitives::icosphere(1);
    let err = displacements(
        &other.mesh().unwrap(),
        &other.positions,
        &mesh,
        &sphere.positions,
    )
    .unwrap_err();
    assert_eq!(
        err,
        MetricsError::TopologyMismatch {
            detail: "42 vertices vs 162".into()
        }
    );
    let swapped = HalfedgeMesh::from_polygons(3, [[0u32, 2, 1]]).unwrap();
    let triangle = HalfedgeMesh::from_polygons(3, [[0u32, 1, 2]]).unwrap();
    let err = check_same_topology(&triangle, &swapped).unwrap_err();
    assert_eq!(
        err.to_string(),
        "the meshes do not share their topology: face 0 is [0, 1, 2] vs [0, 2, 1]"
    );
}

// ---------------------------------------------------------------------------------------
// Hausdorff.

#[test]
fn hausdorff_is_symmetric_where_one_sided_distances_are_not() {
    // The unit square, lifted by 0.5, against the square [0, 2]² at z = 0.
    let mut small = primitives::grid(1, 1);
    for p in &mut small.positions {
        p.z = 0.5;
    }
    let large = primitives::grid(2, 2);
    let (_, a) = build(&small);
    let (_, b) = build(&large);
    let h = hausdorff(&a, &b, HausdorffSampling::Vertices).unwrap();
    assert_eq!(h.forward, 0.5);
    assert_eq!(h.backward, 2.25f64.sqrt()); // (2, 2, 0) to (1, 1, 0.5)
    assert_eq!(h.symmetric, 1.5);
    let swapped = hausdorff(&b, &a, HausdorffSampling::Vertices).unwrap();
    assert_eq!((swapped.forward, swapped.backward), (h.backward, h.forward));
    // Surface samples cannot exceed the true one-sided values (up to the rounding of the
    // sample positions), which here are attained at vertices.
    let sampled = hausdorff(
        &a,
        &b,
        HausdorffSampling::VerticesAndSurface {
            samples: 5000,
            seed: 9,
        },
    )
    .unwrap();
    assert!((sampled.forward - h.forward).abs() < 1e-15);
    assert!((sampled.backward - h.backward).abs() < 1e-15);
}

#[test]
fn known_vertex_distances_give_the_one_sided_hausdorff_distance() {
    // A bumpy open grid with an isolated vertex far off the surface, against a sphere.
    let mut grid = bumpy_grid(4, 6);
    grid.positions.push(DVec3::new(0.0, 0.0, 50.0));
    let sphere = primitives::icosphere(2);
    let (_, from) = build(&grid);
    let (_, to) = build(&sphere);
    let signed = to.signed_distances(&grid.positions).unwrap();
    let unsigned = to.distances(&grid.positions).unwrap();
    for sampling in [
        HausdorffSampling::Vertices,
        HausdorffSampling::VerticesAndSurface {
            samples: 500,
            seed: 3,
        },
    ] {
        let want = one_sided_hausdorff(&from, &to, sampling).unwrap();
        for known in [&signed, &unsigned] {
            let got = one_sided_hausdorff_from_vertex_distances(&from, known, &to, sampling);
            assert_eq!(got.unwrap().to_bits(), want.to_bits(), "{sampling:?}");
        }
    }
    // The isolated vertex is skipped: it is 49 away from the sphere.
    assert!(one_sided_hausdorff(&from, &to, HausdorffSampling::Vertices).unwrap() < 2.0);
    assert_eq!(
        one_sided_hausdorff_from_vertex_distances(
            &from,
            &signed[1..],
            &to,
            HausdorffSampling::Vertices
        )
        .unwrap_err(),
        MetricsError::FieldLength {
            what: "vertex distances",
            got: signed.len() - 1,
            expected: signed.len(),
        }
    );
}

#[test]
fn surface_samples_catch_what_vertices_miss() {
    // One big triangle against a reference with a vertex-free bump: a tent whose apex lies
    // over the middle of the big triangle's face.
    let flat = Primitive {
        positions: vec![
            DVec3::ZERO,
            DVec3::new(4.0, 0.0, 0.0),
            DVec3::new(0.0, 4.0, 0.0),
        ],
        faces: beltrami_halfedge::PolygonList::from_triangles(&[[0, 1, 2]]),
    };
    let mut tent = flat.clone();
    tent.positions.push(DVec3::new(1.0, 1.0, 1.0));
    tent.faces = beltrami_halfedge::PolygonList::from_triangles(&[[0, 1, 3], [1, 2, 3], [2, 0, 3]]);
    let (_, a) = build(&flat);
    let (_, b) = build(&tent);
    let by_vertices = hausdorff(&a, &b, HausdorffSampling::Vertices).unwrap();
    assert_eq!(by_vertices.forward, 0.0); // the flat corners are the tent's corners
    let sampled = hausdorff(
        &a,
        &b,
        HausdorffSampling::VerticesAndSurface {
            samples: 20_000,
            seed: 1,
        },
    )
    .unwrap();
    assert!(sampled.forward > 0.5, "{sampled:?}");
    assert_eq!(sampled.backward, by_vertices.backward); // the apex, 1 above the flat face
    assert_eq!(sampled.backward, 1.0);
}

#[test]
fn surface_sampling_is_reproducible_and_on_the_surface() {
    let sphere = primitives::icosphere(2);
    let (_, index) = build(&sphere);
    let s = index.sample_surface(1000, 42);
    assert_eq!(s.len(), 1000);
    assert_eq!(s, index.sample_surface(1000, 42));
    assert_ne!(s, index.sample_surface(1000, 43));
    let d = index.distances(&s).unwrap();
    assert!(d.iter().all(|&x| x < 1e-15));
    // Area-uniform: the mean of z over the sphere's surface is 0, of z² is 1/3.
    let mean_z2 = index
        .sample_surface(100_000, 1)
        .iter()
        .map(|p| p.z * p.z)
        .sum::<f64>()
        / 1e5;
    assert!((mean_z2 - 1.0 / 3.0).abs() < 0.01, "{mean_z2}");
}

// ---------------------------------------------------------------------------------------
// Volume and area.

#[test]
fn volume_and_area_of_a_cube_and_icospheres() {
    let cube = primitives::cube();
    let mesh = cube.mesh().unwrap();
    assert!((volume(&Geometry::new(&mesh, &cube.positions).unwrap()).unwrap() - 1.0).abs() < 1e-15);
    assert!(
        (surface_area(&Geometry::new(&mesh, &cube.positions).unwrap()).unwrap() - 6.0).abs()
            < 1e-15
    );
    // A cube far from the origin and scaled: 8 mm³.
    let far: Vec<DVec3> = cube
        .positions
        .iter()
        .map(|p| *p * 2.0 + DVec3::splat(1e4))
        .collect();
    assert!((volume(&Geometry::new(&mesh, &far).unwrap()).unwrap() - 8.0).abs() < 1e-9);

    // An inscribed polyhedron of the unit sphere contains the ball of its smallest face
    // distance, so 4π/3 (1 − sag)³ < V < 4π/3, and the same for the area with the square.
    let ball = 4.0 / 3.0 * std::f64::consts::PI;
    for level in [1, 3, 5] {
        let sphere = primitives::icosphere(level);
        let mesh = sphere.mesh().unwrap();
        let sag = sphere_sag(&sphere);
        let v = volume(&Geometry::new(&mesh, &sphere.positions).unwrap()).unwrap();
        assert!(
            v < ball && v > ball * (1.0 - sag).powi(3),
            "level {level}: {v}"
        );
        let a = surface_area(&Geometry::new(&mesh, &sphere.positions).unwrap()).unwrap();
        assert!(
            a < 3.0 * ball && a > 3.0 * ball * (1.0 - sag).powi(2),
            "level {level}: {a}"
        );
    }
    // The level-6 values quoted in the project's research notes (six decimals).
    let sphere = primitives::icosphere(6);
    let mesh = sphere.mesh().unwrap();
    assert!(
        (volume(&Geometry::new(&mesh, &sphere.positions).unwrap()).unwrap() - 4.188224).abs()
            < 5e-7
    );
    assert!(
        (surface_area(&Geometry::new(&mesh, &sphere.positions).unwrap()).unwrap() - 12.565431)
            .abs()
            < 5e-7
    );
}

#[test]
fn volume_of_an_open_mesh_is_an_error() {
    let grid = primitives::grid(2, 2);
    let err = volume(&Geometry::new(&grid.mesh().unwrap(), &grid.positions).unwrap()).unwrap_err();
    assert_eq!(
        err,
        MetricsError::Topology(TopologyError::NotClosed { boundary_loops: 1 })
    );
    let empty = HalfedgeMesh::from_polygons(0, &[] as &[[u32; 3]]).unwrap();
    assert_eq!(
        volume(&Geometry::new(&empty, &[]).unwrap()).unwrap_err(),
        MetricsError::Empty { what: "mesh" }
    );
}

// ---------------------------------------------------------------------------------------
// Errors.

#[test]
fn bad_input_is_rejected_with_a_typed_error() {
    let empty = HalfedgeMesh::from_polygons(0, &[] as &[[u32; 3]]).unwrap();
    assert_eq!(
        SurfaceIndex::new(&empty, &[]).unwrap_err(),
        MetricsError::Empty {
            what: "reference mesh"
        }
    );
    let mut cube = primitives::cube();
    let mesh = cube.mesh().unwrap();
    cube.positions[3].y = f64::NAN;
    assert_eq!(
        SurfaceIndex::new(&mesh, &cube.positions).unwrap_err(),
        MetricsError::NonFinite {
            what: "surface vertex",
            index: 3
        }
    );
    assert!(matches!(
        SurfaceIndex::new(&mesh, &cube.positions[..4]).unwrap_err(),
        MetricsError::Topology(TopologyError::PositionCount {
            positions: 4,
            vertices: 8
        })
    ));
    let quads = primitives::cube_quads();
    assert!(matches!(
        SurfaceIndex::new(&quads.mesh().unwrap(), &quads.positions).unwrap_err(),
        MetricsError::Topology(TopologyError::NotTriangle { face: 0, len: 4 })
    ));

    let (mesh, index) = build(&primitives::cube());
    assert_eq!(
        index
            .closest_point(DVec3::new(0.0, f64::INFINITY, 0.0))
            .unwrap_err(),
        MetricsError::NonFinite {
            what: "query point",
            index: 0
        }
    );
    let points = [DVec3::ZERO, DVec3::ONE, DVec3::new(f64::NAN, 0.0, 0.0)];
    assert_eq!(
        index.distances(&points).unwrap_err(),
        MetricsError::NonFinite {
            what: "query point",
            index: 2
        }
    );
    assert_eq!(
        index.closest_point(DVec3::splat(1e70)).unwrap_err(),
        MetricsError::CoordinateTooLarge {
            what: "query point",
            index: 0,
            value: 1e70,
            limit: 1e60
        }
    );
    let no_vertices = HalfedgeMesh::from_polygons(0, &[] as &[[u32; 3]]).unwrap();
    assert_eq!(
        distance_stats(&no_vertices, &[], &index).unwrap_err(),
        MetricsError::Empty { what: "mesh" }
    );
    assert!(matches!(
        distance_stats(&mesh, &[DVec3::ZERO], &index).unwrap_err(),
        MetricsError::Topology(TopologyError::PositionCount { .. })
    ));
    let _ = EdgeId::new(0);
}

#[test]
fn far_away_and_huge_but_finite_inputs_stay_finite() {
    // Coordinates up to the documented limit give finite distances, never NaN.
    let big = 1e59;
    let mesh = HalfedgeMesh::from_polygons(3, [[0u32, 1, 2]]).unwrap();
    let positions = [
        DVec3::splat(-big),
        DVec3::new(big, -big, 0.0),
        DVec3::new(0.0, big, big),
    ];
    let index = SurfaceIndex::new(&mesh, &positions).unwrap();
    for p in [
        DVec3::ZERO,
        DVec3::splat(big),
        DVec3::splat(-big),
        DVec3::new(big, 0.0, -big),
    ] {
        let c = index.closest_point(p).unwrap();
        assert!(
            c.distance_squared.is_finite() && c.point.is_finite(),
            "{p}: {c:?}"
        );
    }
    // A millimetre-scale patch a kilometre from the origin keeps its digits.
    let grid = primitives::grid(4, 4);
    let offset = DVec3::new(1e6, -2e6, 3e6);
    let far: Vec<DVec3> = grid.positions.iter().map(|p| *p * 1e-3 + offset).collect();
    let index = SurfaceIndex::new(&grid.mesh().unwrap(), &far).unwrap();
    let d = index
        .signed_distance(offset + DVec3::new(2e-3, 2e-3, 1e-6))
        .unwrap();
    assert!((d - 1e-6).abs() < 1e-9, "{d}");
}
