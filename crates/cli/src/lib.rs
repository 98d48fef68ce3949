//! # beltrami-cli
//!
//! The `beltrami` command-line tool as a library, so that a crate with its own weight
//! schemes can ship the full CLI with them registered:
//!
//! ```no_run
//! use beltrami_weights::WeightRegistry;
//! // let mut registry = WeightRegistry::with_builtins();
//! // registry.register(MyScheme)?;
//! let registry = WeightRegistry::with_builtins();
//! std::process::exit(i32::from(beltrami_cli::main_with(registry) != std::process::ExitCode::SUCCESS));
//! ```
//!
//! Errors are one line on stderr starting with `error:` (clap's usage errors add the
//! usage line and tips); the exit code is 1 for bad input (unreadable or invalid mesh,
//! failed run, a file that cannot be written), 2 for bad usage (a bad value or
//! combination of options) and 130 after an interrupt.

use std::ffi::OsString;
use std::io::Write;
use std::process::ExitCode;

use beltrami_weights::WeightRegistry;
use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};

mod compare;
mod decimate;
mod delaunay;
mod edit_report;
mod error;
mod fill_holes;
mod fit;
mod generate;
mod info;
mod load;
mod memory;
mod operator;
mod output;
mod progress;
mod remesh;
mod render;
mod repair;
mod residual;
mod smooth;
mod study;
mod subdivide;
mod text;

use error::CliError;

/// Discrete Laplace–Beltrami operators on triangle meshes, for surface metrology.
#[derive(Debug, Parser)]
#[command(
    name = "beltrami",
    version = env!("BELTRAMI_LONG_VERSION"),
    about = "Discrete Laplace-Beltrami smoothing of triangle meshes, for surface metrology",
    long_about = None
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Print counts, topology and geometry of a mesh (PLY, STL, OBJ or OFF).
    Info(info::InfoArgs),
    /// Write a mesh every command accepts (non-manifold edges cut, pinched vertices
    /// split, faces re-oriented, degenerate and duplicate faces dropped) and say what
    /// changed.
    Repair(repair::RepairArgs),
    /// Smooth a mesh by Laplacian diffusion, x <- x + lambda * L x.
    Smooth(smooth::SmoothArgs),
    /// Draw a mesh as a shaded PNG, optionally coloured by a vertex property or by the
    /// signed distance to a reference surface.
    Render(render::RenderArgs),
    /// Measure a mesh against a reference surface: distances, Hausdorff, normals,
    /// areas, volumes.
    Compare(compare::CompareArgs),
    /// Fit a least-squares sphere, circle or cylinder to a mesh's vertices.
    Fit(fit::FitArgs),
    /// Compute the ISO 25178-2 areal parameters (height, material ratio, volume,
    /// spatial) of a measured mesh's residual from its smoothed version or a fitted form.
    Residual(residual::ResidualArgs),
    /// Write one of the paper's test surfaces, optionally with seeded normal noise.
    Generate(generate::GenerateArgs),
    /// Subdivide a triangle mesh by Loop's or Kobbelt's sqrt(3) scheme.
    Subdivide(subdivide::SubdivideArgs),
    /// Flip edges until no cotangent weight is negative (a Delaunay mesh on the same
    /// vertices), optionally keeping sharp and curved edges.
    Delaunay(delaunay::DelaunayArgs),
    /// Remesh isotropically towards a target edge length (Botsch & Kobbelt 2004),
    /// keeping the boundary and, with --features, sharp edges.
    Remesh(remesh::RemeshArgs),
    /// Fill the holes of a mesh (Liepa's minimum-weight triangulation, refined and
    /// faired), leaving the outer boundary of an open surface open unless --all.
    FillHoles(fill_holes::FillHolesArgs),
    /// Decimate a triangle mesh by quadric error metrics to a target vertex count,
    /// optionally keeping the boundary and bounding normal change and distance.
    Decimate(decimate::DecimateArgs),
    /// Write the Laplacian (or with --mass the lumped mass matrix) of a mesh as a sparse
    /// matrix: Matrix Market .mtx or scipy's CSR .npz.
    Operator(operator::OperatorArgs),
    /// Run the whole comparison study and write its report, plots and renders.
    Study(study::StudyArgs),
    /// List the weight schemes `smooth --weights` and `study --weights` accept.
    Schemes(SchemesArgs),
}

/// Arguments of `beltrami schemes`.
#[derive(Debug, clap::Args)]
struct SchemesArgs {
    /// Print a JSON array of {name, description} objects instead.
    #[arg(long)]
    json: bool,
}

/// One line per registered scheme: its name and description.
fn scheme_lines(registry: &WeightRegistry) -> Vec<String> {
    let width = registry.names().iter().map(|n| n.len()).max().unwrap_or(0);
    registry
        .iter()
        .map(|s| format!("{:width$}  {}", s.name(), first_line(s.description())))
        .collect()
}

fn first_line(text: &str) -> &str {
    text.lines().next().unwrap_or("").trim()
}

fn schemes(
    args: &SchemesArgs,
    registry: &WeightRegistry,
    out: &mut impl Write,
) -> Result<(), CliError> {
    if args.json {
        let list: Vec<serde_json::Value> = registry
            .iter()
            .map(|s| serde_json::json!({"name": s.name(), "description": s.description()}))
            .collect();
        serde_json::to_writer_pretty(&mut *out, &list).map_err(std::io::Error::from)?;
        writeln!(out)?;
    } else {
        for line in scheme_lines(registry) {
            writeln!(out, "{line}")?;
        }
    }
    Ok(())
}

/// The clap command with the schemes of `registry` listed in the help of
/// `smooth --weights` and `study --weights`.
fn command(registry: &WeightRegistry) -> clap::Command {
    let list = scheme_lines(registry).join("\n  ");
    let help = format!(
        "The weight scheme (default: cotangent). Registered schemes ('beltrami schemes' lists them):\n  {list}"
    );
    let study_help = format!(
        "The weight schemes, comma-separated (default: every registered scheme):\n  {list}"
    );
    Cli::command()
        .mut_subcommand("smooth", |c| {
            c.mut_arg("weights", |a| a.long_help(help.clone()))
        })
        .mut_subcommand("study", |c| {
            c.mut_arg("weights", |a| a.long_help(study_help.clone()))
        })
}

/// Runs the CLI on the process's arguments with the schemes of `registry`.
#[must_use]
pub fn main_with(registry: WeightRegistry) -> ExitCode {
    remove_temporary_files_on_signal();
    // The command runs on a worker of its own thread pool, so that the parallel passes
    // of a small mesh (one chunk) run on that thread at once instead of being handed to
    // the pool and waited for: on meshes of a few thousand vertices that hand-over is a
    // large part of each iteration. The same pool size as rayon's global default
    // (`RAYON_NUM_THREADS`, else the number of logical cores); results do not depend
    // on it.
    match rayon::ThreadPoolBuilder::new().build() {
        Ok(pool) => pool.install(|| run_with(std::env::args_os(), &registry)),
        Err(_) => run_with(std::env::args_os(), &registry),
    }
}

/// On Ctrl-C, `SIGTERM` or `SIGHUP`, removes the temporary files of outputs being
/// written (the targets stay as they were) and exits with code 130.
fn remove_temporary_files_on_signal() {
    // Fails only when a handler is already set (a program embedding the CLI set its
    // own); that handler then decides.
    let _ = ctrlc::set_handler(|| {
        beltrami_io::remove_staged_files();
        eprintln!("error: interrupted; outputs not yet complete were discarded");
        std::process::exit(130);
    });
}

/// Runs the CLI on `args` (the first is the program name) with the schemes of
/// `registry`, printing to stdout and stderr, and returns the exit code.
pub fn run_with<I, T>(args: I, registry: &WeightRegistry) -> ExitCode
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let cli = match command(registry)
        .try_get_matches_from(args)
        .and_then(|matches| Cli::from_arg_matches(&matches))
    {
        Ok(cli) => cli,
        Err(err) => return usage_error(&err),
    };
    let mut stdout = std::io::stdout().lock();
    let result = match &cli.command {
        Command::Info(args) => info::run(args, &mut stdout),
        Command::Repair(args) => repair::run(args, &mut stdout),
        Command::Smooth(args) => smooth::run(args, registry, &mut stdout),
        Command::Generate(args) => generate::run(args, &mut stdout),
        Command::Study(args) => study::run(args, registry, &mut stdout),
        Command::Operator(args) => operator::run(args, registry, &mut stdout),
        Command::Subdivide(args) => subdivide::run(args, &mut stdout),
        Command::Delaunay(args) => delaunay::run(args, &mut stdout),
        Command::Remesh(args) => remesh::run(args, &mut stdout),
        Command::FillHoles(args) => fill_holes::run(args, &mut stdout),
        Command::Decimate(args) => decimate::run(args, &mut stdout),
        Command::Compare(args) => compare::run(args, &mut stdout),
        Command::Fit(args) => fit::run(args, &mut stdout),
        Command::Residual(args) => residual::run(args, &mut stdout),
        Command::Schemes(args) => schemes(args, registry, &mut stdout),
        Command::Render(args) => render::run(args, &mut stdout),
    };
    match result.and_then(|()| stdout.flush().map_err(CliError::from)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            if !err.is_closed_pipe() {
                eprintln!("error: {err}");
            }
            ExitCode::from(err.exit_code())
        }
    }
}

/// Help and version go to stdout with exit code 0; any other parse failure is clap's
/// message on stderr (starting with `error:`) and exit code 2.
fn usage_error(err: &clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    match err.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
            let _ = err.print();
            ExitCode::SUCCESS
        }
        ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            eprintln!("error: no command given (see 'beltrami --help')");
            ExitCode::from(2)
        }
        _ => {
            // Clap's whole message: the problem, the usage line that names what is
            // missing, possible values and "did you mean" tips.
            let text = err.to_string();
            eprint!("{text}");
            if !text.ends_with('\n') {
                eprintln!();
            }
            ExitCode::from(2)
        }
    }
}
