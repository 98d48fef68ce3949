//! The custom scheme of `examples/custom_weight` runs through smoothing and the CLI
//! unchanged, exactly like a built-in.

#[path = "../examples/custom_weight/mean_value.rs"]
mod mean_value;

use std::process::ExitCode;

use beltrami::halfedge::primitives;
use beltrami::io::{MeshData, WriteOptions, read_mesh, write_mesh};
use beltrami::smooth::{Boundary, SmoothConfig, smooth};
use beltrami::weights::{Laplacian, LaplacianOptions, WeightRegistry};
use mean_value::MeanValue;

#[test]
fn mean_value_weights_are_positive_and_reproduce_a_plane() {
    let g = primitives::grid(6, 6);
    let mesh = g.mesh().unwrap();
    let lap = Laplacian::new(&mesh, &g.positions, &MeanValue, LaplacianOptions::default()).unwrap();
    for v in mesh.vertices() {
        assert!(lap.row(v).all(|(_, w)| w > 0.0));
        if !mesh.is_boundary_vertex(v) {
            // Mean-value coordinates have linear precision.
            assert!(lap.laplacian_at(v, &g.positions).unwrap().length() < 1e-12);
        }
    }
}

#[test]
fn custom_scheme_runs_through_smoothing_and_the_cli() {
    let sphere = primitives::icosphere(2);
    let mesh = sphere.mesh().unwrap();
    let config = SmoothConfig::new(0.8, 7).boundary(Boundary::Free);
    let direct = smooth(&mesh, &sphere.positions, &MeanValue, config).unwrap();
    assert!(
        direct
            .positions
            .iter()
            .all(|p| p.is_finite() && p.length() < 1.0)
    );

    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("sphere.ply");
    let output = dir.path().join("smoothed.ply");
    let data = MeshData {
        positions: sphere.positions.clone(),
        faces: sphere.faces.clone(),
    };
    write_mesh(&input, &data, &WriteOptions::default()).unwrap();

    let mut registry = WeightRegistry::with_builtins();
    registry.register(MeanValue).unwrap();
    let args = [
        "beltrami",
        "smooth",
        input.to_str().unwrap(),
        output.to_str().unwrap(),
        "--weights",
        "mean-value",
        "--iterations",
        "7",
        "--boundary",
        "free",
    ];
    assert_eq!(beltrami_cli::run_with(args, &registry), ExitCode::SUCCESS);
    let cli = read_mesh(&output).unwrap();
    assert_eq!(cli.faces, sphere.faces);
    // Binary double PLY round-trips exactly: the CLI computed the very same numbers.
    assert_eq!(cli.positions, direct.positions);

    // Without registration the name is unknown: a usage error.
    let builtins = WeightRegistry::with_builtins();
    assert_eq!(beltrami_cli::run_with(args, &builtins), ExitCode::from(2));
}
