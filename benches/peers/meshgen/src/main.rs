//! `peers-meshgen LEVEL NOISY.ply CLEAN.ply [SIGMA_REL] [SEED]`
//!
//! Writes the unit icosphere with LEVEL subdivisions (`beltrami_surfaces::sphere`, the
//! surface `beltrami generate sphere` writes at level 6) twice as binary little-endian
//! PLY (`double` coordinates, `uchar int` face lists): with Gaussian noise along the
//! vertex normals of standard deviation SIGMA_REL × mean edge length (default 0.2) from
//! the platform-independent generator seeded with SEED (default 1), and clean.
//! `beltrami generate` offers the sphere at level 6 only; the peer comparison also
//! needs level 8 (655 362 vertices).

use std::path::PathBuf;
use std::process::ExitCode;

use beltrami_io::{Encoding, MeshData, WriteOptions, write_mesh};
use beltrami_surfaces::{NoiseLevel, add_normal_noise, sphere};

fn run(args: &[String]) -> Result<String, String> {
    let [level, noisy, clean, rest @ ..] = args else {
        return Err("usage: peers-meshgen LEVEL NOISY.ply CLEAN.ply [SIGMA_REL] [SEED]".into());
    };
    let level: u32 = level.parse().map_err(|_| format!("bad level {level:?}"))?;
    if level > 10 {
        return Err(format!(
            "level {level} is too large for a benchmark (at most 10)"
        ));
    }
    let sigma_rel: f64 = match rest.first() {
        Some(s) => s.parse().map_err(|_| format!("bad sigma {s:?}"))?,
        None => 0.2,
    };
    let seed: u64 = match rest.get(1) {
        Some(s) => s.parse().map_err(|_| format!("bad seed {s:?}"))?,
        None => 1,
    };
    let surface = sphere(level);
    let mesh = surface.mesh().map_err(|e| e.to_string())?;
    let (positions, sigma) = add_normal_noise(
        &mesh,
        &surface.positions,
        NoiseLevel::RelativeToMeanEdge(sigma_rel),
        seed,
    )
    .map_err(|e| e.to_string())?;
    let options = WriteOptions {
        encoding: Encoding::BinaryLittleEndian,
        ..WriteOptions::default()
    };
    for (path, positions) in [(noisy, positions), (clean, surface.positions.clone())] {
        let data = MeshData {
            positions,
            faces: surface.faces.clone(),
        };
        write_mesh(&PathBuf::from(path), &data, &options).map_err(|e| format!("{path}: {e}"))?;
    }
    Ok(format!(
        "icosphere level {level}: {} vertices, {} faces, noise sigma {sigma:.6e} (seed {seed}) -> {noisy}, clean -> {clean}",
        mesh.n_vertices(),
        mesh.n_faces()
    ))
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match run(&args) {
        Ok(line) => {
            println!("{line}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
