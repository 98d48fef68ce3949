//! Shrinkage counter-measures (Taubin, volume rescale, HC), physical diffusion time and
//! convergence control.

use std::ops::ControlFlow;

use beltrami_halfedge::geometry::{Geometry, VertexAreaKind};
use beltrami_halfedge::{DVec3, HalfedgeMesh, primitives};
use beltrami_smooth::{
    Boundary, DiffusionTime, Method, SmoothConfig, SmoothError, Smoother, StopReason, WeightUpdate,
    smooth,
};
use beltrami_testkit::SplitMix64;
use beltrami_weights::{
    Cotangent, InverseDistance, LaplacianOptions, Normalization, Uniform, WeightScheme,
};

fn schemes() -> [&'static dyn WeightScheme; 3] {
    [&Uniform, &InverseDistance, &Cotangent]
}

fn sphere(level: u32) -> (HalfedgeMesh, Vec<DVec3>) {
    let s = primitives::icosphere(level);
    (s.mesh().unwrap(), s.positions)
}

/// Radial noise of relative amplitude `amp` on the unit icosphere.
fn noisy_sphere(level: u32, amp: f64, seed: u64) -> (HalfedgeMesh, Vec<DVec3>) {
    let (mesh, x) = sphere(level);
    let mut rng = SplitMix64::new(seed);
    let x = x
        .iter()
        .map(|p| *p * (1.0 + amp * rng.next_symmetric()))
        .collect();
    (mesh, x)
}

fn mean_radius(x: &[DVec3]) -> f64 {
    x.iter().map(|p| p.length()).sum::<f64>() / x.len() as f64
}

fn rms_radius_deviation(x: &[DVec3], r: f64) -> f64 {
    (x.iter().map(|p| (p.length() - r).powi(2)).sum::<f64>() / x.len() as f64).sqrt()
}

fn volume(mesh: &HalfedgeMesh, x: &[DVec3]) -> f64 {
    Geometry::new(mesh, x).unwrap().volume().unwrap()
}

/// A spherical cap of radius 1 (an open patch): an n × n grid mapped onto the sphere.
fn cap(n: u32, noise: f64, seed: u64) -> (HalfedgeMesh, Vec<DVec3>) {
    let g = primitives::grid(n, n);
    let mesh = g.mesh().unwrap();
    let mut rng = SplitMix64::new(seed);
    let half = f64::from(n) / 2.0;
    let x = g
        .positions
        .iter()
        .map(|p| {
            let u = (p.x - half) / f64::from(n) * 1.2;
            let v = (p.y - half) / f64::from(n) * 1.2;
            let d = DVec3::new(u, v, 1.0).normalize();
            d * (1.0 + noise * rng.next_symmetric())
        })
        .collect();
    (mesh, x)
}

#[test]
fn taubin_keeps_the_sphere_radius_within_its_pass_band_bound() {
    let (mesh, x) = sphere(4);
    let (lambda, k_pb) = (0.33, 0.1);
    let method = Method::taubin_pass_band(lambda, k_pb);
    let Method::Taubin { mu } = method else {
        unreachable!()
    };
    let n = 50;
    // Low frequencies pass with a gain in [1, f_max] per iteration.
    let f_max = 1.0 + (lambda + mu).powi(2) / (-4.0 * lambda * mu);
    let bound = f_max.powi(n) - 1.0;
    for scheme in schemes() {
        let r0 = mean_radius(&x);
        let taubin = smooth(
            &mesh,
            &x,
            scheme,
            SmoothConfig::new(lambda, n as usize).method(method),
        )
        .unwrap();
        let plain = smooth(&mesh, &x, scheme, SmoothConfig::new(lambda, n as usize)).unwrap();
        let change = mean_radius(&taubin.positions) / r0 - 1.0;
        let shrink = 1.0 - mean_radius(&plain.positions) / r0;
        assert!(
            change.abs() <= bound,
            "{}: radius change {change:e} outside the bound {bound:e}",
            scheme.name()
        );
        assert!(
            shrink > 20.0 * change.abs(),
            "{}: plain diffusion shrinks by {shrink:e}, Taubin changes by {change:e}",
            scheme.name()
        );
    }
}

#[test]
fn taubin_removes_noise_without_shrinking() {
    let (mesh, x) = noisy_sphere(4, 0.02, 7);
    let out = smooth(
        &mesh,
        &x,
        &Cotangent,
        SmoothConfig::new(0.33, 50).method(Method::taubin_pass_band(0.33, 0.1)),
    )
    .unwrap();
    let before = rms_radius_deviation(&x, mean_radius(&x));
    let after = rms_radius_deviation(&out.positions, mean_radius(&out.positions));
    assert!(after < 0.35 * before, "noise {before:e} -> {after:e}");
    assert!((mean_radius(&out.positions) / mean_radius(&x) - 1.0).abs() < 2e-3);
}

#[test]
fn taubin_rejects_a_mu_outside_the_pass_band_or_an_unstable_one() {
    let (mesh, x) = sphere(1);
    for (lambda, mu) in [(0.5, -0.4), (0.5, f64::NAN), (0.5, 0.2), (0.9, -0.95)] {
        let err = Smoother::new(
            &mesh,
            &x,
            &Uniform,
            SmoothConfig::new(lambda, 1).method(Method::Taubin { mu }),
        )
        .unwrap_err();
        assert!(
            matches!(err, SmoothError::InvalidTaubin { .. }),
            "{lambda} {mu}: {err}"
        );
    }
}

#[test]
fn volume_preservation_keeps_closed_volumes_to_1e_9() {
    let (mesh, x) = noisy_sphere(3, 0.05, 11);
    let torus = primitives::torus(1.0, 0.4, 24, 12);
    let torus_mesh = torus.mesh().unwrap();
    for (mesh, x) in [(&mesh, &x), (&torus_mesh, &torus.positions)] {
        let v0 = volume(mesh, x);
        for scheme in schemes() {
            for method in [Method::Laplacian, Method::taubin_pass_band(0.5, 0.1)] {
                let mut worst: f64 = 0.0;
                let out = Smoother::new(
                    mesh,
                    x,
                    scheme,
                    SmoothConfig::new(0.5, 40)
                        .method(method)
                        .preserve_volume(true),
                )
                .unwrap()
                .run(|it| {
                    worst = worst.max((volume(mesh, it.positions()) / v0 - 1.0).abs());
                    ControlFlow::Continue(())
                })
                .unwrap();
                assert!(
                    worst < 1e-9,
                    "{} {:?}: relative volume error {worst:e}",
                    scheme.name(),
                    method
                );
                // It smoothed: the positions moved.
                assert!(out.report.steps[0].max_displacement > 1e-4);
                // Without the rescale the same run loses volume.
                let plain = smooth(mesh, x, scheme, SmoothConfig::new(0.5, 40)).unwrap();
                assert!(volume(mesh, &plain.positions) / v0 < 0.99);
            }
        }
    }
}

#[test]
fn volume_preservation_needs_a_closed_mesh_without_pins() {
    let (mesh, x) = cap(6, 0.0, 1);
    let err = Smoother::new(
        &mesh,
        &x,
        &Uniform,
        SmoothConfig::new(0.5, 1).preserve_volume(true),
    )
    .unwrap_err();
    assert_eq!(
        err,
        SmoothError::VolumeNeedsClosedMesh { boundary_loops: 1 }
    );
    let (mesh, x) = sphere(1);
    let err = Smoother::new(
        &mesh,
        &x,
        &Uniform,
        SmoothConfig::new(0.5, 1)
            .preserve_volume(true)
            .pinned(vec![beltrami_halfedge::VertexId::new(0)]),
    )
    .unwrap_err();
    assert_eq!(err, SmoothError::VolumeWithPinned);
    // An inside-out sphere, and spheres whose volume the numbers cannot hold (it
    // underflows to 0 at 2^-400 and overflows at 2^400): refused, and the message says
    // what it needs.
    let inverted: Vec<DVec3> = x.iter().map(|&p| -p).collect();
    for (y, volume) in [
        (inverted, None),
        (x.iter().map(|&p| p * 2f64.powi(-400)).collect(), Some(0.0)),
        (
            x.iter().map(|&p| p * 2f64.powi(400)).collect(),
            Some(f64::INFINITY),
        ),
    ] {
        let err = Smoother::new(
            &mesh,
            &y,
            &Uniform,
            SmoothConfig::new(0.5, 1).preserve_volume(true),
        )
        .unwrap_err();
        let SmoothError::DegenerateVolume {
            volume: v,
            iteration: 0,
        } = err
        else {
            panic!("{err:?}");
        };
        if let Some(volume) = volume {
            assert_eq!(v, volume);
        } else {
            assert!(v < 0.0, "{v}");
        }
        let text = err.to_string();
        assert!(
            text.contains("outward-oriented faces") && text.contains("1e-100 to 1e100"),
            "{text}"
        );
    }
}

#[test]
fn hc_keeps_an_open_cap_close_to_its_sphere_while_removing_noise() {
    let (mesh, x) = cap(24, 0.01, 5);
    let n = 30;
    for scheme in schemes() {
        for boundary in [Boundary::Free, Boundary::Fixed] {
            let config = SmoothConfig::new(0.8, n).boundary(boundary);
            let plain = smooth(&mesh, &x, scheme, config.clone()).unwrap();
            let hc = smooth(&mesh, &x, scheme, config.method(Method::hc())).unwrap();
            let noise = rms_radius_deviation(&x, 1.0);
            let plain_err = rms_radius_deviation(&plain.positions, 1.0);
            let hc_err = rms_radius_deviation(&hc.positions, 1.0);
            // HC stays closer to the true sphere than plain diffusion, which shrinks it.
            assert!(
                hc_err < 0.5 * plain_err,
                "{} {boundary:?}: HC {hc_err:e}, plain {plain_err:e}",
                scheme.name()
            );
            // And still removes most of the noise.
            assert!(
                hc_err < 0.7 * noise,
                "{} {boundary:?}: HC {hc_err:e}, noise {noise:e}",
                scheme.name()
            );
        }
    }
}

#[test]
fn hc_rejects_parameters_outside_the_unit_interval() {
    let (mesh, x) = sphere(1);
    let err = Smoother::new(
        &mesh,
        &x,
        &Uniform,
        SmoothConfig::new(0.5, 1).method(Method::Hc {
            alpha: 1.5,
            beta: 0.5,
        }),
    )
    .unwrap_err();
    assert!(matches!(err, SmoothError::InvalidHc { .. }));
}

/// Mean radius after diffusing the unit icosphere of `level` for time `t`.
fn radius_after(level: u32, config: SmoothConfig, scheme: &dyn WeightScheme) -> (f64, usize) {
    let (mesh, x) = sphere(level);
    let out = smooth(&mesh, &x, scheme, config).unwrap();
    (mean_radius(&out.positions), out.report.iterations)
}

#[test]
fn a_diffusion_time_does_not_depend_on_the_mesh_density() {
    // Mean-curvature flow of the unit sphere: r(t)² = 1 − 4t.
    let t: f64 = 0.01;
    let expected = (1.0 - 4.0 * t).sqrt();
    let area =
        LaplacianOptions::new().normalization(Normalization::Area(VertexAreaKind::Barycentric));
    let cases: [(&dyn WeightScheme, SmoothConfig); 3] = [
        (&Cotangent, SmoothConfig::new(1.0, 1).laplacian(area)),
        (&Cotangent, SmoothConfig::new(0.8, 1)),
        (&Uniform, SmoothConfig::new(0.8, 1)),
    ];
    for (scheme, config) in cases {
        let timed = config.clone().duration(DiffusionTime::Time(t));
        let (coarse, n_coarse) = radius_after(3, timed.clone(), scheme);
        let (fine, n_fine) = radius_after(5, timed, scheme);
        // Finer mesh, more (smaller) steps for the same time.
        assert!(n_fine > 8 * n_coarse, "{n_coarse} vs {n_fine}");
        let timed_gap = (coarse - fine).abs();
        assert!(
            (fine - expected).abs() < 2e-3 && (coarse - expected).abs() < 5e-3,
            "{}: {coarse} / {fine} vs {expected}",
            scheme.name()
        );
        // The same λ × iterations on both meshes: the coarse sphere shrinks far more.
        let same_steps = config.iterations(n_coarse);
        let (coarse_n, _) = radius_after(3, same_steps.clone(), scheme);
        let (fine_n, _) = radius_after(5, same_steps, scheme);
        let step_gap = (coarse_n - fine_n).abs();
        assert!(
            step_gap > 5.0 * timed_gap,
            "{}: same time differs by {timed_gap:e}, same steps by {step_gap:e}",
            scheme.name()
        );
    }
}

#[test]
fn a_cutoff_wavelength_passes_half_the_amplitude() {
    // A sinusoidal height field of period P over a large flat grid, fixed boundary:
    // filtered with λc = P, the Gaussian filter transmits 50 % of the amplitude.
    let n = 120;
    let period = 20.0;
    let g = primitives::grid(n, n);
    let mesh = g.mesh().unwrap();
    let wave = |p: &DVec3| (2.0 * std::f64::consts::PI * p.x / period).sin();
    let x: Vec<DVec3> = g
        .positions
        .iter()
        .map(|p| DVec3::new(p.x, p.y, wave(p)))
        .collect();
    let area =
        LaplacianOptions::new().normalization(Normalization::Area(VertexAreaKind::Barycentric));
    for config in [
        SmoothConfig::new(0.8, 1),
        SmoothConfig::new(1.0, 1).laplacian(area),
    ] {
        let out = smooth(
            &mesh,
            &x,
            &Cotangent,
            config.duration(DiffusionTime::Cutoff(period)),
        )
        .unwrap();
        // Amplitude by projection onto the wave, away from the fixed boundary.
        let (mut num, mut den) = (0.0, 0.0);
        for (p, q) in x.iter().zip(&out.positions) {
            if p.x > 30.0 && p.x < 90.0 && p.y > 30.0 && p.y < 90.0 {
                num += q.z * wave(p);
                den += wave(p) * wave(p);
            }
        }
        let transmission = num / den;
        assert!(
            (transmission - 0.5).abs() < 0.02,
            "transmission {transmission}"
        );
    }
}

#[test]
fn invalid_durations_are_typed_errors() {
    let (mesh, x) = sphere(1);
    for d in [
        DiffusionTime::Time(-1.0),
        DiffusionTime::Cutoff(f64::NAN),
        DiffusionTime::Cutoff(-1.0),
    ] {
        let err =
            Smoother::new(&mesh, &x, &Uniform, SmoothConfig::new(0.5, 1).duration(d)).unwrap_err();
        assert!(matches!(err, SmoothError::InvalidDuration { .. }), "{err}");
    }
    let err = Smoother::new(
        &mesh,
        &x,
        &Uniform,
        SmoothConfig::new(0.3, 1)
            .duration(DiffusionTime::Time(0.1))
            .method(Method::taubin_pass_band(0.3, 0.1)),
    )
    .unwrap_err();
    assert!(matches!(err, SmoothError::InvalidDuration { .. }), "{err}");
}

#[test]
fn until_change_stops_when_the_iterations_settle() {
    let (mesh, x) = cap(12, 0.01, 3);
    let out = smooth(
        &mesh,
        &x,
        &Uniform,
        SmoothConfig::new(0.5, 10_000)
            .update(WeightUpdate::Once)
            .until_change(1e-6),
    )
    .unwrap();
    assert_eq!(out.report.stop, StopReason::Converged);
    assert!(out.report.iterations < 10_000);
    let last = out.report.steps.last().unwrap();
    assert!(last.max_displacement <= 1e-6);
    assert!(
        out.report.steps[out.report.steps.len() - 2].max_displacement > 1e-6,
        "stopped late"
    );
    let err = Smoother::new(
        &mesh,
        &x,
        &Uniform,
        SmoothConfig::new(0.5, 1).until_change(0.0),
    )
    .unwrap_err();
    assert_eq!(err, SmoothError::InvalidUntilChange { value: 0.0 });
}

#[test]
fn the_area_step_is_a_share_of_the_explicit_stability_limit() {
    let area =
        LaplacianOptions::new().normalization(Normalization::Area(VertexAreaKind::MixedVoronoi));
    let config = |boundary| SmoothConfig::new(1.0, 3).laplacian(area).boundary(boundary);
    // An open, irregular patch (noise in the plane) whose boundary rows differ from
    // the interior ones, with one vertex pinned.
    let g = primitives::grid(12, 9);
    let mesh = g.mesh().unwrap();
    let mut rng = SplitMix64::new(7);
    let x: Vec<DVec3> = g
        .positions
        .iter()
        .map(|p| *p + DVec3::new(rng.next_symmetric(), rng.next_symmetric(), 0.0) * 0.15)
        .collect();
    for (boundary, pinned) in [
        (Boundary::Fixed, vec![]),
        (Boundary::Free, vec![]),
        (Boundary::Free, vec![beltrami_halfedge::VertexId::new(40)]),
    ] {
        let c = config(boundary).pinned(pinned.clone());
        let step = beltrami_smooth::area_step(&mesh, &x, &Cotangent, &c, 1.0)
            .unwrap()
            .unwrap();
        // Exactly the limit the explicit smoother checks a step against.
        let smoother = Smoother::new(&mesh, &x, &Cotangent, c.clone()).unwrap();
        assert_eq!(
            Some(step),
            smoother.stable_step_limit(),
            "{boundary:?} {pinned:?}"
        );
        // A fraction of it is that fraction, and a run of it is stable.
        let share = beltrami_smooth::area_step(&mesh, &x, &Cotangent, &c, 0.8)
            .unwrap()
            .unwrap();
        assert!((share / step - 0.8).abs() < 1e-15, "{share} {step}");
        let mut run = c.clone();
        run.lambda = share;
        let out = smooth(&mesh, &x, &Cotangent, run).unwrap();
        assert!(out.positions.iter().all(|p| p.is_finite() && p.z == 0.0));
    }
    // On a near-regular mesh (the level-4 icosphere) it is about a quarter of the
    // squared edge length: W/A = 4/h² on a regular triangle mesh.
    let (sphere, y) = sphere(4);
    let h2 = {
        let g = Geometry::new(&sphere, &y).unwrap();
        let lengths: Vec<f64> = sphere.edges().map(|e| g.edge_length(e)).collect();
        lengths.iter().map(|l| l * l).sum::<f64>() / lengths.len() as f64
    };
    let step = beltrami_smooth::area_step(&sphere, &y, &Cotangent, &config(Boundary::Fixed), 1.0)
        .unwrap()
        .unwrap();
    assert!(
        step > 0.15 * h2 && step < 0.25 * h2,
        "{step} against h² {h2}"
    );
    // Weight-sum rows have no such step; positions that do not fit are the operator's
    // error.
    let sum = SmoothConfig::new(0.8, 3);
    assert_eq!(
        beltrami_smooth::area_step(&sphere, &y, &Cotangent, &sum, 0.8),
        Ok(None)
    );
    assert!(matches!(
        beltrami_smooth::area_step(&sphere, &y[1..], &Cotangent, &config(Boundary::Fixed), 0.8),
        Err(SmoothError::Weights(_))
    ));
    // Nothing moves (every vertex pinned): no step.
    let all = config(Boundary::Fixed).pinned(sphere.vertices().collect());
    assert_eq!(
        beltrami_smooth::area_step(&sphere, &y, &Cotangent, &all, 0.8),
        Ok(None)
    );
}
