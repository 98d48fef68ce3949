//! Times the phases of a closest-point RMS: index build and queries, on a noisy icosphere
//! against the clean one (the test case of `benches/distance.rs`), and prints the RMS so
//! that runs can be checked against each other.
//!
//! `cargo run --release -p beltrami-metrics --example distance_phases -- [LEVEL] [REPS]`
//! (level 8 by default: 655 362 points, 1 310 720 triangles; 3 repetitions). Small levels
//! suit `valgrind --tool=callgrind`.

use std::time::Instant;

use beltrami_halfedge::{DVec3, primitives};
use beltrami_metrics::distance::SurfaceIndex;

/// SplitMix64 with Box–Muller normals, as in the bench.
struct Rng(u64);

impl Rng {
    fn next_f64(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn normal(&mut self) -> f64 {
        let u = 1.0 - self.next_f64();
        let v = self.next_f64();
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let level: u32 = args.next().map_or(Ok(8), |a| a.parse())?;
    let reps: usize = args.next().map_or(Ok(3), |a| a.parse())?;
    let sphere = primitives::icosphere(level);
    let mesh = sphere.mesh()?;
    let sigma = 0.2 * 1.1 / f64::from(1u32 << level);
    let mut rng = Rng(0x5EED);
    let noisy: Vec<DVec3> = sphere
        .positions
        .iter()
        .map(|p| *p + DVec3::new(rng.normal(), rng.normal(), rng.normal()) * sigma)
        .collect();
    println!(
        "level {level}: {} points, {} triangles, {} threads",
        noisy.len(),
        mesh.n_faces(),
        rayon::current_num_threads()
    );
    for _ in 0..reps {
        let t = Instant::now();
        let index = SurfaceIndex::new(&mesh, &sphere.positions)?;
        let build = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let d = index.distances(&noisy)?;
        let queries = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let s = index.signed_distances(&noisy)?;
        let signed = t.elapsed().as_secs_f64();
        let rms = (d.iter().map(|d| d * d).sum::<f64>() / d.len() as f64).sqrt();
        let bias = s.iter().sum::<f64>() / s.len() as f64;
        println!(
            "build {build:.3} s, queries {queries:.3} s, signed (incl. pseudo-normals) {signed:.3} s, rms {rms:.9e}, mean signed {bias:.6e}"
        );
    }
    Ok(())
}
