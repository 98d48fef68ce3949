//! Writes a unit icosphere of the given subdivision level, with a deterministic radial
//! ripple so that smoothing moves every vertex: `icosphere LEVEL OUT [--ascii]`.
//! Level 5 has 10242 vertices, 7 has 163842, 8 has 655362, 9 has 2621442. Used to
//! measure memory and to make large inputs for the reliability tests.

use std::path::PathBuf;

use beltrami_halfedge::primitives;
use beltrami_io::{Encoding, MeshData, WriteOptions, write_mesh};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(level), Some(out)) = (args.first(), args.get(1)) else {
        return Err("usage: icosphere LEVEL OUT [--ascii]".into());
    };
    let p = primitives::icosphere(level.parse()?);
    let positions = p
        .positions
        .iter()
        .map(|&x| x * (1.0 + 0.01 * (7.0 * x.x).sin() * (5.0 * x.y).cos()))
        .collect();
    let encoding = if args.iter().any(|a| a == "--ascii") {
        Encoding::Ascii
    } else {
        Encoding::BinaryLittleEndian
    };
    write_mesh(
        PathBuf::from(out),
        &MeshData {
            positions,
            faces: p.faces,
        },
        &WriteOptions::default().encoding(encoding),
    )?;
    Ok(())
}
