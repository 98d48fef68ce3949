//! The validating half-edge builder on icospheres of level 6 (81 920 triangles) and
//! level 8 (1 310 720 triangles), from a `PolygonList`, as `beltrami` builds a mesh it
//! has read; `reversed/LEVEL` builds the faces listed in reverse order (the vertex
//! numbering no longer follows the face order). `cargo bench -p beltrami-halfedge --bench build`.

#![allow(missing_docs)]

use std::hint::black_box;

use beltrami_halfedge::{HalfedgeMesh, PolygonList, primitives};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};

fn bench_build(c: &mut Criterion) {
    let mut group = c.benchmark_group("build");
    group.sample_size(10);
    group.warm_up_time(std::time::Duration::from_secs(1));
    group.measurement_time(std::time::Duration::from_secs(3));
    for level in [6u32, 8] {
        let sphere = primitives::icosphere(level);
        let n = sphere.positions.len();
        let faces = sphere.faces;
        let reversed: PolygonList = (0..faces.len())
            .rev()
            .filter_map(|f| faces.get(f))
            .collect();
        group.throughput(Throughput::Elements(faces.len() as u64));
        for (name, faces) in [("icosphere", &faces), ("reversed", &reversed)] {
            group.bench_with_input(BenchmarkId::new(name, level), faces, |b, faces| {
                b.iter(|| black_box(HalfedgeMesh::from_polygons(n, faces.iter()).expect("valid")));
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench_build);
criterion_main!(benches);
