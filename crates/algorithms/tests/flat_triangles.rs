//! Removing flat triangles: caps (a corner on the opposite edge) and needles (two corners
//! at one point) made on purpose in sound meshes are removed, the result is a valid mesh
//! of the same topology and area whose vertices are input vertices at their input
//! positions, and a mesh without flat triangles comes back as it was.

use beltrami_algorithms::{FlatError, FlatOptions, FlatReport, remove_flat_triangles};
use beltrami_halfedge::{DVec3, EdgeId, EditMesh, FaceId, HalfedgeMesh, VertexId, primitives};
use beltrami_metrics::distance::SurfaceIndex;
use proptest::prelude::*;

/// The sliver-making edits of the tests.
#[derive(Clone, Copy, Debug)]
enum Sliver {
    /// Split an edge at its midpoint and flip the new edge to an opposite corner: the
    /// two halves of the old edge and the far side make a cap.
    Cap,
    /// Split an edge at one of its endpoints: a zero-length edge, and a needle on each
    /// side.
    Needle,
}

/// Makes a sliver at the `pick`-th live edge (modulo their number); returns whether it
/// was made.
fn make(edit: &mut EditMesh, kind: Sliver, pick: usize) -> bool {
    let edges: Vec<EdgeId> = edit.edges().collect();
    let e = edges[pick % edges.len()];
    if !edit.is_split_edge_ok(e) {
        return false;
    }
    let [h, _] = e.halfedges();
    let (a, b) = (edit.from_vertex(h), edit.to_vertex(h));
    let (pa, pb) = (edit.position(a), edit.position(b));
    match kind {
        Sliver::Needle => edit.split_edge(e, pa).is_ok(),
        Sliver::Cap => {
            let Ok(c) = edit.split_edge(e, 0.5 * (pa + pb)) else {
                return false;
            };
            // An edge from c to a corner off the line.
            let spoke = edit.halfedges_around_vertex(c).find(|&g| {
                let x = edit.to_vertex(g);
                x != a && x != b && edit.is_flip_ok(g.edge())
            });
            match spoke {
                Some(g) => edit.flip_edge(g.edge()).is_ok(),
                None => true,
            }
        }
    }
}

fn area(mesh: &HalfedgeMesh, x: &[DVec3]) -> f64 {
    mesh.faces()
        .map(|f| {
            let v = mesh.triangle_vertices(f);
            let (a, b, c) = (x[v[0].index()], x[v[1].index()], x[v[2].index()]);
            0.5 * (b - a).cross(c - a).length()
        })
        .sum()
}

fn flat_count(mesh: &HalfedgeMesh, x: &[DVec3]) -> usize {
    mesh.faces()
        .filter(|&f| {
            let v = mesh.triangle_vertices(f);
            let (a, b, c) = (x[v[0].index()], x[v[1].index()], x[v[2].index()]);
            let longest = (b - a)
                .length_squared()
                .max((c - b).length_squared())
                .max((a - c).length_squared());
            (b - a).cross(c - a).length() <= 1e-12 * longest
        })
        .count()
}

/// The largest distance from the vertices, edge midpoints and centroids of each surface
/// to the other: 0 when one surface covers the same points as the other.
fn surface_gap(a: (&HalfedgeMesh, &[DVec3]), b: (&HalfedgeMesh, &[DVec3])) -> f64 {
    let one_way = |(m, x): (&HalfedgeMesh, &[DVec3]), (n, y): (&HalfedgeMesh, &[DVec3])| {
        let index = SurfaceIndex::new(n, y).unwrap();
        let mut points: Vec<DVec3> = m
            .vertices()
            .filter(|&v| !m.is_isolated(v))
            .map(|v| x[v.index()])
            .collect();
        for f in m.faces() {
            let [p, q, r] = m.triangle_vertices(f).map(|v| x[v.index()]);
            points.extend([
                (p + q + r) / 3.0,
                0.5 * (p + q),
                0.5 * (q + r),
                0.5 * (r + p),
            ]);
        }
        index
            .distances(&points)
            .unwrap()
            .into_iter()
            .fold(0.0f64, f64::max)
    };
    one_way(a, b).max(one_way(b, a))
}

/// The unit normal of a sound triangle `f`, `None` for a flat one.
fn unit_normal(mesh: &HalfedgeMesh, x: &[DVec3], f: FaceId) -> Option<DVec3> {
    let [a, b, c] = mesh.triangle_vertices(f).map(|v| x[v.index()]);
    let n = (b - a).cross(c - a);
    let longest = (b - a)
        .length_squared()
        .max((c - b).length_squared())
        .max((a - c).length_squared());
    (n.length() > 1e-12 * longest).then(|| n.normalize())
}

/// The edges whose two sound triangles face opposite ways (folds).
fn folds(mesh: &HalfedgeMesh, x: &[DVec3]) -> usize {
    mesh.edges()
        .filter(|&e| {
            let [h, t] = e.halfedges();
            let normals = (
                mesh.face(h).and_then(|f| unit_normal(mesh, x, f)),
                mesh.face(t).and_then(|f| unit_normal(mesh, x, f)),
            );
            matches!(normals, (Some(n), Some(m)) if n.dot(m) <= 0.0)
        })
        .count()
}

/// Checks a run on `mesh`: the flat triangles counted right, the topology and area kept,
/// nothing folded, the vertices the input's at their positions. Returns the report.
fn check(
    mesh: &HalfedgeMesh,
    x: &[DVec3],
    options: FlatOptions,
) -> Result<FlatReport, TestCaseError> {
    let before = flat_count(mesh, x);
    let (out, y, report) = remove_flat_triangles(mesh, x, options).unwrap();
    prop_assert_eq!(report.flat_before, before);
    prop_assert_eq!(flat_count(&out, &y), report.flat_after);
    prop_assert!(report.flat_after <= report.flat_before);
    prop_assert_eq!(folds(&out, &y), folds(mesh, x), "{:?}", report);
    EditMesh::from_mesh(&out, &y)
        .unwrap()
        .check_integrity()
        .unwrap();
    prop_assert_eq!(out.euler_characteristic(), mesh.euler_characteristic());
    prop_assert_eq!(out.is_closed(), mesh.is_closed());
    prop_assert_eq!(out.boundary_loops().count(), mesh.boundary_loops().count());
    prop_assert_eq!(report.vertex_origin.len(), y.len());
    for (i, &o) in report.vertex_origin.iter().enumerate() {
        prop_assert_eq!(y[i], x[o]);
    }
    prop_assert!(report.max_move <= options.max_move);
    // Without moving collapses, needles (zero-length edges) are collapsed and caps
    // flipped or deleted: the surface stays where it was, and so does its area.
    let gap = surface_gap((mesh, x), (&out, &y));
    if report.max_move == 0.0 {
        prop_assert!(gap <= 1e-12, "the surface moved by {}: {:?}", gap, report);
        let (a, b) = (area(mesh, x), area(&out, &y));
        prop_assert!(
            (a - b).abs() <= 1e-12 * a,
            "area {} -> {}: {:?}",
            a,
            b,
            report
        );
    } else {
        prop_assert!(
            gap <= report.max_move,
            "the surface moved by {}: {:?}",
            gap,
            report
        );
    }
    // A collapse removes one vertex, a triangle alone its three.
    prop_assert_eq!(
        out.n_vertices() + report.collapses + 3 * report.alone,
        mesh.n_vertices(),
        "{:?}",
        report
    );
    Ok(report)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Random caps and needles on a closed sphere, an open grid and a torus.
    #[test]
    fn random_slivers_are_removed(
        surface in 0usize..3,
        slivers in proptest::collection::vec((any::<bool>(), 0usize..10_000), 1..12),
    ) {
        let p = match surface {
            0 => primitives::icosphere(2),
            1 => primitives::grid(6, 5),
            _ => primitives::torus(1.0, 0.4, 12, 8),
        };
        let mesh = p.mesh().unwrap();
        let mut edit = EditMesh::from_mesh(&mesh, &p.positions).unwrap();
        for (cap, pick) in slivers {
            make(&mut edit, if cap { Sliver::Cap } else { Sliver::Needle }, pick);
            edit.check_integrity().unwrap();
        }
        let (mesh, x) = edit.into_mesh().unwrap();
        let still = check(&mesh, &x, FlatOptions::default())?;
        let moving = check(&mesh, &x, FlatOptions::default().max_move(f64::INFINITY))?;
        prop_assert!(moving.flat_after <= still.flat_after);
        // The same edits at any scale: a power of two keeps every ratio exact.
        for k in [-560, 990] {
            let s = 2f64.powi(k);
            let scaled: Vec<DVec3> = x.iter().map(|&p| p * s).collect();
            let (out, y, report) =
                remove_flat_triangles(&mesh, &scaled, FlatOptions::default()).unwrap();
            let (out1, y1, report1) =
                remove_flat_triangles(&mesh, &x, FlatOptions::default()).unwrap();
            prop_assert_eq!(&out, &out1);
            prop_assert_eq!(y, y1.iter().map(|&p| p * s).collect::<Vec<_>>());
            prop_assert_eq!(
                (report.flat_before, report.flat_after, report.flips, report.collapses),
                (report1.flat_before, report1.flat_after, report1.flips, report1.collapses)
            );
        }
    }
}

/// A cap whose longest edge is on the boundary is deleted, and its middle corner becomes
/// a boundary vertex.
#[test]
fn a_boundary_cap_is_deleted() {
    let p = primitives::grid(4, 4);
    let mesh = p.mesh().unwrap();
    let mut x = p.positions.clone();
    // An interior vertex next to the boundary, moved onto the middle of a boundary edge
    // of one of its triangles.
    let (v, a, b) = mesh
        .vertices()
        .filter(|&v| !mesh.is_boundary_vertex(v))
        .find_map(|v| {
            mesh.halfedges_around_vertex(v).find_map(|h| {
                let g = mesh.next(h);
                mesh.is_boundary_halfedge(g.twin())
                    .then(|| (v, mesh.from_vertex(g), mesh.to_vertex(g)))
            })
        })
        .unwrap();
    x[v.index()] = 0.5 * (x[a.index()] + x[b.index()]);
    assert_eq!(flat_count(&mesh, &x), 1);
    let (out, y, report) = remove_flat_triangles(&mesh, &x, FlatOptions::default()).unwrap();
    assert_eq!((report.deleted, report.flat_after), (1, 0), "{report:?}");
    assert_eq!(out.n_faces(), mesh.n_faces() - 1);
    assert!(
        out.is_boundary_vertex(VertexId::new(
            report
                .vertex_origin
                .iter()
                .position(|&o| o == v.index())
                .unwrap() as u32
        ))
    );
    assert_eq!(y, x);
    assert_eq!(out.boundary_loops().count(), 1);
}

/// A mesh without flat triangles comes back as it was; three corners at one point are a
/// needle too.
#[test]
fn sound_meshes_are_unchanged_and_points_are_needles() {
    let p = primitives::icosphere(2);
    let mesh = p.mesh().unwrap();
    let (out, y, report) =
        remove_flat_triangles(&mesh, &p.positions, FlatOptions::default()).unwrap();
    assert_eq!(out, mesh);
    assert_eq!(y, p.positions);
    assert_eq!(
        (report.flat_before, report.flips, report.collapses),
        (0, 0, 0)
    );

    // Split an edge at its endpoint twice: the second split's needles have three
    // corners at one point.
    let mut edit = EditMesh::from_mesh(&mesh, &p.positions).unwrap();
    let e = edit.edges().next().unwrap();
    let [h, _] = e.halfedges();
    let a = edit.position(edit.from_vertex(h));
    edit.split_edge(e, a).unwrap();
    let e = edit.edges().next().unwrap();
    edit.split_edge(e, a).unwrap();
    let (mesh2, x2) = edit.into_mesh().unwrap();
    let (out, _, report) = remove_flat_triangles(&mesh2, &x2, FlatOptions::default()).unwrap();
    assert_eq!(report.flat_after, 0, "{report:?}");
    assert_eq!(out.n_vertices(), mesh.n_vertices());
}

/// A larger ratio takes near-slivers too; ratios outside [0, 0.1] are refused.
#[test]
fn the_height_ratio_is_an_option() {
    let p = primitives::grid(3, 3);
    let mesh = p.mesh().unwrap();
    for bad in [-1e-3, 0.11, 1.0, f64::NAN] {
        let e = remove_flat_triangles(
            &mesh,
            &p.positions,
            FlatOptions::default().max_height_ratio(bad),
        )
        .unwrap_err();
        assert!(matches!(e, FlatError::Options { .. }), "{e}");
    }
    for bad in [-1e-3, f64::NAN] {
        let e = remove_flat_triangles(&mesh, &p.positions, FlatOptions::default().max_move(bad))
            .unwrap_err();
        assert!(matches!(e, FlatError::Options { .. }), "{e}");
    }
    // An edge split a thousandth off its midpoint: flat at 1e-2, not at the default.
    let mut edit = EditMesh::from_mesh(&mesh, &p.positions).unwrap();
    let inner = edit.edges().find(|&e| !edit.is_boundary_edge(e)).unwrap();
    assert!(make(&mut edit, Sliver::Cap, inner.index()));
    let (mesh, mut x) = edit.into_mesh().unwrap();
    let last = x.len() - 1;
    x[last].z += 1e-3;
    let (_, _, report) = remove_flat_triangles(&mesh, &x, FlatOptions::default()).unwrap();
    assert_eq!(report.flat_before, 0);
    let (_, _, report) =
        remove_flat_triangles(&mesh, &x, FlatOptions::default().max_height_ratio(1e-2)).unwrap();
    assert_eq!(
        (report.flat_before, report.flat_after),
        (1, 0),
        "{report:?}"
    );
    // A near-sliver is not flat: its flip moves the surface by up to its height, which
    // the report gives.
    assert!(
        report.max_height > 0.9e-3 && report.max_height <= 1e-3,
        "{report:?}"
    );
}

/// A cap whose longest edge is on the boundary and whose middle corner is on the boundary
/// too cannot be deleted (the corner would be pinched) nor flipped: it stays, and the
/// surface with it; a collapse allowed to move removes it without folding anything.
#[test]
fn a_boundary_cap_with_its_middle_on_the_boundary() {
    // The cap (0, 2, 1), vertex 1 halfway along the boundary edge 0-2, and beside it
    // across the edge 0-1 the triangle (0, 1, 3); vertex 1 is on the boundary (edges 1-2
    // and 1-3 have one face each).
    let x = vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(2.0, 0.0, 0.0),
        DVec3::new(1.0, -1.0, 0.0),
    ];
    let mesh = HalfedgeMesh::from_polygons(4, [[0u32, 2, 1], [0, 1, 3]]).unwrap();
    assert!(mesh.is_boundary_vertex(VertexId::new(1)));
    assert_eq!(flat_count(&mesh, &x), 1);
    let (out, y, report) = remove_flat_triangles(&mesh, &x, FlatOptions::default()).unwrap();
    assert_eq!(
        (
            report.flat_after,
            report.deleted,
            report.flips,
            report.collapses
        ),
        (1, 0, 0, 0),
        "{report:?}"
    );
    assert_eq!((out.n_faces(), y), (2, x.clone()));
    // Moving vertex 2 onto vertex 1 (or 1 onto 2), along the boundary, removes the cap.
    let (out, y, report) =
        remove_flat_triangles(&mesh, &x, FlatOptions::default().max_move(1.0)).unwrap();
    assert_eq!((report.flat_after, report.collapses), (0, 1), "{report:?}");
    assert_eq!(report.max_move, 1.0);
    assert_eq!(out.n_faces(), 1);
    assert_eq!(folds(&out, &y), 0);
    assert!(
        report.vertex_origin == [0, 1, 3] || report.vertex_origin == [0, 2, 3],
        "{report:?}"
    );
}

/// A flat triangle alone (a component of its own) is deleted with its corners; the
/// rest of the mesh stays as it was.
#[test]
fn a_flat_triangle_alone_is_deleted() {
    let p = primitives::grid(2, 2);
    let n = p.positions.len() as u32;
    let mut x = p.positions.clone();
    x.extend([
        DVec3::new(5.0, 0.0, 0.0),
        DVec3::new(6.0, 0.0, 0.0),
        DVec3::new(7.0, 0.0, 0.0),
    ]);
    let mut faces: Vec<Vec<u32>> = p.faces.iter().map(<[u32]>::to_vec).collect();
    faces.push(vec![n, n + 1, n + 2]);
    let mesh = HalfedgeMesh::from_polygons(x.len(), &faces).unwrap();
    let (out, y, report) = remove_flat_triangles(&mesh, &x, FlatOptions::default()).unwrap();
    assert_eq!((report.alone, report.flat_after), (1, 0), "{report:?}");
    assert_eq!(out.n_faces(), p.faces.len());
    assert_eq!(y, p.positions);
    assert_eq!(report.vertex_origin, (0..n as usize).collect::<Vec<_>>());
}
