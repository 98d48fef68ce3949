//! X3P and SDF height maps: files written by an independent script
//! (`data/height_maps/make.py`, Python's standard library alone), round trips through
//! the writers, the grid as a mesh, and every error path.

use std::io::{Cursor, Write};
use std::path::PathBuf;

use beltrami_halfedge::primitives;
use beltrami_io::{
    HeightMap, IoError, LengthUnit, MeshFormat, ReadOptions, WriteOptions, read_height_map,
    read_height_map_from, read_mesh, read_mesh_from, read_mesh_from_with, read_mesh_with,
    write_height_map, write_height_map_to, write_mesh, write_mesh_to,
};

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/height_maps")
        .join(name)
}

/// Heights equal to the last bit, NaN equal to NaN.
fn assert_same_heights(a: &[f64], b: &[f64]) {
    assert_eq!(a.len(), b.len());
    for (k, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan()),
            "point {k}: {x:e} != {y:e}"
        );
    }
}

/// An awkward height map: values of every magnitude, negative zero, invalid points
/// in a corner, inside and along an edge.
fn awkward_map() -> HeightMap {
    let (nx, ny) = (7, 5);
    let mut z: Vec<f64> = (0..nx * ny)
        .map(|k| ((k as f64) * 0.7).sin() * 1e-6 + (k as f64) * 1.234_567_890_123e-9)
        .collect();
    z[0] = f64::NAN;
    z[3 + nx * 2] = f64::NAN;
    z[nx - 1 + nx * 3] = f64::NAN;
    z[5] = -0.0;
    z[6] = 1e-300;
    z[nx + 1] = 0.1 + 0.2;
    HeightMap::new(nx, ny, 1.1e-6, 0.3e-6 * 3.0, z, LengthUnit::Metre).unwrap()
}

#[test]
fn script_doubles_with_a_mask_read_as_written() {
    let map = read_height_map(data("doubles.x3p")).unwrap();
    assert_eq!((map.nx, map.ny, map.dx, map.dy), (5, 4, 2.5e-6, 5e-6));
    assert_eq!(map.unit, LengthUnit::Metre);
    for j in 0..4 {
        for i in 0..5 {
            let expected = 1e-6 * (0.5 * i as f64 - 0.25 * j as f64) + 1e-7 * (i * j) as f64;
            let got = map.height(i, j);
            if (i, j) == (2, 1) {
                assert_eq!(got, None);
            } else {
                assert_eq!(got, Some(expected), "({i}, {j})");
            }
        }
    }
    assert_eq!(map.invalid_points(), 1);
}

#[test]
fn script_inline_integers_are_scaled_by_the_z_increment_and_offset() {
    let map = read_height_map(data("inline_integers.x3p")).unwrap();
    assert_eq!((map.nx, map.ny, map.dx, map.dy), (3, 3, 1e-5, 2e-5));
    for j in 0..3 {
        for i in 0..3 {
            let expected = (1e-6 + 2e-9 * (i as f64 + 3.0 * j as f64 - 4.0)).to_bits();
            match map.height(i, j) {
                None => assert_eq!((i, j), (1, 1)),
                Some(z) => assert_eq!(z.to_bits(), expected, "({i}, {j})"),
            }
        }
    }
}

#[test]
fn script_floats_with_an_upper_case_checksum_and_a_nan() {
    let map = read_height_map(data("floats.x3p")).unwrap();
    assert_eq!(map.invalid_points(), 1);
    assert_eq!(map.height(3, 2), None);
    let expected = f64::from((2.0 - 1.0) / 8.0 * 1e-6_f32);
    assert_eq!(map.height(2, 1), Some(expected));
}

#[test]
fn script_ascii_sdf_with_bad_points_and_crlf() {
    let map = read_height_map(data("ascii.sdf")).unwrap();
    assert_eq!((map.nx, map.ny, map.dx, map.dy), (4, 3, 5e-7, 1e-6));
    assert_eq!(map.height(0, 2), None);
    assert_eq!(map.height(3, 1), Some(23.0 * 1e-9));
    assert_eq!(map.height(2, 2), Some(6.0 * 1e-9));
    assert_eq!(map.invalid_points(), 1);
}

#[test]
fn script_binary_sdf_marks_the_most_negative_integer_invalid() {
    let map = read_height_map(data("binary.sdf")).unwrap();
    assert_eq!((map.nx, map.ny, map.dx, map.dy), (3, 2, 1e-6, 1.5e-6));
    assert_eq!(map.height(2, 0), None);
    assert_eq!(map.height(1, 1), Some(1050.0 * 2e-9));
    assert_eq!(map.height(0, 0), Some(-50.0 * 2e-9));
}

#[test]
fn x3p_and_sdf_round_trip_every_bit() {
    let map = awkward_map();
    let dir = tempfile::tempdir().unwrap();
    for name in ["a.x3p", "a.sdf"] {
        let path = dir.path().join(name);
        write_height_map(&path, &map).unwrap();
        let back = read_height_map(&path).unwrap();
        assert_eq!((back.nx, back.ny), (map.nx, map.ny), "{name}");
        assert_eq!(back.dx.to_bits(), map.dx.to_bits(), "{name}");
        assert_eq!(back.dy.to_bits(), map.dy.to_bits(), "{name}");
        assert_same_heights(&back.z, &map.z);
        assert!(back.z[5].is_sign_negative(), "{name}: -0 kept");
    }
}

#[test]
fn the_x3p_writer_is_deterministic_and_other_units_are_written_in_metres() {
    let map = awkward_map();
    let mut a = Vec::new();
    let mut b = Vec::new();
    write_height_map_to(&mut a, &map, MeshFormat::X3p).unwrap();
    write_height_map_to(&mut b, &map, MeshFormat::X3p).unwrap();
    assert_eq!(a, b);
    let micrometres =
        HeightMap::new(2, 1, 2.0, 2.0, vec![1.0, 3.0], LengthUnit::Micrometre).unwrap();
    let mut bytes = Vec::new();
    write_height_map_to(&mut bytes, &micrometres, MeshFormat::X3p).unwrap();
    let back = read_height_map_from(&bytes[..], MeshFormat::X3p).unwrap();
    assert_eq!(back.unit, LengthUnit::Metre);
    assert_eq!((back.dx, back.z.as_slice()), (2e-6, &[1e-6, 3e-6][..]));
}

#[test]
fn a_height_map_reads_as_a_row_major_grid_mesh_with_holes() {
    let map = awkward_map();
    let mut bytes = Vec::new();
    write_height_map_to(&mut bytes, &map, MeshFormat::X3p).unwrap();
    let (mesh, report) =
        read_mesh_from_with(&bytes[..], MeshFormat::X3p, &ReadOptions::default()).unwrap();
    let grid = report.height_map.expect("a height map reports its grid");
    assert_eq!((grid.nx, grid.ny, grid.unit), (7, 5, LengthUnit::Metre));
    assert_eq!(grid.stats.invalid_points, 3);
    // Cells: 6 × 4 = 24; the corner point removes 1, the inner one 4, the edge one 2.
    assert_eq!(mesh.faces.len(), 2 * (24 - 1 - 4 - 2));
    assert!(mesh.positions.iter().all(|p| p.is_finite()));
    // Row-major: y never decreases, and x increases within a row.
    for w in mesh.positions.windows(2) {
        assert!(w[1].y > w[0].y || (w[1].y == w[0].y && w[1].x > w[0].x));
    }
    let built = mesh.mesh().unwrap();
    built.check_integrity().unwrap();
    // Every normal points up.
    for face in mesh.faces.iter() {
        let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[face[k] as usize]);
        assert!((b - a).cross(c - a).z > 0.0);
    }
}

#[test]
fn a_mesh_read_from_a_height_map_writes_back_as_the_same_heights() {
    let map = awkward_map();
    let dir = tempfile::tempdir().unwrap();
    let first = dir.path().join("first.x3p");
    write_height_map(&first, &map).unwrap();
    let mesh = read_mesh(&first).unwrap();
    for name in ["second.x3p", "second.sdf"] {
        let second = dir.path().join(name);
        write_mesh(&second, &mesh, &WriteOptions::default()).unwrap();
        let back = read_height_map(&second).unwrap();
        assert_eq!((back.nx, back.ny), (map.nx, map.ny));
        // The spacings are recovered from the coordinates, to within rounding.
        assert!((back.dx / map.dx - 1.0).abs() < 1e-12);
        // Points in no whole cell are not in the mesh: the corner next to the invalid
        // corner point (1, 0)… are kept; compare where the mesh has a vertex.
        let (again, _) = back.to_mesh();
        assert_eq!(again.faces, mesh.faces);
        for (p, q) in again.positions.iter().zip(&mesh.positions) {
            assert_eq!(p.z.to_bits(), q.z.to_bits());
        }
    }
}

#[test]
fn a_mesh_off_a_grid_is_refused_by_the_height_map_writers() {
    let cube = primitives::cube();
    for format in [MeshFormat::X3p, MeshFormat::Sdf] {
        let e = write_mesh_to(Vec::new(), &cube, format, &WriteOptions::default()).unwrap_err();
        assert!(matches!(e, IoError::NotAGrid { .. }), "{e}");
        assert!(e.to_string().contains("both lie on grid point"), "{e}");
    }
    let e = write_height_map(
        tempfile::tempdir().unwrap().path().join("a.ply"),
        &awkward_map(),
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "ply files hold meshes, not height maps (expected .x3p or .sdf)"
    );
}

#[test]
fn a_failed_height_map_write_leaves_the_target_untouched() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scan.x3p");
    std::fs::write(&path, b"old").unwrap();
    let cube = primitives::cube();
    assert!(write_mesh(&path, &cube, &WriteOptions::default()).is_err());
    assert_eq!(std::fs::read(&path).unwrap(), b"old");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

// ---- X3P errors -------------------------------------------------------------------

/// An X3P archive of the given entries (stored uncompressed unless `deflate`).
fn archive(entries: &[(&str, &[u8])]) -> Vec<u8> {
    let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated);
    for (name, bytes) in entries {
        zip.start_file(*name, options).unwrap();
        zip.write_all(bytes).unwrap();
    }
    zip.finish().unwrap().into_inner()
}

/// `main.xml` of a 3 × 2 grid with the z type `z_type`, with `replace` applied.
fn xml(replace: &[(&str, &str)]) -> String {
    let mut text = r#"<?xml version="1.0"?>
<p:ISO5436_2 xmlns:p="http://www.opengps.eu/2008/ISO5436_2">
<Record1>
<FeatureType>SUR</FeatureType>
<Axes>
<CX><AxisType>I</AxisType><DataType>D</DataType><Increment>1e-6</Increment></CX>
<CY><AxisType>I</AxisType><DataType>D</DataType><Increment>2e-6</Increment></CY>
<CZ><AxisType>A</AxisType><DataType>D</DataType></CZ>
</Axes>
</Record1>
<Record3>
<MatrixDimension><SizeX>3</SizeX><SizeY>2</SizeY><SizeZ>1</SizeZ></MatrixDimension>
<DataLink><PointDataLink>bindata/data.bin</PointDataLink></DataLink>
</Record3>
</p:ISO5436_2>
"#
    .to_owned();
    for (from, to) in replace {
        assert!(text.contains(from), "{from}");
        text = text.replace(from, to);
    }
    text
}

fn six_doubles() -> Vec<u8> {
    (0..6)
        .flat_map(|k| (f64::from(k) * 1e-7).to_le_bytes())
        .collect()
}

fn x3p_error(bytes: &[u8]) -> String {
    match read_mesh_from(bytes, MeshFormat::X3p) {
        Ok(mesh) => panic!("expected an error, read {mesh:?}"),
        Err(e) => {
            assert!(read_height_map_from(bytes, MeshFormat::X3p).is_err());
            e.to_string()
        }
    }
}

fn x3p_with(replace: &[(&str, &str)], data: &[u8]) -> String {
    x3p_error(&archive(&[
        ("main.xml", xml(replace).as_bytes()),
        ("bindata/data.bin", data),
    ]))
}

#[test]
fn the_test_archive_itself_reads() {
    let bytes = archive(&[
        ("main.xml", xml(&[]).as_bytes()),
        ("bindata/data.bin", &six_doubles()),
    ]);
    let map = read_height_map_from(&bytes[..], MeshFormat::X3p).unwrap();
    assert_eq!((map.nx, map.ny, map.dx, map.dy), (3, 2, 1e-6, 2e-6));
    assert_eq!(map.height(2, 1), Some(5e-7));
}

#[test]
fn x3p_archive_errors() {
    let good = archive(&[
        ("main.xml", xml(&[]).as_bytes()),
        ("bindata/data.bin", &six_doubles()),
    ]);
    let truncated = x3p_error(&good[..good.len() - 30]);
    assert!(
        truncated.starts_with("invalid x3p archive: "),
        "{truncated}"
    );
    assert!(x3p_error(b"PK\x03\x04 not really").starts_with("invalid x3p archive: "));
    assert!(x3p_error(b"").starts_with("invalid x3p archive: "));
    assert_eq!(
        x3p_error(&archive(&[("bindata/data.bin", &six_doubles())])),
        "invalid x3p archive: the archive has no main.xml"
    );
    assert_eq!(
        x3p_error(&archive(&[("main.xml", xml(&[]).as_bytes())])),
        "bindata/data.bin: the archive has no such entry (named by Record3/DataLink/PointDataLink)"
    );
}

#[test]
fn x3p_main_xml_errors_name_the_field_and_line() {
    let data = six_doubles();
    assert_eq!(
        x3p_with(
            &[("<Increment>1e-6</Increment>", "<Increment>inf</Increment>")],
            &data
        ),
        "line 6: main.xml: Record1/Axes/CX/Increment: \"inf\" is not a finite positive spacing"
    );
    assert_eq!(
        x3p_with(
            &[(
                "<Increment>2e-6</Increment>",
                "<Increment>-2e-6</Increment>"
            )],
            &data
        ),
        "line 7: main.xml: Record1/Axes/CY/Increment: \"-2e-6\" is not a finite positive spacing"
    );
    assert_eq!(
        x3p_with(
            &[("<DataType>D</DataType></CZ>", "<DataType>Q</DataType></CZ>")],
            &data
        ),
        "line 8: main.xml: Record1/Axes/CZ/DataType: \"Q\": expected I, L, F or D"
    );
    assert_eq!(
        x3p_with(&[("<SizeX>3</SizeX>", "<SizeX>three</SizeX>")], &data),
        "line 12: main.xml: Record3/MatrixDimension/SizeX: \"three\" is not a count of 1 or more"
    );
    assert_eq!(
        x3p_with(&[("<SizeZ>1</SizeZ>", "<SizeZ>2</SizeZ>")], &data),
        "line 12: main.xml: Record3/MatrixDimension/SizeZ: 2: a height map has one layer (SizeZ 1)"
    );
    assert_eq!(
        x3p_with(
            &[(
                "<FeatureType>SUR</FeatureType>",
                "<FeatureType>PRF</FeatureType>"
            )],
            &data
        ),
        "line 4: main.xml: Record1/FeatureType: \"PRF\": only SUR (an areal surface on a grid) is a height map"
    );
    assert_eq!(
        x3p_with(
            &[("<CX><AxisType>I</AxisType>", "<CX><AxisType>A</AxisType>")],
            &data
        ),
        "line 6: main.xml: Record1/Axes/CX/AxisType: \"A\": only incremental axes (I) give a grid; absolute axes (A) list each point's position"
    );
    assert_eq!(
        x3p_with(
            &[("<MatrixDimension><SizeX>3</SizeX>", "<MatrixDimension>")],
            &data
        ),
        "line 12: main.xml: Record3/MatrixDimension/SizeX: missing"
    );
    let broken = x3p_with(&[("</Record1>", "</Record2>")], &data);
    assert!(
        broken.starts_with("line 10: main.xml: main.xml: "),
        "{broken}"
    );
    let huge = x3p_with(
        &[(
            "<SizeX>3</SizeX><SizeY>2</SizeY>",
            "<SizeX>4000000000</SizeX><SizeY>4000000000</SizeY>",
        )],
        &data,
    );
    assert!(
        huge.contains("more than the 4294967295 a mesh can index"),
        "{huge}"
    );
}

#[test]
fn x3p_point_data_of_the_wrong_size_is_refused_before_allocating() {
    assert_eq!(
        x3p_with(&[], &six_doubles()[..40]),
        "bindata/data.bin: 40 bytes, but SizeX·SizeY·SizeZ = 6 values of type D need 48"
    );
    assert_eq!(
        x3p_with(&[], &[six_doubles(), vec![0; 8]].concat()),
        "bindata/data.bin: 56 bytes, more than the 48 the archive's description allows"
    );
    // A header claiming a huge grid over a tiny entry fails on the sizes, at once.
    let start = std::time::Instant::now();
    let huge = x3p_with(
        &[(
            "<SizeX>3</SizeX><SizeY>2</SizeY>",
            "<SizeX>60000</SizeX><SizeY>60000</SizeY>",
        )],
        &six_doubles(),
    );
    assert_eq!(
        huge,
        "bindata/data.bin: 48 bytes, but SizeX·SizeY·SizeZ = 3600000000 values of type D need 28800000000"
    );
    assert!(start.elapsed().as_secs_f64() < 1.0);
    let infinite: Vec<u8> = [0.0, 1.0, f64::INFINITY, 0.0, 0.0, 0.0]
        .iter()
        .flat_map(|v: &f64| v.to_le_bytes())
        .collect();
    assert_eq!(
        x3p_with(&[], &infinite),
        "bindata/data.bin: point 2 has the infinite height inf"
    );
}

#[test]
fn x3p_inline_lists_must_hold_one_number_per_point() {
    let list = |datums: &str| {
        let link = "<DataLink><PointDataLink>bindata/data.bin</PointDataLink></DataLink>";
        let text = xml(&[(link, &format!("<DataList>{datums}</DataList>"))]);
        x3p_error(&archive(&[("main.xml", text.as_bytes())]))
    };
    assert_eq!(
        list("<Datum>1</Datum><Datum>2</Datum>"),
        "line 13: main.xml: Record3/DataList: 2 points, but SizeX·SizeY·SizeZ = 6"
    );
    assert_eq!(
        list("<Datum>1</Datum><Datum>x</Datum>"),
        "line 13: main.xml: Record3/DataList/Datum: point 1: \"x\" is not a finite number"
    );
    assert!(
        list(&"<Datum>1</Datum>".repeat(7)).ends_with("more than SizeX·SizeY·SizeZ = 6 points")
    );
}

#[test]
fn x3p_checksums_are_verified_and_lenient_reads_report_them() {
    let main = xml(&[]);
    let wrong = "0123456789abcdef0123456789abcdef *main.xml\n";
    let bytes = archive(&[
        ("main.xml", main.as_bytes()),
        ("bindata/data.bin", &six_doubles()),
        ("md5checksum.hex", wrong.as_bytes()),
    ]);
    let e = x3p_error(&bytes);
    assert!(
        e.starts_with("the md5 checksum of main.xml is ")
            && e.ends_with(", but the archive records 0123456789abcdef0123456789abcdef"),
        "{e}"
    );
    let lenient = ReadOptions::new().lenient(true);
    let (mesh, report) = read_mesh_from_with(&bytes[..], MeshFormat::X3p, &lenient).unwrap();
    assert_eq!(mesh.positions.len(), 6);
    assert_eq!(report.checksum_mismatches, [e]);
    assert!(report.ignored_anything());
    let data_sum = xml(&[(
        "</PointDataLink>",
        "</PointDataLink><MD5ChecksumPointData>00000000000000000000000000000000</MD5ChecksumPointData>",
    )]);
    let e = x3p_error(&archive(&[
        ("main.xml", data_sum.as_bytes()),
        ("bindata/data.bin", &six_doubles()),
    ]));
    assert!(
        e.starts_with("the md5 checksum of bindata/data.bin is "),
        "{e}"
    );
}

#[test]
fn x3p_masks_that_are_too_short_are_refused() {
    let linked = xml(&[(
        "</PointDataLink>",
        "</PointDataLink><ValidPointsLink>bindata/valid.bin</ValidPointsLink>",
    )]);
    let read = |mask: &[u8]| {
        let bytes = archive(&[
            ("main.xml", linked.as_bytes()),
            ("bindata/data.bin", &six_doubles()),
            ("bindata/valid.bin", mask),
        ]);
        read_height_map_from(&bytes[..], MeshFormat::X3p)
    };
    let map = read(&[0b0001_1110]).unwrap();
    assert_eq!(map.invalid_points(), 2);
    assert_eq!((map.height(0, 0), map.height(2, 1)), (None, None));
    assert_eq!(
        read(&[]).unwrap_err().to_string(),
        "bindata/valid.bin: 0 bytes, but a mask of 6 points needs 1"
    );
}

// ---- SDF errors -------------------------------------------------------------------

fn sdf(header: &str, values: &str) -> String {
    format!("aISO-1.0\n{header}*\n{values}\n*\n*\n")
}

const HEADER: &str =
    "NumPoints = 3\nNumProfiles = 2\nXscale = 1e-6\nYscale = 1e-6\nZscale = 1e-9\nDataType = 7\n";

fn sdf_error(text: &str) -> String {
    match read_mesh_from(text.as_bytes(), MeshFormat::Sdf) {
        Ok(mesh) => panic!("expected an error, read {mesh:?}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn the_test_sdf_itself_reads() {
    let map =
        read_height_map_from(sdf(HEADER, "1 2 3\n4 5 BAD").as_bytes(), MeshFormat::Sdf).unwrap();
    assert_eq!(map.height(1, 1), Some(5e-9));
    assert_eq!(map.invalid_points(), 1);
}

#[test]
fn sdf_errors_name_the_line() {
    assert_eq!(
        sdf_error(&sdf(&HEADER.replace("Xscale = 1e-6\n", ""), "1 2 3 4 5 6")),
        "line 7: invalid sdf header: no Xscale in the header"
    );
    assert_eq!(
        sdf_error(&sdf(
            &HEADER.replace("DataType = 7", "DataType = 9"),
            "1 2 3 4 5 6"
        )),
        "line 7: invalid sdf header: DataType 9: expected 0 to 7 (uint8, uint16, uint32, float, int8, int16, int32, double)"
    );
    assert_eq!(
        sdf_error(&sdf(
            &HEADER.replace("Yscale = 1e-6", "Yscale = nan"),
            "1 2 3 4 5 6"
        )),
        "line 5: invalid sdf header: Yscale: expected a finite number, found \"nan\""
    );
    assert_eq!(
        sdf_error(&sdf(
            &HEADER.replace("NumPoints = 3", "NumPoints 3"),
            "1 2 3 4 5 6"
        )),
        "line 2: invalid sdf header: expected \"key = value\", found \"NumPoints 3\""
    );
    assert_eq!(
        sdf_error(&sdf(HEADER, "1 2 3\n4 5")),
        "line 11: sdf value 5: the data end after 5 values, but NumPoints × NumProfiles = 6"
    );
    assert_eq!(
        sdf_error(&sdf(HEADER, "1 2 3\n4 5 6 7")),
        "line 10: sdf value 6: more values than NumPoints × NumProfiles = 6, found \"7\""
    );
    assert_eq!(
        sdf_error(&sdf(HEADER, "1 2 3\n4 five 6")),
        "line 10: sdf value 4: expected a finite number or BAD, found \"five\""
    );
    assert_eq!(
        sdf_error(&sdf(HEADER, "1 2 3\n4 inf 6")),
        "line 10: sdf value 4: expected a finite number or BAD, found \"inf\""
    );
    assert_eq!(
        sdf_error("aISO-2.0\nNumPoints = 1\n"),
        "line 1: invalid sdf header: expected the version line aISO-1.0 or aBCR-1.0 (bISO-1.0, bBCR-1.0 for binary), found \"aISO-2.0\""
    );
    assert_eq!(
        sdf_error("aISO-1.0\nNumPoints = 1\n"),
        "invalid sdf header: the file ends in the header (no \"*\" line after it)"
    );
    assert_eq!(sdf_error(""), "the file is empty");
    let huge = sdf_error(&sdf(
        &HEADER
            .replace("NumPoints = 3", "NumPoints = 100000")
            .replace("NumProfiles = 2", "NumProfiles = 40000"),
        "1",
    ));
    assert_eq!(
        huge,
        "line 3: invalid sdf header: NumPoints × NumProfiles = 4000000000 values need at least 7999999999 bytes, but 6 follow the header"
    );
}

#[test]
fn binary_sdf_errors() {
    let header = |n: u16, data_type: u8| {
        let mut h = b"bISO-1.0".to_vec();
        h.extend([b' '; 34]);
        h.extend(n.to_le_bytes());
        h.extend(n.to_le_bytes());
        for v in [1e-6, 1e-6, 1e-9, -1.0_f64] {
            h.extend(v.to_le_bytes());
        }
        h.extend([0, data_type, 0]);
        assert_eq!(h.len(), 81);
        h
    };
    let mut good = header(2, 3);
    for v in [1.0_f32, f32::NAN, 3.0, 4.0] {
        good.extend(v.to_le_bytes());
    }
    let map = read_height_map_from(&good[..], MeshFormat::Sdf).unwrap();
    assert_eq!(
        (map.invalid_points(), map.height(0, 1)),
        (1, Some(3.0 * 1e-9))
    );
    let e = read_height_map_from(&good[..good.len() - 1], MeshFormat::Sdf).unwrap_err();
    assert_eq!(e.to_string(), "the file ends in the middle of sdf point 3");
    let e = read_height_map_from(&header(65535, 7)[..], MeshFormat::Sdf).unwrap_err();
    assert_eq!(e.to_string(), "the file ends in the middle of sdf point 0");
    let e = read_height_map_from(&header(2, 8)[..], MeshFormat::Sdf).unwrap_err();
    assert!(
        e.to_string().starts_with("invalid sdf header: DataType 8"),
        "{e}"
    );
    let e = read_height_map_from(&good[..50], MeshFormat::Sdf).unwrap_err();
    assert_eq!(
        e.to_string(),
        "the file ends in the middle of binary sdf header 0"
    );
}

#[test]
fn mesh_formats_are_no_height_maps() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cube.ply");
    write_mesh(&path, &primitives::cube(), &WriteOptions::default()).unwrap();
    assert!(matches!(
        read_height_map(&path),
        Err(IoError::NotHeightMapFormat {
            format: MeshFormat::Ply
        })
    ));
    let (_, report) = read_mesh_with(&path, &ReadOptions::default()).unwrap();
    assert_eq!(report.height_map, None);
}

#[test]
fn the_lumped_rule_on_the_grid_mesh_is_the_trapezoid_rule_but_at_the_corners() {
    use beltrami_halfedge::VertexId;
    use beltrami_halfedge::geometry::{Geometry, VertexAreaKind};
    let (nx, ny, dx, dy) = (6, 4, 0.5e-6, 0.25e-6);
    let map = HeightMap::new(nx, ny, dx, dy, vec![0.0; nx * ny], LengthUnit::Metre).unwrap();
    let (data, _) = map.to_mesh();
    let mesh = data.mesh().unwrap();
    let geometry = Geometry::new(&mesh, &data.positions).unwrap();
    let cell = dx * dy;
    for j in 0..ny {
        for i in 0..nx {
            let v = VertexId::new(u32::try_from(i + nx * j).unwrap());
            let area = geometry.vertex_area(v, VertexAreaKind::Barycentric);
            let edge = |k: usize, n: usize| if k == 0 || k == n - 1 { 0.5 } else { 1.0 };
            let corner = (i == 0 || i == nx - 1) && (j == 0 || j == ny - 1);
            let expected = if !corner {
                cell * edge(i, nx) * edge(j, ny)
            } else if i == j || (i == nx - 1 && j == ny - 1) {
                // The corners the diagonals meet.
                cell / 3.0
            } else {
                cell / 6.0
            };
            assert!(
                (area / expected - 1.0).abs() < 1e-12,
                "({i}, {j}): {area:e}, expected {expected:e}"
            );
        }
    }
}

#[test]
fn a_grid_whose_extent_overflows_is_refused() {
    // 20 points 1.2e307 apart: the last one would be at x = inf.
    let err = HeightMap::new(20, 2, 1.2e307, 1.0, vec![0.0; 40], LengthUnit::Metre)
        .expect_err("the extent is not finite");
    let message = err.to_string();
    assert!(
        message.contains("extent along x") && message.contains("1.2e307"),
        "{message}"
    );
    // A spacing whose extent is finite, however large, is taken.
    assert!(
        HeightMap::new(
            20,
            2,
            f64::MAX / 20.0,
            1.0,
            vec![0.0; 40],
            LengthUnit::Metre
        )
        .is_ok()
    );
    // One point along an axis has no extent, whatever its spacing.
    assert!(HeightMap::new(1, 2, f64::MAX, 1.0, vec![0.0; 2], LengthUnit::Metre).is_ok());
}

#[test]
fn a_unit_conversion_that_leaves_the_range_of_f64_is_refused() {
    // Heights of 1e300 m are 1e309 nm: beyond the largest f64.
    let map = HeightMap::new(2, 2, 1.0, 1.0, vec![1e300; 4], LengthUnit::Metre).unwrap();
    let err = map
        .to_unit(LengthUnit::Nanometre)
        .expect_err("the heights overflow");
    let message = err.to_string();
    assert!(
        message.contains("in nm") && message.contains("inf"),
        "{message}"
    );
    // A spacing of 1e-320 µm is 1e-326 m, which rounds to zero: refused, and so is
    // writing the map to a file in metres (X3P, SDF), which leaves no file.
    let tiny = HeightMap::new(2, 2, 1e-320, 1.0, vec![0.0; 4], LengthUnit::Micrometre).unwrap();
    let err = tiny
        .to_unit(LengthUnit::Metre)
        .expect_err("dx rounds to zero");
    assert!(err.to_string().contains("dx"), "{err}");
    let dir = tempfile::tempdir().unwrap();
    for name in ["tiny.x3p", "tiny.sdf"] {
        let path = dir.path().join(name);
        assert!(write_height_map(&path, &tiny).is_err(), "{name}");
        assert!(!path.exists(), "{name}");
    }
    // A conversion that stays in range gives the scaled map.
    let mm = map.to_unit(LengthUnit::Millimetre).unwrap();
    assert_eq!(
        (mm.dx, mm.z[0], mm.unit),
        (1e3, 1e303, LengthUnit::Millimetre)
    );
}
