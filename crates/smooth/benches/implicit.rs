//! Implicit smoothing: one backward-Euler cotangent step (area normalisation, mixed
//! Voronoi mass) on a noisy icosphere of level 6 (40 962 vertices) and 8 (655 362
//! vertices). `cholesky_first` is a whole first step (weights, assembly, symbolic
//! analysis, numeric factorisation, solve); `cholesky_frozen` a later step with the
//! operator frozen (right-hand side and triangular solves only); `cholesky_every` a
//! later step with the weights recomputed (assembly, numeric factorisation, solve);
//! `cg_first` a whole first step by conjugate gradient (weights, assembly, solve: no
//! set-up beyond the matrix) and `cg_frozen` a frozen step by conjugate gradient
//! (relative tolerance 1e-8, the three coordinates at once). `cg_sum_first` and
//! `cg_sum_frozen` are the command line's default step (`--method implicit`:
//! weight-sum normalisation, `t = 0.8`, conjugate gradient to 1e-10), the case of the
//! implicit-step targets in `benches/targets.py`. `cargo bench -p beltrami-smooth --bench implicit` (`-- cg_` for the
//! conjugate-gradient cases only; the Cholesky set-up still runs once).

#![allow(missing_docs)]

use beltrami_halfedge::geometry::VertexAreaKind;
use beltrami_halfedge::{DVec3, HalfedgeMesh};
use beltrami_smooth::{ImplicitSolver, Method, SmoothConfig, Smoother, WeightUpdate, smooth};
use beltrami_testkit::fixtures::jittered_icosphere;
use beltrami_weights::{Cotangent, LaplacianOptions, Normalization};
use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;

fn config(edge: f64, update: WeightUpdate, solver: ImplicitSolver) -> SmoothConfig {
    // A step of ten edge lengths squared: far beyond the explicit limit (about ℓ²/4).
    SmoothConfig::new(10.0 * edge * edge, 1_000_000)
        .update(update)
        .laplacian(
            LaplacianOptions::new()
                .normalization(Normalization::Area(VertexAreaKind::MixedVoronoi)),
        )
        .method(Method::implicit(solver))
}

fn smoother<'a>(mesh: &'a HalfedgeMesh, positions: &[DVec3], config: SmoothConfig) -> Smoother<'a> {
    let mut s = Smoother::new(mesh, positions, &Cotangent, config).expect("valid");
    s.step().expect("first step");
    s
}

fn bench_implicit(c: &mut Criterion) {
    let cg = ImplicitSolver::ConjugateGradient {
        tolerance: 1e-8,
        max_iterations: 10_000,
    };
    for level in [6u32, 8] {
        let sphere = jittered_icosphere(level);
        let edge = 1.1 / f64::from(1u32 << level);
        let mesh = sphere.mesh().expect("icosphere is a valid mesh");
        let x = &sphere.positions;
        let mut group = c.benchmark_group(format!("implicit_icosphere{level}"));
        group.sample_size(10);
        group.warm_up_time(std::time::Duration::from_secs(1));
        group.measurement_time(std::time::Duration::from_secs(5));

        let once = config(edge, WeightUpdate::Once, ImplicitSolver::Cholesky);
        group.bench_function("cholesky_first", |b| {
            b.iter(|| black_box(smoother(&mesh, x, once.clone()).positions()[0]));
        });
        let mut frozen = smoother(&mesh, x, once.clone());
        group.bench_function("cholesky_frozen", |b| {
            b.iter(|| black_box(frozen.step().expect("step")));
        });
        let mut every = smoother(
            &mesh,
            x,
            config(edge, WeightUpdate::Every, ImplicitSolver::Cholesky),
        );
        group.bench_function("cholesky_every", |b| {
            b.iter(|| black_box(every.step().expect("step")));
        });
        let cg_once = config(edge, WeightUpdate::Once, cg);
        group.bench_function("cg_first", |b| {
            b.iter(|| black_box(smoother(&mesh, x, cg_once.clone()).positions()[0]));
        });
        let mut cg_frozen = smoother(&mesh, x, cg_once.clone());
        group.bench_function("cg_frozen", |b| {
            b.iter(|| black_box(cg_frozen.step().expect("step")));
        });
        let sum = SmoothConfig::new(0.8, 1_000_000)
            .update(WeightUpdate::Once)
            .method(Method::implicit(ImplicitSolver::conjugate_gradient()));
        group.bench_function("cg_sum_first", |b| {
            b.iter(|| black_box(smoother(&mesh, x, sum.clone()).positions()[0]));
        });
        let mut sum_frozen = smoother(&mesh, x, sum.clone());
        group.bench_function("cg_sum_frozen", |b| {
            b.iter(|| black_box(sum_frozen.step().expect("step")));
        });
        group.finish();

        // The breakdown of a two-step run (one factorisation) and the factor size.
        let mut two = config(edge, WeightUpdate::Once, ImplicitSolver::Cholesky);
        two.iterations = 2;
        let report = smooth(&mesh, x, &Cotangent, two).expect("valid").report;
        let solver = report.solver.as_ref().expect("an implicit run");
        let cg_step = cg_frozen
            .step()
            .expect("step")
            .solve
            .expect("an implicit step");
        eprintln!(
            "level {level}: {} vertices; two Cholesky steps: assembly {:?}, analysis {:?}, \
             factorisation {:?}, solves {:?}; factor non-zeros {}; \
             CG iterations per frozen step {} (residual {:.1e})",
            x.len(),
            report.weight_time,
            solver.analysis_time,
            solver.factorization_time,
            report.update_time,
            solver.factor_nonzeros,
            cg_step.cg_iterations,
            cg_step.residual.unwrap_or(0.0),
        );
    }
}

criterion_group!(benches, bench_implicit);
criterion_main!(benches);
