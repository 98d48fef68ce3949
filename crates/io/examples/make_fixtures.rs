//! Writes the small mesh files of `fixtures/` from the procedural primitives.
//!
//! ```text
//! cargo run -p beltrami-io --example make_fixtures            # into fixtures/
//! cargo run -p beltrami-io --example make_fixtures -- OUT_DIR  # elsewhere
//! ```
//!
//! The output is deterministic: running it again gives byte-identical files (a test
//! checks that the committed fixtures are up to date).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use beltrami_halfedge::primitives;
use beltrami_io::{Encoding, IoError, MeshData, WriteOptions, write_mesh};

/// Every fixture: file name, mesh, encoding.
fn fixtures() -> Vec<(&'static str, MeshData, Encoding)> {
    use Encoding::{Ascii, BinaryBigEndian, BinaryLittleEndian};
    let tetrahedron = primitives::tetrahedron();
    let cube = primitives::cube();
    let hexagon_fan = primitives::hexagon_fan();
    let grid = primitives::grid(4, 3);
    let torus = primitives::torus(2.0, 0.5, 12, 8);
    let icosphere = primitives::icosphere(2);
    vec![
        ("tetrahedron_ascii.ply", tetrahedron.clone(), Ascii),
        (
            "tetrahedron_le.ply",
            tetrahedron.clone(),
            BinaryLittleEndian,
        ),
        ("tetrahedron_be.ply", tetrahedron, BinaryBigEndian),
        ("cube_binary.stl", cube.clone(), BinaryLittleEndian),
        ("cube_ascii.stl", cube.clone(), Ascii),
        ("cube.obj", cube.clone(), Ascii),
        ("cube_ascii.ply", cube, Ascii),
        ("hexagon_fan_ascii.ply", hexagon_fan.clone(), Ascii),
        ("hexagon_fan.obj", hexagon_fan, Ascii),
        ("grid_4x3.ply", grid.clone(), BinaryLittleEndian),
        ("grid_4x3.obj", grid, Ascii),
        ("torus_12x8.ply", torus, BinaryLittleEndian),
        ("icosphere_2.ply", icosphere.clone(), BinaryLittleEndian),
        ("icosphere_2.stl", icosphere, BinaryLittleEndian),
    ]
}

/// The unit cube as six quads, in the OBJ dialect of real exporters: comments,
/// `o`/`g`/`s`/`usemtl` statements, texture coordinates and normals, a vertex with a
/// `w` and one with a colour, and faces with negative (relative) indices in all four
/// corner forms `a`, `a/b`, `a//c`, `a/b/c`.
fn cube_quads_obj() -> String {
    let cube = primitives::cube_quads();
    let n = cube.positions.len();
    let mut obj = String::from(
        "# The unit cube as six quadrilaterals, written by make_fixtures.\n\
         mtllib cube.mtl\n\
         o cube\n",
    );
    for (i, p) in cube.positions.iter().enumerate() {
        let extra = match i {
            1 => " 1.0",         // w
            2 => " 0.8 0.1 0.1", // vertex colour
            _ => "",
        };
        let _ = writeln!(obj, "v {} {} {}{extra}", p.x, p.y, p.z);
    }
    obj.push_str("vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n");
    obj.push_str("vn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\nvn 1 0 0\nvn 0 1 0\nvn -1 0 0\n");
    obj.push_str("g sides\nusemtl grey\ns off\n");
    for (f, face) in cube.faces.iter().enumerate() {
        obj.push('f');
        for (k, &v) in face.iter().enumerate() {
            // Relative index: -1 is the last vertex defined so far.
            let a = v as i64 - n as i64;
            let (t, normal) = (k + 1, f + 1);
            let _ = match (f + k) % 4 {
                0 => write!(obj, " {a}"),
                1 => write!(obj, " {a}/-{}", 5 - t),
                2 => write!(obj, " {a}//{normal}"),
                _ => write!(obj, " {a}/{t}/-{}", 7 - normal),
            };
        }
        obj.push('\n');
    }
    obj.push_str("# end\n");
    obj
}

/// Writes every fixture into `dir`.
///
/// # Errors
/// When a file cannot be written.
pub(crate) fn write_fixtures(dir: &Path) -> Result<(), IoError> {
    for (name, mesh, encoding) in fixtures() {
        let options = WriteOptions::default().encoding(encoding);
        write_mesh(dir.join(name), &mesh, &options)?;
    }
    std::fs::write(dir.join("cube_quads.obj"), cube_quads_obj()).map_err(|source| IoError::Io {
        operation: "write cube_quads.obj",
        source,
    })
}

#[allow(
    dead_code,
    reason = "tests include this file for `write_fixtures` only"
)]
fn main() -> Result<(), IoError> {
    let dir = std::env::args_os().nth(1).map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures"),
        PathBuf::from,
    );
    std::fs::create_dir_all(&dir).map_err(|source| IoError::Io {
        operation: "create the output directory",
        source,
    })?;
    write_fixtures(&dir)?;
    println!("fixtures written to {}", dir.display());
    Ok(())
}
