//! Property tests of the half-edge builder: arbitrary polygon soups never panic, with or
//! without repairs; every mesh it builds passes `check_integrity`; a repaired mesh is
//! valid input as it stands.

mod props_common;

use beltrami_halfedge::{BuildOptions, HalfedgeMesh};
use props_common::{Soup, config, degenerate_mesh, soup};
use proptest::prelude::*;

/// Every combination of the three repairs.
fn all_options() -> Vec<BuildOptions> {
    let mut all = Vec::new();
    for drop in [false, true] {
        for reorient in [false, true] {
            for split in [false, true] {
                all.push(
                    BuildOptions::new()
                        .drop_degenerate_faces(drop)
                        .reorient(reorient)
                        .split_nonmanifold_vertices(split),
                );
            }
        }
    }
    all
}

/// The faces of a built mesh as vertex-index lists, in face order.
fn faces_of(mesh: &HalfedgeMesh) -> Vec<Vec<u32>> {
    mesh.faces()
        .map(|f| mesh.vertices_around_face(f).map(|v| v.raw()).collect())
        .collect()
}

fn check_soup(soup: &Soup) -> Result<(), TestCaseError> {
    let mut built_plain = None;
    for options in all_options() {
        match HalfedgeMesh::build(soup.n_vertices, &soup.faces, &options) {
            Err(e) => prop_assert!(!e.to_string().is_empty()),
            Ok((mesh, report)) => {
                if let Err(e) = mesh.check_integrity() {
                    return Err(TestCaseError::fail(format!(
                        "{options:?}: built mesh fails its integrity check: {e}"
                    )));
                }
                // The report accounts for every element.
                prop_assert_eq!(
                    mesh.n_vertices(),
                    soup.n_vertices + report.split_vertices.len()
                );
                prop_assert_eq!(
                    mesh.n_faces(),
                    soup.faces.len() - report.dropped_faces.len()
                );
                // A repair that is off never acts.
                if !options.drops_degenerate_faces() {
                    prop_assert!(report.dropped_faces.is_empty());
                }
                if !options.reorients() {
                    prop_assert!(report.flipped_faces.is_empty());
                }
                if !options.splits_nonmanifold_vertices() {
                    prop_assert!(report.split_vertices.is_empty());
                }
                // Each built face is its input face (re-oriented when flipped: same
                // first vertex, the rest reversed; split vertices renamed).
                for (f, face) in faces_of(&mesh).iter().enumerate() {
                    let origin = if report.face_origin.is_empty() {
                        f
                    } else {
                        report.face_origin[f]
                    };
                    let input = &soup.faces[origin];
                    prop_assert_eq!(face.len(), input.len());
                    let original = |v: u32| {
                        report
                            .split_vertices
                            .iter()
                            .find(|s| s.vertex.raw() == v)
                            .map_or(v, |s| s.original.raw())
                    };
                    let mut expected = input.clone();
                    if report.flipped_faces.binary_search(&origin).is_ok() {
                        expected[1..].reverse();
                    }
                    let got: Vec<u32> = face.iter().map(|&v| original(v)).collect();
                    prop_assert_eq!(got, expected, "face {} (input face {})", f, origin);
                }
                if options == BuildOptions::new() {
                    built_plain = Some(mesh);
                }
            }
        }
    }
    // A soup that builds without repairs needs none: with every repair on it builds
    // to the same mesh.
    if let Some(plain) = built_plain {
        let (repaired, report) =
            HalfedgeMesh::build(soup.n_vertices, &soup.faces, &BuildOptions::repair_all())
                .map_err(|e| TestCaseError::fail(format!("repairs broke a valid soup: {e}")))?;
        prop_assert!(report.is_empty());
        prop_assert_eq!(repaired, plain);
    }
    Ok(())
}

proptest! {
    #![proptest_config(config(4096))]

    /// Arbitrary soups — repeated and out-of-range indices, faces of 0 to 6 corners,
    /// non-manifold edges and vertices, mixed orientations — under all eight repair
    /// combinations: a typed error or a mesh that passes `check_integrity` and whose
    /// report accounts for every change.
    #[test]
    fn building_a_polygon_soup_never_panics(soup in soup()) {
        check_soup(&soup)?;
    }
}

proptest! {
    #![proptest_config(config(1024))]

    /// A mesh made with repairs is valid input as it stands: its own face list builds
    /// without any repair, to the same counts, and passes `check_integrity`.
    #[test]
    fn repaired_meshes_rebuild_without_repairs(spec in degenerate_mesh()) {
        let random = spec.realise();
        let mesh = &random.mesh;
        prop_assert!(mesh.check_integrity().is_ok());
        let faces = faces_of(mesh);
        let rebuilt = HalfedgeMesh::from_polygons(mesh.n_vertices(), &faces)
            .map_err(|e| TestCaseError::fail(format!("repaired mesh does not rebuild: {e}")))?;
        prop_assert!(rebuilt.check_integrity().is_ok());
        prop_assert_eq!(
            (rebuilt.n_vertices(), rebuilt.n_edges(), rebuilt.n_faces()),
            (mesh.n_vertices(), mesh.n_edges(), mesh.n_faces())
        );
        prop_assert_eq!(rebuilt.euler_characteristic(), mesh.euler_characteristic());
        prop_assert_eq!(&rebuilt, mesh);
    }
}

/// The soup strategy is not vacuous: among its first cases, some build without repairs,
/// some only with repairs, and some not at all.
#[test]
fn soups_cover_every_outcome() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::deterministic();
    let (mut plain, mut repaired, mut failed) = (0, 0, 0);
    for _ in 0..500 {
        let soup = soup().new_tree(&mut runner).expect("tree").current();
        if HalfedgeMesh::from_polygons(soup.n_vertices, &soup.faces).is_ok() {
            plain += 1;
        } else if HalfedgeMesh::build(soup.n_vertices, &soup.faces, &BuildOptions::repair_all())
            .is_ok()
        {
            repaired += 1;
        } else {
            failed += 1;
        }
    }
    assert!(
        plain >= 10 && repaired >= 10 && failed >= 10,
        "plain {plain}, repaired {repaired}, failed {failed}"
    );
}
