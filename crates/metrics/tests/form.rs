//! F-operators by least-squares forms: a texture laid on a tilted plane, a quadratic
//! form, a sphere cap and a cylinder comes back as the residual, with the texture's Sq;
//! signs follow the faces; the plane and polynomial fits on their own.

use std::f64::consts::{SQRT_2, TAU};

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::{DVec3, HalfedgeMesh, PolygonList, primitives};
use beltrami_metrics::MetricsError;
use beltrami_metrics::fits::{FitPoints, fit_plane, fit_polynomial};
use beltrami_metrics::residual::{
    ArealOptions, FittedForm, Form, FormResidual, areal_parameters, form_residual,
};

const AMPLITUDE: f64 = 0.05;
const WAVELENGTH: f64 = 4.0;

/// The texture `A cos(2π s / λ)`: even about the middle of the patch, so that it is
/// orthogonal to the plane's parameters over whole periods.
fn texture(s: f64) -> f64 {
    AMPLITUDE * (TAU * s / WAVELENGTH).cos()
}

/// A grid of `cells × cells` squares of side `h` centred on the origin, `(x, y)` per
/// vertex, and its faces.
fn patch(cells: u32, h: f64) -> (Vec<(f64, f64)>, PolygonList) {
    let grid = primitives::grid(cells, cells);
    let half = f64::from(cells) * h / 2.0;
    let uv = grid
        .positions
        .iter()
        .map(|p| (p.x * h - half, p.y * h - half))
        .collect();
    (uv, grid.faces)
}

fn residual_of(
    positions: &[DVec3],
    faces: &PolygonList,
    form: Form,
) -> (HalfedgeMesh, FormResidual) {
    let mesh = HalfedgeMesh::from_polygons(positions.len(), faces.iter()).expect("builds");
    let fit = form_residual(&Geometry::new(&mesh, positions).expect("positions"), form)
        .expect("form fits");
    (mesh, fit)
}

/// Sq of the residual over the form (the foot points), lumped rule, reference datum.
fn sq(mesh: &HalfedgeMesh, fit: &FormResidual) -> f64 {
    areal_parameters(
        &Geometry::new(mesh, &fit.foot_points).expect("positions"),
        fit.residual.as_slice(),
        &ArealOptions::default(),
    )
    .expect("areal")
    .sq
}

/// The faces turned over (clockwise seen from where they pointed).
fn reversed(faces: &PolygonList) -> PolygonList {
    let turned: Vec<[u32; 3]> = faces.iter().map(|f| [f[0], f[2], f[1]]).collect();
    PolygonList::from_triangles(&turned)
}

/// A plane tilted off z, with the projection of x onto it as first axis (the axes a fit
/// reports).
fn tilted_frame() -> (DVec3, DVec3, DVec3, DVec3) {
    let normal = DVec3::new(0.3, -0.2, 1.0).normalize();
    let e1 = (DVec3::X - normal * normal.x).normalize();
    let e2 = normal.cross(e1);
    (DVec3::new(3.0, -7.0, 11.0), e1, e2, normal)
}

#[test]
fn a_texture_on_a_tilted_plane() {
    // 40 × 40 units, 10 periods, 8 samples per period.
    let (uv, faces) = patch(80, 0.5);
    let (origin, e1, e2, normal) = tilted_frame();
    let positions: Vec<DVec3> = uv
        .iter()
        .map(|&(x, y)| origin + e1 * x + e2 * y + normal * texture(x))
        .collect();
    let (mesh, fit) = residual_of(&positions, &faces, Form::Plane);
    // By symmetry the plane is the frame's: the residual is the texture itself.
    for (k, &(x, _)) in uv.iter().enumerate() {
        assert!(
            (fit.residual.as_slice()[k] - texture(x)).abs() < 1e-12,
            "{k}"
        );
        assert!((fit.foot_points[k] - (positions[k] - normal * texture(x))).length() < 1e-12);
    }
    let FittedForm::Plane(plane) = fit.form else {
        panic!("{:?}", fit.form)
    };
    assert!(plane.normal.dot(normal) > 1.0 - 1e-14);
    assert!(!fit.flipped);
    let want = AMPLITUDE / SQRT_2;
    assert!(
        (sq(&mesh, &fit) - want).abs() < 0.005 * want,
        "{}",
        sq(&mesh, &fit)
    );

    // The same plane turned over (faces clockwise from the normal's side): the fit's
    // normal still points the same way, but the residual follows the faces.
    let (_, down) = residual_of(&positions, &reversed(&faces), Form::Plane);
    assert!(down.flipped);
    for (a, b) in down.residual.as_slice().iter().zip(fit.residual.as_slice()) {
        assert_eq!(*a, -*b);
    }

    // A polynomial of degree 1 is the plane.
    let (_, linear) = residual_of(&positions, &faces, Form::Polynomial { degree: 1 });
    for (a, b) in linear
        .residual
        .as_slice()
        .iter()
        .zip(fit.residual.as_slice())
    {
        assert!((a - b).abs() < 1e-12);
    }
}

#[test]
fn a_texture_on_a_quadratic_form() {
    // w = 5·10⁻⁴ (u² − 2 v²) in the tilted frame: even in u and v, so its best-fit plane
    // is the frame's; slopes up to 0.04.
    let (uv, faces) = patch(80, 0.5);
    let (origin, e1, e2, normal) = tilted_frame();
    let form = |x: f64, y: f64| 5e-4 * (x * x - 2.0 * y * y);
    let positions: Vec<DVec3> = uv
        .iter()
        .map(|&(x, y)| origin + e1 * x + e2 * y + normal * (form(x, y) + texture(x)))
        .collect();
    let (mesh, fit) = residual_of(&positions, &faces, Form::Polynomial { degree: 2 });
    let FittedForm::Polynomial(poly) = &fit.form else {
        panic!("{:?}", fit.form)
    };
    // The fit finds the form: its height at a few places (frame coordinates), up to the
    // little of the texture a quadratic can absorb.
    for (x, y) in [(0.0, 0.0), (15.0, -5.0), (-19.0, 19.0)] {
        let p = origin + e1 * x + e2 * y;
        let [u, v, w0] = poly.to_frame(p);
        let (w, _) = poly.height(u, v);
        assert!(
            (w - w0 - form(x, y)).abs() < 0.02 * AMPLITUDE,
            "({x}, {y}): {w}"
        );
    }
    // The residual is the orthogonal distance: the texture shortened by the form's
    // slope, by less than 0.1 %.
    let want = AMPLITUDE / SQRT_2;
    let got = sq(&mesh, &fit);
    assert!((got - want).abs() < 0.005 * want, "{got}");
    // A plane leaves the form in the residual.
    let (mesh, flat) = residual_of(&positions, &faces, Form::Plane);
    assert!(sq(&mesh, &flat) > 3.0 * want);
    // A polynomial of degree 6 removes the form and a little of the texture too (the
    // parts of a cosine of 10 periods that Legendre polynomials up to degree 6 reach,
    // about 1 % of its variance): a higher degree never leaves more.
    let (mesh6, sixth) = residual_of(&positions, &faces, Form::Polynomial { degree: 6 });
    let sq6 = sq(&mesh6, &sixth);
    assert!(
        sq6 <= got && (sq6 - want).abs() < 0.015 * want,
        "{sq6} vs {want}"
    );
}

#[test]
fn a_texture_on_a_sphere_cap() {
    // A cap of radius 50 over 40 × 40 units (33° across), the texture along the radius.
    let radius = 50.0;
    let centre = DVec3::new(1.0, 2.0, -40.0);
    let (uv, faces) = patch(160, 0.25);
    let positions: Vec<DVec3> = uv
        .iter()
        .map(|&(x, y)| {
            let d = DVec3::new(x, y, (radius * radius - x * x - y * y).sqrt()).normalize();
            centre + d * (radius + texture(x))
        })
        .collect();
    let (mesh, fit) = residual_of(&positions, &faces, Form::Sphere);
    let FittedForm::Sphere(sphere) = &fit.form else {
        panic!("{:?}", fit.form)
    };
    // On a cap of 33°, the radius and the centre's height trade against each other
    // almost freely, and the texture moves both a little (by 0.15 A here); the fitted
    // sphere stays within A/50 of the nominal one over the cap.
    assert!(
        (sphere.radius - radius).abs() < 0.5 * AMPLITUDE,
        "{}",
        sphere.radius
    );
    for &p in &fit.foot_points {
        assert!(((p - centre).length() - radius).abs() < 0.02 * AMPLITUDE);
    }
    assert!(!fit.flipped, "the faces point out of the sphere");
    for foot in &fit.foot_points {
        assert!(((*foot - sphere.center).length() - sphere.radius).abs() < 1e-9);
    }
    let want = AMPLITUDE / SQRT_2;
    let got = sq(&mesh, &fit);
    assert!((got - want).abs() < 0.005 * want, "{got}");

    // Seen from inside (faces turned towards the centre, a spherical cup): a bump
    // towards the centre is a peak.
    let (_, inside) = residual_of(&positions, &reversed(&faces), Form::Sphere);
    assert!(inside.flipped);
    for (a, b) in inside
        .residual
        .as_slice()
        .iter()
        .zip(fit.residual.as_slice())
    {
        assert_eq!(*a, -*b);
    }
}

#[test]
fn a_texture_on_a_cylinder() {
    // Radius 30 about the y axis, 40 units of arc by 40 along the axis; the texture runs
    // around the axis.
    let radius = 30.0;
    let (uv, faces) = patch(160, 0.25);
    let positions: Vec<DVec3> = uv
        .iter()
        .map(|&(s, y)| {
            let angle = s / radius;
            let r = radius + texture(s);
            DVec3::new(r * angle.sin(), y, r * angle.cos())
        })
        .collect();
    let (mesh, fit) = residual_of(&positions, &faces, Form::Cylinder);
    let FittedForm::Cylinder(cylinder) = &fit.form else {
        panic!("{:?}", fit.form)
    };
    // As for the sphere cap, radius and axis position trade against each other on a
    // partial arc; the fitted cylinder stays within A/50 of the nominal one.
    assert!(
        (cylinder.radius - radius).abs() < 0.5 * AMPLITUDE,
        "{}",
        cylinder.radius
    );
    assert!(cylinder.axis.dot(DVec3::Y).abs() > 1.0 - 1e-9);
    for &p in &fit.foot_points {
        assert!((p.x.hypot(p.z) - radius).abs() < 0.02 * AMPLITUDE);
    }
    let want = AMPLITUDE / SQRT_2;
    let got = sq(&mesh, &fit);
    assert!((got - want).abs() < 0.005 * want, "{got}");
}

#[test]
fn fits_on_their_own_and_errors() {
    // A plane through three points.
    let triangle = [DVec3::ZERO, DVec3::X, DVec3::new(0.0, 1.0, 1.0)];
    let plane = fit_plane(&FitPoints::new(&triangle)).unwrap();
    // (0, −1, 1)/√2 with its largest component made positive: a tie, the first wins.
    assert!(
        (plane.normal - DVec3::new(0.0, 1.0, -1.0) / SQRT_2).length() < 1e-12,
        "{}",
        plane.normal
    );
    assert!(plane.max_residual < 1e-15);
    assert!(matches!(
        fit_plane(&FitPoints::new(&[DVec3::ZERO, DVec3::X, DVec3::X * 2.0])),
        Err(MetricsError::Degenerate { shape: "plane", .. })
    ));
    assert!(matches!(
        fit_plane(&FitPoints::new(&[DVec3::ZERO, DVec3::X])),
        Err(MetricsError::TooFewPoints {
            shape: "plane",
            needed: 3,
            got: 2
        })
    ));
    let grid = primitives::grid(3, 3);
    for degree in [0, 7] {
        assert!(matches!(
            fit_polynomial(&FitPoints::new(&grid.positions), degree),
            Err(MetricsError::InvalidParameter { .. })
        ));
    }
    // Degree 6 has 28 coefficients; a 4 × 4 grid has 16 points.
    assert!(matches!(
        fit_polynomial(&FitPoints::new(&grid.positions), 6),
        Err(MetricsError::TooFewPoints {
            shape: "polynomial",
            needed: 28,
            got: 16
        })
    ));
    // A 4 × 4 grid determines a cubic (10 coefficients); points on two lines do not
    // determine a quadratic.
    let lines: Vec<DVec3> = (0..10)
        .flat_map(|i| {
            [
                DVec3::new(f64::from(i), 0.0, 0.0),
                DVec3::new(f64::from(i), 1.0, 0.1),
            ]
        })
        .collect();
    assert!(fit_polynomial(&FitPoints::new(&grid.positions), 3).is_ok());
    assert!(matches!(
        fit_polynomial(&FitPoints::new(&lines), 2),
        Err(MetricsError::Degenerate {
            shape: "polynomial",
            ..
        })
    ));
    // A sphere through a flat patch is undetermined.
    let mesh = grid.mesh().unwrap();
    assert!(matches!(
        form_residual(
            &Geometry::new(&mesh, &grid.positions).unwrap(),
            Form::Sphere
        ),
        Err(MetricsError::Degenerate {
            shape: "sphere",
            ..
        })
    ));
    let empty = HalfedgeMesh::from_polygons(3, Vec::<[u32; 3]>::new()).unwrap();
    assert_eq!(
        form_residual(&Geometry::new(&empty, &triangle).unwrap(), Form::Plane),
        Err(MetricsError::Empty { what: "mesh" })
    );
}
