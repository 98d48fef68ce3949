//! Quadric decimation of the level-6 icosphere (40 962 vertices) to 10 % of its
//! vertices: the default (optimal placement, shape penalty) and OpenMesh's plain mode
//! (endpoint placement), the decimation alone (`measure_distance(false)`), and the
//! report's Hausdorff distance, which `decimate` measures by default, on its own.
//!
//! `cargo bench -p beltrami-algorithms --bench decimation`

// criterion_group! generates undocumented items.
#![allow(missing_docs)]

use beltrami_algorithms::{DecimateOptions, DecimateReport, decimate};
use beltrami_halfedge::primitives;
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
        let options = options.ratio(0.1).measure_distance(false);
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
            let mut report = DecimateReport::default();
            report
                .measure_distance((&mesh, &sphere.positions), (&out, &positions))
                .expect("measures");
            report
        });
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
