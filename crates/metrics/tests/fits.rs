//! Least-squares fits: exact synthetic data under random rigid motions far from the origin,
//! partial caps and arcs, Gaussian noise against its predicted spread, weights, the
//! smoothed-sphere use, and errors.
//!
//! The NIST Algorithm Testing System's reference data sets (Shakarji 1998) are distributed
//! by NIST on request and are not available to these tests; the cases below use exact data
//! with known parameters instead, and noise whose effect is predicted from the Jacobian.

use beltrami_halfedge::DVec3;
use beltrami_halfedge::primitives;
use beltrami_metrics::MetricsError;
use beltrami_metrics::fits::{FitOptions, FitPoints, fit_circle, fit_cylinder, fit_sphere};
use beltrami_testkit::SplitMix64;
use glam::DQuat;

/// Draws built on testkit's generator.
trait Draws {
    /// Three standard normal numbers, x then y then z.
    fn gaussian3(&mut self) -> DVec3;
    /// A random rotation: a normalised quaternion of four standard normal numbers.
    fn rotation(&mut self) -> DQuat;
}

impl Draws for SplitMix64 {
    fn gaussian3(&mut self) -> DVec3 {
        DVec3::new(self.next_normal(), self.next_normal(), self.next_normal())
    }
    fn rotation(&mut self) -> DQuat {
        let q = DQuat::from_xyzw(
            self.next_normal(),
            self.next_normal(),
            self.next_normal(),
            self.next_normal(),
        );
        q.normalize()
    }
}

/// Points on a sphere cap of polar half-angle `cap` (radians) about +z, area-uniform.
fn cap_points(rng: &mut SplitMix64, n: usize, radius: f64, cap: f64) -> Vec<DVec3> {
    (0..n)
        .map(|_| {
            let z = rng.next_range(cap.cos(), 1.0);
            let phi = rng.next_range(0.0, std::f64::consts::TAU);
            let s = (1.0 - z * z).sqrt();
            DVec3::new(s * phi.cos(), s * phi.sin(), z) * radius
        })
        .collect()
}

/// Points on a cylinder of the z-axis over the angle range `[0, arc]` and `z ∈ [−h, h]`.
fn cylinder_points(rng: &mut SplitMix64, n: usize, radius: f64, arc: f64, h: f64) -> Vec<DVec3> {
    (0..n)
        .map(|_| {
            let phi = rng.next_range(0.0, arc);
            DVec3::new(
                radius * phi.cos(),
                radius * phi.sin(),
                rng.next_range(-h, h),
            )
        })
        .collect()
}

/// Inverse of a symmetric positive definite matrix by Gauss–Jordan elimination.
fn inverse<const N: usize>(m: [[f64; N]; N]) -> [[f64; N]; N] {
    let mut a = m;
    let mut inv = [[0.0; N]; N];
    for (i, row) in inv.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    for i in 0..N {
        let p = a[i][i];
        for j in 0..N {
            a[i][j] /= p;
            inv[i][j] /= p;
        }
        for k in 0..N {
            if k != i {
                let f = a[k][i];
                for j in 0..N {
                    a[k][j] -= f * a[i][j];
                    inv[k][j] -= f * inv[i][j];
                }
            }
        }
    }
    inv
}

/// The standard deviation of a sphere fit's radius for isotropic noise σ along the normals:
/// `σ sqrt((JᵀJ)⁻¹_rr)` with Jacobian rows `[−uᵀ, −1]` at the true parameters.
fn sphere_radius_sigma(unit_normals: &[DVec3], sigma: f64) -> f64 {
    let mut jtj = [[0.0; 4]; 4];
    for u in unit_normals {
        let g = [-u.x, -u.y, -u.z, -1.0];
        for i in 0..4 {
            for j in 0..4 {
                jtj[i][j] += g[i] * g[j];
            }
        }
    }
    sigma * inverse(jtj)[3][3].sqrt()
}

fn options() -> FitOptions {
    FitOptions::default()
}

// ---------------------------------------------------------------------------------------
// Spheres.

#[test]
fn exact_spheres_are_recovered_under_random_motions_far_from_the_origin() {
    let mut rng = SplitMix64::new(1);
    for (cap_deg, n) in [(180.0, 500), (60.0, 300), (30.0, 300)] {
        for _ in 0..5 {
            let radius = rng.next_range(0.5, 50.0);
            let center = DVec3::new(rng.next_range(-1e3, 1e3), rng.next_range(-1e3, 1e3), 1e3);
            let rotation = rng.rotation();
            let local = cap_points(&mut rng, n, radius, f64::to_radians(cap_deg));
            let points: Vec<DVec3> = local.iter().map(|&p| rotation * p + center).collect();
            let fit = fit_sphere(&FitPoints::new(&points), &options()).unwrap();
            // Far from the origin, coordinates carry about 1e-13 absolute rounding.
            assert!(
                (fit.radius - radius).abs() < 1e-9 * radius.max(1.0),
                "{cap_deg}: {fit:?} vs {radius}"
            );
            assert!(
                (fit.center - center).length() < 1e-9 * radius.max(1.0),
                "{cap_deg}: {fit:?}"
            );
            assert!(fit.converged && fit.rms_residual < 1e-10 && fit.max_residual < 1e-10);
            assert!(fit.iterations <= 20, "{fit:?}");
        }
    }
}

#[test]
fn noisy_full_sphere_radius_is_within_a_few_sigma_over_root_n() {
    let mut rng = SplitMix64::new(2);
    let (radius, sigma, n) = (10.0, 0.05, 4000);
    let center = DVec3::new(250.0, -120.0, 40.0);
    let local = cap_points(&mut rng, n, radius, std::f64::consts::PI);
    let points: Vec<DVec3> = local
        .iter()
        .map(|&p| p + center + p.normalize() * (sigma * rng.next_normal()))
        .collect();
    let fit = fit_sphere(&FitPoints::new(&points), &options()).unwrap();
    let bound = 4.0 * sigma / (n as f64).sqrt();
    assert!((fit.radius - radius).abs() < bound, "{fit:?}");
    // Each centre coordinate has variance about 3σ²/n on a full sphere.
    assert!(
        (fit.center - center).abs().max_element() < bound * 3f64.sqrt(),
        "{fit:?}"
    );
    // The residual RMS estimates σ.
    assert!((fit.rms_residual / sigma - 1.0).abs() < 0.05, "{fit:?}");
}

#[test]
fn noisy_cap_radius_is_within_its_predicted_spread() {
    // On a 60° cap the radius is correlated with the centre, so its spread is larger than
    // σ/√n; predict it from the Jacobian and allow four of those.
    let mut rng = SplitMix64::new(3);
    let (radius, sigma, n) = (20.0, 0.02, 3000);
    let local = cap_points(&mut rng, n, radius, f64::to_radians(60.0));
    let normals: Vec<DVec3> = local.iter().map(|p| p.normalize()).collect();
    let predicted = sphere_radius_sigma(&normals, sigma);
    assert!(predicted > 1.5 * sigma / (n as f64).sqrt());
    let rotation = rng.rotation();
    let offset = DVec3::new(-300.0, 800.0, 120.0);
    let points: Vec<DVec3> = local
        .iter()
        .zip(&normals)
        .map(|(&p, &u)| rotation * (p + u * (sigma * rng.next_normal())) + offset)
        .collect();
    let fit = fit_sphere(&FitPoints::new(&points), &options()).unwrap();
    assert!(
        (fit.radius - radius).abs() < 4.0 * predicted,
        "{fit:?}, σ_r {predicted}"
    );
}

#[test]
fn a_smoothed_icosphere_fits_its_mean_radius() {
    // Smoothing shrinks a sphere unevenly; the fitted radius is then the mean distance of
    // the vertices from the fitted centre (the optimality condition in r), and the centre
    // stays at the origin by symmetry of the perturbation's average.
    let sphere = primitives::icosphere(4);
    let shrunk: Vec<DVec3> = sphere
        .positions
        .iter()
        .map(|&p| p * (0.985 + 0.002 * (3.0 * p.x).sin() * (2.0 * p.y).cos()))
        .collect();
    let fit = fit_sphere(&FitPoints::new(&shrunk), &options()).unwrap();
    let mean = shrunk
        .iter()
        .map(|p| (*p - fit.center).length())
        .sum::<f64>()
        / shrunk.len() as f64;
    assert!(
        (fit.radius - mean).abs() < 1e-13,
        "{} vs {mean}",
        fit.radius
    );
    assert!(fit.radius > 0.983 && fit.radius < 0.987);
    // Area-weighted: the radius is the area-weighted mean distance.
    let mesh = sphere.mesh().unwrap();
    let weighted = FitPoints::area_weighted(&mesh, &shrunk).unwrap();
    let wfit = fit_sphere(&weighted, &options()).unwrap();
    let w = weighted.weights().unwrap();
    let wmean = shrunk
        .iter()
        .zip(w)
        .map(|(p, a)| a * (*p - wfit.center).length())
        .sum::<f64>()
        / w.iter().sum::<f64>();
    assert!((wfit.radius - wmean).abs() < 1e-13);
    // The icosphere's sampling is nearly uniform: weighting changes the radius little.
    assert!((wfit.radius - fit.radius).abs() < 1e-4);
}

#[test]
fn weights_act_as_multiplicities() {
    let mut rng = SplitMix64::new(4);
    let local = cap_points(&mut rng, 200, 3.0, 1.2);
    let points: Vec<DVec3> = local.iter().map(|&p| p + rng.gaussian3() * 0.01).collect();
    let mut doubled = points.clone();
    doubled.extend_from_slice(&points[..50]);
    let mut weights = vec![1.0; 200];
    weights[..50].fill(2.0);
    let a = fit_sphere(&FitPoints::new(&doubled), &options()).unwrap();
    let b = fit_sphere(&FitPoints::weighted(&points, &weights).unwrap(), &options()).unwrap();
    assert!((a.radius - b.radius).abs() < 1e-12 && (a.center - b.center).length() < 1e-12);
    assert!((a.rms_residual - b.rms_residual).abs() < 1e-12);
    // Zero weights exclude points.
    let mut outlier = points.clone();
    outlier.push(DVec3::splat(100.0));
    let mut w = vec![1.0; 201];
    w[200] = 0.0;
    let c = fit_sphere(&FitPoints::weighted(&outlier, &w).unwrap(), &options()).unwrap();
    let d = fit_sphere(&FitPoints::new(&points), &options()).unwrap();
    assert!((c.radius - d.radius).abs() < 1e-12);
}

// ---------------------------------------------------------------------------------------
// Circles.

#[test]
fn exact_circles_and_arcs_are_recovered_in_any_plane() {
    let mut rng = SplitMix64::new(5);
    for arc_deg in [360.0, 90.0, 20.0] {
        for _ in 0..5 {
            let radius = rng.next_range(1.0, 40.0);
            let center = DVec3::new(
                rng.next_range(-500.0, 500.0),
                700.0,
                rng.next_range(-500.0, 500.0),
            );
            let rotation = rng.rotation();
            let points: Vec<DVec3> = (0..100)
                .map(|_| {
                    let phi = rng.next_range(0.0, f64::to_radians(arc_deg));
                    rotation * DVec3::new(radius * phi.cos(), radius * phi.sin(), 0.0) + center
                })
                .collect();
            let fit = fit_circle(&FitPoints::new(&points), &options()).unwrap();
            let normal = rotation * DVec3::Z;
            let tol = 1e-8 * radius * 360.0 / arc_deg;
            assert!(
                (fit.radius - radius).abs() < tol,
                "{arc_deg}: {fit:?} vs {radius}"
            );
            assert!((fit.center - center).length() < tol, "{arc_deg}: {fit:?}");
            assert!((fit.axis.dot(normal).abs() - 1.0).abs() < 1e-12);
            assert!(fit.plane_rms < 1e-10 && fit.rms_residual < 1e-10 && fit.converged);
            // Sign convention: the largest component of the axis is positive.
            let a = fit.axis;
            assert!(a.abs().max_element() == a.max_element());
        }
    }
}

#[test]
fn noisy_circle_radius_is_within_a_few_sigma_over_root_n() {
    let mut rng = SplitMix64::new(6);
    let (radius, sigma, n) = (12.0, 0.03, 3000);
    let rotation = rng.rotation();
    let center = DVec3::new(40.0, -30.0, 900.0);
    let points: Vec<DVec3> = (0..n)
        .map(|_| {
            let phi = rng.next_range(0.0, std::f64::consts::TAU);
            let r = radius + sigma * rng.next_normal();
            let h = sigma * rng.next_normal();
            rotation * DVec3::new(r * phi.cos(), r * phi.sin(), h) + center
        })
        .collect();
    let fit = fit_circle(&FitPoints::new(&points), &options()).unwrap();
    assert!(
        (fit.radius - radius).abs() < 4.0 * sigma / (n as f64).sqrt(),
        "{fit:?}"
    );
    assert!((fit.plane_rms / sigma - 1.0).abs() < 0.1, "{fit:?}");
    assert!((fit.rms_residual / sigma - 1.0).abs() < 0.1, "{fit:?}");
    // The 3-D distance combines both.
    let p = points[0];
    assert!(
        (fit.distance(p) - fit.residual(p).hypot((p - fit.center).dot(fit.axis))).abs() < 1e-15
    );
}

// ---------------------------------------------------------------------------------------
// Cylinders.

#[test]
fn exact_cylinders_and_partial_cylinders_are_recovered() {
    let mut rng = SplitMix64::new(7);
    // (arc, half length / radius): long full, short full, long quarter, short quarter.
    for (arc_deg, aspect) in [(360.0, 3.0), (360.0, 0.3), (90.0, 3.0), (90.0, 0.5)] {
        for _ in 0..4 {
            let radius = rng.next_range(1.0, 30.0);
            let rotation = rng.rotation();
            let offset = DVec3::new(
                rng.next_range(-800.0, 800.0),
                -600.0,
                rng.next_range(-800.0, 800.0),
            );
            let local = cylinder_points(
                &mut rng,
                400,
                radius,
                f64::to_radians(arc_deg),
                aspect * radius,
            );
            let points: Vec<DVec3> = local.iter().map(|&p| rotation * p + offset).collect();
            let fit = fit_cylinder(&FitPoints::new(&points), None, &options()).unwrap();
            let axis = rotation * DVec3::Z;
            let tol = 1e-8 * radius;
            assert!(
                (fit.radius - radius).abs() < tol,
                "{arc_deg} {aspect}: {fit:?} vs {radius}"
            );
            assert!(
                (fit.axis.dot(axis).abs() - 1.0).abs() < 1e-12,
                "{arc_deg} {aspect}: {fit:?}"
            );
            // The axis point is on the true axis…
            let off_axis = (fit.axis_point - offset).cross(axis).length();
            assert!(off_axis < tol, "{arc_deg} {aspect}: {off_axis}");
            // …at the height of the centroid.
            let centroid = points.iter().sum::<DVec3>() / points.len() as f64;
            assert!((fit.axis_point - centroid).dot(axis).abs() < tol);
            assert!(fit.converged && fit.rms_residual < 1e-9 * radius);
        }
    }
}

#[test]
fn a_supplied_axis_guess_is_used() {
    let mut rng = SplitMix64::new(8);
    let local = cylinder_points(&mut rng, 300, 5.0, 2.0, 4.0);
    let tilt = DQuat::from_axis_angle(DVec3::X, 0.3);
    let points: Vec<DVec3> = local.iter().map(|&p| tilt * p).collect();
    let guess = tilt * DVec3::new(0.05, 0.02, 1.0);
    let fit = fit_cylinder(&FitPoints::new(&points), Some(guess), &options()).unwrap();
    assert!((fit.radius - 5.0).abs() < 1e-9);
    assert!((fit.axis.dot(tilt * DVec3::Z).abs() - 1.0).abs() < 1e-12);
    assert_eq!(
        fit_cylinder(&FitPoints::new(&points), Some(DVec3::ZERO), &options()).unwrap_err(),
        MetricsError::InvalidParameter {
            name: "axis_guess",
            reason: "must be a finite non-zero vector"
        }
    );
}

#[test]
fn noisy_cylinder_radius_is_within_a_few_sigma_over_root_n() {
    let mut rng = SplitMix64::new(9);
    let (radius, sigma, n) = (8.0, 0.02, 4000);
    let rotation = rng.rotation();
    let points: Vec<DVec3> = cylinder_points(&mut rng, n, radius, std::f64::consts::TAU, 20.0)
        .into_iter()
        .map(|p| {
            let radial = DVec3::new(p.x, p.y, 0.0).normalize();
            rotation * (p + radial * (sigma * rng.next_normal())) + DVec3::new(100.0, 200.0, 300.0)
        })
        .collect();
    let fit = fit_cylinder(&FitPoints::new(&points), None, &options()).unwrap();
    assert!(
        (fit.radius - radius).abs() < 4.0 * sigma / (n as f64).sqrt(),
        "{fit:?}"
    );
    assert!((fit.rms_residual / sigma - 1.0).abs() < 0.05, "{fit:?}");
}

#[test]
fn a_cylinder_mesh_fits_with_area_weights() {
    // A tube: the grid wrapped around the z-axis (open at both ends), radius 2, length 6,
    // with rows twice as dense in its lower half.
    let (nu, nv) = (48u32, 12u32);
    let mut positions = Vec::new();
    for j in 0..=nv {
        let t = f64::from(j) / f64::from(nv);
        let z = if t < 0.5 {
            3.0 * t
        } else {
            1.5 + 9.0 * (t - 0.5)
        };
        for i in 0..nu {
            let phi = std::f64::consts::TAU * f64::from(i) / f64::from(nu);
            positions.push(DVec3::new(2.0 * phi.cos(), 2.0 * phi.sin(), z));
        }
    }
    let id = |i: u32, j: u32| j * nu + i % nu;
    let mut faces = Vec::new();
    for j in 0..nv {
        for i in 0..nu {
            faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            faces.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let mesh = beltrami_halfedge::HalfedgeMesh::from_polygons(positions.len(), &faces).unwrap();
    let input = FitPoints::area_weighted(&mesh, &positions).unwrap();
    let fit = fit_cylinder(&input, None, &options()).unwrap();
    assert!((fit.radius - 2.0).abs() < 1e-12 && (fit.axis - DVec3::Z).length() < 1e-12);
    // The axis point is at the area-weighted centroid's height, the middle of the tube
    // (z = 3), where the plain vertex centroid sits lower, in the dense half.
    assert!(
        (fit.axis_point - DVec3::new(0.0, 0.0, 3.0)).length() < 1e-9,
        "{fit:?}"
    );
    let plain = fit_cylinder(&FitPoints::new(&positions), None, &options()).unwrap();
    assert!(plain.axis_point.z < 2.9);
}

// ---------------------------------------------------------------------------------------
// Errors.

#[test]
fn bad_input_gives_typed_errors() {
    let o = options();
    let few = [DVec3::ZERO, DVec3::X, DVec3::Y];
    assert_eq!(
        fit_sphere(&FitPoints::new(&few), &o).unwrap_err(),
        MetricsError::TooFewPoints {
            shape: "sphere",
            needed: 4,
            got: 3
        }
    );
    assert!(matches!(
        fit_cylinder(&FitPoints::new(&few), None, &o).unwrap_err(),
        MetricsError::TooFewPoints {
            shape: "cylinder",
            needed: 5,
            got: 3
        }
    ));
    // Coplanar points: no sphere.
    let planar: Vec<DVec3> = (0..20)
        .map(|i| DVec3::new((i as f64).cos(), (i as f64).sin(), 2.0))
        .collect();
    assert_eq!(
        fit_sphere(&FitPoints::new(&planar), &o).unwrap_err(),
        MetricsError::Degenerate {
            shape: "sphere",
            reason: "the points are coplanar"
        }
    );
    // …but a circle.
    let circle = fit_circle(&FitPoints::new(&planar), &o).unwrap();
    assert!(
        (circle.radius - 1.0).abs() < 1e-12 && (circle.center - DVec3::Z * 2.0).length() < 1e-12
    );
    // A flat patch: the plane fits better than any cylinder (one standing on the patch
    // was a local minimum, reported as the fit). With noise across it a cylinder of a
    // large radius can fit better than the plane, and is then the fit.
    {
        let flat: Vec<DVec3> = (0..25)
            .map(|i| DVec3::new(f64::from(i % 5), f64::from(i / 5), 0.0))
            .collect();
        let err = fit_cylinder(&FitPoints::new(&flat), None, &o).unwrap_err();
        assert!(
            matches!(
                err,
                MetricsError::Degenerate {
                    shape: "cylinder",
                    reason
                } if reason.contains("better than their least-squares plane")
            ),
            "{err}"
        );
    }
    // A slightly curved one (radius 100 across 4 units) is a cylinder.
    let curved: Vec<DVec3> = (0..25)
        .map(|i| {
            let (x, y) = (f64::from(i % 5), f64::from(i / 5));
            DVec3::new(
                x,
                y,
                100.0 - (100.0f64 * 100.0 - (x - 2.0) * (x - 2.0)).sqrt(),
            )
        })
        .collect();
    let fit = fit_cylinder(&FitPoints::new(&curved), None, &o).unwrap();
    assert!((fit.radius - 100.0).abs() < 1e-6, "{}", fit.radius);
    // Collinear points: no circle, no cylinder.
    let line: Vec<DVec3> = (0..10)
        .map(|i| DVec3::new(1.0, 2.0, 3.0) * f64::from(i))
        .collect();
    assert!(matches!(
        fit_circle(&FitPoints::new(&line), &o).unwrap_err(),
        MetricsError::Degenerate {
            shape: "circle",
            ..
        }
    ));
    assert!(matches!(
        fit_cylinder(&FitPoints::new(&line), None, &o).unwrap_err(),
        MetricsError::Degenerate {
            shape: "cylinder",
            ..
        }
    ));
    let same = [DVec3::ONE; 6];
    assert!(matches!(
        fit_sphere(&FitPoints::new(&same), &o).unwrap_err(),
        MetricsError::Degenerate { .. }
    ));
    let mut nan = planar.clone();
    nan[4].z = f64::NAN;
    assert_eq!(
        fit_circle(&FitPoints::new(&nan), &o).unwrap_err(),
        MetricsError::NonFinite {
            what: "point",
            index: 4
        }
    );
    assert!(matches!(
        FitPoints::weighted(&planar, &[1.0; 3]).unwrap_err(),
        MetricsError::FieldLength {
            what: "weights",
            got: 3,
            expected: 20
        }
    ));
    let mut w = vec![1.0; 20];
    w[1] = -1.0;
    assert!(matches!(
        FitPoints::weighted(&planar, &w).unwrap_err(),
        MetricsError::InvalidParameter { .. }
    ));
    let bad = o.tolerance(0.0);
    assert!(matches!(
        fit_circle(&FitPoints::new(&planar), &bad).unwrap_err(),
        MetricsError::InvalidParameter {
            name: "tolerance",
            ..
        }
    ));
    // Zero weights do not count towards the minimum.
    let points = [DVec3::X, DVec3::Y, DVec3::Z, -DVec3::X, -DVec3::Y];
    let weights = [1.0, 1.0, 1.0, 0.0, 0.0];
    assert!(matches!(
        fit_sphere(&FitPoints::weighted(&points, &weights).unwrap(), &o).unwrap_err(),
        MetricsError::TooFewPoints { got: 3, .. }
    ));
}

#[test]
fn an_iteration_limit_reports_an_unconverged_fit() {
    let mut rng = SplitMix64::new(10);
    let local = cap_points(&mut rng, 300, 5.0, 0.5);
    let points: Vec<DVec3> = local.iter().map(|&p| p + rng.gaussian3() * 0.05).collect();
    let one = FitOptions::default().max_iterations(1).tolerance(1e-15);
    let fit = fit_sphere(&FitPoints::new(&points), &one).unwrap();
    assert_eq!(fit.iterations, 1);
    assert!(!fit.converged);
    assert!(fit.radius.is_finite() && fit.rms_residual.is_finite());
}
