//! Boundary and edge distortion: ring indices against the lattice distance worked out by
//! hand, boundary displacement of known moves, dihedral angles of hinges and the cube.

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::primitives::{self, Primitive};
use beltrami_halfedge::{DVec3, HalfedgeMesh};
use beltrami_metrics::MetricsError;
use beltrami_metrics::distortion::{
    boundary_displacement, boundary_rings, dihedral_angle, dihedral_angles, error_by_ring,
    feature_edge_distortion,
};
use glam::DQuat;

fn build(p: &Primitive) -> HalfedgeMesh {
    let mesh = p.mesh().expect("primitive builds");
    mesh.check_integrity().expect("valid mesh");
    mesh
}

/// Graph distance on the grid's triangulation between vertices `Δ = (dx, dy)` apart.
/// The edges are the unit steps (±1, 0), (0, ±1) and the diagonals ±(1, 1): when `dx`
/// and `dy` have the same sign, `min(|dx|, |dy|)` diagonal steps and the rest straight
/// give `max(|dx|, |dy|)`; with opposite signs a diagonal never helps, `|dx| + |dy|`.
fn lattice_distance(dx: i64, dy: i64) -> i64 {
    if dx * dy >= 0 {
        dx.abs().max(dy.abs())
    } else {
        dx.abs() + dy.abs()
    }
}

#[test]
fn rings_of_a_grid_are_the_distance_to_the_border() {
    // Each step changes i (or j) by at most 1, so the border lines i = 0, i = nx, j = 0,
    // j = ny are min(i, nx − i, j, ny − j) steps away, and that many straight steps reach
    // them.
    let (nx, ny) = (9u32, 6u32);
    let grid = primitives::grid(nx, ny);
    let mesh = build(&grid);
    let rings = boundary_rings(&mesh);
    for (v, p) in grid.positions.iter().enumerate() {
        let (i, j) = (p.x as u32, p.y as u32);
        let expected = i.min(nx - i).min(j).min(ny - j);
        assert_eq!(rings.as_slice()[v], Some(expected), "vertex ({i}, {j})");
    }
}

#[test]
fn rings_around_a_hole_follow_the_lattice_distance() {
    // A 9 × 7 grid without the two triangles of cell (4, 3): its four corners become a
    // second boundary loop. r(v) = min(distance to the border, lattice distance to a
    // corner of the hole).
    let (nx, ny) = (9u32, 7u32);
    let grid = primitives::grid(nx, ny);
    let hole = 2 * (3 * nx + 4) as usize;
    let faces: Vec<&[u32]> = grid
        .faces
        .iter()
        .enumerate()
        .filter(|&(f, _)| f != hole && f != hole + 1)
        .map(|(_, face)| face)
        .collect();
    let mesh = HalfedgeMesh::from_polygons(grid.positions.len(), &faces).expect("valid");
    assert_eq!(mesh.boundary_loops().count(), 2);
    let rings = boundary_rings(&mesh);
    let corners = [(4i64, 3i64), (5, 3), (4, 4), (5, 4)];
    for (v, p) in grid.positions.iter().enumerate() {
        let (i, j) = (p.x as i64, p.y as i64);
        let border = i.min(nx as i64 - i).min(j).min(ny as i64 - j);
        let to_hole = corners
            .iter()
            .map(|&(ci, cj)| lattice_distance(ci - i, cj - j))
            .min()
            .unwrap_or(i64::MAX);
        let expected = border.min(to_hole) as u32;
        assert_eq!(rings.as_slice()[v], Some(expected), "vertex ({i}, {j})");
    }
}

#[test]
fn closed_meshes_and_isolated_vertices_have_no_ring() {
    let sphere = primitives::icosphere(1);
    let mesh = build(&sphere);
    assert!(boundary_rings(&mesh).as_slice().iter().all(Option::is_none));
    let profile = error_by_ring(&mesh, &vec![1.0; mesh.n_vertices()]).expect("valid");
    assert!(profile.rings.is_empty());
    assert_eq!(profile.unreached, mesh.n_vertices());

    // A triangle with an isolated fourth vertex.
    let mesh = HalfedgeMesh::from_polygons(4, [[0u32, 1, 2]]).expect("valid");
    let rings = boundary_rings(&mesh);
    assert_eq!(rings.as_slice(), &[Some(0), Some(0), Some(0), None]);
}

#[test]
fn error_by_ring_groups_the_error_by_ring() {
    let (nx, ny) = (8u32, 6u32);
    let grid = primitives::grid(nx, ny);
    let mesh = build(&grid);
    // A signed error varying along each ring: e = (−1)^i · (1 + j/10).
    let error: Vec<f64> = grid
        .positions
        .iter()
        .map(|p| if (p.x as u32).is_multiple_of(2) { 1.0 } else { -1.0 } * (1.0 + p.y / 10.0))
        .collect();
    let profile = error_by_ring(&mesh, &error).expect("valid");
    assert_eq!(profile.unreached, 0);
    // Rings 0..=3 (the centre rows j = 3 are 3 from the border).
    assert_eq!(profile.rings.len(), 4);
    for (r, ring) in profile.rings.iter().enumerate() {
        let members: Vec<f64> = grid
            .positions
            .iter()
            .zip(&error)
            .filter(|(p, _)| {
                let (i, j) = (p.x as u32, p.y as u32);
                i.min(nx - i).min(j).min(ny - j) == r as u32
            })
            .map(|(_, &e)| e)
            .collect();
        let n = members.len() as f64;
        assert_eq!(ring.ring, r as u32);
        assert_eq!(ring.count, members.len());
        let mean = members.iter().sum::<f64>() / n;
        let rms = (members.iter().map(|e| e * e).sum::<f64>() / n).sqrt();
        let max = members.iter().fold(0.0f64, |m, e| m.max(e.abs()));
        assert!((ring.mean - mean).abs() < 1e-14, "ring {r}");
        assert!((ring.rms - rms).abs() < 1e-14, "ring {r}");
        assert_eq!(ring.max, max, "ring {r}");
    }
    // The border holds 2(nx + ny) vertices; the rings partition the grid.
    assert_eq!(profile.rings[0].count, 2 * (nx + ny) as usize);
    let total: usize = profile.rings.iter().map(|r| r.count).sum();
    assert_eq!(total, mesh.n_vertices());
}

#[test]
fn error_by_ring_rejects_bad_fields() {
    let grid = primitives::grid(2, 2);
    let mesh = build(&grid);
    assert_eq!(
        error_by_ring(&mesh, &[0.0; 4]),
        Err(MetricsError::FieldLength {
            what: "per-vertex error",
            got: 4,
            expected: 9
        })
    );
    let mut error = vec![0.0; 9];
    error[5] = f64::NAN;
    assert_eq!(
        error_by_ring(&mesh, &error),
        Err(MetricsError::NonFinite {
            what: "per-vertex error",
            index: 5
        })
    );
}

/// The unit inward direction at a border vertex of the axis-aligned grid `[0, nx] × [0,
/// ny]`: ±x or ±y along a side, the normalised sum of both at a corner.
fn inward(i: u32, j: u32, nx: u32, ny: u32) -> DVec3 {
    let x = if i == 0 {
        1.0
    } else if i == nx {
        -1.0
    } else {
        0.0
    };
    let y = if j == 0 {
        1.0
    } else if j == ny {
        -1.0
    } else {
        0.0
    };
    DVec3::new(x, y, 0.0).normalize()
}

#[test]
fn boundary_moved_by_a_known_vector_splits_exactly() {
    let (nx, ny) = (6u32, 4u32);
    let grid = primitives::grid(nx, ny);
    let mesh = build(&grid);
    let shift = DVec3::new(0.3, -0.2, 0.5);
    // Boundary vertices move by `shift`; interior ones by something large, which must not
    // count.
    let moved: Vec<DVec3> = grid
        .positions
        .iter()
        .map(|&p| {
            let (i, j) = (p.x as u32, p.y as u32);
            let border = i == 0 || j == 0 || i == nx || j == ny;
            p + if border { shift } else { DVec3::splat(100.0) }
        })
        .collect();
    let original = Geometry::new(&mesh, &grid.positions).expect("positions");
    let smoothed = Geometry::new(&mesh, &moved).expect("positions");
    let d = boundary_displacement(&original, &smoothed).expect("same topology");

    // The flat grid's normal is +z: normal part 0.5, tangential part |(0.3, −0.2)|.
    assert_eq!(d.count, 2 * (nx + ny) as usize);
    let tangential = 0.13f64.sqrt();
    let total = 0.38f64.sqrt();
    for (got, want) in [
        (d.mean, total),
        (d.rms, total),
        (d.max, total),
        (d.mean_normal, 0.5),
        (d.max_normal, 0.5),
        (d.mean_signed_normal, 0.5),
        (d.mean_tangential, tangential),
        (d.max_tangential, tangential),
    ] {
        // Positions up to 6 carry the shift with a rounding of about 1e-15.
        assert!((got - want).abs() < 1e-14, "{got} vs {want}");
    }
    // The inward part, vertex by vertex from the inward directions of the rectangle.
    let inward_mean = grid
        .positions
        .iter()
        .filter(|p| p.x == 0.0 || p.y == 0.0 || p.x == f64::from(nx) || p.y == f64::from(ny))
        .map(|p| shift.dot(inward(p.x as u32, p.y as u32, nx, ny)))
        .sum::<f64>()
        / d.count as f64;
    assert!((d.mean_inward - inward_mean).abs() < 1e-14);
}

#[test]
fn displacement_split_follows_a_tilted_surface() {
    // The same grid rotated in space: normal part a along the rotated normal, tangential
    // part b along a rotated in-plane direction, whatever the rotation.
    let grid = primitives::grid(5, 3);
    let mesh = build(&grid);
    let rotation = DQuat::from_euler(glam::EulerRot::XYZ, 0.4, -0.9, 1.3);
    let original: Vec<DVec3> = grid.positions.iter().map(|&p| rotation * p).collect();
    let normal = rotation * DVec3::Z;
    let along = rotation * DVec3::new(0.6, 0.8, 0.0);
    let (a, b) = (-0.25, 0.75);
    let moved: Vec<DVec3> = original
        .iter()
        .map(|&p| p + a * normal + b * along)
        .collect();
    let d = boundary_displacement(
        &Geometry::new(&mesh, &original).expect("positions"),
        &Geometry::new(&mesh, &moved).expect("positions"),
    )
    .expect("same topology");
    assert_eq!(d.count, 16);
    assert!((d.mean_signed_normal - a).abs() < 1e-14);
    assert!((d.max_normal - 0.25).abs() < 1e-14);
    assert!((d.mean_tangential - b).abs() < 1e-14);
    assert!((d.max - (a * a + b * b).sqrt()).abs() < 1e-14);
}

#[test]
fn closed_mesh_has_no_boundary_displacement() {
    let cube = primitives::cube();
    let mesh = build(&cube);
    let moved: Vec<DVec3> = cube.positions.iter().map(|&p| 2.0 * p).collect();
    let d = boundary_displacement(
        &Geometry::new(&mesh, &cube.positions).expect("positions"),
        &Geometry::new(&mesh, &moved).expect("positions"),
    )
    .expect("same topology");
    assert_eq!(d.count, 0);
    assert_eq!((d.mean, d.max, d.mean_inward), (0.0, 0.0, 0.0));
}

#[test]
fn mismatched_topologies_are_named() {
    let a = primitives::grid(2, 2);
    let b = primitives::grid(2, 3);
    let (mesh_a, mesh_b) = (build(&a), build(&b));
    let err = boundary_displacement(
        &Geometry::new(&mesh_a, &a.positions).expect("positions"),
        &Geometry::new(&mesh_b, &b.positions).expect("positions"),
    )
    .unwrap_err();
    assert_eq!(
        err,
        MetricsError::TopologyMismatch {
            detail: "9 vertices vs 12".into()
        }
    );

    // Same counts, one face listed differently.
    let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ONE];
    let m1 = HalfedgeMesh::from_polygons(4, [[0u32, 1, 2], [1, 3, 2]]).expect("valid");
    let m2 = HalfedgeMesh::from_polygons(4, [[0u32, 1, 2], [2, 1, 3]]).expect("valid");
    let err = feature_edge_distortion(
        &Geometry::new(&m1, &positions).expect("positions"),
        &Geometry::new(&m2, &positions).expect("positions"),
        30.0,
    )
    .unwrap_err();
    assert_eq!(
        err.to_string(),
        "the meshes do not share their topology: face 1 has vertices [1, 3, 2] vs [2, 1, 3]"
    );

    // Non-finite positions are named too.
    let mut bad = a.positions.clone();
    bad[4].y = f64::INFINITY;
    let err = boundary_displacement(
        &Geometry::new(&mesh_a, &a.positions).expect("positions"),
        &Geometry::new(&mesh_a, &bad).expect("positions"),
    )
    .unwrap_err();
    assert_eq!(
        err,
        MetricsError::NonFinite {
            what: "position",
            index: 4
        }
    );
}

/// Two triangles hinged along the x-axis: the first in the xy-plane, the second rotated
/// about the x-axis by `fold` radians, so their normals are `fold` apart.
fn hinge(fold: f64) -> (HalfedgeMesh, Vec<DVec3>) {
    let positions = vec![
        DVec3::ZERO,
        DVec3::X,
        DVec3::new(0.5, 1.0, 0.0),
        DVec3::new(0.5, -fold.cos(), fold.sin()),
    ];
    let mesh = HalfedgeMesh::from_polygons(4, [[0u32, 1, 2], [1, 0, 3]]).expect("valid");
    (mesh, positions)
}

#[test]
fn dihedral_angle_of_a_hinge_is_its_fold() {
    for degrees in [0.0, 1e-6, 10.0, 45.0, 90.0, 135.0, 179.0, 179.999] {
        let (mesh, positions) = hinge(f64::to_radians(degrees));
        let geometry = Geometry::new(&mesh, &positions).expect("positions");
        let angles = dihedral_angles(&geometry);
        let interior: Vec<f64> = angles.as_slice().iter().flatten().copied().collect();
        assert_eq!(interior.len(), 1, "one interior edge");
        assert!(
            (interior[0] - degrees).abs() < 1e-11,
            "{degrees}: {}",
            interior[0]
        );
        // Boundary edges have none.
        assert_eq!(angles.as_slice().iter().filter(|a| a.is_none()).count(), 4);
    }
}

#[test]
fn cube_edges_are_right_angles_and_diagonals_flat() {
    let cube = primitives::cube();
    let mesh = build(&cube);
    let geometry = Geometry::new(&mesh, &cube.positions).expect("positions");
    let mut right = 0;
    let mut flat = 0;
    for e in mesh.edges() {
        let angle = dihedral_angle(&geometry, e).expect("closed mesh");
        let [a, b] = mesh.edge_vertices(e);
        // A cube edge joins vertices differing in one coordinate bit, a face diagonal in two.
        let bits = (a.raw() ^ b.raw()).count_ones();
        match bits {
            1 => {
                assert!((angle - 90.0).abs() < 1e-12);
                right += 1;
            }
            2 => {
                assert_eq!(angle, 0.0);
                flat += 1;
            }
            _ => panic!("no space diagonal in the cube mesh"),
        }
        assert_eq!(dihedral_angles(&geometry)[e], Some(angle));
    }
    assert_eq!((right, flat), (12, 6));
}

/// One explicit uniform Laplacian step `x ← x + λ (mean of neighbours − x)`.
fn uniform_step(mesh: &HalfedgeMesh, positions: &[DVec3], lambda: f64) -> Vec<DVec3> {
    mesh.vertices()
        .map(|v| {
            let ring: Vec<DVec3> = mesh
                .vertices_around_vertex(v)
                .map(|w| positions[w.index()])
                .collect();
            let mean = ring.iter().sum::<DVec3>() / ring.len() as f64;
            positions[v.index()] + lambda * (mean - positions[v.index()])
        })
        .collect()
}

/// The angle in degrees between the normals of two triangles, by `acos` of the normalised
/// cross products (a different formula from the library's `atan2`).
fn normal_angle(t1: [DVec3; 3], t2: [DVec3; 3]) -> f64 {
    let n = |[a, b, c]: [DVec3; 3]| (b - a).cross(c - a).normalize();
    n(t1).dot(n(t2)).clamp(-1.0, 1.0).acos().to_degrees()
}

/// The unit cube with a centre vertex on each side, each side fanned into four triangles
/// around it (14 vertices, 24 faces): a triangulation with the cube's full symmetry, so
/// that smoothing treats all twelve edges alike.
fn symmetric_cube() -> (HalfedgeMesh, Vec<DVec3>) {
    let cube = primitives::cube();
    let quads: [[u32; 4]; 6] = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let mut positions = cube.positions.clone();
    let mut faces = Vec::new();
    for q in quads {
        let centre = positions.len() as u32;
        positions.push(q.iter().map(|&v| cube.positions[v as usize]).sum::<DVec3>() / 4.0);
        for k in 0..4 {
            faces.push([q[k], q[(k + 1) % 4], centre]);
        }
    }
    let mesh = HalfedgeMesh::from_polygons(positions.len(), &faces).expect("valid");
    mesh.check_integrity().expect("valid mesh");
    (mesh, positions)
}

#[test]
fn smoothing_blunts_the_cube_edges() {
    // One uniform step with λ = 1/2 on the symmetric cube: a side centre is the mean of
    // its four corners and stays; corner (0, 0, 0) has neighbours (1,0,0), (0,1,0),
    // (0,0,1) and three side centres, mean (1/3, 1/3, 1/3), so it moves to (1/6, 1/6,
    // 1/6), and likewise every corner. Across edge (0,0,0)–(1,0,0) the two triangles then
    // reach from the edge (at y = z = 1/6) to the side centres (1/2, 1/2, 0) and
    // (1/2, 0, 1/2): in-plane directions (0, 1/3, −1/6) and (0, −1/6, 1/3), whose normals
    // ∝ (0, 1, 2) and (0, 2, 1) make the angle acos(4/5) ≈ 36.87° (it was 90°).
    let (mesh, positions) = symmetric_cube();
    let smoothed = uniform_step(&mesh, &positions, 0.5);
    assert!((smoothed[0] - DVec3::splat(1.0 / 6.0)).length() < 1e-15);
    let reference = Geometry::new(&mesh, &positions).expect("positions");
    let after = Geometry::new(&mesh, &smoothed).expect("positions");
    let report = feature_edge_distortion(&reference, &after, 45.0).expect("valid");

    assert_eq!(report.threshold_deg, 45.0);
    assert_eq!(report.edges.len(), 12, "the cube's edges, not the spokes");
    assert_eq!(report.undefined, 0);
    let blunted = 0.8f64.acos().to_degrees();
    for (summary, value) in [(report.reference, 90.0), (report.smoothed, blunted)] {
        assert!((summary.mean - value).abs() < 1e-12);
        assert!((summary.min - value).abs() < 1e-12);
        assert!((summary.max - value).abs() < 1e-12);
    }
    assert!((report.mean_loss - (90.0 - blunted)).abs() < 1e-12);

    // Edge by edge, against the angle of the normals by acos.
    let triangle = |f, p: &[DVec3]| mesh.triangle_vertices(f).map(|v| p[v.index()]);
    for edge in &report.edges {
        let [h, t] = edge.edge.halfedges();
        let (f, g) = (mesh.face(h).expect("closed"), mesh.face(t).expect("closed"));
        let expected = normal_angle(triangle(f, &smoothed), triangle(g, &smoothed));
        assert!((edge.smoothed_deg - expected).abs() < 1e-10);
        assert!(edge.smoothed_deg < edge.reference_deg);
    }
}

#[test]
fn smoothing_the_plain_cube_changes_every_edge() {
    // On the cube with two triangles per side the step is not symmetric: some edges get
    // flatter, some sharper; the report agrees edge by edge with the acos formula.
    let cube = primitives::cube();
    let mesh = build(&cube);
    let smoothed = uniform_step(&mesh, &cube.positions, 0.5);
    let report = feature_edge_distortion(
        &Geometry::new(&mesh, &cube.positions).expect("positions"),
        &Geometry::new(&mesh, &smoothed).expect("positions"),
        45.0,
    )
    .expect("valid");
    assert_eq!(report.edges.len(), 12);
    let triangle = |f, p: &[DVec3]| mesh.triangle_vertices(f).map(|v| p[v.index()]);
    let mut losses = Vec::new();
    for edge in &report.edges {
        let [h, t] = edge.edge.halfedges();
        let (f, g) = (mesh.face(h).expect("closed"), mesh.face(t).expect("closed"));
        let expected = normal_angle(triangle(f, &smoothed), triangle(g, &smoothed));
        assert!((edge.smoothed_deg - expected).abs() < 1e-10);
        losses.push(edge.reference_deg - edge.smoothed_deg);
    }
    let mean_loss = losses.iter().sum::<f64>() / 12.0;
    assert!((report.mean_loss - mean_loss).abs() < 1e-12);
    assert!(report.mean_loss > 0.0, "on average the edges are blunted");
    assert!((report.reference.mean - report.smoothed.mean - report.mean_loss).abs() < 1e-12);
}

#[test]
fn feature_edges_with_collapsed_faces_are_counted_apart() {
    let cube = primitives::cube();
    let mesh = build(&cube);
    let collapsed = vec![DVec3::splat(0.5); 8];
    let report = feature_edge_distortion(
        &Geometry::new(&mesh, &cube.positions).expect("positions"),
        &Geometry::new(&mesh, &collapsed).expect("positions"),
        45.0,
    )
    .expect("valid");
    assert_eq!(report.undefined, 12);
    assert!(report.edges.is_empty());
    assert_eq!(report.mean_loss, 0.0);
    assert_eq!(report.smoothed.mean, 0.0);
}

#[test]
fn feature_threshold_is_validated() {
    let cube = primitives::cube();
    let mesh = build(&cube);
    let geometry = Geometry::new(&mesh, &cube.positions).expect("positions");
    for t in [0.0, -5.0, 180.0, 200.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            feature_edge_distortion(&geometry, &geometry, t),
            Err(MetricsError::InvalidParameter { .. })
        ));
    }
    // Just below 90 keeps all twelve edges, just above none.
    assert_eq!(
        feature_edge_distortion(&geometry, &geometry, 89.999)
            .expect("valid")
            .edges
            .len(),
        12
    );
    assert!(
        feature_edge_distortion(&geometry, &geometry, 90.001)
            .expect("valid")
            .edges
            .is_empty()
    );
}
