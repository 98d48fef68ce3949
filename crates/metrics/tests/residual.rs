//! The residual and its ISO 25178-2 areal parameters: closed forms (45° plane, sinusoid,
//! constant), exact triangle integrals against brute-force subdivision, the cotangent
//! identity for Sdq, invariants under scaling, and typed errors.

use std::f64::consts::{PI, SQRT_2, TAU};

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::primitives::{self, Primitive};
use beltrami_halfedge::{DVec3, HalfedgeMesh, TopologyError};
use beltrami_metrics::MetricsError;
use beltrami_metrics::residual::{
    ArealOptions, ArealParameters, Datum, Quadrature, areal_parameters, normal_residual,
};
use beltrami_testkit::SplitMix64;
use glam::DQuat;
use proptest::prelude::*;

fn build(p: &Primitive) -> HalfedgeMesh {
    let mesh = p.mesh().expect("primitive builds");
    mesh.check_integrity().expect("valid mesh");
    mesh
}

/// The exact-interpolant quadrature on `datum`: the closed forms below are integrals of
/// the piecewise-linear interpolant.
fn exact(datum: Datum) -> ArealOptions {
    ArealOptions::default()
        .datum(datum)
        .quadrature(Quadrature::ExactInterpolant)
}

fn areal(mesh: &HalfedgeMesh, positions: &[DVec3], field: &[f64], datum: Datum) -> ArealParameters {
    areal_parameters(
        &Geometry::new(mesh, positions).expect("positions"),
        field,
        &exact(datum),
    )
    .expect("valid input")
}

fn close(got: f64, want: f64, tolerance: f64) -> bool {
    (got - want).abs() <= tolerance
}

#[test]
fn a_plane_at_45_degrees_has_sdq_one_and_sdr_root_two_minus_one() {
    let grid = primitives::grid(10, 6);
    let mesh = build(&grid);
    let r: Vec<f64> = grid.positions.iter().map(|p| p.x).collect();
    for datum in [Datum::ReferenceSurface, Datum::Mean] {
        let s = areal(&mesh, &grid.positions, &r, datum);
        assert!(close(s.sdq, 1.0, 1e-12), "{}", s.sdq);
        assert!(close(s.sdr, SQRT_2 - 1.0, 1e-12), "{}", s.sdr);
    }
    // The same height field over a reference form rotated anywhere in space: the gradient
    // is taken in each triangle's own plane.
    let rotation = DQuat::from_euler(glam::EulerRot::ZXY, 0.7, -1.1, 2.3);
    let rotated: Vec<DVec3> = grid
        .positions
        .iter()
        .map(|&p| rotation * p + DVec3::splat(3.0))
        .collect();
    let s = areal(&mesh, &rotated, &r, Datum::ReferenceSurface);
    assert!(close(s.sdq, 1.0, 1e-12) && close(s.sdr, SQRT_2 - 1.0, 1e-12));
    // Heights r = x over [0, 10] as is: Sa = mean x = 5, Sq² = mean x² = 100/3.
    assert!(close(s.sa, 5.0, 1e-12) && close(s.sq, (100.0f64 / 3.0).sqrt(), 1e-12));
    assert!(close(s.area, 60.0, 1e-12) && close(s.mean, 5.0, 1e-12));
}

/// Moments of the piecewise-linear interpolant of samples `s` over unit intervals, by the
/// one-dimensional integrals (an independent route to the 2-D triangle formulas: on the
/// grid, a field that depends on x only is linear in x on every triangle).
fn interval_means(s: &[f64]) -> [f64; 5] {
    let n = (s.len() - 1) as f64;
    let mut m = [0.0; 5];
    for w in s.windows(2) {
        let (a, b) = (w[0], w[1]);
        m[0] += if a * b >= 0.0 {
            (a.abs() + b.abs()) / 2.0
        } else {
            // Two triangles under |linear|, split at the zero a / (a − b).
            (a * a + b * b) / (2.0 * (a.abs() + b.abs()))
        };
        m[1] += (a + b) / 2.0;
        m[2] += (a * a + a * b + b * b) / 3.0;
        m[3] += (a * a * a + a * a * b + a * b * b + b * b * b) / 4.0;
        m[4] += (a.powi(4) + a.powi(3) * b + a * a * b * b + a * b.powi(3) + b.powi(4)) / 5.0;
    }
    m.map(|x| x / n)
}

#[test]
fn sinusoid_matches_the_continuum_within_the_discretisation_bound() {
    // r = A sin(2πx/λ) on a grid of unit cells, λ = N = 48 cells, two periods in x.
    // Continuum (one period): Sq = A/√2, Sa = 2A/π, Ssk = 0, Sku = 3/2, Sdq = A·2π/(λ√2).
    // The interpolant of samples with θ = 2π/N: Sq² = A² (2 + cos θ)/6, so
    // |Sq/(A/√2) − 1| ≤ (1 − cos θ)/3 ≤ θ²/6; Sa = (2A/N) cot(π/N) (zeros at nodes), so
    // |Sa/(2A/π) − 1| = 1 − x cot x ≤ x²/2 with x = π/N; Sdq = √2 A sin(θ/2), within
    // θ²/24 of the continuum relatively.
    let (n, amplitude) = (48u32, 2.5e-3);
    let theta = TAU / f64::from(n);
    let grid = primitives::grid(2 * n, 3);
    let mesh = build(&grid);
    let r: Vec<f64> = grid
        .positions
        .iter()
        .map(|p| amplitude * (theta * p.x).sin())
        .collect();
    let s = areal(&mesh, &grid.positions, &r, Datum::ReferenceSurface);

    let sq = amplitude / SQRT_2;
    let sa = 2.0 * amplitude / PI;
    let sdq = amplitude * theta / SQRT_2;
    assert!(close(s.sq / sq, 1.0, theta * theta / 6.0));
    assert!(close(s.sa / sa, 1.0, (PI / f64::from(n)).powi(2) / 2.0));
    assert!(close(s.sdq / sdq, 1.0, theta * theta / 24.0));
    assert!(s.ssk.expect("Sq > 0").abs() < 1e-12);
    let sku = s.sku.expect("Sq > 0");
    // The interpolant's kurtosis exceeds 3/2 by O(θ⁴): the θ² terms of the fourth moment
    // and of Sq⁴ cancel, and the exact discrete sums give (Sku − 3/2)/θ⁴ → 1/120
    // (0.00872 at N = 12, 0.00836 at N = 48).
    assert!(sku >= 1.5 && sku - 1.5 <= theta.powi(4) / 100.0, "{sku}");

    // Against the interpolant's exact values.
    let exact_sq = amplitude * ((2.0 + theta.cos()) / 6.0).sqrt();
    let exact_sa = 2.0 * amplitude / f64::from(n) / (PI / f64::from(n)).tan();
    let exact_sdq = SQRT_2 * amplitude * (theta / 2.0).sin();
    assert!(close(s.sq / exact_sq, 1.0, 1e-12));
    assert!(close(s.sa / exact_sa, 1.0, 1e-12));
    assert!(close(s.sdq / exact_sdq, 1.0, 1e-12));
    let samples: Vec<f64> = (0..=2 * n)
        .map(|i| amplitude * (theta * f64::from(i)).sin())
        .collect();
    let m = interval_means(&samples);
    assert!(close(sku / (m[4] / (m[2] * m[2])), 1.0, 1e-12));
    // Sp and Sv at the sample peaks: exactly A at x = 12, 60 (N/4 from a zero).
    assert!(close(s.sp, amplitude, 1e-18) && close(s.sv, amplitude, 1e-18));
}

#[test]
fn shifted_sinusoid_changes_sign_inside_triangles() {
    // A phase of 0.3 puts every zero inside a cell: Sa needs the exact split of |r|.
    let (n, amplitude) = (20u32, 0.7);
    let theta = TAU / f64::from(n);
    let grid = primitives::grid(3 * n, 2);
    let mesh = build(&grid);
    let wave = |x: f64| amplitude * (theta * x + 0.3).sin();
    let r: Vec<f64> = grid.positions.iter().map(|p| wave(p.x)).collect();
    let samples: Vec<f64> = (0..=3 * n).map(|i| wave(f64::from(i))).collect();
    let m = interval_means(&samples);
    let s = areal(&mesh, &grid.positions, &r, Datum::ReferenceSurface);
    assert!(close(s.sa, m[0], 1e-14), "{} vs {}", s.sa, m[0]);
    assert!(close(s.mean, m[1], 1e-14));
    assert!(close(s.sq, m[2].sqrt(), 1e-14));
    assert!(close(s.ssk.expect("Sq > 0"), m[3] / m[2].powf(1.5), 1e-12));
    assert!(close(s.sku.expect("Sq > 0"), m[4] / (m[2] * m[2]), 1e-12));
}

#[test]
fn a_constant_field_has_sa_and_sq_its_magnitude() {
    let sphere = primitives::icosphere(2);
    let mesh = build(&sphere);
    for c in [-0.7, 0.7, 3e-9] {
        let r = vec![c; mesh.n_vertices()];
        let s = areal(&mesh, &sphere.positions, &r, Datum::ReferenceSurface);
        let tolerance = 4.0 * f64::EPSILON * c.abs();
        assert!(
            close(s.sa, c.abs(), tolerance) && close(s.sq, c.abs(), tolerance),
            "{s:?}"
        );
        assert!(close(s.ssk.expect("Sq > 0"), c.signum(), 1e-15));
        assert!(close(s.sku.expect("Sq > 0"), 1.0, 1e-15));
        assert_eq!((s.sp, s.sv), (c, c.abs()));
        // Sz = Sp + Sv as the standard writes it: 0 for c < 0, 2c for c > 0.
        assert_eq!(s.sz, c + c.abs());
        assert_eq!((s.sdq, s.sdr), (0.0, 0.0));

        let levelled = areal(&mesh, &sphere.positions, &r, Datum::Mean);
        assert!(
            levelled.sa.abs() <= tolerance && levelled.sq <= tolerance && levelled.sz <= tolerance
        );
        assert_eq!(levelled.datum, Datum::Mean);
        assert!(close(levelled.mean, c, tolerance));
    }
    let zero = areal(
        &mesh,
        &sphere.positions,
        &vec![0.0; mesh.n_vertices()],
        Datum::ReferenceSurface,
    );
    assert_eq!(
        (zero.sa, zero.sq, zero.ssk, zero.sku),
        (0.0, 0.0, None, None)
    );
}

/// Brute force over one triangle: `n²` similar sub-triangles. Returns the integrals of
/// `r, r², r³, r⁴` by the centroid rule and of `|r|` exactly where a sub-triangle does not
/// change sign, by the centroid rule where it does.
fn subdivide(area: f64, [ra, rb, rc]: [f64; 3], n: u32) -> [f64; 5] {
    let sub = area / f64::from(n * n);
    let value = |i: u32, j: u32| {
        let (u, v) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
        ra + u * (rb - ra) + v * (rc - ra)
    };
    let mut integrals = [0.0; 5];
    let mut add = |corners: [f64; 3]| {
        let centre = corners.iter().sum::<f64>() / 3.0;
        // Exact where the corners share a sign (|r| is linear there), approximate where not.
        integrals[0] += sub * centre.abs();
        for (k, integral) in (1..).zip(integrals.iter_mut().skip(1)) {
            *integral += sub * centre.powi(k);
        }
    };
    for i in 0..n {
        for j in 0..n - i {
            add([value(i, j), value(i + 1, j), value(i, j + 1)]);
            if i + j + 2 <= n {
                add([value(i + 1, j), value(i + 1, j + 1), value(i, j + 1)]);
            }
        }
    }
    integrals
}

#[test]
fn triangle_integrals_agree_with_subdivision() {
    let mut random = SplitMix64::new(7);
    let n = 256u32;
    let mut sign_changes = 0;
    for _ in 0..20 {
        let corners = [
            random.next_symmetric_vector(),
            random.next_symmetric_vector(),
            random.next_symmetric_vector(),
        ];
        let values = [
            random.next_symmetric(),
            random.next_symmetric(),
            random.next_symmetric(),
        ];
        let mesh = HalfedgeMesh::from_polygons(3, [[0u32, 1, 2]]).expect("valid");
        let s = areal(&mesh, &corners, &values, Datum::ReferenceSurface);
        let area = s.area;
        let [a, b, c] = corners;
        assert!(close(area, 0.5 * (b - a).cross(c - a).length(), 1e-15));

        // Independent gradient: g = α e₁ + β e₂ with g·e₁ = r_b − r_a, g·e₂ = r_c − r_a.
        let (e1, e2) = (b - a, c - a);
        let (g11, g12, g22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
        let (d1, d2) = (values[1] - values[0], values[2] - values[0]);
        let det = g11 * g22 - g12 * g12;
        let gradient = ((g22 * d1 - g12 * d2) * e1 + (g11 * d2 - g12 * d1) * e2) / det;
        let slope = gradient.length();
        assert!(
            close(s.sdq, slope, 1e-9 * slope.max(1.0)),
            "{} vs {slope}",
            s.sdq
        );
        assert!(close(
            s.sdr,
            (1.0 + slope * slope).sqrt() - 1.0,
            1e-9 * slope.max(1.0)
        ));

        let exact = [
            area * s.sa,
            area * s.mean,
            area * s.sq.powi(2),
            area * s.ssk.unwrap_or(0.0) * s.sq.powi(3),
            area * s.sku.unwrap_or(0.0) * s.sq.powi(4),
        ];
        let brute = subdivide(area, values, n);
        // Centroid rule on a sub-triangle of diameter ≤ diam/n: the linear Taylor term
        // integrates to zero, the remainder is at most ½ |f''| ρ² with
        // |f''| ≤ k(k−1) R^(k−2) |∇r|², R = max |r|, ρ ≤ diam/n.
        let diam = (b - a).length().max((c - a).length()).max((c - b).length());
        let rho = diam / f64::from(n);
        let big = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for k in 1..5 {
            let kf = k as f64;
            let bound =
                area * 0.5 * kf * (kf - 1.0) * big.powi(k as i32 - 2) * slope * slope * rho * rho;
            // Plus the rounding of 65 536 terms.
            assert!(
                close(exact[k], brute[k], bound + 1e-10 * area),
                "k = {k}: {} vs {}",
                exact[k],
                brute[k]
            );
        }
        // |r|: only the sub-triangles the zero line crosses are approximate, at most 3n + 4
        // of them (a line crosses n + 1 lines of each of the three families), each off by
        // at most its area times its range of r (the range over the triangle over n).
        let range = values.iter().fold(f64::NEG_INFINITY, |m, &v| m.max(v))
            - values.iter().fold(f64::INFINITY, |m, &v| m.min(v));
        let changes = values.iter().any(|&v| v > 0.0) && values.iter().any(|&v| v < 0.0);
        let bound = if changes {
            f64::from(3 * n + 4) * area / f64::from(n * n) * range / f64::from(n)
        } else {
            0.0
        };
        sign_changes += usize::from(changes);
        assert!(
            close(exact[0], brute[0], bound + 1e-10 * area),
            "{} vs {} ± {bound}",
            exact[0],
            brute[0]
        );
    }
    assert!(
        sign_changes >= 10,
        "most random triangles change sign: {sign_changes}"
    );
}

#[test]
fn sa_is_exact_where_the_zero_line_crosses() {
    // By hand on the unit right triangle (A = 1/2), splitting at the zero line:
    // (1, −1, −1): the positive corner has area A/4 and mean 1/3 (A/12); the rest has
    // ∫|r| = ∫r₊ − ∫r = A/12 + A/3; total A/2, Sa = 1/2. (2, −1, 0): zero line from c to
    // the point 2/3 along ab; positive part area 2A/3, mean 2/3; negative part area A/3,
    // mean 1/3; Sa = 4/9 + 1/9 = 5/9. (1, 0, −1): two mirror halves, Sa = 1/3.
    let mesh = HalfedgeMesh::from_polygons(3, [[0u32, 1, 2]]).expect("valid");
    let positions = primitives::triangle().positions;
    for (values, sa) in [
        ([1.0, -1.0, -1.0], 0.5),
        ([-1.0, 1.0, 1.0], 0.5),
        ([1.0, 0.0, -1.0], 1.0 / 3.0),
        ([2.0, -1.0, 0.0], 5.0 / 9.0),
    ] {
        let s = areal(&mesh, &positions, &values, Datum::ReferenceSurface);
        assert!(close(s.sa, sa, 1e-15), "{values:?}: {} vs {sa}", s.sa);
    }
}

#[test]
fn sdq_is_the_cotangent_dirichlet_energy() {
    // Σ_T A_T |∇r|² = ½ Σ_edges (cot α + cot β)(r_i − r_j)² for a piecewise-linear r.
    let sphere = primitives::icosphere(2);
    let mesh = build(&sphere);
    let geometry = Geometry::new(&mesh, &sphere.positions).expect("positions");
    let r: Vec<f64> = sphere
        .positions
        .iter()
        .map(|p| (3.0 * p.x).sin() + p.y * p.z)
        .collect();
    let s = areal_parameters(&geometry, &r, &exact(Datum::Mean)).expect("valid");
    let energy: f64 = mesh
        .edges()
        .map(|e| {
            let [h, t] = e.halfedges();
            let [a, b] = mesh.edge_vertices(e);
            let cot = geometry.opposite_cotangent(h) + geometry.opposite_cotangent(t);
            0.5 * cot * (r[a.index()] - r[b.index()]).powi(2)
        })
        .sum();
    assert!(close(s.sdq * s.sdq * s.area, energy, 1e-12 * energy));
}

#[test]
fn sp_sv_and_the_mean_on_a_random_field() {
    let grid = primitives::grid(7, 5);
    let mesh = build(&grid);
    let mut random = SplitMix64::new(11);
    let positions: Vec<DVec3> = grid
        .positions
        .iter()
        .map(|&p| p + 0.2 * random.next_symmetric_vector())
        .collect();
    let r: Vec<f64> = positions
        .iter()
        .map(|_| 0.3 + random.next_symmetric())
        .collect();
    let geometry = Geometry::new(&mesh, &positions).expect("positions");
    let area: f64 = mesh.faces().map(|f| geometry.face_area(f)).sum();
    let mean = mesh
        .faces()
        .map(|f| {
            geometry.face_area(f)
                * mesh
                    .triangle_vertices(f)
                    .map(|v| r[v.index()])
                    .iter()
                    .sum::<f64>()
                / 3.0
        })
        .sum::<f64>()
        / area;
    let (max, min) = r
        .iter()
        .fold((f64::NEG_INFINITY, f64::INFINITY), |(hi, lo), &x| {
            (hi.max(x), lo.min(x))
        });

    let s = areal_parameters(&geometry, &r, &exact(Datum::ReferenceSurface)).expect("valid");
    assert!(close(s.area, area, 1e-13) && close(s.mean, mean, 1e-14));
    assert_eq!((s.sp, s.sv, s.sz), (max, min.abs(), max + min.abs()));
    let m = areal_parameters(&geometry, &r, &exact(Datum::Mean)).expect("valid");
    assert!(close(m.sp, max - mean, 1e-14) && close(m.sv, mean - min, 1e-14));
    assert!(close(m.sz, max - min, 1e-14));
    assert!(close(m.mean, s.mean, 0.0));
    assert!(close(m.sdq, s.sdq, 0.0) && close(m.sdr, s.sdr, 0.0));
    // Levelling minimises the RMS height: Sq² = Sq(levelled)² + μ².
    assert!(close(s.sq * s.sq, m.sq * m.sq + mean * mean, 1e-14));
}

#[test]
fn extreme_scales_give_the_same_dimensionless_parameters() {
    let sphere = primitives::icosphere(1);
    let mesh = build(&sphere);
    let r: Vec<f64> = sphere
        .positions
        .iter()
        .map(|p| 0.1 * p.x + 0.05 * p.y * p.y)
        .collect();
    let base = areal(&mesh, &sphere.positions, &r, Datum::Mean);
    for exponent in [-500, -200, 200, 500] {
        let scale = 2f64.powi(exponent);
        let positions: Vec<DVec3> = sphere.positions.iter().map(|&p| p * scale).collect();
        let field: Vec<f64> = r.iter().map(|&x| x * scale).collect();
        let s = areal(&mesh, &positions, &field, Datum::Mean);
        let relative = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs();
        assert!(
            relative(s.sdq, base.sdq) && relative(s.sdr, base.sdr),
            "2^{exponent}: {s:?}"
        );
        assert!(relative(s.ssk.expect("Sq > 0"), base.ssk.expect("Sq > 0")));
        assert!(relative(s.sku.expect("Sq > 0"), base.sku.expect("Sq > 0")));
        assert!(relative(s.sa / scale, base.sa) && relative(s.sq / scale, base.sq));
        assert!(relative(s.sz / scale, base.sz));
    }
    // A huge field on ordinary positions: moments scale, nothing overflows.
    let huge: Vec<f64> = r.iter().map(|&x| x * 1e200).collect();
    let s = areal(&mesh, &sphere.positions, &huge, Datum::Mean);
    assert!((s.sq / 1e200 - base.sq).abs() <= 1e-12 * base.sq);
    assert!((s.sku.expect("Sq > 0") - base.sku.expect("Sq > 0")).abs() < 1e-12);
    assert!((s.sdq / 1e200 - base.sdq).abs() <= 1e-12 * base.sdq);
    // Sdr ≈ mean |∇r| for such slopes, at most Sdq (the RMS).
    assert!(s.sdr.is_finite() && s.sdr <= s.sdq && s.sdr > 1e-3 * s.sdq);
}

#[test]
fn areal_errors_are_typed() {
    let grid = primitives::grid(2, 2);
    let mesh = build(&grid);
    let geometry = Geometry::new(&mesh, &grid.positions).expect("positions");
    assert_eq!(
        areal_parameters(&geometry, &[0.0; 8], &exact(Datum::Mean)),
        Err(MetricsError::FieldLength {
            what: "residual",
            got: 8,
            expected: 9
        })
    );
    let mut r = vec![0.0; 9];
    r[3] = f64::NAN;
    assert_eq!(
        areal_parameters(&geometry, &r, &exact(Datum::Mean)),
        Err(MetricsError::NonFinite {
            what: "residual value",
            index: 3
        })
    );
    r[3] = f64::NEG_INFINITY;
    assert!(matches!(
        areal_parameters(&geometry, &r, &exact(Datum::Mean)),
        Err(MetricsError::NonFinite { index: 3, .. })
    ));

    let empty = HalfedgeMesh::from_polygons(3, Vec::<[u32; 3]>::new()).expect("valid");
    let points = [DVec3::ZERO, DVec3::X, DVec3::Y];
    assert_eq!(
        areal_parameters(
            &Geometry::new(&empty, &points).expect("positions"),
            &[0.0; 3],
            &ArealOptions::default()
        ),
        Err(MetricsError::Empty { what: "mesh" })
    );
    let collapsed = vec![DVec3::ONE; 9];
    assert_eq!(
        areal_parameters(
            &Geometry::new(&mesh, &collapsed).expect("positions"),
            &[0.0; 9],
            &ArealOptions::default()
        ),
        Err(MetricsError::Empty { what: "mesh area" })
    );
    let quads = primitives::cube_quads();
    let quad_mesh = build(&quads);
    assert_eq!(
        areal_parameters(
            &Geometry::new(&quad_mesh, &quads.positions).expect("positions"),
            &[0.0; 8],
            &ArealOptions::default()
        ),
        Err(MetricsError::Topology(TopologyError::NotTriangle {
            face: 0,
            len: 4
        }))
    );
    let mut bad = grid.positions.clone();
    bad[2].z = f64::NAN;
    assert_eq!(
        areal_parameters(
            &Geometry::new(&mesh, &bad).expect("positions"),
            &[0.0; 9],
            &ArealOptions::default()
        ),
        Err(MetricsError::NonFinite {
            what: "position",
            index: 2
        })
    );
}

#[test]
fn normal_residual_is_the_signed_normal_deviation() {
    // Flat reference form with normal +z: a measured point displaced by (t_x, t_y, h) has
    // residual h; the tangential part is ignored.
    let grid = primitives::grid(5, 4);
    let mesh = build(&grid);
    let mut random = SplitMix64::new(3);
    let heights: Vec<f64> = grid
        .positions
        .iter()
        .map(|_| 0.01 * random.next_symmetric())
        .collect();
    let measured: Vec<DVec3> = grid
        .positions
        .iter()
        .zip(&heights)
        .map(|(&p, &h)| {
            p + DVec3::new(
                0.05 * random.next_symmetric(),
                0.05 * random.next_symmetric(),
                h,
            )
        })
        .collect();
    let r = normal_residual(
        &Geometry::new(&mesh, &measured).expect("positions"),
        &Geometry::new(&mesh, &grid.positions).expect("positions"),
    )
    .expect("same topology");
    for (got, want) in r.as_slice().iter().zip(&heights) {
        assert!(close(*got, *want, 1e-17), "{got} vs {want}");
    }

    // A sphere measured 1 % too large or too small: positive outside, negative inside,
    // |r| = 0.01 p·n ≥ 0.01 cos(max angle between position and normal).
    let sphere = primitives::icosphere(2);
    let mesh = build(&sphere);
    let smoothed = Geometry::new(&mesh, &sphere.positions).expect("positions");
    for factor in [1.01, 0.99] {
        let measured: Vec<DVec3> = sphere.positions.iter().map(|&p| factor * p).collect();
        let r = normal_residual(
            &Geometry::new(&mesh, &measured).expect("positions"),
            &smoothed,
        )
        .expect("same topology");
        for &x in r.as_slice() {
            assert!(close(x, factor - 1.0, 1e-4), "{x}");
            assert_eq!(x.signum(), (factor - 1.0).signum());
        }
    }

    // An isolated vertex has no normal: residual 0.
    let mesh = HalfedgeMesh::from_polygons(4, [[0u32, 1, 2]]).expect("valid");
    let smoothed = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ONE];
    let measured = [DVec3::Z, DVec3::X, DVec3::Y, DVec3::splat(5.0)];
    let r = normal_residual(
        &Geometry::new(&mesh, &measured).expect("positions"),
        &Geometry::new(&mesh, &smoothed).expect("positions"),
    )
    .expect("same topology");
    assert!(close(r.as_slice()[0], 1.0, 1e-15));
    assert_eq!(&r.as_slice()[1..], &[0.0, 0.0, 0.0]);

    // Different topologies are refused.
    let other = build(&primitives::grid(1, 1));
    let err = normal_residual(
        &Geometry::new(&other, &[DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ONE]).expect("positions"),
        &Geometry::new(&mesh, &smoothed).expect("positions"),
    )
    .unwrap_err();
    assert!(
        matches!(err, MetricsError::TopologyMismatch { .. }),
        "{err}"
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Moment inequalities and scaling laws on random fields over a jittered grid:
    /// Sa ≤ Sq (Jensen), Sku ≥ 1 and Ssk² ≤ Sku (Cauchy–Schwarz), Sq ≤ max |r|;
    /// for c·r: Sa, Sq, Sdq scale by |c|, Ssk by sign(c), Sku not at all.
    #[test]
    fn moment_inequalities_and_scaling(
        values in prop::collection::vec(-1.0f64..1.0, 20),
        jitter in prop::collection::vec(-0.3f64..0.3, 20),
        c in prop_oneof![-5.0f64..-0.1, 0.1f64..5.0],
    ) {
        let grid = primitives::grid(4, 3);
        let mesh = build(&grid);
        let positions: Vec<DVec3> = grid.positions.iter().zip(&jitter).map(|(&p, &z)| p + DVec3::new(0.0, 0.0, z)).collect();
        let s = areal(&mesh, &positions, &values, Datum::ReferenceSurface);
        let largest = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        prop_assert!(s.sa <= s.sq * (1.0 + 1e-12));
        prop_assert!(s.sq <= largest * (1.0 + 1e-12));
        if let (Some(ssk), Some(sku)) = (s.ssk, s.sku) {
            prop_assert!(sku >= 1.0 - 1e-12);
            prop_assert!(ssk * ssk <= sku * (1.0 + 1e-12));
        }
        let scaled: Vec<f64> = values.iter().map(|&v| c * v).collect();
        let t = areal(&mesh, &positions, &scaled, Datum::ReferenceSurface);
        let same = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1e-300);
        prop_assert!(same(t.sa, c.abs() * s.sa) && same(t.sq, c.abs() * s.sq));
        prop_assert!(same(t.sdq, c.abs() * s.sdq));
        if let (Some(a), Some(b)) = (t.ssk, s.ssk) {
            prop_assert!((a - c.signum() * b).abs() <= 1e-10);
        }
        if let (Some(a), Some(b)) = (t.sku, s.sku) {
            prop_assert!((a - b).abs() <= 1e-10 * b);
        }
    }
}
