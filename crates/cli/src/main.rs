//! The `beltrami` command-line tool with the built-in weight schemes.

use std::process::ExitCode;

use beltrami_weights::WeightRegistry;

fn main() -> ExitCode {
    beltrami_cli::main_with(WeightRegistry::with_builtins())
}
