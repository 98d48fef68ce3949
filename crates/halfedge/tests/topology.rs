//! Invariants of the half-edge structure on procedural fixtures.

use std::collections::BTreeSet;

use beltrami_halfedge::primitives::{self, Primitive};
use beltrami_halfedge::{DVec3, FaceId, HalfedgeMesh, VertexId};

fn fixtures() -> Vec<(&'static str, Primitive)> {
    vec![
        ("triangle", primitives::triangle()),
        ("hexagon_fan", primitives::hexagon_fan()),
        ("grid_4x3", primitives::grid(4, 3)),
        ("tetrahedron", primitives::tetrahedron()),
        ("cube", primitives::cube()),
        ("cube_quads", primitives::cube_quads()),
        ("icosphere_2", primitives::icosphere(2)),
        ("torus", primitives::torus(2.0, 0.5, 12, 8)),
        ("annulus", annulus()),
    ]
}

/// A 3×3 grid with its centre cell removed: one outer and one inner boundary loop.
fn annulus() -> Primitive {
    let mut g = primitives::grid(3, 3);
    // Cell (1, 1) holds triangles 2 * (1 * 3 + 1) and the next one.
    g.faces = g
        .faces
        .iter()
        .enumerate()
        .filter(|(f, _)| *f != 8 && *f != 9)
        .map(|(_, face)| face)
        .collect();
    g
}

#[test]
fn every_fixture_builds_and_passes_integrity() {
    for (name, p) in fixtures() {
        let mesh = p.mesh().unwrap_or_else(|e| panic!("{name}: {e}"));
        mesh.check_integrity()
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(mesh.n_vertices(), p.positions.len(), "{name}");
        assert_eq!(mesh.n_faces(), p.faces.len(), "{name}");
        assert_eq!(mesh.to_polygons(), p.faces, "{name}: faces round-trip");
    }
}

#[test]
fn euler_characteristic_genus_and_boundary() {
    // (name, V, E, F, χ, boundary loop lengths, genus of the single component)
    type Row = (
        &'static str,
        usize,
        usize,
        usize,
        i64,
        &'static [usize],
        Option<u32>,
    );
    let expected: &[Row] = &[
        ("triangle", 3, 3, 1, 1, &[3], Some(0)),
        ("hexagon_fan", 7, 12, 6, 1, &[6], Some(0)),
        ("grid_4x3", 20, 43, 24, 1, &[14], Some(0)),
        ("tetrahedron", 4, 6, 4, 2, &[], Some(0)),
        ("cube", 8, 18, 12, 2, &[], Some(0)),
        ("cube_quads", 8, 12, 6, 2, &[], Some(0)),
        ("icosphere_2", 162, 480, 320, 2, &[], Some(0)),
        ("torus", 96, 288, 192, 0, &[], Some(1)),
        ("annulus", 16, 32, 16, 0, &[12, 4], Some(0)),
    ];
    let all = fixtures();
    for &(name, v, e, f, chi, loops, genus) in expected {
        let p = &all.iter().find(|(n, _)| *n == name).unwrap().1;
        let mesh = p.mesh().unwrap();
        assert_eq!(
            (mesh.n_vertices(), mesh.n_edges(), mesh.n_faces()),
            (v, e, f),
            "{name}"
        );
        assert_eq!(mesh.euler_characteristic(), chi, "{name}");
        let mut lengths: Vec<usize> = mesh.boundary_loops().map(|l| l.len()).collect();
        lengths.sort_unstable_by(|a, b| b.cmp(a));
        assert_eq!(lengths, loops, "{name}");
        assert_eq!(mesh.is_closed(), loops.is_empty(), "{name}");
        let comps = mesh.connected_components();
        assert_eq!(comps.count(), 1, "{name}");
        assert_eq!(comps.summaries[0].genus(), genus, "{name}");
        assert_eq!(
            mesh.genus(),
            if loops.is_empty() { genus } else { None },
            "{name}"
        );
        assert_eq!(
            mesh.n_boundary_halfedges(),
            loops.iter().sum::<usize>(),
            "{name}"
        );
    }
}

#[test]
fn boundary_vertex_flag_matches_boundary_loops() {
    for (name, p) in fixtures() {
        let mesh = p.mesh().unwrap();
        let on_loop: BTreeSet<VertexId> = mesh
            .boundary_loops()
            .flatten()
            .map(|h| mesh.to_vertex(h))
            .collect();
        for v in mesh.vertices() {
            assert_eq!(
                mesh.is_boundary_vertex(v),
                on_loop.contains(&v),
                "{name} {v}"
            );
        }
        for l in mesh.boundary_loops() {
            for w in l.windows(2) {
                assert_eq!(mesh.next(w[0]), w[1]);
                assert!(mesh.is_boundary_halfedge(w[0]));
            }
        }
    }
}

/// Neighbours and incident faces of every vertex, computed from the face list alone.
fn neighbours_from_faces(p: &Primitive) -> (Vec<BTreeSet<u32>>, Vec<BTreeSet<usize>>) {
    let n = p.positions.len();
    let mut ring = vec![BTreeSet::new(); n];
    let mut faces = vec![BTreeSet::new(); n];
    for (f, face) in p.faces.iter().enumerate() {
        for i in 0..face.len() {
            let (a, b) = (face[i], face[(i + 1) % face.len()]);
            ring[a as usize].insert(b);
            ring[b as usize].insert(a);
            faces[a as usize].insert(f);
        }
    }
    (ring, faces)
}

#[test]
fn circulators_visit_each_neighbour_once() {
    for (name, p) in fixtures() {
        let mesh = p.mesh().unwrap();
        let (ring, faces) = neighbours_from_faces(&p);
        for v in mesh.vertices() {
            let visited: Vec<u32> = mesh.vertices_around_vertex(v).map(VertexId::raw).collect();
            let set: BTreeSet<u32> = visited.iter().copied().collect();
            assert_eq!(
                set.len(),
                visited.len(),
                "{name} {v}: a neighbour visited twice"
            );
            assert_eq!(set, ring[v.index()], "{name} {v}");
            assert_eq!(mesh.valence(v), visited.len());
            let fv: Vec<usize> = mesh.faces_around_vertex(v).map(FaceId::index).collect();
            let fset: BTreeSet<usize> = fv.iter().copied().collect();
            assert_eq!(fset.len(), fv.len(), "{name} {v}: a face visited twice");
            assert_eq!(fset, faces[v.index()], "{name} {v}");
            for h in mesh.halfedges_around_vertex(v) {
                assert_eq!(mesh.from_vertex(h), v);
                assert_eq!(mesh.find_halfedge(v, mesh.to_vertex(h)), Some(h));
            }
        }
        for f in mesh.faces() {
            let vs: Vec<u32> = mesh.vertices_around_face(f).map(VertexId::raw).collect();
            assert_eq!(vs, p.faces.get(f.index()).unwrap(), "{name} {f}");
            for h in mesh.halfedges_around_face(f) {
                assert_eq!(mesh.face(h), Some(f));
            }
            let adjacent: Vec<FaceId> = mesh.faces_around_face(f).collect();
            for g in adjacent {
                assert!(mesh.faces_around_face(g).any(|x| x == f));
            }
        }
    }
}

/// Sum of the counter-clockwise turns between consecutive neighbour directions, seen
/// from `normal`; 2π exactly when the circulation is counter-clockwise and visits the
/// neighbours in angular order.
fn total_turn(centre: DVec3, normal: DVec3, neighbours: &[DVec3]) -> f64 {
    let e1 = (neighbours[0] - centre).reject_from(normal).normalize();
    let e2 = normal.cross(e1);
    let angle = |p: DVec3| {
        let d = p - centre;
        d.dot(e2).atan2(d.dot(e1))
    };
    let tau = std::f64::consts::TAU;
    let mut sum = 0.0;
    for i in 0..neighbours.len() {
        let a = angle(neighbours[i]);
        let b = angle(neighbours[(i + 1) % neighbours.len()]);
        sum += (b - a).rem_euclid(tau);
    }
    sum
}

#[test]
fn circulation_is_counter_clockwise_in_angular_order() {
    for (name, p) in fixtures() {
        if name == "triangle" {
            continue; // two neighbours: order has no meaning
        }
        let mesh = p.mesh().unwrap();
        for v in mesh.vertices() {
            let centre = p.positions[v.index()];
            let ring: Vec<DVec3> = mesh
                .vertices_around_vertex(v)
                .map(|u| p.positions[u.index()])
                .collect();
            // Outward normal: +z for planar fixtures, area-weighted fan normal otherwise.
            let mut normal = DVec3::ZERO;
            for f in mesh.faces_around_vertex(v) {
                let vs: Vec<DVec3> = mesh
                    .vertices_around_face(f)
                    .map(|u| p.positions[u.index()])
                    .collect();
                normal += (vs[1] - vs[0]).cross(vs[2] - vs[0]);
            }
            let turn = total_turn(centre, normal.normalize(), &ring);
            assert!(
                (turn - std::f64::consts::TAU).abs() < 1e-9,
                "{name} {v}: turn {turn}"
            );
        }
    }
}

#[test]
fn boundary_circulation_starts_at_the_boundary_halfedge() {
    let p = primitives::hexagon_fan();
    let mesh = p.mesh().unwrap();
    for v in mesh.vertices().skip(1) {
        let first = mesh.halfedges_around_vertex(v).next().unwrap();
        assert!(mesh.is_boundary_halfedge(first), "{v}");
        // The faces follow without a gap: every later halfedge has a face.
        assert!(
            mesh.halfedges_around_vertex(v)
                .skip(1)
                .all(|h| !mesh.is_boundary_halfedge(h))
        );
    }
    assert!(!mesh.is_boundary_vertex(VertexId::new(0)));
    assert_eq!(mesh.valence(VertexId::new(0)), 6);
}

#[test]
fn edges_are_numbered_by_first_appearance() {
    let mesh = HalfedgeMesh::from_polygons(4, [[0u32, 1, 2], [0, 2, 3]]).unwrap();
    let pairs: Vec<[u32; 2]> = mesh
        .edges()
        .map(|e| mesh.edge_vertices(e).map(VertexId::raw))
        .collect();
    assert_eq!(pairs, [[0, 1], [1, 2], [2, 0], [2, 3], [3, 0]]);
    // The face halfedge ends at the face's first vertex.
    for f in mesh.faces() {
        assert_eq!(
            mesh.to_vertex(mesh.face_halfedge(f)),
            mesh.vertices_around_face(f).next().unwrap()
        );
    }
}

#[test]
fn isolated_vertices_are_kept() {
    let mesh = HalfedgeMesh::from_polygons(5, [[0u32, 1, 2]]).unwrap();
    mesh.check_integrity().unwrap();
    let v = VertexId::new(4);
    assert!(mesh.is_isolated(v));
    assert!(mesh.is_boundary_vertex(v));
    assert_eq!(mesh.valence(v), 0);
    assert_eq!(mesh.vertices_around_vertex(v).count(), 0);
    assert_eq!(mesh.outgoing_halfedge(v), None);
    let comps = mesh.connected_components();
    assert_eq!(comps.count(), 3);
    assert_eq!(comps.summaries[1].genus(), None);
    assert_eq!(mesh.euler_characteristic(), 3);
}

#[test]
fn components_are_labelled_by_lowest_vertex() {
    // Two separate triangles, listed with the higher one first.
    let mesh = HalfedgeMesh::from_polygons(6, [[3u32, 4, 5], [0, 1, 2]]).unwrap();
    let comps = mesh.connected_components();
    assert_eq!(comps.count(), 2);
    assert_eq!(comps.vertex_component.as_slice(), &[0, 0, 0, 1, 1, 1]);
    assert_eq!(comps.face_component.as_slice(), &[1, 0]);
    assert!(comps.summaries.iter().all(|s| s.boundary_loops == 1));
    assert_eq!(mesh.genus(), None);
}

#[test]
fn empty_mesh() {
    let mesh = HalfedgeMesh::from_polygons(0, std::iter::empty::<[u32; 3]>()).unwrap();
    mesh.check_integrity().unwrap();
    assert_eq!(mesh.n_faces(), 0);
    assert!(mesh.is_closed());
    assert_eq!(mesh.boundary_loops().count(), 0);
    assert_eq!(mesh.connected_components().count(), 0);
    assert_eq!(mesh.genus(), None);
}
