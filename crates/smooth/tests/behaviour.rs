//! What smoothing must do: closed forms on the sphere, the boundary modes, the
//! observer, the update policies.

use std::ops::ControlFlow;

use beltrami_halfedge::primitives;
use beltrami_halfedge::{DVec3, HalfedgeMesh, VertexId};
use beltrami_smooth::{
    Boundary, SmoothConfig, SmoothError, Smoother, StopReason, Summation, WeightUpdate, smooth,
};
use beltrami_testkit::SplitMix64;
use beltrami_weights::{Cotangent, InverseDistance, Uniform, WeightScheme};

fn schemes() -> [&'static dyn WeightScheme; 3] {
    [&Uniform, &InverseDistance, &Cotangent]
}

/// An open, bumpy height field over a grid with in-plane jitter.
fn bumpy_grid(n: u32, seed: u64) -> (HalfedgeMesh, Vec<DVec3>) {
    let g = primitives::grid(n, n);
    let mesh = g.mesh().unwrap();
    let mut rng = SplitMix64::new(seed);
    let x = g
        .positions
        .iter()
        .map(|&p| {
            let j = DVec3::new(rng.next_symmetric(), rng.next_symmetric(), 0.0) * 0.2;
            let p = if p.x > 0.0 && p.y > 0.0 && p.x < f64::from(n) && p.y < f64::from(n) {
                p + j
            } else {
                p
            };
            DVec3::new(p.x, p.y, 0.3 * rng.next_symmetric())
        })
        .collect();
    (mesh, x)
}

fn mean_radius(x: &[DVec3]) -> f64 {
    x.iter().map(|p| p.length()).sum::<f64>() / x.len() as f64
}

#[test]
fn a_sphere_shrinks_by_the_predicted_factor() {
    // r_n = r_0 (1 − λ⟨ℓ²⟩/(2 r_0²))^n for normalised weights (see docs): the radial part
    // of the move towards the neighbour average is exactly −⟨ℓ²⟩_w/(2r).
    let p = primitives::icosphere(4);
    let mesh = p.mesh().unwrap();
    let lambda = 0.8;
    let mean_l2: f64 = mesh
        .edges()
        .map(|e| {
            let [a, b] = mesh.edge_vertices(e);
            (p.positions[a.index()] - p.positions[b.index()]).length_squared()
        })
        .sum::<f64>()
        / mesh.n_edges() as f64;
    let factor = 1.0 - lambda * mean_l2 / 2.0;
    for scheme in schemes() {
        let mut radii = Vec::new();
        Smoother::new(&mesh, &p.positions, scheme, SmoothConfig::new(lambda, 50))
            .unwrap()
            .run(|it| {
                radii.push(mean_radius(it.positions()));
                ControlFlow::Continue(())
            })
            .unwrap();
        for n in [1usize, 10, 50] {
            let predicted = factor.powi(n as i32);
            let got = radii[n - 1];
            let shrink_error = ((1.0 - got) - (1.0 - predicted)).abs() / (1.0 - predicted);
            assert!(
                shrink_error < 0.03,
                "{} n={n}: r={got}, predicted {predicted} (shrink off by {:.2} %)",
                scheme.name(),
                100.0 * shrink_error
            );
        }
    }
}

#[test]
fn cotangent_keeps_an_irregular_plane_but_uniform_drifts() {
    let g = primitives::grid(10, 10);
    let mesh = g.mesh().unwrap();
    let mut rng = SplitMix64::new(99);
    let x: Vec<DVec3> = g
        .positions
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            if mesh.is_boundary_vertex(VertexId::new(i as u32)) {
                p
            } else {
                p + DVec3::new(rng.next_symmetric(), rng.next_symmetric(), 0.0) * 0.3
            }
        })
        .collect();
    let config = SmoothConfig::new(0.8, 20);
    let cot = smooth(&mesh, &x, &Cotangent, config.clone()).unwrap();
    let uni = smooth(&mesh, &x, &Uniform, config).unwrap();
    let moved = |y: &[DVec3]| {
        x.iter()
            .zip(y)
            .map(|(a, b)| (*a - *b).length())
            .fold(0.0, f64::max)
    };
    assert!(
        moved(&cot.positions) < 1e-12,
        "cotangent moved {}",
        moved(&cot.positions)
    );
    assert!(
        moved(&uni.positions) > 0.05,
        "uniform moved only {}",
        moved(&uni.positions)
    );
    // Every scheme keeps a plane planar.
    assert!(uni.positions.iter().all(|p| p.z == 0.0));
}

#[test]
fn fixed_boundary_is_bit_identical_and_free_boundary_moves() {
    let (mesh, x) = bumpy_grid(8, 4);
    for scheme in schemes() {
        for update in [WeightUpdate::Every, WeightUpdate::Once] {
            let fixed =
                smooth(&mesh, &x, scheme, SmoothConfig::new(0.8, 15).update(update)).unwrap();
            let free = smooth(
                &mesh,
                &x,
                scheme,
                SmoothConfig::new(0.8, 15)
                    .update(update)
                    .boundary(Boundary::Free),
            )
            .unwrap();
            let mut free_moved = false;
            for v in mesh.vertices().filter(|&v| mesh.is_boundary_vertex(v)) {
                let (a, b) = (x[v.index()], fixed.positions[v.index()]);
                assert_eq!(
                    a.to_array().map(f64::to_bits),
                    b.to_array().map(f64::to_bits)
                );
                free_moved |= free.positions[v.index()] != a;
            }
            assert!(free_moved, "{}: free boundary did not move", scheme.name());
        }
    }
}

#[test]
fn curve_boundary_stays_on_the_boundary_polyline() {
    // A flat square patch: boundary vertices may only slide along the square's sides
    // (corners are pulled inwards along the diagonal chord, then stay on the segment).
    let g = primitives::grid(6, 6);
    let mesh = g.mesh().unwrap();
    let mut rng = SplitMix64::new(8);
    // Spread the boundary vertices unevenly along the sides.
    let x: Vec<DVec3> = g
        .positions
        .iter()
        .map(|&p| {
            let mut q = p;
            if p.y == 0.0 || p.y == 6.0 {
                if p.x > 0.0 && p.x < 6.0 {
                    q.x += 0.3 * rng.next_symmetric();
                }
            } else if (p.x == 0.0 || p.x == 6.0) && p.y > 0.0 && p.y < 6.0 {
                q.y += 0.3 * rng.next_symmetric();
            }
            q
        })
        .collect();
    let pinned: Vec<VertexId> = [0u32, 6, 42, 48].map(VertexId::new).to_vec();
    for scheme in schemes() {
        let out = smooth(
            &mesh,
            &x,
            scheme,
            SmoothConfig::new(0.5, 30)
                .boundary(Boundary::Curve)
                .pinned(pinned.clone()),
        )
        .unwrap();
        for v in mesh.vertices().filter(|&v| mesh.is_boundary_vertex(v)) {
            let (a, b) = (x[v.index()], out.positions[v.index()]);
            // Side vertices keep the coordinate that defines their side (up to rounding).
            if a.y == 0.0 || a.y == 6.0 {
                assert!((b.y - a.y).abs() < 1e-12, "{} {v}", scheme.name());
            }
            if a.x == 0.0 || a.x == 6.0 {
                assert!((b.x - a.x).abs() < 1e-12, "{} {v}", scheme.name());
            }
        }
        // Pinned corners did not move; side vertices evened out.
        for v in &pinned {
            assert_eq!(out.positions[v.index()], x[v.index()]);
        }
        let bottom: Vec<f64> = (0..7).map(|i| out.positions[i].x).collect();
        if scheme.name() == "uniform" {
            // Uniform 1-D weights even out the spacing along a straight side.
            for w in bottom.windows(2) {
                assert!((w[1] - w[0] - 1.0).abs() < 0.05, "{bottom:?}");
            }
        } else {
            // 1/length weights are the 1-D cotangent Laplacian: on a straight side the
            // unit tangents cancel, so nothing slides (no tangential drift).
            for (i, b) in bottom.iter().enumerate() {
                assert!((b - x[i].x).abs() < 1e-10, "{}: {bottom:?}", scheme.name());
            }
        }
    }
}

#[test]
fn small_steps_make_small_moves() {
    let (mesh, x) = bumpy_grid(6, 12);
    for scheme in schemes() {
        let step = |lambda: f64| {
            let out = smooth(&mesh, &x, scheme, SmoothConfig::new(lambda, 1)).unwrap();
            out.report.steps[0].max_displacement
        };
        let (a, b) = (step(1e-4), step(2e-4));
        assert!(a > 0.0 && a < 1e-3, "{}: {a}", scheme.name());
        // One explicit step is linear in λ.
        assert!((b / a - 2.0).abs() < 1e-9, "{}: {b} / {a}", scheme.name());
    }
}

#[test]
fn weights_once_is_a_linear_filter_and_every_is_not() {
    let (mesh, x) = bumpy_grid(6, 21);
    // Uniform weights do not depend on positions: both policies agree bit for bit.
    let a = smooth(&mesh, &x, &Uniform, SmoothConfig::new(0.8, 5)).unwrap();
    let b = smooth(
        &mesh,
        &x,
        &Uniform,
        SmoothConfig::new(0.8, 5).update(WeightUpdate::Once),
    )
    .unwrap();
    assert_eq!(a.positions, b.positions);
    // Cotangent weights do.
    let a = smooth(&mesh, &x, &Cotangent, SmoothConfig::new(0.8, 5)).unwrap();
    let b = smooth(
        &mesh,
        &x,
        &Cotangent,
        SmoothConfig::new(0.8, 5).update(WeightUpdate::Once),
    )
    .unwrap();
    assert_ne!(a.positions, b.positions);
    // With frozen weights, smoothing the sum of two fields is the sum of the smoothed
    // fields (linearity), up to rounding.
    let y: Vec<DVec3> = x.iter().map(|p| DVec3::new(p.x, p.y, 0.5 * p.z)).collect();
    let once = |pos: &[DVec3]| {
        let mut s = Smoother::new(
            &mesh,
            &x,
            &Cotangent,
            SmoothConfig::new(0.8, 5).update(WeightUpdate::Once),
        )
        .unwrap();
        // Drive the frozen operator on other data through the Laplacian it assembled.
        let lap = s.laplacian().clone();
        let _ = s.step();
        let mut cur = pos.to_vec();
        for _ in 0..5 {
            let mut next = cur.clone();
            for v in mesh.vertices().filter(|&v| !mesh.is_boundary_vertex(v)) {
                next[v.index()] = cur[v.index()] + lap.laplacian_at(v, &cur).unwrap() * 0.8;
            }
            cur = next;
        }
        cur
    };
    let sum: Vec<DVec3> = x.iter().zip(&y).map(|(a, b)| *a + *b).collect();
    let (sx, sy, ssum) = (once(&x), once(&y), once(&sum));
    for i in 0..x.len() {
        assert!((sx[i] + sy[i] - ssum[i]).length() < 1e-12);
    }
    // And the smoother with frozen weights is exactly that iteration.
    assert_eq!(b.positions, sx);
}

#[test]
fn observer_sees_every_iteration_and_can_stop_the_run() {
    let p = primitives::icosphere(2);
    let mesh = p.mesh().unwrap();
    let mut seen = Vec::new();
    let out = Smoother::new(&mesh, &p.positions, &Cotangent, SmoothConfig::new(0.8, 100))
        .unwrap()
        .run(|it| {
            seen.push(it.index);
            assert_eq!(it.positions().len(), p.positions.len());
            if it.index == 7 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        })
        .unwrap();
    assert_eq!(seen, (1..=7).collect::<Vec<_>>());
    assert_eq!(out.report.iterations, 7);
    assert_eq!(out.report.stop, StopReason::Observer);
    assert_eq!(out.report.steps.len(), 7);
    // The report's statistics are consistent with the positions.
    let full = smooth(&mesh, &p.positions, &Cotangent, SmoothConfig::new(0.8, 1)).unwrap();
    let max = p
        .positions
        .iter()
        .zip(&full.positions)
        .map(|(a, b)| (*a - *b).length())
        .fold(0.0, f64::max);
    assert_eq!(full.report.steps[0].max_displacement, max);
    assert_eq!(full.report.stop, StopReason::Completed);
}

/// The report counts the iterations summed element by element: all of them where
/// `Summation::Scatter` applies (inverse distances on quads too, by edges), none for
/// cotangents on a mesh with quads (its rows are summed as usual) or with the default
/// summation.
#[test]
fn the_report_counts_the_scattered_sweeps() {
    let sweeps = |p: &primitives::Primitive, scheme: &dyn WeightScheme, summation| {
        let mesh = p.mesh().unwrap();
        let config = SmoothConfig::new(0.5, 4).summation(summation);
        smooth(&mesh, &p.positions, scheme, config)
            .unwrap()
            .report
            .scattered_sweeps
    };
    let sphere = primitives::icosphere(2);
    let quads = primitives::cube_quads();
    for scheme in [&Cotangent as &dyn WeightScheme, &InverseDistance] {
        assert_eq!(sweeps(&sphere, scheme, Summation::Scatter), 4);
        assert_eq!(sweeps(&sphere, scheme, Summation::Rows), 0);
    }
    assert_eq!(sweeps(&quads, &Cotangent, Summation::Scatter), 0);
    assert_eq!(sweeps(&quads, &InverseDistance, Summation::Scatter), 4);
}

#[test]
fn invalid_configurations_are_typed_errors() {
    let p = primitives::icosphere(1);
    let mesh = p.mesh().unwrap();
    let err = |config: SmoothConfig| smooth(&mesh, &p.positions, &Uniform, config).unwrap_err();
    insta::assert_snapshot!(err(SmoothConfig::new(0.0, 1)), @"lambda must be in (0, 1] with weight-sum normalisation, got 0");
    insta::assert_snapshot!(err(SmoothConfig::new(1.5, 1)), @"lambda must be in (0, 1] with weight-sum normalisation, got 1.5");
    // The refused value exactly, and a huge one without its 300 digits.
    insta::assert_snapshot!(err(SmoothConfig::new(1.000_000_1, 1)), @"lambda must be in (0, 1] with weight-sum normalisation, got 1.0000001");
    insta::assert_snapshot!(err(SmoothConfig::new(1e300, 1)), @"lambda must be in (0, 1] with weight-sum normalisation, got 1e300");
    insta::assert_snapshot!(err(SmoothConfig::new(0.5, 1).pinned(vec![VertexId::new(99)])), @"pinned vertex 99 does not exist (the mesh has 42 vertices)");
    let mut x = p.positions.clone();
    x[5].y = f64::NAN;
    let e = smooth(&mesh, &x, &Uniform, SmoothConfig::new(0.5, 1)).unwrap_err();
    assert_eq!(e, SmoothError::NonFiniteInput { vertex: 5 });
}
