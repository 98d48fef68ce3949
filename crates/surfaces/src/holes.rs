//! Holes cut into a surface, as an optical or tactile scan leaves them where the sensor
//! saw nothing (occlusions, steep flanks, reflections): test input for hole filling and
//! for the scan → fill → remesh → smooth pipeline.

use beltrami_halfedge::{DVec3, MeshData};

use crate::{NormalRng, SurfaceError};

/// Stream offset of the hole placement, so that `seed` drives the noise and the holes
/// independently (the same seed with and without holes gives the same noise).
const HOLE_STREAM: u64 = 0x6A09_E667_F3BC_C909;

/// How many candidate centres are drawn per hole before giving up.
const DRAWS_PER_HOLE: usize = 200;

/// What [`cut_holes`] returns: the surface without the cut faces and without the
/// vertices only they used.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct CutHoles {
    /// Positions (the kept vertices, in their input order) and faces (renumbered).
    pub data: MeshData,
    /// For each kept vertex, its index in the input.
    pub kept: Vec<u32>,
    /// The input vertex at the centre of each hole.
    pub centres: Vec<u32>,
    /// The faces removed.
    pub faces_removed: usize,
}

/// Cuts `count` round holes into the triangle mesh `data`: each removes every face
/// whose centroid lies within `radius` (Euclidean, in the positions' unit) of a centre
/// vertex. Centres are drawn from `seed` among the vertices farther than 2 · `radius`
/// from the boundary and than 3 · `radius` from every other centre, so that each hole
/// is a loop of its own, away from the outline; vertices that only removed faces used
/// are dropped and the rest renumbered in their input order.
///
/// The same `data`, `count`, `radius` and `seed` give the same result on every
/// platform.
///
/// # Errors
/// [`SurfaceError::InvalidHoles`] when `radius` is not positive and finite, when
/// fewer than `count` centres fit (after 200 draws per hole), or when the holes would
/// remove every face (a radius beyond a closed surface's size); a
/// [`SurfaceError::Topology`] error when `data` is no valid mesh.
pub fn cut_holes(
    data: &MeshData,
    count: usize,
    radius: f64,
    seed: u64,
) -> Result<CutHoles, SurfaceError> {
    let invalid = |reason: String| SurfaceError::InvalidHoles { reason };
    if !(radius.is_finite() && radius > 0.0) {
        return Err(invalid(format!(
            "the hole radius must be positive and finite, got {radius}"
        )));
    }
    let mesh = data.mesh()?;
    let positions = &data.positions;
    let boundary: Vec<DVec3> = mesh
        .vertices()
        .filter(|&v| mesh.is_boundary_vertex(v))
        .map(|v| positions[v.index()])
        .collect();
    let far_from = |p: DVec3, points: &[DVec3], distance: f64| {
        points
            .iter()
            .all(|q| p.distance_squared(*q) > distance * distance)
    };
    let mut rng = NormalRng::new(seed ^ HOLE_STREAM);
    let mut centres: Vec<u32> = Vec::with_capacity(count);
    let mut centre_points: Vec<DVec3> = Vec::with_capacity(count);
    let n = positions.len();
    for _ in 0..count * DRAWS_PER_HOLE {
        if centres.len() == count || n == 0 {
            break;
        }
        // n ≤ 2³² vertices, so the product is exact enough to pick every index.
        let v = ((rng.next_uniform() * n as f64) as usize).min(n - 1);
        let p = positions[v];
        if mesh.valence(beltrami_halfedge::VertexId::new(v as u32)) > 0
            && far_from(p, &boundary, 2.0 * radius)
            && far_from(p, &centre_points, 3.0 * radius)
        {
            centres.push(v as u32);
            centre_points.push(p);
        }
    }
    if centres.len() < count {
        return Err(invalid(format!(
            "only {} of {count} holes of radius {radius:.4} fit on this surface (away from its boundary and from each other); ask for fewer or smaller holes",
            centres.len()
        )));
    }

    let mut used = vec![false; n];
    let mut faces: Vec<Vec<u32>> = Vec::with_capacity(data.faces.len());
    let mut faces_removed = 0;
    for face in data.faces.iter() {
        let centroid =
            face.iter().map(|&i| positions[i as usize]).sum::<DVec3>() / face.len() as f64;
        if far_from(centroid, &centre_points, radius) {
            for &i in face {
                used[i as usize] = true;
            }
            faces.push(face.to_vec());
        } else {
            faces_removed += 1;
        }
    }
    if faces.is_empty() && faces_removed > 0 {
        return Err(invalid(format!(
            "holes of radius {radius:.4} remove every face of this surface; ask for smaller holes"
        )));
    }
    let mut new_index = vec![u32::MAX; n];
    let mut kept = Vec::new();
    for (old, _) in used.iter().enumerate().filter(|(_, u)| **u) {
        new_index[old] = kept.len() as u32;
        kept.push(old as u32);
    }
    for face in &mut faces {
        for i in face.iter_mut() {
            *i = new_index[*i as usize];
        }
    }
    let cut = MeshData::new(
        kept.iter().map(|&old| positions[old as usize]).collect(),
        faces.iter().map(Vec::as_slice).collect(),
    );
    Ok(CutHoles {
        data: cut,
        kept,
        centres,
        faces_removed,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_hole_larger_than_a_closed_surface_is_refused() {
        let ball = crate::sphere(2).data;
        let err = cut_holes(&ball, 1, 1e9, 1).unwrap_err();
        assert!(err.to_string().contains("remove every face"), "{err}");
        assert!(cut_holes(&ball, 1, 0.3, 1).is_ok());
    }

    #[test]
    fn each_hole_is_a_new_boundary_loop() {
        let lens = crate::flens(&crate::FLensParams::default());
        let before = lens.mesh().unwrap().boundary_loops().count();
        let pitch = crate::FLensParams::default().pitch();
        let cut = cut_holes(&lens.data, 3, 2.5 * pitch, 7).unwrap();
        let mesh = cut.data.mesh().unwrap();
        assert_eq!(mesh.boundary_loops().count(), before + 3);
        assert!(cut.faces_removed > 3 * 10, "{}", cut.faces_removed);
        assert_eq!(mesh.n_faces() + cut.faces_removed, lens.faces.len());
        // Kept vertices keep their positions, and none is isolated.
        for (new, &old) in cut.kept.iter().enumerate() {
            assert_eq!(cut.data.positions[new], lens.positions[old as usize]);
        }
        assert!(mesh.vertices().all(|v| mesh.valence(v) > 0));
        // Same seed, same holes; another seed, other holes.
        assert_eq!(cut_holes(&lens.data, 3, 2.5 * pitch, 7).unwrap(), cut);
        assert_ne!(
            cut_holes(&lens.data, 3, 2.5 * pitch, 8).unwrap().centres,
            cut.centres
        );
    }

    #[test]
    fn closed_surfaces_get_holes_and_impossible_requests_are_refused() {
        let sphere = crate::sphere(3);
        let cut = cut_holes(&sphere.data, 5, 0.2, 1).unwrap();
        assert_eq!(cut.data.mesh().unwrap().boundary_loops().count(), 5);
        let e = cut_holes(&sphere.data, 50, 0.5, 1).unwrap_err();
        assert!(e.to_string().contains("holes of radius"), "{e}");
        assert!(cut_holes(&sphere.data, 1, f64::NAN, 1).is_err());
        assert!(cut_holes(&sphere.data, 1, 0.0, 1).is_err());
        // No holes asked: the surface unchanged.
        let none = cut_holes(&sphere.data, 0, 0.2, 1).unwrap();
        assert_eq!(none.data, sphere.data);
    }
}
