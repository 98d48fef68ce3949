//! The builder runs parts of its work in parallel (rayon); its meshes and its errors
//! must not depend on the number of threads. Large grids (several parallel chunks)
//! with one defect placed at the start, middle and end are built on one and on two
//! threads and compared, and the error names the defect.

use beltrami_halfedge::{HalfedgeMesh, PolygonList, TopologyError, primitives};

fn build_on(threads: usize, n: usize, faces: &PolygonList) -> Result<HalfedgeMesh, TopologyError> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
        .install(|| HalfedgeMesh::from_polygons(n, faces.iter()))
}

fn same_on_one_and_two_threads(
    n: usize,
    faces: &PolygonList,
) -> Result<HalfedgeMesh, TopologyError> {
    let one = build_on(1, n, faces);
    let two = build_on(2, n, faces);
    assert_eq!(format!("{one:?}"), format!("{two:?}"));
    // The borrowed-list builder checks the faces in parallel: the same result.
    for threads in [1, 2] {
        let list = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool")
            .install(|| HalfedgeMesh::from_polygon_list(n, faces));
        assert_eq!(format!("{list:?}"), format!("{two:?}"));
    }
    two
}

fn with_face(faces: &PolygonList, at: usize, face: Option<&[u32]>) -> PolygonList {
    let mut out = PolygonList::new();
    for (f, indices) in faces.iter().enumerate() {
        if f == at {
            if let Some(face) = face {
                out.push(face);
            }
            continue;
        }
        out.push(indices);
    }
    out
}

#[test]
fn meshes_and_errors_do_not_depend_on_the_thread_count() {
    let grid = primitives::grid(200, 200);
    let n = grid.positions.len();
    let faces = grid.faces;
    let mesh = same_on_one_and_two_threads(n, &faces).expect("a grid is valid");
    mesh.check_integrity().expect("valid");
    assert_eq!(mesh.n_faces(), faces.len());

    for at in [0, faces.len() / 2, faces.len() - 1] {
        let face = faces.get(at).expect("in range").to_vec();
        // The face turned round: its edges with its neighbours are inconsistent.
        let flipped = [face[0], face[2], face[1]];
        let err = same_on_one_and_two_threads(n, &with_face(&faces, at, Some(&flipped)))
            .expect_err("inconsistent");
        assert!(
            matches!(err, TopologyError::InconsistentOrientation { .. }),
            "{err}"
        );
        // The face twice: three faces on its inner edges, two faces the same way
        // round on its boundary edges (whichever edge comes first is reported).
        let mut doubled = faces.clone();
        doubled.push(&face);
        let err = same_on_one_and_two_threads(n, &doubled).expect_err("non-manifold");
        assert!(
            matches!(
                err,
                TopologyError::NonManifoldEdge { .. }
                    | TopologyError::InconsistentOrientation { .. }
            ),
            "{err}"
        );
        // Faces that are bad on their own, here and a second one later: the first
        // is named.
        let n32 = u32::try_from(n).expect("small");
        for bad in [
            vec![face[0], face[1], n32],
            vec![face[0], face[1]],
            vec![face[0], face[1], face[0]],
        ] {
            let mut faces = with_face(&faces, at, Some(&bad));
            faces.push(&[0, 0, 1]);
            let err = same_on_one_and_two_threads(n, &faces).expect_err("a bad face");
            assert!(err.to_string().contains(&format!("face {at} ")), "{err}");
        }
        // A face removed: a hole (which pinches a vertex on the grid's border).
        let holed = with_face(&faces, at, None);
        let _ = same_on_one_and_two_threads(n, &holed);
    }

    // Two grids sharing one corner vertex: a pinched vertex.
    let mut pinched = faces.clone();
    let offset = u32::try_from(n).expect("small") - 1;
    for face in faces.iter() {
        let shifted: Vec<u32> = face.iter().map(|&v| v + offset).collect();
        pinched.push(&shifted);
    }
    let err = same_on_one_and_two_threads(2 * n - 1, &pinched).expect_err("pinched");
    assert!(
        matches!(err, TopologyError::NonManifoldVertex { .. }),
        "{err}"
    );
}
