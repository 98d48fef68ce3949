//! `HalfedgeMesh::from_raw_parts`: valid arrays are accepted (and give back the mesh
//! they came from), every kind of corruption is refused with a typed error naming the
//! element, and nothing panics on arbitrary arrays.

use beltrami_halfedge::primitives::{self, Primitive};
use beltrami_halfedge::{HalfedgeMesh, RawConnectivity, TopologyError};
use proptest::prelude::*;

const NONE: u32 = RawConnectivity::NONE;

fn meshes() -> Vec<(&'static str, Primitive)> {
    vec![
        ("triangle", primitives::triangle()),
        ("hexagon_fan", primitives::hexagon_fan()),
        ("grid", primitives::grid(5, 3)),
        ("tetrahedron", primitives::tetrahedron()),
        ("cube", primitives::cube()),
        ("icosphere", primitives::icosphere(2)),
        ("torus", primitives::torus(2.0, 0.5, 9, 5)),
    ]
}

/// Two triangles forming a square: 0-1-2 and 0-2-3, one interior edge.
fn quad() -> HalfedgeMesh {
    HalfedgeMesh::from_polygons(4, [[0u32, 1, 2], [0, 2, 3]]).unwrap()
}

fn integrity(raw: RawConnectivity) -> (String, &'static str) {
    match HalfedgeMesh::from_raw_parts(raw) {
        Err(TopologyError::Integrity { element, invariant }) => (element, invariant),
        other => panic!("expected an integrity error, got {other:?}"),
    }
}

#[test]
fn the_arrays_of_a_valid_mesh_are_accepted_and_give_it_back() {
    for (name, p) in meshes() {
        let mesh = p.mesh().unwrap();
        let back = HalfedgeMesh::from_raw_parts(mesh.clone().into_raw_parts()).unwrap();
        assert_eq!(back, mesh, "{name}");
        back.check_integrity().unwrap();
    }
}

#[test]
fn isolated_vertices_and_empty_meshes_are_accepted() {
    let mesh = HalfedgeMesh::from_polygons(6, [[1u32, 2, 3], [1, 3, 4]]).unwrap();
    let raw = mesh.clone().into_raw_parts();
    assert_eq!(raw.v_out[0], NONE);
    assert_eq!(raw.v_out[5], NONE);
    assert_eq!(HalfedgeMesh::from_raw_parts(raw).unwrap(), mesh);

    let empty = HalfedgeMesh::from_raw_parts(RawConnectivity::default()).unwrap();
    assert_eq!(empty.n_vertices(), 0);
    let points = RawConnectivity {
        v_out: vec![NONE; 3],
        ..RawConnectivity::default()
    };
    assert_eq!(
        HalfedgeMesh::from_raw_parts(points).unwrap().n_vertices(),
        3
    );
}

#[test]
fn any_outgoing_halfedge_of_an_interior_vertex_is_valid() {
    // The convention of `from_polygons` (the halfedge in the vertex's last face) is not
    // an invariant: any outgoing halfedge of an interior vertex will do.
    let mesh = primitives::icosphere(1).mesh().unwrap();
    let mut raw = mesh.clone().into_raw_parts();
    let v = 3;
    let other = mesh
        .halfedges_around_vertex(beltrami_halfedge::VertexId::new(v))
        .nth(2)
        .unwrap();
    raw.v_out[v as usize] = other.raw();
    let rotated = HalfedgeMesh::from_raw_parts(raw).unwrap();
    assert_ne!(rotated, mesh);
    rotated.check_integrity().unwrap();
}

#[test]
fn out_of_range_ids_are_refused_without_panicking() {
    let base = quad().into_raw_parts();
    let mut raw = base.clone();
    raw.h_to[3] = 99;
    assert_eq!(integrity(raw), ("halfedge 3".into(), "links are in range"));
    let mut raw = base.clone();
    raw.h_next[5] = 1000;
    assert_eq!(integrity(raw), ("halfedge 5".into(), "links are in range"));
    let mut raw = base.clone();
    raw.h_face[0] = 2;
    assert_eq!(integrity(raw), ("halfedge 0".into(), "links are in range"));
    let mut raw = base.clone();
    raw.f_he[1] = 10;
    assert_eq!(integrity(raw), ("face 1".into(), "links are in range"));
    let mut raw = base.clone();
    raw.v_out[2] = 10;
    assert_eq!(integrity(raw), ("vertex 2".into(), "links are in range"));
}

#[test]
fn arrays_of_the_wrong_length_are_refused() {
    let base = quad().into_raw_parts();
    let mut raw = base.clone();
    raw.h_next.pop();
    assert_eq!(
        integrity(raw),
        (
            "mesh".into(),
            "every halfedge array has one entry per halfedge"
        )
    );
    let mut raw = base.clone();
    raw.h_to.pop();
    raw.h_next.pop();
    raw.h_face.pop();
    assert_eq!(
        integrity(raw),
        ("mesh".into(), "the number of halfedges is even")
    );
}

#[test]
fn a_broken_next_cycle_is_refused() {
    let base = quad().into_raw_parts();
    // Two halfedges with the same next: `next` is no permutation.
    let mut raw = base.clone();
    raw.h_next[2] = raw.h_next[0];
    assert_eq!(
        integrity(raw),
        ("halfedge 2".into(), "no two halfedges have the same next")
    );
    // Swapping two successors keeps a permutation but breaks the faces.
    let mut raw = base.clone();
    raw.h_next.swap(0, 2);
    let (_, invariant) = integrity(raw);
    assert_eq!(invariant, "next(h) starts where h ends");
}

#[test]
fn a_wrong_twin_is_refused() {
    // Redirecting a halfedge makes it disagree with its twin and its neighbours.
    let base = quad().into_raw_parts();
    let mut raw = base.clone();
    raw.h_to[0] = raw.h_to[1];
    let (element, invariant) = integrity(raw);
    assert!(element.starts_with("halfedge"), "{element}");
    assert!(
        invariant == "next(h) starts where h ends"
            || invariant == "a halfedge joins two different vertices",
        "{invariant}"
    );
    // An edge without a face on either side.
    let mut raw = base;
    let h = (0..raw.h_face.len())
        .find(|&h| raw.h_face[h] == NONE)
        .unwrap();
    raw.h_face[h ^ 1] = NONE;
    let (_, invariant) = integrity(raw);
    assert!(
        invariant == "next(h) lies in the face of h"
            || invariant == "an edge has at least one face",
        "{invariant}"
    );
}

#[test]
fn wrong_face_links_are_refused() {
    let base = quad().into_raw_parts();
    let mut raw = base.clone();
    raw.f_he[0] = raw.f_he[1];
    assert_eq!(
        integrity(raw),
        ("face 0".into(), "the face's halfedge belongs to the face")
    );
    // A face that points at a boundary halfedge.
    let mut raw = base.clone();
    let b = (0..raw.h_face.len())
        .find(|&h| raw.h_face[h] == NONE)
        .unwrap();
    raw.f_he[1] = b as u32;
    assert_eq!(
        integrity(raw),
        ("face 1".into(), "the face's halfedge belongs to the face")
    );
}

#[test]
fn a_face_cycle_claimed_by_two_faces_is_refused() {
    // Two disjoint triangles; relabel the second as face 0 too and drop face 1's entry:
    // its halfedges name face 0 but lie off face 0's cycle.
    let mesh = HalfedgeMesh::from_polygons(6, [[0u32, 1, 2], [3, 4, 5]]).unwrap();
    let mut raw = mesh.into_raw_parts();
    for f in &mut raw.h_face {
        if *f == 1 {
            *f = 0;
        }
    }
    raw.f_he.pop();
    let (element, invariant) = integrity(raw);
    assert!(element.starts_with("halfedge"), "{element}");
    assert_eq!(invariant, "a halfedge lies on the cycle of its face");
}

#[test]
fn the_boundary_outgoing_rule_is_enforced() {
    let mut raw = quad().into_raw_parts();
    // Vertex 0 is on the boundary; point it at its interior outgoing halfedge 0 -> 1.
    raw.v_out[0] = 0;
    assert_eq!(
        integrity(raw),
        (
            "vertex 0".into(),
            "a boundary vertex's outgoing halfedge is a boundary one"
        )
    );
    // An isolated-looking vertex that has edges.
    let mut raw = quad().into_raw_parts();
    raw.v_out[1] = NONE;
    assert_eq!(
        integrity(raw),
        (
            "vertex 1".into(),
            "a vertex with edges has an outgoing halfedge"
        )
    );
    // An outgoing halfedge that starts elsewhere.
    let mut raw = quad().into_raw_parts();
    raw.v_out[1] = raw.v_out[2];
    assert_eq!(
        integrity(raw),
        (
            "vertex 1".into(),
            "the outgoing halfedge starts at the vertex"
        )
    );
}

/// Two triangles sharing only vertex 0 (a bowtie), built as two separate meshes and
/// joined by hand.
fn bowtie() -> RawConnectivity {
    let a = HalfedgeMesh::from_polygons(3, [[0u32, 1, 2]])
        .unwrap()
        .into_raw_parts();
    let nh = a.h_to.len() as u32;
    let shift_v = |v: u32| if v == 0 { 0 } else { v + 2 };
    let mut raw = a.clone();
    raw.v_out.extend([a.v_out[1] + nh, a.v_out[2] + nh]);
    raw.h_to.extend(a.h_to.iter().map(|&v| shift_v(v)));
    raw.h_next.extend(a.h_next.iter().map(|&h| h + nh));
    raw.h_face.extend(
        a.h_face
            .iter()
            .map(|&f| if f == NONE { NONE } else { f + 1 }),
    );
    raw.f_he.extend(a.f_he.iter().map(|&h| h + nh));
    raw
}

#[test]
fn a_pinched_vertex_is_refused() {
    // As built, vertex 0's second fan is not reached by circulation.
    let (element, invariant) = integrity(bowtie());
    assert_eq!(element, "vertex 0");
    assert_eq!(invariant, "circulation visits every outgoing halfedge once");

    // Joining both fans into one circulation through the boundary links passes the
    // element-wise rules but leaves vertex 0 with two boundary halfedges.
    let mut raw = bowtie();
    let nh = raw.h_to.len() / 2;
    let into_0 = |raw: &RawConnectivity, range: std::ops::Range<usize>| {
        range
            .clone()
            .find(|&h| raw.h_face[h] == NONE && raw.h_to[h] == 0)
            .unwrap()
    };
    let (ia, ib) = (into_0(&raw, 0..nh), into_0(&raw, nh..2 * nh));
    let (na, nb) = (raw.h_next[ia], raw.h_next[ib]);
    raw.h_next[ia] = nb;
    raw.h_next[ib] = na;
    assert_eq!(
        integrity(raw),
        (
            "vertex 0".into(),
            "a vertex has at most one outgoing boundary halfedge"
        )
    );
}

#[test]
fn a_face_with_a_repeated_vertex_is_refused() {
    // A quad 0-1-2-3 whose corner 3 is renamed 1: every halfedge still joins two
    // different vertices, but the face lists vertex 1 twice.
    let mesh = HalfedgeMesh::from_polygons(4, [[0u32, 1, 2, 3]]).unwrap();
    let mut raw = mesh.into_raw_parts();
    for v in &mut raw.h_to {
        if *v == 3 {
            *v = 1;
        }
    }
    raw.v_out[3] = NONE;
    let (element, invariant) = integrity(raw);
    assert_eq!(element, "face 0");
    assert_eq!(invariant, "a face lists each vertex once");
}

#[test]
fn two_edges_between_the_same_vertices_are_refused() {
    // Two closed 3-vertex "pillows" (0, 1, 2) and (0, 1, 3), cut open along 01 and glued
    // crosswise: a sphere in which every vertex has one fan, but vertices 0 and 1 are
    // joined by two edges. As a face list it is a non-manifold edge.
    let faces = [[0u32, 1, 2], [0, 2, 1], [0, 1, 3], [0, 3, 1]];
    assert!(matches!(
        HalfedgeMesh::from_polygons(4, faces),
        Err(TopologyError::NonManifoldEdge { .. })
    ));
    // Edges: 0 (face 0's 0->1, face 3's 1->0), 1 (1-2), 2 (2-0), 3 (face 2's 0->1,
    // face 1's 1->0), 4 (1-3), 5 (3-0).
    let raw = RawConnectivity {
        v_out: vec![0, 2, 4, 10],
        h_to: vec![1, 0, 2, 1, 0, 2, 1, 0, 3, 1, 0, 3],
        h_next: vec![2, 11, 4, 7, 0, 3, 8, 5, 10, 1, 6, 9],
        h_face: vec![0, 3, 0, 1, 0, 1, 2, 1, 2, 3, 2, 3],
        f_he: vec![4, 7, 10, 1],
    };
    // Every element-wise rule holds: only the duplicate edge is wrong.
    assert_eq!(
        integrity(raw),
        (
            "vertex 0".into(),
            "two vertices are joined by at most one edge"
        )
    );
}

#[test]
fn check_integrity_and_from_raw_parts_agree_on_valid_meshes() {
    for (name, p) in meshes() {
        let mesh = p.mesh().unwrap();
        mesh.check_integrity().unwrap();
        let raw = mesh.into_raw_parts();
        assert!(HalfedgeMesh::from_raw_parts(raw).is_ok(), "{name}");
    }
}

/// Which array a corruption touches.
#[derive(Clone, Copy, Debug)]
enum Array {
    VOut,
    HTo,
    HNext,
    HFace,
    FHe,
}

/// Sets entry `index` (taken modulo the array's length) of `array` to `value`; false when
/// it already has that value.
fn corrupt(
    raw: &mut RawConnectivity,
    array: Array,
    index: prop::sample::Index,
    value: u32,
) -> bool {
    let entries = match array {
        Array::VOut => &mut raw.v_out,
        Array::HTo => &mut raw.h_to,
        Array::HNext => &mut raw.h_next,
        Array::HFace => &mut raw.h_face,
        Array::FHe => &mut raw.f_he,
    };
    let slot = if entries.is_empty() {
        None
    } else {
        let i = index.index(entries.len());
        entries.get_mut(i)
    };
    match slot {
        Some(s) if *s != value => {
            *s = value;
            true
        }
        _ => false,
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Any single changed entry either gives a valid mesh again (then it passes the
    /// independent element-wise check too) or a typed error; never a panic, and the
    /// same answer twice.
    #[test]
    fn single_corruptions_are_refused_or_valid(
        which in 0usize..4,
        array in prop_oneof![
            Just(Array::VOut), Just(Array::HTo), Just(Array::HNext),
            Just(Array::HFace), Just(Array::FHe)
        ],
        index in any::<prop::sample::Index>(),
        value in prop_oneof![0u32..60, Just(NONE), Just(1000u32)],
    ) {
        let p = [
            primitives::grid(4, 3),
            primitives::tetrahedron(),
            primitives::hexagon_fan(),
            primitives::torus(2.0, 0.5, 5, 4),
        ][which].clone();
        let mut raw = p.mesh().unwrap().into_raw_parts();
        prop_assume!(corrupt(&mut raw, array, index, value));
        let first = HalfedgeMesh::from_raw_parts(raw.clone());
        let second = HalfedgeMesh::from_raw_parts(raw);
        prop_assert_eq!(&first, &second);
        match first {
            Ok(mesh) => mesh.check_integrity().unwrap(),
            Err(TopologyError::Integrity { .. }) => {}
            Err(other) => prop_assert!(false, "unexpected error {other:?}"),
        }
    }
}
