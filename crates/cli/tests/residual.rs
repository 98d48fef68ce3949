//! `beltrami residual` as a user runs it: a measured and a smoothed mesh in, areal
//! parameters out.

mod common;

use common::{beltrami, error_line, f, json, s, write};

use std::f64::consts::{PI, SQRT_2, TAU};
use std::path::{Path, PathBuf};

use beltrami_halfedge::{DVec3, PolygonList, primitives};
use insta::assert_snapshot;
use ply_rs_bw::ply::{DefaultElement, Property};
use serde_json::Value;

fn close(got: f64, want: f64, relative: f64) -> bool {
    (got - want).abs() <= relative * want.abs().max(1e-300)
}

const CELLS: u32 = 64;
const WAVELENGTH: f64 = 16.0;
const AMPLITUDE: f64 = 0.05;
const OFFSET: f64 = 0.01;

/// The height of the measured surface over column `x` of the grid.
fn height(x: f64) -> f64 {
    OFFSET + AMPLITUDE * (TAU * x / WAVELENGTH).sin()
}

/// A flat 64 × 4 grid (the smoothed form, OBJ) and the same grid lifted by
/// `0.01 + 0.05 sin(2π x / 16)` (the measured surface, PLY): four whole periods.
fn sinusoid(dir: &Path) -> (PathBuf, PathBuf, Vec<f64>) {
    let grid = primitives::grid(CELLS, 4);
    let measured: Vec<DVec3> = grid
        .positions
        .iter()
        .map(|p| *p + DVec3::Z * height(p.x))
        .collect();
    let columns = (0..=CELLS).map(|i| height(f64::from(i))).collect();
    (
        write(dir, "measured.ply", measured, grid.faces.clone()),
        write(dir, "flat.obj", grid.positions, grid.faces),
        columns,
    )
}

/// The areal parameters of the profile `v` (unit spacing) extruded along y, heights
/// measured from `datum`, by both quadratures: every cell holds the same linear function
/// of x on both of its triangles, so the surface integrals are 1-D ones.
struct Expected {
    sa: f64,
    sq: f64,
    ssk: f64,
    sku: f64,
    sdq: f64,
    sdr: f64,
}

/// The exact integrals of the piecewise-linear interpolant of `v`.
fn expected_exact(v: &[f64], datum: f64) -> Expected {
    let n = (v.len() - 1) as f64;
    let (mut m1, mut m2, mut m3, mut m4) = (0.0, 0.0, 0.0, 0.0);
    for w in v.windows(2) {
        let (a, b) = (w[0] - datum, w[1] - datum);
        // ∫₀¹ (a + (b − a) t)^k dt = Σ_{i=0..k} a^i b^(k−i) / (k + 1).
        let power =
            |k: i32| (0..=k).map(|i| a.powi(i) * b.powi(k - i)).sum::<f64>() / f64::from(k + 1);
        m1 += if a * b >= 0.0 {
            (a + b).abs() / 2.0
        } else {
            (a * a + b * b) / (2.0 * (a.abs() + b.abs()))
        };
        m2 += power(2);
        m3 += power(3);
        m4 += power(4);
    }
    moments(v, [m1 / n, m2 / n, m3 / n, m4 / n])
}

/// The lumped rule: each vertex weighted by a third of its triangles' areas, which on
/// the grid is the trapezoid rule along x (half weights on the first and last column).
fn expected_lumped(v: &[f64], datum: f64) -> Expected {
    let n = (v.len() - 1) as f64;
    let mut m = [0.0; 4];
    for (i, &value) in v.iter().enumerate() {
        let weight = if i == 0 || i == v.len() - 1 { 0.5 } else { 1.0 };
        let z = value - datum;
        m[0] += weight * z.abs();
        m[1] += weight * z * z;
        m[2] += weight * z.powi(3);
        m[3] += weight * z.powi(4);
    }
    moments(v, m.map(|x| x / n))
}

/// The parameters from the means of `|z|, z², z³, z⁴`, and the slopes of the cells.
fn moments(v: &[f64], [m1, m2, m3, m4]: [f64; 4]) -> Expected {
    let n = (v.len() - 1) as f64;
    let (mut g2, mut dr) = (0.0, 0.0);
    for w in v.windows(2) {
        let g = w[1] - w[0];
        g2 += g * g;
        dr += (1.0 + g * g).sqrt() - 1.0;
    }
    let sq = m2.sqrt();
    Expected {
        sa: m1,
        sq,
        ssk: m3 / sq.powi(3),
        sku: m4 / sq.powi(4),
        sdq: (g2 / n).sqrt(),
        sdr: dr / n,
    }
}

fn check(j: &Value, e: &Expected) {
    for (key, want) in [
        ("sa", e.sa),
        ("sq", e.sq),
        ("sku", e.sku),
        ("sdq", e.sdq),
        ("sdr", e.sdr),
    ] {
        assert!(
            close(f(&j[key]), want, 1e-12),
            "{key}: {} vs {want}",
            j[key]
        );
    }
    assert!(
        (f(&j["ssk"]) - e.ssk).abs() < 1e-12,
        "ssk: {} vs {}",
        j["ssk"],
        e.ssk
    );
}

#[test]
fn sinusoid_residual_by_both_quadratures() {
    let dir = tempfile::tempdir().unwrap();
    let (measured, flat, columns) = sinusoid(dir.path());

    // Heights from the smoothed surface: the offset stays in.
    let j = json(&["residual", s(&measured), s(&flat), "--json"]);
    assert_eq!(j["datum"], "reference");
    assert_eq!(j["quadrature"], "lumped");
    assert_eq!(j["vertices"], 325);
    assert_eq!(j["form"], Value::Null);
    check(&j, &expected_lumped(&columns, 0.0));
    let exact = json(&[
        "residual",
        s(&measured),
        s(&flat),
        "--json",
        "--quadrature",
        "exact",
    ]);
    assert_eq!(exact["quadrature"], "exact");
    check(&exact, &expected_exact(&columns, 0.0));
    for j in [&j, &exact] {
        assert!((f(&j["sp"]) - (AMPLITUDE + OFFSET)).abs() < 1e-15);
        assert!((f(&j["sv"]) - (AMPLITUDE - OFFSET)).abs() < 1e-15);
        assert!((f(&j["sz"]) - 2.0 * AMPLITUDE).abs() < 1e-15);
        assert!((f(&j["mean"]) - OFFSET).abs() < 1e-15);
        assert_eq!(j["area"], 256.0);
    }

    // Heights from the mean: the sine alone.
    let args = [
        "residual",
        s(&measured),
        s(&flat),
        "--json",
        "--remove-mean",
    ];
    let j = json(&args);
    assert_eq!(j["datum"], "mean");
    check(&j, &expected_lumped(&columns, f(&j["mean"])));
    // Against the continuous sine, Sq = A/√2, Ssk = 0, Sku = 3/2: the trapezoid rule over
    // whole periods of a smooth periodic function is exact for these. |sin| has kinks at
    // its zeros, where the rule is second order: Σ_k |sin(πk/8)| / 16 = cot(π/16) / 8,
    // 1.3 % below Sa = 2A/π at 16 samples per period.
    assert!(close(f(&j["sq"]), AMPLITUDE / SQRT_2, 1e-12), "{}", j["sq"]);
    assert!(close(f(&j["sku"]), 1.5, 1e-12), "{}", j["sku"]);
    let sa = AMPLITUDE / (PI / 16.0).tan() / 8.0;
    assert!(close(f(&j["sa"]), sa, 1e-12), "{}", j["sa"]);
    assert!(f(&j["ssk"]).abs() < 1e-9);
    // The interpolant cuts the crests: its Sq is sqrt((2 + cos h)/3) A/√2 with h the
    // phase step 2π/16.
    let j = json(&[&args[..], &["--quadrature", "exact"]].concat());
    check(&j, &expected_exact(&columns, f(&j["mean"])));
    let cut = ((2.0 + (TAU / WAVELENGTH).cos()) / 3.0).sqrt();
    assert!(
        close(f(&j["sq"]), cut * AMPLITUDE / SQRT_2, 1e-12),
        "{}",
        j["sq"]
    );
    assert!((f(&j["sp"]) - AMPLITUDE).abs() < 1e-15);
    assert!((f(&j["sv"]) - AMPLITUDE).abs() < 1e-15);
    // RMS slope of A sin(2πx/λ) is 2πA/(λ√2).
    assert!(close(
        f(&j["sdq"]),
        TAU * AMPLITUDE / (WAVELENGTH * SQRT_2),
        0.02
    ));

    let out = beltrami(&["residual", s(&measured), s(&flat)]);
    assert!(out.status.success());
    let table = String::from_utf8(out.stdout).unwrap();
    for row in [
        "Sa ", "Sq ", "Sp ", "Sv ", "Sz ", "Ssk ", "Sku ", "Sdq ", "Sdr ", "Sxp ", "Sk ", "Spk ",
        "Svk ", "Smr1 ", "Smr2 ", "Sak1 ", "Sak2 ", "Vmp ", "Vmc ", "Vvc ", "Vvv ", "Sal ", "Str ",
        "Std ",
    ] {
        assert!(
            table.lines().any(|l| l.starts_with(row)),
            "{row:?} in\n{table}"
        );
    }
    assert!(table.contains(" %)"), "Sdr as a percentage too:\n{table}");
    assert!(
        table.contains("heights from the smoothed surface"),
        "{table}"
    );
    assert!(
        table.contains("lumped (area-weighted vertex values) quadrature"),
        "{table}"
    );
}

/// The material ratio and volume parameters of a sine, in closed form: its heights
/// follow the arcsine law, `Smc(q) = A cos(πq)`, so `Sxp = A cos(0.025π)`,
/// `Vm(p) = A (sin(πp)/π − p cos(πp))` and `Vv(p) = A ((1 − p) cos(πp) + sin(πp)/π)`.
#[test]
fn material_ratio_and_volume_parameters_of_a_sinusoid() {
    let dir = tempfile::tempdir().unwrap();
    // 64 samples per period, 4 periods along x; each of the 16 rows shifted by 1/16 of a
    // sample, so that the vertices take 1024 distinct heights. (The lumped curve is the
    // distribution of the vertex heights: it resolves material ratios to the weight of
    // one height, here 1/1024; a profile repeated on every row would have only 64.)
    let grid = primitives::grid(256, 16);
    let wave = |x: f64, y: f64| AMPLITUDE * (TAU * (x + y / 16.0) / 64.0 + 0.1).sin();
    let measured: Vec<DVec3> = grid
        .positions
        .iter()
        .map(|p| *p + DVec3::Z * wave(p.x, p.y))
        .collect();
    let measured = write(dir.path(), "m.ply", measured, grid.faces.clone());
    let flat = write(dir.path(), "flat.ply", grid.positions, grid.faces);
    let j = json(&[
        "residual",
        s(&measured),
        s(&flat),
        "--json",
        "--smc",
        "50",
        "--smc",
        "2.5",
        "--smr",
        "0",
    ]);
    let a = AMPLITUDE;
    let vm = |p: f64| a * ((PI * p).sin() / PI - p * (PI * p).cos());
    let vv = |p: f64| a * ((1.0 - p) * (PI * p).cos() + (PI * p).sin() / PI);
    for (key, want) in [
        ("sxp", a * (0.025 * PI).cos()),
        ("vmp", vm(0.1)),
        ("vmc", vm(0.8) - vm(0.1)),
        ("vvc", vv(0.1) - vv(0.8)),
        ("vvv", vv(0.8)),
    ] {
        assert!(
            (f(&j[key]) - want).abs() < 2e-3 * a,
            "{key}: {} vs {want}",
            j[key]
        );
    }
    // Sk of the arcsine curve (its flattest 40 % lie at one end): 1.7747 A.
    assert!((f(&j["sk"]) - 1.7747 * a).abs() < 2e-3 * a, "{}", j["sk"]);
    assert!(f(&j["smr1"]) * f(&j["smr2"]) >= 0.0 && f(&j["smr2"]) <= 100.0);
    assert!((f(&j["smc"][0]["height"])).abs() < 2e-3 * a);
    assert_eq!(j["smc"][0]["ratio"], 50.0);
    assert!((f(&j["smc"][1]["height"]) - a * (0.025 * PI).cos()).abs() < 2e-3 * a);
    assert!((f(&j["smr"][0]["ratio"]) - 50.0).abs() < 0.5);
    assert_eq!(j["smr"][0]["height"], 0.0);
}

/// A flat 96 × 96 grid and the same grid with ridges along y (a sine along x of
/// wavelength 16), written as SMOOTHED and MEASURED.
#[test]
fn spatial_parameters_of_ridges() {
    let dir = tempfile::tempdir().unwrap();
    let grid = primitives::grid(96, 96);
    let measured: Vec<DVec3> = grid
        .positions
        .iter()
        .map(|p| *p + DVec3::Z * (TAU * p.x / 16.0).sin())
        .collect();
    let measured = write(dir.path(), "m.ply", measured, grid.faces.clone());
    let flat = write(dir.path(), "flat.ply", grid.positions, grid.faces);
    let j = json(&["residual", s(&measured), s(&flat), "--json"]);
    let sal = 0.2f64.acos() * 16.0 / TAU;
    assert!(close(f(&j["sal"]), sal, 0.03), "{}", j["sal"]);
    assert!(f(&j["str"]) < 0.1, "{}", j["str"]);
    assert!((f(&j["std"]) - 90.0).abs() < 0.1, "{}", j["std"]);
    assert_eq!(j["spatial"]["step"], 1.0);
    assert_eq!(j["spatial"]["nx"], 97);
    assert_eq!(j["spatial"]["valid_points"], 97 * 97);
    assert_eq!(j["spatial"]["threshold"], 0.2);
    assert_eq!(j["spatial"]["decays_in_every_direction"], false);
    assert_eq!(j["spatial"]["unavailable"], Value::Null);
}

/// A plane tilted off z, its first axis the projection of x, and its normal.
fn tilted_plane() -> (DVec3, DVec3, DVec3) {
    let normal = DVec3::new(0.3, -0.2, 1.0).normalize();
    let u = (DVec3::X - normal * normal.x).normalize();
    (u, normal.cross(u), normal)
}

#[test]
fn form_plane_removes_a_tilted_plane() {
    let dir = tempfile::tempdir().unwrap();
    // A sine texture along the plane's normal, 10 whole periods centred on the patch
    // (so that it does not tilt the fitted plane), 8 samples per period.
    let grid = primitives::grid(80, 80);
    let (u, v, normal) = tilted_plane();
    let texture = |x: f64| AMPLITUDE * (TAU * x / 8.0).cos();
    let measured: Vec<DVec3> = grid
        .positions
        .iter()
        .map(|p| {
            let (x, y) = (p.x - 40.0, p.y - 40.0);
            DVec3::new(10.0, -20.0, 5.0) + u * x + v * y + normal * texture(x)
        })
        .collect();
    let path = write(dir.path(), "tilted.ply", measured.clone(), grid.faces);
    let out_ply = dir.path().join("form.ply");
    let j = json(&[
        "residual",
        s(&path),
        "--form",
        "plane",
        "--json",
        "--scalars",
        s(&out_ply),
    ]);
    assert_eq!(j["smoothed"], Value::Null);
    assert_eq!(j["form"]["kind"], "plane");
    assert_eq!(j["form"]["flipped"], false);
    let n = DVec3::new(
        f(&j["form"]["direction"][0]),
        f(&j["form"]["direction"][1]),
        f(&j["form"]["direction"][2]),
    );
    assert!(n.dot(normal) > 1.0 - 1e-12, "{n}");
    let sq = f(&j["sq"]);
    assert!(close(sq, AMPLITUDE / SQRT_2, 0.005), "{sq}");
    // The lay of the texture runs along v, at 90° from u (the projection of x).
    assert!((f(&j["std"]) - 90.0).abs() < 0.5, "{}", j["std"]);
    // The scalars file holds MEASURED laid onto the plane, with the residual.
    let mut file = std::fs::File::open(&out_ply).unwrap();
    let ply = ply_rs_bw::parser::Parser::<DefaultElement>::new()
        .read_ply(&mut file)
        .unwrap();
    let point = DVec3::new(
        f(&j["form"]["point"][0]),
        f(&j["form"]["point"][1]),
        f(&j["form"]["point"][2]),
    );
    let double = |e: &DefaultElement, k: &str| match e[k] {
        Property::Double(v) => v,
        ref other => panic!("{k} is {other:?}"),
    };
    for (e, m) in ply.payload["vertex"].iter().zip(&measured) {
        let p = DVec3::new(double(e, "x"), double(e, "y"), double(e, "z"));
        assert!((p - point).dot(n).abs() < 1e-9, "on the plane");
        let r = double(e, "residual");
        assert!(
            (p + n * r - *m).length() < 1e-9,
            "the residual lifts it back"
        );
    }

    let out = beltrami(&["residual", s(&path), "--form", "plane"]);
    let table = String::from_utf8(out.stdout).unwrap();
    assert!(
        table.starts_with("Residual r = orthogonal distance of ")
            && table.contains("least-squares plane"),
        "{table}"
    );
    assert!(table.contains("heights from the form"), "{table}");
}

#[test]
fn form_sphere_removes_a_sphere_cap() {
    let dir = tempfile::tempdir().unwrap();
    // A cap of radius 50 over 40 × 40 units, a texture of 10 periods along the radius.
    let grid = primitives::grid(160, 160);
    let radius = 50.0;
    let texture = |x: f64| AMPLITUDE * (TAU * x / 4.0).cos();
    let measured: Vec<DVec3> = grid
        .positions
        .iter()
        .map(|p| {
            let (x, y) = (p.x * 0.25 - 20.0, p.y * 0.25 - 20.0);
            let d = DVec3::new(x, y, (radius * radius - x * x - y * y).sqrt()).normalize();
            d * (radius + texture(x))
        })
        .collect();
    let path = write(dir.path(), "cap.ply", measured, grid.faces);
    let j = json(&["residual", s(&path), "--form", "sphere", "--json"]);
    assert_eq!(j["form"]["kind"], "sphere");
    assert_eq!(j["form"]["direction"], Value::Null);
    assert!((f(&j["form"]["radius"]) - radius).abs() < 0.5 * AMPLITUDE);
    let sq = f(&j["sq"]);
    assert!(close(sq, AMPLITUDE / SQRT_2, 0.005), "{sq}");
    // poly:2 over the cap's plane takes most of the sphere away too, and a cylinder
    // leaves the curvature along its axis.
    let poly = json(&["residual", s(&path), "--form", "poly:4", "--json"]);
    assert_eq!(poly["form"]["kind"], "polynomial");
    assert_eq!(poly["form"]["degree"], 4);
    assert!(
        close(f(&poly["sq"]), AMPLITUDE / SQRT_2, 0.02),
        "{}",
        poly["sq"]
    );
    let cylinder = json(&["residual", s(&path), "--form", "cylinder", "--json"]);
    assert!(f(&cylinder["sq"]) > 2.0 * AMPLITUDE, "{}", cylinder["sq"]);
}

#[test]
fn spatial_parameters_of_a_closed_surface_are_unavailable() {
    let dir = tempfile::tempdir().unwrap();
    let sphere = primitives::icosphere(3);
    let grown: Vec<DVec3> = sphere.positions.iter().map(|&p| 1.01 * p).collect();
    let measured = write(dir.path(), "grown.ply", grown, sphere.faces.clone());
    let reference = write(dir.path(), "unit.ply", sphere.positions, sphere.faces);
    let j = json(&["residual", s(&measured), s(&reference), "--json"]);
    assert_eq!(
        (&j["sal"], &j["str"], &j["std"]),
        (&Value::Null, &Value::Null, &Value::Null)
    );
    assert!(
        j["spatial"]["unavailable"]
            .as_str()
            .unwrap()
            .starts_with("the surface is not a height field over its mean plane"),
        "{}",
        j["spatial"]
    );
    // Everything else is there: a uniform 1 % residual.
    assert!((f(&j["sq"]) - 0.01).abs() < 1e-3);
    let out = beltrami(&["residual", s(&measured), s(&reference)]);
    let table = String::from_utf8(out.stdout).unwrap();
    assert!(
        table.contains("spatial parameters unavailable: the surface is not a height field"),
        "{table}"
    );
}

/// Two small triangles far apart: the grid over their spread has fewer than four
/// points inside them. The spatial parameters are unavailable (as for one triangle),
/// and the rest is reported.
#[test]
fn spatial_parameters_of_pieces_far_apart_are_unavailable() {
    let dir = tempfile::tempdir().unwrap();
    let positions = vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.1),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::new(5.0, 5.0, 0.0),
        DVec3::new(6.0, 5.0, 0.0),
        DVec3::new(5.0, 6.0, 0.2),
    ];
    let faces = PolygonList::from_triangles(&[[0, 1, 2], [3, 4, 5]]);
    let measured = write(dir.path(), "pieces.ply", positions, faces);
    let j = json(&["residual", s(&measured), "--form", "plane", "--json"]);
    assert_eq!(j["sal"], Value::Null);
    assert!(
        j["spatial"]["unavailable"]
            .as_str()
            .is_some_and(|why| why.contains("height grid is empty")),
        "{}",
        j["spatial"]
    );
    assert!(f(&j["sq"]) > 0.0, "{j}");
}

#[test]
fn residual_ply_holds_the_heights_on_the_smoothed_surface() {
    let dir = tempfile::tempdir().unwrap();
    let (measured, flat, columns) = sinusoid(dir.path());
    for remove_mean in [false, true] {
        let out_ply = dir.path().join("residual.ply");
        let mut args = vec![
            "residual",
            s(&measured),
            s(&flat),
            "--json",
            "--out",
            s(&out_ply),
        ];
        if remove_mean {
            args.push("--remove-mean");
        }
        let j = json(&args);
        assert_eq!(j["scalars"], s(&out_ply));
        let shift = if remove_mean { f(&j["mean"]) } else { 0.0 };

        let mut file = std::fs::File::open(&out_ply).unwrap();
        let ply = ply_rs_bw::parser::Parser::<DefaultElement>::new()
            .read_ply(&mut file)
            .unwrap();
        let vertices = &ply.payload["vertex"];
        assert_eq!(vertices.len(), 325);
        let double = |e: &DefaultElement, k: &str| match e[k] {
            Property::Double(v) => v,
            ref other => panic!("{k} is {other:?}"),
        };
        for (i, e) in vertices.iter().enumerate() {
            let column = i % (CELLS as usize + 1);
            assert_eq!(double(e, "z"), 0.0, "the smoothed (flat) surface");
            assert_eq!(double(e, "x"), column as f64);
            let want = columns[column] - shift;
            assert!(
                (double(e, "residual") - want).abs() < 1e-16,
                "vertex {i}: {} vs {want}",
                double(e, "residual")
            );
        }
    }
}

#[test]
fn mismatched_topologies_are_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let a = primitives::grid(8, 8);
    let b = primitives::grid(8, 9);
    let measured = write(
        dir.path(),
        "measured.ply",
        a.positions.clone(),
        a.faces.clone(),
    );
    let other = write(dir.path(), "other.obj", b.positions, b.faces);
    let out = beltrami(&["residual", s(&measured), s(&other)]);
    assert_eq!(out.status.code(), Some(1));
    assert_snapshot!(error_line(&out, dir.path()), @"error: measured.ply vs other.obj: the meshes do not share their topology: 81 vertices vs 90");

    // Same vertices, the other diagonal in every square.
    let id = |i: u32, j: u32| j * 9 + i;
    let mut triangles = Vec::new();
    for j in 0..8 {
        for i in 0..8 {
            triangles.push([id(i, j), id(i + 1, j), id(i, j + 1)]);
            triangles.push([id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let flipped = write(
        dir.path(),
        "diagonals.stl",
        a.positions.clone(),
        PolygonList::from_triangles(&triangles),
    );
    let out = beltrami(&["residual", s(&measured), s(&flipped)]);
    assert_eq!(out.status.code(), Some(1));
    let line = error_line(&out, dir.path());
    assert!(
        line.starts_with(
            "error: measured.ply vs diagonals.stl: the meshes do not share their topology: "
        ),
        "{line}"
    );
}

#[test]
fn bad_input_and_usage() {
    let dir = tempfile::tempdir().unwrap();
    let (measured, flat, _) = sinusoid(dir.path());
    let empty = dir.path().join("empty.ply");
    std::fs::write(
        &empty,
        "ply\nformat ascii 1.0\nelement vertex 0\nproperty double x\nproperty double y\nproperty double z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n",
    )
    .unwrap();
    let out = beltrami(&["residual", s(&measured), s(&empty)]);
    assert_eq!(out.status.code(), Some(1));
    assert_snapshot!(error_line(&out, dir.path()), @"error: empty.ply: the mesh is empty");

    let cloud = dir.path().join("cloud.obj");
    std::fs::write(&cloud, "v 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
    let out = beltrami(&["residual", s(&cloud), s(&cloud)]);
    assert_eq!(out.status.code(), Some(1));
    assert_snapshot!(error_line(&out, dir.path()), @"error: cloud.obj: the mesh has 3 vertices but no faces (points or lines only; residual needs a surface of triangles)");

    // SMOOTHED or --form, not both, not neither; forms by name.
    let out = beltrami(&["residual", s(&measured), s(&flat), "--form", "plane"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        error_line(&out, dir.path())
            .starts_with("error: the argument '[SMOOTHED]' cannot be used with '--form <FORM>'")
    );
    let out = beltrami(&["residual", s(&measured)]);
    assert_eq!(out.status.code(), Some(2));
    assert!(error_line(&out, dir.path()).contains("<SMOOTHED|--form <FORM>>"));
    for (form, message) in [
        (
            "poly:7",
            "the degree of poly:N is a whole number from 1 to 6, got '7'",
        ),
        (
            "poly:x",
            "the degree of poly:N is a whole number from 1 to 6, got 'x'",
        ),
        ("cone", "expected plane, poly:N, sphere or cylinder"),
    ] {
        let out = beltrami(&["residual", s(&measured), "--form", form]);
        assert_eq!(out.status.code(), Some(2));
        let line = error_line(&out, dir.path());
        assert!(line.contains(message), "{line}");
    }
    let out = beltrami(&["residual", s(&measured), s(&flat), "--smc", "101"]);
    assert_eq!(out.status.code(), Some(2));
    assert_snapshot!(error_line(&out, dir.path()), @"error: --smc takes a material ratio in percent from 0 to 100, got 101 (see 'beltrami --help')");
    // A form that does not fit: a sphere through a flat grid.
    let out = beltrami(&["residual", s(&flat), "--form", "sphere"]);
    assert_eq!(out.status.code(), Some(1));
    assert_snapshot!(error_line(&out, dir.path()), @"error: flat.obj: sphere fit is undetermined: the points are coplanar");

    let obj = dir.path().join("residual.obj");
    let out = beltrami(&["residual", s(&measured), s(&flat), "--out", s(&obj)]);
    assert_eq!(out.status.code(), Some(2));
    assert_snapshot!(error_line(&out, dir.path()), @"error: --scalars writes a PLY file (per-vertex scalars need PLY), got 'residual.obj' (see 'beltrami --help')");
    assert!(!obj.exists());
}
