//! Implicit (backward Euler) smoothing: against a dense solve built here from the
//! formulas, first-order agreement with the explicit step, stability, boundary,
//! factorisation reuse, conjugate gradient, determinism and errors.

// The dense reference reads best with the textbook's indices.
#![allow(clippy::needless_range_loop)]

use std::ops::ControlFlow;

use beltrami_halfedge::geometry::{Geometry, VertexAreaKind};
use beltrami_halfedge::primitives::{self, Primitive};
use beltrami_halfedge::{DVec3, HalfedgeId, HalfedgeMesh, VertexId};
use beltrami_smooth::{
    Boundary, ImplicitSolver, Method, SmoothConfig, SmoothError, Smoother, WeightUpdate, smooth,
};
use beltrami_testkit::Lcg64;
use beltrami_weights::{
    Cotangent, InverseDistance, Laplacian, LaplacianOptions, NegativeWeights, Normalization,
    Uniform, WeightContext, WeightScheme,
};

/// `steps` backward-Euler steps of time `t`, solved by Cholesky.
fn implicit(t: f64, steps: usize) -> SmoothConfig {
    SmoothConfig::new(t, steps).method(Method::implicit(ImplicitSolver::Cholesky))
}

/// A deterministic jitter of every vertex by up to `amplitude` per coordinate: the
/// generator starts at the odd state `seed · 0x9E37_79B9_7F4A_7C15 | 1`.
fn jitter(positions: &mut [DVec3], amplitude: f64, seed: u64) {
    let mut rng = Lcg64::new(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
    for p in positions {
        *p += rng.next_symmetric_vector() * amplitude;
    }
}

fn noisy(mut prim: Primitive, amplitude: f64) -> (HalfedgeMesh, Vec<DVec3>) {
    jitter(&mut prim.positions, amplitude, 7);
    let mesh = prim.mesh().unwrap();
    (mesh, prim.positions)
}

fn options(normalization: Normalization) -> LaplacianOptions {
    LaplacianOptions::new().normalization(normalization)
}

const NORMALIZATIONS: [Normalization; 3] = [
    Normalization::WeightSum,
    Normalization::Area(VertexAreaKind::Barycentric),
    Normalization::Area(VertexAreaKind::MixedVoronoi),
];

// ---------------------------------------------------------------------------------
// The dense reference, from the formulas.

#[derive(Clone, Copy, Debug)]
enum Kind {
    Uniform,
    Distance,
    Cotangent,
}

/// `w_ij` as a dense matrix, computed from the positions here.
fn dense_weights(mesh: &HalfedgeMesh, x: &[DVec3], kind: Kind) -> Vec<Vec<f64>> {
    let n = x.len();
    let mut w = vec![vec![0.0; n]; n];
    match kind {
        Kind::Uniform | Kind::Distance => {
            for e in mesh.edges() {
                let [a, b] = mesh.edge_vertices(e);
                let (a, b) = (a.index(), b.index());
                let v = match kind {
                    Kind::Uniform => 1.0,
                    _ => 1.0 / ((x[b] - x[a]).length() + 1e-12),
                };
                w[a][b] = v;
                w[b][a] = v;
            }
        }
        Kind::Cotangent => {
            for f in mesh.faces() {
                let [a, b, c] = mesh.triangle_vertices(f).map(|v| v.index());
                for (o, p, q) in [(a, b, c), (b, c, a), (c, a, b)] {
                    let (u, v) = (x[p] - x[o], x[q] - x[o]);
                    let cot = u.dot(v) / u.cross(v).length();
                    w[p][q] += 0.5 * cot;
                    w[q][p] += 0.5 * cot;
                }
            }
        }
    }
    w
}

/// Barycentric areas from the faces, here; mixed Voronoi from the geometry crate.
fn dense_areas(mesh: &HalfedgeMesh, x: &[DVec3], kind: VertexAreaKind) -> Vec<f64> {
    match kind {
        VertexAreaKind::Barycentric => {
            let mut a = vec![0.0; x.len()];
            for f in mesh.faces() {
                let [p, q, r] = mesh.triangle_vertices(f).map(|v| v.index());
                let area = 0.5 * (x[q] - x[p]).cross(x[r] - x[p]).length();
                for v in [p, q, r] {
                    a[v] += area / 3.0;
                }
            }
            a
        }
        _ => Geometry::new(mesh, x)
            .unwrap()
            .vertex_areas(kind)
            .unwrap()
            .as_slice()
            .to_vec(),
    }
}

/// Solves the symmetric positive definite `a y = b` by a dense Cholesky factorisation.
fn dense_cholesky_solve(a: &[Vec<f64>], b: &[f64]) -> Vec<f64> {
    let n = b.len();
    let mut l = vec![vec![0.0; n]; n];
    for j in 0..n {
        let mut d = a[j][j];
        for k in 0..j {
            d -= l[j][k] * l[j][k];
        }
        assert!(d > 0.0, "the dense matrix is not positive definite");
        l[j][j] = d.sqrt();
        for i in j + 1..n {
            let mut s = a[i][j];
            for k in 0..j {
                s -= l[i][k] * l[j][k];
            }
            l[i][j] = s / l[j][j];
        }
    }
    let mut y = b.to_vec();
    for i in 0..n {
        for k in 0..i {
            y[i] -= l[i][k] * y[k];
        }
        y[i] /= l[i][i];
    }
    for i in (0..n).rev() {
        for k in i + 1..n {
            y[i] -= l[k][i] * y[k];
        }
        y[i] /= l[i][i];
    }
    y
}

/// One backward-Euler step `(M + t K) x' = M x` with Dirichlet rows, densely.
fn dense_step(
    mesh: &HalfedgeMesh,
    x: &[DVec3],
    kind: Kind,
    normalization: Normalization,
    boundary: Boundary,
    t: f64,
) -> Vec<DVec3> {
    let n = x.len();
    let w = dense_weights(mesh, x, kind);
    let sums: Vec<f64> = w.iter().map(|row| row.iter().sum()).collect();
    let mass = match normalization {
        Normalization::WeightSum => sums.clone(),
        Normalization::Area(k) => dense_areas(mesh, x, k),
        _ => unreachable!(),
    };
    let fixed: Vec<bool> = mesh
        .vertices()
        .map(|v| mesh.is_isolated(v) || (boundary == Boundary::Fixed && mesh.is_boundary_vertex(v)))
        .collect();
    let mut a = vec![vec![0.0; n]; n];
    for i in 0..n {
        if fixed[i] {
            a[i][i] = 1.0;
            continue;
        }
        a[i][i] = mass[i] + t * sums[i];
        for j in 0..n {
            if j != i && !fixed[j] {
                a[i][j] = -t * w[i][j];
            }
        }
    }
    let mut out = vec![DVec3::ZERO; n];
    for c in 0..3 {
        let b: Vec<f64> = (0..n)
            .map(|i| {
                if fixed[i] {
                    return x[i][c];
                }
                let mut s = mass[i] * x[i][c];
                for j in 0..n {
                    if fixed[j] {
                        s += t * w[i][j] * x[j][c];
                    }
                }
                s
            })
            .collect();
        for (o, y) in out.iter_mut().zip(dense_cholesky_solve(&a, &b)) {
            o[c] = y;
        }
    }
    out
}

fn max_diff(a: &[DVec3], b: &[DVec3]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (*p - *q).abs().max_element())
        .fold(0.0, f64::max)
}

fn max_abs(a: &[DVec3]) -> f64 {
    a.iter().map(|p| p.abs().max_element()).fold(0.0, f64::max)
}

fn scheme_of(kind: Kind) -> &'static dyn WeightScheme {
    match kind {
        Kind::Uniform => &Uniform,
        Kind::Distance => &InverseDistance,
        Kind::Cotangent => &Cotangent,
    }
}

#[test]
fn one_step_matches_a_dense_solve() {
    let cases: Vec<(&str, HalfedgeMesh, Vec<DVec3>, Boundary, f64)> = {
        let (grid, gx) = noisy(primitives::grid(6, 5), 0.2);
        let (sphere, sx) = noisy(primitives::icosphere(2), 0.02);
        let (tet, tx) = noisy(primitives::tetrahedron(), 0.05);
        vec![
            ("grid fixed", grid.clone(), gx.clone(), Boundary::Fixed, 0.7),
            ("grid free", grid, gx, Boundary::Free, 0.7),
            ("icosphere", sphere, sx, Boundary::Fixed, 0.05),
            ("tetrahedron", tet, tx, Boundary::Fixed, 0.3),
        ]
    };
    for (name, mesh, x, boundary, t_area) in &cases {
        for kind in [Kind::Uniform, Kind::Distance, Kind::Cotangent] {
            for normalization in NORMALIZATIONS {
                let t = if normalization == Normalization::WeightSum {
                    2.5
                } else {
                    *t_area
                };
                let config = implicit(t, 1)
                    .boundary(*boundary)
                    .laplacian(options(normalization));
                let got = smooth(mesh, x, scheme_of(kind), config).unwrap();
                let want = dense_step(mesh, x, kind, normalization, *boundary, t);
                let err = max_diff(&got.positions, &want) / max_abs(&want);
                assert!(
                    err <= 1e-10,
                    "{name} {kind:?} {normalization:?}: relative error {err:e}"
                );
                // The step did something.
                assert!(max_diff(&got.positions, x) > 1e-3 * max_abs(x), "{name}");
                // The conjugate-gradient solver agrees to its tolerance.
                let config = implicit(t, 1)
                    .boundary(*boundary)
                    .laplacian(options(normalization))
                    .method(Method::implicit(ImplicitSolver::ConjugateGradient {
                        tolerance: 1e-13,
                        max_iterations: 500,
                    }));
                let cg = smooth(mesh, x, scheme_of(kind), config).unwrap();
                let err = max_diff(&cg.positions, &want) / max_abs(&want);
                assert!(err <= 1e-9, "{name} {kind:?} {normalization:?} CG: {err:e}");
            }
        }
    }
}

#[test]
fn a_small_step_agrees_with_the_explicit_step_to_first_order() {
    // x' − (x + t L x) = t² L² x + O(t³): halving t divides the difference by 4.
    let (sphere, x) = noisy(primitives::icosphere(3), 0.01);
    let (grid, gx) = noisy(primitives::grid(8, 8), 0.1);
    let area = Normalization::Area(VertexAreaKind::MixedVoronoi);
    for (mesh, x, normalization, t) in [
        (&sphere, &x, area, 4e-5),
        (&grid, &gx, area, 5e-3),
        (&grid, &gx, Normalization::WeightSum, 5e-3),
    ] {
        let difference = |t: f64| {
            let explicit = beltrami_smooth::smooth(
                mesh,
                x,
                &Cotangent,
                SmoothConfig::new(t, 1).laplacian(options(normalization)),
            )
            .unwrap();
            let implicit = smooth(
                mesh,
                x,
                &Cotangent,
                implicit(t, 1).laplacian(options(normalization)),
            )
            .unwrap();
            let moved = max_diff(&explicit.positions, x);
            (max_diff(&implicit.positions, &explicit.positions), moved)
        };
        let (d1, moved) = difference(t);
        let (d2, _) = difference(t / 2.0);
        let (d4, _) = difference(t / 4.0);
        assert!(d1 < 0.1 * moved, "{normalization:?}: {d1:e} vs {moved:e}");
        for ratio in [d1 / d2, d2 / d4] {
            assert!(
                (3.6..4.4).contains(&ratio),
                "{normalization:?}: ratio {ratio} ({d1:e}, {d2:e}, {d4:e})"
            );
        }
    }
}

#[test]
fn a_huge_step_stays_finite_and_inside_the_input_hull() {
    let (grid, x) = noisy(primitives::grid(12, 10), 0.3);
    let (lo, hi) = x
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        });
    let clamp = LaplacianOptions::new()
        .normalization(Normalization::Area(VertexAreaKind::Barycentric))
        .negative(NegativeWeights::Clamp);
    let lambda = 50.0;
    // The explicit step blows up at this step size (with the operator frozen: when
    // it is recomputed, the growing areas slow the blow-up down) ...
    let explicit = beltrami_smooth::smooth(
        &grid,
        &x,
        &Cotangent,
        SmoothConfig::new(lambda, 200)
            .laplacian(clamp)
            .update(WeightUpdate::Once),
    );
    match explicit {
        Err(SmoothError::NonFinite { .. }) => {}
        Ok(out) => assert!(max_abs(&out.positions) > 1e6, "explicit did not blow up"),
        Err(e) => panic!("unexpected error {e}"),
    }
    // ... the implicit one does not, whatever the step, and with non-negative weights
    // every vertex stays within the bounding box of the input (a discrete maximum
    // principle: each new position is a convex combination).
    for (scheme, options) in [
        (&Cotangent as &dyn WeightScheme, clamp),
        (&Uniform, LaplacianOptions::default()),
        (&InverseDistance, options(Normalization::WeightSum)),
    ] {
        for boundary in [Boundary::Fixed, Boundary::Free] {
            for (t, update) in [
                (lambda, WeightUpdate::Once),
                (lambda, WeightUpdate::Every),
                (1e8, WeightUpdate::Every),
            ] {
                // With a free boundary a huge step collapses the patch towards a point
                // at once; weights recomputed from that degenerate patch are not a
                // test of stability, so that flow takes one step only.
                let steps = if boundary == Boundary::Free && update == WeightUpdate::Every {
                    1
                } else {
                    20
                };
                let config = implicit(t, steps)
                    .boundary(boundary)
                    .laplacian(options)
                    .update(update);
                let out = smooth(&grid, &x, scheme, config).unwrap_or_else(|e| {
                    panic!("{} {boundary:?} {t} {update:?}: {e}", scheme.name())
                });
                for p in &out.positions {
                    assert!(p.is_finite());
                    let slack = DVec3::splat(1e-9);
                    assert!(p.cmpge(lo - slack).all() && p.cmple(hi + slack).all());
                }
            }
        }
    }
}

#[test]
fn fixed_boundary_pinned_and_isolated_vertices_keep_their_bits() {
    let mut prim = primitives::grid(7, 6);
    jitter(&mut prim.positions, 0.25, 3);
    // An isolated vertex after the grid's.
    let n = prim.positions.len();
    prim.positions.push(DVec3::new(3.0, 3.0, 5.0));
    let mesh = HalfedgeMesh::from_polygons(n + 1, prim.faces.iter()).unwrap();
    let pinned = VertexId::new(20);
    assert!(!mesh.is_boundary_vertex(pinned));
    for solver in [
        ImplicitSolver::Cholesky,
        ImplicitSolver::conjugate_gradient(),
    ] {
        for normalization in NORMALIZATIONS {
            let config = implicit(0.5, 3)
                .laplacian(options(normalization))
                .pinned(vec![pinned])
                .method(Method::implicit(solver));
            let out = smooth(&mesh, &prim.positions, &Cotangent, config).unwrap();
            for v in mesh.vertices() {
                let still = mesh.is_boundary_vertex(v) || v == pinned;
                let (a, b) = (out.positions[v.index()], prim.positions[v.index()]);
                if still {
                    assert_eq!(
                        a.to_array().map(f64::to_bits),
                        b.to_array().map(f64::to_bits)
                    );
                } else {
                    assert_ne!(a, b, "interior vertex {v:?} did not move");
                }
            }
        }
    }
}

#[test]
fn a_frozen_operator_is_factorised_once() {
    let (sphere, x) = noisy(primitives::icosphere(3), 0.01);
    let area = options(Normalization::Area(VertexAreaKind::MixedVoronoi));
    let run = |scheme: &dyn WeightScheme, update, laplacian| {
        let config = implicit(1e-3, 5).update(update).laplacian(laplacian);
        smooth(&sphere, &x, scheme, config).unwrap().report
    };
    let once = run(&Cotangent, WeightUpdate::Once, area);
    assert_eq!(once.solver.as_ref().unwrap().symbolic_factorizations, 1);
    assert_eq!(once.solver.as_ref().unwrap().numeric_factorizations, 1);
    let factorised: Vec<bool> = once
        .steps
        .iter()
        .map(|s| s.solve.unwrap().factorized)
        .collect();
    assert_eq!(factorised, [true, false, false, false, false]);
    assert!(once.solver.as_ref().unwrap().factor_nonzeros > 0);

    let every = run(&Cotangent, WeightUpdate::Every, area);
    assert_eq!(every.solver.as_ref().unwrap().symbolic_factorizations, 1);
    assert_eq!(every.solver.as_ref().unwrap().numeric_factorizations, 5);
    assert!(every.steps.iter().all(|s| s.solve.unwrap().factorized));

    // Uniform weights with weight-sum normalisation never change.
    let uniform = run(&Uniform, WeightUpdate::Every, LaplacianOptions::default());
    assert_eq!(uniform.solver.as_ref().unwrap().numeric_factorizations, 1);

    // Frozen steps are a linear filter: the same as one step applied five times with
    // the matrix of the input.
    let mut smoother = Smoother::new(
        &sphere,
        &x,
        &Cotangent,
        implicit(1e-3, 5).update(WeightUpdate::Once).laplacian(area),
    )
    .unwrap();
    let factorised = (0..5)
        .filter(|_| smoother.step().unwrap().solve.unwrap().factorized)
        .count();
    assert_eq!(factorised, 1);
    let batch = smooth(
        &sphere,
        &x,
        &Cotangent,
        implicit(1e-3, 5).update(WeightUpdate::Once).laplacian(area),
    )
    .unwrap();
    assert_eq!(smoother.positions(), batch.positions.as_slice());
}

#[test]
fn conjugate_gradient_agrees_with_cholesky() {
    let (sphere, x) = noisy(primitives::icosphere(4), 0.005);
    for (normalization, t) in [
        (Normalization::Area(VertexAreaKind::MixedVoronoi), 1e-2),
        (Normalization::WeightSum, 20.0),
    ] {
        let config = implicit(t, 3).laplacian(options(normalization));
        let direct = smooth(&sphere, &x, &Cotangent, config.clone()).unwrap();
        let tolerance = 1e-10;
        let cg = smooth(
            &sphere,
            &x,
            &Cotangent,
            config.method(Method::implicit(ImplicitSolver::ConjugateGradient {
                tolerance,
                max_iterations: 2000,
            })),
        )
        .unwrap();
        assert_eq!(cg.report.solver.as_ref().unwrap().numeric_factorizations, 0);
        assert_eq!(cg.report.solver.as_ref().unwrap().factor_nonzeros, 0);
        assert!(cg.report.solver.as_ref().unwrap().cg_iterations > 0);
        for s in &cg.report.steps {
            let r = s.solve.unwrap().residual.unwrap();
            assert!(r <= tolerance, "residual {r:e}");
            assert!(s.solve.unwrap().cg_iterations > 0);
        }
        assert!(
            direct
                .report
                .steps
                .iter()
                .all(|s| s.solve.unwrap().residual.is_none())
        );
        let err = max_diff(&cg.positions, &direct.positions);
        assert!(err <= 1e-7, "{normalization:?}: {err:e}");
    }
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    // Level 5 has 10 242 vertices: several parallel chunks.
    let (sphere, x) = noisy(primitives::icosphere(5), 0.002);
    for solver in [
        ImplicitSolver::Cholesky,
        ImplicitSolver::conjugate_gradient(),
    ] {
        let run = |threads| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let config = implicit(1e-3, 2)
                    .laplacian(options(Normalization::Area(VertexAreaKind::MixedVoronoi)))
                    .method(Method::implicit(solver));
                smooth(&sphere, &x, &Cotangent, config).unwrap()
            })
        };
        let (one, two) = (run(1), run(2));
        let bits = |p: &[DVec3]| -> Vec<u64> {
            p.iter()
                .flat_map(|v| v.to_array().map(f64::to_bits))
                .collect()
        };
        assert_eq!(bits(&one.positions), bits(&two.positions), "{solver:?}");
        assert_eq!(one.report.steps, two.report.steps);
    }
}

/// Uniform weights, except a strongly negative weight on edge 0–1.
struct NegativeEdge;

impl WeightScheme for NegativeEdge {
    fn name(&self) -> &str {
        "negative-edge"
    }
    fn weight(&self, ctx: &WeightContext<'_>, h: HalfedgeId) -> f64 {
        let mesh = ctx.mesh();
        let ends = [mesh.from_vertex(h).raw(), mesh.to_vertex(h).raw()];
        if ends == [0, 1] || ends == [1, 0] {
            -1.5
        } else {
            1.0
        }
    }
}

#[test]
fn an_indefinite_system_is_a_typed_error() {
    let tet = primitives::tetrahedron();
    let mesh = tet.mesh().unwrap();
    // With a small step the mass dominates: positive definite, solved.
    let small = smooth(&mesh, &tet.positions, &NegativeEdge, implicit(0.01, 1));
    assert!(small.is_ok(), "{small:?}");
    // With a large one the negative edge wins.
    let err = smooth(&mesh, &tet.positions, &NegativeEdge, implicit(100.0, 1)).unwrap_err();
    assert_eq!(err, SmoothError::NotPositiveDefinite { iteration: 1 });
    assert!(err.to_string().contains("clamp"));
    // Clamping the negative weight makes it smooth again.
    let clamped = smooth(
        &mesh,
        &tet.positions,
        &NegativeEdge,
        implicit(100.0, 1).laplacian(LaplacianOptions::new().negative(NegativeWeights::Clamp)),
    );
    assert!(clamped.is_ok());
}

#[test]
fn negative_cotangent_weights_still_give_a_positive_definite_system() {
    // Strong tangential jitter makes obtuse triangles and negative cotangent weights;
    // the cotangent stiffness is still the (positive semi-definite) Dirichlet energy.
    let mut prim = primitives::grid(10, 10);
    jitter(&mut prim.positions, 0.45, 11);
    let mesh = prim.mesh().unwrap();
    let lap = Laplacian::new(
        &mesh,
        &prim.positions,
        &Cotangent,
        LaplacianOptions::default(),
    )
    .unwrap();
    let negative = mesh
        .vertices()
        .flat_map(|v| lap.row(v).map(|(_, w)| w).collect::<Vec<_>>())
        .filter(|w| *w < 0.0)
        .count();
    assert!(negative > 0, "the test mesh needs negative weights");
    for normalization in NORMALIZATIONS {
        let out = smooth(
            &mesh,
            &prim.positions,
            &Cotangent,
            implicit(1e6, 3).laplacian(options(normalization)),
        )
        .unwrap();
        assert!(out.positions.iter().all(|p| p.is_finite()));
    }
}

#[test]
fn invalid_settings_are_typed_errors() {
    let grid = primitives::grid(3, 3);
    let mesh = grid.mesh().unwrap();
    let x = &grid.positions;
    let err = |config| {
        Smoother::new(&mesh, x, &Uniform, config)
            .map(|_| ())
            .unwrap_err()
    };
    for t in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            err(implicit(t, 1)),
            SmoothError::InvalidLambda { .. }
        ));
    }
    assert_eq!(
        err(implicit(1.0, 1).boundary(Boundary::Curve)),
        SmoothError::CurveNotImplicit
    );
    for (tolerance, max_iterations) in [(0.0, 10), (1.0, 10), (f64::NAN, 10), (1e-8, 0)] {
        assert_eq!(
            err(
                implicit(1.0, 1).method(Method::implicit(ImplicitSolver::ConjugateGradient {
                    tolerance,
                    max_iterations
                }))
            )
            .to_string(),
            SmoothError::InvalidSolverSettings {
                tolerance,
                max_iterations
            }
            .to_string()
        );
    }
    assert!(matches!(
        err(implicit(1.0, 1).pinned(vec![VertexId::new(99)])),
        SmoothError::PinnedOutOfRange { vertex: 99, .. }
    ));
    let mut bad = x.clone();
    bad[2].y = f64::NAN;
    assert_eq!(
        Smoother::new(&mesh, &bad, &Uniform, implicit(1.0, 1))
            .map(|_| ())
            .unwrap_err(),
        SmoothError::NonFiniteInput { vertex: 2 }
    );
}

#[test]
fn conjugate_gradient_that_runs_out_of_iterations_is_an_error() {
    let (sphere, x) = noisy(primitives::icosphere(3), 0.01);
    let config = implicit(50.0, 1).method(Method::implicit(ImplicitSolver::ConjugateGradient {
        tolerance: 1e-14,
        max_iterations: 2,
    }));
    let mut smoother = Smoother::new(&sphere, &x, &Cotangent, config).unwrap();
    match smoother.step() {
        Err(SmoothError::NotConverged {
            iteration: 1,
            iterations: 2,
            residual,
            tolerance,
        }) => assert!(residual > tolerance && residual.is_finite()),
        other => panic!("{other:?}"),
    }
    // The positions are left as they were.
    assert_eq!(smoother.positions(), x.as_slice());
}

#[test]
fn the_observer_sees_every_step_and_can_stop_the_run() {
    let (sphere, x) = noisy(primitives::icosphere(2), 0.02);
    let mut seen = Vec::new();
    let out = Smoother::new(&sphere, &x, &Cotangent, implicit(1.0, 10))
        .unwrap()
        .run(|it| {
            seen.push((it.index, it.stats().max_displacement));
            if it.index == 4 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        })
        .unwrap();
    assert_eq!(seen.len(), 4);
    assert_eq!(out.report.iterations, 4);
    assert_eq!(out.report.steps.len(), 4);
    assert!(seen.iter().all(|&(_, d)| d > 0.0));
    // Diffusion shrinks a sphere, even with steps 10× the explicit limit.
    let r0 = x.iter().map(|p| p.length()).sum::<f64>();
    let r1 = out.positions.iter().map(|p| p.length()).sum::<f64>();
    assert!(r1 < r0);
}

#[test]
fn implicit_runs_share_the_explicit_settings_and_report() {
    use beltrami_smooth::{DiffusionTime, Statistics, StopReason};
    let (sphere, x) = noisy(primitives::icosphere(3), 0.02);

    // The observer's view: the positions after the step and the step's statistics, as
    // the report keeps them.
    let mut views = Vec::new();
    let out = Smoother::new(&sphere, &x, &Cotangent, implicit(2.0, 3))
        .unwrap()
        .run(|it| {
            views.push((it.positions().to_vec(), it.stats()));
            ControlFlow::Continue(())
        })
        .unwrap();
    assert_eq!(views.len(), 3);
    assert_eq!(views[2].0, out.positions);
    let seen: Vec<_> = views.iter().map(|(_, s)| *s).collect();
    assert_eq!(seen, out.report.steps);
    assert!(seen.iter().all(|s| s.solve.is_some_and(|s| s.factorized)));
    let solver = out.report.solver.as_ref().unwrap();
    assert_eq!(solver.numeric_factorizations, 3);

    // On-demand statistics keep no steps in the report, and the same positions.
    let lean = smooth(
        &sphere,
        &x,
        &Cotangent,
        implicit(2.0, 3).statistics(Statistics::OnDemand),
    )
    .unwrap();
    assert!(lean.report.steps.is_empty());
    assert_eq!(lean.positions, out.positions);

    // A convergence threshold stops the run once a step moves no vertex farther.
    let eps = 1e-3;
    let converged = smooth(
        &sphere,
        &x,
        &Cotangent,
        implicit(5.0, 500).until_change(eps),
    )
    .unwrap();
    assert_eq!(converged.report.stop, StopReason::Converged);
    let last = converged.report.steps.last().unwrap();
    assert!(last.max_displacement <= eps);
    assert!(converged.report.iterations < 500);
    let before_last = &converged.report.steps[converged.report.steps.len() - 2];
    assert!(before_last.max_displacement > eps);

    // A diffusion time with weight-sum normalisation: steps of at most λ whose times
    // add up to t, following the explicit run for the same time closely.
    let t = 0.02;
    let config = |method| {
        SmoothConfig::new(0.8, 1)
            .duration(DiffusionTime::Time(t))
            .update(WeightUpdate::Once)
            .method(method)
    };
    let explicit = smooth(&sphere, &x, &Uniform, config(Method::Laplacian)).unwrap();
    let backward = smooth(
        &sphere,
        &x,
        &Uniform,
        config(Method::implicit(ImplicitSolver::Cholesky)),
    )
    .unwrap();
    let (e, b) = (&explicit.report.config, &backward.report.config);
    assert_eq!(b.iterations, e.iterations, "the same plan: {b:?} vs {e:?}");
    assert_eq!(b.lambda.to_bits(), e.lambda.to_bits());
    let radius = |p: &[DVec3]| p.iter().map(|p| p.length()).sum::<f64>() / p.len() as f64;
    let (r0, re, rb) = (
        radius(&x),
        radius(&explicit.positions),
        radius(&backward.positions),
    );
    assert!(re < r0 && rb < r0);
    assert!((re - rb).abs() < 0.05 * (r0 - re), "{r0} {re} {rb}");

    // An implicit step has no explicit stability limit and no internal numbering.
    let smoother = Smoother::new(&sphere, &x, &Cotangent, implicit(2.0, 3)).unwrap();
    assert_eq!(smoother.stable_step_limit(), None);
    assert!(smoother.permutation().is_none());

    // What an implicit run cannot do is refused before any work.
    let closed = implicit(1.0, 1).preserve_volume(true);
    assert_eq!(
        Smoother::new(&sphere, &x, &Uniform, closed)
            .map(|_| ())
            .unwrap_err(),
        SmoothError::VolumeNotImplicit
    );
}

#[test]
fn dirichlet_couplings_give_the_same_bits_on_any_thread_count_and_match_cholesky() {
    // An open 80 × 80 grid (6 561 vertices, two chunks of 4096 rows) with a fixed
    // boundary and a pinned interior vertex: free rows next to them take those columns
    // to the right-hand side, in both chunks.
    let mut prim = primitives::grid(80, 80);
    jitter(&mut prim.positions, 0.2, 5);
    let mesh = prim.mesh().unwrap();
    let pinned = VertexId::new(5000);
    assert!(!mesh.is_boundary_vertex(pinned));
    // In the unit square, edge length ℓ = 1/80.
    let x: Vec<DVec3> = prim.positions.iter().map(|&p| p / 80.0).collect();
    for normalization in [
        Normalization::WeightSum,
        Normalization::Area(VertexAreaKind::MixedVoronoi),
    ] {
        // The command line's default step; half an edge length squared.
        let t = if normalization == Normalization::WeightSum {
            0.8
        } else {
            0.5 / 6400.0
        };
        let config = implicit(t, 2)
            .laplacian(options(normalization))
            .boundary(Boundary::Fixed)
            .pinned(vec![pinned]);
        let direct = smooth(&mesh, &x, &Cotangent, config.clone()).unwrap();
        let cg = config.method(Method::implicit(ImplicitSolver::conjugate_gradient()));
        let run = |threads| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| smooth(&mesh, &x, &Cotangent, cg.clone()).unwrap())
        };
        let (one, two) = (run(1), run(2));
        let bits = |p: &[DVec3]| -> Vec<u64> {
            p.iter()
                .flat_map(|v| v.to_array().map(f64::to_bits))
                .collect()
        };
        assert_eq!(
            bits(&one.positions),
            bits(&two.positions),
            "{normalization:?}"
        );
        assert_eq!(one.report.steps, two.report.steps);
        // The fixed rows keep their bits; the free ones move as the exact solve says.
        for v in mesh.vertices() {
            if mesh.is_boundary_vertex(v) || v == pinned {
                assert_eq!(bits(&[one.positions[v.index()]]), bits(&[x[v.index()]]));
            }
        }
        // CG stops at `‖b − A x‖ ≤ 1e-10 ‖b‖`, and `‖b‖` includes the Dirichlet rows
        // (identity rows, `b_i = x_i`, about 1 here): with area normalisation the free
        // rows' scale is the mass, about ℓ² = 1.6e-4, so the tolerance allows position
        // errors up to about 1e-10 · ‖b‖ / ℓ² ≈ 7e-6 (3e-7 measured); with weight-sum
        // normalisation the two scales agree and the sphere's 1e-7 holds.
        let allowed = if normalization == Normalization::WeightSum {
            1e-7
        } else {
            1e-5
        };
        let err = max_diff(&one.positions, &direct.positions);
        assert!(err <= allowed, "{normalization:?}: {err:e}");
        let moved = max_diff(&one.positions, &x);
        assert!(
            moved > 1e-4,
            "{normalization:?}: the grid did not move ({moved:e})"
        );
    }
}

/// Far from unit size the implicit step's squared lengths leave the range of numbers:
/// beyond `IMPLICIT_COORDINATES` (2^±480) the run is refused with the typed error that
/// names the largest coordinate (at 2^±520 it was wrong by a tenth of the size, or
/// refused as not positive definite); inside it the result scales with the mesh.
#[test]
fn far_from_unit_size_the_implicit_step_is_refused_with_the_reason() {
    assert_eq!(
        beltrami_smooth::IMPLICIT_COORDINATES,
        2f64.powi(-480)..=2f64.powi(480)
    );
    let (mesh, x) = noisy(primitives::icosphere(3), 0.02);
    let config = implicit(0.5, 2);
    let unit = smooth(&mesh, &x, &Cotangent, config.clone())
        .unwrap()
        .positions;
    for k in [-1000, -520, 520, 1000] {
        let s = 2f64.powi(k);
        let far: Vec<DVec3> = x.iter().map(|&p| p * s).collect();
        match smooth(&mesh, &far, &Cotangent, config.clone()) {
            Err(e @ SmoothError::ImplicitScale { largest }) => {
                assert_eq!(largest, max_abs(&far), "2^{k}");
                assert!(e.to_string().contains("another unit"), "{e}");
            }
            other => panic!("2^{k}: {other:?}"),
        }
    }
    for k in [-400, 400] {
        let s = 2f64.powi(k);
        let far: Vec<DVec3> = x.iter().map(|&p| p * s).collect();
        let y = smooth(&mesh, &far, &Cotangent, config.clone())
            .unwrap()
            .positions;
        let back: Vec<DVec3> = y.iter().map(|&p| p / s).collect();
        assert!(
            max_diff(&back, &unit) <= 1e-14,
            "2^{k}: {}",
            max_diff(&back, &unit)
        );
    }
    // Explicit smoothing has no such limit.
    let far: Vec<DVec3> = x.iter().map(|&p| p * 2f64.powi(1000)).collect();
    assert!(smooth(&mesh, &far, &Cotangent, SmoothConfig::new(0.5, 2)).is_ok());
}
