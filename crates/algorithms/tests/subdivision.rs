//! Invariants of Loop and √3 subdivision on procedural meshes: predicted counts,
//! valid connectivity, preserved topology, the boundary rules, affine invariance,
//! determinism across thread counts, and the errors.

use beltrami_algorithms::{Scheme, SubdivisionError, loop_subdivide, sqrt3_subdivide};
use beltrami_halfedge::primitives::{self, Primitive};
use beltrami_halfedge::{DVec3, HalfedgeMesh, VertexId};

fn meshes() -> Vec<(&'static str, Primitive)> {
    vec![
        ("triangle", primitives::triangle()),
        ("hexagon_fan", primitives::hexagon_fan()),
        ("grid", primitives::grid(5, 3)),
        ("tetrahedron", primitives::tetrahedron()),
        ("cube", primitives::cube()),
        ("icosphere", primitives::icosphere(1)),
        ("torus", primitives::torus(2.0, 0.5, 9, 5)),
        ("holes", beltrami_testkit::fixtures::holes_patch()),
    ]
}

#[test]
fn counts_are_predicted_and_topology_is_kept() {
    for (name, p) in meshes() {
        let mesh = p.mesh().unwrap();
        for scheme in Scheme::ALL {
            for steps in 0..=3 {
                let (fine, positions) = scheme.subdivide(&mesh, &p.positions, steps).unwrap();
                let case = format!("{name} {scheme} {steps}");
                fine.check_integrity().unwrap();
                assert_eq!(positions.len(), fine.n_vertices(), "{case}");
                let c = scheme.counts(&mesh, steps);
                assert_eq!(c.vertices, fine.n_vertices() as u64, "{case}");
                assert_eq!(c.edges, fine.n_edges() as u64, "{case}");
                assert_eq!(c.faces, fine.n_faces() as u64, "{case}");
                assert_eq!(
                    c.boundary_edges,
                    fine.n_boundary_halfedges() as u64,
                    "{case}"
                );
                assert_eq!(
                    fine.euler_characteristic(),
                    mesh.euler_characteristic(),
                    "{case}"
                );
                assert_eq!(
                    fine.boundary_loops().count(),
                    mesh.boundary_loops().count(),
                    "{case}"
                );
                assert!(fine.is_triangle_mesh(), "{case}");
                // The old vertices keep their ids and their neighbourhoods: an old
                // boundary vertex stays on the boundary.
                for v in mesh.vertices() {
                    assert_eq!(
                        mesh.is_boundary_vertex(v),
                        fine.is_boundary_vertex(v),
                        "{case} {v}"
                    );
                }
            }
        }
    }
}

#[test]
fn the_result_is_an_affine_combination_of_the_input() {
    // Subdivision commutes with affine maps: subdivide(A p + t) = A subdivide(p) + t.
    let a = glam::DMat3::from_cols(
        DVec3::new(1.3, 0.2, -0.4),
        DVec3::new(-0.1, 0.9, 0.3),
        DVec3::new(0.5, 0.0, 1.7),
    );
    let t = DVec3::new(10.0, -3.0, 0.25);
    for (name, p) in meshes() {
        let mesh = p.mesh().unwrap();
        let moved: Vec<DVec3> = p.positions.iter().map(|&x| a * x + t).collect();
        for scheme in Scheme::ALL {
            let (_, base) = scheme.subdivide(&mesh, &p.positions, 2).unwrap();
            let (_, of_moved) = scheme.subdivide(&mesh, &moved, 2).unwrap();
            for (i, (b, m)) in base.iter().zip(&of_moved).enumerate() {
                let want = a * *b + t;
                assert!((want - *m).length() < 1e-12, "{name} {scheme} vertex {i}");
            }
        }
    }
}

#[test]
fn points_stay_in_the_convex_hull() {
    // All masks have positive weights, so a subdivided sphere stays inside its ball.
    let ico = primitives::icosphere(2);
    let mesh = ico.mesh().unwrap();
    for scheme in Scheme::ALL {
        let (_, positions) = scheme.subdivide(&mesh, &ico.positions, 3).unwrap();
        let max = positions.iter().map(|p| p.length()).fold(0.0, f64::max);
        let min = positions
            .iter()
            .map(|p| p.length())
            .fold(f64::INFINITY, f64::min);
        assert!(max <= 1.0 + 1e-15, "{scheme}: {max}");
        // Both schemes approximate: the result shrinks inside the control mesh, but
        // the icosphere is already round, so by less than 3 % (Loop: 0.975).
        assert!(min > 0.97, "{scheme}: {min}");
    }
}

/// The grid with its interior vertices pushed out of the plane.
fn bumpy_grid() -> (HalfedgeMesh, Vec<DVec3>, Vec<DVec3>) {
    let g = primitives::grid(6, 4);
    let mesh = g.mesh().unwrap();
    let bumped = g
        .positions
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            if mesh.is_boundary_vertex(VertexId::new(i as u32)) {
                p
            } else {
                p + DVec3::new(0.0, 0.0, 0.3 + 0.1 * (i % 3) as f64)
            }
        })
        .collect();
    (mesh, g.positions, bumped)
}

#[test]
fn the_loop_boundary_depends_on_the_boundary_only() {
    let (mesh, flat, bumped) = bumpy_grid();
    let (fine, a) = loop_subdivide(&mesh, &flat, 2).unwrap();
    let (_, b) = loop_subdivide(&mesh, &bumped, 2).unwrap();
    let mut boundary = 0;
    for v in fine.vertices() {
        if fine.is_boundary_vertex(v) {
            assert_eq!(a[v.index()], b[v.index()], "{v}");
            assert_eq!(b[v.index()].z, 0.0, "{v}");
            boundary += 1;
        } else {
            assert!(b[v.index()].z > 0.0, "{v}: the interior is pulled up");
        }
    }
    assert_eq!(boundary, 2 * (6 + 4) * 4);
}

#[test]
fn loop_boundary_masks() {
    // A straight boundary edge stays straight; a corner is cut by the 1-6-1 rule.
    let (mesh, flat, _) = bumpy_grid();
    let (_, p) = loop_subdivide(&mesh, &flat, 1).unwrap();
    // Vertex 0 is the corner (0, 0) with boundary neighbours 1 = (1, 0) and 7 = (0, 1).
    let corner = p[0];
    let want = (flat[0] * 6.0 + flat[1] + flat[7]) / 8.0;
    assert!((corner - want).length() < 1e-15, "{corner} vs {want}");
    assert!(corner.x > 0.0 && corner.y > 0.0);
}

#[test]
fn sqrt3_keeps_the_boundary_on_even_steps_and_trisects_it_on_odd_steps() {
    let (mesh, flat, bumped) = bumpy_grid();
    let (one, after_one) = sqrt3_subdivide(&mesh, &bumped, 1).unwrap();
    for v in mesh.vertices().filter(|&v| mesh.is_boundary_vertex(v)) {
        assert_eq!(
            after_one[v.index()],
            bumped[v.index()],
            "{v}: even steps fix the boundary"
        );
    }
    assert_eq!(one.n_boundary_halfedges(), mesh.n_boundary_halfedges());
    let (two, after_two) = sqrt3_subdivide(&mesh, &bumped, 2).unwrap();
    assert_eq!(two.n_boundary_halfedges(), 3 * mesh.n_boundary_halfedges());
    // On a straight boundary side the odd-step rules reproduce the line and space the
    // new points evenly: (1 + 16 * 2 + 10 * 3) / 27 etc. of equally spaced points.
    let (_, flat_two) = sqrt3_subdivide(&mesh, &flat, 2).unwrap();
    for v in two.vertices().filter(|&v| two.is_boundary_vertex(v)) {
        assert_eq!(after_two[v.index()].z, 0.0, "{v}");
        assert_eq!(flat_two[v.index()].z, 0.0, "{v}");
    }
}

#[test]
fn the_result_does_not_depend_on_the_number_of_threads() {
    let p = beltrami_testkit::fixtures::noisy_icosphere();
    let mesh = p.mesh().unwrap();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| Scheme::ALL.map(|s| s.subdivide(&mesh, &p.positions, 2).unwrap()))
    };
    let one = run(1);
    let four = run(4);
    for (a, b) in one.iter().zip(&four) {
        assert_eq!(a.0, b.0);
        assert!(
            a.1.iter()
                .zip(&b.1)
                .all(|(x, y)| x.to_array().map(f64::to_bits) == y.to_array().map(f64::to_bits))
        );
    }
}

#[test]
fn errors_name_the_problem() {
    let quads = primitives::cube_quads();
    let mesh = quads.mesh().unwrap();
    let err = loop_subdivide(&mesh, &quads.positions, 1).unwrap_err();
    assert_eq!(err, SubdivisionError::NotTriangle { face: 0, len: 4 });
    assert_eq!(
        err.to_string(),
        "face 0 has 4 vertices; subdivision needs a triangle mesh"
    );

    // A mixed mesh names its first non-triangle.
    let mixed = HalfedgeMesh::from_polygons(5, [&[0u32, 1, 2][..], &[0, 2, 3, 4]]).unwrap();
    let err = sqrt3_subdivide(&mixed, &[DVec3::ZERO; 5], 1).unwrap_err();
    assert_eq!(err, SubdivisionError::NotTriangle { face: 1, len: 4 });

    let tet = primitives::tetrahedron();
    let mesh = tet.mesh().unwrap();
    let err = sqrt3_subdivide(&mesh, &tet.positions[..3], 1).unwrap_err();
    assert_eq!(
        err,
        SubdivisionError::PositionCount {
            positions: 3,
            vertices: 4
        }
    );

    let err = loop_subdivide(&mesh, &tet.positions, 20).unwrap_err();
    assert!(
        matches!(
            err,
            SubdivisionError::TooLarge {
                scheme: "loop",
                steps: 20,
                kind: "vertices",
                ..
            }
        ),
        "{err:?}"
    );
    let err = sqrt3_subdivide(&mesh, &tet.positions, 500).unwrap_err();
    // A saturated count is not printed as if it were exact.
    assert!(
        err.to_string()
            .contains("would make more than 18446744073709551614"),
        "{err}"
    );
    assert!(
        matches!(
            err,
            SubdivisionError::TooLarge {
                count: u64::MAX,
                ..
            }
        ),
        "{err:?}"
    );
}

/// The size check both the command and the Python package run before subdividing:
/// the bytes per face of the result against a budget, and the most steps that fit.
#[test]
fn the_size_check_finds_the_most_steps_that_fit() {
    let tet = primitives::tetrahedron();
    let mesh = tet.mesh().unwrap();
    // After 1, 2, 3 steps, Loop: 16, 64, 256 faces; √3: 12, 36, 108.
    let per = Scheme::BYTES_PER_FACE;
    assert!(Scheme::Loop.fits(&mesh, 2, Some(64 * per), 0));
    assert!(!Scheme::Loop.fits(&mesh, 2, Some(64 * per - 1), 0));
    assert!(!Scheme::Loop.fits(&mesh, 2, Some(64 * per), 1));
    assert_eq!(
        Scheme::Loop.most_steps_that_fit(&mesh, 10, Some(64 * per), 0),
        2
    );
    assert_eq!(
        Scheme::Sqrt3.most_steps_that_fit(&mesh, 10, Some(108 * per), 0),
        3
    );
    // No budget: only the element limit, which 14 Loop steps pass (4·4¹⁴ faces, three
    // halfedges each, under u32::MAX) and 15 do not.
    assert!(Scheme::Loop.fits(&mesh, 14, None, 0));
    assert!(!Scheme::Loop.fits(&mesh, 20, None, 0));
    assert_eq!(Scheme::Loop.most_steps_that_fit(&mesh, 40, None, 0), 14);
    // Nothing fits: 0.
    assert_eq!(Scheme::Loop.most_steps_that_fit(&mesh, 5, Some(0), 0), 0);
}

#[test]
fn zero_steps_return_the_input() {
    let tet = primitives::tetrahedron();
    let mesh = tet.mesh().unwrap();
    for scheme in Scheme::ALL {
        let (m, p) = scheme.subdivide(&mesh, &tet.positions, 0).unwrap();
        assert_eq!(m, mesh);
        assert_eq!(p, tet.positions);
        assert_eq!(Scheme::from_name(scheme.name()), Some(scheme));
    }
    assert_eq!(Scheme::from_name("butterfly"), None);
}

/// The face list a Loop step documents: face `f` with vertices `[a, b, c]` (its halfedge
/// `h0` ends at `a`, `h1 = next(h0)` at `b`, `h2` at `c`) becomes `[a, ab, ca]`,
/// `[b, bc, ab]`, `[c, ca, bc]`, `[ab, bc, ca]`, the point of edge `e` being vertex
/// `n_vertices + e`.
fn documented_loop_faces(mesh: &HalfedgeMesh) -> Vec<[u32; 3]> {
    let point = |h: beltrami_halfedge::HalfedgeId| (mesh.n_vertices() + h.edge().index()) as u32;
    mesh.faces()
        .flat_map(|f| {
            let h0 = mesh.face_halfedge(f);
            let h1 = mesh.next(h0);
            let h2 = mesh.next(h1);
            let [a, b, c] = [h0, h1, h2].map(|h| mesh.to_vertex(h).raw());
            let (ab, bc, ca) = (point(h1), point(h2), point(h0));
            [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        })
        .collect()
}

/// `p` with isolated vertices: one before vertex 0, one after every `stride`-th
/// vertex and one at the end.
fn with_isolated_vertices(p: &Primitive, stride: u32) -> Primitive {
    let new_id = |v: u32| v + v / stride + 1;
    let n = p.positions.len() as u32;
    let mut positions = vec![DVec3::splat(7.0); new_id(n - 1) as usize + 2];
    for (v, &x) in (0..n).zip(&p.positions) {
        positions[new_id(v) as usize] = x;
    }
    let mut faces = beltrami_halfedge::PolygonList::new();
    for f in p.faces.iter() {
        let f: Vec<u32> = f.iter().map(|&v| new_id(v)).collect();
        faces.push(&f);
    }
    Primitive::new(positions, faces)
}

#[test]
fn a_loop_step_equals_building_its_face_list() {
    // The closed-form connectivity of a step must be exactly what the general builder
    // makes of the documented face list: the same edge numbering, halfedge directions,
    // outgoing halfedges, boundary links and face halfedges (HalfedgeMesh: PartialEq).
    let mut cases = meshes();
    cases.push(("icosphere3", primitives::icosphere(3)));
    cases.push(("torus_fine", primitives::torus(3.0, 1.0, 24, 11)));
    cases.extend(beltrami_testkit::fixtures::openmesh_inputs());
    let grid = primitives::grid(6, 4);
    cases.push(("grid_with_isolated", with_isolated_vertices(&grid, 5)));
    let sphere = primitives::icosphere(1);
    cases.push(("sphere_with_isolated", with_isolated_vertices(&sphere, 4)));
    for (name, p) in cases {
        let mut mesh = p.mesh().unwrap();
        let mut positions = p.positions.clone();
        for step in 1..=3 {
            let faces = documented_loop_faces(&mesh);
            let expected =
                HalfedgeMesh::from_polygons(mesh.n_vertices() + mesh.n_edges(), &faces).unwrap();
            let (fine, fine_positions) = loop_subdivide(&mesh, &positions, 1).unwrap();
            assert!(
                fine == expected,
                "{name}, step {step}: the connectivity differs"
            );
            // Several steps at once are the same as one at a time.
            let (at_once, at_once_positions) =
                loop_subdivide(&p.mesh().unwrap(), &p.positions, step).unwrap();
            assert!(at_once == fine, "{name}, {step} steps at once");
            assert_eq!(
                at_once_positions, fine_positions,
                "{name}, {step} steps at once"
            );
            mesh = fine;
            positions = fine_positions;
        }
    }
}
