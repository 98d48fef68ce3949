//! Deterministic test meshes: small enough for CI, irregular enough to catch real bugs.
//!
//! Every function returns the same positions to the last bit on every platform: the
//! noise comes from [`SplitMix64`] or [`Lcg64`] (integer arithmetic) and only `+ − ×`
//! and exact operations are applied to it — except [`noisy_flens`] and
//! [`with_bench_noise`], which take their seeded Gaussian noise from `beltrami-surfaces`
//! (ChaCha8 bits, `libm`'s pure-Rust logarithm and correctly rounded `sqrt`, also
//! identical everywhere), and [`gaussian_noisy_icosphere`], whose Box–Muller noise goes
//! through the platform's `ln` and `cos`. The
//! meshes of [`openmesh_inputs`] are committed in
//! `fixtures/` (written by `cargo run -p beltrami-testkit --example make_openmesh_inputs`)
//! and are the inputs of the OpenMesh references in `fixtures/openmesh/`.

use beltrami_halfedge::primitives::{self, Primitive};
use beltrami_halfedge::{DVec3, HalfedgeMesh, PolygonList};
use beltrami_surfaces::{FLensParams, NoiseLevel, Surface, add_normal_noise, flens};

use crate::rng::{Lcg64, SplitMix64};

/// Moves every position by a deterministic jitter in `[-1, 1)³ × amplitude` (length
/// units of the positions): an [`Lcg64`] started at the state
/// `seed ^ 0x9E37_79B9_7F4A_7C15`, one `next_symmetric_vector` per position, in order.
pub fn jitter(positions: &mut [DVec3], amplitude: f64, seed: u64) {
    let mut rng = Lcg64::new(seed ^ 0x9E37_79B9_7F4A_7C15);
    for p in positions {
        *p += rng.next_symmetric_vector() * amplitude;
    }
}

/// The fixtures the OpenMesh references are generated for, by name: the file is
/// `fixtures/<name>.ply` and the references are in `fixtures/openmesh/<name>/`.
#[must_use]
pub fn openmesh_inputs() -> Vec<(&'static str, Primitive)> {
    vec![
        ("obtuse_grid_24x16", obtuse_grid()),
        ("noisy_icosphere_4", noisy_icosphere()),
        ("noisy_torus_36x12", noisy_torus()),
        ("holes_30x20", holes_patch()),
        ("flens_68x33", noisy_flens()),
    ]
}

/// The seed of [`noisy_flens`]'s noise: that of `beltrami study`'s default configuration.
pub const FLENS_NOISE_SEED: u64 = 1;

/// The standard deviation of [`noisy_flens`]'s noise, as a multiple of the mean edge
/// length: that of `beltrami study`'s default configuration.
pub const FLENS_NOISE_LEVEL: f64 = 0.2;

/// The paper's F-lens, `beltrami_surfaces::flens(&FLensParams::default())` (a 68 × 33
/// grid: 2244 vertices, 4288 triangles, one boundary loop of 198 edges, millimetres),
/// with Gaussian noise along the area-weighted vertex normals of standard deviation
/// [`FLENS_NOISE_LEVEL`] × the mean edge length (0.2105 mm), seed
/// [`FLENS_NOISE_SEED`] — `beltrami_surfaces::add_normal_noise`, boundary vertices
/// included. This is the noisy F-lens `beltrami study` smooths by default. The noise
/// tips the grid's right angles, so 688 edges have negative cotangent weights.
///
/// # Panics
/// Never: the F-lens is a valid mesh and the noise level is valid (both are tested).
#[must_use]
pub fn noisy_flens() -> Primitive {
    let lens = flens(&FLensParams::default());
    let mesh = lens.mesh().expect("the F-lens is a valid mesh");
    let (positions, _sigma) = add_normal_noise(
        &mesh,
        &lens.positions,
        NoiseLevel::RelativeToMeanEdge(FLENS_NOISE_LEVEL),
        FLENS_NOISE_SEED,
    )
    .expect("a valid noise level");
    Primitive {
        positions,
        faces: lens.data.faces,
    }
}

/// An open, irregular 24 × 16 grid with many obtuse triangles, so that cotangent weights
/// are negative on some edges (425 vertices, 768 triangles, one boundary loop).
///
/// Vertex `(i, j)` (index `j · 25 + i`) starts at `(i, j)`; interior vertices are
/// jittered by up to ±0.35 in x and y, boundary vertices only along their side (the
/// corners stay), and the height is a gentle saddle `0.01 ((x − 12)² − (y − 8)²)` plus
/// up to ±0.05 of noise. Each square is split along a randomly chosen diagonal.
#[must_use]
pub fn obtuse_grid() -> Primitive {
    let (nx, ny) = (24u32, 16u32);
    let mut rng = SplitMix64::new(0x0b7e_5e01);
    let mut positions = Vec::with_capacity(((nx + 1) * (ny + 1)) as usize);
    for j in 0..=ny {
        for i in 0..=nx {
            let (jx, jy, jz) = (
                rng.next_symmetric(),
                rng.next_symmetric(),
                rng.next_symmetric(),
            );
            let x_side = i == 0 || i == nx;
            let y_side = j == 0 || j == ny;
            let x = f64::from(i) + if x_side { 0.0 } else { 0.35 * jx };
            let y = f64::from(j) + if y_side { 0.0 } else { 0.35 * jy };
            let z = 0.01 * ((x - 12.0) * (x - 12.0) - (y - 8.0) * (y - 8.0)) + 0.05 * jz;
            positions.push(DVec3::new(x, y, z));
        }
    }
    let id = |i: u32, j: u32| j * (nx + 1) + i;
    let mut faces = Vec::with_capacity((2 * nx * ny) as usize);
    for j in 0..ny {
        for i in 0..nx {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if rng.next_u64() & 1 == 0 {
                faces.push([a, b, c]);
                faces.push([a, c, d]);
            } else {
                faces.push([a, b, d]);
                faces.push([b, c, d]);
            }
        }
    }
    Primitive {
        positions,
        faces: PolygonList::from_triangles(&faces),
    }
}

/// The unit icosphere of level 4 (2562 vertices, 5120 triangles) with radial noise:
/// each vertex `p` moves to `p (1 + 0.02 u)`, `u` uniform in `[-1, 1)` — about a quarter
/// of the mean edge length.
#[must_use]
pub fn noisy_icosphere() -> Primitive {
    let mut sphere = primitives::icosphere(4);
    let mut rng = SplitMix64::new(0x1c05_f4e4);
    for p in &mut sphere.positions {
        *p *= 1.0 + 0.02 * rng.next_symmetric();
    }
    sphere
}

/// The unit icosphere of `level` (`primitives::icosphere(level)`) and, beside it, its
/// positions with Gaussian noise: every coordinate of every vertex moves by `sigma` times
/// a [`SplitMix64::next_normal`] number (x, y, z in turn, vertex after vertex) of the
/// generator seeded with `seed`.
///
/// The noise goes through `ln` and `cos` (Box–Muller), so unlike the other fixtures its
/// last bits may differ between platforms' math libraries. It is the test case of the
/// closest-point benchmark and its phase-timing example.
#[must_use]
pub fn gaussian_noisy_icosphere(level: u32, sigma: f64, seed: u64) -> (Primitive, Vec<DVec3>) {
    let sphere = primitives::icosphere(level);
    let mut rng = SplitMix64::new(seed);
    let noisy = sphere
        .positions
        .iter()
        .map(|p| {
            let x = rng.next_normal();
            let y = rng.next_normal();
            let z = rng.next_normal();
            *p + DVec3::new(x, y, z) * sigma
        })
        .collect();
    (sphere, noisy)
}

/// The unit icosphere of `level` with every coordinate moved by up to a fifth of its
/// mean edge length (about `1.1 / 2^level`), uniformly: `p + 0.2 · 1.1 / 2^level · u`,
/// `u` from [`Lcg64::next_symmetric_vector`] of the generator started at
/// `0x9E37_79B9_7F4A_7C15`, vertex after vertex. The mesh of the explicit and implicit
/// smoothing benchmarks.
#[must_use]
pub fn jittered_icosphere(level: u32) -> Primitive {
    let mut sphere = primitives::icosphere(level);
    let edge = 1.1 / f64::from(1u32 << level);
    let amplitude = 0.2 * edge;
    let mut rng = Lcg64::new(0x9E37_79B9_7F4A_7C15);
    for p in &mut sphere.positions {
        *p += rng.next_symmetric_vector() * amplitude;
    }
    sphere
}

/// `surface` with Gaussian noise along its area-weighted vertex normals of standard
/// deviation 0.2 × the mean edge length, seed 42
/// (`beltrami_surfaces::add_normal_noise`, boundary vertices included), beside its mesh:
/// the meshes of the sweep and refresh benchmarks of `beltrami-weights`.
///
/// # Panics
/// When `surface` is not a valid mesh (never for the surfaces of `beltrami-surfaces`).
#[must_use]
pub fn with_bench_noise(surface: &Surface) -> (HalfedgeMesh, Vec<DVec3>) {
    let mesh = surface.mesh().expect("a valid surface");
    let (positions, _sigma) = add_normal_noise(
        &mesh,
        &surface.positions,
        NoiseLevel::RelativeToMeanEdge(0.2),
        42,
    )
    .expect("a valid noise level");
    (mesh, positions)
}

/// A grid of `nx × ny` unit squares (`primitives::grid`) with each interior vertex
/// moved in the plane by up to `amount` of a cell along x and y (two
/// [`SplitMix64::next_symmetric`] draws from `seed` per interior vertex, in vertex
/// order); boundary vertices stay. Beside its mesh.
///
/// # Panics
/// Never for `nx, ny ≥ 1` (the grid is a valid mesh).
#[must_use]
pub fn jittered_grid(nx: u32, ny: u32, amount: f64, seed: u64) -> (HalfedgeMesh, Vec<DVec3>) {
    let grid = primitives::grid(nx, ny);
    let mesh = grid.mesh().expect("a grid is a valid mesh");
    let mut rng = SplitMix64::new(seed);
    let positions = grid
        .positions
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            let boundary = mesh.is_boundary_vertex(beltrami_halfedge::VertexId::new(
                u32::try_from(i).expect("grid vertex ids fit u32"),
            ));
            if boundary {
                p
            } else {
                p + DVec3::new(rng.next_symmetric(), rng.next_symmetric(), 0.0) * amount
            }
        })
        .collect();
    (mesh, positions)
}

/// A torus (genus 1) with tube-centre radius 2 and tube radius 0.6 on a 36 × 12 grid
/// (432 vertices, 864 triangles), every coordinate moved by up to ±0.03.
#[must_use]
pub fn noisy_torus() -> Primitive {
    let mut torus = primitives::torus(2.0, 0.6, 36, 12);
    let mut rng = SplitMix64::new(0x70_5005);
    for p in &mut torus.positions {
        let u = DVec3::new(
            rng.next_symmetric(),
            rng.next_symmetric(),
            rng.next_symmetric(),
        );
        *p += 0.03 * u;
    }
    torus
}

/// A 30 × 20 grid patch with five holes of different shapes: four rectangular blocks of
/// cells (4 × 5, 6 × 4, 3 × 4 and 1 × 1 cells) and one single missing triangle, so the
/// mesh has six boundary loops (the outer rim, four rectangles, one of length 3).
///
/// Grid vertices are jittered by up to ±0.2 in x and y; the height is a low dome
/// `0.5 − 0.002 ((x − 15)² + (y − 10)²)` plus up to ±0.03 of noise. Squares alternate
/// their diagonal. Vertices that lose all their faces are dropped; the others keep their
/// order.
#[must_use]
pub fn holes_patch() -> Primitive {
    let (nx, ny) = (30u32, 20u32);
    let mut rng = SplitMix64::new(0x401e_5000);
    let mut grid = Vec::with_capacity(((nx + 1) * (ny + 1)) as usize);
    for j in 0..=ny {
        for i in 0..=nx {
            let (jx, jy, jz) = (
                rng.next_symmetric(),
                rng.next_symmetric(),
                rng.next_symmetric(),
            );
            let x = f64::from(i) + 0.2 * jx;
            let y = f64::from(j) + 0.2 * jy;
            let z = 0.5 - 0.002 * ((x - 15.0) * (x - 15.0) + (y - 10.0) * (y - 10.0)) + 0.03 * jz;
            grid.push(DVec3::new(x, y, z));
        }
    }
    // Holes as half-open cell ranges [i0, i1) × [j0, j1), at least one cell apart from each
    // other and from the rim, so every vertex keeps a single fan.
    let holes = [
        (4, 8, 4, 9),
        (14, 20, 11, 15),
        (23, 26, 3, 7),
        (10, 11, 16, 17),
    ];
    let in_hole = |i: u32, j: u32| {
        holes
            .iter()
            .any(|&(i0, i1, j0, j1)| (i0..i1).contains(&i) && (j0..j1).contains(&j))
    };
    let missing_triangle = (21, 9);
    let id = |i: u32, j: u32| j * (nx + 1) + i;
    let mut faces = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            if in_hole(i, j) {
                continue;
            }
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            let pair = if (i + j) % 2 == 0 {
                [[a, b, c], [a, c, d]]
            } else {
                [[a, b, d], [b, c, d]]
            };
            if (i, j) == missing_triangle {
                faces.push(pair[1]);
            } else {
                faces.extend_from_slice(&pair);
            }
        }
    }
    compact(&grid, &faces)
}

/// A small open patch with two degenerate triangles, for checks that weights and
/// smoothing stay finite (7 vertices, 6 triangles):
///
/// - `(0, 1, 2)` is collinear: vertex 2 is the midpoint of edge 0–1 (zero area);
/// - `(6, 3, 5)` has a zero-length edge: vertex 5 coincides with vertex 3.
///
/// The other four triangles are well shaped, and vertex 3 is the only interior vertex
/// of the collinear triangle's neighbourhood.
#[must_use]
pub fn degenerate_patch() -> Primitive {
    let positions = vec![
        DVec3::new(0.0, 0.0, 0.0),  // 0 A
        DVec3::new(2.0, 0.0, 0.0),  // 1 B
        DVec3::new(1.0, 0.0, 0.0),  // 2 C, midpoint of A B
        DVec3::new(1.0, 1.0, 0.1),  // 3 D
        DVec3::new(1.0, -1.0, 0.0), // 4 E
        DVec3::new(1.0, 1.0, 0.1),  // 5 F, coincides with D
        DVec3::new(0.0, 1.0, 0.0),  // 6 G
    ];
    let faces = [
        [0, 2, 3],
        [2, 1, 3],
        [0, 1, 2],
        [0, 4, 1],
        [0, 3, 6],
        [6, 3, 5],
    ];
    Primitive {
        positions,
        faces: PolygonList::from_triangles(&faces),
    }
}

/// Keeps the vertices that some face uses, in their order, and renumbers the faces.
fn compact(positions: &[DVec3], faces: &[[u32; 3]]) -> Primitive {
    let mut used = vec![false; positions.len()];
    for f in faces {
        for &v in f {
            used[v as usize] = true;
        }
    }
    let mut new_index = vec![u32::MAX; positions.len()];
    let mut kept = Vec::new();
    for (i, p) in positions.iter().enumerate() {
        if used[i] {
            new_index[i] = kept.len() as u32;
            kept.push(*p);
        }
    }
    let faces: Vec<[u32; 3]> = faces
        .iter()
        .map(|f| f.map(|v| new_index[v as usize]))
        .collect();
    Primitive {
        positions: kept,
        faces: PolygonList::from_triangles(&faces),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use beltrami_halfedge::geometry::Geometry;

    #[test]
    fn every_fixture_builds_and_passes_the_integrity_check() {
        for (name, p) in openmesh_inputs()
            .into_iter()
            .chain([("degenerate", degenerate_patch())])
        {
            let mesh = p.mesh().unwrap_or_else(|e| panic!("{name}: {e}"));
            mesh.check_integrity().unwrap();
            assert!(
                mesh.vertices().all(|v| !mesh.is_isolated(v)),
                "{name}: isolated vertex"
            );
        }
    }

    #[test]
    fn fixtures_have_the_documented_shape() {
        let grid = obtuse_grid().mesh().unwrap();
        assert_eq!((grid.n_vertices(), grid.n_faces()), (425, 768));
        assert_eq!(grid.boundary_loops().count(), 1);

        let sphere = noisy_icosphere().mesh().unwrap();
        assert_eq!((sphere.n_vertices(), sphere.n_faces()), (2562, 5120));
        assert_eq!(sphere.genus(), Some(0));

        let torus = noisy_torus().mesh().unwrap();
        assert_eq!((torus.n_vertices(), torus.n_faces()), (432, 864));
        assert_eq!(torus.genus(), Some(1));

        let holes = holes_patch().mesh().unwrap();
        let mut loops: Vec<usize> = holes.boundary_loops().map(|l| l.len()).collect();
        loops.sort_unstable();
        assert_eq!(loops, [3, 4, 14, 18, 20, 100]);
        assert_eq!(holes.connected_components().count(), 1);

        let lens = noisy_flens();
        let lens_mesh = lens.mesh().unwrap();
        assert_eq!((lens_mesh.n_vertices(), lens_mesh.n_faces()), (2244, 4288));
        let loops: Vec<usize> = lens_mesh.boundary_loops().map(|l| l.len()).collect();
        assert_eq!(loops, [198]);
        // Every vertex moved, boundary vertices included.
        let clean = flens(&FLensParams::default());
        assert!(
            lens.positions
                .iter()
                .zip(&clean.positions)
                .all(|(a, b)| a != b)
        );
    }

    #[test]
    fn the_obtuse_grid_has_negative_cotangent_weights() {
        let p = obtuse_grid();
        let mesh = p.mesh().unwrap();
        let g = Geometry::new(&mesh, &p.positions).unwrap();
        let negative = mesh
            .edges()
            .filter(|e| {
                let [h0, h1] = e.halfedges();
                g.opposite_cotangent(h0) + g.opposite_cotangent(h1) < 0.0
            })
            .count();
        assert!(negative >= 10, "only {negative} negative edges");
    }

    #[test]
    fn the_noisy_flens_has_the_documented_noise_and_negative_weights() {
        let clean = flens(&FLensParams::default());
        let mesh = clean.mesh().unwrap();
        let sigma = FLENS_NOISE_LEVEL
            * Geometry::new(&mesh, &clean.positions)
                .unwrap()
                .mean_edge_length()
                .unwrap();
        assert!((sigma - 0.2105).abs() < 5e-5, "{sigma}");

        let noisy = noisy_flens();
        let g = Geometry::new(&mesh, &noisy.positions).unwrap();
        let negative = mesh
            .edges()
            .filter(|e| {
                let [h0, h1] = e.halfedges();
                g.opposite_cotangent(h0) + g.opposite_cotangent(h1) < 0.0
            })
            .count();
        assert_eq!(negative, 688);
    }

    #[test]
    fn the_degenerate_patch_is_degenerate_where_documented() {
        let p = degenerate_patch();
        let mesh = p.mesh().unwrap();
        let g = Geometry::new(&mesh, &p.positions).unwrap();
        let degenerate: Vec<usize> = mesh
            .faces()
            .filter(|&f| g.is_degenerate_face(f))
            .map(|f| f.index())
            .collect();
        assert_eq!(degenerate, [2, 5]);
    }

    #[test]
    fn fixtures_are_deterministic() {
        assert_eq!(obtuse_grid(), obtuse_grid());
        assert_eq!(holes_patch(), holes_patch());
        assert_eq!(noisy_flens(), noisy_flens());
    }
}
