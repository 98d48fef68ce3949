//! OFF: exact round trips, the header variants found in shape data sets, and every
//! error with its line.

mod common;

use std::time::Instant;

use beltrami_halfedge::primitives;
use beltrami_io::{
    Encoding, IoError, MeshData, MeshFormat, PolygonList, Precision, WriteOptions, declared_counts,
    read_mesh, read_mesh_from, write_mesh, write_mesh_to,
};
use common::{assert_bit_identical, f32_mesh, messy_mesh};
use glam::DVec3;

fn read(text: &str) -> MeshData {
    match read_mesh_from(text.as_bytes(), MeshFormat::Off) {
        Ok(mesh) => mesh,
        Err(e) => panic!("{text:?}: {e}"),
    }
}

fn error(text: &str) -> IoError {
    match read_mesh_from(text.as_bytes(), MeshFormat::Off) {
        Ok(mesh) => panic!("{text:?}: expected an error, read {mesh:?}"),
        Err(e) => e,
    }
}

fn message(text: &str) -> String {
    error(text).to_string()
}

fn write(mesh: &MeshData, precision: Precision) -> String {
    let mut bytes = Vec::new();
    let options = WriteOptions::default().precision(precision);
    write_mesh_to(&mut bytes, mesh, MeshFormat::Off, &options).expect("write");
    String::from_utf8(bytes).expect("text")
}

/// The unit triangle, vertices 0 (origin), 1 (x) and 2 (y).
fn triangle() -> MeshData {
    MeshData {
        positions: vec![DVec3::ZERO, DVec3::X, DVec3::Y],
        faces: PolygonList::from_triangles(&[[0, 1, 2]]),
    }
}

const TRIANGLE: &str = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";

// ---------------------------------------------------------------- writing

#[test]
fn the_writer_writes_plain_off() {
    assert_eq!(write(&triangle(), Precision::Double), TRIANGLE);
    let quads: MeshData = primitives::cube_quads();
    let text = write(&quads, Precision::Double);
    assert!(text.starts_with("OFF\n8 6 0\n"), "{text}");
    assert_eq!(text.lines().filter(|l| l.starts_with("4 ")).count(), 6);
    assert_eq!(
        write(&MeshData::default(), Precision::Double),
        "OFF\n0 0 0\n"
    );
}

#[test]
fn off_round_trips_exactly() {
    let mut meshes: Vec<MeshData> = vec![
        primitives::triangle(),
        primitives::cube_quads(),
        primitives::hexagon_fan(),
        primitives::torus(2.0, 0.5, 12, 8),
        primitives::icosphere(2),
        MeshData::default(),
    ];
    // Random bit patterns, subnormals, extremes, faces of 2 and 6 vertices.
    meshes.push(messy_mesh());
    for mesh in &meshes {
        let back = read(&write(mesh, Precision::Double));
        assert_bit_identical(&back, mesh);
    }
    // Single precision: the shortest decimal of each f32, which reads back as an f64
    // that rounds to it.
    let torus: MeshData = primitives::torus(2.0, 0.5, 12, 8);
    let back = read(&write(&torus, Precision::Single));
    assert_bit_identical(&f32_mesh(&back), &f32_mesh(&torus));
    assert_ne!(back, f32_mesh(&torus));
}

#[test]
fn off_files_round_trip_through_paths_whatever_the_encoding() -> Result<(), IoError> {
    let dir = tempfile::tempdir().expect("temporary directory");
    let mesh = messy_mesh();
    for (name, encoding) in [
        ("a.off", Encoding::BinaryLittleEndian),
        ("b.OFF", Encoding::Ascii),
    ] {
        let path = dir.path().join(name);
        let options = WriteOptions::default().encoding(encoding);
        write_mesh(&path, &mesh, &options)?;
        assert_bit_identical(&read_mesh(&path)?, &mesh);
        let counts = declared_counts(&path)?.expect("an off header declares its counts");
        assert_eq!(
            (counts.vertices, counts.faces),
            (Some(mesh.positions.len()), mesh.faces.len())
        );
    }
    // Nothing but the target is left in the folder: the write went through a
    // temporary file renamed over it.
    assert_eq!(std::fs::read_dir(dir.path()).expect("list").count(), 2);
    Ok(())
}

// ---------------------------------------------------------------- header variants

#[test]
fn header_variants_of_shape_data_sets_are_read() {
    let variants = [
        // Counts on the keyword line; no edge count.
        "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
        "OFF\n3 1\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
        // No space after the keyword (ModelNet).
        "OFF3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
        // No keyword (Geomview: optional).
        "3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
        // Colours, normals, texture coordinates after the coordinates; a face colour.
        "COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n3 0 1 2 0.5 0.5 0.5\n",
        "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n",
        "CNOFF\n3 1 0\n0 0 0 0 0 1 1 1 1 1\n1 0 0 0 0 1 1 1 1 1\n0 1 0 0 0 1 1 1 1 1\n3 0 1 2\n",
        "STOFF\n3 1 0\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2 255 0 0\n",
        // Comments and blank lines anywhere; odd whitespace.
        "# made by hand\n\nOFF # keyword\n# counts next\n 3\t1  0 \n\n0 0 0 # origin\n1 0 0\n\n0 1 0\n# faces\n3 0 1 2\n\n",
        // Windows and classic Mac OS line endings, a byte order mark, no final newline.
        "OFF\r\n3 1 0\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n",
        "OFF\r3 1 0\r0 0 0\r1 0 0\r0 1 0\r3 0 1 2\r",
        "\u{feff}OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2",
        // Numbers in any notation.
        "OFF\n3 1 0\n0.0 -0e0 0\n1e0 0 0\n0 +1.0 0\n3 0 1 2\n",
    ];
    for text in variants {
        assert_eq!(read(text), triangle(), "{text:?}");
    }
}

#[test]
fn polygons_of_any_size_pass_through() {
    let mesh = read("OFF\n4 3 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n2 0 1\n3 0 0 1\n");
    assert_eq!(mesh.faces.get(0), Some(&[0, 1, 2, 3][..]));
    assert_eq!(mesh.faces.get(1), Some(&[0, 1][..]));
    assert_eq!(mesh.faces.get(2), Some(&[0, 0, 1][..]));
    // A points-only file (no faces) is fine.
    let points = read("OFF\n2 0 0\n0 0 0\n1 2 3\n");
    assert_eq!(points.positions, [DVec3::ZERO, DVec3::new(1.0, 2.0, 3.0)]);
    assert!(points.faces.is_empty());
}

// ---------------------------------------------------------------- errors

#[test]
fn empty_and_blank_files_are_empty() {
    for text in ["", " ", "\n\n", "\r\n\t \r", "\u{feff}\n"] {
        assert!(matches!(error(text), IoError::Empty), "{text:?}");
    }
    assert_eq!(
        message("# a comment\n"),
        "invalid off header: the file holds only comments, no \"OFF\" line"
    );
}

#[test]
fn unsupported_variants_and_other_formats_are_named() {
    assert_eq!(
        message("OFF BINARY\n3 1 0\n"),
        "line 1: invalid off header: binary off is not supported (convert the file to ascii off or ply)"
    );
    assert_eq!(
        message("4OFF\n1 0 0\n0 0 0 1\n"),
        "line 1: invalid off header: 4OFF (homogeneous coordinates) is not supported"
    );
    assert_eq!(
        message("nOFF\n3\n1 0 0\n0 0 0\n"),
        "line 1: invalid off header: nOFF (a dimension given in the file) is not supported"
    );
    let ply = "ply\nformat ascii 1.0\nelement vertex 0\nend_header\n";
    assert_eq!(
        message(ply),
        "line 1: invalid off header: the file starts with \"ply\", not with \"OFF\"; is this a ply file? rename it to .ply"
    );
    assert_eq!(
        message("# exported\nv 0 0 0\n"),
        "line 2: invalid off header: the file starts with \"v\", not with \"OFF\"; is this an obj file? rename it to .obj"
    );
    assert_eq!(
        message("solid x\nendsolid x\n"),
        "line 1: invalid off header: the file starts with \"solid\", not with \"OFF\"; is this an stl file? rename it to .stl"
    );
    assert!(matches!(
        error("OFF\u{0}\u{1}\n"),
        IoError::NotText { line: 1 }
    ));
}

#[test]
fn malformed_counts_are_syntax_errors() {
    assert_eq!(
        message("OFF\n"),
        "line 1: expected the vertex count, found nothing"
    );
    assert_eq!(
        message("OFF\n3 x 0\n"),
        "line 2: expected the face count, found \"x\""
    );
    assert_eq!(
        message("OFF\n3 1 0 9\n"),
        "line 2: expected the end of the counts line, found \"9\""
    );
    assert_eq!(
        message("OFF -3 1 0\n"),
        "line 1: expected the vertex count, found \"-3\""
    );
}

#[test]
fn counts_beyond_the_file_fail_before_anything_is_read() {
    let start = Instant::now();
    assert_eq!(
        message("OFF\n4000000000 0 0\n0 0 0\n"),
        "header declares 4000000000 vertices but the file holds at most 1"
    );
    assert_eq!(
        message("OFF\n99999999999 0 0\n0 0 0\n"),
        format!(
            "header declares 99999999999 vertices, more than the {} a mesh can index",
            beltrami_halfedge::MAX_ELEMENTS
        )
    );
    assert_eq!(
        message("OFF\n1000000 0 0\n0 0 0\n1 0 0\n"),
        "header declares 1000000 vertices but the file holds at most 2"
    );
    assert_eq!(
        message("OFF\n3 3000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
        "header declares 3000000000 faces but the file holds at most 4"
    );
    assert!(start.elapsed().as_secs_f64() < 1.0);
}

#[test]
fn fewer_or_more_elements_than_declared() {
    // Long enough lines that the counts fit the file's size.
    let long = "OFF\n4 1 0\n0.00000 0.00000 0.00000\n1.00000 0.00000 0.00000\n\
                0.00000 1.00000 0.00000\n";
    assert_eq!(message(long), "the file ends in the middle of vertex 3");
    let long = "OFF\n3 2 0\n0.00000 0.00000 0.00000\n1.00000 0.00000 0.00000\n\
                0.00000 1.00000 0.00000\n3 0 1 2\n";
    assert_eq!(message(long), "the file ends in the middle of face 1");
    let extra = message(&format!("{TRIANGLE}\n# more\n3 2 1 0\n"));
    assert_eq!(
        extra,
        "line 9: unexpected data after the 1 face the header declares"
    );
    // A vertex line more than declared shifts the face lines: "0 1 0" is a face of no
    // vertices (and a colour), and the real face is one too many.
    assert_eq!(
        message("OFF\n2 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
        "line 6: unexpected data after the 1 face the header declares"
    );
    assert_eq!(
        message("OFF\n2 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
        "line 6: face 1 refers to vertex 2, but only 2 vertices are defined"
    );
}

#[test]
fn bad_vertices_and_faces_name_their_line() {
    let cases = [
        (
            "OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n",
            "line 4: expected a number, found nothing",
        ),
        (
            "OFF\n3 1 0\n0 0 0\n1 0 zero\n0 1 0\n3 0 1 2\n",
            "line 4: expected a number, found \"zero\"",
        ),
        (
            "OFF\n3 1 0\n0 0 0\n1 0 0\n0 nan 0\n3 0 1 2\n",
            "line 5: vertex 2 has a non-finite coordinate (NaN)",
        ),
        (
            "OFF\n3 1 0\n0 0 0\n1e999 0 0\n0 1 0\n3 0 1 2\n",
            "line 4: vertex 1 has a non-finite coordinate (inf)",
        ),
        (
            "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n",
            "line 6: expected a vertex index, found nothing",
        ),
        (
            "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n",
            "line 6: expected a vertex index, found \"1.5\"",
        ),
        (
            "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\nthree 0 1 2\n",
            "line 6: expected the number of vertices of the face, found \"three\"",
        ),
        (
            "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
            "line 6: face 0 refers to vertex 3, but only 3 vertices are defined",
        ),
        (
            "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n",
            "line 6: face 0 refers to vertex -1, but only 3 vertices are defined",
        ),
    ];
    for (text, expected) in cases {
        let e = error(text);
        assert_eq!(e.to_string(), expected, "{text:?}");
        assert_eq!(e.line(), expected[5..6].parse().ok());
    }
}
