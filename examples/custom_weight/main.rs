//! A weight scheme of your own, run through the whole `beltrami` CLI by name.
//!
//! ```sh
//! cargo run --release --example custom_weight -- smooth fixtures/icosphere_2.ply out.ply --weights mean-value
//! ```
//!
//! The scheme (`mean_value.rs`) is about twenty lines: a name and a per-halfedge weight
//! read from the [`WeightContext`](beltrami::weights::WeightContext). Registering it
//! next to the built-ins is all it takes for `smooth`, and everything else that picks
//! schemes by name, to accept `--weights mean-value`.

mod mean_value;

use std::process::ExitCode;

use beltrami::weights::WeightRegistry;

fn main() -> ExitCode {
    let mut registry = WeightRegistry::with_builtins();
    if let Err(e) = registry.register(mean_value::MeanValue) {
        eprintln!("error: {e}");
        return ExitCode::from(1);
    }
    beltrami_cli::main_with(registry)
}
