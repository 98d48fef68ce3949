//! Instrument height maps (X3P, SDF) through the commands: read as triangulated grids
//! in metres, written back where the mesh is still a grid, refused in one line where
//! it is not.

mod common;

use common::{beltrami, error_line, f, json, s, squashed_sphere};

use std::f64::consts::{SQRT_2, TAU};
use std::path::{Path, PathBuf};

use beltrami_io::{
    HeightMap, LengthUnit, WriteOptions, read_height_map, read_mesh, write_height_map, write_mesh,
};

const NX: usize = 161;
const NY: usize = 41;
/// The sampling step, 1 µm.
const STEP: f64 = 1e-6;
/// The texture: a sine of 0.2 µm amplitude and 20 µm wavelength along x (8 periods).
const AMPLITUDE: f64 = 0.2e-6;
const WAVELENGTH: f64 = 20e-6;

/// A sine texture on a plane tilted by 1 and 2 mrad, with four invalid points (one
/// inside, one on an edge, and the two beside a corner, which leave the corner point
/// in no whole cell).
fn scan() -> HeightMap {
    let mut z = Vec::with_capacity(NX * NY);
    for j in 0..NY {
        for i in 0..NX {
            let (x, y) = (i as f64 * STEP, j as f64 * STEP);
            z.push(1e-3 * x + 2e-3 * y + AMPLITUDE * (TAU * x / WAVELENGTH).sin());
        }
    }
    for (i, j) in [(80, 20), (0, 10), (NX - 1, NY - 2), (NX - 2, NY - 1)] {
        z[i + NX * j] = f64::NAN;
    }
    HeightMap::new(NX, NY, STEP, STEP, z, LengthUnit::Metre).unwrap()
}

fn write_scan(dir: &Path, name: &str) -> PathBuf {
    let path = dir.join(name);
    write_height_map(&path, &scan()).unwrap();
    path
}

#[test]
fn residual_of_an_x3p_scan_after_levelling_is_the_sines_rms() {
    let dir = tempfile::tempdir().unwrap();
    let x3p = write_scan(dir.path(), "scan.x3p");
    let summary = json(&["residual", s(&x3p), "--form", "plane", "--json"]);
    let sq = f(&summary["sq"]);
    // The continuous value over whole periods: A/√2 (the tilt changes it by 3e-6).
    let expected = AMPLITUDE / SQRT_2;
    assert!(
        (sq / expected - 1.0).abs() < 5e-3,
        "Sq {sq:e}, expected {expected:e}"
    );
    // 161 × 41 points less the 4 invalid ones and the one left without a whole cell.
    assert_eq!(summary["vertices"], NX * NY - 4 - 1);
    // The same grid as a PLY mesh gives the same numbers: the loader adds nothing.
    let ply = dir.path().join("scan.ply");
    write_mesh(&ply, &read_mesh(&x3p).unwrap(), &WriteOptions::default()).unwrap();
    let from_ply = json(&["residual", s(&ply), "--form", "plane", "--json"]);
    for key in ["sa", "sq", "sp", "sv", "sku", "sdq", "sdr", "sk", "vmc"] {
        assert_eq!(summary[key], from_ply[key], "{key}");
    }
}

#[test]
fn sdf_and_x3p_of_the_same_heights_give_the_same_residual() {
    let dir = tempfile::tempdir().unwrap();
    let x3p = write_scan(dir.path(), "scan.x3p");
    let sdf = write_scan(dir.path(), "scan.sdf");
    let a = json(&["residual", s(&x3p), "--form", "plane", "--json"]);
    let b = json(&["residual", s(&sdf), "--form", "plane", "--json"]);
    for key in ["sa", "sq", "sz", "ssk", "sku", "sdq", "sal", "str"] {
        assert_eq!(a[key], b[key], "{key}");
    }
}

#[test]
fn the_table_says_what_the_grid_became() {
    let dir = tempfile::tempdir().unwrap();
    let x3p = write_scan(dir.path(), "scan.x3p");
    for command in [
        &["residual", s(&x3p), "--form", "plane"][..],
        &["info", s(&x3p)],
    ] {
        let out = beltrami(command);
        assert!(out.status.success(), "{command:?}");
        let stdout = String::from_utf8(out.stdout).unwrap();
        let note = format!(
            "note: read {} as a height map of 161 × 41 points 1e-6 × 1e-6 m apart, coordinates in m; left out (holes) 4 invalid points and 1 point in no cell of four valid points",
            x3p.display()
        );
        assert!(stdout.lines().any(|l| l == note), "{command:?}: {stdout}");
    }
}

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures")
        .join(name)
}

#[test]
fn a_repaired_height_map_is_written_back_as_one() {
    let dir = tempfile::tempdir().unwrap();
    let x3p = write_scan(dir.path(), "scan.x3p");
    for name in ["back.x3p", "back.sdf"] {
        let out = dir.path().join(name);
        let run = beltrami(&["repair", s(&x3p), s(&out)]);
        assert!(run.status.success(), "{name}");
        let back = read_height_map(&out).unwrap();
        let original = scan();
        assert_eq!((back.nx, back.ny), (NX, NY));
        // The point in no whole cell was left out of the mesh: it is invalid now.
        assert_eq!(back.invalid_points(), original.invalid_points() + 1);
        for (k, (a, b)) in back.z.iter().zip(&original.z).enumerate() {
            assert!(
                a.is_nan() || a.to_bits() == b.to_bits(),
                "{name}: point {k}"
            );
        }
    }
}

#[test]
fn height_map_outputs_that_cannot_be_written_are_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let x3p = write_scan(dir.path(), "scan.x3p");
    // Per-vertex scalars need PLY, or a height map for a height-map input: a usage
    // error before anything is read.
    let out = beltrami(&[
        "residual",
        s(&x3p),
        "--form",
        "plane",
        "--scalars",
        s(&dir.path().join("r.stl")),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        error_line(&out, dir.path()),
        "error: --scalars writes a PLY file (per-vertex scalars need PLY), got 'r.stl' (see 'beltrami --help')"
    );
    let ply = dir.path().join("scan.ply");
    write_mesh(&ply, &read_mesh(&x3p).unwrap(), &WriteOptions::default()).unwrap();
    let out = beltrami(&[
        "residual",
        s(&ply),
        "--form",
        "plane",
        "--scalars",
        s(&dir.path().join("r.x3p")),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        error_line(&out, dir.path()).contains("only for a height-map MEASURED"),
        "{}",
        error_line(&out, dir.path())
    );
    assert!(!dir.path().join("r.x3p").exists());
    // A mesh that is no grid cannot become a height map.
    let sphere = squashed_sphere(dir.path(), "sphere.ply", 2);
    let out = beltrami(&["repair", s(&sphere), s(&dir.path().join("sphere.x3p"))]);
    assert_eq!(out.status.code(), Some(1));
    let line = error_line(&out, dir.path());
    assert!(
        line.starts_with("error: sphere.x3p: not a height map: "),
        "{line}"
    );
    assert!(!dir.path().join("sphere.x3p").exists());
    // Nor one whose vertices happen to lie on a grid but whose faces do not tile its
    // cell once, facing up (a tetrahedron's four corners on a 2 × 2 grid): the file
    // would read back as two triangles.
    let tetrahedron = fixture("tetrahedron_ascii.ply");
    let tet = dir.path().join("tet.x3p");
    let out = beltrami(&["repair", s(&tetrahedron), s(&tet)]);
    assert_eq!(out.status.code(), Some(1));
    let line = error_line(&out, dir.path());
    assert!(
        line.starts_with("error: tet.x3p: not a height map: ") && line.contains("faces down"),
        "{line}"
    );
    assert!(!tet.exists());
    // And delaunay, whose flips change the triangles, refuses a height-map OUTPUT
    // before reading anything.
    let out = beltrami(&["delaunay", s(&x3p), s(&dir.path().join("d.x3p"))]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        error_line(&out, dir.path()).contains("delaunay cannot write"),
        "{}",
        error_line(&out, dir.path())
    );
}

#[test]
fn broken_height_maps_fail_with_exit_code_1_and_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let x3p = write_scan(dir.path(), "scan.x3p");
    let bytes = std::fs::read(&x3p).unwrap();
    let cut = dir.path().join("cut.x3p");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    let out = beltrami(&["residual", s(&cut), "--form", "plane"]);
    assert_eq!(out.status.code(), Some(1));
    let line = error_line(&out, dir.path());
    assert!(
        line.starts_with("error: cut.x3p: invalid x3p archive: "),
        "{line}"
    );

    let sdf = dir.path().join("short.sdf");
    std::fs::write(
        &sdf,
        "aISO-1.0\nNumPoints = 3\nNumProfiles = 2\nXscale = 1e-6\nYscale = 1e-6\nZscale = 1e-9\nDataType = 7\n*\n1 2 3\n4 5\n*\n",
    )
    .unwrap();
    let out = beltrami(&["info", s(&sdf)]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        error_line(&out, dir.path()),
        "error: short.sdf: line 11: sdf value 5: the data end after 5 values, but NumPoints × NumProfiles = 6"
    );
}

#[test]
fn commands_that_leave_the_grid_refuse_a_height_map_output_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let x3p = write_scan(dir.path(), "scan.x3p");
    for (command, extra) in [
        ("smooth", &[][..]),
        ("remesh", &[][..]),
        ("decimate", &["--ratio", "0.5"][..]),
        ("fill-holes", &[][..]),
        ("subdivide", &[][..]),
    ] {
        for name in ["out.x3p", "out.sdf"] {
            let out_path = dir.path().join(name);
            let mut args = vec![command, s(&x3p), s(&out_path)];
            args.extend(extra);
            let out = beltrami(&args);
            assert_eq!(out.status.code(), Some(2), "{command} {name}");
            let line = error_line(&out, dir.path());
            assert!(
                line.starts_with(&format!("error: {command} cannot write "))
                    && line.contains("as a height map"),
                "{command}: {line}"
            );
            assert!(!out_path.exists());
        }
    }
}

#[test]
fn info_names_the_height_map_format() {
    let dir = tempfile::tempdir().unwrap();
    for (name, format) in [("scan.x3p", "X3P"), ("scan.sdf", "SDF")] {
        let path = write_scan(dir.path(), name);
        assert_eq!(json(&["info", s(&path), "--json"])["format"], format);
    }
}

#[test]
fn a_residual_is_written_back_as_a_height_map_on_the_measured_grid() {
    let dir = tempfile::tempdir().unwrap();
    let x3p = write_scan(dir.path(), "scan.x3p");
    for name in ["levelled.x3p", "levelled.sdf"] {
        let out = dir.path().join(name);
        let run = beltrami(&[
            "residual",
            s(&x3p),
            "--form",
            "plane",
            "--remove-mean",
            "--scalars",
            s(&out),
            "--json",
        ]);
        assert!(
            run.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&run.stderr)
        );
        let back = read_height_map(&out).unwrap();
        // The same grid, the tilt gone: what is left is the sine.
        assert_eq!((back.nx, back.ny), (NX, NY));
        let valid: Vec<f64> = back.z.iter().copied().filter(|z| !z.is_nan()).collect();
        let rms = (valid.iter().map(|z| z * z).sum::<f64>() / valid.len() as f64).sqrt();
        assert!(
            (rms / (AMPLITUDE / SQRT_2) - 1.0).abs() < 0.02,
            "{name}: rms {rms}"
        );
        let peak = valid.iter().fold(0.0f64, |m, z| m.max(z.abs()));
        // With the tilt (2.4e-7 over the grid) the peak would pass 3e-7; the plane also
        // takes up a little of the sine, so the peak is not quite the amplitude.
        assert!(
            peak < 1.25 * AMPLITUDE,
            "{name}: the tilt is gone, peak {peak}"
        );
        // And it reads back as the residual's own input: its residual from a plane is
        // the same Sq.
        let summary = json(&["residual", s(&out), "--form", "plane", "--json"]);
        let first = json(&["residual", s(&x3p), "--form", "plane", "--json"]);
        let sq = |j: &serde_json::Value| j["sq"].as_f64().unwrap();
        assert!((sq(&summary) / sq(&first) - 1.0).abs() < 1e-3, "{name}");
    }
}
