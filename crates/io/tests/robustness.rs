//! Mangled files never panic: every prefix and many random mutations of every
//! fixture either read or give an error.

mod common;

use std::path::Path;

use beltrami_io::{MeshFormat, read_mesh_from};
use common::{Lcg, fixture};

const FIXTURES: [&str; 15] = [
    "tetrahedron_ascii.ply",
    "tetrahedron_le.ply",
    "tetrahedron_be.ply",
    "cube_binary.stl",
    "cube_ascii.stl",
    "cube.obj",
    "cube_ascii.ply",
    "hexagon_fan_ascii.ply",
    "hexagon_fan.obj",
    "grid_4x3.ply",
    "grid_4x3.obj",
    "torus_12x8.ply",
    "icosphere_2.ply",
    "icosphere_2.stl",
    "cube_quads.obj",
];

fn load(name: &str) -> (Vec<u8>, MeshFormat) {
    let path = fixture(name);
    let format = MeshFormat::from_path(Path::new(name)).expect("format");
    (std::fs::read(path).expect("fixture"), format)
}

#[test]
fn every_prefix_reads_or_fails_cleanly() {
    for name in FIXTURES {
        let (bytes, format) = load(name);
        let step = (bytes.len() / 400).max(1);
        for end in (0..bytes.len()).step_by(step) {
            let _ = read_mesh_from(&bytes[..end], format);
        }
    }
}

#[test]
fn random_mutations_read_or_fail_cleanly() {
    let mut rng = Lcg(42);
    for name in FIXTURES {
        let (bytes, format) = load(name);
        for _ in 0..300 {
            let mut mutated = bytes.clone();
            for _ in 0..1 + rng.below(4) {
                let at = rng.below(mutated.len());
                match rng.below(4) {
                    0 => mutated[at] = rng.next_u64() as u8,
                    1 => mutated[at] ^= 1 << rng.below(8),
                    2 => {
                        mutated.remove(at);
                    }
                    _ => mutated.insert(at, b"0123456789 -\n"[rng.below(13)]),
                }
            }
            // Reading as every format: an STL read as PLY must fail cleanly too.
            for other in [
                MeshFormat::Ply,
                MeshFormat::Stl,
                MeshFormat::Obj,
                MeshFormat::Off,
            ] {
                let _ = read_mesh_from(&mutated[..], other);
            }
            let _ = format;
        }
    }
}

#[test]
fn header_counts_are_guarded_for_every_element() {
    // Huge counts in each position of a binary header.
    let (bytes, _) = load("tetrahedron_le.ply");
    let text = String::from_utf8_lossy(&bytes).into_owned();
    for (from, to) in [
        ("element vertex 4", "element vertex 4294967295"),
        ("element face 4", "element face 4294967295"),
        ("element vertex 4", "element vertex 18446744073709551615"),
    ] {
        let header_end = text.find("end_header\n").expect("header") + 11;
        let mut mangled = text[..header_end].replace(from, to).into_bytes();
        mangled.extend_from_slice(&bytes[header_end..]);
        assert!(
            read_mesh_from(&mangled[..], MeshFormat::Ply).is_err(),
            "{to}"
        );
    }
}
