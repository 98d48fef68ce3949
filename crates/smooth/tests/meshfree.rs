//! A smoother given its mesh by value goes on without the half-edge mesh once the
//! operator is built (built-in schemes on triangle meshes): it keeps the triangle list
//! instead, and every result is the same bits as the run that keeps the mesh — every
//! built-in scheme, both cotangent kernels, weight-sum and both area normalisations,
//! fixed, free and curve boundaries, volume preservation, weights updated every
//! iteration or once, reordered or not; the operator of the last sweep
//! (`Smoother::laplacian`) too. Runs that cannot go without the mesh (polygon faces, a
//! scheme of your own, the implicit method) hand it back as before.
//! `tests/owned.rs` compares every other observable of the same runs.

use std::ops::ControlFlow;

use beltrami_halfedge::geometry::VertexAreaKind;
use beltrami_halfedge::{DVec3, HalfedgeId, HalfedgeMesh, primitives};
use beltrami_smooth::{
    Boundary, ImplicitSolver, Method, OwnedFaces, Reorder, SmoothConfig, Smoother, WeightUpdate,
};
use beltrami_testkit::fixtures::jitter;
use beltrami_weights::{
    Cotangent, CotangentKernel, InverseDistance, LaplacianOptions, Normalization, Uniform,
    WeightContext, WeightScheme,
};

type Bits = Vec<[u64; 3]>;

fn bits(p: &[DVec3]) -> Bits {
    p.iter()
        .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
        .collect()
}

/// A noisy closed sphere, a bumpy open grid, and a torus with an isolated vertex (the
/// closedness of each).
fn meshes() -> Vec<(&'static str, HalfedgeMesh, Vec<DVec3>, bool)> {
    let mut sphere = primitives::icosphere(3);
    jitter(&mut sphere.positions, 0.03, 1);
    let mut grid = primitives::grid(15, 11);
    for p in &mut grid.positions {
        p.z = 0.1 * (3.0 * p.x).sin() * (2.0 * p.y).cos();
    }
    jitter(&mut grid.positions, 0.01, 2);
    let torus = primitives::torus(2.0, 0.6, 18, 9);
    let mut positions = torus.positions.clone();
    jitter(&mut positions, 0.02, 3);
    positions.push(DVec3::new(5.0, -1.0, 0.5));
    let isolated = HalfedgeMesh::from_polygons(positions.len(), torus.faces.iter()).unwrap();
    vec![
        ("sphere", sphere.mesh().unwrap(), sphere.positions, true),
        ("grid", grid.mesh().unwrap(), grid.positions, false),
        ("torus and an isolated vertex", isolated, positions, false),
    ]
}

/// The operator's weights and scales, as bits.
fn operator_bits(smoother: &Smoother<'_>) -> (Vec<u64>, Vec<u64>) {
    let rows = smoother.laplacian().rows();
    (
        rows.weights.iter().map(|w| w.to_bits()).collect(),
        rows.scales.iter().map(|s| s.to_bits()).collect(),
    )
}

/// Runs `config` with the mesh borrowed (kept through the run) and given by value, two
/// steps then the rest; checks the positions after each, the operator of the last
/// sweep, the final positions and what is handed back. Returns whether the owned run
/// went on without the mesh.
fn compare(
    name: &str,
    mesh: &HalfedgeMesh,
    x: &[DVec3],
    scheme: &dyn WeightScheme,
    config: &SmoothConfig,
) -> bool {
    let what = format!("{name} / {} / {config:?}", scheme.name());
    let mut kept = Smoother::new(mesh, x, scheme, config.clone()).unwrap();
    let mut free = Smoother::from_owned(mesh.clone(), x.to_vec(), scheme, config.clone()).unwrap();
    for _ in 0..2 {
        let a = kept.step().unwrap();
        let b = free.step().unwrap();
        assert_eq!(
            [a.max_displacement.to_bits(), a.mean_displacement.to_bits()],
            [b.max_displacement.to_bits(), b.mean_displacement.to_bits()],
            "{what}: step statistics"
        );
        assert_eq!(bits(&kept.positions()), bits(&free.positions()), "{what}");
        assert_eq!(
            operator_bits(&kept),
            operator_bits(&free),
            "{what}: operator"
        );
        assert_eq!(
            kept.stable_step_limit().map(f64::to_bits),
            free.stable_step_limit().map(f64::to_bits),
            "{what}: stable step"
        );
    }
    let kept = kept.run(|_| ControlFlow::Continue(())).unwrap();
    let (free, faces) = free.run_owned_faces(|_| ControlFlow::Continue(())).unwrap();
    assert_eq!(
        bits(&kept.positions),
        bits(&free.positions),
        "{what}: result"
    );
    let faces = faces.expect("a mesh given by value");
    assert_eq!(faces.to_polygons(), mesh.to_polygons(), "{what}: faces");
    let without = matches!(faces, OwnedFaces::Triangles(_));
    assert_eq!(
        &faces.into_mesh(x.len()).unwrap(),
        mesh,
        "{what}: the mesh rebuilt"
    );
    without
}

#[test]
fn the_sweep_without_the_mesh_changes_no_bit() {
    let schemes: [&dyn WeightScheme; 3] = [&Uniform, &InverseDistance, &Cotangent];
    let normalisations = [
        (Normalization::WeightSum, 0.6),
        (Normalization::Area(VertexAreaKind::Barycentric), 2e-3),
        (Normalization::Area(VertexAreaKind::MixedVoronoi), 2e-3),
    ];
    let mut runs = 0;
    for (name, mesh, x, closed) in meshes() {
        for scheme in schemes {
            for kernel in [CotangentKernel::PerTriangle, CotangentKernel::Ring] {
                if kernel == CotangentKernel::Ring && scheme.name() != Cotangent.name() {
                    continue;
                }
                for (normalization, lambda) in normalisations {
                    let options = LaplacianOptions::new()
                        .normalization(normalization)
                        .cotangent_kernel(kernel);
                    for boundary in [Boundary::Fixed, Boundary::Free, Boundary::Curve] {
                        if boundary == Boundary::Curve && normalization != Normalization::WeightSum
                        {
                            continue;
                        }
                        for update in [WeightUpdate::Every, WeightUpdate::Once] {
                            for (method, volume) in [
                                (Method::Laplacian, false),
                                (Method::Laplacian, true),
                                (Method::Taubin { mu: -0.63 }, false),
                            ] {
                                if volume && !closed {
                                    continue;
                                }
                                let mut config = SmoothConfig::new(lambda, 5)
                                    .laplacian(options)
                                    .boundary(boundary)
                                    .update(update)
                                    .method(method)
                                    .preserve_volume(volume);
                                // An area-normalised step: 0.4 of the stable limit.
                                let probe =
                                    Smoother::new(&mesh, &x, scheme, config.clone()).unwrap();
                                if let Some(limit) = probe.stable_step_limit() {
                                    config = config.lambda(0.4 * limit);
                                }
                                drop(probe);
                                for reorder in [Reorder::Never, Reorder::Always] {
                                    let config = config.clone().reorder(reorder);
                                    assert!(
                                        compare(name, &mesh, &x, scheme, &config),
                                        "{name} / {} / {config:?}: the run kept the mesh",
                                        scheme.name()
                                    );
                                    runs += 1;
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    assert!(runs > 300, "{runs} runs");
}

/// Inverse distance through the generic weight path: a scheme of the caller's own.
struct Custom;

impl WeightScheme for Custom {
    fn name(&self) -> &str {
        "custom"
    }

    fn weight(&self, ctx: &WeightContext<'_>, h: HalfedgeId) -> f64 {
        1.0 / (ctx.edge_length(h) + 1e-12)
    }
}

#[test]
fn runs_that_need_the_mesh_keep_it() {
    let (_, mesh, x, _) = meshes().swap_remove(0);
    let config = SmoothConfig::new(0.5, 3);
    // A scheme of the caller's own reads the mesh.
    assert!(!compare("sphere", &mesh, &x, &Custom, &config));
    // The implicit method keeps it.
    let implicit = config
        .clone()
        .lambda(1.0)
        .method(Method::implicit(ImplicitSolver::conjugate_gradient()));
    let smoother = Smoother::from_owned(mesh.clone(), x.clone(), &Cotangent, implicit).unwrap();
    let (_, faces) = smoother
        .run_owned_faces(|_| ControlFlow::Continue(()))
        .unwrap();
    assert_eq!(faces, Some(OwnedFaces::Mesh(mesh.clone())));
    // Polygon faces: the cube's quads.
    let cube = primitives::cube_quads();
    let quads = cube.mesh().unwrap();
    for scheme in [&Uniform as &dyn WeightScheme, &InverseDistance] {
        assert!(!compare("cube", &quads, &cube.positions, scheme, &config));
    }
    // A borrowed mesh is not handed back.
    let smoother = Smoother::new(&mesh, &x, &Uniform, config).unwrap();
    let (_, faces) = smoother
        .run_owned_faces(|_| ControlFlow::Continue(()))
        .unwrap();
    assert_eq!(faces, None);
}
