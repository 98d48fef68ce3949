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
//! Errors are one line on stderr starting with `error:`; the exit code is 1 for bad
//! input (unreadable or invalid mesh, failed run) and 2 for bad usage.

use std::ffi::OsString;
use std::io::Write;
use std::process::ExitCode;

use beltrami_weights::WeightRegistry;
use clap::{Parser, Subcommand};

mod compare;
mod error;
mod fit;
mod generate;
mod info;
mod load;
mod memory;
mod output;
mod render;
mod residual;
mod smooth;
mod study;

use error::CliError;

/// Discrete Laplace–Beltrami operators on triangle meshes, for surface metrology.
#[derive(Debug, Parser)]
#[command(name = "beltrami", version = env!("BELTRAMI_LONG_VERSION"), about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Print counts, topology and geometry of a mesh (PLY, STL or OBJ).
    Info(info::InfoArgs),
    /// Smooth a mesh by Laplacian diffusion, x <- x + lambda * L x.
    Smooth(smooth::SmoothArgs),
    /// Write one of the paper's test surfaces, optionally with seeded normal noise.
    Generate(generate::GenerateArgs),
    /// Run the whole comparison study and write its report, plots and renders.
    Study(study::StudyArgs),
    /// Measure a mesh against a reference surface: distances, Hausdorff, normals,
    /// areas, volumes.
    Compare(compare::CompareArgs),
    /// Fit a least-squares sphere, circle or cylinder to a mesh's vertices.
    Fit(fit::FitArgs),
    /// Compute the ISO 25178-2 areal parameters of a measured mesh's residual from its
    /// smoothed version.
    Residual(residual::ResidualArgs),
    /// Draw a mesh as a shaded PNG image, optionally coloured by a vertex property or by
    /// the signed distance to a reference surface, with a colour bar.
    Render(render::RenderArgs),
}

/// Runs the CLI on the process's arguments with the schemes of `registry`.
#[must_use]
pub fn main_with(registry: WeightRegistry) -> ExitCode {
    run_with(std::env::args_os(), &registry)
}

/// Runs the CLI on `args` (the first is the program name) with the schemes of
/// `registry`, printing to stdout and stderr, and returns the exit code.
pub fn run_with<I, T>(args: I, registry: &WeightRegistry) -> ExitCode
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(err) => return usage_error(&err),
    };
    let mut stdout = std::io::stdout().lock();
    let result = match &cli.command {
        Command::Info(args) => info::run(args, &mut stdout),
        Command::Smooth(args) => smooth::run(args, registry, &mut stdout),
        Command::Generate(args) => generate::run(args, &mut stdout),
        Command::Study(args) => study::run(args, registry, &mut stdout),
        Command::Compare(args) => compare::run(args, &mut stdout),
        Command::Fit(args) => fit::run(args, &mut stdout),
        Command::Residual(args) => residual::run(args, &mut stdout),
        Command::Render(args) => render::run(args, &mut stdout),
    };
    match result.and_then(|()| stdout.flush().map_err(CliError::from)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err}");
            ExitCode::from(err.exit_code())
        }
    }
}

/// Help and version go to stdout with exit code 0; any other parse failure is one
/// `error:` line on stderr and exit code 2.
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
            let text = err.to_string();
            let line = text.lines().next().unwrap_or("error: invalid usage");
            let line = line.strip_prefix("error: ").unwrap_or(line);
            eprintln!("error: {line} (see 'beltrami --help')");
            ExitCode::from(2)
        }
    }
}
