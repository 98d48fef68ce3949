//! Explicit smoothing: 10 iterations on a noisy icosphere (level 6, 40 962 vertices;
//! level 8, 655 362 vertices) for each built-in scheme, with weights recomputed every
//! iteration and computed once; `NAME_steps` times the iterations alone, `NAME` a whole
//! `smooth` call (operator assembly included). `cargo bench -p beltrami-smooth --bench smooth`.

#![allow(missing_docs)]

use beltrami_halfedge::DVec3;
use beltrami_halfedge::primitives;
use beltrami_smooth::{SmoothConfig, Smoother, WeightUpdate, smooth};
use beltrami_weights::{Cotangent, InverseDistance, Uniform, WeightScheme};
use criterion::{BatchSize, BenchmarkId, Criterion, criterion_group, criterion_main};
use std::hint::black_box;

const ITERATIONS: usize = 10;

/// A deterministic jitter of every vertex by up to `amplitude` per coordinate
/// (a 64-bit linear congruential generator, so the bench needs no extra crate).
fn jitter(positions: &mut [DVec3], amplitude: f64) {
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    };
    for p in positions {
        *p += DVec3::new(next(), next(), next()) * amplitude;
    }
}

fn bench_smooth(c: &mut Criterion) {
    let schemes: [&dyn WeightScheme; 3] = [&Uniform, &InverseDistance, &Cotangent];
    for level in [6u32, 8] {
        let mut sphere = primitives::icosphere(level);
        // Noise of about a fifth of the mean edge length (edges halve per level).
        let edge = 1.1 / f64::from(1u32 << level);
        jitter(&mut sphere.positions, 0.2 * edge);
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

criterion_group!(benches, bench_smooth);
criterion_main!(benches);
