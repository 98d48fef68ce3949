//! Internal vertex reordering changes no bit: `Reorder::Always` against `Reorder::Never`
//! for every scheme, method, boundary mode, update policy, normalisation, with and
//! without volume preservation, a diffusion time and pinned vertices, on a closed noisy
//! sphere, a bumpy open grid and a grid with isolated vertices; and the same errors on
//! runs that blow up. The one exception, cotangent rows recomputed every iteration and
//! summed triangle by triangle (`Summation::Scatter`, `sums_by_scatter`), is held to
//! rounding instead.

use std::ops::ControlFlow;

use beltrami_halfedge::geometry::VertexAreaKind;
use beltrami_halfedge::{DVec3, HalfedgeId, HalfedgeMesh, VertexId, primitives};
use beltrami_smooth::{
    Boundary, DiffusionTime, Method, Reorder, SmoothConfig, SmoothError, Smoother, Statistics,
    StepStats, Summation, WeightUpdate,
};
use beltrami_testkit::fixtures::jitter;
use beltrami_testkit::numbering::{ROUNDING, max_difference, sums_by_scatter};
use beltrami_weights::{
    Cotangent, InverseDistance, LaplacianOptions, Normalization, Uniform, WeightContext,
    WeightScheme,
};

struct TestMesh {
    name: &'static str,
    mesh: HalfedgeMesh,
    positions: Vec<DVec3>,
    closed: bool,
}

fn meshes() -> Vec<TestMesh> {
    let mut sphere = primitives::icosphere(3);
    jitter(&mut sphere.positions, 0.03, 1);
    let mut grid = primitives::grid(17, 13);
    for p in &mut grid.positions {
        p.z = 0.1 * (3.0 * p.x).sin() * (2.0 * p.y).cos();
    }
    jitter(&mut grid.positions, 0.01, 2);
    // The grid again with isolated vertices before, among and after the used ones.
    let n = grid.positions.len() as u32;
    let remap = |v: u32| if v < n / 2 { v + 1 } else { v + 2 };
    let mut positions = vec![DVec3::new(9.0, 9.0, 9.0)];
    positions.extend_from_slice(&grid.positions[..(n / 2) as usize]);
    positions.push(DVec3::new(-3.0, 0.5, 1.0));
    positions.extend_from_slice(&grid.positions[(n / 2) as usize..]);
    positions.push(DVec3::new(0.25, -7.0, 2.0));
    let faces: Vec<Vec<u32>> = grid
        .faces
        .iter()
        .map(|f| f.iter().map(|&v| remap(v)).collect())
        .collect();
    let isolated = HalfedgeMesh::from_polygons(positions.len(), &faces).unwrap();
    vec![
        TestMesh {
            name: "sphere",
            mesh: sphere.mesh().unwrap(),
            positions: sphere.positions,
            closed: true,
        },
        TestMesh {
            name: "grid",
            mesh: grid.mesh().unwrap(),
            positions: grid.positions,
            closed: false,
        },
        TestMesh {
            name: "isolated",
            mesh: isolated,
            positions,
            closed: false,
        },
    ]
}

/// A scheme without a built-in kernel (the generic weight path): inverse distance
/// written out, NaN on edges whose end lies beyond `nan_beyond` in x.
struct Custom {
    nan_beyond: f64,
}

impl WeightScheme for Custom {
    fn name(&self) -> &str {
        "custom"
    }

    fn weight(&self, ctx: &WeightContext<'_>, h: HalfedgeId) -> f64 {
        let to = ctx.mesh().to_vertex(h);
        if ctx.position(to).x > self.nan_beyond {
            return f64::NAN;
        }
        1.0 / (ctx.edge_length(h) + 1e-3)
    }
}

/// `a` and `b` are the same run to rounding: the same errors, iterations and stuck
/// counts, positions within [`ROUNDING`] and displacement statistics within a relative
/// 1e-9 (a mean of displacements near 1e-3 carries the positions' rounding).
fn same_to_rounding(a: &Seen, b: &Seen, label: &str) {
    assert_eq!(format!("{:?}", a.new), format!("{:?}", b.new), "{label}");
    let stats = |x: &[u64; 3], y: &[u64; 3]| {
        assert_eq!(x[2], y[2], "{label}: stuck vertices");
        for k in 0..2 {
            let (p, q) = (f64::from_bits(x[k]), f64::from_bits(y[k]));
            assert!(
                (p - q).abs() <= 1e-9 * p.abs().max(q.abs()),
                "{label}: {p} against {q}"
            );
        }
    };
    assert_eq!(a.observed.len(), b.observed.len(), "{label}");
    for (x, y) in a.observed.iter().zip(&b.observed) {
        assert_eq!(x.0, y.0, "{label}");
        let d = max_difference(&x.1, &y.1);
        assert!(d <= ROUNDING, "{label}: iteration {} differs by {d:e}", x.0);
        stats(&x.2, &y.2);
    }
    match (&a.result, &b.result) {
        (Some(Ok((p, s, a))), Some(Ok((q, t, b)))) => {
            assert_eq!(a, b, "{label}: triangle sweeps");
            let d = max_difference(p, q);
            assert!(d <= ROUNDING, "{label}: the result differs by {d:e}");
            assert_eq!(s.len(), t.len(), "{label}");
            for (x, y) in s.iter().zip(t) {
                stats(x, y);
            }
        }
        (x, y) => assert_eq!(format!("{x:?}"), format!("{y:?}"), "{label}"),
    }
}

/// Everything a caller sees of a run (compared as Debug text, since errors may carry
/// NaN values; positions and statistics are bit patterns).
#[derive(Debug)]
struct Seen {
    new: Result<(u64, usize), SmoothError>,
    observed: Vec<(usize, Bits, [u64; 3])>,
    /// Positions, step statistics, and the iterations summed by triangles.
    result: Option<Result<(Bits, Bits, usize), SmoothError>>,
}

/// Bit patterns of vectors.
type Bits = Vec<[u64; 3]>;

fn bits(p: &[DVec3]) -> Vec<[u64; 3]> {
    p.iter()
        .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
        .collect()
}

fn stat_bits(s: &StepStats) -> [u64; 3] {
    [
        s.max_displacement.to_bits(),
        s.mean_displacement.to_bits(),
        s.stuck_vertices as u64,
    ]
}

fn observe(m: &TestMesh, scheme: &dyn WeightScheme, config: SmoothConfig) -> Seen {
    let smoother = match Smoother::new(&m.mesh, &m.positions, scheme, config) {
        Ok(s) => s,
        Err(e) => {
            return Seen {
                new: Err(e),
                observed: Vec::new(),
                result: None,
            };
        }
    };
    let new = Ok((
        smoother.config().lambda.to_bits(),
        smoother.config().iterations,
    ));
    let mut observed = Vec::new();
    let result = smoother
        .run(|it| {
            observed.push((it.index, bits(it.positions()), stat_bits(&it.stats())));
            ControlFlow::Continue(())
        })
        .map(|out| {
            (
                bits(&out.positions),
                out.report.steps.iter().map(stat_bits).collect(),
                out.report.scattered_sweeps,
            )
        });
    Seen {
        new,
        observed,
        result: Some(result),
    }
}

/// Runs `config` with and without reordering; returns whether the run succeeded. The
/// runs are the same bits, or for a configuration that sums its rows element by
/// element ([`sums_by_scatter`]) the same to rounding ([`same_to_rounding`]).
fn same(m: &TestMesh, scheme: &dyn WeightScheme, config: SmoothConfig) -> bool {
    if config.summation == Summation::Rows
        && [Cotangent.name(), InverseDistance.name()].contains(&scheme.name())
    {
        same(m, scheme, config.clone().summation(Summation::Scatter));
    }
    let never = observe(m, scheme, config.clone().reorder(Reorder::Never));
    let always = observe(m, scheme, config.clone().reorder(Reorder::Always));
    if sums_by_scatter(scheme, &config) {
        same_to_rounding(&never, &always, &format!("{} {config:?}", m.name));
        // Every iteration of a run that went through was scattered.
        if let Some(Ok((_, _, sweeps))) = &never.result {
            assert_eq!(*sweeps, never.observed.len(), "{} {config:?}", m.name);
        }
        return matches!(never.result, Some(Ok(_)));
    }
    assert!(
        format!("{never:?}") == format!("{always:?}"),
        "{} / {} / {config:?}: reordering changed the run\nnever: {:?}\nalways: {:?}",
        m.name,
        scheme.name(),
        never.result.as_ref().map(|r| r.as_ref().err()),
        always.result.as_ref().map(|r| r.as_ref().err()),
    );
    matches!(never.result, Some(Ok(_)))
}

#[test]
fn reordering_changes_no_bit() {
    let custom = Custom {
        nan_beyond: f64::INFINITY,
    };
    let schemes: [&dyn WeightScheme; 4] = [&Uniform, &InverseDistance, &Cotangent, &custom];
    let mut runs = 0;
    let mut ok = 0;
    for m in meshes() {
        // Vertices in the middle of the numbering, both used ones (isolated mesh: 1 is
        // used, 0 is not).
        let pinned = vec![
            VertexId::new(0),
            VertexId::new(1),
            VertexId::new(m.positions.len() as u32 / 3),
        ];
        for scheme in schemes {
            for normalization in [
                Normalization::WeightSum,
                Normalization::Area(VertexAreaKind::MixedVoronoi),
            ] {
                let weight_sum = normalization == Normalization::WeightSum;
                let lambda = if weight_sum { 0.6 } else { 2e-4 };
                let methods = [
                    Method::Laplacian,
                    Method::Taubin {
                        mu: if weight_sum { -0.63 } else { -2.1e-4 },
                    },
                    Method::hc(),
                ];
                for method in methods {
                    for boundary in [Boundary::Fixed, Boundary::Free, Boundary::Curve] {
                        if boundary == Boundary::Curve && !weight_sum {
                            continue;
                        }
                        for update in [WeightUpdate::Every, WeightUpdate::Once] {
                            for volume in [false, true] {
                                if volume && !m.closed {
                                    continue;
                                }
                                for with_pinned in [false, true] {
                                    if volume && with_pinned {
                                        continue;
                                    }
                                    let mut config = SmoothConfig::new(lambda, 4)
                                        .method(method)
                                        .boundary(boundary)
                                        .update(update)
                                        .preserve_volume(volume)
                                        .laplacian(
                                            LaplacianOptions::new().normalization(normalization),
                                        );
                                    if with_pinned {
                                        config = config.pinned(pinned.clone());
                                    }
                                    runs += 1;
                                    ok += usize::from(same(&m, scheme, config.clone()));
                                    if method == Method::Laplacian {
                                        let duration =
                                            config.duration(DiffusionTime::Time(if weight_sum {
                                                3e-3
                                            } else {
                                                1e-3
                                            }));
                                        runs += 1;
                                        ok += usize::from(same(&m, scheme, duration));
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    // Nearly every configuration runs to the end (the rest must fail identically).
    assert!(ok * 10 >= runs * 9, "{ok} of {runs} runs succeeded");
}

#[test]
fn blow_ups_report_the_same_error() {
    let area =
        LaplacianOptions::new().normalization(Normalization::Area(VertexAreaKind::MixedVoronoi));
    let mut errors = 0;
    for m in meshes() {
        for method in [
            Method::Laplacian,
            Method::Taubin { mu: -2e30 },
            Method::hc(),
        ] {
            for volume in [false, true] {
                if volume && !m.closed {
                    continue;
                }
                for scheme in [&Cotangent as &dyn WeightScheme, &Uniform] {
                    let config = SmoothConfig::new(1e30, 60)
                        .method(method)
                        .preserve_volume(volume)
                        .boundary(Boundary::Free)
                        .laplacian(area);
                    let never = observe(&m, scheme, config.clone().reorder(Reorder::Never));
                    let always = observe(&m, scheme, config.reorder(Reorder::Always));
                    assert_eq!(
                        format!("{never:?}"),
                        format!("{always:?}"),
                        "{} / {method:?} / {volume}",
                        m.name
                    );
                    errors += usize::from(matches!(never.result, Some(Err(_))));
                }
            }
        }
    }
    assert!(errors >= 5, "only {errors} runs failed");
}

#[test]
fn weight_and_input_errors_name_the_callers_vertices() {
    for m in meshes() {
        // Non-finite weights as soon as a vertex moves beyond x = 0.2 (the grid spans
        // [0, 1]; the sphere [-1, 1]): in assembly on the sphere, later on the grid.
        for nan_beyond in [0.2, 0.97] {
            let custom = Custom { nan_beyond };
            for boundary in [Boundary::Free, Boundary::Curve] {
                let config = SmoothConfig::new(0.5, 5).boundary(boundary);
                let never = observe(&m, &custom, config.clone().reorder(Reorder::Never));
                let always = observe(&m, &custom, config.reorder(Reorder::Always));
                // Debug text: the errors carry NaN values.
                assert_eq!(format!("{never:?}"), format!("{always:?}"), "{}", m.name);
            }
        }
        // A non-finite input and a pinned vertex out of range.
        let mut bad = m.positions.clone();
        bad[m.positions.len() / 2].y = f64::NAN;
        bad[m.positions.len() / 3].x = f64::INFINITY;
        for config in [
            SmoothConfig::new(0.5, 2),
            SmoothConfig::new(0.5, 2).pinned(vec![VertexId::new(1 << 30)]),
        ] {
            let run = |reorder| {
                Smoother::new(&m.mesh, &bad, &Uniform, config.clone().reorder(reorder))
                    .map(|s| bits(&s.positions()))
            };
            assert_eq!(run(Reorder::Never), run(Reorder::Always));
        }
        // Too few positions.
        let short = &m.positions[1..];
        let run = |reorder| {
            Smoother::new(
                &m.mesh,
                short,
                &Uniform,
                SmoothConfig::new(0.5, 2).reorder(reorder),
            )
            .map(|s| bits(&s.positions()))
        };
        assert_eq!(run(Reorder::Never), run(Reorder::Always));
    }
}

#[test]
fn stepping_by_hand_sees_the_callers_numbering() {
    for m in meshes() {
        let config = SmoothConfig::new(0.5, 3).method(Method::hc());
        let mut never = Smoother::new(
            &m.mesh,
            &m.positions,
            &Cotangent,
            config.clone().reorder(Reorder::Never),
        )
        .unwrap();
        let mut always = Smoother::new(
            &m.mesh,
            &m.positions,
            &Cotangent,
            config.reorder(Reorder::Always),
        )
        .unwrap();
        assert!(never.permutation().is_none());
        let perm = always.permutation().unwrap().clone();
        assert_eq!(bits(&never.positions()), bits(&always.positions()));
        for _ in 0..3 {
            let (a, b) = (never.step().unwrap(), always.step().unwrap());
            assert_eq!(stat_bits(&a), stat_bits(&b));
            assert_eq!(bits(&never.positions()), bits(&always.positions()));
        }
        // The operator is in the internal numbering.
        let v = VertexId::new(1);
        let internal: Vec<(u32, u64)> = always
            .laplacian()
            .row(perm.to_new(v))
            .map(|(j, w)| (perm.to_old(j).raw(), w.to_bits()))
            .collect();
        let plain: Vec<(u32, u64)> = never
            .laplacian()
            .row(v)
            .map(|(j, w)| (j.raw(), w.to_bits()))
            .collect();
        assert_eq!(internal, plain);
    }
}

#[test]
fn auto_reorders_large_meshes_only() {
    let small = primitives::icosphere(2);
    let mesh = small.mesh().unwrap();
    let s = Smoother::new(&mesh, &small.positions, &Uniform, SmoothConfig::new(0.5, 1)).unwrap();
    assert!(s.permutation().is_none());
    let large = primitives::icosphere(7); // 163 842 vertices
    let mesh = large.mesh().unwrap();
    let s = Smoother::new(&mesh, &large.positions, &Uniform, SmoothConfig::new(0.5, 1)).unwrap();
    assert!(s.permutation().is_some());
    let s = Smoother::new(
        &mesh,
        &large.positions,
        &Uniform,
        SmoothConfig::new(0.5, 1).reorder(Reorder::Never),
    )
    .unwrap();
    assert!(s.permutation().is_none());
}

/// The positions, per-iteration statistics (asked of the observer when `ask`), report
/// steps, iteration count and stop reason of a run.
type Lazy = (Bits, Vec<[u64; 3]>, Vec<[u64; 3]>, usize, String);

fn run_lazy(m: &TestMesh, scheme: &dyn WeightScheme, config: SmoothConfig, ask: bool) -> Lazy {
    let mut asked = Vec::new();
    let out = Smoother::new(&m.mesh, &m.positions, scheme, config)
        .unwrap()
        .run(|it| {
            if ask {
                asked.push(stat_bits(&it.stats()));
                // Asked twice, the same answer.
                assert_eq!(stat_bits(&it.stats()), *asked.last().unwrap());
            }
            ControlFlow::Continue(())
        })
        .unwrap();
    (
        bits(&out.positions),
        asked,
        out.report.steps.iter().map(stat_bits).collect(),
        out.report.iterations,
        format!("{:?} {}", out.report.stop, out.report.max_stuck_vertices),
    )
}

#[test]
fn statistics_on_demand_are_the_same_bits() {
    let schemes: [&dyn WeightScheme; 3] = [&Uniform, &InverseDistance, &Cotangent];
    for m in meshes() {
        for scheme in schemes {
            for boundary in [Boundary::Fixed, Boundary::Free, Boundary::Curve] {
                for method in [Method::Laplacian, Method::hc()] {
                    let base = SmoothConfig::new(0.8, 6).boundary(boundary).method(method);
                    for (reorder, summation) in [
                        (Reorder::Never, Summation::Rows),
                        (Reorder::Always, Summation::Rows),
                        (Reorder::Never, Summation::Scatter),
                        (Reorder::Always, Summation::Scatter),
                    ] {
                        // Against the eager run in the same numbering (reordering itself
                        // is the test above).
                        let base = base.clone().reorder(reorder).summation(summation);
                        let every = run_lazy(&m, scheme, base.clone(), true);
                        assert_eq!(every.2.len(), 6);
                        assert_eq!(every.1, every.2, "{} {}", m.name, scheme.name());
                        let config = base
                            .clone()
                            .reorder(reorder)
                            .statistics(Statistics::OnDemand);
                        // Asked by the observer: the eager run's statistics.
                        let asked = run_lazy(&m, scheme, config.clone(), true);
                        assert_eq!(asked.0, every.0, "{} {} {reorder:?}", m.name, scheme.name());
                        assert_eq!(asked.1, every.2, "{} {} {reorder:?}", m.name, scheme.name());
                        assert!(asked.2.is_empty());
                        assert_eq!(asked.4, every.4);
                        // Not asked: the same positions.
                        let quiet = run_lazy(&m, scheme, config.clone(), false);
                        assert_eq!(quiet.0, every.0);
                        assert!(quiet.1.is_empty() && quiet.2.is_empty());
                        // A convergence stop finds the same iteration.
                        let eps = f64::from_bits(every.2[3][0]);
                        let until = run_lazy(&m, scheme, config.until_change(eps), false);
                        let until_every =
                            run_lazy(&m, scheme, base.clone().until_change(eps), false);
                        assert_eq!(until.3, until_every.3);
                        assert!(until.3 <= 4, "{} {}", m.name, scheme.name());
                        assert_eq!(until.0, until_every.0);
                        assert_eq!(until.4, until_every.4);
                    }
                }
            }
        }
    }
}

#[test]
fn advance_moves_like_step() {
    for m in meshes() {
        for reorder in [Reorder::Never, Reorder::Always] {
            let config = SmoothConfig::new(0.8, 5)
                .boundary(Boundary::Free)
                .reorder(reorder);
            let mut a = Smoother::new(&m.mesh, &m.positions, &Cotangent, config.clone()).unwrap();
            let mut b = Smoother::new(&m.mesh, &m.positions, &Cotangent, config).unwrap();
            for _ in 0..5 {
                a.step().unwrap();
                b.advance().unwrap();
            }
            assert_eq!(b.iteration(), 5);
            assert_eq!(bits(&a.positions()), bits(&b.positions()));
            assert_ne!(bits(&b.positions()), bits(&m.positions));
        }
    }
}
