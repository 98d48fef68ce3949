//! Delaunay flipping: planar meshes end with no negative cotangent weight and an
//! unchanged surface; curved ones are bounded by the dihedral option; the result is a
//! valid mesh on the same vertices; bad input is refused with the offending element.

use beltrami_algorithms::{DelaunayError, DelaunayOptions, delaunay_flip};
use beltrami_halfedge::{DVec3, HalfedgeMesh, primitives};
use beltrami_smooth::{SmoothConfig, WeightUpdate, smooth};
use beltrami_surfaces::{BlockParams, block};
use beltrami_testkit::SplitMix64;
use beltrami_weights::{Cotangent, Laplacian, LaplacianOptions};

/// A grid with its interior vertices moved about in the plane z = 0.
fn jittered_grid(nx: u32, ny: u32, amount: f64, seed: u64) -> (HalfedgeMesh, Vec<DVec3>) {
    let grid = primitives::grid(nx, ny);
    let mesh = grid.mesh().unwrap();
    let mut rng = SplitMix64::new(seed);
    let x = grid
        .positions
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            if mesh.is_boundary_vertex(beltrami_halfedge::VertexId::new(i as u32)) {
                p
            } else {
                p + DVec3::new(rng.next_symmetric(), rng.next_symmetric(), 0.0) * amount
            }
        })
        .collect();
    (mesh, x)
}

/// Interior edges whose cotangent weight is negative, counted on the operator itself.
fn negative_weights(mesh: &HalfedgeMesh, x: &[DVec3]) -> usize {
    let lap = Laplacian::new(mesh, x, &Cotangent, LaplacianOptions::default()).unwrap();
    mesh.vertices()
        .map(|v| lap.row(v).filter(|&(_, w)| w < -1e-12).count())
        .sum::<usize>()
        / 2
}

/// Faces whose normal turned by more than 90° between two position sets.
fn flipped_faces(mesh: &HalfedgeMesh, before: &[DVec3], after: &[DVec3]) -> usize {
    let normal = |x: &[DVec3], f| {
        let v: Vec<_> = mesh.vertices_around_face(f).collect();
        (x[v[1].index()] - x[v[0].index()]).cross(x[v[2].index()] - x[v[0].index()])
    };
    mesh.faces()
        .filter(|&f| normal(before, f).dot(normal(after, f)) < 0.0)
        .count()
}

#[test]
fn a_planar_mesh_ends_with_no_negative_weight_and_the_same_surface() {
    for seed in 1..4 {
        let (mesh, x) = jittered_grid(16, 12, 0.35, seed);
        let before = negative_weights(&mesh, &x);
        let (out, y, report) = delaunay_flip(&mesh, &x, DelaunayOptions::default()).unwrap();
        assert!(before > 0, "the jitter makes some edges non-Delaunay");
        assert_eq!(report.negative_before, before);
        assert_eq!(report.negative_after, 0);
        assert_eq!(negative_weights(&out, &y), 0);
        assert!(report.flips >= before);
        assert!(!report.hit_flip_limit);
        // The same vertices, in the same order; as many faces; a valid mesh.
        assert_eq!(y, x);
        assert_eq!(out.n_faces(), mesh.n_faces());
        assert_eq!(out.n_edges(), mesh.n_edges());
        out.check_integrity().unwrap();
        assert_eq!(out.boundary_loops().count(), 1);
        assert!(report.max_deviation < 1e-12, "{}", report.max_deviation);
        // Deterministic.
        let again = delaunay_flip(&mesh, &x, DelaunayOptions::default()).unwrap();
        assert_eq!(again.0.to_polygons(), out.to_polygons());
    }
}

#[test]
fn the_dihedral_bound_keeps_curved_edges_and_bounds_the_change() {
    // A curved patch: the jittered grid lifted onto a cylinder of radius 3.
    let (mesh, x) = jittered_grid(20, 14, 0.35, 7);
    let x: Vec<DVec3> = x
        .iter()
        .map(|p| {
            let a = p.x / 3.0;
            DVec3::new(3.0 * a.sin(), p.y, 3.0 * a.cos())
        })
        .collect();
    let free = delaunay_flip(&mesh, &x, DelaunayOptions::default())
        .unwrap()
        .2;
    let bound = 2f64.to_radians();
    let (out, _, kept) =
        delaunay_flip(&mesh, &x, DelaunayOptions::default().max_dihedral(bound)).unwrap();
    assert!(free.flips > 0 && free.max_deviation > 0.0);
    assert!(kept.flips < free.flips, "{} vs {}", kept.flips, free.flips);
    assert!(kept.max_deviation <= free.max_deviation);
    assert!(kept.kept_by_dihedral > 0);
    assert_eq!(
        kept.negative_after,
        kept.kept_by_dihedral + kept.kept_by_topology + kept.kept_by_flip_limit
    );
    out.check_integrity().unwrap();
    // A zero bound flips only exactly flat pairs: none on a cylinder.
    let none = delaunay_flip(&mesh, &x, DelaunayOptions::default().max_dihedral(0.0))
        .unwrap()
        .2;
    assert_eq!(none.flips, 0);
    assert_eq!(none.max_deviation, 0.0);
    // The flip limit is obeyed and reported.
    let limited = delaunay_flip(&mesh, &x, DelaunayOptions::default().max_flips(3))
        .unwrap()
        .2;
    assert_eq!(limited.flips, 3);
    assert!(limited.hit_flip_limit);
    // What the limit left is counted as such, not as unflippable.
    assert!(limited.kept_by_flip_limit > 0);
    assert_eq!(limited.kept_by_dihedral, 0);
    assert_eq!(
        limited.negative_after,
        limited.kept_by_topology + limited.kept_by_flip_limit
    );
    assert!(limited.kept_by_topology <= free.negative_after);
}

#[test]
fn the_block_loses_its_negative_weights_but_recomputed_weights_still_fold() {
    let surface = block(&BlockParams::default());
    let mesh = surface.data.mesh().unwrap();
    let x = surface.data.positions.clone();
    let (flat, y, report) = delaunay_flip(&mesh, &x, DelaunayOptions::default()).unwrap();
    // The block's faces are planar: every negative weight goes, the surface stays.
    assert!(report.negative_before > 0);
    assert_eq!(report.negative_after, 0);
    assert!(
        report.max_deviation < 1e-9 * 100.0,
        "{}",
        report.max_deviation
    );
    // What it does to cotangent smoothing (100 iterations of λ = 0.8): with the weights
    // computed once, the Delaunay mesh's are all non-negative and no face folds. With
    // weights recomputed every iteration the block's faces still fold, on either mesh:
    // those negative weights appear as the smoothing rounds the sharp edges, not in the
    // input triangulation (measured: 144 folded faces before flipping, 168 after).
    let folded = |m: &HalfedgeMesh, p: &[DVec3], update| {
        let config = SmoothConfig::new(0.8, 100).update(update);
        let out = smooth(m, p, &Cotangent, config).unwrap();
        flipped_faces(m, p, &out.positions)
    };
    assert_eq!(folded(&flat, &y, WeightUpdate::Once), 0);
    assert!(folded(&mesh, &x, WeightUpdate::Every) > 0);
    assert!(folded(&flat, &y, WeightUpdate::Every) > 0);
}

#[test]
fn bad_input_is_refused_with_the_offending_element() {
    let cube = primitives::cube_quads();
    let mesh = cube.mesh().unwrap();
    assert!(matches!(
        delaunay_flip(&mesh, &cube.positions, DelaunayOptions::default()),
        Err(DelaunayError::NotTriangle { face: 0, len: 4 })
    ));
    let (mesh, mut x) = jittered_grid(4, 4, 0.1, 1);
    assert!(matches!(
        delaunay_flip(&mesh, &x[1..], DelaunayOptions::default()),
        Err(DelaunayError::PositionCount { .. })
    ));
    x[5].y = f64::NAN;
    assert!(matches!(
        delaunay_flip(&mesh, &x, DelaunayOptions::default()),
        Err(DelaunayError::NonFinite { vertex: 5 })
    ));
    x[5].y = 0.5;
    for bad in [-1.0, f64::NAN] {
        assert!(matches!(
            delaunay_flip(&mesh, &x, DelaunayOptions::default().max_dihedral(bad)),
            Err(DelaunayError::Options { .. })
        ));
    }
}
