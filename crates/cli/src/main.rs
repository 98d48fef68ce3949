//! The `beltrami` command-line tool.
//!
//! Errors are one line on stderr starting with `error:`; the exit code is 1 for bad
//! input (unreadable or invalid mesh) and 2 for bad usage.

use std::io::Write;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod error;
mod info;
mod load;

use error::CliError;

/// Discrete Laplace–Beltrami operators on triangle meshes, for surface metrology.
#[derive(Debug, Parser)]
#[command(name = "beltrami", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Print counts, topology and geometry of a mesh (PLY, STL or OBJ).
    Info(info::InfoArgs),
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(err) => return usage_error(&err),
    };
    let mut stdout = std::io::stdout().lock();
    let result = match &cli.command {
        Command::Info(args) => info::run(args, &mut stdout),
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
