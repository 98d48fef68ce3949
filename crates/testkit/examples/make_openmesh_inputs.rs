//! Writes the input meshes of the OpenMesh references (`fixtures/<name>.ply`) from
//! `beltrami_testkit::fixtures::openmesh_inputs`.
//!
//! ```text
//! cargo run -p beltrami-testkit --example make_openmesh_inputs            # into fixtures/
//! cargo run -p beltrami-testkit --example make_openmesh_inputs -- OUT_DIR  # elsewhere
//! ```
//!
//! The files are binary little-endian PLY with double coordinates, exact to the last bit
//! and byte-identical on every run; a test checks that the committed ones are up to date.
//! After changing a fixture, run this, then `tools/openmesh-ref/regenerate.sh`.

use std::path::{Path, PathBuf};

use beltrami_io::{IoError, WriteOptions, write_mesh};
use beltrami_testkit::fixtures::openmesh_inputs;

/// Writes every input into `dir` and returns the paths written.
///
/// # Errors
/// When a file cannot be written.
pub(crate) fn write_inputs(dir: &Path) -> Result<Vec<PathBuf>, IoError> {
    let mut written = Vec::new();
    for (name, mesh) in openmesh_inputs() {
        let path = dir.join(format!("{name}.ply"));
        write_mesh(&path, &mesh, &WriteOptions::default())?;
        written.push(path);
    }
    Ok(written)
}

fn main() -> Result<(), IoError> {
    let dir = std::env::args_os().nth(1).map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures"),
        PathBuf::from,
    );
    for path in write_inputs(&dir)? {
        println!("{}", path.display());
    }
    Ok(())
}
