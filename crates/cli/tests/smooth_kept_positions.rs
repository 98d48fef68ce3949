//! `beltrami smooth` keeps the input positions (for the summary's mean displacement) in
//! a temporary file through the run: the summary and the output are the same as when
//! no temporary file can be written (the positions then stay in memory), the file is
//! gone after the run, and the summary's volume after a run that went on without the
//! half-edge mesh (over its triangles) is the one computed on the mesh.

mod common;

use std::path::Path;
use std::process::{Command, Output};

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::{DVec3, HalfedgeMesh, primitives};
use beltrami_io::read_mesh;
use beltrami_testkit::Lcg64;

use common::{s, write};

/// `beltrami args` with the temporary directory `tmp`.
fn run_with_tmp(args: &[&str], tmp: &Path) -> Output {
    let out = Command::new(env!("CARGO_BIN_EXE_beltrami"))
        .args(args)
        .env("TMPDIR", tmp)
        .output()
        .expect("the binary runs");
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// A noisy closed sphere, written as binary PLY.
fn noisy_sphere(dir: &Path) -> std::path::PathBuf {
    let sphere = primitives::icosphere(4);
    let mut rng = Lcg64::new(7);
    let positions: Vec<DVec3> = sphere
        .positions
        .iter()
        .map(|&p| p + rng.next_symmetric_vector() * 0.01)
        .collect();
    write(dir, "sphere.ply", positions, sphere.faces)
}

#[test]
fn the_summary_is_the_same_with_the_positions_in_a_file_or_in_memory() {
    let dir = tempfile::tempdir().unwrap();
    let input = noisy_sphere(dir.path());
    let tmp = dir.path().join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    let missing = dir.path().join("no such directory");
    for options in [
        &["--weights", "uniform", "--iterations", "5"][..],
        &[
            "--weights",
            "cotangent",
            "--update",
            "once",
            "--iterations",
            "3",
        ],
        &[
            "--weights",
            "distance",
            "--preserve-volume",
            "--iterations",
            "3",
        ],
        &["--weights", "bilateral", "--iterations", "2"],
        &["--method", "implicit", "--lambda", "1", "--iterations", "1"],
    ] {
        let outputs = [dir.path().join("a.ply"), dir.path().join("b.ply")];
        let mut stdout = Vec::new();
        for (output, tmp) in outputs.iter().zip([&tmp, &missing]) {
            let mut args = vec!["smooth", s(&input), s(output)];
            args.extend_from_slice(options);
            let out = run_with_tmp(&args, tmp);
            let text = String::from_utf8(out.stdout).unwrap();
            // The line names the output file; the rest must agree.
            stdout.push(text.replace(s(output), "OUTPUT"));
        }
        assert_eq!(stdout[0], stdout[1], "{options:?}");
        assert!(stdout[0].contains("mean displacement"), "{}", stdout[0]);
        assert_eq!(
            std::fs::read(&outputs[0]).unwrap(),
            std::fs::read(&outputs[1]).unwrap(),
            "{options:?}"
        );
        // The temporary file is removed.
        assert_eq!(std::fs::read_dir(&tmp).unwrap().count(), 0, "{options:?}");
    }
}

#[test]
fn the_volume_after_a_run_without_the_mesh_is_the_meshs() {
    let dir = tempfile::tempdir().unwrap();
    let input = noisy_sphere(dir.path());
    let output = dir.path().join("out.ply");
    let out = run_with_tmp(
        &["smooth", s(&input), s(&output), "--iterations", "4"],
        dir.path(),
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let result = read_mesh(&output).unwrap();
    let mesh = HalfedgeMesh::from_polygon_list(result.positions.len(), &result.faces).unwrap();
    let after = Geometry::new(&mesh, &result.positions)
        .unwrap()
        .volume()
        .unwrap();
    // The summary prints six significant digits of the volume computed on the mesh.
    let printed = format!("-> {} (", beltrami_cli_number(after));
    assert!(text.contains(&printed), "{text} lacks {printed}");
}

/// The summary's number format (`number` of the command's text module): six
/// significant digits, trailing zeros trimmed.
fn beltrami_cli_number(x: f64) -> String {
    let trim = |t: &str| {
        if t.contains('.') {
            t.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            t.to_string()
        }
    };
    let magnitude = x.abs();
    if (1e-4..1e6).contains(&magnitude) {
        let exponent = magnitude.log10().floor() as i32;
        let decimals = usize::try_from((5 - exponent).max(0)).unwrap_or(0);
        trim(&format!("{x:.decimals$}"))
    } else {
        let text = format!("{x:.5e}");
        let (mantissa, exponent) = text.split_once('e').unwrap();
        format!("{}e{exponent}", trim(mantissa))
    }
}
