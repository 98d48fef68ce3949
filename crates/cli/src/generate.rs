//! `beltrami generate`: the paper's test surfaces, optionally with seeded noise.

use std::io::Write;
use std::path::{Path, PathBuf};

use beltrami_io::MeshData;
use beltrami_surfaces::{NoiseLevel, Surface, SurfaceKind, add_normal_noise, cut_holes};
use clap::ValueEnum;

use crate::error::CliError;
use crate::output::{Outputs, Staged};
use crate::text::{counted, number};

/// `" mm"` for a surface in millimetres, nothing for a unitless one (the unit sphere,
/// whose unit is written `1`).
fn unit_suffix(unit: &str) -> String {
    if unit.is_empty() || unit == "1" {
        String::new()
    } else {
        format!(" {unit}")
    }
}

/// Arguments of `beltrami generate`.
#[derive(Debug, clap::Args)]
pub(crate) struct GenerateArgs {
    /// The surface: flens (open free-form lens, mm), sphere (unit icosphere), block
    /// (genus-3 part with sharp edges, mm), golfball (dimpled ball, mm).
    surface: SurfaceArg,
    /// The output mesh (.ply, .stl, .obj or .off).
    output: PathBuf,
    /// Add Gaussian noise along the vertex normals with this standard deviation, as a
    /// multiple of the mean edge length (as in `study`), or in the surface's length
    /// unit with --absolute-noise.
    #[arg(long, allow_hyphen_values = true)]
    noise: Option<f64>,
    /// Read --noise in the surface's length unit instead of as a multiple of the mean
    /// edge length.
    #[arg(long, requires = "noise")]
    absolute_noise: bool,
    /// Read --noise as a multiple of the mean edge length (the default; kept for
    /// scripts written when the default was absolute).
    #[arg(
        long,
        requires = "noise",
        conflicts_with = "absolute_noise",
        hide = true
    )]
    relative: bool,
    /// Seed of the noise and of the holes' places (the same seed gives the same numbers
    /// on every platform) [default: 1].
    #[arg(long)]
    seed: Option<u64>,
    /// Cut this many round holes into the surface, as a scan leaves them where the
    /// sensor saw nothing: each removes the faces whose centroid lies within
    /// --hole-radius of a seeded vertex away from the boundary and from the other
    /// holes. The clean reference (--clean) stays whole.
    #[arg(long, value_name = "N")]
    holes: Option<usize>,
    /// With --holes: the holes' radius as a multiple of the mean edge length.
    #[arg(
        long,
        allow_hyphen_values = true,
        value_name = "R",
        default_value_t = 3.0,
        requires = "holes"
    )]
    hole_radius: f64,
    /// Also write the clean surface (the reference: without noise and without holes) to
    /// this file.
    #[arg(long)]
    clean: Option<PathBuf>,
    /// Replace write-protected output files.
    #[arg(long)]
    force: bool,
    /// Write PLY (and STL) as ascii text instead of binary.
    #[arg(long)]
    ascii: bool,
    /// The sphere's subdivision level, 0 to 11 (the paper's sphere is 6: 40 962
    /// vertices; 8 gives 655 362, 10 gives 10 485 762 and 11 gives 41 943 042 vertices,
    /// for benchmarks).
    /// Only for `sphere`.
    #[arg(long, value_parser = clap::value_parser!(u32).range(0..=MAX_SPHERE_LEVEL as i64))]
    level: Option<u32>,
    /// Write the vertices in a random order drawn from this seed (the same on every
    /// platform; faces keep their order), to benchmark a poor vertex order such as a
    /// scanner's. The noise, if any, is drawn before the shuffle, so the shuffled file
    /// holds the same points as the unshuffled one.
    #[arg(long, value_name = "SEED")]
    shuffle: Option<u64>,
}

/// The largest `--level` of `generate sphere`: 41 943 042 vertices and 83 886 080
/// faces, about 2 GiB of positions and faces (a 2 GB binary PLY); level 12 would need
/// four times that.
const MAX_SPHERE_LEVEL: u32 = 11;

#[derive(Clone, Copy, Debug, ValueEnum)]
enum SurfaceArg {
    Flens,
    Sphere,
    Block,
    Golfball,
}

impl SurfaceArg {
    fn kind(self) -> SurfaceKind {
        match self {
            Self::Flens => SurfaceKind::FLens,
            Self::Sphere => SurfaceKind::Sphere,
            Self::Block => SurfaceKind::Block,
            Self::Golfball => SurfaceKind::GolfBall,
        }
    }
}

fn stage(
    staged: &mut Staged,
    path: &Path,
    surface: &Surface,
    positions: Vec<beltrami_halfedge::DVec3>,
    ascii: bool,
) -> Result<(), CliError> {
    let data = MeshData {
        positions,
        faces: surface.faces.clone(),
    };
    staged.push_mesh(path, &data, ascii)
}

/// Runs `beltrami generate`.
pub(crate) fn run(args: &GenerateArgs, out: &mut impl Write) -> Result<(), CliError> {
    check_args(args)?;
    // A height map holds metres; the surfaces are in mm (the sphere has no unit), and
    // written as one their lengths would be read a thousand times too large.
    const WHY: &str =
        "the surfaces are in mm (the sphere has no unit) and a height map holds metres";
    crate::output::refuse_height_map_output(&args.output, "generate", WHY)?;
    if let Some(clean) = &args.clean {
        crate::output::refuse_height_map_output(clean, "generate", WHY)?;
    }
    let seed = args.seed.unwrap_or(1);
    let mut outputs = Outputs::new();
    outputs
        .add_mesh(&args.output, "OUTPUT")
        .add_opt(args.clean.as_ref(), "--clean");
    outputs.check(&[], args.force)?;
    let surface = match (args.surface, args.level) {
        (SurfaceArg::Sphere, Some(level)) => beltrami_surfaces::sphere(level),
        (_, Some(_)) => {
            return Err(CliError::Usage(
                "--level applies to the sphere only".to_string(),
            ));
        }
        (kind, None) => kind.kind().generate(),
    };
    let mesh = surface
        .mesh()
        .map_err(|e| CliError::Usage(format!("internal: generated surface is invalid: {e}")))?;
    let (positions, mut note) = noisy_positions(args, &mesh, &surface, seed)?;
    let (surface, positions) = match args.shuffle {
        None => (surface, positions),
        Some(seed) => {
            // The noisy positions follow the clean surface's renumbering.
            let order = beltrami_surfaces::shuffle_order(positions.len(), seed);
            let noisy = order.iter().map(|&old| positions[old as usize]).collect();
            (surface.shuffled(seed), noisy)
        }
    };
    let mut staged = Staged::new();
    let counts = match args.holes {
        None => {
            stage(&mut staged, &args.output, &surface, positions, args.ascii)?;
            (mesh.n_vertices(), mesh.n_faces())
        }
        Some(count) => {
            let (counts, holes_note) =
                stage_with_holes(&mut staged, args, &mesh, &surface, positions, count)?;
            note.push_str(&holes_note);
            counts
        }
    };
    if let Some(clean) = &args.clean {
        stage(
            &mut staged,
            clean,
            &surface,
            surface.positions.clone(),
            args.ascii,
        )?;
    }
    staged.commit()?;
    if let Some(seed) = args.shuffle {
        note.push_str(&format!(", vertices shuffled (seed {seed})"));
    }
    writeln!(
        out,
        "generated {} ({}, {}, {}){note} -> {}",
        surface.name,
        counted(counts.0, "vertex", "vertices"),
        counted(counts.1, "face", "faces"),
        if unit_suffix(surface.unit).is_empty() {
            "unitless".to_string()
        } else {
            format!("lengths in {}", surface.unit)
        },
        args.output.display()
    )?;
    if let Some(clean) = &args.clean {
        writeln!(out, "clean reference -> {}", clean.display())?;
    }
    Ok(())
}

/// The usage errors of option combinations: `--seed` and `--clean` need `--noise` or
/// `--holes`, `--holes` excludes `--shuffle`, `--hole-radius` is positive.
fn check_args(args: &GenerateArgs) -> Result<(), CliError> {
    if args.noise.is_none() && args.holes.is_none() {
        if args.seed.is_some() {
            return Err(CliError::Usage(
                "--seed needs --noise or --holes (it seeds them)".to_string(),
            ));
        }
        if args.clean.is_some() {
            return Err(CliError::Usage(
                "--clean needs --noise or --holes (without them OUTPUT is the clean surface)"
                    .to_string(),
            ));
        }
    }
    if args.holes.is_some() && args.shuffle.is_some() {
        return Err(CliError::Usage(
            "--holes and --shuffle cannot be combined (cutting holes renumbers the vertices)"
                .to_string(),
        ));
    }
    if !(args.hole_radius.is_finite() && args.hole_radius > 0.0) {
        return Err(CliError::Usage(format!(
            "--hole-radius must be a positive number, got {}",
            number(args.hole_radius)
        )));
    }
    Ok(())
}

/// The positions with `--noise` added along the normals (the clean ones without), and
/// the note that says how much.
fn noisy_positions(
    args: &GenerateArgs,
    mesh: &beltrami_halfedge::HalfedgeMesh,
    surface: &Surface,
    seed: u64,
) -> Result<(Vec<beltrami_halfedge::DVec3>, String), CliError> {
    let Some(level) = args.noise else {
        return Ok((surface.positions.clone(), String::new()));
    };
    let noise = if args.absolute_noise {
        NoiseLevel::Absolute(level)
    } else {
        NoiseLevel::RelativeToMeanEdge(level)
    };
    let (noisy, sigma) = add_normal_noise(mesh, &surface.positions, noise, seed)
        .map_err(|e| CliError::Usage(e.to_string()))?;
    let how = if args.absolute_noise {
        String::new()
    } else {
        format!(", {} x the mean edge length", number(level))
    };
    let note = format!(
        ", normal noise sigma = {}{}{how} (seed {})",
        number(sigma),
        unit_suffix(surface.unit),
        seed
    );
    Ok((noisy, note))
}

/// Cuts `count` holes (of `--hole-radius` mean edge lengths) into the surface with
/// `positions` and stages it for OUTPUT; returns its vertex and face counts and the
/// note that describes the holes.
fn stage_with_holes(
    staged: &mut Staged,
    args: &GenerateArgs,
    mesh: &beltrami_halfedge::HalfedgeMesh,
    surface: &Surface,
    positions: Vec<beltrami_halfedge::DVec3>,
    count: usize,
) -> Result<((usize, usize), String), CliError> {
    let seed = args.seed.unwrap_or(1);
    let radius = args.hole_radius * mesh_mean_edge(mesh, &surface.positions)?;
    let noisy = MeshData::new(positions, surface.faces.clone());
    let cut = cut_holes(&noisy, count, radius, seed).map_err(|e| CliError::Usage(e.to_string()))?;
    let counts = (cut.data.positions.len(), cut.data.faces.len());
    let note = format!(
        ", {} of radius {}{} cut (seed {seed}, {} removed)",
        counted(count, "hole", "holes"),
        number(radius),
        unit_suffix(surface.unit),
        counted(cut.faces_removed, "face", "faces"),
    );
    staged.push_mesh(&args.output, &cut.data, args.ascii)?;
    Ok((counts, note))
}

/// The mean edge length of the clean surface, in its unit (each edge once).
fn mesh_mean_edge(
    mesh: &beltrami_halfedge::HalfedgeMesh,
    positions: &[beltrami_halfedge::DVec3],
) -> Result<f64, CliError> {
    beltrami_halfedge::geometry::Geometry::new(mesh, positions)
        .ok()
        .and_then(|g| g.mean_edge_length())
        .ok_or_else(|| CliError::Usage("internal: generated surface has no edges".to_string()))
}
