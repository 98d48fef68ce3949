//! The schemes of this crate pass the conformance check every built-in scheme passes,
//! and stay finite on degenerate input.

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::{DVec3, HalfedgeMesh, PolygonList};
use beltrami_schemes::{BaseWeight, BilateralNormal, register_all};
use beltrami_smooth::{Boundary, SmoothConfig, smooth};
use beltrami_testkit::{SchemeClaims, assert_scheme_conforms, check_scheme};
use beltrami_weights::{WeightContext, WeightRegistry, WeightScheme};

#[test]
fn the_default_scheme_conforms_and_is_symmetric() {
    let scheme = BilateralNormal::default();
    let report = check_scheme(&scheme, SchemeClaims::new().symmetric(true));
    assert!(report.passed(), "{report}");
    // 3 fixtures x (finite, bulk equals single, symmetric, translation, assembles).
    assert_eq!(report.checks.len(), 15, "{report}");
}

#[test]
fn every_variant_conforms() {
    for sigma in [0.02, 0.1, 1.0, 1e6] {
        for base in [BaseWeight::Cotangent, BaseWeight::Uniform] {
            let scheme = BilateralNormal::new(sigma, base).unwrap();
            assert_scheme_conforms(&scheme, SchemeClaims::new().symmetric(true));
        }
    }
}

#[test]
fn invalid_sigmas_are_refused() {
    for sigma in [0.0, -0.1, f64::NAN, f64::INFINITY] {
        let err = BilateralNormal::new(sigma, BaseWeight::Cotangent).unwrap_err();
        assert!(err.to_string().contains("sigma"), "{err}");
        assert!(BilateralNormal::default().with_sigma(sigma).is_err());
    }
    let s = BilateralNormal::default()
        .with_sigma(0.3)
        .unwrap()
        .with_base(BaseWeight::Uniform);
    assert_eq!((s.sigma(), s.base()), (0.3, BaseWeight::Uniform));
}

#[test]
fn register_all_adds_bilateral_after_the_builtins() {
    let mut registry = WeightRegistry::with_builtins();
    register_all(&mut registry).unwrap();
    assert_eq!(
        registry.names(),
        ["uniform", "distance", "cotangent", "bilateral"]
    );
    let scheme = registry.get("bilateral").unwrap();
    assert!(scheme.depends_on_positions());
    assert!(!scheme.description().is_empty());
    assert!(register_all(&mut registry).is_err());
}

/// A fan around vertex 0 where every vertex sits at the same point (all faces have zero
/// area and every normal is undefined), plus a fan with one zero-length edge and a
/// collinear (zero-area) face.
fn degenerate_fans() -> Vec<(Vec<DVec3>, Vec<[u32; 3]>)> {
    let fan = vec![[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1]];
    let coincident = vec![DVec3::new(1.0, 2.0, 3.0); 5];
    let mixed = vec![
        DVec3::ZERO,
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),  // coincides with vertex 1
        DVec3::new(-1.0, 0.0, 0.0), // 2, 0, 3 collinear
        DVec3::new(0.0, -1.0, 0.2),
    ];
    vec![(coincident, fan.clone()), (mixed, fan)]
}

#[test]
fn weights_and_smoothing_stay_finite_on_degenerate_fans() {
    for (positions, faces) in degenerate_fans() {
        let list = PolygonList::from_triangles(&faces);
        let mesh = HalfedgeMesh::from_polygons(positions.len(), list.iter()).expect("a valid fan");
        let ctx = WeightContext::new(Geometry::new(&mesh, &positions).unwrap());
        for base in [BaseWeight::Cotangent, BaseWeight::Uniform] {
            let scheme = BilateralNormal::default().with_base(base);
            let mut bulk = vec![f64::NAN; mesh.n_halfedges()];
            scheme.fill_weights(&ctx, &mut bulk);
            for h in mesh.halfedges() {
                let w = scheme.weight(&ctx, h);
                assert!(w.is_finite() && w >= 0.0, "{} gives {w}", scheme.name());
                assert_eq!(w.to_bits(), bulk[h.index()].to_bits());
                assert!(scheme.curve_weight(&ctx, h).is_finite());
            }
            let out = smooth(
                &mesh,
                &positions,
                &scheme,
                SmoothConfig::new(0.8, 5).boundary(Boundary::Free),
            )
            .unwrap();
            assert!(out.positions.iter().all(|p| p.is_finite()));
        }
    }
}
