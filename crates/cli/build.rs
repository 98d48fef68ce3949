//! Records the commit the binary is built from, for `beltrami --version`, so that a
//! benchmark or a bug report can name the exact sources. Outside a git checkout (a
//! source package) the version is the crate's alone. The commit is HEAD's when the
//! binary was built.

use std::path::PathBuf;
use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git").args(args).output().ok()?;
    if !out.status.success() {
        return None;
    }
    let text = String::from_utf8(out.stdout).ok()?;
    Some(text.trim().to_string())
}

fn main() {
    let version = env!("CARGO_PKG_VERSION");
    let long = match git(&["rev-parse", "--short=12", "HEAD"]) {
        Some(commit) => {
            // Rebuild when HEAD moves or the index changes (a commit, a checkout).
            for name in ["HEAD", "index"] {
                if let Some(path) = git(&["rev-parse", "--git-path", name]) {
                    let path = PathBuf::from(path);
                    let path = if path.is_absolute() {
                        path
                    } else {
                        std::env::current_dir().unwrap_or_default().join(path)
                    };
                    println!("cargo:rerun-if-changed={}", path.display());
                }
            }
            let branch = git(&["symbolic-ref", "-q", "HEAD"])
                .and_then(|reference| git(&["rev-parse", "--git-path", &reference]));
            if let Some(path) = branch {
                println!("cargo:rerun-if-changed={path}");
            }
            // Uncommitted edits are not flagged: the script does not rerun when a source
            // file changes, so such a flag could be stale.
            format!("{version} (commit {commit})")
        }
        None => version.to_string(),
    };
    println!("cargo:rustc-env=BELTRAMI_LONG_VERSION={long}");
    println!("cargo:rerun-if-changed=build.rs");
}
