//! The block: a closed genus-3 part with sharp edges.

use std::collections::HashMap;

use beltrami_halfedge::{DVec3, PolygonList};

use crate::noise::NormalRng;
use crate::surface::Surface;

/// Parameters of the block: a box of `cells` lattice cells of `pitch` mm with three
/// square through-holes along y, stacked along z.
///
/// The paper's block is a genus-3 denoising benchmark model (8771 vertices, 17550
/// faces, about 20 × 20 × 38 mm, sharp edges). Its file is not redistributable, so
/// beltrami builds a part of the same kind: a 20 × 20 × 39.3 mm box with three
/// 4.4 × 3.7 mm through-holes, hence also genus 3 (F = 2V + 8), with 8780 vertices and
/// 17568 faces. Every edge of the box and of the holes is sharp (90°), which is what the
/// paper uses the block for (edge blurring). The surface lattice is triangulated and
/// then jittered *within* each flat side (and along each straight edge), so the
/// triangulation is irregular like a scanned and remeshed part, while the shape stays
/// exactly the box with holes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlockParams {
    /// Lattice cells along x, y, z.
    pub cells: [u32; 3],
    /// Lattice pitch, mm.
    pub pitch: f64,
    /// Hole size in cells along x and z.
    pub hole: [u32; 2],
    /// In-plane jitter as a fraction of the pitch (0 gives the regular lattice; at most
    /// 0.25 keeps every triangle valid).
    pub jitter: f64,
    /// Seed of the jitter.
    pub seed: u64,
}

impl Default for BlockParams {
    fn default() -> Self {
        Self {
            cells: [27, 27, 53],
            pitch: 20.0 / 27.0,
            hole: [6, 5],
            jitter: 0.2,
            seed: 1,
        }
    }
}

/// Builds the block (closed, genus 3, outward normals), centred on the origin, mm.
///
/// # Panics
/// If the holes do not fit inside the box with a wall of at least one cell, or if
/// `jitter` is outside [0, 0.25].
#[must_use]
pub fn block(params: &BlockParams) -> Surface {
    let [nx, ny, nz] = params.cells.map(|c| c as i32);
    let [hw, hh] = params.hole.map(|c| c as i32);
    assert!(
        (0.0..=0.25).contains(&params.jitter),
        "jitter must be in [0, 0.25]"
    );
    let hx0 = (nx - hw) / 2;
    let holes: Vec<(i32, i32)> = [nz / 4, nz / 2, 3 * nz / 4]
        .iter()
        .map(|&c| (c - hh / 2, c - hh / 2 + hh))
        .collect();
    assert!(
        hx0 >= 1 && holes[0].0 >= 1 && holes[2].1 < nz && holes[0].1 < holes[1].0,
        "the holes must fit inside the block"
    );
    let solid = |x: i32, y: i32, z: i32| {
        (0..nx).contains(&x)
            && (0..ny).contains(&y)
            && (0..nz).contains(&z)
            && !((hx0..hx0 + hw).contains(&x)
                && holes.iter().any(|&(z0, z1)| (z0..z1).contains(&z)))
    };

    let mut index: HashMap<[i32; 3], u32> = HashMap::new();
    let mut lattice: Vec<[i32; 3]> = Vec::new();
    // Per vertex: bit k set when a quad with normal along axis k touches it.
    let mut axes: Vec<u8> = Vec::new();
    let mut faces = PolygonList::new();
    for x in 0..nx {
        for y in 0..ny {
            for z in 0..nz {
                if !solid(x, y, z) {
                    continue;
                }
                for k in 0..3 {
                    for s in [1, -1] {
                        let mut n = [x, y, z];
                        n[k] += s;
                        if solid(n[0], n[1], n[2]) {
                            continue;
                        }
                        // The quad on the side of the cell facing +s·e_k, wound so that
                        // e_a × e_b = e_k points outwards (reversed for s = −1).
                        let (a, b) = ((k + 1) % 3, (k + 2) % 3);
                        let mut base = [x, y, z];
                        if s > 0 {
                            base[k] += 1;
                        }
                        let corner = |da: i32, db: i32| {
                            let mut p = base;
                            p[a] += da;
                            p[b] += db;
                            p
                        };
                        let mut quad = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
                        if s < 0 {
                            quad.reverse();
                        }
                        let ids = quad.map(|p| {
                            let id = *index.entry(p).or_insert_with(|| {
                                lattice.push(p);
                                axes.push(0);
                                (lattice.len() - 1) as u32
                            });
                            axes[id as usize] |= 1 << k;
                            id
                        });
                        faces.push(&[ids[0], ids[1], ids[2]]);
                        faces.push(&[ids[0], ids[2], ids[3]]);
                    }
                }
            }
        }
    }

    let h = params.pitch;
    let centre = DVec3::new(f64::from(nx), f64::from(ny), f64::from(nz)) * 0.5;
    let mut rng = NormalRng::new(params.seed);
    let positions = lattice
        .iter()
        .zip(&axes)
        .map(|(p, &mask)| {
            let mut q = DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2])) - centre;
            // Free directions: those not normal to any incident side. On a flat side two
            // directions are free, on a straight edge one, at a corner none.
            for k in 0..3 {
                let shift = params.jitter * (2.0 * rng.next_uniform() - 1.0);
                if mask & (1 << k) == 0 {
                    q[k] += shift;
                }
            }
            q * h
        })
        .collect();
    Surface::new("block", positions, faces, "mm")
}
