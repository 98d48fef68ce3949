//! `beltrami residual`: the ISO 25178-2 areal parameters of a measured surface's
//! residual from its smoothed form.

use std::io::Write;
use std::path::PathBuf;

use beltrami_halfedge::geometry::Geometry;
use beltrami_metrics::MetricsError;
use beltrami_metrics::distance::check_same_topology;
use beltrami_metrics::residual::{
    ArealOptions, Datum, Quadrature, areal_parameters, normal_residual,
};
use serde::Serialize;

use crate::compare::{check_ply_path, load_input, metrics_error, pair_subject, stage_scalar_ply};
use crate::error::CliError;
use crate::load::ReadArgs;
use crate::output::{Outputs, Staged};
use crate::text::number;

/// Arguments of `beltrami residual`.
#[derive(Debug, clap::Args)]
pub(crate) struct ResidualArgs {
    /// The measured mesh (.ply, .stl, .obj or .off).
    measured: PathBuf,
    /// Its smoothed version, the reference form: the same vertices and faces, new
    /// positions (e.g. the output of `beltrami smooth`).
    smoothed: PathBuf,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
    /// Write the smoothed mesh to this PLY file with the residual of every vertex as the
    /// property `residual` and a colour map (blue pits, white 0, red peaks), as
    /// `compare --scalars` writes signed distances. `--out` is an older name.
    #[arg(long, value_name = "RESIDUAL.ply", alias = "out")]
    scalars: Option<PathBuf>,
    /// Measure heights from the residual's area-weighted mean instead of from the
    /// smoothed surface.
    #[arg(long)]
    remove_mean: bool,
    /// Replace the --scalars file even when it is MEASURED or SMOOTHED or
    /// write-protected.
    #[arg(long)]
    force: bool,
    #[command(flatten)]
    read: ReadArgs,
}

/// What `residual` reports; also the JSON schema of `residual --json`.
#[derive(Debug, Serialize)]
struct Summary {
    measured: String,
    smoothed: String,
    vertices: usize,
    faces: usize,
    /// `"reference"` (heights from the smoothed surface) or `"mean"`.
    datum: &'static str,
    sa: f64,
    sq: f64,
    sp: f64,
    sv: f64,
    sz: f64,
    /// Null when Sq = 0.
    ssk: Option<f64>,
    /// Null when Sq = 0.
    sku: Option<f64>,
    sdq: f64,
    sdr: f64,
    /// The area-weighted mean residual before any datum shift.
    mean: f64,
    /// The smoothed surface's area.
    area: f64,
    /// The `--scalars` file, or null.
    scalars: Option<String>,
}

/// Runs `beltrami residual`.
pub(crate) fn run(args: &ResidualArgs, out: &mut impl Write) -> Result<(), CliError> {
    if let Some(path) = &args.scalars {
        check_ply_path("--scalars", path)?;
    }
    let mut outputs = Outputs::new();
    outputs.add_opt(args.scalars.as_ref(), "--scalars");
    outputs.check(&[&args.measured, &args.smoothed], args.force)?;
    let measured = load_input(&args.measured, &args.read, Some("residual"))?;
    let smoothed = load_input(&args.smoothed, &args.read, Some("residual"))?;
    let pair = pair_subject(&args.measured, &args.smoothed);
    let on_pair = |source| CliError::Metrics {
        subject: pair.clone(),
        source,
    };
    // Checked here so that the message names the meshes in the order given.
    check_same_topology(&measured.mesh, &smoothed.mesh).map_err(&on_pair)?;
    let measured_geometry = Geometry::new(&measured.mesh, &measured.positions)
        .map_err(|e| metrics_error(&args.measured)(e.into()))?;
    let smoothed_geometry = Geometry::new(&smoothed.mesh, &smoothed.positions)
        .map_err(|e| metrics_error(&args.smoothed)(e.into()))?;
    let residual = normal_residual(&measured_geometry, &smoothed_geometry).map_err(&on_pair)?;
    let datum = if args.remove_mean {
        Datum::Mean
    } else {
        Datum::ReferenceSurface
    };
    let options = ArealOptions {
        datum,
        quadrature: Quadrature::ExactInterpolant,
    };
    let s = areal_parameters(&smoothed_geometry, residual.as_slice(), &options).map_err(
        |e| match e {
            // The parameters are computed on the smoothed surface.
            MetricsError::Topology(_) | MetricsError::Empty { .. } => {
                metrics_error(&args.smoothed)(e)
            }
            e => on_pair(e),
        },
    )?;
    let mut staged = Staged::new();
    let written = match &args.scalars {
        Some(path) => {
            let shift = if args.remove_mean { s.mean } else { 0.0 };
            let heights: Vec<f64> = residual.as_slice().iter().map(|r| r - shift).collect();
            Some(stage_scalar_ply(&mut staged, path, &smoothed, "residual", &heights)?.0)
        }
        None => None,
    };
    staged.commit()?;
    let summary = Summary {
        measured: args.measured.display().to_string(),
        smoothed: args.smoothed.display().to_string(),
        vertices: smoothed.mesh.n_vertices(),
        faces: smoothed.mesh.n_faces(),
        datum: if args.remove_mean {
            "mean"
        } else {
            "reference"
        },
        sa: s.sa,
        sq: s.sq,
        sp: s.sp,
        sv: s.sv,
        sz: s.sz,
        ssk: s.ssk,
        sku: s.sku,
        sdq: s.sdq,
        sdr: s.sdr,
        mean: s.mean,
        area: s.area,
        scalars: written,
    };
    if args.json {
        serde_json::to_writer_pretty(&mut *out, &summary).map_err(std::io::Error::from)?;
        writeln!(out)?;
    } else {
        write_table(&summary, out)?;
    }
    Ok(())
}

fn write_table(s: &Summary, out: &mut impl Write) -> std::io::Result<()> {
    writeln!(
        out,
        "Residual r = (measured - smoothed) . n (n: the smoothed surface's vertex normal) of {} against {}",
        s.measured, s.smoothed
    )?;
    writeln!(
        out,
        "over {} vertices, {} faces; heights from {}; lengths in the files' unit.",
        s.vertices,
        s.faces,
        if s.datum == "mean" {
            format!("the mean residual {}", number(s.mean))
        } else {
            "the smoothed surface".to_string()
        }
    )?;
    let dimensionless = |x: Option<f64>| x.map_or_else(|| "- (Sq = 0)".to_string(), number);
    let rows = [
        ("Sa", number(s.sa), "arithmetic mean height"),
        ("Sq", number(s.sq), "root mean square height"),
        ("Sp", number(s.sp), "maximum peak height"),
        ("Sv", number(s.sv), "maximum pit depth"),
        ("Sz", number(s.sz), "maximum height, Sp + Sv"),
        ("Ssk", dimensionless(s.ssk), "skewness (dimensionless)"),
        ("Sku", dimensionless(s.sku), "kurtosis (dimensionless)"),
        (
            "Sdq",
            number(s.sdq),
            "root mean square gradient (dimensionless)",
        ),
        (
            "Sdr",
            format!("{} ({} %)", number(s.sdr), number(100.0 * s.sdr)),
            "developed interfacial area ratio",
        ),
    ];
    for (key, value, what) in rows {
        writeln!(out, "{key:<4} {value:<24} {what}")?;
    }
    if let Some(file) = &s.scalars {
        writeln!(out, "residual -> {file}")?;
    }
    Ok(())
}
