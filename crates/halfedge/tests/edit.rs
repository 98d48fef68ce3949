//! EditMesh operators on small hand-checked configurations: what each operator does,
//! what it refuses and why, and how properties follow.

use beltrami_halfedge::edit::EditError;
use beltrami_halfedge::primitives::{self, Primitive};
use beltrami_halfedge::{DVec3, EdgeId, EditMesh, FaceId, HalfedgeId, HalfedgeMesh, VertexId};

fn edit(p: &Primitive) -> EditMesh {
    EditMesh::from_mesh(&p.mesh().unwrap(), &p.positions).unwrap()
}

fn v(i: u32) -> VertexId {
    VertexId::new(i)
}

fn he(mesh: &EditMesh, a: u32, b: u32) -> HalfedgeId {
    mesh.find_halfedge(v(a), v(b))
        .unwrap_or_else(|| panic!("no halfedge {a} -> {b}"))
}

/// Faces as vertex-index cycles rotated to start at their smallest index, sorted.
fn face_set(mesh: &EditMesh) -> Vec<Vec<u32>> {
    let mut faces: Vec<Vec<u32>> = mesh
        .face_vertex_lists()
        .into_iter()
        .map(|f| {
            let raw: Vec<u32> = f.iter().map(|v| v.raw()).collect();
            let k = (0..raw.len()).min_by_key(|&i| raw[i]).unwrap();
            raw[k..].iter().chain(&raw[..k]).copied().collect()
        })
        .collect();
    faces.sort();
    faces
}

fn counts(mesh: &EditMesh) -> (usize, usize, usize) {
    (mesh.n_vertices(), mesh.n_edges(), mesh.n_faces())
}

/// The two-triangle square `(0, 1, 2), (0, 2, 3)`.
fn square() -> Primitive {
    let mut p = primitives::grid(1, 1);
    p.positions = vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
    p.faces = [[0u32, 1, 2], [0, 2, 3]].iter().map(|f| &f[..]).collect();
    p
}

#[test]
fn round_trip_without_edits_is_exact() {
    for p in [
        primitives::icosphere(2),
        primitives::torus(2.0, 0.5, 12, 8),
        primitives::grid(4, 3),
        primitives::cube_quads(),
    ] {
        let mesh = p.mesh().unwrap();
        let e = EditMesh::from_mesh(&mesh, &p.positions).unwrap();
        e.check_integrity().unwrap();
        let (back, positions) = e.to_mesh().unwrap();
        assert_eq!(back, mesh);
        assert_eq!(positions, p.positions);
        assert_eq!(e.to_mesh_data().faces, p.faces);
    }
}

#[test]
fn from_mesh_checks_the_position_count() {
    let p = primitives::triangle();
    let err = EditMesh::from_mesh(&p.mesh().unwrap(), &p.positions[..2]).unwrap_err();
    assert_eq!(
        err.to_string(),
        "2 positions were given for a mesh of 3 vertices"
    );
}

#[test]
fn flip_exchanges_the_diagonal() {
    let mut m = edit(&square());
    let e = he(&m, 0, 2).edge();
    m.flip_edge(e).unwrap();
    m.check_integrity().unwrap();
    assert_eq!(face_set(&m), [vec![0, 1, 3], vec![1, 2, 3]]);
    assert!(m.find_halfedge(v(0), v(2)).is_none());
    assert!(m.find_halfedge(v(1), v(3)).is_some());
    // Flipping back restores the faces.
    m.flip_edge(e).unwrap();
    assert_eq!(face_set(&m), [vec![0, 1, 2], vec![0, 2, 3]]);
}

#[test]
fn flip_refusals_name_the_edge() {
    let mut m = edit(&square());
    let boundary = he(&m, 0, 1).edge();
    assert_eq!(
        m.flip_edge(boundary),
        Err(EditError::FlipBoundaryEdge { edge: boundary })
    );
    // On a tetrahedron every flip would duplicate an edge.
    let mut t = edit(&primitives::tetrahedron());
    for e in t.edges().collect::<Vec<_>>() {
        assert!(matches!(
            t.flip_edge(e),
            Err(EditError::FlipEdgeExists { edge, .. }) if edge == e
        ));
    }
    let gone = EdgeId::new(99);
    assert_eq!(m.flip_edge(gone), Err(EditError::NoSuchEdge { edge: gone }));
    let mut q = edit(&primitives::cube_quads());
    assert!(matches!(
        q.flip_edge(EdgeId::new(0)),
        Err(EditError::NotTriangle { len: 4, .. })
    ));
}

#[test]
fn split_edge_interior_and_boundary() {
    let mut m = edit(&square());
    let e = he(&m, 0, 2).edge();
    let mid = DVec3::new(0.5, 0.5, 0.0);
    let c = m.split_edge(e, mid).unwrap();
    m.check_integrity().unwrap();
    assert_eq!(counts(&m), (5, 8, 4));
    assert_eq!(m.position(c), mid);
    assert_eq!(m.valence(c), 4);
    assert!(!m.is_boundary_vertex(c));
    assert_eq!(
        face_set(&m),
        [vec![0, 1, 4], vec![0, 4, 3], vec![1, 2, 4], vec![2, 3, 4]]
    );

    let b = he(&m, 0, 1).edge();
    let d = m.split_edge(b, DVec3::new(0.5, 0.0, 0.0)).unwrap();
    m.check_integrity().unwrap();
    assert_eq!(counts(&m), (6, 10, 5));
    assert!(m.is_boundary_vertex(d));
    assert_eq!(m.valence(d), 3);
    assert_eq!(m.euler_characteristic(), 1);
}

#[test]
fn split_face_makes_a_fan() {
    let mut m = edit(&primitives::triangle());
    let c = m
        .split_face(FaceId::new(0), DVec3::new(0.3, 0.3, 0.0))
        .unwrap();
    m.check_integrity().unwrap();
    assert_eq!(counts(&m), (4, 6, 3));
    assert_eq!(m.valence(c), 3);
    assert_eq!(face_set(&m), [vec![0, 1, 3], vec![0, 3, 2], vec![1, 2, 3]]);
    // A quad becomes four triangles.
    let mut q = edit(&primitives::cube_quads());
    q.split_face(FaceId::new(0), DVec3::new(0.5, 0.5, 0.0))
        .unwrap();
    q.check_integrity().unwrap();
    assert_eq!(counts(&q), (9, 16, 9));
}

#[test]
fn collapse_merges_and_removes_two_triangles() {
    let mut m = edit(&primitives::icosphere(1));
    let before = counts(&m);
    let h = m.halfedges().next().unwrap();
    let (from, to) = (m.from_vertex(h), m.to_vertex(h));
    let kept = m.collapse_edge(h).unwrap();
    m.check_integrity().unwrap();
    assert_eq!(kept, to);
    assert!(!m.is_live_vertex(from));
    assert_eq!(counts(&m), (before.0 - 1, before.1 - 3, before.2 - 2));
    assert!(m.has_garbage());
    let maps = m.garbage_collection();
    assert!(!m.has_garbage());
    assert_eq!(maps.vertices[from], None);
    m.check_integrity().unwrap();
    let (frozen, _) = m.to_mesh().unwrap();
    assert_eq!(frozen.euler_characteristic(), 2);
}

#[test]
fn collapse_refusals_follow_openmesh() {
    // Tetrahedron: the end points of every edge share exactly the two opposite
    // vertices, so the link condition holds and OpenMesh accepts; the result is two
    // triangles on the same three vertices, a valid closed mesh.
    let t = edit(&primitives::tetrahedron());
    for h in t.halfedges() {
        assert!(t.is_collapse_ok(h), "{h:?}");
        // ...which decimation and remeshing refuse, to keep the solid.
        assert!(t.collapse_flattens_tetrahedron(h), "{h:?}");
    }
    let ico = edit(&primitives::icosphere(0));
    assert!(
        ico.halfedges()
            .all(|h| !ico.collapse_flattens_tetrahedron(h))
    );
    // Once an icosahedron is collapsed down to a tetrahedron, its edges flatten it.
    let mut solid = edit(&primitives::icosphere(0));
    while solid.n_vertices() > 4 {
        let h = solid
            .halfedges()
            .find(|&h| solid.is_collapse_ok(h) && !solid.collapse_flattens_tetrahedron(h))
            .unwrap();
        solid.collapse_edge(h).unwrap();
        solid.check_integrity().unwrap();
    }
    assert!(
        solid
            .halfedges()
            .all(|h| solid.collapse_flattens_tetrahedron(h))
    );
    let h = solid.halfedges().next().unwrap();
    solid.collapse_edge(h).unwrap();
    assert!(
        solid
            .halfedges()
            .all(|h| !solid.collapse_flattens_tetrahedron(h))
    );

    // A lone triangle: both other edges of the face are boundary edges.
    let tri = edit(&primitives::triangle());
    let h = he(&tri, 0, 1);
    assert_eq!(
        tri.check_collapse(h),
        Err(EditError::CollapseDanglingTriangle {
            halfedge: h,
            vertex: v(2)
        })
    );

    // The square's diagonal: both its triangles have their other two edges on the
    // boundary.
    let sq = edit(&square());
    let d = he(&sq, 0, 2);
    assert_eq!(
        sq.check_collapse(d),
        Err(EditError::CollapseDanglingTriangle {
            halfedge: d,
            vertex: v(3)
        })
    );

    // A 3 × 1 strip: the middle diagonal 1 -> 6 joins two boundary vertices through
    // the interior.
    let strip = edit(&primitives::grid(3, 1));
    let d = he(&strip, 1, 6);
    assert_eq!(
        strip.check_collapse(d),
        Err(EditError::CollapseBoundaryPinch { halfedge: d })
    );
    assert!(strip.is_collapse_ok(he(&strip, 1, 2)));

    // A valence-3 vertex inside a triangle: collapsing one of the triangle's edges
    // breaks the link condition (the centre is a common neighbour, not opposite).
    let mut fan = edit(&primitives::icosphere(0));
    let f = FaceId::new(0);
    let corners: Vec<VertexId> = fan.vertices_around_face(f).collect();
    let centre = fan.split_face(f, DVec3::ZERO).unwrap();
    let outer = fan.find_halfedge(corners[0], corners[1]).unwrap();
    assert!(!fan.is_boundary_halfedge(outer));
    let err = fan.check_collapse(outer).unwrap_err();
    assert!(
        matches!(err, EditError::CollapseLinkCondition { vertex, .. } if vertex == corners[2] || vertex == centre),
        "{err}"
    );
}

#[test]
fn refused_operations_change_nothing() {
    let mut m = edit(&square());
    let before = format!("{m:?}");
    let d = he(&m, 0, 2);
    assert!(m.collapse_edge(d).is_err());
    assert!(m.flip_edge(he(&m, 0, 1).edge()).is_err());
    assert!(m.add_face(&[v(0), v(1), v(2)]).is_err());
    assert_eq!(format!("{m:?}"), before);
}

#[test]
fn add_face_builds_and_rejects_like_openmesh() {
    let mut m = EditMesh::new();
    let vs: Vec<VertexId> = (0..6)
        .map(|i| m.add_vertex(DVec3::new(f64::from(i), 0.0, 0.0)))
        .collect();
    // A fan around 0: faces added out of order, so the middle one re-links.
    m.add_face(&[vs[0], vs[1], vs[2]]).unwrap();
    m.add_face(&[vs[0], vs[3], vs[4]]).unwrap();
    m.check_integrity().unwrap();
    assert_eq!(m.boundary_fans(vs[0]), 2);
    assert!(matches!(
        m.to_mesh(),
        Err(beltrami_halfedge::TopologyError::NonManifoldVertex { fans: 2, .. })
    ));
    m.add_face(&[vs[0], vs[2], vs[3]]).unwrap();
    m.check_integrity().unwrap();
    assert_eq!(m.boundary_fans(vs[0]), 1);
    m.to_mesh().unwrap();

    // Wrong orientation: the halfedge 0 -> 1 already has a face.
    assert_eq!(
        m.add_face(&[vs[0], vs[1], vs[5]]),
        Err(EditError::ComplexEdge {
            from: vs[0],
            to: vs[1]
        })
    );
    // Close the fan: 0 becomes interior, and a further face at 0 is a complex vertex.
    m.add_face(&[vs[0], vs[4], vs[5]]).unwrap();
    m.add_face(&[vs[0], vs[5], vs[1]]).unwrap();
    m.check_integrity().unwrap();
    assert!(!m.is_boundary_vertex(vs[0]));
    assert_eq!(
        m.add_face(&[vs[0], vs[2], vs[1]]),
        Err(EditError::ComplexVertex { vertex: vs[0] })
    );
    assert_eq!(
        m.add_face(&[vs[1], vs[1], vs[2]]),
        Err(EditError::RepeatedVertex { vertex: vs[1] })
    );
    assert_eq!(
        m.add_face(&[vs[1], vs[2]]),
        Err(EditError::FaceTooSmall { len: 2 })
    );
    assert_eq!(m.euler_characteristic(), 1);
}

#[test]
fn add_face_relinks_fans_at_a_vertex() {
    // Three fans at vertex 0, then a face joining the first two through two existing
    // boundary halfedges (3 -> 0 and 0 -> 2).
    let mut m = EditMesh::new();
    let vs: Vec<VertexId> = (0..7).map(|_| m.add_vertex(DVec3::ZERO)).collect();
    m.add_face(&[vs[0], vs[1], vs[2]]).unwrap();
    m.add_face(&[vs[0], vs[3], vs[4]]).unwrap();
    m.add_face(&[vs[0], vs[5], vs[6]]).unwrap();
    m.check_integrity().unwrap();
    assert_eq!(m.boundary_fans(vs[0]), 3);
    m.add_face(&[vs[3], vs[0], vs[2]]).unwrap();
    m.check_integrity().unwrap();
    assert_eq!(m.boundary_fans(vs[0]), 2);
    assert_eq!((m.n_edges(), m.n_faces()), (10, 4));
}

#[test]
fn delete_face_and_vertex_free_what_they_leave() {
    let mut m = edit(&square());
    m.delete_face(FaceId::new(0)).unwrap();
    m.check_integrity().unwrap();
    // Edges 0-1 and 1-2 lose their only face; vertex 1 its only edges.
    assert_eq!(counts(&m), (3, 3, 1));
    assert!(!m.is_live_vertex(v(1)));
    assert_eq!(
        m.delete_face(FaceId::new(0)),
        Err(EditError::NoSuchFace {
            face: FaceId::new(0)
        })
    );
    let mut s = edit(&primitives::icosphere(1));
    let top = v(0);
    let valence = s.valence(top);
    s.delete_vertex(top).unwrap();
    s.check_integrity().unwrap();
    assert_eq!(s.n_faces(), 80 - valence);
    s.garbage_collection();
    let (frozen, _) = s.to_mesh().unwrap();
    assert_eq!(frozen.boundary_loops().count(), 1);
    assert_eq!(frozen.euler_characteristic(), 1);
}

#[test]
fn properties_follow_the_documented_rules() {
    let mut m = edit(&square());
    let x = m.add_vertex_property("x", f64::NAN).unwrap();
    let label = m.add_vertex_property("label", u32::MAX).unwrap();
    let feature = m.add_edge_property("feature", false).unwrap();
    let region = m.add_face_property("region", 0u8).unwrap();
    let corner = m.add_halfedge_property("corner", -1i32).unwrap();
    assert_eq!(
        m.add_vertex_property("x", 0.0),
        Err(EditError::PropertyExists {
            kind: "vertex",
            name: "x".into()
        })
    );
    for vv in m.vertices().collect::<Vec<_>>() {
        let p = m.position(vv).x;
        m.set(x, vv, p);
        m.set(label, vv, vv.raw());
    }
    for f in m.faces().collect::<Vec<_>>() {
        m.set(region, f, 10 + f.raw() as u8);
    }
    for h in m.halfedges().collect::<Vec<_>>() {
        m.set(corner, h, h.raw() as i32);
    }
    let diagonal = he(&m, 0, 2);
    m.set(feature, diagonal.edge(), true);

    // Split the diagonal at a quarter from vertex 0: x is interpolated, the label is not.
    let c = m
        .split_edge(diagonal.edge(), DVec3::new(0.25, 0.25, 0.0))
        .unwrap();
    assert_eq!(*m.get(x, c), 0.25);
    assert_eq!(*m.get(label, c), u32::MAX);
    // Both halves of the diagonal are features; the new spokes are not.
    assert!(*m.get(feature, m.find_halfedge(v(0), c).unwrap().edge()));
    assert!(*m.get(feature, m.find_halfedge(v(2), c).unwrap().edge()));
    assert!(!*m.get(feature, m.find_halfedge(v(1), c).unwrap().edge()));
    // Each new triangle carries the region of the one it was cut from.
    let mut regions: Vec<u8> = m.faces().map(|f| *m.get(region, f)).collect();
    regions.sort_unstable();
    assert_eq!(regions, [10, 10, 11, 11]);
    // Halves of a split halfedge copy their parent's corner value.
    let h02 = m.find_halfedge(c, v(2)).unwrap();
    let h0c = m.find_halfedge(v(0), c).unwrap();
    assert_eq!(*m.get(corner, h02), diagonal.raw() as i32);
    assert_eq!(*m.get(corner, h0c), diagonal.raw() as i32);

    // Collapse 1 -> c? Refused (boundary pinch); collapse c -> 1 is interior-to-boundary.
    let hc1 = m.find_halfedge(c, v(1)).unwrap();
    let kept = m.collapse_edge(hc1).unwrap();
    assert_eq!(kept, v(1));
    assert_eq!(*m.get(label, kept), 1);
    assert_eq!(*m.get(x, kept), 1.0);

    // Garbage collection remaps every property.
    let before: Vec<(u32, f64)> = m
        .vertices()
        .map(|w| (*m.get(label, w), *m.get(x, w)))
        .collect();
    let maps = m.garbage_collection();
    let after: Vec<(u32, f64)> = m
        .vertices()
        .map(|w| (*m.get(label, w), *m.get(x, w)))
        .collect();
    assert_eq!(before, after);
    assert_eq!(m.values(label).len(), m.n_vertices());
    assert_eq!(maps.vertices.iter().filter(|(_, n)| n.is_none()).count(), 1);
    m.check_integrity().unwrap();
    let (frozen, positions) = m.to_mesh().unwrap();
    assert_eq!(positions.len(), frozen.n_vertices());
    for (i, p) in positions.iter().enumerate() {
        assert_eq!(m.values(x)[i], p.x);
    }
    // Removing a property invalidates its handle.
    assert!(m.remove_property(label));
    assert!(!m.has_property(label));
    assert!(m.find_property::<VertexId, u32>("label").is_none());
}

#[test]
fn split_face_blends_by_barycentric_coordinates() {
    let mut m = edit(&primitives::triangle());
    let s = m.add_vertex_property("s", 0.0_f64).unwrap();
    for (i, val) in [1.0, 2.0, 4.0].into_iter().enumerate() {
        m.set(s, v(i as u32), val);
    }
    let corners: Vec<DVec3> = (0..3).map(|i| m.position(v(i))).collect();
    let p = corners[0] * 0.5 + corners[1] * 0.25 + corners[2] * 0.25;
    let c = m.split_face(FaceId::new(0), p).unwrap();
    let expect: f64 = 0.5 * 1.0 + 0.25 * 2.0 + 0.25 * 4.0;
    assert!((m.get(s, c) - expect).abs() < 1e-14, "{}", m.get(s, c));
}

#[test]
fn a_frozen_mesh_survives_edit_and_back() {
    let p = primitives::torus(2.0, 0.5, 12, 8);
    let mesh: HalfedgeMesh = p.mesh().unwrap();
    let mut m = EditMesh::from_mesh(&mesh, &p.positions).unwrap();
    for e in m.edges().step_by(3).collect::<Vec<_>>() {
        if m.is_flip_ok(e) {
            m.flip_edge(e).unwrap();
        }
    }
    let (frozen, _) = m.into_mesh().unwrap();
    frozen.check_integrity().unwrap();
    assert_eq!(frozen.euler_characteristic(), 0);
    let rebuilt =
        HalfedgeMesh::from_polygons(frozen.n_vertices(), frozen.to_polygons().iter()).unwrap();
    assert_eq!(rebuilt.n_edges(), frozen.n_edges());
}

#[test]
#[should_panic(expected = "the property was removed from this mesh (or belongs to another mesh)")]
fn a_handle_of_another_mesh_is_caught() {
    let mut a = edit(&square());
    let mut b = edit(&square());
    let pa = a.add_vertex_property("s", 0.0_f64).unwrap();
    let _pb = b.add_vertex_property("s", 0.0_f64).unwrap();
    let _ = b.get(pa, v(0));
}

#[test]
fn a_clone_shares_property_handles() {
    let mut a = edit(&square());
    let p = a.add_face_property("region", 7u32).unwrap();
    let mut b = a.clone();
    b.set(p, FaceId::new(1), 9);
    assert_eq!(
        (*a.get(p, FaceId::new(1)), *b.get(p, FaceId::new(1))),
        (7, 9)
    );
}

#[test]
fn error_messages_name_the_element() {
    let sq = edit(&square());
    let d = he(&sq, 0, 2);
    assert_eq!(
        sq.check_collapse(d).unwrap_err().to_string(),
        "collapsing halfedge 2 would leave a dangling edge: the triangle with vertex 3 has both other edges on the boundary"
            .replace("halfedge 2", &d.to_string())
    );
    let b = he(&sq, 0, 1).edge();
    assert_eq!(
        sq.check_flip(b).unwrap_err().to_string(),
        format!("{b} is a boundary edge; only an interior edge can be flipped")
    );
    let mut m = edit(&primitives::icosphere(0));
    let interior = v(0);
    let err = m.add_face(&[interior, v(1), v(7)]).unwrap_err();
    assert_eq!(
        err.to_string(),
        "complex vertex: vertex 0 is interior (its fan is closed), a new face cannot touch it"
    );
}

fn opposite_cot(mesh: &EditMesh, h: HalfedgeId) -> f64 {
    let Some(o) = mesh.opposite_vertex(h) else {
        return 0.0;
    };
    let u = mesh.position(mesh.from_vertex(h)) - mesh.position(o);
    let w = mesh.position(mesh.to_vertex(h)) - mesh.position(o);
    u.dot(w) / u.cross(w).length()
}

fn negative_edges(mesh: &EditMesh) -> usize {
    mesh.edges()
        .filter(|&e| {
            let [h, t] = e.halfedges();
            !mesh.is_boundary_edge(e) && opposite_cot(mesh, h) + opposite_cot(mesh, t) < -1e-12
        })
        .count()
}

#[test]
fn lawson_flips_make_a_planar_mesh_delaunay() {
    // A jittered planar grid: many edges have a negative cotangent weight.
    let mut p = primitives::grid(12, 9);
    let mut rng = beltrami_testkit::SplitMix64::new(11);
    for q in &mut p.positions {
        q.x += 0.45 * rng.next_symmetric() / 12.0;
        q.y += 0.45 * rng.next_symmetric() / 9.0;
    }
    let mut m = edit(&p);
    assert!(negative_edges(&m) > 10, "{}", negative_edges(&m));
    let mut flipped = true;
    let mut rounds = 0;
    while flipped {
        flipped = false;
        rounds += 1;
        assert!(rounds < 1000, "Lawson's algorithm terminates in the plane");
        for e in m.edges().collect::<Vec<_>>() {
            let [h, t] = e.halfedges();
            if !m.is_boundary_edge(e)
                && opposite_cot(&m, h) + opposite_cot(&m, t) < -1e-12
                && m.is_flip_ok(e)
            {
                m.flip_edge(e).unwrap();
                flipped = true;
            }
        }
    }
    m.check_integrity().unwrap();
    assert_eq!(negative_edges(&m), 0);
    assert_eq!(m.n_vertices(), p.positions.len());
    let (frozen, _) = m.to_mesh().unwrap();
    assert_eq!(frozen.euler_characteristic(), 1);
}
