//! `beltrami info`: counts, topology and geometry of a mesh.

use std::io::Write;
use std::path::PathBuf;

use beltrami_algorithms::quality::ASPECT_RATIO_BINS;
use beltrami_algorithms::{MeshQuality, QualityError, flipped_faces, mesh_quality};
use beltrami_halfedge::DVec3;
use beltrami_halfedge::geometry::Geometry;
use serde::Serialize;

use crate::error::{CliError, not_triangles};
use crate::load::{LoadedMesh, ReadArgs, coincident_vertices, load};
use crate::repair::RepairJson;
use crate::text::{counted, number, vector};

/// Arguments of `beltrami info`.
#[derive(Debug, clap::Args)]
pub(crate) struct InfoArgs {
    /// The mesh file (.ply, .stl, .obj, .off, or an .x3p or .sdf height map).
    mesh: PathBuf,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
    /// Also measure triangle quality: angles, aspect ratios, edge-length spread,
    /// valences and negative cotangent weights (a triangle mesh only).
    #[arg(long)]
    quality: bool,
    /// With --quality: count the faces whose orientation turned against this mesh,
    /// which must have the same vertices and faces (e.g. the input of a smoothing
    /// run).
    #[arg(long, value_name = "MESH", requires = "quality")]
    reference: Option<PathBuf>,
    #[command(flatten)]
    read: ReadArgs,
}

/// Everything `info` reports; also the JSON schema of `info --json`.
#[derive(Debug, Serialize)]
struct Summary {
    file: String,
    format: &'static str,
    vertices: usize,
    faces: usize,
    edges: usize,
    triangle_mesh: bool,
    boundary_loops: usize,
    boundary_loop_lengths: Vec<usize>,
    components: usize,
    euler_characteristic: i64,
    closed: bool,
    /// Genus of a connected mesh, open or closed (χ = 2 − 2g − b); null for several
    /// components (see `component_genus`) or a mesh without faces.
    genus: Option<u32>,
    /// The genus of each connected component, in the order of their lowest vertex;
    /// null for an isolated vertex.
    component_genus: Vec<Option<u32>>,
    isolated_vertices: usize,
    degenerate_faces: usize,
    bbox_min: Option<[f64; 3]>,
    bbox_max: Option<[f64; 3]>,
    mean_edge_length: Option<f64>,
    area: f64,
    /// Enclosed volume of a closed mesh; null when open.
    volume: Option<f64>,
    /// What --repair changed (empty lists without it).
    repairs: RepairJson,
    /// With --quality.
    #[serde(skip_serializing_if = "Option::is_none")]
    quality: Option<QualityJson>,
}

/// The JSON of `info --quality`: [`MeshQuality`] with the angles in degrees.
#[derive(Debug, Serialize)]
pub(crate) struct QualityJson {
    degenerate_faces: usize,
    pub(crate) min_angle_degrees: Option<f64>,
    max_angle_degrees: Option<f64>,
    pub(crate) mean_min_angle_degrees: Option<f64>,
    mean_aspect_ratio: Option<f64>,
    pub(crate) max_aspect_ratio: Option<f64>,
    /// Upper ends of the aspect-ratio bins; the last bin is open.
    aspect_ratio_bins: Vec<f64>,
    aspect_ratio_histogram: Vec<usize>,
    edge_length_min: Option<f64>,
    edge_length_mean: Option<f64>,
    edge_length_max: Option<f64>,
    pub(crate) edge_length_cv: Option<f64>,
    /// Index k: interior vertices with k edges.
    valence_histogram: Vec<usize>,
    /// Index k: boundary vertices with k edges.
    boundary_valence_histogram: Vec<usize>,
    /// Share of vertices with valence 6 (4 on the boundary), 0 to 1.
    pub(crate) regular_share: f64,
    interior_edges: usize,
    negative_cotangent_edges: usize,
    pub(crate) negative_cotangent_share: f64,
    /// Faces turned against --reference; null without it.
    flipped_faces: Option<usize>,
}

impl QualityJson {
    pub(crate) fn new(q: &MeshQuality, flipped_faces: Option<usize>) -> Self {
        let shape = q.shape.as_ref();
        let edges = q.edge_length.as_ref();
        Self {
            degenerate_faces: q.degenerate_faces,
            min_angle_degrees: shape.map(|s| s.min_angle),
            max_angle_degrees: shape.map(|s| s.max_angle),
            mean_min_angle_degrees: shape.map(|s| s.mean_min_angle),
            mean_aspect_ratio: shape.map(|s| s.mean_aspect_ratio),
            max_aspect_ratio: shape.map(|s| s.max_aspect_ratio),
            aspect_ratio_bins: ASPECT_RATIO_BINS.to_vec(),
            aspect_ratio_histogram: shape.map_or_else(
                || vec![0; ASPECT_RATIO_BINS.len() + 1],
                |s| s.aspect_ratio_histogram.clone(),
            ),
            edge_length_min: edges.map(|e| e.min),
            edge_length_mean: edges.map(|e| e.mean),
            edge_length_max: edges.map(|e| e.max),
            edge_length_cv: edges.map(|e| e.cv),
            valence_histogram: q.valence_histogram.clone(),
            boundary_valence_histogram: q.boundary_valence_histogram.clone(),
            regular_share: q.regular_share,
            interior_edges: q.interior_edges,
            negative_cotangent_edges: q.negative_cotangent_edges,
            negative_cotangent_share: q.negative_cotangent_share(),
            flipped_faces,
        }
    }

    /// The rows `info --quality` prints under the table.
    pub(crate) fn rows(&self) -> Vec<(&'static str, String)> {
        let deg = |a: Option<f64>| a.map_or_else(|| "-".to_string(), |a| format!("{}°", number(a)));
        let mut rows = vec![
            (
                "angles",
                format!(
                    "min {}, max {}, mean of the smallest {}",
                    deg(self.min_angle_degrees),
                    deg(self.max_angle_degrees),
                    deg(self.mean_min_angle_degrees)
                ),
            ),
            (
                "aspect ratio",
                match (self.mean_aspect_ratio, self.max_aspect_ratio) {
                    (Some(mean), Some(max)) => {
                        let mut bins = Vec::new();
                        let mut lo = 1.0;
                        for (i, n) in self.aspect_ratio_histogram.iter().enumerate() {
                            let label = match self.aspect_ratio_bins.get(i) {
                                Some(hi) => format!("{}-{}", number(lo), number(*hi)),
                                None => format!(">={}", number(lo)),
                            };
                            if let Some(hi) = self.aspect_ratio_bins.get(i) {
                                lo = *hi;
                            }
                            bins.push(format!("{label}: {n}"));
                        }
                        format!(
                            "mean {}, max {} ({})",
                            number(mean),
                            number(max),
                            bins.join(", ")
                        )
                    }
                    _ => "-".to_string(),
                },
            ),
            (
                "edge length",
                match (
                    self.edge_length_min,
                    self.edge_length_max,
                    self.edge_length_cv,
                ) {
                    (Some(lo), Some(hi), Some(cv)) => format!(
                        "min {}, max {}, coefficient of variation {}",
                        number(lo),
                        number(hi),
                        number(cv)
                    ),
                    _ => "-".to_string(),
                },
            ),
            (
                "valences",
                format!(
                    "{} regular (6 inside, 4 on the boundary); inside {}{}",
                    percent(self.regular_share),
                    histogram(&self.valence_histogram),
                    if self.boundary_valence_histogram.is_empty() {
                        String::new()
                    } else {
                        format!("; boundary {}", histogram(&self.boundary_valence_histogram))
                    }
                ),
            ),
            (
                "negative cotangent",
                format!(
                    "{} of {} interior edges ({})",
                    self.negative_cotangent_edges,
                    self.interior_edges,
                    percent(self.negative_cotangent_share)
                ),
            ),
        ];
        if let Some(n) = self.flipped_faces {
            rows.push(("flipped faces", format!("{n} against the reference")));
        }
        rows
    }
}

fn percent(share: f64) -> String {
    format!("{}%", number(100.0 * share))
}

/// `k:n` pairs of the non-empty valences.
fn histogram(counts: &[usize]) -> String {
    let pairs: Vec<String> = counts
        .iter()
        .enumerate()
        .filter(|(_, n)| **n > 0)
        .map(|(k, n)| format!("{k}:{n}"))
        .collect();
    if pairs.is_empty() {
        "-".to_string()
    } else {
        pairs.join(" ")
    }
}

fn summarise(args: &InfoArgs, loaded: &LoadedMesh, quality: Option<QualityJson>) -> Summary {
    let s = Geometry::new(&loaded.mesh, &loaded.positions)
        .expect("the loader gives one position per vertex")
        .summary();
    Summary {
        file: args.mesh.display().to_string(),
        format: loaded.format.name(),
        vertices: s.vertices,
        faces: s.faces,
        edges: s.edges,
        triangle_mesh: s.triangle_mesh,
        boundary_loops: s.boundary_loop_lengths.len(),
        boundary_loop_lengths: s.boundary_loop_lengths,
        components: s.components,
        euler_characteristic: s.euler_characteristic,
        closed: s.closed,
        genus: s.genus,
        component_genus: s.component_genus,
        isolated_vertices: s.isolated_vertices,
        degenerate_faces: s.degenerate_faces,
        bbox_min: s.bounding_box.map(|(lo, _)| lo.to_array()),
        bbox_max: s.bounding_box.map(|(_, hi)| hi.to_array()),
        mean_edge_length: s.mean_edge_length,
        area: s.area,
        volume: s.volume,
        repairs: RepairJson::from(&loaded.repair.clone().unwrap_or_default()),
        quality,
    }
}

/// The quality figures of `info --quality`, with the flipped faces against
/// `--reference`.
fn measure_quality(args: &InfoArgs, loaded: &mut LoadedMesh) -> Result<QualityJson, CliError> {
    let input_error = |path: &PathBuf, e: QualityError| CliError::Input {
        path: path.clone(),
        message: match e {
            QualityError::NotTriangle { face, len } => not_triangles("--quality", face, len),
            e => e.to_string(),
        },
    };
    let quality =
        mesh_quality(&loaded.mesh, &loaded.positions).map_err(|e| input_error(&args.mesh, e))?;
    let flipped = match &args.reference {
        None => None,
        Some(path) => {
            let reference = load(path, &args.read)?;
            loaded.repair_lines.extend(reference.read_notes(path, true));
            if reference.faces != loaded.faces {
                let (theirs, ours) = (reference.faces.len(), loaded.faces.len());
                let how = match reference
                    .faces
                    .iter()
                    .zip(loaded.faces.iter())
                    .position(|(a, b)| a != b)
                {
                    Some(f) if theirs == ours => format!(
                        "face {f} is ({}) there against ({}) here: the same number of faces, numbered differently (a format that welds its vertices, as STL does, renumbers them)",
                        face_text(reference.faces.get(f)),
                        face_text(loaded.faces.get(f))
                    ),
                    _ => format!("{theirs} faces against {ours}"),
                };
                return Err(CliError::Input {
                    path: path.clone(),
                    message: format!(
                        "--reference must have the same faces as {} ({how}); the flipped-face count compares two placements of one mesh",
                        args.mesh.display(),
                    ),
                });
            }
            Some(
                flipped_faces(&loaded.mesh, &loaded.positions, &reference.positions)
                    .map_err(|e| input_error(path, e))?,
            )
        }
    };
    Ok(QualityJson::new(&quality, flipped))
}

/// Runs `beltrami info`.
pub(crate) fn run(args: &InfoArgs, out: &mut impl Write) -> Result<(), CliError> {
    let mut loaded = load(&args.mesh, &args.read)?;
    // Pieces with boundaries may be one surface written apart at seams: say so.
    if !args.json
        && loaded.repair.is_none()
        && !loaded.mesh.is_closed()
        && loaded.mesh.connected_components().count() > 1
        && let Some(c) = coincident_vertices(&loaded.positions, &loaded.faces)
    {
        let lie = counted(c.vertices, "vertex lies", "vertices lie");
        let (them, d) = (
            if c.vertices == 1 { "it" } else { "them" },
            number(c.distance),
        );
        loaded.repair_lines.push(if c.rejoined == 0 {
            format!(
                "note: {lie} within {d} of another, so the surface is in pieces along {them} (texture seams, an exporter's duplicates?); --repair --merge-distance {d} joins {them}"
            )
        } else if c.rejoined >= c.vertices {
            // Joining them would undo a repair: say why they are apart instead.
            format!(
                "note: {lie} within {d} of another, so the surface is in pieces along {them}; joined, they would make it non-manifold (an edge of more than two faces or a pinched vertex, which `repair` splits apart), so leave {them} apart"
            )
        } else {
            format!(
                "note: {lie} within {d} of another, so the surface is in pieces along {them}; --repair --merge-distance {d} joins them where the surface stays manifold ({} would be split apart again)",
                c.rejoined
            )
        });
    }
    let quality = if args.quality {
        Some(measure_quality(args, &mut loaded)?)
    } else {
        None
    };
    let summary = summarise(args, &loaded, quality);
    if !args.json && summary.degenerate_faces > 0 && summary.triangle_mesh {
        loaded.repair_lines.push(format!(
            "note: {} of zero area (flat for {} size): cotangent weights treat {it} as absent and remeshing splits {it} into more; `beltrami repair {} OUT --flat-faces` removes flat triangles without moving the surface",
            counted(summary.degenerate_faces, "face is", "faces are"),
            if summary.degenerate_faces == 1 { "its" } else { "their" },
            args.mesh.display(),
            it = if summary.degenerate_faces == 1 { "it" } else { "them" },
        ));
    }
    if args.json {
        serde_json::to_writer_pretty(&mut *out, &summary).map_err(std::io::Error::from)?;
        writeln!(out)?;
    } else {
        write_table(&summary, &loaded.repair_lines, out)?;
    }
    Ok(())
}

fn opt<T: std::fmt::Display>(value: Option<T>, none: &str) -> String {
    value.map_or_else(|| none.to_string(), |v| v.to_string())
}

fn vec3(v: [f64; 3]) -> String {
    vector(DVec3::from_array(v))
}

fn write_table(s: &Summary, repair_lines: &[String], out: &mut impl Write) -> std::io::Result<()> {
    let mut rows: Vec<(&str, String)> = vec![
        ("file", format!("{} ({})", s.file, s.format)),
        ("vertices", s.vertices.to_string()),
        (
            "faces",
            format!(
                "{}{}",
                s.faces,
                if s.triangle_mesh {
                    " (triangles)"
                } else {
                    " (polygons)"
                }
            ),
        ),
        ("edges", s.edges.to_string()),
        (
            "boundary loops",
            if s.boundary_loops == 0 {
                "0".to_string()
            } else {
                let lengths: Vec<String> = s
                    .boundary_loop_lengths
                    .iter()
                    .map(ToString::to_string)
                    .collect();
                format!("{} (edges: {})", s.boundary_loops, lengths.join(", "))
            },
        ),
        ("components", s.components.to_string()),
        ("euler characteristic", s.euler_characteristic.to_string()),
        ("closed", if s.closed { "yes" } else { "no" }.to_string()),
        (
            "genus",
            match (s.genus, s.component_genus.len()) {
                (Some(g), _) => g.to_string(),
                (None, 0 | 1) => "- (no faces)".to_string(),
                (None, _) => format!(
                    "per component: {}",
                    s.component_genus
                        .iter()
                        .map(|g| opt(*g, "-"))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            },
        ),
        ("isolated vertices", s.isolated_vertices.to_string()),
        ("degenerate faces", s.degenerate_faces.to_string()),
        ("bbox min", opt(s.bbox_min.map(vec3), "-")),
        ("bbox max", opt(s.bbox_max.map(vec3), "-")),
        ("mean edge length", opt(s.mean_edge_length.map(number), "-")),
        ("area", number(s.area)),
        ("volume", opt(s.volume.map(number), "- (open mesh)")),
    ];
    if let Some(q) = &s.quality {
        rows.extend(q.rows());
    }
    for (key, value) in rows {
        writeln!(out, "{key:<21} {value}")?;
    }
    for line in repair_lines {
        writeln!(out, "{line}")?;
    }
    Ok(())
}

/// A face's vertex indices as "a b c".
fn face_text(face: Option<&[u32]>) -> String {
    face.unwrap_or_default()
        .iter()
        .map(u32::to_string)
        .collect::<Vec<_>>()
        .join(" ")
}
