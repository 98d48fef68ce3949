//! Writes the bad-input corpus `fixtures/bad/`: small broken (and a few awkward but
//! valid) mesh files that `crates/cli/tests/bad_input.rs` feeds to the command-line
//! tool. Deterministic; `bad_input.rs` fails if a committed file differs.
//!
//! ```sh
//! cargo run -p beltrami-cli --example make_bad_fixtures
//! ```

use std::path::Path;

use beltrami_testkit::SplitMix64;

/// Every file of the corpus: name and bytes.
pub(crate) fn files() -> Vec<(&'static str, Vec<u8>)> {
    let mut out: Vec<(&'static str, Vec<u8>)> = Vec::new();
    let mut add = |name: &'static str, bytes: Vec<u8>| out.push((name, bytes));

    // PLY: truncation and lying headers.
    let ascii = tetra_ascii_ply(4, 4, TETRA_VERTICES, TETRA_FACES);
    // Cut in the middle of the last face line: "3 2 0 3" becomes "3 2 0".
    add("truncated_ascii.ply", ascii[..ascii.len() - 3].to_vec());
    let binary = tetra_binary_ply(4, 4);
    add("truncated_binary.ply", binary[..binary.len() - 7].to_vec());
    add(
        "count_exceeds_ascii.ply",
        tetra_ascii_ply(40, 4, TETRA_VERTICES, TETRA_FACES),
    );
    add("count_exceeds_binary.ply", tetra_binary_ply(4, 1000));
    add(
        "four_billion_vertices.ply",
        tetra_binary_ply(4_000_000_000, 4),
    );

    // PLY: wrong or unknown property types.
    add(
        "x_is_list.ply",
        b"ply\nformat ascii 1.0\nelement vertex 3\nproperty list uchar float x\n\
          property float y\nproperty float z\nelement face 1\n\
          property list uchar int vertex_indices\nend_header\n\
          1 0 0 0\n1 1 0 0\n1 0 1 0\n3 0 1 2\n"
            .to_vec(),
    );
    add(
        "unknown_property_type.ply",
        b"ply\nformat ascii 1.0\nelement vertex 3\nproperty quad x\n\
          property float y\nproperty float z\nelement face 1\n\
          property list uchar int vertex_indices\nend_header\n\
          0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"
            .to_vec(),
    );
    add(
        "face_indices_float.ply",
        b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n\
          property float y\nproperty float z\nelement face 1\n\
          property list uchar float vertex_indices\nend_header\n\
          0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"
            .to_vec(),
    );

    // Garbage with a mesh extension, and empty files.
    let noise = garbage(300);
    add("garbage.ply", noise.clone());
    add("garbage.stl", noise.clone());
    add("garbage.obj", noise);
    add("empty.ply", Vec::new());
    add("empty.stl", Vec::new());
    add("empty.obj", Vec::new());

    // Non-finite coordinates.
    let nan_vertices = "0 0 0\n1 0 0\n0 1 0\n0 0 nan\n";
    // 1e999 overflows to infinity when read.
    let inf_vertices = "0 0 0\n1 1e999 0\n0 1 0\n0 0 1\n";
    add(
        "nan_ascii.ply",
        tetra_ascii_ply(4, 4, nan_vertices, TETRA_FACES),
    );
    add(
        "inf_ascii.ply",
        tetra_ascii_ply(4, 4, inf_vertices, TETRA_FACES),
    );
    let mut nan_binary = tetra_binary_ply(4, 4);
    let header_end = nan_binary.len() - 4 * 3 * 8 - 4 * 13;
    // The y of vertex 2.
    nan_binary[header_end + 7 * 8..header_end + 8 * 8].copy_from_slice(&f64::NAN.to_le_bytes());
    add("nan_binary.ply", nan_binary);
    add("nan.obj", obj(nan_vertices, "1 3 2\n1 2 4\n2 3 4\n3 1 4\n"));
    add("inf.obj", obj(inf_vertices, "1 3 2\n1 2 4\n2 3 4\n3 1 4\n"));

    // Bad face indices.
    add(
        "index_out_of_range.ply",
        tetra_ascii_ply(4, 4, TETRA_VERTICES, "3 0 2 1\n3 0 1 3\n3 1 2 4\n3 2 0 3\n"),
    );
    add(
        "index_negative.ply",
        tetra_ascii_ply(
            4,
            4,
            TETRA_VERTICES,
            "3 0 2 1\n3 0 1 -3\n3 1 2 3\n3 2 0 3\n",
        ),
    );
    add(
        "index_out_of_range.obj",
        obj(TETRA_VERTICES, "1 3 2\n1 2 4\n2 3 5\n3 1 4\n"),
    );
    add(
        "index_zero.obj",
        obj(TETRA_VERTICES, "1 3 2\n0 2 4\n2 3 4\n3 1 4\n"),
    );
    add(
        "index_negative.obj",
        obj(TETRA_VERTICES, "1 3 2\n1 2 4\n-2 -1 -5\n3 1 4\n"),
    );

    // Invalid connectivity.
    add(
        "repeated_vertex.obj",
        obj(TETRA_VERTICES, "1 3 2\n1 2 2\n2 3 4\n3 1 4\n"),
    );
    add(
        "nonmanifold_edge.obj",
        obj(
            "0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n",
            "1 2 3\n2 1 4\n1 2 5\n",
        ),
    );
    add(
        "nonmanifold_vertex.obj",
        obj("0 0 0\n1 0 0\n1 1 0\n-1 0 0\n-1 -1 0\n", "1 2 3\n1 4 5\n"),
    );
    add(
        "inconsistent_orientation.obj",
        obj("0 0 0\n1 0 0\n1 1 0\n0 1 0\n", "1 2 3\n1 3 4\n1 2 4\n"),
    );

    // STL.
    add("stl_count_mismatch.stl", stl_binary(5, 1));
    add(
        "stl_broken_facet.stl",
        b"solid broken\n  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n\
          \x20     vertex 1 0 0\n      vertex 0 1 0\n  endfacet\nendsolid broken\n"
            .to_vec(),
    );

    // Valid: isolated vertices are kept and never move.
    add(
        "isolated_vertices.obj",
        obj(
            "0 0 0\n1 0 0\n0 1 0\n0.25 0.25 0.5\n5 5 5\n0.3 0.1 0.7\n-2 3 0.125\n",
            "1 4 2\n2 4 3\n3 4 1\n1 6 3\n3 6 2\n2 6 1\n",
        ),
    );
    out
}

/// The unit tetrahedron, counter-clockwise seen from outside (ascii PLY rows).
const TETRA_VERTICES: &str = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
const TETRA_FACES: &str = "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n";

fn tetra_ascii_ply(n_vertices: u64, n_faces: u64, vertices: &str, faces: &str) -> Vec<u8> {
    format!(
        "ply\nformat ascii 1.0\nelement vertex {n_vertices}\nproperty double x\n\
         property double y\nproperty double z\nelement face {n_faces}\n\
         property list uchar int vertex_indices\nend_header\n{vertices}{faces}"
    )
    .into_bytes()
}

/// The tetrahedron in binary little-endian PLY with the given header counts.
fn tetra_binary_ply(n_vertices: u64, n_faces: u64) -> Vec<u8> {
    let mut bytes = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {n_vertices}\n\
         property double x\nproperty double y\nproperty double z\nelement face {n_faces}\n\
         property list uchar int vertex_indices\nend_header\n"
    )
    .into_bytes();
    for p in [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ] {
        for c in p {
            bytes.extend_from_slice(&f64::to_le_bytes(c));
        }
    }
    for f in [[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]] {
        bytes.push(3);
        for i in f {
            bytes.extend_from_slice(&i32::to_le_bytes(i));
        }
    }
    bytes
}

fn obj(vertices: &str, faces: &str) -> Vec<u8> {
    let mut text = String::new();
    for line in vertices.lines() {
        text.push_str("v ");
        text.push_str(line);
        text.push('\n');
    }
    for line in faces.lines() {
        text.push_str("f ");
        text.push_str(line);
        text.push('\n');
    }
    text.into_bytes()
}

/// A binary STL whose header declares `declared` triangles but holds `present`.
fn stl_binary(declared: u32, present: u32) -> Vec<u8> {
    let mut bytes = vec![0u8; 80];
    bytes[..11].copy_from_slice(b"binary test");
    bytes.extend_from_slice(&declared.to_le_bytes());
    for _ in 0..present {
        for value in [
            0.0f32, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0,
        ] {
            bytes.extend_from_slice(&value.to_le_bytes());
        }
        bytes.extend_from_slice(&[0, 0]);
    }
    bytes
}

/// Deterministic noise that starts with no recognisable magic: the low byte of each
/// [`SplitMix64`] number.
fn garbage(len: usize) -> Vec<u8> {
    let mut rng = SplitMix64::new(0x5eed_ba5e_0bad_f11e);
    (0..len).map(|_| rng.next_u64() as u8).collect()
}

fn main() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/bad");
    std::fs::create_dir_all(&dir).expect("create fixtures/bad");
    for (name, bytes) in files() {
        std::fs::write(dir.join(name), bytes).expect("write a fixture");
    }
}
