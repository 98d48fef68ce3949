//! STL welding within a tolerance: a CAD export with round-off in its coordinates
//! reads closed, the merge follows its documented rule exactly (checked against a
//! brute-force implementation of the rule), and tolerances that make no sense are
//! refused.

mod common;

use std::collections::HashMap;

use beltrami_halfedge::{HalfedgeMesh, primitives};
use beltrami_io::{
    IoError, MeshData, MeshFormat, PolygonList, ReadOptions, ReadReport, Weld, read_mesh,
    read_mesh_from_with, read_mesh_with,
};
use common::Lcg;
use glam::DVec3;

/// A binary STL of `triangles` (three corners each); normals zero.
fn binary_stl(triangles: &[[[f32; 3]; 3]]) -> Vec<u8> {
    let mut bytes = vec![b' '; 80];
    bytes.extend(u32::try_from(triangles.len()).expect("count").to_le_bytes());
    for triangle in triangles {
        bytes.extend([0u8; 12]);
        for corner in triangle {
            for c in corner {
                bytes.extend(c.to_le_bytes());
            }
        }
        bytes.extend([0, 0]);
    }
    bytes
}

fn read(bytes: &[u8], weld: Weld) -> (MeshData, ReadReport) {
    let options = ReadOptions::new().weld(weld);
    match read_mesh_from_with(bytes, MeshFormat::Stl, &options) {
        Ok(read) => read,
        Err(e) => panic!("{weld:?}: {e}"),
    }
}

/// Edges (unordered vertex pairs) used by one face only: the cracks of a mesh that
/// should be closed.
fn open_edges(mesh: &MeshData) -> usize {
    let mut uses: HashMap<(u32, u32), usize> = HashMap::new();
    for face in mesh.faces.iter() {
        for (k, &a) in face.iter().enumerate() {
            let b = face[(k + 1) % face.len()];
            *uses.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    uses.values().filter(|&&n| n == 1).count()
}

/// The next `f32` above (`+1`) or below (`-1`) `x`, by its bits (`x` finite, not 0).
fn step(x: f32, direction: i32) -> f32 {
    let bits = x.to_bits();
    f32::from_bits(if (direction > 0) == (x > 0.0) {
        bits + 1
    } else {
        bits - 1
    })
}

/// The level-3 icosphere as a CAD exporter might write it: each corner of each
/// triangle computed on its own, so that about a third of them are one `f32` step
/// off, and zeros come out as `±2.7e-16` now and then.
fn cad_icosphere() -> (MeshData, Vec<u8>) {
    let sphere = primitives::icosphere(3);
    let mut rng = Lcg(2024);
    let mut triangles = Vec::new();
    for face in sphere.faces.iter() {
        let mut triangle = [[0f32; 3]; 3];
        for (corner, &v) in triangle.iter_mut().zip(face) {
            *corner = sphere.positions[v as usize].as_vec3().to_array();
            let axis = rng.below(3);
            let c = &mut corner[axis];
            match rng.below(6) {
                0 if *c != 0.0 => *c = step(*c, 1),
                1 if *c != 0.0 => *c = step(*c, -1),
                2 if *c == 0.0 => *c = 2.7e-16,
                3 if *c == 0.0 => *c = -2.7e-16,
                _ => {}
            }
        }
        triangles.push(triangle);
    }
    (sphere, binary_stl(&triangles))
}

#[test]
fn a_cad_export_with_round_off_reads_closed() {
    let (sphere, bytes) = cad_icosphere();
    let (n, f) = (sphere.positions.len(), sphere.faces.len());
    assert_eq!((n, f), (642, 1280));

    // Exact welding: the round-off splits vertices and opens cracks.
    let (cracked, exact) = read(&bytes, Weld::Exact);
    assert_eq!(exact.weld_distance, Some(0.0));
    assert_eq!((exact.welded_vertices, exact.dropped_faces.len()), (0, 0));
    assert_eq!(cracked.faces.len(), f);
    let split = cracked.positions.len() - n;
    assert!(split > 100, "only {split} split vertices");
    assert!(open_edges(&cracked) > 100);

    // The default tolerance closes every crack and keeps every triangle.
    let (mesh, report) = read(&bytes, Weld::default());
    assert_eq!((mesh.positions.len(), mesh.faces.len()), (n, f));
    assert_eq!(report.welded_vertices, split);
    assert!(report.dropped_faces.is_empty());
    let diagonal = 2.0 * 3.0_f64.sqrt(); // the unit sphere's bounding box, within f32 steps
    let distance = report.weld_distance.expect("stl is welded");
    assert!(
        (distance / (1e-6 * diagonal) - 1.0).abs() < 1e-6,
        "{distance}"
    );
    assert_eq!(open_edges(&mesh), 0);
    let built = HalfedgeMesh::from_polygons(n, mesh.faces.iter()).expect("a closed manifold");
    assert_eq!(built.boundary_loops().count(), 0);
    assert_eq!(built.n_vertices() + built.n_faces() - built.n_edges(), 2);
    // Each vertex is where one of its corners was written: within an f32 step of the
    // sphere's vertex (or ±2.7e-16 for a 0).
    for (face, original) in mesh.faces.iter().zip(sphere.faces.iter()) {
        for (&v, &o) in face.iter().zip(original) {
            let gap = mesh.positions[v as usize] - sphere.positions[o as usize];
            assert!(gap.abs().max_element() < 2e-7, "{gap}");
        }
    }
    // `read_mesh` welds with the default too.
    let dir = tempfile::tempdir().expect("temporary directory");
    let path = dir.path().join("cad.stl");
    std::fs::write(&path, &bytes).expect("write");
    assert_eq!(read_mesh(&path).expect("read"), mesh);
    let (again, again_report) = read_mesh_with(&path, &ReadOptions::default()).expect("read");
    assert_eq!((again, again_report), (mesh, report));
}

/// The rule, by brute force: in order, each vertex joins the earliest kept vertex
/// within `distance`, else it is kept; triangles that become degenerate (and were not)
/// are dropped.
fn weld_by_the_rule(exact: &MeshData, distance: f64) -> (MeshData, ReadReport) {
    let mut kept: Vec<DVec3> = Vec::new();
    let mut map = Vec::new();
    for &p in &exact.positions {
        match kept.iter().position(|&k| (k - p).length() <= distance) {
            Some(k) => map.push(k as u32),
            None => {
                map.push(kept.len() as u32);
                kept.push(p);
            }
        }
    }
    let degenerate = |f: &[u32]| f[0] == f[1] || f[1] == f[2] || f[0] == f[2];
    let mut faces = PolygonList::new();
    let mut dropped = Vec::new();
    for (t, face) in exact.faces.iter().enumerate() {
        let welded: Vec<u32> = face.iter().map(|&v| map[v as usize]).collect();
        if degenerate(&welded) && !degenerate(face) {
            dropped.push(t);
        } else {
            faces.push(&welded);
        }
    }
    let mut report = ReadReport::default();
    report.weld_distance = Some(distance);
    report.welded_vertices = exact.positions.len() - kept.len();
    report.dropped_faces = dropped;
    (
        MeshData {
            positions: kept,
            faces,
        },
        report,
    )
}

#[test]
fn the_merge_follows_its_rule_exactly() {
    // Points in clusters whose spacing is near the tolerance, so that merges, chains
    // and cell borders all occur; offsets move the clusters across cells.
    let mut rng = Lcg(99);
    for (round, distance) in [0.01, 0.003, 0.25, 1e-5].into_iter().enumerate() {
        let mut corners = Vec::new();
        for _ in 0..600 {
            let centre =
                [rng.below(6), rng.below(6), rng.below(2)].map(|k| k as f64 * 3.0 * distance);
            let jitter =
                [0, 1, 2].map(|_| (rng.below(2001) as f64 - 1000.0) / 1000.0 * 0.9 * distance);
            let offset = round as f64 * 0.37 * distance;
            corners.push([0, 1, 2].map(|k| (centre[k] + jitter[k] + offset) as f32));
        }
        let triangles: Vec<[[f32; 3]; 3]> = corners
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect();
        let bytes = binary_stl(&triangles);
        let (exact, _) = read(&bytes, Weld::Exact);
        let (welded, report) = read(&bytes, Weld::Absolute(distance));
        let (expected, expected_report) = weld_by_the_rule(&exact, distance);
        assert!(report.welded_vertices > 50, "{distance}: {report:?}");
        assert!(!report.dropped_faces.is_empty(), "{distance}");
        assert_eq!(report, expected_report, "{distance}");
        assert_eq!(welded, expected, "{distance}");
        // Relative: the same rule with the distance taken from the diagonal.
        let (relative, relative_report) = read(&bytes, Weld::Relative(1e-3));
        let distance = relative_report.weld_distance.expect("welded");
        assert_eq!(
            (relative, relative_report),
            weld_by_the_rule(&exact, distance)
        );
    }
}

#[test]
fn chains_do_not_merge_through_and_the_earliest_vertex_wins() {
    let t = 0.5_f64;
    let far = [[10.0, 0.0, 0.0], [0.0, 10.0, 0.0], [0.0, 0.0, 10.0]];
    // a, b = a + 0.6t, c = a + 1.2t along x: b joins a, c is more than t from a.
    let a = [0.0f32, 0.0, 0.0];
    let b = [0.3f32, 0.0, 0.0];
    let c = [0.6f32, 0.0, 0.0];
    // d is more than t from a, and e within t of both a and d: e joins a, the earlier.
    let d = [0.0f32, 0.55, 0.0];
    let e = [0.0f32, 0.3, 0.1];
    let triangles = [
        [a, far[0], far[1]],
        [d, far[1], far[2]],
        [b, far[2], far[0]],
        [c, far[0], far[2]],
        [e, far[1], far[0]],
    ];
    let (mesh, report) = read(&binary_stl(&triangles), Weld::Absolute(t));
    let p = |x: [f32; 3]| DVec3::from_array(x.map(f64::from));
    assert_eq!(
        mesh.positions,
        [p(a), p(far[0]), p(far[1]), p(d), p(far[2]), p(c)]
    );
    assert_eq!(
        mesh.faces,
        PolygonList::from_triangles(&[[0, 1, 2], [3, 2, 4], [0, 4, 1], [5, 1, 4], [0, 2, 1]])
    );
    assert_eq!(report.welded_vertices, 2);
}

#[test]
fn collapsed_triangles_are_dropped_and_reported() {
    let t = 1e-3;
    let slivers = [
        // Two corners within t: collapses.
        [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        [[0.0f32, 0.0, 0.0], [0.0005, 0.0, 0.0], [0.0, 1.0, 0.0]],
        // Repeated in the file itself: kept for the builder to report.
        [[1.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        [[1.0f32, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
    ];
    let bytes = binary_stl(&slivers);
    let (mesh, report) = read(&bytes, Weld::Absolute(t));
    assert_eq!(report.dropped_faces, [1]);
    assert_eq!(report.welded_vertices, 1);
    assert_eq!(
        mesh.faces,
        PolygonList::from_triangles(&[[0, 1, 2], [1, 1, 2], [1, 3, 2]])
    );
    // Exact welding drops nothing.
    let (exact, report) = read(&bytes, Weld::Exact);
    assert_eq!((exact.faces.len(), report.dropped_faces.len()), (4, 0));
}

#[test]
fn zero_tolerances_are_exact_welding() {
    let (_, bytes) = cad_icosphere();
    let exact = read(&bytes, Weld::Exact);
    assert_eq!(read(&bytes, Weld::Relative(0.0)), exact);
    assert_eq!(read(&bytes, Weld::Absolute(0.0)), exact);
    // A tolerance far below the f32 spacing of the coordinates changes nothing either,
    // even where cell numbers overflow.
    for tiny in [1e-30, 1e-300, 5e-324] {
        let (mesh, report) = read(&bytes, Weld::Absolute(tiny));
        assert_eq!(mesh, exact.0, "{tiny}");
        assert_eq!(report.welded_vertices, 0);
    }
}

#[test]
fn extreme_tolerances_and_coordinates_stay_well_defined() {
    // Everything within the tolerance: one vertex, every triangle collapsed.
    let (_, bytes) = cad_icosphere();
    let (mesh, report) = read(&bytes, Weld::Absolute(1e300));
    assert_eq!(mesh.positions.len(), 1);
    assert!(mesh.faces.is_empty());
    assert_eq!(report.dropped_faces.len(), 1280);
    // Coordinates at the ends of the f32 range.
    let big = f32::MAX;
    let triangles = [
        [[big, big, big], [-big, big, big], [big, -big, -big]],
        [
            [big, big, big],
            [step(big, -1), big, big],
            [1e-45, 0.0, -1e-45],
        ],
    ];
    let bytes = binary_stl(&triangles);
    let (mesh, report) = read(&bytes, Weld::default());
    // The diagonal is about 1.2e39: the tolerance of 1.2e33 merges the neighbours of
    // f32::MAX (one step is 2e31 there), which collapses the second triangle, and
    // nothing else.
    assert_eq!(report.welded_vertices, 1);
    assert_eq!(mesh.positions.len(), 4);
    assert!(mesh.positions.iter().all(|p| p.is_finite()));
    assert_eq!(report.dropped_faces, [1]);
}

#[test]
fn invalid_tolerances_are_refused_for_every_format() {
    let (_, stl) = cad_icosphere();
    let obj = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    for weld in [
        Weld::Relative(-1e-6),
        Weld::Absolute(-0.5),
        Weld::Relative(f64::NAN),
        Weld::Absolute(f64::INFINITY),
    ] {
        let options = ReadOptions::new().weld(weld);
        for (bytes, format) in [(&stl[..], MeshFormat::Stl), (&obj[..], MeshFormat::Obj)] {
            let e = read_mesh_from_with(bytes, format, &options).expect_err("invalid tolerance");
            assert!(matches!(e, IoError::WeldTolerance { .. }), "{e}");
        }
    }
    let e = read_mesh_from_with(
        &stl[..],
        MeshFormat::Stl,
        &ReadOptions::new().weld(Weld::Relative(-1e-6)),
    )
    .expect_err("negative");
    assert_eq!(
        e.to_string(),
        "invalid weld tolerance -0.000001: expected a finite number, 0 or more"
    );
    // Formats with shared vertices are not welded.
    let (_, report) =
        read_mesh_from_with(&obj[..], MeshFormat::Obj, &ReadOptions::default()).expect("obj");
    assert_eq!(report, ReadReport::default());
}
