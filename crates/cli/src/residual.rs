//! `beltrami residual`: the ISO 25178-2 areal parameters of a measured surface's
//! residual from its form: its smoothed version, or a least-squares plane, polynomial,
//! sphere or cylinder.

use std::io::Write;
use std::path::{Path, PathBuf};

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::{DVec3, PolygonList};
use beltrami_io::{MeshData, MeshFormat};
use beltrami_metrics::MetricsError;
use beltrami_metrics::distance::check_same_topology;
use beltrami_metrics::residual::{
    ArealOptions, Datum, FittedForm, Form, Quadrature, SXP_RATIOS, SurfaceTexture, TextureOptions,
    VOLUME_RATIOS, form_residual, normal_residual, surface_texture,
};
use serde::Serialize;

use crate::compare::{check_ply_path, load_input, metrics_error, pair_subject, stage_scalar_ply};
use crate::error::CliError;
use crate::load::{LoadedMesh, ReadArgs};
use crate::output::{Outputs, Staged};
use crate::text::{number, vector};

/// Arguments of `beltrami residual`.
#[derive(Debug, clap::Args)]
#[command(
    group(clap::ArgGroup::new("reference").required(true).args(["smoothed", "form"])),
    override_usage = "beltrami residual [OPTIONS] <MEASURED> <SMOOTHED>\n       beltrami residual [OPTIONS] <MEASURED> --form <FORM>",
    after_long_help = "The residual is what is left of MEASURED once its form is removed \
(the F-operator of ISO 25178-2), by one of two routes:

  residual MEASURED SMOOTHED   the signed normal deviation from SMOOTHED, the same mesh \
smoothed (e.g. by `beltrami smooth`), along SMOOTHED's vertex normals;
  residual MEASURED --form F   the signed orthogonal distance from the least-squares \
form F fitted to MEASURED (area-weighted): plane, poly:N (a polynomial of degree N = 1 to \
6 over the best-fit plane), sphere or cylinder.

Positive residuals lie on the side MEASURED's faces point to (outside, or up). The \
parameters are integrals over the reference surface: SMOOTHED, or MEASURED laid onto the \
form. Height integrals use the lumped rule by default (each vertex weighted by its \
barycentric area: the trapezoid rule on a grid); --quadrature exact integrates the \
piecewise-linear interpolant instead, which cuts the crests of a sampled texture. The \
spatial parameters Sal, Str and Std are computed on the residual resampled onto a square \
grid in the reference surface's best-fit plane at its median edge length; they are null \
when the surface folds over that plane (a closed surface). docs/metrics.md has every \
formula."
)]
pub(crate) struct ResidualArgs {
    /// The measured mesh (.ply, .stl, .obj or .off) or height map (.x3p or .sdf, read in
    /// metres as a triangulated grid).
    measured: PathBuf,
    /// Its smoothed version, the reference form: the same vertices and faces, new
    /// positions (e.g. the output of `beltrami smooth`). Give this or --form.
    smoothed: Option<PathBuf>,
    /// Remove a least-squares form fitted to MEASURED instead of a smoothed mesh: plane,
    /// poly:N (N = 1 to 6), sphere or cylinder.
    #[arg(long, value_name = "FORM", value_parser = parse_form)]
    form: Option<Form>,
    /// How height integrals are evaluated: lumped (area-weighted vertex values, which
    /// converge to the sampled surface) or exact (exact integrals of the piecewise-linear
    /// interpolant).
    #[arg(long, value_enum, default_value_t = QuadratureArg::Lumped)]
    quadrature: QuadratureArg,
    /// Also report the areal material ratio Smr(c) at this height (length units, on the
    /// datum in use); repeatable.
    #[arg(long, value_name = "HEIGHT", allow_hyphen_values = true)]
    smr: Vec<f64>,
    /// Also report the inverse areal material ratio Smc(mr) at this material ratio (in
    /// percent, 0 to 100); repeatable.
    #[arg(long, value_name = "PERCENT", allow_hyphen_values = true)]
    smc: Vec<f64>,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
    /// Write the reference surface (SMOOTHED, or MEASURED laid onto the form) to this
    /// PLY file with the residual of every vertex as the property `residual` and a colour
    /// map (blue pits, white 0, red peaks), as `compare --scalars` writes signed
    /// distances. For a height-map MEASURED (.x3p, .sdf) the path may end in .x3p or
    /// .sdf instead: the residual is written as a height map on MEASURED's grid, for
    /// instrument software. `--out` is an older name.
    #[arg(long, value_name = "RESIDUAL.ply", alias = "out")]
    scalars: Option<PathBuf>,
    /// Measure heights from the residual's area-weighted mean instead of from the
    /// reference surface.
    #[arg(long)]
    remove_mean: bool,
    /// Replace the --scalars file even when it is MEASURED (an edit in place) or
    /// write-protected. It never replaces SMOOTHED.
    #[arg(long)]
    force: bool,
    #[command(flatten)]
    read: ReadArgs,
}

/// `--quadrature`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum QuadratureArg {
    /// Area-weighted vertex values.
    Lumped,
    /// Exact integrals of the piecewise-linear interpolant.
    Exact,
}

impl QuadratureArg {
    fn quadrature(self) -> Quadrature {
        match self {
            Self::Lumped => Quadrature::Lumped,
            Self::Exact => Quadrature::ExactInterpolant,
        }
    }

    fn name(self) -> &'static str {
        match self {
            Self::Lumped => "lumped",
            Self::Exact => "exact",
        }
    }
}

/// `plane`, `poly:N`, `sphere` or `cylinder`.
fn parse_form(text: &str) -> Result<Form, String> {
    text.parse()
}

/// What `residual` reports; also the JSON schema of `residual --json`.
#[derive(Debug, Serialize)]
struct Summary {
    measured: String,
    /// Null with --form.
    smoothed: Option<String>,
    /// The fitted form with --form, else null.
    form: Option<FormSummary>,
    vertices: usize,
    faces: usize,
    /// `"reference"` (heights from the reference surface) or `"mean"`.
    datum: &'static str,
    /// `"lumped"` or `"exact"`.
    quadrature: &'static str,
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
    /// Smc(2.5 %) − Smc(50 %).
    sxp: f64,
    sk: f64,
    spk: f64,
    svk: f64,
    /// Percent.
    smr1: f64,
    /// Percent.
    smr2: f64,
    /// Percent × length.
    sak1: f64,
    /// Percent × length.
    sak2: f64,
    /// Volumes per unit area (length; mL/m² for µm).
    vmp: f64,
    vmc: f64,
    vvc: f64,
    vvv: f64,
    /// Null when the spatial parameters are unavailable or undefined.
    sal: Option<f64>,
    str: Option<f64>,
    /// Degrees, counter-clockwise from the x axis, in [0, 180).
    std: Option<f64>,
    /// `--smr` values: `[{height, ratio}]`, the ratio in percent.
    smr: Vec<SmrValue>,
    /// `--smc` values: `[{ratio, height}]`.
    smc: Vec<SmrValue>,
    /// How the spatial parameters were sampled.
    spatial: SpatialJson,
    /// The area-weighted mean residual before any datum shift.
    mean: f64,
    /// The reference surface's area.
    area: f64,
    /// The `--scalars` file, or null.
    scalars: Option<String>,
    /// What reading the files did besides reading them (a height map's grid, a lenient
    /// read's skipped lines, `--weld`, `--repair`), one line each; empty when nothing.
    notes: Vec<String>,
}

/// A point of the material ratio curve.
#[derive(Debug, Serialize)]
struct SmrValue {
    /// Length units, on the datum.
    height: f64,
    /// Percent.
    ratio: f64,
}

/// The fitted form of `--form`.
#[derive(Debug, Serialize)]
struct FormSummary {
    /// `"plane"`, `"polynomial"`, `"sphere"` or `"cylinder"`.
    kind: &'static str,
    /// The polynomial's degree, else null.
    degree: Option<u32>,
    /// Plane: its point (the centroid); polynomial: the origin of its frame; sphere: the
    /// centre; cylinder: the axis point nearest the centroid.
    point: [f64; 3],
    /// Plane, polynomial: the plane's unit normal; cylinder: the unit axis; sphere: null.
    direction: Option<[f64; 3]>,
    /// Sphere and cylinder, else null.
    radius: Option<f64>,
    /// Area-weighted RMS of the orthogonal residuals.
    rms_residual: f64,
    /// Whether the residual's sign is the opposite of the fit's own (the faces point
    /// into the sphere or cylinder, or against the plane's normal).
    flipped: bool,
}

/// The grid the spatial parameters were computed on.
#[derive(Debug, Serialize)]
struct SpatialJson {
    /// The grid step (length), null when unavailable.
    step: Option<f64>,
    /// Grid points along the plane's u and v axes.
    nx: Option<usize>,
    ny: Option<usize>,
    /// Grid points inside the projection of the surface.
    valid_points: Option<usize>,
    /// The autocorrelation threshold s of Sal and Str.
    threshold: f64,
    /// Whether the autocorrelation fell to s in every direction (else Str is an upper
    /// bound).
    decays_in_every_direction: bool,
    /// Why Sal, Str and Std are null, or null.
    unavailable: Option<String>,
}

/// Runs `beltrami residual`.
pub(crate) fn run(args: &ResidualArgs, out: &mut impl Write) -> Result<(), CliError> {
    let height_map_out = match &args.scalars {
        Some(path) => scalars_target(path, &args.measured)?,
        None => false,
    };
    check_material_ratio_args(args)?;
    let mut outputs = Outputs::new();
    // The residual mesh is the command's result: --force lets it replace MEASURED.
    if let Some(path) = &args.scalars {
        outputs.add_mesh(path, "--scalars");
    }
    let mut inputs = vec![&args.measured];
    inputs.extend(args.smoothed.as_ref());
    outputs.check(&inputs, args.force)?;
    let measured = load_input(&args.measured, &args.read, Some("residual"))?;
    let mut notes = measured.read_notes(&args.measured, args.smoothed.is_some());
    // The grid's points, for a residual written back as a height map.
    let grid_points = height_map_out.then(|| (measured.positions.clone(), measured.faces.clone()));

    let Residual {
        values: residual,
        reference,
        form,
        subject,
    } = residual_and_reference(args, measured)?;
    if let Some(smoothed) = &args.smoothed {
        notes.extend(reference.read_notes(smoothed, true));
    }
    let on_reference = |source: MetricsError| match (&subject, &source) {
        // The parameters are computed on the smoothed surface.
        (Subject::Pair(_), MetricsError::Topology(_) | MetricsError::Empty { .. }) => {
            metrics_error(args.smoothed.as_deref().unwrap_or(&args.measured))(source)
        }
        (Subject::Pair(pair), _) => CliError::Metrics {
            subject: pair.clone(),
            source,
        },
        (Subject::Measured, _) => metrics_error(&args.measured)(source),
    };
    let geometry =
        Geometry::new(&reference.mesh, &reference.positions).map_err(|e| on_reference(e.into()))?;
    let texture =
        surface_texture(&geometry, &residual, &texture_options(args)).map_err(&on_reference)?;
    let written = write_scalars(args, grid_points, &reference, &texture.heights)?;
    let summary = summarise(
        args,
        &reference.mesh,
        Parts {
            form,
            texture: &texture,
            scalars: written,
        },
        notes,
    );
    if args.json {
        serde_json::to_writer_pretty(&mut *out, &summary).map_err(std::io::Error::from)?;
        writeln!(out)?;
    } else {
        write_table(&summary, out)?;
        // What the reader made of the files (a height map's grid and holes, a lenient
        // read, --weld, --repair).
        for line in &summary.notes {
            writeln!(out, "{line}")?;
        }
    }
    Ok(())
}

/// Checks `--smc` (ratios from 0 to 100 %) and `--smr` (finite heights).
fn check_material_ratio_args(args: &ResidualArgs) -> Result<(), CliError> {
    for &mr in &args.smc {
        if !(0.0..=100.0).contains(&mr) {
            return Err(CliError::Usage(format!(
                "--smc takes a material ratio in percent from 0 to 100, got {mr}"
            )));
        }
    }
    if let Some(c) = args.smr.iter().find(|c| !c.is_finite()) {
        return Err(CliError::Usage(format!(
            "--smr takes a finite height, got {c}"
        )));
    }
    Ok(())
}

/// The residual per vertex and the surface it lives on.
struct Residual {
    values: Vec<f64>,
    /// SMOOTHED, or MEASURED laid onto the fitted form.
    reference: LoadedMesh,
    /// The fitted form of `--form`.
    form: Option<FormSummary>,
    /// Whose error a failure of the parameters is.
    subject: Subject,
}

/// The residual of MEASURED against SMOOTHED (same connectivity), or against the form
/// of `--form` fitted to it.
fn residual_and_reference(args: &ResidualArgs, measured: LoadedMesh) -> Result<Residual, CliError> {
    let on_measured = metrics_error(&args.measured);
    match (&args.smoothed, args.form) {
        (Some(smoothed_path), _) => {
            let smoothed = load_input(smoothed_path, &args.read, Some("residual"))?;
            let pair = pair_subject(&args.measured, smoothed_path);
            // Checked here so that the message names the meshes in the order given.
            check_same_topology(&measured.mesh, &smoothed.mesh).map_err(|source| {
                if args.read.triangulate {
                    // Each mesh's polygons were split by its own shape.
                    CliError::Input {
                        path: smoothed_path.clone(),
                        message: format!(
                            "{source}; --triangulate splits each mesh's polygons by its own shape, so the two can differ: triangulate MEASURED once with `beltrami repair --triangulate` and smooth that"
                        ),
                    }
                } else {
                    CliError::Metrics {
                        subject: pair.clone(),
                        source,
                    }
                }
            })?;
            let measured_geometry = Geometry::new(&measured.mesh, &measured.positions)
                .map_err(|e| on_measured(e.into()))?;
            let smoothed_geometry = Geometry::new(&smoothed.mesh, &smoothed.positions)
                .map_err(|e| metrics_error(smoothed_path)(e.into()))?;
            let residual =
                normal_residual(&measured_geometry, &smoothed_geometry).map_err(|source| {
                    CliError::Metrics {
                        subject: pair.clone(),
                        source,
                    }
                })?;
            Ok(Residual {
                values: residual.into_vec(),
                reference: smoothed,
                form: None,
                subject: Subject::Pair(pair),
            })
        }
        (None, Some(form)) => {
            let geometry = Geometry::new(&measured.mesh, &measured.positions)
                .map_err(|e| on_measured(e.into()))?;
            let fit = form_residual(&geometry, form).map_err(&on_measured)?;
            let summary = form_summary(&fit.form, fit.flipped);
            let residual = fit.residual.into_vec();
            let mut laid = measured;
            laid.positions = fit.foot_points;
            Ok(Residual {
                values: residual,
                reference: laid,
                form: Some(summary),
                subject: Subject::Measured,
            })
        }
        (None, None) => Err(CliError::Usage(
            "residual needs SMOOTHED or --form".to_string(),
        )),
    }
}

/// The options of the texture parameters: the datum, the quadrature and the material
/// ratios asked for.
fn texture_options(args: &ResidualArgs) -> TextureOptions {
    TextureOptions::default()
        .areal(
            ArealOptions::default()
                .datum(if args.remove_mean {
                    Datum::Mean
                } else {
                    Datum::ReferenceSurface
                })
                .quadrature(args.quadrature.quadrature()),
        )
        .smr_heights(args.smr.clone())
        .smc_ratios(args.smc.clone())
}

/// Writes `--scalars`, if given: the heights over MEASURED's grid points for a height
/// map (`grid_points`), else a PLY of the reference with the residual per vertex.
/// Returns the file's name.
fn write_scalars(
    args: &ResidualArgs,
    grid_points: Option<(Vec<DVec3>, PolygonList)>,
    reference: &LoadedMesh,
    heights: &[f64],
) -> Result<Option<String>, CliError> {
    let mut staged = Staged::new();
    let written = match (&args.scalars, grid_points) {
        (Some(path), Some((mut positions, faces))) => {
            // The residual as the heights over MEASURED's grid points.
            for (p, h) in positions.iter_mut().zip(heights) {
                p.z = *h;
            }
            staged.push_mesh(path, &MeshData { positions, faces }, false)?;
            Some(path.display().to_string())
        }
        (Some(path), None) => {
            Some(stage_scalar_ply(&mut staged, path, reference, "residual", heights)?.0)
        }
        (None, _) => None,
    };
    staged.commit()?;
    Ok(written)
}

/// Whether `--scalars PATH` is a height map (.x3p, .sdf) rather than a PLY file; a
/// height map needs a height-map MEASURED, whose grid it is written on.
fn scalars_target(path: &Path, measured: &Path) -> Result<bool, CliError> {
    let height_map = |p: &Path| {
        matches!(
            MeshFormat::from_path(p),
            Ok(MeshFormat::X3p | MeshFormat::Sdf)
        )
    };
    if !height_map(path) {
        check_ply_path("--scalars", path)?;
        return Ok(false);
    }
    if height_map(measured) {
        Ok(true)
    } else {
        Err(CliError::Usage(format!(
            "--scalars writes a height map ('{}') only for a height-map MEASURED (.x3p or .sdf), whose grid it uses; write the residual of '{}' as PLY",
            path.display(),
            measured.display()
        )))
    }
}

/// Whose error a failure of the parameters is.
enum Subject {
    /// `MEASURED vs SMOOTHED`.
    Pair(String),
    /// MEASURED alone (with --form).
    Measured,
}

/// What [`summarise`] puts together.
struct Parts<'a> {
    form: Option<FormSummary>,
    texture: &'a SurfaceTexture,
    scalars: Option<String>,
}

fn summarise(
    args: &ResidualArgs,
    mesh: &beltrami_halfedge::HalfedgeMesh,
    p: Parts<'_>,
    notes: Vec<String>,
) -> Summary {
    let Parts {
        form,
        texture: t,
        scalars,
    } = p;
    let (s, k, v, sp) = (&t.areal, &t.stratified, &t.volume, &t.spatial);
    Summary {
        measured: args.measured.display().to_string(),
        smoothed: args.smoothed.as_ref().map(|p| p.display().to_string()),
        form,
        vertices: mesh.n_vertices(),
        faces: mesh.n_faces(),
        datum: if args.remove_mean {
            "mean"
        } else {
            "reference"
        },
        quadrature: args.quadrature.name(),
        sa: s.sa,
        sq: s.sq,
        sp: s.sp,
        sv: s.sv,
        sz: s.sz,
        ssk: s.ssk,
        sku: s.sku,
        sdq: s.sdq,
        sdr: s.sdr,
        sxp: t.sxp,
        sk: k.sk,
        spk: k.spk,
        svk: k.svk,
        smr1: k.smr1,
        smr2: k.smr2,
        sak1: k.sak1,
        sak2: k.sak2,
        vmp: v.vmp,
        vmc: v.vmc,
        vvc: v.vvc,
        vvv: v.vvv,
        sal: sp.sal,
        str: sp.str,
        std: sp.std,
        smr: t
            .smr
            .iter()
            .map(|&(height, ratio)| SmrValue { height, ratio })
            .collect(),
        smc: t
            .smc
            .iter()
            .map(|&(height, ratio)| SmrValue { height, ratio })
            .collect(),
        spatial: SpatialJson {
            step: sp.step,
            nx: sp.nx,
            ny: sp.ny,
            valid_points: sp.valid_points,
            threshold: sp.threshold,
            decays_in_every_direction: sp.decays_in_every_direction,
            unavailable: sp.unavailable.clone(),
        },
        mean: s.mean,
        area: s.area,
        scalars,
        notes,
    }
}

fn form_summary(form: &FittedForm, flipped: bool) -> FormSummary {
    FormSummary {
        kind: form.kind(),
        degree: form.degree(),
        point: form.point().to_array(),
        direction: form.direction().map(|d| d.to_array()),
        radius: form.radius(),
        rms_residual: form.rms_residual(),
        flipped,
    }
}

/// A table row: the parameter, its value, what it means.
type Row = (&'static str, String, String);

fn write_table(s: &Summary, out: &mut impl Write) -> std::io::Result<()> {
    write_heading(s, out)?;
    for (title, rows) in parameter_sections(s) {
        writeln!(out, "{title}")?;
        for (key, value, what) in rows {
            writeln!(out, "{key:<5} {value:<24} {what}")?;
        }
    }
    write_notes(s, out)
}

/// The table's first lines: what the residual is, of which mesh, and how heights are
/// measured.
fn write_heading(s: &Summary, out: &mut impl Write) -> std::io::Result<()> {
    match (&s.form, &s.smoothed) {
        (Some(form), _) => {
            let what = match form.degree {
                Some(d) => format!("polynomial of degree {d}"),
                None => form.kind.to_string(),
            };
            writeln!(
                out,
                "Residual r = orthogonal distance of {} from its least-squares {what}",
                s.measured
            )?;
            let point = vector(DVec3::from_array(form.point));
            let mut line = match form.kind {
                "sphere" => format!("centre {point}"),
                "cylinder" => format!("axis through {point}"),
                _ => format!("through {point}"),
            };
            if let Some(d) = form.direction {
                let name = if form.kind == "cylinder" {
                    "direction"
                } else {
                    "normal"
                };
                line += &format!(", {name} {}", vector(DVec3::from_array(d)));
            }
            if let Some(r) = form.radius {
                line += &format!(", radius {}", number(r));
            }
            writeln!(
                out,
                "form: {line}; rms residual {}{}",
                number(form.rms_residual),
                if form.flipped {
                    " (faces point inwards: positive towards the inside)"
                } else {
                    ""
                }
            )?;
        }
        (None, Some(smoothed)) => writeln!(
            out,
            "Residual r = (measured - smoothed) . n (n: the smoothed surface's vertex normal) of {} against {smoothed}",
            s.measured
        )?,
        (None, None) => {}
    }
    writeln!(
        out,
        "over {} vertices, {} faces; heights from {}; lengths in the files' unit; {} quadrature.",
        s.vertices,
        s.faces,
        if s.datum == "mean" {
            format!("the mean residual {}", number(s.mean))
        } else if s.form.is_some() {
            "the form".to_string()
        } else {
            "the smoothed surface".to_string()
        },
        if s.quadrature == "lumped" {
            "lumped (area-weighted vertex values)"
        } else {
            "exact-interpolant"
        }
    )?;
    Ok(())
}

/// The parameters by section: the titles and the rows of each.
fn parameter_sections(s: &Summary) -> [(&'static str, Vec<Row>); 5] {
    let dimensionless = |x: Option<f64>| x.map_or_else(|| "- (Sq = 0)".to_string(), number);
    let percent = |x: f64| format!("{} %", number(x));
    let spatial = |x: Option<f64>| x.map_or_else(|| "-".to_string(), number);
    let (p, q) = VOLUME_RATIOS;
    [
        (
            "height",
            vec![
                ("Sa", number(s.sa), "arithmetic mean height".into()),
                ("Sq", number(s.sq), "root mean square height".into()),
                ("Sp", number(s.sp), "maximum peak height".into()),
                ("Sv", number(s.sv), "maximum pit depth".into()),
                ("Sz", number(s.sz), "maximum height, Sp + Sv".into()),
                (
                    "Ssk",
                    dimensionless(s.ssk),
                    "skewness (dimensionless)".into(),
                ),
                (
                    "Sku",
                    dimensionless(s.sku),
                    "kurtosis (dimensionless)".into(),
                ),
            ],
        ),
        (
            "hybrid",
            vec![
                (
                    "Sdq",
                    number(s.sdq),
                    "root mean square gradient (dimensionless)".into(),
                ),
                (
                    "Sdr",
                    format!("{} ({} %)", number(s.sdr), number(100.0 * s.sdr)),
                    "developed interfacial area ratio".into(),
                ),
            ],
        ),
        (
            "material ratio (ISO 13565-2 on the areal material ratio curve)",
            vec![
                (
                    "Sxp",
                    number(s.sxp),
                    format!(
                        "peak extreme height, Smc({} %) - Smc({} %)",
                        SXP_RATIOS.0, SXP_RATIOS.1
                    ),
                ),
                ("Sk", number(s.sk), "core height".into()),
                ("Spk", number(s.spk), "reduced peak height".into()),
                ("Svk", number(s.svk), "reduced dale height".into()),
                (
                    "Smr1",
                    percent(s.smr1),
                    "material ratio at the top of the core".into(),
                ),
                (
                    "Smr2",
                    percent(s.smr2),
                    "material ratio at the bottom of the core".into(),
                ),
                (
                    "Sak1",
                    number(s.sak1),
                    "peak area above the core (% x length)".into(),
                ),
                (
                    "Sak2",
                    number(s.sak2),
                    "dale area below the core (% x length)".into(),
                ),
            ],
        ),
        (
            "volume (per unit area; mL/m^2 when lengths are in um)",
            vec![
                (
                    "Vmp",
                    number(s.vmp),
                    format!("peak material volume at {p} %"),
                ),
                (
                    "Vmc",
                    number(s.vmc),
                    format!("core material volume, {p} % to {q} %"),
                ),
                (
                    "Vvc",
                    number(s.vvc),
                    format!("core void volume, {p} % to {q} %"),
                ),
                ("Vvv", number(s.vvv), format!("dale void volume at {q} %")),
            ],
        ),
        (
            "spatial",
            vec![
                (
                    "Sal",
                    spatial(s.sal),
                    format!(
                        "autocorrelation length (fastest decay to s = {})",
                        s.spatial.threshold
                    ),
                ),
                (
                    "Str",
                    spatial(s.str),
                    format!(
                        "texture aspect ratio: near 0 directional, 1 isotropic{}",
                        if s.str.is_some() && !s.spatial.decays_in_every_direction {
                            " (an upper bound)"
                        } else {
                            ""
                        }
                    ),
                ),
                (
                    "Std",
                    s.std
                        .map_or_else(|| "-".to_string(), |d| format!("{} deg", number(d))),
                    "texture direction: the lay, counter-clockwise from x".into(),
                ),
            ],
        ),
    ]
}

/// The lines under the parameters: the spatial grid, the material ratios asked for and
/// the scalar file.
fn write_notes(s: &Summary, out: &mut impl Write) -> std::io::Result<()> {
    match (&s.spatial.unavailable, s.spatial.step) {
        (Some(why), _) => writeln!(out, "spatial parameters unavailable: {why}")?,
        (None, Some(step)) => writeln!(
            out,
            "spatial parameters on a grid of {} x {} points ({} inside the surface) at step {} in the mean plane",
            s.spatial.nx.unwrap_or(0),
            s.spatial.ny.unwrap_or(0),
            s.spatial.valid_points.unwrap_or(0),
            number(step)
        )?,
        (None, None) => {}
    }
    for v in &s.smr {
        writeln!(
            out,
            "Smr({}) = {} %  areal material ratio at this height",
            number(v.height),
            number(v.ratio)
        )?;
    }
    for v in &s.smc {
        writeln!(
            out,
            "Smc({} %) = {}  height at this material ratio",
            number(v.ratio),
            number(v.height)
        )?;
    }
    if let Some(file) = &s.scalars {
        writeln!(out, "residual -> {file}")?;
    }
    Ok(())
}
