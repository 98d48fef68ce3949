//! The committed fixtures: up to date, and read back as the primitives they come from.

mod common;

#[allow(dead_code, reason = "only `write_fixtures` is used here")]
#[path = "../examples/make_fixtures.rs"]
mod make_fixtures;

use beltrami_halfedge::primitives;
use beltrami_io::{MeshData, read_mesh};
use common::{assert_bit_identical, assert_same_up_to_renumbering, fixture};

/// Every fixture and the primitive it holds.
fn expected() -> Vec<(&'static str, MeshData)> {
    let tetrahedron = primitives::tetrahedron();
    let cube = primitives::cube();
    let hexagon_fan = primitives::hexagon_fan();
    let grid = primitives::grid(4, 3);
    let icosphere = primitives::icosphere(2);
    vec![
        ("tetrahedron_ascii.ply", tetrahedron.clone()),
        ("tetrahedron_le.ply", tetrahedron.clone()),
        ("tetrahedron_be.ply", tetrahedron),
        ("cube_binary.stl", cube.clone()),
        ("cube_ascii.stl", cube.clone()),
        ("cube.obj", cube.clone()),
        ("cube_ascii.ply", cube),
        ("hexagon_fan_ascii.ply", hexagon_fan.clone()),
        ("hexagon_fan.obj", hexagon_fan),
        ("grid_4x3.ply", grid.clone()),
        ("grid_4x3.obj", grid),
        ("torus_12x8.ply", primitives::torus(2.0, 0.5, 12, 8)),
        ("icosphere_2.ply", icosphere.clone()),
        ("icosphere_2.stl", icosphere),
        ("cube_quads.obj", primitives::cube_quads()),
    ]
}

#[test]
fn fixtures_are_up_to_date() {
    let dir = tempfile::tempdir().expect("temporary directory");
    make_fixtures::write_fixtures(dir.path()).expect("generate");
    let mut generated: Vec<_> = std::fs::read_dir(dir.path())
        .expect("read dir")
        .map(|e| e.expect("entry").file_name())
        .collect();
    generated.sort();
    assert_eq!(generated.len(), expected().len());
    for name in generated {
        let fresh = std::fs::read(dir.path().join(&name)).expect("generated");
        let committed = std::fs::read(fixture(&name.to_string_lossy())).expect("committed");
        assert!(
            fresh == committed,
            "fixtures/{} is stale: run `cargo run -p beltrami-io --example make_fixtures`",
            name.to_string_lossy()
        );
        assert!(committed.len() < 50 * 1024, "{name:?} is too large");
    }
}

#[test]
fn fixtures_read_back_as_their_primitives() {
    for (name, mesh) in expected() {
        let read = read_mesh(fixture(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        if name.ends_with(".stl") {
            // Coordinates of these primitives are not all exact in f32.
            let exact = common::f32_mesh(&mesh);
            assert_same_up_to_renumbering(&exact, &read);
        } else {
            assert_bit_identical(&read, &mesh);
        }
    }
}

#[test]
fn stl_welding_matches_the_ply_of_the_same_mesh() {
    for (stl, ply) in [
        ("cube_binary.stl", "cube_ascii.ply"),
        ("cube_ascii.stl", "cube_ascii.ply"),
        ("icosphere_2.stl", "icosphere_2.ply"),
    ] {
        let welded = read_mesh(fixture(stl)).expect("stl");
        let indexed = read_mesh(fixture(ply)).expect("ply");
        assert_eq!(welded.positions.len(), indexed.positions.len(), "{stl}");
        assert_same_up_to_renumbering(&common::f32_mesh(&indexed), &welded);
    }
}
