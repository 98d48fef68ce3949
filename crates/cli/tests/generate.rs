//! `beltrami generate` as a user runs it.

use std::process::{Command, Output};

use beltrami_io::read_mesh;
use serde_json::Value;

fn beltrami(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_beltrami"))
        .args(args)
        .output()
        .expect("the binary runs")
}

#[test]
fn every_surface_is_written_with_its_counts() {
    let dir = tempfile::tempdir().unwrap();
    for (name, vertices, faces, closed) in [
        ("flens", 2244, 4288, false),
        ("sphere", 40962, 81920, true),
        ("block", 8780, 17568, true),
        ("golfball", 79212, 158420, true),
    ] {
        let path = dir.path().join(format!("{name}.ply"));
        let out = beltrami(&["generate", name, path.to_str().unwrap()]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let info = beltrami(&["info", path.to_str().unwrap(), "--json"]);
        let j: Value = serde_json::from_slice(&info.stdout).unwrap();
        assert_eq!(j["vertices"], vertices, "{name}");
        assert_eq!(j["faces"], faces, "{name}");
        assert_eq!(j["closed"], closed, "{name}");
    }
}

#[test]
fn noise_is_seeded_and_the_clean_surface_is_kept() {
    let dir = tempfile::tempdir().unwrap();
    let p = |n: &str| dir.path().join(n).to_str().unwrap().to_string();
    let run = |out: &str, seed: &str| {
        let o = beltrami(&[
            "generate",
            "flens",
            &p(out),
            "--noise",
            "0.2",
            "--relative",
            "--seed",
            seed,
            "--clean",
            &p("clean.ply"),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8(o.stdout).unwrap()
    };
    let text = run("a.ply", "7");
    assert!(text.contains("normal noise sigma ="), "{text}");
    run("b.ply", "7");
    run("c.ply", "8");
    let read = |n: &str| std::fs::read(p(n)).unwrap();
    assert_eq!(read("a.ply"), read("b.ply"), "same seed, same bytes");
    assert_ne!(read("a.ply"), read("c.ply"));
    let clean = read_mesh(std::path::Path::new(&p("clean.ply"))).unwrap();
    let noisy = read_mesh(std::path::Path::new(&p("a.ply"))).unwrap();
    assert_eq!(clean.faces, noisy.faces);
    assert_ne!(clean.positions, noisy.positions);
}

#[test]
fn bad_usage_is_exit_2() {
    let out = beltrami(&["generate", "teapot", "x.ply"]);
    assert_eq!(out.status.code(), Some(2));
    let out = beltrami(&["generate", "flens", "x.ply", "--relative"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8(out.stderr).unwrap();
    // The parser's whole message, naming what is missing.
    assert!(
        stderr.starts_with(
            "error: the following required arguments were not provided:\n  --noise <NOISE>"
        ),
        "{stderr}"
    );
    let out = beltrami(&["generate", "flens", "x.ply", "--noise", "-1"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(
        stderr.contains("-1"),
        "a negative value reaches the check: {stderr}"
    );
    // A height map holds metres and the surfaces are in mm: refused, before any work,
    // for OUTPUT and --clean alike (a flens written as .x3p read back 1000 times too
    // large).
    let dir = tempfile::tempdir().unwrap();
    for args in [
        vec!["generate", "flens", "a.x3p"],
        vec!["generate", "sphere", "a.sdf"],
        vec![
            "generate", "flens", "a.ply", "--noise", "0.2", "--clean", "c.x3p",
        ],
    ] {
        let args: Vec<String> = args
            .iter()
            .map(|a| {
                if [".x3p", ".sdf", ".ply"].iter().any(|e| a.ends_with(e)) {
                    dir.path().join(a).display().to_string()
                } else {
                    (*a).to_string()
                }
            })
            .collect();
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = beltrami(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let stderr = String::from_utf8(out.stderr).unwrap();
        assert!(
            stderr.contains("cannot write") && stderr.contains("a height map holds metres"),
            "{stderr}"
        );
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            0,
            "{args:?}"
        );
    }
}

#[test]
fn sphere_level_sets_the_subdivisions_and_is_refused_elsewhere() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.ply");
    let path = path.to_str().unwrap();
    // Level L: 10 * 4^L + 2 vertices, 20 * 4^L faces.
    for (level, vertices, faces) in [("0", 12, 20), ("2", 162, 320), ("4", 2562, 5120)] {
        let out = beltrami(&["generate", "sphere", path, "--level", level]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let mesh = read_mesh(std::path::Path::new(path)).unwrap();
        assert_eq!(mesh.positions.len(), vertices, "level {level}");
        assert_eq!(mesh.faces.len(), faces, "level {level}");
        for p in &mesh.positions {
            assert!((p.length() - 1.0).abs() < 1e-12, "level {level}: {p}");
        }
    }
    for (surface, level) in [("flens", "3"), ("sphere", "12")] {
        let out = beltrami(&["generate", surface, path, "--level", level]);
        assert!(
            !out.status.success(),
            "{surface} --level {level} was accepted"
        );
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(err.starts_with("error: ") && err.contains("level"), "{err}");
    }
}

#[test]
fn shuffle_renumbers_the_vertices_of_the_same_surface() {
    let dir = tempfile::tempdir().unwrap();
    let p = |n: &str| dir.path().join(n).to_str().unwrap().to_string();
    let make = |out: &str, clean: &str, extra: &[&str]| {
        let mut args = vec![
            "generate",
            "sphere",
            out,
            "--level",
            "3",
            "--noise",
            "0.2",
            "--relative",
            "--seed",
            "5",
            "--clean",
            clean,
        ];
        args.extend_from_slice(extra);
        let o = beltrami(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    make(&p("plain.ply"), &p("plain_clean.ply"), &[]);
    make(&p("a.ply"), &p("a_clean.ply"), &["--shuffle", "9"]);
    make(&p("b.ply"), &p("b_clean.ply"), &["--shuffle", "9"]);
    make(&p("c.ply"), &p("c_clean.ply"), &["--shuffle", "10"]);
    let bytes = |n: &str| std::fs::read(p(n)).unwrap();
    assert_eq!(bytes("a.ply"), bytes("b.ply"), "same seed, same file");
    assert_ne!(
        bytes("a.ply"),
        bytes("c.ply"),
        "another seed, another order"
    );
    assert_ne!(bytes("a.ply"), bytes("plain.ply"), "the order changed");
    let read = |n: &str| read_mesh(std::path::Path::new(&p(n))).unwrap();
    for (plain, shuffled) in [("plain.ply", "a.ply"), ("plain_clean.ply", "a_clean.ply")] {
        let (plain, shuffled) = (read(plain), read(shuffled));
        assert_eq!(plain.faces.len(), shuffled.faces.len());
        // Face f has the same corner points in the same order.
        for (f, g) in plain.faces.iter().zip(shuffled.faces.iter()) {
            for (&u, &v) in f.iter().zip(g) {
                assert_eq!(plain.positions[u as usize], shuffled.positions[v as usize]);
            }
        }
        // Every vertex is used (the icosphere has no isolated vertex), so the faces
        // matching corner by corner make the renumbering a bijection of the same points.
        let mut a: Vec<[u64; 3]> = plain
            .positions
            .iter()
            .map(|q| q.to_array().map(f64::to_bits))
            .collect();
        let mut b: Vec<[u64; 3]> = shuffled
            .positions
            .iter()
            .map(|q| q.to_array().map(f64::to_bits))
            .collect();
        a.sort_unstable();
        b.sort_unstable();
        assert_eq!(a, b);
    }
}

#[test]
fn holes_are_cut_into_the_noisy_surface_and_the_reference_stays_whole() {
    let dir = tempfile::tempdir().unwrap();
    let p = |n: &str| dir.path().join(n).to_str().unwrap().to_string();
    let out = beltrami(&[
        "generate",
        "flens",
        &p("scan.ply"),
        "--noise",
        "0.1",
        "--holes",
        "3",
        "--clean",
        &p("clean.ply"),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("3 holes of radius"), "{text}");
    let scan = read_mesh(std::path::Path::new(&p("scan.ply"))).unwrap();
    let clean = read_mesh(std::path::Path::new(&p("clean.ply"))).unwrap();
    assert!(scan.faces.len() < clean.faces.len());
    assert_eq!(
        clean.positions.len(),
        2244,
        "the reference is the whole lens"
    );
    let loops = |m: &beltrami_io::MeshData| m.mesh().unwrap().boundary_loops().count();
    assert_eq!(loops(&scan), loops(&clean) + 3);
    // The same noise with and without holes: every kept vertex is a noisy vertex.
    let out = beltrami(&["generate", "flens", &p("noisy.ply"), "--noise", "0.1"]);
    assert!(out.status.success());
    let noisy = read_mesh(std::path::Path::new(&p("noisy.ply"))).unwrap();
    assert!(scan.positions.iter().all(|q| noisy.positions.contains(q)));
    // Holes without noise need no --noise; bad combinations are usage errors.
    let out = beltrami(&["generate", "sphere", &p("holed.ply"), "--holes", "2"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for bad in [
        &["--holes", "1", "--shuffle", "3"][..],
        &["--holes", "500"],
        &["--holes", "1", "--hole-radius", "0"],
        &["--seed", "4"],
        &["--clean", "c.ply"],
    ] {
        let mut args = vec!["generate", "flens", "bad.ply"];
        args.extend_from_slice(bad);
        let out = beltrami(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{bad:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{bad:?}: {err}");
    }
    assert!(!std::path::Path::new("bad.ply").exists());
}
