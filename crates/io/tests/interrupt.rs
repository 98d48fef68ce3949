//! `remove_staged_files`, as a signal handler calls it before the process exits: it
//! removes every temporary file of this process and closes the registry, so that no
//! write creates a new one afterwards. It runs in a test binary of its own because it
//! closes the registry for the whole process.

use std::path::Path;

use beltrami_io::{IoError, check_writable, remove_staged_files, stage_bytes, stage_dir};

fn temporaries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name.starts_with(".beltrami-"))
        .collect()
}

fn is_interrupted(e: &IoError) -> bool {
    matches!(e, IoError::Io { source, .. } if source.kind() == std::io::ErrorKind::Interrupted)
}

#[test]
fn remove_staged_files_clears_the_temporaries_and_no_write_follows() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.json");
    std::fs::write(&path, b"old").unwrap();
    let staged = stage_bytes(&path, b"new").unwrap();
    let staged_dir = stage_dir(dir.path().join("results")).unwrap();
    assert_eq!(temporaries(dir.path()).len(), 2);

    assert_eq!(remove_staged_files(), 2);
    assert!(temporaries(dir.path()).is_empty());

    // The staged outputs cannot be committed any more; the targets are untouched.
    assert!(staged.commit().is_err());
    assert!(staged_dir.commit().is_err());
    assert_eq!(std::fs::read(&path).unwrap(), b"old");
    assert!(!dir.path().join("results").exists());

    // No new temporary file is created: a write, a staged directory and the
    // writability probe all fail as interrupted.
    let late = stage_bytes(&path, b"late").unwrap_err();
    assert!(is_interrupted(&late), "{late:?}");
    let late_dir = stage_dir(dir.path().join("later")).unwrap_err();
    assert!(is_interrupted(&late_dir), "{late_dir:?}");
    let probe = check_writable(&path).unwrap_err();
    assert!(is_interrupted(&probe), "{probe:?}");
    assert!(temporaries(dir.path()).is_empty());
    assert_eq!(std::fs::read(&path).unwrap(), b"old");
    assert_eq!(remove_staged_files(), 0);
}
