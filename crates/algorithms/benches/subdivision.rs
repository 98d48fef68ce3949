//! Loop and √3 subdivision of the level-4 icosphere (2562 vertices, 5120 faces).
//!
//! `cargo bench -p beltrami-algorithms --bench subdivision`

// criterion_group! generates undocumented items.
#![allow(missing_docs)]

use beltrami_algorithms::{loop_subdivide, sqrt3_subdivide};
use beltrami_halfedge::primitives;
use criterion::{Criterion, criterion_group, criterion_main};

fn bench(c: &mut Criterion) {
    let ico = primitives::icosphere(4);
    let mesh = ico.mesh().expect("the icosphere builds");
    c.bench_function("loop_subdivide icosphere(4) x2", |b| {
        b.iter(|| loop_subdivide(&mesh, &ico.positions, 2).expect("subdivides"));
    });
    c.bench_function("sqrt3_subdivide icosphere(4) x2", |b| {
        b.iter(|| sqrt3_subdivide(&mesh, &ico.positions, 2).expect("subdivides"));
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
