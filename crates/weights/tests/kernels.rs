//! The built-in schemes' kernels (recognised by type) give the same bits as the
//! generic path (`fill_weights`, gathered into rows) on meshes that exercise every branch:
//! irregular planes with negative cotangents, noisy spheres, degenerate and coincident
//! triangles, coordinates far outside the plain range, boundaries, quads, every option;
//! and the rows computed one at a time (`Laplacian::fresh_rows`) give the bits that
//! `Laplacian::update` stores — with either cotangent kernel (per triangle, or from the
//! rows' one-rings), so the two kernels give the same bits too.

use beltrami_halfedge::geometry::VertexAreaKind;
use beltrami_halfedge::primitives;
use beltrami_halfedge::{DVec3, HalfedgeId, HalfedgeMesh, VertexId};
use beltrami_testkit::SplitMix64;
use beltrami_weights::{
    Cotangent, CotangentKernel, InverseDistance, Laplacian, LaplacianOptions, NegativeWeights,
    Normalization, Uniform, WeightContext, WeightScheme,
};

/// The same weights without a kernel: the generic path (a type of its own, so the
/// operator does not recognise it as a built-in).
struct Generic(&'static dyn WeightScheme);

impl WeightScheme for Generic {
    fn name(&self) -> &str {
        self.0.name()
    }
    fn weight(&self, ctx: &WeightContext<'_>, h: HalfedgeId) -> f64 {
        self.0.weight(ctx, h)
    }
    fn fill_weights(&self, ctx: &WeightContext<'_>, out: &mut [f64]) {
        self.0.fill_weights(ctx, out);
    }
}

fn assert_same(mesh: &HalfedgeMesh, x: &[DVec3], options: LaplacianOptions, label: &str) {
    for scheme in [
        &Uniform as &'static dyn WeightScheme,
        &InverseDistance,
        &Cotangent,
    ] {
        let fast = Laplacian::new(mesh, x, scheme, options);
        assert_fresh_rows(mesh, x, scheme, options, fast.as_ref().ok(), label);
        let slow = Laplacian::new(mesh, x, &Generic(scheme), options);
        let (fast, slow) = match (fast, slow) {
            (Ok(f), Ok(s)) => (f, s),
            (Err(f), Err(s)) => {
                assert_eq!(
                    format!("{f:?}"),
                    format!("{s:?}"),
                    "{label} {}",
                    scheme.name()
                );
                continue;
            }
            (f, s) => panic!("{label} {}: {f:?} vs {s:?}", scheme.name()),
        };
        assert_eq!(fast.stuck_rows(), slow.stuck_rows(), "{label}");
        for v in mesh.vertices() {
            let a: Vec<(VertexId, u64)> = fast.row(v).map(|(j, w)| (j, w.to_bits())).collect();
            let b: Vec<(VertexId, u64)> = slow.row(v).map(|(j, w)| (j, w.to_bits())).collect();
            assert_eq!(a, b, "{label} {} row {v}", scheme.name());
            assert_eq!(
                fast.weight_sum(v).to_bits(),
                slow.weight_sum(v).to_bits(),
                "{label} {v}"
            );
            assert_eq!(
                fast.scale(v).map(f64::to_bits),
                slow.scale(v).map(f64::to_bits)
            );
            let la = fast
                .laplacian_at(v, x)
                .map(|l| l.to_array().map(f64::to_bits));
            let lb = slow
                .laplacian_at(v, x)
                .map(|l| l.to_array().map(f64::to_bits));
            assert_eq!(la, lb, "{label} {v}");
        }
    }
}

/// [`Laplacian::fresh_rows`] at `x`, from an operator assembled at other positions,
/// gives every row's weights and scale with the bits of `assembled` (the operator
/// assembled at `x`, `None` when that failed): a row whose weights do not sum to a
/// finite value is refused (`None`), which `update` handles (with an error, or through
/// the generic path when only the sum overflows); and `FreshRows::block` over blocks
/// that split the rows anywhere gives the same bits.
fn assert_fresh_rows(
    mesh: &HalfedgeMesh,
    x: &[DVec3],
    scheme: &dyn WeightScheme,
    options: LaplacianOptions,
    assembled: Option<&Laplacian>,
    label: &str,
) {
    let elsewhere: Vec<DVec3> = x
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            let p = if p.is_finite() { p } else { DVec3::ONE };
            DVec3::new(0.5 * p.y + 1.0, p.x, p.z + 0.01 * i as f64)
        })
        .collect();
    let Ok(mut stale) = Laplacian::new(mesh, &elsewhere, scheme, options) else {
        return;
    };
    let fresh = stale.fresh_rows(mesh, x, scheme);
    let Some(assembled) = assembled else {
        if let Some(fresh) = fresh {
            let mut w = vec![0.0; 64];
            let refused = mesh
                .vertices()
                .any(|v| fresh.row(v.index(), x, &mut w).is_none());
            assert!(
                refused,
                "{label} {}: an error, but fresh rows",
                scheme.name()
            );
        }
        return;
    };
    let fresh = fresh.unwrap_or_else(|| panic!("{label} {}: no fresh rows", scheme.name()));
    // Blocks of rows (split anywhere) have the bits of the rows one at a time.
    let n = mesh.n_vertices();
    let offsets = fresh.offsets();
    let mut weights = vec![f64::NAN; offsets[n] as usize];
    let mut scales = vec![f64::NAN; n];
    let mut finite = true;
    for range in [0..n / 3, n / 3..n / 3, n / 3..n] {
        let slots = offsets[range.start] as usize..offsets[range.end] as usize;
        finite &= fresh.block(range.start, x, &mut weights[slots], &mut scales[range]);
    }
    let sums_finite = mesh.vertices().all(|v| assembled.weight_sum(v).is_finite());
    assert_eq!(finite, sums_finite, "{label} {}", scheme.name());
    if finite {
        let want: Vec<u64> = assembled
            .rows()
            .weights
            .iter()
            .map(|w| w.to_bits())
            .collect();
        let got: Vec<u64> = weights.iter().map(|w| w.to_bits()).collect();
        assert_eq!(got, want, "{label} {} blocks", scheme.name());
        let want: Vec<u64> = assembled
            .rows()
            .scales
            .iter()
            .map(|w| w.to_bits())
            .collect();
        let got: Vec<u64> = scales.iter().map(|w| w.to_bits()).collect();
        assert_eq!(got, want, "{label} {} block scales", scheme.name());
    }
    assert_eq!(fresh.offsets(), assembled.rows().offsets, "{label}");
    assert_eq!(fresh.neighbours(), assembled.rows().neighbours, "{label}");
    assert_eq!(
        fresh.unit_weights(),
        assembled.rows().unit_weights,
        "{label}"
    );
    for v in mesh.vertices() {
        let mut w = vec![f64::NAN; assembled.row(v).len()];
        let Some(scale) = fresh.row(v.index(), x, &mut w) else {
            assert!(!assembled.weight_sum(v).is_finite(), "{label} {v}: refused");
            continue;
        };
        let want: Vec<u64> = assembled.row(v).map(|(_, w)| w.to_bits()).collect();
        let got: Vec<u64> = w.iter().map(|w| w.to_bits()).collect();
        assert_eq!(got, want, "{label} {} row {v}", scheme.name());
        let want = assembled.scale(v).map_or(0, f64::to_bits);
        assert_eq!(scale.to_bits(), want, "{label} {} row {v}", scheme.name());
        let alone = fresh.scale(v.index(), x).map(f64::to_bits);
        assert_eq!(alone, Some(want), "{label} {v}");
    }
}

fn all_options() -> Vec<LaplacianOptions> {
    let mut out = Vec::new();
    for normalization in [
        Normalization::WeightSum,
        Normalization::Area(VertexAreaKind::MixedVoronoi),
        Normalization::Area(VertexAreaKind::Barycentric),
    ] {
        for negative in [
            NegativeWeights::Keep,
            NegativeWeights::Clamp,
            NegativeWeights::Abs,
        ] {
            for kernel in [CotangentKernel::PerTriangle, CotangentKernel::Ring] {
                out.push(
                    LaplacianOptions::new()
                        .normalization(normalization)
                        .negative(negative)
                        .cotangent_kernel(kernel),
                );
            }
        }
    }
    out
}

#[test]
fn kernels_match_the_generic_path() {
    let mut rng = SplitMix64::new(17);
    let mut cases: Vec<(String, HalfedgeMesh, Vec<DVec3>)> = Vec::new();
    // An irregular plane (negative cotangents, boundary).
    let g = primitives::grid(12, 9);
    let mesh = g.mesh().unwrap();
    let x: Vec<DVec3> = g
        .positions
        .iter()
        .map(|&p| {
            p + DVec3::new(
                rng.next_symmetric(),
                rng.next_symmetric(),
                0.1 * rng.next_symmetric(),
            ) * 0.45
        })
        .collect();
    cases.push(("grid".into(), mesh.clone(), x.clone()));
    // Degenerate and coincident triangles: collapse some vertices onto neighbours.
    let mut y = x.clone();
    y[14] = y[15];
    y[30] = (y[29] + y[31]) * 0.5;
    y[40] = y[41] + (y[41] - y[39]) * 1e-14;
    cases.push(("degenerate".into(), mesh.clone(), y));
    // Far outside the plain range, both ways.
    for s in [1e-170, 1e-300, 1e170, 1e300] {
        let z: Vec<DVec3> = x.iter().map(|&p| p * s).collect();
        cases.push((format!("scale {s:e}"), mesh.clone(), z));
    }
    // A noisy sphere (closed).
    let sphere = primitives::icosphere(3);
    let mesh = sphere.mesh().unwrap();
    let z: Vec<DVec3> = sphere
        .positions
        .iter()
        .map(|&p| p * (1.0 + 0.1 * rng.next_symmetric()))
        .collect();
    cases.push(("sphere".into(), mesh, z));
    // Tori and a cube (valence 3 vertices); 286 triangles are two chunks of the
    // per-triangle plan's refresh, the second not a whole number of blocks.
    for p in [
        primitives::torus(2.0, 0.7, 13, 7),
        primitives::torus(2.0, 0.7, 13, 11),
        primitives::cube(),
    ] {
        let mesh = p.mesh().unwrap();
        cases.push(("closed".into(), mesh, p.positions.clone()));
    }
    for (label, mesh, x) in &cases {
        for options in all_options() {
            assert_same(mesh, x, options, &format!("{label} {options:?}"));
        }
    }
}

#[test]
fn kernels_match_on_quads_and_isolated_vertices() {
    let p = primitives::cube_quads();
    let mesh = p.mesh().unwrap();
    let x: Vec<DVec3> = p.positions.iter().map(|&q| q * 1.3).collect();
    for options in all_options() {
        assert_same(&mesh, &x, options, "quads");
    }
    // A mesh with an isolated vertex and a mixed triangle/quad fan.
    let faces: [&[u32]; 3] = [&[0, 1, 2], &[0, 2, 3, 4], &[0, 4, 5]];
    let mesh = HalfedgeMesh::from_polygons(7, faces).unwrap();
    let x = vec![
        DVec3::ZERO,
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(1.0, 1.0, 0.1),
        DVec3::new(0.0, 1.2, 0.0),
        DVec3::new(-1.0, 1.0, -0.1),
        DVec3::new(-1.0, -0.3, 0.0),
        DVec3::new(5.0, 5.0, 5.0),
    ];
    for options in all_options() {
        assert_same(&mesh, &x, options, "mixed");
    }
}

#[test]
fn non_finite_positions_give_the_generic_error() {
    let g = primitives::grid(5, 5);
    let mesh = g.mesh().unwrap();
    for bad in [f64::NAN, f64::INFINITY] {
        let mut x = g.positions.clone();
        x[12].y = bad;
        for kernel in [CotangentKernel::PerTriangle, CotangentKernel::Ring] {
            let options = LaplacianOptions::default().cotangent_kernel(kernel);
            assert_same(&mesh, &x, options, "non-finite");
        }
    }
    // Finite weights whose row sum overflows.
    let mut x = g.positions.clone();
    x[12] = x[13] + DVec3::new(1e-320, 0.0, 0.0);
    for kernel in [CotangentKernel::PerTriangle, CotangentKernel::Ring] {
        let options = LaplacianOptions::default().cotangent_kernel(kernel);
        assert_same(&mesh, &x, options, "huge weights");
    }
}

#[test]
fn updates_reuse_the_operator() {
    let sphere = primitives::icosphere(3);
    let mesh = sphere.mesh().unwrap();
    let mut rng = SplitMix64::new(5);
    for scheme in [
        &Uniform as &'static dyn WeightScheme,
        &InverseDistance,
        &Cotangent,
    ] {
        let mut lap = Laplacian::new(
            &mesh,
            &sphere.positions,
            scheme,
            LaplacianOptions::default(),
        )
        .unwrap();
        for _ in 0..3 {
            let x: Vec<DVec3> = sphere
                .positions
                .iter()
                .map(|&p| p * (1.0 + 0.2 * rng.next_symmetric()))
                .collect();
            lap.update(&mesh, &x, scheme).unwrap();
            let fresh =
                Laplacian::new(&mesh, &x, &Generic(scheme), LaplacianOptions::default()).unwrap();
            for v in mesh.vertices() {
                let a: Vec<u64> = lap.row(v).map(|(_, w)| w.to_bits()).collect();
                let b: Vec<u64> = fresh.row(v).map(|(_, w)| w.to_bits()).collect();
                assert_eq!(a, b);
                assert_eq!(lap.scale(v), fresh.scale(v));
            }
        }
    }
}

/// The batched kernels work two triangles (or two row slots) at a time: meshes whose
/// triangle counts and valences leave every tail length, and batches that mix ordinary,
/// degenerate, obtuse and out-of-range (geometry fallback) triangles.
#[test]
fn kernels_match_on_mixed_lanes_and_tails() {
    let mut rng = SplitMix64::new(29);
    let mut cases: Vec<(String, HalfedgeMesh, Vec<DVec3>)> = Vec::new();
    // Fans of 1 to 7 triangles around vertex 0 (odd and even triangle counts, rows of
    // every length), open and closed.
    for n in 1..=7u32 {
        for closed in [false, true] {
            let faces: Vec<[u32; 3]> = (1..=n)
                .filter(|&k| closed || k < n)
                .map(|k| [0, k, k % n + 1])
                .collect();
            if faces.is_empty() || (closed && n < 3) {
                continue;
            }
            let mesh = HalfedgeMesh::from_polygons(n as usize + 1, &faces).unwrap();
            let x: Vec<DVec3> = (0..=n)
                .map(|k| {
                    let a = f64::from(k) * 0.9;
                    let r = if k == 0 {
                        0.0
                    } else {
                        1.0 + 0.3 * rng.next_symmetric()
                    };
                    DVec3::new(r * a.cos(), r * a.sin(), 0.2 * rng.next_symmetric())
                })
                .collect();
            cases.push((format!("fan {n} {closed}"), mesh, x));
        }
    }
    let g = primitives::grid(9, 7);
    let mesh = g.mesh().unwrap();
    let x: Vec<DVec3> = g
        .positions
        .iter()
        .map(|&p| {
            p + DVec3::new(
                rng.next_symmetric(),
                rng.next_symmetric(),
                0.2 * rng.next_symmetric(),
            ) * 0.4
        })
        .collect();
    // Every other vertex collapsed onto its right-hand neighbour: degenerate and
    // ordinary triangles side by side.
    let mut y = x.clone();
    for k in (0..y.len() - 1).step_by(2) {
        y[k] = y[k + 1];
    }
    cases.push(("alternating degenerate".into(), mesh.clone(), y));
    // Nearly flat triangles on both sides of the degeneracy threshold.
    let mut y = x.clone();
    for (k, p) in y.iter_mut().enumerate() {
        p.z = 0.0;
        if k % 3 == 0 {
            p.y *= 1e-12;
        }
    }
    cases.push(("nearly flat".into(), mesh.clone(), y));
    // A needle and triangles at the degeneracy threshold: in a closed fan of six,
    // triangle (0, 1, 2) gets its apex 2 at height h·|p1 − p0| over its longest edge
    // 0–1, so twice its area over that edge squared is h: 1e-9 (a needle, cotangents
    // near 1e9), and 1e-12 · (1 ± 1e-3) and 1e-12 (at `DEGENERACY_RATIO`).
    let faces: Vec<[u32; 3]> = (1..=6).map(|k| [0, k, k % 6 + 1]).collect();
    let fan = HalfedgeMesh::from_polygons(7, &faces).unwrap();
    for h in [1e-9, 1.001e-12, 1e-12, 0.999e-12] {
        let mut y: Vec<DVec3> = (0..=6u32)
            .map(|k| {
                let a = f64::from(k) * std::f64::consts::TAU / 6.0;
                let r = if k == 0 { 0.0 } else { 1.0 };
                DVec3::new(r * a.cos(), r * a.sin(), 0.1 * rng.next_symmetric())
            })
            .collect();
        let (p0, p1) = (y[0], y[1]);
        let n = (p1 - p0).cross(DVec3::Z).normalize();
        y[2] = p0 + (p1 - p0) * 0.6 + n * (h * (p1 - p0).length());
        cases.push((format!("fan with h = {h:e}"), fan.clone(), y));
    }
    // Part of the mesh far outside the plain range: plain and fallback triangles in
    // one batch.
    for s in [1e-250, 1e250] {
        let y: Vec<DVec3> = x
            .iter()
            .enumerate()
            .map(|(k, &p)| if k % 5 == 2 { p * s } else { p })
            .collect();
        cases.push((format!("partly scaled {s:e}"), mesh.clone(), y));
    }
    for (label, mesh, x) in &cases {
        for options in all_options() {
            assert_same(mesh, x, options, &format!("{label} {options:?}"));
        }
    }
}
