//! The committed inputs of the OpenMesh references are what the fixture functions make.

#[path = "../examples/make_openmesh_inputs.rs"]
#[allow(dead_code, reason = "only `write_inputs` is used here")]
mod make_openmesh_inputs;

use std::path::Path;

use beltrami_testkit::fixtures::openmesh_inputs;

fn fixtures_dir() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures"))
}

#[test]
fn committed_inputs_are_up_to_date() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let written = make_openmesh_inputs::write_inputs(dir.path()).expect("write");
    assert_eq!(written.len(), openmesh_inputs().len());
    for path in written {
        let name = path.file_name().expect("file name");
        let fresh = std::fs::read(&path).expect("generated");
        let committed = std::fs::read(fixtures_dir().join(name)).unwrap_or_default();
        assert!(
            fresh == committed,
            "fixtures/{} is stale or missing: run `cargo run -p beltrami-testkit --example \
             make_openmesh_inputs`, then `tools/openmesh-ref/regenerate.sh`",
            name.to_string_lossy()
        );
    }
}

#[test]
fn committed_inputs_read_back_bit_for_bit() {
    for (name, mesh) in openmesh_inputs() {
        let read = beltrami_io::read_mesh(fixtures_dir().join(format!("{name}.ply")))
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(read.faces, mesh.faces, "{name}");
        let same = read
            .positions
            .iter()
            .zip(&mesh.positions)
            .all(|(a, b)| a.to_array().map(f64::to_bits) == b.to_array().map(f64::to_bits));
        assert!(
            same && read.positions.len() == mesh.positions.len(),
            "{name}"
        );
    }
}
