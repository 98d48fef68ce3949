//! `repair`: each defect on a small fixture, exact reports, and random soups whose
//! repair must always build.

use beltrami_halfedge::{
    DVec3, HalfedgeMesh, PolygonList, RepairOptions, RepairReport, Repaired, TopologyError,
    primitives, repair,
};

fn run(positions: &[DVec3], faces: &PolygonList) -> Repaired {
    let repaired = repair(positions, faces, &RepairOptions::default()).expect("repairable");
    check(positions, faces, &repaired);
    repaired
}

fn tris(faces: &[[u32; 3]]) -> PolygonList {
    PolygonList::from_triangles(faces)
}

fn polys(faces: &[&[u32]]) -> PolygonList {
    faces.iter().copied().collect()
}

/// The faces of a tetrahedron `a, b, c, d` with `det(b − a, c − a, d − a) > 0`,
/// outward.
fn tet(a: u32, b: u32, c: u32, d: u32) -> [[u32; 3]; 4] {
    [[a, c, b], [a, b, d], [b, c, d], [a, d, c]]
}

/// Every output vertex is a kept input vertex or a copy; the input vertex it stands for.
fn output_sources(repaired: &Repaired) -> Vec<u32> {
    let report = &repaired.report;
    let mut source = vec![u32::MAX; repaired.positions.len()];
    for (v, o) in report.vertex_map.iter().enumerate() {
        if let Some(o) = *o {
            let s = &mut source[o as usize];
            // A merged vertex maps to its target's output vertex: keep the target.
            *s = (*s).min(v as u32);
        }
    }
    for &(v, copy) in &report.split_vertices {
        assert_eq!(
            source[copy as usize],
            u32::MAX,
            "copy {copy} is also a kept vertex"
        );
        source[copy as usize] = v;
    }
    assert!(
        source.iter().all(|&s| s != u32::MAX),
        "every output vertex has a source"
    );
    source
}

/// The input face as `repair` keeps it: through the merge, without corners repeating
/// the previous one; `None` when degenerate.
fn cleaned(face: &[u32], target: &[u32]) -> Option<Vec<u32>> {
    let mut out: Vec<u32> = Vec::new();
    for &v in face {
        let t = target[v as usize];
        if out.last() != Some(&t) {
            out.push(t);
        }
    }
    while out.len() > 1 && out.first() == out.last() {
        out.pop();
    }
    let mut sorted = out.clone();
    sorted.sort_unstable();
    sorted.dedup();
    (out.len() >= 3 && sorted.len() == out.len()).then_some(out)
}

/// The smallest of all rotations of the face and of its reverse.
fn cycle_key(face: &[u32]) -> Vec<u32> {
    let mut best: Option<Vec<u32>> = None;
    let mut reversed = face.to_vec();
    reversed.reverse();
    for f in [face.to_vec(), reversed] {
        for r in 0..f.len() {
            let mut g = f.clone();
            g.rotate_left(r);
            if best.as_ref().is_none_or(|b| g < *b) {
                best = Some(g);
            }
        }
    }
    best.unwrap_or_default()
}

/// Every promise of `repair`, checked independently of its implementation.
fn check(positions: &[DVec3], faces: &PolygonList, repaired: &Repaired) {
    let n = positions.len();
    let report = &repaired.report;
    let mesh = repaired.mesh().expect("the repaired faces build");
    mesh.check_integrity().expect("integrity");
    assert_eq!(mesh.n_vertices(), repaired.positions.len());

    // Faces: kept + degenerate + duplicates = input, each once.
    assert_eq!(report.face_origin.len(), repaired.faces.len());
    assert_eq!(
        repaired.faces.len()
            + report.dropped_degenerate_faces.len()
            + report.dropped_duplicate_faces.len(),
        faces.len()
    );
    let mut seen = vec![0u8; faces.len()];
    for &f in report
        .face_origin
        .iter()
        .chain(&report.dropped_degenerate_faces)
        .chain(report.dropped_duplicate_faces.iter().map(|(f, _)| f))
    {
        seen[f] += 1;
    }
    assert!(
        seen.iter().all(|&s| s == 1),
        "each input face accounted once"
    );
    assert!(report.face_origin.windows(2).all(|w| w[0] < w[1]));

    // Merging: targets are earlier kept vertices within the distance.
    let mut target: Vec<u32> = (0..n as u32).collect();
    for &(v, t) in &report.merged_vertices {
        assert!(t < v);
        target[v as usize] = t;
    }
    for &(_, t) in &report.merged_vertices {
        assert_eq!(target[t as usize], t, "a target is not merged itself");
    }

    // Vertices: positions are bit-identical to their source's (merge target's).
    assert_eq!(report.vertex_map.len(), n);
    let source = output_sources(repaired);
    for (o, &s) in source.iter().enumerate() {
        assert_eq!(
            target[s as usize], s,
            "an output vertex stands for a kept vertex"
        );
        assert_eq!(
            repaired.positions[o].to_array().map(f64::to_bits),
            positions[s as usize].to_array().map(f64::to_bits)
        );
    }
    for (v, o) in report.vertex_map.iter().enumerate() {
        match o {
            Some(o) => assert_eq!(source[*o as usize], target[v]),
            None => assert!(report.removed_vertices.contains(&(v as u32))),
        }
    }
    assert_eq!(
        report.removed_vertices.len(),
        report.vertex_map.iter().filter(|o| o.is_none()).count()
    );
    // Kept vertices first, in input order, then the copies.
    let kept: Vec<u32> = (0..n)
        .filter_map(|v| {
            (target[v] as usize == v)
                .then_some(report.vertex_map[v])
                .flatten()
        })
        .collect();
    assert_eq!(kept, (0..kept.len() as u32).collect::<Vec<_>>());
    assert_eq!(
        kept.len() + report.split_vertices.len(),
        repaired.positions.len()
    );

    // Each output face is its input face, cleaned, perhaps flipped (first vertex kept).
    let mut keys = std::collections::HashSet::new();
    for (o, face) in repaired.faces.iter().enumerate() {
        let f = report.face_origin[o];
        let mut expected = cleaned(faces.get(f).expect("in range"), &target)
            .expect("a kept face is not degenerate");
        if report.flipped_faces.contains(&f) {
            expected[1..].reverse();
        }
        let back: Vec<u32> = face.iter().map(|&v| source[v as usize]).collect();
        assert_eq!(back, expected, "output face {o} (input face {f})");
        assert!(keys.insert(cycle_key(&back)), "no duplicates remain");
    }
    for &f in &report.dropped_degenerate_faces {
        assert!(cleaned(faces.get(f).expect("in range"), &target).is_none());
    }
    for &(f, g) in &report.dropped_duplicate_faces {
        assert!(g < f && report.face_origin.contains(&g));
        let key =
            |f: usize| cleaned(faces.get(f).expect("in range"), &target).map(|c| cycle_key(&c));
        assert_eq!(key(f), key(g));
    }
    // Cut edges: exactly the edges of more than two kept faces.
    let mut uses = std::collections::BTreeMap::new();
    for &f in &report.face_origin {
        let face = cleaned(faces.get(f).expect("in range"), &target).expect("kept");
        for (i, &a) in face.iter().enumerate() {
            let b = face[(i + 1) % face.len()];
            *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    let shared: Vec<(u32, u32)> = uses
        .into_iter()
        .filter(|&(_, c)| c > 2)
        .map(|(e, _)| e)
        .collect();
    assert_eq!(report.cut_edges, shared);
    assert_eq!(report.is_empty(), report.to_string() == "no repair needed");
}

#[test]
fn a_duplicate_face_of_a_tetrahedron_is_dropped() {
    let t = primitives::tetrahedron();
    for copy in [[0, 1, 2], [1, 2, 0], [2, 1, 0], [0, 2, 1]] {
        let mut faces = t.faces.clone();
        faces.push(&copy);
        let repaired = run(&t.positions, &faces);
        let report = &repaired.report;
        assert_eq!(report.dropped_duplicate_faces, [(4, 0)], "copy {copy:?}");
        assert_eq!(report.to_string(), "1 duplicate face dropped");
        assert_eq!(repaired.positions, t.positions);
        assert_eq!(repaired.faces, t.faces);
        let mesh = repaired.mesh().unwrap();
        assert!(mesh.is_closed());
        assert_eq!(
            (mesh.n_vertices(), mesh.connected_components().count()),
            (4, 1)
        );
    }
    // The copy listed first: the copy is kept and the original dropped.
    let mut faces = tris(&[[2, 0, 1]]);
    for f in t.faces.iter() {
        faces.push(f);
    }
    let repaired = run(&t.positions, &faces);
    assert_eq!(repaired.report.dropped_duplicate_faces, [(1, 0)]);
    assert!(repaired.mesh().unwrap().is_closed());
}

#[test]
fn two_tetrahedra_sharing_an_edge_are_cut_apart() {
    let positions = vec![
        DVec3::ZERO,
        DVec3::X,
        DVec3::Y,
        DVec3::Z,
        DVec3::NEG_Y,
        DVec3::NEG_Z,
    ];
    let mut faces: Vec<[u32; 3]> = tet(0, 1, 2, 3).to_vec();
    faces.extend(tet(0, 1, 4, 5));
    let faces = tris(&faces);
    assert!(matches!(
        HalfedgeMesh::from_polygons(6, faces.iter()),
        Err(TopologyError::NonManifoldEdge { a: 0, b: 1, .. })
    ));
    let repaired = run(&positions, &faces);
    let report = &repaired.report;
    assert_eq!(report.cut_edges, [(0, 1)]);
    // The second tetrahedron gets copies 6 and 7 of vertices 0 and 1.
    assert_eq!(report.split_vertices, [(0, 6), (1, 7)]);
    assert_eq!(
        report.to_string(),
        "1 non-manifold edge cut, 2 vertices split off"
    );
    assert_eq!(repaired.faces.get(4), Some(&[6, 4, 7][..]));
    let mesh = repaired.mesh().unwrap();
    let components = mesh.connected_components();
    assert_eq!(components.count(), 2);
    for c in &components.summaries {
        assert!(c.is_closed() && c.genus() == Some(0));
        assert_eq!((c.vertices, c.faces), (4, 4));
    }
}

#[test]
fn two_cubes_sharing_an_edge_are_cut_apart() {
    let cube = primitives::cube();
    // The second cube is the first moved by (1, 1, 0): its vertices 0 and 4 are the
    // first cube's 3 and 7 (edge x = y = 1); the others are new, numbered from 8.
    let map = |v: u32| match v {
        0 => 3,
        4 => 7,
        v if v < 4 => 7 + v,
        v => 6 + v,
    };
    let mut positions = cube.positions.clone();
    for v in [1, 2, 3, 5, 6, 7] {
        assert_eq!(map(v) as usize, positions.len());
        positions.push(cube.positions[v as usize] + DVec3::new(1.0, 1.0, 0.0));
    }
    let mut faces = cube.faces.clone();
    for f in cube.faces.iter() {
        let moved: Vec<u32> = f.iter().map(|&v| map(v)).collect();
        faces.push(&moved);
    }
    let repaired = run(&positions, &faces);
    let report = &repaired.report;
    assert_eq!(report.cut_edges, [(3, 7)]);
    assert_eq!(report.split_vertices, [(3, 14), (7, 15)]);
    assert!(report.flipped_faces.is_empty() && report.opened_edges.is_empty());
    let mesh = repaired.mesh().unwrap();
    let components = mesh.connected_components();
    assert_eq!(components.count(), 2);
    for c in &components.summaries {
        assert!(c.is_closed() && c.genus() == Some(0));
        assert_eq!((c.vertices, c.faces), (8, 12));
    }
}

#[test]
fn a_book_of_three_pages_keeps_one_sheet_and_detaches_the_third_page() {
    let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::NEG_Y, DVec3::Z];
    let faces = tris(&[[0, 1, 2], [1, 0, 3], [0, 1, 4]]);
    let repaired = run(&positions, &faces);
    let report = &repaired.report;
    assert_eq!(report.cut_edges, [(0, 1)]);
    assert_eq!(report.split_vertices, [(0, 5), (1, 6)]);
    assert_eq!(repaired.faces, tris(&[[0, 1, 2], [1, 0, 3], [5, 6, 4]]));
    let mesh = repaired.mesh().unwrap();
    assert_eq!(mesh.connected_components().count(), 2);
    assert_eq!(mesh.n_edges(), 5 + 3);
}

#[test]
fn pages_pair_with_the_earliest_later_page_running_the_other_way() {
    // Four pages on edge (0, 1), listed so that the two running 0 -> 1 come first:
    // face 0 pairs with face 2 (the earliest later face running 1 -> 0), face 1 with
    // face 3. The second sheet gets copies 6 and 7 of vertices 0 and 1.
    let positions = vec![
        DVec3::ZERO,
        DVec3::X,
        DVec3::Y,
        DVec3::NEG_Y,
        DVec3::Z,
        DVec3::NEG_Z,
    ];
    let faces = tris(&[[0, 1, 2], [0, 1, 4], [1, 0, 3], [1, 0, 5]]);
    let repaired = run(&positions, &faces);
    assert_eq!(repaired.report.cut_edges, [(0, 1)]);
    assert_eq!(repaired.report.split_vertices, [(0, 6), (1, 7)]);
    assert!(repaired.report.flipped_faces.is_empty());
    assert_eq!(
        repaired.faces,
        tris(&[[0, 1, 2], [6, 7, 4], [1, 0, 3], [7, 6, 5]])
    );
    assert_eq!(repaired.mesh().unwrap().connected_components().count(), 2);
}

#[test]
fn pages_running_the_same_way_are_paired_and_one_flipped() {
    // Three pages all running 0 -> 1: faces 0 and 1 form a sheet once face 1 is
    // flipped; face 2 is alone.
    let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::NEG_Y, DVec3::Z];
    let faces = tris(&[[0, 1, 2], [0, 1, 3], [0, 1, 4]]);
    let repaired = run(&positions, &faces);
    let report = &repaired.report;
    assert_eq!(report.cut_edges, [(0, 1)]);
    assert_eq!(report.flipped_faces, [1]);
    assert_eq!(repaired.faces.get(1), Some(&[0, 3, 1][..]));
    assert_eq!(repaired.mesh().unwrap().connected_components().count(), 2);
}

#[test]
fn sheets_that_stay_joined_around_both_ends_of_a_cut_edge_are_detached() {
    // Edge (3, 4) carries faces 0 and 1 (one sheet) and face 2. Face 3 joins face 2 to
    // face 1 around vertex 4, face 4 around vertex 3, so after the cut both sheets
    // would still run from 3 to 4: face 2 is detached around vertex 3 (the lower end)
    // by opening its other edge there, (2, 3).
    let positions: Vec<DVec3> = (0..5).map(|i| DVec3::splat(f64::from(i))).collect();
    let faces = tris(&[[4, 3, 0], [3, 4, 1], [3, 2, 4], [1, 2, 4], [3, 2, 1]]);
    let repaired = run(&positions, &faces);
    let report = &repaired.report;
    assert_eq!(report.cut_edges, [(3, 4)]);
    assert_eq!(report.opened_edges, [(2, 3)]);
    assert_eq!(report.split_vertices, [(3, 5)]);
    assert_eq!(repaired.faces.get(2), Some(&[5, 2, 4][..]));
    assert_eq!(repaired.mesh().unwrap().connected_components().count(), 1);
}

#[test]
fn a_doubled_sheet_keeps_one_copy() {
    // A 2 x 2 grid listed twice, the copy turned round (a wall scanned from both sides).
    let g = primitives::grid(2, 2);
    let mut faces = g.faces.clone();
    for f in g.faces.iter() {
        faces.push(&[f[0], f[2], f[1]]);
    }
    let repaired = run(&g.positions, &faces);
    let expected: Vec<(usize, usize)> = (0..8).map(|f| (f + 8, f)).collect();
    assert_eq!(repaired.report.dropped_duplicate_faces, expected);
    assert_eq!(repaired.faces, g.faces);
    assert_eq!(repaired.positions, g.positions);
}

#[test]
fn two_sheets_crossing_along_an_edge_are_separated() {
    // Two unit squares through edge (0, 1) along x: one in the xy-plane, one in the
    // xz-plane, each split into two triangles on either side of the edge.
    let positions = vec![
        DVec3::ZERO,
        DVec3::X,
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::new(0.0, -1.0, 0.0),
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::new(0.0, 0.0, -1.0),
    ];
    let faces = tris(&[[0, 1, 2], [1, 0, 3], [0, 1, 4], [1, 0, 5]]);
    let repaired = run(&positions, &faces);
    assert_eq!(repaired.report.cut_edges, [(0, 1)]);
    let mesh = repaired.mesh().unwrap();
    let components = mesh.connected_components();
    assert_eq!(components.count(), 2);
    for c in &components.summaries {
        assert_eq!((c.vertices, c.faces, c.boundary_loops), (4, 2, 1));
    }
}

#[test]
fn a_bow_tie_is_split() {
    let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::NEG_X, DVec3::NEG_Y];
    let faces = tris(&[[0, 1, 2], [0, 3, 4]]);
    let repaired = run(&positions, &faces);
    let report = &repaired.report;
    assert_eq!(report.split_vertices, [(0, 5)]);
    assert!(report.cut_edges.is_empty());
    assert_eq!(repaired.faces, tris(&[[0, 1, 2], [5, 3, 4]]));
    assert_eq!(repaired.positions[5], DVec3::ZERO);
    assert_eq!(repaired.mesh().unwrap().connected_components().count(), 2);
}

#[test]
fn two_closed_fans_at_one_vertex_are_split() {
    // Two tetrahedra sharing vertex 0 only.
    let positions = vec![
        DVec3::ZERO,
        DVec3::X,
        DVec3::Y,
        DVec3::Z,
        DVec3::NEG_X,
        DVec3::NEG_Z,
        DVec3::NEG_Y,
    ];
    let mut faces: Vec<[u32; 3]> = tet(0, 1, 2, 3).to_vec();
    faces.extend(tet(0, 4, 5, 6));
    let repaired = run(&positions, &tris(&faces));
    assert_eq!(repaired.report.split_vertices, [(0, 7)]);
    let components = repaired.mesh().unwrap().connected_components();
    assert_eq!(components.count(), 2);
    assert!(components.summaries.iter().all(|c| c.is_closed()));
}

#[test]
fn inconsistent_orientation_flips_the_fewer_faces() {
    let cube = primitives::cube();
    let reversed = |keep: &dyn Fn(usize) -> bool| -> PolygonList {
        cube.faces
            .iter()
            .enumerate()
            .map(|(f, face)| {
                if keep(f) {
                    face.to_vec()
                } else {
                    vec![face[0], face[2], face[1]]
                }
            })
            .collect::<Vec<_>>()
            .iter()
            .map(Vec::as_slice)
            .collect()
    };
    // Faces 4 and 5 turned round: they are flipped back.
    let faces = reversed(&|f| f != 4 && f != 5);
    let repaired = run(&cube.positions, &faces);
    assert_eq!(repaired.report.flipped_faces, [4, 5]);
    assert_eq!(repaired.faces, cube.faces);
    assert_eq!(repaired.report.to_string(), "2 faces flipped");
    // Faces 0..8 turned round: consistency alone flips the other four, not these
    // eight, which leaves the cube inside out ...
    let faces = reversed(&|f| f >= 8);
    let consistent = repair(
        &cube.positions,
        &faces,
        &RepairOptions::new().orient_outward(false),
    )
    .unwrap();
    assert_eq!(consistent.report.flipped_faces, [8, 9, 10, 11]);
    assert!(consistent.mesh().unwrap().is_closed());
    // ... so by default the closed cube is then turned to face outward: the eight
    // are flipped back and the faces are the cube's own.
    let repaired = run(&cube.positions, &faces);
    assert_eq!(repaired.report.flipped_faces, [0, 1, 2, 3, 4, 5, 6, 7]);
    assert_eq!(repaired.faces, cube.faces);
}

#[test]
fn a_closed_part_written_inside_out_is_turned_outward() {
    // Every face of the cube clockwise: consistent, closed, negative volume.
    let cube = primitives::cube();
    let inside_out: PolygonList = cube
        .faces
        .iter()
        .map(|face| vec![face[0], face[2], face[1]])
        .collect::<Vec<_>>()
        .iter()
        .map(Vec::as_slice)
        .collect();
    let repaired = run(&cube.positions, &inside_out);
    assert_eq!(repaired.report.flipped_faces, (0..12).collect::<Vec<_>>());
    assert_eq!(repaired.faces, cube.faces);
    let kept = repair(
        &cube.positions,
        &inside_out,
        &RepairOptions::new().orient_outward(false),
    )
    .unwrap();
    assert!(kept.report.is_empty());
    // An open patch keeps its orientation whichever way it faces.
    let grid = primitives::grid(3, 2);
    let down: PolygonList = grid
        .faces
        .iter()
        .map(|face| vec![face[0], face[2], face[1]])
        .collect::<Vec<_>>()
        .iter()
        .map(Vec::as_slice)
        .collect();
    assert!(run(&grid.positions, &down).report.is_empty());
}

#[test]
fn a_moebius_strip_is_cut_open_or_rejected() {
    // A strip of four quads closed with a half twist.
    let positions: Vec<DVec3> = (0..8).map(|i| DVec3::new(f64::from(i), 0.0, 0.0)).collect();
    let faces = polys(&[&[0, 1, 5, 4], &[1, 2, 6, 5], &[2, 3, 7, 6], &[3, 4, 0, 7]]);
    let repaired = run(&positions, &faces);
    let report = &repaired.report;
    assert_eq!(report.opened_edges.len(), 1, "{report:?}");
    assert_eq!(report.split_vertices.len(), 2);
    let mesh = repaired.mesh().unwrap();
    let components = mesh.connected_components();
    assert_eq!(components.count(), 1);
    // Cut across, the strip is a disc.
    assert_eq!(components.summaries[0].boundary_loops, 1);
    assert_eq!(components.summaries[0].genus(), Some(0));

    let options = RepairOptions::new().cut_non_orientable(false);
    let e = repair(&positions, &faces, &options).unwrap_err();
    assert_eq!(e, TopologyError::NonOrientable { face: 0 });
}

#[test]
fn degenerate_faces_are_dropped_and_repeated_corners_removed() {
    let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ONE];
    let faces = polys(&[
        &[0, 1, 2],
        &[0, 0, 1],    // two distinct vertices
        &[1, 2],       // too small
        &[0, 2, 3, 3], // a zero-length edge: kept as [0, 2, 3]
        &[0, 1, 0, 2], // touches itself at 0
        &[],
        &[3, 3, 3],
    ]);
    let repaired = run(&positions, &faces);
    let report = &repaired.report;
    assert_eq!(report.dropped_degenerate_faces, [1, 2, 4, 5, 6]);
    assert_eq!(report.shortened_faces, [3]);
    assert_eq!(report.face_origin, [0, 3]);
    assert_eq!(repaired.faces, tris(&[[0, 1, 2], [0, 2, 3]]));
    assert_eq!(
        report.to_string(),
        "5 degenerate faces dropped, 1 face shortened"
    );
}

#[test]
fn unreferenced_vertices_are_removed_with_a_vertex_map() {
    let positions: Vec<DVec3> = (0..6).map(|i| DVec3::splat(f64::from(i))).collect();
    // Vertex 5 is used only by a degenerate face.
    let faces = polys(&[&[0, 2, 4], &[5, 5, 0]]);
    let repaired = run(&positions, &faces);
    let report = &repaired.report;
    assert_eq!(report.removed_vertices, [1, 3, 5]);
    assert_eq!(
        report.vertex_map,
        [Some(0), None, Some(1), None, Some(2), None]
    );
    assert_eq!(repaired.faces, tris(&[[0, 1, 2]]));
    assert_eq!(
        repaired.positions,
        [positions[0], positions[2], positions[4]]
    );

    let keep = RepairOptions::new().drop_unreferenced(false);
    let repaired = repair(&positions, &faces, &keep).unwrap();
    check(&positions, &faces, &repaired);
    assert!(repaired.report.removed_vertices.is_empty());
    assert_eq!(repaired.positions, positions);
    assert_eq!(repaired.faces, tris(&[[0, 2, 4]]));
}

#[test]
fn near_duplicate_vertices_merge_into_a_connected_mesh() {
    let eps = DVec3::new(1e-9, -1e-9, 0.0);
    let positions = vec![
        DVec3::ZERO,
        DVec3::X,
        DVec3::Y,
        DVec3::Y + eps,
        DVec3::X - eps,
        DVec3::new(1.0, 1.0, 0.0),
    ];
    let faces = tris(&[[0, 1, 2], [3, 4, 5]]);
    let apart = run(&positions, &faces);
    assert!(apart.report.is_empty());
    assert_eq!(apart.mesh().unwrap().connected_components().count(), 2);

    let options = RepairOptions::new().merge_distance(Some(1e-6));
    let repaired = repair(&positions, &faces, &options).unwrap();
    check(&positions, &faces, &repaired);
    let report = &repaired.report;
    assert_eq!(report.merged_vertices, [(3, 2), (4, 1)]);
    assert_eq!(
        report.vertex_map,
        [Some(0), Some(1), Some(2), Some(2), Some(1), Some(3)]
    );
    assert_eq!(repaired.faces, tris(&[[0, 1, 2], [2, 1, 3]]));
    assert_eq!(
        repaired.positions,
        [positions[0], positions[1], positions[2], positions[5]]
    );
    let mesh = repaired.mesh().unwrap();
    assert_eq!(mesh.connected_components().count(), 1);
    assert_eq!(mesh.n_edges(), 5);
    assert_eq!(report.to_string(), "2 vertices merged");

    // A distance below the gap merges nothing.
    let options = RepairOptions::new().merge_distance(Some(1e-10));
    assert!(
        repair(&positions, &faces, &options)
            .unwrap()
            .report
            .is_empty()
    );
}

#[test]
fn merging_is_greedy_in_vertex_order_and_does_not_chain() {
    // Points 0.6 apart on a line, merge distance 1: 1 merges into 0, 2 is 1.2 from 0
    // and stays, 3 merges into 2 (not into 1, which is merged).
    let positions: Vec<DVec3> = (0..4).map(|i| DVec3::X * (0.6 * f64::from(i))).collect();
    let faces = PolygonList::new();
    let options = RepairOptions::new()
        .merge_distance(Some(1.0))
        .drop_unreferenced(false);
    let report = repair(&positions, &faces, &options).unwrap().report;
    assert_eq!(report.merged_vertices, [(1, 0), (3, 2)]);
    assert_eq!(report.vertex_map, [Some(0), Some(0), Some(1), Some(1)]);
}

#[test]
fn merging_handles_exact_duplicates_and_odd_distances_and_positions() {
    let positions = vec![
        DVec3::ZERO,
        DVec3::X,
        DVec3::Y,
        DVec3::new(-0.0, 0.0, 0.0),
        DVec3::new(f64::NAN, 0.0, 0.0),
        DVec3::new(f64::NAN, 0.0, 0.0),
        DVec3::splat(f64::INFINITY),
        DVec3::splat(f64::INFINITY),
        DVec3::splat(1e300),
    ];
    let faces = tris(&[[0, 1, 2], [3, 4, 5], [6, 7, 8]]);
    let exact = RepairOptions::new().merge_distance(Some(0.0));
    let repaired = repair(&positions, &faces, &exact).unwrap();
    check(&positions, &faces, &repaired);
    // -0 and +0 coincide; NaN and infinite positions are never merged.
    assert_eq!(repaired.report.merged_vertices, [(3, 0)]);

    for odd in [-1.0, f64::NAN] {
        let options = RepairOptions::new().merge_distance(Some(odd));
        let repaired = repair(&positions, &faces, &options).unwrap();
        check(&positions, &faces, &repaired);
        assert!(repaired.report.merged_vertices.is_empty());
    }
    // An infinite distance merges every finite vertex into vertex 0: every face with
    // two finite vertices collapses.
    let all = RepairOptions::new().merge_distance(Some(f64::INFINITY));
    let repaired = repair(&positions, &faces, &all).unwrap();
    check(&positions, &faces, &repaired);
    assert_eq!(
        repaired.report.merged_vertices,
        [(1, 0), (2, 0), (3, 0), (8, 0)]
    );
    assert_eq!(repaired.report.dropped_degenerate_faces, [0]);
    let huge = RepairOptions::new().merge_distance(Some(f64::MAX));
    let repaired = repair(&positions, &faces, &huge).unwrap();
    check(&positions, &faces, &repaired);
    assert_eq!(repaired.report.merged_vertices.len(), 4);
}

#[test]
fn out_of_range_indices_are_an_error() {
    let positions = vec![DVec3::ZERO; 3];
    let e = repair(
        &positions,
        &tris(&[[0, 1, 2], [1, 1, 7]]),
        &RepairOptions::default(),
    )
    .unwrap_err();
    assert_eq!(
        e,
        TopologyError::VertexOutOfRange {
            face: 1,
            vertex: 7,
            n_vertices: 3
        }
    );
}

#[test]
fn empty_input_gives_empty_output() {
    let repaired = repair(&[], &PolygonList::new(), &RepairOptions::default()).unwrap();
    assert!(repaired.positions.is_empty() && repaired.faces.is_empty());
    assert_eq!(repaired.report, RepairReport::default());
    assert_eq!(repaired.report.to_string(), "no repair needed");
}

#[test]
fn a_mesh_that_needs_no_repair_is_returned_unchanged() {
    for p in [
        primitives::triangle(),
        primitives::hexagon_fan(),
        primitives::grid(4, 3),
        primitives::tetrahedron(),
        primitives::cube(),
        primitives::cube_quads(),
        primitives::icosphere(2),
        primitives::torus(2.0, 0.5, 8, 5),
    ] {
        let options = RepairOptions::new().merge_distance(Some(1e-9));
        let repaired = repair(&p.positions, &p.faces, &options).unwrap();
        check(&p.positions, &p.faces, &repaired);
        assert!(repaired.report.is_empty(), "{}", repaired.report);
        assert_eq!(repaired.positions, p.positions);
        assert_eq!(repaired.faces, p.faces);
        let n = p.positions.len() as u32;
        assert_eq!(
            repaired.report.vertex_map,
            (0..n).map(Some).collect::<Vec<_>>()
        );
        assert_eq!(
            repaired.report.face_origin,
            (0..p.faces.len()).collect::<Vec<_>>()
        );
        assert_eq!(repaired.mesh().unwrap(), p.mesh().unwrap());
    }
}

#[test]
fn the_report_summarises_every_kind_of_change() {
    let mut report = RepairReport::default();
    report.merged_vertices = vec![(1, 0)];
    report.dropped_degenerate_faces = vec![1, 2];
    report.shortened_faces = vec![3];
    report.dropped_duplicate_faces = vec![(5, 4)];
    report.cut_edges = vec![(0, 1), (1, 2)];
    report.opened_edges = vec![(2, 3)];
    report.flipped_faces = vec![6];
    report.split_vertices = vec![(0, 9)];
    report.removed_vertices = vec![7, 8];
    assert!(!report.is_empty());
    assert_eq!(
        report.to_string(),
        "1 vertex merged, 2 degenerate faces dropped, 1 duplicate face dropped, \
         1 face shortened, 2 non-manifold edges cut, 1 edge opened, 1 face flipped, \
         1 vertex split off, 2 unreferenced vertices removed"
    );
}

/// A large grid with defects near its start, middle and end (several parallel chunks).
fn defective_grid() -> (Vec<DVec3>, PolygonList) {
    let g = primitives::grid(200, 200);
    let n = g.faces.len();
    let mut faces = PolygonList::new();
    for (f, face) in g.faces.iter().enumerate() {
        if [1, n / 2, n - 2].contains(&f) {
            faces.push(&[face[0], face[2], face[1]]);
        } else {
            faces.push(face);
        }
        if [5, n / 3, n - 7].contains(&f) {
            faces.push(&[face[1], face[0], face[2]]);
        }
        if [9, n / 4].contains(&f) {
            faces.push(&[face[0], face[0], face[1]]);
        }
    }
    (g.positions, faces)
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let (positions, faces) = defective_grid();
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool")
            .install(|| repair(&positions, &faces, &RepairOptions::default()))
            .expect("repairable")
    };
    let one = on(1);
    let two = on(2);
    assert_eq!(one, two);
    check(&positions, &faces, &two);
    let report = &two.report;
    assert_eq!(report.dropped_duplicate_faces.len(), 3);
    assert_eq!(report.dropped_degenerate_faces.len(), 2);
    assert_eq!(report.flipped_faces.len(), 3);
    assert!(two.mesh().unwrap().connected_components().count() == 1);
}

mod random {
    use super::*;
    use proptest::prelude::*;

    fn soup() -> impl Strategy<Value = (Vec<DVec3>, Vec<Vec<u32>>)> {
        (3usize..9).prop_flat_map(|n| {
            let positions = proptest::collection::vec(
                (0u8..3, 0u8..3, 0u8..2)
                    .prop_map(|(x, y, z)| DVec3::new(x.into(), y.into(), z.into())),
                n,
            );
            let face = proptest::collection::vec(0..n as u32, 2..5);
            let faces = proptest::collection::vec(face, 0..16);
            (positions, faces)
        })
    }

    fn merge_option() -> impl Strategy<Value = Option<f64>> {
        prop_oneof![
            Just(None),
            Just(Some(0.0)),
            Just(Some(1.0)),
            Just(Some(1.5))
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]

        /// Any soup repairs into faces that build, with every promise of the report
        /// kept; without cutting, only a non-orientable component is an error.
        #[test]
        fn random_soups_repair_into_meshes(
            (positions, faces) in soup(),
            merge in merge_option(),
            drop_unreferenced in any::<bool>(),
        ) {
            let faces: PolygonList = faces.iter().map(Vec::as_slice).collect();
            let options = RepairOptions::new()
                .merge_distance(merge)
                .drop_unreferenced(drop_unreferenced);
            let repaired = repair(&positions, &faces, &options).unwrap();
            check(&positions, &faces, &repaired);
            // Kept vertices are more than the merge distance apart.
            if let Some(d) = merge {
                let kept: Vec<usize> = (0..positions.len())
                    .filter(|&v| !repaired.report.merged_vertices.iter().any(|&(m, _)| m as usize == v))
                    .collect();
                for (i, &a) in kept.iter().enumerate() {
                    for &b in &kept[i + 1..] {
                        prop_assert!(positions[a].distance(positions[b]) > d);
                    }
                }
            }
            // Repairing the output again changes nothing (without merging, which would
            // join the copies of split vertices to their originals again).
            let again = repair(&repaired.positions, &repaired.faces, &options.merge_distance(None)).unwrap();
            prop_assert!(again.report.is_empty(), "{}", again.report);
            prop_assert_eq!(&again.faces, &repaired.faces);

            match repair(&positions, &faces, &options.cut_non_orientable(false)) {
                Ok(r) => {
                    check(&positions, &faces, &r);
                    prop_assert!(r.report.opened_edges.len() <= repaired.report.opened_edges.len());
                }
                Err(TopologyError::NonOrientable { face }) => {
                    prop_assert!(repaired.report.face_origin.contains(&face));
                    prop_assert!(!repaired.report.opened_edges.is_empty());
                }
                Err(e) => prop_assert!(false, "unexpected error {e}"),
            }
        }

        /// With triangulation: every output face is a triangle on corners of its input
        /// face, each kept input face gives its corners − 2 triangles (one when it was
        /// a triangle), every input face is accounted once, the lists name each face
        /// once, and the faces build.
        #[test]
        fn random_soups_repair_into_triangles(
            (positions, faces) in soup(),
            merge in merge_option(),
        ) {
            let faces: PolygonList = faces.iter().map(Vec::as_slice).collect();
            let options = RepairOptions::new().merge_distance(merge).triangulate(true);
            let repaired = repair(&positions, &faces, &options).unwrap();
            let report = &repaired.report;
            let mesh = repaired.mesh().expect("the repaired faces build");
            mesh.check_integrity().expect("integrity");
            prop_assert!(repaired.faces.is_triangles());
            let mut target: Vec<u32> = (0..positions.len() as u32).collect();
            for &(v, t) in &report.merged_vertices {
                target[v as usize] = t;
            }
            let source = output_sources(&repaired);
            let mut kept = report.face_origin.clone();
            prop_assert!(kept.windows(2).all(|w| w[0] <= w[1]));
            kept.dedup();
            prop_assert_eq!(
                kept.len() + report.dropped_degenerate_faces.len() + report.dropped_duplicate_faces.len(),
                faces.len()
            );
            for &f in &kept {
                let corners = cleaned(faces.get(f).unwrap(), &target).expect("kept");
                let n = report.face_origin.iter().filter(|&&g| g == f).count();
                prop_assert_eq!(n, corners.len() - 2, "input face {}", f);
                prop_assert_eq!(report.triangulated_faces.contains(&f), corners.len() > 3);
            }
            for (o, t) in repaired.faces.iter().enumerate() {
                let f = report.face_origin[o];
                let corners = cleaned(faces.get(f).unwrap(), &target).unwrap();
                prop_assert!(t.iter().all(|&v| corners.contains(&source[v as usize])));
            }
            for list in [&report.flipped_faces, &report.triangulated_faces] {
                prop_assert!(list.windows(2).all(|w| w[0] < w[1]), "{:?}", list);
            }
            let mut duplicates: Vec<usize> = report.dropped_duplicate_faces.iter().map(|&(f, _)| f).collect();
            duplicates.dedup();
            prop_assert_eq!(duplicates.len(), report.dropped_duplicate_faces.len());
        }

        /// A subset of a grid's triangles that already builds comes back unchanged.
        #[test]
        fn valid_grid_subsets_are_unchanged(keep in proptest::collection::vec(any::<bool>(), 2 * 4 * 4)) {
            let g = primitives::grid(4, 4);
            let faces: PolygonList = g.faces.iter().zip(&keep).filter(|(_, k)| **k).map(|(f, _)| f).collect();
            let options = RepairOptions::new().drop_unreferenced(false);
            let repaired = repair(&g.positions, &faces, &options).unwrap();
            check(&g.positions, &faces, &repaired);
            if HalfedgeMesh::from_polygons(g.positions.len(), faces.iter()).is_ok() {
                prop_assert!(repaired.report.is_empty(), "{}", repaired.report);
                prop_assert_eq!(&repaired.faces, &faces);
            } else {
                prop_assert!(!repaired.report.split_vertices.is_empty());
            }
        }
    }
}

/// A quad listed twice from different corners is one duplicate, with triangulation as
/// without: the copies are compared as polygons, before they are split.
#[test]
fn a_duplicate_quad_is_dropped_before_the_split() {
    let cube = primitives::cube_quads();
    let mut faces = cube.faces.clone();
    let first: Vec<u32> = cube.faces.get(0).unwrap().to_vec();
    faces.push(&[first[2], first[3], first[0], first[1]]);
    for triangulate in [false, true] {
        let options = RepairOptions::new().triangulate(triangulate);
        let repaired = repair(&cube.positions, &faces, &options).unwrap();
        assert_eq!(repaired.report.dropped_duplicate_faces, [(6, 0)]);
        assert!(repaired.report.cut_edges.is_empty());
        assert_eq!(repaired.faces.len(), if triangulate { 12 } else { 6 });
        let mesh = repaired.mesh().unwrap();
        assert!(mesh.is_closed());
        assert_eq!(mesh.n_vertices(), 8);
        assert_eq!(
            repaired.report.to_string(),
            if triangulate {
                "1 duplicate face dropped, 6 faces triangulated"
            } else {
                "1 duplicate face dropped"
            }
        );
    }
}
