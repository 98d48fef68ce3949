//! The paper's figures: plots of the rows and renders of the smoothed meshes.

use std::path::Path;

use beltrami_halfedge::DVec3;
use beltrami_halfedge::geometry::Geometry;
use beltrami_metrics::profile::{Plane, Polyline, cross_section};
use beltrami_surfaces::SurfaceKind;
use beltrami_viz::plot::{LinePlot, Series, write_plot};
use beltrami_viz::render::{ColorMap, Image, View, grid, render_mesh};

use crate::error::StudyError;
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
    let input = rows
        .iter()
        .find(|r| r.surface == surface && r.scheme == "input")
        .and_then(&f);
    result
        .runs
        .iter()
        .map(|run| {
            let points = input.map(|v| (0.0, v)).into_iter().chain(
                rows.iter()
                    .filter(|r| r.surface == surface && r.scheme == run.scheme)
                    .filter_map(|r| f(r).map(|v| (r.iteration as f64, v))),
            );
            Series::new(run.scheme.clone(), points)
        })
        .collect()
}

/// Per scheme, the mean RMS over the seeds at every iteration up to
/// [`EARLY_ITERATIONS`], starting from the input's.
fn early_series(result: &SurfaceResult) -> Vec<Series> {
    let mean_at = |scheme: &str, it: usize| {
        let v: Vec<f64> = result
            .rms_curve
            .iter()
            .filter(|p| p.scheme == scheme && p.iteration == it)
            .map(|p| p.rms)
            .collect();
        (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
    };
    let input = mean_at("input", 0);
    result
        .runs
        .iter()
        .map(|run| {
            let points = input.map(|v| (0.0, v)).into_iter().chain(
                (1..=EARLY_ITERATIONS)
                    .filter_map(|it| mean_at(&run.scheme, it).map(|v| (it as f64, v))),
            );
            Series::new(run.scheme.clone(), points)
        })
        .collect()
}

struct PlotSpec {
    stem: String,
    title: String,
    y_label: String,
    caption: String,
    log_y: bool,
    series: Vec<Series>,
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
    let mut plot = LinePlot::new(spec.title, "iterations", spec.y_label);
    plot.series = spec.series;
    plot.log_y = spec.log_y;
    let rel = format!("plots/{}", spec.stem);
    write_plot(&plot, &dir.join(&rel)).map_err(viz(&spec.stem))?;
    figures.push(Figure {
        path: rel,
        caption: spec.caption,
        surface: surface.to_string(),
    });
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

/// Writes every plot and render into `dir/plots` and `dir/renders`.
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
        let name = result.case.clean.name;
        let unit = result.case.clean.unit;
        let u = if unit == "1" {
            String::new()
        } else {
            format!(" ({unit})")
        };
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
            },
            name,
            &mut figures,
        )?;
        write_line(
            dir,
            PlotSpec {
                stem: format!("rms_early_{name}"),
                title: format!("{name}: RMS, iterations 0 to {EARLY_ITERATIONS}"),
                y_label: format!("RMS distance{u}"),
                caption: format!(
                    "RMS distance to the clean surface on the {name}, every iteration from 0 to {EARLY_ITERATIONS} (mean over the noise seeds): the RMS-optimal iteration count lies here"
                ),
                log_y: false,
                series: early_series(result),
            },
            name,
            &mut figures,
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
            },
            name,
            &mut figures,
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
                    series: series_by_scheme(result, rows, |r| r.sphere_radius),
                },
                name,
                &mut figures,
            )?;
        }
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
                },
                name,
                &mut figures,
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
                },
                name,
                &mut figures,
            )?;
            ring_plot(dir, result, shown, &mut figures)?;
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
                },
                name,
                &mut figures,
            )?;
        }
        if matches!(result.case.kind, SurfaceKind::FLens | SurfaceKind::Block) {
            profile_plot(dir, result, shown, &mut figures)?;
        }
        render_grid(dir, results, result, &mut figures)?;
    }
    Ok(figures)
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
        "RMS distance to the clean surface",
    );
    for m in &result.measured {
        if m.row.iteration == shown || m.row.scheme == "input" {
            if let Some(rings) = &m.rings {
                let points = rings.rings.iter().map(|r| (f64::from(r.ring), r.rms));
                plot.series.push(Series::new(m.row.scheme.clone(), points));
            }
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

/// The longest polyline of a plane section, as (u, v) coordinates in the plane.
fn section(
    positions: &[DVec3],
    result: &SurfaceResult,
    plane: &Plane,
    axes: (DVec3, DVec3),
) -> Result<Vec<(f64, f64)>, StudyError> {
    let geometry = Geometry::new(&result.case.mesh, positions)
        .map_err(|e| StudyError::Config(e.to_string()))?;
    let polylines: Vec<Polyline> =
        cross_section(&geometry, plane).map_err(|source| StudyError::Metrics {
            surface: result.case.clean.name.to_string(),
            scheme: "profile".into(),
            source,
        })?;
    let longest = polylines
        .iter()
        .max_by(|a, b| a.length().total_cmp(&b.length()));
    Ok(longest
        .map(|l| {
            let mut pts: Vec<(f64, f64)> = l
                .positions()
                .map(|p| (p.dot(axes.0), p.dot(axes.1)))
                .collect();
            if l.closed {
                if let Some(&first) = pts.first() {
                    pts.push(first);
                }
            }
            pts
        })
        .unwrap_or_default())
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
            "section y = 0",
            ("x", "z"),
        ),
        _ => (
            Plane::new(DVec3::new(0.0, 0.0, 0.01), DVec3::Z),
            (DVec3::X, DVec3::Y),
            "section z = 0.01",
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
        format!("{name}: cross-section profile ({what}) after {shown} iterations"),
        format!("{} ({unit})", labels.0),
        format!("{} ({unit})", labels.1),
    );
    plot.aspect_equal = result.case.kind == SurfaceKind::Block;
    plot.series.push(Series::new(
        "clean",
        section(&result.case.clean.positions, result, &plane, axes)?,
    ));
    plot.series.push(Series::new(
        "input",
        section(&result.case.noisy, result, &plane, axes)?,
    ));
    for run in &result.runs {
        if let Some(s) = run.snapshots.iter().find(|s| s.iteration == shown) {
            plot.series.push(Series::new(
                run.scheme.clone(),
                section(&s.positions, result, &plane, axes)?,
            ));
        }
    }
    let rel = format!("plots/profile_{name}");
    write_plot(&plot, &dir.join(&rel)).map_err(viz(&rel))?;
    figures.push(Figure {
        path: rel,
        caption: format!("Cross-section profile of the {name} ({what}): clean, noisy input and each scheme after {shown} iterations (the paper's cross-sectional profile comparison)"),
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
    let unit = if result.case.clean.unit == "1" {
        String::new()
    } else {
        format!(" ({})", result.case.clean.unit)
    };
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
