//! The `beltrami` command-line tool with the built-in weight schemes and the
//! edge-preserving ones of `beltrami-schemes`.

use std::process::ExitCode;

use beltrami_weights::WeightRegistry;

fn main() -> ExitCode {
    let mut registry = WeightRegistry::with_builtins();
    if let Err(e) = beltrami_schemes::register_all(&mut registry) {
        eprintln!("error: {e}");
        return ExitCode::FAILURE;
    }
    beltrami_cli::main_with(registry)
}
