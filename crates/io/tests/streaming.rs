//! The readers stream: reading a file holds the mesh and a bounded buffer, never the
//! whole file. Each file here carries 16 MiB or more that the mesh does not keep
//! (ignored PLY elements, OBJ normals and comments, STL text), and a counting global
//! allocator checks that the peak allocation of `read_mesh` exceeds what the returned
//! mesh holds by far less than that. Reading the same bytes from a non-seekable
//! reader (`read_mesh_from`), which holds the input, is measured too, to show that the
//! check can fail.

use std::io::Write;
use std::path::Path;

use beltrami_halfedge::primitives;
use beltrami_io::{
    Encoding, MeshData, MeshFormat, WriteOptions, read_mesh, read_mesh_from, write_mesh_to,
};
use peak_alloc::PeakAlloc;

#[global_allocator]
static ALLOCATOR: PeakAlloc = PeakAlloc;

/// Bytes of each file that the mesh does not keep.
const PADDING: usize = 16 << 20;
/// The most a read may allocate beyond the mesh it returns: the 256 KiB read buffer,
/// one line, capacity slack and the STL welding table.
const TRANSIENT_LIMIT: usize = 4 << 20;

/// (peak allocation during the read, bytes still allocated after it), both relative
/// to before the read.
fn measure(read: impl FnOnce() -> MeshData) -> (usize, usize, MeshData) {
    let before = ALLOCATOR.current_usage();
    ALLOCATOR.reset_peak_usage();
    let mesh = read();
    let peak = ALLOCATOR.peak_usage() - before;
    let retained = ALLOCATOR.current_usage().saturating_sub(before);
    (peak, retained, mesh)
}

fn check(path: &Path, format: MeshFormat, expected: &MeshData, exact: bool) {
    let length = std::fs::metadata(path).unwrap().len() as usize;
    assert!(length >= PADDING, "{path:?} is only {length} bytes");
    let (peak, retained, mesh) = measure(|| read_mesh(path).unwrap());
    if exact {
        assert!(&mesh == expected, "{path:?} reads back the mesh");
    } else {
        assert_eq!(mesh.faces.len(), expected.faces.len(), "{path:?}");
        assert_eq!(mesh.positions.len(), expected.positions.len(), "{path:?}");
    }
    let transient = peak - retained;
    println!(
        "{}: file {length} B, mesh {retained} B, peak {peak} B, transient {transient} B",
        path.file_name().unwrap().to_string_lossy()
    );
    assert!(
        transient < TRANSIENT_LIMIT,
        "{path:?}: read_mesh allocated {transient} bytes beyond the mesh for a {length}-byte file"
    );
    drop(mesh);

    // The same bytes through a reader that cannot seek are held whole: the check
    // above would catch that.
    let bytes = std::fs::read(path).unwrap();
    let (peak, retained, _) = measure(|| read_mesh_from(&bytes[..], format).unwrap());
    assert!(peak - retained >= length, "read_mesh_from holds a copy");
}

fn ply_header(format: &str, mesh: &MeshData, junk: usize, junk_properties: &str) -> String {
    format!(
        "ply\nformat {format} 1.0\nelement vertex {}\nproperty double x\nproperty double y\nproperty double z\nelement face {}\nproperty list uchar int vertex_indices\nelement junk {junk}\n{junk_properties}end_header\n",
        mesh.positions.len(),
        mesh.faces.len()
    )
}

#[test]
fn readers_hold_the_mesh_not_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let small = primitives::icosphere(4);

    // Binary PLY with a 16 MiB element the mesh ignores (skipped in one seek).
    let junk = PADDING / 16;
    let mut ply = ply_header(
        "binary_little_endian",
        &small,
        junk,
        "property double a\nproperty double b\n",
    )
    .into_bytes();
    for p in &small.positions {
        for c in p.to_array() {
            ply.extend_from_slice(&c.to_le_bytes());
        }
    }
    for face in small.faces.iter() {
        ply.push(3);
        for &i in face {
            ply.extend_from_slice(&(i as i32).to_le_bytes());
        }
    }
    ply.resize(ply.len() + PADDING, 0x3f);
    let path = dir.path().join("padded_binary.ply");
    std::fs::write(&path, &ply).unwrap();
    check(&path, MeshFormat::Ply, &small, true);

    // Ascii PLY with a million ignored lines.
    let mut text = Vec::new();
    write_mesh_to(
        &mut text,
        &small,
        MeshFormat::Ply,
        &WriteOptions::default().encoding(Encoding::Ascii),
    )
    .unwrap();
    let body = &text[text.windows(11).position(|w| w == b"end_header\n").unwrap() + 11..];
    let line = b"0.123456789012345 -9.87654321098765\n";
    let junk = PADDING / line.len() + 1;
    let mut ply = ply_header(
        "ascii",
        &small,
        junk,
        "property double a\nproperty double b\n",
    )
    .into_bytes();
    ply.extend_from_slice(body);
    for _ in 0..junk {
        ply.extend_from_slice(line);
    }
    let path = dir.path().join("padded_ascii.ply");
    std::fs::write(&path, &ply).unwrap();
    check(&path, MeshFormat::Ply, &small, true);

    // OBJ with normals and comments the reader skips.
    let path = dir.path().join("padded.obj");
    let mut file = std::io::BufWriter::new(std::fs::File::create(&path).unwrap());
    write_mesh_to(&mut file, &small, MeshFormat::Obj, &WriteOptions::default()).unwrap();
    let line = b"vn 0.577350269189626 0.577350269189626 0.577350269189626 # normal\n";
    for _ in 0..PADDING / line.len() + 1 {
        file.write_all(line).unwrap();
    }
    drop(file);
    check(&path, MeshFormat::Obj, &small, true);

    // Ascii STL: about 250 bytes of text per facet, 20 bytes of mesh.
    let large = primitives::icosphere(6);
    let path = dir.path().join("sphere.stl");
    let file = std::io::BufWriter::new(std::fs::File::create(&path).unwrap());
    let ascii = WriteOptions::default().encoding(Encoding::Ascii);
    write_mesh_to(file, &large, MeshFormat::Stl, &ascii).unwrap();
    // STL holds f32 and numbers welded vertices by first appearance: compare counts.
    check(&path, MeshFormat::Stl, &large, false);
}
