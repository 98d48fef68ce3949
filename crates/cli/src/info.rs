//! `beltrami info`: counts, topology and geometry of a mesh.

use std::io::Write;
use std::path::PathBuf;

use beltrami_halfedge::geometry::Geometry;
use beltrami_io::MeshFormat;
use serde::Serialize;

use crate::error::CliError;
use crate::load::{LoadedMesh, load};

/// Arguments of `beltrami info`.
#[derive(Debug, clap::Args)]
pub(crate) struct InfoArgs {
    /// The mesh file (.ply, .stl or .obj).
    mesh: PathBuf,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
    /// Repair what is well defined (drop degenerate faces, re-orient, split pinched
    /// vertices) instead of failing, and report what changed.
    #[arg(long)]
    repair: bool,
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
    /// Genus of a closed, connected mesh; null otherwise.
    genus: Option<u32>,
    isolated_vertices: usize,
    degenerate_faces: usize,
    bbox_min: Option<[f64; 3]>,
    bbox_max: Option<[f64; 3]>,
    mean_edge_length: Option<f64>,
    area: f64,
    /// Enclosed volume of a closed mesh; null when open.
    volume: Option<f64>,
    repairs: Repairs,
}

#[derive(Debug, Serialize)]
struct Repairs {
    dropped_faces: Vec<usize>,
    flipped_faces: Vec<usize>,
    split_vertices: Vec<u32>,
}

fn format_name(format: MeshFormat) -> &'static str {
    match format {
        MeshFormat::Ply => "PLY",
        MeshFormat::Stl => "STL",
        MeshFormat::Obj => "OBJ",
        _ => "unknown",
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
        components: mesh.connected_components().count(),
        euler_characteristic: mesh.euler_characteristic(),
        closed: mesh.is_closed(),
        genus: mesh.genus(),
        isolated_vertices: mesh.vertices().filter(|&v| mesh.is_isolated(v)).count(),
        degenerate_faces,
        bbox_min: bbox.map(|(lo, _)| lo.to_array()),
        bbox_max: bbox.map(|(_, hi)| hi.to_array()),
        mean_edge_length: geometry.mean_edge_length(),
        area: geometry.surface_area(),
        volume: geometry.volume().ok(),
        repairs: Repairs {
            dropped_faces: loaded.report.dropped_faces.clone(),
            flipped_faces: loaded.report.flipped_faces.clone(),
            split_vertices: loaded
                .report
                .split_vertices
                .iter()
                .map(|s| s.original.raw())
                .collect(),
        },
    }
}

/// Runs `beltrami info`.
pub(crate) fn run(args: &InfoArgs, out: &mut impl Write) -> Result<(), CliError> {
    let loaded = load(&args.mesh, args.repair)?;
    let summary = summarise(args, &loaded);
    if args.json {
        serde_json::to_writer_pretty(&mut *out, &summary).map_err(std::io::Error::from)?;
        writeln!(out)?;
    } else {
        write_table(&summary, out)?;
    }
    Ok(())
}

fn opt<T: std::fmt::Display>(value: Option<T>, none: &str) -> String {
    value.map_or_else(|| none.to_string(), |v| v.to_string())
}

fn vec3(v: [f64; 3]) -> String {
    format!("({}, {}, {})", v[0], v[1], v[2])
}

fn write_table(s: &Summary, out: &mut impl Write) -> std::io::Result<()> {
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
        ("genus", opt(s.genus, "- (open or several components)")),
        ("isolated vertices", s.isolated_vertices.to_string()),
        ("degenerate faces", s.degenerate_faces.to_string()),
        ("bbox min", opt(s.bbox_min.map(vec3), "-")),
        ("bbox max", opt(s.bbox_max.map(vec3), "-")),
        ("mean edge length", opt(s.mean_edge_length, "-")),
        ("area", s.area.to_string()),
        ("volume", opt(s.volume, "- (open mesh)")),
    ];
    for (key, value) in rows {
        writeln!(out, "{key:<21} {value}")?;
    }
    let r = &s.repairs;
    if !r.dropped_faces.is_empty() {
        writeln!(
            out,
            "repaired: dropped {} degenerate face(s): {:?}",
            r.dropped_faces.len(),
            r.dropped_faces
        )?;
    }
    if !r.flipped_faces.is_empty() {
        writeln!(
            out,
            "repaired: flipped {} face(s): {:?}",
            r.flipped_faces.len(),
            r.flipped_faces
        )?;
    }
    if !r.split_vertices.is_empty() {
        writeln!(
            out,
            "repaired: split {} pinched vertex copy(ies) of vertices {:?}",
            r.split_vertices.len(),
            r.split_vertices
        )?;
    }
    Ok(())
}
