//! The spatial parameters Sal, Str and Std on analytic textures (ridges, rotated ridges,
//! an isotropic sum of waves), on grids with invalid points and unequal spacings, and on
//! meshes through the resampling onto their best-fit plane.

use std::f64::consts::{PI, TAU};

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::primitives;
use beltrami_halfedge::{DVec3, HalfedgeMesh};
use beltrami_metrics::MetricsError;
use beltrami_metrics::residual::{
    HeightGrid, ResampleOptions, SpatialOptions, SpatialParameters, resample_to_grid,
    spatial_parameters,
};
use glam::DQuat;

/// `z(x, y)` sampled on an `nx × ny` grid of spacings `dx`, `dy`, with the points where
/// `valid` fails left out.
fn sampled(
    (nx, ny): (usize, usize),
    (dx, dy): (f64, f64),
    z: impl Fn(f64, f64) -> f64,
    valid: impl Fn(f64, f64) -> bool,
) -> HeightGrid {
    let mut heights = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let (x, y) = (i as f64 * dx, j as f64 * dy);
            heights.push(valid(x, y).then(|| z(x, y)));
        }
    }
    HeightGrid::new(nx, ny, dx, dy, heights).expect("valid grid")
}

fn spatial(grid: &HeightGrid) -> SpatialParameters {
    spatial_parameters(grid, &SpatialOptions::default()).expect("spatial parameters")
}

/// Sal of a sine of wavelength `λ` at the threshold 0.2: its autocorrelation is
/// `cos(2π t_x / λ)`, which falls to 0.2 at `arccos(0.2) λ / 2π` along x (and later in
/// every other direction).
fn sine_sal(wavelength: f64) -> f64 {
    0.2f64.acos() * wavelength / TAU
}

fn ridges(angle_degrees: f64, wavelength: f64) -> impl Fn(f64, f64) -> f64 {
    let (s, c) = angle_degrees.to_radians().sin_cos();
    move |x, y| (TAU * (x * c + y * s) / wavelength).sin()
}

#[test]
fn ridges_along_y() {
    // 16 periods across a 257 × 257 grid of unit spacing.
    let grid = sampled((257, 257), (1.0, 1.0), ridges(0.0, 16.0), |_, _| true);
    let s = spatial(&grid);
    let sal = s.sal.expect("decays along x");
    assert!(
        (sal - sine_sal(16.0)).abs() < 0.01 * sine_sal(16.0),
        "{sal}"
    );
    // Along y it never decays: the texture aspect ratio is Sal over the longest
    // supported lag, 3/4 of the side along y (where a quarter of the points still have
    // a partner), less the reach of the bicubic interpolation.
    assert!(!s.decays_in_every_direction);
    let str = s.str.expect("Str");
    assert!(
        (sal / (0.75 * 256.0)..sal / (0.74 * 256.0)).contains(&str),
        "{str}"
    );
    // The crests run along y: the lay is at 90° from x.
    assert!((s.std.expect("Std") - 90.0).abs() < 0.05, "{:?}", s.std);

    // Doubling the extent halves the finite-area bias of the autocorrelation.
    let small = sampled((129, 129), (1.0, 1.0), ridges(0.0, 16.0), |_, _| true);
    let e_small = (spatial(&small).sal.unwrap() - sine_sal(16.0)).abs();
    assert!((sal - sine_sal(16.0)).abs() < e_small);
}

#[test]
fn rotated_ridges_turn_std_with_them() {
    for angle in [30.0, 75.0, 135.0] {
        let grid = sampled((257, 257), (1.0, 1.0), ridges(angle, 16.0), |_, _| true);
        let s = spatial(&grid);
        // The wave runs at `angle`; its crests at angle + 90°.
        let lay = (angle + 90.0) % 180.0;
        let std = s.std.unwrap();
        let off = (std - lay + 90.0).rem_euclid(180.0) - 90.0;
        assert!(off.abs() < 0.5, "wave at {angle}°: Std {std}, lay {lay}");
        let sal = s.sal.unwrap();
        assert!(
            (sal - sine_sal(16.0)).abs() < 0.015 * sine_sal(16.0),
            "{angle}: {sal}"
        );
        assert!(s.str.unwrap() < 0.05);
    }
}

#[test]
fn unequal_spacings_are_lengths() {
    // Half the spacing along y, twice the points: the same physical square. A wave at
    // 45° in physical coordinates is at 63.4° in index space; Std must say 135°.
    let grid = sampled((257, 513), (1.0, 0.5), ridges(45.0, 16.0), |_, _| true);
    let s = spatial(&grid);
    assert!((s.std.unwrap() - 135.0).abs() < 0.5, "{:?}", s.std);
    assert!((s.sal.unwrap() - sine_sal(16.0)).abs() < 0.015 * sine_sal(16.0));
}

/// `Σ_j cos(k (x cos θ_j + y sin θ_j) + φ_j)` over 24 directions `θ_j = jπ/24`, with
/// scattered phases: its autocorrelation is `(1/24) Σ_j cos(k t · e_j)`, nearly a Bessel
/// function `J₀(k |t|)`, the same in every direction.
fn isotropic(wavelength: f64) -> impl Fn(f64, f64) -> f64 {
    let k = TAU / wavelength;
    move |x, y| {
        (0..24)
            .map(|j| {
                let theta = PI * f64::from(j) / 24.0;
                let phase = TAU * (0.618_034 * f64::from(j)).fract();
                (k * (x * theta.cos() + y * theta.sin()) + phase).cos()
            })
            .sum()
    }
}

/// The first lag at which `(1/24) Σ_j cos(k t cos(α − θ_j))` falls to `s`, the analytic
/// autocorrelation of [`isotropic`] along the direction `α`.
fn isotropic_decay(wavelength: f64, alpha: f64, s: f64) -> f64 {
    let k = TAU / wavelength;
    let acf = |t: f64| {
        (0..24)
            .map(|j| (k * t * (alpha - PI * f64::from(j) / 24.0).cos()).cos())
            .sum::<f64>()
            / 24.0
    };
    let (mut lo, mut hi) = (0.0, wavelength / 2.0);
    assert!(acf(hi) < s);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if acf(mid) > s { lo = mid } else { hi = mid }
    }
    lo
}

#[test]
fn an_isotropic_texture_has_str_near_one() {
    let grid = sampled((257, 257), (1.0, 1.0), isotropic(12.0), |_, _| true);
    let s = spatial(&grid);
    let want = (0..=24)
        .map(|i| isotropic_decay(12.0, PI / 24.0 * f64::from(i) / 24.0, 0.2))
        .fold(f64::INFINITY, f64::min);
    let sal = s.sal.unwrap();
    assert!((sal - want).abs() < 0.03 * want, "{sal} vs {want}");
    assert!(s.decays_in_every_direction);
    assert!(s.str.unwrap() > 0.9, "{:?}", s.str);
}

#[test]
fn invalid_points_are_left_out() {
    // Ridges on a disk of radius 120 inside the square: the same parameters.
    let disk = |x: f64, y: f64| (x - 128.0).powi(2) + (y - 128.0).powi(2) <= 120.0 * 120.0;
    let grid = sampled((257, 257), (1.0, 1.0), ridges(0.0, 16.0), disk);
    assert!(grid.valid_count() < 257 * 257 * 4 / 5);
    let s = spatial(&grid);
    assert!((s.sal.unwrap() - sine_sal(16.0)).abs() < 0.02 * sine_sal(16.0));
    assert!((s.std.unwrap() - 90.0).abs() < 0.2, "{:?}", s.std);
}

#[test]
fn constant_heights_and_errors() {
    let flat = sampled((8, 8), (1.0, 1.0), |_, _| 3.5, |_, _| true);
    let s = spatial(&flat);
    assert_eq!((s.sal, s.str, s.std), (None, None, None));

    let grid = sampled((8, 8), (1.0, 1.0), ridges(0.0, 4.0), |_, _| true);
    for threshold in [0.0, 1.0, -0.2, f64::NAN] {
        assert!(matches!(
            spatial_parameters(&grid, &SpatialOptions::default().threshold(threshold)),
            Err(MetricsError::InvalidParameter { .. })
        ));
    }
    let line = sampled((8, 1), (1.0, 1.0), ridges(0.0, 4.0), |_, _| true);
    assert_eq!(
        spatial_parameters(&line, &SpatialOptions::default()),
        Err(MetricsError::Empty {
            what: "height grid"
        })
    );
    assert!(matches!(
        HeightGrid::new(2, 2, 0.0, 1.0, vec![Some(0.0); 4]),
        Err(MetricsError::InvalidParameter { .. })
    ));
    assert_eq!(
        HeightGrid::new(2, 2, 1.0, 1.0, vec![Some(0.0); 3]),
        Err(MetricsError::FieldLength {
            what: "heights",
            got: 3,
            expected: 4
        })
    );
    assert_eq!(
        HeightGrid::new(2, 1, 1.0, 1.0, vec![Some(0.0), Some(f64::NAN)]),
        Err(MetricsError::NonFinite {
            what: "height",
            index: 1
        })
    );
}

/// A `cells × cells` grid mesh of unit spacing, positions moved by `place`, with the
/// field `z` evaluated at the unmoved grid points.
fn grid_mesh(
    cells: u32,
    place: impl Fn(DVec3) -> DVec3,
    z: impl Fn(f64, f64) -> f64,
) -> (HalfedgeMesh, Vec<DVec3>, Vec<f64>) {
    let grid = primitives::grid(cells, cells);
    let mesh = grid.mesh().expect("grid builds");
    let field = grid.positions.iter().map(|p| z(p.x, p.y)).collect();
    let positions = grid.positions.iter().map(|&p| place(p)).collect();
    (mesh, positions, field)
}

fn resampled_spatial(mesh: &HalfedgeMesh, positions: &[DVec3], field: &[f64]) -> SpatialParameters {
    let geometry = Geometry::new(mesh, positions).expect("positions");
    let grid = resample_to_grid(&geometry, field, &ResampleOptions::default()).expect("resampled");
    spatial(&grid.grid)
}

#[test]
fn a_mesh_is_resampled_at_its_own_points_and_in_its_own_plane() {
    let z = ridges(0.0, 16.0);
    let (mesh, flat, field) = grid_mesh(256, |p| p, &z);
    let geometry = Geometry::new(&mesh, &flat).unwrap();
    let g = resample_to_grid(&geometry, &field, &ResampleOptions::default()).unwrap();
    assert_eq!((g.grid.nx(), g.grid.ny(), g.step), (257, 257, 1.0));
    assert_eq!(g.grid.valid_count(), 257 * 257);
    assert_eq!(g.folded_fraction, 0.0);
    for (k, h) in g.grid.heights().iter().enumerate() {
        assert!((h.unwrap() - field[k]).abs() < 1e-12, "grid point {k}");
    }
    let direct = sampled((257, 257), (1.0, 1.0), &z, |_, _| true);
    let on_mesh = spatial(&g.grid);
    let s = spatial(&direct);
    assert!((on_mesh.sal.unwrap() - s.sal.unwrap()).abs() < 1e-9);
    assert!((on_mesh.std.unwrap() - s.std.unwrap()).abs() < 1e-9);

    // Tilted by 40° about x and moved: the same grid in the tilted plane.
    let tilt = DQuat::from_rotation_x(40f64.to_radians());
    let (mesh, tilted, field) = grid_mesh(256, |p| tilt * p + DVec3::new(5.0, -3.0, 7.0), &z);
    let t = resampled_spatial(&mesh, &tilted, &field);
    assert!((t.sal.unwrap() - s.sal.unwrap()).abs() < 1e-6);
    assert!((t.std.unwrap() - 90.0).abs() < 0.05);

    // Turned by 20° about the normal: the lay turns with it, measured from x.
    let turn = DQuat::from_rotation_z(20f64.to_radians());
    let (mesh, turned, field) = grid_mesh(256, |p| turn * p, &z);
    let r = resampled_spatial(&mesh, &turned, &field);
    assert!((r.std.unwrap() - 110.0).abs() < 0.5, "{:?}", r.std);
    assert!((r.sal.unwrap() - sine_sal(16.0)).abs() < 0.02 * sine_sal(16.0));
}

#[test]
fn an_irregular_mesh_samples_the_same_texture() {
    // Every vertex jittered within its cell by up to 0.3: the resampled heights are
    // the linear interpolation of the texture over irregular triangles.
    let jitter = |p: DVec3| {
        let a = (p.x * 12.9898 + p.y * 78.233).sin() * 43_758.545;
        let b = (p.x * 39.3468 + p.y * 11.135).sin() * 24_634.634;
        p + DVec3::new(
            0.3 * (2.0 * a.fract().abs() - 1.0),
            0.3 * (2.0 * b.fract().abs() - 1.0),
            0.0,
        )
    };
    let z = ridges(30.0, 16.0);
    let grid = primitives::grid(256, 256);
    let mesh = grid.mesh().unwrap();
    let positions: Vec<DVec3> = grid.positions.iter().map(|&p| jitter(p)).collect();
    let field: Vec<f64> = positions.iter().map(|p| z(p.x, p.y)).collect();
    let s = resampled_spatial(&mesh, &positions, &field);
    let off = (s.std.unwrap() - 120.0 + 90.0).rem_euclid(180.0) - 90.0;
    assert!(off.abs() < 0.5, "{:?}", s.std);
    assert!(
        (s.sal.unwrap() - sine_sal(16.0)).abs() < 0.03 * sine_sal(16.0),
        "{:?}",
        s.sal
    );
}

#[test]
fn points_outside_the_mesh_are_invalid() {
    // An L: the grid without its upper right quarter.
    let grid = primitives::grid(40, 40);
    let triangles: Vec<[u32; 3]> = grid
        .faces
        .iter()
        .filter(|f| {
            let centre = f.iter().map(|&v| grid.positions[v as usize]).sum::<DVec3>() / 3.0;
            !(centre.x > 20.0 && centre.y > 20.0)
        })
        .map(|f| [f[0], f[1], f[2]])
        .collect();
    let mesh = HalfedgeMesh::from_polygons(grid.positions.len(), &triangles).unwrap();
    let field: Vec<f64> = grid.positions.iter().map(|p| (p.x * 0.4).sin()).collect();
    let geometry = Geometry::new(&mesh, &grid.positions).unwrap();
    let g = resample_to_grid(&geometry, &field, &ResampleOptions::default()).unwrap();
    assert_eq!((g.grid.nx(), g.grid.ny()), (41, 41));
    // 41² points less the 20 × 20 strictly inside the missing quarter.
    assert_eq!(g.grid.valid_count(), 41 * 41 - 20 * 20);
    // The first column and row lie at x = 0 and y = 0: point (i, j) is (x, y) = (i, j).
    assert!(g.grid.height(30, 30).is_none() && g.grid.height(40, 21).is_none());
    let at = |x: usize, y: usize| g.grid.height(x, y);
    assert!((at(30, 10).unwrap() - 12f64.sin()).abs() < 1e-12 && at(20, 20).is_some());
}

#[test]
fn a_closed_surface_is_no_height_field() {
    let sphere = primitives::icosphere(3);
    let mesh = sphere.mesh().unwrap();
    let field = vec![0.0; sphere.positions.len()];
    let geometry = Geometry::new(&mesh, &sphere.positions).unwrap();
    match resample_to_grid(&geometry, &field, &ResampleOptions::default()) {
        Err(MetricsError::NotAHeightField { folded_percent }) => {
            assert!((folded_percent - 50.0).abs() < 5.0, "{folded_percent}");
        }
        other => panic!("{other:?}"),
    }
    let grid = primitives::grid(4, 4);
    let mesh = grid.mesh().unwrap();
    let geometry = Geometry::new(&mesh, &grid.positions).unwrap();
    for step in [0.0, -1.0, f64::INFINITY] {
        assert!(matches!(
            resample_to_grid(
                &geometry,
                &[0.0; 25],
                &ResampleOptions::default().step(Some(step))
            ),
            Err(MetricsError::InvalidParameter { .. })
        ));
    }
    // Too coarse a step for 4 × 4 points.
    assert_eq!(
        resample_to_grid(
            &geometry,
            &[0.0; 25],
            &ResampleOptions::default().step(Some(2.0))
        ),
        Err(MetricsError::Empty {
            what: "height grid"
        })
    );
}
