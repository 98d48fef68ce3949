//! Closest-point RMS of a noisy icosphere's vertices against a clean icosphere: level 8
//! (655 362 query points, 1 310 720 reference triangles) and level 6. Three cases per level:
//! the index build alone (`index_build`), the queries against a built index (`queries`:
//! unsigned distances of every noisy vertex), and both with the RMS (`rms`, the closest-point
//! figure of `docs/performance.md`).
//!
//! Run with `cargo bench -p beltrami-metrics --bench distance`.

// `criterion_group!` generates an undocumented public function.
#![allow(missing_docs)]

use beltrami_halfedge::DVec3;
use beltrami_halfedge::primitives;
use beltrami_metrics::distance::{SurfaceIndex, distance_stats};
use criterion::{Criterion, criterion_group, criterion_main};

/// SplitMix64 with Box–Muller normals, for reproducible noise.
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

fn bench_level(c: &mut Criterion, level: u32, samples: usize) {
    let sphere = primitives::icosphere(level);
    let mesh = sphere.mesh().expect("icosphere");
    // Noise of a fifth of the edge length, in every direction.
    let sigma = 0.2 * 1.1 / f64::from(1u32 << level);
    let mut rng = Rng(0x5EED);
    let noisy: Vec<DVec3> = sphere
        .positions
        .iter()
        .map(|p| *p + DVec3::new(rng.normal(), rng.normal(), rng.normal()) * sigma)
        .collect();
    let name = format!(
        "icosphere_level{level}_{}pts_{}tris",
        noisy.len(),
        mesh.n_faces()
    );
    let mut group = c.benchmark_group("distance");
    group.sample_size(samples);
    group.bench_function(format!("index_build_{name}"), |b| {
        b.iter(|| SurfaceIndex::new(&mesh, &sphere.positions).expect("index"));
    });
    let index = SurfaceIndex::new(&mesh, &sphere.positions).expect("index");
    group.bench_function(format!("queries_{name}"), |b| {
        b.iter(|| index.distances(&noisy).expect("distances"));
    });
    drop(index);
    group.bench_function(format!("rms_{name}"), |b| {
        b.iter(|| {
            let index = SurfaceIndex::new(&mesh, &sphere.positions).expect("index");
            distance_stats(&mesh, &noisy, &index).expect("stats").rms
        });
    });
    group.finish();
}

fn distance(c: &mut Criterion) {
    bench_level(c, 6, 20);
    bench_level(c, 8, 10);
}

criterion_group!(benches, distance);
criterion_main!(benches);
