//! Times the phases of a closest-point RMS: index build and queries, on a noisy icosphere
//! against the clean one (the test case of `benches/distance.rs`), or on two binary PLY
//! files (`beltrami generate sphere --level 8 --noise 0.2 --relative --seed 18 s8.ply
//! --clean s8c.ply`, the case of `beltrami compare`), and prints the RMS so that runs can be
//! checked against each other.
//!
//! ```text
//! cargo run --release -p beltrami-metrics --example distance_phases -- \
//!     [LEVEL | MESH.ply REFERENCE.ply] [REPS] [PHASES] [DUMP]
//! ```
//!
//! - `LEVEL`: icosphere level (8 by default: 655 362 points, 1 310 720 triangles);
//! - `REPS`: repetitions (3 by default);
//! - `PHASES`: `all` (default: index build, unsigned pass, signed pass), `distances` (index
//!   build and one unsigned pass), `build` (index build only) or `none` (set-up only).
//!   Under `valgrind --tool=callgrind`, the differences of the totals of `none`, `build`
//!   and `distances` are the instruction counts of the index build and of one query pass;
//! - `DUMP`: with `all`, a file to write every result to (the `f64` bits of the unsigned
//!   and signed distances, the closest face and feature of each point, little-endian), so
//!   that two builds can be compared with `cmp`.

use std::io::Write;
use std::time::Instant;

use beltrami_halfedge::{DVec3, HalfedgeMesh};
use beltrami_metrics::distance::{Feature, SurfaceIndex};
use beltrami_testkit::fixtures::gaussian_noisy_icosphere;

/// Reads the binary PLY that `beltrami generate` writes (`double x, y, z` per vertex, a
/// `uchar`-counted `int` list per face, triangles only): exactly that layout, any other is
/// rejected.
fn read_ply(path: &str) -> Result<(Vec<DVec3>, HalfedgeMesh), Box<dyn std::error::Error>> {
    let bytes = std::fs::read(path)?;
    let end = b"end_header\n";
    let header_len = bytes
        .windows(end.len())
        .position(|w| w == end)
        .ok_or("no PLY header")?
        + end.len();
    let header = std::str::from_utf8(&bytes[..header_len])?;
    let count = |element: &str| -> Result<usize, Box<dyn std::error::Error>> {
        let line = header
            .lines()
            .find(|l| l.starts_with(&format!("element {element} ")))
            .ok_or("missing element")?;
        Ok(line.rsplit(' ').next().unwrap_or("").parse()?)
    };
    let (n_vertices, n_faces) = (count("vertex")?, count("face")?);
    let expected = "format binary_little_endian 1.0\nelement vertex N\nproperty double x\n\
                    property double y\nproperty double z\nelement face M\n\
                    property list uchar int vertex_indices\nend_header";
    let layout: Vec<String> = header
        .lines()
        .filter(|l| !l.starts_with("comment") && *l != "ply")
        .map(|l| {
            l.replace(&format!("vertex {n_vertices}"), "vertex N")
                .replace(&format!("face {n_faces}"), "face M")
        })
        .collect();
    if layout.join("\n") != expected {
        return Err("not the binary PLY layout of `beltrami generate`".into());
    }
    let body = &bytes[header_len..];
    if body.len() != 24 * n_vertices + 13 * n_faces {
        return Err("unexpected PLY body length".into());
    }
    let f64_at = |o: usize| f64::from_le_bytes(body[o..o + 8].try_into().expect("8 bytes"));
    let positions = (0..n_vertices)
        .map(|v| DVec3::new(f64_at(24 * v), f64_at(24 * v + 8), f64_at(24 * v + 16)))
        .collect();
    let faces = body[24 * n_vertices..].chunks_exact(13);
    if faces.clone().any(|face| face[0] != 3) {
        return Err("not a triangle mesh".into());
    }
    let triangles: Vec<[u32; 3]> = faces
        .map(|face| {
            std::array::from_fn(|k| {
                u32::from_le_bytes(face[1 + 4 * k..5 + 4 * k].try_into().expect("4 bytes"))
            })
        })
        .collect();
    let mesh = HalfedgeMesh::from_polygons(n_vertices, &triangles)?;
    Ok((positions, mesh))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (noisy, reference, mesh, rest) = if args.first().is_some_and(|a| a.ends_with(".ply")) {
        let (noisy, _) = read_ply(&args[0])?;
        let (reference, mesh) = read_ply(args.get(1).ok_or("missing REFERENCE.ply")?)?;
        (noisy, reference, mesh, &args[2..])
    } else {
        let level: u32 = args.first().map_or(Ok(8), |a| a.parse())?;
        let sigma = 0.2 * 1.1 / f64::from(1u32 << level);
        let (sphere, noisy) = gaussian_noisy_icosphere(level, sigma, 0x5EED);
        let mesh = sphere.mesh()?;
        (noisy, sphere.positions, mesh, args.get(1..).unwrap_or(&[]))
    };
    let reps: usize = rest.first().map_or(Ok(3), |a| a.parse())?;
    let phases = rest.get(1).map_or("all", String::as_str);
    let dump = rest.get(2);
    println!(
        "{} points, {} triangles, {} threads, phases {phases}",
        noisy.len(),
        mesh.n_faces(),
        rayon::current_num_threads()
    );
    for _ in 0..reps {
        match phases {
            "none" => {}
            "build" => {
                let t = Instant::now();
                let index = SurfaceIndex::new(&mesh, &reference)?;
                println!(
                    "build {:.3} s ({} faces)",
                    t.elapsed().as_secs_f64(),
                    index.n_faces()
                );
            }
            "distances" | "all" => {
                // The index build and one unsigned query pass (both phases).
                let t = Instant::now();
                let index = SurfaceIndex::new(&mesh, &reference)?;
                let build = t.elapsed().as_secs_f64();
                let t = Instant::now();
                let d = index.distances(&noisy)?;
                let queries = t.elapsed().as_secs_f64();
                let rms = (d.iter().map(|d| d * d).sum::<f64>() / d.len() as f64).sqrt();
                if phases == "distances" {
                    println!("build {build:.3} s, queries {queries:.3} s, rms {rms:.9e}");
                    continue;
                }
                let t = Instant::now();
                let s = index.signed_distances(&noisy)?;
                let signed = t.elapsed().as_secs_f64();
                let bias = s.iter().sum::<f64>() / s.len() as f64;
                println!(
                    "build {build:.3} s, queries {queries:.3} s, signed (incl. pseudo-normals) {signed:.3} s, rms {rms:.9e}, mean signed {bias:.6e}"
                );
                if let Some(path) = dump {
                    let closest = index.closest_points(&noisy)?;
                    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
                    for ((d, s), c) in d.iter().zip(&s).zip(&closest) {
                        out.write_all(&d.to_bits().to_le_bytes())?;
                        out.write_all(&s.to_bits().to_le_bytes())?;
                        out.write_all(&c.distance_squared.to_bits().to_le_bytes())?;
                        for x in c.point.to_array() {
                            out.write_all(&x.to_bits().to_le_bytes())?;
                        }
                        let (kind, id) = match c.feature {
                            Feature::Face => (0u32, 0u32),
                            Feature::Edge(e) => (1, e.raw()),
                            Feature::Vertex(v) => (2, v.raw()),
                        };
                        for x in [c.face.raw(), kind, id] {
                            out.write_all(&x.to_le_bytes())?;
                        }
                    }
                }
            }
            other => return Err(format!("unknown PHASES {other}").into()),
        }
    }
    Ok(())
}
