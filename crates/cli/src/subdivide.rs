//! `beltrami subdivide`: Loop or √3 subdivision of a triangle mesh.

use std::io::Write;
use std::path::{Path, PathBuf};

use beltrami_algorithms::{MeshCounts, Scheme};
use beltrami_halfedge::{HalfedgeMesh, MAX_ELEMENTS};
use clap::ValueEnum;
use serde::Serialize;

use crate::error::{CliError, not_triangles};
use crate::load::{ReadArgs, load};
use crate::memory::Size;
use crate::output::{Outputs, notes_for_output, refuse_height_map_output, write_result};
use crate::text::counted;

/// Arguments of `beltrami subdivide`.
#[derive(Debug, clap::Args)]
pub(crate) struct SubdivideArgs {
    /// The triangle mesh to subdivide (.ply, .stl, .obj, .off, or an .x3p or .sdf height map).
    input: PathBuf,
    /// The subdivided mesh (.ply, .stl, .obj or .off by extension).
    output: PathBuf,
    /// The scheme: loop (Loop 1987: each triangle becomes 4, about 4x the vertices per
    /// step) or sqrt3 (Kobbelt 2000: each triangle becomes 3, two steps split every
    /// edge in three). Both match OpenMesh's LoopT and Sqrt3T, boundary rules included.
    #[arg(long, value_enum, default_value_t = SchemeArg::Loop)]
    scheme: SchemeArg,
    /// The number of steps (at least 1). A step that would make more elements than a
    /// mesh holds, or need more memory than is available, is refused before any work.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    steps: u32,
    /// Print a JSON summary (counts before and after) instead of the sentence.
    #[arg(long)]
    json: bool,
    /// Write PLY (and STL) as ascii text instead of binary.
    #[arg(long)]
    ascii: bool,
    /// Replace OUTPUT even when it is the input (an edit in place) or write-protected.
    #[arg(long)]
    force: bool,
    #[command(flatten)]
    read: ReadArgs,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum SchemeArg {
    Loop,
    Sqrt3,
}

impl SchemeArg {
    fn scheme(self) -> Scheme {
        match self {
            Self::Loop => Scheme::Loop,
            Self::Sqrt3 => Scheme::Sqrt3,
        }
    }
}

/// Refuses a `--steps` whose result would not fit in a mesh or in memory, naming the
/// largest number of steps that fits.
fn check_size(mesh: &HalfedgeMesh, scheme: Scheme, steps: u32) -> Result<MeshCounts, CliError> {
    let available = beltrami_io::available_memory();
    let base = crate::memory::BASE_BYTES;
    let counts = scheme.counts(mesh, steps as usize);
    if scheme.fits(mesh, steps as usize, available, base) {
        return Ok(counts);
    }
    let largest = scheme.most_steps_that_fit(mesh, steps as usize, available, base);
    let why = if counts.faces > MAX_ELEMENTS as u64 || counts.halfedges() > MAX_ELEMENTS as u64 {
        format!("more than the {MAX_ELEMENTS} a mesh holds")
    } else {
        format!(
            "needing about {} of memory, more than the {} available",
            Size(Scheme::bytes_needed(counts.faces, base)),
            Size(available.unwrap_or(0))
        )
    };
    let faces = if counts.faces == u64::MAX {
        "more than 2^64".to_string()
    } else {
        counts.faces.to_string()
    };
    Err(CliError::Usage(format!(
        "--steps {steps}: {steps} {} of {scheme} subdivision would make {faces} faces, {why}; at most --steps {largest} fits this mesh",
        crate::text::plural(steps as usize, "step", "steps"),
    )))
}

/// The JSON of `subdivide --json`.
#[derive(Debug, Serialize)]
struct Summary {
    input: String,
    output: String,
    scheme: &'static str,
    steps: u32,
    vertices_in: usize,
    faces_in: usize,
    closed: bool,
    vertices: usize,
    edges: usize,
    faces: usize,
    seconds: f64,
    /// What `--repair` changed (and the reading's other notes), one line each.
    notes: Vec<String>,
}

/// Runs `beltrami subdivide`.
pub(crate) fn run(args: &SubdivideArgs, out: &mut impl Write) -> Result<(), CliError> {
    refuse_height_map_output(
        &args.output,
        "subdivide",
        "subdivision moves the vertices and adds new ones",
    )?;
    let mut outputs = Outputs::new();
    outputs.add_mesh(&args.output, "OUTPUT");
    outputs.check(&[&args.input], args.force)?;
    let loaded = load(&args.input, &args.read)?;
    loaded.require_faces(&args.input, "subdivide")?;
    crate::repair::refuse_stl_after_split(&args.output, loaded.repair.as_ref())?;
    let scheme = args.scheme.scheme();
    let mesh = &loaded.mesh;
    if let Some(f) = mesh.faces().find(|&f| mesh.face_valence(f) != 3) {
        return Err(not_a_triangle_mesh(
            &args.input,
            f.index(),
            mesh.face_valence(f),
        ));
    }
    check_size(mesh, scheme, args.steps)?;

    let start = std::time::Instant::now();
    let (fine, positions) = scheme
        .subdivide(mesh, &loaded.positions, args.steps as usize)
        .map_err(|e| CliError::Input {
            path: args.input.clone(),
            message: e.to_string(),
        })?;
    let seconds = start.elapsed().as_secs_f64();
    let notes = notes_for_output(&args.output, &loaded.repair_lines, &fine);
    write_result(&args.output, &fine, positions, args.ascii)?;

    if args.json {
        let summary = Summary {
            input: args.input.display().to_string(),
            output: args.output.display().to_string(),
            scheme: scheme.name(),
            steps: args.steps,
            vertices_in: mesh.n_vertices(),
            faces_in: mesh.n_faces(),
            closed: mesh.is_closed(),
            vertices: fine.n_vertices(),
            edges: fine.n_edges(),
            faces: fine.n_faces(),
            seconds,
            notes,
        };
        serde_json::to_writer_pretty(&mut *out, &summary).map_err(std::io::Error::from)?;
        writeln!(out)?;
        return Ok(());
    }
    for line in &notes {
        writeln!(out, "{line}")?;
    }
    writeln!(
        out,
        "subdivided {} ({}, {}) by {} of {scheme} -> {} ({}, {})",
        args.input.display(),
        counted(mesh.n_vertices(), "vertex", "vertices"),
        counted(mesh.n_faces(), "face", "faces"),
        counted(args.steps as usize, "step", "steps"),
        args.output.display(),
        counted(fine.n_vertices(), "vertex", "vertices"),
        counted(fine.n_faces(), "face", "faces"),
    )?;
    Ok(())
}

/// The error for a mesh with a face that is not a triangle.
fn not_a_triangle_mesh(path: &Path, face: usize, len: usize) -> CliError {
    CliError::Input {
        path: path.to_path_buf(),
        message: not_triangles("subdivide", face, len),
    }
}
