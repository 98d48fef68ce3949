//! `HalfedgeMesh::split_triangles` against `from_polygons` of the face list it documents,
//! with the full integrity check on every result (in release builds too).

use beltrami_halfedge::primitives::{self, Primitive};
use beltrami_halfedge::{HalfedgeMesh, TopologyError};

/// The face list of the 1-to-4 split, as `split_triangles` documents it.
fn split_faces(mesh: &HalfedgeMesh) -> Vec<[u32; 3]> {
    let nv = mesh.n_vertices() as u32;
    let mut faces = Vec::new();
    for f in mesh.faces() {
        let h0 = mesh.face_halfedge(f);
        let h1 = mesh.next(h0);
        let h2 = mesh.next(h1);
        let [a, b, c] = [h0, h1, h2].map(|h| mesh.to_vertex(h).raw());
        let point = |h: beltrami_halfedge::HalfedgeId| nv + h.edge().raw();
        let (ab, bc, ca) = (point(h1), point(h2), point(h0));
        faces.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
    }
    faces
}

fn meshes() -> Vec<(String, HalfedgeMesh)> {
    let mut with_isolated: Primitive = primitives::grid(4, 3);
    with_isolated.positions.push(beltrami_halfedge::DVec3::ZERO);
    let mut list: Vec<(String, Primitive)> = vec![
        ("triangle".into(), primitives::triangle()),
        ("hexagon fan".into(), primitives::hexagon_fan()),
        ("grid".into(), primitives::grid(5, 4)),
        ("tetrahedron".into(), primitives::tetrahedron()),
        ("cube".into(), primitives::cube()),
        ("icosphere".into(), primitives::icosphere(2)),
        ("torus".into(), primitives::torus(2.0, 0.7, 10, 6)),
        ("grid with an isolated vertex".into(), with_isolated),
    ];
    // A grid with two holes: three boundary loops.
    let mut holes = primitives::grid(6, 6);
    let gone = [14, 15, 44, 45];
    holes.faces = holes
        .faces
        .iter()
        .enumerate()
        .filter(|(f, _)| !gone.contains(f))
        .map(|(_, face)| face)
        .collect();
    list.push(("grid with holes".into(), holes));
    list.into_iter()
        .map(|(name, p)| (name, p.mesh().unwrap()))
        .collect()
}

#[test]
fn a_split_equals_building_its_face_list_and_passes_every_check() {
    for (name, mesh) in meshes() {
        let mut coarse = mesh;
        for step in 0..3 {
            let fine = coarse.split_triangles().unwrap();
            fine.check_integrity()
                .unwrap_or_else(|e| panic!("{name}, step {step}: {e}"));
            let built = HalfedgeMesh::from_polygons(
                coarse.n_vertices() + coarse.n_edges(),
                split_faces(&coarse),
            )
            .unwrap();
            assert!(fine == built, "{name}, step {step}");
            coarse = fine;
        }
    }
}

#[test]
fn polygons_are_refused_naming_the_face() {
    let quads = primitives::cube_quads().mesh().unwrap();
    assert_eq!(
        quads.split_triangles(),
        Err(TopologyError::NotTriangle { face: 0, len: 4 })
    );
}
