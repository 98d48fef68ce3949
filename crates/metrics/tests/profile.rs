//! Cross-section profiles: cube and grid cuts worked out by hand, cuts exactly through
//! vertex layers, the icosphere's equator against the polygonal bound, orientation, and
//! the deviation between offset profiles.

use std::collections::HashSet;
use std::f64::consts::{PI, TAU};

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::primitives::{self, Primitive};
use beltrami_halfedge::{DVec3, HalfedgeMesh, TopologyError};
use beltrami_metrics::MetricsError;
use beltrami_metrics::profile::{
    Plane, PointSource, Polyline, ProfilePoint, cross_section, profile_deviation, profile_length,
};

fn build(p: &Primitive) -> HalfedgeMesh {
    let mesh = p.mesh().expect("primitive builds");
    mesh.check_integrity().expect("valid mesh");
    mesh
}

fn section(mesh: &HalfedgeMesh, positions: &[DVec3], point: DVec3, normal: DVec3) -> Vec<Polyline> {
    let plane = Plane::new(point, normal).expect("valid plane");
    cross_section(&Geometry::new(mesh, positions).expect("positions"), &plane).expect("triangles")
}

/// Twice the signed area of a polygon's projection on the xy-plane (shoelace formula):
/// positive when it runs counter-clockwise seen from +z.
fn shoelace_xy(line: &Polyline) -> f64 {
    let p: Vec<DVec3> = line.positions().collect();
    (0..p.len())
        .map(|i| {
            let (a, b) = (p[i], p[(i + 1) % p.len()]);
            a.x * b.y - b.x * a.y
        })
        .sum()
}

/// Every point lies on the element it records: a vertex point is that vertex exactly, an
/// edge point lies strictly inside its edge, on the plane.
fn check_sources(mesh: &HalfedgeMesh, positions: &[DVec3], plane: &Plane, lines: &[Polyline]) {
    for line in lines {
        for p in &line.points {
            match p.source {
                PointSource::Vertex(v) => {
                    assert_eq!(p.position, positions[v.index()]);
                    assert_eq!(plane.signed_distance(p.position), 0.0);
                }
                PointSource::Edge(e) => {
                    let [a, b] = mesh.edge_vertices(e).map(|v| positions[v.index()]);
                    let (da, db) = (plane.signed_distance(a), plane.signed_distance(b));
                    assert!(da * db < 0.0, "an edge point's edge ends on both sides");
                    let t = (p.position - a).dot(b - a) / (b - a).length_squared();
                    assert!(t > 0.0 && t < 1.0);
                    assert!((a + t * (b - a) - p.position).length() < 1e-14);
                    assert!(plane.signed_distance(p.position).abs() < 1e-14);
                }
            }
        }
        // No point repeats within a polyline (these cuts do not touch themselves).
        let sources: HashSet<_> = line.points.iter().map(|p| p.source).collect();
        assert_eq!(sources.len(), line.points.len(), "no duplicated point");
    }
}

#[test]
fn unit_cube_at_half_height_is_one_square() {
    // z = 0.5 cuts the four vertical edges (at the square's corners) and one diagonal on
    // each side (at the midpoints of its sides): eight points, perimeter 4.
    let cube = primitives::cube();
    let mesh = build(&cube);
    let plane = Plane::new(DVec3::new(0.0, 0.0, 0.5), DVec3::Z).expect("valid");
    let lines = section(&mesh, &cube.positions, plane.point(), plane.normal());
    assert_eq!(lines.len(), 1);
    let square = &lines[0];
    assert!(square.closed);
    assert_eq!(square.points.len(), 8);
    assert!(square.positions().all(|p| p.z == 0.5));
    assert!((square.length() - 4.0).abs() < 1e-15);
    // Outward normals, plane normal +z: counter-clockwise seen from above, area 1.
    assert!((shoelace_xy(square) - 2.0).abs() < 1e-15);
    check_sources(&mesh, &cube.positions, &plane, &lines);
    let corners: Vec<DVec3> = square
        .positions()
        .filter(|p| p.x.fract() == 0.0 && p.y.fract() == 0.0)
        .collect();
    assert_eq!(corners.len(), 4);
}

#[test]
fn cube_cut_through_its_top_vertex_layer() {
    // z = 1: the four top vertices lie on the plane (positive side), all others below.
    // Every cut edge ends at a top vertex, so the loop is the top square through the four
    // vertices, each once.
    let cube = primitives::cube();
    let mesh = build(&cube);
    let plane = Plane::new(DVec3::new(0.0, 0.0, 1.0), DVec3::Z).expect("valid");
    let lines = section(&mesh, &cube.positions, plane.point(), plane.normal());
    assert_eq!(lines.len(), 1);
    let top = &lines[0];
    assert!(top.closed);
    assert_eq!(top.points.len(), 4);
    assert!(
        top.points
            .iter()
            .all(|p| matches!(p.source, PointSource::Vertex(v) if v.raw() >= 4))
    );
    assert_eq!(top.length(), 4.0);
    assert_eq!(shoelace_xy(top), 2.0);
    check_sources(&mesh, &cube.positions, &plane, &lines);

    // z = 0 with normal +z: no vertex is strictly below, so the section is empty (the
    // documented side rule). With normal −z the bottom square appears, clockwise seen from
    // +z (counter-clockwise about −z).
    assert!(section(&mesh, &cube.positions, DVec3::ZERO, DVec3::Z).is_empty());
    let bottom = section(&mesh, &cube.positions, DVec3::ZERO, -DVec3::Z);
    assert_eq!(bottom.len(), 1);
    assert_eq!(bottom[0].points.len(), 4);
    assert!(bottom[0].positions().all(|p| p.z == 0.0));
    assert_eq!(shoelace_xy(&bottom[0]), -2.0);
}

/// The grid `nx × ny` stood up in the xz-plane: vertex (i, j) at (i, 0, j).
fn standing_grid(nx: u32, ny: u32) -> (HalfedgeMesh, Vec<DVec3>) {
    let grid = primitives::grid(nx, ny);
    let mesh = build(&grid);
    let positions = grid
        .positions
        .iter()
        .map(|p| DVec3::new(p.x, 0.0, p.y))
        .collect();
    (mesh, positions)
}

#[test]
fn grid_cut_through_a_vertex_row_has_no_duplicates() {
    let (nx, ny) = (4, 3);
    let (mesh, positions) = standing_grid(nx, ny);
    // z = 1: the row j = 1 lies on the plane; rows above are positive, row 0 negative. The
    // horizontal and diagonal edges from row 0 end at row-1 vertices: one open chain of the
    // five row-1 vertices, from one side of the grid to the other.
    for (z, normal) in [
        (1.0, DVec3::Z),
        (2.0, DVec3::Z),
        (0.0, -DVec3::Z),
        (3.0, DVec3::Z),
    ] {
        let plane = Plane::new(DVec3::new(0.0, 0.0, z), normal).expect("valid");
        let lines = section(&mesh, &positions, plane.point(), plane.normal());
        assert_eq!(lines.len(), 1, "z = {z}");
        let chain = &lines[0];
        assert!(!chain.closed);
        assert_eq!(chain.points.len(), nx as usize + 1, "z = {z}");
        assert!(
            chain
                .points
                .iter()
                .all(|p| matches!(p.source, PointSource::Vertex(_)))
        );
        assert_eq!(chain.length(), f64::from(nx));
        // In order along x (one way or the other), each vertex of the row once.
        let xs: Vec<f64> = chain.positions().map(|p| p.x).collect();
        let ascending: Vec<f64> = (0..=nx).map(f64::from).collect();
        let descending: Vec<f64> = ascending.iter().rev().copied().collect();
        assert!(xs == ascending || xs == descending, "z = {z}: {xs:?}");
        check_sources(&mesh, &positions, &plane, &lines);
    }
    // z = 0 with normal +z: the bottom row is on the plane, nothing below: empty.
    assert!(section(&mesh, &positions, DVec3::ZERO, DVec3::Z).is_empty());
}

#[test]
fn open_grid_gives_an_open_chain_running_along_n_cross_nf() {
    // x = 2.5 on the flat 6 × 4 grid cuts the five horizontal edges (2, j)–(3, j) at
    // (2.5, j) and the four diagonals (2, j)–(3, j + 1) at (2.5, j + 1/2): nine points on a
    // segment of length 4. The face normal is +z and the plane normal +x, so the chain
    // runs along x × z = −y: from y = 4 down to y = 0.
    let grid = primitives::grid(6, 4);
    let mesh = build(&grid);
    let plane = Plane::new(DVec3::new(2.5, 0.0, 0.0), DVec3::X).expect("valid");
    let lines = section(&mesh, &grid.positions, plane.point(), plane.normal());
    assert_eq!(lines.len(), 1);
    let chain = &lines[0];
    assert!(!chain.closed);
    let ys: Vec<f64> = chain.positions().map(|p| p.y).collect();
    let expected: Vec<f64> = (0..=8).rev().map(|k| f64::from(k) / 2.0).collect();
    assert_eq!(ys, expected);
    assert!(chain.positions().all(|p| p.x == 2.5 && p.z == 0.0));
    assert_eq!(chain.length(), 4.0);
    assert_eq!(profile_length(&lines), 4.0);
    let direction = plane.normal().cross(DVec3::Z);
    assert!(chain.segments().all(|(a, b)| (b - a).dot(direction) > 0.0));
    check_sources(&mesh, &grid.positions, &plane, &lines);
}

#[test]
fn oblique_cut_across_a_corner() {
    // The plane x + y = 1/2 separates vertex (0, 0) from the rest: it cuts (0,0)–(1,0) at
    // (1/2, 0), the diagonal (0,0)–(1,1) at (1/4, 1/4) and (0,0)–(0,1) at (0, 1/2).
    let grid = primitives::grid(4, 4);
    let mesh = build(&grid);
    let lines = section(
        &mesh,
        &grid.positions,
        DVec3::new(0.5, 0.0, 0.0),
        DVec3::new(1.0, 1.0, 0.0),
    );
    assert_eq!(lines.len(), 1);
    let points: Vec<DVec3> = lines[0].positions().collect();
    let expected = [
        DVec3::new(0.5, 0.0, 0.0),
        DVec3::new(0.25, 0.25, 0.0),
        DVec3::new(0.0, 0.5, 0.0),
    ];
    // Direction n × z with n ∝ (1, 1, 0): ∝ (1, −1, 0), from (0, 1/2) to (1/2, 0).
    let reversed: Vec<DVec3> = expected.iter().rev().copied().collect();
    assert_eq!(points.len(), 3);
    for (p, q) in points.iter().zip(&reversed) {
        assert!((*p - *q).length() < 1e-16, "{p} vs {q}");
    }
    assert!((lines[0].length() - 0.5f64.sqrt()).abs() < 1e-15);
}

#[test]
fn diagonal_cut_along_mesh_edges() {
    // The plane x = y contains the diagonals (k, k)–(k+1, k+1): those edges lie in the
    // plane (positive side) and are not cut; the section runs through the vertices (k, k)
    // reached from the negative side x < y. One chain of six vertex points, length 5√2.
    let grid = primitives::grid(5, 5);
    let mesh = build(&grid);
    let plane = Plane::new(DVec3::ZERO, DVec3::new(1.0, -1.0, 0.0)).expect("valid");
    let lines = section(&mesh, &grid.positions, plane.point(), plane.normal());
    assert_eq!(lines.len(), 1);
    let chain = &lines[0];
    assert!(!chain.closed);
    assert_eq!(chain.points.len(), 6);
    assert!(chain.positions().all(|p| p.x == p.y));
    assert!((chain.length() - 5.0 * 2f64.sqrt()).abs() < 1e-14);
    check_sources(&mesh, &grid.positions, &plane, &lines);
}

#[test]
fn a_hole_splits_the_section_into_two_chains() {
    // A 6 × 6 grid without the cells [2, 4) × [2, 4); x = 3.5 crosses the grid from y = 0
    // to 2 and from 4 to 6.
    let grid = primitives::grid(6, 6);
    let faces: Vec<&[u32]> = grid
        .faces
        .iter()
        .enumerate()
        .filter(|&(f, _)| {
            let cell = f / 2;
            let (i, j) = (cell % 6, cell / 6);
            !((2..4).contains(&i) && (2..4).contains(&j))
        })
        .map(|(_, face)| face)
        .collect();
    let mesh = HalfedgeMesh::from_polygons(grid.positions.len(), &faces).expect("valid");
    let lines = section(&mesh, &grid.positions, DVec3::new(3.5, 0.0, 0.0), DVec3::X);
    assert_eq!(lines.len(), 2);
    assert!(lines.iter().all(|l| !l.closed && l.length() == 2.0));
    assert_eq!(profile_length(&lines), 4.0);
}

/// The distance from the origin to the plane of each face, minimised: the radius of the
/// largest ball around the origin inside a convex polyhedron.
fn inradius(mesh: &HalfedgeMesh, positions: &[DVec3]) -> f64 {
    mesh.faces()
        .map(|f| {
            let [a, b, c] = mesh.triangle_vertices(f).map(|v| positions[v.index()]);
            let n = (b - a).cross(c - a).normalize();
            a.dot(n)
        })
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn icosphere_equator_is_a_loop_of_length_near_two_pi() {
    // The level-3 icosphere is convex (checked below): the section by z = 0 is a convex
    // polygon containing the disc of the inscribed radius r_in and inside the unit disc,
    // so 2π r_in ≤ length ≤ 2π (perimeters of nested convex sets grow). The icosahedron
    // has vertices on z = 0, so the loop also passes through vertices on the plane.
    let sphere = primitives::icosphere(3);
    let mesh = build(&sphere);
    let positions = &sphere.positions;
    for f in mesh.faces() {
        let [a, b, c] = mesh.triangle_vertices(f).map(|v| positions[v.index()]);
        let n = (b - a).cross(c - a);
        assert!(positions.iter().all(|&p| (p - a).dot(n) <= 1e-12), "convex");
    }
    let r_in = inradius(&mesh, positions);
    assert!(r_in > 0.98);

    let plane = Plane::new(DVec3::ZERO, DVec3::Z).expect("valid");
    let lines = section(&mesh, positions, plane.point(), plane.normal());
    assert_eq!(lines.len(), 1);
    let equator = &lines[0];
    assert!(equator.closed);
    let length = equator.length();
    assert!(length <= TAU && length >= TAU * r_in, "{length}");
    assert!(
        equator
            .points
            .iter()
            .any(|p| matches!(p.source, PointSource::Vertex(_)))
    );
    check_sources(&mesh, positions, &plane, &lines);

    // Counter-clockwise about +z: the polar angle grows all the way round, once.
    let angles: Vec<f64> = equator.positions().map(|p| p.y.atan2(p.x)).collect();
    let mut turned = 0.0;
    for i in 0..angles.len() {
        let mut step = angles[(i + 1) % angles.len()] - angles[i];
        if step < -PI {
            step += TAU;
        }
        assert!(step > 0.0);
        turned += step;
    }
    assert!((turned - TAU).abs() < 1e-12);
    let area = shoelace_xy(equator) / 2.0;
    assert!(area <= PI && area >= PI * r_in * r_in);
}

#[test]
fn torus_cut_through_its_hole_gives_two_loops_of_opposite_turn() {
    // The torus R = 2, r = 0.5 about the z-axis cut by z = 0: an outer loop near radius
    // 2.5 running counter-clockwise about +z and an inner loop near radius 1.5 running
    // clockwise, the boundary of the annulus the plane cuts from the solid torus.
    let torus = primitives::torus(2.0, 0.5, 48, 16);
    let mesh = build(&torus);
    let lines = section(&mesh, &torus.positions, DVec3::ZERO, DVec3::Z);
    assert_eq!(lines.len(), 2);
    assert!(lines.iter().all(|l| l.closed));
    let mut areas: Vec<f64> = lines.iter().map(|l| shoelace_xy(l) / 2.0).collect();
    areas.sort_by(f64::total_cmp);
    // Both loops are the regular 48-gons through the torus's vertices on the equators: the
    // outer vertices lie on z = 0; the inner ones at z = r sin π ≈ 6·10⁻¹⁷, just above, so
    // the inner loop cuts their edges a hair below them. Area (n/2) ρ² sin(2π/n).
    let polygon = |rho: f64| 24.0 * rho * rho * (TAU / 48.0).sin();
    assert!(close_rel(areas[0], -polygon(1.5), 1e-12), "{areas:?}");
    assert!(close_rel(areas[1], polygon(2.5), 1e-12), "{areas:?}");
}

fn close_rel(got: f64, want: f64, relative: f64) -> bool {
    (got - want).abs() <= relative * want.abs()
}

#[test]
fn profile_deviation_between_offset_planes_is_the_offset() {
    let grid = primitives::grid(4, 4);
    let mesh = build(&grid);
    let offset = 0.3;
    let lifted: Vec<DVec3> = grid
        .positions
        .iter()
        .map(|&p| p + DVec3::new(0.0, 0.0, offset))
        .collect();
    let cut = |positions: &[DVec3]| section(&mesh, positions, DVec3::new(0.0, 1.5, 0.0), DVec3::Y);
    let (a, b) = (cut(&lifted), cut(&grid.positions));
    for (from, to) in [(&a, &b), (&b, &a)] {
        let d = profile_deviation(from, to).expect("non-empty");
        assert_eq!(d.count, 9);
        assert!((d.mean - offset).abs() < 1e-15);
        assert!((d.rms - offset).abs() < 1e-15);
        assert!((d.max - offset).abs() < 1e-15);
    }
    let same = profile_deviation(&a, &a).expect("non-empty");
    assert_eq!((same.rms, same.max), (0.0, 0.0));
}

fn point(x: f64, y: f64) -> ProfilePoint {
    ProfilePoint {
        position: DVec3::new(x, y, 0.0),
        source: PointSource::Vertex(beltrami_halfedge::VertexId::new(0)),
    }
}

#[test]
fn profile_deviation_measures_to_the_nearest_segment() {
    // Reference: the open chain (0,0) → (2,0) → (2,2). Points: (1, 1) is 1 from both
    // segments; (3, 3) is √2 from the end (2, 2); (−1, 0) is 1 from (0, 0).
    let reference = [Polyline {
        points: vec![point(0.0, 0.0), point(2.0, 0.0), point(2.0, 2.0)],
        closed: false,
    }];
    let profile = [Polyline {
        points: vec![point(1.0, 1.0), point(3.0, 3.0), point(-1.0, 0.0)],
        closed: false,
    }];
    let d = profile_deviation(&profile, &reference).expect("non-empty");
    let sqrt2 = 2f64.sqrt();
    assert!((d.max - sqrt2).abs() < 1e-15);
    assert!((d.mean - (2.0 + sqrt2) / 3.0).abs() < 1e-15);
    assert!((d.rms - (4.0f64 / 3.0).sqrt()).abs() < 1e-15);
    // Closing the reference adds the segment (2,2) → (0,0), through (1, 1).
    let closed = [Polyline {
        closed: true,
        ..reference[0].clone()
    }];
    let d = profile_deviation(&profile[..], &closed).expect("non-empty");
    assert!((d.max - sqrt2).abs() < 1e-15 && (d.mean - (1.0 + sqrt2) / 3.0).abs() < 1e-15);
    // A single-point reference is a point.
    let single = [Polyline {
        points: vec![point(0.0, 0.0)],
        closed: true,
    }];
    assert_eq!(single[0].length(), 0.0);
    let d = profile_deviation(&profile, &single).expect("non-empty");
    assert!((d.max - 18f64.sqrt()).abs() < 1e-15);
}

#[test]
fn errors_are_typed() {
    for normal in [
        DVec3::ZERO,
        DVec3::new(f64::NAN, 0.0, 1.0),
        DVec3::new(0.0, f64::INFINITY, 0.0),
    ] {
        assert!(matches!(
            Plane::new(DVec3::ZERO, normal),
            Err(MetricsError::InvalidParameter {
                name: "plane normal",
                ..
            })
        ));
    }
    assert!(matches!(
        Plane::new(DVec3::new(0.0, f64::NAN, 0.0), DVec3::Z),
        Err(MetricsError::InvalidParameter {
            name: "plane point",
            ..
        })
    ));
    // Tiny and huge normals normalise.
    assert_eq!(
        Plane::new(DVec3::ZERO, DVec3::new(0.0, 1e-310, 0.0))
            .expect("valid")
            .normal(),
        DVec3::Y
    );
    assert_eq!(
        Plane::new(DVec3::ZERO, DVec3::new(0.0, 0.0, -1e308))
            .expect("valid")
            .normal(),
        -DVec3::Z
    );

    let quads = primitives::cube_quads();
    let mesh = build(&quads);
    let plane = Plane::new(DVec3::splat(0.5), DVec3::Z).expect("valid");
    assert_eq!(
        cross_section(
            &Geometry::new(&mesh, &quads.positions).expect("positions"),
            &plane
        ),
        Err(MetricsError::Topology(TopologyError::NotTriangle {
            face: 0,
            len: 4
        }))
    );

    let cube = primitives::cube();
    let mesh = build(&cube);
    let mut bad = cube.positions.clone();
    bad[6].x = f64::NAN;
    assert_eq!(
        cross_section(&Geometry::new(&mesh, &bad).expect("positions"), &plane),
        Err(MetricsError::NonFinite {
            what: "position",
            index: 6
        })
    );

    let some = [Polyline {
        points: vec![point(0.0, 0.0)],
        closed: false,
    }];
    assert_eq!(
        profile_deviation(&[], &some),
        Err(MetricsError::Empty { what: "profile" })
    );
    assert_eq!(
        profile_deviation(&some, &[Polyline::default()]),
        Err(MetricsError::Empty {
            what: "reference profile"
        })
    );
    let nan = [Polyline {
        points: vec![point(0.0, 0.0), point(f64::NAN, 0.0)],
        closed: false,
    }];
    assert_eq!(
        profile_deviation(&nan, &some),
        Err(MetricsError::NonFinite {
            what: "profile point",
            index: 1
        })
    );
}
