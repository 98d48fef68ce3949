//! `beltrami compare`: distances, normals, areas and volumes of a mesh against a
//! reference surface.
//!
//! Also holds what the metric commands (`compare`, `fit`, `residual`) share: loading an
//! input that must not be empty, the number format of their tables, and writing a
//! per-vertex scalar with a diverging colour map to a PLY file.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use beltrami_halfedge::geometry::{Geometry, VertexAreaKind};
use beltrami_io::{MeshData, MeshFormat, VertexAttributes, WriteOptions, stage_bytes, stage_ply};
use beltrami_metrics::MetricsError;
use beltrami_metrics::distance::{
    DistanceStats, HausdorffDistance, SampledDistance, SignedDistanceStats, SurfaceIndex,
    check_same_topology, displacement_stats, surface_distance,
};
use beltrami_metrics::measures::{closed_volume, surface_area};
use beltrami_metrics::normals::{NormalDeviation, normal_deviation};
use beltrami_viz::render::ColorMap;
use serde::Serialize;

use crate::error::CliError;
use crate::load::{LoadedMesh, ReadArgs, load};
use crate::output::{Outputs, Staged};
use crate::render::{ColorRange, DEFAULT_SIZE, VertexScalars, ViewKind, render_png};
use crate::text::number;

/// The seed of the surface samples of `--samples`: fixed, so that a run is repeatable.
const SAMPLE_SEED: u64 = 1;

/// Arguments of `beltrami compare`.
#[derive(Debug, clap::Args)]
pub(crate) struct CompareArgs {
    /// The mesh to judge (.ply, .stl, .obj, .off, or an .x3p or .sdf height map), e.g. a smoothed or measured surface.
    mesh: PathBuf,
    /// The reference surface (.ply, .stl, .obj, .off, or an .x3p or .sdf height map), e.g. the clean or nominal surface.
    reference: PathBuf,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
    /// Write MESH to this PLY file with the signed distance of every vertex as the
    /// property `signed_distance` and a colour map (blue inside, white on, red outside).
    #[arg(long, value_name = "OUT.ply")]
    scalars: Option<PathBuf>,
    /// Also draw MESH coloured by its signed distance to REFERENCE, with a colour bar,
    /// as `beltrami render MESH OUT.png --distance-to REFERENCE` does (iso view,
    /// 1200x900).
    #[arg(long, value_name = "OUT.png")]
    png: Option<PathBuf>,
    /// Also measure the Hausdorff distance from N points per surface spread uniformly
    /// by area (fixed seed), not only from the vertices, and the RMS distance of those
    /// points to the other surface each way ("surface rms", Metro's area-weighted error
    /// over whole faces) (N up to 10 million).
    #[arg(long, allow_hyphen_values = true, value_name = "N", value_parser = clap::value_parser!(u64).range(1..=10_000_000))]
    samples: Option<u64>,
    /// Replace the --scalars or --png file even when it is write-protected. They never
    /// replace MESH or REFERENCE.
    #[arg(long)]
    force: bool,
    #[command(flatten)]
    read: ReadArgs,
}

/// Everything `compare` reports; also the JSON schema of `compare --json`.
#[derive(Debug, Serialize)]
struct Comparison {
    mesh: MeshSummary,
    reference: MeshSummary,
    /// RMS of the unsigned vertex distances to the reference surface.
    rms: f64,
    /// Mean unsigned vertex distance.
    mean: f64,
    /// Largest unsigned vertex distance.
    max: f64,
    /// Area-weighted RMS (barycentric vertex areas of MESH).
    area_rms: f64,
    signed: Signed,
    /// The symmetric Hausdorff distance, max of the two one-sided ones.
    hausdorff: f64,
    hausdorff_mesh_to_reference: f64,
    hausdorff_reference_to_mesh: f64,
    /// Surface samples per surface on top of the vertices (0: vertices only).
    hausdorff_samples: u64,
    /// With `--samples`: the RMS distance of the surface samples of each surface to the
    /// other (Metro's RMS error, weighted by area over the whole surface, face interiors
    /// included); null without.
    surface_rms: Option<SurfaceRms>,
    /// Whether both meshes have the same vertices and faces.
    same_topology: bool,
    /// Plain per-vertex displacement `|x_i − y_i|`; null unless the topologies match.
    displacement: Option<Displacement>,
    /// Angles between corresponding face normals; null unless the topologies match.
    normal_deviation_deg: Option<NormalAngles>,
    /// The area-weighted normal error E_a (dimensionless); null with the angles.
    normal_area_weighted_error: Option<f64>,
    /// Enclosed volumes; null unless both meshes are closed.
    volume: Option<Volumes>,
    area: Areas,
    /// The `--scalars` output, or null.
    scalars: Option<Scalars>,
    /// The `--png` image, or null.
    png: Option<String>,
    /// What reading the files did besides reading them (a lenient read's skipped
    /// lines, `--weld`, `--repair`), one line each, naming the file; empty when nothing.
    notes: Vec<String>,
    /// Wall-clock seconds of each phase (JSON only).
    seconds: Seconds,
}

/// Wall-clock seconds spent in each phase of `compare`, so that the closest-point work
/// can be compared with other tools like for like. Not reproducible (timings).
#[derive(Debug, Serialize)]
struct Seconds {
    /// Reading both files and building their half-edge meshes.
    read: f64,
    /// Building both closest-point indexes (hierarchies and pseudo-normals).
    index_build: f64,
    /// The closest-point queries: MESH's vertices against REFERENCE (signed, also giving
    /// the unsigned distances and the mesh → reference Hausdorff distance), then
    /// REFERENCE's vertices (and surface samples) against MESH.
    queries: f64,
    /// Everything else: statistics, areas, volumes, normals, displacement, `--scalars`.
    other: f64,
    /// The whole command, from the start to just before printing.
    total: f64,
}

/// The sampled RMS distances of `compare --samples` (`SampledDistance::rms` each way).
#[derive(Debug, Serialize)]
struct SurfaceRms {
    /// The larger of the two one-sided values.
    symmetric: f64,
    mesh_to_reference: f64,
    reference_to_mesh: f64,
}

#[derive(Debug, Serialize)]
struct MeshSummary {
    file: String,
    vertices: usize,
    faces: usize,
    closed: bool,
}

#[derive(Debug, Serialize)]
struct Signed {
    mean: f64,
    min: f64,
    max: f64,
    std_dev: f64,
}

#[derive(Debug, Serialize)]
struct Displacement {
    rms: f64,
    mean: f64,
    max: f64,
    area_rms: f64,
}

#[derive(Debug, Serialize)]
struct NormalAngles {
    mean: f64,
    rms: f64,
    max: f64,
    /// Faces compared (degenerate ones are skipped).
    faces: usize,
}

#[derive(Debug, Serialize)]
struct Volumes {
    mesh: f64,
    reference: f64,
    /// `mesh / reference`; `None` when the reference encloses no volume.
    ratio: Option<f64>,
}

#[derive(Debug, Serialize)]
struct Areas {
    mesh: f64,
    reference: f64,
}

#[derive(Debug, Serialize)]
struct Scalars {
    file: String,
    /// The signed distance shown in full red (its negative in full blue).
    color_range: f64,
}

/// Runs `beltrami compare`.
pub(crate) fn run(args: &CompareArgs, out: &mut impl Write) -> Result<(), CliError> {
    check_outputs(args)?;
    let start = Instant::now();
    let mesh = load_input(&args.mesh, &args.read, Some("compare"))?;
    let reference = load_input(&args.reference, &args.read, Some("compare"))?;
    let read = start.elapsed().as_secs_f64();
    let on_mesh = metrics_error(&args.mesh);
    let on_reference = metrics_error(&args.reference);

    let d = distances(args, &mesh, &reference)?;
    let unsigned: Vec<f64> = d.signed.iter().map(|s| s.abs()).collect();
    let areas = Geometry::new(&mesh.mesh, &mesh.positions)
        .and_then(|g| g.vertex_areas(VertexAreaKind::Barycentric))
        .map_err(|e| on_mesh(e.into()))?;
    let stats = DistanceStats::new(&unsigned, areas.as_slice()).map_err(&on_mesh)?;
    let signed_stats = SignedDistanceStats::new(&d.signed).map_err(&on_mesh)?;

    let mut notes = Notes::default();
    let (displacement, normals) = vertex_to_vertex(args, &mesh, &reference, &mut notes)?;
    let mesh_geometry = geometry(&mesh).map_err(&on_mesh)?;
    let reference_geometry = geometry(&reference).map_err(&on_reference)?;
    let mesh_volume = closed_volume(&mesh_geometry).map_err(&on_mesh)?;
    let reference_volume = closed_volume(&reference_geometry).map_err(&on_reference)?;
    let reference_extent = beltrami_metrics::measures::surface_extent(&reference_geometry);
    notes.volume = match (mesh_volume, reference_volume) {
        (Some(_), Some(_)) => String::new(),
        (None, Some(_)) => format!("{} is open", args.mesh.display()),
        (Some(_), None) => format!("{} is open", args.reference.display()),
        (None, None) => "both meshes are open".to_string(),
    };
    let area = Areas {
        mesh: surface_area(&mesh_geometry).map_err(&on_mesh)?,
        reference: surface_area(&reference_geometry).map_err(&on_reference)?,
    };
    let scalars = write_outputs(args, &mesh, &d.signed)?;

    let h = d.hausdorff;
    let mut comparison = Comparison {
        mesh: summary(&args.mesh, &mesh),
        reference: summary(&args.reference, &reference),
        rms: stats.rms,
        mean: stats.mean,
        max: stats.max,
        area_rms: stats.area_weighted_rms,
        signed: Signed {
            mean: signed_stats.mean,
            min: signed_stats.min,
            max: signed_stats.max,
            std_dev: signed_stats.std_dev,
        },
        hausdorff: h.symmetric,
        hausdorff_mesh_to_reference: h.forward,
        hausdorff_reference_to_mesh: h.backward,
        hausdorff_samples: d.samples,
        surface_rms: d.sampled.map(|(there, back)| SurfaceRms {
            symmetric: there.rms.max(back.rms),
            mesh_to_reference: there.rms,
            reference_to_mesh: back.rms,
        }),
        same_topology: displacement.is_some(),
        displacement: displacement.map(|d| Displacement {
            rms: d.rms,
            mean: d.mean,
            max: d.max,
            area_rms: d.area_weighted_rms,
        }),
        normal_deviation_deg: normals.map(|n| NormalAngles {
            mean: n.mean_deg,
            rms: n.rms_deg,
            max: n.max_deg,
            faces: n.compared,
        }),
        normal_area_weighted_error: normals.map(|n| n.area_weighted_error),
        volume: mesh_volume
            .zip(reference_volume)
            .map(|(mesh, reference)| Volumes {
                mesh,
                reference,
                ratio: beltrami_metrics::measures::volume_ratio(mesh, reference, reference_extent),
            }),
        area,
        scalars: scalars.map(|(file, color_range)| Scalars { file, color_range }),
        png: args.png.as_ref().map(|p| p.display().to_string()),
        notes: [
            mesh.read_notes(&args.mesh, true),
            reference.read_notes(&args.reference, true),
        ]
        .concat(),
        seconds: Seconds {
            read,
            index_build: d.index_build,
            queries: d.queries,
            other: 0.0,
            total: 0.0,
        },
    };
    comparison.seconds.total = start.elapsed().as_secs_f64();
    comparison.seconds.other =
        (comparison.seconds.total - read - d.index_build - d.queries).max(0.0);
    if args.json {
        serde_json::to_writer_pretty(&mut *out, &comparison).map_err(std::io::Error::from)?;
        writeln!(out)?;
    } else {
        write_table(&comparison, &notes, out)?;
    }
    Ok(())
}

/// Checks the output options before anything is read: `--scalars` is a PLY file,
/// `--png` a PNG, and neither is an input or the other (see [`Outputs::check`]).
fn check_outputs(args: &CompareArgs) -> Result<(), CliError> {
    if let Some(path) = &args.scalars {
        check_ply_path("--scalars", path)?;
    }
    if let Some(path) = &args.png
        && !path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png"))
    {
        return Err(CliError::Usage(format!(
            "--png writes a PNG image: it must end in .png, got '{}'",
            path.display()
        )));
    }
    let mut outputs = Outputs::new();
    outputs
        .add_opt(args.scalars.as_ref(), "--scalars")
        .add_opt(args.png.as_ref(), "--png");
    outputs.check(&[&args.mesh, &args.reference], args.force)
}

/// The point-to-surface distances both ways and the seconds they took.
struct Distances {
    /// The signed distance of each of MESH's vertices to REFERENCE.
    signed: Vec<f64>,
    hausdorff: HausdorffDistance,
    /// `--samples` (0: vertices only).
    samples: u64,
    /// The sampled distances MESH → REFERENCE and back, with `--samples`.
    sampled: Option<(SampledDistance, SampledDistance)>,
    index_build: f64,
    queries: f64,
}

/// Builds both surfaces' closest-point indices and measures the signed vertex
/// distances and the two one-sided Hausdorff distances.
fn distances(
    args: &CompareArgs,
    mesh: &LoadedMesh,
    reference: &LoadedMesh,
) -> Result<Distances, CliError> {
    let on_mesh = metrics_error(&args.mesh);
    let on_reference = metrics_error(&args.reference);
    let clock = Instant::now();
    let reference_index =
        SurfaceIndex::new(&reference.mesh, &reference.positions).map_err(&on_reference)?;
    reference_index.prepare_signed();
    let mesh_index = SurfaceIndex::new(&mesh.mesh, &mesh.positions).map_err(&on_mesh)?;
    let index_build = clock.elapsed().as_secs_f64();

    let samples = args.samples.unwrap_or(0);
    let Ok(count) = usize::try_from(samples) else {
        return Err(CliError::Usage(format!("--samples {samples} is too large")));
    };
    let clock = Instant::now();
    // One closest-point query per vertex gives the signed and the unsigned distance, and
    // the vertex part of the mesh → reference Hausdorff distance; the surface samples
    // give both the sampled part of each Hausdorff distance and the surface RMS.
    let signed = reference_index
        .signed_distances(&mesh.positions)
        .map_err(&on_mesh)?;
    let both = surface_distance(&mesh_index, &signed, &reference_index, count, SAMPLE_SEED)
        .map_err(&on_mesh)?;
    Ok(Distances {
        signed,
        hausdorff: both.hausdorff,
        samples,
        sampled: both.sampled,
        index_build,
        queries: clock.elapsed().as_secs_f64(),
    })
}

/// The vertex-to-vertex figures of two meshes with one topology: displacements and
/// face-normal deviations; `None` (with the reason in `notes`) otherwise.
fn vertex_to_vertex(
    args: &CompareArgs,
    mesh: &LoadedMesh,
    reference: &LoadedMesh,
    notes: &mut Notes,
) -> Result<(Option<DistanceStats>, Option<NormalDeviation>), CliError> {
    let pair = pair_subject(&args.mesh, &args.reference);
    let on_pair = |source| CliError::Metrics {
        subject: pair.clone(),
        source,
    };
    match check_same_topology(&mesh.mesh, &reference.mesh) {
        Ok(()) => {
            let d = displacement_stats(
                &mesh.mesh,
                &mesh.positions,
                &reference.mesh,
                &reference.positions,
            )
            .map_err(&on_pair)?;
            let n = match normal_deviation(
                &mesh.mesh,
                &mesh.positions,
                &reference.mesh,
                &reference.positions,
            ) {
                Ok(n) => Some(n),
                Err(MetricsError::Empty { .. }) => {
                    notes.normals = "every face is degenerate".to_string();
                    None
                }
                Err(e) => return Err(on_pair(e)),
            };
            Ok((Some(d), n))
        }
        Err(MetricsError::TopologyMismatch { detail }) => {
            notes.topology = format!("the meshes do not share their topology: {detail}");
            notes.normals.clone_from(&notes.topology);
            Ok((None, None))
        }
        Err(e) => Err(on_pair(e)),
    }
}

/// Writes `--scalars` (MESH with its signed distances) and `--png` (MESH coloured by
/// them) as one staged write; returns the scalar file's name and colour range.
fn write_outputs(
    args: &CompareArgs,
    mesh: &LoadedMesh,
    signed: &[f64],
) -> Result<Option<(String, f64)>, CliError> {
    let mut staged = Staged::new();
    let scalars = match &args.scalars {
        Some(path) => Some(stage_scalar_ply(
            &mut staged,
            path,
            mesh,
            "signed_distance",
            signed,
        )?),
        None => None,
    };
    if let Some(path) = &args.png {
        let name = args.reference.file_name().map_or_else(
            || args.reference.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        let label = format!("signed distance to {name} (mesh units)");
        let rendered = render_png(
            &mesh.mesh,
            &mesh.positions,
            Some(VertexScalars {
                label: &label,
                values: signed,
                range: ColorRange::Symmetric,
            }),
            ViewKind::Iso,
            DEFAULT_SIZE,
            path,
        )?;
        staged.push(path, |path| stage_bytes(path, &rendered.bytes))?;
    }
    staged.commit()?;
    Ok(scalars)
}

/// Why a row of the table is empty.
#[derive(Debug, Default)]
struct Notes {
    topology: String,
    normals: String,
    volume: String,
}

fn summary(path: &Path, loaded: &LoadedMesh) -> MeshSummary {
    MeshSummary {
        file: path.display().to_string(),
        vertices: loaded.mesh.n_vertices(),
        faces: loaded.mesh.n_faces(),
        closed: loaded.mesh.is_closed(),
    }
}

/// The geometry of a loaded mesh.
fn geometry(loaded: &LoadedMesh) -> Result<Geometry<'_>, MetricsError> {
    Ok(Geometry::new(&loaded.mesh, &loaded.positions)?)
}

fn write_table(c: &Comparison, notes: &Notes, out: &mut impl Write) -> std::io::Result<()> {
    let n = |x: f64| number(x);
    for (title, rows) in table_sections(c, notes) {
        let indent = if title.is_empty() { "" } else { "  " };
        if !title.is_empty() {
            writeln!(out, "{title}")?;
        }
        for (key, value) in rows {
            writeln!(out, "{indent}{key:<w$} {value}", w = 21 - indent.len())?;
        }
    }
    if let Some(s) = &c.scalars {
        writeln!(
            out,
            "signed distances -> {} (signed_distance; colours: blue {}, white 0, red {})",
            s.file,
            n(-s.color_range),
            n(s.color_range)
        )?;
    }
    if let Some(png) = &c.png {
        writeln!(out, "image of the signed distances -> {png}")?;
    }
    for line in &c.notes {
        writeln!(out, "{line}")?;
    }
    Ok(())
}

/// The sections of the table (a title, empty for the unindented first one, and the
/// rows' keys and values).
fn table_sections(
    c: &Comparison,
    notes: &Notes,
) -> [(&'static str, Vec<(&'static str, String)>); 4] {
    let n = |x: f64| number(x);
    let describe = |m: &MeshSummary| {
        format!(
            "{} ({} vertices, {} faces, {})",
            m.file,
            m.vertices,
            m.faces,
            if m.closed { "closed" } else { "open" }
        )
    };
    [
        (
            "", // the files, unindented
            vec![
                ("mesh", describe(&c.mesh)),
                ("reference", describe(&c.reference)),
                (
                    "unit",
                    "the files' length unit (areas in unit², volumes in unit³), not scaled"
                        .to_string(),
                ),
            ],
        ),
        (
            "distance of the mesh's vertices to the reference surface (closest point on the closest triangle)",
            vec![
                ("rms", n(c.rms)),
                ("mean", n(c.mean)),
                ("max", n(c.max)),
                ("area-weighted rms", n(c.area_rms)),
            ],
        ),
        (
            "signed distance (positive on the side the reference's normals point to: outside)",
            vec![
                ("mean", n(c.signed.mean)),
                ("min", n(c.signed.min)),
                ("max", n(c.signed.max)),
                ("std dev", n(c.signed.std_dev)),
            ],
        ),
        ("surfaces", surface_rows(c, notes)),
    ]
}

/// The rows of the "surfaces" section: Hausdorff distance, surface RMS (with
/// `--samples`), displacement, normal
/// deviation, area and volume (with why one is missing).
fn surface_rows(c: &Comparison, notes: &Notes) -> Vec<(&'static str, String)> {
    let n = |x: f64| number(x);
    let hausdorff_points = if c.hausdorff_samples == 0 {
        "vertices".to_string()
    } else {
        format!("vertices and {} surface samples", c.hausdorff_samples)
    };
    let mut rows = vec![(
        "hausdorff",
        format!(
            "{} (mesh -> reference {}, reference -> mesh {}; from {hausdorff_points})",
            n(c.hausdorff),
            n(c.hausdorff_mesh_to_reference),
            n(c.hausdorff_reference_to_mesh),
        ),
    )];
    if let Some(r) = &c.surface_rms {
        rows.push((
            "surface rms",
            format!(
                "{} (mesh -> reference {}, reference -> mesh {}; from {} surface samples each)",
                n(r.symmetric),
                n(r.mesh_to_reference),
                n(r.reference_to_mesh),
                c.hausdorff_samples,
            ),
        ));
    }
    rows.extend([
        (
            "displacement",
            c.displacement.as_ref().map_or_else(
                || format!("- ({})", notes.topology),
                |d| {
                    format!(
                        "rms {}, mean {}, max {}, area-weighted rms {} (vertex i to vertex i)",
                        n(d.rms),
                        n(d.mean),
                        n(d.max),
                        n(d.area_rms)
                    )
                },
            ),
        ),
        (
            "normal deviation",
            match (&c.normal_deviation_deg, c.normal_area_weighted_error) {
                (Some(a), Some(e)) => format!(
                    "mean {}°, rms {}°, max {}° over {} faces; area-weighted error {}",
                    n(a.mean),
                    n(a.rms),
                    n(a.max),
                    a.faces,
                    n(e)
                ),
                _ => format!("- ({})", notes.normals),
            },
        ),
        (
            "area",
            format!("mesh {}, reference {}", n(c.area.mesh), n(c.area.reference)),
        ),
        (
            "volume",
            c.volume.as_ref().map_or_else(
                || format!("- ({})", notes.volume),
                |v| {
                    format!(
                        "mesh {}, reference {}, ratio {}",
                        n(v.mesh),
                        n(v.reference),
                        v.ratio
                            .map_or_else(|| "- (the reference encloses no volume)".to_string(), n)
                    )
                },
            ),
        ),
    ]);
    rows
}

/// `"a.ply vs b.ply"`: the subject of an error about a pair of files.
pub(crate) fn pair_subject(a: &Path, b: &Path) -> String {
    format!("{} vs {}", a.display(), b.display())
}

/// Turns a metrics error about the file at `path` into a CLI error.
pub(crate) fn metrics_error(path: &Path) -> impl Fn(MetricsError) -> CliError + '_ {
    move |source| CliError::Metrics {
        subject: path.display().to_string(),
        source,
    }
}

/// Reads a mesh for a metric command (no repairs: the numbers are about the file as it
/// is). An input without vertices is an error; so is one without faces when
/// `needs_surface` names what needs them.
pub(crate) fn load_input(
    path: &Path,
    read: &ReadArgs,
    needs_surface: Option<&'static str>,
) -> Result<LoadedMesh, CliError> {
    let loaded = load(path, read)?;
    if loaded.mesh.n_vertices() == 0 {
        return Err(metrics_error(path)(MetricsError::Empty { what: "mesh" }));
    }
    if let Some(needed_by) = needs_surface {
        loaded.require_faces(path, needed_by)?;
    }
    Ok(loaded)
}

/// Fails with a usage error unless `path` names a PLY file (an option that writes
/// per-vertex scalars, which only PLY holds).
pub(crate) fn check_ply_path(option: &str, path: &Path) -> Result<(), CliError> {
    if MeshFormat::from_path(path).ok() == Some(MeshFormat::Ply) {
        Ok(())
    } else {
        Err(CliError::Usage(format!(
            "{option} writes a PLY file (per-vertex scalars need PLY), got '{}'",
            path.display()
        )))
    }
}

/// Stages `loaded` (its positions and faces as read) for the PLY file `path` with one
/// scalar per vertex as `property double <name>` and vertex colours from a diverging
/// map symmetric about 0 (blue at `−m`, white at 0, red at `m`, with `m` the largest
/// absolute value); the file is written when `staged` is committed. Returns the file
/// name and `m`.
pub(crate) fn stage_scalar_ply(
    staged: &mut Staged,
    path: &Path,
    loaded: &LoadedMesh,
    name: &str,
    values: &[f64],
) -> Result<(String, f64), CliError> {
    let map = ColorMap::symmetric_for(values);
    let data = MeshData {
        positions: loaded.positions.clone(),
        faces: loaded.faces.clone(),
    };
    let attributes = VertexAttributes {
        scalars: vec![(name.to_string(), values.to_vec())],
        colors: Some(values.iter().map(|&v| map.color(v)).collect()),
    };
    staged.push(path, |path| {
        stage_ply(path, &data, &attributes, &WriteOptions::default())
    })?;
    Ok((path.display().to_string(), map.max))
}
