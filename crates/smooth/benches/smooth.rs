//! Explicit smoothing: 10 iterations on a noisy icosphere (level 6, 40 962 vertices;
//! level 8, 655 362 vertices) for each built-in scheme, with weights recomputed every
//! iteration and computed once; `NAME_steps` times the iterations alone, `NAME` a whole
//! `smooth` call (operator assembly included). `cargo bench -p beltrami-smooth --bench smooth`.
//!
//! `reorder_icosphere8/SCHEME_POLICY/ORDER/REORDER`: a whole `smooth` call (10
//! iterations) on the level-8 icosphere in its generated vertex order and in a seeded
//! shuffled order, with `Reorder::Never` and `Reorder::Always` (renumbering included);
//! `SCHEME_POLICY_steps/...` times the iterations alone (`Smoother::step`, with
//! statistics), `SCHEME_POLICY_advance/...` the same without statistics
//! (`Smoother::advance`).

#![allow(missing_docs)]

use beltrami_halfedge::reorder::VertexPermutation;
use beltrami_smooth::{Reorder, SmoothConfig, Smoother, WeightUpdate, smooth};
use beltrami_testkit::fixtures::jittered_icosphere;
use beltrami_weights::{Cotangent, InverseDistance, Uniform, WeightScheme};
use criterion::{BatchSize, BenchmarkId, Criterion, criterion_group, criterion_main};
use std::hint::black_box;

const ITERATIONS: usize = 10;

fn bench_smooth(c: &mut Criterion) {
    let schemes: [&dyn WeightScheme; 3] = [&Uniform, &InverseDistance, &Cotangent];
    for level in [6u32, 8] {
        // Noise of about a fifth of the mean edge length (edges halve per level).
        let sphere = jittered_icosphere(level);
        let mesh = sphere.mesh().expect("icosphere is a valid mesh");
        let n = sphere.positions.len();
        let mut group = c.benchmark_group(format!("smooth_icosphere{level}"));
        group.sample_size(10);
        group.warm_up_time(std::time::Duration::from_secs(1));
        group.measurement_time(std::time::Duration::from_secs(3));
        group.throughput(criterion::Throughput::Elements((n * ITERATIONS) as u64));
        for scheme in schemes {
            for (policy, update) in [("every", WeightUpdate::Every), ("once", WeightUpdate::Once)] {
                let config = SmoothConfig::new(0.8, ITERATIONS).update(update);
                // The iterations alone: the smoother (operator assembly, first weights)
                // is built outside the timed part.
                group.bench_with_input(
                    BenchmarkId::new(format!("{}_steps", scheme.name()), policy),
                    &config,
                    |b, config| {
                        b.iter_batched(
                            || {
                                Smoother::new(&mesh, &sphere.positions, scheme, config.clone())
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
                // A whole run, assembly included.
                group.bench_with_input(
                    BenchmarkId::new(scheme.name(), policy),
                    &config,
                    |b, config| {
                        b.iter(|| {
                            smooth(&mesh, black_box(&sphere.positions), scheme, config.clone())
                                .expect("smoothing succeeds")
                        });
                    },
                );
            }
        }
        group.finish();
    }
}

/// A seeded Fisher–Yates shuffle of `0..n` (64-bit LCG).
fn shuffled_order(n: usize, seed: u64) -> VertexPermutation {
    let mut state = seed;
    let mut ids: Vec<u32> = (0..n as u32).collect();
    for i in (1..n).rev() {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let j = ((state >> 33) % (i as u64 + 1)) as usize;
        ids.swap(i, j);
    }
    VertexPermutation::from_new_to_old(ids).expect("a permutation")
}

fn bench_reorder(c: &mut Criterion) {
    let level = 8u32;
    let sphere = jittered_icosphere(level);
    let mesh = sphere.mesh().expect("icosphere is a valid mesh");
    let n = sphere.positions.len();
    let shuffle = shuffled_order(n, 42);
    let shuffled_mesh = shuffle.apply_to_mesh(&mesh);
    let shuffled_positions = shuffle.permute(&sphere.positions);
    let mut group = c.benchmark_group(format!("reorder_icosphere{level}"));
    group.sample_size(10);
    group.warm_up_time(std::time::Duration::from_secs(1));
    group.measurement_time(std::time::Duration::from_secs(3));
    group.throughput(criterion::Throughput::Elements((n * ITERATIONS) as u64));
    let cases: [(&dyn WeightScheme, &str, WeightUpdate); 2] = [
        (&Uniform, "once", WeightUpdate::Once),
        (&Cotangent, "every", WeightUpdate::Every),
    ];
    for (scheme, policy, update) in cases {
        for (order, mesh, positions) in [
            ("generated", &mesh, &sphere.positions),
            ("shuffled", &shuffled_mesh, &shuffled_positions),
        ] {
            for (name, reorder) in [("never", Reorder::Never), ("always", Reorder::Always)] {
                let config = SmoothConfig::new(0.8, ITERATIONS)
                    .update(update)
                    .reorder(reorder);
                // The iterations alone (renumbering and assembly outside).
                group.bench_function(
                    format!("{}_{policy}_steps/{order}/{name}", scheme.name()),
                    |b| {
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
                // The iterations alone without displacement statistics.
                group.bench_function(
                    format!("{}_{policy}_advance/{order}/{name}", scheme.name()),
                    |b| {
                        b.iter_batched(
                            || {
                                Smoother::new(mesh, positions, scheme, config.clone())
                                    .expect("valid configuration")
                            },
                            |mut smoother| {
                                for _ in 0..ITERATIONS {
                                    smoother.advance().expect("finite step");
                                }
                                smoother
                            },
                            BatchSize::LargeInput,
                        );
                    },
                );
                // A whole run, renumbering and assembly included.
                group.bench_function(format!("{}_{policy}/{order}/{name}", scheme.name()), |b| {
                    b.iter(|| {
                        smooth(mesh, black_box(positions), scheme, config.clone())
                            .expect("smoothing succeeds")
                    });
                });
            }
        }
    }
    group.finish();
}

criterion_group!(benches, bench_smooth, bench_reorder);
criterion_main!(benches);
