//! `beltrami fit`: least-squares sphere, circle or cylinder through a mesh's vertices.

use std::io::Write;
use std::path::PathBuf;

use beltrami_metrics::fits::{FitOptions, FitPoints, fit_circle, fit_cylinder, fit_sphere};
use clap::ValueEnum;
use serde::Serialize;

use crate::compare::{load_input, metrics_error};
use crate::error::CliError;
use crate::load::ReadArgs;
use crate::text::{number, vector};

/// Arguments of `beltrami fit`.
#[derive(Debug, clap::Args)]
pub(crate) struct FitArgs {
    /// The shape: sphere, circle (a plane through the points, then the circle in it) or
    /// cylinder.
    shape: Shape,
    /// The mesh or point set (.ply, .stl, .obj, .off, or an .x3p or .sdf height map).
    mesh: PathBuf,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
    /// Weigh each vertex by its share of the surface area (a third of its triangles'
    /// areas): a fit over the surface rather than over the vertex set.
    #[arg(long)]
    weighted: bool,
    #[command(flatten)]
    read: ReadArgs,
}

#[derive(Clone, Copy, Debug, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
enum Shape {
    Sphere,
    Circle,
    Cylinder,
}

/// What `fit` reports; also the JSON schema of `fit --json`.
#[derive(Debug, Serialize)]
struct FitSummary {
    file: String,
    shape: Shape,
    weighted: bool,
    /// Points that took part (of positive weight).
    points: usize,
    /// The centre (sphere, circle) or the axis point nearest the points' centroid
    /// (cylinder).
    center: [f64; 3],
    /// The unit axis (circle: the plane normal), largest component positive.
    #[serde(skip_serializing_if = "Option::is_none")]
    axis: Option<[f64; 3]>,
    radius: f64,
    rms_residual: f64,
    max_residual: f64,
    /// The RMS distance of the points from the circle's plane (circle only).
    #[serde(skip_serializing_if = "Option::is_none")]
    plane_rms: Option<f64>,
    iterations: usize,
    converged: bool,
    /// What reading the file did besides reading it (a height map's grid, a lenient
    /// read's skipped lines, `--weld`, `--repair`), one line each; empty when nothing.
    notes: Vec<String>,
}

/// Runs `beltrami fit`.
pub(crate) fn run(args: &FitArgs, out: &mut impl Write) -> Result<(), CliError> {
    let loaded = load_input(
        &args.mesh,
        &args.read,
        args.weighted.then_some("--weighted"),
    )?;
    let on_mesh = metrics_error(&args.mesh);
    let input = if args.weighted {
        FitPoints::area_weighted(&loaded.mesh, &loaded.positions).map_err(&on_mesh)?
    } else {
        FitPoints::new(&loaded.positions)
    };
    let points = input.weights().map_or(loaded.positions.len(), |w| {
        w.iter().filter(|&&w| w > 0.0).count()
    });
    let options = FitOptions::default();
    let base = |center: glam::DVec3, radius, rms_residual, max_residual, iterations, converged| {
        FitSummary {
            file: args.mesh.display().to_string(),
            shape: args.shape,
            weighted: args.weighted,
            points,
            center: center.to_array(),
            axis: None,
            radius,
            rms_residual,
            max_residual,
            plane_rms: None,
            iterations,
            converged,
            notes: loaded.read_notes(&args.mesh, false),
        }
    };
    let summary = match args.shape {
        Shape::Sphere => {
            let f = fit_sphere(&input, &options).map_err(&on_mesh)?;
            base(
                f.center,
                f.radius,
                f.rms_residual,
                f.max_residual,
                f.iterations,
                f.converged,
            )
        }
        Shape::Circle => {
            let f = fit_circle(&input, &options).map_err(&on_mesh)?;
            FitSummary {
                axis: Some(f.axis.to_array()),
                plane_rms: Some(f.plane_rms),
                ..base(
                    f.center,
                    f.radius,
                    f.rms_residual,
                    f.max_residual,
                    f.iterations,
                    f.converged,
                )
            }
        }
        Shape::Cylinder => {
            let f = fit_cylinder(&input, None, &options).map_err(&on_mesh)?;
            FitSummary {
                axis: Some(f.axis.to_array()),
                ..base(
                    f.axis_point,
                    f.radius,
                    f.rms_residual,
                    f.max_residual,
                    f.iterations,
                    f.converged,
                )
            }
        }
    };
    if args.json {
        serde_json::to_writer_pretty(&mut *out, &summary).map_err(std::io::Error::from)?;
        writeln!(out)?;
    } else {
        write_table(&summary, out)?;
    }
    Ok(())
}

fn write_table(s: &FitSummary, out: &mut impl Write) -> std::io::Result<()> {
    let shape = format!("{:?}", s.shape).to_lowercase();
    writeln!(
        out,
        "Least-squares {shape} (orthogonal distances) through {} {}{} of {}; lengths in the file's unit.",
        s.points,
        if s.weighted { "area-weighted " } else { "" },
        crate::text::plural(s.points, "point", "points"),
        s.file
    )?;
    let v = |a: [f64; 3]| vector(glam::DVec3::from_array(a));
    let mut rows: Vec<(&str, String)> = vec![(
        if matches!(s.shape, Shape::Cylinder) {
            "axis point"
        } else {
            "center"
        },
        v(s.center),
    )];
    if let Some(axis) = s.axis {
        rows.push((
            if matches!(s.shape, Shape::Circle) {
                "normal"
            } else {
                "axis"
            },
            v(axis),
        ));
    }
    rows.extend([
        ("radius", number(s.radius)),
        ("rms residual", number(s.rms_residual)),
        ("max residual", number(s.max_residual)),
    ]);
    if let Some(plane) = s.plane_rms {
        rows.push(("plane rms", number(plane)));
    }
    rows.push((
        "iterations",
        format!(
            "{} ({})",
            s.iterations,
            if s.converged {
                "converged"
            } else {
                "stopped at the limit, not converged"
            }
        ),
    ));
    for (key, value) in rows {
        writeln!(out, "{key:<21} {value}")?;
    }
    for line in &s.notes {
        writeln!(out, "{line}")?;
    }
    Ok(())
}
