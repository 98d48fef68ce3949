//! Small procedural meshes for examples, tests and benchmarks.
//!
//! Every primitive is counter-clockwise oriented (normals point outwards for closed
//! ones and towards +z for planar ones) and in unit-scale coordinates.

use std::collections::HashMap;

use glam::DVec3;

use crate::mesh_data::MeshData;
use crate::polygons::PolygonList;

/// Positions and faces of a procedural mesh: the workspace's [`MeshData`], under the
/// name the primitives have always returned.
pub type Primitive = MeshData;

fn tri(positions: Vec<DVec3>, triangles: &[[u32; 3]]) -> Primitive {
    Primitive {
        positions,
        faces: PolygonList::from_triangles(triangles),
    }
}

/// One triangle in the xy-plane: (0,0,0), (1,0,0), (0,1,0).
#[must_use]
pub fn triangle() -> Primitive {
    tri(vec![DVec3::ZERO, DVec3::X, DVec3::Y], &[[0, 1, 2]])
}

/// A regular hexagon of unit radius in the xy-plane, fanned into six triangles around
/// a centre vertex 0 (open: one boundary loop of six edges).
#[must_use]
pub fn hexagon_fan() -> Primitive {
    let mut positions = vec![DVec3::ZERO];
    for k in 0..6 {
        let a = f64::from(k) * std::f64::consts::FRAC_PI_3;
        positions.push(DVec3::new(a.cos(), a.sin(), 0.0));
    }
    let faces: Vec<[u32; 3]> = (0..6u32).map(|k| [0, 1 + k, 1 + (k + 1) % 6]).collect();
    tri(positions, &faces)
}

/// An open grid of `nx × ny` squares over `[0, nx] × [0, ny]` in the xy-plane, each split
/// into two triangles along its (i, j)–(i+1, j+1) diagonal. Vertex `(i, j)` has index
/// `j * (nx + 1) + i`.
///
/// # Panics
/// If `nx` or `ny` is 0.
#[must_use]
pub fn grid(nx: u32, ny: u32) -> Primitive {
    assert!(nx > 0 && ny > 0, "a grid needs at least one cell");
    let mut positions = Vec::with_capacity(((nx + 1) * (ny + 1)) as usize);
    for j in 0..=ny {
        for i in 0..=nx {
            positions.push(DVec3::new(f64::from(i), f64::from(j), 0.0));
        }
    }
    let id = |i: u32, j: u32| j * (nx + 1) + i;
    let mut faces = Vec::with_capacity((2 * nx * ny) as usize);
    for j in 0..ny {
        for i in 0..nx {
            faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            faces.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    tri(positions, &faces)
}

/// A regular tetrahedron inscribed in the unit sphere.
#[must_use]
pub fn tetrahedron() -> Primitive {
    let s = 1.0 / 3f64.sqrt();
    let positions = vec![
        DVec3::new(s, s, s),
        DVec3::new(s, -s, -s),
        DVec3::new(-s, s, -s),
        DVec3::new(-s, -s, s),
    ];
    tri(positions, &[[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]])
}

/// The unit cube `[0, 1]³`, two triangles per side (8 vertices, 12 faces).
#[must_use]
pub fn cube() -> Primitive {
    let positions = (0..8u32)
        .map(|i| DVec3::new(f64::from(i & 1), f64::from((i >> 1) & 1), f64::from(i >> 2)))
        .collect();
    // Vertex i has x = bit 0, y = bit 1, z = bit 2.
    let faces = [
        [0, 2, 3],
        [0, 3, 1], // z = 0, normal -z
        [4, 5, 7],
        [4, 7, 6], // z = 1, normal +z
        [0, 1, 5],
        [0, 5, 4], // y = 0, normal -y
        [2, 6, 7],
        [2, 7, 3], // y = 1, normal +y
        [0, 4, 6],
        [0, 6, 2], // x = 0, normal -x
        [1, 3, 7],
        [1, 7, 5], // x = 1, normal +x
    ];
    tri(positions, &faces)
}

/// The unit cube `[0, 1]³` as six quadrilaterals (a polygon mesh).
#[must_use]
pub fn cube_quads() -> Primitive {
    let t = cube();
    let quads: [[u32; 4]; 6] = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    Primitive {
        positions: t.positions,
        faces: quads.iter().map(|q| &q[..]).collect(),
    }
}

/// The unit icosphere: a regular icosahedron subdivided `level` times (each triangle
/// split into four, new vertices projected onto the unit sphere). It has
/// `10·4^level + 2` vertices and `20·4^level` faces.
///
/// # Panics
/// If `level > 12` (more than `u32` vertices would be needed for the faces).
#[must_use]
pub fn icosphere(level: u32) -> Primitive {
    assert!(level <= 12, "icosphere level {level} is too large");
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut positions: Vec<DVec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| DVec3::new(x, y, z).normalize())
    .collect();
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut midpoint: HashMap<(u32, u32), u32> = HashMap::with_capacity(faces.len() * 3 / 2);
        let mut mid = |a: u32, b: u32, positions: &mut Vec<DVec3>| -> u32 {
            let key = (a.min(b), a.max(b));
            *midpoint.entry(key).or_insert_with(|| {
                let p = (positions[a as usize] + positions[b as usize]).normalize();
                positions.push(p);
                (positions.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(faces.len() * 4);
        for &[a, b, c] in &faces {
            let ab = mid(a, b, &mut positions);
            let bc = mid(b, c, &mut positions);
            let ca = mid(c, a, &mut positions);
            next.extend_from_slice(&[[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    tri(positions, &faces)
}

/// A torus around the z-axis (genus 1) with tube centre radius `major` and tube radius
/// `minor`, on an `n_major × n_minor` grid of quads split into triangles.
///
/// # Panics
/// If `n_major < 3` or `n_minor < 3`.
#[must_use]
pub fn torus(major: f64, minor: f64, n_major: u32, n_minor: u32) -> Primitive {
    assert!(
        n_major >= 3 && n_minor >= 3,
        "a torus needs at least 3x3 cells"
    );
    let tau = std::f64::consts::TAU;
    let mut positions = Vec::with_capacity((n_major * n_minor) as usize);
    for i in 0..n_major {
        let u = tau * f64::from(i) / f64::from(n_major);
        for j in 0..n_minor {
            let v = tau * f64::from(j) / f64::from(n_minor);
            let r = major + minor * v.cos();
            positions.push(DVec3::new(r * u.cos(), r * u.sin(), minor * v.sin()));
        }
    }
    let id = |i: u32, j: u32| (i % n_major) * n_minor + (j % n_minor);
    let mut faces = Vec::with_capacity((2 * n_major * n_minor) as usize);
    for i in 0..n_major {
        for j in 0..n_minor {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            faces.push([a, b, c]);
            faces.push([a, c, d]);
        }
    }
    tri(positions, &faces)
}
