//! The weight refresh alone: `Laplacian::update` with the built-in uniform, inverse
//! distance and cotangent schemes (weight-sum normalisation, negative weights kept) on
//! the noisy icosphere of level 6 (40 962 vertices) and 8 (655 362 vertices), with
//! normal noise of 0.2 × the mean edge length (seed 42), the sweep bench's mesh. The
//! operator is assembled outside the timed part; each iteration refreshes every weight,
//! row sum and scale once (uniform is the floor: the row pass without arithmetic).
//!
//! ```sh
//! cargo bench -p beltrami-weights --bench refresh
//! cargo bench -p beltrami-weights --bench refresh -- cotangent/icosphere8
//! ```

#![allow(missing_docs)]

use beltrami_halfedge::{DVec3, HalfedgeMesh};
use beltrami_testkit::fixtures::with_bench_noise;
use beltrami_weights::{
    Cotangent, InverseDistance, Laplacian, LaplacianOptions, Uniform, WeightScheme,
};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use std::time::Duration;

const SCHEMES: [&dyn WeightScheme; 3] = [&Uniform, &InverseDistance, &Cotangent];

fn noisy(level: u32) -> (HalfedgeMesh, Vec<DVec3>) {
    with_bench_noise(&beltrami_surfaces::sphere(level))
}

fn refresh(c: &mut Criterion) {
    for level in [6, 8] {
        let (mesh, positions) = noisy(level);
        let mut group = c.benchmark_group("refresh");
        group.throughput(Throughput::Elements(mesh.n_vertices() as u64));
        if level == 8 {
            group.sample_size(10);
            group.measurement_time(Duration::from_secs(5));
        }
        for scheme in SCHEMES {
            let mut lap = Laplacian::new(&mesh, &positions, scheme, LaplacianOptions::default())
                .expect("operator");
            group.bench_function(
                BenchmarkId::new(scheme.name(), format!("icosphere{level}")),
                |b| b.iter(|| lap.update(&mesh, &positions, scheme).expect("refresh")),
            );
        }
        group.finish();
    }
}

criterion_group!(benches, refresh);
criterion_main!(benches);
