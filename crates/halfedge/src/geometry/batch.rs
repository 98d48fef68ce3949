//! Whole-mesh and batched queries: vertex areas and face cotangents in parallel with
//! fixed chunks, triangle cotangents and distances two or four at a time in SIMD lanes.
//!
//! Every value here has the bits of the per-element query it batches
//! ([`Geometry::vertex_area`], [`Geometry::face_opposite_cotangents`],
//! [`distance`](super::distance)): the lanes do the per-element arithmetic operation by
//! operation (IEEE add, multiply, divide and square root are exact per lane, see
//! `lanes.rs`), only where the edge vectors lie in the plain range that needs no
//! rescaling; everything else goes through the per-element kernel. Chunks are fixed, so
//! results do not depend on the thread count.

use glam::DVec3;
use rayon::prelude::*;
use wide::{CmpEq, CmpGe, CmpGt, CmpLt};

use super::kernel::{self, SQRT_MIN};
use super::lanes::V3;
use super::{DEGENERACY_RATIO, Geometry, VertexAreaKind};
use crate::error::TopologyError;
use crate::ids::{ElementId, FaceId, VertexId};

/// Elements per parallel work unit. Fixed, so that results do not depend on the number
/// of threads.
const CHUNK: usize = 4096;

/// The lane type of the batched kernels.
type Lanes = wide::f64x2;
/// Elements per batch (the lanes of [`Lanes`]).
const LANES: usize = 2;

/// 2^-398: a squared edge length at least this has a component of at least 2^-200.
const SQUARED_LO: f64 = f64::from_bits((1023 - 398) << 52);
/// 2^400: a squared edge length below this has every component below 2^200.
const SQUARED_HI: f64 = f64::from_bits((1023 + 400) << 52);

impl Geometry<'_> {
    /// The area of every vertex under `kind` into `out` (one entry per vertex), in
    /// parallel with fixed chunks; each entry is bit-identical to
    /// [`vertex_area`](Self::vertex_area). For a caller that refreshes areas every
    /// iteration without allocating.
    ///
    /// # Errors
    /// [`TopologyError::NotTriangle`] for [`VertexAreaKind::MixedVoronoi`] when a face is
    /// not a triangle (the first such face is named); `out` is then unchanged.
    ///
    /// # Panics
    /// If `out` does not have one entry per vertex.
    pub fn vertex_areas_into(
        &self,
        kind: VertexAreaKind,
        out: &mut [f64],
    ) -> Result<(), TopologyError> {
        let m = self.mesh;
        assert_eq!(out.len(), m.n_vertices(), "one area per vertex");
        if kind == VertexAreaKind::MixedVoronoi
            && !m.is_triangle_mesh()
            && let Some(f) = m.faces().find(|&f| self.triangle(f).is_none())
        {
            return Err(TopologyError::NotTriangle {
                face: f.raw(),
                len: m.face_valence(f),
            });
        }
        out.par_chunks_mut(CHUNK)
            .enumerate()
            .for_each(|(c, areas)| {
                for (k, a) in areas.iter_mut().enumerate() {
                    *a = self.vertex_area(VertexId::from_index(c * CHUNK + k), kind);
                }
            });
        Ok(())
    }

    /// The cotangents of every face, in parallel with fixed chunks: `out[f]` holds the
    /// cotangents opposite the three halfedges of triangle `f` in face order (the
    /// halfedges ending at its first, second and third vertex), the values of
    /// [`face_opposite_cotangents`](Self::face_opposite_cotangents) bit for bit (0 for a
    /// degenerate triangle).
    ///
    /// # Errors
    /// [`TopologyError::NotTriangle`] when a face is not a triangle (the first such face
    /// is named); `out` is then unspecified.
    ///
    /// # Panics
    /// If `out` does not have one entry per face.
    pub fn face_cotangents_into(&self, out: &mut [[f64; 3]]) -> Result<(), TopologyError> {
        let m = self.mesh;
        assert_eq!(out.len(), m.n_faces(), "three cotangents per face");
        let bad = out
            .par_chunks_mut(CHUNK)
            .enumerate()
            .map(|(c, out)| {
                let first = c * CHUNK;
                let mut triangles = Vec::with_capacity(out.len());
                for k in 0..out.len() {
                    let f = FaceId::from_index(first + k);
                    let h0 = m.face_halfedge(f);
                    let h1 = m.next(h0);
                    let h2 = m.next(h1);
                    if m.next(h2) != h0 {
                        return Some(f);
                    }
                    triangles.push([m.to_vertex(h0), m.to_vertex(h1), m.to_vertex(h2)]);
                }
                self.triangle_cotangents_into(&triangles, out.as_flattened_mut());
                None
            })
            .collect::<Vec<_>>();
        match bad.into_iter().flatten().next() {
            Some(f) => Err(TopologyError::NotTriangle {
                face: f.raw(),
                len: m.face_valence(f),
            }),
            None => Ok(()),
        }
    }

    /// The cotangents of the triangles `triangles` (vertex triples in face order, for a
    /// layout of the caller's choosing): `out[3k..3k + 3]` gets the cotangents opposite
    /// the halfedges ending at the first, second and third vertex of triangle `k`, the
    /// bits of [`face_opposite_cotangents`](Self::face_opposite_cotangents) for a face
    /// with those vertices (0 for a degenerate triangle). Two triangles at a time;
    /// sequential, so that a caller can run it on chunks in parallel.
    ///
    /// # Panics
    /// If `out.len() != 3 * triangles.len()` or a vertex is out of bounds.
    pub fn triangle_cotangents_into(&self, triangles: &[[VertexId; 3]], out: &mut [f64]) {
        assert_eq!(
            out.len(),
            3 * triangles.len(),
            "three cotangents per triangle"
        );
        let positions = self.positions;
        let scalar = |t: &[VertexId; 3], out: &mut [f64]| {
            let [a, b, c] = t.map(|v| positions[v.index()]);
            out.copy_from_slice(&triangle_cotangents(a, b, c));
        };
        let batches = triangles.chunks_exact(LANES);
        let tail = batches.remainder();
        let mut outs = out.chunks_exact_mut(3 * LANES);
        for (tris, out) in batches.zip(&mut outs) {
            let mut p = [[[0.0; LANES]; 3]; 3];
            for (l, t) in tris.iter().enumerate() {
                for (p, v) in p.iter_mut().zip(t) {
                    let q = positions[v.index()];
                    p[0][l] = q.x;
                    p[1][l] = q.y;
                    p[2][l] = q.z;
                }
            }
            let v = |[x, y, z]: [[f64; LANES]; 3]| V3 {
                x: Lanes::from(x),
                y: Lanes::from(y),
                z: Lanes::from(z),
            };
            let ([c1, c2, c0], plain) = triangle_cotangents_lanes(v(p[0]), v(p[1]), v(p[2]));
            // A zero cotangent may have the wrong sign (see `cot_lanes`): its triangle goes
            // through the kernel.
            let zero = Lanes::splat(0.0);
            let exact = !(c1.cmp_eq(zero) | c2.cmp_eq(zero) | c0.cmp_eq(zero));
            if (plain & exact).all() {
                let (c1, c2, c0) = (c1.to_array(), c2.to_array(), c0.to_array());
                for (l, o) in out.chunks_exact_mut(3).enumerate() {
                    o.copy_from_slice(&[c1[l], c2[l], c0[l]]);
                }
            } else {
                for (t, o) in tris.iter().zip(out.chunks_exact_mut(3)) {
                    scalar(t, o);
                }
            }
        }
        for (t, o) in tail.iter().zip(outs.into_remainder().chunks_exact_mut(3)) {
            scalar(t, o);
        }
    }

    /// The cotangents of the triangles `triangles`, as
    /// [`triangle_cotangents_into`](Self::triangle_cotangents_into) computes them (the
    /// same bits), laid out in blocks of [`BLOCK`] triangles: the cotangent opposite the
    /// halfedge ending at the `k`-th vertex of triangle `t` is
    /// `out[`[`blocked_index`]`(t, k)]`, `3 × BLOCK` values per block (a short last
    /// block's unused values are 0). Four triangles at a time in lane arrays, compiled
    /// for AVX2 where the processor has it (chosen at run time; the same operations in
    /// the same order, no fused multiply-adds, so the same bits either way); sequential,
    /// so that a caller can run it on chunks of whole blocks in parallel.
    ///
    /// # Panics
    /// If `out.len() != 3 * BLOCK * triangles.len().div_ceil(BLOCK)` or a vertex is out
    /// of bounds.
    pub fn triangle_cotangents_blocked_into(&self, triangles: &[[VertexId; 3]], out: &mut [f64]) {
        assert_eq!(
            out.len(),
            3 * BLOCK * triangles.len().div_ceil(BLOCK),
            "three cotangents per triangle, whole blocks"
        );
        pulp::Arch::new().dispatch(BlockedCotangents {
            positions: self.positions,
            triangles,
            out,
        });
    }
}

/// Each squared length `q` in `squared` replaced by `f(√q)`, four at a time in lane
/// arrays compiled for AVX2 where the processor has it (chosen at run time; the same
/// operations either way); returns whether every length was plain: at least
/// `sqrt(f64::MIN_POSITIVE)` and finite. Where it was, `√q` of a squared length `q =
/// v · v` (glam's `DVec3::length_squared` of `v = x_j − x_i`) is
/// [`distance`](super::distance)`(x_i, x_j)` bit for bit, so `f(√q)` is what
/// [`distances_with`] stores; where it was not, the values are meaningless and the
/// caller computes the distances with [`distances_with`] (which rescales them). For a
/// caller that computes a block of rows' squared lengths first and then their weights
/// in full registers.
pub fn lengths_with<F>(squared: &mut [f64], f: F) -> bool
where
    F: Fn(f64) -> f64,
{
    pulp::Arch::new().dispatch(Lengths { squared, f })
}

/// [`lengths_with`]'s work, for [`pulp::Arch::dispatch`] (a type rather than a closure,
/// as [`BlockedCotangents`]).
struct Lengths<'a, F> {
    squared: &'a mut [f64],
    f: F,
}

impl<F: Fn(f64) -> f64> pulp::WithSimd for Lengths<'_, F> {
    type Output = bool;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _: S) -> bool {
        let Self { squared, f } = self;
        let plain = |l: f64| (SQRT_MIN..f64::INFINITY).contains(&l);
        let mut quads = squared.chunks_exact_mut(BLOCK);
        let mut all = [true; BLOCK];
        for q in &mut quads {
            let len: [f64; BLOCK] = std::array::from_fn(|l| q[l].sqrt());
            for l in 0..BLOCK {
                all[l] &= plain(len[l]);
                q[l] = f(len[l]);
            }
        }
        let mut tail = true;
        for q in quads.into_remainder() {
            let len = q.sqrt();
            tail &= plain(len);
            *q = f(len);
        }
        tail & all.iter().all(|&p| p)
    }
}

/// Triangles per block of [`Geometry::triangle_cotangents_blocked_into`]: four lanes,
/// one AVX2 register per coordinate where the processor has it.
pub const BLOCK: usize = 4;

/// Where [`Geometry::triangle_cotangents_blocked_into`] puts the cotangent opposite the
/// halfedge ending at the `k`-th vertex (`k < 3`) of triangle `t`.
#[inline]
pub const fn blocked_index(t: usize, k: usize) -> usize {
    3 * BLOCK * (t / BLOCK) + BLOCK * k + t % BLOCK
}

/// [`Geometry::triangle_cotangents_blocked_into`]'s work, for [`pulp::Arch::dispatch`]:
/// a type rather than a closure, so that its body is compiled inside the dispatched
/// function (a closure's body may stay a function of its own, compiled for the
/// baseline).
struct BlockedCotangents<'a> {
    positions: &'a [DVec3],
    triangles: &'a [[VertexId; 3]],
    out: &'a mut [f64],
}

impl pulp::WithSimd for BlockedCotangents<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _: S) {
        let Self {
            positions,
            triangles,
            out,
        } = self;
        for (tris, out) in triangles.chunks(BLOCK).zip(out.chunks_exact_mut(3 * BLOCK)) {
            let mut p = [[[0.0; BLOCK]; 3]; 3];
            // A short last block repeats its last triangle.
            for l in 0..BLOCK {
                for (p, v) in p.iter_mut().zip(&tris[l.min(tris.len() - 1)]) {
                    let q = positions[v.index()];
                    p[0][l] = q.x;
                    p[1][l] = q.y;
                    p[2][l] = q.z;
                }
            }
            let (cots, plain) = triangle_cotangents_array(&p);
            if plain {
                for (o, c) in out.chunks_exact_mut(BLOCK).zip(cots) {
                    o.copy_from_slice(&c);
                }
            } else {
                for (l, t) in tris.iter().enumerate() {
                    let [a, b, c] = t.map(|v| positions[v.index()]);
                    for (k, c) in triangle_cotangents(a, b, c).into_iter().enumerate() {
                        out[BLOCK * k + l] = c;
                    }
                }
            }
            for o in out.chunks_exact_mut(BLOCK) {
                o[tris.len()..].fill(0.0);
            }
        }
        // A zero cotangent from the lanes may have the wrong sign (see `cot_lanes`): its
        // triangle goes through the kernel. Zeros are rare (right angles, degenerate
        // triangles, a short last block's padding), so they are looked for after the
        // lanes, in one pass that does not hold up theirs (a test inside the loop cost
        // 6 % of a cotangent run).
        if out.iter().fold(false, |z, &c| z | (c == 0.0)) {
            for (i, out) in out.iter_mut().enumerate() {
                let t = i / (3 * BLOCK) * BLOCK + i % BLOCK;
                if *out == 0.0 && t < triangles.len() {
                    let [a, b, c] = triangles[t].map(|v| positions[v.index()]);
                    *out = triangle_cotangents(a, b, c)[i / BLOCK % 3];
                }
            }
        }
    }
}

/// [`triangle_cotangents_lanes`] for [`BLOCK`] triangles whose corners are
/// `p[corner][coordinate][lane]`, operation by operation, in lane arrays: the
/// cotangents opposite the halfedges ending at `p0`, `p1`, `p2`, and whether every
/// lane's three edge vectors are plain (else the values are meaningless).
#[inline(always)]
fn triangle_cotangents_array(p: &[[[f64; BLOCK]; 3]; 3]) -> ([[f64; BLOCK]; 3], bool) {
    type W = [f64; BLOCK];
    let sub = |a: &[W; 3], b: &[W; 3]| -> [W; 3] {
        std::array::from_fn(|k| std::array::from_fn(|l| a[k][l] - b[k][l]))
    };
    // glam's `DVec3::dot` and `DVec3::cross`, operation by operation (see `lanes.rs`).
    let dot = |a: &[W; 3], b: &[W; 3]| -> W {
        std::array::from_fn(|l| a[0][l] * b[0][l] + a[1][l] * b[1][l] + a[2][l] * b[2][l])
    };
    let cross = |a: &[W; 3], b: &[W; 3]| -> [W; 3] {
        [
            std::array::from_fn(|l| a[1][l] * b[2][l] - b[1][l] * a[2][l]),
            std::array::from_fn(|l| a[2][l] * b[0][l] - b[2][l] * a[0][l]),
            std::array::from_fn(|l| a[0][l] * b[1][l] - b[0][l] * a[1][l]),
        ]
    };
    let s1 = sub(&p[1], &p[0]);
    let s2 = sub(&p[2], &p[0]);
    let e = sub(&p[2], &p[1]);
    let (q1, q2, qe) = (dot(&s1, &s1), dot(&s2, &s2), dot(&e, &e));
    // Plain edges, from the squared lengths (see `in_range`); a NaN is not plain.
    let in_range = |q: f64| (SQUARED_LO..SQUARED_HI).contains(&q);
    let plain = (0..BLOCK).fold(true, |all, l| {
        all & in_range(q1[l]) & in_range(q2[l]) & in_range(qe[l])
    });
    // In plain lanes the squared lengths are finite, so `max` is `fast_max`.
    let limit: W = std::array::from_fn(|l| DEGENERACY_RATIO * q1[l].max(q2[l]).max(qe[l]));
    let length = |x: [W; 3]| -> W { dot(&x, &x).map(f64::sqrt) };
    // The corners of `triangle_cotangents_lanes`: at p0 (s1, s2), at p1 (e, −s1), at
    // p2 (−s2, −e).
    let (cross0, cross1, cross2) = (
        length(cross(&s1, &s2)),
        length(cross(&e, &s1)),
        length(cross(&s2, &e)),
    );
    let (d0, d1, d2) = (dot(&s1, &s2), dot(&e, &s1), dot(&s2, &e));
    // `cot_lanes`: `dot / cross` where `cross > limit` and the quotient is finite, +0
    // elsewhere.
    let cot = |dot: W, cross: W| -> W {
        std::array::from_fn(|l| {
            let c = dot[l] / cross[l];
            if (cross[l] > limit[l]) & (c.abs() < f64::INFINITY) {
                c
            } else {
                0.0
            }
        })
    };
    let c0 = cot(d0, cross0);
    // `0 − d`, as the lanes' negation (`wide`'s `Neg`) computes it: +0 where the dot
    // product cancels to +0 (a right angle), as the corner's own `u · v` does; a sign
    // flip would give −0 there.
    let c1 = cot(d1.map(|d| 0.0 - d), cross1);
    let c2 = cot(d2, cross2);
    ([c1, c2, c0], plain)
}

/// The distances from `origin` to the points `positions[j]` for `j` in `targets` (vertex
/// indices), into `out`: the bits of [`distance`](super::distance), two at a time. For a
/// row of a sparse operator, whose columns are vertex indices.
///
/// # Panics
/// If `out` is shorter than `targets` or a target is out of bounds.
#[inline]
pub fn distances_into(origin: DVec3, positions: &[DVec3], targets: &[u32], out: &mut [f64]) {
    distances_with(origin, positions, targets, out, |d| d);
}

/// [`distances_into`] with `f` applied to each distance before it is stored: `out[k] =
/// f(distance(origin, positions[targets[k]]))`. One pass for a caller that stores a
/// function of the distance (an inverse-distance weight, say).
///
/// The distances are computed two at a time in SIMD lanes, and `f` is applied to both
/// lanes of a pair in one expression, so a branch-free `f` (such as `|d| 1.0 / (d +
/// eps)`) is compiled to packed instructions as well: one packed division per pair
/// instead of two scalar ones, the same bits (IEEE operations are correctly rounded in
/// every lane). Whether every pair was in the plain range (where the plain length is
/// the distance) is tested once for the whole row; if one was not, the row's pairs are
/// redone with the per-element distance, so `f` may be called more than once for a
/// slot (it should be a pure function).
///
/// # Panics
/// If `out` is shorter than `targets` or a target is out of bounds.
#[inline]
pub fn distances_with<F>(origin: DVec3, positions: &[DVec3], targets: &[u32], out: &mut [f64], f: F)
where
    F: Fn(f64) -> f64,
{
    let out = &mut out[..targets.len()];
    let o = V3 {
        x: Lanes::splat(origin.x),
        y: Lanes::splat(origin.y),
        z: Lanes::splat(origin.z),
    };
    let (lo, hi) = (Lanes::splat(SQRT_MIN), Lanes::splat(f64::INFINITY));
    // `f` of the plain lengths from `origin` to the targets `a` and `b`, and whether
    // both lengths are plain: at least sqrt(MIN_POSITIVE) and finite (NaN fails both
    // comparisons), where the plain length is the distance.
    let pair = |a: u32, b: u32| {
        let [a, b] = [positions[a as usize], positions[b as usize]];
        let v = V3 {
            x: Lanes::from([a.x, b.x]),
            y: Lanes::from([a.y, b.y]),
            z: Lanes::from([a.z, b.z]),
        } - o;
        let len = v.dot(v).sqrt();
        let [l0, l1] = len.to_array();
        ([f(l0), f(l1)], len.cmp_ge(lo) & len.cmp_lt(hi))
    };
    // The origin goes to the per-element fallback as three numbers: a `DVec3` passed
    // there would live on the stack, and the lanes above would then load its `y` and
    // `z` as one 16-byte read across two smaller stores, which the processor cannot
    // forward (a stall at the start of every row).
    let (ox, oy, oz) = (origin.x, origin.y, origin.z);
    let exact =
        |d: &mut [f64], targets: &[u32]| exact_distances(ox, oy, oz, positions, targets, d, &f);
    // Six neighbours, the most common row of a triangle mesh: no loop.
    if let (Ok(js), Ok(d)) = (
        <&[u32; 6]>::try_from(targets),
        <&mut [f64; 6]>::try_from(&mut *out),
    ) {
        let (d01, p01) = pair(js[0], js[1]);
        let (d23, p23) = pair(js[2], js[3]);
        let (d45, p45) = pair(js[4], js[5]);
        *d = [d01[0], d01[1], d23[0], d23[1], d45[0], d45[1]];
        if !(p01 & p23 & p45).all() {
            exact(d, js);
        }
        return;
    }
    let pairs = targets.chunks_exact(LANES);
    let tail = pairs.remainder();
    let (paired, rest) = out.split_at_mut(targets.len() - tail.len());
    // All lanes true: every pair so far was plain.
    let mut plain = lo.cmp_eq(lo);
    for (js, d) in pairs.zip(paired.chunks_exact_mut(LANES)) {
        let (w, p) = pair(js[0], js[1]);
        plain &= p;
        d.copy_from_slice(&w);
    }
    if !plain.all() {
        exact(paired, targets);
    }
    if !tail.is_empty() {
        exact(rest, tail);
    }
}

/// `out[k] = f(distance(origin, positions[targets[k]]))` with the per-element
/// distance, the origin `(ox, oy, oz)`: the fallback of [`distances_with`], out of its
/// loop.
#[cold]
#[inline(never)]
fn exact_distances<F>(
    ox: f64,
    oy: f64,
    oz: f64,
    positions: &[DVec3],
    targets: &[u32],
    out: &mut [f64],
    f: &F,
) where
    F: Fn(f64) -> f64,
{
    let origin = DVec3::new(ox, oy, oz);
    for (d, &j) in out.iter_mut().zip(targets) {
        *d = f(kernel::distance(origin, positions[j as usize]));
    }
}

/// The cotangent weights around one vertex, from its one-ring: the two cotangents
/// opposite each edge to a neighbour, summed, for a sparse operator whose rows list the
/// neighbours counter-clockwise and which keeps no per-triangle data.
///
/// The vertex is at `origin`; its neighbours are `positions[ring[k]]`, counter-clockwise
/// (as [`HalfedgeMesh::halfedges_around_vertex`](crate::HalfedgeMesh::halfedges_around_vertex)
/// visits them); triangle `k` is `(origin, ring[k], ring[k + 1])` (cyclically: `ring[n]`
/// is `ring[0]`) and is a face of the mesh when `is_triangle(k)` — on a triangle mesh,
/// every `k` at an interior vertex and every `k` but the boundary gap at a boundary
/// vertex (its first slot, where the circulator starts). Then
///
/// `out[k] = f(α_k + β_k)`
///
/// with `α_k` the cotangent at `ring[k + 1]` in triangle `k` and `β_k` the cotangent at
/// `ring[k − 1]` in triangle `k − 1` (+0 for a triangle that is not a face): the
/// cotangents opposite the edge to `ring[k]` in the face on its left and on its right,
/// so `f = |s| 0.5 · s` gives the cotangent weights. Each cotangent has the bits of
/// [`Geometry::opposite_cotangent`] for that corner (0 where the triangle is degenerate
/// as seen from the corner), computed two triangles at a time in SIMD lanes where the
/// edges are in the plain range and by the per-corner kernel elsewhere. Every corner is
/// its own: nothing depends on where a face starts, so the rows of both ends of an edge
/// agree bit for bit.
///
/// # Panics
/// If `out` is shorter than `ring` or a neighbour is out of bounds.
#[inline(always)]
pub fn ring_cotangents_with<P, F>(
    origin: DVec3,
    positions: &[DVec3],
    ring: &[u32],
    is_triangle: P,
    out: &mut [f64],
    f: F,
) where
    P: Fn(usize) -> bool,
    F: Fn(f64) -> f64,
{
    let n = ring.len();
    let out = &mut out[..n];
    let at = |k: usize| positions[ring[k] as usize];
    if n < 2 {
        // No two distinct neighbours: every cotangent is the kernel's (0 for a corner
        // whose two neighbours coincide).
        if n == 1 {
            let c = if is_triangle(0) {
                kernel::corner_cotangent(at(0), origin, at(0))
            } else {
                0.0
            };
            out[0] = f(c + c);
        }
        return;
    }
    let wrap = |k: usize| if k >= n { k - n } else { k };
    let o = V3 {
        x: Lanes::splat(origin.x),
        y: Lanes::splat(origin.y),
        z: Lanes::splat(origin.z),
    };
    // α of slot 0 waits for β of the last triangle; `carry` is β of the next slot.
    let mut first = 0.0;
    let mut carry = 0.0;
    let mut k = 0;
    while k < n {
        // Lane 0: triangle k = (ring[k], ring[k + 1]); lane 1: triangle k + 1.
        let p = [at(k), at(wrap(k + 1)), at(wrap(k + 2))];
        let v = |a: DVec3, b: DVec3| V3 {
            x: Lanes::from([a.x, b.x]),
            y: Lanes::from([a.y, b.y]),
            z: Lanes::from([a.z, b.z]),
        };
        let (at_b, at_a, plain) = ring_corners_lanes(o, v(p[0], p[1]), v(p[1], p[2]));
        let (at_b, at_a, plain) = (at_b.to_array(), at_a.to_array(), plain.move_mask());
        for l in 0..LANES {
            let t = k + l;
            if t == n {
                break;
            }
            let (alpha, beta) = if !is_triangle(t) {
                (0.0, 0.0)
            } else if plain & (1 << l) != 0 && at_b[l] != 0.0 && at_a[l] != 0.0 {
                // (A zero may have the wrong sign, see `cot_lanes`: the kernel's instead.)
                (at_b[l], at_a[l])
            } else {
                let (a, b) = (p[l], p[l + 1]);
                (
                    kernel::corner_cotangent(b, origin, a),
                    kernel::corner_cotangent(a, origin, b),
                )
            };
            if t == 0 {
                first = alpha;
            } else {
                out[t] = f(alpha + carry);
            }
            carry = beta;
        }
        k += LANES;
    }
    out[0] = f(first + carry);
}

/// For [`LANES`] triangles `(o, a, b)`: the cotangents at `b` and at `a` (the kernel's
/// `Corner::cot`, operation by operation) and a mask of the lanes whose three edges are
/// all plain (finite, largest component in `[2^-200, 2^200]`); other lanes' values are
/// meaningless.
#[inline(always)]
fn ring_corners_lanes(o: V3<Lanes>, a: V3<Lanes>, b: V3<Lanes>) -> (Lanes, Lanes, Lanes) {
    let da = a - o;
    let db = b - o;
    let e = b - a;
    let (qa, qb, qe) = (da.dot(da), db.dot(db), e.dot(e));
    let plain = in_range(qa) & in_range(qb) & in_range(qe);
    // Plain lanes: finite, not NaN, `fast_max` is `f64::max` (see
    // `triangle_cotangents_lanes`).
    let limit = Lanes::splat(DEGENERACY_RATIO) * qa.fast_max(qb).fast_max(qe);
    // Corner at b: u = o − b = −db, v = a − b = −e, so u · v = db · e and u × v = db × e
    // (each product of two negated factors is the product of the factors) up to the
    // signs of zeros, which the caller takes from the kernel (see `cot_lanes`).
    let xb = db.cross(e);
    let at_b = cot_lanes(db.dot(e), xb.dot(xb).sqrt(), limit);
    // Corner at a: u = o − a = −da, v = b − a = e: u · v = −(da · e), |u × v| = |da × e|.
    let xa = da.cross(e);
    let at_a = cot_lanes(-da.dot(e), xa.dot(xa).sqrt(), limit);
    (at_b, at_a, plain)
}

/// Plain squared edge lengths: `|s|² ≥ 2^-398` implies a component of at least 2^-200
/// (three squares below 2^-400 round to at most 3 · 2^-400), and `|s|² < 2^400` implies
/// every component below 2^200 (a larger square rounds to at least 2^400). NaN and
/// infinite components fail the second test.
#[inline(always)]
fn in_range(q: Lanes) -> Lanes {
    q.cmp_ge(Lanes::splat(SQUARED_LO)) & q.cmp_lt(Lanes::splat(SQUARED_HI))
}

/// The cotangents opposite the three halfedges of triangle `(p0, p1, p2)` (in face
/// order, the halfedges ending at p0, p1, p2), each 0 where the triangle is degenerate
/// as seen from its corner: the kernel's, as [`Geometry::face_opposite_cotangents`]
/// computes them (which first skips a triangle degenerate at every corner, whose
/// cotangents are all 0 anyway).
#[inline]
fn triangle_cotangents(p0: DVec3, p1: DVec3, p2: DVec3) -> [f64; 3] {
    // h0 ends at p0, so its opposite corner is p1; h1 ↔ p2; h2 ↔ p0.
    [
        kernel::corner_cotangent(p1, p2, p0),
        kernel::corner_cotangent(p2, p0, p1),
        kernel::corner_cotangent(p0, p1, p2),
    ]
}

/// [`triangle_cotangents`] for [`LANES`] triangles at once, in the plain frames: where
/// the three edge vectors of a triangle are in the plain range (largest component in
/// `[2^-200, 2^200]`), the kernel's frames are the plain differences and its operations
/// are these, lane by lane. Returns the cotangents opposite the halfedges ending at `p0`, `p1`, `p2`
/// and a mask of the lanes whose three edge vectors are all plain (finite, largest
/// component in `[2^-200, 2^200]`); other lanes' values are meaningless.
#[inline(always)]
fn triangle_cotangents_lanes(p0: V3<Lanes>, p1: V3<Lanes>, p2: V3<Lanes>) -> ([Lanes; 3], Lanes) {
    let s1 = p1 - p0;
    let s2 = p2 - p0;
    let e = p2 - p1;
    let (q1, q2, qe) = (s1.dot(s1), s2.dot(s2), e.dot(e));
    // Plain edges, from the squared lengths (see `in_range`).
    let plain = in_range(q1) & in_range(q2) & in_range(qe);
    // Each corner's degeneracy test (`Corner::is_degenerate`) compares its own cross
    // product with the longest of the same three squared edges, the plain differences
    // in plain lanes. They are finite and not NaN there, where `fast_max` is `f64::max`
    // (and the largest of three numbers does not depend on their order).
    let limit = Lanes::splat(DEGENERACY_RATIO) * q1.fast_max(q2).fast_max(qe);
    // Corner 0 at p0: u = s1, v = s2.
    let x0 = s1.cross(s2);
    let cross0 = x0.dot(x0).sqrt();
    // Corner 1 at p1: u = p2 − p1 = e, v = p0 − p1 = −s1 (up to the signs of zeros):
    // u · v = −(e · s1) where it is not zero (see `cot_lanes`), and |u × v| = |e × s1|.
    let x1 = e.cross(s1);
    let cross1 = x1.dot(x1).sqrt();
    // Corner 2 at p2: u = p0 − p2 = −s2, v = p1 − p2 = −e: the products of s2 and e
    // (each product of two negated factors is the product of the factors), up to the
    // signs of zeros.
    let x2 = s2.cross(e);
    let cross2 = x2.dot(x2).sqrt();
    let c0 = cot_lanes(s1.dot(s2), cross0, limit);
    let c1 = cot_lanes(-e.dot(s1), cross1, limit);
    let c2 = cot_lanes(s2.dot(e), cross2, limit);
    ([c1, c2, c0], plain)
}

/// `Corner::cot` lane by lane, in plain lanes: `dot / cross` where `cross > limit`
/// (`DEGENERACY_RATIO` times the longest squared edge; false for NaN) and the quotient
/// is finite, +0 elsewhere.
///
/// A zero from the lanes is computed again by the per-corner kernel, by every caller. The
/// lanes take corners 1 and 2's products from three shared edge vectors (`s1 = p1 −
/// p0`, `s2 = p2 − p0`, `e = p2 − p1`) rather than from each corner's own (`p0 − p1`
/// and so on), exact up to signs: each own vector is the negated shared one, except that
/// `x − x` is +0 in both orders. So a nonzero dot product is the corner's own bit for
/// bit, but one whose terms are all zeros takes its sign from them and may come out −0
/// where the corner's own is +0, or the reverse (a right angle out of a coordinate plane,
/// `[(1,0,0), (0,1,1), (0,0,0)]`), and a weight −0 where OpenMesh's is +0. Zeros are
/// rare, so they go through the kernel instead of every corner taking its own vectors
/// (which cost 5 to 10 % of a cotangent run).
#[inline(always)]
fn cot_lanes(dot: Lanes, cross: Lanes, limit: Lanes) -> Lanes {
    let c = dot / cross;
    let finite = c.abs().cmp_lt(Lanes::splat(f64::INFINITY));
    c & (cross.cmp_gt(limit) & finite)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::HalfedgeMesh;
    use crate::geometry::distance;
    use crate::geometry::kernel::{Corner, Triangle};
    use crate::geometry::kernel::{SAFE_HI, SAFE_LO};

    /// A deterministic generator of numbers in [-1, 1) (SplitMix64).
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^= z >> 31;
            (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        }
        fn point(&mut self) -> DVec3 {
            DVec3::new(self.next(), self.next(), self.next())
        }
    }

    /// Triangles that exercise every branch: ordinary, obtuse (negative cotangents),
    /// degenerate and nearly degenerate on both sides of the threshold, coincident
    /// points, scales near and far outside the plain range, NaN and infinite points.
    fn triangles() -> Vec<[DVec3; 3]> {
        let mut rng = Rng(3);
        let mut out = Vec::new();
        for _ in 0..64 {
            out.push([rng.point(), rng.point(), rng.point()]);
        }
        let (a, b) = (DVec3::new(0.3, -0.2, 0.1), DVec3::new(1.1, 0.4, -0.3));
        let n = DVec3::new(0.2, -0.1, 0.9).cross(b - a).normalize();
        for h in [
            0.0, 1e-14, 1e-13, 0.99e-12, 1e-12, 1.01e-12, 1e-11, 1e-6, 0.5, 3.0,
        ] {
            for t in [-0.7, 0.1, 0.5, 1.6] {
                let c = a + (b - a) * t + n * (h * (b - a).length());
                out.push([a, b, c]);
                out.push([c, a, b]);
            }
        }
        out.push([a, a, b]);
        out.push([a, b, b]);
        out.push([a; 3]);
        out.push([DVec3::ZERO; 3]);
        // Largest edge components around 2^±200 and far outside.
        let base: Vec<[DVec3; 3]> = out.iter().take(16).copied().collect();
        for s in [
            2f64.powi(-201),
            2f64.powi(-200),
            2f64.powi(-199),
            1e-59,
            1e58,
            2f64.powi(199),
            2f64.powi(200),
            1e-170,
            1e170,
            1e-300,
            1e300,
            1e308,
        ] {
            for t in &base {
                out.push(t.map(|p| p * s));
            }
        }
        // Far from the origin (cancellation in the differences).
        for t in base.iter().take(4) {
            out.push(t.map(|p| p * 1e-9 + DVec3::splat(1e7)));
        }
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let [p, q, r] = base[0];
            out.push([DVec3::new(bad, p.y, p.z), q, r]);
            out.push([p, DVec3::new(q.x, bad, q.z), r]);
            out.push([p, q, DVec3::new(r.x, r.y, bad)]);
            out.push([DVec3::splat(bad), q, r]);
        }
        out.push([
            DVec3::splat(-1.5e308),
            DVec3::splat(1.5e308),
            DVec3::new(1e308, -1e308, 0.0),
        ]);
        // Right angles whose dot products are exact zeros: every ordered triangle of
        // three points of {−1, 0, 1}³ that are not on a line, in and out of the
        // coordinate planes (where a zero's sign depends on which point an edge vector
        // subtracts): the sign of a zero cotangent is the corner's own.
        let point = |k: usize| {
            DVec3::new(
                (k % 3) as f64 - 1.0,
                (k / 3 % 3) as f64 - 1.0,
                (k / 9) as f64 - 1.0,
            )
        };
        for a in 0..27 {
            for b in (0..27).filter(|&b| b != a) {
                for c in (0..27).filter(|&c| c != a && c != b) {
                    let t = [point(a), point(b), point(c)];
                    if (t[1] - t[0]).cross(t[2] - t[0]) != DVec3::ZERO
                        && (a + 3 * b + 7 * c) % 13 == 0
                    {
                        out.push(t);
                    }
                }
            }
        }
        out
    }

    /// The triangles as a soup mesh, its positions, and each face's vertices in face
    /// order (the ends of the face's halfedges from `face_halfedge`).
    fn soup(tris: &[[DVec3; 3]]) -> (HalfedgeMesh, Vec<DVec3>, Vec<[VertexId; 3]>) {
        let faces: Vec<[u32; 3]> = (0..tris.len() as u32)
            .map(|k| [3 * k, 3 * k + 1, 3 * k + 2])
            .collect();
        let mesh = HalfedgeMesh::from_polygons(3 * tris.len(), &faces).unwrap();
        let positions: Vec<DVec3> = tris.iter().flatten().copied().collect();
        let order = mesh
            .faces()
            .map(|f| {
                let h0 = mesh.face_halfedge(f);
                let h1 = mesh.next(h0);
                let h2 = mesh.next(h1);
                [h0, h1, h2].map(|h| mesh.to_vertex(h))
            })
            .collect();
        (mesh, positions, order)
    }

    /// The per-face query's three cotangents of every face, in face order.
    fn per_face_cotangents(geometry: &Geometry<'_>) -> Vec<f64> {
        geometry
            .mesh
            .faces()
            .flat_map(|f| {
                let t = geometry.face_opposite_cotangents(f).unwrap();
                [t[0].1, t[1].1, t[2].1]
            })
            .collect()
    }

    fn bits(x: &[f64]) -> Vec<u64> {
        x.iter().map(|x| x.to_bits()).collect()
    }

    /// Every slice (each start and length, so every tail length and every mix of
    /// plain, degenerate and rescaled lanes in a batch) gives the per-face query's bits,
    /// and so does the whole-mesh query.
    #[test]
    fn batched_cotangents_have_the_bits_of_the_per_face_query() {
        let (mesh, positions, order) = soup(&triangles());
        let geometry = Geometry::new(&mesh, &positions).unwrap();
        let want = per_face_cotangents(&geometry);
        for start in 0..order.len() {
            for len in (0..=9).chain([order.len() - start]) {
                let Some(slice) = order.get(start..start + len) else {
                    continue;
                };
                let mut out = vec![f64::NAN; 3 * len];
                geometry.triangle_cotangents_into(slice, &mut out);
                assert_eq!(
                    bits(&out),
                    bits(&want[3 * start..3 * (start + len)]),
                    "{start}+{len}"
                );
            }
        }
        let mut all = vec![[f64::NAN; 3]; mesh.n_faces()];
        geometry.face_cotangents_into(&mut all).unwrap();
        assert_eq!(bits(all.as_flattened()), bits(&want));
    }

    /// The blocked layout has the per-face query's bits at `blocked_index` for every
    /// slice (each start and length: every short last block, every mix of plain,
    /// degenerate and rescaled lanes in a block), zeros in a short last block's unused
    /// lanes, and the same bits compiled for the baseline (SSE2) as for the widest
    /// registers the processor has.
    #[test]
    fn blocked_cotangents_have_the_bits_of_the_per_face_query() {
        let (mesh, positions, order) = soup(&triangles());
        let geometry = Geometry::new(&mesh, &positions).unwrap();
        let want = per_face_cotangents(&geometry);
        for start in 0..order.len() {
            for len in (0..=9).chain([order.len() - start]) {
                let Some(slice) = order.get(start..start + len) else {
                    continue;
                };
                let n = 3 * BLOCK * len.div_ceil(BLOCK);
                let mut out = vec![f64::NAN; n];
                geometry.triangle_cotangents_blocked_into(slice, &mut out);
                let mut baseline = vec![f64::NAN; n];
                pulp::Arch::Scalar.dispatch(BlockedCotangents {
                    positions: &positions,
                    triangles: slice,
                    out: &mut baseline,
                });
                assert_eq!(bits(&out), bits(&baseline), "{start}+{len}");
                let mut expected = vec![0.0; n];
                for t in 0..len {
                    for k in 0..3 {
                        expected[blocked_index(t, k)] = want[3 * (start + t) + k];
                    }
                }
                assert_eq!(bits(&out), bits(&expected), "{start}+{len}");
            }
        }
    }

    /// Every corner's cotangent is its own: rotating a triangle's vertex list (so that
    /// the face starts at another vertex) gives every corner the same bits, in the
    /// per-face query and in the lanes alike.
    #[test]
    fn corner_cotangents_do_not_depend_on_where_the_face_starts() {
        let tris = triangles();
        let rotated: Vec<[DVec3; 3]> = tris.iter().map(|&[a, b, c]| [b, c, a]).collect();
        let (mesh, positions, order) = soup(&tris);
        let (mesh_r, positions_r, order_r) = soup(&rotated);
        let g = Geometry::new(&mesh, &positions).unwrap();
        let gr = Geometry::new(&mesh_r, &positions_r).unwrap();
        let mut out = vec![0.0; 3 * order.len()];
        let mut out_r = vec![0.0; 3 * order.len()];
        g.triangle_cotangents_into(&order, &mut out);
        gr.triangle_cotangents_into(&order_r, &mut out_r);
        for (k, (o, r)) in out.chunks(3).zip(out_r.chunks(3)).enumerate() {
            // Opposite the halfedges ending at a, b, c: corners b, c, a; rotated, the
            // halfedges end at b, c, a, opposite corners c, a, b.
            assert_eq!(bits(o), bits(&[r[2], r[0], r[1]]), "triangle {k}");
        }
    }

    /// The degeneracy test of the corner (`Corner::is_degenerate`, its own cross product
    /// against the longest of the three plain edges) against the one it replaced (the
    /// cross product in the frame at the face's first vertex, the third edge as the
    /// difference of the other two): on triangles whose exact ratio of twice the area to
    /// the longest edge squared is known, both give the exact answer unless that ratio
    /// lies within 1 % of `DEGENERACY_RATIO` — only triangles at the threshold changed.
    #[test]
    fn the_corner_test_changes_only_triangles_at_the_threshold() {
        let old = |[p0, p1, p2]: [DVec3; 3]| {
            let (s1, s2) = (p1 - p0, p2 - p0);
            let s3 = s2 - s1;
            let longest2 = s1.dot(s1).max(s2.dot(s2)).max(s3.dot(s3));
            let two_area = s1.cross(s2).length();
            two_area <= DEGENERACY_RATIO * longest2 || two_area.is_nan()
        };
        let mut rng = Rng(41);
        let (mut near, mut changed) = (0, 0);
        for _ in 0..400 {
            let (a, b) = (rng.point(), rng.point());
            let base = b - a;
            let len = base.length();
            let n = rng.point().cross(base).normalize();
            // The apex over the base (the base is the longest edge): ratio h / len.
            let t = 0.5 + 0.45 * rng.next();
            for delta in [
                -0.5, -0.1, -0.01, -1e-3, -1e-5, 0.0, 1e-5, 1e-3, 0.01, 0.1, 0.5,
            ] {
                let h = len * DEGENERACY_RATIO * (1.0 + delta);
                let c = a + base * t + n * h;
                for t in [[a, b, c], [b, c, a], [c, a, b]] {
                    let corners = [
                        Corner::new(t[0], t[1], t[2]),
                        Corner::new(t[1], t[2], t[0]),
                        Corner::new(t[2], t[0], t[1]),
                    ];
                    let exact = delta <= 0.0;
                    for corner in corners {
                        let new = corner.is_degenerate();
                        if f64::abs(delta) >= 0.01 {
                            assert_eq!(new, exact, "{delta}");
                            assert_eq!(old(t), exact, "{delta}");
                        } else {
                            near += 1;
                            changed += usize::from(new != old(t));
                        }
                    }
                    assert_eq!(
                        Triangle(t).is_degenerate(),
                        corners.iter().all(|c| c.is_degenerate())
                    );
                }
            }
        }
        // At the threshold the two tests do disagree sometimes (rounding).
        assert!(near > 0 && changed < near, "{changed} of {near}");
    }

    /// The one-ring kernel gives, for every slot of every row, the bits of the two
    /// per-halfedge queries summed (`opposite_cotangent` of the slot's halfedge and of
    /// its twin): closed and open meshes, rows of every length, plain and rescaled and
    /// degenerate triangles side by side, a quad.
    #[test]
    fn ring_cotangents_have_the_bits_of_the_per_halfedge_query() {
        let mut rng = Rng(7);
        let mut cases: Vec<(HalfedgeMesh, Vec<DVec3>)> = Vec::new();
        let sphere = crate::primitives::icosphere(2);
        let x: Vec<DVec3> = sphere
            .positions
            .iter()
            .map(|&p| p * (1.0 + 0.3 * rng.next()))
            .collect();
        cases.push((sphere.mesh().unwrap(), x));
        let grid = crate::primitives::grid(7, 6);
        let mesh = grid.mesh().unwrap();
        let x: Vec<DVec3> = grid
            .positions
            .iter()
            .map(|&p| p + rng.point() * 0.4)
            .collect();
        cases.push((mesh.clone(), x.clone()));
        let mut y = x.clone();
        for k in (0..y.len() - 1).step_by(3) {
            y[k] = y[k + 1];
        }
        y[10] = (y[11] + y[9]) * 0.5;
        cases.push((mesh.clone(), y));
        for s in [1e-250, 1e250, 1e300] {
            let y = x
                .iter()
                .enumerate()
                .map(|(k, &p)| if k % 4 == 1 { p * s } else { p })
                .collect();
            cases.push((mesh.clone(), y));
        }
        let mut y = x.clone();
        y[20] = DVec3::new(f64::NAN, 0.0, 0.0);
        cases.push((mesh, y));
        // Fans of every short length, and long ones.
        for n in (1..=7u32).chain([29, 30, 31, 40]) {
            for closed in [false, true] {
                let faces: Vec<[u32; 3]> = (1..=n)
                    .filter(|&k| closed || k < n)
                    .map(|k| [0, k, k % n + 1])
                    .collect();
                if faces.is_empty() || (closed && n < 3) {
                    continue;
                }
                let mesh = HalfedgeMesh::from_polygons(n as usize + 1, &faces).unwrap();
                let mut x: Vec<DVec3> = (0..=n).map(|_| rng.point()).collect();
                cases.push((mesh.clone(), x.clone()));
                // A far and a collapsed neighbour: corners redone by the kernel.
                x[2] *= 1e260;
                x[n as usize] = x[n as usize - 1];
                cases.push((mesh, x));
            }
        }
        let faces: [&[u32]; 3] = [&[0, 1, 2], &[0, 2, 3, 4], &[0, 4, 5]];
        let mesh = HalfedgeMesh::from_polygons(6, faces).unwrap();
        cases.push((mesh, (0..6).map(|_| rng.point()).collect()));
        for (c, (mesh, x)) in cases.iter().enumerate() {
            let g = Geometry::new(mesh, x).unwrap();
            for v in mesh.vertices() {
                let hs: Vec<_> = mesh.halfedges_around_vertex(v).collect();
                let ring: Vec<u32> = hs.iter().map(|&h| mesh.to_vertex(h).raw()).collect();
                let is_triangle = |k: usize| {
                    let h = hs[k];
                    mesh.face(h).is_some() && mesh.next(mesh.next(mesh.next(h))) == h
                };
                let mut out = vec![f64::NAN; ring.len() + 1];
                ring_cotangents_with(x[v.index()], x, &ring, is_triangle, &mut out, |c| c);
                let want: Vec<f64> = hs
                    .iter()
                    .map(|&h| g.opposite_cotangent(h) + g.opposite_cotangent(h.twin()))
                    .chain([f64::NAN])
                    .collect();
                assert_eq!(bits(&out), bits(&want), "case {c} vertex {v}");
            }
        }
    }

    /// The plain-range test on squared lengths accepts only edges whose largest
    /// component is in [2^-200, 2^200] (so the lanes never take a triangle the kernel
    /// would rescale), and accepts the ordinary ones.
    #[test]
    fn squared_range_is_inside_the_plain_range() {
        let plain = |e: DVec3| {
            let m = e.abs().max_element();
            e.is_finite() && (SAFE_LO..=SAFE_HI).contains(&m)
        };
        let mut rng = Rng(11);
        for e in -215..=215 {
            for _ in 0..40 {
                let s = DVec3::new(rng.next(), rng.next(), rng.next()) * 2f64.powi(e);
                let q = s.dot(s);
                let accepted = (SQUARED_LO..SQUARED_HI).contains(&q);
                if accepted {
                    assert!(plain(s), "{s:?}");
                }
                if (-190..=190).contains(&e) && s.abs().max_element() > 0.01 * 2f64.powi(e) {
                    assert!(accepted, "{s:?}");
                }
            }
        }
    }

    /// Every row length (tails), plain and rescaled slots mixed in one pair.
    #[test]
    fn batched_distances_have_the_bits_of_distance() {
        let mut rng = Rng(23);
        let mut positions: Vec<DVec3> = (0..40).map(|_| rng.point()).collect();
        let xi = positions[0];
        positions.extend([
            xi,
            xi + DVec3::new(1e-160, 0.0, 0.0),
            xi + DVec3::new(3e-154, 0.0, 0.0),
            DVec3::splat(1e300),
            DVec3::splat(-1e308),
            DVec3::new(f64::NAN, 0.0, 0.0),
            DVec3::new(0.0, f64::INFINITY, 0.0),
        ]);
        let n = positions.len() as u32;
        let targets: Vec<u32> = (0..3 * n).map(|k| (k * 7 + 3) % n).collect();
        for start in 0..targets.len() {
            for len in 0..=9 {
                let Some(nb) = targets.get(start..start + len) else {
                    continue;
                };
                let mut out = vec![0.0; len + 2];
                distances_into(xi, &positions, nb, &mut out);
                let want: Vec<f64> = nb
                    .iter()
                    .map(|&j| distance(xi, positions[j as usize]))
                    .chain([0.0, 0.0])
                    .collect();
                assert_eq!(bits(&out), bits(&want), "{start}+{len}");
            }
        }
    }

    /// `distances_with` applies its function to the bits of `distance` for every slot:
    /// the inverse-distance weight and its clamped and absolute forms (which the lanes
    /// compute two at a time), on every row length, with rows of six (the unrolled
    /// path) that mix plain slots with coincident, tiny, huge, NaN and infinite ones.
    #[test]
    fn distances_with_applies_f_to_every_distance() {
        let mut rng = Rng(29);
        let mut positions: Vec<DVec3> = (0..30).map(|_| rng.point()).collect();
        let xi = positions[0];
        positions.extend([
            xi,
            xi + DVec3::new(0.0, 1e-160, 0.0),
            DVec3::splat(1e300),
            DVec3::splat(-1e308),
            DVec3::new(0.0, 0.0, f64::NAN),
            DVec3::new(f64::NEG_INFINITY, 0.0, 0.0),
        ]);
        let n = positions.len() as u32;
        let special = |j: u32| j == 0 || j >= 30;
        let targets: Vec<u32> = (0..4 * n).map(|k| (k * 5 + 1) % n).collect();
        let fs: [fn(f64) -> f64; 3] = [
            |d| 1.0 / (d + 1e-12),
            |d| (1.0 / (d + 1e-12)).max(0.0),
            |d| (1.0 / (d + 1e-12)).abs(),
        ];
        let mut mixed_sixes = 0;
        for (c, f) in fs.iter().enumerate() {
            for start in 0..targets.len() {
                for len in 0..=9 {
                    let Some(nb) = targets.get(start..start + len) else {
                        continue;
                    };
                    if len == 6 && nb.iter().any(|&j| special(j)) && !nb.iter().all(|&j| special(j))
                    {
                        mixed_sixes += 1;
                    }
                    let mut out = vec![-7.0; len + 1];
                    distances_with(xi, &positions, nb, &mut out, f);
                    let want: Vec<f64> = nb
                        .iter()
                        .map(|&j| f(distance(xi, positions[j as usize])))
                        .chain([-7.0])
                        .collect();
                    assert_eq!(bits(&out), bits(&want), "function {c}, {start}+{len}");
                }
            }
        }
        assert!(mixed_sixes > 0);
    }

    /// `f` of the square roots of squared lengths has the bits of `f` of the geometry's
    /// distance where every length is plain, and says so; one length that is not
    /// (coincident points, 1e-160 apart, beyond 1e154, NaN, infinite) anywhere in a
    /// slice of any length makes it say not; the bits do not depend on the vector width.
    #[test]
    fn lengths_with_are_the_distances_where_plain() {
        let mut rng = Rng(31);
        let mut positions: Vec<DVec3> = (0..40).map(|_| rng.point()).collect();
        let xi = positions[0];
        let odd = [
            xi,
            xi + DVec3::new(0.0, 1e-160, 0.0),
            DVec3::splat(1e300),
            DVec3::new(0.0, 0.0, f64::NAN),
            DVec3::new(f64::NEG_INFINITY, 0.0, 0.0),
        ];
        positions.extend(odd);
        let f = |d: f64| 1.0 / (d + 1e-12);
        for start in 1..positions.len() {
            for len in 0..=9 {
                let Some(points) = positions.get(start..start + len) else {
                    continue;
                };
                let mut q: Vec<f64> = points.iter().map(|&p| (p - xi).length_squared()).collect();
                let mut baseline = q.clone();
                let plain = lengths_with(&mut q, f);
                let base_plain = pulp::Arch::Scalar.dispatch(Lengths {
                    squared: &mut baseline,
                    f,
                });
                assert_eq!(plain, base_plain, "{start}+{len}");
                assert_eq!(bits(&q), bits(&baseline), "{start}+{len}");
                assert_eq!(plain, len == 0 || start + len <= 40, "{start}+{len}");
                if plain {
                    let want: Vec<f64> = points.iter().map(|&p| f(distance(xi, p))).collect();
                    assert_eq!(bits(&q), bits(&want), "{start}+{len}");
                }
            }
        }
        // A length of 1e-160 (not a coincident point) is below the plain range.
        let mut tiny = [DVec3::new(0.0, 1e-160, 0.0).length_squared(), 1.0, 4.0, 9.0];
        assert!(!lengths_with(&mut tiny, f));
        let mut fine = [DVec3::new(0.0, 1e-150, 0.0).length_squared(), 1.0, 4.0, 9.0];
        assert!(lengths_with(&mut fine, f));
    }

    /// On closed fans of three triangles with right angles in and out of the coordinate
    /// planes, each slot's two cotangents have the bits, signs of zeros included, of
    /// the kernel's corners summed in the kernel's order.
    #[test]
    fn ring_cotangents_keep_the_signs_of_the_corners_own_zeros() {
        let point = |k: usize| {
            DVec3::new(
                (k % 3) as f64 - 1.0,
                (k / 3 % 3) as f64 - 1.0,
                (k / 9) as f64 - 1.0,
            )
        };
        let mut zeros = 0;
        for o in [0, 4, 13, 22] {
            for k in 0..27 * 27 * 27 {
                let ring = [k % 27, k / 27 % 27, k / 729];
                if ring.contains(&o)
                    || ring[0] == ring[1]
                    || ring[1] == ring[2]
                    || ring[0] == ring[2]
                {
                    continue;
                }
                let (origin, q) = (point(o), ring.map(point));
                let positions: Vec<DVec3> = q.to_vec();
                let mut out = [f64::NAN; 3];
                ring_cotangents_with(origin, &positions, &[0, 1, 2], |_| true, &mut out, |c| c);
                // Slot t: the angle at q[t + 1] in (o, q[t], q[t + 1]) and the angle at
                // q[t − 1] in (o, q[t − 1], q[t]).
                let want: [f64; 3] = std::array::from_fn(|t| {
                    let (prev, next) = (q[(t + 2) % 3], q[(t + 1) % 3]);
                    kernel::corner_cotangent(next, origin, q[t])
                        + kernel::corner_cotangent(prev, origin, q[t])
                });
                zeros += want.iter().filter(|&&w| w == 0.0).count();
                assert_eq!(
                    out.map(f64::to_bits),
                    want.map(f64::to_bits),
                    "{origin} {q:?}"
                );
            }
        }
        assert!(zeros > 0);
    }

    /// The parallel vertex areas are the per-vertex query's, for both kinds.
    #[test]
    fn vertex_areas_into_has_the_bits_of_the_per_vertex_query() {
        let sphere = crate::primitives::icosphere(3);
        let mesh = sphere.mesh().unwrap();
        let mut rng = Rng(5);
        let x: Vec<DVec3> = sphere
            .positions
            .iter()
            .map(|&p| p * (1.0 + 0.2 * rng.next()))
            .collect();
        let geometry = Geometry::new(&mesh, &x).unwrap();
        for kind in [VertexAreaKind::Barycentric, VertexAreaKind::MixedVoronoi] {
            let mut out = vec![f64::NAN; mesh.n_vertices()];
            geometry.vertex_areas_into(kind, &mut out).unwrap();
            for v in mesh.vertices() {
                assert_eq!(
                    out[v.index()].to_bits(),
                    geometry.vertex_area(v, kind).to_bits()
                );
            }
        }
    }
}
