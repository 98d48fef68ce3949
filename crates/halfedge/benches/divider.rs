//! The throughput of the divider: f64 square roots and divisions on independent data,
//! one at a time (scalar), two (`wide::f64x2`, SSE2), four (`wide::f64x4` on the
//! x86-64 baseline, which is two SSE2 registers) and, where the processor has them,
//! four in one AVX2 register (`pulp::x86::V3`) and eight in one AVX-512 register
//! (`pulp::x86::V4`), both chosen at run time.
//!
//! Each element is independent of the others, so what is measured is how many the
//! unit finishes per unit of time (its throughput), not how long one takes (its
//! latency): the floor under any kernel that needs a given number of square roots and
//! divisions per vertex. The groups:
//!
//! - `sqrt`: `√x`;
//! - `div`: `a / b`;
//! - `inverse_distance`: `1 / (√q + ε)`, the arithmetic of one inverse-distance weight
//!   from a squared edge length (one square root and one division per slot, six slots
//!   per vertex of a closed triangle mesh);
//! - `cotangents`: the three cotangents of a triangle from its corners, two triangles
//!   at a time in `f64x2` lanes: as `triangle_cotangents_lanes` computes them (three
//!   cross products, square roots and divisions, the library's bits) and a variant
//!   kept here only (one cross product, one square root, one reciprocal and three
//!   multiplications: fewer divider operations, other last bits);
//! - `cotangents_into`: the library's `Geometry::triangle_cotangents_into` on a noisy
//!   sphere (positions gathered, the plain-range fallback), for reference.
//!
//! Throughput is reported per element (per triangle for the cotangents). Run one group
//! with `cargo bench -p beltrami-halfedge --bench divider -- sqrt`.

#![allow(missing_docs)]

use std::hint::black_box;

use beltrami_halfedge::geometry::{DEGENERACY_RATIO, Geometry};
use beltrami_halfedge::{DVec3, VertexId, primitives};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use wide::{CmpGt, CmpLt, f64x2, f64x4};

/// Elements per measured pass: inputs and outputs fit in L1 (3 × 8 KiB).
const N: usize = 1024;

/// The inverse-distance ε.
const EPS: f64 = 1e-12;

/// Deterministic numbers in [1, 2) (SplitMix64): normal, and not special-cased by any
/// divider.
fn numbers(seed: u64, n: usize) -> Vec<f64> {
    let mut s = seed;
    (0..n)
        .map(|_| {
            s = s.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = s;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^= z >> 31;
            1.0 + (z >> 11) as f64 / (1u64 << 53) as f64
        })
        .collect()
}

/// The arithmetic of one element at each width.
trait Op {
    fn scalar(a: f64, b: f64) -> f64;
    fn x2(a: f64x2, b: f64x2) -> f64x2;
    fn x4(a: f64x4, b: f64x4) -> f64x4;
}

struct Sqrt;
impl Op for Sqrt {
    #[inline(always)]
    fn scalar(a: f64, _: f64) -> f64 {
        a.sqrt()
    }
    #[inline(always)]
    fn x2(a: f64x2, _: f64x2) -> f64x2 {
        a.sqrt()
    }
    #[inline(always)]
    fn x4(a: f64x4, _: f64x4) -> f64x4 {
        a.sqrt()
    }
}

struct Div;
impl Op for Div {
    #[inline(always)]
    fn scalar(a: f64, b: f64) -> f64 {
        a / b
    }
    #[inline(always)]
    fn x2(a: f64x2, b: f64x2) -> f64x2 {
        a / b
    }
    #[inline(always)]
    fn x4(a: f64x4, b: f64x4) -> f64x4 {
        a / b
    }
}

struct InverseDistance;
impl Op for InverseDistance {
    #[inline(always)]
    fn scalar(q: f64, _: f64) -> f64 {
        1.0 / (q.sqrt() + EPS)
    }
    #[inline(always)]
    fn x2(q: f64x2, _: f64x2) -> f64x2 {
        f64x2::ONE / (q.sqrt() + f64x2::splat(EPS))
    }
    #[inline(always)]
    fn x4(q: f64x4, _: f64x4) -> f64x4 {
        f64x4::ONE / (q.sqrt() + f64x4::splat(EPS))
    }
}

/// One element at a time; `black_box` on each input keeps the compiler from
/// vectorising the loop.
#[inline(never)]
fn run_scalar<O: Op>(a: &[f64], b: &[f64], out: &mut [f64]) {
    for ((o, &a), &b) in out.iter_mut().zip(a).zip(b) {
        *o = O::scalar(black_box(a), b);
    }
}

#[inline(never)]
fn run_x2<O: Op>(a: &[f64], b: &[f64], out: &mut [f64]) {
    for ((o, a), b) in out
        .chunks_exact_mut(2)
        .zip(a.chunks_exact(2))
        .zip(b.chunks_exact(2))
    {
        let r = O::x2(f64x2::from([a[0], a[1]]), f64x2::from([b[0], b[1]]));
        o.copy_from_slice(&r.to_array());
    }
}

#[inline(never)]
fn run_x4<O: Op>(a: &[f64], b: &[f64], out: &mut [f64]) {
    for ((o, a), b) in out
        .chunks_exact_mut(4)
        .zip(a.chunks_exact(4))
        .zip(b.chunks_exact(4))
    {
        let a = f64x4::from([a[0], a[1], a[2], a[3]]);
        let b = f64x4::from([b[0], b[1], b[2], b[3]]);
        o.copy_from_slice(&O::x4(a, b).to_array());
    }
}

/// The operations of [`Op`] in the registers of a runtime-detected instruction set.
#[cfg(target_arch = "x86_64")]
mod dispatched {
    use pulp::Simd;

    /// Which arithmetic (`0` sqrt, `1` div, `2` inverse distance) in the widest
    /// registers of `simd`, over `a`, `b` into `out` (lengths a multiple of the width).
    #[inline(always)]
    fn run<S: Simd>(simd: S, op: u8, a: &[f64], b: &[f64], out: &mut [f64]) {
        let (a, _) = S::as_simd_f64s(a);
        let (b, _) = S::as_simd_f64s(b);
        let (out, _) = S::as_mut_simd_f64s(out);
        let eps = simd.splat_f64s(super::EPS);
        let one = simd.splat_f64s(1.0);
        for ((o, &a), &b) in out.iter_mut().zip(a).zip(b) {
            *o = match op {
                0 => simd.sqrt_f64s(a),
                1 => simd.div_f64s(a, b),
                _ => simd.div_f64s(one, simd.add_f64s(simd.sqrt_f64s(a), eps)),
            };
        }
    }

    /// [`run`] with AVX2 (four lanes), `false` when the processor lacks it.
    pub(crate) fn avx2(op: u8, a: &[f64], b: &[f64], out: &mut [f64]) -> bool {
        let Some(simd) = pulp::x86::V3::try_new() else {
            return false;
        };
        simd.vectorize(
            #[inline(always)]
            || run(simd, op, a, b, out),
        );
        true
    }

    /// [`run`] with AVX-512 (eight lanes), `false` when the processor lacks it.
    pub(crate) fn avx512(op: u8, a: &[f64], b: &[f64], out: &mut [f64]) -> bool {
        let Some(simd) = pulp::x86::V4::try_new() else {
            return false;
        };
        simd.vectorize(
            #[inline(always)]
            || run(simd, op, a, b, out),
        );
        true
    }
}

fn group<O: Op>(c: &mut Criterion, name: &str, op: u8) {
    let a = numbers(1, N);
    let b = numbers(2, N);
    let mut out = vec![0.0; N];
    let mut g = c.benchmark_group(name);
    g.warm_up_time(std::time::Duration::from_millis(500));
    g.measurement_time(std::time::Duration::from_secs(2));
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("scalar", |bench| {
        bench.iter(|| run_scalar::<O>(black_box(&a), black_box(&b), &mut out));
    });
    g.bench_function("wide_f64x2", |bench| {
        bench.iter(|| run_x2::<O>(black_box(&a), black_box(&b), &mut out));
    });
    g.bench_function("wide_f64x4_baseline", |bench| {
        bench.iter(|| run_x4::<O>(black_box(&a), black_box(&b), &mut out));
    });
    #[cfg(target_arch = "x86_64")]
    {
        if dispatched::avx2(op, &a, &b, &mut out) {
            g.bench_function("avx2_f64x4", |bench| {
                bench.iter(|| dispatched::avx2(op, black_box(&a), black_box(&b), &mut out));
            });
        }
        if dispatched::avx512(op, &a, &b, &mut out) {
            g.bench_function("avx512_f64x8", |bench| {
                bench.iter(|| dispatched::avx512(op, black_box(&a), black_box(&b), &mut out));
            });
        }
    }
    g.finish();
}

fn divider(c: &mut Criterion) {
    group::<Sqrt>(c, "sqrt", 0);
    group::<Div>(c, "div", 1);
    group::<InverseDistance>(c, "inverse_distance", 2);
}

/// Three coordinates of two triangles' corners in lanes.
#[derive(Clone, Copy)]
struct V3 {
    x: f64x2,
    y: f64x2,
    z: f64x2,
}

impl V3 {
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Self {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
    #[inline(always)]
    fn dot(self, o: Self) -> f64x2 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    #[inline(always)]
    fn cross(self, o: Self) -> Self {
        Self {
            x: self.y * o.z - o.y * self.z,
            y: self.z * o.x - o.z * self.x,
            z: self.x * o.y - o.x * self.y,
        }
    }
}

/// `dot / cross` where `cross > limit` and the quotient is finite, else 0.
#[inline(always)]
fn cot(dot: f64x2, cross: f64x2, limit: f64x2) -> f64x2 {
    let c = dot / cross;
    c & (cross.cmp_gt(limit) & c.abs().cmp_lt(f64x2::splat(f64::INFINITY)))
}

/// The library's lane arithmetic (`triangle_cotangents_lanes`): three cross
/// products, square roots and divisions per triangle.
#[inline(always)]
fn three_roots(p0: V3, p1: V3, p2: V3) -> [f64x2; 3] {
    let (s1, s2, e) = (p1.sub(p0), p2.sub(p0), p2.sub(p1));
    let (q1, q2, qe) = (s1.dot(s1), s2.dot(s2), e.dot(e));
    let limit = f64x2::splat(DEGENERACY_RATIO) * q1.fast_max(q2).fast_max(qe);
    let x0 = s1.cross(s2);
    let x1 = e.cross(s1);
    let x2 = s2.cross(e);
    [
        cot(-e.dot(s1), x1.dot(x1).sqrt(), limit),
        cot(s2.dot(e), x2.dot(x2).sqrt(), limit),
        cot(s1.dot(s2), x0.dot(x0).sqrt(), limit),
    ]
}

/// One cross product, one square root and one reciprocal per triangle (`|s1 × s2|`
/// serves all three corners): other last bits than the library's, kept here only to
/// measure what it would save.
#[inline(always)]
fn one_root(p0: V3, p1: V3, p2: V3) -> [f64x2; 3] {
    let (s1, s2, e) = (p1.sub(p0), p2.sub(p0), p2.sub(p1));
    let (q1, q2, qe) = (s1.dot(s1), s2.dot(s2), e.dot(e));
    let limit = f64x2::splat(DEGENERACY_RATIO) * q1.fast_max(q2).fast_max(qe);
    let x0 = s1.cross(s2);
    let two_area = x0.dot(x0).sqrt();
    let r = f64x2::ONE / two_area;
    let keep = two_area.cmp_gt(limit);
    let c = |d: f64x2| {
        let c = d * r;
        c & (keep & c.abs().cmp_lt(f64x2::splat(f64::INFINITY)))
    };
    [c(-e.dot(s1)), c(s2.dot(e)), c(s1.dot(s2))]
}

/// A noisy level-`level` icosphere and its triangles' vertices.
fn noisy_sphere(level: u32) -> (beltrami_halfedge::HalfedgeMesh, Vec<DVec3>) {
    let sphere = primitives::icosphere(level);
    let mesh = sphere.mesh().expect("an icosphere is a mesh");
    let noise = numbers(3, 3 * sphere.positions.len());
    let x = sphere
        .positions
        .iter()
        .zip(noise.chunks_exact(3))
        .map(|(&p, n)| p + (DVec3::new(n[0], n[1], n[2]) - 1.5) * 0.01)
        .collect();
    (mesh, x)
}

fn cotangents(c: &mut Criterion) {
    let (mesh, x) = noisy_sphere(5);
    let triangles: Vec<[VertexId; 3]> = mesh
        .faces()
        .map(|f| {
            let h0 = mesh.face_halfedge(f);
            let h1 = mesh.next(h0);
            let h2 = mesh.next(h1);
            [h0, h1, h2].map(|h| mesh.to_vertex(h))
        })
        .collect();
    // Pairs of triangles in lanes, structure of arrays.
    let lanes: Vec<[V3; 3]> = triangles
        .chunks_exact(2)
        .map(|t| {
            std::array::from_fn(|k| {
                let (a, b) = (x[t[0][k].index()], x[t[1][k].index()]);
                V3 {
                    x: f64x2::from([a.x, b.x]),
                    y: f64x2::from([a.y, b.y]),
                    z: f64x2::from([a.z, b.z]),
                }
            })
        })
        .collect();
    let mut out = vec![[f64x2::ZERO; 3]; lanes.len()];
    let mut g = c.benchmark_group("cotangents");
    g.throughput(Throughput::Elements(2 * lanes.len() as u64));
    g.bench_function("three_roots", |bench| {
        bench.iter(|| {
            for (o, &[p0, p1, p2]) in out.iter_mut().zip(black_box(&lanes)) {
                *o = three_roots(p0, p1, p2);
            }
        });
    });
    g.bench_function("one_root", |bench| {
        bench.iter(|| {
            for (o, &[p0, p1, p2]) in out.iter_mut().zip(black_box(&lanes)) {
                *o = one_root(p0, p1, p2);
            }
        });
    });
    g.finish();
    let geometry = Geometry::new(&mesh, &x).expect("positions match");
    let mut flat = vec![0.0; 3 * triangles.len()];
    let mut g = c.benchmark_group("cotangents_into");
    g.throughput(Throughput::Elements(triangles.len() as u64));
    g.bench_function("library", |bench| {
        bench.iter(|| geometry.triangle_cotangents_into(black_box(&triangles), &mut flat));
    });
    g.finish();
}

criterion_group!(benches, divider, cotangents);
criterion_main!(benches);
