//! Robustness of the explicit smoother on degenerate input: coincident vertices, zero-area,
//! needle and nearly flat obtuse triangles, isolated vertices, a single triangle,
//! non-finite input, invalid parameters, custom schemes that misbehave, unstable area
//! steps. Every run must end in `Ok` with finite positions or in a typed
//! [`SmoothError`] — never a panic and never a NaN. Also: rigid-motion equivariance and
//! bit-for-bit determinism across runs and thread counts.

use std::ops::ControlFlow;
use std::panic::{AssertUnwindSafe, catch_unwind};

use beltrami_halfedge::geometry::VertexAreaKind;
use beltrami_halfedge::{DVec3, HalfedgeId, HalfedgeMesh, TopologyError, VertexId, primitives};
use beltrami_smooth::{
    Boundary, SmoothConfig, SmoothError, Smoothed, Smoother, Summation, WeightUpdate, smooth,
};
use beltrami_testkit::SplitMix64;
use beltrami_weights::{
    Cotangent, InverseDistance, LaplacianOptions, NegativeWeights, Normalization, Uniform,
    WeightContext, WeightError, WeightScheme,
};
use glam::{DMat3, DQuat};
use proptest::prelude::*;

// ---------------------------------------------------------------------------------------
// Helpers.
// ---------------------------------------------------------------------------------------

const SCHEMES: [&dyn WeightScheme; 3] = [&Uniform, &InverseDistance, &Cotangent];
/// Indices into [`SCHEMES`].
const UNIFORM: usize = 0;
const DISTANCE: usize = 1;
const COTANGENT: usize = 2;
const NEGATIVES: [NegativeWeights; 3] = [
    NegativeWeights::Keep,
    NegativeWeights::Clamp,
    NegativeWeights::Abs,
];
const BOUNDARIES: [Boundary; 3] = [Boundary::Fixed, Boundary::Free, Boundary::Curve];
const UPDATES: [WeightUpdate; 2] = [WeightUpdate::Every, WeightUpdate::Once];
const NORMALIZATIONS: [Normalization; 3] = [
    Normalization::WeightSum,
    Normalization::Area(VertexAreaKind::Barycentric),
    Normalization::Area(VertexAreaKind::MixedVoronoi),
];

/// A mesh with its positions, built from triangles.
#[derive(Clone)]
struct Case {
    name: String,
    positions: Vec<DVec3>,
    faces: Vec<[u32; 3]>,
}

impl Case {
    fn new(name: impl Into<String>, positions: Vec<DVec3>, faces: Vec<[u32; 3]>) -> Self {
        Self {
            name: name.into(),
            positions,
            faces,
        }
    }

    fn from_primitive(name: &str, p: &primitives::Primitive) -> Self {
        let faces = p
            .faces
            .iter()
            .map(|f| <[u32; 3]>::try_from(f).expect("triangles"))
            .collect();
        Self::new(name, p.positions.clone(), faces)
    }

    fn jitter(mut self, seed: u64, amplitude: f64) -> Self {
        let mut rng = SplitMix64::new(seed);
        for p in &mut self.positions {
            *p += rng.next_symmetric_vector() * amplitude;
        }
        self
    }

    fn mesh(&self) -> HalfedgeMesh {
        HalfedgeMesh::from_polygons(self.positions.len(), &self.faces)
            .unwrap_or_else(|e| panic!("{}: {e}", self.name))
    }

    fn mean_edge(&self) -> f64 {
        let mut sum = 0.0;
        let mut n = 0;
        for f in &self.faces {
            for k in 0..3 {
                sum += (self.positions[f[(k + 1) % 3] as usize] - self.positions[f[k] as usize])
                    .length();
                n += 1;
            }
        }
        // A mesh without faces or with every vertex at one point still gets a unit scale.
        if n == 0 || sum == 0.0 {
            1.0
        } else {
            sum / f64::from(n)
        }
    }
}

fn bounds(positions: &[DVec3]) -> (DVec3, DVec3) {
    positions
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        })
}

fn diagonal(positions: &[DVec3]) -> f64 {
    let (lo, hi) = bounds(positions);
    if positions.is_empty() {
        0.0
    } else {
        (hi - lo).length()
    }
}

fn bits(p: DVec3) -> [u64; 3] {
    p.to_array().map(f64::to_bits)
}

/// Every configuration: scheme × update × boundary × negative policy × normalisation.
fn configs(area_lambda: f64) -> Vec<(usize, SmoothConfig)> {
    let mut out = Vec::new();
    for (s, _) in SCHEMES.iter().enumerate() {
        for update in UPDATES {
            for boundary in BOUNDARIES {
                for negative in NEGATIVES {
                    for normalization in NORMALIZATIONS {
                        let lambda = if normalization == Normalization::WeightSum {
                            0.8
                        } else {
                            area_lambda
                        };
                        let config = SmoothConfig::new(lambda, 10)
                            .update(update)
                            .boundary(boundary)
                            .laplacian(
                                LaplacianOptions::new()
                                    .normalization(normalization)
                                    .negative(negative),
                            );
                        out.push((s, config));
                    }
                }
            }
        }
    }
    out
}

/// Whether every update of `config` with `scheme` is a convex combination of old
/// positions (non-negative weights, weight-sum normalisation, λ ≤ 1), so the result
/// stays in the input's bounding box.
fn is_convex(scheme: usize, config: &SmoothConfig) -> bool {
    config.laplacian.normalization == Normalization::WeightSum
        && (scheme != COTANGENT || config.laplacian.negative != NegativeWeights::Keep)
}

#[derive(Default, Debug)]
struct Tally {
    ok: usize,
    non_finite: usize,
    curve_rejected: usize,
}

/// Runs `config` and checks the outcome: no panic; `Ok` has finite positions, leaves
/// isolated vertices (and, with a fixed boundary, boundary vertices) bit-identical,
/// has statistics that are not NaN, and stays in the input's bounding box for convex updates;
/// `Err` is a typed error that the configuration explains.
fn check(
    case: &Case,
    mesh: &HalfedgeMesh,
    scheme: usize,
    config: &SmoothConfig,
    tally: &mut Tally,
) {
    let label = format!("{} / {} / {config:?}", case.name, SCHEMES[scheme].name());
    let result = catch_unwind(AssertUnwindSafe(|| {
        smooth(mesh, &case.positions, SCHEMES[scheme], config.clone())
    }))
    .unwrap_or_else(|_| panic!("{label}: panicked"));
    let area = config.laplacian.normalization != Normalization::WeightSum;
    match result {
        Ok(out) => {
            assert!(
                !(area && config.boundary == Boundary::Curve),
                "{label}: curve boundary accepted with area normalisation"
            );
            check_output(case, mesh, scheme, config, &out, &label);
            tally.ok += 1;
        }
        Err(SmoothError::CurveNeedsWeightSum) => {
            assert!(area && config.boundary == Boundary::Curve, "{label}");
            tally.curve_rejected += 1;
        }
        Err(SmoothError::NonFinite { vertex, iteration }) => {
            // Only a step that is not a convex combination can blow up.
            assert!(
                !is_convex(scheme, config),
                "{label}: vertex {vertex} became non-finite"
            );
            assert!(
                (vertex as usize) < case.positions.len()
                    && (1..=config.iterations).contains(&iteration)
            );
            tally.non_finite += 1;
        }
        Err(e) => panic!("{label}: unexpected error {e}"),
    }
}

fn check_output(
    case: &Case,
    mesh: &HalfedgeMesh,
    scheme: usize,
    config: &SmoothConfig,
    out: &Smoothed,
    label: &str,
) {
    assert_eq!(out.positions.len(), case.positions.len(), "{label}");
    for (i, p) in out.positions.iter().enumerate() {
        assert!(p.is_finite(), "{label}: vertex {i} is {p}");
    }
    // Statistics are never NaN. (They can be +inf for finite positions beyond about
    // 1e154: see `step_statistics_are_finite_when_positions_are`.)
    for s in &out.report.steps {
        assert!(
            s.max_displacement >= 0.0 && s.mean_displacement >= 0.0,
            "{label}: {s:?}"
        );
    }
    for v in mesh.vertices() {
        let fixed = mesh.is_isolated(v)
            || (config.boundary == Boundary::Fixed && mesh.is_boundary_vertex(v))
            || config.pinned.contains(&v);
        if fixed {
            assert_eq!(
                bits(out.positions[v.index()]),
                bits(case.positions[v.index()]),
                "{label}: vertex {} moved",
                v.raw()
            );
        }
    }
    if is_convex(scheme, config) && !case.positions.is_empty() {
        let (lo, hi) = bounds(&case.positions);
        let slack = DVec3::splat(1e-12 * diagonal(&case.positions));
        for (i, p) in out.positions.iter().enumerate() {
            assert!(
                p.cmpge(lo - slack).all() && p.cmple(hi + slack).all(),
                "{label}: vertex {i} at {p} left the input's bounding box [{lo}, {hi}]"
            );
        }
    }
}

/// [`check`]s every configuration on `case`, then every area-normalised one again with
/// a step far beyond the stability limit for `unstable_iterations` iterations.
fn run_all_with(case: &Case, unstable_iterations: usize) -> Tally {
    let mesh = case.mesh();
    let area_lambda = 0.01 * case.mean_edge().powi(2);
    let mut tally = Tally::default();
    for (scheme, config) in configs(area_lambda) {
        check(case, &mesh, scheme, &config, &mut tally);
    }
    // Area normalisation with a step far beyond the stability limit, long enough to
    // overflow where the operator lets it.
    for (scheme, mut config) in configs(1e3 * case.mean_edge().powi(2)) {
        if config.laplacian.normalization != Normalization::WeightSum {
            config.iterations = unstable_iterations;
            check(case, &mesh, scheme, &config, &mut tally);
        }
    }
    assert!(tally.ok > 0, "{}: {tally:?}", case.name);
    assert_eq!(tally.curve_rejected, 2 * 3 * 2 * 3 * 2, "{}", case.name);
    tally
}

fn run_all(case: &Case) -> Tally {
    run_all_with(case, 100)
}

fn grid_index(nx: u32) -> impl Fn(u32, u32) -> usize {
    move |i, j| (j * (nx + 1) + i) as usize
}

fn jittered_grid(n: u32, seed: u64) -> Case {
    Case::from_primitive(&format!("grid {n}x{n}"), &primitives::grid(n, n)).jitter(seed, 0.2)
}

// ---------------------------------------------------------------------------------------
// Degenerate meshes.
// ---------------------------------------------------------------------------------------

#[test]
fn coincident_vertices() {
    let id = grid_index(5);
    // Two interior vertices joined by an edge, at the same position.
    let mut interior = jittered_grid(5, 1);
    interior.name = "coincident interior pair".into();
    interior.positions[id(2, 2)] = interior.positions[id(3, 2)];
    // Two boundary vertices joined by a boundary edge.
    let mut boundary = jittered_grid(5, 2);
    boundary.name = "coincident boundary pair".into();
    boundary.positions[id(1, 0)] = boundary.positions[id(2, 0)];
    // A whole triangle collapsed to a point (three coincident vertices).
    let mut collapsed = jittered_grid(5, 3);
    collapsed.name = "collapsed triangle".into();
    let p = collapsed.positions[id(2, 2)];
    collapsed.positions[id(3, 2)] = p;
    collapsed.positions[id(3, 3)] = p;
    // The centre of a hexagon on one of its corners.
    let mut hex = Case::from_primitive("hexagon centre on a corner", &primitives::hexagon_fan());
    hex.positions[0] = hex.positions[1];
    // A closed mesh with a coincident pair.
    let mut sphere = Case::from_primitive(
        "icosphere with a coincident pair",
        &primitives::icosphere(1),
    );
    let f = sphere.faces[0];
    sphere.positions[f[0] as usize] = sphere.positions[f[1] as usize];
    for case in [interior, boundary, collapsed, hex, sphere] {
        let tally = run_all(&case);
        eprintln!("{}: {tally:?}", case.name);
    }
}

#[test]
fn zero_area_triangles() {
    // Three exactly collinear vertices form a triangle between two ordinary ones; vertex
    // 1 is interior and one of its three triangles has zero area.
    let strip = Case::new(
        "collinear triangle in a strip",
        vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.2),
            DVec3::new(1.0, -1.0, -0.1),
        ],
        vec![[0, 1, 3], [1, 2, 3], [0, 4, 2], [0, 2, 1]],
    );
    assert!(!strip.mesh().is_boundary_vertex(VertexId::new(1)));
    // A grid whose three middle rows lie on one line: the two strips between them have
    // zero area, and the middle row has no non-degenerate triangle at all.
    let mut band = jittered_grid(6, 4);
    band.name = "grid with a flattened band".into();
    let id = grid_index(6);
    for j in 2..=4 {
        for i in 0..=6 {
            let p = &mut band.positions[id(i, j)];
            *p = DVec3::new(p.x + 0.1 * f64::from(j), 3.0, 0.0);
        }
    }
    // Every triangle degenerate: a hexagon fan squashed onto a line.
    let mut flat = Case::from_primitive("hexagon squashed onto a line", &primitives::hexagon_fan());
    for p in &mut flat.positions {
        p.y = 0.0;
    }
    // A grid vertex moved exactly onto the line through two neighbours of one of its
    // triangles (which then has zero area; the triangles on the other side fold over).
    let mut folded =
        Case::from_primitive("grid vertex on a neighbour line", &primitives::grid(4, 4));
    let id4 = grid_index(4);
    folded.positions[id4(2, 2)] = DVec3::new(3.0, 1.5, 0.0);
    for case in [strip, band, flat, folded] {
        let tally = run_all(&case);
        eprintln!("{}: {tally:?}", case.name);
    }
}

#[test]
fn needle_triangles() {
    // One edge 1e-9 of the others: an interior grid vertex moved next to a neighbour.
    let id = grid_index(5);
    let mut grid = jittered_grid(5, 5);
    grid.name = "grid with needles".into();
    grid.positions[id(2, 2)] = grid.positions[id(3, 2)] + DVec3::new(0.0, 1e-9, 0.0);
    let mut grid_boundary = jittered_grid(5, 6);
    grid_boundary.name = "grid with a boundary needle".into();
    grid_boundary.positions[id(0, 2)] =
        grid_boundary.positions[id(0, 3)] + DVec3::new(1e-9, 0.0, 1e-9);
    let single = Case::new(
        "single needle",
        vec![
            DVec3::ZERO,
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1e-9, 0.0),
        ],
        vec![[0, 1, 2]],
    );
    for case in [grid, grid_boundary, single] {
        let tally = run_all(&case);
        eprintln!("{}: {tally:?}", case.name);
    }
}

#[test]
fn very_obtuse_triangles() {
    let hex = primitives::hexagon_fan();
    let mid = (hex.positions[1] + hex.positions[2]) * 0.5;
    let mut cases = Vec::new();
    for (name, t) in [("obtuse 179.8", 0.999), ("obtuse 180 - 2e-5", 1.0 - 1e-7)] {
        let mut c = Case::from_primitive(name, &hex);
        c.positions[0] = mid * t;
        // Check the angle at the centre in triangle (0, 1, 2).
        let (u, v) = (
            c.positions[1] - c.positions[0],
            c.positions[2] - c.positions[0],
        );
        assert!(u.angle_between(v).to_degrees() > 179.0);
        cases.push(c);
    }
    cases.push(Case::new(
        "single obtuse",
        vec![
            DVec3::ZERO,
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(1.0, 1e-3, 0.0),
        ],
        vec![[0, 1, 2]],
    ));
    // An obtuse triangle inside a grid: a vertex pushed almost onto the opposite edge
    // of one of its triangles.
    let id = grid_index(4);
    let mut grid =
        Case::from_primitive("grid with a flat obtuse triangle", &primitives::grid(4, 4));
    // Triangle (1,1), (2,1), (2,2): move (2,1) near the midpoint of (1,1)-(2,2).
    grid.positions[id(2, 1)] = DVec3::new(1.5 + 1e-4, 1.5 - 1e-4, 0.0);
    cases.push(grid);
    for case in cases {
        let tally = run_all(&case);
        eprintln!("{}: {tally:?}", case.name);
    }
}

#[test]
fn isolated_vertices_never_move() {
    // A jittered grid with isolated vertices before, among and after the used ones.
    let grid = jittered_grid(4, 7);
    let n = grid.positions.len() as u32;
    let remap = |v: u32| if v < n / 2 { v + 1 } else { v + 2 };
    let mut positions = vec![DVec3::new(9.0, 9.0, 9.0)];
    positions.extend_from_slice(&grid.positions[..(n / 2) as usize]);
    positions.push(DVec3::new(-3.0, 0.5, 1.0));
    positions.extend_from_slice(&grid.positions[(n / 2) as usize..]);
    positions.push(DVec3::new(0.25, -7.0, 2.0));
    let faces = grid.faces.iter().map(|f| f.map(remap)).collect();
    let case = Case::new("grid with isolated vertices", positions, faces);
    let mesh = case.mesh();
    let isolated: Vec<u32> = mesh
        .vertices()
        .filter(|&v| mesh.is_isolated(v))
        .map(VertexId::raw)
        .collect();
    assert_eq!(isolated, vec![0, n / 2 + 1, n + 2]);
    run_all(&case); // checks bit-identity of isolated vertices in every configuration

    // Only isolated vertices, and no vertices at all.
    let lonely = Case::new(
        "isolated vertices only",
        vec![DVec3::ONE, DVec3::X * 2.0],
        vec![],
    );
    let empty = Case::new("empty mesh", vec![], vec![]);
    for case in [lonely, empty] {
        let mesh = case.mesh();
        for (scheme, config) in configs(0.01) {
            let label = format!("{} / {config:?}", case.name);
            match smooth(&mesh, &case.positions, SCHEMES[scheme], config.clone()) {
                Ok(out) => {
                    check_output(&case, &mesh, scheme, &config, &out, &label);
                    assert!(
                        out.report
                            .steps
                            .iter()
                            .all(|s| s.max_displacement == 0.0 && s.stuck_vertices == 0)
                    );
                }
                Err(SmoothError::CurveNeedsWeightSum) => {
                    assert_ne!(config.laplacian.normalization, Normalization::WeightSum);
                }
                Err(e) => panic!("{label}: {e}"),
            }
        }
    }
}

#[test]
fn single_triangle() {
    let plain = Case::from_primitive("triangle", &primitives::triangle());
    let tilted = Case::new(
        "tilted triangle",
        vec![
            DVec3::new(0.1, 0.2, 0.3),
            DVec3::new(1.7, -0.4, 0.9),
            DVec3::new(-0.3, 1.1, -0.5),
        ],
        vec![[0, 1, 2]],
    );
    let collinear = Case::new(
        "collinear triangle",
        vec![
            DVec3::ZERO,
            DVec3::new(1.0, 1.0, 1.0),
            DVec3::new(3.0, 3.0, 3.0),
        ],
        vec![[0, 1, 2]],
    );
    let point = Case::new(
        "triangle collapsed to a point",
        vec![DVec3::ONE; 3],
        vec![[0, 1, 2]],
    );
    for case in [plain, tilted, collinear, point] {
        run_all(&case);
        // With a free boundary and uniform weights the triangle contracts to its
        // centroid, which stays put.
        let mesh = case.mesh();
        let out = smooth(
            &mesh,
            &case.positions,
            &Uniform,
            SmoothConfig::new(0.5, 5).boundary(Boundary::Free),
        )
        .unwrap();
        let c0: DVec3 = case.positions.iter().sum::<DVec3>() / 3.0;
        let c1: DVec3 = out.positions.iter().sum::<DVec3>() / 3.0;
        assert!(
            (c0 - c1).length() <= 1e-14 * (1.0 + c0.length()),
            "{}",
            case.name
        );
    }
}

// ---------------------------------------------------------------------------------------
// Invalid input and parameters.
// ---------------------------------------------------------------------------------------

#[test]
fn non_finite_input_names_the_vertex() {
    let sphere = Case::from_primitive("icosphere", &primitives::icosphere(1));
    let mesh = sphere.mesh();
    let n = sphere.positions.len();
    for v in [0, 7, n - 1] {
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for axis in 0..3 {
                let mut positions = sphere.positions.clone();
                positions[v][axis] = bad;
                for (scheme, config) in configs(0.01) {
                    let err = smooth(&mesh, &positions, SCHEMES[scheme], config.clone());
                    match err {
                        Err(SmoothError::NonFiniteInput { vertex }) => {
                            assert_eq!(vertex as usize, v)
                        }
                        Err(SmoothError::CurveNeedsWeightSum) => {}
                        other => panic!("{v} {bad} {axis} {config:?}: {other:?}"),
                    }
                }
            }
        }
    }
    // Two bad vertices: one of them is named.
    let mut positions = sphere.positions.clone();
    positions[3].y = f64::NAN;
    positions[11].z = f64::INFINITY;
    match smooth(&mesh, &positions, &Cotangent, SmoothConfig::default()) {
        Err(SmoothError::NonFiniteInput { vertex }) => assert!(vertex == 3 || vertex == 11),
        other => panic!("{other:?}"),
    }
    // An isolated vertex counts too, although it never moves.
    let mut positions = sphere.positions.clone();
    positions.push(DVec3::new(f64::NAN, 0.0, 0.0));
    let with_isolated = HalfedgeMesh::from_polygons(n + 1, &sphere.faces).unwrap();
    assert_eq!(
        smooth(
            &with_isolated,
            &positions,
            &Uniform,
            SmoothConfig::default()
        )
        .unwrap_err(),
        SmoothError::NonFiniteInput { vertex: n as u32 }
    );
}

#[test]
fn invalid_lambda_is_rejected() {
    let grid = jittered_grid(3, 8);
    let mesh = grid.mesh();
    let area = |kind| {
        LaplacianOptions::new()
            .normalization(Normalization::Area(kind))
            .negative(NegativeWeights::Keep)
    };
    for scheme in SCHEMES {
        for lambda in [
            0.0,
            -0.0,
            1.5,
            f64::NAN,
            -0.5,
            f64::INFINITY,
            1.0 + f64::EPSILON,
        ] {
            let err =
                smooth(&mesh, &grid.positions, scheme, SmoothConfig::new(lambda, 3)).unwrap_err();
            match err {
                SmoothError::InvalidLambda { lambda: got, .. } => {
                    assert!(got.to_bits() == lambda.to_bits(), "{got} {lambda}");
                }
                other => panic!("{lambda}: {other:?}"),
            }
        }
        for lambda in [1.0, 1e-300, 0.5] {
            smooth(&mesh, &grid.positions, scheme, SmoothConfig::new(lambda, 3)).unwrap();
        }
        for kind in [VertexAreaKind::Barycentric, VertexAreaKind::MixedVoronoi] {
            for lambda in [0.0, f64::NAN, -1.0, f64::INFINITY, f64::NEG_INFINITY] {
                let config = SmoothConfig::new(lambda, 3).laplacian(area(kind));
                let err = smooth(&mesh, &grid.positions, scheme, config).unwrap_err();
                assert!(
                    matches!(err, SmoothError::InvalidLambda { .. }),
                    "{lambda}: {err:?}"
                );
            }
            // λ is a diffusion time with area normalisation: 1.5 is allowed.
            let config = SmoothConfig::new(1.5, 1).laplacian(area(kind));
            match smooth(&mesh, &grid.positions, scheme, config) {
                Ok(out) => assert!(out.positions.iter().all(|p| p.is_finite())),
                Err(e) => assert!(matches!(e, SmoothError::NonFinite { .. }), "{e:?}"),
            }
        }
    }
}

#[test]
fn pinned_vertex_out_of_range() {
    let grid = jittered_grid(3, 9);
    let mesh = grid.mesh();
    let n = grid.positions.len();
    for bad in [n as u32, n as u32 + 5, u32::MAX] {
        let config = SmoothConfig::default().pinned(vec![VertexId::new(0), VertexId::new(bad)]);
        assert_eq!(
            smooth(&mesh, &grid.positions, &Cotangent, config).unwrap_err(),
            SmoothError::PinnedOutOfRange {
                vertex: bad,
                n_vertices: n
            }
        );
    }
    // The last vertex is in range, and stays put even on a free boundary.
    let last = VertexId::new(n as u32 - 1);
    let config = SmoothConfig::default()
        .boundary(Boundary::Free)
        .pinned(vec![last, last]);
    let out = smooth(&mesh, &grid.positions, &Cotangent, config).unwrap();
    assert_eq!(bits(out.positions[n - 1]), bits(grid.positions[n - 1]));
    assert_ne!(out.positions[n - 2], grid.positions[n - 2]);
}

#[test]
fn positions_that_do_not_match_the_mesh_are_an_error() {
    let grid = jittered_grid(3, 10);
    let mesh = grid.mesh();
    let n = grid.positions.len();
    for len in [0, n - 1, n + 1] {
        let mut positions = grid.positions.clone();
        positions.resize(len, DVec3::ZERO);
        for boundary in BOUNDARIES {
            let err = smooth(
                &mesh,
                &positions,
                &Cotangent,
                SmoothConfig::default().boundary(boundary),
            )
            .unwrap_err();
            assert_eq!(
                err,
                SmoothError::Weights(WeightError::Topology(TopologyError::PositionCount {
                    positions: len,
                    vertices: n
                }))
            );
        }
    }
}

#[test]
fn zero_iterations_return_the_input() {
    let grid = jittered_grid(3, 11);
    let mesh = grid.mesh();
    for scheme in SCHEMES {
        let out = smooth(&mesh, &grid.positions, scheme, SmoothConfig::new(0.8, 0)).unwrap();
        assert_eq!(out.report.iterations, 0);
        assert!(out.report.steps.is_empty());
        assert_eq!(out.positions, grid.positions);
    }
}

// ---------------------------------------------------------------------------------------
// Custom schemes that misbehave.
// ---------------------------------------------------------------------------------------

/// Returns `value` on every halfedge out of `from` (all halfedges when `None`), 1
/// elsewhere.
struct Constant {
    value: f64,
    from: Option<u32>,
}

impl WeightScheme for Constant {
    fn name(&self) -> &str {
        "constant"
    }
    fn weight(&self, ctx: &WeightContext<'_>, h: HalfedgeId) -> f64 {
        match self.from {
            Some(v) if ctx.mesh().from_vertex(h).raw() != v => 1.0,
            _ => self.value,
        }
    }
}

/// Uniform weights until a vertex has moved away from where it started, NaN afterwards.
struct NanOnceMoved {
    start: Vec<DVec3>,
}

impl WeightScheme for NanOnceMoved {
    fn name(&self) -> &str {
        "nan-once-moved"
    }
    fn weight(&self, ctx: &WeightContext<'_>, h: HalfedgeId) -> f64 {
        let v = ctx.mesh().from_vertex(h);
        if ctx.position(v) == self.start[v.index()] {
            1.0
        } else {
            f64::NAN
        }
    }
}

/// Uniform weights with a chosen 1-D boundary weight.
struct CurveWeight(f64);

impl WeightScheme for CurveWeight {
    fn name(&self) -> &str {
        "curve-weight"
    }
    fn weight(&self, _ctx: &WeightContext<'_>, _h: HalfedgeId) -> f64 {
        1.0
    }
    fn curve_weight(&self, _ctx: &WeightContext<'_>, _h: HalfedgeId) -> f64 {
        self.0
    }
}

#[test]
fn a_scheme_that_returns_nan_is_an_error() {
    let grid = jittered_grid(4, 12);
    let mesh = grid.mesh();
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        for from in [None, Some(7)] {
            let scheme = Constant { value: bad, from };
            for (_, config) in configs(0.01) {
                match smooth(&mesh, &grid.positions, &scheme, config.clone()) {
                    Err(SmoothError::Weights(WeightError::NonFiniteWeight {
                        scheme: name,
                        from: f,
                        to,
                        value,
                    })) => {
                        assert_eq!(name, "constant");
                        assert_eq!(value.to_bits(), bad.to_bits());
                        if let Some(v) = from {
                            assert_eq!(f, v);
                        }
                        let h = mesh.find_halfedge(VertexId::new(f), VertexId::new(to));
                        assert!(h.is_some(), "{f} -> {to} is not an edge");
                    }
                    Err(SmoothError::CurveNeedsWeightSum) => {}
                    other => panic!("{bad} {from:?} {config:?}: {other:?}"),
                }
            }
        }
    }
}

#[test]
fn a_scheme_that_turns_nan_mid_run_is_an_error() {
    let grid = jittered_grid(4, 13);
    let mesh = grid.mesh();
    let scheme = NanOnceMoved {
        start: grid.positions.clone(),
    };
    for (_, config) in configs(0.01) {
        let result = smooth(&mesh, &grid.positions, &scheme, config.clone());
        match (config.update, result) {
            // Recomputed weights see the moved vertices in iteration 2.
            (
                WeightUpdate::Every,
                Err(SmoothError::Weights(WeightError::NonFiniteWeight { value, .. })),
            ) => {
                assert!(value.is_nan());
            }
            // Frozen weights never see them.
            (WeightUpdate::Once, Ok(out)) => assert!(out.positions.iter().all(|p| p.is_finite())),
            (_, Err(SmoothError::CurveNeedsWeightSum)) => {}
            (update, other) => panic!("{update:?} {config:?}: {other:?}"),
        }
    }
    // Driven step by step: the failing step reports the error and the positions stay
    // those of the last good iterate.
    let mut smoother =
        Smoother::new(&mesh, &grid.positions, &scheme, SmoothConfig::new(0.8, 5)).unwrap();
    smoother.step().unwrap();
    let before = smoother.positions().to_vec();
    assert!(matches!(smoother.step(), Err(SmoothError::Weights(_))));
    assert_eq!(smoother.positions(), &before[..]);
}

#[test]
fn a_non_finite_curve_weight_is_an_error() {
    let grid = jittered_grid(3, 14);
    let mesh = grid.mesh();
    for bad in [f64::NAN, f64::INFINITY] {
        let config = SmoothConfig::new(0.8, 3).boundary(Boundary::Curve);
        match smooth(&mesh, &grid.positions, &CurveWeight(bad), config) {
            Err(SmoothError::Weights(WeightError::NonFiniteWeight { value, .. })) => {
                assert_eq!(value.to_bits(), bad.to_bits());
            }
            other => panic!("{bad}: {other:?}"),
        }
        // Other boundary modes do not use it.
        for boundary in [Boundary::Fixed, Boundary::Free] {
            let config = SmoothConfig::new(0.8, 3).boundary(boundary);
            smooth(&mesh, &grid.positions, &CurveWeight(bad), config).unwrap();
        }
    }
}

#[test]
fn unusable_weights_leave_vertices_stuck_and_counted() {
    let grid = jittered_grid(4, 15);
    let mesh = grid.mesh();
    let interior = mesh
        .vertices()
        .filter(|&v| !mesh.is_boundary_vertex(v))
        .count();
    let boundary = grid.positions.len() - interior;
    // Zero, negative and overflowing weight sums: no vertex can move.
    for value in [0.0, -1.0, f64::MAX] {
        for negative in [NegativeWeights::Keep, NegativeWeights::Clamp] {
            if value == f64::MAX && negative == NegativeWeights::Clamp {
                continue;
            }
            let scheme = Constant { value, from: None };
            let config = SmoothConfig::new(0.8, 4)
                .boundary(Boundary::Free)
                .laplacian(
                    LaplacianOptions::new()
                        .normalization(Normalization::WeightSum)
                        .negative(negative),
                );
            let out = smooth(&mesh, &grid.positions, &scheme, config).unwrap();
            assert_eq!(out.positions, grid.positions, "{value} {negative:?}");
            assert!(
                out.report
                    .steps
                    .iter()
                    .all(|s| s.stuck_vertices == interior + boundary)
            );
            assert_eq!(out.report.max_stuck_vertices, interior + boundary);
        }
    }
    // 1-D weights that sum to zero or less: curve vertices are stuck, interior ones move.
    for value in [0.0, -1.0] {
        let config = SmoothConfig::new(0.8, 4).boundary(Boundary::Curve);
        let out = smooth(&mesh, &grid.positions, &CurveWeight(value), config).unwrap();
        assert!(
            out.report
                .steps
                .iter()
                .all(|s| s.stuck_vertices == boundary),
            "{value}"
        );
        for v in mesh.vertices().filter(|&v| mesh.is_boundary_vertex(v)) {
            assert_eq!(
                bits(out.positions[v.index()]),
                bits(grid.positions[v.index()])
            );
        }
        assert_ne!(out.positions, grid.positions);
    }
}

#[test]
fn huge_weights_stay_finite_or_fail_cleanly() {
    let grid = jittered_grid(4, 16);
    let mesh = grid.mesh();
    for value in [1e300, 1e-300, 5e-324] {
        let scheme = Constant { value, from: None };
        for (_, config) in configs(0.01) {
            match smooth(&mesh, &grid.positions, &scheme, config.clone()) {
                Ok(out) => assert!(
                    out.positions.iter().all(|p| p.is_finite()),
                    "{value} {config:?}"
                ),
                Err(SmoothError::NonFinite { .. } | SmoothError::CurveNeedsWeightSum) => {}
                Err(e) => panic!("{value} {config:?}: {e}"),
            }
        }
    }
}

// ---------------------------------------------------------------------------------------
// Unstable area steps.
// ---------------------------------------------------------------------------------------

#[test]
fn huge_area_step_is_non_finite_error_or_finite() {
    let sphere = Case::from_primitive("unit icosphere", &primitives::icosphere(2));
    let mesh = sphere.mesh();
    let mut outcomes = [0usize; 2];
    for scheme in SCHEMES {
        for kind in [VertexAreaKind::Barycentric, VertexAreaKind::MixedVoronoi] {
            for update in UPDATES {
                for negative in NEGATIVES {
                    for iterations in [10, 200] {
                        let config = SmoothConfig::new(1e6, iterations).update(update).laplacian(
                            LaplacianOptions::new()
                                .normalization(Normalization::Area(kind))
                                .negative(negative),
                        );
                        let label = format!("{} {config:?}", scheme.name());
                        match smooth(&mesh, &sphere.positions, scheme, config) {
                            Ok(out) => {
                                assert!(out.positions.iter().all(|p| p.is_finite()), "{label}");
                                assert!(
                                    out.report.steps.iter().all(|s| !s.max_displacement.is_nan()
                                        && !s.mean_displacement.is_nan()),
                                    "{label}"
                                );
                                outcomes[0] += 1;
                            }
                            Err(SmoothError::NonFinite { vertex, iteration }) => {
                                assert!((vertex as usize) < sphere.positions.len());
                                assert!((1..=iterations).contains(&iteration), "{label}");
                                outcomes[1] += 1;
                            }
                            Err(e) => panic!("{label}: {e}"),
                        }
                    }
                }
            }
        }
    }
    eprintln!(
        "huge area step: {} finite, {} NonFinite",
        outcomes[0], outcomes[1]
    );
    // With frozen weights the step multiplies the error by about 1e6·W/A every
    // iteration: 200 iterations overflow.
    assert!(outcomes[1] > 0);
}

#[test]
fn a_failed_step_keeps_the_last_finite_iterate() {
    let sphere = Case::from_primitive("unit icosphere", &primitives::icosphere(2));
    let mesh = sphere.mesh();
    let config = SmoothConfig::new(1e6, 1000)
        .update(WeightUpdate::Once)
        .laplacian(
            LaplacianOptions::new()
                .normalization(Normalization::Area(VertexAreaKind::Barycentric))
                .negative(NegativeWeights::Keep),
        );
    let mut smoother = Smoother::new(&mesh, &sphere.positions, &Cotangent, config).unwrap();
    let mut failed = false;
    for k in 1..=1000 {
        let before = smoother.positions().to_vec();
        match smoother.step() {
            Ok(stats) => assert!(!stats.max_displacement.is_nan()),
            Err(SmoothError::NonFinite { vertex, iteration }) => {
                assert_eq!(iteration, k);
                assert!((vertex as usize) < before.len());
                let after: Vec<[u64; 3]> = smoother.positions().iter().map(|&p| bits(p)).collect();
                let expected: Vec<[u64; 3]> = before.iter().map(|&p| bits(p)).collect();
                assert_eq!(after, expected);
                assert!(smoother.positions().iter().all(|p| p.is_finite()));
                failed = true;
                break;
            }
            Err(e) => panic!("{e}"),
        }
    }
    assert!(failed, "1000 steps of 1e6 never overflowed");
}

// ---------------------------------------------------------------------------------------
// Extreme scales.
// ---------------------------------------------------------------------------------------

/// A noisy hexagon fan and a jittered grid: one interior vertex with a free-moving
/// boundary, and many interior vertices.
fn scale_cases() -> Vec<Case> {
    vec![
        Case::from_primitive("noisy hexagon", &primitives::hexagon_fan()).jitter(18, 0.1),
        jittered_grid(4, 19),
    ]
}

const SCALE_EXPONENTS: [i32; 8] = [-600, -300, -100, 0, 100, 300, 520, 600];

#[test]
fn power_of_two_scaling_commutes_bit_for_bit() {
    // Scaling by 2^k is exact, uniform and cotangent weights do not depend on the scale
    // (the geometry rescales extreme edge vectors by powers of two), and weight-sum
    // normalisation is dimensionless: smoothing 2^k x gives exactly 2^k times the result
    // for x, far beyond the range where squared lengths overflow or underflow. (Inverse
    // distance is excluded: its ε = 1e-12 sets a scale. The default 1-D curve weight is
    // inverse distance too, so cotangent runs without the curve mode here.) Cotangent rows
    // summed by triangles keep the property through a sweep on positions rescaled by a
    // power of two.
    for case in scale_cases() {
        let mesh = case.mesh();
        for k in SCALE_EXPONENTS {
            let s = 2f64.powi(k);
            let scaled: Vec<DVec3> = case.positions.iter().map(|&p| p * s).collect();
            for (scheme, boundaries) in [
                (UNIFORM, &BOUNDARIES[..]),
                (COTANGENT, &[Boundary::Fixed, Boundary::Free][..]),
            ] {
                for &boundary in boundaries {
                    for (update, summation) in UPDATES
                        .into_iter()
                        .flat_map(|u| [(u, Summation::Rows), (u, Summation::Scatter)])
                    {
                        for negative in NEGATIVES {
                            let config = SmoothConfig::new(0.8, 10)
                                .boundary(boundary)
                                .update(update)
                                .summation(summation)
                                .laplacian(
                                    LaplacianOptions::new()
                                        .normalization(Normalization::WeightSum)
                                        .negative(negative),
                                );
                            let label = format!(
                                "{} 2^{k} {} {config:?}",
                                case.name,
                                SCHEMES[scheme].name()
                            );
                            let a = smooth(&mesh, &case.positions, SCHEMES[scheme], config.clone())
                                .unwrap();
                            let b = smooth(&mesh, &scaled, SCHEMES[scheme], config).unwrap();
                            assert_ne!(a.positions, case.positions, "{label}");
                            for (i, (p, q)) in a.positions.iter().zip(&b.positions).enumerate() {
                                assert_eq!(bits(*p * s), bits(*q), "{label}: vertex {i}");
                            }
                            assert_eq!(
                                a.report.max_stuck_vertices, b.report.max_stuck_vertices,
                                "{label}"
                            );
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn step_statistics_are_finite_when_positions_are() {
    // Uniform smoothing commutes with 2^k scaling bit for bit (test above), so the
    // displacement statistics must scale by 2^k too. At 2^520 the library reports
    // max_displacement = mean_displacement = inf; at 2^-600 it reports 0 although every
    // free vertex moved.
    for case in scale_cases() {
        let mesh = case.mesh();
        let config = SmoothConfig::new(0.8, 3).boundary(Boundary::Free);
        let reference = smooth(&mesh, &case.positions, &Uniform, config.clone()).unwrap();
        for k in SCALE_EXPONENTS {
            let s = 2f64.powi(k);
            let scaled: Vec<DVec3> = case.positions.iter().map(|&p| p * s).collect();
            let out = smooth(&mesh, &scaled, &Uniform, config.clone()).unwrap();
            assert!(out.positions.iter().all(|p| p.is_finite()));
            for (a, b) in reference.report.steps.iter().zip(&out.report.steps) {
                for (x, y) in [
                    (a.max_displacement, b.max_displacement),
                    (a.mean_displacement, b.mean_displacement),
                ] {
                    assert!(
                        y.is_finite() && (y / s - x).abs() <= 1e-14 * x,
                        "{} 2^{k}: displacement {y:e}, expected {:e}",
                        case.name,
                        x * s
                    );
                }
            }
        }
    }
    // The same through an unstable area step on the unit icosphere: iteration 20 returns
    // Ok with positions of about 1e155 and infinite statistics.
    let sphere = Case::from_primitive("unit icosphere", &primitives::icosphere(2));
    let mesh = sphere.mesh();
    let config = SmoothConfig::new(1e6, 1000)
        .update(WeightUpdate::Once)
        .laplacian(
            LaplacianOptions::new()
                .normalization(Normalization::Area(VertexAreaKind::Barycentric))
                .negative(NegativeWeights::Keep),
        );
    let mut smoother = Smoother::new(&mesh, &sphere.positions, &Cotangent, config).unwrap();
    while let Ok(stats) = smoother.step() {
        let largest = smoother
            .positions()
            .iter()
            .map(|p| p.abs().max_element())
            .fold(0.0, f64::max);
        if largest > 1e300 {
            // Displacements and their sum may now exceed f64::MAX for real.
            break;
        }
        assert!(
            stats.max_displacement.is_finite() && stats.mean_displacement.is_finite(),
            "iteration {}: {stats:?} with positions up to {largest:e}",
            smoother.iteration()
        );
    }
}

#[test]
fn inverse_distance_weights_survive_extreme_scales() {
    // Far above ε = 1e-12, inverse-distance smoothing is scale-invariant up to the
    // rounding of the ε term: smoothing 2^k x gives 2^k times the result for x, to about
    // 1e-11. From 2^520 (edges of about 3e156) on, the library's weights are
    // 1/(inf + ε) = 0: nothing moves and every free vertex is counted stuck. The same
    // happens to the curve boundary of cotangent smoothing, whose 1-D weights are inverse
    // distances.
    for case in scale_cases() {
        let mesh = case.mesh();
        for (scheme, boundary) in [
            (DISTANCE, Boundary::Fixed),
            (DISTANCE, Boundary::Free),
            (DISTANCE, Boundary::Curve),
            (COTANGENT, Boundary::Curve),
        ] {
            let config = SmoothConfig::new(0.8, 10).boundary(boundary);
            let reference =
                smooth(&mesh, &case.positions, SCHEMES[scheme], config.clone()).unwrap();
            let diag = diagonal(&case.positions);
            for k in [100, 300, 520, 600] {
                let s = 2f64.powi(k);
                let scaled: Vec<DVec3> = case.positions.iter().map(|&p| p * s).collect();
                let out = smooth(&mesh, &scaled, SCHEMES[scheme], config.clone()).unwrap();
                let label = format!(
                    "{} 2^{k} {} {boundary:?}",
                    case.name,
                    SCHEMES[scheme].name()
                );
                assert_eq!(out.report.max_stuck_vertices, 0, "{label}");
                for (p, q) in reference.positions.iter().zip(&out.positions) {
                    let d = (*p - *q / s).abs().max_element() / diag;
                    assert!(d <= 1e-9, "{label}: relative difference {d:e}");
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------
// Properties.
// ---------------------------------------------------------------------------------------

/// A jittered grid or icosphere, perturbed by `amplitude` times its edge length, with
/// `collapses` vertices moved onto a neighbour.
fn perturbed(sphere: bool, seed: u64, amplitude: f64, collapses: &[(usize, usize)]) -> Case {
    let (mut case, edge) = if sphere {
        (
            Case::from_primitive("icosphere", &primitives::icosphere(1)),
            0.6,
        )
    } else {
        (Case::from_primitive("grid", &primitives::grid(6, 5)), 1.0)
    };
    case = case.jitter(seed, amplitude * edge);
    for &(v, k) in collapses {
        let v = (v % case.positions.len()) as u32;
        if let Some(f) = case.faces.iter().find(|f| f.contains(&v)) {
            let at = f.iter().position(|&x| x == v).unwrap();
            let other = f[(at + 1 + k % 2) % 3];
            case.positions[v as usize] = case.positions[other as usize];
        }
    }
    case.name = format!(
        "{} seed {seed} amplitude {amplitude} collapses {collapses:?}",
        case.name
    );
    case
}

fn rigid_motion(axis: DVec3, angle: f64, t: DVec3) -> impl Fn(DVec3) -> DVec3 {
    let r = DMat3::from_quat(DQuat::from_axis_angle(axis.normalize(), angle));
    move |p| r * p + t
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    #[test]
    fn perturbed_meshes_give_finite_output(
        sphere in any::<bool>(),
        seed in any::<u64>(),
        amplitude in 0.0..0.3f64,
        collapses in proptest::collection::vec((0usize..1000, 0usize..2), 0..4),
    ) {
        let case = perturbed(sphere, seed, amplitude, &collapses);
        run_all_with(&case, 20);
    }

    #[test]
    fn smoothing_commutes_with_rigid_motions(
        sphere in any::<bool>(),
        seed in any::<u64>(),
        amplitude in 0.0..0.25f64,
        axis in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64)
            .prop_filter("a direction", |(x, y, z)| x * x + y * y + z * z > 0.01),
        angle in 0.0..std::f64::consts::TAU,
        shift in (-5.0..5.0f64, -5.0..5.0f64, -5.0..5.0f64),
    ) {
        let case = perturbed(sphere, seed, amplitude, &[]);
        let mesh = case.mesh();
        let motion = rigid_motion(DVec3::new(axis.0, axis.1, axis.2), angle, DVec3::new(shift.0, shift.1, shift.2));
        let moved: Vec<DVec3> = case.positions.iter().map(|&p| motion(p)).collect();
        let diag = diagonal(&case.positions);
        for (scheme, config) in configs(0.0) {
            if config.laplacian.normalization != Normalization::WeightSum {
                continue;
            }
            let a = smooth(&mesh, &case.positions, SCHEMES[scheme], config.clone()).unwrap();
            let b = smooth(&mesh, &moved, SCHEMES[scheme], config.clone()).unwrap();
            let tolerance = if ill_conditioned(scheme, &config) && !sphere { 1e-6 } else { 1e-12 };
            for (i, (p, q)) in a.positions.iter().zip(&b.positions).enumerate() {
                let d = (motion(*p) - *q).abs().max_element() / diag;
                prop_assert!(
                    d <= tolerance,
                    "{} / {} / {:?}: vertex {}: difference {:e}",
                    case.name, SCHEMES[scheme].name(), config, i, d
                );
            }
        }
    }
}

/// Cotangent weights recomputed every iteration with a free boundary: on an open mesh
/// this flow pulls boundary triangles into slivers (twice the area down to 1e-6 of the
/// longest edge squared) whose large cotangents amplify rounding. A rounding-level change
/// of the input (the rounding of a rotation) then changes the result by up to about
/// 1e-10 of the mesh size (see `cotangent_free_boundary_flow_amplifies_rounding`), so
/// rigid-motion equivariance holds there only to that level.
fn ill_conditioned(scheme: usize, config: &SmoothConfig) -> bool {
    scheme == COTANGENT && config.boundary == Boundary::Free && config.update == WeightUpdate::Every
}

#[test]
fn cotangent_free_boundary_flow_amplifies_rounding() {
    // The reason for the looser equivariance tolerance above: perturbing the input by
    // 1e-15 (no rotation at all) moves the result by far more than 1e-15.
    let case = perturbed(false, 41, 0.2, &[]);
    let mesh = case.mesh();
    let mut rng = SplitMix64::new(42);
    let nudged: Vec<DVec3> = case
        .positions
        .iter()
        .map(|&p| p + rng.next_symmetric_vector() * 1e-15)
        .collect();
    let diag = diagonal(&case.positions);
    let mut worst = 0.0f64;
    for negative in NEGATIVES {
        let config = SmoothConfig::new(0.8, 10)
            .boundary(Boundary::Free)
            .laplacian(
                LaplacianOptions::new()
                    .normalization(Normalization::WeightSum)
                    .negative(negative),
            );
        assert!(ill_conditioned(COTANGENT, &config));
        let a = smooth(&mesh, &case.positions, &Cotangent, config.clone()).unwrap();
        let b = smooth(&mesh, &nudged, &Cotangent, config).unwrap();
        let d = a
            .positions
            .iter()
            .zip(&b.positions)
            .map(|(p, q)| (*p - *q).abs().max_element())
            .fold(0.0, f64::max);
        worst = worst.max(d / diag);
    }
    assert!(worst > 1e-14, "amplification {worst:e}");
    assert!(worst < 1e-6, "amplification {worst:e}");
}

// ---------------------------------------------------------------------------------------
// Determinism.
// ---------------------------------------------------------------------------------------

/// Enough vertices for more than one parallel work unit (4096 vertices each).
fn large_grid() -> Case {
    Case::from_primitive("grid 80x60", &primitives::grid(80, 60)).jitter(17, 0.3)
}

fn determinism_configs() -> Vec<(usize, SmoothConfig)> {
    let mut out = Vec::new();
    for (s, _) in SCHEMES.iter().enumerate() {
        for boundary in BOUNDARIES {
            for negative in [NegativeWeights::Keep, NegativeWeights::Clamp] {
                out.push((
                    s,
                    SmoothConfig::new(0.8, 10).boundary(boundary).laplacian(
                        LaplacianOptions::new()
                            .normalization(Normalization::WeightSum)
                            .negative(negative),
                    ),
                ));
            }
        }
        out.push((
            s,
            SmoothConfig::new(0.01, 10)
                .update(WeightUpdate::Once)
                .boundary(Boundary::Free)
                .laplacian(
                    LaplacianOptions::new()
                        .normalization(Normalization::Area(VertexAreaKind::MixedVoronoi))
                        .negative(NegativeWeights::Keep),
                ),
        ));
    }
    out
}

/// Positions and per-iteration statistics as bits.
fn fingerprint(out: &Smoothed) -> (Vec<[u64; 3]>, Vec<[u64; 3]>) {
    (
        out.positions.iter().map(|&p| bits(p)).collect(),
        out.report
            .steps
            .iter()
            .map(|s| {
                [
                    s.max_displacement.to_bits(),
                    s.mean_displacement.to_bits(),
                    s.stuck_vertices as u64,
                ]
            })
            .collect(),
    )
}

#[test]
fn repeated_runs_are_bit_identical() {
    let case = large_grid();
    let mesh = case.mesh();
    assert!(case.positions.len() > 4096);
    for (scheme, config) in determinism_configs() {
        let a = smooth(&mesh, &case.positions, SCHEMES[scheme], config.clone()).unwrap();
        let b = smooth(&mesh, &case.positions, SCHEMES[scheme], config.clone()).unwrap();
        assert!(fingerprint(&a) == fingerprint(&b), "{config:?}");
        // And it did something.
        assert_ne!(a.positions, case.positions);
    }
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let case = large_grid();
    let mesh = case.mesh();
    let pools: Vec<rayon::ThreadPool> = [1, 2, 3]
        .iter()
        .map(|&n| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap()
        })
        .collect();
    for (scheme, config) in determinism_configs() {
        let runs: Vec<_> = pools
            .iter()
            .map(|pool| {
                pool.install(|| {
                    let mut count = 0;
                    let out =
                        Smoother::new(&mesh, &case.positions, SCHEMES[scheme], config.clone())
                            .unwrap()
                            .run(|_| {
                                count += 1;
                                ControlFlow::Continue(())
                            })
                            .unwrap();
                    assert_eq!(count, 10);
                    fingerprint(&out)
                })
            })
            .collect();
        assert!(
            runs[0] == runs[1],
            "1 vs 2 threads: {} {config:?}",
            SCHEMES[scheme].name()
        );
        assert!(
            runs[0] == runs[2],
            "1 vs 3 threads: {} {config:?}",
            SCHEMES[scheme].name()
        );
    }
}
