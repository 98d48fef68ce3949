//! The quality figures against shapes whose angles, aspect ratios and valences are known
//! in closed form, and against the Delaunay flipper's own count of negative weights.

use beltrami_algorithms::quality::ASPECT_RATIO_BINS;
use beltrami_algorithms::{
    DelaunayOptions, QualityError, delaunay_flip, flipped_faces, mesh_quality,
};
use beltrami_halfedge::primitives::{self, Primitive};
use beltrami_halfedge::{DVec3, PolygonList};
use beltrami_testkit::SplitMix64;

fn triangles(positions: Vec<DVec3>, faces: &[[u32; 3]]) -> Primitive {
    Primitive {
        positions,
        faces: PolygonList::from_triangles(faces),
    }
}

#[test]
fn an_icosahedron_is_equilateral_with_twelve_valence_five_vertices() {
    let ico = primitives::icosphere(0);
    let q = mesh_quality(&ico.mesh().unwrap(), &ico.positions).unwrap();
    let s = q.shape.as_ref().unwrap();
    assert!((s.min_angle - 60.0).abs() < 1e-9, "{}", s.min_angle);
    assert!((s.max_angle - 60.0).abs() < 1e-9, "{}", s.max_angle);
    assert!((s.mean_aspect_ratio - 1.0).abs() < 1e-12);
    assert_eq!(s.aspect_ratio_histogram[0], 20);
    let e = q.edge_length.unwrap();
    assert!(e.cv < 1e-12 && (e.max - e.min) < 1e-12);
    assert_eq!(q.valence_histogram, vec![0, 0, 0, 0, 0, 12]);
    assert!(q.boundary_valence_histogram.is_empty());
    assert_eq!(q.regular_share, 0.0);
    assert_eq!((q.interior_edges, q.negative_cotangent_edges), (30, 0));
}

#[test]
fn a_grid_has_right_isosceles_triangles_and_regular_valences() {
    let grid = primitives::grid(5, 5);
    let q = mesh_quality(&grid.mesh().unwrap(), &grid.positions).unwrap();
    let s = q.shape.as_ref().unwrap();
    assert!((s.min_angle - 45.0).abs() < 1e-12);
    assert!((s.max_angle - 90.0).abs() < 1e-12);
    assert!((s.mean_min_angle - 45.0).abs() < 1e-12);
    // Longest edge √2, area ½: √3 · 2 / (4 · ½) = √3, in the bin [1.5, 2).
    assert!((s.max_aspect_ratio - 3f64.sqrt()).abs() < 1e-12);
    assert_eq!(s.aspect_ratio_histogram[1], 50);
    // 16 interior vertices, all of valence 6; the boundary's 20 have valences 2 to 4.
    assert_eq!(q.valence_histogram.iter().sum::<usize>(), 16);
    assert_eq!(q.valence_histogram[6], 16);
    assert_eq!(q.boundary_valence_histogram.iter().sum::<usize>(), 20);
    // Boundary valence 4 on the sides; the corners have 2 or 3.
    assert_eq!(q.boundary_valence_histogram[4], 16);
    assert!((q.regular_share - 32.0 / 36.0).abs() < 1e-15);
    // Right angles: every quadrilateral is cocircular, no weight is negative.
    assert_eq!(q.negative_cotangent_edges, 0);
    let e = q.edge_length.unwrap();
    assert_eq!((e.min, e.max), (1.0, 2f64.sqrt()));
    // The same grid at 1e300: the edge lengths and their spread stay finite and scale
    // (the plain lengths' squares overflowed, and the mean's sum: inf and NaN).
    let huge: Vec<DVec3> = grid.positions.iter().map(|p| *p * 1e300).collect();
    let big = mesh_quality(&grid.mesh().unwrap(), &huge).unwrap();
    let b = big.edge_length.unwrap();
    assert_eq!((b.min, b.max), (1e300, 2f64.sqrt() * 1e300));
    assert!((b.mean / 1e300 - e.mean).abs() < 1e-12 * e.mean, "{b:?}");
    assert!((b.cv - e.cv).abs() < 1e-12, "{b:?} against {e:?}");
}

#[test]
fn a_sliver_has_the_aspect_ratio_of_the_formula() {
    // Longest edge 1, shortest altitude 0.1: √3 · 1 / (4 · 0.05) = 8.66…
    let sliver = triangles(
        vec![
            DVec3::ZERO,
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.3, 0.1, 0.0),
        ],
        &[[0, 1, 2]],
    );
    let q = mesh_quality(&sliver.mesh().unwrap(), &sliver.positions).unwrap();
    let s = q.shape.unwrap();
    assert!((s.max_aspect_ratio - 3f64.sqrt() / 0.2).abs() < 1e-12);
    assert_eq!(s.aspect_ratio_histogram[ASPECT_RATIO_BINS.len() - 1], 1);
    let angles = [
        (0.1f64).atan2(0.3).to_degrees(),
        (0.1f64).atan2(0.7).to_degrees(),
    ];
    assert!((s.min_angle - angles[1]).abs() < 1e-12);
    assert!((s.max_angle - (180.0 - angles[0] - angles[1])).abs() < 1e-12);
}

#[test]
fn a_degenerate_triangle_is_counted_apart_and_gives_no_nan() {
    let flat = triangles(
        vec![
            DVec3::ZERO,
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
        ],
        &[[0, 1, 3], [1, 2, 3], [0, 2, 1]],
    );
    // Faces 0 and 1 fine, face 2 has zero area (collinear).
    let mesh = flat.mesh().unwrap();
    let q = mesh_quality(&mesh, &flat.positions).unwrap();
    assert_eq!(q.degenerate_faces, 1);
    let s = q.shape.unwrap();
    assert!(s.min_angle.is_finite() && s.mean_aspect_ratio.is_finite());
}

#[test]
fn only_degenerate_triangles_give_no_shape_figures() {
    let line = triangles(
        vec![
            DVec3::ZERO,
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
        ],
        &[[0, 1, 2]],
    );
    let q = mesh_quality(&line.mesh().unwrap(), &line.positions).unwrap();
    assert_eq!((q.faces, q.degenerate_faces), (1, 1));
    assert!(q.shape.is_none());
}

#[test]
fn negative_weights_agree_with_the_delaunay_flipper() {
    for seed in 0..5 {
        let mut grid = primitives::grid(10, 8);
        let mut rng = SplitMix64::new(seed);
        for p in &mut grid.positions {
            *p += DVec3::new(
                0.35 * rng.next_symmetric(),
                0.35 * rng.next_symmetric(),
                0.0,
            );
        }
        let mesh = grid.mesh().unwrap();
        let before = mesh_quality(&mesh, &grid.positions).unwrap();
        let (flipped, positions, report) =
            delaunay_flip(&mesh, &grid.positions, DelaunayOptions::default()).unwrap();
        assert!(report.negative_before > 0, "seed {seed}");
        assert_eq!(before.negative_cotangent_edges, report.negative_before);
        let after = mesh_quality(&flipped, &positions).unwrap();
        assert_eq!(after.negative_cotangent_edges, report.negative_after);
        assert_eq!(after.negative_cotangent_edges, 0);
        assert!(
            after.shape.unwrap().min_angle >= before.shape.unwrap().min_angle,
            "a Delaunay triangulation maximises the smallest angle"
        );
    }
}

#[test]
fn small_rigid_motions_flip_nothing_and_a_mirrored_plane_flips_everything() {
    let torus = primitives::torus(2.0, 0.7, 12, 8);
    let mesh = torus.mesh().unwrap();
    // A rotation by less than a right angle turns no normal by as much as 90°.
    let (axis, angle) = (DVec3::new(1.0, 2.0, 3.0).normalize(), 1.5);
    let rotation = glam::DQuat::from_axis_angle(axis, angle);
    let moved: Vec<DVec3> = torus
        .positions
        .iter()
        .map(|p| rotation * *p + DVec3::new(5.0, -1.0, 0.5))
        .collect();
    assert_eq!(flipped_faces(&mesh, &moved, &torus.positions).unwrap(), 0);
    // Mirroring a planar patch across a line in its plane turns every triangle over.
    let grid = primitives::grid(6, 4);
    let mirrored: Vec<DVec3> = grid
        .positions
        .iter()
        .map(|p| DVec3::new(-p.x, p.y, p.z))
        .collect();
    let mesh = grid.mesh().unwrap();
    assert_eq!(
        flipped_faces(&mesh, &mirrored, &grid.positions).unwrap(),
        mesh.n_faces()
    );
}

#[test]
fn bad_input_gives_typed_errors() {
    let quads = primitives::cube_quads();
    assert!(matches!(
        mesh_quality(&quads.mesh().unwrap(), &quads.positions),
        Err(QualityError::NotTriangle { len: 4, .. })
    ));
    let cube = primitives::cube();
    let mesh = cube.mesh().unwrap();
    assert_eq!(
        mesh_quality(&mesh, &cube.positions[1..]),
        Err(QualityError::PositionCount {
            positions: 7,
            vertices: 8
        })
    );
    let mut nan = cube.positions.clone();
    nan[3].y = f64::NAN;
    assert_eq!(
        mesh_quality(&mesh, &nan),
        Err(QualityError::NonFinite { vertex: 3 })
    );
    assert_eq!(
        flipped_faces(&mesh, &cube.positions, &nan),
        Err(QualityError::NonFinite { vertex: 3 })
    );
}
