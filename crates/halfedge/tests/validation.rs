//! Every validation error, with its exact message, and the opt-in repairs.

use beltrami_halfedge::primitives;
use beltrami_halfedge::{BuildOptions, HalfedgeMesh, TopologyError, VertexId, VertexSplit};
use insta::assert_snapshot;

fn err<const N: usize>(n_vertices: usize, faces: &[[u32; N]]) -> TopologyError {
    HalfedgeMesh::from_polygons(n_vertices, faces).expect_err("input must be rejected")
}

#[test]
fn vertex_out_of_range() {
    let e = err(3, &[[0, 1, 2], [0, 2, 7]]);
    assert!(matches!(
        e,
        TopologyError::VertexOutOfRange {
            face: 1,
            vertex: 7,
            n_vertices: 3
        }
    ));
    assert_snapshot!(e, @"face 1 refers to vertex 7, but there are only 3 vertices");
}

#[test]
fn face_too_small() {
    let faces: Vec<Vec<u32>> = vec![vec![0, 1, 2], vec![1, 2]];
    let e = HalfedgeMesh::from_polygons(3, &faces).unwrap_err();
    assert_snapshot!(e, @"face 1 has 2 vertices; a face needs at least 3");
}

#[test]
fn repeated_vertex() {
    let e = err(4, &[[0, 1, 2, 3], [0, 3, 2, 3]]);
    assert!(matches!(
        e,
        TopologyError::RepeatedVertex { face: 1, vertex: 3 }
    ));
    assert_snapshot!(e, @"face 1 lists vertex 3 more than once");
    // Large polygons take the sorting path.
    let mut big: Vec<u32> = (0..40).collect();
    big[30] = 5;
    let e = HalfedgeMesh::from_polygons(40, [big]).unwrap_err();
    assert_snapshot!(e, @"face 0 lists vertex 5 more than once");
}

#[test]
fn non_manifold_edge() {
    // Three triangles on edge (0, 1).
    let e = err(5, &[[0, 1, 2], [1, 0, 3], [0, 1, 4]]);
    assert_snapshot!(e, @"non-manifold edge (0, 1): shared by 3 faces (0, 1, 2); a manifold edge has at most 2");
}

#[test]
fn inconsistent_orientation() {
    let e = err(4, &[[0, 1, 2], [0, 1, 3]]);
    assert!(matches!(
        e,
        TopologyError::InconsistentOrientation {
            from: 0,
            to: 1,
            faces: [0, 1]
        }
    ));
    assert_snapshot!(e, @"inconsistent orientation: faces 0 and 1 both traverse edge 0 -> 1");
}

#[test]
fn the_earliest_face_problem_is_reported() {
    // Face 3/4 disagree on (5, 6); faces 0/1 disagree on (0, 1): faces 0/1 are reported.
    let e = err(8, &[[0, 1, 2], [0, 1, 3], [5, 6, 7], [5, 6, 4], [2, 3, 4]]);
    assert_snapshot!(e, @"inconsistent orientation: faces 0 and 1 both traverse edge 0 -> 1");
}

#[test]
fn non_manifold_vertex_with_two_open_fans() {
    // A bow tie: two triangles touching at vertex 0.
    let e = err(5, &[[0, 1, 2], [0, 3, 4]]);
    assert_snapshot!(e, @"non-manifold vertex 0: its faces form 2 separate fans");
}

#[test]
fn non_manifold_vertex_with_closed_fans() {
    // Two tetrahedra sharing vertex 0 only: no boundary anywhere.
    let t = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
    let mut faces: Vec<[u32; 3]> = t.to_vec();
    faces.extend(t.iter().map(|f| f.map(|v| if v == 0 { 0 } else { v + 3 })));
    let e = err(7, &faces);
    assert_snapshot!(e, @"non-manifold vertex 0: its faces form 2 separate fans");
}

#[test]
fn non_manifold_vertex_with_closed_and_open_fan() {
    // A tetrahedron plus a dangling triangle at vertex 0.
    let e = err(6, &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2], [0, 4, 5]]);
    assert_snapshot!(e, @"non-manifold vertex 0: its faces form 2 separate fans");
}

#[test]
fn too_many_vertices() {
    let e = HalfedgeMesh::from_polygons(u32::MAX as usize + 1, [[0u32, 1, 2]]).unwrap_err();
    assert_snapshot!(e, @"too many vertices: 4294967296 (at most 4294967295 are supported)");
}

#[test]
fn drop_degenerate_faces() {
    let faces: Vec<Vec<u32>> = vec![vec![0, 1, 2], vec![1, 1, 2], vec![0, 2, 3], vec![3, 0]];
    let options = BuildOptions::new().drop_degenerate_faces(true);
    let (mesh, report) = HalfedgeMesh::build(4, &faces, &options).unwrap();
    mesh.check_integrity().unwrap();
    assert_eq!(mesh.n_faces(), 2);
    assert_eq!(report.dropped_faces, [1, 3]);
    assert_eq!(report.face_origin, [0, 2]);
    // Out of range stays an error even with the repair.
    let e = HalfedgeMesh::build(3, [[0u32, 1, 9]], &options).unwrap_err();
    assert!(matches!(e, TopologyError::VertexOutOfRange { .. }));
}

#[test]
fn reorient_fixes_a_flipped_cube_face() {
    let cube = primitives::cube();
    let mut faces: Vec<Vec<u32>> = cube.faces.iter().map(<[u32]>::to_vec).collect();
    faces[4].reverse();
    faces[5].reverse();
    let e = HalfedgeMesh::from_polygons(8, &faces).unwrap_err();
    assert!(matches!(e, TopologyError::InconsistentOrientation { .. }));
    let (mesh, report) =
        HalfedgeMesh::build(8, &faces, &BuildOptions::new().reorient(true)).unwrap();
    mesh.check_integrity().unwrap();
    assert_eq!(report.flipped_faces, [4, 5]);
    assert!(mesh.is_closed());
    // A flipped face keeps its first vertex: the reversed [5, 1, 0] becomes [5, 0, 1].
    let f4: Vec<u32> = mesh
        .vertices_around_face(beltrami_halfedge::FaceId::new(4))
        .map(VertexId::raw)
        .collect();
    assert_eq!(f4, [5, 0, 1]);
}

#[test]
fn reorient_rejects_a_moebius_strip() {
    // A strip of 4 quads, closed with a half twist.
    let faces = [[0u32, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 4, 0, 7]];
    let e = HalfedgeMesh::build(8, faces, &BuildOptions::new().reorient(true)).unwrap_err();
    assert_snapshot!(e, @"the component of face 0 is not orientable: no consistent orientation exists");
}

#[test]
fn split_non_manifold_vertices() {
    // Bow tie at 0 plus two tetrahedra-like closed fans are covered by the error tests;
    // here: three fans at vertex 0.
    let faces = [[0u32, 1, 2], [0, 3, 4], [0, 5, 6]];
    let options = BuildOptions::new().split_nonmanifold_vertices(true);
    let (mesh, report) = HalfedgeMesh::build(7, faces, &options).unwrap();
    mesh.check_integrity().unwrap();
    assert_eq!(mesh.n_vertices(), 9);
    assert_eq!(
        report.split_vertices,
        [
            VertexSplit {
                vertex: VertexId::new(7),
                original: VertexId::new(0)
            },
            VertexSplit {
                vertex: VertexId::new(8),
                original: VertexId::new(0)
            }
        ]
    );
    assert_eq!(mesh.connected_components().count(), 3);
    for v in mesh.vertices() {
        assert!(mesh.valence(v) == 2);
    }
}

#[test]
fn split_closed_fans() {
    let t = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
    let mut faces: Vec<[u32; 3]> = t.to_vec();
    faces.extend(t.iter().map(|f| f.map(|v| if v == 0 { 0 } else { v + 3 })));
    let options = BuildOptions::new().split_nonmanifold_vertices(true);
    let (mesh, report) = HalfedgeMesh::build(7, faces, &options).unwrap();
    mesh.check_integrity().unwrap();
    assert_eq!(report.split_vertices.len(), 1);
    let comps = mesh.connected_components();
    assert_eq!(comps.count(), 2);
    assert!(
        comps
            .summaries
            .iter()
            .all(|c| c.is_closed() && c.genus() == Some(0))
    );
}

#[test]
fn a_valid_mesh_needs_no_repair() {
    let p = primitives::torus(2.0, 0.5, 6, 5);
    let (mesh, report) = HalfedgeMesh::build(
        p.positions.len(),
        p.faces.iter(),
        &BuildOptions::repair_all(),
    )
    .unwrap();
    assert!(report.is_empty());
    assert_eq!(mesh, p.mesh().unwrap());
}

mod random {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Any subset of a grid's triangles builds once pinched vertices are split, and the
        /// result satisfies every invariant; without the repair it builds or reports a
        /// non-manifold vertex, nothing else.
        #[test]
        fn grid_subsets_build(keep in proptest::collection::vec(any::<bool>(), 2 * 5 * 4)) {
            let g = primitives::grid(5, 4);
            let faces: Vec<&[u32]> = g.faces.iter().zip(&keep).filter(|(_, k)| **k).map(|(f, _)| f).collect();
            let n = g.positions.len();
            match HalfedgeMesh::from_polygons(n, faces.iter().copied()) {
                Ok(mesh) => mesh.check_integrity().unwrap(),
                Err(TopologyError::NonManifoldVertex { .. }) => {}
                Err(e) => panic!("unexpected error {e}"),
            }
            let options = BuildOptions::new().split_nonmanifold_vertices(true);
            let (mesh, report) = HalfedgeMesh::build(n, faces.iter().copied(), &options).unwrap();
            mesh.check_integrity().unwrap();
            prop_assert_eq!(mesh.n_vertices(), n + report.split_vertices.len());
            prop_assert_eq!(mesh.n_faces(), faces.len());
            let comps = mesh.connected_components();
            let chi: i64 = comps.summaries.iter().map(|c| c.euler_characteristic()).sum();
            prop_assert_eq!(chi, mesh.euler_characteristic());
            // Planar pieces: every face-bearing component is a disc with holes (genus 0).
            prop_assert!(comps.summaries.iter().all(|c| c.faces == 0 || c.genus() == Some(0)));
        }

        /// Rotating each face's vertex list or shuffling the faces changes no count.
        #[test]
        fn face_order_does_not_change_counts(rot in 0usize..3, seed in any::<u64>()) {
            let p = primitives::icosphere(1);
            let mut faces: Vec<Vec<u32>> = p.faces.iter().map(|f| { let mut f = f.to_vec(); f.rotate_left(rot); f }).collect();
            let mut state = seed | 1;
            for i in (1..faces.len()).rev() {
                state ^= state << 13; state ^= state >> 7; state ^= state << 17;
                faces.swap(i, (state % (i as u64 + 1)) as usize);
            }
            let mesh = HalfedgeMesh::from_polygons(p.positions.len(), &faces).unwrap();
            mesh.check_integrity().unwrap();
            prop_assert_eq!((mesh.n_edges(), mesh.euler_characteristic(), mesh.genus()), (120, 2, Some(0)));
        }
    }
}
