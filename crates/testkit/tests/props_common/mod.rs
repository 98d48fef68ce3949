//! Generators and helpers shared by the property tests (`properties_*.rs`).
//!
//! Default case counts are chosen so that the whole property suite runs in well under a
//! minute on two cores in the test profile; `PROPTEST_CASES=N` overrides them all.

#![allow(
    dead_code,
    unreachable_pub,
    reason = "each test binary uses a different part of this module"
)]

use beltrami_halfedge::primitives::{self, Primitive};
use beltrami_halfedge::{BuildOptions, DVec3, HalfedgeMesh};
use proptest::prelude::*;

/// The proptest configuration of a property: `cases` unless `PROPTEST_CASES` is set.
pub fn config(cases: u32) -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(cases);
    ProptestConfig {
        cases,
        // No shrinking marathons: a failing case is reported after at most this many
        // shrink steps.
        max_shrink_iters: 2048,
        ..ProptestConfig::default()
    }
}

/// An arbitrary polygon soup: a vertex count and faces whose indices may repeat, be out
/// of range (up to `n + 1`) or form faces of fewer than three vertices.
#[derive(Clone, Debug)]
pub struct Soup {
    /// The vertex count.
    pub n_vertices: usize,
    /// The faces.
    pub faces: Vec<Vec<u32>>,
}

/// Polygon soups of up to 24 vertices and 32 faces: half of them wild (faces of 0 to 6
/// corners, any index up to `n + 1`), half triangle soups over few vertices (in range,
/// so that many build, with or without repairs).
pub fn soup() -> impl Strategy<Value = Soup> {
    let wild = (0usize..24).prop_flat_map(|n| {
        let index = 0..(n as u32 + 2);
        prop::collection::vec(prop::collection::vec(index, 0..7), 0..32).prop_map(move |faces| {
            Soup {
                n_vertices: n,
                faces,
            }
        })
    });
    let triangles = (3usize..10).prop_flat_map(|n| {
        let index = 0..n as u32;
        prop::collection::vec(
            [index.clone(), index.clone(), index].prop_map(|t| t.to_vec()),
            1..12,
        )
        .prop_map(move |faces| Soup {
            n_vertices: n,
            faces,
        })
    });
    prop_oneof![wild, triangles]
}

/// The procedural shape a random mesh starts from.
#[derive(Clone, Copy, Debug)]
pub enum Shape {
    /// An open grid of `nx × ny` squares (triangulated).
    Grid(u32, u32),
    /// An icosphere of the given subdivision level (closed, genus 0).
    Icosphere(u32),
    /// A torus with `n_major × n_minor` quads, triangulated (closed, genus 1).
    Torus(u32, u32),
    /// A regular hexagon fan (open, one interior vertex).
    HexagonFan,
    /// A tetrahedron.
    Tetrahedron,
    /// A cube of quads (not a triangle mesh).
    CubeQuads,
}

impl Shape {
    /// The shape's vertices and faces.
    pub fn primitive(self) -> Primitive {
        match self {
            Self::Grid(nx, ny) => primitives::grid(nx, ny),
            Self::Icosphere(level) => primitives::icosphere(level),
            Self::Torus(a, b) => primitives::torus(2.0, 0.7, a, b),
            Self::HexagonFan => primitives::hexagon_fan(),
            Self::Tetrahedron => primitives::tetrahedron(),
            Self::CubeQuads => primitives::cube_quads(),
        }
    }
}

/// Triangle-mesh shapes only.
pub fn triangle_shape() -> impl Strategy<Value = Shape> {
    prop_oneof![
        3 => (1u32..7, 1u32..7).prop_map(|(a, b)| Shape::Grid(a, b)),
        2 => (0u32..2).prop_map(Shape::Icosphere),
        2 => (3u32..8, 3u32..6).prop_map(|(a, b)| Shape::Torus(a, b)),
        1 => Just(Shape::HexagonFan),
        1 => Just(Shape::Tetrahedron),
    ]
}

/// Any shape, quads included.
pub fn any_shape() -> impl Strategy<Value = Shape> {
    prop_oneof![
        8 => triangle_shape(),
        1 => Just(Shape::CubeQuads),
    ]
}

/// A way to make geometry degenerate.
#[derive(Clone, Copy, Debug)]
pub enum Degeneracy {
    /// Vertex `a` moves onto vertex `b` (coincident vertices).
    Coincide(usize, usize),
    /// The third corner of a face moves onto the line through its first two, at
    /// parameter `t` (a zero-area face, or a face with two coincident corners).
    ZeroArea(usize, f64),
    /// The third corner of a face moves to `1e-9` of an edge length from the line
    /// through its first two (a needle or a cap).
    Needle(usize, f64),
    /// The whole mesh is flattened onto the plane z = 0.
    Flatten,
}

/// Degeneracies; indices are taken modulo the vertex or face count.
pub fn degeneracy() -> impl Strategy<Value = Degeneracy> {
    prop_oneof![
        (any::<usize>(), any::<usize>()).prop_map(|(a, b)| Degeneracy::Coincide(a, b)),
        (any::<usize>(), -1.0f64..2.0).prop_map(|(f, t)| Degeneracy::ZeroArea(f, t)),
        (any::<usize>(), -1.0f64..2.0).prop_map(|(f, t)| Degeneracy::Needle(f, t)),
        Just(Degeneracy::Flatten),
    ]
}

/// What a random mesh is made of: a shape, faces removed, per-vertex noise and
/// degeneracies. [`MeshSpec::realise`] turns it into a valid mesh.
#[derive(Clone, Debug)]
pub struct MeshSpec {
    /// The starting shape.
    pub shape: Shape,
    /// Face `f` is removed when `remove[f % len]` is true (no face is removed when empty).
    pub remove: Vec<bool>,
    /// Noise per vertex (cyclic), in units of `noise_scale` times the mean edge length.
    pub noise: Vec<[f64; 3]>,
    /// The noise amplitude relative to the mean edge length.
    pub noise_scale: f64,
    /// Degeneracies applied after the noise, in order.
    pub degeneracies: Vec<Degeneracy>,
}

/// A built mesh with its positions (one per vertex, split vertices included).
#[derive(Clone, Debug)]
pub struct RandomMesh {
    /// The mesh.
    pub mesh: HalfedgeMesh,
    /// Its positions.
    pub positions: Vec<DVec3>,
}

impl MeshSpec {
    /// Builds the mesh: the shape's faces less the removed ones, with every repair on
    /// (removing faces can pinch a vertex, which is split). The positions of split
    /// vertices copy their originals.
    pub fn realise(&self) -> RandomMesh {
        let primitive = self.shape.primitive();
        let faces: Vec<&[u32]> = primitive
            .faces
            .iter()
            .enumerate()
            .filter(|(f, _)| self.remove.is_empty() || !self.remove[f % self.remove.len()])
            .map(|(_, face)| face)
            .collect();
        let mut positions = primitive.positions.clone();
        let h = mean_edge(&primitive);
        for (i, p) in positions.iter_mut().enumerate() {
            if let Some(n) = (!self.noise.is_empty()).then(|| self.noise[i % self.noise.len()]) {
                *p += DVec3::from_array(n) * (self.noise_scale * h);
            }
        }
        let n_faces = primitive.faces.len();
        for d in &self.degeneracies {
            match *d {
                Degeneracy::Coincide(a, b) => {
                    let n = positions.len();
                    positions[a % n] = positions[b % n];
                }
                Degeneracy::ZeroArea(f, t) | Degeneracy::Needle(f, t) => {
                    let face = primitive.faces.get(f % n_faces).expect("face");
                    let (a, b, c) = (face[0] as usize, face[1] as usize, face[2] as usize);
                    let (pa, pb) = (positions[a], positions[b]);
                    let mut p = pa + (pb - pa) * t;
                    if matches!(d, Degeneracy::Needle(..)) {
                        let normal = (pb - pa).normalize_or(DVec3::X).any_orthonormal_vector();
                        p += normal * (1e-9 * (pb - pa).length());
                    }
                    positions[c] = p;
                }
                Degeneracy::Flatten => positions.iter_mut().for_each(|p| p.z = 0.0),
            }
        }
        let (mesh, report) =
            HalfedgeMesh::build(positions.len(), &faces, &BuildOptions::repair_all())
                .expect("a subset of an oriented manifold's faces builds with repairs");
        for split in &report.split_vertices {
            let copy = positions[split.original.index()];
            positions.push(copy);
        }
        RandomMesh { mesh, positions }
    }
}

fn mean_edge(primitive: &Primitive) -> f64 {
    let (mut sum, mut count) = (0.0, 0usize);
    for face in primitive.faces.iter() {
        for k in 0..face.len() {
            let (a, b) = (face[k] as usize, face[(k + 1) % face.len()] as usize);
            sum += (primitive.positions[a] - primitive.positions[b]).length();
            count += 1;
        }
    }
    if count == 0 { 1.0 } else { sum / count as f64 }
}

fn noise_vec() -> impl Strategy<Value = Vec<[f64; 3]>> {
    prop::collection::vec([-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0], 0..64)
}

/// Random meshes with noise up to 0.3 mean edge lengths, some faces removed (one in
/// eight on average) and up to four degeneracies (coincident vertices, zero-area and
/// needle faces, a flattened mesh). Quads included.
pub fn degenerate_mesh() -> impl Strategy<Value = MeshSpec> {
    (
        any_shape(),
        prop::collection::vec(prop::bool::weighted(0.125), 0..40),
        noise_vec(),
        0.0f64..0.3,
        prop::collection::vec(degeneracy(), 0..5),
    )
        .prop_map(
            |(shape, remove, noise, noise_scale, degeneracies)| MeshSpec {
                shape,
                remove,
                noise,
                noise_scale,
                degeneracies,
            },
        )
}

/// Well-shaped random triangle meshes: noise up to 0.1 mean edge lengths (every
/// triangle keeps angles well away from 0 and π), some faces removed, no degeneracy.
pub fn well_shaped_mesh() -> impl Strategy<Value = MeshSpec> {
    (
        triangle_shape(),
        prop::collection::vec(prop::bool::weighted(0.1), 0..40),
        noise_vec(),
        0.0f64..0.1,
    )
        .prop_map(|(shape, remove, noise, noise_scale)| MeshSpec {
            shape,
            remove,
            noise,
            noise_scale,
            degeneracies: Vec::new(),
        })
}

/// The bounding-box diagonal of `positions` (0 when empty).
pub fn bbox_diagonal(positions: &[DVec3]) -> f64 {
    let Some(first) = positions.first() else {
        return 0.0;
    };
    let (lo, hi) = positions
        .iter()
        .fold((*first, *first), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    (hi - lo).length()
}

/// Whether two positions are the same to the last bit (`-0.0` differs from `0.0`).
pub fn same_bits(a: DVec3, b: DVec3) -> bool {
    a.to_array().map(f64::to_bits) == b.to_array().map(f64::to_bits)
}
