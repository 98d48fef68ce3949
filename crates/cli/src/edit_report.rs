//! What `remesh`, `decimate` and `fill-holes` share once their algorithm has run: the
//! mesh quality of the input and of the result (printed as a before/after table, and
//! carried in `--json` and in the `--report FILE.json` document), and one staged write
//! of the result mesh together with the report, so that neither appears without the
//! other.

use std::io::Write;
use std::path::{Path, PathBuf};

use beltrami_algorithms::{QualityError, mesh_quality};
use beltrami_halfedge::{DVec3, HalfedgeMesh};
use serde::Serialize;

use crate::error::{CliError, not_triangles};
use crate::info::QualityJson;
use crate::output::{Outputs, write_result_and_report};
use crate::text::number;

/// The quality of the input and of the result, as `info --quality --json` reports it
/// (angles in degrees).
#[derive(Debug, Serialize)]
pub(crate) struct QualityChange {
    /// The input mesh.
    pub(crate) quality_before: QualityJson,
    /// The result.
    pub(crate) quality_after: QualityJson,
}

impl QualityChange {
    /// Measures both meshes; `input` and `command` name them in an error (a face that
    /// is not a triangle cannot reach this point, since every editing algorithm refuses
    /// it first).
    pub(crate) fn measure(
        input: &Path,
        command: &str,
        before: (&HalfedgeMesh, &[DVec3]),
        after: (&HalfedgeMesh, &[DVec3]),
    ) -> Result<Self, CliError> {
        let error = |e: QualityError| CliError::Input {
            path: input.to_path_buf(),
            message: match e {
                QualityError::NotTriangle { face, len } => not_triangles(command, face, len),
                e => e.to_string(),
            },
        };
        let quality_before = mesh_quality(before.0, before.1).map_err(error)?;
        let quality_after = mesh_quality(after.0, after.1).map_err(error)?;
        Ok(Self {
            quality_before: QualityJson::new(&quality_before, None),
            quality_after: QualityJson::new(&quality_after, None),
        })
    }

    /// The before/after table printed under the command's sentence: one row per
    /// figure, the input's value, then the result's.
    pub(crate) fn write_table(&self, out: &mut impl Write) -> std::io::Result<()> {
        let (b, a) = (&self.quality_before, &self.quality_after);
        let degrees =
            |x: Option<f64>| x.map_or_else(|| "-".to_string(), |x| format!("{}°", number(x)));
        let plain = |x: Option<f64>| x.map_or_else(|| "-".to_string(), number);
        let percent = |x: f64| format!("{}%", number(100.0 * x));
        let rows = [
            (
                "smallest angle",
                degrees(b.min_angle_degrees),
                degrees(a.min_angle_degrees),
            ),
            (
                "mean smallest angle",
                degrees(b.mean_min_angle_degrees),
                degrees(a.mean_min_angle_degrees),
            ),
            (
                "largest aspect ratio",
                plain(b.max_aspect_ratio),
                plain(a.max_aspect_ratio),
            ),
            (
                "edge length CV",
                plain(b.edge_length_cv),
                plain(a.edge_length_cv),
            ),
            (
                "regular vertices",
                percent(b.regular_share),
                percent(a.regular_share),
            ),
            (
                "negative cotangent",
                percent(b.negative_cotangent_share),
                percent(a.negative_cotangent_share),
            ),
        ];
        writeln!(out, "{:<21} {:>12} {:>12}", "quality", "before", "after")?;
        for (name, before, after) in rows {
            writeln!(out, "{name:<21} {before:>12} {after:>12}")?;
        }
        Ok(())
    }
}

/// The `--json` and `--report` document: the command's own summary with the quality
/// before and after beside it, and the notes the sentence would have had (what
/// `--repair` changed, what `--lenient` ignored, the STL weld), one line each.
#[derive(Debug, Serialize)]
struct EditReport<'a, S: Serialize> {
    #[serde(flatten)]
    summary: &'a S,
    #[serde(flatten)]
    quality: &'a QualityChange,
    notes: &'a [String],
}

/// The output options the editing commands share.
#[derive(Debug, clap::Args)]
pub(crate) struct EditOutputArgs {
    /// Print a JSON summary (with the mesh quality before and after) instead of the
    /// sentence and the quality table.
    #[arg(long)]
    json: bool,
    /// Also write the JSON summary, with the mesh quality before and after, to this
    /// file.
    #[arg(long, value_name = "FILE.json")]
    report: Option<PathBuf>,
    /// Write PLY (and STL) as ascii text instead of binary.
    #[arg(long)]
    ascii: bool,
    /// Replace OUTPUT even when it is the input (an edit in place), and OUTPUT or the
    /// --report file even when it is write-protected. No output ever replaces another
    /// input (a file of feature edges), and the report never replaces the input.
    #[arg(long)]
    force: bool,
}

impl EditOutputArgs {
    /// Checks OUTPUT and the `--report` file against each other and the input, before
    /// any work (see [`Outputs::check`]).
    pub(crate) fn check(&self, output: &Path, input: &PathBuf) -> Result<(), CliError> {
        self.check_inputs(output, &[input])
    }

    /// [`check`](Self::check) against several input files (INPUT and a file of options).
    pub(crate) fn check_inputs(&self, output: &Path, inputs: &[&PathBuf]) -> Result<(), CliError> {
        let mut outputs = Outputs::new();
        outputs
            .add_mesh(output, "OUTPUT")
            .add_opt(self.report.as_ref(), "--report");
        outputs.check(inputs, self.force)
    }

    /// Writes the result mesh to `output` and, with `--report`, the JSON document
    /// (`summary` with `quality` and `notes`) as one staged write; with `--json` prints
    /// the document. Returns whether it printed it (then the command prints nothing
    /// else).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn write(
        &self,
        output: &Path,
        mesh: &HalfedgeMesh,
        positions: Vec<DVec3>,
        summary: &impl Serialize,
        quality: &QualityChange,
        notes: &[String],
        out: &mut impl Write,
    ) -> Result<bool, CliError> {
        let mut json = serde_json::to_vec_pretty(&EditReport {
            summary,
            quality,
            notes,
        })
        .map_err(std::io::Error::from)?;
        json.push(b'\n');
        write_result_and_report(
            output,
            mesh,
            positions,
            self.ascii,
            self.report.as_ref().map(|path| (path, json.as_slice())),
        )?;
        if self.json {
            out.write_all(&json)?;
        }
        Ok(self.json)
    }
}
