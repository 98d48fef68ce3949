//! `beltrami smooth`: Laplacian diffusion smoothing of a mesh file.

use std::io::Write;
use std::ops::ControlFlow;
use std::time::Instant;

use beltrami_halfedge::geometry::{Geometry, TriangleGeometry};
use beltrami_halfedge::{DVec3, HalfedgeMesh};
use beltrami_io::{MeshData, declared_counts, stage_bytes};
use beltrami_smooth::{
    Method, OwnedFaces, SmoothConfig, SmoothError, SmoothReport, Smoothed, Smoother, area_step,
};
use beltrami_weights::WeightRegistry;
use beltrami_weights::{CotangentKernel, WeightScheme};

use crate::error::CliError;
use crate::load::{LoadedMesh, load_checked_keeping};
use crate::memory::{self, LARGE_RUN_VERTICES, MemoryEstimate};
use crate::output::{Outputs, Staged, notes_for_output, refuse_height_map_output};
use crate::text::{number, plural};

mod args;
pub(crate) mod kept;
mod report;

pub(crate) use args::{AreaArg, NegativeArg, NormalizeArg, SmoothArgs, normalization};
use args::{
    CotangentKernelArg, LARGE_RUN_ITERATIONS, MethodArg, SolverArg, SummationArg, TAUBIN_LAMBDA,
    TAUBIN_PASS_BAND, UpdateArg,
};
use kept::KeptPositions;
use report::{ReadSeconds, build_report, method_label};

/// Runs `beltrami smooth`.
pub(crate) fn run(
    args: &SmoothArgs,
    registry: &WeightRegistry,
    out: &mut impl Write,
) -> Result<(), CliError> {
    let scheme = registry.get(&args.weights)?;
    args.check_combination()?;
    if args.summation == SummationArg::Scatter
        && let Some(needed) = args.config().scatter_unmet(scheme.as_ref())
    {
        return Err(CliError::Usage(format!(
            "--summation scatter needs {needed}; it applies to --weights cotangent (with --cotangent-negative keep) or distance, with --update every --normalize sum --method explicit, without --preserve-volume"
        )));
    }
    refuse_height_map_output(
        &args.output,
        "smooth",
        "smoothing moves the vertices in x and y, off the grid",
    )?;
    let mut outputs = Outputs::new();
    outputs
        .add_mesh(&args.output, "OUTPUT")
        .add_opt(args.report.as_ref(), "--report");
    outputs.check(&[&args.input], args.force)?;
    let t0 = Instant::now();
    let (loaded, kept, kernel) = load_within_memory(args, scheme.as_ref())?;
    loaded.require_faces(&args.input, "smooth")?;
    crate::repair::refuse_stl_after_split(&args.output, loaded.repair.as_ref())?;
    if !args.pin.is_empty() {
        crate::repair::refuse_indices_after_renumbering(
            "--pin",
            &args.input,
            loaded.repair.as_ref(),
        )?;
    }
    let read_seconds = t0.elapsed().as_secs_f64();
    let LoadedMesh {
        mesh,
        positions,
        faces,
        repair_lines,
        parse_seconds,
        build_seconds,
        ..
    } = loaded;
    // The output is written with the mesh's own faces (`to_polygons` gives the list
    // the mesh was built from back exactly; a run without the mesh keeps its triangles,
    // the same list), so the list as read is not kept through the run.
    faces.release();
    let shape = Shape::of(&mesh);
    let mut notes = notes_for_output(&args.output, &repair_lines, &mesh);
    if args.preserve_volume {
        let parts = mesh
            .connected_components()
            .summaries
            .iter()
            .filter(|c| c.faces > 0)
            .count();
        if parts > 1 {
            notes.push(format!(
                "note: --preserve-volume rescales the whole mesh about one centroid: its {parts} separate parts keep their volume together, not each its own, and move apart as they shrink (smooth each part alone to keep its own)"
            ));
        }
    }
    let before = Before::of(&mesh, &positions, kept);
    let (smoothed, owned) = run_smoother(args, mesh, positions, scheme.as_ref(), kernel)?;

    let t1 = Instant::now();
    let change = before
        .change(&owned, &smoothed.positions)
        .map_err(|e| kept::read_back_error(&args.input, e))?;
    let faces = owned.to_polygons();
    drop(owned);
    let data = MeshData {
        positions: smoothed.positions,
        faces,
    };
    let mut staged = Staged::new();
    staged.push_mesh(&args.output, &data, args.ascii)?;
    let write_seconds = t1.elapsed().as_secs_f64();

    let r = &smoothed.report;
    if let Some(path) = &args.report {
        let read = ReadSeconds {
            total: read_seconds,
            parse: parse_seconds,
            build: build_seconds,
        };
        let report = build_report(args, &data, r, read, write_seconds, &notes);
        let mut json = serde_json::to_vec_pretty(&report).map_err(std::io::Error::from)?;
        json.push(b'\n');
        staged.push(path, |path| stage_bytes(path, &json))?;
    }
    staged.commit()?;

    write_summary(out, args, &notes, shape, data.positions.len(), r, &change)?;
    Ok(())
}

/// What the summary says about the mesh's shape, taken before the smoother owns it.
#[derive(Clone, Copy, Debug)]
struct Shape {
    closed: bool,
    triangles: bool,
}

impl Shape {
    fn of(mesh: &HalfedgeMesh) -> Self {
        Self {
            closed: mesh.is_closed(),
            triangles: mesh.is_triangle_mesh(),
        }
    }
}

/// Loads INPUT after checking the memory the run needs: first on the counts the file
/// declares (PLY header, binary STL count), before anything is read; then on the exact
/// counts, before the mesh is built.
fn load_within_memory(
    args: &SmoothArgs,
    scheme: &dyn WeightScheme,
) -> Result<(LoadedMesh, KeptPositions, CotangentKernel), CliError> {
    let mut kernel = CotangentKernel::PerTriangle;
    if let Ok(Some(declared)) = declared_counts(&args.input) {
        let faces = declared.faces;
        kernel = choose_kernel(args, scheme, false, |memory| match declared.vertices {
            Some(vertices) => MemoryEstimate::new(memory, vertices, faces, faces.saturating_mul(3)),
            None => MemoryEstimate::for_triangle_soup(memory, faces),
        })?;
    }
    let (loaded, kept) = load_checked_keeping(&args.input, &args.read, |data| {
        kernel = choose_kernel(args, scheme, true, |memory| {
            MemoryEstimate::new(
                memory,
                data.positions.len(),
                data.faces.len(),
                data.faces.n_corners(),
            )
        })?;
        Ok(())
    })?;
    Ok((loaded, kept, kernel))
}

/// The cotangent kernel of the run, after checking that its estimate (`estimate` of
/// the run's memory profile) fits: `--cotangent-kernel`, or for `auto` the per-triangle
/// kernel, and the one-ring kernel when only that fits (with a note). A run that fits
/// with neither fails with the per-triangle kernel's figure. With `--summation
/// scatter` or `--update once`, `auto` is the one-ring kernel: the operator's kernel
/// then computes the weights once, and the per-triangle table would be 120 bytes per
/// vertex for nothing (the same bits either way).
fn choose_kernel(
    args: &SmoothArgs,
    scheme: &dyn WeightScheme,
    exact: bool,
    estimate: impl Fn(&memory::Run) -> MemoryEstimate,
) -> Result<CotangentKernel, CliError> {
    let ring = args.cotangent_kernel == CotangentKernelArg::Ring
        || (args.cotangent_kernel == CotangentKernelArg::Auto
            && (args.summation == SummationArg::Scatter || args.update == UpdateArg::Once));
    let first = memory_run(args, scheme, ring);
    let fits = check_memory(args, &estimate(&first), exact);
    let auto = args.cotangent_kernel == CotangentKernelArg::Auto;
    match fits {
        Ok(()) if ring => Ok(CotangentKernel::Ring),
        Ok(()) => Ok(CotangentKernel::PerTriangle),
        Err(e) if auto && first.weights == memory::Weights::Cotangent => {
            let lean = memory_run(args, scheme, true);
            if check_memory(args, &estimate(&lean), exact).is_err() {
                return Err(e);
            }
            if exact {
                eprintln!(
                    "note: cotangents are computed from each vertex's one-ring (the per-triangle table does not fit the memory available; same results, about 1.4 times the time)"
                );
            }
            Ok(CotangentKernel::Ring)
        }
        Err(e) => Err(e),
    }
}

/// The lines on standard output: the notes (the load's, the output format's), what the run did, the diffusion time
/// and the vertices that could not move.
fn write_summary(
    out: &mut impl Write,
    args: &SmoothArgs,
    notes: &[String],
    shape: Shape,
    n_vertices: usize,
    r: &SmoothReport,
    change: &Change,
) -> Result<(), CliError> {
    for line in notes {
        writeln!(out, "{line}")?;
    }
    let boundary = if shape.closed {
        "no boundary".to_string()
    } else {
        format!("{} boundary", format!("{:?}", args.boundary).to_lowercase())
    };
    writeln!(
        out,
        "smoothed {} ({} vertices) with {} weights, {}: {} {}, lambda {}, {boundary}, {}; mean displacement {}{} -> {}",
        args.input.display(),
        n_vertices,
        r.scheme,
        method_label(&r.config.method, args.preserve_volume),
        r.iterations,
        plural(r.iterations, "iteration", "iterations"),
        number(r.config.lambda),
        r.stop.name(),
        number(change.mean_displacement),
        change
            .volume
            .map(|(before, after)| {
                // A volume beyond the range of f64 (inf) has no percentage to show.
                let change = 100.0 * (after - before) / before;
                format!(
                    ", volume {} -> {}{}",
                    number(before),
                    number(after),
                    if change.is_finite() {
                        format!(" ({change:+.3} %)")
                    } else {
                        String::new()
                    }
                )
            })
            .unwrap_or_default(),
        args.output.display()
    )?;
    if let Some(d) = r.config.duration {
        writeln!(
            out,
            "diffusion time {} (length²), Gaussian sigma {}",
            number(d.time()),
            number(d.sigma())
        )?;
    }
    if r.max_stuck_vertices > 0 {
        // Uniform and inverse-distance weights exist on polygons too.
        let why = if shape.triangles || matches!(r.scheme.as_str(), "uniform" | "distance") {
            "weights summing to <= 0 or zero area".to_string()
        } else {
            format!(
                "the mesh has polygon faces, on which {} weights are 0; use --weights uniform or distance, or triangulate the mesh",
                r.scheme
            )
        };
        writeln!(
            out,
            "note: up to {} {} per iteration could not move ({why})",
            r.max_stuck_vertices,
            plural(r.max_stuck_vertices, "vertex", "vertices"),
        )?;
    }
    if args.summation == SummationArg::Scatter && r.scattered_sweeps < r.iterations {
        let why = if r.scheme == "distance" {
            "an edge too long for plain products, or a vertex order too scattered for it"
        } else if shape.triangles {
            "a triangle collapsed to a point, or a vertex order too scattered for it"
        } else {
            "the mesh has polygon faces"
        };
        writeln!(
            out,
            "note: {} of {} iterations were summed by rows, not scattered ({why})",
            r.iterations - r.scattered_sweeps,
            r.iterations
        )?;
    }
    Ok(())
}

/// How far a run moved the mesh: the mean vertex displacement, and for a closed mesh
/// the enclosed volume before and after.
struct Change {
    mean_displacement: f64,
    volume: Option<(f64, f64)>,
}

/// What [`Change`] needs of the input, taken before the run: its positions (for the
/// displacements; in a temporary file through the run) and, for a closed mesh, its
/// volume.
struct Before {
    positions: KeptPositions,
    /// `None` for a mesh with a boundary; `Some(None)` when the volume cannot be
    /// computed.
    volume: Option<Option<f64>>,
}

/// The enclosed volume of a closed mesh, or `None` when it cannot be computed.
fn volume(mesh: &HalfedgeMesh, positions: &[DVec3]) -> Option<f64> {
    Geometry::new(mesh, positions)
        .ok()
        .and_then(|g| g.volume().ok())
}

/// The enclosed volume of the closed mesh `faces` (as [`volume`] on the mesh, the same
/// bits over the triangles of a run without it), or `None` when it cannot be computed.
fn volume_of(faces: &OwnedFaces, positions: &[DVec3]) -> Option<f64> {
    match faces {
        OwnedFaces::Mesh(mesh) => volume(mesh, positions),
        OwnedFaces::Triangles(t) => TriangleGeometry::new(t, positions).ok().map(|g| g.volume()),
        _ => None,
    }
}

impl Before {
    fn of(mesh: &HalfedgeMesh, positions: &[DVec3], kept: KeptPositions) -> Self {
        Self {
            positions: kept,
            volume: mesh.is_closed().then(|| volume(mesh, positions)),
        }
    }

    /// The change from the input to `after` on `faces` (the input's connectivity).
    ///
    /// # Errors
    /// When the input positions cannot be read back from their temporary file.
    fn change(mut self, faces: &OwnedFaces, after: &[DVec3]) -> std::io::Result<Change> {
        let mean_displacement = self.positions.mean_displacement(after)?;
        drop(self.positions);
        let volume = self.volume.and_then(|before| {
            before
                .zip(volume_of(faces, after))
                .filter(|(b, _)| *b != 0.0)
        });
        Ok(Change {
            mean_displacement,
            volume,
        })
    }
}

/// With `--normalize area` and neither `--lambda` nor `--time`/`--cutoff`: the step
/// scaled to the mesh ([`area_step`]: the method's default λ, 0.8 or Taubin's 0.6307,
/// taken as a fraction of the largest stable explicit step on the input, where 0.8
/// length² would be unstable or collapse a small part), and Taubin's μ with it (the
/// pass band scaled alike) unless `--mu` was given. Returns the step and the fraction;
/// `None` (and `config` as it was) otherwise.
fn default_area_step(
    args: &SmoothArgs,
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    scheme: &dyn WeightScheme,
    config: &mut SmoothConfig,
) -> Result<Option<(f64, f64)>, SmoothError> {
    if args.lambda.is_some() || config.duration.is_some() || args.normalize() != NormalizeArg::Area
    {
        return Ok(None);
    }
    let fraction = args.lambda();
    let Some(step) = area_step(mesh, positions, scheme, config, fraction)? else {
        return Ok(None);
    };
    config.lambda = step;
    if args.method == MethodArg::Taubin && args.mu.is_none() {
        config.method = Method::taubin_pass_band(step, TAUBIN_PASS_BAND * fraction / step);
    }
    Ok(Some((step, fraction)))
}

/// An invalid Taubin pair, with a pair that works: Taubin's classic (0.6307, −0.6732),
/// or with the μ given, the largest λ that keeps both conditions.
fn taubin_hint(args: &SmoothArgs, e: CliError) -> CliError {
    let CliError::Smooth {
        source: source @ SmoothError::InvalidTaubin { .. },
        ..
    } = &e
    else {
        return e;
    };
    let hint = match args.mu {
        Some(mu) if mu.is_finite() && mu < 0.0 => {
            // λ < −μ (positive pass band) and (1 − 2λ)(1 − 2μ) > −1 (no growth).
            let limit = (-mu).min(0.5 * (1.0 + 1.0 / (1.0 - 2.0 * mu)));
            format!("with --mu {mu}, take --lambda below {}", number(limit))
        }
        _ => format!(
            "leave --lambda out for Taubin's classic pair (lambda {TAUBIN_LAMBDA}, mu -0.6732, pass band {TAUBIN_PASS_BAND})"
        ),
    };
    CliError::Usage(format!("{source}; {hint}"))
}

/// The advice after an implicit step's solver failed (no convergence, or a system that
/// is not positive definite): steps too long for the part draw the surface together
/// until its system degenerates — with `--normalize area` the step is a time in
/// length², and the default 0.8 shrinks a part a few units across to a point in a few
/// steps (a unit sphere's mean-curvature flow ends at t = 0.25).
fn implicit_hint(args: &SmoothArgs, lambda: f64, e: CliError) -> CliError {
    let CliError::Smooth {
        path,
        source:
            source @ (SmoothError::NotConverged { .. } | SmoothError::NotPositiveDefinite { .. }),
    } = &e
    else {
        return e;
    };
    if args.method != MethodArg::Implicit {
        return e;
    }
    let step = if args.normalize() == NormalizeArg::Area {
        format!(
            "with --normalize area, --lambda is a time step in length², here {}; mean-curvature flow shrinks a unit sphere to a point by t = 0.25",
            number(lambda)
        )
    } else {
        format!("--lambda {}", number(lambda))
    };
    // A time given is the whole diffusion: smaller steps only split it.
    let advice = if args.time.is_some() || args.cutoff.is_some() {
        "give a shorter --time or --cutoff (smaller steps of the same time draw it together as well)"
    } else if args.update == UpdateArg::Once {
        "give a smaller --lambda"
    } else {
        "give a smaller --lambda, or --update once to keep the first step's weights"
    };
    CliError::Input {
        path: path.clone(),
        message: format!(
            "{source}; the steps may have drawn the surface together until its system degenerated ({step}): {advice}"
        ),
    }
}

/// Fails with [`CliError::MemoryLimit`] when `estimate` exceeds `--max-memory`, or,
/// without it and on the `exact` counts of the data as read, the memory the machine
/// has available; with `exact`, prints the estimate on stderr for a large run or with
/// `--verbose`.
///
/// The counts a file declares are checked against `--max-memory` alone: a header that
/// declares more than its file holds is then reported by the reader as what it is, not
/// as a run too large for the machine.
fn check_memory(args: &SmoothArgs, estimate: &MemoryEstimate, exact: bool) -> Result<(), CliError> {
    let available = if args.max_memory.is_none() && exact {
        beltrami_io::available_memory()
    } else {
        None
    };
    if let Some(limit) = memory::exceeded_limit(estimate.bytes, args.max_memory, available) {
        return Err(CliError::MemoryLimit {
            path: args.input.clone(),
            estimate: *estimate,
            limit,
        });
    }
    if exact && (args.verbose || estimate.vertices > LARGE_RUN_VERTICES) {
        eprintln!("note: this run needs {estimate} of memory");
    }
    Ok(())
}

/// What the run does, as far as its memory goes: the method and solver, the weights'
/// path, the options that add buffers, and the iterations whose statistics it keeps
/// (unknown before the operator is built for an explicit run for a time).
fn memory_run(args: &SmoothArgs, scheme: &dyn WeightScheme, ring: bool) -> memory::Run {
    let implicit = args.method == MethodArg::Implicit;
    let for_time = args.time.is_some() || args.cutoff.is_some();
    memory::Run {
        method: match (args.method, args.solver()) {
            (MethodArg::Explicit, _) => memory::Method::Explicit,
            (MethodArg::Taubin, _) => memory::Method::Taubin,
            (MethodArg::Hc, _) => memory::Method::Hc,
            (MethodArg::Implicit, SolverArg::Cg) => memory::Method::ImplicitCg,
            (MethodArg::Implicit, SolverArg::Cholesky) => memory::Method::ImplicitCholesky,
        },
        weights: match memory::Weights::of(scheme) {
            memory::Weights::Cotangent if ring => memory::Weights::CotangentRing,
            weights => weights,
        },
        preserve_volume: args.preserve_volume,
        area: args.normalize() == NormalizeArg::Area,
        iterations: match (implicit, for_time) {
            (true, true) => 1,
            (false, true) => 0,
            (_, false) => args.iterations,
        },
        report_steps: args.report.is_some() && !args.no_step_stats,
        scatter: args.summation == SummationArg::Scatter,
    }
}

/// Every method (plain, Taubin, HC, implicit) through [`Smoother`], which takes the
/// mesh and the positions by value (no copy of either, the mesh renumbered in place)
/// and hands back the mesh, or only its triangles when the run went on without it.
fn run_smoother(
    args: &SmoothArgs,
    mesh: HalfedgeMesh,
    positions: Vec<DVec3>,
    scheme: &dyn WeightScheme,
    kernel: CotangentKernel,
) -> Result<(Smoothed, OwnedFaces), CliError> {
    let mut config = args.config();
    config.laplacian = config.laplacian.cotangent_kernel(kernel);
    let defaulted = default_area_step(args, &mesh, &positions, scheme, &mut config);
    let lambda = config.lambda;
    let smooth_error = |source| {
        implicit_hint(
            args,
            lambda,
            taubin_hint(
                args,
                CliError::Smooth {
                    path: args.input.clone(),
                    source,
                },
            ),
        )
    };
    let defaulted = defaulted.map_err(smooth_error)?;
    let smoother = Smoother::from_owned(mesh, positions, scheme, config).map_err(smooth_error)?;
    // Steps given directly must be stable (a time chooses its own stable step); with area
    // rows the Taubin pair is checked against the limit, with the pair that fits.
    match smoother.check_stable_steps() {
        Err(e @ SmoothError::InvalidTaubin { .. }) => {
            let limit = smoother.stable_step_limit().unwrap_or(f64::NAN);
            return Err(CliError::Usage(format!(
                "{e}; with --normalize area the largest stable explicit step here is {}: Taubin's classic pair is --lambda {} --mu {} (leave both out to take it)",
                number(limit),
                number(TAUBIN_LAMBDA * limit),
                number(
                    match Method::taubin_pass_band(TAUBIN_LAMBDA * limit, TAUBIN_PASS_BAND / limit)
                    {
                        Method::Taubin { mu } => mu,
                        _ => f64::NAN,
                    }
                )
            )));
        }
        other => other.map_err(smooth_error)?,
    }
    check_plan(args, smoother.config().iterations, smoother.config().lambda)?;
    if let Some((step, fraction)) = defaulted {
        eprintln!(
            "note: --normalize area without --lambda: lambda {}, {} of the largest stable explicit step on the input ({}); give --lambda, --time or --cutoff to choose",
            number(step),
            number(fraction),
            number(step / fraction)
        );
    }
    // A bar on a terminal for runs of 20 iterations or more.
    let planned = smoother.config().iterations;
    let progress = crate::progress::bar(planned, "iterations", planned >= 20);
    let (smoothed, faces) = smoother
        .run_owned_faces(|it| {
            if let Some(bar) = &progress {
                bar.set_position(it.index as u64);
            }
            ControlFlow::Continue(())
        })
        .map_err(smooth_error)?;
    if let Some(bar) = progress {
        bar.finish_and_clear();
    }
    let faces = faces.expect("a mesh given by value is handed back");
    Ok((smoothed, faces))
}

/// Refuses a run planning more than `--max-iterations` iterations, and prints the
/// plan on stderr with `--verbose` or for a long run.
fn check_plan(args: &SmoothArgs, iterations: usize, step: f64) -> Result<(), CliError> {
    if iterations > args.max_iterations {
        return Err(CliError::Usage(format!(
            "the run would take {iterations} iterations of step {}, more than --max-iterations {} (is --time or --cutoff in the mesh's length unit? raise --max-iterations to run it anyway)",
            number(step),
            args.max_iterations
        )));
    }
    if args.verbose || iterations > LARGE_RUN_ITERATIONS {
        eprintln!(
            "note: planned {iterations} {} of step {}",
            plural(iterations, "iteration", "iterations"),
            number(step)
        );
    }
    Ok(())
}
