//! `beltrami info`: counts, topology and geometry of a mesh.

use std::io::Write;
use std::path::PathBuf;

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::{DVec3, HalfedgeMesh};
use beltrami_io::MeshFormat;
use serde::Serialize;

use crate::error::CliError;
use crate::load::{LoadedMesh, ReadArgs, coincident_vertices, load};
use crate::repair::RepairJson;
use crate::text::{counted, number, vector};

/// Arguments of `beltrami info`.
#[derive(Debug, clap::Args)]
pub(crate) struct InfoArgs {
    /// The mesh file (.ply, .stl, .obj or .off).
    mesh: PathBuf,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
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
}

fn format_name(format: MeshFormat) -> &'static str {
    match format {
        MeshFormat::Ply => "PLY",
        MeshFormat::Stl => "STL",
        MeshFormat::Obj => "OBJ",
        MeshFormat::Off => "OFF",
        _ => "mesh",
    }
}

fn summarise(args: &InfoArgs, loaded: &LoadedMesh) -> Summary {
    let mesh = &loaded.mesh;
    let geometry =
        Geometry::new(mesh, &loaded.positions).expect("the loader gives one position per vertex");
    let mut loop_lengths: Vec<usize> = mesh.boundary_loops().map(|l| l.len()).collect();
    loop_lengths.sort_unstable_by(|a, b| b.cmp(a));
    let bbox = geometry.bounding_box();
    let triangle_mesh = mesh.is_triangle_mesh();
    let components = mesh.connected_components();
    let component_genus: Vec<Option<u32>> =
        components.summaries.iter().map(|c| c.genus()).collect();
    let degenerate_faces = mesh
        .faces()
        .filter(|&f| geometry.is_degenerate_face(f))
        .count();
    Summary {
        file: args.mesh.display().to_string(),
        format: format_name(loaded.format),
        vertices: mesh.n_vertices(),
        faces: mesh.n_faces(),
        edges: mesh.n_edges(),
        triangle_mesh,
        boundary_loops: loop_lengths.len(),
        boundary_loop_lengths: loop_lengths,
        components: components.count(),
        euler_characteristic: mesh.euler_characteristic(),
        closed: mesh.n_faces() > 0 && mesh.is_closed(),
        genus: match component_genus.as_slice() {
            [only] => *only,
            _ => None,
        },
        component_genus,
        isolated_vertices: mesh.vertices().filter(|&v| mesh.is_isolated(v)).count(),
        degenerate_faces,
        bbox_min: bbox.map(|(lo, _)| lo.to_array()),
        bbox_max: bbox.map(|(_, hi)| hi.to_array()),
        mean_edge_length: geometry.mean_edge_length(),
        area: surface_area(&geometry, mesh, &loaded.positions),
        volume: geometry.volume().ok(),
        repairs: RepairJson::from(&loaded.repair.clone().unwrap_or_default()),
    }
}

/// The surface area, computed again at a power-of-two scale when the face areas
/// overflow (coordinates beyond about 1e154), so that `inf` means that the true area
/// is beyond `f64`.
fn surface_area(geometry: &Geometry<'_>, mesh: &HalfedgeMesh, positions: &[DVec3]) -> f64 {
    let area = geometry.surface_area();
    if area.is_finite() {
        return area;
    }
    let largest = positions
        .iter()
        .map(|p| p.abs().max_element())
        .fold(0.0f64, f64::max);
    if !largest.is_finite() || largest == 0.0 {
        return area;
    }
    // 2^-k with 2^k near the largest coordinate: exact scaling, areas scale by 4^-k.
    let k = largest.log2().ceil();
    let scale = (-k).exp2();
    let scaled: Vec<DVec3> = positions.iter().map(|p| *p * scale).collect();
    match Geometry::new(mesh, &scaled) {
        Ok(g) => g.surface_area() * (2.0 * k).exp2(),
        Err(_) => area,
    }
}

/// Runs `beltrami info`.
pub(crate) fn run(args: &InfoArgs, out: &mut impl Write) -> Result<(), CliError> {
    let mut loaded = load(&args.mesh, &args.read)?;
    // Pieces with boundaries may be one surface written apart at seams: say so.
    if !args.json
        && loaded.repair.is_none()
        && !loaded.mesh.is_closed()
        && loaded.mesh.connected_components().count() > 1
        && let Some((n, d)) = coincident_vertices(&loaded.positions, &loaded.faces)
    {
        loaded.repair_lines.push(format!(
            "note: {} within {} of another, so the surface is in pieces along them (texture seams, an exporter's duplicates?); --repair --merge-distance {} joins them",
            counted(n, "vertex lies", "vertices lie"),
            number(d),
            number(d)
        ));
    }
    let summary = summarise(args, &loaded);
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
    let rows: Vec<(&str, String)> = vec![
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
    for (key, value) in rows {
        writeln!(out, "{key:<21} {value}")?;
    }
    for line in repair_lines {
        writeln!(out, "{line}")?;
    }
    Ok(())
}
