//! Quadric-error decimation: valid output, exact target, preserved topology, every
//! constraint's guarantee, determinism, typed errors, and the Hausdorff distance against
//! OpenMesh's `DecimaterT` + `ModQuadricT` at the same vertex count
//! (`fixtures/openmesh/<name>/decimation/`, written by `tools/openmesh-ref`).

use std::fs;
use std::path::{Path, PathBuf};

use beltrami_algorithms::{
    DecimateError, DecimateOptions, DecimateReport, DecimateStop, Placement, decimate,
};
use beltrami_halfedge::primitives::{self, Primitive};
use beltrami_halfedge::{DVec3, HalfedgeMesh};
use beltrami_metrics::distance::{HausdorffSampling, SurfaceIndex, hausdorff, sampled_distance};
use beltrami_surfaces::{FLensParams, flens};
use beltrami_testkit::SplitMix64;
use beltrami_testkit::fixtures::{noisy_flens, noisy_icosphere, openmesh_inputs};
use beltrami_testkit::openmesh::read_f64s;
use proptest::prelude::*;

fn run(p: &Primitive, options: &DecimateOptions) -> (HalfedgeMesh, Vec<DVec3>, DecimateReport) {
    decimate(&p.mesh().unwrap(), &p.positions, options).unwrap()
}

fn boundary_loops(mesh: &HalfedgeMesh) -> usize {
    mesh.boundary_loops().count()
}

fn face_normal(mesh: &HalfedgeMesh, positions: &[DVec3], f: beltrami_halfedge::FaceId) -> DVec3 {
    let [a, b, c] = mesh.triangle_vertices(f).map(|v| positions[v.index()]);
    (b - a).cross(c - a).normalize()
}

fn centroid(mesh: &HalfedgeMesh, positions: &[DVec3], f: beltrami_halfedge::FaceId) -> DVec3 {
    let [a, b, c] = mesh.triangle_vertices(f).map(|v| positions[v.index()]);
    (a + b + c) / 3.0
}

fn aspect(mesh: &HalfedgeMesh, positions: &[DVec3], f: beltrami_halfedge::FaceId) -> f64 {
    let [a, b, c] = mesh.triangle_vertices(f).map(|v| positions[v.index()]);
    let l2 = (b - a)
        .length_squared()
        .max((c - b).length_squared())
        .max((a - c).length_squared());
    l2 * 3f64.sqrt() / (2.0 * (b - a).cross(c - a).length())
}

/// The test surfaces: closed genus 0 and 1, an open disc and the paper's F-lens.
fn surfaces() -> Vec<(&'static str, Primitive)> {
    vec![
        ("icosphere", primitives::icosphere(3)),
        ("torus", primitives::torus(1.0, 0.35, 36, 12)),
        ("grid", primitives::grid(16, 12)),
        ("noisy icosphere", noisy_icosphere()),
        ("F-lens", noisy_flens()),
    ]
}

#[test]
fn reaches_the_target_exactly_and_keeps_the_topology() {
    for (name, p) in surfaces() {
        let mesh = p.mesh().unwrap();
        // The grid has 56 boundary vertices of 221: kept, they need a larger target.
        for (ratio, options) in [
            (0.25, DecimateOptions::default()),
            (0.4, DecimateOptions::default().keep_boundary(true)),
            (
                0.25,
                DecimateOptions::default().placement(Placement::Optimal),
            ),
        ] {
            let options = options.ratio(ratio);
            let (out, positions, report) = decimate(&mesh, &p.positions, &options).unwrap();
            out.check_integrity().unwrap();
            let target = (ratio * mesh.n_vertices() as f64).round() as usize;
            assert_eq!(report.target_vertices, target, "{name}");
            assert!(report.target_reached, "{name} {options:?}: {report:?}");
            assert_eq!(report.stop, DecimateStop::TargetReached);
            assert_eq!(out.n_vertices(), target, "{name}");
            assert_eq!(positions.len(), target);
            assert_eq!(report.vertices_after, target);
            assert_eq!(report.faces_after, out.n_faces());
            assert_eq!(report.collapses, mesh.n_vertices() - target);
            assert_eq!(out.is_closed(), mesh.is_closed(), "{name}");
            assert_eq!(
                out.euler_characteristic(),
                mesh.euler_characteristic(),
                "{name}"
            );
            assert_eq!(boundary_loops(&out), boundary_loops(&mesh), "{name}");
            assert!(positions.iter().all(|p| p.is_finite()));
            assert!(report.hausdorff.is_finite() && report.hausdorff >= 0.0);
            assert_eq!(
                report.hausdorff,
                report.hausdorff_to_input.max(report.hausdorff_from_input)
            );
            // No triangle is degenerate.
            for f in out.faces() {
                assert!(aspect(&out, &positions, f).is_finite(), "{name}");
            }
        }
    }
}

/// A target at or above the vertex count collapses nothing, and the default run (fit
/// included) gives the input back: the same faces, every position bit for bit.
#[test]
fn a_target_above_the_vertex_count_gives_the_input_back() {
    let sphere = noisy_icosphere();
    let mesh = sphere.mesh().unwrap();
    let n = mesh.n_vertices();
    for target in [n, n + 1, 10 * n] {
        let (out, positions, report) = decimate(
            &mesh,
            &sphere.positions,
            &DecimateOptions::default().vertices(target),
        )
        .unwrap();
        assert_eq!(report.collapses, 0);
        assert_eq!((report.flips, report.fit_rounds), (0, 0));
        assert_eq!((report.fit_rms_before, report.fit_rms_after), (0.0, 0.0));
        assert!(report.target_reached);
        // The measurement's surface samples round (an output identical to the input).
        assert!(report.hausdorff < 1e-12, "{}", report.hausdorff);
        assert_eq!(out.n_vertices(), n);
        let bits = |p: &[DVec3]| {
            p.iter()
                .map(|q| q.to_array().map(f64::to_bits))
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(&positions), bits(&sphere.positions));
        let faces = |m: &HalfedgeMesh| {
            m.faces()
                .map(|f| m.triangle_vertices(f))
                .collect::<Vec<_>>()
        };
        assert_eq!(faces(&out), faces(&mesh));
    }
}

/// Below the vertex count, with an error bound no collapse meets: nothing is collapsed,
/// so nothing is fitted either, and the positions come back bit for bit.
#[test]
fn a_bound_no_collapse_meets_leaves_the_positions_alone() {
    let sphere = noisy_icosphere();
    let mesh = sphere.mesh().unwrap();
    let options = DecimateOptions::default()
        .vertices(mesh.n_vertices() / 2)
        .max_error(1e-300);
    let (out, positions, report) = decimate(&mesh, &sphere.positions, &options).unwrap();
    assert_eq!(report.collapses, 0);
    assert!(report.refused.error > 0);
    assert_eq!(report.stop, DecimateStop::NoCollapseLeft);
    assert_eq!((report.flips, report.fit_rounds), (0, 0));
    assert_eq!(out.n_vertices(), mesh.n_vertices());
    let bits = |p: &[DVec3]| {
        p.iter()
            .map(|q| q.to_array().map(f64::to_bits))
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&positions), bits(&sphere.positions));
}

#[test]
fn endpoint_placement_keeps_input_positions() {
    let p = noisy_icosphere();
    let (_, positions, _) = run(&p, &DecimateOptions::openmesh().ratio(0.3));
    let mut input: Vec<[u64; 3]> = p
        .positions
        .iter()
        .map(|q| q.to_array().map(f64::to_bits))
        .collect();
    input.sort_unstable();
    for q in positions {
        assert!(input.binary_search(&q.to_array().map(f64::to_bits)).is_ok());
    }
}

/// The smallest interior angle of the mesh's triangles, degrees.
fn min_angle(mesh: &HalfedgeMesh, positions: &[DVec3]) -> f64 {
    mesh.faces()
        .map(|f| {
            let t = mesh.triangle_vertices(f).map(|v| positions[v.index()]);
            (0..3)
                .map(|i| {
                    let (a, b, c) = (t[i], t[(i + 1) % 3], t[(i + 2) % 3]);
                    (b - a).angle_between(c - a).to_degrees()
                })
                .fold(f64::INFINITY, f64::min)
        })
        .fold(f64::INFINITY, f64::min)
}

/// The share of interior vertices of valence 6.
fn regular_share(mesh: &HalfedgeMesh) -> f64 {
    let regular = mesh.vertices().filter(|&v| mesh.valence(v) == 6).count();
    regular as f64 / mesh.n_vertices() as f64
}

#[test]
fn the_default_gives_well_shaped_triangles_and_a_smaller_distance() {
    // The paper's level-6 sphere (40 962 vertices) to 10 %, and a noisy sphere to 20 %.
    let sphere = primitives::icosphere(6);
    // The noise dominates the noisy sphere's distance: there the default only has to
    // be no worse.
    for (name, p, ratio, angle, distance) in [
        ("icosphere 6", &sphere, 0.1, 15.0, 0.8),
        ("noisy icosphere", &noisy_icosphere(), 0.2, 10.0, 1.0),
    ] {
        let (plain, plain_positions, plain_report) =
            run(p, &DecimateOptions::openmesh().ratio(ratio));
        let (out, positions, report) = run(p, &DecimateOptions::default().ratio(ratio));
        assert!(report.target_reached, "{name}");
        out.check_integrity().unwrap();
        let (a, a_plain) = (
            min_angle(&out, &positions),
            min_angle(&plain, &plain_positions),
        );
        // The default's smallest angle is that of MeshLab's and MeshLib's outputs or
        // better (about 15° on the level-6 sphere), and better than without it.
        assert!(a > angle, "{name}: smallest angle {a}° (plain {a_plain}°)");
        assert!(a > a_plain + 5.0, "{name}: {a}° against {a_plain}°");
        assert!(
            report.hausdorff < distance * plain_report.hausdorff,
            "{name}: {} against {}",
            report.hausdorff,
            plain_report.hausdorff
        );
        assert!(
            regular_share(&out) > regular_share(&plain),
            "{name}: regular share {} against {}",
            regular_share(&out),
            regular_share(&plain)
        );
    }
}

/// The smallest shape quality `4A / (√3 ℓ²_max)` of `mesh`'s triangles.
fn worst_quality(mesh: &HalfedgeMesh, positions: &[DVec3]) -> f64 {
    mesh.faces()
        .map(|f| 1.0 / aspect(mesh, positions, f))
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn the_valence_flips_raise_the_regular_share_within_their_tolerance() {
    for (name, p, ratio) in [
        ("noisy icosphere", noisy_icosphere(), 0.2),
        ("noisy F-lens", noisy_flens(), 0.3),
        ("icosphere 5", primitives::icosphere(5), 0.1),
    ] {
        let mesh = p.mesh().unwrap();
        // Without the final fit, which moves the vertices after the flips.
        let plain = DecimateOptions::default().ratio(ratio).fit_rounds(0);
        let (flat, flat_positions, flat_report) = run(&p, &plain.flip_tolerance(0.0));
        let (out, positions, report) = run(&p, &plain);
        assert_eq!(flat_report.flips, 0, "{name}");
        assert!(report.flips > 0, "{name}: no flip");
        out.check_integrity().unwrap();
        assert_eq!(out.n_vertices(), flat.n_vertices(), "{name}");
        assert_eq!(
            out.euler_characteristic(),
            mesh.euler_characteristic(),
            "{name}"
        );
        assert_eq!(
            out.boundary_loops().count(),
            mesh.boundary_loops().count(),
            "{name}"
        );
        // The flips follow the same collapses: the same vertices, bit for bit.
        assert_eq!(positions, flat_positions, "{name}");
        assert_eq!(report.max_quadric_error, flat_report.max_quadric_error);
        assert!(
            regular_share(&out) > regular_share(&flat),
            "{name}: regular share {} against {}",
            regular_share(&out),
            regular_share(&flat)
        );
        // Each flip moves the surface by at most the tolerance, 0.2 of the largest
        // collapse error, and no flip touches another's triangles' distance by more.
        let tolerance = 0.2 * report.max_quadric_error;
        assert!(
            report.hausdorff <= flat_report.hausdorff + tolerance * (1.0 + 1e-9),
            "{name}: Hausdorff {} against {} (tolerance {tolerance})",
            report.hausdorff,
            flat_report.hausdorff
        );
        // No triangle worse than the worst before or than quality 0.4.
        let (q, q_flat) = (
            worst_quality(&out, &positions),
            worst_quality(&flat, &flat_positions),
        );
        assert!(q >= q_flat.min(0.4) - 1e-12, "{name}: {q} against {q_flat}");
    }
    // OpenMesh's decimater makes no flips; the flips follow no distance or normal bound.
    let p = noisy_icosphere();
    for options in [
        DecimateOptions::openmesh().ratio(0.2),
        DecimateOptions::default().ratio(0.2).max_distance(1.0),
        DecimateOptions::default()
            .ratio(0.2)
            .max_normal_deviation(1.0),
    ] {
        assert_eq!(run(&p, &options).2.flips, 0, "{options:?}");
    }
    // An aspect-ratio bound holds for the flipped triangles too.
    let (out, positions, report) = run(
        &p,
        &DecimateOptions::default().ratio(0.2).max_aspect_ratio(3.0),
    );
    let worst = out
        .faces()
        .map(|f| aspect(&out, &positions, f))
        .fold(0.0f64, f64::max);
    assert!(report.flips > 0);
    assert!(worst <= 3.0 * (1.0 + 1e-12), "{worst}");
}

/// The sampled RMS distance between two surfaces, the larger of the two ways (Metro's
/// error).
fn surface_rms(a: (&HalfedgeMesh, &[DVec3]), b: (&HalfedgeMesh, &[DVec3])) -> f64 {
    let a = SurfaceIndex::new(a.0, a.1).unwrap();
    let b = SurfaceIndex::new(b.0, b.1).unwrap();
    let there = sampled_distance(&a, &b, 100_000, 3).unwrap().rms;
    let back = sampled_distance(&b, &a, 100_000, 3).unwrap().rms;
    there.max(back)
}

/// The final fit moves only vertices: the same triangles, the boundary bit for bit, no
/// triangle turned over, none worse than the worst before or than quality 0.3; and the
/// surface comes closer to the input: the sampled RMS distance both ways falls by 45 %
/// on the smooth level-5 sphere, by 20 % and 10 % on the noisy sphere and F-lens, whose
/// noise no coarse surface follows (37–44 % on the bench surfaces), and the fit's own
/// energy by more than a fifth.
#[test]
fn the_final_fit_brings_the_surface_closer_and_keeps_the_triangles() {
    // The largest share of the unfitted surface distance the fit may leave: on a noisy
    // input part of the distance is noise no coarse surface follows.
    for (name, p, ratio, share) in [
        ("icosphere 5", primitives::icosphere(5), 0.1, 0.6),
        ("noisy F-lens", noisy_flens(), 0.3, 0.93),
        ("noisy icosphere", noisy_icosphere(), 0.2, 0.85),
    ] {
        let mesh = p.mesh().unwrap();
        let input = (&mesh, p.positions.as_slice());
        let (plain, plain_positions, plain_report) =
            run(&p, &DecimateOptions::default().ratio(ratio).fit_rounds(0));
        let (out, positions, report) = run(&p, &DecimateOptions::default().ratio(ratio));
        out.check_integrity().unwrap();
        assert_eq!(plain_report.fit_rounds, 0, "{name}");
        assert_eq!(report.fit_rounds, 2, "{name}");
        assert_eq!(out.to_polygons(), plain.to_polygons(), "{name}");
        for v in out.vertices().filter(|&v| out.is_boundary_vertex(v)) {
            assert_eq!(positions[v.index()], plain_positions[v.index()], "{name}");
        }
        for f in out.faces() {
            let turned =
                face_normal(&out, &positions, f).dot(face_normal(&plain, &plain_positions, f));
            assert!(turned > 0.0, "{name}: face {f:?} turned over");
        }
        let (q, q_plain) = (
            worst_quality(&out, &positions),
            worst_quality(&plain, &plain_positions),
        );
        assert!(
            q >= q_plain.min(0.3) - 1e-12,
            "{name}: {q} against {q_plain}"
        );
        assert!(
            report.fit_rms_after < 0.8 * report.fit_rms_before,
            "{name}: {report:?}"
        );
        let (fitted, unfitted) = (
            surface_rms((&out, &positions), input),
            surface_rms((&plain, &plain_positions), input),
        );
        assert!(
            fitted < share * unfitted,
            "{name}: surface RMS {fitted} against {unfitted}"
        );
    }
    // No fit where the output's vertices must be input vertices, or where a bound
    // follows the collapses only.
    let p = noisy_icosphere();
    for options in [
        DecimateOptions::openmesh(),
        DecimateOptions::default().placement(Placement::Endpoint),
        DecimateOptions::default().max_distance(1.0),
        DecimateOptions::default().max_normal_deviation(1.0),
    ] {
        assert_eq!(run(&p, &options.ratio(0.2)).2.fit_rounds, 0, "{options:?}");
    }
}

#[test]
fn the_shape_penalty_orders_collapses_but_never_stops_them() {
    // The strongest penalty still reaches the target, on a closed and an open surface,
    // and the penalty lifts the smallest angle over no penalty at the same placement.
    for (name, p) in [
        ("noisy icosphere", noisy_icosphere()),
        ("F-lens", noisy_flens()),
    ] {
        let optimal = DecimateOptions::default().ratio(0.15);
        let (out, positions, report) = run(&p, &optimal.quality_threshold(1.0));
        assert!(report.target_reached, "{name}: {report:?}");
        out.check_integrity().unwrap();
        let (bare, bare_positions, _) = run(&p, &optimal.quality_threshold(0.0));
        assert!(
            min_angle(&out, &positions) > min_angle(&bare, &bare_positions),
            "{name}"
        );
    }
    let o = DecimateOptions::openmesh();
    assert_eq!(o.placement, Placement::Endpoint);
    assert_eq!(o.quality_threshold, 0.0);
    let d = DecimateOptions::default();
    assert_eq!(d.placement, Placement::Optimal);
    assert_eq!(d.quality_threshold, 0.4);
}

#[test]
fn a_sphere_stays_close_to_the_sphere() {
    let p = primitives::icosphere(4);
    for placement in [Placement::Endpoint, Placement::Optimal] {
        let (out, positions, report) = run(
            &p,
            &DecimateOptions::default().ratio(0.1).placement(placement),
        );
        assert_eq!(out.euler_characteristic(), 2);
        // 256 vertices on a unit sphere: the chord sagitta of an edge of ~0.22 is ~0.006.
        assert!(report.hausdorff < 0.03, "{placement:?}: {report:?}");
        for q in positions {
            assert!((q.length() - 1.0).abs() < 0.03, "{placement:?}");
        }
    }
}

#[test]
fn keep_boundary_keeps_every_boundary_vertex_bit_for_bit() {
    for (name, p) in [
        ("grid", primitives::grid(16, 12)),
        ("F-lens", noisy_flens()),
        ("holes", openmesh_inputs().remove(3).1),
    ] {
        let mesh = p.mesh().unwrap();
        let boundary: Vec<[u64; 3]> = mesh
            .vertices()
            .filter(|&v| mesh.is_boundary_vertex(v))
            .map(|v| p.positions[v.index()].to_array().map(f64::to_bits))
            .collect();
        for placement in [Placement::Endpoint, Placement::Optimal] {
            let options = DecimateOptions::default()
                .ratio(0.3)
                .keep_boundary(true)
                .placement(placement);
            let (out, positions, report) = decimate(&mesh, &p.positions, &options).unwrap();
            let mut kept: Vec<[u64; 3]> = out
                .vertices()
                .filter(|&v| out.is_boundary_vertex(v))
                .map(|v| positions[v.index()].to_array().map(f64::to_bits))
                .collect();
            let mut want = boundary.clone();
            kept.sort_unstable();
            want.sort_unstable();
            assert_eq!(kept, want, "{name} {placement:?}");
            assert!(report.refused.boundary > 0, "{name}");
        }
        // Without the option the boundary is decimated too.
        let (out, _, _) =
            decimate(&mesh, &p.positions, &DecimateOptions::default().ratio(0.3)).unwrap();
        let n = out
            .vertices()
            .filter(|&v| out.is_boundary_vertex(v))
            .count();
        assert!(n < boundary.len(), "{name}");
    }
}

#[test]
fn uniform_plane_weights_and_the_stabilizer_keep_every_guarantee() {
    for (name, p) in surfaces() {
        let mesh = p.mesh().unwrap();
        for options in [
            DecimateOptions::default().area_weighted(false),
            DecimateOptions::default().stabilizer(1e-3),
            DecimateOptions::default()
                .area_weighted(false)
                .stabilizer(1e-3),
            DecimateOptions::default()
                .area_weighted(false)
                .stabilizer(1e-3)
                .keep_boundary(true),
        ] {
            let ratio = if options.keep_boundary { 0.4 } else { 0.25 };
            let (out, positions, report) =
                decimate(&mesh, &p.positions, &options.ratio(ratio)).unwrap();
            out.check_integrity().unwrap();
            assert!(report.target_reached, "{name} {options:?}: {report:?}");
            assert_eq!(
                out.euler_characteristic(),
                mesh.euler_characteristic(),
                "{name}"
            );
            assert_eq!(boundary_loops(&out), boundary_loops(&mesh), "{name}");
            assert!(report.max_quadric_error.is_finite());
            for f in out.faces() {
                assert!(aspect(&out, &positions, f).is_finite(), "{name}");
            }
            if options.keep_boundary {
                // Boundary vertices never move, whatever the weights.
                for v in mesh.vertices().filter(|&v| mesh.is_boundary_vertex(v)) {
                    assert!(positions.contains(&p.positions[v.index()]), "{name}");
                }
            }
        }
    }
}

#[test]
fn the_stabilizer_places_flat_collapses_between_their_ends() {
    // On a flat grid every quadric is one plane: without the stabilizer the optimal
    // position is undefined and an end point is kept (the output's vertices are input
    // vertices); the pull towards the input positions places the kept vertex between
    // them, still exactly in the plane and inside the grid.
    let p = primitives::grid(12, 12);
    for area_weighted in [true, false] {
        let options = DecimateOptions::default()
            .ratio(0.3)
            .area_weighted(area_weighted);
        let (_, without, _) = run(&p, &options);
        assert!(without.iter().all(|q| p.positions.contains(q)));
        let (out, with, report) = run(&p, &options.stabilizer(1e-3));
        assert!(report.target_reached);
        let moved = with.iter().filter(|q| !p.positions.contains(q)).count();
        assert!(moved > with.len() / 4, "{moved} of {}", with.len());
        let (lo, hi) = p
            .positions
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &q| {
                (lo.min(q), hi.max(q))
            });
        for q in &with {
            assert_eq!(q.z, 0.0);
            assert!(q.cmpge(lo).all() && q.cmple(hi).all(), "{q}");
        }
        assert!(report.hausdorff < 1e-12, "{report:?}");
        for f in out.faces() {
            assert!(face_normal(&out, &with, f).z > 0.0);
        }
    }
}

#[test]
fn decimation_commutes_with_scaling_by_a_power_of_two() {
    // Scaling by 2^k scales every quantity of the decimation exactly when each weight
    // has the right unit (with area weights the pull's weight scales with the mean
    // area, as the plane errors do), so the same collapses are done in the same order.
    let p = noisy_icosphere();
    let mut scaled = p.clone();
    for q in &mut scaled.positions {
        *q *= 1024.0;
    }
    for options in [
        DecimateOptions::default(),
        DecimateOptions::default().area_weighted(false),
        DecimateOptions::default().stabilizer(1e-3),
        DecimateOptions::default()
            .area_weighted(false)
            .stabilizer(1e-3),
    ] {
        let options = options.ratio(0.2).measure_distance(false);
        let (a, pa, ra) = run(&p, &options);
        let (b, pb, rb) = run(&scaled, &options);
        assert_eq!(a.to_polygons(), b.to_polygons(), "{options:?}");
        for (x, y) in pa.iter().zip(&pb) {
            assert_eq!(*x * 1024.0, *y, "{options:?}");
        }
        assert_eq!(ra.max_quadric_error * 1024.0, rb.max_quadric_error);
    }
}

/// A part far from the origin (a machine's coordinates: 10⁷ away, with a size of
/// about 1) decimates as it does at the origin: the quadrics are relative to the
/// bounding box's centre. With absolute coordinates their constant terms (10¹⁴)
/// rounded away every error below 10⁻², and the result was ten times farther from the
/// input (and `max_quadric_error` 0).
#[test]
fn decimation_does_not_depend_on_where_the_part_lies() {
    let p = noisy_flens();
    let offset = DVec3::new(1.0e7, -3.0e6, 5.0e6);
    let mut moved = p.clone();
    for q in &mut moved.positions {
        *q += offset;
    }
    for options in [
        DecimateOptions::default(),
        DecimateOptions::default().placement(Placement::Endpoint),
        DecimateOptions::openmesh(),
    ] {
        let options = options.ratio(0.3);
        let (_, pa, ra) = run(&p, &options);
        let (_, pb, rb) = run(&moved, &options);
        assert_eq!(ra.vertices_after, rb.vertices_after, "{options:?}");
        assert!(ra.max_quadric_error > 0.0);
        let relative = |a: f64, b: f64| (a - b).abs() / a.max(b);
        assert!(
            relative(ra.max_quadric_error, rb.max_quadric_error) < 0.05,
            "{options:?}: {} at the origin, {} moved",
            ra.max_quadric_error,
            rb.max_quadric_error
        );
        assert!(
            relative(ra.hausdorff, rb.hausdorff) < 0.05,
            "{options:?}: {} at the origin, {} moved",
            ra.hausdorff,
            rb.hausdorff
        );
        // The same collapses, so the same vertices up to the rounding of the offset.
        assert_eq!(pa.len(), pb.len());
        let worst = pa
            .iter()
            .zip(&pb)
            .map(|(a, b)| (*b - offset).distance(*a))
            .fold(0.0, f64::max);
        assert!(worst < 1e-6, "{options:?}: {worst}");
        // A stray point at the machine's origin (an isolated vertex) changes nothing:
        // the quadrics' origin is the box of the vertices in a face.
        let mut stray = moved.clone();
        stray.positions.push(DVec3::ZERO);
        let (_, _, rc) = run(&stray, &options);
        assert_eq!(rc.vertices_after, rb.vertices_after + 1, "{options:?}");
        assert!(
            relative(rb.max_quadric_error, rc.max_quadric_error) < 1e-9,
            "{options:?}: {} without the stray point, {} with it",
            rb.max_quadric_error,
            rc.max_quadric_error
        );
    }
}

#[test]
fn a_planar_grid_stays_planar_with_zero_error() {
    let p = primitives::grid(12, 12);
    for placement in [Placement::Endpoint, Placement::Optimal] {
        let (out, positions, report) = run(
            &p,
            &DecimateOptions::default().ratio(0.3).placement(placement),
        );
        assert!(report.target_reached);
        assert!(positions.iter().all(|q| q.z == 0.0), "{placement:?}");
        assert_eq!(report.max_quadric_error, 0.0, "{placement:?}");
        assert!(report.hausdorff < 1e-12, "{placement:?}: {report:?}");
        // Every triangle keeps the orientation of the grid's.
        for f in out.faces() {
            assert!(face_normal(&out, &positions, f).z > 0.0);
        }
    }
}

#[test]
fn the_normal_deviation_bound_holds() {
    let p = primitives::icosphere(4);
    let mesh = p.mesh().unwrap();
    let input = SurfaceIndex::new(&mesh, &p.positions).unwrap();
    let max_angle = |bound: Option<f64>| -> (f64, DecimateReport) {
        let mut options = DecimateOptions::default().ratio(0.05);
        if let Some(b) = bound {
            options = options.max_normal_deviation(b);
        }
        let (out, positions, report) = decimate(&mesh, &p.positions, &options).unwrap();
        let mut worst: f64 = 0.0;
        for f in out.faces() {
            let n = face_normal(&out, &positions, f);
            let closest = input.closest_point(centroid(&out, &positions, f)).unwrap();
            let m = face_normal(&mesh, &p.positions, closest.face);
            assert!(n.dot(m) > 0.0, "a face flipped");
            worst = worst.max(n.angle_between(m));
        }
        (worst, report)
    };
    let (free, free_report) = max_angle(None);
    // The final fit of the unbounded run lowers its largest deviation (to 3.7°).
    let bound = 3f64.to_radians();
    let (bounded, report) = max_angle(Some(bound));
    assert!(free_report.target_reached);
    assert!(!report.target_reached, "{report:?}");
    assert_eq!(report.stop, DecimateStop::NoCollapseLeft);
    assert!(report.refused.normal_deviation > 0);
    assert!(bounded <= bound, "{} > 3 degrees", bounded.to_degrees());
    assert!(free > bound, "the bound must matter: {}", free.to_degrees());
}

#[test]
fn no_face_flips_on_a_noisy_surface() {
    // Against the surface the noise was added to: the unit sphere, and the clean F-lens.
    let lens = flens(&FLensParams::default());
    let lens_mesh = lens.mesh().unwrap();
    let clean = SurfaceIndex::new(&lens_mesh, &lens.positions).unwrap();
    for (name, p) in [
        ("noisy icosphere", noisy_icosphere()),
        ("F-lens", noisy_flens()),
    ] {
        let mesh = p.mesh().unwrap();
        // Without a normal bound only turns by 90° or more of one face are refused, and
        // a fold against the surface can remain; a bound as loose as 60° removes them.
        let bound = DecimateOptions::default().max_normal_deviation(60f64.to_radians());
        for options in [
            bound.ratio(0.2),
            bound.ratio(0.1).placement(Placement::Optimal),
        ] {
            let (out, positions, _) = decimate(&mesh, &p.positions, &options).unwrap();
            for f in out.faces() {
                let n = face_normal(&out, &positions, f);
                let c = centroid(&out, &positions, f);
                let m = if name == "F-lens" {
                    face_normal(
                        &lens_mesh,
                        &lens.positions,
                        clean.closest_point(c).unwrap().face,
                    )
                } else {
                    c.normalize()
                };
                // No normal points against the surface. (A sliver whose three vertices
                // lie on one great circle of the radially noisy sphere has its normal in
                // the tangent plane, a dot product of rounding size.)
                assert!(n.dot(m) > -1e-9, "{name} {options:?}: face {f:?}");
            }
        }
    }
}

#[test]
fn the_error_bound_holds_and_stops_early() {
    let p = noisy_icosphere();
    let free = run(&p, &DecimateOptions::default().ratio(0.1)).2;
    let bound = 0.25 * free.max_quadric_error;
    let (_, _, report) = run(&p, &DecimateOptions::default().ratio(0.1).max_error(bound));
    assert!(report.max_quadric_error <= bound);
    assert!(!report.target_reached);
    assert!(report.refused.error > 0);
    assert!(report.vertices_after > free.vertices_after);
}

#[test]
fn the_distance_bound_holds_for_every_input_vertex() {
    for (name, p) in [
        ("noisy icosphere", noisy_icosphere()),
        ("F-lens", noisy_flens()),
    ] {
        let free = run(&p, &DecimateOptions::default().ratio(0.1)).2;
        let bound = 0.5 * free.hausdorff_from_input;
        for placement in [Placement::Endpoint, Placement::Optimal] {
            let options = DecimateOptions::default()
                .ratio(0.1)
                .max_distance(bound)
                .placement(placement);
            let (out, positions, report) = run(&p, &options);
            out.check_integrity().unwrap();
            assert!(report.refused.distance > 0, "{name}");
            let index = SurfaceIndex::new(&out, &positions).unwrap();
            let worst = index
                .distances(&p.positions)
                .unwrap()
                .into_iter()
                .fold(0.0f64, f64::max);
            assert!(
                worst <= bound * (1.0 + 1e-9),
                "{name} {placement:?}: {worst} > {bound}"
            );
        }
    }
}

#[test]
fn the_aspect_ratio_bound_holds() {
    let p = noisy_icosphere();
    let mesh = p.mesh().unwrap();
    let worst_in = mesh
        .faces()
        .map(|f| aspect(&mesh, &p.positions, f))
        .fold(0.0f64, f64::max);
    let worst = |options: &DecimateOptions| {
        let (out, positions, report) = decimate(&mesh, &p.positions, options).unwrap();
        let w = out
            .faces()
            .map(|f| aspect(&out, &positions, f))
            .fold(0.0f64, f64::max);
        (w, report)
    };
    let bound = 3.0;
    let (free, _) = worst(&DecimateOptions::default().ratio(0.2));
    let (bounded, report) = worst(
        &DecimateOptions::default()
            .ratio(0.2)
            .max_aspect_ratio(bound),
    );
    // No triangle worse than the bound or the worst input triangle.
    assert!(
        bounded <= bound.max(worst_in),
        "{bounded} (input {worst_in})"
    );
    assert!(free > bounded, "the bound must matter: {free}");
    assert!(report.refused.aspect_ratio > 0);
}

#[test]
fn the_distance_measured_later_is_the_one_measured_inside() {
    let p = noisy_flens();
    let mesh = p.mesh().unwrap();
    let options = DecimateOptions::default().ratio(0.3);
    let (out, positions, measured) = decimate(&mesh, &p.positions, &options).unwrap();
    assert!(measured.distance_measured);
    assert!(measured.hausdorff > 0.0);
    assert_eq!(
        measured.hausdorff,
        measured
            .hausdorff_to_input
            .max(measured.hausdorff_from_input)
    );
    let (out2, positions2, mut later) =
        decimate(&mesh, &p.positions, &options.measure_distance(false)).unwrap();
    // Skipping the measurement changes nothing of the decimation.
    assert_eq!(out.to_polygons(), out2.to_polygons());
    assert_eq!(positions, positions2);
    assert!(!later.distance_measured);
    assert_eq!(
        (
            later.hausdorff,
            later.hausdorff_to_input,
            later.hausdorff_from_input
        ),
        (0.0, 0.0, 0.0)
    );
    later
        .measure_distance((&mesh, &p.positions), (&out2, &positions2))
        .unwrap();
    assert_eq!(later, measured);
}

#[test]
fn decimation_is_deterministic() {
    let p = noisy_flens();
    let options = DecimateOptions::default()
        .ratio(0.2)
        .max_normal_deviation(0.5)
        .max_distance(0.5)
        .placement(Placement::Optimal);
    let a = run(&p, &options);
    let b = run(&p, &options);
    assert_eq!(a.0.to_polygons(), b.0.to_polygons());
    let bits = |v: &[DVec3]| -> Vec<[u64; 3]> {
        v.iter().map(|q| q.to_array().map(f64::to_bits)).collect()
    };
    assert_eq!(bits(&a.1), bits(&b.1));
    assert_eq!(a.2, b.2);
}

#[test]
fn the_result_does_not_depend_on_the_thread_count() {
    // The initial bounds are computed on rayon's threads: one thread and several give
    // the same bytes, for the default, a boundary (the F-lens) and the OpenMesh mode.
    let bits = |v: &[DVec3]| -> Vec<[u64; 3]> {
        v.iter().map(|q| q.to_array().map(f64::to_bits)).collect()
    };
    for (p, options) in [
        (noisy_icosphere(), DecimateOptions::default().ratio(0.2)),
        (noisy_flens(), DecimateOptions::default().ratio(0.3)),
        (noisy_flens(), DecimateOptions::openmesh().ratio(0.3)),
        (
            noisy_flens(),
            DecimateOptions::default()
                .ratio(0.3)
                .area_weighted(false)
                .stabilizer(1e-3),
        ),
    ] {
        let on = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| run(&p, &options))
        };
        let (one, many) = (on(1), on(4));
        assert!(one.2.collapses > 0);
        assert_eq!(one.0.to_polygons(), many.0.to_polygons());
        assert_eq!(bits(&one.1), bits(&many.1));
        assert_eq!(one.2, many.2);
    }
}

/// The block's flat sides leave few collapses that make well-shaped triangles once the
/// first generation is done: entries go back into the queue many times per collapse, and
/// the loop keys its whole queue at once. The result still keeps every guarantee and
/// does not depend on the thread count.
#[test]
fn keying_the_whole_queue_keeps_the_guarantees_and_the_bytes_on_any_thread_count() {
    let block = beltrami_surfaces::SurfaceKind::Block.generate();
    let mesh = block.mesh().unwrap();
    let options = DecimateOptions::default().ratio(0.1);
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| decimate(&mesh, &block.positions, &options).unwrap())
    };
    let (one, many) = (on(1), on(3));
    assert!(one.2.keyings > 0, "the queue was never keyed at once");
    assert_eq!(one.0.to_polygons(), many.0.to_polygons());
    let bits = |v: &[DVec3]| -> Vec<[u64; 3]> {
        v.iter().map(|q| q.to_array().map(f64::to_bits)).collect()
    };
    assert_eq!(bits(&one.1), bits(&many.1));
    assert_eq!(one.2, many.2);
    let (out, y, report) = one;
    assert!(report.target_reached);
    assert_eq!(out.n_vertices(), report.target_vertices);
    assert!(out.check_integrity().is_ok());
    assert_eq!(out.euler_characteristic(), mesh.euler_characteristic());
    // The block's sides are planes and its edges straight: every input vertex still lies
    // on the output, to rounding.
    assert!(report.hausdorff < 1e-9, "{}", report.hausdorff);
    assert!(min_angle(&out, &y) > 5.0, "{}", min_angle(&out, &y));
    // The shape penalty is not worse for the keying: the default run's aspect ratios
    // stay under the same bound as on the other surfaces.
    let worst = out
        .faces()
        .map(|f| aspect(&out, &y, f))
        .fold(0.0f64, f64::max);
    assert!(worst < 20.0, "{worst}");
}

#[test]
fn bad_input_and_options_are_typed_errors() {
    let p = primitives::icosphere(1);
    let mesh = p.mesh().unwrap();
    let bad = |o: DecimateOptions| decimate(&mesh, &p.positions, &o).unwrap_err();
    let d = DecimateOptions::default();
    for options in [
        d.vertices(0),
        d.ratio(0.0),
        d.ratio(1.5),
        d.ratio(f64::NAN),
        d.max_error(-1.0),
        d.max_error(f64::INFINITY),
        d.max_normal_deviation(4.0),
        d.max_normal_deviation(f64::NAN),
        d.max_aspect_ratio(0.5),
        d.max_distance(-0.1),
        d.quality_threshold(-0.1),
        d.quality_threshold(1.5),
        d.quality_threshold(f64::NAN),
        d.stabilizer(-1e-3),
        d.stabilizer(f64::INFINITY),
        d.stabilizer(f64::NAN),
        d.flip_tolerance(-0.1),
        d.flip_tolerance(f64::INFINITY),
        d.flip_tolerance(f64::NAN),
    ] {
        assert!(
            matches!(bad(options), DecimateError::Options { .. }),
            "{options:?}"
        );
    }
    assert!(matches!(
        decimate(&mesh, &p.positions[1..], &d),
        Err(DecimateError::PositionCount { .. })
    ));
    let mut nan = p.positions.clone();
    nan[3].y = f64::NAN;
    assert_eq!(
        decimate(&mesh, &nan, &d).unwrap_err(),
        DecimateError::NonFinite { vertex: 3 }
    );
    let quads = primitives::cube_quads();
    assert!(matches!(
        decimate(&quads.mesh().unwrap(), &quads.positions, &d),
        Err(DecimateError::NotTriangle { len: 4, .. })
    ));
    // A target above the vertex count is reached without collapses.
    let (out, _, report) = decimate(&mesh, &p.positions, &d.vertices(1000)).unwrap();
    assert_eq!(out.n_vertices(), mesh.n_vertices());
    assert!(report.target_reached && report.collapses == 0);
    // A tetrahedron cannot lose a vertex: the target is missed, with the reason.
    let tet = primitives::tetrahedron();
    let (out, _, report) = run(&tet, &d.vertices(1));
    assert_eq!(out.n_vertices(), 4);
    assert!(!report.target_reached);
    assert_eq!(report.stop, DecimateStop::NoCollapseLeft);
    assert!(report.refused.topology > 0);
}

fn references() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/openmesh")
}

fn read_faces(path: &Path) -> Vec<[u32; 3]> {
    let bytes = fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(bytes.len() % 12, 0, "{}", path.display());
    bytes
        .chunks_exact(12)
        .map(|c| {
            let at = |i: usize| u32::from_le_bytes(c[4 * i..4 * i + 4].try_into().unwrap());
            [at(0), at(1), at(2)]
        })
        .collect()
}

/// The symmetric Hausdorff distance to the input, with the same sampling for every
/// output compared.
fn distance_to(
    input: &SurfaceIndex,
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    samples: usize,
) -> f64 {
    let out = SurfaceIndex::new(mesh, positions).unwrap();
    let sampling = HausdorffSampling::VerticesAndSurface { samples, seed: 7 };
    hausdorff(&out, input, sampling).unwrap().symmetric
}

#[test]
fn hausdorff_is_no_worse_than_openmesh() {
    let mut compared = 0;
    let mut ratios = Vec::new();
    for (name, p) in openmesh_inputs() {
        let dir = references().join(name).join("decimation");
        let Ok(cases) = fs::read_to_string(dir.join("cases.txt")) else {
            continue;
        };
        let mesh = p.mesh().unwrap();
        let input = SurfaceIndex::new(&mesh, &p.positions).unwrap();
        let samples = 4 * mesh.n_faces();
        for line in cases.lines() {
            let words: Vec<&str> = line.split_whitespace().collect();
            let [percent, target, n_vertices, n_faces] = words[..] else {
                panic!("{name}: bad line {line:?}");
            };
            let target: usize = target.parse().unwrap();
            let theirs: Vec<DVec3> = read_f64s(&dir.join(format!("ratio_{percent}.f64")))
                .unwrap()
                .chunks_exact(3)
                .map(|c| DVec3::new(c[0], c[1], c[2]))
                .collect();
            let their_faces = read_faces(&dir.join(format!("ratio_{percent}.faces.u32")));
            assert_eq!(theirs.len().to_string(), n_vertices, "{name}");
            assert_eq!(their_faces.len().to_string(), n_faces, "{name}");
            let their_mesh = HalfedgeMesh::from_polygons(theirs.len(), &their_faces).unwrap();

            let d_theirs = distance_to(&input, &their_mesh, &theirs, samples);
            let mut d = [0.0; 3];
            for (i, options) in [
                DecimateOptions::openmesh(),
                DecimateOptions::openmesh().placement(Placement::Optimal),
                DecimateOptions::default(),
            ]
            .into_iter()
            .enumerate()
            {
                let options = options.vertices(target);
                let (ours, positions, report) = decimate(&mesh, &p.positions, &options).unwrap();
                assert_eq!(ours.n_vertices(), theirs.len(), "{name} {percent}%");
                assert!(report.target_reached);
                d[i] = distance_to(&input, &ours, &positions, samples);
            }
            println!(
                "| {name} | {percent} % | {target} | {d_theirs:.4} | {:.4} ({:+.1} %) | {:.4} ({:+.1} %) | {:.4} ({:+.1} %) |",
                d[0],
                100.0 * (d[0] / d_theirs - 1.0),
                d[1],
                100.0 * (d[1] / d_theirs - 1.0),
                d[2],
                100.0 * (d[2] / d_theirs - 1.0),
            );
            // The default (optimal placement, shape penalty) is no worse than OpenMesh.
            assert!(
                d[2] <= d_theirs,
                "{name} {percent}%: default {} vs OpenMesh {d_theirs}",
                d[2]
            );
            // Endpoint placement without the penalty is OpenMesh's own algorithm, with
            // its update rule; beltrami also refuses collapses that flip a triangle,
            // which `ModQuadricT` alone allows, and the order of equal-cost collapses
            // differs: that moves the largest error of a noisy surface by a few per cent
            // either way (+5.1 % at most over these fixtures).
            assert!(
                d[0] <= 1.06 * d_theirs,
                "{name} {percent}%: endpoint {} vs OpenMesh {d_theirs}",
                d[0]
            );
            assert!(
                d[1] <= 1.05 * d_theirs,
                "{name} {percent}%: optimal {} vs OpenMesh {d_theirs}",
                d[1]
            );
            ratios.push(d[0] / d_theirs);
            compared += 1;
        }
    }
    assert!(compared >= 6, "only {compared} OpenMesh cases");
    // Over all cases, endpoint placement is no worse than OpenMesh on average.
    let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
    assert!(mean <= 1.0, "mean ratio {mean}");
}

fn small_mesh(kind: u8, seed: u64) -> Primitive {
    let mut p = match kind % 4 {
        0 => primitives::icosphere(2),
        1 => primitives::torus(1.0, 0.4, 12, 6),
        2 => primitives::grid(8, 6),
        _ => openmesh_inputs().remove(3).1,
    };
    let mut rng = SplitMix64::new(seed);
    for q in &mut p.positions {
        *q += 0.005 * rng.next_symmetric_vector();
    }
    p
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn random_meshes_and_targets(kind in 0u8..4, seed in any::<u64>(), ratio in 0.05f64..1.0,
                                 keep in any::<bool>(), optimal in any::<bool>(),
                                 quality in prop::sample::select(vec![0.0, 0.4, 1.0])) {
        let p = small_mesh(kind, seed);
        let mesh = p.mesh().unwrap();
        let options = DecimateOptions::default()
            .ratio(ratio)
            .keep_boundary(keep)
            .quality_threshold(quality)
            .placement(if optimal { Placement::Optimal } else { Placement::Endpoint });
        let (out, positions, report) = decimate(&mesh, &p.positions, &options).unwrap();
        out.check_integrity().unwrap();
        prop_assert_eq!(positions.len(), out.n_vertices());
        prop_assert_eq!(out.euler_characteristic(), mesh.euler_characteristic());
        prop_assert_eq!(boundary_loops(&out), boundary_loops(&mesh));
        prop_assert!(out.n_vertices() >= report.target_vertices);
        prop_assert_eq!(report.target_reached, out.n_vertices() == report.target_vertices);
        prop_assert!(report.hausdorff.is_finite());
    }
}

#[test]
fn a_progress_closure_can_stop_the_decimation() {
    use std::ops::ControlFlow;
    let sphere = primitives::icosphere(5); // 10 242 vertices
    let mesh = sphere.mesh().unwrap();
    let options = beltrami_algorithms::DecimateOptions::default().vertices(1000);
    let mut calls = 0;
    let err = beltrami_algorithms::decimate_with_progress(
        &mesh,
        &sphere.positions,
        &options,
        |done, planned| {
            calls += 1;
            assert_eq!(planned, 9242);
            if done >= 4096 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        },
    )
    .unwrap_err();
    assert_eq!(calls, 1);
    assert!(
        matches!(
            err,
            beltrami_algorithms::DecimateError::Stopped {
                done: 4096,
                planned: 9242
            }
        ),
        "{err:?}"
    );
}
