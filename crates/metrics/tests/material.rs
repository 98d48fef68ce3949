//! The areal material ratio curve and its parameters against closed forms: a profile
//! whose curve is a chosen polyline (Sk, Spk, Svk, Smr1, Smr2, Sak1, Sak2 by hand), a
//! sinusoid (arcsine heights: Sk, Sxp and the volumes in closed form), uniform heights,
//! the inverse relations between Smr and Smc, and typed errors.

use std::f64::consts::{PI, TAU};

use beltrami_halfedge::DVec3;
use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::primitives;
use beltrami_metrics::MetricsError;
use beltrami_metrics::residual::{
    ArealOptions, Datum, MaterialRatioCurve, Quadrature, StratifiedParameters,
};

fn options(quadrature: Quadrature) -> ArealOptions {
    ArealOptions::default()
        .datum(Datum::ReferenceSurface)
        .quadrature(quadrature)
}

/// The curve of a field `z(x)` on a grid of `cells × 2` squares over `[0, 1] × [0, 2 /
/// cells]`: a surface whose heights depend on x alone, so that for a decreasing `z` the
/// share of the area at or above `z(x)` is exactly `x`.
fn profile_curve(cells: u32, z: impl Fn(f64) -> f64, quadrature: Quadrature) -> MaterialRatioCurve {
    let grid = primitives::grid(cells, 2);
    let mesh = grid.mesh().expect("grid builds");
    let scale = 1.0 / f64::from(cells);
    let positions: Vec<DVec3> = grid.positions.iter().map(|&p| p * scale).collect();
    let field: Vec<f64> = positions.iter().map(|p| z(p.x)).collect();
    MaterialRatioCurve::from_mesh(
        &Geometry::new(&mesh, &positions).expect("positions"),
        &field,
        &options(quadrature),
    )
    .expect("valid")
}

/// A decreasing polyline through (0, 3), (0.1, 1), (0.9, −1), (1, −4): a steep peak
/// zone, a core of slope −2.5 per unit ratio, a steep dale zone.
fn stratified_profile(x: f64) -> f64 {
    if x <= 0.1 {
        3.0 - 20.0 * x
    } else if x <= 0.9 {
        1.0 - 2.5 * (x - 0.1)
    } else {
        -1.0 - 30.0 * (x - 0.9)
    }
}

/// By hand: the equivalent line is the core line `1.25 − 2.5 q`, so `c₁ = 1.25`,
/// `c₂ = −1.25`, `Sk = 2.5`. The peak zone meets `c₁` at `q = (3 − 1.25)/20 = 0.0875`:
/// `Smr1 = 8.75 %`, and the peak area above `c₁` is a triangle of base 8.75 % and height
/// 1.75: `Sak1 = 7.65625 %·length`, `Spk = 1.75`. The dale zone meets `c₂` at
/// `q = 0.9 + 0.25/30`: `Smr2 = 90.8333 %`, a triangle of base `100 % − Smr2 = 9.1667 %`
/// and height 2.75: `Sak2 = 12.6042 %·length`, `Svk = 2.75`.
fn expected_stratified() -> StratifiedParameters {
    let smr2 = 100.0 * (0.9 + 0.25 / 30.0);
    StratifiedParameters {
        sk: 2.5,
        spk: 1.75,
        svk: 2.75,
        smr1: 8.75,
        smr2,
        sak1: 0.5 * 8.75 * 1.75,
        sak2: 0.5 * (100.0 - smr2) * 2.75,
        core_top: 1.25,
        core_bottom: -1.25,
        window_start: f64::NAN, // anywhere in [10 %, 50 %]
    }
}

fn check_stratified(got: &StratifiedParameters, tolerance: f64) {
    let want = expected_stratified();
    for (name, g, w) in [
        ("sk", got.sk, want.sk),
        ("spk", got.spk, want.spk),
        ("svk", got.svk, want.svk),
        ("smr1", got.smr1, want.smr1),
        ("smr2", got.smr2, want.smr2),
        ("sak1", got.sak1, want.sak1),
        ("sak2", got.sak2, want.sak2),
        ("core_top", got.core_top, want.core_top),
        ("core_bottom", got.core_bottom, want.core_bottom),
    ] {
        assert!(
            (g - w).abs() <= tolerance * w.abs().max(1.0),
            "{name}: {g} vs {w}"
        );
    }
    assert!(
        (10.0 - 1e-6..=50.0 + 1e-6).contains(&got.window_start),
        "the window lies in the core: {}",
        got.window_start
    );
}

#[test]
fn the_sk_family_of_a_chosen_curve() {
    // The exact interpolant reproduces the polyline (its kinks lie on grid lines): exact
    // up to the 4097 height levels the curve is evaluated at.
    let exact = profile_curve(1000, stratified_profile, Quadrature::ExactInterpolant);
    check_stratified(&exact.stratified(), 1e-5);
    // The lumped rule: trapezoid weights on the columns, mid-point plotting positions.
    let lumped = profile_curve(1000, stratified_profile, Quadrature::Lumped);
    check_stratified(&lumped.stratified(), 3e-3);
    // And the curve itself: Smc(q) = z(q), Smr(z(x)) = x.
    for q in [0.05, 0.3, 0.5, 0.95] {
        assert!((exact.smc(100.0 * q).unwrap() - stratified_profile(q)).abs() < 1e-6);
        assert!((exact.smr(stratified_profile(q)) - 100.0 * q).abs() < 1e-6);
        assert!((lumped.smc(100.0 * q).unwrap() - stratified_profile(q)).abs() < 1e-3);
    }
    assert!((exact.highest() - 3.0).abs() < 1e-12 && (exact.lowest() + 4.0).abs() < 1e-12);
}

/// The Sk construction on a sine of amplitude `A` by hand, for the window `[0, 40 %]`:
/// its heights follow the arcsine law, `Smc(q) = A cos(πq)`. Over the window the curve's
/// mean is `A sin(0.4π) / 0.4π`, and the least-squares slope is
/// `β = A · 12/0.4³ · ∫₀^0.4 (q − 0.2) cos(πq) dq`
/// `= A · 12/0.4³ · (0.2 sin(0.4π)/π + (cos(0.4π) − 1)/π²)`. The line's heights at 0 and
/// 1 are `c₁ = mean − 0.2 β` (above the crests) and `c₂ = mean + 0.8 β`; Smr2 is where
/// `A cos(πq) = c₂`, and the dale area below `c₂` is
/// `∫_{q₂}^1 (c₂ − A cos πq) dq = c₂ (1 − q₂) + A sin(π q₂)/π`.
/// Returns `(Sk, c₁, c₂, Smr2 as a fraction, Svk)`.
fn sine_window(amplitude: f64) -> (f64, f64, f64, f64, f64) {
    let mean = amplitude * (0.4 * PI).sin() / (0.4 * PI);
    let integral = 0.2 * (0.4 * PI).sin() / PI + ((0.4 * PI).cos() - 1.0) / (PI * PI);
    let beta = amplitude * 12.0 / 0.4f64.powi(3) * integral;
    let (c1, c2) = (mean - 0.2 * beta, mean + 0.8 * beta);
    let q2 = (c2 / amplitude).acos() / PI;
    let dales = c2 * (1.0 - q2) + amplitude * (PI * q2).sin() / PI;
    (-beta, c1, c2, q2, 2.0 * dales / (1.0 - q2))
}

#[test]
fn a_sinusoid_has_the_arcsine_curve_and_its_closed_forms() {
    let amplitude = 0.7;
    // Four whole periods over [0, 1], 2000 cells; the phase keeps the samples off the
    // symmetry of the crests, so that no two columns share a height (ties would make the
    // lumped curve locally uneven, and the least-gradient window, at the ends of a
    // sine's curve where it bends most, is sensitive to that).
    let wave = |x: f64| amplitude * (TAU * 4.0 * x + 0.123).sin();
    // The exact interpolant of 500 samples per period is within 2·10⁻⁴ A of the sine
    // everywhere; the lumped rule integrates the distribution function (a step function
    // of the height) by area-weighted counting, whose error near the crests, where the
    // arcsine density is singular, is a few 10⁻⁴ A.
    for (quadrature, tolerance) in [
        (Quadrature::ExactInterpolant, 2e-4),
        (Quadrature::Lumped, 5e-4),
    ] {
        let curve = profile_curve(2000, wave, quadrature);
        let close = |got: f64, want: f64, what: &str| {
            assert!(
                (got - want).abs() <= tolerance * amplitude,
                "{quadrature:?} {what}: {got} vs {want}"
            );
        };
        for q in [0.025, 0.1, 0.3, 0.5, 0.8, 0.975] {
            close(
                curve.smc(100.0 * q).unwrap(),
                amplitude * (PI * q).cos(),
                "Smc",
            );
        }
        // The flattest 40 % of the arcsine curve lies at either end (the crests and
        // the troughs, where a sine dwells): two windows tie, [0, 40 %] and [60, 100 %].
        // Both give the same Sk; the one taken puts either the peaks or the dales
        // outside the core.
        let s = curve.stratified();
        let (sk, c1, c2, mr2, svk) = sine_window(amplitude);
        close(s.sk, sk, "Sk");
        if s.window_start < 30.0 {
            assert!(s.window_start.abs() < 0.1, "{}", s.window_start);
            close(s.core_top, c1, "c1");
            close(s.core_bottom, c2, "c2");
            assert_eq!((s.smr1, s.spk, s.sak1), (0.0, 0.0, 0.0));
            assert!((s.smr2 - 100.0 * mr2).abs() < 0.1, "{}", s.smr2);
            // Svk hangs on where the curve meets c₂, a ratio the lumped rule finds to
            // first order in the spacing.
            assert!(
                (s.svk - svk).abs() < 2e-3 * amplitude,
                "{quadrature:?} Svk: {} vs {svk}",
                s.svk
            );
        } else {
            assert!((s.window_start - 60.0).abs() < 0.1, "{}", s.window_start);
            close(s.core_top, -c2, "c1");
            close(s.core_bottom, -c1, "c2");
            assert_eq!((s.smr2, s.svk, s.sak2), (100.0, 0.0, 0.0));
            assert!((s.smr1 - 100.0 * (1.0 - mr2)).abs() < 0.1, "{}", s.smr1);
            assert!(
                (s.spk - svk).abs() < 2e-3 * amplitude,
                "{quadrature:?} Spk: {} vs {svk}",
                s.spk
            );
        }
        // Sxp = Smc(2.5 %) − Smc(50 %) = A cos(0.025 π).
        close(
            curve.sxp(2.5, 50.0).unwrap(),
            amplitude * (0.025 * PI).cos(),
            "Sxp",
        );
        // Vm(p) = A (sin(πp)/π − p cos(πp)), Vv(p) = A ((1 − p) cos(πp) + sin(πp)/π).
        let vm = |p: f64| amplitude * ((PI * p).sin() / PI - p * (PI * p).cos());
        let vv = |p: f64| amplitude * ((1.0 - p) * (PI * p).cos() + (PI * p).sin() / PI);
        let v = curve.volume(10.0, 80.0).unwrap();
        close(v.vmp, vm(0.1), "Vmp");
        close(v.vmc, vm(0.8) - vm(0.1), "Vmc");
        close(v.vvc, vv(0.1) - vv(0.8), "Vvc");
        close(v.vvv, vv(0.8), "Vvv");
        assert_eq!((v.p, v.q), (10.0, 80.0));
    }
}

#[test]
fn smr_and_smc_are_inverse_and_the_volumes_add_up() {
    // An irregular field on a bumpy grid: z = sin(3x + 0.1) cos(2y + 0.2) + 0.3 x (no two
    // vertices at the same height, so the curve has no plateau).
    let grid = primitives::grid(40, 30);
    let mesh = grid.mesh().expect("grid builds");
    let positions: Vec<DVec3> = grid
        .positions
        .iter()
        .map(|p| DVec3::new(p.x * 0.1, p.y * 0.1, 0.05 * (p.x * 0.7).sin()))
        .collect();
    let z: Vec<f64> = positions
        .iter()
        .map(|p| (3.0 * p.x + 0.1).sin() * (2.0 * p.y + 0.2).cos() + 0.3 * p.x)
        .collect();
    let geometry = Geometry::new(&mesh, &positions).expect("positions");
    for quadrature in [Quadrature::Lumped, Quadrature::ExactInterpolant] {
        let curve = MaterialRatioCurve::from_mesh(&geometry, &z, &options(quadrature)).unwrap();
        let points = curve.points();
        assert_eq!(points[0].0, 0.0);
        assert_eq!(points[points.len() - 1].0, 1.0);
        assert!(
            points
                .windows(2)
                .all(|w| w[1].0 >= w[0].0 && w[1].1 <= w[0].1),
            "monotone"
        );
        let (top, bottom) = (curve.highest(), curve.lowest());
        assert_eq!(curve.smr(top + 1.0), 0.0);
        assert_eq!(curve.smr(bottom), 100.0);
        for mr in [1.0, 17.0, 50.0, 83.0, 99.0] {
            let c = curve.smc(mr).unwrap();
            assert!((curve.smr(c) - mr).abs() < 1e-9, "{quadrature:?} {mr}");
            // Vv(mr) − Vm(mr) = ∫₀¹ (Smc(mr) − Smc(q)) dq = Smc(mr) − mean of Smc.
            let mean_height = c - (curve.vv(mr).unwrap() - curve.vm(mr).unwrap());
            let mean_at_zero = curve.smc(0.0).unwrap() - curve.vv(0.0).unwrap();
            assert!((mean_height - mean_at_zero).abs() < 1e-12, "{quadrature:?}");
        }
        assert_eq!(curve.vm(0.0).unwrap(), 0.0);
        assert_eq!(curve.vv(100.0).unwrap(), 0.0);
        // Sxp(p, p) = 0 and Sxp grows as p falls.
        assert_eq!(curve.sxp(30.0, 30.0).unwrap(), 0.0);
        assert!(curve.sxp(1.0, 50.0).unwrap() > curve.sxp(10.0, 50.0).unwrap());
    }
    // The lumped curve's mean height is the area-weighted mean of the vertex heights, up
    // to the plotting positions (exact for equal neighbouring weights).
    let lumped =
        MaterialRatioCurve::from_mesh(&geometry, &z, &options(Quadrature::Lumped)).unwrap();
    let datum = ArealOptions::default()
        .datum(Datum::Mean)
        .quadrature(Quadrature::Lumped);
    let levelled = MaterialRatioCurve::from_mesh(&geometry, &z, &datum).unwrap();
    // Heights from the mean: the curve moves down by the mean and keeps its shape.
    let shift = lumped.smc(50.0).unwrap() - levelled.smc(50.0).unwrap();
    for mr in [5.0, 40.0, 95.0] {
        let d = lumped.smc(mr).unwrap() - levelled.smc(mr).unwrap();
        assert!((d - shift).abs() < 1e-12);
    }
    let mean_of_smc = lumped.smc(0.0).unwrap() - lumped.vv(0.0).unwrap();
    assert!(
        (mean_of_smc - shift).abs() < 2e-3,
        "{mean_of_smc} vs {shift}"
    );
}

#[test]
fn uniform_heights_are_all_core() {
    // A tilted plane: heights uniform on [0, 1]; the curve is the straight line.
    let curve = profile_curve(500, |x| 1.0 - x, Quadrature::ExactInterpolant);
    let s = curve.stratified();
    assert!((s.sk - 1.0).abs() < 1e-9 && (s.core_top - 1.0).abs() < 1e-9);
    assert!(s.smr1.abs() < 1e-6 && (s.smr2 - 100.0).abs() < 1e-6);
    assert!(s.spk.abs() < 1e-6 && s.svk.abs() < 1e-6);
    let v = curve.volume(10.0, 80.0).unwrap();
    // Vm(p) = p²/2, Vv(p) = (1 − p)²/2.
    assert!((v.vmp - 0.005).abs() < 1e-9 && (v.vvv - 0.02).abs() < 1e-9);
    assert!((v.vmc - 0.315).abs() < 1e-9 && (v.vvc - 0.385).abs() < 1e-9);

    // Constant heights: a flat curve, no core, no volumes.
    let flat = profile_curve(10, |_| 0.25, Quadrature::ExactInterpolant);
    let lumped_flat = profile_curve(10, |_| 0.25, Quadrature::Lumped);
    for curve in [flat, lumped_flat] {
        let s = curve.stratified();
        assert!(s.sk.abs() < 1e-15 && s.spk.abs() < 1e-15 && s.svk.abs() < 1e-15);
        assert_eq!(curve.smc(37.0).unwrap(), 0.25);
        assert_eq!(curve.volume(10.0, 80.0).unwrap().vvc, 0.0);
    }
}

#[test]
fn weighted_heights_and_errors() {
    // Equal weights: the empirical distribution of the samples.
    let curve = MaterialRatioCurve::from_weighted_heights(&[4.0, 2.0, 0.0], &[1.0, 1.0, 1.0])
        .expect("valid");
    assert_eq!(curve.smc(100.0 / 6.0).unwrap(), 4.0);
    assert_eq!(curve.smc(50.0).unwrap(), 2.0);
    assert_eq!(curve.smr(3.0), 100.0 / 3.0);
    // Equal heights make one point, at the middle of their joint share.
    let plateau =
        MaterialRatioCurve::from_weighted_heights(&[2.0, 1.0, 1.0, 0.0], &[1.0; 4]).unwrap();
    assert_eq!(
        plateau.points(),
        [
            (0.0, 2.0),
            (0.125, 2.0),
            (0.5, 1.0),
            (0.875, 0.0),
            (1.0, 0.0)
        ]
    );
    assert_eq!(plateau.smr(1.0), 50.0);
    assert_eq!(plateau.smc(50.0).unwrap(), 1.0);
    // A flat stretch of the curve: Smr at its height is its largest ratio.
    assert_eq!(plateau.smr(2.0), 12.5);
    // A zero weight leaves its sample out.
    let curve = MaterialRatioCurve::from_weighted_heights(&[9.0, 1.0], &[0.0, 1.0]).unwrap();
    assert_eq!(curve.highest(), 1.0);

    for bad in [-1.0, 100.5, f64::NAN] {
        assert!(matches!(
            curve.smc(bad),
            Err(MetricsError::InvalidParameter { .. })
        ));
        assert!(matches!(
            curve.vm(bad),
            Err(MetricsError::InvalidParameter { .. })
        ));
    }
    assert!(matches!(
        curve.sxp(60.0, 50.0),
        Err(MetricsError::InvalidParameter { .. })
    ));
    assert!(matches!(
        curve.volume(80.0, 10.0),
        Err(MetricsError::InvalidParameter { .. })
    ));
    assert_eq!(
        MaterialRatioCurve::from_weighted_heights(&[1.0], &[1.0, 2.0]),
        Err(MetricsError::FieldLength {
            what: "weights",
            got: 2,
            expected: 1
        })
    );
    assert_eq!(
        MaterialRatioCurve::from_weighted_heights(&[1.0, f64::INFINITY], &[1.0, 1.0]),
        Err(MetricsError::NonFinite {
            what: "height",
            index: 1
        })
    );
    assert!(matches!(
        MaterialRatioCurve::from_weighted_heights(&[1.0], &[-1.0]),
        Err(MetricsError::InvalidParameter { .. })
    ));
    assert_eq!(
        MaterialRatioCurve::from_weighted_heights(&[1.0], &[0.0]),
        Err(MetricsError::Empty { what: "weights" })
    );
    let grid = primitives::grid(2, 2);
    let mesh = grid.mesh().unwrap();
    let geometry = Geometry::new(&mesh, &grid.positions).unwrap();
    assert_eq!(
        MaterialRatioCurve::from_mesh(&geometry, &[0.0; 3], &ArealOptions::default()),
        Err(MetricsError::FieldLength {
            what: "residual",
            got: 3,
            expected: 9
        })
    );
}
