//! `beltrami subdivide` as a user runs it: every fixture subdivides with both schemes
//! into the library's result, a broken or non-triangle input gives one error line and
//! no output, and bad usage exits with code 2 before anything is read or written.

mod common;

use std::fs;
use std::path::{Path, PathBuf};

use beltrami_algorithms::Scheme;
use beltrami_io::read_mesh;
use common::{beltrami, error_line, s};
use serde_json::Value;

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

/// The mesh files at the top of `fixtures/`.
fn fixture_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = fs::read_dir(fixtures())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.extension()
                .is_some_and(|e| ["ply", "stl", "obj", "off"].contains(&e.to_str().unwrap()))
        })
        .collect();
    files.sort();
    assert!(files.len() >= 15, "{files:?}");
    files
}

#[test]
fn every_fixture_subdivides_into_the_library_result() {
    let dir = tempfile::tempdir().unwrap();
    let mut triangle_meshes = 0;
    for input in fixture_files() {
        let data = read_mesh(&input).unwrap();
        let name = input.file_name().unwrap().to_str().unwrap();
        let mesh =
            beltrami_halfedge::HalfedgeMesh::from_polygons(data.positions.len(), data.faces.iter())
                .unwrap();
        for (scheme, steps) in [(Scheme::Loop, 1), (Scheme::Sqrt3, 2)] {
            let output = dir.path().join(format!("{scheme}_{name}.ply"));
            let args = [
                "subdivide",
                s(&input),
                s(&output),
                "--scheme",
                scheme.name(),
                "--steps",
                &steps.to_string(),
                "--json",
            ];
            let out = beltrami(&args);
            if !mesh.is_triangle_mesh() {
                assert_eq!(out.status.code(), Some(1), "{name}");
                let line = error_line(&out, &fixtures());
                assert!(
                    line.contains("has 4 vertices; subdivide needs a triangle mesh"),
                    "{line}"
                );
                assert!(!output.exists(), "{name}: no output after an error");
                continue;
            }
            assert!(
                out.status.success(),
                "{name}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            let summary: Value = serde_json::from_slice(&out.stdout).unwrap();
            let (expected, positions) = scheme.subdivide(&mesh, &data.positions, steps).unwrap();
            let written = read_mesh(&output).unwrap();
            assert_eq!(written.positions, positions, "{name} {scheme}: positions");
            assert_eq!(
                written.faces,
                expected.to_polygons(),
                "{name} {scheme}: faces"
            );
            assert_eq!(summary["faces"], expected.n_faces(), "{name}");
            assert_eq!(summary["vertices"], expected.n_vertices(), "{name}");
            assert_eq!(summary["faces_in"], mesh.n_faces(), "{name}");
            let factor = if scheme == Scheme::Loop { 4 } else { 9 };
            assert_eq!(expected.n_faces(), factor * mesh.n_faces(), "{name}");
            triangle_meshes += 1;
        }
    }
    assert!(triangle_meshes >= 2 * 14, "{triangle_meshes}");
}

#[test]
fn the_default_is_one_loop_step_and_the_sentence_names_it() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("out.obj");
    let input = fixtures().join("tetrahedron_le.ply");
    let out = beltrami(&["subdivide", s(&input), s(&output)]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("(4 vertices, 4 faces) by 1 step of loop -> ")
            && text.trim_end().ends_with("(10 vertices, 16 faces)"),
        "{text}"
    );
    assert_eq!(read_mesh(&output).unwrap().faces.len(), 16);
}

#[test]
fn isolated_vertices_are_kept_in_place() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("bad/isolated_vertices.obj");
    let output = dir.path().join("out.ply");
    let out = beltrami(&["subdivide", s(&input), s(&output), "--scheme", "sqrt3"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let before = read_mesh(&input).unwrap();
    let after = read_mesh(&output).unwrap();
    let used: std::collections::HashSet<u32> = before.faces.iter().flatten().copied().collect();
    let isolated: Vec<usize> = (0..before.positions.len())
        .filter(|&v| !used.contains(&(v as u32)))
        .collect();
    assert!(!isolated.is_empty());
    for v in isolated {
        assert_eq!(after.positions[v], before.positions[v], "vertex {v}");
    }
}

#[test]
fn broken_files_give_one_line_and_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let bad = fixtures().join("bad");
    let mut files: Vec<PathBuf> = fs::read_dir(&bad)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    for input in files {
        let name = input.file_name().unwrap().to_str().unwrap().to_string();
        if name == "isolated_vertices.obj" {
            continue; // the one valid file of the corpus
        }
        let output = dir.path().join(format!("{name}.ply"));
        let out = beltrami(&["subdivide", s(&input), s(&output)]);
        assert_eq!(
            out.status.code(),
            Some(1),
            "{name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let line = error_line(&out, &bad);
        assert_eq!(line.lines().count(), 1, "{name}: {line}");
        assert!(
            line.starts_with(&format!("error: {name}: ")),
            "{name}: {line}"
        );
        assert!(!output.exists(), "{name}: no output after an error");
    }
}

#[test]
fn a_quad_mesh_is_refused_naming_the_face() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("out.ply");
    let out = beltrami(&[
        "subdivide",
        s(&fixtures().join("cube_quads.obj")),
        s(&output),
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        error_line(&out, &fixtures()),
        "error: cube_quads.obj: face 0 has 4 vertices; subdivide needs a triangle mesh (--repair --triangulate splits the polygons into triangles)"
    );
    assert!(!output.exists());
}

#[test]
fn usage_errors_exit_2_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("icosphere_2.ply");
    let output = dir.path().join("out.ply");
    for args in [
        vec!["--steps", "0"],
        vec!["--steps", "-1"],
        vec!["--steps", "two"],
        vec!["--scheme", "butterfly"],
        vec!["--steps", "40"],
        vec!["--steps", "12", "--scheme", "loop"],
    ] {
        let mut all = vec!["subdivide", s(&input), s(&output)];
        all.extend(&args);
        let out = beltrami(&all);
        assert_eq!(
            out.status.code(),
            Some(2),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        error_line(&out, dir.path());
        assert!(!output.exists(), "{args:?}");
    }
    // The size check names the largest number of steps that fits.
    let out = beltrami(&["subdivide", s(&input), s(&output), "--steps", "40"]);
    let line = error_line(&out, dir.path());
    assert!(line.contains("at most --steps "), "{line}");
    assert!(line.contains("more than 2^64 faces"), "{line}");

    let missing = beltrami(&["subdivide", s(&input)]);
    assert_eq!(missing.status.code(), Some(2));
}

#[test]
fn the_input_is_not_overwritten_without_force() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.ply");
    fs::copy(fixtures().join("icosphere_2.ply"), &input).unwrap();
    let before = fs::read(&input).unwrap();
    let out = beltrami(&["subdivide", s(&input), s(&input)]);
    assert_eq!(out.status.code(), Some(2));
    assert!(error_line(&out, dir.path()).contains("refusing to overwrite the input file"));
    assert_eq!(fs::read(&input).unwrap(), before);
    let out = beltrami(&["subdivide", s(&input), s(&input), "--force"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(read_mesh(&input).unwrap().faces.len(), 4 * 320);
}

/// Under an address-space limit (`ulimit -v`, as a batch system sets one) the memory
/// check counts what the limit leaves, not the machine's free memory: a subdivision
/// that would not fit is refused in one line naming the steps that fit (exit 2, as
/// for `--steps` beyond the machine), where it used to abort with an allocation failure
/// and a backtrace.
#[cfg(target_os = "linux")]
#[test]
fn an_address_space_limit_is_the_memory_available() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("icosphere_2.ply");
    let output = dir.path().join("fine.ply");
    // 162 vertices × 4^9 ≈ 42 million: gigabytes, under a 1.5 GB limit.
    let script = format!(
        "ulimit -v 1500000 && RAYON_NUM_THREADS=1 exec {} subdivide {} {} --steps 9",
        env!("CARGO_BIN_EXE_beltrami"),
        s(&input),
        s(&output)
    );
    let out = std::process::Command::new("sh")
        .args(["-c", &script])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    // What the limit leaves: below its 1 500 000 KiB (1.43 GiB), where the machine has
    // more (the process's own mappings count against it; with one thread the pool
    // starts none besides the main thread).
    let available = stderr
        .split("more than the ")
        .nth(1)
        .and_then(|rest| rest.split(" available").next())
        .and_then(|size| {
            let (n, unit) = size.split_once(' ')?;
            let scale = match unit {
                "GiB" => 1.0,
                "MiB" => 1.0 / 1024.0,
                _ => return None,
            };
            Some(n.parse::<f64>().ok()? * scale)
        })
        .unwrap_or_else(|| panic!("{stderr}"));
    assert!(
        available > 0.5 && available < 1_500_000.0 / 1024.0 / 1024.0,
        "{stderr}"
    );
    assert!(stderr.contains("at most --steps"), "{stderr}");
    assert!(!output.exists());
}
