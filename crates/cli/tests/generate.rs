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
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    let out = beltrami(&["generate", "flens", "x.ply", "--noise", "-1"]);
    assert_eq!(out.status.code(), Some(2));
}
