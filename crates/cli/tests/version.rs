//! `beltrami --version` names the release and, in a git checkout, the commit.

use std::process::Command;

#[test]
fn version_names_the_release_and_the_commit() {
    let out = Command::new(env!("CARGO_BIN_EXE_beltrami"))
        .arg("--version")
        .output()
        .expect("the binary runs");
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    let expected = format!("beltrami {}", env!("CARGO_PKG_VERSION"));
    assert!(text.starts_with(&expected), "{text}");
    let in_checkout = Command::new("git")
        .args(["rev-parse", "--short=12", "HEAD"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .ok()
        .filter(|o| o.status.success());
    if let Some(head) = in_checkout {
        let head = String::from_utf8(head.stdout).unwrap();
        // The binary was built from this checkout, maybe at an earlier commit of it:
        // the line names a 12-digit hexadecimal commit.
        let commit = text
            .split("(commit ")
            .nth(1)
            .and_then(|rest| rest.split(')').next())
            .unwrap_or_else(|| panic!("no commit in {text:?}"));
        assert_eq!(commit.len(), head.trim().len(), "{text}");
        assert!(commit.chars().all(|c| c.is_ascii_hexdigit()), "{text}");
    }
}
