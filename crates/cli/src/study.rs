//! `beltrami study`: the whole comparison in one command.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use beltrami_io::MeshData;
use beltrami_io::stage_dir;
use beltrami_smooth::{Boundary, WeightUpdate};
use beltrami_study::{
    Countermeasure, OutDirError, Progress, ScanConfig, ScanMethod, ScanSurface, StudyConfig,
    Verdict, run_scan, run_study, sig, write_scan, write_study,
};
use beltrami_surfaces::{NoiseLevel, Size, SurfaceKind};
use beltrami_weights::{WeightRegistry, WeightScheme};
use clap::ValueEnum;
use clap::builder::ArgPredicate;

use crate::error::CliError;
use crate::load::{ReadArgs, load};
use crate::smooth::{AreaArg, NegativeArg, NormalizeArg, normalization};
use crate::text::counted;

/// Arguments of `beltrami study`.
///
/// The defaults reproduce the paper: all four surfaces, every registered weight
/// scheme, 10, 20, …, 100 and 200 iterations, λ = 0.8, noise σ = 0.2 × mean edge
/// length, a free boundary (the paper's F-lens loses its outline), weights recomputed
/// every iteration.
///
/// DIR is replaced as a whole when the study has finished: a failed or interrupted
/// run leaves an earlier study in DIR as it was, and no stale plots survive.
#[derive(Debug, clap::Args)]
pub(crate) struct StudyArgs {
    /// The output directory: new, empty, or holding an earlier study (which is
    /// replaced as a whole once the new one has been written).
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
    /// The iteration counts to observe, comma-separated and ascending (the paper's by
    /// default). With --input: one number, the last explicit iteration observed
    /// (default 100).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "10,20,30,40,50,60,70,80,90,100,200",
        default_value_if("input", ArgPredicate::IsPresent, None)
    )]
    iterations: Vec<usize>,
    /// The step λ, in (0, 1]; with --normalize area, the fraction of each run's largest
    /// stable explicit step (Taubin's μ scaled alike).
    #[arg(long, default_value_t = 0.8, allow_hyphen_values = true)]
    lambda: f64,
    /// The noise σ as a multiple of the mean edge length (or absolute with
    /// --absolute-noise), as in `generate`.
    #[arg(long, default_value_t = 0.2, allow_hyphen_values = true)]
    noise: f64,
    /// Read --noise in the surfaces' length unit instead.
    #[arg(long)]
    absolute_noise: bool,
    /// The seed of the noise (of the first input; further seeds count up from it).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// The number of noise seeds (--seed, --seed + 1, …). The paper's schemes (uniform,
    /// distance, cotangent) run on each seed's input, other schemes on the first; tables
    /// give the mean and the range over the seeds, and verdicts take the range into
    /// account. Plots draw the mean with the range; renders and counter-measures use the first seed. The default, 3,
    /// was chosen by measurement: each further seed adds a few seconds to the default
    /// study on two cores.
    #[arg(long, default_value_t = beltrami_study::DEFAULT_SEEDS)]
    seeds: usize,
    /// How boundary vertices move. Free by default, as in the paper, whose F-lens
    /// loses its outline (`smooth` keeps a measured patch's outline: fixed, the
    /// default with --input).
    #[arg(
        long,
        value_enum,
        default_value_t = BoundaryArg::Free,
        default_value_if("input", ArgPredicate::IsPresent, "fixed")
    )]
    boundary: BoundaryArg,
    /// When weights are computed.
    #[arg(long, value_enum, default_value_t = UpdateArg::Every)]
    update: UpdateArg,
    /// Treatment of negative weights (cotangent weights of edges whose opposite angles
    /// sum to more than 180°): keep them (the paper's), clamp them to 0, or take their
    /// absolute value. As in `smooth`.
    #[arg(long, value_enum, default_value_t = NegativeArg::Keep)]
    cotangent_negative: NegativeArg,
    /// Row normalisation: sum (divide by the weight sum, paper Eq. 2, the default) or
    /// area (divide by the vertex area, paper Eq. 6, where a step is a time in length²
    /// whose stable range follows each mesh's unit and density: --lambda is then the
    /// fraction of each run's largest stable explicit step).
    #[arg(long, value_enum, default_value_t = NormalizeArg::Sum)]
    normalize: NormalizeArg,
    /// The vertex area for --normalize area.
    #[arg(long, value_enum, default_value_t = AreaArg::Mixed)]
    vertex_area: AreaArg,
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
    /// Remeshing before smoothing (the paper's MeshLab step), reported beside the
    /// original meshes: the target edge length L in each surface's unit (default:
    /// each clean mesh's mean edge length, --remesh-relative 1).
    #[arg(long, value_name = "L", conflicts_with_all = ["remesh_relative", "no_remesh"], allow_hyphen_values = true)]
    remesh: Option<f64>,
    /// The remeshing target edge length as R × each clean mesh's mean edge length.
    #[arg(
        long,
        value_name = "R",
        conflicts_with = "no_remesh",
        allow_hyphen_values = true
    )]
    remesh_relative: Option<f64>,
    /// Skip the remeshing comparison.
    #[arg(long)]
    no_remesh: bool,
    /// Skip the worked example of `--input` on the noisy block (the report's "study on
    /// a given surface" and the scan/ directory).
    #[arg(long)]
    no_scan_example: bool,
    /// Study this surface (a scan: .ply, .stl, .obj or .off) instead of the paper's:
    /// every scheme with plain, Taubin, HC and implicit smoothing, observed iteration by
    /// iteration (see docs/study-input.md). Not with --surfaces, --small, --seed,
    /// --seeds, --noise, --absolute-noise, the counter-measure or the remeshing options.
    #[arg(
        long,
        value_name = "SCAN",
        conflicts_with_all = [
            "surfaces", "small", "seed", "seeds", "noise", "absolute_noise",
            "countermeasure_weights", "no_countermeasures", "remesh", "remesh_relative",
            "no_remesh", "no_scan_example"
        ]
    )]
    input: Option<PathBuf>,
    /// With --input: the clean surface to measure against (any mesh of the part, in the
    /// same unit and position). Adds the RMS distance per iteration, the RMS-optimal
    /// count per scheme and method, and the best meshes (`best-<scheme>-<method>.ply`).
    #[arg(long, value_name = "CLEAN")]
    reference: Option<PathBuf>,
    /// With --input: the methods, comma-separated: plain, taubin, hc, implicit
    /// (default: all four).
    #[arg(long, value_delimiter = ',')]
    methods: Vec<String>,
    /// With --input: the implicit time steps, comma-separated, each run as one
    /// backward-Euler step (default 0.25, 0.5, 1, 2, 4, 8, 16, 32).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    implicit_steps: Vec<f64>,
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
    let config = StudyConfig::paper(registry)
        .surfaces(surfaces)
        .size(if args.small { Size::Small } else { Size::Paper })
        .schemes(schemes)
        .iterations(args.iterations.clone())
        .lambda(args.lambda)
        .noise(if args.absolute_noise {
            NoiseLevel::Absolute(args.noise)
        } else {
            NoiseLevel::RelativeToMeanEdge(args.noise)
        })
        .seed(args.seed)
        .seeds(args.seeds)
        .boundary(match args.boundary {
            BoundaryArg::Fixed => Boundary::Fixed,
            BoundaryArg::Free => Boundary::Free,
            BoundaryArg::Curve => Boundary::Curve,
        })
        .update(match args.update {
            UpdateArg::Every => WeightUpdate::Every,
            UpdateArg::Once => WeightUpdate::Once,
        })
        .negative(args.cotangent_negative.policy())
        .normalization(normalization(args.normalize, args.vertex_area))
        .countermeasures(if args.no_countermeasures {
            Vec::new()
        } else {
            Countermeasure::defaults(args.lambda)
        })
        .countermeasure_scheme(if args.no_countermeasures {
            None
        } else {
            Some(registry.get(&args.countermeasure_weights)?)
        })
        .edge_comparison(
            registry
                .get("bilateral")
                .ok()
                .zip(registry.get("cotangent").ok()),
        )
        .remesh(match (args.no_remesh, args.remesh, args.remesh_relative) {
            (true, ..) => None,
            (_, Some(l), _) => Some(beltrami_study::default_remesh().edge_length(l)),
            (_, _, Some(r)) => Some(beltrami_study::default_remesh().relative_edge_length(r)),
            _ => Some(beltrami_study::default_remesh()),
        })
        .timing(true)
        .scan_example(!args.no_scan_example);
    config
        .validate()
        .map_err(|e| CliError::Usage(e.to_string()))?;
    Ok(config)
}

/// Refuses an output directory that holds anything but an earlier study (see
/// [`beltrami_study::check_out_dir`]), before the study runs.
fn check_out_dir(dir: &Path, is_entry: impl Fn(&str) -> bool) -> Result<(), CliError> {
    beltrami_study::check_out_dir(dir, is_entry).map_err(|e| match e {
        OutDirError::Unwritable(source) => CliError::Io {
            path: dir.to_path_buf(),
            source,
        },
        e => CliError::Usage(format!("--out {e}")),
    })
}

/// A progress bar per run on a terminal; nothing otherwise.
pub(crate) fn terminal_progress() -> impl FnMut(Progress<'_>) {
    let terminal = std::io::stderr().is_terminal();
    let mut bar: Option<indicatif::ProgressBar> = None;
    move |p: Progress<'_>| {
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
    }
}

/// Runs `beltrami study`.
pub(crate) fn run(
    args: &StudyArgs,
    registry: &WeightRegistry,
    out: &mut impl Write,
) -> Result<(), CliError> {
    if let Some(input) = &args.input {
        return run_input(args, input, registry, out);
    }
    // With --input these select the methods and the ground truth; without it they
    // would be ignored. Checked here rather than by clap's `requires`, which clap skips
    // when an option that conflicts with --input (such as --small) is given.
    for (given, option) in [
        (!args.methods.is_empty(), "--methods"),
        (!args.implicit_steps.is_empty(), "--implicit-steps"),
        (args.reference.is_some(), "--reference"),
    ] {
        if given {
            return Err(CliError::Usage(format!(
                "{option} applies to the study of a given surface: pass --input SCAN (the paper's study runs plain smoothing with its counter-measures)"
            )));
        }
    }
    let config = config(args, registry)?;
    check_out_dir(&args.out, beltrami_study::is_any_study_entry)?;
    let mut progress = terminal_progress();
    let results = run_study(&config, &mut progress).map_err(CliError::Study)?;
    let io = |source| CliError::Io {
        path: args.out.clone(),
        source,
    };
    let staged = stage_dir(&args.out).map_err(io)?;
    let written = write_study(&results, staged.path()).map_err(CliError::Study)?;
    staged.commit().map_err(io)?;
    for caution in results.remeshing.iter().flat_map(|c| c.cautions()) {
        eprintln!("warning: {caution}");
    }
    writeln!(
        out,
        "study: {} x {}, {}, {:.1} s -> {}",
        counted(config.surfaces.len(), "surface", "surfaces"),
        counted(config.schemes.len(), "scheme", "schemes"),
        counted(written.rows.len(), "observation", "observations"),
        results.wall_time_s,
        args.out.join("report.md").display()
    )?;
    writeln!(
        out,
        "the paper's statements checked (evidence and numbers in {}):",
        args.out.join("report.md").display()
    )?;
    for f in &written.findings {
        let mark = match f.verdict {
            Verdict::Reproduced => "reproduced   ",
            Verdict::Contradicted => "contradicted ",
            Verdict::Inconclusive => "inconclusive ",
            _ => "not evaluated",
        };
        writeln!(out, "  {mark}  {}", f.id)?;
    }
    Ok(())
}

/// The configuration of `study --input`.
fn scan_config(args: &StudyArgs, registry: &WeightRegistry) -> Result<ScanConfig, CliError> {
    let schemes: Vec<Arc<dyn WeightScheme>> = if args.weights.is_empty() {
        registry.iter().cloned().collect()
    } else {
        args.weights
            .iter()
            .map(|w| registry.get(w))
            .collect::<Result<_, _>>()?
    };
    let mut config = ScanConfig::default()
        .schemes(schemes)
        .lambda(args.lambda)
        .boundary(match args.boundary {
            BoundaryArg::Fixed => Boundary::Fixed,
            BoundaryArg::Free => Boundary::Free,
            BoundaryArg::Curve => Boundary::Curve,
        })
        .update(match args.update {
            UpdateArg::Every => WeightUpdate::Every,
            UpdateArg::Once => WeightUpdate::Once,
        });
    match args.iterations.as_slice() {
        [] => {}
        [n] => config = config.max_iterations(*n),
        _ => {
            return Err(CliError::Usage(
                "with --input, --iterations takes one number: the last iteration observed (every one up to 20 is observed, then every 5th)".into(),
            ));
        }
    }
    if !args.methods.is_empty() {
        let methods = args
            .methods
            .iter()
            .map(|m| ScanMethod::from_label(m))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| CliError::Usage(format!("--methods: {e}")))?;
        config = config.methods(methods);
    }
    if !args.implicit_steps.is_empty() {
        config = config.implicit_steps(args.implicit_steps.clone());
    }
    config
        .validate()
        .map_err(|e| CliError::Usage(e.to_string()))?;
    Ok(config)
}

/// Reads a surface for `study --input` (or its reference), named by its file name.
fn load_scan(path: &Path) -> Result<ScanSurface, CliError> {
    let loaded = load(path, &ReadArgs::default())?;
    loaded.require_faces(path, "study")?;
    let name = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    ScanSurface::new(
        name,
        MeshData {
            positions: loaded.positions,
            faces: loaded.faces,
        },
    )
    .map_err(|e| CliError::Input {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// Runs `beltrami study --input SCAN [--reference CLEAN]`.
fn run_input(
    args: &StudyArgs,
    input: &Path,
    registry: &WeightRegistry,
    out: &mut impl Write,
) -> Result<(), CliError> {
    let config = scan_config(args, registry)?;
    check_out_dir(&args.out, beltrami_study::is_any_study_entry)?;
    let scan = load_scan(input)?;
    let reference = args.reference.as_deref().map(load_scan).transpose()?;
    let mut progress = terminal_progress();
    let results = run_scan(scan, reference, &config, &mut progress).map_err(CliError::Study)?;
    for w in &results.warnings {
        eprintln!("warning: {w}");
    }
    let io = |source| CliError::Io {
        path: args.out.clone(),
        source,
    };
    let staged = stage_dir(&args.out).map_err(io)?;
    write_scan(&results, staged.path()).map_err(CliError::Study)?;
    staged.commit().map_err(io)?;
    writeln!(
        out,
        "study of {}: {} x {}, {}, {:.1} s -> {}",
        results.input.name,
        counted(config.schemes.len(), "scheme", "schemes"),
        counted(config.methods.len(), "method", "methods"),
        counted(results.rows.len(), "observation", "observations"),
        results.wall_time_s,
        args.out.join("report.md").display()
    )?;
    let base = results.baseline();
    match base.rms {
        None => writeln!(
            out,
            "no --reference: no ground truth, so no best count; the report shows what smoothing removes and how much it shrinks"
        )?,
        Some(input_rms) => {
            writeln!(
                out,
                "RMS distance to the reference: input {}; the smallest per scheme and method:",
                sig(input_rms)
            )?;
            for b in &results.best {
                let count = if b.method == "implicit" {
                    format!("1 step of {}", b.step)
                } else {
                    counted(b.iteration, "iteration", "iterations")
                };
                writeln!(
                    out,
                    "  {:<22} {:<20} rms {}{} -> {}",
                    format!("{}/{}", b.scheme, b.method),
                    count,
                    sig(b.rms),
                    if b.rms < input_rms {
                        ""
                    } else if b.rms == input_rms {
                        " (no better than the input)"
                    } else {
                        " (worse than the input)"
                    },
                    args.out.join(&b.file).display()
                )?;
            }
        }
    }
    Ok(())
}
