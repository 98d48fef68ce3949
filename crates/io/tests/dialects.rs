//! Files as they come from the wild: byte order marks, classic Mac OS line endings,
//! OBJ line continuations, points and polylines, files of one format named as
//! another, PLY files that hold more or other than their header declares, blank files.
//! Each of these was once read as a different mesh than the file holds.

use beltrami_io::{IoError, MeshData, MeshFormat, PolygonList, declared_counts, read_mesh_from};
use glam::DVec3;

fn read(bytes: &[u8], format: MeshFormat) -> MeshData {
    match read_mesh_from(bytes, format) {
        Ok(mesh) => mesh,
        Err(e) => panic!("{format}: {e}"),
    }
}

fn error(bytes: &[u8], format: MeshFormat) -> IoError {
    match read_mesh_from(bytes, format) {
        Ok(mesh) => panic!("{format}: expected an error, read {mesh:?}"),
        Err(e) => e,
    }
}

/// The unit triangle, vertices 0 (origin), 1 (x) and 2 (y).
fn triangle() -> MeshData {
    MeshData {
        positions: vec![DVec3::ZERO, DVec3::X, DVec3::Y],
        faces: PolygonList::from_triangles(&[[0, 1, 2]]),
    }
}

const BOM: &str = "\u{feff}";

const OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

const PLY_HEADER: &str = "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\n\
                          property double y\nproperty double z\nelement face 1\n\
                          property list uchar int vertex_indices\nend_header\n";

/// The triangle in ascii PLY: the header (9 lines), vertices on lines 10 to 12, the
/// face on line 13.
fn ply_ascii() -> String {
    format!("{PLY_HEADER}0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
}

/// The triangle in binary PLY.
fn ply_binary(big_endian: bool) -> Vec<u8> {
    let format = if big_endian {
        "binary_big_endian"
    } else {
        "binary_little_endian"
    };
    let mut bytes = PLY_HEADER.replace("ascii", format).into_bytes();
    for p in triangle().positions {
        for c in p.to_array() {
            bytes.extend(if big_endian {
                c.to_be_bytes()
            } else {
                c.to_le_bytes()
            });
        }
    }
    bytes.push(3);
    for i in 0i32..3 {
        bytes.extend(if big_endian {
            i.to_be_bytes()
        } else {
            i.to_le_bytes()
        });
    }
    bytes
}

const STL: &str = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
                   vertex 0 1 0\nendloop\nendfacet\nendsolid t\n";

// ---------------------------------------------------------------- byte order marks

#[test]
fn byte_order_marks_are_skipped() {
    assert_eq!(
        read(format!("{BOM}{OBJ}").as_bytes(), MeshFormat::Obj),
        triangle()
    );
    assert_eq!(
        read(format!("{BOM}{}", ply_ascii()).as_bytes(), MeshFormat::Ply),
        triangle()
    );
    let mut binary = BOM.as_bytes().to_vec();
    binary.extend(ply_binary(false));
    assert_eq!(read(&binary, MeshFormat::Ply), triangle());
    assert_eq!(
        read(format!("{BOM}{STL}").as_bytes(), MeshFormat::Stl),
        triangle()
    );
    // Line numbers do not move: the bad number is on line 2.
    let e = error(
        format!("{BOM}v 0 0 0\nv 1 x 0\n").as_bytes(),
        MeshFormat::Obj,
    );
    assert_eq!(e.to_string(), "line 2: expected a number, found \"x\"");
}

// ---------------------------------------------------------------- line endings

#[test]
fn classic_mac_line_endings() {
    let obj = OBJ.replace('\n', "\r");
    assert_eq!(read(obj.as_bytes(), MeshFormat::Obj), triangle());
    let stl = STL.replace('\n', "\r");
    assert_eq!(read(stl.as_bytes(), MeshFormat::Stl), triangle());
    // Errors name the right line.
    let bad = stl.replace("vertex 1 0 0", "vertex 1.0.0 0 0");
    let e = error(bad.as_bytes(), MeshFormat::Stl);
    assert_eq!(e.to_string(), "line 5: expected a number, found \"1.0.0\"");
    let bad = obj.replace("v 0 1 0", "v 0 1");
    let e = error(bad.as_bytes(), MeshFormat::Obj);
    assert_eq!(e.to_string(), "line 3: expected a number, found nothing");
    // Mixed endings, as left by copying between systems.
    let mixed = "v 0 0 0\r\nv 1 0 0\rv 0 1 0\nf 1 2 3";
    assert_eq!(read(mixed.as_bytes(), MeshFormat::Obj), triangle());
    // PLY headers are parsed line by line on `\n`: a clear error instead.
    let ply = ply_ascii().replace('\n', "\r");
    let e = error(ply.as_bytes(), MeshFormat::Ply);
    assert_eq!(
        e.to_string(),
        "line 1: invalid ply header: the lines end with a bare carriage return (classic Mac OS); \
         convert the line endings to \\n or \\r\\n"
    );
    // Windows endings are fine everywhere.
    let crlf = ply_ascii().replace('\n', "\r\n");
    assert_eq!(read(crlf.as_bytes(), MeshFormat::Ply), triangle());
}

// ---------------------------------------------------------------- other formats as OBJ

#[test]
fn files_of_other_formats_are_not_read_as_empty_obj() {
    let cases = [
        (
            ply_ascii(),
            "line 1: \"ply\" is not an obj statement; is this a ply file? rename it to .ply",
        ),
        (
            STL.to_owned(),
            "line 1: \"solid\" is not an obj statement; is this an stl file? rename it to .stl",
        ),
        (
            "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n".to_owned(),
            "line 1: \"OFF\" is not an obj statement; is this an off file? rename it to .off",
        ),
        (
            "# points\n\n0.5 1 2\n1 2 3\n".to_owned(),
            "line 3: \"0.5\" is not an obj statement, and the file has no vertex (\"v\") lines",
        ),
        (
            "hello world\nf 1 2 3\n".to_owned(),
            "line 1: \"hello\" is not an obj statement, and the file has no vertex (\"v\") lines",
        ),
    ];
    for (text, message) in cases {
        let e = error(text.as_bytes(), MeshFormat::Obj);
        assert_eq!(e.to_string(), message);
        assert_eq!(e.line(), message[5..6].parse().ok());
    }
    // Statements of the specification that are not used are no sign of another
    // format: a file with them and no vertices is an empty mesh.
    let mesh = read(
        b"# normals only\nvn 0 0 1\ng part\nusemtl m\n",
        MeshFormat::Obj,
    );
    assert_eq!(mesh, MeshData::default());
    // In a file with vertices, words that are no statement are ignored.
    let mesh = read(
        format!("{OBJ}vertex_color 1 0 0\n").as_bytes(),
        MeshFormat::Obj,
    );
    assert_eq!(mesh, triangle());
}

// ---------------------------------------------------------------- OBJ statements

#[test]
fn obj_line_continuations_join_lines() {
    let text = "v 0 0 0\nv 1 \\\n  0 0\nv 0 1 0\nf 1 \\\r\n2 \\\n 3\n";
    assert_eq!(read(text.as_bytes(), MeshFormat::Obj), triangle());
    // A comment that ends with a backslash (a Windows path) continues nothing.
    let text = format!("# exported from C:\\scans\\\n{OBJ}");
    assert_eq!(read(text.as_bytes(), MeshFormat::Obj), triangle());
    // A statement's errors name its first line.
    let e = error(b"v 0 0 0\nv 1 \\\n x 0\n", MeshFormat::Obj);
    assert_eq!(e.to_string(), "line 2: expected a number, found \"x\"");
    // A backslash on the last line continues on nothing.
    let text = format!("{OBJ}f 1 2 3 \\");
    assert_eq!(read(text.as_bytes(), MeshFormat::Obj).faces.len(), 2);
}

#[test]
fn obj_points_and_polylines_read_as_vertices_without_faces() {
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\np 1 2 3\nl 1 2 3 1\nl 1/1 2/2\n";
    let mesh = read(text.as_bytes(), MeshFormat::Obj);
    assert_eq!(mesh.positions, triangle().positions);
    assert!(mesh.faces.is_empty());
}

// ---------------------------------------------------------------- blank files

#[test]
fn blank_files_are_empty_in_every_format() {
    for format in [
        MeshFormat::Ply,
        MeshFormat::Stl,
        MeshFormat::Obj,
        MeshFormat::Off,
    ] {
        for text in ["", " ", "\n\n", " \r\n\t\n", "\u{feff}", "\u{feff}\n  "] {
            let e = error(text.as_bytes(), format);
            assert!(matches!(e, IoError::Empty), "{format} {text:?}: {e}");
        }
    }
    // The same for the counts a file declares.
    let dir = tempfile::tempdir().expect("temporary directory");
    for name in ["blank.ply", "blank.stl", "blank.obj", "blank.off"] {
        let path = dir.path().join(name);
        std::fs::write(&path, " \n\t\r\n").expect("write");
        let e = declared_counts(&path).expect_err("blank");
        assert!(matches!(e, IoError::Empty), "{name}: {e}");
    }
    // A comment is content: an OBJ file of comments is an empty mesh, not an empty file.
    assert_eq!(read(b"# nothing\n", MeshFormat::Obj), MeshData::default());
}

// ---------------------------------------------------------------- PLY

#[test]
fn ply_data_beyond_the_declared_counts_is_an_error() {
    let extra_face = format!("{}3 2 1 0\n", ply_ascii());
    assert_eq!(
        error(extra_face.as_bytes(), MeshFormat::Ply).to_string(),
        "line 14: unexpected data after the 1 face the header declares"
    );
    // One vertex more than declared: its line is no face.
    let extra_vertex = ply_ascii().replace("element vertex 3", "element vertex 2");
    assert_eq!(
        error(extra_vertex.as_bytes(), MeshFormat::Ply).to_string(),
        "line 12: cannot read face 0: the line holds 3 values, but the properties of the \
         element take 1"
    );
    // Values beyond the properties of a line.
    let extra_value = ply_ascii().replace("1 0 0\n", "1 0 0 7\n");
    assert_eq!(
        error(extra_value.as_bytes(), MeshFormat::Ply).to_string(),
        "line 11: cannot read vertex 1: the line holds 4 values, but the properties of the \
         element take 3"
    );
    // Whitespace after the last line is no data.
    let padded = format!("{}\n  \n\t\r\n", ply_ascii());
    assert_eq!(read(padded.as_bytes(), MeshFormat::Ply), triangle());

    for big_endian in [false, true] {
        let mut bytes = ply_binary(big_endian);
        assert_eq!(read(&bytes, MeshFormat::Ply), triangle());
        bytes.push(b'\n');
        assert_eq!(
            error(&bytes, MeshFormat::Ply).to_string(),
            "1 unexpected byte after the 1 face the header declares"
        );
        // A second face the header does not declare.
        bytes.pop();
        bytes.extend([3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]);
        assert_eq!(
            error(&bytes, MeshFormat::Ply).to_string(),
            "13 unexpected bytes after the 1 face the header declares"
        );
    }
}

/// Five vertices and one element of triangle strips with the index list `strips`.
fn strips_ply(strips: &str) -> String {
    let count = strips.split_whitespace().count();
    format!(
        "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n\
         property float z\nelement tristrips 1\nproperty list int int vertex_indices\n\
         end_header\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n2 2 0\n{count} {strips}\n"
    )
}

#[test]
fn ply_triangle_strips_are_read() {
    // Two strips; the second triangle of the first is turned to keep the orientation.
    let mesh = read(strips_ply("0 1 2 3 -1 2 3 4").as_bytes(), MeshFormat::Ply);
    assert_eq!(mesh.positions.len(), 5);
    assert_eq!(
        mesh.faces,
        PolygonList::from_triangles(&[[0, 1, 2], [2, 1, 3], [2, 3, 4]])
    );
    // Triangles with a repeated corner only join strips: skipped, parity kept.
    let mesh = read(strips_ply("0 1 2 2 3 4").as_bytes(), MeshFormat::Ply);
    assert_eq!(
        mesh.faces,
        PolygonList::from_triangles(&[[0, 1, 2], [3, 2, 4]])
    );
    // The same strips in binary.
    let header = strips_ply("")
        .replace("ascii", "binary_little_endian")
        .split("end_header\n")
        .next()
        .map(|h| format!("{h}end_header\n"))
        .expect("header");
    let mut bytes = header.into_bytes();
    for p in [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
        [2.0, 2.0, 0.0],
    ] {
        bytes.extend(p.iter().flat_map(|c| c.to_le_bytes()));
    }
    bytes.extend(8i32.to_le_bytes());
    for i in [0i32, 1, 2, 3, -1, 2, 3, 4] {
        bytes.extend(i.to_le_bytes());
    }
    let binary = read(&bytes, MeshFormat::Ply);
    assert_eq!(
        binary.faces,
        PolygonList::from_triangles(&[[0, 1, 2], [2, 1, 3], [2, 3, 4]])
    );
    // Indices are checked: -1 ends a strip, any other negative value is an error, and
    // so is an index that names no vertex.
    let e = error(strips_ply("0 1 -2 3").as_bytes(), MeshFormat::Ply);
    assert_eq!(
        e.to_string(),
        "line 15: cannot read tristrips 0: vertex index -2 (only -1, which ends a strip, may be negative)"
    );
    let e = error(strips_ply("0 1 5").as_bytes(), MeshFormat::Ply);
    assert_eq!(
        e.to_string(),
        "face 0 refers to vertex 5, but only 5 vertices are defined"
    );
}

#[test]
fn ply_faces_in_an_unsupported_element_are_an_error() {
    let text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                property float z\nelement range_grid 1\nproperty list uchar int vertex_indices\n\
                end_header\n0 0 0\n1 0 0\n0 1 0\n1 0\n";
    assert_eq!(
        error(text.as_bytes(), MeshFormat::Ply).to_string(),
        "element \"range_grid\" holds vertex indices but is no face element this reader \
         supports (\"face\", \"tristrips\")"
    );
    // Edges (a wireframe) are no faces: the file reads as vertices without faces.
    let edges = format!(
        "{}2 0 1\n",
        text.replace("range_grid", "edge")
            .strip_suffix("1 0\n")
            .expect("the range grid line")
    );
    let mesh = read(edges.as_bytes(), MeshFormat::Ply);
    assert_eq!((mesh.positions.len(), mesh.faces.len()), (3, 0));
}

#[test]
fn ply_names_declared_twice_are_an_error() {
    let twice_x = ply_ascii().replace(
        "property double y\n",
        "property double x\nproperty double y\n",
    );
    let message =
        "line 5: invalid ply header: property \"x\" of element \"vertex\" is declared twice";
    assert_eq!(
        error(twice_x.as_bytes(), MeshFormat::Ply).to_string(),
        message
    );
    // Binary (the fast vertex path) refuses the header the same way.
    let mut binary = ply_binary(false);
    let header_end = binary
        .windows(11)
        .position(|w| w == b"end_header\n")
        .expect("header")
        + 11;
    let header = String::from_utf8(binary[..header_end].to_vec())
        .expect("text")
        .replace(
            "property double y\n",
            "property double x\nproperty double y\n",
        );
    binary.splice(..header_end, header.into_bytes());
    assert_eq!(error(&binary, MeshFormat::Ply).to_string(), message);

    let twice_face = ply_ascii().replace(
        "end_header\n",
        "element face 0\nproperty list uchar int vertex_indices\nend_header\n",
    );
    assert_eq!(
        error(twice_face.as_bytes(), MeshFormat::Ply).to_string(),
        "line 9: invalid ply header: element \"face\" is declared twice"
    );
}
