//! Guards for output files: a command never overwrites one of its inputs unless told
//! to with `--force`.

use std::path::{Path, PathBuf};

use crate::error::CliError;

/// Whether `a` and `b` name the same existing file: the same path after resolving
/// symbolic links and `..`, or (on Unix) the same inode on the same device, which also
/// catches hard links. A path that does not exist names no input.
pub(crate) fn same_file(a: &Path, b: &Path) -> bool {
    let (Ok(ma), Ok(mb)) = (std::fs::metadata(a), std::fs::metadata(b)) else {
        return false;
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if ma.dev() == mb.dev() && ma.ino() == mb.ino() {
            return true;
        }
    }
    let _ = (ma, mb);
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(ca), Ok(cb)) => ca == cb,
        _ => false,
    }
}

/// Fails with [`CliError::OverwritesInput`] when `output` is one of `inputs` and
/// `force` is not set. Call it before reading anything, so that a refused run changes
/// nothing.
pub(crate) fn check_not_input(
    output: &Path,
    inputs: &[&PathBuf],
    force: bool,
) -> Result<(), CliError> {
    if force {
        return Ok(());
    }
    match inputs.iter().find(|input| same_file(output, input)) {
        Some(input) => Err(CliError::OverwritesInput {
            output: output.to_path_buf(),
            input: (*input).clone(),
        }),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn links_and_aliases_are_the_same_file() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.ply");
        std::fs::write(&a, b"x").unwrap();
        let b = dir.path().join("b.ply");
        std::fs::write(&b, b"x").unwrap();
        let alias = dir.path().join(".").join("a.ply");
        assert!(same_file(&a, &alias));
        assert!(!same_file(&a, &b));
        assert!(!same_file(&a, &dir.path().join("missing.ply")));
        let hard = dir.path().join("hard.ply");
        std::fs::hard_link(&a, &hard).unwrap();
        assert!(same_file(&a, &hard));
        #[cfg(unix)]
        {
            let soft = dir.path().join("soft.ply");
            std::os::unix::fs::symlink(&a, &soft).unwrap();
            assert!(same_file(&a, &soft));
        }
        assert!(check_not_input(&hard, &[&b, &a], false).is_err());
        assert!(check_not_input(&hard, &[&b, &a], true).is_ok());
        assert!(check_not_input(&b, &[&a], false).is_ok());
    }
}
