//! `Geometry::summary`: counts, topology and geometry of a mesh in one record.

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::{DVec3, HalfedgeMesh, primitives};

#[test]
fn an_open_grid_has_one_boundary_loop_and_genus_zero() {
    let grid = primitives::grid(3, 2); // 4 × 3 vertices, 12 triangles
    let mesh = grid.mesh().unwrap();
    let s = Geometry::new(&mesh, &grid.positions).unwrap().summary();
    assert_eq!((s.vertices, s.faces), (12, 12));
    assert_eq!(s.edges, mesh.n_edges());
    assert!(s.triangle_mesh);
    assert_eq!(s.boundary_loop_lengths, [10]);
    assert_eq!((s.components, s.genus), (1, Some(0)));
    assert_eq!(s.euler_characteristic, 1);
    assert!(!s.closed);
    assert_eq!(s.volume, None);
    assert_eq!(s.area, 6.0);
    assert_eq!(
        s.bounding_box,
        Some((DVec3::ZERO, DVec3::new(3.0, 2.0, 0.0)))
    );
    assert_eq!((s.isolated_vertices, s.degenerate_faces), (0, 0));
}

#[test]
fn several_components_have_no_single_genus() {
    // A torus and, apart from it, a triangle and an isolated vertex.
    let torus = primitives::torus(2.0, 0.5, 12, 8);
    let n = torus.positions.len() as u32;
    let mut positions = torus.positions.clone();
    positions.extend([
        DVec3::X * 9.0,
        DVec3::Y * 9.0,
        DVec3::Z * 9.0,
        DVec3::ONE * 9.0,
    ]);
    let mut faces: Vec<Vec<u32>> = torus.faces.iter().map(|f| f.to_vec()).collect();
    faces.push(vec![n, n + 1, n + 2]);
    let mesh = HalfedgeMesh::from_polygons(positions.len(), &faces).unwrap();
    let s = Geometry::new(&mesh, &positions).unwrap().summary();
    assert_eq!(s.components, 3);
    assert_eq!(s.genus, None);
    assert_eq!(s.component_genus, [Some(1), Some(0), None]);
    assert_eq!(s.isolated_vertices, 1);
    assert_eq!(s.boundary_loop_lengths, [3]);
    assert!(!s.closed);
}

#[test]
fn an_area_near_the_largest_f64_is_finite_and_one_beyond_it_infinite() {
    // The doubled face area 2.25e308 overflows f64; the area itself, 1.125e308, fits.
    let positions = [DVec3::ZERO, DVec3::X * 1.5e154, DVec3::Y * 1.5e154];
    let mesh = HalfedgeMesh::from_polygons(3, [[0u32, 1, 2]]).unwrap();
    let geometry = Geometry::new(&mesh, &positions).unwrap();
    let s = geometry.summary();
    assert!((s.area / 1.125e308 - 1.0).abs() < 1e-12, "{}", s.area);
    // Beyond f64 even at the best scale: infinity.
    let positions = [DVec3::ZERO, DVec3::X * 1e300, DVec3::Y * 1e300];
    let s = Geometry::new(&mesh, &positions).unwrap().summary();
    assert_eq!(s.area, f64::INFINITY);
}

#[test]
fn a_mesh_without_faces_is_not_closed_and_has_no_volume() {
    let positions = [DVec3::ZERO, DVec3::X, DVec3::Y];
    let mesh = HalfedgeMesh::from_polygons(3, Vec::<[u32; 3]>::new()).unwrap();
    let s = Geometry::new(&mesh, &positions).unwrap().summary();
    assert_eq!((s.vertices, s.faces), (3, 0));
    assert!(!s.closed);
    assert_eq!(s.volume, None);
}
