//! The paper's figures: plots of the rows and renders of the smoothed meshes.

use std::path::Path;

use beltrami_halfedge::DVec3;
use beltrami_halfedge::geometry::Geometry;
use beltrami_metrics::profile::{Plane, Polyline, cross_section};
use beltrami_surfaces::SurfaceKind;
use beltrami_viz::plot::{LinePlot, Series, write_plot};
use beltrami_viz::render::{ColorMap, Image, View, grid, render_mesh};

use crate::closed_form::{predicted_radius, weighted_mean_edge_sq};
use crate::error::StudyError;
use crate::findings::sig;
use crate::measure::Reference;
use crate::results::Row;
use crate::run::{EARLY_ITERATIONS, StudyResults, SurfaceResult};

/// A figure written by the study: its file stem (under `plots/` or `renders/`), its
/// caption and the paper figure it corresponds to.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Figure {
    /// Path relative to the output directory, without extension for plots
    /// (`plots/rms_flens` → `.svg` and `.png`), with `.png` for renders.
    pub path: String,
    /// What it shows.
    pub caption: String,
    /// The surface it belongs to.
    pub surface: String,
}

fn viz(name: &str) -> impl Fn(beltrami_viz::VizError) -> StudyError + '_ {
    move |e| StudyError::Plot {
        name: name.to_string(),
        reason: e.to_string(),
    }
}

/// One series per scheme of `f(row)` against the iteration, the noisy input as
/// iteration 0.
fn series_by_scheme(
    result: &SurfaceResult,
    rows: &[Row],
    f: impl Fn(&Row) -> Option<f64>,
) -> Vec<Series> {
    let surface = result.case.clean.name;
    // Per iteration, the values over the noise seeds (the rows hold every seed).
    let by_iteration = |scheme: &str| {
        let mut at: Vec<(usize, Vec<f64>)> = Vec::new();
        for r in rows
            .iter()
            .filter(|r| r.surface == surface && r.scheme == scheme)
        {
            if let Some(v) = f(r) {
                match at.iter_mut().find(|(i, _)| *i == r.iteration) {
                    Some((_, values)) => values.push(v),
                    None => at.push((r.iteration, vec![v])),
                }
            }
        }
        at.sort_by_key(|(i, _)| *i);
        at
    };
    let input = by_iteration("input");
    let mut series = Vec::new();
    for run in &result.runs {
        let at: Vec<(usize, Vec<f64>)> = input
            .iter()
            .map(|(_, v)| (0, v.clone()))
            .chain(by_iteration(&run.scheme))
            .collect();
        series.extend(mean_and_range(result, &run.scheme, &at));
    }
    series
}

/// A length unit for an axis or a column header: ` (mm)`, or ` (clean radii)` for the
/// unit sphere, whose lengths are in units of its clean radius (unit `"1"`).
pub(crate) fn unit_label(unit: &str) -> String {
    if unit == "1" {
        " (clean radii)".into()
    } else {
        format!(" ({unit})")
    }
}

/// The palette slot of the input (black).
pub(crate) const INPUT_STYLE: usize = 6;
/// The palette slot of the clean surface (grey).
pub(crate) const CLEAN_STYLE: usize = 7;

/// The palette slot of a series: a scheme keeps its position among the study's schemes
/// in every plot (skipping the slots of the input and the clean surface), `"input"` and
/// `"clean"` have their own.
pub(crate) fn scheme_style(result: &SurfaceResult, label: &str) -> usize {
    match label {
        "input" => INPUT_STYLE,
        "clean" => CLEAN_STYLE,
        _ => {
            let i = result
                .runs
                .iter()
                .position(|r| r.scheme == label)
                .unwrap_or(result.runs.len());
            if i < INPUT_STYLE { i } else { i + 2 }
        }
    }
}

/// Two curves closer than this fraction of a plot's height everywhere are drawn on top
/// of each other; the study then adds a difference panel.
pub const OVERLAP_FRACTION: f64 = 0.02;

/// Whether every series lies within [`OVERLAP_FRACTION`] of the plot's height (the
/// span of all finite values) of the first one at each of the first one's x values
/// (series without a point there are not compared). `false` with fewer than two
/// series or a span of zero.
#[must_use]
pub fn curves_overlap(series: &[Series]) -> bool {
    let Some((first, rest)) = series.split_first() else {
        return false;
    };
    if rest.is_empty() {
        return false;
    }
    let values = series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .filter(|v| v.is_finite());
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    let span = hi - lo;
    if span.is_nan() || span <= 0.0 {
        return false;
    }
    rest.iter().all(|s| {
        first.points.iter().all(|&(x, y)| {
            s.points
                .iter()
                .find(|p| p.0 == x)
                .is_none_or(|p| (p.1 - y).abs() <= OVERLAP_FRACTION * span)
        })
    })
}

/// Each series after the first minus the first at the first one's x values (a
/// difference panel), keeping labels and styles; points without a partner are left out.
#[must_use]
pub fn differences(series: &[Series]) -> Vec<Series> {
    let Some((first, rest)) = series.split_first() else {
        return Vec::new();
    };
    rest.iter()
        .map(|s| {
            let points = s
                .points
                .iter()
                .filter_map(|&(x, y)| first.points.iter().find(|p| p.0 == x).map(|p| (x, y - p.1)));
            let mut d = Series::new(format!("{} − {}", s.label, first.label), points);
            d.style = s.style;
            d
        })
        .collect()
}

/// The fitted radius per scheme and, on the unit sphere, each scheme's closed-form
/// prediction r₀ (1 − λ⟨ℓ²⟩_w/2r₀²)ⁿ as a dashed line in the scheme's colour (see
/// [`crate::closed_form`]).
fn radius_series(results: &StudyResults, result: &SurfaceResult, rows: &[Row]) -> Vec<Series> {
    let mut series = series_by_scheme(result, rows, |r| r.sphere_radius);
    // The closed form is that of weight-sum rows.
    if result.case.kind != SurfaceKind::Sphere
        || results.config.normalization != beltrami_weights::Normalization::WeightSum
    {
        return series;
    }
    let last = results.config.max_iterations();
    for scheme in &results.config.schemes {
        if !result.runs.iter().any(|r| r.scheme == scheme.name()) {
            continue;
        }
        let Some(l2) = weighted_mean_edge_sq(
            &result.case.mesh,
            &result.case.clean.positions,
            scheme.as_ref(),
        ) else {
            continue;
        };
        let lambda = results.config.lambda;
        let points = (0..=last).map(|n| (n as f64, predicted_radius(1.0, lambda, l2, n)));
        series.push(
            Series::new(format!("{} (closed form)", scheme.name()), points)
                .with_style(scheme_style(result, scheme.name()))
                .dashed(),
        );
    }
    series
}

/// Per scheme, the mean RMS over the seeds at every iteration up to
/// [`EARLY_ITERATIONS`], starting from the input's.
fn early_series(result: &SurfaceResult) -> Vec<Series> {
    let values_at = |scheme: &str, it: usize| -> Vec<f64> {
        result
            .rms_curve
            .iter()
            .filter(|p| p.scheme == scheme && p.iteration == it)
            .map(|p| p.rms)
            .collect()
    };
    let input = values_at("input", 0);
    let mut series = Vec::new();
    for run in &result.runs {
        let at: Vec<(usize, Vec<f64>)> = std::iter::once((0, input.clone()))
            .chain((1..=EARLY_ITERATIONS).map(|it| (it, values_at(&run.scheme, it))))
            .filter(|(_, v)| !v.is_empty())
            .collect();
        series.extend(mean_and_range(result, &run.scheme, &at));
    }
    series
}

/// The mean line of `scheme` through `at` (iteration, values over the seeds) and, when
/// some iteration has several seeds, their range as two thin dashed lines in the same
/// colour, left out of the legend.
fn mean_and_range(result: &SurfaceResult, scheme: &str, at: &[(usize, Vec<f64>)]) -> Vec<Series> {
    let point = |g: &dyn Fn(&[f64]) -> f64| -> Vec<(f64, f64)> {
        at.iter().map(|(i, v)| (*i as f64, g(v))).collect()
    };
    let style = scheme_style(result, scheme);
    let mut series = vec![
        Series::new(scheme, point(&|v| v.iter().sum::<f64>() / v.len() as f64)).with_style(style),
    ];
    if at.iter().any(|(_, v)| v.len() > 1) {
        let lo = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = |v: &[f64]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        for bound in [point(&lo), point(&hi)] {
            series.push(
                Series::new(format!("{scheme} (seed range)"), bound)
                    .with_style(style)
                    .dashed()
                    .without_legend(),
            );
        }
    }
    series
}

struct PlotSpec {
    stem: String,
    title: String,
    y_label: String,
    caption: String,
    log_y: bool,
    series: Vec<Series>,
    /// Add a difference panel (each scheme minus the first) when the schemes' curves
    /// overlap (see [`curves_overlap`]).
    diff: bool,
}

fn write_line(
    dir: &Path,
    spec: PlotSpec,
    surface: &str,
    figures: &mut Vec<Figure>,
) -> Result<(), StudyError> {
    if spec
        .series
        .iter()
        .all(|s| s.points.iter().all(|p| !p.1.is_finite()))
    {
        return Ok(());
    }
    let data: Vec<Series> = spec.series.iter().filter(|s| !s.dashed).cloned().collect();
    // Predictions are dashed and listed; the seeds' range is dashed and not listed.
    let predicted: Vec<Series> = spec
        .series
        .iter()
        .filter(|s| s.dashed && s.in_legend)
        .cloned()
        .collect();
    let diff = spec.diff && curves_overlap(&data);
    let mut plot = LinePlot::new(spec.title.clone(), "iterations", spec.y_label.clone());
    plot.series = spec.series.clone();
    plot.log_y = spec.log_y;
    let rel = format!("plots/{}", spec.stem);
    write_plot(&plot, &dir.join(&rel)).map_err(viz(&spec.stem))?;
    let spread = spec.series.iter().any(|s| !s.in_legend);
    figures.push(Figure {
        path: rel,
        caption: if spread {
            format!(
                "{}; lines: the mean over the noise seeds, thin dashed lines in the same colour: their range",
                spec.caption
            )
        } else {
            spec.caption.clone()
        },
        surface: surface.to_string(),
    });
    if diff {
        let base = data.first().map_or("", |s| s.label.as_str()).to_string();
        let mut plot = LinePlot::new(
            format!("{}: difference from {base}", spec.title),
            "iterations",
            format!("{}, scheme − {base}", spec.y_label),
        );
        // The data minus the first data series; predictions (dashed) minus the first
        // prediction: the measured gap beside the predicted one.
        plot.series = differences(&data);
        plot.series
            .extend(differences(&predicted).into_iter().map(Series::dashed));
        let stem = format!("{}_diff", spec.stem);
        let rel = format!("plots/{stem}");
        write_plot(&plot, &dir.join(&rel)).map_err(viz(&stem))?;
        figures.push(Figure {
            path: rel,
            caption: format!(
                "The same as a difference from `{base}`: the schemes' curves above lie within {} % of the plot's height of each other, too close to tell apart",
                100.0 * OVERLAP_FRACTION
            ),
            surface: surface.to_string(),
        });
    }
    Ok(())
}

/// The iteration the paper shows most (100), or the largest studied if smaller.
pub(crate) fn shown_iteration(results: &StudyResults) -> usize {
    let it = &results.config.iterations;
    if it.contains(&100) {
        100
    } else {
        *it.last().unwrap_or(&0)
    }
}

/// Up to four iteration counts spread over the study, for render grids.
pub(crate) fn render_iterations(results: &StudyResults) -> Vec<usize> {
    let it = &results.config.iterations;
    let mut picks: Vec<usize> = [10, 50, 100, 200]
        .into_iter()
        .filter(|i| it.contains(i))
        .collect();
    if picks.len() < 2 {
        picks = it.clone();
        if picks.len() > 4 {
            let n = picks.len();
            picks = vec![picks[0], picks[n / 3], picks[2 * n / 3], picks[n - 1]];
        }
    }
    picks
}

/// Writes every plot and render into `dir/plots` and `dir/renders`. `rows` are every
/// seed's ([`StudyResults::all_seed_rows`](crate::StudyResults::all_seed_rows)): the
/// lines are means over the seeds, with their range as thin dashed lines.
///
/// # Errors
/// [`StudyError::Plot`], [`StudyError::Image`] or [`StudyError::Metrics`].
pub fn write_figures(
    results: &StudyResults,
    rows: &[Row],
    dir: &Path,
) -> Result<Vec<Figure>, StudyError> {
    let mut figures = Vec::new();
    let shown = shown_iteration(results);
    for result in &results.surfaces {
        write_history_plots(dir, results, result, rows, &mut figures)?;
        write_shape_plots(dir, result, rows, shown, &mut figures)?;
        if matches!(result.case.kind, SurfaceKind::FLens | SurfaceKind::Block) {
            profile_plot(dir, result, shown, &mut figures)?;
        }
        render_grid(dir, results, result, &mut figures)?;
        if result.case.kind == SurfaceKind::GolfBall {
            golf_closeup(dir, result, shown, &mut figures)?;
        }
    }
    Ok(figures)
}

/// The plots of a surface's figures over the iterations: RMS distance (all and early),
/// time, and the fitted radius of the sphere and the golf ball.
fn write_history_plots(
    dir: &Path,
    results: &StudyResults,
    result: &SurfaceResult,
    rows: &[Row],
    figures: &mut Vec<Figure>,
) -> Result<(), StudyError> {
    let name = result.case.clean.name;
    let u = unit_label(result.case.clean.unit);
    write_line(
        dir,
        PlotSpec {
            stem: format!("rms_{name}"),
            title: format!("{name}: RMS distance to the clean surface"),
            y_label: format!("RMS distance{u}"),
            caption: format!(
                "RMS of the vertex distances from the smoothed {name} to the clean surface (paper Figs. 4a, 7a, 9a)"
            ),
            log_y: false,
            series: series_by_scheme(result, rows, |r| Some(r.rms)),
            diff: true,
        },
        name,
        figures,
    )?;
    write_line(
        dir,
        PlotSpec {
            stem: format!("rms_early_{name}"),
            title: format!("{name}: RMS, iterations 0 to {EARLY_ITERATIONS}"),
            y_label: format!("RMS distance{u}"),
            caption: format!(
                "RMS distance to the clean surface on the {name}, every iteration from 0 to {EARLY_ITERATIONS}: the RMS-optimal iteration count lies here"
            ),
            log_y: false,
            series: early_series(result),
            diff: true,
        },
        name,
        figures,
    )?;
    write_line(
        dir,
        PlotSpec {
            stem: format!("time_{name}"),
            title: format!("{name}: computation time"),
            y_label: "cumulative time (s)".into(),
            caption: format!(
                "Cumulative smoothing time on the {name} (paper Figs. 4b, 7c, 9c, 11b)"
            ),
            log_y: true,
            series: series_by_scheme(result, rows, |r| (r.iteration > 0).then_some(r.time_s)),
            diff: false,
        },
        name,
        figures,
    )?;
    if matches!(
        result.case.kind,
        SurfaceKind::Sphere | SurfaceKind::GolfBall
    ) {
        write_line(
            dir,
            PlotSpec {
                stem: format!("radius_{name}"),
                title: format!("{name}: fitted sphere radius"),
                y_label: format!("radius{u}"),
                caption: format!(
                    "Radius of the least-squares sphere through the smoothed {name} (paper Figs. 7b, 11a)"
                ),
                log_y: false,
                series: radius_series(results, result, rows),
                diff: true,
            },
            name,
            figures,
        )?;
    }
    Ok(())
}

/// The plots of a surface's shape over the iterations: the enclosed volume of a closed
/// surface or the boundary displacement (and ring plot) of an open one, and the
/// sharpness of the block's edges.
fn write_shape_plots(
    dir: &Path,
    result: &SurfaceResult,
    rows: &[Row],
    shown: usize,
    figures: &mut Vec<Figure>,
) -> Result<(), StudyError> {
    let name = result.case.clean.name;
    let u = unit_label(result.case.clean.unit);
    if result.case.mesh.is_closed() {
        write_line(
            dir,
            PlotSpec {
                stem: format!("volume_{name}"),
                title: format!("{name}: enclosed volume"),
                y_label: "volume / clean volume".into(),
                caption: format!(
                    "Volume of the smoothed {name} relative to the clean one (paper Fig. 9b)"
                ),
                log_y: false,
                series: series_by_scheme(result, rows, |r| r.volume_ratio),
                diff: true,
            },
            name,
            figures,
        )?;
    } else {
        write_line(
            dir,
            PlotSpec {
                stem: format!("boundary_{name}"),
                title: format!("{name}: boundary displacement"),
                y_label: format!("mean boundary displacement{u}"),
                caption: format!(
                    "Mean displacement of the {name}'s boundary vertices from the noisy input (paper Fig. 5)"
                ),
                log_y: false,
                series: series_by_scheme(result, rows, |r| r.boundary_mean),
                diff: true,
            },
            name,
            figures,
        )?;
        ring_plot(dir, result, shown, figures)?;
    }
    if result.case.kind == SurfaceKind::Block {
        write_line(
            dir,
            PlotSpec {
                stem: format!("dihedral_{name}"),
                title: format!("{name}: sharpness of the feature edges"),
                y_label: "mean dihedral angle (deg)".into(),
                caption: format!(
                    "Mean dihedral angle at the {name}'s sharp edges (90° when sharp; paper Fig. 8)"
                ),
                log_y: false,
                series: series_by_scheme(result, rows, |r| r.feature_dihedral_deg),
                diff: false,
            },
            name,
            figures,
        )?;
    }
    Ok(())
}

fn ring_plot(
    dir: &Path,
    result: &SurfaceResult,
    shown: usize,
    figures: &mut Vec<Figure>,
) -> Result<(), StudyError> {
    let name = result.case.clean.name;
    let mut plot = LinePlot::new(
        format!("{name}: error by distance from the boundary after {shown} iterations"),
        "rings from the boundary",
        format!(
            "RMS distance to the clean surface{}",
            unit_label(result.case.clean.unit)
        ),
    );
    for m in &result.measured {
        if (m.row.iteration == shown || m.row.scheme == "input")
            && let Some(rings) = &m.rings
        {
            let points = rings.rings.iter().map(|r| (f64::from(r.ring), r.rms));
            plot.series.push(
                Series::new(m.row.scheme.clone(), points)
                    .with_style(scheme_style(result, &m.row.scheme)),
            );
        }
    }
    if plot.series.is_empty() {
        return Ok(());
    }
    let rel = format!("plots/rings_{name}");
    write_plot(&plot, &dir.join(&rel)).map_err(viz(&rel))?;
    figures.push(Figure {
        path: rel,
        caption: format!("RMS distance to the clean {name} by ring of vertices at the same graph distance from the boundary, after {shown} iterations: how far boundary distortion reaches inwards (paper Fig. 5)"),
        surface: name.to_string(),
    });
    Ok(())
}

/// Every polyline of a plane section, as (u, v) coordinates in the plane, the longest
/// first, joined by a non-finite point (where the plotted line breaks): a section
/// through the block's middle hole has two loops, one per wall.
fn section(
    positions: &[DVec3],
    result: &SurfaceResult,
    plane: &Plane,
    axes: (DVec3, DVec3),
) -> Result<Vec<(f64, f64)>, StudyError> {
    let geometry = Geometry::new(&result.case.mesh, positions)
        .map_err(|e| StudyError::Config(e.to_string()))?;
    let mut polylines: Vec<Polyline> =
        cross_section(&geometry, plane).map_err(|source| StudyError::Metrics {
            surface: result.case.clean.name.to_string(),
            scheme: "profile".into(),
            source,
        })?;
    polylines.sort_by(|a, b| b.length().total_cmp(&a.length()));
    let mut out = Vec::new();
    for l in &polylines {
        if !out.is_empty() {
            out.push((f64::NAN, f64::NAN));
        }
        let start = out.len();
        out.extend(l.positions().map(|p| (p.dot(axes.0), p.dot(axes.1))));
        if l.closed && out.len() > start {
            out.push(out[start]);
        }
    }
    Ok(out)
}

fn profile_plot(
    dir: &Path,
    result: &SurfaceResult,
    shown: usize,
    figures: &mut Vec<Figure>,
) -> Result<(), StudyError> {
    let name = result.case.clean.name;
    // F-lens: the x–z profile along y = 0; block: the x–y outline at mid-height.
    let (plane, axes, what, labels) = match result.case.kind {
        SurfaceKind::FLens => (
            Plane::new(DVec3::ZERO, DVec3::Y),
            (DVec3::X, DVec3::Z),
            "y = 0",
            ("x", "z"),
        ),
        _ => (
            Plane::new(DVec3::new(0.0, 0.0, 0.01), DVec3::Z),
            (DVec3::X, DVec3::Y),
            "z = 0.01, both walls of the middle hole",
            ("x", "y"),
        ),
    };
    let plane = plane.map_err(|source| StudyError::Metrics {
        surface: name.to_string(),
        scheme: "profile".into(),
        source,
    })?;
    let unit = result.case.clean.unit;
    let mut plot = LinePlot::new(
        format!("{name}: section {what}, {shown} iterations"),
        format!("{} ({unit})", labels.0),
        format!("{} ({unit})", labels.1),
    );
    plot.aspect_equal = result.case.kind == SurfaceKind::Block;
    plot.series.push(
        Series::new(
            "clean",
            section(&result.case.clean.positions, result, &plane, axes)?,
        )
        .with_style(CLEAN_STYLE),
    );
    plot.series.push(
        Series::new("input", section(&result.case.noisy, result, &plane, axes)?)
            .with_style(INPUT_STYLE),
    );
    for run in &result.runs {
        if let Some(s) = run.snapshots.iter().find(|s| s.iteration == shown) {
            plot.series.push(
                Series::new(
                    run.scheme.clone(),
                    section(&s.positions, result, &plane, axes)?,
                )
                .with_style(scheme_style(result, &run.scheme)),
            );
        }
    }
    let rel = format!("plots/profile_{name}");
    write_plot(&plot, &dir.join(&rel)).map_err(viz(&rel))?;
    figures.push(Figure {
        path: rel,
        caption: format!("Cross-section profile of the {name} (section {what}): clean, noisy input and each scheme after {shown} iterations (the paper's cross-sectional profile comparison)"),
        surface: name.to_string(),
    });
    Ok(())
}

fn render_grid(
    dir: &Path,
    results: &StudyResults,
    result: &SurfaceResult,
    figures: &mut Vec<Figure>,
) -> Result<(), StudyError> {
    let name = result.case.clean.name;
    let metrics_error = |source| StudyError::Metrics {
        surface: name.to_string(),
        scheme: "render".into(),
        source,
    };
    let reference = Reference::new(&result.case).map_err(metrics_error)?;
    let iterations = render_iterations(results);
    let clean = &result.case.clean.positions;
    let frame = Geometry::new(&result.case.mesh, clean)
        .ok()
        .and_then(|g| g.bounding_box());
    let view = match result.case.kind {
        SurfaceKind::FLens => View {
            direction: DVec3::new(0.3, 0.6, -1.0).normalize(),
            up: DVec3::Y,
        },
        _ => View::default_for(clean),
    };
    // One colour scale for the whole grid: ±3σ of the noise.
    let colors = ColorMap::symmetric(3.0 * result.case.sigma);
    let (w, h) = (360, 270);
    let mut panels: Vec<Image> = Vec::new();
    let image_error = |e: beltrami_viz::VizError| StudyError::Image {
        name: format!("renders/{name}"),
        reason: e.to_string(),
    };
    let input_signed = reference
        .signed_distances(&result.case.noisy)
        .map_err(metrics_error)?;
    let input_panel = render_mesh(
        &result.case.mesh,
        &result.case.noisy,
        Some(&input_signed),
        &colors,
        &view,
        frame,
        w,
        h,
    )
    .map_err(image_error)?;
    for run in &result.runs {
        panels.push(input_panel.clone());
        for &it in &iterations {
            let s = run
                .snapshots
                .iter()
                .find(|s| s.iteration == it)
                .ok_or_else(|| StudyError::Config(format!("no snapshot at iteration {it}")))?;
            let signed = reference
                .signed_distances(&s.positions)
                .map_err(metrics_error)?;
            panels.push(
                render_mesh(
                    &result.case.mesh,
                    &s.positions,
                    Some(&signed),
                    &colors,
                    &view,
                    frame,
                    w,
                    h,
                )
                .map_err(image_error)?,
            );
        }
    }
    let mut columns = vec!["input".to_string()];
    columns.extend(iterations.iter().map(|i| format!("{i} iterations")));
    let rows: Vec<String> = result.runs.iter().map(|r| r.scheme.clone()).collect();
    let unit = unit_label(result.case.clean.unit);
    let image = grid(
        &panels,
        columns.len(),
        &columns,
        &rows,
        &format!("{name}: signed distance to the clean surface"),
        Some((&colors, &format!("signed distance{unit}"))),
    )
    .map_err(image_error)?;
    let rel = format!("renders/{name}.png");
    image.write_png(&dir.join(&rel)).map_err(image_error)?;
    figures.push(Figure {
        path: rel,
        caption: format!("The {name} smoothed by each scheme (rows) after increasing iteration counts (columns), coloured by signed distance to the clean surface (paper Figs. 3, 6, 8, 10)"),
        surface: name.to_string(),
    });
    Ok(())
}

/// The first interior vertex of valence 5 (an icosahedron corner of the golf ball).
pub(crate) fn valence5_vertex(mesh: &beltrami_halfedge::HalfedgeMesh) -> Option<usize> {
    mesh.vertices()
        .find(|&v| !mesh.is_boundary_vertex(v) && mesh.valence(v) == 5)
        .map(|v| v.index())
}

/// Half the width of the golf ball close-up, in mean edge lengths.
const CLOSEUP_EDGES: f64 = 8.0;

/// A close-up of the golf ball around a valence-5 vertex, looking along its normal:
/// the input and each scheme after `shown` iterations, coloured by the residual — the
/// signed distance to the clean surface minus its mean over the whole ball (the uniform
/// shrink) — so the local bumps at the irregular vertex show.
fn golf_closeup(
    dir: &Path,
    result: &SurfaceResult,
    shown: usize,
    figures: &mut Vec<Figure>,
) -> Result<(), StudyError> {
    let name = result.case.clean.name;
    let Some(closeup) = Closeup::new(dir, result)? else {
        return Ok(());
    };
    let (labels, positions) = closeup_panels(result, shown);
    let (residuals, largest) = closeup.residuals(&positions)?;
    if !(largest > 0.0 && largest.is_finite()) {
        return Ok(());
    }
    let unit = unit_label(result.case.clean.unit);
    let u = result.case.clean.unit;
    let across = sig(2.0 * closeup.half);
    let rel = closeup.render(
        &positions,
        &residuals,
        &labels,
        &ColorMap::symmetric(largest),
        [
            &format!("{name}: residual near a valence-5 vertex"),
            &format!("signed distance − its mean{unit}"),
            &format!("{name}_valence5"),
        ],
    )?;
    figures.push(Figure {
        path: rel,
        caption: format!("Close-up of the {name} around a valence-5 vertex (an icosahedron corner; {across} {u} across), seen along its normal: the noisy input and each scheme after {shown} iterations, coloured by the signed distance to the clean surface minus its mean over the whole ball (the overall shrink removed); the colour scale spans the smoothed panels' largest residual there, {} {u}", sig(largest)),
        surface: name.to_string(),
    });
    // Each scheme against the schemes' mean: where one departs from the others.
    if let Some((departures, spread)) = scheme_departures(&residuals, &closeup.near) {
        let rel = closeup.render(
            &positions[1..],
            &departures,
            &labels[1..],
            &ColorMap::symmetric(spread),
            [
                &format!("{name}: each scheme minus the schemes' mean near a valence-5 vertex"),
                &format!("signed distance − the schemes' mean{unit}"),
                &format!("{name}_valence5_schemes"),
            ],
        )?;
        figures.push(Figure {
            path: rel,
            caption: format!("The same close-up, each scheme's signed distance minus the mean over the schemes after {shown} iterations: where one scheme departs from the others near the irregular vertex (colour scale ±{} {u}, the largest departure there)", sig(spread)),
            surface: name.to_string(),
        });
    }
    Ok(())
}

/// The panels of the close-up: the noisy input, then each scheme that has a snapshot
/// at iteration `shown`; their labels and positions.
fn closeup_panels(result: &SurfaceResult, shown: usize) -> (Vec<String>, Vec<&[DVec3]>) {
    let mut labels = vec!["input".to_string()];
    let mut positions: Vec<&[DVec3]> = vec![&result.case.noisy];
    for run in &result.runs {
        if let Some(s) = run.snapshots.iter().find(|s| s.iteration == shown) {
            labels.push(format!("{} ({shown} it.)", run.scheme));
            positions.push(&s.positions);
        }
    }
    (labels, positions)
}

/// Each scheme's residual minus the schemes' mean (`residuals[0]` is the input's), and
/// the largest departure near the vertex; `None` with fewer than two schemes or no
/// finite positive departure.
fn scheme_departures(residuals: &[Vec<f64>], near: &[usize]) -> Option<(Vec<Vec<f64>>, f64)> {
    if residuals.len() <= 2 {
        return None;
    }
    let k = (residuals.len() - 1) as f64;
    let mean: Vec<f64> = (0..residuals[0].len())
        .map(|i| residuals[1..].iter().map(|r| r[i]).sum::<f64>() / k)
        .collect();
    let departures: Vec<Vec<f64>> = residuals[1..]
        .iter()
        .map(|r| r.iter().zip(&mean).map(|(a, m)| a - m).collect())
        .collect();
    let spread = departures
        .iter()
        .flat_map(|d| near.iter().map(move |&i| d[i].abs()))
        .fold(0.0, f64::max);
    (spread > 0.0 && spread.is_finite()).then_some((departures, spread))
}

/// The view of a close-up around a valence-5 vertex of a surface.
struct Closeup<'a> {
    /// The study's output directory.
    dir: &'a Path,
    /// The surface's connectivity.
    mesh: &'a beltrami_halfedge::HalfedgeMesh,
    /// The surface's name, for errors.
    name: &'static str,
    /// The distance to the clean surface.
    reference: Reference<'a>,
    /// Looking along the vertex's inward normal.
    view: View,
    /// The box shown: `half` around the vertex on each axis.
    frame: Option<(DVec3, DVec3)>,
    /// Half the width shown, in the surface's unit.
    half: f64,
    /// The clean vertices within `half` of the vertex.
    near: Vec<usize>,
}

impl<'a> Closeup<'a> {
    /// The close-up of `result`'s surface, or `None` when it has no valence-5 vertex or
    /// no usable normal or edge length.
    ///
    /// # Errors
    /// [`StudyError::Metrics`] when the reference surface cannot be indexed.
    fn new(dir: &'a Path, result: &'a SurfaceResult) -> Result<Option<Self>, StudyError> {
        let name = result.case.clean.name;
        let mesh = &result.case.mesh;
        let clean = &result.case.clean.positions;
        let Some(v) = valence5_vertex(mesh) else {
            return Ok(None);
        };
        let reference = Reference::new(&result.case).map_err(closeup_error(name))?;
        let centre = clean.iter().copied().sum::<DVec3>() / clean.len().max(1) as f64;
        let p = clean[v];
        let normal = (p - centre).normalize_or_zero();
        if normal == DVec3::ZERO {
            return Ok(None);
        }
        let mean_edge = beltrami_algorithms::mesh_quality(mesh, clean)
            .ok()
            .and_then(|q| q.edge_length)
            .map_or(0.0, |e| e.mean);
        let half = CLOSEUP_EDGES * mean_edge;
        if half.is_nan() || half <= 0.0 {
            return Ok(None);
        }
        let frame = Some((p - DVec3::splat(half), p + DVec3::splat(half)));
        let up = if normal.cross(DVec3::Z).length() > 0.1 {
            DVec3::Z
        } else {
            DVec3::Y
        };
        let near: Vec<usize> = clean
            .iter()
            .enumerate()
            .filter(|(_, q)| q.distance(p) <= half)
            .map(|(i, _)| i)
            .collect();
        Ok(Some(Closeup {
            dir,
            mesh,
            name,
            reference,
            view: View::new(-normal, up),
            frame,
            half,
            near,
        }))
    }

    /// Each panel's signed distance to the clean surface minus its mean, and the
    /// largest of them near the vertex over the smoothed panels (the input's noise
    /// would swamp the colour scale).
    ///
    /// # Errors
    /// [`StudyError::Metrics`] when a distance cannot be measured.
    fn residuals(&self, positions: &[&[DVec3]]) -> Result<(Vec<Vec<f64>>, f64), StudyError> {
        let mut residuals = Vec::with_capacity(positions.len());
        let mut largest: f64 = 0.0;
        for (k, pos) in positions.iter().enumerate() {
            let signed = self
                .reference
                .signed_distances(pos)
                .map_err(closeup_error(self.name))?;
            let mean = signed.iter().sum::<f64>() / signed.len().max(1) as f64;
            let r: Vec<f64> = signed.iter().map(|d| d - mean).collect();
            if k > 0 {
                largest = self
                    .near
                    .iter()
                    .map(|&i| r[i].abs())
                    .fold(largest, f64::max);
            }
            residuals.push(r);
        }
        Ok((residuals, largest))
    }

    /// Renders one row of panels (positions coloured by `values`) with a colour bar and
    /// writes it to `renders/{stem}.png`; `[title, bar, stem]` name the image, its
    /// colour bar and its file. Returns the path relative to the output directory.
    ///
    /// # Errors
    /// [`StudyError::Image`] when rendering or writing fails.
    fn render(
        &self,
        positions: &[&[DVec3]],
        values: &[Vec<f64>],
        labels: &[String],
        colors: &ColorMap,
        [title, bar, stem]: [&str; 3],
    ) -> Result<String, StudyError> {
        let image_error = |e: beltrami_viz::VizError| StudyError::Image {
            name: format!("renders/{stem}"),
            reason: e.to_string(),
        };
        let panels = positions
            .iter()
            .zip(values)
            .map(|(pos, r)| {
                render_mesh(
                    self.mesh,
                    pos,
                    Some(r),
                    colors,
                    &self.view,
                    self.frame,
                    360,
                    360,
                )
            })
            .collect::<Result<Vec<_>, _>>()
            .map_err(image_error)?;
        let image = grid(
            &panels,
            panels.len(),
            labels,
            &[String::new()],
            title,
            Some((colors, bar)),
        )
        .map_err(image_error)?;
        let rel = format!("renders/{stem}.png");
        image.write_png(&self.dir.join(&rel)).map_err(image_error)?;
        Ok(rel)
    }
}

/// The error of a metric that the close-up of surface `name` needs.
fn closeup_error(name: &str) -> impl Fn(beltrami_metrics::MetricsError) -> StudyError + '_ {
    move |source| StudyError::Metrics {
        surface: name.to_string(),
        scheme: "close-up".into(),
        source,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overlap_is_judged_against_the_plot_height() {
        let a = Series::new("uniform", [(0.0, 1.0), (10.0, 0.5), (20.0, 0.0)]);
        let close = Series::new("cotangent", [(0.0, 1.0), (10.0, 0.51), (20.0, 0.01)]);
        let apart = Series::new("distance", [(0.0, 1.0), (10.0, 0.6), (20.0, 0.0)]);
        assert!(curves_overlap(&[a.clone(), close.clone()]));
        assert!(!curves_overlap(&[a.clone(), close.clone(), apart]));
        assert!(!curves_overlap(std::slice::from_ref(&a)));
        let flat = Series::new("flat", [(0.0, 1.0), (1.0, 1.0)]);
        assert!(!curves_overlap(&[flat.clone(), flat]));
        let d = differences(&[a, close.with_style(2)]);
        assert_eq!(d.len(), 1);
        assert_eq!(d[0].label, "cotangent − uniform");
        assert_eq!(d[0].style, Some(2));
        assert_eq!(d[0].points.len(), 3);
        assert!((d[0].points[1].1 - 0.01).abs() < 1e-12);
    }

    #[test]
    fn units_label_lengths() {
        assert_eq!(unit_label("mm"), " (mm)");
        assert_eq!(unit_label("1"), " (clean radii)");
    }
}
