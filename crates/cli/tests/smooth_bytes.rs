//! `beltrami smooth` writes, byte for byte, the file the library's result gives when it
//! is written with the faces as read (the command hands the mesh to the smoother by
//! value and writes the faces back from it): binary and ascii PLY, OBJ with polygon
//! faces, OFF, STL; a mesh small enough to be smoothed in the caller's numbering and
//! one large enough to be renumbered; explicit, Taubin and implicit runs; a repaired
//! input.

mod common;

use std::path::Path;

use beltrami_halfedge::{DVec3, HalfedgeMesh, RepairOptions, primitives, repair};
use beltrami_io::{Encoding, MeshData, WriteOptions, read_mesh, write_mesh};
use beltrami_smooth::{
    Boundary, ImplicitSolver, Method, Reorder, SmoothConfig, WeightUpdate, smooth,
};
use beltrami_testkit::Lcg64;
use beltrami_weights::{Cotangent, InverseDistance, Uniform, WeightScheme};

use common::{beltrami, s};

fn fixture(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures")
        .join(name)
}

/// The bytes of the file the library writes for `config` on `input`: the mesh as read
/// (repaired first with `repaired`), smoothed by [`smooth`] with a borrowed mesh, and
/// written with the faces as read.
fn library_bytes(
    input: &Path,
    output: &Path,
    scheme: &dyn WeightScheme,
    config: SmoothConfig,
    repaired: bool,
    ascii: bool,
) -> Vec<u8> {
    let mut data = read_mesh(input).unwrap();
    if repaired {
        let r = repair(&data.positions, &data.faces, &RepairOptions::new()).unwrap();
        data = MeshData {
            positions: r.positions,
            faces: r.faces,
        };
    }
    let mesh = HalfedgeMesh::from_polygon_list(data.positions.len(), &data.faces).unwrap();
    let out = smooth(&mesh, &data.positions, scheme, config).unwrap();
    assert_ne!(out.positions, data.positions, "the run moves the mesh");
    let written = MeshData {
        positions: out.positions,
        faces: data.faces,
    };
    let encoding = if ascii {
        Encoding::Ascii
    } else {
        Encoding::BinaryLittleEndian
    };
    write_mesh(
        output,
        &written,
        &WriteOptions::default().encoding(encoding),
    )
    .unwrap();
    std::fs::read(output).unwrap()
}

/// Runs `beltrami smooth input output options` and returns the output's bytes.
fn cli_bytes(input: &Path, output: &Path, options: &[&str]) -> Vec<u8> {
    let mut args = vec!["smooth", s(input), s(output)];
    args.extend_from_slice(options);
    let out = beltrami(&args);
    assert!(
        out.status.success(),
        "{options:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    std::fs::read(output).unwrap()
}

/// A noisy torus of `n × m` vertices written as binary PLY.
fn noisy_torus(dir: &Path, n: u32, m: u32) -> std::path::PathBuf {
    let torus = primitives::torus(2.0, 0.7, n, m);
    let mut rng = Lcg64::new(22);
    let positions: Vec<DVec3> = torus
        .positions
        .iter()
        .map(|&p| p + rng.next_symmetric_vector() * 0.01)
        .collect();
    let path = dir.join(format!("torus_{n}x{m}.ply"));
    write_mesh(
        &path,
        &MeshData {
            positions,
            faces: torus.faces,
        },
        &WriteOptions::default(),
    )
    .unwrap();
    path
}

/// A run on a fixture: its name, the output's name, the command's options, the
/// library's scheme and configuration for them, whether the input is repaired, whether
/// the output is ascii.
type Case<'a> = (
    &'a str,
    &'a str,
    &'a [&'a str],
    &'a dyn WeightScheme,
    SmoothConfig,
    bool,
    bool,
);

#[test]
fn small_meshes_write_the_same_bytes_as_the_library() {
    let dir = tempfile::tempdir().unwrap();
    let want = dir.path().join("want");
    std::fs::create_dir(&want).unwrap();
    let cases: [Case<'_>; 6] = [
        (
            "noisy_torus_36x12.ply",
            "out.ply",
            &["--lambda", "0.5", "--iterations", "5"],
            &Cotangent,
            SmoothConfig::new(0.5, 5),
            false,
            false,
        ),
        (
            "noisy_icosphere_4.ply",
            "out.off",
            &[
                "--weights",
                "distance",
                "--update",
                "once",
                "--iterations",
                "4",
            ],
            &InverseDistance,
            SmoothConfig::new(0.8, 4).update(WeightUpdate::Once),
            false,
            false,
        ),
        (
            "cube_quads.obj",
            "out.obj",
            &[
                "--weights",
                "uniform",
                "--boundary",
                "free",
                "--iterations",
                "3",
            ],
            &Uniform,
            SmoothConfig::new(0.8, 3).boundary(Boundary::Free),
            false,
            false,
        ),
        (
            "holes_30x20.ply",
            "out.stl",
            &["--method", "implicit", "--lambda", "2", "--iterations", "2"],
            &Cotangent,
            SmoothConfig::new(2.0, 2)
                .method(Method::implicit(ImplicitSolver::conjugate_gradient())),
            false,
            false,
        ),
        (
            "flens_68x33.ply",
            "ascii.ply",
            &[
                "--method",
                "taubin",
                "--lambda",
                "0.5",
                "--mu",
                "-0.53",
                "--iterations",
                "3",
                "--ascii",
            ],
            &Cotangent,
            SmoothConfig::new(0.5, 3).method(Method::Taubin { mu: -0.53 }),
            false,
            true,
        ),
        (
            "bad/inconsistent_orientation.obj",
            "repaired.obj",
            &["--repair", "--weights", "uniform", "--iterations", "2"],
            &Uniform,
            SmoothConfig::new(0.8, 2),
            true,
            false,
        ),
    ];
    for (input, output, options, scheme, config, repaired, ascii) in cases {
        let input = fixture(input);
        let got = cli_bytes(&input, &dir.path().join(output), options);
        let expected = library_bytes(&input, &want.join(output), scheme, config, repaired, ascii);
        assert!(got == expected, "{input:?} -> {output}: the bytes differ");
    }
}

#[test]
fn a_renumbered_mesh_writes_the_same_bytes_as_the_library() {
    let dir = tempfile::tempdir().unwrap();
    // 51 200 vertices: from 50 000 the smoother renumbers the mesh it is given.
    let input = noisy_torus(dir.path(), 320, 160);
    assert!(Reorder::Auto.applies(320 * 160));
    let cases: [(&str, &[&str], SmoothConfig); 3] = [
        (
            "plain.ply",
            &["--iterations", "3"],
            SmoothConfig::new(0.8, 3),
        ),
        (
            "taubin.ply",
            &[
                "--method",
                "taubin",
                "--lambda",
                "0.5",
                "--mu",
                "-0.53",
                "--iterations",
                "2",
                "--report",
                "r.json",
            ],
            SmoothConfig::new(0.5, 2).method(Method::Taubin { mu: -0.53 }),
        ),
        (
            "implicit.ply",
            &["--method", "implicit", "--lambda", "1", "--iterations", "1"],
            SmoothConfig::new(1.0, 1)
                .method(Method::implicit(ImplicitSolver::conjugate_gradient())),
        ),
    ];
    for (output, options, config) in cases {
        let options: Vec<String> = options
            .iter()
            .map(|o| {
                if *o == "r.json" {
                    s(&dir.path().join(o)).to_string()
                } else {
                    (*o).to_string()
                }
            })
            .collect();
        let options: Vec<&str> = options.iter().map(String::as_str).collect();
        let got = cli_bytes(&input, &dir.path().join(output), &options);
        let expected = library_bytes(
            &input,
            &dir.path().join(format!("want-{output}")),
            &Cotangent,
            config,
            false,
            false,
        );
        assert!(got == expected, "{output}: the bytes differ");
    }
}
