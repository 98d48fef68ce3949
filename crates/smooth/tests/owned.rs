//! A smoother given its mesh and positions by value (`Smoother::from_owned`, which
//! renumbers the mesh in place) changes no bit against one that borrows them
//! (`Smoother::new`): positions, observer positions and statistics, the chosen step and
//! errors, for every scheme, method, boundary mode and update policy, with and without
//! reordering, explicit and implicit; and `run_owned` hands back the mesh exactly as it
//! was given.

use std::ops::ControlFlow;

use beltrami_halfedge::geometry::VertexAreaKind;
use beltrami_halfedge::{DVec3, HalfedgeId, HalfedgeMesh, VertexId, primitives};
use beltrami_smooth::{
    Boundary, DiffusionTime, ImplicitSolver, Method, Reorder, SmoothConfig, SmoothError, Smoother,
    Statistics, StepStats, Summation, WeightUpdate,
};
use beltrami_testkit::fixtures::jitter;
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

/// A noisy closed sphere, a bumpy open grid, and a torus with an isolated vertex.
fn meshes() -> Vec<TestMesh> {
    let mut sphere = primitives::icosphere(3);
    jitter(&mut sphere.positions, 0.03, 1);
    let mut grid = primitives::grid(15, 11);
    for p in &mut grid.positions {
        p.z = 0.1 * (3.0 * p.x).sin() * (2.0 * p.y).cos();
    }
    jitter(&mut grid.positions, 0.01, 2);
    let torus = primitives::torus(2.0, 0.6, 18, 9);
    let mut positions = torus.positions.clone();
    jitter(&mut positions, 0.02, 3);
    positions.push(DVec3::new(5.0, -1.0, 0.5));
    let isolated = HalfedgeMesh::from_polygons(positions.len(), torus.faces.iter()).unwrap();
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
            name: "torus and an isolated vertex",
            mesh: isolated,
            positions,
            closed: false,
        },
    ]
}

/// Inverse distance through the generic weight path, NaN on edges whose end lies
/// beyond `nan_beyond` in x.
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

type Bits = Vec<[u64; 3]>;

fn bits(p: &[DVec3]) -> Bits {
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

/// Everything a caller sees of a run but its wall times (compared as Debug text, since
/// errors may carry NaN values).
#[derive(Debug)]
#[expect(dead_code, reason = "compared through its Debug text")]
struct Seen {
    new: Result<(u64, usize, Option<u64>), SmoothError>,
    observed: Vec<(usize, Bits, [u64; 3])>,
    result: Option<Result<Outcome, SmoothError>>,
}

/// The result of a finished run: positions, per-iteration statistics, the iteration
/// count and stop reason, the stuck vertices, the solver's counts.
#[derive(Debug)]
#[expect(dead_code, reason = "compared through its Debug text")]
struct Outcome {
    positions: Bits,
    steps: Vec<[u64; 3]>,
    iterations: usize,
    stop: String,
    stuck: usize,
    solver: Option<(usize, usize, usize, usize)>,
}

/// Runs `config` on `m`, borrowing the mesh (`owned` false) or giving it by value; the
/// mesh handed back is checked against the input.
fn observe(m: &TestMesh, scheme: &dyn WeightScheme, config: SmoothConfig, owned: bool) -> Seen {
    let made = if owned {
        Smoother::from_owned(m.mesh.clone(), m.positions.clone(), scheme, config)
    } else {
        Smoother::new(&m.mesh, &m.positions, scheme, config)
    };
    let smoother = match made {
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
        smoother.stable_step_limit().map(f64::to_bits),
    ));
    let mut observed = Vec::new();
    let result = smoother
        .run_owned(|it| {
            observed.push((it.index, bits(it.positions()), stat_bits(&it.stats())));
            ControlFlow::Continue(())
        })
        .map(|(out, mesh)| {
            if owned {
                assert_eq!(
                    mesh.as_ref(),
                    Some(&m.mesh),
                    "{}: the mesh handed back",
                    m.name
                );
            } else {
                assert!(mesh.is_none(), "a borrowed mesh is not handed back");
            }
            let r = out.report;
            Outcome {
                positions: bits(&out.positions),
                steps: r.steps.iter().map(stat_bits).collect(),
                iterations: r.iterations,
                stop: r.stop.name().to_string(),
                stuck: r.max_stuck_vertices,
                solver: r.solver.map(|s| {
                    (
                        s.symbolic_factorizations,
                        s.numeric_factorizations,
                        s.factor_nonzeros,
                        s.cg_iterations,
                    )
                }),
            }
        });
    Seen {
        new,
        observed,
        result: Some(result),
    }
}

/// Runs `config` borrowed and owned, with and without reordering (each against the
/// borrowed run with the same setting: what reordering itself changes is
/// `reorder.rs`'s subject); returns whether the run succeeded.
fn same(m: &TestMesh, scheme: &dyn WeightScheme, config: SmoothConfig) -> bool {
    if config.summation == Summation::Rows
        && [Cotangent.name(), InverseDistance.name()].contains(&scheme.name())
    {
        same(m, scheme, config.clone().summation(Summation::Scatter));
    }
    let mut succeeded = true;
    for reorder in [Reorder::Never, Reorder::Always] {
        let borrowed = observe(m, scheme, config.clone().reorder(reorder), false);
        let want = format!("{borrowed:?}");
        succeeded &= matches!(borrowed.result, Some(Ok(_)));
        let owned = observe(m, scheme, config.clone().reorder(reorder), true);
        assert!(
            format!("{owned:?}") == want,
            "{} / {} / {reorder:?} / {config:?}: giving the mesh by value changed the run\nborrowed: {:?}\nowned: {:?}",
            m.name,
            scheme.name(),
            borrowed.result.as_ref().map(|r| r.as_ref().err()),
            owned.result.as_ref().map(|r| r.as_ref().err()),
        );
    }
    succeeded
}

#[test]
fn owning_the_mesh_changes_no_bit() {
    let custom = Custom {
        nan_beyond: f64::INFINITY,
    };
    let schemes: [&dyn WeightScheme; 4] = [&Uniform, &InverseDistance, &Cotangent, &custom];
    let (mut runs, mut ok) = (0, 0);
    for m in meshes() {
        let pinned = vec![
            VertexId::new(1),
            VertexId::new(m.positions.len() as u32 / 3),
        ];
        for scheme in schemes {
            for method in [
                Method::Laplacian,
                Method::Taubin { mu: -0.63 },
                Method::hc(),
                Method::implicit(ImplicitSolver::conjugate_gradient()),
                Method::implicit(ImplicitSolver::Cholesky),
            ] {
                let implicit = matches!(method, Method::Implicit { .. });
                for boundary in [Boundary::Fixed, Boundary::Free, Boundary::Curve] {
                    if boundary == Boundary::Curve && implicit {
                        continue;
                    }
                    for update in [WeightUpdate::Every, WeightUpdate::Once] {
                        for volume in [false, true] {
                            if volume && (!m.closed || implicit) {
                                continue;
                            }
                            let lambda = if implicit { 3.0 } else { 0.6 };
                            let mut config = SmoothConfig::new(lambda, 3)
                                .method(method)
                                .boundary(boundary)
                                .update(update)
                                .preserve_volume(volume);
                            if !volume {
                                config = config.pinned(pinned.clone());
                            }
                            if method == Method::Laplacian {
                                // Statistics only when the observer asks (what the
                                // command does without --report).
                                let on_demand = config.clone().statistics(Statistics::OnDemand);
                                runs += 1;
                                ok += usize::from(same(&m, scheme, on_demand));
                            }
                            runs += 1;
                            ok += usize::from(same(&m, scheme, config));
                        }
                    }
                }
            }
        }
        // Area normalisation and a diffusion time, explicit and implicit.
        let area = LaplacianOptions::new()
            .normalization(Normalization::Area(VertexAreaKind::MixedVoronoi));
        for method in [
            Method::Laplacian,
            Method::implicit(ImplicitSolver::conjugate_gradient()),
        ] {
            for scheme in [&Cotangent as &dyn WeightScheme, &Uniform] {
                let config = SmoothConfig::new(1e-3, 3)
                    .method(method)
                    .laplacian(area)
                    .duration(DiffusionTime::Time(2e-3));
                runs += 1;
                ok += usize::from(same(&m, scheme, config));
            }
        }
    }
    assert!(ok * 10 >= runs * 9, "{ok} of {runs} runs succeeded");
}

#[test]
fn errors_are_the_same_when_the_mesh_is_given() {
    let mut blow_ups = 0;
    for m in meshes() {
        // Non-finite weights: in assembly or during the run.
        for nan_beyond in [0.2, 0.97] {
            let custom = Custom { nan_beyond };
            for boundary in [Boundary::Free, Boundary::Curve] {
                same(&m, &custom, SmoothConfig::new(0.5, 5).boundary(boundary));
            }
        }
        // Blow-ups.
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
                        .laplacian(
                            LaplacianOptions::new()
                                .normalization(Normalization::Area(VertexAreaKind::MixedVoronoi)),
                        );
                    blow_ups += usize::from(!same(&m, scheme, config));
                }
            }
        }
        // Bad settings and bad input are refused before any work.
        let mut bad = m.positions.clone();
        bad[m.positions.len() / 2].y = f64::NAN;
        let cases = [
            (m.positions.clone(), SmoothConfig::new(2.0, 2)),
            (bad, SmoothConfig::new(0.5, 2)),
            (
                m.positions.clone(),
                SmoothConfig::new(0.5, 2).pinned(vec![VertexId::new(1 << 30)]),
            ),
            (m.positions[1..].to_vec(), SmoothConfig::new(0.5, 2)),
        ];
        for (positions, config) in cases {
            for reorder in [Reorder::Never, Reorder::Always] {
                let config = config.clone().reorder(reorder);
                let borrowed = Smoother::new(&m.mesh, &positions, &Uniform, config.clone())
                    .map(|s| bits(&s.positions()));
                let owned =
                    Smoother::from_owned(m.mesh.clone(), positions.clone(), &Uniform, config)
                        .map(|s| bits(&s.positions()));
                assert!(borrowed.is_err(), "{}", m.name);
                assert_eq!(format!("{borrowed:?}"), format!("{owned:?}"), "{}", m.name);
            }
        }
    }
    assert!(blow_ups >= 5, "only {blow_ups} runs failed");
}

#[test]
fn stepping_an_owned_smoother_gives_the_callers_numbering() {
    let m = &meshes()[0];
    let config = SmoothConfig::new(0.5, 4).reorder(Reorder::Always);
    let mut borrowed = Smoother::new(&m.mesh, &m.positions, &Cotangent, config.clone()).unwrap();
    let mut owned =
        Smoother::from_owned(m.mesh.clone(), m.positions.clone(), &Cotangent, config).unwrap();
    assert_eq!(borrowed.permutation(), owned.permutation());
    assert!(owned.permutation().is_some());
    for _ in 0..3 {
        let (a, b) = (borrowed.step().unwrap(), owned.step().unwrap());
        assert_eq!(stat_bits(&a), stat_bits(&b));
        assert_eq!(bits(&borrowed.positions()), bits(&owned.positions()));
    }
    assert_ne!(bits(&owned.positions()), bits(&m.positions));
    let rows = |s: &Smoother<'_>| -> Vec<(u32, u64)> {
        let l = s.laplacian();
        (0..l.n_rows() as u32)
            .flat_map(|v| {
                l.row(VertexId::new(v))
                    .map(|(j, w)| (j.raw(), w.to_bits()))
                    .collect::<Vec<_>>()
            })
            .collect()
    };
    assert_eq!(rows(&borrowed), rows(&owned));
    // Stopped early by the observer: the mesh still comes back as given.
    let owned = Smoother::from_owned(
        m.mesh.clone(),
        m.positions.clone(),
        &Cotangent,
        SmoothConfig::new(0.5, 10).reorder(Reorder::Always),
    )
    .unwrap();
    let (out, mesh) = owned.run_owned(|_| ControlFlow::Break(())).unwrap();
    assert_eq!(out.report.iterations, 1);
    assert_eq!(mesh.as_ref(), Some(&m.mesh));
}
