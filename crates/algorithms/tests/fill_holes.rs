//! Hole filling: holes cut into closed surfaces close again into a valid mesh of the
//! same topology; refinement matches the rim's density; fairing brings the patch close
//! to the true sphere; the input's vertices keep their ids and bits; the outer boundary
//! of an open surface stays open; skipped loops are reported with the reason; bad
//! input is refused with a typed error.

use beltrami_algorithms::{
    FairWeights, FillError, FillOptions, FillReport, SkipReason, fill_hole, fill_holes,
    fill_holes_with_progress,
};
use beltrami_halfedge::{DVec3, EditMesh, HalfedgeMesh, MeshData, VertexId, primitives};
use beltrami_surfaces::{FLensParams, flens};
use proptest::prelude::*;

/// The mesh of `data` without the faces `cut` selects, its vertices renumbered in their
/// order with those left without a face dropped.
fn cut(
    data: &MeshData,
    drop_face: impl Fn(&[u32], &[DVec3]) -> bool,
) -> (HalfedgeMesh, Vec<DVec3>) {
    let kept: Vec<&[u32]> = data
        .faces
        .iter()
        .filter(|f| !drop_face(f, &data.positions))
        .collect();
    let mut new_id = vec![u32::MAX; data.positions.len()];
    for f in &kept {
        for &v in *f {
            new_id[v as usize] = 0;
        }
    }
    let mut positions = Vec::new();
    for (i, id) in new_id.iter_mut().enumerate() {
        if *id == 0 {
            *id = positions.len() as u32;
            positions.push(data.positions[i]);
        }
    }
    let faces: Vec<Vec<u32>> = kept
        .iter()
        .map(|f| f.iter().map(|&v| new_id[v as usize]).collect())
        .collect();
    let mesh = HalfedgeMesh::from_polygons(positions.len(), &faces).unwrap();
    (mesh, positions)
}

/// The vertices within `k` rings of `center`.
fn ring(data: &MeshData, center: u32, k: usize) -> Vec<u32> {
    let mut set = vec![center];
    for _ in 0..k {
        let mut next = set.clone();
        for f in data.faces.iter() {
            if f.iter().any(|v| set.contains(v)) {
                next.extend_from_slice(f);
            }
        }
        next.sort_unstable();
        next.dedup();
        set = next;
    }
    set
}

/// Faces with a vertex strictly inside the `k`-ring of `center` are cut: the hole's rim
/// is the `k`-ring's outer circle.
fn cut_ring(data: &MeshData, center: u32, k: usize) -> (HalfedgeMesh, Vec<DVec3>) {
    let inner = ring(data, center, k - 1);
    cut(data, |f, _| f.iter().any(|v| inner.contains(v)))
}

fn all() -> FillOptions {
    FillOptions::default().fill_all(true)
}

/// The checks every filled closed surface passes.
fn assert_closed_like(
    open: &HalfedgeMesh,
    x: &[DVec3],
    out: &HalfedgeMesh,
    y: &[DVec3],
    euler: i64,
    report: &FillReport,
) {
    out.check_integrity().unwrap();
    assert!(out.is_closed());
    assert_eq!(out.euler_characteristic(), euler);
    // The input's vertices keep their ids and bits; new ones are appended.
    assert_eq!(&y[..x.len()], x);
    assert_eq!(y.len(), x.len() + report.vertices_added);
    assert_eq!(out.n_faces(), open.n_faces() + report.faces_added);
    // The input's faces keep their ids and corners.
    let (a, b) = (open.to_polygons(), out.to_polygons());
    for f in 0..open.n_faces() {
        assert_eq!(a.get(f), b.get(f));
    }
    assert!(y.iter().all(|p| p.is_finite()));
}

/// The largest distance of the new vertices from the unit sphere.
fn off_sphere(x: &[DVec3], y: &[DVec3]) -> f64 {
    y[x.len()..]
        .iter()
        .map(|p| (p.length() - 1.0).abs())
        .fold(0.0, f64::max)
}

#[test]
fn a_ring_hole_in_a_sphere_closes_with_the_sphere_topology() {
    let ico = primitives::icosphere(3);
    let (open, x) = cut_ring(&ico, 0, 2);
    assert_eq!(open.boundary_loops().count(), 1);
    let (out, y, report) = fill_holes(&open, &x, &all()).unwrap();
    assert_eq!(report.loops, 1);
    assert_eq!(report.filled.len(), 1);
    assert!(report.skipped.is_empty());
    let hole = &report.filled[0];
    assert!(hole.vertices_added > 0, "refinement adds vertices");
    hole.faced_check();
    assert_closed_like(&open, &x, &out, &y, 2, &report);
    assert_eq!(out.genus(), Some(0));
}

trait FacedCheck {
    fn faced_check(&self);
}

impl FacedCheck for beltrami_algorithms::FilledHole {
    /// A disc of n rim vertices and m interior vertices has n + 2m − 2 triangles.
    fn faced_check(&self) {
        assert_eq!(
            self.faces_added,
            self.boundary_edges + 2 * self.vertices_added - 2
        );
        assert!(self.area > 0.0 && self.perimeter > 0.0);
    }
}

#[test]
fn a_hole_in_a_torus_closes_with_genus_one() {
    let torus = primitives::torus(3.0, 1.0, 24, 12);
    let (open, x) = cut_ring(&torus, 40, 2);
    let (out, y, report) = fill_holes(&open, &x, &all()).unwrap();
    assert_eq!(report.filled.len(), 1);
    report.filled[0].faced_check();
    assert_closed_like(&open, &x, &out, &y, 0, &report);
    assert_eq!(out.genus(), Some(1));
}

#[test]
fn refinement_matches_the_rim_density() {
    let ico = primitives::icosphere(4);
    let (open, x) = cut(&ico, |f, p| f.iter().all(|&v| p[v as usize].z > 0.75));
    let (out, y, report) = fill_holes(&open, &x, &all()).unwrap();
    let hole = &report.filled[0];
    let rim = hole.perimeter / hole.boundary_edges as f64;
    // The patch's edges: those with a new end or not in the input.
    let mut sum = 0.0;
    let mut count = 0_usize;
    for e in out.edges() {
        let h = e.halfedge(0);
        let (a, b) = (out.from_vertex(h), out.to_vertex(h));
        let new =
            a.index() >= x.len() || b.index() >= x.len() || open.find_halfedge(a, b).is_none();
        if new {
            sum += y[a.index()].distance(y[b.index()]);
            count += 1;
        }
    }
    let mean = sum / count as f64;
    assert!(count > 3 * hole.boundary_edges, "{count} patch edges");
    assert!(
        (mean / rim - 1.0).abs() < 0.3,
        "patch mean edge {mean} vs rim {rim}"
    );
    // Without refinement: the bare triangulation, long chords across the hole.
    let (_, _, bare) = fill_holes(&open, &x, &all().refine(false)).unwrap();
    assert_eq!(bare.vertices_added, 0);
    assert_eq!(bare.faces_added, hole.boundary_edges - 2);
}

#[test]
fn fairing_brings_the_patch_to_the_sphere() {
    let ico = primitives::icosphere(4);
    let (open, x) = cut(&ico, |f, p| f.iter().all(|&v| p[v as usize].z > 0.75));
    let (out, faired, report) = fill_holes(&open, &x, &all()).unwrap();
    assert_eq!(report.filled[0].faired_order, Some(2));
    assert!(!report.filled[0].fair_fallback);
    let (flat_mesh, flat, flat_report) = fill_holes(&open, &x, &all().fair(false)).unwrap();
    assert_eq!(flat_report.filled[0].faired_order, None);
    // The same refinement either way: fairing only moves the new vertices.
    assert_eq!(flat_mesh.to_polygons(), out.to_polygons());
    let (d_faired, d_flat) = (off_sphere(&x, &faired), off_sphere(&x, &flat));
    // The cap's height is 1 − 0.75 = 0.25: the flat patch is nearly that far inside.
    // The thin plate is not a sphere, but follows it to a tenth of that.
    assert!(d_flat > 0.15, "flat patch {d_flat}");
    assert!(d_faired < 0.04, "faired patch {d_faired}");
    assert!(d_faired < d_flat / 5.0);
    // The membrane (k = 1) only continues the rim's position, not its tangent plane:
    // on a planar rim it stays close to flat, worse than the thin plate.
    let (_, membrane, _) = fill_holes(&open, &x, &all().fair_order(1)).unwrap();
    let d_membrane = off_sphere(&x, &membrane);
    assert!(d_faired < d_membrane, "{d_membrane}");
    // Uniform weights work too, less exactly on this irregular sampling.
    let uniform = all().fair_weights(FairWeights::Uniform);
    let (_, y, _) = fill_holes(&open, &x, &uniform).unwrap();
    let d_uniform = off_sphere(&x, &y);
    println!(
        "z > 0.75: flat {d_flat}, membrane {d_membrane}, uniform thin plate {d_uniform}, cotangent thin plate {d_faired}"
    );
    assert!(d_uniform < d_flat / 2.0, "{d_uniform}");
}

/// The table of `docs/hole-filling.md`: caps of the unit sphere cut and filled, the
/// largest distance of the new vertices from the sphere with and without fairing.
#[test]
fn sphere_caps_table() {
    let ico = primitives::icosphere(4);
    println!(
        "| cap | rim edges | faces added | vertices added | flat: max distance | faired (k = 2): max distance |"
    );
    println!("|---|---:|---:|---:|---:|---:|");
    for z0 in [0.9, 0.75, 0.5] {
        let (open, x) = cut(&ico, |f, p| f.iter().all(|&v| p[v as usize].z > z0));
        let (_, faired, report) = fill_holes(&open, &x, &all()).unwrap();
        let (_, flat, _) = fill_holes(&open, &x, &all().fair(false)).unwrap();
        let hole = &report.filled[0];
        let (d_faired, d_flat) = (off_sphere(&x, &faired), off_sphere(&x, &flat));
        assert!(d_faired < d_flat / 3.0, "z > {z0}: {d_faired} vs {d_flat}");
        println!(
            "| z > {z0} | {} | {} | {} | {d_flat:.4} | {d_faired:.5} |",
            hole.boundary_edges, hole.faces_added, hole.vertices_added
        );
    }
}

/// A 24 × 12 lens with a round hole in its middle (0.15 of its width across), the
/// lens itself, and the half-width it was measured with.
fn holed_lens() -> (HalfedgeMesh, Vec<DVec3>, MeshData, f64) {
    let lens = flens(&FLensParams {
        nx: 24,
        ny: 12,
        ..FLensParams::default()
    });
    let center =
        lens.positions.iter().fold(DVec3::ZERO, |s, &p| s + p) / lens.positions.len() as f64;
    let half_width = lens
        .positions
        .iter()
        .map(|p| (p.x - center.x).abs())
        .fold(0.0, f64::max);
    let radius = 0.15 * half_width;
    let (open, x) = cut(&lens, |f, p| {
        f.iter().any(|&v| {
            let q = p[v as usize];
            (q.x - center.x).hypot(q.y - center.y) < radius
        })
    });
    (open, x, lens.data, half_width)
}

#[test]
fn the_outer_boundary_of_an_open_surface_stays_open() {
    let (open, x, _, _) = holed_lens();
    assert_eq!(open.boundary_loops().count(), 2);
    let outer_edges = open.boundary_loops().map(|l| l.len()).max().unwrap();
    let (out, y, report) = fill_holes(&open, &x, &FillOptions::default()).unwrap();
    assert_eq!(report.filled.len(), 1);
    assert_eq!(report.skipped.len(), 1);
    assert_eq!(report.skipped[0].reason, SkipReason::OuterBoundary);
    assert_eq!(report.skipped[0].boundary_edges, outer_edges);
    out.check_integrity().unwrap();
    let loops: Vec<usize> = out.boundary_loops().map(|l| l.len()).collect();
    assert_eq!(loops, [outer_edges]);
    assert_eq!(&y[..x.len()], &x[..]);
    // With `fill_all` the outer boundary is closed too: no boundary left.
    let (closed, _, report) =
        fill_holes(&open, &x, &FillOptions::default().fill_all(true)).unwrap();
    assert_eq!(report.filled.len(), 2);
    assert!(closed.is_closed());
}

/// Two open patches side by side, one with a hole and one without: each patch's outer
/// boundary stays open (one per component), and only the hole is filled. With a single
/// "largest loop" for the whole mesh, the second patch's rim was closed into a pillow.
#[test]
fn every_components_outer_boundary_stays_open() {
    let (holed, x, lens, half_width) = holed_lens();
    // The second patch: the whole lens, moved aside by one and a half widths (its rim as
    // long as the first patch's, and longer than that patch's hole).
    let width = 3.0 * half_width;
    let mut faces: Vec<Vec<u32>> = holed
        .faces()
        .map(|f| {
            holed
                .vertices_around_face(f)
                .map(|v| v.index() as u32)
                .collect()
        })
        .collect();
    let offset = x.len() as u32;
    faces.extend(
        lens.faces
            .iter()
            .map(|f| f.iter().map(|&v| v + offset).collect::<Vec<u32>>()),
    );
    let mut positions = x.clone();
    positions.extend(
        lens.positions
            .iter()
            .map(|&p| p + DVec3::new(width, 0.0, 0.0)),
    );
    let two = HalfedgeMesh::from_polygons(positions.len(), &faces).unwrap();
    assert_eq!(two.connected_components().count(), 2);
    let rims: Vec<usize> = two.boundary_loops().map(|l| l.len()).collect();
    assert_eq!(rims.len(), 3);
    let (out, y, report) = fill_holes(&two, &positions, &FillOptions::default()).unwrap();
    out.check_integrity().unwrap();
    assert_eq!(report.filled.len(), 1);
    assert_eq!(report.skipped.len(), 2);
    assert!(
        report
            .skipped
            .iter()
            .all(|s| s.reason == SkipReason::OuterBoundary)
    );
    // The hole filled is the first patch's (the shortest loop); both rims stay open.
    let hole = *rims.iter().min().unwrap();
    assert_eq!(report.filled[0].boundary_edges, hole);
    let mut left: Vec<usize> = out.boundary_loops().map(|l| l.len()).collect();
    let mut rims_left: Vec<usize> = rims.iter().copied().filter(|&l| l != hole).collect();
    left.sort_unstable();
    rims_left.sort_unstable();
    assert_eq!(left, rims_left);
    assert_eq!(out.connected_components().count(), 2);
    assert_eq!(&y[..positions.len()], &positions[..]);
    // `fill_all` closes both rims as well.
    let (closed, _, report) =
        fill_holes(&two, &positions, &FillOptions::default().fill_all(true)).unwrap();
    assert_eq!(report.filled.len(), 3);
    assert!(closed.is_closed());
}

#[test]
fn max_loop_edges_skips_a_big_hole_and_reports_it() {
    let ico = primitives::icosphere(3);
    // Two holes: a 1-ring (5 or 6 edges) and a 2-ring (more), far apart.
    let small = ring(&ico, 0, 0);
    let far = (0..ico.positions.len() as u32)
        .max_by(|&a, &b| {
            let d = |v: u32| ico.positions[v as usize].distance(ico.positions[0]);
            d(a).total_cmp(&d(b))
        })
        .unwrap();
    let big = ring(&ico, far, 1);
    let (open, x) = cut(&ico, |f, _| {
        f.iter().any(|v| small.contains(v) || big.contains(v))
    });
    let sizes: Vec<usize> = open.boundary_loops().map(|l| l.len()).collect();
    assert_eq!(sizes.len(), 2);
    let limit = *sizes.iter().min().unwrap();
    let options = all().max_loop_edges(limit);
    let (out, _, report) = fill_holes(&open, &x, &options).unwrap();
    assert_eq!(report.filled.len(), 1);
    assert_eq!(report.filled[0].boundary_edges, limit);
    assert_eq!(report.skipped.len(), 1);
    assert_eq!(report.skipped[0].reason, SkipReason::TooLarge);
    assert!(report.skipped[0].boundary_edges > limit);
    let left: Vec<usize> = out.boundary_loops().map(|l| l.len()).collect();
    assert_eq!(left, [report.skipped[0].boundary_edges]);
    // By default (no fill_all) the larger is kept as the "outer" boundary instead.
    let (_, _, report) = fill_holes(&open, &x, &FillOptions::default()).unwrap();
    assert_eq!(report.filled.len(), 1);
    assert_eq!(report.skipped[0].reason, SkipReason::OuterBoundary);
}

#[test]
fn a_hole_of_three_edges_becomes_one_triangle() {
    let ico = primitives::icosphere(2);
    // Every face but the fourth.
    let kept: Vec<&[u32]> = ico
        .faces
        .iter()
        .enumerate()
        .filter(|&(i, _)| i != 3)
        .map(|(_, f)| f)
        .collect();
    let open = HalfedgeMesh::from_polygons(ico.positions.len(), &kept).unwrap();
    let (out, y, report) = fill_holes(&open, &ico.positions, &all()).unwrap();
    assert_eq!(report.faces_added, 1);
    assert_eq!(report.vertices_added, 0);
    assert_eq!(y, ico.positions);
    let mut want = ico.faces.get(3).unwrap().to_vec();
    let got = out.to_polygons();
    let mut last = got.get(got.len() - 1).unwrap().to_vec();
    want.sort_unstable();
    last.sort_unstable();
    assert_eq!(last, want);
    assert!(out.is_closed());
}

/// The rim of a lone triangle is a loop of three edges whose only triangulation repeats
/// the triangle: a duplicate face (which `repair` drops), so the loop stays open, with
/// `--all` too, as hole-filling.md says of loops that would duplicate an edge. A
/// triangle on the loop next to two other triangles (a hole, above) still fills.
#[test]
fn the_rim_of_a_lone_triangle_stays_open() {
    let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y];
    let mesh = HalfedgeMesh::from_polygons(3, [&[0u32, 1, 2][..]]).unwrap();
    let (out, y, report) = fill_holes(&mesh, &positions, &all()).unwrap();
    assert_eq!(report.faces_added, 0);
    assert_eq!(out.n_faces(), 1);
    assert_eq!(y, positions);
    assert_eq!(report.skipped.len(), 1);
    assert_eq!(
        report.skipped[0].reason,
        SkipReason::NoManifoldTriangulation
    );
    // Two triangles sharing an edge: their four-edge rim fills without a duplicate.
    let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(1.0, 1.0, 0.2)];
    let mesh = HalfedgeMesh::from_polygons(4, [&[0u32, 1, 2][..], &[1, 3, 2]]).unwrap();
    let (out, _, report) = fill_holes(&mesh, &positions, &all()).unwrap();
    assert!(report.faces_added >= 2, "{report:?}");
    let mut faces: Vec<Vec<u32>> = out
        .to_polygons()
        .iter()
        .map(|f| {
            let mut f = f.to_vec();
            f.sort_unstable();
            f
        })
        .collect();
    let n = faces.len();
    faces.sort();
    faces.dedup();
    assert_eq!(faces.len(), n, "a duplicate face");
}

#[test]
fn filling_is_deterministic() {
    let torus = primitives::torus(3.0, 1.0, 24, 12);
    let (open, x) = cut(&torus, |f, p| {
        f.iter()
            .any(|&v| p[v as usize].x > 3.5 || p[v as usize].y > 3.5)
    });
    let a = fill_holes(&open, &x, &all()).unwrap();
    let b = fill_holes(&open, &x, &all()).unwrap();
    assert_eq!(a.0.to_polygons(), b.0.to_polygons());
    let bits = |y: &[DVec3]| -> Vec<u64> {
        y.iter()
            .flat_map(|p| p.to_array().map(f64::to_bits))
            .collect()
    };
    assert_eq!(bits(&a.1), bits(&b.1));
    assert_eq!(a.2, b.2);
    assert_eq!(a.2.filled.len(), 2);
}

/// The progress closure sees every loop once, in order, and a `Break` stops the run
/// with the typed error; with `Continue` the result is [`fill_holes`]'s.
#[test]
fn a_progress_closure_sees_every_loop_and_can_stop_the_filling() {
    use std::ops::ControlFlow;
    let torus = primitives::torus(3.0, 1.0, 24, 12);
    let (open, x) = cut(&torus, |f, p| {
        f.iter()
            .any(|&v| p[v as usize].x > 3.5 || p[v as usize].y > 3.5)
    });
    let mut seen = Vec::new();
    let watched = fill_holes_with_progress(&open, &x, &all(), |done, total| {
        seen.push((done, total));
        ControlFlow::Continue(())
    })
    .unwrap();
    assert_eq!(seen, [(1, 2), (2, 2)]);
    let plain = fill_holes(&open, &x, &all()).unwrap();
    assert_eq!(watched.0.to_polygons(), plain.0.to_polygons());
    assert_eq!(watched.1, plain.1);
    assert_eq!(watched.2, plain.2);

    let mut calls = 0;
    let err = fill_holes_with_progress(&open, &x, &all(), |done, _| {
        calls += 1;
        if done == 1 {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    })
    .unwrap_err();
    assert_eq!(calls, 1);
    assert_eq!(err, FillError::Stopped { done: 1, total: 2 });
    assert_eq!(
        err.to_string(),
        "hole filling was stopped after 1 of 2 boundary loops"
    );
    // A closed mesh has no loop: the closure is never called.
    let closed = torus.mesh().unwrap();
    fill_holes_with_progress(&closed, &torus.positions, &all(), |_, _| {
        panic!("no loop to report")
    })
    .unwrap();
}

#[test]
fn bad_input_and_options_are_refused_with_a_typed_error() {
    let ico = primitives::icosphere(1);
    let mesh = ico.mesh().unwrap();
    let x = &ico.positions;
    assert!(matches!(
        fill_holes(&mesh, &x[1..], &all()),
        Err(FillError::PositionCount { .. })
    ));
    let mut nan = x.clone();
    nan[5].y = f64::NAN;
    assert_eq!(
        fill_holes(&mesh, &nan, &all()).unwrap_err(),
        FillError::NonFinite { vertex: 5 }
    );
    for options in [
        all().max_loop_edges(2),
        all().fair_order(0),
        all().fair_order(3),
    ] {
        assert!(matches!(
            fill_holes(&mesh, x, &options),
            Err(FillError::Options { .. })
        ));
    }
    let quads = primitives::cube_quads();
    assert!(matches!(
        fill_holes(&quads.mesh().unwrap(), &quads.positions, &all()),
        Err(FillError::NotTriangle { .. })
    ));
    // A closed mesh: nothing to do, the same mesh back.
    let (out, y, report) = fill_holes(&mesh, x, &all()).unwrap();
    assert_eq!((report.loops, report.faces_added), (0, 0));
    assert_eq!(out.to_polygons(), mesh.to_polygons());
    assert_eq!(&y, x);
}

#[test]
fn fill_hole_refuses_interior_halfedges_and_pinched_loops() {
    let ico = primitives::icosphere(2);
    let mut mesh = EditMesh::from_mesh(&ico.mesh().unwrap(), &ico.positions).unwrap();
    let h = mesh.halfedges().next().unwrap();
    assert_eq!(
        fill_hole(&mut mesh, h, &FillOptions::default()).unwrap_err(),
        FillError::NotBoundary { halfedge: h }
    );
    // Two faces of vertex 0 that share only that vertex: two holes through it.
    let v = VertexId::new(0);
    let fan: Vec<_> = mesh.faces_around_vertex(v).collect();
    mesh.delete_face(fan[0]).unwrap();
    mesh.delete_face(fan[2]).unwrap();
    let before = mesh.clone();
    let b = mesh
        .halfedges()
        .find(|&h| mesh.is_boundary_halfedge(h))
        .unwrap();
    let err = fill_hole(&mut mesh, b, &FillOptions::default()).unwrap_err();
    assert!(
        matches!(
            err,
            FillError::Skipped {
                reason: SkipReason::NonManifoldVertex,
                ..
            }
        ),
        "{err}"
    );
    assert_eq!(mesh.face_vertex_lists(), before.face_vertex_lists());
}

#[test]
fn fill_hole_on_an_edit_mesh_appends_its_patch() {
    let ico = primitives::icosphere(3);
    let mut mesh = EditMesh::from_mesh(&ico.mesh().unwrap(), &ico.positions).unwrap();
    for v in ring(&ico, 0, 1) {
        let fan: Vec<_> = mesh.faces_around_vertex(VertexId::new(v)).collect();
        for f in fan {
            mesh.delete_face(f).unwrap();
        }
    }
    let n = mesh.vertex_capacity();
    let h = mesh
        .halfedges()
        .find(|&h| mesh.is_boundary_halfedge(h))
        .unwrap();
    let hole = fill_hole(&mut mesh, h, &FillOptions::default()).unwrap();
    hole.faced_check();
    assert!(mesh.is_closed());
    mesh.check_integrity().unwrap();
    assert!(mesh.vertex_capacity() >= n + hole.vertices_added);
    mesh.garbage_collection();
    let (closed, _) = mesh.into_mesh().unwrap();
    assert_eq!(closed.euler_characteristic(), 2);
}

fn random_hole_case(torus: bool, center: u32, k: usize) {
    let data = if torus {
        primitives::torus(3.0, 1.0, 18, 9)
    } else {
        primitives::icosphere(2)
    };
    let center = center % data.positions.len() as u32;
    let (open, x) = cut_ring(&data, center, k);
    let euler = if torus { 0 } else { 2 };
    let (out, y, report) = fill_holes(&open, &x, &all()).unwrap();
    assert!(report.skipped.is_empty(), "{report:?}");
    for hole in &report.filled {
        hole.faced_check();
    }
    assert_closed_like(&open, &x, &out, &y, euler, &report);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn random_ring_holes_close(torus in any::<bool>(), center in 0u32..1000, k in 1usize..3) {
        random_hole_case(torus, center, k);
    }
}

/// A round hole of a few hundred edges in a plane: the O(n³) triangulation stays fast,
/// the outer rim (the longer loop) stays open, and the thin plate of a planar rim with a
/// planar ring outside it is the plane itself.
#[test]
fn a_hole_of_hundreds_of_edges_in_a_plane_stays_planar() {
    let grid = primitives::grid(100, 100);
    let center = DVec3::new(50.0, 50.0, 0.0);
    let (open, x) = cut(&grid, |f, p| {
        f.iter().any(|&v| p[v as usize].distance(center) < 30.0)
    });
    let start = std::time::Instant::now();
    let (out, y, report) = fill_holes(&open, &x, &FillOptions::default()).unwrap();
    let seconds = start.elapsed().as_secs_f64();
    assert_eq!(report.filled.len(), 1);
    assert_eq!(report.skipped[0].reason, SkipReason::OuterBoundary);
    let hole = &report.filled[0];
    assert!(hole.boundary_edges > 150, "{}", hole.boundary_edges);
    hole.faced_check();
    out.check_integrity().unwrap();
    assert_eq!(out.boundary_loops().count(), 1);
    let z = y[x.len()..].iter().map(|p| p.z.abs()).fold(0.0, f64::max);
    assert!(z < 1e-9, "{z}");
    // The patch covers the hole: its area is the disc's, less the rim's polygon gaps.
    let disc = std::f64::consts::PI * 30.0 * 30.0;
    assert!(
        hole.area > 0.95 * disc && hole.area < 1.05 * disc,
        "{}",
        hole.area
    );
    println!(
        "{} rim edges: {} faces, {} vertices added in {seconds:.3} s",
        hole.boundary_edges, hole.faces_added, hole.vertices_added
    );
}
