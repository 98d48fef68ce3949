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
use clap::{Args, CommandFactory, FromArgMatches, Parser, Subcommand};

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
    #[command(flatten)]
    global: GlobalArgs,
    #[command(subcommand)]
    command: Command,
}

/// Options every subcommand takes (before or after its name).
#[derive(Debug, clap::Args)]
struct GlobalArgs {
    /// Write outputs without flushing them to disk (fsync): faster, not safe against a
    /// power loss.
    ///
    /// Outputs still replace their targets by a rename, and a killed run leaves them
    /// untouched, but a power loss or system crash soon after the run may leave an old,
    /// empty or partial file. On a network file system a write error that only the
    /// flush would have reported (a full disk, a quota) may then go unnoticed: use it on
    /// local scratch space, where it saves about a millisecond per output.
    #[arg(long, global = true, display_order = 1000)]
    no_sync: bool,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Print counts, topology and geometry of a mesh (PLY, STL, OBJ or OFF).
    Info(info::InfoArgs),
    /// Write a mesh every command accepts (non-manifold edges cut, pinched vertices
    /// split, faces re-oriented, degenerate and duplicate faces dropped; polygons split
    /// into triangles with --triangulate) and say what changed.
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
    // Every subcommand in its place (`mut_subcommand` would move the two to the end of
    // the list that clap's errors print).
    Cli::command().mut_subcommands(|c| with_scheme_list(c, registry))
}

/// `smooth` or `study` (any other subcommand is returned as it is) with the schemes
/// of `registry` listed in the help of `--weights`.
fn with_scheme_list(sub: clap::Command, registry: &WeightRegistry) -> clap::Command {
    let intro = match sub.get_name() {
        "smooth" => {
            "The weight scheme (default: cotangent). Registered schemes ('beltrami schemes' lists them):"
        }
        "study" => "The weight schemes, comma-separated (default: every registered scheme):",
        _ => return sub,
    };
    let list = scheme_lines(registry).join("\n  ");
    sub.mut_arg("weights", |a| a.long_help(format!("{intro}\n  {list}")))
}

/// Adds a subcommand's arguments to a command (`clap::Args::augment_args`).
type Augment = fn(clap::Command) -> clap::Command;

/// The subcommands by name, each with the function that adds its arguments: a command
/// line whose first argument names one of them is parsed by a command holding that
/// subcommand alone ([`parse_lean`]).
const SUBCOMMANDS: [(&str, Augment); 16] = [
    ("info", info::InfoArgs::augment_args),
    ("repair", repair::RepairArgs::augment_args),
    ("smooth", smooth::SmoothArgs::augment_args),
    ("render", render::RenderArgs::augment_args),
    ("compare", compare::CompareArgs::augment_args),
    ("fit", fit::FitArgs::augment_args),
    ("residual", residual::ResidualArgs::augment_args),
    ("generate", generate::GenerateArgs::augment_args),
    ("subdivide", subdivide::SubdivideArgs::augment_args),
    ("delaunay", delaunay::DelaunayArgs::augment_args),
    ("remesh", remesh::RemeshArgs::augment_args),
    ("fill-holes", fill_holes::FillHolesArgs::augment_args),
    ("decimate", decimate::DecimateArgs::augment_args),
    ("operator", operator::OperatorArgs::augment_args),
    ("study", study::StudyArgs::augment_args),
    ("schemes", SchemesArgs::augment_args),
];

/// The command with only the subcommand `name` and its arguments (the same as in
/// [`command`] but for the subcommand's one-line description and the other
/// subcommands), or `None` for a name that is not a subcommand.
fn lean_command(name: &str, registry: &WeightRegistry) -> Option<clap::Command> {
    let (name, augment) = SUBCOMMANDS.iter().find(|(n, _)| *n == name)?;
    let sub = with_scheme_list(augment(clap::Command::new(*name)), registry);
    Some(GlobalArgs::augment_args(clap::Command::new("beltrami")).subcommand(sub))
}

/// Parses a command line that names a subcommand and parses without error, help or
/// version, with a command holding that subcommand alone: clap's derived command
/// builds every subcommand's arguments (about half a millisecond, a tenth of a small
/// run). Anything else (`None`) goes through the whole command, which gives the help
/// texts and the error messages; a line that parses here parses there to the same
/// values (tested).
fn parse_lean(args: &[OsString], registry: &WeightRegistry) -> Option<Cli> {
    let name = args.get(1)?.to_str()?;
    let matches = lean_command(name, registry)?
        .try_get_matches_from(args)
        .ok()?;
    Cli::from_arg_matches(&matches).ok()
}

/// Runs the CLI on the process's arguments with the schemes of `registry`: a program's
/// `main`, and its last act. The command runs in a thread pool that takes the calling
/// thread as one of its workers and stays registered with it; a program that goes on
/// using rayon afterwards calls [`run_with`] instead.
#[must_use]
pub fn main_with(registry: WeightRegistry) -> ExitCode {
    let args: Vec<OsString> = std::env::args_os().collect();
    // Help, version and usage errors need no threads (the signal handler is one).
    let cli = match parse(&args, &registry) {
        Ok(cli) => cli,
        Err(code) => return code,
    };
    remove_temporary_files_on_signal();
    // The command runs on a worker of its own thread pool, so that the parallel passes
    // of a small mesh (one chunk) run on that thread at once instead of being handed to
    // the pool and waited for: on meshes of a few thousand vertices that hand-over is a
    // large part of each iteration. This thread is one of the pool's workers (one
    // thread fewer to start, and no hand-over of the command itself). The same pool
    // size as rayon's global default (`RAYON_NUM_THREADS`, else the number of logical
    // cores); results do not depend on it.
    match rayon::ThreadPoolBuilder::new().use_current_thread().build() {
        Ok(pool) => pool.install(|| execute(&cli, &registry)),
        Err(_) => execute(&cli, &registry),
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
/// `registry`, printing to stdout and stderr, and returns the exit code. It sets the
/// process-wide [`beltrami_io::set_flush_to_disk`] from `--no-sync` (on without it).
pub fn run_with<I, T>(args: I, registry: &WeightRegistry) -> ExitCode
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let args: Vec<OsString> = args.into_iter().map(Into::into).collect();
    match parse(&args, registry) {
        Ok(cli) => execute(&cli, registry),
        Err(code) => code,
    }
}

/// The parsed command line, or the exit code of help, version or a usage error (whose
/// text is printed).
fn parse(args: &[OsString], registry: &WeightRegistry) -> Result<Cli, ExitCode> {
    if let Some(cli) = parse_lean(args, registry) {
        return Ok(cli);
    }
    command(registry)
        .try_get_matches_from(args)
        .and_then(|matches| Cli::from_arg_matches(&matches))
        .map_err(|err| usage_error(&err))
}

/// Runs a parsed command line, printing to stdout and stderr, and returns the exit code.
fn execute(cli: &Cli, registry: &WeightRegistry) -> ExitCode {
    // Process-wide: every call sets it from its own command line.
    beltrami_io::set_flush_to_disk(!cli.global.no_sync);
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A subcommand without what only the top-level help shows (its description and
    /// place in the list).
    fn without_listing(command: clap::Command) -> String {
        format!(
            "{:?}",
            command.about(None).long_about(None).display_order(0)
        )
    }

    #[test]
    fn the_lean_subcommands_are_the_derived_ones() {
        let registry = WeightRegistry::with_builtins();
        let full = command(&registry);
        let mut names: Vec<&str> = full
            .get_subcommands()
            .map(clap::Command::get_name)
            .collect();
        let mut lean_names: Vec<&str> = SUBCOMMANDS.iter().map(|(n, _)| *n).collect();
        names.sort_unstable();
        lean_names.sort_unstable();
        assert_eq!(lean_names, names);
        for sub in full.get_subcommands() {
            let lean = lean_command(sub.get_name(), &registry).expect("in the table");
            let lean_sub = lean.find_subcommand(sub.get_name()).unwrap().clone();
            assert_eq!(
                without_listing(lean_sub),
                without_listing(sub.clone()),
                "{}",
                sub.get_name()
            );
        }
        assert!(lean_command("smoth", &registry).is_none());
    }

    fn parsed(line: &str) -> (Option<String>, Result<String, clap::error::ErrorKind>) {
        let registry = WeightRegistry::with_builtins();
        let args: Vec<OsString> = std::iter::once("beltrami")
            .chain(line.split_whitespace())
            .map(OsString::from)
            .collect();
        let lean = parse_lean(&args, &registry).map(|cli| format!("{cli:?}"));
        let full = command(&registry)
            .try_get_matches_from(&args)
            .and_then(|m| Cli::from_arg_matches(&m))
            .map(|cli| format!("{cli:?}"))
            .map_err(|e| e.kind());
        (lean, full)
    }

    #[test]
    fn a_line_parsed_lean_parses_to_the_same_values() {
        for line in [
            "smooth in.ply out.ply",
            "smooth in.ply out.ply --weights distance --update every --iterations 100 --lambda 0.8 --normalize sum --boundary free --report r.json --no-step-stats",
            "smooth in.ply out.ply --method taubin --summation rows",
            "info in.ply --quality --json",
            "generate sphere --level 3 s.ply --noise 0.2 --relative --seed 1",
            "remesh in.ply out.ply --edge-length 0.1 --features 45",
            "decimate in.ply out.ply --ratio 0.1",
            "fill-holes in.ply out.ply",
            "compare a.ply b.ply --json",
            "schemes --json",
            "study --out results",
            "smooth in.ply out.ply --no-sync",
            "generate sphere s.ply --no-sync --level 2",
        ] {
            let (lean, full) = parsed(line);
            assert_eq!(lean.as_deref(), Some(full.as_deref().unwrap()), "{line}");
        }
    }

    #[test]
    fn help_version_and_errors_go_through_the_derived_command() {
        for line in [
            "",
            "--help",
            "--version",
            "smooth --help",
            "smooth -h",
            "help smooth",
            "smooth",
            "smooth in.ply",
            "smooth in.ply out.ply --weights",
            "smooth in.ply out.ply --iterations many",
            "smooth in.ply out.ply --bogus",
            "smooth in.ply out.ply --version",
            "smoth in.ply out.ply",
            "fill_holes in.ply out.ply",
        ] {
            let (lean, full) = parsed(line);
            assert_eq!(lean, None, "{line}");
            assert!(full.is_err(), "{line}");
        }
        // A global option before the subcommand's name: the derived command parses it.
        let (lean, full) = parsed("--no-sync smooth in.ply out.ply");
        assert_eq!(lean, None);
        assert!(full.unwrap().contains("no_sync: true"));
    }
}
