//! Every error path, with its exact message (snapshots in `snapshots/`).

mod common;

use std::path::Path;
use std::time::Instant;

use beltrami_halfedge::primitives;
use beltrami_io::{
    Encoding, IoError, MeshData, MeshFormat, PolygonList, Precision, VertexAttributes,
    WriteOptions, read_mesh, read_mesh_from, write_mesh_to, write_ply_to,
};
use common::fixture;
use glam::DVec3;
use insta::assert_snapshot;

fn read_error(bytes: &[u8], format: MeshFormat) -> IoError {
    match read_mesh_from(bytes, format) {
        Ok(mesh) => panic!("expected an error, read {mesh:?}"),
        Err(e) => e,
    }
}

fn ply(bytes: &[u8]) -> String {
    read_error(bytes, MeshFormat::Ply).to_string()
}

fn stl(bytes: &[u8]) -> String {
    read_error(bytes, MeshFormat::Stl).to_string()
}

fn obj(text: &str) -> String {
    read_error(text.as_bytes(), MeshFormat::Obj).to_string()
}

fn fixture_bytes(name: &str) -> Vec<u8> {
    std::fs::read(fixture(name)).expect("fixture")
}

/// A binary little-endian PLY: `header` lines between the format line and
/// `end_header`, then `payload`.
fn binary_ply(header: &str, payload: &[u8]) -> Vec<u8> {
    let mut bytes =
        format!("ply\nformat binary_little_endian 1.0\n{header}end_header\n").into_bytes();
    bytes.extend_from_slice(payload);
    bytes
}

const TRIANGLE_HEADER: &str = "element vertex 3\nproperty float x\nproperty float y\n\
                               property float z\nelement face 1\n\
                               property list uchar int vertex_indices\n";

fn ascii_ply(header: &str, body: &str) -> Vec<u8> {
    format!("ply\nformat ascii 1.0\n{header}end_header\n{body}").into_bytes()
}

fn floats(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

// ---------------------------------------------------------------- extensions, empty

#[test]
fn unknown_extension() {
    let e = read_mesh(Path::new("scan.xyz")).expect_err("unsupported");
    assert_snapshot!("unknown_extension", e.to_string());
    let e = read_mesh(Path::new("scan")).expect_err("no extension");
    assert_snapshot!("missing_extension", e.to_string());
}

#[test]
fn empty_files() {
    for format in [
        MeshFormat::Ply,
        MeshFormat::Stl,
        MeshFormat::Obj,
        MeshFormat::Off,
    ] {
        assert_eq!(read_error(b"", format).to_string(), "the file is empty");
    }
}

#[test]
fn missing_file_names_the_operation() {
    let e = read_mesh(Path::new("/nonexistent/dir/scan.ply")).expect_err("missing");
    assert!(
        e.to_string().starts_with("failed to read the file: "),
        "{e}"
    );
    assert!(matches!(
        e,
        IoError::Io {
            operation: "read the file",
            ..
        }
    ));
}

// ---------------------------------------------------------------- PLY

#[test]
fn ply_header_with_four_billion_vertices_fails_fast() {
    let start = Instant::now();
    let bytes = binary_ply(
        "element vertex 4000000000\nproperty float x\nproperty float y\nproperty float z\n",
        &[0u8; 144],
    );
    let e = read_error(&bytes, MeshFormat::Ply);
    assert!(start.elapsed().as_secs_f64() < 1.0);
    assert!(matches!(
        e,
        IoError::CountExceedsFile {
            declared: 4_000_000_000,
            available: 12,
            ..
        }
    ));
    assert_snapshot!("ply_four_billion_vertices_binary", e.to_string());

    let ascii = ascii_ply(
        "element vertex 4000000000\nproperty float x\nproperty float y\nproperty float z\n",
        "0 0 0\n1 0 0\n",
    );
    assert_snapshot!("ply_four_billion_vertices_ascii", ply(&ascii));
}

#[test]
fn ply_lying_face_count_fails_before_decoding() {
    let mut payload = floats(&[0.0; 9]);
    payload.extend_from_slice(&[3, 0, 0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0]);
    let header = TRIANGLE_HEADER.replace("element face 1", "element face 3000000000");
    assert_snapshot!("ply_lying_face_count", ply(&binary_ply(&header, &payload)));
}

#[test]
fn ply_huge_count_of_an_element_without_properties_is_skipped() {
    // Nothing to read for such an element in binary: it must not loop or allocate.
    let start = Instant::now();
    let mut payload = floats(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    payload.extend_from_slice(&[3, 0, 0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0]);
    let header = format!("element nothing 4000000000\n{TRIANGLE_HEADER}");
    let mesh = read_mesh_from(&binary_ply(&header, &payload)[..], MeshFormat::Ply).expect("read");
    assert_eq!((mesh.positions.len(), mesh.faces.len()), (3, 1));
    assert!(start.elapsed().as_secs_f64() < 1.0);
}

#[test]
fn ply_truncated_binary() {
    let bytes = fixture_bytes("tetrahedron_le.ply");
    // Inside the last face: the header counts still fit, the record does not.
    assert_snapshot!(
        "ply_truncated_binary_in_face",
        ply(&bytes[..bytes.len() - 5])
    );
    // Inside the vertices: the declared vertices cannot fit.
    let header_end = bytes.len() - 4 * 24 - 4 * 13;
    assert_snapshot!(
        "ply_truncated_binary_in_vertices",
        ply(&bytes[..header_end + 50])
    );
}

#[test]
fn ply_truncated_big_endian_matches_little_endian() {
    let le = fixture_bytes("tetrahedron_le.ply");
    let be = fixture_bytes("tetrahedron_be.ply");
    assert_eq!(ply(&le[..le.len() - 5]), ply(&be[..be.len() - 5]));
}

#[test]
fn ply_truncated_ascii() {
    let bytes = fixture_bytes("tetrahedron_ascii.ply");
    let text = String::from_utf8(bytes).expect("text");
    let cut: String =
        text.lines()
            .take(text.lines().count() - 2)
            .fold(String::new(), |mut s, line| {
                s.push_str(line);
                s.push('\n');
                s
            });
    assert_snapshot!("ply_truncated_ascii_lines", ply(cut.as_bytes()));
    // Cut inside the last line.
    let partial = &text[..text.len() - 3];
    assert_snapshot!("ply_truncated_ascii_mid_line", ply(partial.as_bytes()));
}

#[test]
fn ply_nan_coordinate() {
    let payload = floats(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, f32::NAN, 0.0]);
    let mut payload = payload;
    payload.extend_from_slice(&[3, 0, 0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0]);
    assert_snapshot!(
        "ply_nan_binary",
        ply(&binary_ply(TRIANGLE_HEADER, &payload))
    );

    let body = "0 0 0\n1 0 0\n0 1e999 0\n3 0 1 2\n";
    assert_snapshot!("ply_inf_ascii", ply(&ascii_ply(TRIANGLE_HEADER, body)));
    let body = "0 0 0\n1 0 0\n0 nan 0\n3 0 1 2\n";
    assert_snapshot!("ply_nan_word_ascii", ply(&ascii_ply(TRIANGLE_HEADER, body)));
}

#[test]
fn ply_garbage_bytes() {
    let mut rng = common::Lcg(3);
    let garbage: Vec<u8> = (0..1024).map(|_| rng.next_u64() as u8).collect();
    assert_snapshot!("ply_garbage", ply(&garbage));
    // Valid magic, then garbage.
    let mut bytes = b"ply\n".to_vec();
    bytes.extend_from_slice(&garbage);
    assert!(matches!(
        read_error(&bytes, MeshFormat::Ply),
        IoError::PlyHeader { .. }
    ));
}

#[test]
fn ply_malformed_header() {
    let bytes = b"ply\nformat ascii 1.0\nelemnt vertex 3\nend_header\n";
    assert_snapshot!("ply_header_unknown_keyword", ply(bytes));
    let bytes = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n";
    assert_snapshot!("ply_header_no_end", ply(bytes));
    let bytes = b"ply\nelement vertex 0\nend_header\n";
    assert_snapshot!("ply_header_no_format", ply(bytes));
    let bytes = b"ply\nformat ascii 1.0\nelement vertex 99999999999999999999999\nend_header\n";
    assert_snapshot!("ply_header_count_overflow", ply(bytes));
}

#[test]
fn ply_wrong_schema() {
    let no_vertex = ascii_ply(
        "element face 0\nproperty list uchar int vertex_indices\n",
        "",
    );
    assert_snapshot!("ply_no_vertex_element", ply(&no_vertex));

    let no_z = ascii_ply(
        "element vertex 1\nproperty float x\nproperty float y\n",
        "0 0\n",
    );
    assert_snapshot!("ply_no_z", ply(&no_z));

    let list_x = ascii_ply(
        "element vertex 1\nproperty list uchar float x\nproperty float y\nproperty float z\n",
        "1 0 0 0\n",
    );
    assert_snapshot!("ply_list_where_x_should_be", ply(&list_x));

    let float_indices = ascii_ply(
        &TRIANGLE_HEADER.replace("list uchar int", "list uchar float"),
        "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    );
    assert_snapshot!("ply_float_face_indices", ply(&float_indices));

    let scalar_indices = ascii_ply(
        &TRIANGLE_HEADER.replace("list uchar int", "int"),
        "0 0 0\n1 0 0\n0 1 0\n3\n",
    );
    assert_snapshot!("ply_scalar_face_indices", ply(&scalar_indices));

    let no_indices = ascii_ply(
        &TRIANGLE_HEADER.replace("vertex_indices", "corners"),
        "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    );
    assert_snapshot!("ply_no_vertex_indices", ply(&no_indices));
}

#[test]
fn ply_bad_values() {
    let body = "0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n";
    assert_snapshot!(
        "ply_float_in_index_list",
        ply(&ascii_ply(TRIANGLE_HEADER, body))
    );
    let body = "0 0 0\n1 0\n0 1 0\n3 0 1 2\n";
    assert_snapshot!("ply_too_few_values", ply(&ascii_ply(TRIANGLE_HEADER, body)));
    let body = "0 0 0\n1 0 0\n0 1 0\n3 0 1\n";
    assert_snapshot!("ply_short_list", ply(&ascii_ply(TRIANGLE_HEADER, body)));
    let body = "0 0 0\n1 x 0\n0 1 0\n3 0 1 2\n";
    assert_snapshot!("ply_word_in_vertex", ply(&ascii_ply(TRIANGLE_HEADER, body)));

    let header = TRIANGLE_HEADER.replace("list uchar int", "list char int");
    let mut payload = floats(&[0.0; 9]);
    payload.push(0xff); // count -1
    payload.extend_from_slice(&[0; 12]);
    assert_snapshot!(
        "ply_negative_list_length",
        ply(&binary_ply(&header, &payload))
    );
}

#[test]
fn ply_face_indices() {
    let body = "0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n";
    assert_snapshot!(
        "ply_negative_index_ascii",
        ply(&ascii_ply(TRIANGLE_HEADER, body))
    );

    let header = TRIANGLE_HEADER.replace("element face 1", "element face 2");
    let body = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 7\n";
    assert_snapshot!(
        "ply_index_out_of_range_ascii",
        ply(&ascii_ply(&header, body))
    );

    let mut payload = floats(&[0.0; 9]);
    payload.extend_from_slice(&[3, 0, 0, 0, 0, 1, 0, 0, 0, 3, 0, 0, 0]);
    assert_snapshot!(
        "ply_index_out_of_range_binary",
        ply(&binary_ply(TRIANGLE_HEADER, &payload))
    );
}

#[test]
fn ply_degenerate_faces_pass_through() {
    let header = TRIANGLE_HEADER.replace("element face 1", "element face 3");
    let body = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n2 0 1\n3 0 0 1\n";
    let mesh = read_mesh_from(&ascii_ply(&header, body)[..], MeshFormat::Ply).expect("read");
    assert_eq!(mesh.faces.get(1), Some(&[0, 1][..]));
    assert_eq!(mesh.faces.get(2), Some(&[0, 0, 1][..]));
}

#[test]
fn ply_unknown_elements_and_properties_are_ignored() {
    let header = "element vertex 3\nproperty uchar red\nproperty double x\nproperty short y\n\
                  property list uchar float uv\nproperty int z\nproperty float quality\n\
                  element material 2\nproperty list ushort uchar name\nproperty uint id\n\
                  element face 1\nproperty uchar flags\nproperty list ushort uint vertex_index\n\
                  element edge 1\nproperty int vertex1\nproperty int vertex2\n";
    let body = "9 0.5 1 2 0.1 0.2 3 0.9\n9 1.5 2 2 0.1 0.2 3 0.9\n9 2.5 3 2 0.1 0.2 3 0.9\n\
                2 65 66 7\n1 2 3 4 5 6\n\
                7 3 0 1 2\n0 1\n";
    let mesh = read_mesh_from(&ascii_ply(header, body)[..], MeshFormat::Ply).expect("ascii");
    assert_eq!(
        mesh.positions,
        [
            DVec3::new(0.5, 1.0, 3.0),
            DVec3::new(1.5, 2.0, 3.0),
            DVec3::new(2.5, 3.0, 3.0)
        ]
    );
    assert_eq!(mesh.faces.get(0), Some(&[0, 1, 2][..]));

    // The same in big-endian binary.
    let mut payload = Vec::new();
    for (x, y) in [(0.5f64, 1i16), (1.5, 2), (2.5, 3)] {
        payload.push(9u8);
        payload.extend_from_slice(&x.to_be_bytes());
        payload.extend_from_slice(&y.to_be_bytes());
        payload.push(2);
        payload.extend_from_slice(&0.1f32.to_be_bytes());
        payload.extend_from_slice(&0.2f32.to_be_bytes());
        payload.extend_from_slice(&3i32.to_be_bytes());
        payload.extend_from_slice(&0.9f32.to_be_bytes());
    }
    for _ in 0..2 {
        payload.extend_from_slice(&2u16.to_be_bytes());
        payload.extend_from_slice(b"ab");
        payload.extend_from_slice(&1u32.to_be_bytes());
    }
    payload.push(7);
    payload.extend_from_slice(&3u16.to_be_bytes());
    for i in 0u32..3 {
        payload.extend_from_slice(&i.to_be_bytes());
    }
    payload.extend_from_slice(&[0; 8]);
    let mut bytes = format!("ply\nformat binary_big_endian 1.0\n{header}end_header\n").into_bytes();
    bytes.extend_from_slice(&payload);
    let binary = read_mesh_from(&bytes[..], MeshFormat::Ply).expect("binary");
    assert_eq!(binary, mesh);
}

#[test]
fn ply_crlf_comments_and_obj_info_are_accepted() {
    let text = "ply\r\nformat ascii 1.0\r\ncomment made by hand\r\nobj_info scanner 7\r\n\
                element vertex 3\r\nproperty float x\r\nproperty float y\r\nproperty float z\r\n\
                element face 1\r\nproperty list uchar uint vertex_indices\r\nend_header\r\n\
                0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n";
    let mesh = read_mesh_from(text.as_bytes(), MeshFormat::Ply).expect("read");
    assert_eq!(mesh.positions[1], DVec3::X);
    assert_eq!(mesh.faces.get(0), Some(&[0, 1, 2][..]));
}

// ---------------------------------------------------------------- STL

fn binary_stl(count: u32, triangles: &[[f32; 9]]) -> Vec<u8> {
    let mut bytes = vec![b' '; 80];
    bytes.extend_from_slice(&count.to_le_bytes());
    for t in triangles {
        bytes.extend_from_slice(&floats(&[0.0; 3]));
        bytes.extend_from_slice(&floats(t));
        bytes.extend_from_slice(&[0, 0]);
    }
    bytes
}

const ASCII_FACET: &str = "solid t\n  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      \
                           vertex 1 0 0\n      vertex 0 1 0\n    endloop\n  endfacet\nendsolid t\n";

#[test]
fn stl_binary_count_disagrees_with_length() {
    let bytes = binary_stl(1000, &[[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]; 12]);
    let e = read_error(&bytes, MeshFormat::Stl);
    assert!(matches!(
        e,
        IoError::StlTriangleCount {
            declared: 1000,
            file_length: 684
        }
    ));
    assert_snapshot!("stl_wrong_count", e.to_string());

    // A binary header that starts with "solid" is not taken for ascii.
    let mut solid = bytes;
    solid[..11].copy_from_slice(b"solid cube ");
    assert_eq!(stl(&solid), e.to_string());

    // Truncated: one byte short of the declared triangles.
    let cube = fixture_bytes("cube_binary.stl");
    assert_snapshot!("stl_truncated_binary", stl(&cube[..cube.len() - 1]));
}

#[test]
fn stl_too_short() {
    assert_snapshot!("stl_too_short", stl(b"not an stl file"));
}

#[test]
fn stl_garbage_bytes() {
    let mut rng = common::Lcg(5);
    let garbage: Vec<u8> = (0..1000).map(|_| rng.next_u64() as u8).collect();
    assert!(matches!(
        read_error(&garbage, MeshFormat::Stl),
        IoError::StlTriangleCount { .. }
    ));
}

#[test]
fn stl_ascii_broken_facets() {
    let missing_endloop = ASCII_FACET.replace("    endloop\n", "");
    assert_snapshot!("stl_ascii_missing_endloop", stl(missing_endloop.as_bytes()));
    let bad_number = ASCII_FACET.replace("vertex 1 0 0", "vertex 1.0.0 0 0");
    assert_snapshot!("stl_ascii_bad_number", stl(bad_number.as_bytes()));
    let four = ASCII_FACET.replace("vertex 0 1 0", "vertex 0 1 0\n      vertex 1 1 0");
    assert_snapshot!("stl_ascii_four_vertices", stl(four.as_bytes()));
    let truncated = &ASCII_FACET[..ASCII_FACET.find("vertex 1 0 0").expect("vertex")];
    assert_snapshot!("stl_ascii_truncated", stl(truncated.as_bytes()));
    let no_endsolid = ASCII_FACET.replace("endsolid t\n", "");
    assert_snapshot!("stl_ascii_no_endsolid", stl(no_endsolid.as_bytes()));
    let trailing = format!("{ASCII_FACET}garbage\n");
    assert_snapshot!("stl_ascii_trailing_garbage", stl(trailing.as_bytes()));
}

#[test]
fn stl_ascii_variants_are_accepted() {
    // Upper case keywords, several solids, odd whitespace, unnamed solids, NaN normal.
    let text = format!(
        "  SOLID\r\nFACET NORMAL nan nan nan\r\n OUTER LOOP\r\n VERTEX 0 0 0\r\n VERTEX 1 0 0\r\n\
         VERTEX 0 1 0\r\n ENDLOOP\r\n ENDFACET\r\nENDSOLID\r\n{}",
        ASCII_FACET.replace("vertex 0 1 0", "vertex 0 -1 0")
    );
    let mesh = read_mesh_from(text.as_bytes(), MeshFormat::Stl).expect("read");
    assert_eq!((mesh.positions.len(), mesh.faces.len()), (4, 2));
    assert_eq!(mesh.faces.get(1), Some(&[0, 1, 3][..]));
}

#[test]
fn stl_nan_coordinates() {
    let nan = ASCII_FACET.replace("vertex 1 0 0", "vertex 1 NaN 0");
    assert_snapshot!("stl_ascii_nan", stl(nan.as_bytes()));
    let ok = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let bad = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, f32::INFINITY, 0.0];
    assert_snapshot!("stl_binary_inf", stl(&binary_stl(2, &[ok, bad])));
}

#[test]
fn stl_welds_signed_zeros() {
    let a = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let b = [-0.0, -0.0, 0.0, 0.0, 1.0, -0.0, -1.0, 0.0, 0.0];
    let mesh = read_mesh_from(&binary_stl(2, &[a, b])[..], MeshFormat::Stl).expect("read");
    assert_eq!(mesh.positions.len(), 4);
    assert_eq!(mesh.faces.get(1), Some(&[0, 2, 3][..]));
    let coordinates = mesh.positions.iter().flat_map(|p| p.to_array());
    assert!(
        coordinates
            .clone()
            .all(|c| c != 0.0 || c.is_sign_positive())
    );
    assert!(mesh.positions[0].x.is_sign_positive());
}

// ---------------------------------------------------------------- OBJ

#[test]
fn obj_face_indices() {
    let zero = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n";
    assert_snapshot!("obj_index_zero", obj(zero));
    let beyond = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n\nf 1 2 9\n";
    assert_snapshot!("obj_index_beyond_total", obj(beyond));
    let negative = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\nv 1 1 1\n";
    assert_snapshot!("obj_negative_index_beyond_defined", obj(negative));
    let huge = "v 0 0 0\nf 1 2 99999999999\n";
    assert_snapshot!("obj_index_beyond_u32", obj(huge));
    let word = "v 0 0 0\nf 1 a/1 1\n";
    assert_snapshot!("obj_index_not_a_number", obj(word));
    let empty_index = "v 0 0 0\nf 1 /1/1 1\n";
    assert_snapshot!("obj_index_missing", obj(empty_index));
}

#[test]
fn obj_forward_references_and_degenerate_faces_pass() {
    let text = "f 1 2 3\nf 1 2\nf 1 1 2\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n";
    let mesh = read_mesh_from(text.as_bytes(), MeshFormat::Obj).expect("read");
    assert_eq!(mesh.faces.len(), 4);
    assert_eq!(mesh.faces.get(3), Some(&[0, 1, 2][..]));
}

#[test]
fn obj_bad_vertices() {
    assert_snapshot!("obj_nan", obj("v 0 0 0\nv 1 NaN 0\n"));
    assert_snapshot!("obj_inf", obj("v 0 0 0\nv 1 0 -inf\n"));
    assert_snapshot!("obj_word_in_vertex", obj("# c\nv 1 x 3\n"));
    assert_snapshot!("obj_too_few_coordinates", obj("v 1 2\n"));
}

#[test]
fn obj_garbage_bytes() {
    let mut rng = common::Lcg(11);
    let garbage: Vec<u8> = (0..1000).map(|_| rng.next_u64() as u8).collect();
    assert!(matches!(
        read_error(&garbage, MeshFormat::Obj),
        IoError::NotText { .. } | IoError::Syntax { .. }
    ));
    assert_snapshot!("obj_binary_data", obj("v 0 0 0\nhello\u{0}\u{1}world\n"));
}

#[test]
fn obj_ignores_other_statements_and_latin1_comments() {
    let mut text = b"# Messung \xe4\xf6\xfc (latin-1)\nmtllib a.mtl\no part\ng g1\ns 1\nusemtl m\n\
                     v 0 0 0 1\nv 1 0 0 0.5 0.5 0.5\nv 0 1 0\nvt 0 0\nvn 0 0 1\nvp 0.5\n\
                     l 1 2\nfoo bar\n\n   \t\nf 1/1/1 2//1 3/1\n"
        .to_vec();
    text.extend_from_slice(b"f 1 2 3 # a trailing comment\nv 1 1 1#comment\n");
    let mesh = read_mesh_from(&text[..], MeshFormat::Obj).expect("read");
    assert_eq!((mesh.positions.len(), mesh.faces.len()), (4, 2));
    assert_eq!(mesh.positions[3], DVec3::ONE);
}

// ---------------------------------------------------------------- writing

fn triangle() -> MeshData {
    primitives::triangle()
}

fn ply_write_error(
    mesh: &MeshData,
    attributes: &VertexAttributes,
    options: &WriteOptions,
) -> String {
    let mut sink = Vec::new();
    write_ply_to(&mut sink, mesh, attributes, options)
        .expect_err("must fail")
        .to_string()
}

#[test]
fn write_attribute_errors() {
    let mesh = triangle();
    let options = WriteOptions::default();
    let short = VertexAttributes {
        scalars: vec![("deviation".to_owned(), vec![0.0, 1.0])],
        colors: None,
    };
    assert_snapshot!(
        "write_attribute_length",
        ply_write_error(&mesh, &short, &options)
    );
    let colors = VertexAttributes {
        scalars: vec![],
        colors: Some(vec![[0, 0, 0]; 4]),
    };
    assert_snapshot!(
        "write_color_length",
        ply_write_error(&mesh, &colors, &options)
    );
    for (case, name) in [
        ("write_name_space", "mean curvature"),
        ("write_name_digit", "2nd"),
        ("write_name_reserved", "x"),
        ("write_name_empty", ""),
    ] {
        let named = VertexAttributes {
            scalars: vec![(name.to_owned(), vec![0.0; 3])],
            colors: None,
        };
        assert_snapshot!(case, ply_write_error(&mesh, &named, &options));
    }
    let twice = VertexAttributes {
        scalars: vec![
            ("d".to_owned(), vec![0.0; 3]),
            ("d".to_owned(), vec![0.0; 3]),
        ],
        colors: None,
    };
    assert_snapshot!("write_name_twice", ply_write_error(&mesh, &twice, &options));

    let nan = VertexAttributes {
        scalars: vec![("d".to_owned(), vec![0.0, f64::NAN, 0.0])],
        colors: None,
    };
    let ascii = options.encoding(Encoding::Ascii);
    assert_snapshot!(
        "write_nan_attribute_ascii",
        ply_write_error(&mesh, &nan, &ascii)
    );
    // Binary holds NaN fine.
    write_ply_to(&mut Vec::new(), &mesh, &nan, &options).expect("binary NaN attribute");
}

#[test]
fn write_mesh_errors() {
    let mut nan = triangle();
    nan.positions[2].y = f64::NAN;
    let mut sink = Vec::new();
    for format in [
        MeshFormat::Ply,
        MeshFormat::Stl,
        MeshFormat::Obj,
        MeshFormat::Off,
    ] {
        let e = write_mesh_to(&mut sink, &nan, format, &WriteOptions::default()).expect_err("nan");
        assert_eq!(e.to_string(), "vertex 2 has a non-finite coordinate (NaN)");
    }

    let mut dangling = triangle();
    dangling.faces = PolygonList::from_triangles(&[[0, 1, 2], [0, 2, 3]]);
    let e = write_mesh_to(
        &mut sink,
        &dangling,
        MeshFormat::Obj,
        &WriteOptions::default(),
    )
    .expect_err("index");
    assert_snapshot!("write_index_out_of_range", e.to_string());

    let mut huge = triangle();
    huge.positions[1].x = 1e39;
    let e = write_mesh_to(&mut sink, &huge, MeshFormat::Stl, &WriteOptions::default())
        .expect_err("range");
    assert_snapshot!("write_beyond_f32", e.to_string());
    let single = WriteOptions::default().precision(Precision::Single);
    assert!(write_mesh_to(&mut sink, &huge, MeshFormat::Ply, &single).is_err());
    assert!(write_mesh_to(&mut sink, &huge, MeshFormat::Ply, &WriteOptions::default()).is_ok());

    // Corners that round to one point in f32 (below its range, or closer than it
    // resolves) would be joined by a reader: refused for STL, with the face and the
    // pair; PLY keeps them apart by index.
    for (scale, offset) in [(1e-46, None), (-1e-46, None), (1.0, Some(1e-12))] {
        let mut close = triangle();
        for p in &mut close.positions {
            *p *= scale;
        }
        if scale < 0.0 {
            // Corners at −0 and +0 in f32 (vertex 1 at +1e-46, vertex 0 at 0): one
            // point to a reader.
            close.positions[0] = DVec3::new(-0.0, 0.0, 0.0);
            close.positions[1] = -close.positions[1];
        }
        if let Some(offset) = offset {
            close.positions[2] = close.positions[1] + DVec3::new(offset, 0.0, 0.0);
        }
        let e = write_mesh_to(&mut sink, &close, MeshFormat::Stl, &WriteOptions::default())
            .expect_err("coincide");
        assert!(
            matches!(e, IoError::CornersCoincide { face: 0, .. }),
            "{scale} {offset:?}: {e}"
        );
        assert!(e.to_string().starts_with("face 0: vertices "), "{e}");
        assert!(
            write_mesh_to(&mut sink, &close, MeshFormat::Ply, &WriteOptions::default()).is_ok()
        );
    }

    let big_endian = WriteOptions::default().encoding(Encoding::BinaryBigEndian);
    let e =
        write_mesh_to(&mut sink, &triangle(), MeshFormat::Stl, &big_endian).expect_err("encoding");
    assert_snapshot!("write_stl_big_endian", e.to_string());
}

#[test]
fn errors_report_their_line() {
    let e = read_error(b"v 0 0 0\nf 1 2 0\n", MeshFormat::Obj);
    assert_eq!(e.line(), Some(2));
    let e = read_error(b"", MeshFormat::Obj);
    assert_eq!(e.line(), None);
}
