//! A batch of signed queries computes the vertex pseudo-normals only of the vertices its
//! closest points lie on; a single signed query computes all of them. Both must give the
//! same bits, on any number of threads.

use beltrami_halfedge::DVec3;
use beltrami_halfedge::primitives;
use beltrami_metrics::distance::{Feature, SurfaceIndex};
use beltrami_testkit::SplitMix64;

/// Points off an icosphere: its vertices pushed along their position by ±5 % (whose
/// closest points are vertices) and random points in a shell around it (mostly faces
/// and edges), in a fixed order.
fn points(sphere: &[DVec3], rng: &mut SplitMix64) -> Vec<DVec3> {
    let mut out = Vec::new();
    for (i, &p) in sphere.iter().enumerate() {
        let scale = if i % 2 == 0 { 1.05 } else { 0.95 };
        out.push(p * scale);
        let random = DVec3::new(
            rng.next_unit() - 0.5,
            rng.next_unit() - 0.5,
            rng.next_unit() - 0.5,
        );
        out.push(random.normalize_or_zero() * (0.8 + 0.4 * rng.next_unit()));
    }
    out
}

fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
        .install(f)
}

#[test]
fn batch_signs_are_those_of_single_queries() {
    let sphere = primitives::icosphere(5);
    let mesh = sphere.mesh().expect("valid");
    let mut rng = SplitMix64::new(7);
    let points = points(&sphere.positions, &mut rng);

    // The batch first, on a fresh index (vertex pseudo-normals computed for the
    // vertices it needs only), on one and on three threads.
    let batches: Vec<Vec<f64>> = [1, 3]
        .into_iter()
        .map(|threads| {
            let index = SurfaceIndex::new(&mesh, &sphere.positions).expect("an index");
            on_threads(threads, || index.signed_distances(&points).expect("finite"))
        })
        .collect();
    assert_eq!(
        batches[0].iter().map(|d| d.to_bits()).collect::<Vec<_>>(),
        batches[1].iter().map(|d| d.to_bits()).collect::<Vec<_>>()
    );

    // Single queries: every vertex pseudo-normal computed.
    let index = SurfaceIndex::new(&mesh, &sphere.positions).expect("an index");
    let closest = index.closest_points(&points).expect("finite");
    let vertices = closest
        .iter()
        .filter(|c| matches!(c.feature, Feature::Vertex(_)))
        .count();
    assert!(vertices > points.len() / 4, "{vertices} vertex features");
    for (p, &batch) in points.iter().zip(&batches[0]) {
        let single = index.signed_distance(*p).expect("finite");
        assert_eq!(single.to_bits(), batch.to_bits(), "{p:?}");
    }
    // And a batch after them (all pseudo-normals at hand) gives the same bits again.
    let again = index.signed_distances(&points).expect("finite");
    assert_eq!(
        again.iter().map(|d| d.to_bits()).collect::<Vec<_>>(),
        batches[0].iter().map(|d| d.to_bits()).collect::<Vec<_>>()
    );
    // Inside (0.95) and outside (1.05) of the sphere, by the sign.
    for (i, d) in batches[0].iter().enumerate().step_by(2) {
        assert_eq!(*d < 0.0, (i / 2) % 2 == 1, "point {i}: {d}");
    }
}
