//! The input checks every algorithm makes first, in the same order and with the same
//! messages: one position per vertex, triangles only, finite positions.

use beltrami_algorithms::{
    DecimateOptions, DelaunayOptions, FillOptions, RemeshOptions, decimate, delaunay_flip,
    fill_holes, loop_subdivide, mesh_quality, remesh,
};
use beltrami_halfedge::{DVec3, HalfedgeMesh, primitives};

/// The message of each algorithm's error for `mesh` and `positions`.
fn messages(mesh: &HalfedgeMesh, positions: &[DVec3]) -> [String; 5] {
    [
        remesh(mesh, positions, &RemeshOptions::default())
            .unwrap_err()
            .to_string(),
        fill_holes(mesh, positions, &FillOptions::default())
            .unwrap_err()
            .to_string(),
        decimate(mesh, positions, &DecimateOptions::default())
            .unwrap_err()
            .to_string(),
        delaunay_flip(mesh, positions, DelaunayOptions::default())
            .unwrap_err()
            .to_string(),
        mesh_quality(mesh, positions).unwrap_err().to_string(),
    ]
}

#[test]
fn a_quad_is_named_with_the_algorithm_that_needs_triangles() {
    // Two quads and a triangle: the first quad is named, before the positions' count.
    let mesh =
        HalfedgeMesh::from_polygons(7, &[vec![0u32, 1, 2, 3], vec![0, 3, 4], vec![4, 3, 5, 6]])
            .unwrap();
    let positions = vec![DVec3::ZERO; 7];
    assert_eq!(
        messages(&mesh, &positions),
        [
            "face 0 has 4 vertices; remeshing needs a triangle mesh",
            "face 0 has 4 vertices; hole filling needs a triangle mesh",
            "face 0 has 4 vertices; decimation needs a triangle mesh",
            "face 0 has 4 vertices; Delaunay flipping needs a triangle mesh",
            "face 0 has 4 vertices; the quality figures are for triangle meshes",
        ]
    );
    assert_eq!(
        loop_subdivide(&mesh, &positions, 1)
            .unwrap_err()
            .to_string(),
        "face 0 has 4 vertices; subdivision needs a triangle mesh"
    );
}

#[test]
fn the_position_count_is_checked_first() {
    let grid = primitives::grid(2, 2);
    let mesh = grid.mesh().unwrap();
    let short = &grid.positions[1..];
    let [remesh, fill, decimate, delaunay, quality] = messages(&mesh, short);
    for m in [remesh, fill, decimate, delaunay] {
        assert_eq!(m, "8 positions were given for a mesh of 9 vertices");
    }
    assert_eq!(quality, "8 positions for a mesh of 9 vertices");
}

#[test]
fn the_first_non_finite_position_is_named() {
    let grid = primitives::grid(2, 2);
    let mesh = grid.mesh().unwrap();
    let mut positions = grid.positions.clone();
    positions[7] = DVec3::new(0.0, f64::NAN, 0.0);
    positions[8] = DVec3::splat(f64::INFINITY);
    for m in messages(&mesh, &positions) {
        assert_eq!(m, "vertex 7 has a non-finite position");
    }
}
