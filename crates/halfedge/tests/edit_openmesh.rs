//! EditMesh against OpenMesh's TriMesh operators (`tools/openmesh-ref`, editing.cc):
//! the same sequence of flips, splits and collapses, named by vertex labels, gets the
//! same accept/refuse answer at every step and leaves the same faces; on the final mesh,
//! `is_collapse_ok` and `is_flip_ok` agree for every halfedge and edge.

use std::collections::BTreeSet;
use std::path::PathBuf;

use beltrami_halfedge::edit::VertexProperty;
use beltrami_halfedge::{EditMesh, HalfedgeId, VertexId};
use beltrami_testkit::fixtures::openmesh_inputs;

type Tri = [u32; 3];

fn reference_dir(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/openmesh")
        .join(name)
        .join("editing")
}

fn rotated(t: [u32; 3]) -> Tri {
    let k = (0..3).min_by_key(|&i| t[i]).unwrap();
    [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
}

fn labelled_faces(mesh: &EditMesh, label: VertexProperty<u32>) -> BTreeSet<Tri> {
    mesh.faces()
        .map(|f| {
            let l: Vec<u32> = mesh
                .vertices_around_face(f)
                .map(|v| *mesh.get(label, v))
                .collect();
            rotated([l[0], l[1], l[2]])
        })
        .collect()
}

struct Replay {
    mesh: EditMesh,
    label: VertexProperty<u32>,
    by_label: Vec<VertexId>,
}

impl Replay {
    fn vertex(&self, l: u32) -> VertexId {
        let v = self.by_label[l as usize];
        assert!(
            self.mesh.is_live_vertex(v),
            "label {l} is not a live vertex"
        );
        v
    }

    fn halfedge(&self, a: u32, b: u32) -> HalfedgeId {
        self.mesh
            .find_halfedge(self.vertex(a), self.vertex(b))
            .unwrap_or_else(|| panic!("no halfedge {a} -> {b}"))
    }

    fn new_label(&mut self, v: VertexId, l: u32) {
        assert_eq!(l as usize, self.by_label.len(), "labels are consecutive");
        self.by_label.push(v);
        self.mesh.set(self.label, v, l);
    }
}

fn parse(line: &str) -> (String, Vec<u32>) {
    let mut words = line.split_whitespace();
    let op = words.next().unwrap().to_owned();
    (op, words.map(|w| w.parse().unwrap()).collect())
}

fn bits(text: &str, section: &str) -> String {
    let start = text.find(section).unwrap_or_else(|| panic!("no {section}")) + section.len();
    text[start..]
        .lines()
        .skip(1)
        .take_while(|l| !l.starts_with('#'))
        .collect()
}

#[test]
fn edits_match_openmesh_on_every_fixture() {
    for (name, input) in openmesh_inputs() {
        let dir = reference_dir(name);
        let ops = std::fs::read_to_string(dir.join("ops.txt")).unwrap();
        let faces_ref = std::fs::read_to_string(dir.join("faces.txt")).unwrap();
        let queries = std::fs::read_to_string(dir.join("queries.txt")).unwrap();

        let mut mesh = EditMesh::from_mesh_data(&input).unwrap();
        let label = mesh.add_vertex_property("label", u32::MAX).unwrap();
        let by_label: Vec<VertexId> = mesh.vertices().collect();
        for &v in &by_label {
            mesh.set(label, v, v.raw());
        }
        let input_faces = labelled_faces(&mesh, label);
        let mut r = Replay {
            mesh,
            label,
            by_label,
        };
        let (mut accepted, mut refused) = (0, 0);
        let (mut added_faces, mut refused_faces) = (0, 0);
        for (step, line) in ops.lines().enumerate() {
            let (op, a) = parse(line);
            let at = format!("{name}, step {step}: {line}");
            match op.as_str() {
                "flip" => {
                    let e = r.halfedge(a[0], a[1]).edge();
                    let ok = r.mesh.is_flip_ok(e);
                    assert_eq!(ok, a[2] == 1, "{at}: {:?}", r.mesh.check_flip(e));
                    if ok {
                        r.mesh.flip_edge(e).unwrap();
                    }
                    if ok { accepted += 1 } else { refused += 1 }
                }
                "collapse" => {
                    let h = r.halfedge(a[0], a[1]);
                    let ok = r.mesh.is_collapse_ok(h);
                    assert_eq!(ok, a[2] == 1, "{at}: {:?}", r.mesh.check_collapse(h));
                    if ok {
                        assert_eq!(r.mesh.collapse_edge(h).unwrap(), r.vertex(a[1]));
                    }
                    if ok { accepted += 1 } else { refused += 1 }
                }
                "split_edge" => {
                    let e = r.halfedge(a[0], a[1]).edge();
                    let [p, q] = r.mesh.edge_vertices(e);
                    let mid = 0.5 * (r.mesh.position(p) + r.mesh.position(q));
                    let v = r.mesh.split_edge(e, mid).unwrap();
                    r.new_label(v, a[2]);
                }
                "split_face" => {
                    let h = r.halfedge(a[0], a[1]);
                    let f = r.mesh.face(h).unwrap_or_else(|| panic!("{at}: no face"));
                    assert_eq!(r.mesh.to_vertex(r.mesh.next(h)), r.vertex(a[2]), "{at}");
                    let c = r
                        .mesh
                        .vertices_around_face(f)
                        .map(|v| r.mesh.position(v))
                        .sum::<beltrami_halfedge::DVec3>()
                        / 3.0;
                    let v = r.mesh.split_face(f, c).unwrap();
                    r.new_label(v, a[3]);
                }
                "delete_face" => {
                    let f = r
                        .mesh
                        .face(r.halfedge(a[0], a[1]))
                        .unwrap_or_else(|| panic!("{at}: no face"));
                    let l: Vec<u32> = r
                        .mesh
                        .vertices_around_face(f)
                        .map(|v| *r.mesh.get(label, v))
                        .collect();
                    assert_eq!(
                        rotated([l[0], l[1], l[2]]),
                        rotated([a[0], a[1], a[2]]),
                        "{at}"
                    );
                    r.mesh.delete_face(f).unwrap();
                }
                "add_face" => {
                    let vs = [r.vertex(a[0]), r.vertex(a[1]), r.vertex(a[2])];
                    let ok = r.mesh.is_add_face_ok(&vs);
                    assert_eq!(ok, a[3] == 1, "{at}: {:?}", r.mesh.check_add_face(&vs));
                    if ok {
                        r.mesh.add_face(&vs).unwrap();
                        added_faces += 1;
                    } else {
                        refused_faces += 1;
                    }
                }
                other => panic!("{at}: unknown operation {other}"),
            }
            r.mesh
                .check_integrity()
                .unwrap_or_else(|e| panic!("{at}: {e}"));
        }
        assert!(
            accepted > 100 && refused > 20,
            "{name}: {accepted} accepted, {refused} refused"
        );

        assert!(
            added_faces > 10 && refused_faces > 5,
            "{name}: add_face {added_faces} accepted, {refused_faces} refused"
        );

        r.mesh.garbage_collection();
        r.mesh.check_integrity().unwrap();
        // Deleting and adding faces may leave pinched vertices, which only the frozen
        // mesh refuses.
        let pinched = r.mesh.vertices().any(|v| r.mesh.boundary_fans(v) > 1);
        match r.mesh.to_mesh() {
            Ok((frozen, _)) => {
                assert!(!pinched, "{name}");
                frozen.check_integrity().unwrap();
            }
            Err(e) => assert!(pinched, "{name}: {e}"),
        }

        // Faces: the difference to the input, as OpenMesh lists it.
        let final_faces = labelled_faces(&r.mesh, label);
        let mut expected = String::new();
        for t in input_faces.difference(&final_faces) {
            expected += &format!("removed {} {} {}\n", t[0], t[1], t[2]);
        }
        for t in final_faces.difference(&input_faces) {
            expected += &format!("added {} {} {}\n", t[0], t[1], t[2]);
        }
        assert!(
            expected == faces_ref,
            "{name}: the faces differ from OpenMesh's"
        );

        // Queries on the final mesh, in label order.
        let m = &r.mesh;
        let lab = |v: VertexId| *m.get(label, v);
        let mut collapse: Vec<((u32, u32), bool)> = m
            .halfedges()
            .map(|h| {
                (
                    (lab(m.from_vertex(h)), lab(m.to_vertex(h))),
                    m.is_collapse_ok(h),
                )
            })
            .collect();
        collapse.sort_unstable();
        let mut flip: Vec<((u32, u32), bool)> = m
            .edges()
            .map(|e| {
                let [x, y] = m.edge_vertices(e).map(lab);
                ((x.min(y), x.max(y)), m.is_flip_ok(e))
            })
            .collect();
        flip.sort_unstable();
        let as_bits = |v: &[((u32, u32), bool)]| -> String {
            v.iter()
                .map(|(_, ok)| if *ok { '1' } else { '0' })
                .collect()
        };
        let collapse_bits = as_bits(&collapse);
        let flip_bits = as_bits(&flip);
        let collapse_ref = bits(&queries, "# collapse_ok");
        let flip_ref = bits(&queries, "# flip_ok");
        assert_eq!(collapse_bits.len(), collapse_ref.len(), "{name}");
        for (i, (a, b)) in collapse_bits.chars().zip(collapse_ref.chars()).enumerate() {
            assert_eq!(a, b, "{name}: is_collapse_ok of {:?}", collapse[i].0);
        }
        assert_eq!(flip_bits, flip_ref, "{name}: is_flip_ok");
        assert!(
            collapse_ref.contains('0') && flip_ref.contains('0'),
            "{name}"
        );
    }
}
