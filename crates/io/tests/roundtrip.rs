//! Write then read: every format and encoding gives back what was written.

mod common;

use beltrami_halfedge::primitives;
use beltrami_io::{
    Encoding, MeshData, MeshFormat, PolygonList, Precision, VertexAttributes, WriteOptions,
    read_mesh, read_mesh_from, write_mesh, write_mesh_to, write_ply_to,
};
use common::{assert_bit_identical, assert_same_up_to_renumbering, f32_mesh, fixture, messy_mesh};
use glam::DVec3;

const ENCODINGS: [Encoding; 3] = [
    Encoding::Ascii,
    Encoding::BinaryLittleEndian,
    Encoding::BinaryBigEndian,
];

fn options(encoding: Encoding, precision: Precision) -> WriteOptions {
    WriteOptions::default()
        .encoding(encoding)
        .precision(precision)
}

fn through(mesh: &MeshData, format: MeshFormat, options: &WriteOptions) -> MeshData {
    let mut bytes = Vec::new();
    write_mesh_to(&mut bytes, mesh, format, options).expect("write");
    read_mesh_from(&bytes[..], format).expect("read back")
}

/// The mesh with every coordinate rounded to f32.
fn rounded(mesh: &MeshData) -> MeshData {
    f32_mesh(mesh)
}

fn primitives_list() -> Vec<MeshData> {
    vec![
        primitives::triangle(),
        primitives::tetrahedron(),
        primitives::cube(),
        primitives::cube_quads(),
        primitives::hexagon_fan(),
        primitives::grid(4, 3),
        primitives::torus(2.0, 0.5, 12, 8),
        primitives::icosphere(2),
    ]
}

#[test]
fn ply_double_round_trips_bit_for_bit_in_every_encoding() {
    let mut meshes = primitives_list();
    meshes.push(messy_mesh());
    for mesh in &meshes {
        for encoding in ENCODINGS {
            let back = through(mesh, MeshFormat::Ply, &options(encoding, Precision::Double));
            assert_bit_identical(&back, mesh);
        }
    }
}

#[test]
fn ply_single_precision_rounds_to_f32_exactly() {
    let mesh = MeshData {
        positions: messy_mesh()
            .positions
            .into_iter()
            .map(|p| p.clamp(DVec3::splat(-1e30), DVec3::splat(1e30)))
            .collect(),
        faces: messy_mesh().faces,
    };
    for encoding in ENCODINGS {
        let back = through(
            &mesh,
            MeshFormat::Ply,
            &options(encoding, Precision::Single),
        );
        assert_bit_identical(&back, &rounded(&mesh));
    }
}

#[test]
fn ply_header_declares_doubles_and_uchar_int_faces() {
    let mesh: MeshData = primitives::triangle();
    let mut bytes = Vec::new();
    write_ply_to(
        &mut bytes,
        &mesh,
        &VertexAttributes::default(),
        &options(Encoding::BinaryBigEndian, Precision::Double),
    )
    .expect("write");
    let text = String::from_utf8_lossy(&bytes);
    let header = &text[..text.find("end_header\n").expect("header") + 11];
    insta::assert_snapshot!("ply_header_binary_big_endian", header);
}

#[test]
fn ply_with_attributes_reads_back_ignoring_them() {
    let mesh = messy_mesh();
    let n = mesh.positions.len();
    let attributes = VertexAttributes {
        scalars: vec![
            (
                "deviation".to_owned(),
                (0..n).map(|i| i as f64 * 0.1).collect(),
            ),
            ("mean_curvature".to_owned(), vec![-1.5; n]),
        ],
        colors: Some((0..n).map(|i| [i as u8, 255 - i as u8, 7]).collect()),
    };
    for encoding in ENCODINGS {
        let mut bytes = Vec::new();
        write_ply_to(
            &mut bytes,
            &mesh,
            &attributes,
            &options(encoding, Precision::Double),
        )
        .expect("write");
        let text = String::from_utf8_lossy(&bytes);
        assert!(text.contains(
            "property double z\nproperty double deviation\nproperty double mean_curvature\n\
             property uchar red\nproperty uchar green\nproperty uchar blue\n"
        ));
        let back = read_mesh_from(&bytes[..], MeshFormat::Ply).expect("read back");
        assert_bit_identical(&back, &mesh);
    }
}

#[test]
fn ply_ascii_attributes_are_written_exactly() {
    let mesh: MeshData = primitives::triangle();
    let attributes = VertexAttributes {
        scalars: vec![("d".to_owned(), vec![0.1, -1e-300, 2.5])],
        colors: Some(vec![[1, 2, 3], [4, 5, 6], [7, 8, 9]]),
    };
    let mut bytes = Vec::new();
    write_ply_to(
        &mut bytes,
        &mesh,
        &attributes,
        &options(Encoding::Ascii, Precision::Double),
    )
    .expect("write");
    let text = String::from_utf8_lossy(&bytes);
    let body = &text[text.find("end_header\n").expect("header") + 11..];
    let first: Vec<&str> = body.lines().next().expect("a line").split(' ').collect();
    assert_eq!(first, ["0", "0", "0", "0.1", "1", "2", "3"]);
    let second = body.lines().nth(1).expect("a line");
    let value: f64 = second
        .split(' ')
        .nth(3)
        .expect("d")
        .parse()
        .expect("number");
    assert_eq!(value, -1e-300);
}

#[test]
fn ply_faces_longer_than_255_use_uint_counts() {
    let n = 300u32;
    let positions = (0..n)
        .map(|i| {
            let a = f64::from(i) * std::f64::consts::TAU / f64::from(n);
            DVec3::new(a.cos(), a.sin(), 0.0)
        })
        .collect();
    let ring: Vec<u32> = (0..n).collect();
    let mut faces = PolygonList::new();
    faces.push(&ring);
    let mesh = MeshData { positions, faces };
    for encoding in ENCODINGS {
        let mut bytes = Vec::new();
        write_mesh_to(
            &mut bytes,
            &mesh,
            MeshFormat::Ply,
            &options(encoding, Precision::Double),
        )
        .expect("write");
        assert!(String::from_utf8_lossy(&bytes).contains("property list uint int vertex_indices"));
        let back = read_mesh_from(&bytes[..], MeshFormat::Ply).expect("read back");
        assert_bit_identical(&back, &mesh);
    }
}

#[test]
fn obj_round_trips_exactly() {
    let mut meshes = primitives_list();
    meshes.push(messy_mesh());
    for mesh in &meshes {
        // The encoding is ignored: OBJ is text.
        for encoding in ENCODINGS {
            let back = through(mesh, MeshFormat::Obj, &options(encoding, Precision::Double));
            assert_bit_identical(&back, mesh);
        }
    }
}

#[test]
fn obj_single_precision_writes_the_shortest_decimal_of_the_f32() {
    let mesh: MeshData = primitives::torus(2.0, 0.5, 12, 8);
    let back = through(
        &mesh,
        MeshFormat::Obj,
        &options(Encoding::Ascii, Precision::Single),
    );
    // The decimal read back as f64 rounds to the same f32.
    assert_bit_identical(&rounded(&back), &rounded(&mesh));
    assert_ne!(back, rounded(&mesh));
}

#[test]
fn stl_round_trips_f32_coordinates_in_both_encodings() {
    for mesh in primitives_list() {
        let exact = f32_mesh(&mesh);
        for encoding in [Encoding::BinaryLittleEndian, Encoding::Ascii] {
            let back = through(
                &exact,
                MeshFormat::Stl,
                &options(encoding, Precision::Double),
            );
            if exact.faces.is_triangles() {
                assert_same_up_to_renumbering(&exact, &back);
            } else {
                // Quads are fan-triangulated: 6 quads become 12 triangles.
                assert_eq!(back.positions.len(), exact.positions.len());
                assert_eq!(back.faces.len(), 2 * exact.faces.len());
            }
        }
    }
}

#[test]
fn stl_welds_the_messy_mesh_back_to_its_used_vertices() {
    // Random f64 bit patterns overflow f32; keep the coordinates in range.
    let mesh = messy_mesh();
    let positions: Vec<DVec3> = (0..mesh.positions.len())
        .map(|i| DVec3::new(i as f64 * 0.25, -(i as f64), 1e-3 * i as f64))
        .collect();
    let triangles: Vec<[u32; 3]> = mesh
        .faces
        .iter()
        .filter(|f| f.len() == 3 && f[0] != f[1] && f[1] != f[2] && f[0] != f[2])
        .map(|f| [f[0], f[1], f[2]])
        .collect();
    let exact = f32_mesh(&MeshData {
        positions,
        faces: PolygonList::from_triangles(&triangles),
    });
    let back = through(
        &exact,
        MeshFormat::Stl,
        &options(Encoding::BinaryLittleEndian, Precision::Double),
    );
    // Vertices no face uses are not in an STL; the rest come back in order of first use.
    let mut used: Vec<u32> = exact.faces.indices().to_vec();
    used.sort_unstable();
    used.dedup();
    assert_eq!(back.positions.len(), used.len());
    for (fa, fb) in exact.faces.iter().zip(back.faces.iter()) {
        for (&a, &b) in fa.iter().zip(fb) {
            assert_eq!(exact.positions[a as usize], back.positions[b as usize]);
        }
    }
}

#[test]
fn stl_write_is_lossy_for_f64_and_computes_normals() {
    let mesh = MeshData {
        positions: vec![DVec3::new(0.1, 0.0, 0.0), DVec3::X * 2.0, DVec3::Y],
        faces: PolygonList::from_triangles(&[[0, 1, 2]]),
    };
    let mut ascii = Vec::new();
    write_mesh_to(
        &mut ascii,
        &mesh,
        MeshFormat::Stl,
        &options(Encoding::Ascii, Precision::Double),
    )
    .expect("write");
    insta::assert_snapshot!("stl_ascii_one_triangle", String::from_utf8_lossy(&ascii));
    let back = read_mesh_from(&ascii[..], MeshFormat::Stl).expect("read back");
    assert_eq!(back.positions[0].x, f64::from(0.1f32));
}

#[test]
fn files_round_trip_through_paths() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let mesh = messy_mesh();
    for name in ["m.ply", "m.PLY", "m.obj"] {
        let path = dir.path().join(name);
        write_mesh(&path, &mesh, &WriteOptions::default()).expect("write");
        assert_bit_identical(&read_mesh(&path).expect("read"), &mesh);
    }
    let cube: MeshData = primitives::cube();
    for (name, encoding) in [
        ("binary.stl", Encoding::BinaryLittleEndian),
        ("ascii.Stl", Encoding::Ascii),
    ] {
        let path = dir.path().join(name);
        write_mesh(&path, &cube, &options(encoding, Precision::Double)).expect("write");
        assert_same_up_to_renumbering(&cube, &read_mesh(&path).expect("read"));
    }
}

#[test]
fn empty_meshes_round_trip() {
    let empty = MeshData::default();
    for format in [
        MeshFormat::Ply,
        MeshFormat::Stl,
        MeshFormat::Obj,
        MeshFormat::Off,
    ] {
        for encoding in [Encoding::Ascii, Encoding::BinaryLittleEndian] {
            let back = through(&empty, format, &options(encoding, Precision::Double));
            assert_eq!(back, empty, "{format} {encoding}");
        }
    }
}

#[test]
fn fixture_cube_quads_obj_reads_as_the_primitive() {
    let mesh = read_mesh(fixture("cube_quads.obj")).expect("read");
    assert_bit_identical(&mesh, &primitives::cube_quads());
}

#[test]
fn ply_binary_and_ascii_files_convert_into_each_other_bit_for_bit() {
    // Random bit patterns (every exponent, subnormals included) through files:
    // binary -> ascii -> binary gives the same bytes, and both read back the same bits.
    let dir = tempfile::tempdir().expect("temporary directory");
    let mesh = messy_mesh();
    let binary = dir.path().join("a.ply");
    let ascii = dir.path().join("b.ply");
    let again = dir.path().join("c.ply");
    write_mesh(&binary, &mesh, &WriteOptions::default()).expect("binary");
    let from_binary = read_mesh(&binary).expect("read binary");
    write_mesh(
        &ascii,
        &from_binary,
        &options(Encoding::Ascii, Precision::Double),
    )
    .expect("ascii");
    let from_ascii = read_mesh(&ascii).expect("read ascii");
    assert_bit_identical(&from_ascii, &mesh);
    write_mesh(&again, &from_ascii, &WriteOptions::default()).expect("binary again");
    assert_eq!(
        std::fs::read(&again).unwrap(),
        std::fs::read(&binary).unwrap()
    );
}

#[test]
fn stl_and_obj_round_trips_are_idempotent() {
    // STL stores f32, and its facet normals are computed from the coordinates: the
    // first write rounds, and from the second write on, writing what was read gives
    // the same bytes and the same coordinate bits. OBJ is exact from the first write.
    let dir = tempfile::tempdir().expect("temporary directory");
    let mesh = beltrami_halfedge::primitives::icosphere(3);
    for (name, encoding) in [
        ("a.stl", Encoding::BinaryLittleEndian),
        ("b.stl", Encoding::Ascii),
        ("c.obj", Encoding::Ascii),
    ] {
        let opts = options(encoding, Precision::Double);
        let paths: Vec<_> = (0..3)
            .map(|i| dir.path().join(format!("{i}-{name}")))
            .collect();
        write_mesh(&paths[0], &mesh, &opts).expect("write");
        let first = read_mesh(&paths[0]).expect("read");
        write_mesh(&paths[1], &first, &opts).expect("write again");
        let second = read_mesh(&paths[1]).expect("read again");
        write_mesh(&paths[2], &second, &opts).expect("write a third time");
        let bytes = |i: usize| std::fs::read(&paths[i]).unwrap();
        assert!(bytes(1) == bytes(2), "{name}: a re-written file changes");
        assert_bit_identical(&second, &first);
        if name.ends_with(".obj") {
            assert_bit_identical(&first, &mesh);
            assert!(bytes(0) == bytes(1), "{name}");
        } else {
            assert_eq!(first.faces.len(), mesh.faces.len());
        }
    }
}
