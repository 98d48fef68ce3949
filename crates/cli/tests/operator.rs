//! `beltrami operator` as a user runs it: the .mtx file holds the library's Laplacian
//! entry for entry (17 significant digits read back to the same f64), the .npz holds
//! scipy's CSR arrays in save_npz's order, `--mass` writes the vertex areas, the
//! output is the same bytes on every run, and bad usage (exit 2) or bad input (exit 1)
//! leaves no file.

mod common;

use std::fs;
use std::io::Read;
use std::path::{Path, PathBuf};

use beltrami_halfedge::VertexId;
use beltrami_halfedge::geometry::{Geometry, VertexAreaKind};
use beltrami_io::read_mesh;
use beltrami_weights::{Laplacian, LaplacianOptions, Normalization, WeightRegistry};
use common::{beltrami, s};
use serde_json::Value;

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

/// A (row, column, value) entry, 0-based.
type Entry = (usize, usize, f64);

/// The entries of a Matrix Market file and its size line (rows, columns, entries).
fn read_mtx(path: &Path) -> ((usize, usize, usize), Vec<Entry>) {
    let text = fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("%%MatrixMarket matrix coordinate real general")
    );
    let size: Vec<usize> = lines
        .next()
        .unwrap()
        .split(' ')
        .map(|t| t.parse().unwrap())
        .collect();
    let entries: Vec<Entry> = lines
        .map(|line| {
            let t: Vec<&str> = line.split(' ').collect();
            assert_eq!(t.len(), 3, "{line}");
            let mantissa = t[2].split('e').next().unwrap();
            assert_eq!(
                mantissa.trim_start_matches('-').len(),
                18,
                "17 significant digits: {line}"
            );
            (
                t[0].parse::<usize>().unwrap() - 1,
                t[1].parse::<usize>().unwrap() - 1,
                t[2].parse().unwrap(),
            )
        })
        .collect();
    ((size[0], size[1], size[2]), entries)
}

/// The library's Laplacian of `path` as sorted (row, column, value) triples.
fn library_laplacian(path: &Path, normalization: Normalization) -> Vec<Entry> {
    let data = read_mesh(path).unwrap();
    let mesh = data.mesh().unwrap();
    let scheme = WeightRegistry::with_builtins().get("cotangent").unwrap();
    let options = LaplacianOptions::new().normalization(normalization);
    let lap = Laplacian::new(&mesh, &data.positions, scheme.as_ref(), options).unwrap();
    let mut triples = Vec::new();
    for i in 0..mesh.n_vertices() {
        let v = VertexId::new(i as u32);
        let Some(scale) = lap.scale(v) else { continue };
        let mut row: Vec<(usize, usize, f64)> =
            lap.row(v).map(|(j, w)| (i, j.index(), w * scale)).collect();
        row.push((i, i, -lap.weight_sum(v) * scale));
        row.sort_by_key(|t| t.1);
        triples.extend(row);
    }
    triples
}

#[test]
fn the_mtx_file_is_the_library_laplacian_to_the_bit() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("noisy_icosphere_4.ply");
    let n = read_mesh(&input).unwrap().positions.len();
    for (word, normalization) in [
        ("sum", Normalization::WeightSum),
        ("area", Normalization::Area(VertexAreaKind::MixedVoronoi)),
    ] {
        let out = dir.path().join(format!("{word}.mtx"));
        let o = beltrami(&["operator", s(&input), s(&out), "--normalize", word]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let ((rows, cols, nnz), entries) = read_mtx(&out);
        assert_eq!((rows, cols), (n, n));
        assert_eq!(nnz, entries.len());
        let want = library_laplacian(&input, normalization);
        assert_eq!(entries.len(), want.len());
        for (got, want) in entries.iter().zip(&want) {
            assert_eq!((got.0, got.1), (want.0, want.1));
            assert_eq!(got.2.to_bits(), want.2.to_bits(), "{got:?} {want:?}");
        }
        // Every row of a closed mesh sums to zero (constants are in the kernel).
        let mut sums = vec![0.0f64; n];
        let mut scale = vec![0.0f64; n];
        for &(i, _, v) in &entries {
            sums[i] += v;
            scale[i] = scale[i].max(v.abs());
        }
        for i in 0..n {
            assert!(sums[i].abs() <= 1e-12 * scale[i], "row {i}: {}", sums[i]);
        }
        if word == "sum" {
            // L_ii = -W_i * (1 / W_i): -1 to rounding.
            assert!(
                entries
                    .iter()
                    .all(|&(i, j, v)| i != j || (v + 1.0).abs() <= 2.0 * f64::EPSILON)
            );
        }
    }
}

#[test]
fn the_npz_file_holds_scipy_csr_arrays_in_save_npz_order() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("icosphere_2.ply");
    let mtx = dir.path().join("l.mtx");
    let npz = dir.path().join("l.npz");
    assert!(beltrami(&["operator", s(&input), s(&mtx)]).status.success());
    let o = beltrami(&["operator", s(&input), s(&npz), "--json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary: Value = serde_json::from_slice(&o.stdout).unwrap();
    let ((n, _, nnz), entries) = read_mtx(&mtx);
    assert_eq!(summary["rows"], n);
    assert_eq!(summary["nonzeros"], nnz);
    assert_eq!(summary["matrix"], "laplacian");
    assert_eq!(summary["zero_rows"], 0);

    let mut archive = zip::ZipArchive::new(fs::File::open(&npz).unwrap()).unwrap();
    let names: Vec<String> = (0..archive.len())
        .map(|i| archive.by_index(i).unwrap().name().to_string())
        .collect();
    assert_eq!(
        names,
        [
            "indices.npy",
            "indptr.npy",
            "format.npy",
            "shape.npy",
            "data.npy"
        ]
    );
    let mut file = |name: &str| {
        let mut bytes = Vec::new();
        archive
            .by_name(name)
            .unwrap()
            .read_to_end(&mut bytes)
            .unwrap();
        assert!(bytes.starts_with(b"\x93NUMPY\x01\x00"), "{name}");
        let header_len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
        let header = String::from_utf8(bytes[10..10 + header_len].to_vec()).unwrap();
        assert_eq!((10 + header_len) % 64, 0, "{name}: {header}");
        (header, bytes[10 + header_len..].to_vec())
    };
    let (header, data) = file("data.npy");
    assert!(header.contains(&format!(
        "'descr': '<f8', 'fortran_order': False, 'shape': ({nnz},)"
    )));
    let values: Vec<f64> = data
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect();
    let want: Vec<f64> = entries.iter().map(|e| e.2).collect();
    assert_eq!(values, want);
    let (header, indices) = file("indices.npy");
    assert!(header.contains("'<i4'"), "{header}");
    let columns: Vec<usize> = indices
        .chunks_exact(4)
        .map(|c| i32::from_le_bytes(c.try_into().unwrap()) as usize)
        .collect();
    assert_eq!(columns, entries.iter().map(|e| e.1).collect::<Vec<_>>());
    let (header, indptr) = file("indptr.npy");
    assert!(
        header.contains(&format!("'shape': ({},)", n + 1)),
        "{header}"
    );
    assert_eq!(indptr.len(), 4 * (n + 1));
    let (header, format) = file("format.npy");
    assert!(
        header.contains("'descr': '|S3'") && header.contains("'shape': ()"),
        "{header}"
    );
    assert_eq!(format, b"csr");
    let (header, shape) = file("shape.npy");
    assert!(
        header.contains("'descr': '<i8'") && header.contains("'shape': (2,)"),
        "{header}"
    );
    assert_eq!(shape[..8], (n as i64).to_le_bytes());
    assert_eq!(shape[8..], (n as i64).to_le_bytes());
}

#[test]
fn mass_writes_the_vertex_areas_on_the_diagonal() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("flens_68x33.ply");
    let data = read_mesh(&input).unwrap();
    let mesh = data.mesh().unwrap();
    for (word, kind) in [
        ("mixed", VertexAreaKind::MixedVoronoi),
        ("barycentric", VertexAreaKind::Barycentric),
    ] {
        let out = dir.path().join(format!("{word}.mtx"));
        let o = beltrami(&[
            "operator",
            s(&input),
            s(&out),
            "--mass",
            "--vertex-area",
            word,
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let areas = Geometry::new(&mesh, &data.positions)
            .unwrap()
            .vertex_areas(kind)
            .unwrap();
        let ((n, _, nnz), entries) = read_mtx(&out);
        assert_eq!((n, nnz), (mesh.n_vertices(), mesh.n_vertices()));
        for (i, &(r, c, v)) in entries.iter().enumerate() {
            assert_eq!((r, c), (i, i));
            assert_eq!(v.to_bits(), areas.as_slice()[i].to_bits());
            assert!(v > 0.0);
        }
    }
}

#[test]
fn the_same_input_gives_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("noisy_torus_36x12.ply");
    for ext in ["mtx", "npz"] {
        let a = dir.path().join(format!("a.{ext}"));
        let b = dir.path().join(format!("b.{ext}"));
        assert!(beltrami(&["operator", s(&input), s(&a)]).status.success());
        assert!(beltrami(&["operator", s(&input), s(&b)]).status.success());
        assert_eq!(fs::read(&a).unwrap(), fs::read(&b).unwrap(), "{ext}");
    }
}

#[test]
fn bad_input_and_usage_leave_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.mtx");
    for bad in fs::read_dir(fixtures().join("bad")).unwrap() {
        let bad = bad.unwrap().path();
        if bad.ends_with("isolated_vertices.obj") {
            continue; // the one valid file of the corpus
        }
        let o = beltrami(&["operator", s(&bad), s(&out)]);
        assert_eq!(o.status.code(), Some(1), "{bad:?}");
        assert_eq!(
            String::from_utf8_lossy(&o.stderr).lines().count(),
            1,
            "{bad:?}"
        );
        assert!(!out.exists(), "{bad:?}");
    }
    let quads = fixtures().join("cube_quads.obj");
    let o = beltrami(&["operator", s(&quads), s(&out)]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("needs a triangle mesh"));
    assert!(!out.exists());

    let input = fixtures().join("grid_4x3.ply");
    let txt = dir.path().join("out.txt");
    for (args, output) in [
        (&["--weights", "nonesuch"][..], &out),
        (&["--normalize", "max"][..], &out),
        (&["--mass", "--weights", "uniform"][..], &out),
        (&["--vertex-area", "voronoi"][..], &out),
        (&[][..], &txt),
    ] {
        let mut all = vec!["operator", s(&input), s(output)];
        all.extend_from_slice(args);
        let o = beltrami(&all);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(!output.exists(), "{args:?}");
    }
    // The input is not overwritten without --force.
    let o = beltrami(&["operator", s(&input), s(&input)]);
    assert_eq!(o.status.code(), Some(2));
}
