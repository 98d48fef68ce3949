//! What the operator holds: `heap_bytes` follows what is stored; `fresh_rows` releases
//! the stored weights and `update` stores them again; uniform weights are never stored
//! (ones are made when asked for); halfedge ids are read from the mesh.

use beltrami_halfedge::primitives;
use beltrami_halfedge::{DVec3, HalfedgeMesh, VertexId};
use beltrami_testkit::SplitMix64;
use beltrami_weights::{
    Cotangent, CotangentKernel, InverseDistance, Laplacian, LaplacianOptions, Uniform, WeightScheme,
};

fn noisy_sphere() -> (HalfedgeMesh, Vec<DVec3>) {
    let sphere = primitives::icosphere(3);
    let mut rng = SplitMix64::new(3);
    let x = sphere
        .positions
        .iter()
        .map(|&p| p * (1.0 + 0.1 * rng.next_symmetric()))
        .collect();
    (sphere.mesh().unwrap(), x)
}

/// The bytes of the rows alone: offsets and neighbours (`u32`), sums and scales (`f64`).
fn row_bytes(mesh: &HalfedgeMesh) -> usize {
    let (n, h) = (mesh.n_vertices(), mesh.n_halfedges());
    4 * (n + 1) + 4 * h + 16 * n
}

#[test]
fn heap_bytes_follow_what_is_stored() {
    let (mesh, x) = noisy_sphere();
    let h = mesh.n_halfedges();
    let rows = row_bytes(&mesh);
    let weights = 8 * h;
    let bits = 8 * h.div_ceil(64);
    let options = LaplacianOptions::default();
    let ring = options.cotangent_kernel(CotangentKernel::Ring);

    // Cotangent, per-triangle kernel (the default): the rows, the weights and the
    // plan (each triangle's vertices and three cotangents, each slot's two indices).
    let f = mesh.n_faces();
    let plan = 12 * f + 8 * (3 * f + 1) + 8 * h;
    let mut lap = Laplacian::new(&mesh, &x, &Cotangent, options).unwrap();
    assert_eq!(lap.heap_bytes(), rows + weights + plan);
    lap.fresh_rows(&mesh, &x, &Cotangent).unwrap();
    assert_eq!(lap.heap_bytes(), rows + plan);

    // Cotangent, ring kernel: the rows, the weights and one bit per slot; nothing per
    // triangle.
    let mut lap = Laplacian::new(&mesh, &x, &Cotangent, ring).unwrap();
    assert_eq!(lap.heap_bytes(), rows + weights + bits);
    assert!(lap.weights_stored());
    // Computed in the sweep: the stored weights are released...
    let fresh = lap.fresh_rows(&mesh, &x, &Cotangent).unwrap();
    assert!(fresh.offsets().len() == mesh.n_vertices() + 1);
    assert!(!lap.weights_stored());
    assert_eq!(lap.heap_bytes(), rows + bits);
    // ... and stored again, with the same bits, by an update.
    lap.update(&mesh, &x, &Cotangent).unwrap();
    assert!(lap.weights_stored());
    assert_eq!(lap.heap_bytes(), rows + weights + bits);
    let again = Laplacian::new(&mesh, &x, &Cotangent, ring).unwrap();
    let bits_of =
        |l: &Laplacian| -> Vec<u64> { l.rows().weights.iter().map(|w| w.to_bits()).collect() };
    assert_eq!(bits_of(&lap), bits_of(&again));

    // Inverse distance: no triangle bits.
    let mut lap = Laplacian::new(&mesh, &x, &InverseDistance, options).unwrap();
    assert_eq!(lap.heap_bytes(), rows + weights);
    lap.fresh_rows(&mesh, &x, &InverseDistance).unwrap();
    assert_eq!(lap.heap_bytes(), rows);

    // Uniform: no weights until they are asked for, then ones.
    let mut lap = Laplacian::new(&mesh, &x, &Uniform, ring).unwrap();
    assert_eq!(lap.heap_bytes(), rows);
    assert!(lap.weights_stored());
    let rows_view = lap.rows();
    assert!(rows_view.unit_weights);
    assert_eq!(rows_view.weights.len(), h);
    assert!(rows_view.weights.iter().all(|&w| w == 1.0));
    assert_eq!(lap.heap_bytes(), rows + weights);
    // Still readable after fresh rows (made again on demand).
    lap.fresh_rows(&mesh, &x, &Uniform).unwrap();
    assert!(lap.weights_stored());
    let v = VertexId::new(0);
    let valence = mesh.halfedges_around_vertex(v).count() as f64;
    assert_eq!(lap.row(v).map(|(_, w)| w).sum::<f64>(), valence);

    // A scheme changed by an update: cotangent after uniform stores weights.
    lap.update(&mesh, &x, &Cotangent).unwrap();
    assert_eq!(lap.heap_bytes(), rows + weights + bits);
    lap.update(&mesh, &x, &Uniform).unwrap();
    assert_eq!(lap.heap_bytes(), rows + bits);
    assert!(lap.rows().weights.iter().all(|&w| w == 1.0));
}

#[test]
#[should_panic(expected = "released by `fresh_rows`")]
fn released_weights_are_not_read() {
    let (mesh, x) = noisy_sphere();
    let ring = LaplacianOptions::default().cotangent_kernel(CotangentKernel::Ring);
    let mut lap = Laplacian::new(&mesh, &x, &Cotangent, ring).unwrap();
    lap.fresh_rows(&mesh, &x, &Cotangent).unwrap();
    let _ = lap.rows();
}

/// A plug-in scheme (not recognised as built-in) reads its slots' halfedges from the
/// mesh: its rows are the halfedge weights in circulation order.
#[test]
fn row_halfedges_come_from_the_mesh() {
    struct Directed;
    impl WeightScheme for Directed {
        fn name(&self) -> &str {
            "directed"
        }
        fn weight(
            &self,
            _: &beltrami_weights::WeightContext<'_>,
            h: beltrami_halfedge::HalfedgeId,
        ) -> f64 {
            1.0 + f64::from(h.raw())
        }
    }
    let grid = primitives::grid(5, 4);
    let mesh = grid.mesh().unwrap();
    let lap = Laplacian::new(
        &mesh,
        &grid.positions,
        &Directed,
        LaplacianOptions::default(),
    )
    .unwrap();
    assert!(lap.heap_bytes() >= row_bytes(&mesh) + 16 * mesh.n_halfedges());
    for v in mesh.vertices() {
        let hs: Vec<_> = lap.row_halfedges_in(&mesh, v).collect();
        let ring: Vec<_> = mesh.halfedges_around_vertex(v).collect();
        assert_eq!(hs, ring);
        let row: Vec<(VertexId, f64)> = lap.row(v).collect();
        let want: Vec<(VertexId, f64)> = hs
            .iter()
            .map(|&h| (mesh.to_vertex(h), 1.0 + f64::from(h.raw())))
            .collect();
        assert_eq!(row, want, "{v}");
    }
}

#[test]
#[should_panic(expected = "row_halfedges_in")]
fn row_halfedges_are_not_kept_for_a_simple_mesh() {
    let grid = primitives::grid(3, 3);
    let mesh = grid.mesh().unwrap();
    let lap = Laplacian::new(
        &mesh,
        &grid.positions,
        &Cotangent,
        LaplacianOptions::default(),
    )
    .unwrap();
    let _ = lap.row_halfedges(VertexId::new(4)).count();
}

/// `new_without_weights` computes and checks what `new` does (sums, scales, stuck rows,
/// errors) and keeps no weight array; its fresh rows and a later update are `new`'s.
#[test]
fn an_operator_without_weights_is_new_without_the_array() {
    let (mesh, x) = noisy_sphere();
    let h = mesh.n_halfedges();
    let ring = LaplacianOptions::default().cotangent_kernel(CotangentKernel::Ring);
    for (scheme, options, extra) in [
        (&Uniform as &dyn WeightScheme, ring, 0),
        (&InverseDistance, ring, 0),
        (&Cotangent, ring, 8 * h.div_ceil(64)),
    ] {
        let full = Laplacian::new(&mesh, &x, scheme, options).unwrap();
        let mut lean = Laplacian::new_without_weights(&mesh, &x, scheme, options).unwrap();
        assert_eq!(
            lean.heap_bytes(),
            row_bytes(&mesh) + extra,
            "{}",
            scheme.name()
        );
        assert_eq!(lean.weights_stored(), scheme.name() == "uniform");
        assert_eq!(lean.stuck_rows(), full.stuck_rows());
        for v in mesh.vertices() {
            assert_eq!(lean.weight_sum(v).to_bits(), full.weight_sum(v).to_bits());
            assert_eq!(
                lean.scale(v).map(f64::to_bits),
                full.scale(v).map(f64::to_bits)
            );
        }
        let fresh = lean.fresh_rows(&mesh, &x, scheme).unwrap();
        let offsets = fresh.offsets().to_vec();
        let mut w = vec![0.0; offsets[mesh.n_vertices()] as usize];
        let mut s = vec![0.0; mesh.n_vertices()];
        assert!(fresh.block(0, &x, &mut w, &mut s));
        let want: Vec<u64> = full.rows().weights.iter().map(|w| w.to_bits()).collect();
        let got: Vec<u64> = w.iter().map(|w| w.to_bits()).collect();
        assert_eq!(got, want, "{}", scheme.name());
        lean.update(&mesh, &x, scheme).unwrap();
        let stored: Vec<u64> = lean.rows().weights.iter().map(|w| w.to_bits()).collect();
        assert_eq!(stored, want);
    }
    // The same errors as `new`.
    let mut bad = x.clone();
    bad[3].x = f64::NAN;
    let lean = Laplacian::new_without_weights(&mesh, &bad, &InverseDistance, ring).map(|_| ());
    let full = Laplacian::new(&mesh, &bad, &InverseDistance, ring).map(|_| ());
    assert!(lean.is_err());
    assert_eq!(format!("{lean:?}"), format!("{full:?}"));
}
