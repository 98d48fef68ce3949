//! Writes replace the target atomically: on error nothing is left behind.

use std::fs;
use std::path::Path;

use beltrami_halfedge::primitives;
use beltrami_io::{
    IoError, MeshData, VertexAttributes, WriteOptions, read_mesh, write_mesh, write_ply,
};

/// The names in a directory, sorted.
fn entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .expect("read dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn writing_into_a_missing_directory_fails_and_leaves_nothing() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let target = dir.path().join("missing").join("cube.ply");
    let cube: MeshData = primitives::cube();
    let e = write_mesh(&target, &cube, &WriteOptions::default()).expect_err("no directory");
    assert!(matches!(
        e,
        IoError::Io {
            operation: "create a file in the output's directory",
            ..
        }
    ));
    // The system's message and the directory, not the bare kind ("entity not found")
    // or the temporary file's name.
    let text = e.to_string();
    assert!(text.contains("No such file or directory"), "{text}");
    assert!(text.contains("missing"), "{text}");
    assert!(!text.contains(".beltrami-"), "{text}");
    assert!(!target.exists());
    assert!(entries(dir.path()).is_empty());
}

#[test]
fn a_failing_write_leaves_the_existing_file_byte_identical() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let target = dir.path().join("scan.ply");
    let cube: MeshData = primitives::cube();
    write_mesh(&target, &cube, &WriteOptions::default()).expect("first write");
    let before = fs::read(&target).expect("read");

    let wrong = VertexAttributes {
        scalars: vec![("deviation".to_owned(), vec![0.0; 3])],
        colors: None,
    };
    let e = write_ply(&target, &cube, &wrong, &WriteOptions::default()).expect_err("length");
    assert!(matches!(e, IoError::AttributeLength { .. }));
    assert_eq!(fs::read(&target).expect("read"), before);
    assert_eq!(entries(dir.path()), ["scan.ply"]);

    let mut nan = cube.clone();
    nan.positions[0].x = f64::NAN;
    write_mesh(&target, &nan, &WriteOptions::default()).expect_err("nan");
    assert_eq!(fs::read(&target).expect("read"), before);
    assert_eq!(entries(dir.path()), ["scan.ply"]);
}

#[test]
fn a_successful_write_replaces_the_file_and_leaves_no_temporary() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let target = dir.path().join("mesh.obj");
    fs::write(&target, "old content").expect("write");
    let torus: MeshData = primitives::torus(2.0, 0.5, 12, 8);
    write_mesh(&target, &torus, &WriteOptions::default()).expect("write");
    assert_eq!(read_mesh(&target).expect("read"), torus);
    assert_eq!(entries(dir.path()), ["mesh.obj"]);
}

#[cfg(unix)]
#[test]
fn permissions_are_kept_for_existing_files_and_ordinary_for_new_ones() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().expect("temporary directory");
    let cube: MeshData = primitives::cube();

    let fresh = dir.path().join("fresh.stl");
    write_mesh(&fresh, &cube, &WriteOptions::default()).expect("write");
    let mode = fs::metadata(&fresh).expect("metadata").permissions().mode();
    // Readable by others unless the umask forbids it; never the 0o600 of a temporary.
    assert_eq!(mode & 0o600, 0o600);
    assert_ne!(mode & 0o777, 0o600, "mode {mode:o}");

    let existing = dir.path().join("existing.stl");
    fs::write(&existing, "x").expect("write");
    fs::set_permissions(&existing, fs::Permissions::from_mode(0o640)).expect("chmod");
    write_mesh(&existing, &cube, &WriteOptions::default()).expect("write");
    let mode = fs::metadata(&existing)
        .expect("metadata")
        .permissions()
        .mode();
    assert_eq!(mode & 0o777, 0o640);
}

#[test]
fn a_relative_path_without_directory_is_written_in_the_current_directory() {
    // `Path::parent` of "x.ply" is "", which must mean ".".
    let dir = tempfile::tempdir().expect("temporary directory");
    let cwd = std::env::current_dir().expect("cwd");
    std::env::set_current_dir(dir.path()).expect("cd");
    let result = write_mesh(
        Path::new("plain.ply"),
        &primitives::triangle(),
        &WriteOptions::default(),
    );
    std::env::set_current_dir(cwd).expect("cd back");
    result.expect("write");
    assert_eq!(entries(dir.path()), ["plain.ply"]);
}
