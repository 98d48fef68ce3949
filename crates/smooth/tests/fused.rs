//! Weights recomputed every iteration are computed inside the explicit sweep, row by
//! row, without storing them: this checks that path against the operator refreshed
//! first and applied as `Laplacian::laplacian_at` documents it, step by step and bit for
//! bit, for every built-in scheme, normalisation, negative-weight policy and boundary
//! mode, with a pinned vertex, on open and closed meshes, with and without reordering;
//! and that `Smoother::laplacian` is still the operator the last sweep used. Cotangent
//! rows with weight-sum normalisation and negative weights kept are summed triangle by
//! triangle instead (`sums_by_scatter`): those steps are the operator's to rounding.

use beltrami_halfedge::geometry::{Geometry, VertexAreaKind};
use beltrami_halfedge::{DVec3, HalfedgeMesh, VertexId, primitives};
use beltrami_smooth::{Boundary, Reorder, SmoothConfig, Smoother, Summation, WeightUpdate};
use beltrami_testkit::SplitMix64;
use beltrami_testkit::numbering::{ROUNDING, max_difference, sums_by_scatter};
use beltrami_weights::{
    Cotangent, InverseDistance, Laplacian, LaplacianOptions, NegativeWeights, Normalization,
    Uniform, WeightContext, WeightScheme,
};

fn bits(p: &[DVec3]) -> Vec<[u64; 3]> {
    p.iter().map(|q| q.to_array().map(f64::to_bits)).collect()
}

fn jittered(p: &primitives::Primitive, amount: f64, seed: u64) -> (HalfedgeMesh, Vec<DVec3>) {
    let mut rng = SplitMix64::new(seed);
    let x = p
        .positions
        .iter()
        .map(|&q| {
            q + DVec3::new(
                rng.next_symmetric(),
                rng.next_symmetric(),
                rng.next_symmetric(),
            ) * amount
        })
        .collect();
    (p.mesh().unwrap(), x)
}

/// One explicit step by hand: the operator refreshed at `x` (`lap`), every vertex moved
/// as the smoother documents (fixed boundary and pinned vertices stay, curve-boundary
/// vertices move towards their two boundary neighbours, the rest by their row).
fn step_by_hand(
    mesh: &HalfedgeMesh,
    x: &[DVec3],
    lap: &Laplacian,
    scheme: &dyn WeightScheme,
    config: &SmoothConfig,
) -> Vec<DVec3> {
    let ctx = WeightContext::new(Geometry::new(mesh, x).unwrap());
    let lambda = config.lambda;
    mesh.vertices()
        .map(|v| {
            let xi = x[v.index()];
            let boundary = mesh.is_boundary_vertex(v);
            if mesh.is_isolated(v)
                || config.pinned.contains(&v)
                || (boundary && config.boundary == Boundary::Fixed)
            {
                return xi;
            }
            if boundary && config.boundary == Boundary::Curve {
                let out = mesh.outgoing_halfedge(v).unwrap();
                let (ha, hb) = (mesh.prev(out).twin(), out);
                let (a, b) = (mesh.to_vertex(ha), mesh.to_vertex(hb));
                let (wa, wb) = (scheme.curve_weight(&ctx, ha), scheme.curve_weight(&ctx, hb));
                let s = x[a.index()] * wa + x[b.index()] * wb;
                let inv = 1.0 / (wa + wb);
                return if inv.is_finite() && inv > 0.0 {
                    xi + (s * inv - xi) * lambda
                } else {
                    xi
                };
            }
            lap.laplacian_at(v, x).map_or(xi, |l| xi + l * lambda)
        })
        .collect()
}

fn options() -> Vec<(LaplacianOptions, f64)> {
    let mut out = Vec::new();
    for (normalization, lambda) in [
        (Normalization::WeightSum, 0.8),
        (Normalization::Area(VertexAreaKind::Barycentric), 0.002),
        (Normalization::Area(VertexAreaKind::MixedVoronoi), 0.002),
    ] {
        for negative in [
            NegativeWeights::Keep,
            NegativeWeights::Clamp,
            NegativeWeights::Abs,
        ] {
            let options = LaplacianOptions::new()
                .normalization(normalization)
                .negative(negative);
            out.push((options, lambda));
        }
    }
    out
}

#[test]
fn fresh_weights_in_the_sweep_are_the_refreshed_operator_bit_for_bit() {
    let cases = [
        jittered(&primitives::grid(9, 7), 0.3, 3),
        jittered(&primitives::icosphere(2), 0.05, 5),
        jittered(&primitives::torus(2.0, 0.7, 11, 6), 0.05, 7),
    ];
    let iterations = 3;
    for (mesh, x0) in &cases {
        for scheme in [&Uniform as &dyn WeightScheme, &InverseDistance, &Cotangent] {
            for (options, lambda) in options() {
                for (boundary, summation) in [Boundary::Fixed, Boundary::Free, Boundary::Curve]
                    .into_iter()
                    .flat_map(|b| [(b, Summation::Rows), (b, Summation::Scatter)])
                {
                    let config = SmoothConfig::new(lambda, iterations)
                        .update(WeightUpdate::Every)
                        .laplacian(options)
                        .boundary(boundary)
                        .pinned(vec![VertexId::new(5)])
                        .reorder(Reorder::Never)
                        .summation(summation);
                    let label = format!("{} {options:?} {boundary:?} {summation:?}", scheme.name());
                    let by_triangles = sums_by_scatter(scheme, &config);
                    let Ok(mut smoother) = Smoother::new(mesh, x0, scheme, config.clone()) else {
                        // A curve boundary needs weight-sum rows.
                        assert!(boundary == Boundary::Curve && lambda < 0.1, "{label}");
                        continue;
                    };
                    let mut reordered =
                        Smoother::new(mesh, x0, scheme, config.clone().reorder(Reorder::Always))
                            .unwrap();
                    let mut lap = Laplacian::new(mesh, x0, scheme, options).unwrap();
                    let mut x = x0.clone();
                    for k in 0..iterations {
                        lap.update(mesh, &x, scheme).unwrap();
                        let want = step_by_hand(mesh, &x, &lap, scheme, &config);
                        smoother.advance().unwrap();
                        reordered.advance().unwrap();
                        let got = smoother.positions().into_owned();
                        if by_triangles {
                            // Each row summed triangle by triangle: the operator's to
                            // rounding, in either numbering.
                            for p in [&got, &reordered.positions().into_owned()] {
                                let d = max_difference(&bits(p), &bits(&want));
                                assert!(d <= ROUNDING, "{label} {k}: {d:e}");
                            }
                        } else {
                            assert_eq!(bits(&got), bits(&want), "{label} {k}");
                            assert_eq!(bits(&reordered.positions()), bits(&want), "{label} {k}");
                        }
                        // The operator the smoother shows is the one its last sweep used.
                        let shown = smoother.laplacian();
                        for v in mesh.vertices() {
                            let a: Vec<u64> = shown.row(v).map(|(_, w)| w.to_bits()).collect();
                            let b: Vec<u64> = lap.row(v).map(|(_, w)| w.to_bits()).collect();
                            assert_eq!(a, b, "{label} {k} row {v}");
                            assert_eq!(shown.scale(v), lap.scale(v), "{label} {k} {v}");
                        }
                        // The next operator at the smoother's own positions.
                        x = got;
                    }
                }
            }
        }
    }
}

/// The step statistics (stuck count, displacements) of the fused sweep are those of
/// the positions it produced.
#[test]
fn fresh_sweeps_report_their_statistics() {
    let (mesh, x0) = jittered(&primitives::grid(9, 7), 0.3, 11);
    for scheme in [&Uniform as &dyn WeightScheme, &InverseDistance, &Cotangent] {
        let config = SmoothConfig::new(0.8, 2)
            .update(WeightUpdate::Every)
            .laplacian(LaplacianOptions::new().negative(NegativeWeights::Clamp))
            .boundary(Boundary::Free)
            .reorder(Reorder::Never);
        let mut smoother = Smoother::new(&mesh, &x0, scheme, config).unwrap();
        let mut before = x0.clone();
        for _ in 0..2 {
            let stats = smoother.step().unwrap();
            let after = smoother.positions().into_owned();
            let d: Vec<f64> = before
                .iter()
                .zip(&after)
                .map(|(&a, &b)| beltrami_halfedge::geometry::distance(a, b))
                .collect();
            let max = d.iter().fold(0.0f64, |m, &d| m.max(d));
            assert_eq!(stats.max_displacement, max, "{}", scheme.name());
            assert!(stats.mean_displacement > 0.0 && stats.mean_displacement <= max);
            before = after;
        }
    }
}

/// A run whose weights change every iteration keeps no weight array from the start;
/// its operator is still there to read before the first step, with the bits of
/// `Laplacian::new` at the input positions, for both cotangent kernels.
#[test]
fn the_operator_of_a_lean_run_can_be_read_before_the_first_step() {
    use beltrami_weights::CotangentKernel;
    let (mesh, x) = jittered(&primitives::icosphere(2), 0.02, 7);
    for kernel in [CotangentKernel::PerTriangle, CotangentKernel::Ring] {
        let options = LaplacianOptions::new().cotangent_kernel(kernel);
        let config = SmoothConfig::new(0.5, 3)
            .update(WeightUpdate::Every)
            .laplacian(options);
        let reference = Laplacian::new(&mesh, &x, &Cotangent, options).unwrap();
        let mut smoother = Smoother::new(&mesh, &x, &Cotangent, config).unwrap();
        let rows = smoother.laplacian().rows();
        let want = reference.rows();
        assert_eq!(rows.neighbours, want.neighbours);
        let wbits = |w: &[f64]| w.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(wbits(rows.weights), wbits(want.weights), "{kernel:?}");
        assert_eq!(wbits(rows.scales), wbits(want.scales), "{kernel:?}");
        smoother.step().unwrap();
        assert!(smoother.laplacian().weights_stored());
    }
}
