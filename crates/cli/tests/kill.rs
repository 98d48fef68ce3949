//! A `beltrami` process killed at any moment leaves at its output path the old file
//! or the new one, whole, never a partial file; and the temporary files a kill can
//! leave behind do not disturb the next run.

#![cfg(unix)]

mod common;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Instant;

use beltrami_io::read_mesh;
use common::s;

/// `beltrami generate sphere OUT --noise … --ascii`: 40962 vertices written as about
/// 3.5 MB of text, so that a good share of the run is spent writing.
fn generate(output: &Path) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_beltrami"));
    command
        .args([
            "generate",
            "sphere",
            s(output),
            "--noise",
            "0.2",
            "--relative",
        ])
        .args(["--seed", "3", "--ascii"])
        .stdout(Stdio::null())
        .stderr(Stdio::null());
    command
}

fn temporaries(dir: &Path) -> usize {
    std::fs::read_dir(dir)
        .unwrap()
        .filter(|e| {
            let name = e.as_ref().unwrap().file_name();
            let name = name.to_string_lossy();
            name.starts_with(".beltrami-") && name.ends_with(".tmp")
        })
        .count()
}

#[test]
fn a_killed_writer_leaves_the_old_file_or_the_new_one() {
    let dir = tempfile::tempdir().unwrap();
    // The new file, written by a run that completes (generation is deterministic).
    let reference = dir.path().join("reference.ply");
    let start = Instant::now();
    assert!(generate(&reference).status().unwrap().success());
    let duration = start.elapsed();
    let new = std::fs::read(&reference).unwrap();
    // The old file: the clean sphere.
    let output = dir.path().join("out.ply");
    let status = Command::new(env!("CARGO_BIN_EXE_beltrami"))
        .args(["generate", "sphere", s(&output)])
        .stdout(Stdio::null())
        .status()
        .unwrap();
    assert!(status.success());
    let old = std::fs::read(&output).unwrap();
    assert_ne!(old, new);

    // Kill moments spread over 1.2 times a full run, from a fixed sequence.
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let (mut saw_old, mut saw_new) = (0, 0);
    for _ in 0..40 {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        let fraction = (state >> 11) as f64 / (1u64 << 53) as f64;
        let delay = duration.mul_f64(1.2 * fraction);
        let mut child = generate(&output).spawn().unwrap();
        std::thread::sleep(delay);
        child.kill().ok(); // SIGKILL; fails only when the child has already exited.
        child.wait().unwrap();
        let now = std::fs::read(&output).unwrap();
        if now == old {
            saw_old += 1;
        } else if now == new {
            saw_new += 1;
            std::fs::write(&output, &old).unwrap();
        } else {
            panic!("a partial file at the output path ({} bytes)", now.len());
        }
        assert!(read_mesh(&output).is_ok());
    }
    let left = temporaries(dir.path());
    println!("old {saw_old}, new {saw_new}, temporary files left by kills {left}");

    // The next run is not disturbed by what the kills left: it writes the whole new
    // file and leaves no temporary file of its own.
    assert!(generate(&output).status().unwrap().success());
    assert_eq!(std::fs::read(&output).unwrap(), new);
    assert_eq!(temporaries(dir.path()), left);
}

/// Ctrl-C and `SIGTERM`, unlike `SIGKILL`, reach the process: it removes the temporary
/// file of the output it was writing, leaves the old file in place and exits with 130.
#[test]
fn an_interrupted_writer_leaves_the_old_file_and_no_temporary_file() {
    let dir = tempfile::tempdir().unwrap();
    let reference = dir.path().join("reference.ply");
    let start = Instant::now();
    assert!(generate(&reference).status().unwrap().success());
    let duration = start.elapsed();
    let new = std::fs::read(&reference).unwrap();
    let output = dir.path().join("out.ply");
    std::fs::write(&output, b"old").unwrap();

    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let mut interrupted = 0;
    for signal in ["-TERM", "-INT"].into_iter().cycle().take(24) {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        let fraction = (state >> 11) as f64 / (1u64 << 53) as f64;
        let mut child = generate(&output).spawn().unwrap();
        std::thread::sleep(duration.mul_f64(fraction));
        let _ = Command::new("kill")
            .args([signal, &child.id().to_string()])
            .status();
        let status = child.wait().unwrap();
        let now = std::fs::read(&output).unwrap();
        match status.code() {
            Some(130) => {
                interrupted += 1;
                // Interrupted before the rename: the old file; after it (while the
                // directory was flushed): the whole new one.
                assert!(now == b"old" || now == new, "a partial output");
                std::fs::write(&output, b"old").unwrap();
            }
            Some(0) => {
                assert_eq!(now, new);
                std::fs::write(&output, b"old").unwrap();
            }
            // A signal that arrived before the handler was installed ends the
            // process the default way; the output is untouched then too.
            None => assert_eq!(now, b"old"),
            Some(code) => panic!("exit code {code}"),
        }
        assert_eq!(temporaries(dir.path()), 0, "a temporary file was left");
    }
    assert!(interrupted > 0, "no run was interrupted while writing");
}
