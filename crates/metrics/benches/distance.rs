//! Closest-point RMS of a noisy icosphere's vertices against a clean icosphere: level 8
//! (655 362 query points, 1 310 720 reference triangles) and level 6. Three cases per level:
//! the index build alone (`index_build`), the queries against a built index (`queries`:
//! unsigned distances of every noisy vertex), and both with the RMS (`rms`, the closest-point
//! figure of `docs/performance.md`).
//!
//! Run with `cargo bench -p beltrami-metrics --bench distance`.

// `criterion_group!` generates an undocumented public function.
#![allow(missing_docs)]

use beltrami_metrics::distance::{SurfaceIndex, distance_stats};
use beltrami_testkit::fixtures::gaussian_noisy_icosphere;
use criterion::{Criterion, criterion_group, criterion_main};

fn bench_level(c: &mut Criterion, level: u32, samples: usize) {
    // Noise of a fifth of the edge length, in every direction.
    let sigma = 0.2 * 1.1 / f64::from(1u32 << level);
    let (sphere, noisy) = gaussian_noisy_icosphere(level, sigma, 0x5EED);
    let mesh = sphere.mesh().expect("icosphere");
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
