//! Normal deviation: identity, rigid rotations, flips, degenerate faces, weights, errors.

use beltrami_halfedge::primitives;
use beltrami_halfedge::{DVec3, HalfedgeMesh};
use beltrami_metrics::MetricsError;
use beltrami_metrics::normals::{face_angles_deg, normal_deviation};

/// Rodrigues' rotation of `p` about the unit `axis` by `angle` radians.
fn rotate(p: DVec3, axis: DVec3, angle: f64) -> DVec3 {
    let (s, c) = angle.sin_cos();
    p * c + axis.cross(p) * s + axis * axis.dot(p) * (1.0 - c)
}

#[test]
fn identical_meshes_deviate_by_nothing() {
    let sphere = primitives::icosphere(3);
    let mesh = sphere.mesh().unwrap();
    let d = normal_deviation(&mesh, &sphere.positions, &mesh, &sphere.positions).unwrap();
    assert_eq!(
        (d.mean_deg, d.rms_deg, d.max_deg, d.area_weighted_error),
        (0.0, 0.0, 0.0, 0.0)
    );
    assert_eq!((d.compared, d.skipped), (1280, 0));
}

#[test]
fn a_patch_rotated_about_an_axis_in_its_plane_turns_every_normal_by_the_angle() {
    let grid = primitives::grid(6, 4);
    let mesh = grid.mesh().unwrap();
    let axis = DVec3::new(3.0, -4.0, 0.0) / 5.0; // in the grid's plane
    for degrees in [0.001, 1.0, 37.0, 90.0, 179.0] {
        let angle = f64::to_radians(degrees);
        // Rotate and move far away: neither changes the angles.
        let moved: Vec<DVec3> = grid
            .positions
            .iter()
            .map(|&p| rotate(p, axis, angle) + DVec3::new(1e3, -5e2, 2e2))
            .collect();
        let d = normal_deviation(&mesh, &moved, &mesh, &grid.positions).unwrap();
        let tolerance = 1e-9;
        assert!((d.mean_deg - degrees).abs() < tolerance, "{degrees}: {d:?}");
        assert!((d.rms_deg - degrees).abs() < tolerance, "{degrees}: {d:?}");
        assert!((d.max_deg - degrees).abs() < tolerance, "{degrees}: {d:?}");
        // |n − n'| = 2 sin(α/2) for every face.
        let chord = 2.0 * (angle / 2.0).sin();
        assert!(
            (d.area_weighted_error - chord).abs() < 1e-12,
            "{degrees}: {d:?}"
        );
        for theta in face_angles_deg(&mesh, &moved, &mesh, &grid.positions).unwrap() {
            assert!((theta.unwrap() - degrees).abs() < tolerance);
        }
    }
}

#[test]
fn a_rotated_sphere_turns_each_normal_by_the_angle_of_its_projection() {
    // Rotating by α about an axis a turns a unit normal n by θ with
    // sin(θ/2) = sin(α/2) |n × a| (the chord |n − Rn| = 2 sin(α/2) |n × a|).
    let sphere = primitives::icosphere(3);
    let mesh = sphere.mesh().unwrap();
    let axis = DVec3::new(1.0, -2.0, 0.5).normalize();
    let angle = 0.4f64;
    let moved: Vec<DVec3> = sphere
        .positions
        .iter()
        .map(|&p| rotate(p, axis, angle))
        .collect();
    let angles = face_angles_deg(&mesh, &moved, &mesh, &sphere.positions).unwrap();
    let mut sum = 0.0;
    for (f, theta) in mesh.faces().zip(&angles) {
        let [a, b, c] = mesh
            .triangle_vertices(f)
            .map(|v| sphere.positions[v.index()]);
        let n = (b - a).cross(c - a).normalize();
        let expected = 2.0 * ((angle / 2.0).sin() * n.cross(axis).length()).asin();
        let theta = theta.unwrap();
        assert!((theta - expected.to_degrees()).abs() < 1e-11, "{f:?}");
        sum += theta;
    }
    let d = normal_deviation(&mesh, &moved, &mesh, &sphere.positions).unwrap();
    assert!((d.mean_deg - sum / 1280.0).abs() < 1e-12);
    assert!(d.max_deg <= angle.to_degrees() + 1e-12);
}

#[test]
fn a_mirrored_patch_has_its_normals_flipped() {
    // Mirroring a planar patch in x reverses its orientation: the normals go from +z to -z.
    let grid = primitives::grid(5, 3);
    let mesh = grid.mesh().unwrap();
    let mirrored: Vec<DVec3> = grid
        .positions
        .iter()
        .map(|p| DVec3::new(-p.x, p.y, p.z))
        .collect();
    let d = normal_deviation(&mesh, &mirrored, &mesh, &grid.positions).unwrap();
    assert_eq!((d.mean_deg, d.rms_deg, d.max_deg), (180.0, 180.0, 180.0));
    assert_eq!(d.area_weighted_error, 2.0);
}

#[test]
fn area_weights_come_from_the_first_mesh() {
    // Two faces of a 1 × 1 square; fold one of them up by lifting the corner it alone owns.
    // grid(1, 1): faces [0, 1, 3] and [0, 3, 2]; vertex 2 = (0, 1) belongs to face 1 only.
    let grid = primitives::grid(1, 1);
    let mesh = grid.mesh().unwrap();
    let mut folded = grid.positions.clone();
    folded[2].z = 1.0;
    let d = normal_deviation(&mesh, &folded, &mesh, &grid.positions).unwrap();
    // Face 1 of the folded mesh: (0,0,0), (1,1,0), (0,1,1). Its normal and area by hand.
    let (a, b, c) = (
        DVec3::ZERO,
        DVec3::new(1.0, 1.0, 0.0),
        DVec3::new(0.0, 1.0, 1.0),
    );
    let cross = (b - a).cross(c - a);
    let n = cross.normalize();
    let area = 0.5 * cross.length(); // √3 / 2
    let theta = n.dot(DVec3::Z).acos().to_degrees(); // acos(1/√3) = 54.7356…°
    assert!((theta - 54.735_610_317_245_35).abs() < 1e-12);
    assert!((d.mean_deg - theta / 2.0).abs() < 1e-12);
    assert!((d.rms_deg - theta / 2f64.sqrt()).abs() < 1e-12);
    assert!((d.max_deg - theta).abs() < 1e-12);
    let expected = (area * (n - DVec3::Z).length_squared() / (0.5 + area)).sqrt();
    assert!((d.area_weighted_error - expected).abs() < 1e-15);
    // With the roles exchanged the reference's areas weigh: both faces have area 1/2.
    let swapped = normal_deviation(&mesh, &grid.positions, &mesh, &folded).unwrap();
    let expected = (0.5 * (n - DVec3::Z).length_squared() / 1.0).sqrt();
    assert!((swapped.area_weighted_error - expected).abs() < 1e-15);
}

#[test]
fn degenerate_faces_are_skipped_and_counted() {
    let grid = primitives::grid(2, 1); // 4 faces
    let mesh = grid.mesh().unwrap();
    let mut collapsed = grid.positions.clone();
    // Vertex 4 = (1, 1) onto vertex 1 = (1, 0): the two faces with the diagonal 0–4 or 1–5
    // that contain both become segments.
    collapsed[4] = collapsed[1];
    let angles = face_angles_deg(&mesh, &collapsed, &mesh, &grid.positions).unwrap();
    let skipped = angles.iter().filter(|a| a.is_none()).count();
    assert!(skipped >= 1);
    let d = normal_deviation(&mesh, &collapsed, &mesh, &grid.positions).unwrap();
    assert_eq!(d.skipped, skipped);
    assert_eq!(d.compared + d.skipped, 4);
    assert!(d.mean_deg.is_finite() && d.area_weighted_error.is_finite());
    // Every face degenerate: nothing to compare.
    let point = vec![DVec3::ZERO; grid.positions.len()];
    assert_eq!(
        normal_deviation(&mesh, &point, &mesh, &grid.positions).unwrap_err(),
        MetricsError::Empty {
            what: "set of non-degenerate faces"
        }
    );
}

#[test]
fn meshes_must_share_their_topology() {
    let a = primitives::icosphere(1);
    let b = primitives::icosphere(2);
    let err = normal_deviation(
        &a.mesh().unwrap(),
        &a.positions,
        &b.mesh().unwrap(),
        &b.positions,
    )
    .unwrap_err();
    assert_eq!(
        err.to_string(),
        "the meshes do not share their topology: 42 vertices vs 162"
    );
    // Same vertex count, a face listed in another order.
    let t1 = HalfedgeMesh::from_polygons(4, [[0u32, 1, 2], [0, 2, 3]]).unwrap();
    let t2 = HalfedgeMesh::from_polygons(4, [[0u32, 1, 2], [2, 3, 0]]).unwrap();
    let p = [DVec3::ZERO, DVec3::X, DVec3::ONE, DVec3::Y];
    assert!(matches!(
        normal_deviation(&t1, &p, &t2, &p).unwrap_err(),
        MetricsError::TopologyMismatch { .. }
    ));
    let mut bad = p;
    bad[2].x = f64::NAN;
    assert_eq!(
        normal_deviation(&t1, &p, &t1, &bad).unwrap_err(),
        MetricsError::NonFinite {
            what: "reference position",
            index: 2
        }
    );
}
