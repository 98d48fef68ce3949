//! The fuzzers' inputs as ordinary tests: every file of the committed, minimised fuzz
//! corpora (`fuzz/corpus/read_{ply,stl,obj,off,x3p,sdf}/`) and every reproducer of a crash
//! found by fuzzing (`fixtures/fuzz/{ply,stl,obj,off,x3p,sdf}/`) reads or fails with an error — never a
//! panic — and an accepted mesh keeps the readers' guarantees: finite coordinates, face
//! indices in range, and a mesh that the half-edge builder takes without panicking.
//!
//! This runs the same checks as the fuzz targets (`fuzz/src/lib.rs`) without cargo-fuzz,
//! on every `cargo test`. See `docs/reliability.md`.

use std::path::{Path, PathBuf};

use beltrami_halfedge::{BuildOptions, HalfedgeMesh};
use beltrami_io::{MeshFormat, read_mesh_from};

fn repository() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The files of `dir`, sorted; none when it does not exist.
fn files(dir: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut files: Vec<PathBuf> = entries
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    files
}

/// What the fuzz targets check for one input.
fn check(bytes: &[u8], format: MeshFormat, name: &str) -> bool {
    let Ok(mesh) = read_mesh_from(bytes, format) else {
        return false;
    };
    let n = mesh.positions.len();
    assert!(
        mesh.positions.iter().all(|p| p.is_finite()),
        "{name}: a non-finite coordinate was accepted"
    );
    if let Some(max) = mesh.faces.max_index() {
        assert!((max as usize) < n, "{name}: index {max} with {n} vertices");
    }
    for options in [BuildOptions::new(), BuildOptions::repair_all()] {
        if let Ok((built, _)) = HalfedgeMesh::build(n, mesh.faces.iter(), &options) {
            assert!(
                built.check_integrity().is_ok(),
                "{name}: built mesh fails its integrity check"
            );
        }
    }
    true
}

fn replay(format: MeshFormat, corpus: &str, reproducers: &str) {
    let root = repository();
    let corpus = files(&root.join("fuzz/corpus").join(corpus));
    let reproducers = files(&root.join("fixtures/fuzz").join(reproducers));
    assert!(
        !corpus.is_empty(),
        "the committed fuzz corpus for {format} is missing"
    );
    let mut accepted = 0;
    for path in corpus.iter().chain(&reproducers) {
        let bytes = std::fs::read(path).expect("corpus file");
        let name = path.display().to_string();
        if check(&bytes, format, &name) {
            accepted += 1;
        }
    }
    // The corpus holds valid meshes as well as broken ones: both paths are exercised.
    assert!(accepted > 0, "no {format} input of the corpus was accepted");
    assert!(
        accepted < corpus.len() + reproducers.len(),
        "every {format} input of the corpus was accepted"
    );
}

#[test]
fn ply_corpus_and_reproducers_read_or_fail_cleanly() {
    replay(MeshFormat::Ply, "read_ply", "ply");
}

#[test]
fn stl_corpus_and_reproducers_read_or_fail_cleanly() {
    replay(MeshFormat::Stl, "read_stl", "stl");
}

#[test]
fn obj_corpus_and_reproducers_read_or_fail_cleanly() {
    replay(MeshFormat::Obj, "read_obj", "obj");
}

#[test]
fn off_corpus_and_reproducers_read_or_fail_cleanly() {
    replay(MeshFormat::Off, "read_off", "off");
}

#[test]
fn x3p_corpus_and_reproducers_read_or_fail_cleanly() {
    replay(MeshFormat::X3p, "read_x3p", "x3p");
}

#[test]
fn sdf_corpus_and_reproducers_read_or_fail_cleanly() {
    replay(MeshFormat::Sdf, "read_sdf", "sdf");
}
