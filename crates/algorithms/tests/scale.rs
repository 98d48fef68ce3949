//! Remeshing, decimation and hole filling give the same result at any size: a mesh
//! multiplied by a power of two `2^k` gives the unit-size result times `2^k`, bit for bit
//! (vertices, faces and every length of the report), from `2^-1000` to `2^1000`. The
//! reference meshes are not at the size the runs scale to (their largest coordinate
//! outside `[1, 2)`: 0.6, 0.7, 3), so that the runs at `2^k` times their size, brought
//! to `[1, 2)`, are computed at another size than the reference's and the comparison
//! holds the algorithms themselves to exact scaling, not only the scaling around them.
//! Without the runs' own scaling these failed from about `2^±100` on (decimation changed
//! its result, then collapsed nothing; remeshing called a small sphere flat and refused a
//! large one; hole filling filled nothing).

use beltrami_algorithms::{
    DecimateOptions, DecimateReport, FillOptions, FillReport, RemeshError, RemeshOptions,
    RemeshReport, decimate, fill_holes, mesh_quality, remesh, remesh_with_feature_edges,
};
use beltrami_halfedge::{DVec3, HalfedgeMesh, MeshData, PolygonList, primitives};
use beltrami_testkit::fixtures::jittered_icosphere;

/// The exponents tried: inside and outside the range a mesh is used at its own size
/// (`2^-40..=2^40`), up to where the unit sphere's coordinates stay normal numbers.
const POWERS: [i32; 10] = [-1000, -600, -300, -100, -41, 41, 100, 300, 600, 1000];

fn scaled(x: &[DVec3], s: f64) -> Vec<DVec3> {
    x.iter().map(|&p| p * s).collect()
}

fn faces(mesh: &HalfedgeMesh) -> Vec<[u32; 3]> {
    mesh.faces()
        .map(|f| mesh.triangle_vertices(f).map(|v| v.raw()))
        .collect()
}

/// The same faces, and positions that are `base`'s times `s` to the bit.
fn assert_same_result(
    what: &str,
    (mesh, x): (&HalfedgeMesh, &[DVec3]),
    (base, y): (&HalfedgeMesh, &[DVec3]),
    s: f64,
) {
    assert_eq!(faces(mesh), faces(base), "{what}: faces");
    assert_eq!(x, scaled(y, s), "{what}: positions");
}

/// The level-3 icosphere, every coordinate jittered by up to a fifth of an edge, at
/// 0.6 of its size (largest coordinate 0.61: run at twice that when scaled).
fn sphere() -> (HalfedgeMesh, Vec<DVec3>) {
    let sphere = jittered_icosphere(3);
    let x = scaled(&sphere.positions, 0.6);
    assert!((0.5..1.0).contains(&largest(&x)));
    (sphere.mesh().unwrap(), x)
}

fn largest(x: &[DVec3]) -> f64 {
    x.iter().map(|p| p.abs().max_element()).fold(0.0, f64::max)
}

fn remesh_lengths(r: &RemeshReport) -> [f64; 5] {
    [
        r.target_edge_length,
        r.mean_edge_length_before,
        r.mean_edge_length,
        r.hausdorff,
        r.hausdorff_from_input,
    ]
}

fn remesh_counts(r: &RemeshReport) -> [usize; 8] {
    [
        r.splits,
        r.collapses,
        r.flips,
        r.vertices,
        r.faces,
        r.feature_edges,
        r.corners,
        r.degenerate_faces,
    ]
}

#[test]
fn remeshing_gives_the_same_result_at_any_size() {
    let (mesh, x) = sphere();
    let cube = primitives::cube();
    let cube_mesh = cube.mesh().unwrap();
    // At three times its size (largest coordinate 3: run at half that when scaled).
    let cube_x = scaled(&cube.positions, 3.0);
    let cases: [(&str, &HalfedgeMesh, &[DVec3], RemeshOptions); 5] = [
        ("default", &mesh, &x, RemeshOptions::default().iterations(3)),
        ("faceted", &mesh, &x, {
            let mut o = RemeshOptions::default().iterations(3);
            o.smooth_projection = false;
            o
        }),
        (
            "absolute length",
            &mesh,
            &x,
            RemeshOptions::default().edge_length(0.2).iterations(3),
        ),
        (
            "adaptive",
            &mesh,
            &x,
            RemeshOptions::default()
                .adaptive(0.05, 0.4, 0.004)
                .iterations(3),
        ),
        (
            "cube with features",
            &cube_mesh,
            &cube_x,
            RemeshOptions::default()
                .edge_length(0.9)
                .feature_angle(45f64.to_radians())
                .iterations(3),
        ),
    ];
    for (name, mesh, x, options) in cases {
        let (base, y, report) = remesh(mesh, x, &options).unwrap();
        assert!(report.splits + report.collapses > 0, "{name}: remeshed");
        for k in POWERS {
            let s = 2f64.powi(k);
            let o = match options.edge_length {
                beltrami_algorithms::EdgeLength::Absolute(l) => options.edge_length(l * s),
                beltrami_algorithms::EdgeLength::Adaptive(a) => options.adaptive(
                    a.min_edge.unwrap() * s,
                    a.max_edge.unwrap() * s,
                    a.approx_error.unwrap() * s,
                ),
                _ => options,
            };
            let what = format!("{name}, 2^{k}");
            let (out, z, r) =
                remesh(mesh, &scaled(x, s), &o).unwrap_or_else(|e| panic!("{what}: {e}"));
            assert_same_result(&what, (&out, &z), (&base, &y), s);
            assert_eq!(remesh_counts(&r), remesh_counts(&report), "{what}");
            assert_eq!(
                remesh_lengths(&r),
                remesh_lengths(&report).map(|l| l * s),
                "{what}"
            );
            assert_eq!(r.edge_length_cv, report.edge_length_cv, "{what}");
            if let Some(a) = report.adaptive {
                let b = r.adaptive.unwrap();
                assert_eq!(
                    [b.min_edge, b.max_edge, b.approx_error],
                    [a.min_edge * s, a.max_edge * s, a.approx_error * s],
                    "{what}"
                );
            }
        }
    }
    // Given feature edges (indices) need no scaling.
    let line: Vec<[u32; 2]> = mesh
        .edges()
        .map(|e| mesh.edge_vertices(e).map(|v| v.raw()))
        .filter(|[a, b]| x[*a as usize].z.abs() < 0.3 && x[*b as usize].z.abs() < 0.3)
        .take(20)
        .collect();
    let options = RemeshOptions::default().iterations(2);
    let go = |x: &[DVec3]| {
        remesh_with_feature_edges(&mesh, x, &line, &options, |_, _| {
            std::ops::ControlFlow::Continue(())
        })
        .unwrap()
    };
    let (base, y, _) = go(&x);
    for k in [-500, 500] {
        let s = 2f64.powi(k);
        let (out, z, _) = go(&scaled(&x, s));
        assert_same_result(&format!("given edges, 2^{k}"), (&out, &z), (&base, &y), s);
    }
}

/// The errors name lengths in the caller's unit, and the options are checked as given.
#[test]
fn remeshing_errors_name_the_callers_lengths_at_any_size() {
    let (mesh, x) = sphere();
    let s = 2f64.powi(-700);
    let tiny = scaled(&x, s);
    // A target far too short for the surface: the error names the length given.
    let length = 1e-5 * s;
    match remesh(&mesh, &tiny, &RemeshOptions::default().edge_length(length)) {
        Err(RemeshError::TooManyFaces { edge_length, .. }) => assert_eq!(edge_length, length),
        other => panic!("{other:?}"),
    }
    // A target far too long: the surface would shrink or degenerate (the remeshing
    // tests' cases); the lengths are the caller's.
    // A square with a stray collinear triangle beside it fails as degenerate at any
    // length (as in the remeshing tests).
    let flat = MeshData::new(
        vec![
            DVec3::ZERO,
            DVec3::X,
            DVec3::Y,
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(3.0, 0.0, 0.0),
            DVec3::new(4.0, 0.0, 0.0),
            DVec3::new(5.0, 0.0, 0.0),
        ],
        PolygonList::from_triangles(&[[0, 1, 3], [0, 3, 2], [4, 5, 6]]),
    );
    let (mut shrunk, mut degenerate) = (0, 0);
    for (surface, size, length) in [
        (primitives::icosphere(2), 0.7, 3.5),
        (primitives::torus(1.0, 0.4, 24, 12), 0.7, 3.5),
        (flat, 1.0, 0.05),
    ] {
        let m = surface.mesh().unwrap();
        let x = scaled(&surface.positions, size);
        let unit = remesh(&m, &x, &RemeshOptions::default().edge_length(length));
        let small = remesh(
            &m,
            &scaled(&x, s),
            &RemeshOptions::default().edge_length(length * s),
        );
        match (unit, small) {
            (
                Err(RemeshError::Shrunk {
                    extent: e1,
                    diagonal: d1,
                    edge_length: l1,
                }),
                Err(RemeshError::Shrunk {
                    extent: e2,
                    diagonal: d2,
                    edge_length: l2,
                }),
            ) => {
                assert_eq!([e2, d2, l2], [e1 * s, d1 * s, l1 * s]);
                shrunk += 1;
            }
            (
                Err(RemeshError::Degenerate {
                    edge_length: l1,
                    diagonal: d1,
                    faces: f1,
                    ..
                }),
                Err(RemeshError::Degenerate {
                    edge_length: l2,
                    diagonal: d2,
                    faces: f2,
                    ..
                }),
            ) => {
                assert_eq!((f2, [l2, d2]), (f1, [l1 * s, d1 * s]));
                degenerate += 1;
            }
            (Ok((a, x, _)), Ok((b, y, _))) => assert_same_result("coarse", (&b, &y), (&a, &x), s),
            other => panic!("{other:?}"),
        }
    }
    assert!(
        shrunk > 0 && degenerate > 0,
        "shrunk {shrunk}, degenerate {degenerate}"
    );
    // A length whose run value is subnormal is still named as given.
    let huge = scaled(&x, 2f64.powi(1000));
    match remesh(&mesh, &huge, &RemeshOptions::default().edge_length(1e-10)) {
        Err(RemeshError::TooManyFaces { edge_length, .. }) => assert_eq!(edge_length, 1e-10),
        other => panic!("{other:?}"),
    }
    // The checks come in the same order at any size: a pair that is no edge is named
    // before the options' length.
    let bad = RemeshOptions::default().edge_length(-1.0);
    let no_edge = |x: &[DVec3]| {
        remesh_with_feature_edges(&mesh, x, &[[0, 1_000_000]], &bad, |_, _| {
            std::ops::ControlFlow::Continue(())
        })
        .map(|_| ())
    };
    assert!(matches!(no_edge(&x), Err(RemeshError::FeatureEdge { .. })));
    assert_eq!(no_edge(&tiny), no_edge(&x));
    // A length that is no length is refused with the value given, not a scaled one.
    let message = remesh(&mesh, &tiny, &RemeshOptions::default().edge_length(-2.5))
        .unwrap_err()
        .to_string();
    assert!(message.contains("got -2.5"), "{message}");
    // A positive length whose scaled value would overflow is still a length: far
    // beyond the surface's extent it is capped as at unit size.
    let options = RemeshOptions::default().edge_length(1e300).iterations(1);
    let (base, y, unit) = remesh(&mesh, &x, &options).unwrap();
    let s = 2f64.powi(-1000);
    let (out, z, report) = remesh(&mesh, &scaled(&x, s), &options).unwrap();
    assert_same_result("1e300 at 2^-1000", (&out, &z), (&base, &y), s);
    assert_eq!(report.target_edge_length, 1e300);
    assert_eq!(unit.target_edge_length, 1e300);
}

fn decimate_lengths(r: &DecimateReport) -> [f64; 6] {
    [
        r.max_quadric_error,
        r.fit_rms_before,
        r.fit_rms_after,
        r.hausdorff,
        r.hausdorff_to_input,
        r.hausdorff_from_input,
    ]
}

#[test]
fn decimation_gives_the_same_result_at_any_size() {
    let (mesh, x) = sphere();
    let bounded = |e: f64, d: f64| {
        DecimateOptions::default()
            .ratio(0.1)
            .max_error(e)
            .max_distance(d)
    };
    let cases = [
        ("default", DecimateOptions::default().ratio(0.2), None),
        // Bounds that stop the run before its target: unscaled they would stop it
        // elsewhere.
        ("bounded", bounded(0.004, 0.02), Some((0.004, 0.02))),
    ];
    for (name, options, bounds) in cases {
        let (base, y, report) = decimate(&mesh, &x, &options).unwrap();
        assert!(report.collapses > 0 && report.distance_measured, "{name}");
        if bounds.is_some() {
            assert!(!report.target_reached, "{name}: the bounds stop it");
        }
        for k in POWERS {
            let s = 2f64.powi(k);
            let o = bounds.map_or(options, |(e, d)| bounded(e * s, d * s));
            let what = format!("{name}, 2^{k}");
            let (out, z, r) =
                decimate(&mesh, &scaled(&x, s), &o).unwrap_or_else(|e| panic!("{what}: {e}"));
            assert_same_result(&what, (&out, &z), (&base, &y), s);
            assert_eq!(
                (r.collapses, r.flips, r.fit_rounds, r.refused, r.stop),
                (
                    report.collapses,
                    report.flips,
                    report.fit_rounds,
                    report.refused,
                    report.stop
                ),
                "{what}"
            );
            assert_eq!(
                decimate_lengths(&r),
                decimate_lengths(&report).map(|l| l * s),
                "{what}"
            );
            // Measured afterwards, at the caller's size.
            let mut later = DecimateReport::default();
            later
                .measure_distance((&mesh, &scaled(&x, s)), (&out, &z))
                .unwrap();
            assert_eq!(later.hausdorff, report.hausdorff * s, "{what}");
        }
    }
    // Positions that do not match the mesh are refused, far from unit size too.
    let mut longer = scaled(&x, 2f64.powi(300));
    longer.push(DVec3::ZERO);
    let (out, y, _) = decimate(&mesh, &x, &DecimateOptions::default().ratio(0.3)).unwrap();
    let mut later = DecimateReport::default();
    assert!(
        later
            .measure_distance((&mesh, &longer), (&out, &y))
            .is_err()
    );
}

/// The sphere of [`sphere`] (before its scaling to 0.6) with its caps above `z = 0.75`
/// and below `z = -0.8` cut off, at 0.6 of its size.
fn holed_sphere() -> (HalfedgeMesh, Vec<DVec3>) {
    let sphere = jittered_icosphere(3);
    let kept: Vec<[u32; 3]> = sphere
        .faces
        .iter()
        .filter(|f| {
            f.iter().all(|&v| {
                let z = sphere.positions[v as usize].z;
                (-0.8..0.75).contains(&z)
            })
        })
        .map(|f| [f[0], f[1], f[2]])
        .collect();
    let data = MeshData::new(sphere.positions.clone(), PolygonList::from_triangles(&kept));
    let (mesh, x) = (data.mesh().unwrap(), scaled(&data.positions, 0.6));
    assert_eq!(mesh.boundary_loops().count(), 2);
    (mesh, x)
}

fn fill_lengths(r: &FillReport) -> Vec<[f64; 2]> {
    r.filled.iter().map(|h| [h.perimeter, h.area]).collect()
}

#[test]
fn hole_filling_gives_the_same_result_at_any_size() {
    let (mesh, x) = holed_sphere();
    for (name, options) in [
        ("default", FillOptions::default().fill_all(true)),
        ("one loop left open", FillOptions::default()),
        (
            "harmonic",
            FillOptions::default().fill_all(true).fair_order(1),
        ),
    ] {
        let (base, y, report) = fill_holes(&mesh, &x, &options).unwrap();
        assert!(report.vertices_added > 0, "{name}");
        for k in POWERS {
            let s = 2f64.powi(k);
            let what = format!("{name}, 2^{k}");
            let (out, z, r) = fill_holes(&mesh, &scaled(&x, s), &options)
                .unwrap_or_else(|e| panic!("{what}: {e}"));
            assert_same_result(&what, (&out, &z), (&base, &y), s);
            assert_eq!(
                (r.loops, r.faces_added, r.vertices_added, r.skipped.len()),
                (
                    report.loops,
                    report.faces_added,
                    report.vertices_added,
                    report.skipped.len()
                ),
                "{what}"
            );
            let expected: Vec<[f64; 2]> = fill_lengths(&report)
                .iter()
                .map(|[p, a]| [p * s, a * s * s])
                .collect();
            assert_eq!(fill_lengths(&r), expected, "{what}");
            let perimeters =
                |r: &FillReport| -> Vec<f64> { r.skipped.iter().map(|h| h.perimeter).collect() };
            assert_eq!(
                perimeters(&r),
                perimeters(&report)
                    .iter()
                    .map(|p| p * s)
                    .collect::<Vec<_>>(),
                "{what}"
            );
        }
    }
}

#[test]
fn quality_figures_are_the_same_at_any_size() {
    use beltrami_algorithms::flipped_faces;
    let (mesh, x) = sphere();
    let unit = mesh_quality(&mesh, &x).unwrap();
    let mut moved = x.clone();
    moved[5] = -moved[5];
    let flipped = flipped_faces(&mesh, &moved, &x).unwrap();
    assert!(flipped > 0);
    for k in POWERS {
        let s = 2f64.powi(k);
        let q = mesh_quality(&mesh, &scaled(&x, s)).unwrap();
        let (a, b) = (q.edge_length.unwrap(), unit.edge_length.unwrap());
        assert_eq!(
            [a.min, a.mean, a.max],
            [b.min * s, b.mean * s, b.max * s],
            "2^{k}"
        );
        assert_eq!(a.cv, b.cv, "2^{k}");
        assert_eq!(q.shape, unit.shape, "2^{k}");
        assert_eq!(
            (
                q.degenerate_faces,
                q.negative_cotangent_edges,
                q.regular_share
            ),
            (
                unit.degenerate_faces,
                unit.negative_cotangent_edges,
                unit.regular_share
            ),
            "2^{k}"
        );
        assert_eq!(
            flipped_faces(&mesh, &scaled(&moved, s), &scaled(&x, s)).unwrap(),
            flipped,
            "2^{k}"
        );
    }
}

/// A stray vertex far away (in no face: a scan's outlier at the machine's origin)
/// does not decide the size a run is computed at: the surface's result is the one
/// without it, at any distance.
#[test]
fn an_isolated_vertex_far_away_changes_nothing() {
    let (mesh, x) = sphere();
    let data = MeshData::new(
        x.iter()
            .copied()
            .chain([DVec3::new(1e20, 0.0, 0.0)])
            .collect(),
        mesh.to_polygons(),
    );
    let stray = data.mesh().unwrap();
    assert_eq!(stray.n_vertices(), mesh.n_vertices() + 1);
    let mut near = data.positions.clone();
    near[x.len()] = DVec3::new(0.25, 0.0, 0.0);
    let options = DecimateOptions::default().ratio(0.2);
    let (a, ya, ra) = decimate(&stray, &data.positions, &options).unwrap();
    let (b, yb, rb) = decimate(&stray, &near, &options).unwrap();
    assert!(ra.collapses > 0);
    assert_eq!(faces(&a), faces(&b));
    let moved = ya.iter().zip(&yb).filter(|(p, q)| p != q).count();
    assert_eq!(moved, 1, "only the stray vertex differs");
    assert_eq!(ra.hausdorff, rb.hausdorff);
    let options = RemeshOptions::default().iterations(2);
    let (a, ya, _) = remesh(&stray, &data.positions, &options).unwrap();
    let (b, yb, _) = remesh(&stray, &near, &options).unwrap();
    assert_eq!(faces(&a), faces(&b));
    let moved = ya.iter().zip(&yb).filter(|(p, q)| p != q).count();
    assert_eq!(moved, 1, "only the stray vertex differs");
    let shape = |y: &[DVec3]| mesh_quality(&stray, y).unwrap().shape;
    assert_eq!(shape(&data.positions), shape(&near));
}

/// A stray point at another magnitude than a surface far from unit size comes back as
/// it was, and the surface's result is still the unit-size one scaled (the run's power
/// of two is lowered so that the stray point stays finite).
#[test]
fn a_stray_point_beside_a_surface_far_from_unit_size_comes_back_as_it_was() {
    let (mesh, x) = sphere();
    let s = 2f64.powi(-990);
    let strays = [DVec3::new(1e10, -3.0, 0.5), DVec3::new(1e-300, 0.0, 0.0)];
    let with = |surface: &[DVec3], strays: &[DVec3]| {
        MeshData::new(
            surface.iter().chain(strays).copied().collect(),
            mesh.to_polygons(),
        )
    };
    let unit = with(&x, &[DVec3::new(0.25, 0.0, 0.0), DVec3::new(0.5, 0.0, 0.0)]);
    let far = with(&scaled(&x, s), &strays);
    let (unit_mesh, far_mesh) = (unit.mesh().unwrap(), far.mesh().unwrap());
    let n = x.len();
    let options = DecimateOptions::default().ratio(0.2);
    let (a, ya, _) = decimate(&unit_mesh, &unit.positions, &options).unwrap();
    let (b, yb, _) = decimate(&far_mesh, &far.positions, &options).unwrap();
    assert_eq!(faces(&a), faces(&b));
    let m = ya.len() - 2;
    assert_eq!(yb[..m], scaled(&ya[..m], s)[..], "decimate: the surface");
    assert_eq!(yb[m..], strays, "decimate: the strays");
    let options = RemeshOptions::default().iterations(2);
    let (a, ya, _) = remesh(&unit_mesh, &unit.positions, &options).unwrap();
    let (b, yb, _) = remesh(&far_mesh, &far.positions, &options).unwrap();
    assert_eq!(faces(&a), faces(&b));
    // The strays keep their order among the vertices kept, before the new ones.
    let isolated: Vec<usize> = (0..yb.len())
        .filter(|&i| b.is_isolated(beltrami_halfedge::VertexId::new(i as u32)))
        .collect();
    assert_eq!(isolated.len(), 2);
    for (i, (p, q)) in yb.iter().zip(&ya).enumerate() {
        if isolated.contains(&i) {
            continue;
        }
        assert_eq!(*p, *q * s, "remesh: surface vertex {i}");
    }
    assert_eq!(
        isolated.iter().map(|&i| yb[i]).collect::<Vec<_>>(),
        strays,
        "remesh: the strays"
    );
    assert_eq!(n + 2, far.positions.len());
    // Hole filling keeps the input's vertices first, the strays among them.
    let (holed, hx) = holed_sphere();
    let data = |surface: &[DVec3], strays: &[DVec3]| {
        MeshData::new(
            surface.iter().chain(strays).copied().collect(),
            holed.to_polygons(),
        )
    };
    let unit = data(
        &hx,
        &[DVec3::new(0.25, 0.0, 0.0), DVec3::new(0.5, 0.0, 0.0)],
    );
    let far = data(&scaled(&hx, s), &strays);
    let options = FillOptions::default().fill_all(true);
    let (a, ya, _) = fill_holes(&unit.mesh().unwrap(), &unit.positions, &options).unwrap();
    let (b, yb, _) = fill_holes(&far.mesh().unwrap(), &far.positions, &options).unwrap();
    assert_eq!(faces(&a), faces(&b));
    let k = hx.len();
    assert_eq!(yb[k..k + 2], strays, "fill-holes: the strays");
    assert_eq!(yb[..k], scaled(&ya[..k], s)[..], "fill-holes: the input");
    assert_eq!(
        yb[k + 2..],
        scaled(&ya[k + 2..], s)[..],
        "fill-holes: the patches"
    );
}

/// Options wrong in a way that scaling to the edge of the range of numbers would hide
/// (two lengths beyond it become one) are still refused as at unit size, and an
/// adaptive run's error names the sizing field's smallest length as at unit size.
#[test]
fn adaptive_lengths_far_from_unit_size_are_checked_and_named_as_given() {
    let (mesh, x) = sphere();
    let s = 1e-300;
    let tiny = scaled(&x, s);
    let swapped = RemeshOptions::default().adaptive(1e300, 1e299, 1e-3);
    for y in [&x, &tiny] {
        let message = remesh(&mesh, y, &swapped).unwrap_err().to_string();
        assert!(message.contains("exceeds the largest"), "{message}");
    }
    // A tolerance so fine that the field's smallest length (the chord of that
    // tolerance, about 7e-5, above the smallest length allowed) makes too many faces.
    let s = 2f64.powi(-700);
    let fine = |s: f64| RemeshOptions::default().adaptive(1e-9 * s, 1e-4 * s, 1e-9 * s);
    let length = |y: &[DVec3], o: &RemeshOptions| match remesh(&mesh, y, o) {
        Err(RemeshError::TooManyFaces { edge_length, .. }) => edge_length,
        other => panic!("{other:?}"),
    };
    let unit = length(&x, &fine(1.0));
    assert!(
        unit > 1e-6,
        "the field's smallest, not the smallest allowed: {unit}"
    );
    assert_eq!(length(&scaled(&x, s), &fine(s)), unit * s);
}

/// The sphere of [`sphere`] with a cap (vertex 2 of face 10 moved onto the midpoint of
/// the face's other two) and a needle (the vertices of face 40's first edge 1e-14 of
/// their distance apart).
fn flawed_sphere() -> (HalfedgeMesh, Vec<DVec3>) {
    let (mesh, mut x) = sphere();
    let cap = mesh
        .triangle_vertices(beltrami_halfedge::FaceId::new(10))
        .map(|v| v.index());
    x[cap[2]] = 0.5 * (x[cap[0]] + x[cap[1]]);
    let needle = mesh
        .triangle_vertices(beltrami_halfedge::FaceId::new(40))
        .map(|v| v.index());
    x[needle[1]] = x[needle[0]] + (x[needle[1]] - x[needle[0]]) * 1e-14;
    (mesh, x)
}

#[test]
fn delaunay_flips_and_flat_triangle_removal_give_the_same_result_at_any_size() {
    use beltrami_algorithms::{DelaunayOptions, FlatOptions, delaunay_flip, remove_flat_triangles};
    let (mesh, x) = flawed_sphere();
    let (base, y, report) = delaunay_flip(&mesh, &x, DelaunayOptions::default()).unwrap();
    assert!(report.flips > 0 && report.max_deviation > 0.0);
    for k in POWERS.into_iter().chain([1020]) {
        let s = 2f64.powi(k);
        let (out, z, r) = delaunay_flip(&mesh, &scaled(&x, s), DelaunayOptions::default()).unwrap();
        assert_same_result(&format!("delaunay, 2^{k}"), (&out, &z), (&base, &y), s);
        assert_eq!(
            (
                r.flips,
                r.negative_before,
                r.negative_after,
                r.max_deviation
            ),
            (
                report.flips,
                report.negative_before,
                report.negative_after,
                report.max_deviation * s
            ),
            "delaunay, 2^{k}"
        );
    }
    // A longest move that takes the needle (its edge about 1e-15 long), scaled with the
    // mesh. (The flatness test and the edits scale exactly without a scaled run: no
    // product of four coordinates, and the cotangents are not used.)
    let options = |s: f64| FlatOptions::default().max_move(1e-13 * s);
    let (base, y, report) = remove_flat_triangles(&mesh, &x, options(1.0)).unwrap();
    assert!(report.flips > 0 && report.collapses > 0, "{report:?}");
    // Up to coordinates of 1e307, whose squares overflow.
    for k in POWERS.into_iter().chain([1020]) {
        let s = 2f64.powi(k);
        let (out, z, r) = remove_flat_triangles(&mesh, &scaled(&x, s), options(s)).unwrap();
        assert_same_result(&format!("flat, 2^{k}"), (&out, &z), (&base, &y), s);
        assert_eq!(
            (
                r.flat_before,
                r.flat_after,
                r.flips,
                r.collapses,
                &r.vertex_origin
            ),
            (
                report.flat_before,
                report.flat_after,
                report.flips,
                report.collapses,
                &report.vertex_origin
            ),
            "flat, 2^{k}"
        );
        assert_eq!(
            [r.max_move, r.max_height],
            [report.max_move * s, report.max_height * s],
            "flat, 2^{k}"
        );
    }
}

/// A stray point beyond the closest-point index's range (1e60) beside a surface at its
/// own size is held aside as well: remeshing, decimation and the Delaunay flips run, and
/// it comes back as it was. The algorithms that keep input positions keep their bits
/// even where a scaled run rounds them (a coordinate subnormal at the run's size).
#[test]
fn stray_points_far_away_and_tiny_coordinates_keep_their_bits() {
    use beltrami_algorithms::{DelaunayOptions, delaunay_flip};
    let (mesh, x) = flawed_sphere();
    let stray = DVec3::new(1e70, 0.0, -1e70);
    let data = MeshData::new(
        x.iter().copied().chain([stray]).collect(),
        mesh.to_polygons(),
    );
    let m = data.mesh().unwrap();
    let (_, y, _) = remesh(&m, &data.positions, &RemeshOptions::default().iterations(1)).unwrap();
    assert!(y.contains(&stray));
    let (out, y, report) =
        decimate(&m, &data.positions, &DecimateOptions::default().ratio(0.3)).unwrap();
    assert!(y.contains(&stray));
    // Measured afterwards as the command does, the same distance.
    let mut later = DecimateReport::default();
    later
        .measure_distance((&m, &data.positions), (&out, &y))
        .unwrap();
    assert_eq!(later.hausdorff, report.hausdorff);
    let (_, y, r) = delaunay_flip(&m, &data.positions, DelaunayOptions::default()).unwrap();
    assert!(r.flips > 0);
    assert_eq!(y, data.positions);
    // A surface at 2^1000 with a coordinate near zero, subnormal at the run's size.
    let s = 2f64.powi(1000);
    let mut far = scaled(&x, s);
    far[0].y = 1e-300;
    let (_, y, _) = delaunay_flip(&mesh, &far, DelaunayOptions::default()).unwrap();
    assert_eq!(y, far);
    let (holed, hx) = holed_sphere();
    let mut far = scaled(&hx, s);
    far[0].y = 1e-300;
    let (_, y, r) = fill_holes(&holed, &far, &FillOptions::default().fill_all(true)).unwrap();
    assert!(r.vertices_added > 0);
    assert_eq!(y[..far.len()], far[..]);
}
