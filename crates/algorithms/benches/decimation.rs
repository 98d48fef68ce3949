//! Quadric decimation of the level-6 icosphere (40 962 vertices) to 10 % of its
//! vertices: the default (optimal placement, shape penalty) and OpenMesh's plain mode
//! (endpoint placement). Each run includes the report's Hausdorff distance, measured
//! here on its own too.
//!
//! `cargo bench -p beltrami-algorithms --bench decimation`

// criterion_group! generates undocumented items.
#![allow(missing_docs)]

use beltrami_algorithms::{DecimateOptions, decimate};
use beltrami_halfedge::primitives;
use beltrami_metrics::distance::{HausdorffSampling, SurfaceIndex, hausdorff};
use criterion::{Criterion, criterion_group, criterion_main};

fn bench(c: &mut Criterion) {
    let sphere = primitives::icosphere(6);
    let mesh = sphere.mesh().expect("the icosphere builds");
    let mut group = c.benchmark_group("decimate icosphere(6) to 10 %");
    group.sample_size(10);
    for (name, options) in [
        ("default", DecimateOptions::default()),
        ("openmesh", DecimateOptions::openmesh()),
    ] {
        let options = options.ratio(0.1);
        group.bench_function(name, |b| {
            b.iter(|| decimate(&mesh, &sphere.positions, &options).expect("decimates"));
        });
    }
    let (out, positions, _) = decimate(
        &mesh,
        &sphere.positions,
        &DecimateOptions::default().ratio(0.1),
    )
    .expect("decimates");
    group.bench_function("the report's Hausdorff distance alone", |b| {
        b.iter(|| {
            let sampling = HausdorffSampling::VerticesAndSurface {
                samples: mesh.n_faces(),
                seed: 0x0dec_1a7e,
            };
            hausdorff(
                &SurfaceIndex::new(&out, &positions).expect("indexes"),
                &SurfaceIndex::new(&mesh, &sphere.positions).expect("indexes"),
                sampling,
            )
            .expect("measures")
        });
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
