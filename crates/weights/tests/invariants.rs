//! Invariants of the weight schemes and the assembled Laplacian.

use beltrami_halfedge::geometry::{Geometry, VertexAreaKind};
use beltrami_halfedge::primitives::{self, Primitive};
use beltrami_halfedge::{DVec3, HalfedgeMesh, VertexId};
use beltrami_testkit::SplitMix64;
use beltrami_testkit::fixtures::jittered_grid;
use beltrami_weights::{
    Cotangent, InverseDistance, Laplacian, LaplacianOptions, NegativeWeights, Normalization,
    Uniform, WeightContext, WeightError, WeightRegistry, WeightScheme,
};

fn schemes() -> Vec<Box<dyn WeightScheme>> {
    vec![
        Box::new(Uniform),
        Box::new(InverseDistance),
        Box::new(Cotangent),
    ]
}

fn opts(normalization: Normalization, negative: NegativeWeights) -> LaplacianOptions {
    LaplacianOptions::new()
        .normalization(normalization)
        .negative(negative)
}

#[test]
fn uniform_weights_sum_to_the_valence() {
    let p = primitives::icosphere(2);
    let mesh = p.mesh().unwrap();
    let lap = Laplacian::new(&mesh, &p.positions, &Uniform, LaplacianOptions::default()).unwrap();
    for v in mesh.vertices() {
        assert_eq!(lap.weight_sum(v), mesh.valence(v) as f64);
        assert_eq!(lap.scale(v), Some(1.0 / mesh.valence(v) as f64));
    }
    assert_eq!(lap.stuck_rows(), 0);
}

#[test]
fn cotangent_and_distance_weights_are_symmetric() {
    let (mesh, x) = jittered_grid(6, 6, 0.3, 7);
    for scheme in [&Cotangent as &dyn WeightScheme, &InverseDistance] {
        let lap = Laplacian::new(&mesh, &x, scheme, LaplacianOptions::default()).unwrap();
        for v in mesh.vertices() {
            for (j, w) in lap.row(v) {
                let back = lap.row(j).find(|(k, _)| *k == v).unwrap().1;
                assert_eq!(w.to_bits(), back.to_bits(), "{} {v} {j}", scheme.name());
            }
        }
    }
}

#[test]
fn bulk_weights_equal_the_simple_form_bit_for_bit() {
    let p = primitives::icosphere(2);
    let mesh = p.mesh().unwrap();
    let mut rng = SplitMix64::new(3);
    let x: Vec<DVec3> = p
        .positions
        .iter()
        .map(|&q| q * (1.0 + 0.05 * rng.next_symmetric()))
        .collect();
    let ctx = WeightContext::new(Geometry::new(&mesh, &x).unwrap());
    for scheme in schemes() {
        let mut bulk = vec![0.0; mesh.n_halfedges()];
        scheme.fill_weights(&ctx, &mut bulk);
        for h in mesh.halfedges() {
            assert_eq!(
                bulk[h.index()].to_bits(),
                scheme.weight(&ctx, h).to_bits(),
                "{} {h:?}",
                scheme.name()
            );
        }
    }
}

#[test]
fn cotangent_laplacian_of_a_linear_function_vanishes_on_an_irregular_plane() {
    let (mesh, x) = jittered_grid(8, 8, 0.35, 11);
    let cot = Laplacian::new(&mesh, &x, &Cotangent, LaplacianOptions::default()).unwrap();
    let uni = Laplacian::new(&mesh, &x, &Uniform, LaplacianOptions::default()).unwrap();
    let mut uniform_drift: f64 = 0.0;
    for v in mesh.vertices().filter(|&v| !mesh.is_boundary_vertex(v)) {
        let l = cot.laplacian_at(v, &x).unwrap();
        assert!(l.length() < 1e-13, "{v}: {l}");
        uniform_drift = uniform_drift.max(uni.laplacian_at(v, &x).unwrap().length());
    }
    // Uniform weights do not have linear precision: they drift tangentially.
    assert!(uniform_drift > 0.05, "uniform drift {uniform_drift}");
}

#[test]
fn irregular_planes_have_negative_cotangent_weights_and_policies_treat_them() {
    let (mesh, x) = jittered_grid(8, 8, 0.45, 5);
    let keep = Laplacian::new(&mesh, &x, &Cotangent, LaplacianOptions::default()).unwrap();
    let negatives = mesh
        .vertices()
        .flat_map(|v| keep.row(v).map(|(_, w)| w).collect::<Vec<_>>())
        .filter(|&w| w < 0.0)
        .count();
    assert!(negatives > 0, "the jitter must create obtuse pairs");
    for (policy, check) in [
        (
            NegativeWeights::Clamp,
            (|raw: f64, w: f64| w == raw.max(0.0)) as fn(f64, f64) -> bool,
        ),
        (NegativeWeights::Abs, |raw: f64, w: f64| w == raw.abs()),
    ] {
        let lap = Laplacian::new(
            &mesh,
            &x,
            &Cotangent,
            opts(Normalization::WeightSum, policy),
        )
        .unwrap();
        for v in mesh.vertices() {
            for ((_, raw), (_, w)) in keep.row(v).zip(lap.row(v)) {
                assert!(check(raw, w), "{policy:?}: {raw} -> {w}");
            }
        }
    }
}

#[test]
fn area_normalised_cotangent_laplacian_is_the_mean_curvature_normal_on_a_sphere() {
    // Δx = −2H n with H = 1 on the unit sphere: L x ≈ −2 x.
    let p = primitives::icosphere(4);
    let mesh = p.mesh().unwrap();
    // Mixed-Voronoi areas make the operator pointwise consistent; barycentric areas only
    // on average (the barycentric cell of a vertex is not its Voronoi cell).
    for (kind, worst_bound, mean_bound) in [
        (VertexAreaKind::MixedVoronoi, 0.01, 0.004),
        (VertexAreaKind::Barycentric, 0.32, 0.006),
    ] {
        let lap = Laplacian::new(
            &mesh,
            &p.positions,
            &Cotangent,
            opts(Normalization::Area(kind), NegativeWeights::Keep),
        )
        .unwrap();
        let mut worst: f64 = 0.0;
        let mut sum = 0.0;
        for v in mesh.vertices() {
            let x = p.positions[v.index()];
            let l = lap.laplacian_at(v, &p.positions).unwrap();
            // Along the inward normal, and of length 2H = 2.
            assert!(l.normalize().dot(-x) > 0.999, "{kind:?} {v}");
            let e = (l + 2.0 * x).length();
            worst = worst.max(e);
            sum += e;
        }
        let mean = sum / mesh.n_vertices() as f64;
        assert!(worst < worst_bound, "{kind:?}: |Lx + 2x| up to {worst}");
        assert!(mean < mean_bound, "{kind:?}: mean |Lx + 2x| = {mean}");
    }
}

#[test]
fn laplacian_is_equivariant_under_rigid_motions() {
    let (mesh, x) = jittered_grid(5, 5, 0.3, 2);
    // Lift the grid out of the plane so that the test is three-dimensional.
    let x: Vec<DVec3> = x
        .iter()
        .map(|p| DVec3::new(p.x, p.y, 0.1 * (p.x * p.y).sin()))
        .collect();
    let rot = glam::DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
    let t = DVec3::new(5.0, -3.0, 2.0);
    let y: Vec<DVec3> = x.iter().map(|&p| rot * p + t).collect();
    for scheme in schemes() {
        for normalization in [
            Normalization::WeightSum,
            Normalization::Area(VertexAreaKind::MixedVoronoi),
        ] {
            let o = opts(normalization, NegativeWeights::Keep);
            let a = Laplacian::new(&mesh, &x, scheme.as_ref(), o).unwrap();
            let b = Laplacian::new(&mesh, &y, scheme.as_ref(), o).unwrap();
            for v in mesh.vertices() {
                let la = a.laplacian_at(v, &x).unwrap();
                let lb = b.laplacian_at(v, &y).unwrap();
                assert!((rot * la - lb).length() < 1e-9, "{} {v}", scheme.name());
            }
        }
    }
}

#[test]
fn isolated_vertices_are_stuck_rows() {
    let mesh = HalfedgeMesh::from_polygons(4, [[0u32, 1, 2]]).unwrap();
    let x = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ONE];
    let lap = Laplacian::new(&mesh, &x, &Uniform, LaplacianOptions::default()).unwrap();
    assert_eq!(lap.scale(VertexId::new(3)), None);
    assert_eq!(lap.laplacian_at(VertexId::new(3), &x), None);
    assert_eq!(lap.stuck_rows(), 1);
}

#[test]
fn a_scheme_that_returns_nan_is_an_error() {
    struct Broken;
    impl WeightScheme for Broken {
        fn name(&self) -> &str {
            "broken"
        }
        fn weight(&self, ctx: &WeightContext<'_>, h: beltrami_halfedge::HalfedgeId) -> f64 {
            if ctx.mesh().from_vertex(h).raw() == 2 {
                f64::NAN
            } else {
                1.0
            }
        }
    }
    let p: Primitive = primitives::triangle();
    let mesh = p.mesh().unwrap();
    let err =
        Laplacian::new(&mesh, &p.positions, &Broken, LaplacianOptions::default()).unwrap_err();
    assert!(
        matches!(err, WeightError::NonFiniteWeight { from: 2, .. }),
        "{err}"
    );
    insta::assert_snapshot!(err, @r#"weight scheme "broken" gave a non-finite weight (NaN) on the edge from vertex 2 to vertex 1"#);
}

#[test]
fn positions_must_match_the_mesh() {
    let p = primitives::triangle();
    let mesh = p.mesh().unwrap();
    let err = Laplacian::new(
        &mesh,
        &p.positions[..2],
        &Uniform,
        LaplacianOptions::default(),
    )
    .unwrap_err();
    insta::assert_snapshot!(err, @"2 positions were given for a mesh of 3 vertices");
}

#[test]
fn registry_rejects_duplicates_and_bad_names() {
    struct Named(&'static str);
    impl WeightScheme for Named {
        fn name(&self) -> &str {
            self.0
        }
        fn weight(&self, _: &WeightContext<'_>, _: beltrami_halfedge::HalfedgeId) -> f64 {
            1.0
        }
    }
    let mut r = WeightRegistry::with_builtins();
    insta::assert_snapshot!(r.register(Named("uniform")).unwrap_err(), @r#"a weight scheme named "uniform" is already registered"#);
    insta::assert_snapshot!(r.register(Named("My Scheme")).unwrap_err(), @r#"invalid weight scheme name "My Scheme": use lowercase letters, digits, '-' and '_'"#);
    r.register(Named("gauss-2")).unwrap();
    assert_eq!(r.names(), ["uniform", "distance", "cotangent", "gauss-2"]);
    let err = r.get("cot").err().unwrap();
    insta::assert_snapshot!(err, @r#"unknown weight scheme "cot" (known: uniform, distance, cotangent, gauss-2)"#);
}

#[test]
fn rows_with_a_non_positive_weight_sum_are_stuck_in_both_normalisations() {
    struct Negative;
    impl WeightScheme for Negative {
        fn name(&self) -> &str {
            "negative"
        }
        fn weight(&self, _: &WeightContext<'_>, _: beltrami_halfedge::HalfedgeId) -> f64 {
            -1.0
        }
    }
    let p = primitives::hexagon_fan();
    let mesh = p.mesh().unwrap();
    for normalization in [
        Normalization::WeightSum,
        Normalization::Area(VertexAreaKind::Barycentric),
    ] {
        let lap = Laplacian::new(
            &mesh,
            &p.positions,
            &Negative,
            opts(normalization, NegativeWeights::Keep),
        )
        .unwrap();
        assert_eq!(lap.stuck_rows(), mesh.n_vertices(), "{normalization:?}");
        // Abs makes every row movable again.
        let abs = Laplacian::new(
            &mesh,
            &p.positions,
            &Negative,
            opts(normalization, NegativeWeights::Abs),
        )
        .unwrap();
        assert_eq!(abs.stuck_rows(), 0, "{normalization:?}");
    }
}
