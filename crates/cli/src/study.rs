//! `beltrami study`: the whole comparison in one command.

use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::sync::Arc;

use beltrami_smooth::{Boundary, WeightUpdate};
use beltrami_study::{
    Countermeasure, Progress, StudyConfig, Verdict, paper_iterations, run_study, write_study,
};
use beltrami_surfaces::{NoiseLevel, Size, SurfaceKind};
use beltrami_weights::{NegativeWeights, WeightRegistry, WeightScheme};
use clap::ValueEnum;

use crate::error::CliError;

/// Arguments of `beltrami study`.
///
/// The defaults reproduce the paper: all four surfaces, every registered weight
/// scheme, 10, 20, …, 100 and 200 iterations, λ = 0.8, noise σ = 0.2 × mean edge
/// length, a free boundary (the paper's F-lens loses its outline), weights recomputed
/// every iteration.
#[derive(Debug, clap::Args)]
pub(crate) struct StudyArgs {
    /// The output directory (created if needed).
    #[arg(long, default_value = "study")]
    out: PathBuf,
    /// The surfaces, comma-separated: flens, sphere, block, golfball.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "flens,sphere,block,golfball"
    )]
    surfaces: Vec<String>,
    /// The weight schemes, comma-separated (default: every registered scheme).
    #[arg(long, value_delimiter = ',')]
    weights: Vec<String>,
    /// The iteration counts to observe, comma-separated and ascending.
    #[arg(long, value_delimiter = ',')]
    iterations: Vec<usize>,
    /// The step λ, in (0, 1].
    #[arg(long, default_value_t = 0.8)]
    lambda: f64,
    /// The noise σ as a multiple of the mean edge length (or absolute with
    /// --absolute-noise).
    #[arg(long, default_value_t = 0.2)]
    noise: f64,
    /// Read --noise in the surfaces' length unit instead.
    #[arg(long)]
    absolute_noise: bool,
    /// The seed of the noise.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// How boundary vertices move.
    #[arg(long, value_enum, default_value_t = BoundaryArg::Free)]
    boundary: BoundaryArg,
    /// When weights are computed.
    #[arg(long, value_enum, default_value_t = UpdateArg::Every)]
    update: UpdateArg,
    /// Small variants of the surfaces (a quick look; not the paper's sizes).
    #[arg(long)]
    small: bool,
    /// The weight scheme of the shrinkage counter-measure runs (Taubin, HC, volume
    /// rescale beside plain diffusion on the F-lens, sphere and block).
    #[arg(long, default_value = "cotangent")]
    countermeasure_weights: String,
    /// Skip the shrinkage counter-measure runs.
    #[arg(long)]
    no_countermeasures: bool,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum BoundaryArg {
    Fixed,
    Free,
    Curve,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum UpdateArg {
    Every,
    Once,
}

fn config(args: &StudyArgs, registry: &WeightRegistry) -> Result<StudyConfig, CliError> {
    let surfaces = args
        .surfaces
        .iter()
        .map(|s| SurfaceKind::from_name(s).map_err(|e| CliError::Usage(e.to_string())))
        .collect::<Result<Vec<_>, _>>()?;
    let schemes: Vec<Arc<dyn WeightScheme>> = if args.weights.is_empty() {
        registry.iter().cloned().collect()
    } else {
        args.weights
            .iter()
            .map(|w| registry.get(w))
            .collect::<Result<_, _>>()?
    };
    let config = StudyConfig {
        surfaces,
        size: if args.small { Size::Small } else { Size::Paper },
        schemes,
        iterations: if args.iterations.is_empty() {
            paper_iterations()
        } else {
            args.iterations.clone()
        },
        lambda: args.lambda,
        noise: if args.absolute_noise {
            NoiseLevel::Absolute(args.noise)
        } else {
            NoiseLevel::RelativeToMeanEdge(args.noise)
        },
        seed: args.seed,
        boundary: match args.boundary {
            BoundaryArg::Fixed => Boundary::Fixed,
            BoundaryArg::Free => Boundary::Free,
            BoundaryArg::Curve => Boundary::Curve,
        },
        update: match args.update {
            UpdateArg::Every => WeightUpdate::Every,
            UpdateArg::Once => WeightUpdate::Once,
        },
        negative: NegativeWeights::Keep,
        countermeasures: if args.no_countermeasures {
            Vec::new()
        } else {
            Countermeasure::defaults(args.lambda)
        },
        countermeasure_scheme: if args.no_countermeasures {
            None
        } else {
            Some(registry.get(&args.countermeasure_weights)?)
        },
        edge_comparison: registry
            .get("bilateral")
            .ok()
            .zip(registry.get("cotangent").ok()),
    };
    config
        .validate()
        .map_err(|e| CliError::Usage(e.to_string()))?;
    Ok(config)
}

/// Runs `beltrami study`.
pub(crate) fn run(
    args: &StudyArgs,
    registry: &WeightRegistry,
    out: &mut impl Write,
) -> Result<(), CliError> {
    let config = config(args, registry)?;
    let terminal = std::io::stderr().is_terminal();
    let mut bar: Option<indicatif::ProgressBar> = None;
    let mut progress = |p: Progress<'_>| {
        if !terminal {
            return;
        }
        match p {
            Progress::RunStarted(surface, scheme, n) => {
                let b = indicatif::ProgressBar::new(n as u64);
                b.set_style(
                    indicatif::ProgressStyle::with_template(
                        "{msg:24} {bar:40} {pos}/{len} {elapsed}",
                    )
                    .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
                );
                b.set_message(format!("{surface} / {scheme}"));
                bar = Some(b);
            }
            Progress::Iteration(i) => {
                if let Some(b) = &bar {
                    b.set_position(i as u64);
                }
            }
            Progress::RunFinished => {
                if let Some(b) = bar.take() {
                    b.finish();
                }
            }
        }
    };
    let results = run_study(&config, &mut progress).map_err(CliError::Study)?;
    let written = write_study(&results, &args.out).map_err(CliError::Study)?;
    writeln!(
        out,
        "study: {} surface(s) x {} scheme(s), {} observation(s), {:.1} s -> {}",
        config.surfaces.len(),
        config.schemes.len(),
        written.rows.len(),
        results.wall_time_s,
        args.out.join("report.md").display()
    )?;
    for f in &written.findings {
        let mark = match f.verdict {
            Verdict::Reproduced => "reproduced    ",
            Verdict::NotReproduced => "not reproduced",
            _ => "not evaluated ",
        };
        writeln!(out, "  {mark}  {}", f.id)?;
    }
    Ok(())
}
