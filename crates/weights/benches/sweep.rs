//! Explicit smoothing sweeps (`Smoother::step`, 10 iterations, λ = 0.8, weight-sum
//! normalisation, fixed boundary) for each built-in scheme with weights recomputed
//! every iteration (`every`) or frozen (`once`):
//!
//! - `surfaces`: the paper's four surfaces (F-lens, sphere, block, golf ball) with
//!   normal noise of 0.2 × the mean edge length (seed 42);
//! - `icosphere8`: the 655 362-vertex icosphere with the same noise, in four vertex
//!   orders: `ordered` (as subdivision numbers them), `shuffled` (a seeded ChaCha8
//!   Fisher–Yates shuffle), and the shuffled mesh renumbered by `rcm`
//!   (reverse Cuthill–McKee) or `hilbert` (a 3-D Hilbert curve), see
//!   `beltrami_halfedge::reorder`.
//!
//! Only the iterations are timed (the smoother, hence operator assembly and the first
//! weights, is built outside), so `every` refreshes the weights 9 times per sample.
//!
//! ```sh
//! cargo bench -p beltrami-weights --bench sweep                 # everything
//! cargo bench -p beltrami-weights --bench sweep -- icosphere8/uniform
//! ```

#![allow(missing_docs)]

use beltrami_halfedge::reorder::{VertexPermutation, hilbert_order, rcm_order};
use beltrami_halfedge::{DVec3, HalfedgeMesh};
use beltrami_smooth::{SmoothConfig, Smoother, WeightUpdate};
use beltrami_surfaces::SurfaceKind;
use beltrami_testkit::fixtures::with_bench_noise;
use beltrami_weights::{Cotangent, InverseDistance, Uniform, WeightScheme};
use criterion::{BatchSize, BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{Rng, SeedableRng};
use std::time::Duration;

const ITERATIONS: usize = 10;
const SCHEMES: [&dyn WeightScheme; 3] = [&Uniform, &InverseDistance, &Cotangent];
const POLICIES: [(&str, WeightUpdate); 2] =
    [("every", WeightUpdate::Every), ("once", WeightUpdate::Once)];

/// A seeded Fisher–Yates shuffle of the vertex numbering.
fn shuffled(n: usize, seed: u64) -> VertexPermutation {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut order: Vec<u32> = (0..n as u32).collect();
    for i in (1..n).rev() {
        let j = (rng.next_u64() % (i as u64 + 1)) as usize;
        order.swap(i, j);
    }
    VertexPermutation::from_new_to_old(order).expect("a permutation")
}

fn noisy(kind: Option<SurfaceKind>) -> (HalfedgeMesh, Vec<DVec3>) {
    let surface = match kind {
        Some(kind) => kind.generate(),
        None => beltrami_surfaces::sphere(8),
    };
    with_bench_noise(&surface)
}

fn bench_case(
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    label: &str,
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
) {
    for scheme in SCHEMES {
        for (policy, update) in POLICIES {
            let config = SmoothConfig::new(0.8, ITERATIONS).update(update);
            group.bench_with_input(
                BenchmarkId::new(format!("{}/{label}", scheme.name()), policy),
                &config,
                |b, config| {
                    b.iter_batched(
                        || {
                            Smoother::new(mesh, positions, scheme, config.clone())
                                .expect("valid configuration")
                        },
                        |mut smoother| {
                            for _ in 0..ITERATIONS {
                                smoother.step().expect("finite step");
                            }
                            smoother
                        },
                        BatchSize::LargeInput,
                    );
                },
            );
        }
    }
}

fn configure(
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    n: usize,
) {
    group.sample_size(10);
    group.warm_up_time(Duration::from_millis(500));
    group.measurement_time(Duration::from_secs(2));
    group.throughput(Throughput::Elements((n * ITERATIONS) as u64));
}

fn bench_surfaces(c: &mut Criterion) {
    for kind in SurfaceKind::ALL {
        let (mesh, positions) = noisy(Some(kind));
        let mut group = c.benchmark_group(format!("surfaces/{}", kind.name()));
        configure(&mut group, positions.len());
        bench_case(&mut group, "ordered", &mesh, &positions);
        group.finish();
    }
}

fn bench_icosphere8(c: &mut Criterion) {
    let (mesh, positions) = noisy(None);
    let shuffle = shuffled(positions.len(), 8);
    let s_mesh = shuffle.apply_to_mesh(&mesh);
    let s_positions = shuffle.permute(&positions);
    let mut group = c.benchmark_group("icosphere8");
    configure(&mut group, positions.len());
    bench_case(&mut group, "ordered", &mesh, &positions);
    bench_case(&mut group, "shuffled", &s_mesh, &s_positions);
    for (label, perm) in [
        ("rcm", rcm_order(&s_mesh)),
        ("hilbert", hilbert_order(&s_positions)),
    ] {
        let r_mesh = perm.apply_to_mesh(&s_mesh);
        let r_positions = perm.permute(&s_positions);
        bench_case(&mut group, label, &r_mesh, &r_positions);
    }
    group.finish();
}

criterion_group!(benches, bench_surfaces, bench_icosphere8);
criterion_main!(benches);
