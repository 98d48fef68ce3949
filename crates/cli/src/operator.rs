//! `beltrami operator`: the Laplacian (or the lumped mass matrix) of a mesh as a sparse
//! matrix file, Matrix Market (`.mtx`) or scipy's CSR `.npz`, for people's own solvers.
//!
//! The matrix is the one the smoother applies, with the sign and normalisation of
//! docs/laplacian.md (`x + λ L x` is one explicit step), and the same entries, bit for
//! bit, as the Python package's `beltrami.laplacian` and `beltrami.mass_matrix`.

use std::io::{Cursor, Write};
use std::path::{Path, PathBuf};

use beltrami_halfedge::VertexId;
use beltrami_halfedge::geometry::{Geometry, VertexAreaKind};
use beltrami_io::stage_bytes;
use beltrami_weights::{
    Laplacian, LaplacianOptions, NegativeWeights, Normalization, WeightRegistry, WeightScheme,
};
use clap::ValueEnum;
use serde::Serialize;

use crate::error::{CliError, not_triangles};
use crate::load::{LoadedMesh, ReadArgs, load};
use crate::output::{Outputs, Staged};

/// Arguments of `beltrami operator`.
#[derive(Debug, clap::Args)]
pub(crate) struct OperatorArgs {
    /// The triangle mesh (.ply, .stl, .obj, .off, or an .x3p or .sdf height map).
    input: PathBuf,
    /// The matrix file: .mtx (Matrix Market coordinate real general, 1-based, 17
    /// significant digits) or .npz (scipy.sparse.save_npz's CSR layout, read by
    /// scipy.sparse.load_npz).
    output: PathBuf,
    /// Write the lumped mass matrix (the diagonal of vertex areas, length² of the
    /// mesh's unit) instead of the Laplacian.
    #[arg(long, conflicts_with_all = ["weights", "normalize", "cotangent_negative"])]
    mass: bool,
    /// The weight scheme: uniform, distance, cotangent, or a registered name
    /// ('beltrami schemes' lists them).
    #[arg(long, default_value = "cotangent")]
    weights: String,
    /// Row normalisation: sum (L_ij = w_ij / W_i, L_ii = -1) or area (L_ij = w_ij /
    /// A_i, L_ii = -W_i / A_i, in 1/length²).
    #[arg(long, value_enum, default_value_t = NormalizeArg::Sum)]
    normalize: NormalizeArg,
    /// The vertex area A_i, for --normalize area and --mass: mixed (mixed Voronoi,
    /// Meyer et al. 2003) or barycentric (a third of the incident triangles' areas).
    #[arg(long, value_enum, default_value_t = AreaArg::Mixed)]
    vertex_area: AreaArg,
    /// Treatment of negative weights: keep them, clamp them to 0, or take their
    /// absolute value.
    #[arg(long, value_enum, default_value_t = NegativeArg::Keep)]
    cotangent_negative: NegativeArg,
    /// Print a JSON summary instead of the sentence.
    #[arg(long)]
    json: bool,
    /// Replace OUTPUT even when it is write-protected. It never replaces the input.
    #[arg(long)]
    force: bool,
    #[command(flatten)]
    read: ReadArgs,
}

/// `--normalize`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
enum NormalizeArg {
    Sum,
    Area,
}

/// `--vertex-area`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
enum AreaArg {
    Mixed,
    Barycentric,
}

/// `--cotangent-negative`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
enum NegativeArg {
    Keep,
    Clamp,
    Abs,
}

/// The file format, from OUTPUT's extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum MatrixFormat {
    MatrixMarket,
    Npz,
}

impl MatrixFormat {
    fn of(path: &Path) -> Result<Self, CliError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("mtx") => Ok(Self::MatrixMarket),
            Some("npz") => Ok(Self::Npz),
            _ => Err(CliError::Usage(format!(
                "OUTPUT {} must end in .mtx (Matrix Market) or .npz (scipy CSR)",
                path.display()
            ))),
        }
    }
}

/// A square sparse matrix in compressed sparse rows, column indices sorted in each row.
#[derive(Debug, Clone, PartialEq)]
struct Csr {
    n: usize,
    data: Vec<f64>,
    indices: Vec<usize>,
    indptr: Vec<usize>,
}

/// The JSON of `operator --json`.
#[derive(Debug, Serialize)]
struct Summary {
    input: String,
    output: String,
    /// `laplacian` or `mass`.
    matrix: &'static str,
    rows: usize,
    nonzeros: usize,
    /// The weight scheme (None for the mass matrix).
    weights: Option<String>,
    normalize: Option<NormalizeArg>,
    vertex_area: Option<AreaArg>,
    cotangent_negative: Option<NegativeArg>,
    /// Rows left zero: vertices that cannot move (weights summing to <= 0, zero area,
    /// isolated). Always 0 for the mass matrix.
    zero_rows: usize,
    /// What `--repair` changed (and the reading's other notes), one line each.
    notes: Vec<String>,
}

/// Runs `beltrami operator`.
pub(crate) fn run(
    args: &OperatorArgs,
    registry: &WeightRegistry,
    out: &mut impl Write,
) -> Result<(), CliError> {
    let format = MatrixFormat::of(&args.output)?;
    let scheme = if args.mass {
        None
    } else {
        Some(registry.get(&args.weights)?)
    };
    let mut outputs = Outputs::new();
    outputs.add(&args.output, "OUTPUT");
    outputs.check(&[&args.input], args.force)?;
    let loaded = load(&args.input, &args.read)?;
    loaded.require_faces(&args.input, "operator")?;
    if let Some((face, len)) = loaded
        .faces
        .iter()
        .enumerate()
        .find_map(|(i, f)| (f.len() != 3).then_some((i, f.len())))
    {
        return Err(CliError::Input {
            path: args.input.clone(),
            message: not_triangles("operator", face, len),
        });
    }
    let matrix = build_matrix(args, scheme.as_deref(), &loaded)?;
    let input_error = |message: String| CliError::Input {
        path: args.input.clone(),
        message,
    };
    let bytes = match format {
        MatrixFormat::MatrixMarket => matrix_market(&matrix),
        MatrixFormat::Npz => npz(&matrix).map_err(|e| input_error(e.to_string()))?,
    };
    let mut staged = Staged::new();
    staged.push(&args.output, |path| stage_bytes(path, &bytes))?;
    staged.commit()?;

    write_result(args, &matrix, &loaded.repair_lines, out)
}

/// The mass matrix (`--mass`) or the Laplacian of `scheme`, with the options of `args`.
///
/// # Errors
/// [`CliError::Input`] when the areas or the Laplacian cannot be computed or an entry
/// is not finite.
fn build_matrix(
    args: &OperatorArgs,
    scheme: Option<&dyn WeightScheme>,
    loaded: &LoadedMesh,
) -> Result<Csr, CliError> {
    let kind = match args.vertex_area {
        AreaArg::Mixed => VertexAreaKind::MixedVoronoi,
        AreaArg::Barycentric => VertexAreaKind::Barycentric,
    };
    let input_error = |message: String| CliError::Input {
        path: args.input.clone(),
        message,
    };
    let matrix = match scheme {
        None => {
            let areas = Geometry::new(&loaded.mesh, &loaded.positions)
                .and_then(|g| g.vertex_areas(kind))
                .map_err(|e| input_error(e.to_string()))?;
            let n = areas.as_slice().len();
            Csr {
                n,
                data: areas.as_slice().to_vec(),
                indices: (0..n).collect(),
                indptr: (0..=n).collect(),
            }
        }
        Some(scheme) => {
            let options = LaplacianOptions::new()
                .normalization(match args.normalize {
                    NormalizeArg::Sum => Normalization::WeightSum,
                    NormalizeArg::Area => Normalization::Area(kind),
                })
                .negative(match args.cotangent_negative {
                    NegativeArg::Keep => NegativeWeights::Keep,
                    NegativeArg::Clamp => NegativeWeights::Clamp,
                    NegativeArg::Abs => NegativeWeights::Abs,
                });
            let lap = Laplacian::new(&loaded.mesh, &loaded.positions, scheme, options)
                .map_err(|e| input_error(e.to_string()))?;
            laplacian_csr(&lap, loaded.mesh.n_vertices())
        }
    };
    if let Some(i) = matrix.data.iter().position(|v| !v.is_finite()) {
        return Err(input_error(format!(
            "the matrix has a non-finite entry ({}) in row {}",
            matrix.data[i],
            matrix.indptr.partition_point(|&p| p <= i) - 1
        )));
    }
    Ok(matrix)
}

/// The summary on standard output: JSON with `--json`, else the load's notes and one
/// line.
fn write_result(
    args: &OperatorArgs,
    matrix: &Csr,
    repair_lines: &[String],
    out: &mut impl Write,
) -> Result<(), CliError> {
    let zero_rows = matrix.indptr.windows(2).filter(|w| w[0] == w[1]).count();
    let name = if args.mass { "mass" } else { "laplacian" };
    if args.json {
        let laplacian = !args.mass;
        let summary = Summary {
            input: args.input.display().to_string(),
            output: args.output.display().to_string(),
            matrix: name,
            rows: matrix.n,
            nonzeros: matrix.data.len(),
            weights: laplacian.then(|| args.weights.clone()),
            normalize: laplacian.then_some(args.normalize),
            vertex_area: (args.mass || args.normalize == NormalizeArg::Area)
                .then_some(args.vertex_area),
            cotangent_negative: laplacian.then_some(args.cotangent_negative),
            zero_rows,
            notes: repair_lines.to_vec(),
        };
        serde_json::to_writer_pretty(&mut *out, &summary).map_err(std::io::Error::from)?;
        writeln!(out)?;
        return Ok(());
    }
    for line in repair_lines {
        writeln!(out, "{line}")?;
    }
    let zero = if zero_rows > 0 {
        format!(" ({zero_rows} zero rows: vertices that cannot move)")
    } else {
        String::new()
    };
    writeln!(
        out,
        "wrote the {n} x {n} {what} of {} -> {}: {} nonzeros{zero}",
        args.input.display(),
        args.output.display(),
        matrix.data.len(),
        n = matrix.n,
        what = if args.mass {
            "mass matrix".to_string()
        } else {
            format!("{} Laplacian", args.weights)
        },
    )?;
    Ok(())
}

/// The rows of `lap` with their diagonal, `scale` applied, columns sorted; vertices
/// without a scale (that cannot move) get an empty row.
fn laplacian_csr(lap: &Laplacian, n: usize) -> Csr {
    let mut data = Vec::new();
    let mut indices = Vec::new();
    let mut indptr = Vec::with_capacity(n + 1);
    indptr.push(0);
    let mut row: Vec<(usize, f64)> = Vec::new();
    for i in 0..n {
        let v = VertexId::new(i as u32);
        if let Some(scale) = lap.scale(v) {
            row.clear();
            row.extend(lap.row(v).map(|(j, w)| (j.index(), w * scale)));
            row.push((i, -lap.weight_sum(v) * scale));
            row.sort_by_key(|&(j, _)| j);
            for &(j, w) in &row {
                indices.push(j);
                data.push(w);
            }
        }
        indptr.push(indices.len());
    }
    Csr {
        n,
        data,
        indices,
        indptr,
    }
}

/// `x` with 17 significant digits in C's `%.16e` form (`-1.0000000000000000e+00`),
/// which reads back to the same f64.
fn sci17(x: f64) -> String {
    let s = format!("{x:.16e}");
    let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
    let exponent: i32 = exponent.parse().unwrap_or(0);
    let sign = if exponent < 0 { '-' } else { '+' };
    format!("{mantissa}e{sign}{:02}", exponent.unsigned_abs())
}

/// The Matrix Market file: coordinate real general, 1-based, row by row.
fn matrix_market(m: &Csr) -> Vec<u8> {
    let mut text = String::with_capacity(48 * m.data.len() + 128);
    text.push_str("%%MatrixMarket matrix coordinate real general\n");
    text.push_str(&format!("{} {} {}\n", m.n, m.n, m.data.len()));
    for i in 0..m.n {
        for k in m.indptr[i]..m.indptr[i + 1] {
            text.push_str(&format!(
                "{} {} {}\n",
                i + 1,
                m.indices[k] + 1,
                sci17(m.data[k])
            ));
        }
    }
    text.into_bytes()
}

/// One `.npy` file (format version 1.0) of a 1-D array or a 0-d byte string, as
/// `numpy.save` writes it: magic, header length, the header dict padded with spaces
/// to a multiple of 64 bytes and ended by a newline, then the little-endian data.
fn npy(descr: &str, shape: &str, data: &[u8]) -> Vec<u8> {
    let dict = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}");
    let unpadded = 10 + dict.len() + 1;
    let padding = (64 - unpadded % 64) % 64;
    let header_len = dict.len() + padding + 1;
    let mut out = Vec::with_capacity(10 + header_len + data.len());
    out.extend_from_slice(b"\x93NUMPY\x01\x00");
    out.extend_from_slice(&(header_len as u16).to_le_bytes());
    out.extend_from_slice(dict.as_bytes());
    out.extend(std::iter::repeat_n(b' ', padding));
    out.push(b'\n');
    out.extend_from_slice(data);
    out
}

/// The index arrays as numpy's little-endian `int32` when every value fits (what
/// scipy chooses for such a matrix), otherwise `int64`: `(descr, bytes)`.
fn index_array(values: &[usize], int32: bool) -> (&'static str, Vec<u8>) {
    if int32 {
        let bytes = values
            .iter()
            .flat_map(|&v| (v as i32).to_le_bytes())
            .collect();
        ("<i4", bytes)
    } else {
        let bytes = values
            .iter()
            .flat_map(|&v| (v as i64).to_le_bytes())
            .collect();
        ("<i8", bytes)
    }
}

/// The `.npz` of `scipy.sparse.save_npz(path, csr_matrix)`: a deflated zip of
/// `indices.npy`, `indptr.npy`, `format.npy` (`b'csr'`), `shape.npy` and `data.npy`,
/// in that order, dated 1980-01-01 so that the bytes depend on the matrix only.
fn npz(m: &Csr) -> zip::result::ZipResult<Vec<u8>> {
    let int32 = m.data.len() <= i32::MAX as usize && m.n <= i32::MAX as usize;
    let (index_descr, indices) = index_array(&m.indices, int32);
    let (_, indptr) = index_array(&m.indptr, int32);
    let shape: Vec<u8> = [m.n as i64, m.n as i64]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let data: Vec<u8> = m.data.iter().flat_map(|v| v.to_le_bytes()).collect();
    let files = [
        (
            "indices.npy",
            npy(index_descr, &format!("({},)", m.indices.len()), &indices),
        ),
        (
            "indptr.npy",
            npy(index_descr, &format!("({},)", m.indptr.len()), &indptr),
        ),
        ("format.npy", npy("|S3", "()", b"csr")),
        ("shape.npy", npy("<i8", "(2,)", &shape)),
        (
            "data.npy",
            npy("<f8", &format!("({},)", m.data.len()), &data),
        ),
    ];
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .last_modified_time(zip::DateTime::default())
        .large_file(true);
    let mut writer = zip::ZipWriter::new(Cursor::new(Vec::new()));
    for (name, bytes) in files {
        writer.start_file(name, options)?;
        writer.write_all(&bytes)?;
    }
    Ok(writer.finish()?.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seventeen_digits_in_c_form_read_back_exactly() {
        assert_eq!(sci17(-1.0), "-1.0000000000000000e+00");
        assert_eq!(sci17(0.0), "0.0000000000000000e+00");
        assert_eq!(sci17(2f64.powi(-20)), "9.5367431640625000e-07");
        assert_eq!(sci17(2f64.powi(100)), "1.2676506002282294e+30");
        assert!(sci17(2f64.powi(-1000)).ends_with("e-302"));
        for x in [
            0.1,
            1.0 / 3.0,
            -2.0f64.sqrt() * 1e7,
            f64::MIN_POSITIVE,
            2f64.powi(-1000),
        ] {
            assert_eq!(sci17(x).parse::<f64>().unwrap().to_bits(), x.to_bits());
        }
    }

    #[test]
    fn npy_headers_are_aligned_to_64_bytes() {
        for shape in ["()", "(2,)", "(123456789,)"] {
            let file = npy("<f8", shape, &[]);
            assert_eq!(file.len() % 64, 0, "{shape}");
            assert_eq!(file.last(), Some(&b'\n'));
            let header_len = u16::from_le_bytes([file[8], file[9]]) as usize;
            assert_eq!(10 + header_len, file.len());
        }
    }
}
