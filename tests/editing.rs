//! The editing story end to end, through the facade only: load a mesh, attach a
//! per-vertex scalar, split, collapse and flip, garbage-collect, write a PLY with the
//! scalar, and find the scalar right for every vertex of the file.

use beltrami::io::Encoding;
use beltrami::prelude::*;

/// The vertex rows of an ascii PLY: every number of each row after the header.
fn ascii_vertex_rows(text: &str, n: usize) -> Vec<Vec<f64>> {
    let body = text.split("end_header\n").nth(1).expect("a PLY header");
    body.lines()
        .take(n)
        .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
        .collect()
}

#[test]
fn a_scalar_follows_splits_collapses_flips_and_garbage_collection_into_the_file()
-> Result<(), Box<dyn std::error::Error>> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/fixtures/noisy_icosphere_4.ply"
    );
    let data = read_mesh(path)?;
    let mut mesh = EditMesh::from_mesh_data(&data)?;
    // The scalar is the x coordinate: linear, so a midpoint split interpolates it
    // exactly, and a collapse keeps the kept vertex's own value and position.
    let x: VertexProperty<f64> = mesh.add_vertex_property("x", f64::NAN)?;
    for v in mesh.vertices().collect::<Vec<_>>() {
        let p = mesh.position(v);
        mesh.set(x, v, p.x);
    }
    let (mut splits, mut collapses, mut flips) = (0, 0, 0);
    let edges: Vec<EdgeId> = mesh.edges().step_by(7).collect();
    for e in edges {
        let [a, b] = mesh.edge_vertices(e);
        let mid = 0.5 * (mesh.position(a) + mesh.position(b));
        mesh.split_edge(e, mid)?;
        splits += 1;
    }
    let halfedges: Vec<HalfedgeId> = mesh.halfedges().step_by(13).collect();
    for h in halfedges {
        if mesh.is_live_halfedge(h) && mesh.is_collapse_ok(h) {
            mesh.collapse_edge(h)?;
            collapses += 1;
        }
    }
    let edges: Vec<EdgeId> = mesh.edges().step_by(5).collect();
    for e in edges {
        if mesh.is_flip_ok(e) {
            mesh.flip_edge(e)?;
            flips += 1;
        }
    }
    assert!(splits > 100 && collapses > 100 && flips > 100);
    mesh.check_integrity()?;
    let maps = mesh.garbage_collection();
    assert!(!maps.is_identity(), "collapses leave ids to compact");
    assert!(mesh.values(x).iter().all(|v| v.is_finite()));

    let dir = tempfile::tempdir()?;
    let out = dir.path().join("edited.ply");
    let attributes = VertexAttributes {
        scalars: vec![("x_copy".to_owned(), mesh.values(x).to_vec())],
        colors: None,
    };
    let options = WriteOptions::default().encoding(Encoding::Ascii);
    write_ply(&out, &mesh.to_mesh_data(), &attributes, &options)?;

    let back = read_mesh(&out)?;
    assert_eq!(back.positions.len(), mesh.n_vertices());
    back.mesh()?; // a valid mesh
    let rows = ascii_vertex_rows(&std::fs::read_to_string(&out)?, mesh.n_vertices());
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row.len(), 4, "x y z and the scalar");
        assert!(
            (row[3] - row[0]).abs() <= 1e-12 * row[0].abs().max(1.0),
            "vertex {i}: scalar {} at x {}",
            row[3],
            row[0]
        );
    }
    Ok(())
}

#[test]
fn a_refused_edit_is_a_typed_error_and_changes_nothing() {
    let tet = primitives::tetrahedron();
    let mut mesh = EditMesh::from_mesh_data(&tet).unwrap();
    let e = mesh.edges().next().unwrap();
    // Every edge of a tetrahedron flips into an edge that already exists.
    let before = mesh.to_mesh_data();
    assert!(matches!(
        mesh.flip_edge(e),
        Err(EditError::FlipEdgeExists { .. })
    ));
    assert_eq!(mesh.to_mesh_data(), before);
}
