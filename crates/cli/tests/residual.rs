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

/// The exact areal parameters of the piecewise-linear profile `v` (unit spacing)
/// extruded along y, heights measured from `datum`: every cell holds the same linear
/// function of x on both of its triangles, so the surface integrals are 1-D ones.
struct Expected {
    sa: f64,
    sq: f64,
    ssk: f64,
    sku: f64,
    sdq: f64,
    sdr: f64,
}

fn expected(v: &[f64], datum: f64) -> Expected {
    let n = (v.len() - 1) as f64;
    let (mut m1, mut m2, mut m3, mut m4, mut g2, mut dr) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
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
        let g = b - a;
        g2 += g * g;
        dr += (1.0 + g * g).sqrt() - 1.0;
    }
    let sq = (m2 / n).sqrt();
    Expected {
        sa: m1 / n,
        sq,
        ssk: m3 / n / sq.powi(3),
        sku: m4 / n / sq.powi(4),
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
fn sinusoid_residual_has_the_exact_areal_parameters_and_sq_near_a_over_root_2() {
    let dir = tempfile::tempdir().unwrap();
    let (measured, flat, columns) = sinusoid(dir.path());

    // Heights from the smoothed surface: the offset stays in.
    let j = json(&["residual", s(&measured), s(&flat), "--json"]);
    assert_eq!(j["datum"], "reference");
    assert_eq!(j["vertices"], 325);
    check(&j, &expected(&columns, 0.0));
    assert!((f(&j["sp"]) - (AMPLITUDE + OFFSET)).abs() < 1e-15);
    assert!((f(&j["sv"]) - (AMPLITUDE - OFFSET)).abs() < 1e-15);
    assert!((f(&j["sz"]) - 2.0 * AMPLITUDE).abs() < 1e-15);
    assert!((f(&j["mean"]) - OFFSET).abs() < 1e-15);
    assert_eq!(j["area"], 256.0);

    // Heights from the mean: the sine alone.
    let j = json(&[
        "residual",
        s(&measured),
        s(&flat),
        "--json",
        "--remove-mean",
    ]);
    assert_eq!(j["datum"], "mean");
    check(&j, &expected(&columns, f(&j["mean"])));
    // Against the continuous sine: Sq = A/√2, Sa = 2A/π, Ssk = 0, Sku = 3/2, within the
    // error of linear interpolation at 16 points per period.
    let sq = f(&j["sq"]);
    assert!(close(sq, AMPLITUDE / SQRT_2, 0.02), "{sq}");
    assert!(
        sq < AMPLITUDE / SQRT_2,
        "linear interpolation cuts the crests"
    );
    assert!(close(f(&j["sa"]), 2.0 * AMPLITUDE / PI, 0.02));
    assert!(f(&j["ssk"]).abs() < 1e-9);
    assert!(close(f(&j["sku"]), 1.5, 0.03));
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
        "Sa ", "Sq ", "Sp ", "Sv ", "Sz ", "Ssk ", "Sku ", "Sdq ", "Sdr ",
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

    let obj = dir.path().join("residual.obj");
    let out = beltrami(&["residual", s(&measured), s(&flat), "--out", s(&obj)]);
    assert_eq!(out.status.code(), Some(2));
    assert_snapshot!(error_line(&out, dir.path()), @"error: --scalars writes a PLY file (per-vertex scalars need PLY), got 'residual.obj' (see 'beltrami --help')");
    assert!(!obj.exists());
}
