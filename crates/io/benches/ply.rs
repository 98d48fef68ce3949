//! Binary PLY reading and writing on an icosphere of level 6 (40 962 vertices, 81 920
//! faces, 2.0 MB) and level 8 (655 362 vertices, 1 310 720 faces, 32.8 MB, the layout
//! of `s8.ply` in `docs/performance/io.md`): `double x y z`, `list uchar int vertex_indices`.
//! `cargo bench -p beltrami-io --bench ply`.
//!
//! - `read/LEVEL`: `read_mesh` of the file (from the page cache), header to `MeshData`;
//! - `read_from/LEVEL`: `read_mesh_from` of the bytes already in memory (the decoding
//!   alone, plus one copy);
//! - `encode/LEVEL`: `write_mesh_to` into a `Vec` (the encoding alone);
//! - `write/LEVEL`: `write_mesh` to a file, with the atomic protocol (`fsync`, rename).

#![allow(missing_docs)]

use std::hint::black_box;

use beltrami_halfedge::primitives;
use beltrami_io::{MeshFormat, WriteOptions, read_mesh, read_mesh_from, write_mesh, write_mesh_to};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};

fn bench_ply(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let mut group = c.benchmark_group("ply");
    group.sample_size(10);
    group.warm_up_time(std::time::Duration::from_secs(1));
    group.measurement_time(std::time::Duration::from_secs(3));
    for level in [6u32, 8] {
        let mesh = primitives::icosphere(level);
        let path = dir.path().join(format!("icosphere{level}.ply"));
        write_mesh(&path, &mesh, &WriteOptions::default()).expect("writes");
        let bytes = std::fs::read(&path).expect("reads");
        group.throughput(Throughput::Bytes(bytes.len() as u64));
        group.bench_with_input(BenchmarkId::new("read", level), &path, |b, path| {
            b.iter(|| black_box(read_mesh(path).expect("reads")));
        });
        group.bench_with_input(BenchmarkId::new("read_from", level), &bytes, |b, bytes| {
            b.iter(|| black_box(read_mesh_from(&bytes[..], MeshFormat::Ply).expect("reads")));
        });
        group.bench_with_input(BenchmarkId::new("encode", level), &mesh, |b, mesh| {
            let mut out = Vec::with_capacity(bytes.len());
            b.iter(|| {
                out.clear();
                write_mesh_to(&mut out, mesh, MeshFormat::Ply, &WriteOptions::default())
                    .expect("writes");
                black_box(out.len())
            });
        });
        let out = dir.path().join(format!("out{level}.ply"));
        group.bench_with_input(BenchmarkId::new("write", level), &mesh, |b, mesh| {
            b.iter(|| write_mesh(&out, mesh, &WriteOptions::default()).expect("writes"));
        });
    }
    group.finish();
}

criterion_group!(benches, bench_ply);
criterion_main!(benches);
