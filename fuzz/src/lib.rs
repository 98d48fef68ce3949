//! The checks behind beltrami's fuzz targets, shared by the targets in `fuzz_targets/`.
//!
//! Each check panics only when a documented guarantee is broken: a reader that accepts
//! a non-finite coordinate or an index that names no vertex, a built mesh that fails
//! [`HalfedgeMesh::check_integrity`], a smoothing run that returns `Ok` with a NaN or an
//! infinite position, or a fixed boundary vertex that moved. Every other outcome — a
//! typed error included — is a pass.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

use arbitrary::Arbitrary;
use beltrami_halfedge::geometry::VertexAreaKind;
use beltrami_halfedge::{BuildOptions, DVec3, HalfedgeMesh, VertexId};
use beltrami_io::{MeshFormat, read_mesh_from};
use beltrami_smooth::{Boundary, SmoothConfig, WeightUpdate, smooth};
use beltrami_weights::{LaplacianOptions, NegativeWeights, Normalization, WeightRegistry};

/// Reads `data` as `format`; an accepted mesh must hold finite coordinates and in-range
/// indices, and the builder (with and without repairs) must take it without panicking
/// and give meshes that pass the integrity check.
pub fn check_read(data: &[u8], format: MeshFormat) {
    let mesh = match read_mesh_from(data, format) {
        Ok(mesh) => mesh,
        Err(e) => {
            // The message must format (it is what the CLI prints).
            let _ = e.to_string();
            return;
        }
    };
    let n = mesh.positions.len();
    if let Some(i) = mesh.positions.iter().position(|p| !p.is_finite()) {
        panic!("{format} reader accepted a non-finite vertex {i}");
    }
    if let Some(max) = mesh.faces.max_index() {
        assert!(
            (max as usize) < n,
            "{format} reader accepted index {max} with {n} vertices"
        );
    }
    for options in [BuildOptions::new(), BuildOptions::repair_all()] {
        if let Ok((built, _)) = HalfedgeMesh::build(n, mesh.faces.iter(), &options)
            && let Err(e) = built.check_integrity()
        {
            panic!("built mesh fails its integrity check: {e}");
        }
    }
}

/// The largest vertex count of a fuzzed mesh (keeps an execution short).
pub const MAX_VERTICES: usize = 40;
/// The largest face count of a fuzzed mesh.
pub const MAX_FACES: usize = 64;
/// The largest polygon size of a fuzzed face.
pub const MAX_FACE_LEN: usize = 8;

/// One coordinate: mostly on a coarse grid (so that coincident vertices, zero-area and
/// needle triangles are common), sometimes any `f64` bit pattern.
#[derive(Arbitrary, Clone, Copy, Debug)]
pub enum Coord {
    /// `k / 4`: small, exact, often repeated.
    Grid(i8),
    /// `k × 1e-9`: near-coincident points.
    Tiny(i8),
    /// Any bit pattern: huge, subnormal, NaN, infinite.
    Raw(f64),
}

impl Coord {
    fn value(self) -> f64 {
        match self {
            Self::Grid(k) => f64::from(k) / 4.0,
            Self::Tiny(k) => f64::from(k) * 1e-9,
            Self::Raw(x) => x,
        }
    }
}

/// The step of a fuzzed run.
#[derive(Arbitrary, Clone, Copy, Debug)]
pub enum Lambda {
    /// The paper's 0.8.
    Paper,
    /// 1.0, the largest weight-sum step.
    One,
    /// A small diffusion time, usable with area normalisation.
    Small,
    /// Any value, valid or not.
    Raw(f64),
}

impl Lambda {
    fn value(self) -> f64 {
        match self {
            Self::Paper => 0.8,
            Self::One => 1.0,
            Self::Small => 1e-3,
            Self::Raw(x) => x,
        }
    }
}

/// An arbitrary polygon soup with positions and smoothing parameters.
#[derive(Arbitrary, Debug)]
pub struct SmoothInput {
    /// Vertex count (modulo [`MAX_VERTICES`] + 1).
    pub n_vertices: u8,
    /// Faces; each index is taken modulo `n_vertices + 2`, so that an index out of range
    /// occurs too.
    pub faces: Vec<Vec<u8>>,
    /// Coordinates, three per vertex, repeated cyclically when too few (0 when none).
    pub coords: Vec<Coord>,
    /// The step.
    pub lambda: Lambda,
    /// Iterations (modulo 4, plus 1).
    pub iterations: u8,
    /// Normalisation: weight sum, or area with the mixed or barycentric vertex area.
    pub normalization: u8,
    /// Negative-weight policy: keep, clamp or abs.
    pub negative: u8,
    /// Pinned vertices (modulo `n_vertices + 1`, so that an out-of-range one occurs too).
    pub pinned: Vec<u8>,
}

/// Builds the mesh of `input` without and with every repair, then smooths each mesh
/// that builds with every scheme of the default registry, every boundary mode and both
/// weight-update policies. Panics only when a guarantee is broken.
pub fn check_build_smooth(input: &SmoothInput) {
    let n = usize::from(input.n_vertices) % (MAX_VERTICES + 1);
    let modulus = n + 2;
    let faces: Vec<Vec<u32>> = input
        .faces
        .iter()
        .take(MAX_FACES)
        .map(|f| {
            f.iter()
                .take(MAX_FACE_LEN)
                .map(|&i| (usize::from(i) % modulus) as u32)
                .collect()
        })
        .collect();
    let positions: Vec<DVec3> = (0..n)
        .map(|v| {
            let c = |k: usize| {
                if input.coords.is_empty() {
                    0.0
                } else {
                    input.coords[(3 * v + k) % input.coords.len()].value()
                }
            };
            DVec3::new(c(0), c(1), c(2))
        })
        .collect();
    let normalization = match input.normalization % 4 {
        1 => Normalization::Area(VertexAreaKind::MixedVoronoi),
        2 => Normalization::Area(VertexAreaKind::Barycentric),
        _ => Normalization::WeightSum,
    };
    let negative = match input.negative % 3 {
        0 => NegativeWeights::Keep,
        1 => NegativeWeights::Clamp,
        _ => NegativeWeights::Abs,
    };
    let laplacian = LaplacianOptions::new().normalization(normalization).negative(negative);
    let pinned: Vec<VertexId> = input
        .pinned
        .iter()
        .take(4)
        .map(|&p| VertexId::new((usize::from(p) % (n + 1)) as u32))
        .collect();
    let iterations = usize::from(input.iterations % 4) + 1;
    let registry = WeightRegistry::with_builtins();

    for options in [BuildOptions::new(), BuildOptions::repair_all()] {
        let Ok((mesh, report)) = HalfedgeMesh::build(n, &faces, &options) else {
            continue;
        };
        if let Err(e) = mesh.check_integrity() {
            panic!("built mesh fails its integrity check: {e}");
        }
        let mut positions = positions.clone();
        for split in &report.split_vertices {
            let copy = positions[split.original.index()];
            positions.push(copy);
        }
        assert_eq!(positions.len(), mesh.n_vertices(), "split vertices");
        for scheme in registry.iter() {
            for boundary in [Boundary::Fixed, Boundary::Free, Boundary::Curve] {
                for update in [WeightUpdate::Every, WeightUpdate::Once] {
                    let config = SmoothConfig::new(input.lambda.value(), iterations)
                        .boundary(boundary)
                        .update(update)
                        .laplacian(laplacian)
                        .pinned(pinned.clone());
                    match smooth(&mesh, &positions, scheme.as_ref(), config) {
                        Err(e) => {
                            let _ = e.to_string();
                        }
                        Ok(out) => {
                            check_output(&mesh, &positions, &out.positions, boundary, &pinned)
                        }
                    }
                }
            }
        }
    }
}

fn check_output(
    mesh: &HalfedgeMesh,
    input: &[DVec3],
    output: &[DVec3],
    boundary: Boundary,
    pinned: &[VertexId],
) {
    assert_eq!(output.len(), input.len(), "output length");
    if let Some(i) = output.iter().position(|p| !p.is_finite()) {
        panic!(
            "smoothing returned Ok with a non-finite vertex {i}: {}",
            output[i]
        );
    }
    for v in mesh.vertices() {
        let must_stay = pinned.contains(&v)
            || mesh.is_isolated(v)
            || (boundary == Boundary::Fixed && mesh.is_boundary_vertex(v));
        if must_stay {
            let (a, b) = (input[v.index()], output[v.index()]);
            assert!(
                a.to_array().map(f64::to_bits) == b.to_array().map(f64::to_bits),
                "vertex {} must not move: {a} -> {b}",
                v.index()
            );
        }
    }
}
