//! The golf ball: a regulation-size dimpled sphere.

use std::collections::HashMap;

use beltrami_halfedge::{DVec3, PolygonList};

use crate::surface::Surface;

/// The regular icosahedron on the unit sphere (the level-0 icosphere) as positions and
/// its 20 counter-clockwise faces.
fn icosahedron() -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let p = beltrami_halfedge::primitives::icosphere(0);
    let faces = p.faces.iter().map(|f| [f[0], f[1], f[2]]).collect();
    (p.positions, faces)
}

/// Where a lattice point of a subdivided icosahedron face lies, named so that points on
/// shared edges and corners get the same key (and the same arithmetic) from every face.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
enum Key {
    Corner(u32),
    Edge(u32, u32, u32),
    Inner(u32, u32, u32),
}

/// The class-I geodesic sphere of frequency `nu` on the unit sphere: every icosahedron
/// face is divided into `nu²` triangles and the lattice points are projected radially.
/// It has `10·nu² + 2` vertices and `20·nu²` faces, counter-clockwise (outward).
///
/// # Panics
/// If `nu` is 0.
#[must_use]
pub fn geodesic_sphere(nu: u32) -> Surface {
    assert!(nu > 0, "the frequency must be positive");
    let (corners, ico) = icosahedron();
    let n = f64::from(nu);
    let mut index: HashMap<Key, u32> = HashMap::new();
    let mut positions = Vec::with_capacity((10 * nu * nu + 2) as usize);
    let mut faces = PolygonList::with_capacity((20 * nu * nu) as usize, (60 * nu * nu) as usize);
    for (fi, &[a, b, c]) in ico.iter().enumerate() {
        let edge = |p: u32, q: u32, steps_from_p: u32| {
            if p < q {
                Key::Edge(p, q, steps_from_p)
            } else {
                Key::Edge(q, p, nu - steps_from_p)
            }
        };
        let key = |i: u32, j: u32| match (i, j) {
            (0, 0) => Key::Corner(a),
            _ if i == nu => Key::Corner(b),
            _ if j == nu => Key::Corner(c),
            (_, 0) => edge(a, b, i),
            (0, _) => edge(a, c, j),
            _ if i + j == nu => edge(b, c, j),
            _ => Key::Inner(fi as u32, i, j),
        };
        let mut id = |i: u32, j: u32| -> u32 {
            let k = key(i, j);
            *index.entry(k).or_insert_with(|| {
                let p = match k {
                    Key::Corner(v) => corners[v as usize],
                    Key::Edge(p, q, t) => {
                        let (p, q) = (corners[p as usize], corners[q as usize]);
                        (p + (q - p) * (f64::from(t) / n)).normalize()
                    }
                    Key::Inner(_, i, j) => {
                        let (pa, pb, pc) = (
                            corners[a as usize],
                            corners[b as usize],
                            corners[c as usize],
                        );
                        (pa + (pb - pa) * (f64::from(i) / n) + (pc - pa) * (f64::from(j) / n))
                            .normalize()
                    }
                };
                positions.push(p);
                (positions.len() - 1) as u32
            })
        };
        for j in 0..nu {
            for i in 0..nu - j {
                let (p00, p10, p01) = (id(i, j), id(i + 1, j), id(i, j + 1));
                faces.push(&[p00, p10, p01]);
                if i + j + 1 < nu {
                    let p11 = id(i + 1, j + 1);
                    faces.push(&[p10, p11, p01]);
                }
            }
        }
    }
    Surface::new("geodesic", positions, faces, "1")
}

/// Parameters of the golf ball, in millimetres.
///
/// Defaults: the regulation minimum diameter 42.67 mm (USGA/R&A), 362 spherical-cap
/// dimples on the vertices of a frequency-6 icosahedral geodesic layout (mean pitch
/// about 4 mm), each 3.8 mm across and 0.18 mm deep (depth/diameter 0.047, within the
/// range golf-ball patents recommend), on a frequency-89 geodesic sphere: 79 212 vertices
/// and 158 420 faces, close to the paper's 78 721 / 157 438 (also F = 2V − 4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GolfBallParams {
    /// Ball diameter, mm.
    pub diameter: f64,
    /// Frequency of the geodesic mesh (10·ν² + 2 vertices).
    pub mesh_frequency: u32,
    /// Frequency of the geodesic dimple layout (10·ν² + 2 dimples).
    pub dimple_frequency: u32,
    /// Chord diameter of a dimple, mm.
    pub dimple_diameter: f64,
    /// Depth of a dimple, mm.
    pub dimple_depth: f64,
}

impl Default for GolfBallParams {
    fn default() -> Self {
        Self {
            diameter: 42.67,
            mesh_frequency: 89,
            dimple_frequency: 6,
            dimple_diameter: 3.8,
            dimple_depth: 0.18,
        }
    }
}

impl GolfBallParams {
    /// The distance from the ball centre to the surface along unit direction `u`, given
    /// the unit dimple axes: the ball radius R, or nearer where a dimple's cap sphere
    /// (radius ρ = (d²/4 + δ²)/(2δ), centre at R + ρ − δ along the axis) cuts in.
    #[must_use]
    pub fn radial_distance(&self, u: DVec3, axes: &[DVec3]) -> f64 {
        let r = self.diameter / 2.0;
        let (d, depth) = (self.dimple_diameter, self.dimple_depth);
        let rho = (d * d / 4.0 + depth * depth) / (2.0 * depth);
        let centre_distance = r + rho - depth;
        // A dimple only reaches directions within its rim's half-angle.
        let cos_rim = ((r * r + centre_distance * centre_distance - rho * rho)
            / (2.0 * r * centre_distance))
            .clamp(-1.0, 1.0);
        let mut best = r;
        for &a in axes {
            let uc = u.dot(a) * centre_distance;
            if uc / centre_distance < cos_rim {
                continue;
            }
            let disc = uc * uc - centre_distance * centre_distance + rho * rho;
            if disc >= 0.0 {
                best = best.min(uc - disc.sqrt());
            }
        }
        best
    }
}

/// Builds the golf ball (closed, genus 0, outward normals), centred on the origin, mm.
///
/// # Panics
/// If a frequency is 0 or a dimple is not shallower than its radius.
#[must_use]
pub fn golf_ball(params: &GolfBallParams) -> Surface {
    assert!(
        params.dimple_depth > 0.0 && params.dimple_depth < params.dimple_diameter / 2.0,
        "a dimple must be shallower than its radius"
    );
    let axes = geodesic_sphere(params.dimple_frequency).data.positions;
    let sphere = geodesic_sphere(params.mesh_frequency);
    let positions = sphere
        .positions
        .iter()
        .map(|&u| u * params.radial_distance(u, &axes))
        .collect();
    Surface::new("golfball", positions, sphere.data.faces, "mm")
}
