//! Loop and √3 subdivision against OpenMesh's `LoopT` and `Sqrt3T`
//! (`fixtures/openmesh/<name>/subdivision/`, written by `tools/openmesh-ref`).
//!
//! Positions must agree within 1e-12 of the bounding-box diagonal and the triangles
//! must be the same, with the same orientation. After one step both number the vertices
//! alike, which is checked; after two steps OpenMesh's numbering differs (it edits in
//! place), so its vertices are matched to beltrami's by position first.

use std::collections::HashMap;
use std::fs;
use std::path::{Path, PathBuf};

use beltrami_algorithms::Scheme;
use beltrami_halfedge::{DVec3, HalfedgeMesh};
use beltrami_testkit::fixtures::openmesh_inputs;
use beltrami_testkit::openmesh::read_f64s;

const TOLERANCE: f64 = 1e-12;

fn references() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/openmesh")
}

fn read_faces(path: &Path) -> Vec<[u32; 3]> {
    let bytes = fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(bytes.len() % 12, 0, "{}", path.display());
    bytes
        .chunks_exact(12)
        .map(|c| {
            let at = |i: usize| u32::from_le_bytes(c[4 * i..4 * i + 4].try_into().unwrap());
            [at(0), at(1), at(2)]
        })
        .collect()
}

fn diagonal(p: &[DVec3]) -> f64 {
    let lo = p.iter().fold(DVec3::INFINITY, |a, &b| a.min(b));
    let hi = p.iter().fold(DVec3::NEG_INFINITY, |a, &b| a.max(b));
    (hi - lo).length()
}

/// For each of `theirs`, the index of the nearest of `ours` (a hash grid of cells far
/// larger than the tolerance and far smaller than any edge), checked to be a bijection.
fn match_by_position(ours: &[DVec3], theirs: &[DVec3], cell: f64) -> Vec<usize> {
    let key = |p: DVec3| (p / cell).floor().as_i64vec3().to_array();
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (i, &p) in ours.iter().enumerate() {
        grid.entry(key(p)).or_default().push(i);
    }
    let mut taken = vec![false; ours.len()];
    theirs
        .iter()
        .enumerate()
        .map(|(j, &q)| {
            let [x, y, z] = key(q);
            let mut best: Option<(f64, usize)> = None;
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        for &i in grid.get(&[x + dx, y + dy, z + dz]).into_iter().flatten() {
                            let d = (ours[i] - q).length();
                            if best.is_none_or(|(bd, _)| d < bd) {
                                best = Some((d, i));
                            }
                        }
                    }
                }
            }
            let (_, i) = best.unwrap_or_else(|| panic!("no vertex near OpenMesh's vertex {j}"));
            assert!(!taken[i], "two OpenMesh vertices match vertex {i}");
            taken[i] = true;
            i
        })
        .collect()
}

/// The triangle rotated so that its smallest index comes first (orientation kept).
fn canonical([a, b, c]: [u32; 3]) -> [u32; 3] {
    if a < b && a < c {
        [a, b, c]
    } else if b < c {
        [b, c, a]
    } else {
        [c, a, b]
    }
}

fn sorted_triangles(faces: impl IntoIterator<Item = [u32; 3]>) -> Vec<[u32; 3]> {
    let mut t: Vec<_> = faces.into_iter().map(canonical).collect();
    t.sort_unstable();
    t
}

fn our_triangles(mesh: &HalfedgeMesh) -> Vec<[u32; 3]> {
    sorted_triangles(
        mesh.faces()
            .map(|f| mesh.triangle_vertices(f).map(|v| v.raw())),
    )
}

#[test]
fn subdivision_matches_openmesh() {
    let mut compared = Vec::new();
    for (name, input) in openmesh_inputs() {
        let dir = references().join(name).join("subdivision");
        let cases = fs::read_to_string(dir.join("cases.txt"))
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
        let mesh = input.mesh().unwrap();
        for line in cases.lines() {
            let words: Vec<&str> = line.split_whitespace().collect();
            let [scheme, steps, n_vertices, n_faces] = words[..] else {
                panic!("{name}: bad line {line:?}");
            };
            let scheme = Scheme::from_name(scheme).unwrap();
            let steps: usize = steps.parse().unwrap();
            let case = format!("{name} {scheme} {steps}");
            let stem = format!("{scheme}_{steps}");

            let (ours, positions) = scheme.subdivide(&mesh, &input.positions, steps).unwrap();
            ours.check_integrity().unwrap();
            assert_eq!(
                ours.n_vertices().to_string(),
                n_vertices,
                "{case}: vertices"
            );
            assert_eq!(ours.n_faces().to_string(), n_faces, "{case}: faces");

            let theirs: Vec<DVec3> = read_f64s(&dir.join(format!("{stem}.f64")))
                .unwrap()
                .chunks_exact(3)
                .map(|c| DVec3::new(c[0], c[1], c[2]))
                .collect();
            let their_faces = read_faces(&dir.join(format!("{stem}.faces.u32")));
            assert_eq!(theirs.len(), positions.len(), "{case}");
            let diag = diagonal(&input.positions);

            // OpenMesh vertex j is our vertex map[j].
            let map: Vec<usize> = if steps == 1 {
                (0..theirs.len()).collect()
            } else {
                match_by_position(&positions, &theirs, 1e-6 * diag)
            };
            let mut max_dev = 0.0_f64;
            let mut identical = 0;
            for (j, &q) in theirs.iter().enumerate() {
                let p = positions[map[j]];
                max_dev = max_dev.max((p - q).length());
                identical += usize::from(p == q);
            }
            assert!(
                max_dev <= TOLERANCE * diag,
                "{case}: positions differ by {max_dev:e} (diagonal {diag})"
            );
            let mapped = sorted_triangles(
                their_faces
                    .iter()
                    .map(|t| t.map(|v| map[v as usize] as u32)),
            );
            assert!(
                mapped == our_triangles(&ours),
                "{case}: the triangles differ"
            );
            println!(
                "{case}: {} vertices, {} faces, max deviation {:.1e} of the diagonal, {identical} positions bit-identical",
                positions.len(),
                ours.n_faces(),
                max_dev / diag
            );
            compared.push((name, scheme, steps, ours.is_closed()));
        }
    }
    // The references cover both schemes over two steps, the √3 boundary rule (an odd
    // step on an open mesh) and a closed mesh.
    assert!(
        compared
            .iter()
            .any(|c| c.1 == Scheme::Loop && c.2 == 2 && !c.3)
    );
    assert!(
        compared
            .iter()
            .any(|c| c.1 == Scheme::Sqrt3 && c.2 == 2 && !c.3)
    );
    assert!(
        compared
            .iter()
            .any(|c| c.1 == Scheme::Sqrt3 && c.2 == 2 && c.3)
    );
    assert!(compared.iter().any(|c| c.0 == "holes_30x20" && c.2 == 2));
}
