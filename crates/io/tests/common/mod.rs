//! Helpers shared by the integration tests.
#![allow(dead_code, reason = "each test file uses a different subset")]

use std::collections::HashMap;
use std::path::PathBuf;

use beltrami_io::{MeshData, PolygonList};
use glam::DVec3;

/// A file of the repository's `fixtures/` folder.
pub(crate) fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures")
        .join(name)
}

/// A deterministic pseudo-random generator (64-bit LCG, high bits).
pub(crate) struct Lcg(pub(crate) u64);

impl Lcg {
    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let hi = self.0 >> 32;
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (hi << 32) | (self.0 >> 32)
    }

    /// A finite f64 from random bits (any exponent).
    pub(crate) fn finite_f64(&mut self) -> f64 {
        loop {
            let x = f64::from_bits(self.next_u64());
            if x.is_finite() {
                return x;
            }
        }
    }

    pub(crate) fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
}

/// Coordinates that are hard to round-trip: random bit patterns over the whole f64
/// range, subnormals, signed zeros, extremes and decimals with no exact binary form,
/// on faces of several sizes (a repeated vertex and a two-vertex face included: the
/// readers pass them through).
pub(crate) fn messy_mesh() -> MeshData {
    let mut rng = Lcg(7);
    let mut positions = vec![
        DVec3::new(0.1, 1.0 / 3.0, -123_456.789),
        DVec3::new(-0.0, 5e-324, f64::MIN_POSITIVE),
        DVec3::new(1e300, -1e-300, f64::MAX),
        DVec3::new(f64::MIN, 2.0f64.powi(52) + 1.0, 0.1 + 0.2),
        DVec3::new(12.345_678_901_234_567, -98.765, 1e-7),
    ];
    for _ in 0..40 {
        positions.push(DVec3::new(
            rng.finite_f64(),
            rng.finite_f64(),
            rng.finite_f64(),
        ));
    }
    let n = positions.len();
    let mut faces = PolygonList::new();
    for _ in 0..30 {
        let len = 3 + rng.below(4);
        let face: Vec<u32> = (0..len).map(|_| rng.below(n) as u32).collect();
        faces.push(&face);
    }
    faces.push(&[0, 1, 1]);
    faces.push(&[2, 3]);
    MeshData { positions, faces }
}

/// A mesh whose coordinates are all exact in f32 (for STL).
pub(crate) fn f32_mesh(mesh: &MeshData) -> MeshData {
    MeshData {
        positions: mesh
            .positions
            .iter()
            .map(|p| p.as_vec3().as_dvec3())
            .collect(),
        faces: mesh.faces.clone(),
    }
}

/// Same vertices, same faces, every coordinate bit identical.
pub(crate) fn assert_bit_identical(a: &MeshData, b: &MeshData) {
    assert_eq!(a.positions.len(), b.positions.len(), "vertex count");
    for (i, (p, q)) in a.positions.iter().zip(&b.positions).enumerate() {
        let bits = |v: &DVec3| v.to_array().map(f64::to_bits);
        assert_eq!(bits(p), bits(q), "vertex {i}: {p} vs {q}");
    }
    assert_eq!(a.faces, b.faces);
}

/// Same mesh up to a renumbering of the vertices: the same number of vertices, face
/// `f` of both has the same corner positions, and the renumbering is one-to-one.
pub(crate) fn assert_same_up_to_renumbering(a: &MeshData, b: &MeshData) {
    assert_eq!(a.positions.len(), b.positions.len(), "vertex count");
    assert_eq!(a.faces.len(), b.faces.len(), "face count");
    let mut map = HashMap::new();
    for (f, (fa, fb)) in a.faces.iter().zip(b.faces.iter()).enumerate() {
        assert_eq!(fa.len(), fb.len(), "face {f}");
        for (&va, &vb) in fa.iter().zip(fb) {
            assert_eq!(
                a.positions[va as usize], b.positions[vb as usize],
                "face {f}"
            );
            assert_eq!(*map.entry(va).or_insert(vb), vb, "face {f}: vertex {va}");
        }
    }
    let mut targets: Vec<u32> = map.values().copied().collect();
    targets.sort_unstable();
    targets.dedup();
    assert_eq!(targets.len(), map.len(), "the renumbering is one-to-one");
}
